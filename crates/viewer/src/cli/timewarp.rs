//! `stereotrace timewarp`: what the viewer's timewarp buys, measured headless. A head moves
//! at constant speed from the scene's pose (`--motion`, `motion.rs`); the display shows
//! `--display-hz` frames a second, and a stereo frame is traced every `--trace-every` N of
//! them, at that display frame's pose. Every displayed frame k shows the last traced frame,
//! `k mod N` display frames old, made for pose k by each warp method:
//!
//! - `none`: the traced frame as it is, at the pose it was traced for (no timewarp);
//! - `rotation`: a depth-less timewarp, the rotation of the classic ATW (van Waveren 2016):
//!   [`stereo::Warp`] with every pixel at infinity, so the picture turns with the head and
//!   ignores its translation;
//! - `depth`: the viewer's timewarp, [`stereo::Warp`] by each eye's depth (6-DoF).
//!
//! Each is scored, both eyes together, against a stereo frame traced at pose k in the same
//! `--mode`: the frame the tracer would have shown had it kept up, so that the score is what
//! the warp loses and nothing else (a warp to the traced pose is that frame bit for bit). The
//! frames are traced as the viewer's worker traces them for its timewarp
//! (`window/worker.rs`): with a guard band (`--guard-band`, the viewer's 5 % by default) and
//! each eye's colour and depth; the warp reads the pair with the views it was traced through
//! ([`StereoFrame::warp_sources`]) and turns the head into the band, and only the shown part
//! is scored. The scene time stays at `--time`: only the head moves.
//!
//! The medians (`--json`, the table) are over the displayed frames. Ctrl-C stops after the
//! displayed frame being measured; the rows done are still written.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

use anyhow::Result;
use serde_json::Value;
use stereo::{Options, Quality, StereoFrame, Warp, WarpClass, WarpCounts, WarpSource};
use tracer::{Camera, Tracer};

use crate::args::TimewarpArgs;
use crate::cli::age_plot::AgeFigure;
use crate::cli::plot;
use crate::crop::Crop;
use crate::setup::{self, BadInput, FrameSetup};
use viewer::write_bytes;

/// Longest `--seconds` accepted.
pub const MAX_SECONDS: f64 = 60.0;

/// The warp methods, in the order of the rows, the table and the JSON.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Method {
    /// The traced frame as it is.
    None,
    /// The warp with every pixel at infinity: the rotation alone.
    Rotation,
    /// The warp by depth.
    Depth,
}

impl Method {
    const ALL: [Method; 3] = [Method::None, Method::Rotation, Method::Depth];

    fn name(self) -> &'static str {
        match self {
            Method::None => "none",
            Method::Rotation => "rotation",
            Method::Depth => "depth",
        }
    }
}

/// The CSV's header.
const HEADER: &str =
    "trace_every,frame,age_frames,age_ms,method,psnr_db,share_over_2_255,share_not_identical,hole_share,ms";

/// One displayed frame shown by one method, scored: a CSV row.
#[derive(Clone, Copy, Debug)]
struct Row {
    trace_every: u32,
    /// The displayed frame, from 0.
    frame: u32,
    /// Display frames since the frame shown was traced.
    age: u32,
    method: Method,
    /// Both eyes against the trace at the frame's pose.
    quality: Quality,
    /// Both eyes' pixels the warp had no pixel of their own eye for (0 for `none`).
    hole_share: f64,
    /// Wall time of the warp of both eyes, ms (0 for `none`).
    ms: f64,
}

/// One `--trace-every` value's frames.
struct Run {
    trace_every: u32,
    rows: Vec<Row>,
    /// Wall time of each displayed frame's reference trace (a stereo frame at the eye size).
    trace_ms: Vec<f64>,
    /// Wall time of each traced frame (with the guard band and both eyes' depths).
    banded_ms: Vec<f64>,
}

impl Run {
    /// Displayed frames scored.
    fn frames(&self) -> usize {
        self.trace_ms.len()
    }
}

/// The experiment's frames and buffers, reused from frame to frame and run to run.
struct Experiment {
    size: (u32, u32),
    guard: (u32, u32),
    opts: Options,
    /// The last traced frame (banded, with depths), with the views it was traced through.
    source: StereoFrame,
    /// Its eyes' shown part: what `none` displays.
    stale: [Vec<u32>; 2],
    /// Depths at infinity, the size of a banded eye: the `rotation` warp's.
    far: Vec<f32>,
    /// The trace at the displayed frame's pose.
    reference: StereoFrame,
    warp: Warp,
    out: [Vec<u32>; 2],
    classes: [Vec<WarpClass>; 2],
}

impl Experiment {
    fn new(size: (u32, u32), guard: (u32, u32), opts: Options) -> Self {
        let mut source = StereoFrame::new();
        source.set_depths(true);
        Self {
            size,
            guard,
            opts,
            source,
            stale: Default::default(),
            far: Vec::new(),
            reference: StereoFrame::new(),
            warp: Warp::new(),
            out: Default::default(),
            classes: Default::default(),
        }
    }

    /// Traces the frame displays show until the next trace, at `pose`: returns its wall
    /// time, ms.
    fn trace_source(&mut self, tracer: &Tracer, pose: &Camera) -> f64 {
        let started = Instant::now();
        self.source.render_banded(tracer, pose, self.size, self.guard, self.opts);
        let ms = started.elapsed().as_secs_f64() * 1e3;
        let ((w, h), (gx, gy)) = (self.size, self.guard);
        let shown = Crop { x: gx, y: gy, w, h };
        self.stale =
            [shown.apply(&self.source.left().rgb, w + 2 * gx), shown.apply(&self.source.right().rgb, w + 2 * gx)];
        self.far.clear();
        self.far.resize(self.source.left().z.len(), f32::INFINITY);
        ms
    }

    /// Traces the reference at `pose`: returns its wall time, ms.
    fn trace_reference(&mut self, tracer: &Tracer, pose: &Camera) -> f64 {
        let started = Instant::now();
        self.reference.render(tracer, pose, self.size.0, self.size.1, self.opts);
        started.elapsed().as_secs_f64() * 1e3
    }

    /// The last traced frame shown at `pose` by `method`, scored against the reference:
    /// (quality, hole share, warp ms).
    fn show(&mut self, method: Method, pose: &Camera) -> (Quality, f64, f64) {
        let Self { source, stale, far, reference, warp, out, classes, .. } = self;
        // (The source keeps its depths, Experiment::new: a warp always has its sources.)
        let warped = if method == Method::None { None } else { source.warp_sources() };
        let (shown, holes, ms) = match warped {
            None => (&*stale, 0.0, 0.0),
            Some(mut sources) => {
                if method == Method::Rotation {
                    sources = sources.map(|eye| WarpSource { z: &far[..], ..eye });
                }
                let targets = source.views().warped_to(pose);
                let [left_out, right_out] = &mut *out;
                let [left_classes, right_classes] = classes;
                let started = Instant::now();
                let counts = warp.warp(
                    sources,
                    [&targets[0], &targets[1]],
                    [left_out, right_out],
                    [left_classes, right_classes],
                );
                let ms = started.elapsed().as_secs_f64() * 1e3;
                (&*out, hole_share(counts), ms)
            }
        };
        let quality = both_eyes(
            Quality::compare(&shown[0], &reference.left().rgb),
            Quality::compare(&shown[1], &reference.right().rgb),
        );
        (quality, holes, ms)
    }
}

/// The share of both eyes' pixels that are holes: filled from the other eye or by the warp's
/// row rule (as the viewer's timewarp counts them).
fn hole_share([l, r]: [WarpCounts; 2]) -> f64 {
    let holes = l.other_eye + l.filled + r.other_eye + r.filled;
    holes as f64 / (l.total() + r.total()).max(1) as f64
}

/// Two eyes of one size measured as one image: the mean squared error (hence the PSNR), the
/// mean error and the shares are the means of the eyes', the largest error the larger.
pub(crate) fn both_eyes(l: Quality, r: Quality) -> Quality {
    let peak = 255.0 * 255.0;
    let mse = |q: &Quality| if q.psnr_db.is_finite() { peak / 10f64.powf(q.psnr_db / 10.0) } else { 0.0 };
    let m = 0.5 * (mse(&l) + mse(&r));
    Quality {
        psnr_db: if m == 0.0 { f64::INFINITY } else { 10.0 * (peak / m).log10() },
        mean_abs: 0.5 * (l.mean_abs + r.mean_abs),
        max_abs: l.max_abs.max(r.max_abs),
        share_over_2_255: 0.5 * (l.share_over_2_255 + r.share_over_2_255),
        share_not_identical: 0.5 * (l.share_not_identical + r.share_not_identical),
    }
}

/// The median; of an even count, the mean of the middle two, or the lower when the upper is
/// +∞ (a PSNR of identical frames), so that half the frames identical never reads as all.
pub(crate) fn median(mut v: Vec<f64>) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else if v[n / 2].is_infinite() {
        v[n / 2 - 1]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// The number of displayed frames in `seconds` at `hz`, checked.
fn displayed_frames(seconds: f64, hz: u32) -> Result<u32, BadInput> {
    if !(seconds.is_finite() && seconds > 0.0 && seconds <= MAX_SECONDS) {
        return Err(BadInput(format!("--seconds {seconds}: must be more than 0 and at most {MAX_SECONDS}")));
    }
    let frames = (seconds * f64::from(hz)).round();
    if frames < 1.0 {
        return Err(BadInput(format!(
            "--seconds {seconds} --display-hz {hz}: under one displayed frame; give at least {} s",
            1.0 / f64::from(hz)
        )));
    }
    Ok(frames as u32)
}

/// Runs the command.
pub fn run(args: &TimewarpArgs) -> Result<()> {
    let hz = args.display_hz;
    let frames = displayed_frames(args.seconds, hz)?;
    plot::check_outputs(args.csv.as_deref(), args.plot.as_deref())?;
    // The traced frame (banded, 1.2 frames), the reference and the warped eyes.
    let setup = FrameSetup::load(&args.frame, 4)?;
    let size = (args.frame.width, args.frame.height);
    let guard = setup::guard_band(size, args.guard_band as f32 / 100.0);
    let opts = Options { mode: args.mode, retrace_edges: false };
    let tracer = Tracer::new(&setup.scene, args.frame.time);
    let start = setup.camera;
    let pose = |k: u32| args.motion.pose(&start, f64::from(k) / f64::from(hz));

    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = Arc::clone(&stop);
        // If a handler is already installed (only in tests), Ctrl-C keeps its default.
        let _ = ctrlc::set_handler(move || stop.store(true, Ordering::SeqCst));
    }
    let values = &args.trace_every.0;
    let bar = indicatif::ProgressBar::new(u64::from(frames) * values.len() as u64).with_style(
        indicatif::ProgressStyle::with_template("{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} frames {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let mut experiment = Experiment::new(size, guard, opts);
    // Warm-up, untimed: the first trace and warp size every buffer.
    experiment.trace_source(&tracer, &pose(0));
    experiment.trace_reference(&tracer, &pose(0));
    experiment.show(Method::Depth, &pose(1));

    let mut runs: Vec<Run> = Vec::new();
    'runs: for &n in values {
        let mut run = Run { trace_every: n, rows: Vec::new(), trace_ms: Vec::new(), banded_ms: Vec::new() };
        bar.set_message(every(n));
        for k in 0..frames {
            if stop.load(Ordering::SeqCst) {
                runs.push(run);
                break 'runs;
            }
            let at = pose(k);
            if k % n == 0 {
                run.banded_ms.push(experiment.trace_source(&tracer, &at));
            }
            run.trace_ms.push(experiment.trace_reference(&tracer, &at));
            for method in Method::ALL {
                let (quality, hole_share, ms) = experiment.show(method, &at);
                run.rows.push(Row { trace_every: n, frame: k, age: k % n, method, quality, hole_share, ms });
            }
            bar.inc(1);
            if bar.is_hidden() && ((k + 1) % hz == 0 || k + 1 == frames) {
                // No terminal for the bar: a line per displayed second instead (logs, tests).
                eprintln!("timewarp: {}: frame {}/{frames} done", every(n), k + 1);
            }
        }
        runs.push(run);
    }
    bar.finish_and_clear();

    let done: usize = runs.iter().map(Run::frames).sum();
    let planned = frames as usize * values.len();
    let rows: Vec<Row> = runs.iter().flat_map(|r| r.rows.iter().copied()).collect();
    let inputs = Inputs { args, scene: setup.path.display().to_string(), guard, frame_ms: 1e3 / f64::from(hz) };
    if let Some(path) = &args.csv {
        write_bytes(path, csv(&rows, hz).as_bytes())?;
    }
    if let Some(path) = &args.plot {
        if !rows.is_empty() {
            let figure = AgeFigure { title: inputs.title(), frame_ms: inputs.frame_ms, series: &series(&rows, hz) };
            plot::write(path, &figure)?;
        }
    }
    if args.json {
        let reports: Vec<Value> = runs.iter().map(|r| report(&inputs, r)).collect();
        let out = if reports.len() == 1 { reports[0].clone() } else { Value::Array(reports) };
        super::print_out(&(serde_json::to_string_pretty(&out)? + "\n"))?;
    } else {
        super::print_out(&table(&inputs, &runs))?;
    }
    let wrote =
        [args.csv.as_ref().map(|p| p.display().to_string()), args.plot.as_ref().map(|p| p.display().to_string())]
            .into_iter()
            .flatten()
            .collect::<Vec<_>>();
    let interrupted = if done < planned { " (interrupted)" } else { "" };
    eprintln!(
        "timewarp: {done} of {planned} displayed frames × {} methods{interrupted}: {} rows{}",
        Method::ALL.len(),
        rows.len(),
        if wrote.is_empty() { String::new() } else { format!(", written to {}", wrote.join(" and ")) }
    );
    if done < planned {
        anyhow::bail!("interrupted after {done} of {planned} displayed frames; the rows done were written");
    }
    Ok(())
}

mod output;

use output::{csv, every, report, series, table, Inputs};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_median_never_reads_half_identical_as_identical() {
        assert_eq!(median(vec![3.0, 1.0, 2.0]), 2.0, "odd: the middle");
        assert_eq!(median(vec![4.0, 1.0, 2.0, 3.0]), 2.5, "even: the mean of the middle two");
        assert_eq!(median(vec![f64::INFINITY, 30.0]), 30.0, "half identical: the finite one");
        assert_eq!(median(vec![f64::INFINITY, f64::INFINITY, 30.0]), f64::INFINITY, "most identical: ∞");
    }

    #[test]
    fn two_eyes_score_as_one_image() {
        let a = [0x0003_0000, 0x0000_0000];
        let b = [0x0000_0000, 0x0000_0000];
        let one = Quality::compare(&[a, b].concat(), &[b, b].concat());
        let two = both_eyes(Quality::compare(&a, &b), Quality::compare(&b, &b));
        assert!((one.psnr_db - two.psnr_db).abs() < 1e-9, "{} vs {}", one.psnr_db, two.psnr_db);
        assert_eq!((one.max_abs, one.share_over_2_255, one.share_not_identical), (two.max_abs, 0.25, 0.25));
        assert!((one.mean_abs - two.mean_abs).abs() < 1e-12);
        assert!(both_eyes(Quality::compare(&b, &b), Quality::compare(&b, &b)).psnr_db.is_infinite());
    }

    #[test]
    fn seconds_are_bounded_and_make_whole_frames() {
        assert_eq!(displayed_frames(1.0, 90).unwrap(), 90);
        assert_eq!(displayed_frames(0.05, 90).unwrap(), 5, "4.5 rounds to 5");
        for bad in [0.0, -1.0, 61.0, f64::NAN, f64::INFINITY] {
            let err = displayed_frames(bad, 90).unwrap_err().0;
            assert!(err.starts_with(&format!("--seconds {bad}: must be more than 0")), "{err}");
        }
        assert!(displayed_frames(0.1, 1).unwrap_err().0.contains("under one displayed frame"));
    }
}
