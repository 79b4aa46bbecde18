//! # stereotrace-tests — end-to-end checks across the crates
//!
//! Golden images of the seed scene (colour and mask) and whole-scene quality checks over
//! every file in `assets/scenes`. Tests that run the `stereotrace` binary itself (the CLI and
//! the window smoke test) live in `crates/viewer/tests`, because Cargo only hands a binary's
//! path (`CARGO_BIN_EXE_*`) to tests of the binary's own package.
//!
//! [`assert_golden`] compares an image with `assets/golden/<name>.png` at a per-channel
//! tolerance. On failure it writes `<name>.new.png` (what was rendered) and `<name>.diff.png`
//! (white where a channel is off by more than the tolerance) beside the golden file and
//! names the first failing pixel. `STEREOTRACE_BLESS=1` rewrites the golden files instead.

use std::fs::File;
use std::path::{Path, PathBuf};

/// The workspace root.
#[must_use]
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// Every scene file in `assets/scenes`, sorted.
#[must_use]
pub fn scene_files() -> Vec<PathBuf> {
    let dir = root().join("assets/scenes");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap_or_else(|e| panic!("{}: {e}", dir.display())).path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    v
}

/// Reads an 8-bit RGB PNG as `0x00RRGGBB` pixels.
pub fn read_png(path: &Path) -> Result<(u32, u32, Vec<u32>), String> {
    let file = File::open(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
    decoder.set_transformations(png::Transformations::EXPAND | png::Transformations::STRIP_16);
    let mut reader = decoder.read_info().map_err(|e| format!("{}: {e}", path.display()))?;
    let mut buf = vec![0; reader.output_buffer_size().ok_or("image too large")?];
    let info = reader.next_frame(&mut buf).map_err(|e| format!("{}: {e}", path.display()))?;
    let channels = info.color_type.samples();
    if channels < 3 {
        return Err(format!("{}: expected an RGB image", path.display()));
    }
    let px = buf[..info.buffer_size()]
        .chunks_exact(channels)
        .map(|c| (u32::from(c[0]) << 16) | (u32::from(c[1]) << 8) | u32::from(c[2]))
        .collect();
    Ok((info.width, info.height, px))
}

/// Writes `0x00RRGGBB` pixels as an 8-bit RGB PNG with the binary's writer
/// ([`viewer::write_png`]), panicking on failure: a test's failure report.
pub fn write_png(path: &Path, width: u32, height: u32, pixels: &[u32]) {
    viewer::write_png(path, width, height, pixels).unwrap_or_else(|e| panic!("{e:#}"));
}

/// Compares an image with its golden file; see the crate docs. `tolerance` is in 8-bit
/// levels per channel; `max_share_over` is the share of pixels allowed beyond it (for
/// libm differences between machines), 0 for none.
pub fn assert_golden(name: &str, width: u32, height: u32, pixels: &[u32], tolerance: u8, max_share_over: f64) {
    let dir = root().join("assets/golden");
    let golden = dir.join(format!("{name}.png"));
    if std::env::var_os("STEREOTRACE_BLESS").is_some() {
        write_png(&golden, width, height, pixels);
        eprintln!("blessed {}", golden.display());
        return;
    }
    let new = dir.join(format!("{name}.new.png"));
    let diff_path = dir.join(format!("{name}.diff.png"));
    let (gw, gh, expected) = read_png(&golden).unwrap_or_else(|e| {
        write_png(&new, width, height, pixels);
        panic!("{e}\nwrote {}; run with STEREOTRACE_BLESS=1 to accept it", new.display())
    });
    if (gw, gh) != (width, height) {
        write_png(&new, width, height, pixels);
        panic!("{name}: golden is {gw}×{gh}, rendered {width}×{height}; wrote {}", new.display());
    }
    let mut first = None;
    let mut over = 0usize;
    let diff: Vec<u32> = pixels
        .iter()
        .zip(&expected)
        .enumerate()
        .map(|(k, (&a, &b))| {
            let worst = [16, 8, 0].iter().map(|s| ((a >> s) as u8).abs_diff((b >> s) as u8)).max().unwrap_or(0);
            if worst > tolerance {
                over += 1;
                first.get_or_insert((k, a, b, worst));
                0x00FF_FFFF
            } else {
                0
            }
        })
        .collect();
    let share = over as f64 / pixels.len().max(1) as f64;
    if share > max_share_over {
        write_png(&new, width, height, pixels);
        write_png(&diff_path, width, height, &diff);
        let (k, a, b, worst) = first.unwrap_or_default();
        panic!(
            "{name}: {over} pixels ({:.3}%) differ by more than {tolerance} levels (allowed {:.3}%); first at ({}, {}): rendered #{a:06x}, golden #{b:06x}, off by {worst}\nwrote {} and {}",
            100.0 * share,
            100.0 * max_share_over,
            k % width as usize,
            k / width as usize,
            new.display(),
            diff_path.display()
        );
    }
    let _ = std::fs::remove_file(&new);
    let _ = std::fs::remove_file(&diff_path);
}
