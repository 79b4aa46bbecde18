//! The headless commands, `stereotrace render`, `bench`, `sweep` and `timewarp`, and what only
//! they use.
//!
//! The modules, in order: each uses only those listed before it (and the shared modules at
//! the top of the crate: the arguments, the scene setup, the reference trace, the crop).
//! - `report`, the JSON keys;
//! - `render` (one frame, or an animation, to PNG files and the JSON report) and `bench`
//!   (every mode on the same frames);
//! - `plot`, the sweep's figure (and what every figure shares), and `sweep`, which measures
//!   each step with `bench`'s loop;
//! - `age_plot`, the timewarp's figure, and `timewarp`, which warps traced frames to the poses
//!   of a moving head and scores them against traces there.

pub mod report;

/// Writes a command's report to standard output. A reader that has closed the pipe
/// (`stereotrace render --json | head -c 100`) wanted no more of it: that is not an error,
/// and not the panic `print!` makes of it.
///
/// # Errors
///
/// Any other failure to write, such as a full disk.
pub fn print_out(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => {
            Err(anyhow::Error::new(e).context("writing the report to standard output"))
        }
        _ => Ok(()),
    }
}

pub mod bench;
pub mod render;

pub mod plot;
pub mod sweep;

pub mod age_plot;
pub mod timewarp;

pub mod pick;
