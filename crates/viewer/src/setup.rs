//! Loading a scene and applying command-line overrides, with input errors kept apart from
//! other failures (exit code 2 vs 1), and the check that a frame fits in memory.
//!
//! The memory a frame may use is the host's `MemAvailable` (/proc/meminfo), or the number of
//! bytes in [`MEMORY_ENV`] when that is set: the one place the limit comes from, so tests
//! (and hosts whose /proc/meminfo misleads, such as some containers) can inject it.

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

/// Checks `STEREOTRACE_LANES`: unset, or `4` to force the tracer's 4-lane SIMD fallback.
/// Anything else is refused rather than silently ignored.
pub fn check_lanes_env() -> Result<()> {
    match std::env::var_os(tracer::LANES_VAR) {
        None => Ok(()),
        Some(v) if v.to_str().is_some_and(|v| v.trim() == "4") => Ok(()),
        Some(v) => Err(BadInput(format!(
            "{}={}: must be 4 (the 4-lane fallback); unset it to use the widest lanes the CPU has",
            tracer::LANES_VAR,
            v.to_string_lossy()
        ))
        .into()),
    }
}

/// The environment variable that sets the memory available to a frame, in bytes, in place of
/// the host's `MemAvailable`.
pub const MEMORY_ENV: &str = "STEREOTRACE_MEMORY_AVAILABLE";

/// Bytes one eye-pixel costs across a stereo frame and its full-trace reference: colour,
/// depth, hit parameter and the visible-surface record for three films, plus the source
/// map and mask.
const BYTES_PER_PIXEL: u64 = 3 * (4 + 4 + 4 + 44) + 4 + 1 + 4;

/// Refuses, before allocating anything, a frame that cannot fit in the memory available.
fn check_memory(width: u32, height: u32, frames: u64) -> Result<()> {
    fits_in_memory(width, height, frames, available_memory()?)
}

/// Whether `frames` frames of `width` × `height` eyes fit in `available` bytes (`None`: no
/// limit known).
fn fits_in_memory(width: u32, height: u32, frames: u64, available: Option<u64>) -> Result<()> {
    let need = u64::from(width) * u64::from(height) * BYTES_PER_PIXEL * frames.max(1);
    let available = available.unwrap_or(u64::MAX);
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

/// The memory available: [`MEMORY_ENV`] if set, else `MemAvailable` from /proc/meminfo where
/// there is one.
fn available_memory() -> Result<Option<u64>> {
    match std::env::var(MEMORY_ENV) {
        Ok(v) => v
            .trim()
            .parse()
            .map(Some)
            .map_err(|_| BadInput(format!("{MEMORY_ENV}={v}: must be a whole number of bytes")).into()),
        Err(std::env::VarError::NotPresent) => Ok(meminfo_available()),
        Err(std::env::VarError::NotUnicode(v)) => {
            Err(BadInput(format!("{MEMORY_ENV}={}: must be a whole number of bytes", v.to_string_lossy())).into())
        }
    }
}

/// `MemAvailable` from /proc/meminfo, where there is one.
fn meminfo_available() -> Option<u64> {
    let info = std::fs::read_to_string("/proc/meminfo").ok()?;
    let line = info.lines().find(|l| l.starts_with("MemAvailable:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_frame_fits_up_to_the_last_byte() {
        let need = 64 * 64 * BYTES_PER_PIXEL;
        assert!(fits_in_memory(64, 64, 1, Some(need)).is_ok(), "exactly enough");
        assert!(fits_in_memory(64, 64, 1, None).is_ok(), "no limit known");
        let e = fits_in_memory(64, 64, 1, Some(need - 1)).unwrap_err();
        assert!(e.downcast_ref::<BadInput>().is_some(), "bad input, exit 2: {e}");
        let e = fits_in_memory(16_384, 16_384, 1, Some(16 << 30)).unwrap_err().to_string();
        assert_eq!(
            e, "--width 16384 --height 16384: the frame needs 44.2 GiB but only 16.0 GiB of memory is available",
            "the message names the flags and both sizes"
        );
        assert!(fits_in_memory(64, 64, 2, Some(need)).is_err(), "two frames need twice as much");
    }
}
