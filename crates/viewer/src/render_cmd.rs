//! `stereotrace render`: one stereo frame to PNG files (the eyes, the mask, where the right
//! eye differs from a full trace, each whole or cropped; the combined pair) and an optional
//! JSON report, or an animation of the orbit as numbered combined frames.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context, Result};
use serde_json::json;
use stereo::{compose, mask_image, Options, StereoFrame};
use tracer::{RayCounts, Tracer};

use crate::cli::RenderArgs;
use crate::reference::Reference;
use crate::report;
use crate::setup::{BadInput, FrameSetup};
use viewer::{parent_dir, write_png};

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
    let setup = FrameSetup::load(&args.frame, 1)?;
    let (w, h) = (args.frame.width, args.frame.height);
    let tracer = Tracer::new(&setup.scene, args.frame.time);
    let opts = Options { mode: args.mode, retrace_edges: args.retrace_edges };
    let mut frame = StereoFrame::new();
    let stats = frame.render(&tracer, &setup.camera, w, h, opts);

    // An eye image, or its --crop.
    let write_eye = |p: &Path, image: &[u32]| match args.crop {
        Some(c) => write_png(p, c.w, c.h, &c.apply(image, w)),
        None => write_png(p, w, h, image),
    };
    if let Some(p) = &args.left {
        write_eye(p, &frame.left().rgb)?;
    }
    if let Some(p) = &args.right {
        write_eye(p, &frame.right().rgb)?;
    }
    if let Some(p) = &args.mask {
        let mut mask = Vec::new();
        mask_image(frame.mask(), &mut mask);
        write_eye(p, &mask)?;
    }
    let mut reference = None;
    if args.diff.is_some() || args.json {
        let mut r = Reference::default();
        r.trace(&tracer, &setup.camera, w, h);
        reference = Some(r);
    }
    if let (Some(p), Some(r)) = (&args.diff, &reference) {
        let mut diff = Vec::new();
        r.difference(&frame.right().rgb, &mut diff);
        write_eye(p, &diff)?;
    }
    if let Some(p) = &args.out {
        let mut pair = Vec::new();
        compose(args.layout, args.swap_eyes, &frame.left().rgb, &frame.right().rgb, w, h, &mut pair);
        let (ow, oh) = args.layout.size(w, h);
        write_png(p, ow, oh, &pair)?;
    }
    if let (true, Some(reference)) = (args.json, &reference) {
        let q = reference.compare(&frame.right().rgb);
        let mut out = json!({
            "scene": setup.path.display().to_string(),
            "width": w,
            "height": h,
            "mode": args.mode.name(),
            "retrace_edges": args.retrace_edges,
            "ipd": shortest(setup.camera.ipd),
            "distance": shortest(setup.camera.distance),
            "depth": setup.scene.render.max_depth,
            "time": shortest(args.frame.time),
            "threads": rayon::current_num_threads(),
            "lanes": tracer::lane_width(),
            "quality": report::quality(&q),
        });
        if let (Some(o), serde_json::Value::Object(f)) = (out.as_object_mut(), report::frame(&stats)) {
            o.extend(f);
        }
        println!("{}", serde_json::to_string_pretty(&out)?);
    }
    Ok(())
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
    let setup = FrameSetup::load(&args.frame, 1)?;
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = Arc::clone(&stop);
        // If a handler is already installed (only in tests), Ctrl-C keeps its default.
        let _ = ctrlc::set_handler(move || stop.store(true, Ordering::SeqCst));
    }
    let (w, h) = (args.frame.width, args.frame.height);
    let (ow, oh) = args.layout.size(w, h);
    let opts = Options { mode: args.mode, retrace_edges: args.retrace_edges };
    let mut tracer = Tracer::new(&setup.scene, args.frame.time);
    let mut frame = StereoFrame::new();
    let mut pair = Vec::new();
    let (mut left_rays, mut right_rays) = (RayCounts::default(), RayCounts::default());
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
        tracer.update(&setup.scene, args.frame.time + k as f32 / args.fps);
        let stats = frame.render(&tracer, &setup.camera, w, h, opts);
        left_rays += stats.left.rays;
        right_rays += stats.right.rays;
        compose(args.layout, args.swap_eyes, &frame.left().rgb, &frame.right().rgb, w, h, &mut pair);
        write_png(&dir.join(format!("frame_{k:05}.png")), ow, oh, &pair)?;
        written += 1;
        bar.inc(1);
    }
    bar.finish_and_clear();
    let secs = start.elapsed().as_secs_f64();
    let interrupted = if written < frames { " (interrupted)" } else { "" };
    eprintln!(
        "wrote {written} of {frames} frames{interrupted}, {ow}×{oh} {} ({} mode), to {} in {secs:.1} s: {:.1} ms/frame; right eye {:.0}% of the left eye's rays",
        args.layout,
        args.mode,
        dir.display(),
        1e3 * secs / f64::from(written.max(1)),
        100.0 * right_rays.total() as f64 / left_rays.total().max(1) as f64,
    );
    if written < frames {
        anyhow::bail!("interrupted after {written} frames");
    }
    Ok(())
}

/// Fails before any work if an output's directory is missing.
fn check_output_dir(path: &Path) -> Result<()> {
    let dir = parent_dir(path);
    if dir.is_dir() {
        Ok(())
    } else {
        Err(BadInput(format!("{}: directory {} does not exist", path.display(), dir.display())).into())
    }
}
