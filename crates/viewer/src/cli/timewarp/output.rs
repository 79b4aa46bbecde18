//! The reports of `stereotrace timewarp`: the JSON object and the table of a run's medians,
//! the CSV of every displayed frame, and the figure's series.

use std::fmt::Write as _;

use serde_json::{json, Map, Value};

use super::{median, Method, Row, Run, HEADER};
use crate::args::TimewarpArgs;
use crate::cli::age_plot::Series;

/// "a trace every N frames", or "every frame".
pub(super) fn every(n: u32) -> String {
    if n == 1 {
        "a trace every frame".into()
    } else {
        format!("a trace every {n} frames")
    }
}

/// What the reports name besides the measurements.
pub(super) struct Inputs<'a> {
    pub(super) args: &'a TimewarpArgs,
    pub(super) scene: String,
    pub(super) guard: (u32, u32),
    /// One display frame, ms.
    pub(super) frame_ms: f64,
}

impl Inputs<'_> {
    pub(super) fn title(&self) -> String {
        let a = self.args;
        let name =
            std::path::Path::new(&self.scene).file_name().map_or(self.scene.clone(), |n| n.to_string_lossy().into());
        let every = match a.trace_every.0.as_slice() {
            [n] => every(*n),
            [first, .., last] if a.trace_every.0.windows(2).all(|w| w[1] == w[0] + 1) => {
                format!("a trace every {first}..{last} frames")
            }
            list => format!("a trace every {} frames", list.iter().map(u32::to_string).collect::<Vec<_>>().join(",")),
        };
        format!(
            "stereotrace timewarp: {name}, {}×{}, {}, {} Hz, {every}",
            a.frame.width, a.frame.height, a.motion, a.display_hz
        )
    }
}

/// The JSON object of one run: the inputs, then the medians over its displayed frames.
pub(super) fn report(inputs: &Inputs, run: &Run) -> Value {
    let a = inputs.args;
    let mut warps = Map::new();
    for method in Method::ALL {
        let mine = || run.rows.iter().filter(move |r| r.method == method);
        let of = |f: fn(&Row) -> f64| median(mine().map(f).collect());
        let psnr = of(|r| r.quality.psnr_db);
        warps.insert(
            method.name().into(),
            json!({
                "psnr_db": psnr.is_finite().then_some(psnr),
                "share_over_2_255": of(|r| r.quality.share_over_2_255),
                "share_not_identical": of(|r| r.quality.share_not_identical),
                "hole_share": of(|r| r.hole_share),
                "ms": of(|r| r.ms),
            }),
        );
    }
    let finite = |v: f64| v.is_finite().then_some(v);
    json!({
        "scene": inputs.scene,
        "width": a.frame.width,
        "height": a.frame.height,
        "mode": a.mode.name(),
        "motion": a.motion.to_string(),
        "display_hz": a.display_hz,
        "trace_every": run.trace_every,
        "seconds": a.seconds,
        "guard": [inputs.guard.0, inputs.guard.1],
        "threads": rayon::current_num_threads(),
        "lanes": tracer::lane_width(),
        "trace_ms": finite(median(run.trace_ms.clone())),
        "banded_trace_ms": finite(median(run.banded_ms.clone())),
        "frames": run.frames(),
        "warps": warps,
    })
}

/// The human table: per run, the medians of each method.
pub(super) fn table(inputs: &Inputs, runs: &[Run]) -> String {
    let a = inputs.args;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{}: {}×{} per eye, {}, motion {}, {} Hz ({:.1} ms a frame), guard band {}×{}; medians over the displayed frames",
        inputs.scene, a.frame.width, a.frame.height, a.mode, a.motion, a.display_hz, inputs.frame_ms, inputs.guard.0, inputs.guard.1
    );
    for run in runs {
        let _ = writeln!(
            out,
            "\n{}: {} frames; stereo trace {:.2} ms (banded, with depths: {:.2} ms)",
            every(run.trace_every),
            run.frames(),
            median(run.trace_ms.clone()),
            median(run.banded_ms.clone())
        );
        let _ = writeln!(
            out,
            "{:<9} {:>8} {:>8} {:>10} {:>8} {:>8}",
            "method", "PSNR dB", ">2/255", "identical", "holes", "warp ms"
        );
        for method in Method::ALL {
            let of = |f: fn(&Row) -> f64| median(run.rows.iter().filter(|r| r.method == method).map(f).collect());
            let psnr = of(|r| r.quality.psnr_db);
            let _ = writeln!(
                out,
                "{:<9} {:>8} {:>7.3}% {:>9.3}% {:>7.3}% {:>8.2}",
                method.name(),
                if psnr.is_finite() { format!("{psnr:.1}") } else { "inf".into() },
                100.0 * of(|r| r.quality.share_over_2_255),
                100.0 * (1.0 - of(|r| r.quality.share_not_identical)),
                100.0 * of(|r| r.hole_share),
                of(|r| r.ms),
            );
        }
    }
    out
}

/// The CSV: a header, then a row per displayed frame and method.
pub(super) fn csv(rows: &[Row], hz: u32) -> String {
    let mut out = format!("{HEADER}\n");
    for r in rows {
        let q = &r.quality;
        let psnr = if q.psnr_db.is_finite() { format!("{:.3}", q.psnr_db) } else { "inf".into() };
        let _ = writeln!(
            out,
            "{},{},{},{:.3},{},{},{:.6},{:.6},{:.6},{:.3}",
            r.trace_every,
            r.frame,
            r.age,
            age_ms(r.age, hz),
            r.method.name(),
            psnr,
            q.share_over_2_255,
            q.share_not_identical,
            r.hole_share,
            r.ms,
        );
    }
    out
}

/// Display frames of age in ms.
fn age_ms(age: u32, hz: u32) -> f64 {
    f64::from(age) * 1e3 / f64::from(hz)
}

/// The plot's series: per method, every frame and each age's median.
pub(super) fn series(rows: &[Row], hz: u32) -> Vec<Series> {
    Method::ALL
        .iter()
        .map(|&method| {
            let mine: Vec<&Row> = rows.iter().filter(|r| r.method == method).collect();
            let mut ages: Vec<u32> = mine.iter().map(|r| r.age).collect();
            ages.sort_unstable();
            ages.dedup();
            Series {
                name: method.name(),
                frames: mine.iter().map(|r| (age_ms(r.age, hz), r.quality.psnr_db)).collect(),
                medians: ages
                    .iter()
                    .map(|&a| {
                        let at: Vec<f64> = mine.iter().filter(|r| r.age == a).map(|r| r.quality.psnr_db).collect();
                        (age_ms(a, hz), median(at))
                    })
                    .collect(),
            }
        })
        .collect()
}
