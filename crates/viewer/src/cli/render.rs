//! `stereotrace render`: one stereo frame to PNG files (the eyes, the mask, where the right
//! eye differs from a full trace, each whole or cropped; the combined pair) and an optional
//! JSON report, or an animation of the orbit as numbered combined frames.
//!
//! With `--supersample S` every stage runs at (W·S) × (H·S) samples and the eyes are
//! filtered down to W × H ([`stereo::downsample`]: a box filter in linear light) before they
//! are written or measured. The mask PNG stays at the sampled size, one pixel per sample
//! (its `--crop` scaled by S), as the report's ray and pixel counts do; `quality` and
//! `--diff` compare the filtered right eye with a full trace filtered alike,
//! `quality_samples` the samples themselves. The scene's outlines (`--outline PX`) are
//! drawn on each eye's samples, PX × S samples wide, before the filter; `quality` is
//! measured without them, as the reference has none.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context, Result};
use serde_json::json;
use stereo::{compose, downsample, mask_image, Options, Outlined, Quality, StereoFrame};
use tracer::{RayCounts, Tracer};

use crate::args::RenderArgs;
use crate::cli::report;
use crate::reference::Reference;
use crate::setup::{check_output_dir, BadInput, FrameSetup};
use viewer::write_png;

/// Runs the command.
pub fn run(args: &RenderArgs) -> Result<()> {
    if let (Some(frames), Some(dir)) = (args.frames, &args.out_dir) {
        return animate(args, frames, dir);
    }
    if [&args.left, &args.right, &args.mask, &args.diff, &args.out].iter().all(|p| p.is_none()) && !args.json {
        return Err(BadInput(
            "nothing to do: give --left, --right, --mask, --diff, --out, --json or --frames with --out-dir".into(),
        )
        .into());
    }
    for path in [&args.left, &args.right, &args.mask, &args.diff, &args.out].into_iter().flatten() {
        check_output_dir(path)?;
    }
    if let Some(c) = args.crop {
        if !c.fits(args.frame.width, args.frame.height) {
            return Err(BadInput(format!(
                "--crop {c}: the rectangle must lie inside the {}×{} eye image",
                args.frame.width, args.frame.height
            ))
            .into());
        }
    }
    let started = Instant::now();
    let setup = FrameSetup::load_supersampled(&args.frame, 1, args.supersample)?;
    let loaded = started.elapsed();
    let size = Sizes::of(args);
    let (w, h) = size.out;
    let tracer = Tracer::new(&setup.scene, args.frame.time);
    let built = started.elapsed().saturating_sub(loaded);
    let opts = Options { mode: args.mode, retrace_edges: args.retrace_edges };
    let mut frame = StereoFrame::new();
    // Outlines read each eye's first hits: kept by the frame, no pass of their own where
    // the eye's pass makes them (`StereoFrame::set_depths`).
    frame.set_depths(size.outline(&setup) > 0.0);
    let stats = frame.render(&tracer, &setup.camera, size.samples.0, size.samples.1, opts);
    let mut outlined = Outlined::new();
    let mut filtered = Filtered::default();
    let (left, right) = filtered.eyes(outlined.eyes(&tracer, &frame, size.outline(&setup)), size);

    // An eye image, or its --crop.
    let write_eye = |p: &Path, image: &[u32]| match args.crop {
        Some(c) => write_png(p, c.w, c.h, &c.apply(image, w)),
        None => write_png(p, w, h, image),
    };
    if let Some(p) = &args.left {
        write_eye(p, left)?;
    }
    if let Some(p) = &args.right {
        write_eye(p, right)?;
    }
    if let Some(p) = &args.mask {
        let mut mask = Vec::new();
        mask_image(frame.mask(), &mut mask);
        match args.crop {
            Some(c) => {
                let s = args.supersample;
                let c = crate::crop::Crop { x: c.x * s, y: c.y * s, w: c.w * s, h: c.h * s };
                write_png(p, c.w, c.h, &c.apply(&mask, size.samples.0))?;
            }
            None => write_png(p, size.samples.0, size.samples.1, &mask)?,
        }
    }
    let mut reference = None;
    if args.diff.is_some() || args.json {
        let mut r = Reference::default();
        r.trace(&tracer, &setup.camera, size.samples.0, size.samples.1);
        reference = Some(r);
    }
    if let (Some(p), Some(r)) = (&args.diff, &mut reference) {
        let mut diff = Vec::new();
        r.difference_filtered(right, (size.samples, size.out), &mut diff);
        write_eye(p, &diff)?;
    }
    if let Some(p) = &args.out {
        let mut pair = Vec::new();
        compose(args.layout, args.swap_eyes, left, right, w, h, &mut pair);
        let (ow, oh) = args.layout.size(w, h);
        write_png(p, ow, oh, &pair)?;
    }
    if let (true, Some(reference)) = (args.json, &mut reference) {
        // Measured before the outlines, which the reference has not.
        let per_sample = reference.compare(&frame.right().rgb);
        let mut plain = Filtered::default();
        let right = plain.eyes([&frame.left().rgb, &frame.right().rgb], size).1;
        let q = reference.compare_filtered(right, size.samples, size.out);
        let cost = Cost { load: loaded, build: built, memory: report::memory(&tracer.memory(), frame.bins_memory()) };
        print_report(args, (&setup, size), (&stats, &q, &per_sample), &cost)?;
    }
    Ok(())
}

/// What a scene cost before its frame: reading it, building its tracer, and the memory
/// that grows with it.
struct Cost {
    load: std::time::Duration,
    build: std::time::Duration,
    memory: serde_json::Value,
}

/// `--json`: the frame report on stdout.
fn print_report(
    args: &RenderArgs,
    (setup, size): (&FrameSetup, Sizes),
    (stats, q, per_sample): (&stereo::FrameStats, &Quality, &Quality),
    cost: &Cost,
) -> Result<()> {
    let (w, h) = size.out;
    let mut out = json!({
        "scene": setup.path.display().to_string(),
        "width": w,
        "height": h,
        "supersample": args.supersample,
        "sample_width": size.samples.0,
        "sample_height": size.samples.1,
        "mode": args.mode.name(),
        "retrace_edges": args.retrace_edges,
        "ipd": shortest(setup.camera.ipd),
        "distance": shortest(setup.camera.distance),
        "depth": setup.scene.render.max_depth,
        "time": shortest(args.frame.time),
        "threads": rayon::current_num_threads(),
        "lanes": tracer::lane_width(),
        "spheres": setup.scene.sphere_count(),
        "load_ms": cost.load.as_secs_f64() * 1e3,
        "build_ms": cost.build.as_secs_f64() * 1e3,
        "memory": cost.memory.clone(),
        "quality": report::quality(q),
        "quality_samples": report::quality(per_sample),
    });
    if let (Some(o), serde_json::Value::Object(f)) = (out.as_object_mut(), report::frame(stats)) {
        o.extend(f);
    }
    super::print_out(&(serde_json::to_string_pretty(&out)? + "\n"))?;
    Ok(())
}

/// An eye's output size and the size it is traced at.
#[derive(Clone, Copy, Debug)]
struct Sizes {
    /// Width and height of the images written, per eye.
    out: (u32, u32),
    /// Width and height traced: `out` × `--supersample`.
    samples: (u32, u32),
}

impl Sizes {
    fn of(args: &RenderArgs) -> Self {
        let (w, h, s) = (args.frame.width, args.frame.height, args.supersample);
        // FrameSetup::load_supersampled checked that an eye has fewer than u32::MAX samples.
        Self { out: (w, h), samples: (w * s, h * s) }
    }

    /// The scene's outline width in samples: its width in pixels of the image times the
    /// supersampling (drawn on the samples, before the filter).
    fn outline(self, setup: &FrameSetup) -> f32 {
        (setup.scene.render.cues.outline * (self.samples.0 / self.out.0.max(1))) as f32
    }
}

/// The eyes filtered down to the output size, kept from frame to frame.
#[derive(Debug, Default)]
struct Filtered {
    left: Vec<u32>,
    right: Vec<u32>,
}

impl Filtered {
    /// A frame's left and right images (`eyes`, at the sampled size) at the output size:
    /// themselves without supersampling, else filtered into these buffers.
    fn eyes<'a>(&'a mut self, [left, right]: [&'a [u32]; 2], size: Sizes) -> (&'a [u32], &'a [u32]) {
        if size.samples == size.out {
            return (left, right);
        }
        downsample(left, size.samples, &mut self.left, size.out);
        downsample(right, size.samples, &mut self.right, size.out);
        (&self.left, &self.right)
    }
}

/// An f32 as the f64 with the same shortest decimal form (0.65, not 0.6499999761581421).
fn shortest(v: f32) -> f64 {
    v.to_string().parse().unwrap_or(f64::from(v))
}

/// `--frames N --out-dir DIR`: the orbit as numbered combined frames, with a progress bar.
/// Ctrl-C stops after the frame being written, so only whole files are left.
fn animate(args: &RenderArgs, frames: u32, dir: &Path) -> Result<()> {
    if !(args.fps.is_finite() && args.fps > 0.0) {
        return Err(BadInput(format!("--fps {}: must be a number > 0", args.fps)).into());
    }
    let setup = FrameSetup::load_supersampled(&args.frame, 1, args.supersample)?;
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = Arc::clone(&stop);
        // If a handler is already installed (only in tests), Ctrl-C keeps its default.
        let _ = ctrlc::set_handler(move || stop.store(true, Ordering::SeqCst));
    }
    let size = Sizes::of(args);
    let (w, h) = size.out;
    let (ow, oh) = args.layout.size(w, h);
    let opts = Options { mode: args.mode, retrace_edges: args.retrace_edges };
    let mut tracer = Tracer::new(&setup.scene, args.frame.time);
    let mut frame = StereoFrame::new();
    // Only the scene time moves: each frame retraces what can have changed (`--no-reuse`:
    // everything), the same bytes either way.
    frame.set_reuse((!args.no_reuse).then_some(&setup.scene));
    // (As for one frame: the outlines read the planes the frame keeps.)
    frame.set_depths(size.outline(&setup) > 0.0);
    let mut filtered = Filtered::default();
    let mut outlined = Outlined::new();
    let mut pair = Vec::new();
    let (mut left_rays, mut right_rays) = (RayCounts::default(), RayCounts::default());
    let (mut made, mut pixels) = (0u64, 0u64);
    let bar = indicatif::ProgressBar::new(u64::from(frames)).with_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} frames, {per_sec}, eta {eta}",
        )
        .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let start = Instant::now();
    let mut written = 0;
    for k in 0..frames {
        if stop.load(Ordering::SeqCst) {
            break;
        }
        tracer.advance(&setup.scene, args.frame.time + k as f32 / args.fps);
        let stats = frame.render(&tracer, &setup.camera, size.samples.0, size.samples.1, opts);
        left_rays += stats.left.rays;
        right_rays += stats.right.rays;
        (made, pixels) = (made + stats.reuse.made, pixels + stats.reuse.pixels);
        let (left, right) = filtered.eyes(outlined.eyes(&tracer, &frame, size.outline(&setup)), size);
        compose(args.layout, args.swap_eyes, left, right, w, h, &mut pair);
        write_png(&dir.join(format!("frame_{k:05}.png")), ow, oh, &pair)?;
        written += 1;
        bar.inc(1);
    }
    bar.finish_and_clear();
    let secs = start.elapsed().as_secs_f64();
    let interrupted = if written < frames { " (interrupted)" } else { "" };
    eprintln!(
        "wrote {written} of {frames} frames{interrupted}, {ow}×{oh} {} ({} mode), to {} in {secs:.1} s: {:.1} ms/frame; right eye {:.0}% of the left eye's rays; {:.1}% of the pixels traced ({})",
        args.layout,
        args.mode,
        dir.display(),
        1e3 * secs / f64::from(written.max(1)),
        100.0 * right_rays.total() as f64 / left_rays.total().max(1) as f64,
        100.0 * made as f64 / pixels.max(1) as f64,
        if args.no_reuse { "reuse off" } else { "the rest kept from the frame before" },
    );
    if written < frames {
        anyhow::bail!("interrupted after {written} frames");
    }
    Ok(())
}
