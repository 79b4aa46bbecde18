//! Loading a scene and applying command-line overrides, with input errors kept apart from
//! other failures (exit code 2 vs 1), and the check that a frame fits in memory.
//!
//! The memory a frame may use is the host's `MemAvailable` (/proc/meminfo), or the number of
//! bytes in [`MEMORY_ENV`] when that is set: the one place the limit comes from, so tests
//! (and hosts whose /proc/meminfo misleads, such as some containers) can inject it.

use std::fmt;
use std::path::{Path, PathBuf};

use anyhow::Result;
use tracer::{Camera, LoadOptions, Scene, MAX_DEPTH_LIMIT};

use crate::args::FrameArgs;

/// Bad input from the user (an argument out of range): exit code 2, like a bad scene file.
#[derive(Debug)]
pub struct BadInput(pub String);

impl fmt::Display for BadInput {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BadInput {}

/// How a structure file given as the scene is read: `--assembly` and `--radius-scale S`
/// (S a finite number > 0).
pub fn load_options(assembly: bool, radius_scale: f32) -> Result<LoadOptions> {
    if !(radius_scale.is_finite() && radius_scale > 0.0) {
        return Err(BadInput(format!(
            "--radius-scale {radius_scale}: must be a finite number > 0 (1 for van der Waals spheres, 0.25 for CPK balls)"
        ))
        .into());
    }
    Ok(LoadOptions { assembly, radius_scale })
}

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
        Self::load_supersampled(args, frames_in_memory, 1)
    }

    /// As [`FrameSetup::load`] for a frame traced at `supersample` × `supersample` samples
    /// per pixel (`render --supersample`): the checks count the samples.
    pub fn load_supersampled(args: &FrameArgs, frames_in_memory: u64, supersample: u32) -> Result<Self> {
        let path = resolve_scene(&args.scene);
        let mut scene = args.look.apply(Scene::load_with(&path, load_options(args.assembly, args.radius_scale)?)?);
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
        let frame = Frame { width: args.width, height: args.height, supersample };
        frame.check_samples()?;
        check_memory(frame, frames_in_memory)?;
        Ok(Self { camera: scene.camera, scene, path })
    }
}

/// The timewarp's guard band around an eye traced at `size`: `share` of its width and of its
/// height beyond each side, rounded to whole samples (the viewer's and `timewarp`'s alike).
#[must_use]
pub fn guard_band((width, height): (u32, u32), share: f32) -> (u32, u32) {
    let band = |n: u32| (n as f32 * share).round() as u32;
    (band(width), band(height))
}

/// Checks `STEREOTRACE_LANES`: unset (the default, 8 lanes where the CPU has AVX2), or a
/// lane width this CPU has: `4` (the fallback), `8`, or `16` (AVX-512). Anything else is
/// refused rather than silently ignored.
pub fn check_lanes_env() -> Result<()> {
    let Some(v) = std::env::var_os(tracer::LANES_VAR) else { return Ok(()) };
    let asked = v.to_str().and_then(|v| v.trim().parse::<usize>().ok());
    match asked {
        Some(lanes) if tracer::simd_level_of(lanes).is_some() => Ok(()),
        Some(lanes) if tracer::LANE_WIDTHS.contains(&lanes) => Err(BadInput(format!(
            "{}={lanes}: this CPU has no {lanes}-lane instruction set ({}); it has {}",
            tracer::LANES_VAR,
            if lanes == 16 { "AVX-512" } else { "AVX2 and FMA" },
            widths_here()
        ))
        .into()),
        _ => Err(BadInput(format!(
            "{}={}: must be a lane width this CPU has ({}); unset it for the default",
            tracer::LANES_VAR,
            v.to_string_lossy(),
            widths_here()
        ))
        .into()),
    }
}

/// The lane widths this CPU has, as a list for a message: "4, 8 or 16".
fn widths_here() -> String {
    let here: Vec<String> =
        tracer::LANE_WIDTHS.iter().filter(|&&l| tracer::simd_level_of(l).is_some()).map(ToString::to_string).collect();
    match here.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => here.join(""),
    }
}

/// The environment variable that sets the memory available to a frame, in bytes, in place of
/// the host's `MemAvailable`.
pub const MEMORY_ENV: &str = "STEREOTRACE_MEMORY_AVAILABLE";

/// Bytes one eye-pixel costs across a stereo frame and its full-trace reference: colour,
/// depth, hit parameter and the visible-surface record for three films, plus the source
/// map and mask (177); and what temporal reuse keeps (31): both eyes' marks (12 bytes of
/// arc each, and their bits), the stage-3 classes, the last frame's sources and classes,
/// and the bits of the pixels made. With supersampling this is per sample: every stage runs
/// at the sampled size.
const BYTES_PER_PIXEL: u64 = 3 * (4 + 4 + 4 + 44) + 4 + 1 + 4 + (2 * 12 + 1 + 4 + 1 + 1);

/// Bytes a supersampled frame adds per output pixel: the filtered left eye, right eye and
/// reference (colour only).
const BYTES_PER_FILTERED_PIXEL: u64 = 3 * 4;

/// The size of one frame as the command line asks for it.
#[derive(Clone, Copy, Debug)]
struct Frame {
    /// Output width per eye, pixels.
    width: u32,
    /// Output height per eye, pixels.
    height: u32,
    /// Samples per pixel per axis.
    supersample: u32,
}

impl Frame {
    /// Samples per eye.
    fn samples(self) -> u64 {
        u64::from(self.width) * u64::from(self.height) * u64::from(self.supersample).pow(2)
    }

    /// Bytes one frame needs: [`BYTES_PER_PIXEL`] per sample, and with supersampling
    /// [`BYTES_PER_FILTERED_PIXEL`] per output pixel.
    fn bytes(self) -> u64 {
        let filtered = if self.supersample > 1 { u64::from(self.width) * u64::from(self.height) } else { 0 };
        self.samples() * BYTES_PER_PIXEL + filtered * BYTES_PER_FILTERED_PIXEL
    }

    /// The flags that set the size, as typed.
    fn flags(self) -> String {
        let s = if self.supersample > 1 { format!(" --supersample {}", self.supersample) } else { String::new() };
        format!("--width {} --height {}{s}", self.width, self.height)
    }

    /// Refuses an eye of `u32::MAX` samples or more, which the reprojection's source map
    /// cannot name (only reachable with supersampling: 16384 × 16384 × 4 × 4).
    fn check_samples(self) -> Result<()> {
        if self.samples() >= u64::from(u32::MAX) {
            let (w, h) = (
                u64::from(self.width) * u64::from(self.supersample),
                u64::from(self.height) * u64::from(self.supersample),
            );
            return Err(BadInput(format!(
                "{}: {w} × {h} samples per eye; an eye must have fewer than {} samples",
                self.flags(),
                u32::MAX
            ))
            .into());
        }
        Ok(())
    }
}

/// Refuses, before allocating anything, a frame that cannot fit in the memory available.
fn check_memory(frame: Frame, frames: u64) -> Result<()> {
    fits_in_memory(frame, frames, available_memory()?)
}

/// Whether `frames` frames fit in `available` bytes (`None`: no limit known).
fn fits_in_memory(frame: Frame, frames: u64, available: Option<u64>) -> Result<()> {
    let need = frame.bytes().saturating_mul(frames.max(1));
    let available = available.unwrap_or(u64::MAX);
    if need > available {
        let gib = |b: u64| b as f64 / f64::from(1u32 << 30);
        return Err(BadInput(format!(
            "{}: the frame needs {:.1} GiB but only {:.1} GiB of memory is available",
            frame.flags(),
            gib(need),
            gib(available)
        ))
        .into());
    }
    Ok(())
}

/// Bytes the viewer's render worker needs for a frame traced at `samples` and shown at `out`
/// (per eye): [`BYTES_PER_PIXEL`] and the three rotating copies of the class mask (1 byte
/// each) per sample, and per shown pixel the three copies of the left eye, right eye, mask
/// overlay and anaglyph plus the filtered reference (4 bytes each).
#[must_use]
pub fn viewer_frame_bytes(samples: (u32, u32), out: (u32, u32)) -> u64 {
    let pixels = |(w, h): (u32, u32)| u64::from(w) * u64::from(h);
    pixels(samples) * (BYTES_PER_PIXEL + 3) + pixels(out) * (3 * 4 * 4 + 4)
}

/// Whether the viewer may trace a frame at `samples` to show it at `out`: fewer than
/// `u32::MAX` samples per eye, and [`viewer_frame_bytes`] within `available` (`None`: no
/// limit known).
#[must_use]
pub fn viewer_frame_fits(samples: (u32, u32), out: (u32, u32), available: Option<u64>) -> bool {
    u64::from(samples.0) * u64::from(samples.1) < u64::from(u32::MAX)
        && available.is_none_or(|a| viewer_frame_bytes(samples, out) <= a)
}

/// The memory available: [`MEMORY_ENV`] if set, else `MemAvailable` from /proc/meminfo where
/// there is one.
pub fn available_memory() -> Result<Option<u64>> {
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

/// Fails before any work if an output's directory is missing.
pub fn check_output_dir(path: &Path) -> Result<()> {
    let dir = viewer::parent_dir(path);
    if dir.is_dir() {
        Ok(())
    } else {
        Err(BadInput(format!("{}: directory {} does not exist", path.display(), dir.display())).into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(width: u32, height: u32, supersample: u32) -> Frame {
        Frame { width, height, supersample }
    }

    #[test]
    fn a_frame_fits_up_to_the_last_byte() {
        let need = 64 * 64 * BYTES_PER_PIXEL;
        assert!(fits_in_memory(frame(64, 64, 1), 1, Some(need)).is_ok(), "exactly enough");
        assert!(fits_in_memory(frame(64, 64, 1), 1, None).is_ok(), "no limit known");
        let e = fits_in_memory(frame(64, 64, 1), 1, Some(need - 1)).unwrap_err();
        assert!(e.downcast_ref::<BadInput>().is_some(), "bad input, exit 2: {e}");
        let e = fits_in_memory(frame(16_384, 16_384, 1), 1, Some(16 << 30)).unwrap_err().to_string();
        assert_eq!(
            e, "--width 16384 --height 16384: the frame needs 52.0 GiB but only 16.0 GiB of memory is available",
            "the message names the flags and both sizes"
        );
        assert!(fits_in_memory(frame(64, 64, 1), 2, Some(need)).is_err(), "two frames need twice as much");
    }

    #[test]
    fn supersampling_counts_every_sample_and_the_filtered_eyes() {
        // 64 × 64 at S = 2: 128 × 128 samples at 208 bytes, and 64 × 64 filtered pixels of the
        // left, right and reference images at 4 bytes each.
        assert_eq!(BYTES_PER_PIXEL, 208);
        let need = 128 * 128 * 208 + 64 * 64 * 12;
        assert_eq!(frame(64, 64, 2).bytes(), need);
        assert!(fits_in_memory(frame(64, 64, 2), 1, Some(need)).is_ok(), "exactly enough");
        let e = fits_in_memory(frame(64, 64, 2), 1, Some(need - 1)).unwrap_err().to_string();
        assert!(e.starts_with("--width 64 --height 64 --supersample 2: the frame needs"), "{e}");
        assert_eq!(frame(64, 64, 4).samples(), 256 * 256);
    }

    #[test]
    fn the_viewer_supersamples_only_what_fits() {
        // 8 × 4 shown, 16 × 8 traced: 128 samples at 211 bytes, 32 pixels at 52.
        assert_eq!(viewer_frame_bytes((16, 8), (8, 4)), 128 * 211 + 32 * 52);
        let need = viewer_frame_bytes((16, 8), (8, 4));
        assert!(viewer_frame_fits((16, 8), (8, 4), Some(need)), "exactly enough");
        assert!(!viewer_frame_fits((16, 8), (8, 4), Some(need - 1)), "one byte short");
        assert!(viewer_frame_fits((16, 8), (8, 4), None), "no limit known");
        assert!(!viewer_frame_fits((65_536, 65_536), (32_768, 32_768), None), "u32::MAX samples never fit");
    }

    #[test]
    fn an_eye_of_u32_max_samples_is_refused() {
        assert!(frame(16_384, 16_384, 3).check_samples().is_ok(), "49152² = 2415919104 samples");
        let e = frame(16_384, 16_384, 4).check_samples().unwrap_err();
        assert!(e.downcast_ref::<BadInput>().is_some(), "bad input, exit 2: {e}");
        assert_eq!(
            e.to_string(),
            "--width 16384 --height 16384 --supersample 4: 65536 × 65536 samples per eye; an eye must have fewer than 4294967295 samples"
        );
        assert!(frame(16_384, 16_384, 1).check_samples().is_ok());
    }
}
