//! The viewer window (being written).

use crate::cli::WindowArgs;

pub fn run(_args: &WindowArgs) -> anyhow::Result<()> {
    anyhow::bail!("the window is not built yet")
}
