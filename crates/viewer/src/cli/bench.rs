//! `stereotrace bench`: every mode on the same frames, with time, rays, pixel classes and
//! quality against a full trace.
//!
//! Frames are taken at scene times t, t + 1/30 s, …; for each frame every mode renders in
//! turn (interleaved, so a noisy neighbour on the machine hurts all modes alike) after one
//! untimed warm-up frame per mode. Times and counts are medians over the frames; quality is
//! the worst frame's. An eye's time includes its outlines when the scene has them
//! (`--outline`; quality is measured without them). `sweep` measures each of its steps with the same loop
//! ([`Bench::measure`]) and the same medians ([`Summary::of`]).
//!
//! The animation rows (`--animate N`) play N frames 1/60 s apart from the same start with
//! the head still, per mode: each frame is traced fresh (reuse off) and, in a second
//! `StereoFrame` that has seen the frame before, with exact reuse (`stereo`'s `reuse/`),
//! interleaved. They report the median stereo time of each and the median share of pixels
//! the reused frames made anew. The frame before the first, which primes reuse, is not
//! counted.

use std::fmt::Write as _;

use anyhow::Result;
use serde_json::{json, Map, Value};
use stereo::{FrameStats, Mode, Options, Outlined, Quality, StereoFrame};
use tracer::{Camera, Eye, RayCounts, Scene, Tracer};

use crate::args::BenchArgs;
use crate::cli::report;
use crate::reference::Reference;
use crate::setup::FrameSetup;

/// One measured variant: its name in reports, the mode, and whether edges are retraced.
pub(crate) type Variant = (&'static str, Mode, bool);

/// The modes measured, as (name, options): the four modes plus copy and reshade with edge
/// retracing.
pub(crate) const VARIANTS: [Variant; 6] = [
    ("full", Mode::Full, false),
    ("copy", Mode::Copy, false),
    ("copy+edges", Mode::Copy, true),
    ("reshade", Mode::Reshade, false),
    ("reshade+edges", Mode::Reshade, true),
    ("exact", Mode::Exact, false),
];

/// One variant's frames and their quality against the full trace.
pub(crate) struct Measured {
    name: &'static str,
    frames: Vec<FrameStats>,
    quality: Vec<Quality>,
}

/// Seconds of scene time between the frames of an animation row.
const ANIMATION_STEP_S: f32 = 1.0 / 60.0;

/// One mode's animation row: medians over its frames.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Animation {
    frames: u32,
    fresh_ms: f64,
    reused_ms: f64,
    retraced_share: f64,
}

/// Plays `frames` frames of the animation in mode `opts`, fresh and reused, interleaved.
fn animate(setup: &FrameSetup, start: f32, (w, h): (u32, u32), opts: Options, frames: u32) -> Animation {
    let mut tracer = Tracer::new(&setup.scene, start);
    let (mut fresh, mut reusing) = (StereoFrame::new(), StereoFrame::new());
    reusing.set_reuse(Some(&setup.scene));
    reusing.render(&tracer, &setup.camera, w, h, opts);
    fresh.render(&tracer, &setup.camera, w, h, opts);
    let (mut fresh_ms, mut reused_ms, mut shares) = (Vec::new(), Vec::new(), Vec::new());
    let stereo_ms = |s: &FrameStats| s.left.ms + s.right.ms;
    for k in 1..=frames {
        tracer.advance(&setup.scene, start + k as f32 * ANIMATION_STEP_S);
        fresh_ms.push(stereo_ms(&fresh.render(&tracer, &setup.camera, w, h, opts)));
        let reused = reusing.render(&tracer, &setup.camera, w, h, opts);
        reused_ms.push(stereo_ms(&reused));
        shares.push(reused.reuse.retraced_share());
    }
    Animation {
        frames,
        fresh_ms: median(&mut fresh_ms),
        reused_ms: median(&mut reused_ms),
        retraced_share: median(&mut shares),
    }
}

/// The buffers a measurement reuses from run to run.
#[derive(Default)]
pub(crate) struct Bench {
    frame: StereoFrame,
    reference: Reference,
    outlined: Outlined,
}

impl Bench {
    /// Renders `variants` on `frames` frames of `scene` seen by `camera` at `w` × `h` per
    /// eye, frame k at scene time `time_of(k)`: one untimed warm-up frame per variant in the
    /// tracer's current state first, then each frame in every variant in turn (interleaved),
    /// each measured against a full trace of the same frame.
    pub(crate) fn measure(
        &mut self,
        tracer: &mut Tracer,
        (scene, camera): (&Scene, &Camera),
        (w, h): (u32, u32),
        variants: &[Variant],
        frames: u32,
        time_of: impl Fn(u32) -> f32,
    ) -> Vec<Measured> {
        let mut results: Vec<Measured> =
            variants.iter().map(|&(name, ..)| Measured { name, frames: Vec::new(), quality: Vec::new() }).collect();
        // The scene's outlines read each eye's first hits: the left film's, and the right
        // eye's, from its own pass in full and exact modes, from a depth pass in the others
        // (timed with that eye).
        let width = scene.render.cues.outline as f32;
        self.frame.set_depths(width > 0.0);
        for &(_, mode, retrace_edges) in variants {
            self.frame.render(tracer, camera, w, h, Options { mode, retrace_edges });
        }
        for k in 0..frames {
            tracer.advance(scene, time_of(k));
            self.reference.trace(tracer, camera, w, h);
            for (m, &(_, mode, retrace_edges)) in results.iter_mut().zip(variants) {
                let mut stats = self.frame.render(tracer, camera, w, h, Options { mode, retrace_edges });
                // The scene's outlines, each eye's timed with that eye.
                if width > 0.0 {
                    stats.right.ms += stats.stages.depth;
                    for (eye, ms) in [(Eye::Left, &mut stats.left.ms), (Eye::Right, &mut stats.right.ms)] {
                        let t = std::time::Instant::now();
                        self.outlined.draw(tracer, &self.frame, eye, width);
                        *ms += t.elapsed().as_secs_f64() * 1e3;
                    }
                }
                m.frames.push(stats);
                m.quality.push(self.reference.compare(&self.frame.right().rgb));
            }
        }
        results
    }
}

/// Runs the command.
pub fn run(args: &BenchArgs) -> Result<()> {
    let setup = FrameSetup::load(&args.frame, 1)?;
    let (w, h) = (args.frame.width, args.frame.height);
    let mut tracer = Tracer::new(&setup.scene, args.frame.time);
    let t0 = args.frame.time;
    let results =
        Bench::default().measure(&mut tracer, (&setup.scene, &setup.camera), (w, h), &VARIANTS, args.frames, |k| {
            t0 + k as f32 / 30.0
        });

    let animations: Vec<Option<Animation>> = VARIANTS
        .iter()
        .map(|&(_, mode, retrace_edges)| {
            let opts = Options { mode, retrace_edges };
            (args.animate > 0).then(|| animate(&setup, args.frame.time, (w, h), opts, args.animate))
        })
        .collect();

    let mut lefts: Vec<f64> = results.iter().flat_map(|m| m.frames.iter().map(|s| s.left.ms)).collect();
    let mono_ms = median(&mut lefts);
    let threads = rayon::current_num_threads();
    let summaries: Vec<Summary> =
        results.iter().zip(animations).map(|(m, a)| Summary { animation: a, ..Summary::of(m, threads) }).collect();

    if args.json {
        let mut modes = Map::new();
        for s in &summaries {
            let mut v = report::frame(&s.stats);
            if let Value::Object(o) = &mut v {
                o.insert("quality".into(), report::quality(&s.quality));
                o.insert("stereo_ms".into(), json!(s.stereo_ms));
                o.insert("stereo_over_mono".into(), json!(s.stereo_over_mono));
                o.insert("stereo_ms_over_mono_ms".into(), json!(s.stereo_ms / mono_ms));
                o.insert("mrays_per_s_per_core".into(), json!(s.mrays_per_core));
                if let Some(a) = s.animation {
                    o.insert(
                        "animation".into(),
                        json!({
                            "frames": a.frames,
                            "fresh_ms": a.fresh_ms,
                            "reused_ms": a.reused_ms,
                            "retraced_share": a.retraced_share,
                        }),
                    );
                }
            }
            modes.insert(s.name.to_owned(), v);
        }
        let out = json!({
            "scene": setup.path.display().to_string(),
            "width": w,
            "height": h,
            "frames": args.frames,
            "threads": threads,
            "lanes": tracer::lane_width(),
            "spheres": setup.scene.sphere_count(),
            "mono_ms": mono_ms,
            "modes": modes,
        });
        super::print_out(&(serde_json::to_string_pretty(&out)? + "\n"))?;
    } else {
        super::print_out(&table(&setup.path.display().to_string(), w, h, args.frames, threads, mono_ms, &summaries))?;
    }
    Ok(())
}

/// One variant's medians over its frames (quality: the worst frame's).
pub(crate) struct Summary {
    pub(crate) name: &'static str,
    pub(crate) stats: FrameStats,
    pub(crate) quality: Quality,
    pub(crate) stereo_ms: f64,
    /// Median over frames of (left + right) / left: each stereo frame against the mono
    /// frame inside it (see [`Summary::of`]).
    pub(crate) stereo_over_mono: f64,
    pub(crate) mrays_per_core: f64,
    /// The animation row, if measured.
    pub(crate) animation: Option<Animation>,
}

impl Summary {
    /// Medians over the frames of mode `m`.
    ///
    /// The stereo frame's cost as a multiple of a mono frame is taken frame by frame: a
    /// mono frame is exactly the left eye's trace, so each frame's left eye is the mono
    /// frame it is compared with, measured moments apart under the same load. The ratio of
    /// this mode's median stereo time to the median left eye of all modes (reported too,
    /// as `stereo_ms_over_mono_ms`) mixes two sets of samples, and on a shared machine
    /// swings by more than the right eye costs.
    pub(crate) fn of(m: &Measured, threads: usize) -> Self {
        let stats = median_stats(&m.frames);
        let mut stereo: Vec<f64> = m.frames.iter().map(|s| s.left.ms + s.right.ms).collect();
        let stereo_ms = median(&mut stereo);
        let mut ratios: Vec<f64> =
            m.frames.iter().map(|s| (s.left.ms + s.right.ms) / s.left.ms.max(f64::MIN_POSITIVE)).collect();
        let stereo_over_mono = median(&mut ratios);
        let mut rates: Vec<f64> = m
            .frames
            .iter()
            .map(|s| {
                (s.left.rays.total() + s.right.rays.total()) as f64 / ((s.left.ms + s.right.ms) * 1e3) / threads as f64
            })
            .collect();
        Self {
            name: m.name,
            stats,
            quality: worst(&m.quality),
            stereo_ms,
            stereo_over_mono,
            mrays_per_core: median(&mut rates),
            animation: None,
        }
    }
}

fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn median_u64(frames: &[FrameStats], f: impl Fn(&FrameStats) -> u64) -> u64 {
    let mut v: Vec<f64> = frames.iter().map(|s| f(s) as f64).collect();
    median(&mut v).round() as u64
}

fn median_f64(frames: &[FrameStats], f: impl Fn(&FrameStats) -> f64) -> f64 {
    let mut v: Vec<f64> = frames.iter().map(f).collect();
    median(&mut v)
}

fn median_rays(frames: &[FrameStats], f: impl Fn(&FrameStats) -> RayCounts) -> RayCounts {
    RayCounts {
        primary: median_u64(frames, |s| f(s).primary),
        shadow: median_u64(frames, |s| f(s).shadow),
        reflection: median_u64(frames, |s| f(s).reflection),
    }
}

/// Field-by-field medians.
fn median_stats(frames: &[FrameStats]) -> FrameStats {
    let mut s = FrameStats::default();
    s.left.rays = median_rays(frames, |s| s.left.rays);
    s.right.rays = median_rays(frames, |s| s.right.rays);
    s.left.ms = median_f64(frames, |s| s.left.ms);
    s.right.ms = median_f64(frames, |s| s.right.ms);
    s.pixels.reprojected = median_u64(frames, |s| s.pixels.reprojected);
    s.pixels.retraced_gap = median_u64(frames, |s| s.pixels.retraced_gap);
    s.pixels.retraced_edge = median_u64(frames, |s| s.pixels.retraced_edge);
    s.pixels.traced = median_u64(frames, |s| s.pixels.traced);
    s.stages.trace_left = median_f64(frames, |s| s.stages.trace_left);
    s.stages.reproject = median_f64(frames, |s| s.stages.reproject);
    s.stages.retrace = median_f64(frames, |s| s.stages.retrace);
    s.stages.reshade = median_f64(frames, |s| s.stages.reshade);
    s.sphere_tests = median_u64(frames, |s| s.sphere_tests);
    s
}

/// The worst frame on each quality measure.
fn worst(q: &[Quality]) -> Quality {
    q.iter().fold(Quality { psnr_db: f64::INFINITY, ..Quality::default() }, |a, b| Quality {
        psnr_db: a.psnr_db.min(b.psnr_db),
        mean_abs: a.mean_abs.max(b.mean_abs),
        max_abs: a.max_abs.max(b.max_abs),
        share_over_2_255: a.share_over_2_255.max(b.share_over_2_255),
        share_not_identical: a.share_not_identical.max(b.share_not_identical),
    })
}

fn table(scene: &str, w: u32, h: u32, frames: u32, threads: usize, mono_ms: f64, rows: &[Summary]) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{scene}: {w}×{h} per eye, {frames} frames, {threads} threads, {lanes}-lane shading; medians (quality: worst frame); mono frame {mono_ms:.1} ms",
        lanes = tracer::lane_width()
    );
    let _ = writeln!(
        out,
        "{:<14} {:>8} {:>8} {:>7} {:>7} {:>9} {:>9} {:>11} {:>7} {:>8} {:>9} {:>8} {:>7}",
        "mode",
        "left ms",
        "right ms",
        "R/L ms",
        "st/mono",
        "left Mr",
        "right Mr",
        "ray % L/R",
        "reproj",
        "PSNR dB",
        "identical",
        ">2/255",
        "Mr/s/c"
    );
    for r in rows {
        let s = &r.stats;
        let share = 100.0 * s.left.rays.total() as f64 / (s.left.rays.total() + s.right.rays.total()).max(1) as f64;
        let psnr = if r.quality.psnr_db.is_finite() { format!("{:.1}", r.quality.psnr_db) } else { "inf".into() };
        let _ = writeln!(
            out,
            "{:<14} {:>8.1} {:>8.1} {:>6.0}% {:>6.2}× {:>9.3} {:>9.3} {:>5.0}/{:<5.0} {:>6.1}% {:>8} {:>8.3}% {:>7.3}% {:>7.1}",
            r.name,
            s.left.ms,
            s.right.ms,
            100.0 * s.right_time_ratio(),
            r.stereo_over_mono,
            s.left.rays.total() as f64 / 1e6,
            s.right.rays.total() as f64 / 1e6,
            share,
            100.0 - share,
            100.0 * s.pixels.reprojected_share(),
            psnr,
            100.0 * (1.0 - r.quality.share_not_identical),
            100.0 * r.quality.share_over_2_255,
            r.mrays_per_core,
        );
    }
    let _ = writeln!(
        out,
        "ray % L/R: share of all rays spent per eye (the seed paper's §5.1: 87/13 for copy). st/mono: median over frames of (left + right) / left, a stereo frame over the mono (left-only) frame inside it."
    );
    let _ = writeln!(out, "\nstages, ms (medians): the right eye is reproject + retrace + reshade");
    let _ = writeln!(
        out,
        "{:<14} {:>10} {:>10} {:>10} {:>10} {:>10}",
        "mode", "trace left", "reproject", "retrace", "reshade", "stereo"
    );
    for r in rows {
        let st = &r.stats.stages;
        let _ = writeln!(
            out,
            "{:<14} {:>10.2} {:>10.2} {:>10.2} {:>10.2} {:>10.2}",
            r.name, st.trace_left, st.reproject, st.retrace, st.reshade, r.stereo_ms
        );
    }
    if let Some(frames) = rows.iter().find_map(|r| r.animation.map(|a| a.frames)) {
        let _ = writeln!(
            out,
            "\nanimation: {frames} frames 1/60 s apart, head still; stereo ms per frame, fresh against exact reuse (medians)"
        );
        let _ =
            writeln!(out, "{:<14} {:>9} {:>9} {:>9} {:>10}", "mode", "fresh ms", "reused ms", "reused %", "retraced %");
        for r in rows {
            if let Some(a) = r.animation {
                let _ = writeln!(
                    out,
                    "{:<14} {:>9.2} {:>9.2} {:>8.0}% {:>9.1}%",
                    r.name,
                    a.fresh_ms,
                    a.reused_ms,
                    100.0 * a.reused_ms / a.fresh_ms.max(f64::MIN_POSITIVE),
                    100.0 * a.retraced_share
                );
            }
        }
    }
    out
}
