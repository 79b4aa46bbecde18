//! Command-line arguments (clap), of the window and of the headless commands alike.
//! `stereotrace` alone opens the window.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};
use stereo::{Layout, Mode};

mod cues;

pub use cues::CueArgs;

use crate::crop::Crop;
use crate::motion::Motion;

mod progressive;
mod replay;

pub use progressive::ProgressiveArgs;
pub use replay::{Policy, ReplayArgs};

/// Default scene, relative to the workspace root (also found next to the executable's
/// workspace when run from elsewhere; see `setup::resolve_scene`).
pub const DEFAULT_SCENE: &str = "assets/scenes/seed.toml";

/// Largest image side accepted, per eye, in pixels.
pub const MAX_SIDE: u32 = 16_384;

/// stereotrace — a real-time CPU ray tracer that renders a stereo pair and makes the right
/// eye by reprojecting the left (Adelson & Hodges 1993).
///
/// Without a subcommand it opens the viewer window.
#[derive(Debug, Parser)]
#[command(name = "stereotrace", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    #[command(flatten)]
    pub window: WindowArgs,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Render one stereo frame headless to PNG files.
    Render(RenderArgs),
    /// Render the same frames in every mode and report time, rays and quality.
    Bench(BenchArgs),
    /// Every mode over a range of one parameter: cost and quality per step, as CSV and a plot.
    Sweep(SweepArgs),
    /// A head moving at constant speed: a frame traced every N display frames, each displayed
    /// frame that traced frame warped to its own pose, scored against a trace there.
    Timewarp(TimewarpArgs),
    /// The atom (or sphere) a pixel's primary ray hits first in one eye: its fields, the
    /// ray and the hit point.
    Pick(PickArgs),
    /// The viewer's own pipeline run headless in real time along a scripted head motion and
    /// a rest: every presented frame recorded, then scored against a supersampled trace.
    Replay(ReplayArgs),
}

/// Options of the viewer window.
#[derive(Debug, Args)]
#[expect(clippy::struct_excessive_bools, reason = "independent command-line switches, as clap declares them")]
pub struct WindowArgs {
    /// Scene file: TOML, or a structure (.pdb, .ent, .cif, .mmcif, .gro, .xyz, optionally
    /// .gz) framed as a scene of its own [default: assets/scenes/seed.toml].
    #[arg(long, value_name = "PATH", global = false)]
    pub scene: Option<PathBuf>,
    /// Initial window width in logical pixels (both eyes together).
    #[arg(long, value_name = "W", default_value_t = 1600, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SIDE)))]
    pub width: u32,
    /// Initial window height in logical pixels.
    #[arg(long, value_name = "H", default_value_t = 600, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SIDE)))]
    pub height: u32,
    /// Exit after this many presented frames (for tests).
    #[arg(long, value_name = "N")]
    pub frames: Option<u64>,
    /// Write the last presented frame, UI included, to this PNG on exit (for tests).
    #[arg(long, value_name = "PATH")]
    pub dump: Option<PathBuf>,
    /// Start with the orbit paused at this time, in seconds.
    #[arg(long, value_name = "T")]
    pub time: Option<f32>,
    /// Start with live PSNR on (the right eye measured against a full trace every frame).
    #[arg(long)]
    pub live_psnr: bool,
    /// Start at this render scale, in percent of the eye's size on screen (25 to 200; above
    /// 100 supersampled, 200 = 2 × 2 samples per pixel).
    #[arg(long, value_name = "PERCENT", value_parser = clap::value_parser!(u32).range(25..=200))]
    pub render_scale: Option<u32>,
    /// Start with reuse off: every frame traced afresh, even while only the orbit moves.
    #[arg(long)]
    pub no_reuse: bool,
    /// Start with the timewarp off: each traced frame is shown as it is, at the pose it was
    /// traced for (the panel's "timewarp" tick turns it on again).
    #[arg(long)]
    pub no_timewarp: bool,
    /// The timewarp's guard band: each eye is traced this percentage of its width and height
    /// beyond each side (0 to 25).
    #[arg(long, value_name = "PERCENT", default_value_t = 5, value_parser = clap::value_parser!(u32).range(0..=25))]
    pub guard_band: u32,
    /// With the timewarp on, the display's refresh rate: while the head moves, a warped frame
    /// is presented this many times a second (1 to 240).
    #[arg(long, value_name = "HZ", default_value_t = 90, value_parser = clap::value_parser!(u32).range(1..=240))]
    pub display_hz: u32,
    #[command(flatten)]
    pub progressive: ProgressiveArgs,
    /// A structure file's biological assembly (PDB BIOMT, mmCIF pdbx_struct_oper_list)
    /// instead of its asymmetric unit.
    #[arg(long)]
    pub assembly: bool,
    /// A structure file's atoms' radii: this times their van der Waals radii (1 spheres,
    /// 0.25 balls).
    #[arg(long, value_name = "S", default_value_t = tracer::DEFAULT_RADIUS_SCALE)]
    pub radius_scale: f32,
    #[command(flatten)]
    pub look: LookArgs,
}

/// Camera and render overrides shared by `render` and `bench`.
#[derive(Debug, Args, Clone)]
pub struct FrameArgs {
    /// Scene file: TOML, or a structure (.pdb, .ent, .cif, .mmcif, .gro, .xyz, optionally
    /// .gz) framed as a scene of its own.
    #[arg(long, value_name = "PATH", default_value = DEFAULT_SCENE)]
    pub scene: PathBuf,
    /// For a structure file: build its first biological assembly (PDB BIOMT, mmCIF
    /// assembly_gen) instead of the atoms as they are.
    #[arg(long)]
    pub assembly: bool,
    /// For a structure file: atom radius = van der Waals radius × this (1: spheres, 0.25:
    /// CPK balls).
    #[arg(long, value_name = "S", default_value_t = tracer::DEFAULT_RADIUS_SCALE)]
    pub radius_scale: f32,
    /// Width of each eye in pixels.
    #[arg(long, value_name = "W", default_value_t = 1280, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SIDE)))]
    pub width: u32,
    /// Height of each eye in pixels.
    #[arg(long, value_name = "H", default_value_t = 720, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SIDE)))]
    pub height: u32,
    /// Interpupillary distance e (scene units); default from the scene.
    #[arg(long, value_name = "E", allow_negative_numbers = true)]
    pub ipd: Option<f32>,
    /// Distance d from the eyes to the zero-parallax window; default from the scene.
    #[arg(long, value_name = "D", allow_negative_numbers = true)]
    pub distance: Option<f32>,
    /// Reflection depth (bounces); default from the scene.
    #[arg(long, value_name = "N")]
    pub depth: Option<u32>,
    /// Scene time in seconds (positions the revolving spheres).
    #[arg(long, value_name = "T", default_value_t = 0.0, allow_negative_numbers = true)]
    pub time: f32,
    #[command(flatten)]
    pub look: LookArgs,
}

/// How the scene's structures are coloured, which of their atoms are hidden, and the cues:
/// the window's and every headless command's.
#[derive(Debug, Args, Clone, Copy, Default, PartialEq)]
pub struct LookArgs {
    /// Colour the structures' atoms by element, chain, residue (RasMol's shapely), bfactor
    /// (blue–white–red), plddt (AlphaFold's bands), rainbow (N to C terminus) or hetero
    /// (ligands by element, the polymer grey) [default: element, or the scene's color_by].
    #[arg(long, value_name = "SCHEME", value_parser = parse_color_by)]
    pub color: Option<tracer::ColorBy>,
    /// With --color bfactor: the B-factors blue (A) to red (B), A < B [default: the file's
    /// range].
    #[arg(long, value_name = "A,B", value_parser = tracer::parse_color_range, allow_hyphen_values = true)]
    pub color_range: Option<(f32, f32)>,
    /// Atoms out of the scene, comma-separated: water (HOH, WAT, H2O, DOD, SOL, TIP3),
    /// hydrogen, hetero (HETATM records).
    #[arg(long, value_name = "ITEMS", value_parser = parse_hide)]
    pub hide: Option<tracer::Hide>,
    #[command(flatten)]
    pub cues: CueArgs,
}

impl LookArgs {
    /// The colouring asked for, `None` to keep the scene's own.
    #[must_use]
    pub fn coloring(&self) -> Option<tracer::Coloring> {
        let by = self.color.or(self.color_range.map(|_| tracer::ColorBy::BFactor))?;
        Some(tracer::Coloring { by, range: self.color_range })
    }

    /// `scene` with the atoms hidden and the colours asked for (nothing changes without
    /// the flags).
    #[must_use]
    pub fn apply(&self, mut scene: tracer::Scene) -> tracer::Scene {
        if let Some(hide) = self.hide.filter(|h| !h.is_empty()) {
            scene = scene.hidden(hide);
        }
        if let Some(coloring) = self.coloring() {
            scene.recolor(&coloring);
        }
        self.cues.apply(&mut scene);
        scene
    }
}

fn parse_color_by(s: &str) -> Result<tracer::ColorBy, String> {
    s.parse()
}

fn parse_hide(s: &str) -> Result<tracer::Hide, String> {
    s.parse()
}

/// `stereotrace render`.
#[derive(Debug, Args)]
#[expect(clippy::struct_excessive_bools, reason = "each bool is one command-line flag")]
pub struct RenderArgs {
    #[command(flatten)]
    pub frame: FrameArgs,
    /// How the right eye is made.
    #[arg(long, value_name = "MODE", default_value = "exact", value_parser = parse_mode)]
    pub mode: Mode,
    /// For copy and reshade: also retrace pixels on object edges.
    #[arg(long)]
    pub retrace_edges: bool,
    /// Left-eye PNG to write.
    #[arg(long, value_name = "L.png")]
    pub left: Option<PathBuf>,
    /// Right-eye PNG to write.
    #[arg(long, value_name = "R.png")]
    pub right: Option<PathBuf>,
    /// Debug-mask PNG to write (how each right pixel was made).
    #[arg(long, value_name = "M.png")]
    pub mask: Option<PathBuf>,
    /// PNG of where the right eye differs from a full trace: red over 2/255 on some channel,
    /// amber by 1 or 2 levels, the reference in pale grey where identical.
    #[arg(long, value_name = "D.png")]
    pub diff: Option<PathBuf>,
    /// Write only this rectangle (pixels: left column, top row, width, height) of --left,
    /// --right, --mask and --diff.
    #[arg(long, value_name = "X,Y,W,H", conflicts_with_all = ["out", "frames"])]
    pub crop: Option<Crop>,
    /// Combined stereo image to write, in --layout.
    #[arg(long, value_name = "PAIR.png")]
    pub out: Option<PathBuf>,
    /// Layout of the combined image(s): side-by-side (left eye left), cross-eyed, anaglyph (red-cyan).
    #[arg(long, value_name = "LAYOUT", default_value = "side-by-side", value_parser = parse_layout)]
    pub layout: Layout,
    /// Exchange the eyes in the combined image(s).
    #[arg(long)]
    pub swap_eyes: bool,
    /// Render an animation of N frames of the orbit, as numbered combined PNGs in --out-dir.
    #[arg(long, value_name = "N", requires = "out_dir", conflicts_with = "json", value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub frames: Option<u32>,
    /// Frames per second of the animation: scene time advances 1/F s per frame.
    #[arg(long, value_name = "F", default_value_t = 30.0)]
    pub fps: f32,
    /// Trace every pixel of every animation frame, rather than only those that can have
    /// changed since the frame before (the output is the same either way).
    #[arg(long, requires = "frames")]
    pub no_reuse: bool,
    /// Folder for the animation's frames (created if missing).
    #[arg(long, value_name = "DIR", requires = "frames")]
    pub out_dir: Option<PathBuf>,
    /// Print the frame report as JSON on stdout (includes quality against a full trace).
    #[arg(long)]
    pub json: bool,
    /// Anti-aliasing: trace S × S samples per pixel (S = 1 to 4 per axis), so every stage runs
    /// at (W·S) × (H·S), and box-filter them down to W × H in linear light.
    #[arg(long, value_name = "S", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SUPERSAMPLE)))]
    pub supersample: u32,
}

/// Largest `render --supersample` factor, per axis.
pub const MAX_SUPERSAMPLE: u32 = 4;

/// `stereotrace bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    #[command(flatten)]
    pub frame: FrameArgs,
    /// Frames per mode; the report gives medians.
    #[arg(long, value_name = "N", default_value_t = 5, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub frames: u32,
    /// Frames of the animation rows: per mode, N consecutive frames 1/60 s apart with the
    /// head still, traced fresh and with reuse (0 leaves the rows out).
    #[arg(long, value_name = "N", default_value_t = 60, value_parser = clap::value_parser!(u32).range(0..=10_000))]
    pub animate: u32,
    /// Print one JSON object instead of the table.
    #[arg(long)]
    pub json: bool,
}

/// `stereotrace sweep`.
#[derive(Debug, Args)]
pub struct SweepArgs {
    #[command(flatten)]
    pub frame: FrameArgs,
    /// The parameter swept: the IPD e, the zero-parallax distance d, the reflection depth, or
    /// the scene time (s).
    #[arg(long, value_name = "PARAM", value_enum)]
    pub param: SweepParam,
    /// First value of the parameter.
    #[arg(long, value_name = "A", allow_negative_numbers = true)]
    pub from: f64,
    /// Last value of the parameter (≥ --from).
    #[arg(long, value_name = "B", allow_negative_numbers = true)]
    pub to: f64,
    /// Number of values, evenly spaced from A to B inclusive.
    #[arg(long, value_name = "N", default_value_t = 11, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub steps: u32,
    /// Modes to run, comma-separated: full, copy, copy+edges, reshade, reshade+edges, exact
    /// [default: full,copy,reshade,exact].
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    pub modes: Option<Vec<String>>,
    /// Frames per step; times are medians over them (every frame of a step is the same scene
    /// state, so rays and quality are the same on each).
    #[arg(long, value_name = "N", default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub frames: u32,
    /// CSV file to write, a row per step and mode; without it the CSV goes to stdout.
    #[arg(long, value_name = "F.csv")]
    pub csv: Option<PathBuf>,
    /// Plot to write: PNG, or SVG when the name ends in .svg.
    #[arg(long, value_name = "F.png|F.svg")]
    pub plot: Option<PathBuf>,
}

/// The parameter `sweep` varies.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum SweepParam {
    /// The interpupillary distance e (scene units, ≥ 0).
    Ipd,
    /// The distance d from the eyes to the zero-parallax window (scene units, > 0).
    Distance,
    /// The reflection depth (whole bounces, 0 to 16).
    Depth,
    /// The scene time in seconds (positions the revolving spheres).
    Time,
}

/// `stereotrace timewarp`.
#[derive(Debug, Args)]
pub struct TimewarpArgs {
    #[command(flatten)]
    pub frame: FrameArgs,
    /// How each traced frame's right eye is made (the viewer's default: exact).
    #[arg(long, value_name = "MODE", default_value = "exact", value_parser = parse_mode)]
    pub mode: Mode,
    /// The head's constant motion from the scene's pose: KEY=NUMBER pairs separated by
    /// commas, yaw and pitch in degrees a second, x, y, z in scene units a second along the
    /// starting head's axes (right, up, forward); e.g. yaw=30,x=0.3.
    #[arg(long, value_name = "yaw=DEG_PER_S,…", allow_hyphen_values = true)]
    pub motion: Motion,
    /// The display's refresh rate: a frame is displayed this many times a second (1 to 240).
    #[arg(long, value_name = "HZ", default_value_t = 90, value_parser = clap::value_parser!(u32).range(1..=240))]
    pub display_hz: u32,
    /// A frame is traced every N display frames (N ≥ 1); several runs with a list (1,2,4) or
    /// a range (1..6, inclusive).
    #[arg(long, value_name = "N|LIST|A..B", value_parser = parse_trace_every)]
    pub trace_every: TraceEvery,
    /// Seconds of display (more than 0, at most 60): round(T × HZ) displayed frames.
    #[arg(long, value_name = "T", default_value_t = 1.0, allow_negative_numbers = true)]
    pub seconds: f64,
    /// The guard band the frames are traced with, as the viewer's timewarp traces them: this
    /// percentage of each eye's width and height beyond each side (0 to 25).
    #[arg(long, value_name = "PERCENT", default_value_t = 5, value_parser = clap::value_parser!(u32).range(0..=25))]
    pub guard_band: u32,
    /// Print one JSON object of medians (an array of them for several --trace-every values)
    /// instead of the table.
    #[arg(long)]
    pub json: bool,
    /// CSV file to write: a row per displayed frame and warp method.
    #[arg(long, value_name = "F.csv")]
    pub csv: Option<PathBuf>,
    /// Plot to write, PSNR against the age of the frame shown, a line per method: PNG, or SVG
    /// when the name ends in .svg.
    #[arg(long, value_name = "F.png|F.svg")]
    pub plot: Option<PathBuf>,
}

/// `stereotrace pick`.
#[derive(Debug, Args)]
pub struct PickArgs {
    #[command(flatten)]
    pub frame: FrameArgs,
    /// Frame number of the orbit animation (as `render --frames` numbers its files): scene
    /// time --time + FRAME / --fps [default: 0, the scene at --time].
    #[arg(value_name = "FRAME")]
    pub frame_number: Option<u32>,
    /// Frames per second of the animation FRAME counts in.
    #[arg(long, value_name = "F", default_value_t = 30.0)]
    pub fps: f32,
    /// The eye whose pixel is picked.
    #[arg(long, value_name = "EYE", value_enum, default_value_t = PickEye::Left)]
    pub eye: PickEye,
    /// The pixel: column and row from the eye image's top-left corner, 0-based.
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    pub at: String,
    /// Print one JSON object (on a miss too) instead of the text.
    #[arg(long)]
    pub json: bool,
}

/// `pick --eye`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum PickEye {
    /// The left eye.
    Left,
    /// The right eye.
    Right,
}

/// Largest `timewarp --trace-every` value.
pub const MAX_TRACE_EVERY: u32 = 1000;

/// `timewarp --trace-every`: the values of N, one run each, in the order given.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TraceEvery(pub Vec<u32>);

/// `N`, `A,B,…` or `A..B` (inclusive), each 1 to [`MAX_TRACE_EVERY`], none twice.
fn parse_trace_every(s: &str) -> Result<TraceEvery, String> {
    let expected =
        format!("expected a whole number of display frames 1 to {MAX_TRACE_EVERY}, a list (1,2,4) or a range (1..6)");
    let number = |t: &str| -> Result<u32, String> {
        match t.trim().parse::<u32>() {
            Ok(n) if (1..=MAX_TRACE_EVERY).contains(&n) => Ok(n),
            _ => Err(format!("`{}` in `{s}`: {expected}", t.trim())),
        }
    };
    let values: Vec<u32> = if let Some((a, b)) = s.split_once("..") {
        let (a, b) = (number(a)?, number(b)?);
        if a > b {
            return Err(format!("`{s}`: the range's first value is above its last"));
        }
        (a..=b).collect()
    } else {
        s.split(',').map(number).collect::<Result<_, _>>()?
    };
    if let Some(n) = values.iter().enumerate().find_map(|(k, n)| values[..k].contains(n).then_some(n)) {
        return Err(format!("`{s}`: {n} is given twice"));
    }
    Ok(TraceEvery(values))
}

fn parse_mode(s: &str) -> Result<Mode, String> {
    s.parse()
}

fn parse_layout(s: &str) -> Result<Layout, String> {
    s.parse()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trace_every_takes_a_number_a_list_or_a_range() {
        assert_eq!(parse_trace_every("3"), Ok(TraceEvery(vec![3])));
        assert_eq!(parse_trace_every("1, 2,4"), Ok(TraceEvery(vec![1, 2, 4])));
        assert_eq!(parse_trace_every("1..6"), Ok(TraceEvery((1..=6).collect())));
        for bad in ["0", "-1", "1.5", "", "1,,2", "1..", "6..1", "1..1001", "2,2"] {
            assert!(parse_trace_every(bad).is_err(), "{bad:?} is refused");
        }
        assert!(parse_trace_every("0").unwrap_err().starts_with("`0` in `0`: expected a whole number"));
        assert_eq!(parse_trace_every("2,2").unwrap_err(), "`2,2`: 2 is given twice");
    }
}
