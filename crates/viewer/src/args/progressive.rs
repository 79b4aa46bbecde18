//! The window's progressive policy (`window/worker/progress.rs`): its flags.

use clap::Args;

/// How the window samples its frames: coarse while the head moves, refined at rest.
#[derive(Debug, Args, Clone, Copy)]
pub struct ProgressiveArgs {
    /// Trace every frame at full resolution, as before the progressive policy: no coarse
    /// frames while the head moves, no refinement while it rests.
    #[arg(long)]
    pub no_progressive: bool,
    /// While the head moves, the age a traced pair aims at when presented, milliseconds
    /// (5 to 1000): the progressive policy picks each pair's sample density for it.
    #[arg(long, value_name = "MS", default_value_t = 33, value_parser = clap::value_parser!(u32).range(5..=1000))]
    pub target_age_ms: u32,
    /// While the head rests, refine up to S × S samples a pixel (1 to 8), converging to
    /// `render --supersample S`.
    #[arg(long, value_name = "S", default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=8))]
    pub max_supersample: u32,
}
