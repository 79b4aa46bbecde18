//! PNG (and other file) output that never leaves a half-written file: write to a temporary
//! file beside the target, then rename it into place.

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use anyhow::{Context, Result};

/// Writes `pixels` (`0x00RRGGBB`, row-major) as an 8-bit sRGB PNG at `path`, atomically.
pub fn write_png(path: &Path, width: u32, height: u32, pixels: &[u32]) -> Result<()> {
    assert_eq!(pixels.len(), width as usize * height as usize, "pixel count does not match the size");
    write_atomically(path, |tmp| write_file(tmp, width, height, pixels))
}

/// Writes `bytes` (a CSV, an SVG) to `path`, atomically, like [`write_png`].
pub fn write_bytes(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomically(path, |tmp| std::fs::write(tmp, bytes).with_context(|| format!("cannot create {}", tmp.display())))
}

/// Lets `write` make a temporary file beside `path`, then renames it into place; removes it
/// if anything fails.
fn write_atomically(path: &Path, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    let dir = parent_dir(path);
    if !dir.is_dir() {
        anyhow::bail!("cannot write {}: directory {} does not exist", path.display(), dir.display());
    }
    let name = path.file_name().with_context(|| format!("cannot write {}: not a file name", path.display()))?;
    let tmp = dir.join(format!(".{}.{}.tmp", name.to_string_lossy(), std::process::id()));
    let result = write(&tmp).and_then(|()| {
        std::fs::rename(&tmp, path).with_context(|| format!("cannot move {} into place", path.display()))
    });
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.with_context(|| format!("cannot write {}", path.display()))
}

/// The directory a file will be written into (`.` for a bare file name).
#[must_use]
pub fn parent_dir(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

fn write_file(tmp: &Path, width: u32, height: u32, pixels: &[u32]) -> Result<()> {
    let file = File::create(tmp).with_context(|| format!("cannot create {}", tmp.display()))?;
    let mut encoder = png::Encoder::new(BufWriter::new(file), width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    let mut writer = encoder.write_header()?;
    let bytes: Vec<u8> = pixels.iter().flat_map(|&p| tracer::unpack_rgb(p)).collect();
    writer.write_image_data(&bytes)?;
    writer.finish()?;
    Ok(())
}
