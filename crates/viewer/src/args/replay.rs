//! `stereotrace replay`'s arguments (`replay.rs`).

use std::path::PathBuf;

use clap::{Args, ValueEnum};
use stereo::Mode;

use super::{parse_mode, FrameArgs, MAX_SUPERSAMPLE};
use crate::motion::Motion;

/// `stereotrace replay`.
#[derive(Debug, Args)]
pub struct ReplayArgs {
    #[command(flatten)]
    pub frame: FrameArgs,
    /// How each traced frame's right eye is made (the viewer's default: exact).
    #[arg(long, value_name = "MODE", default_value = "exact", value_parser = parse_mode)]
    pub mode: Mode,
    /// The head's constant motion from the scene's pose, as `timewarp --motion`: KEY=NUMBER
    /// pairs separated by commas, yaw and pitch in degrees a second, x, y, z in scene units a
    /// second along the starting head's axes (right, up, forward); e.g. yaw=20,x=1.5.
    #[arg(long, value_name = "yaw=DEG_PER_S,…", allow_hyphen_values = true)]
    pub motion: Motion,
    /// Seconds the head moves (more than 0, at most 60).
    #[arg(long, value_name = "T", default_value_t = 4.0, allow_negative_numbers = true)]
    pub seconds: f64,
    /// Seconds the head then rests where the motion left it (0 to 600).
    #[arg(long, value_name = "S", default_value_t = 2.0, allow_negative_numbers = true)]
    pub still: f64,
    /// The display's refresh rate: a tick this many times a second (1 to 240).
    #[arg(long, value_name = "HZ", default_value_t = 90, value_parser = clap::value_parser!(u32).range(1..=240))]
    pub display_hz: u32,
    /// Every k-th presented frame is scored (1 to 10000).
    #[arg(long, value_name = "K", default_value_t = 10, value_parser = clap::value_parser!(u32).range(1..=10_000))]
    pub score_every: u32,
    /// The reference, and a resting view's refinement, at S × S samples a pixel (1 to 4).
    #[arg(long, value_name = "S", default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SUPERSAMPLE)))]
    pub max_supersample: u32,
    /// progressive (coarse and young while the head moves, refined at rest) or fixed (every
    /// frame traced at full resolution, the viewer's behaviour before it).
    #[arg(long, value_name = "POLICY", value_enum, default_value_t = Policy::Progressive)]
    pub policy: Policy,
    /// With the progressive policy, the age a moving head's traced pair aims at when
    /// presented, milliseconds (more than 0, at most 1000).
    #[arg(long, value_name = "MS", default_value_t = 33.0, allow_negative_numbers = true)]
    pub target_age_ms: f32,
    /// The timewarp's guard band, as the viewer's: this percentage of each eye's width and
    /// height beyond each side (0 to 25).
    #[arg(long, value_name = "PERCENT", default_value_t = 5, value_parser = clap::value_parser!(u32).range(0..=25))]
    pub guard_band: u32,
    /// Print one JSON object (the policy, the frames, their medians, converge_s) instead of
    /// the summary.
    #[arg(long)]
    pub json: bool,
    /// CSV file to write: a row per presented frame.
    #[arg(long, value_name = "F.csv")]
    pub csv: Option<PathBuf>,
    /// Plot to write, PSNR and age over time with the moving and resting parts marked: PNG,
    /// or SVG when the name ends in .svg.
    #[arg(long, value_name = "F.png|F.svg")]
    pub plot: Option<PathBuf>,
}

/// `replay --policy`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Policy {
    /// Coarse and young while the head moves, refined while it rests.
    Progressive,
    /// Every frame at full resolution.
    Fixed,
}

impl Policy {
    /// The policy's name on the command line and in reports.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Policy::Progressive => "progressive",
            Policy::Fixed => "fixed",
        }
    }
}
