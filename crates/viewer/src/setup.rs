//! Loading a scene and applying command-line overrides, with input errors kept apart from
//! other failures (exit code 2 vs 1).

use std::fmt;
use std::path::{Path, PathBuf};

use anyhow::Result;
use tracer::{Camera, Scene, MAX_DEPTH_LIMIT};

use crate::cli::FrameArgs;

/// Bad input from the user (an argument out of range): exit code 2, like a bad scene file.
#[derive(Debug)]
pub struct BadInput(pub String);

impl fmt::Display for BadInput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BadInput {}

/// Finds a scene file. A relative path is looked up in the current directory first, then
/// in the workspace root, so `cargo run` and the bundled scenes work from any directory.
/// A path found nowhere is returned as given, so the error names what the user typed.
#[must_use]
pub fn resolve_scene(path: &Path) -> PathBuf {
    if path.is_absolute() || path.exists() {
        return path.to_path_buf();
    }
    let in_workspace = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join(path);
    if in_workspace.exists() {
        in_workspace
    } else {
        path.to_path_buf()
    }
}

/// A loaded scene with the command line's overrides applied.
pub struct FrameSetup {
    /// The scene as loaded, with `render.max_depth` overridden.
    pub scene: Scene,
    /// The camera with `ipd` and `distance` overridden.
    pub camera: Camera,
    /// Where the scene came from.
    pub path: PathBuf,
}

impl FrameSetup {
    /// Loads `args.scene` and applies the overrides; checks the frame fits in memory.
    pub fn load(args: &FrameArgs, frames_in_memory: u64) -> Result<Self> {
        let path = resolve_scene(&args.scene);
        let mut scene = Scene::load(&path)?;
        if let Some(ipd) = args.ipd {
            if !(ipd.is_finite() && ipd >= 0.0) {
                return Err(BadInput(format!("--ipd {ipd}: must be a finite number ≥ 0")).into());
            }
            scene.camera.ipd = ipd;
        }
        if let Some(d) = args.distance {
            if !(d.is_finite() && d > 0.0) {
                return Err(BadInput(format!("--distance {d}: must be a finite number > 0")).into());
            }
            scene.camera.distance = d;
        }
        if let Some(depth) = args.depth {
            if depth > MAX_DEPTH_LIMIT {
                return Err(BadInput(format!("--depth {depth}: must be 0 to {MAX_DEPTH_LIMIT}")).into());
            }
            scene.render.max_depth = depth;
        }
        if !args.time.is_finite() {
            return Err(BadInput(format!("--time {}: must be a finite number of seconds", args.time)).into());
        }
        check_memory(args.width, args.height, frames_in_memory)?;
        Ok(Self { camera: scene.camera, scene, path })
    }
}

/// Bytes one eye-pixel costs across a stereo frame and its full-trace reference: colour,
/// depth and the visible-surface record for three films, plus the source map and mask.
const BYTES_PER_PIXEL: u64 = 3 * (4 + 4 + 44) + 4 + 1 + 4;

/// Refuses, before allocating anything, a frame that cannot fit in the memory available.
fn check_memory(width: u32, height: u32, frames: u64) -> Result<()> {
    let need = u64::from(width) * u64::from(height) * BYTES_PER_PIXEL * frames.max(1);
    let available = available_memory().unwrap_or(u64::MAX);
    if need > available {
        let gib = |b: u64| b as f64 / f64::from(1u32 << 30);
        return Err(BadInput(format!(
            "--width {width} --height {height}: the frame needs {:.1} GiB but only {:.1} GiB of memory is available",
            gib(need),
            gib(available)
        ))
        .into());
    }
    Ok(())
}

/// `MemAvailable` from /proc/meminfo, where there is one.
fn available_memory() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}
