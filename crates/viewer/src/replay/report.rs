//! `replay`'s reports: the JSON object and the summary of the run's medians, overall and
//! for the moving and resting parts, and the CSV of every presented frame.

use std::fmt::Write as _;

use serde_json::{json, Value};

use super::record::{Frame, Recording};
use super::score::Scored;
use crate::args::{Policy, ReplayArgs};
use crate::cli::timewarp::median;
use crate::setup::FrameSetup;

/// The CSV's header.
pub const HEADER: &str = "frame,t_s,phase,seq,age_ms,guessed_share,warped,density,spp,converged,yaw_deg,pitch_deg,x,y,z,psnr_db,share_over_2_255,fresh_psnr_db";

/// The value at the nearest rank `p` (0..=1) of `v` (+∞ sorts last); NaN when empty.
pub fn percentile(mut v: Vec<f64>, p: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let rank = (p * v.len() as f64).ceil() as usize;
    v[rank.clamp(1, v.len()) - 1]
}

/// A number, or null when it is not finite (a PSNR of identical frames, or no frames).
fn finite(v: f64) -> Value {
    if v.is_finite() {
        json!(v)
    } else {
        Value::Null
    }
}

/// The medians and tails of some presented frames.
#[derive(Clone, Copy, Debug)]
pub struct Stats {
    pub frames: usize,
    pub scored: usize,
    pub psnr_median: f64,
    pub psnr_p10: f64,
    pub over_median: f64,
    pub age_median: f64,
    pub age_p90: f64,
    pub guessed_median: f64,
    pub density_median: f64,
    pub spp_median: f64,
    pub converged_share: f64,
    /// The scored frames' poses traced fresh at one sample a pixel (`score.rs`).
    pub fresh_median: f64,
    pub fresh_p10: f64,
}

impl Stats {
    /// Of the frames `which` of `recording`.
    fn of(which: &[usize], recording: &Recording, scored: &Scored) -> Self {
        let frames: Vec<&Frame> = which.iter().map(|&k| &recording.frames[k]).collect();
        let quality: Vec<_> = which.iter().filter_map(|&k| scored.quality[k]).collect();
        let psnr = || quality.iter().map(|q| q.psnr_db).collect::<Vec<_>>();
        let fresh = || which.iter().filter_map(|&k| scored.fresh[k]).map(|q| q.psnr_db).collect::<Vec<_>>();
        let of = |f: fn(&Frame) -> f64| frames.iter().map(|&fr| f(fr)).collect::<Vec<_>>();
        let converged = frames.iter().filter(|f| f.sampling.converged).count();
        Self {
            frames: frames.len(),
            scored: quality.len(),
            psnr_median: median(psnr()),
            psnr_p10: percentile(psnr(), 0.1),
            over_median: median(quality.iter().map(|q| q.share_over_2_255).collect()),
            age_median: median(of(|f| f.age_ms)),
            age_p90: percentile(of(|f| f.age_ms), 0.9),
            guessed_median: median(of(|f| f.guessed_share)),
            density_median: median(of(|f| f64::from(f.sampling.density))),
            spp_median: median(of(|f| f64::from(f.sampling.spp))),
            converged_share: converged as f64 / frames.len().max(1) as f64,
            fresh_median: median(fresh()),
            fresh_p10: percentile(fresh(), 0.1),
        }
    }

    fn json(&self) -> Value {
        json!({
            "frames": self.frames,
            "scored": self.scored,
            "psnr_db": {"median": finite(self.psnr_median), "p10": finite(self.psnr_p10)},
            "share_over_2_255": {"median": finite(self.over_median)},
            "age_ms": {"median": finite(self.age_median), "p90": finite(self.age_p90)},
            "guessed_share": {"median": finite(self.guessed_median)},
            "fresh": {"psnr_db": {"median": finite(self.fresh_median), "p10": finite(self.fresh_p10)}},
            "sampling": {
                "density": {"median": finite(self.density_median)},
                "spp": {"median": finite(self.spp_median)},
                "converged_share": self.converged_share,
            },
        })
    }
}

/// What the reports say of a run.
pub struct Summary<'a> {
    args: &'a ReplayArgs,
    scene: String,
    pub ticks: u64,
    pub converge_s: Option<f64>,
    /// Seconds from the stop to the first frame at the resting pose at every pixel.
    pub first_full_s: Option<f64>,
    /// The resting refinement's most bytes at once.
    pub accumulation_bytes: usize,
    pub interrupted: bool,
    /// All presented frames, the moving part's and the resting part's.
    pub all: Stats,
    pub moving: Stats,
    pub resting: Stats,
}

impl<'a> Summary<'a> {
    pub fn new(args: &'a ReplayArgs, setup: &FrameSetup, recording: &Recording, scored: &Scored) -> Self {
        let all: Vec<usize> = (0..recording.frames.len()).collect();
        let [(_, moving), (_, resting)] = recording.phases();
        Self {
            args,
            scene: setup.path.display().to_string(),
            ticks: recording.ticks,
            converge_s: scored.converge_s,
            first_full_s: recording.first_full_s(),
            accumulation_bytes: recording.accumulation_bytes,
            interrupted: recording.interrupted || scored.interrupted,
            all: Stats::of(&all, recording, scored),
            moving: Stats::of(&moving, recording, scored),
            resting: Stats::of(&resting, recording, scored),
        }
    }

    /// The plot's title.
    pub fn title(&self) -> String {
        let a = self.args;
        let name = std::path::Path::new(&self.scene)
            .file_name()
            .map_or(self.scene.clone(), |n| n.to_string_lossy().into_owned());
        format!(
            "stereotrace replay: {name}, {}×{}, {}, {} s + {} s still, {} Hz, {}",
            a.frame.width,
            a.frame.height,
            a.motion,
            a.seconds,
            a.still,
            a.display_hz,
            a.policy.name()
        )
    }

    /// `--json`.
    pub fn json(&self) -> Value {
        let a = self.args;
        let mut presented = self.all.json();
        if let Some(o) = presented.as_object_mut() {
            o.remove("frames");
            o.remove("scored");
        }
        json!({
            "scene": self.scene,
            "width": a.frame.width,
            "height": a.frame.height,
            "mode": a.mode.name(),
            "motion": a.motion.to_string(),
            "seconds": a.seconds,
            "still": a.still,
            "display_hz": a.display_hz,
            "score_every": a.score_every,
            "max_supersample": a.max_supersample,
            "policy": a.policy.name(),
            "target_age_ms": (a.policy == Policy::Progressive).then_some(a.target_age_ms),
            "threads": rayon::current_num_threads(),
            "lanes": tracer::lane_width(),
            "ticks": self.ticks,
            "frames": self.all.frames,
            "scored": self.all.scored,
            "presented": presented,
            "moving": self.moving.json(),
            "resting": self.resting.json(),
            "converge_s": self.converge_s,
            "first_full_s": self.first_full_s,
            "memory": { "accumulation": self.accumulation_bytes },
        })
    }

    /// The summary printed without `--json`.
    pub fn text(&self) -> String {
        let a = self.args;
        let mut out = String::new();
        let _ = writeln!(
            out,
            "{}: {}×{} per eye, {}, motion {} for {} s then still {} s, {} Hz, policy {}",
            self.scene,
            a.frame.width,
            a.frame.height,
            a.mode,
            a.motion,
            a.seconds,
            a.still,
            a.display_hz,
            a.policy.name()
        );
        let _ = writeln!(
            out,
            "{:<9} {:>7} {:>7} {:>9} {:>8} {:>8} {:>9} {:>9} {:>9} {:>9}",
            "part", "frames", "scored", "PSNR dB", "p10", ">2/255", "age ms", "age p90", "guessed", "fresh dB"
        );
        // No frames: a dash; an infinite PSNR (identical): inf.
        let num = |v: f64, f: &dyn Fn(f64) -> String| if v.is_nan() { "-".into() } else { f(v) };
        let db = |v: f64| num(v, &|v| if v.is_finite() { format!("{v:.1}") } else { "inf".into() });
        let percent = |v: f64| num(v, &|v| format!("{:.3}%", 100.0 * v));
        let ms = |v: f64| num(v, &|v| format!("{v:.1}"));
        for (name, s) in [("all", &self.all), ("moving", &self.moving), ("resting", &self.resting)] {
            let _ = writeln!(
                out,
                "{name:<9} {:>7} {:>7} {:>9} {:>8} {:>8} {:>9} {:>9} {:>9} {:>9}",
                s.frames,
                s.scored,
                db(s.psnr_median),
                db(s.psnr_p10),
                percent(s.over_median),
                ms(s.age_median),
                ms(s.age_p90),
                percent(s.guessed_median),
                db(s.fresh_median)
            );
        }
        let s = a.max_supersample;
        let _ = match self.converge_s {
            Some(t) => {
                writeln!(out, "converge_s: {t:.3} (the {s}×{s} reference at rest reached {t:.3} s after the stop)")
            }
            None => writeln!(out, "converge_s: null (the {s}×{s} reference at rest was never reached)"),
        };
        out
    }

    /// The line on stderr at the end.
    pub fn done_line(&self) -> String {
        let a = self.args;
        let wrote: Vec<String> = [&a.csv, &a.plot].into_iter().flatten().map(|p| p.display().to_string()).collect();
        format!(
            "replay: {} frames presented in {} ticks, {} scored{}{}",
            self.all.frames,
            self.ticks,
            self.all.scored,
            if self.interrupted { " (interrupted)" } else { "" },
            if wrote.is_empty() { String::new() } else { format!(", written to {}", wrote.join(" and ")) }
        )
    }
}

/// The CSV: a header, then a row per presented frame (the scores empty unless scored).
pub fn csv(recording: &Recording, scored: &Scored) -> String {
    let mut out = format!("{HEADER}\n");
    for (k, f) in recording.frames.iter().enumerate() {
        let (p, s) = (f.tick.pose, f.sampling);
        let (psnr, over) = match scored.quality[k] {
            Some(q) if q.psnr_db.is_finite() => (format!("{:.3}", q.psnr_db), format!("{:.6}", q.share_over_2_255)),
            Some(q) => ("inf".into(), format!("{:.6}", q.share_over_2_255)),
            None => (String::new(), String::new()),
        };
        let fresh = match scored.fresh[k] {
            Some(q) if q.psnr_db.is_finite() => format!("{:.3}", q.psnr_db),
            Some(_) => "inf".into(),
            None => String::new(),
        };
        let _ = writeln!(
            out,
            "{k},{:.4},{},{},{:.3},{:.6},{},{},{},{},{},{},{},{},{},{psnr},{over},{fresh}",
            f.tick.t,
            if f.tick.moving { "moving" } else { "resting" },
            f.seq,
            f.age_ms,
            f.guessed_share,
            u8::from(f.warped),
            s.density,
            s.spp,
            u8::from(s.converged),
            p.yaw_deg,
            p.pitch_deg,
            p.position.x,
            p.position.y,
            p.position.z,
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_take_the_nearest_rank() {
        let v: Vec<f64> = (1..=10).map(f64::from).collect();
        assert_eq!(percentile(v.clone(), 0.1), 1.0);
        assert_eq!(percentile(v.clone(), 0.9), 9.0);
        assert_eq!(percentile(v, 1.0), 10.0);
        assert_eq!(percentile(vec![f64::INFINITY, 30.0, 20.0], 0.1), 20.0, "the low tail of PSNRs");
        assert!(percentile(Vec::new(), 0.5).is_nan());
    }
}
