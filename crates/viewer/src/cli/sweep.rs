//! `stereotrace sweep`: every mode over a range of one parameter (the IPD, the zero-parallax
//! distance, the reflection depth or the scene time), with the cost and quality of the right
//! eye at each step, as a CSV and a plot (`plot.rs`).
//!
//! Each step loads the scene with the step's value applied as its command-line override
//! would be (`setup.rs`), and measures the modes with `bench`'s loop: a warm-up frame per
//! mode, then `--frames` frames with every mode in turn, each against a full trace of the same
//! frame. A step's frames are all the same scene state, so rays and quality are the same on
//! each and the medians only steady the times. Ctrl-C stops after the step being measured; the
//! rows already done are still written.

use std::fmt::Write as _;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use anyhow::Result;
use tracer::{Tracer, MAX_DEPTH_LIMIT};

use crate::args::{FrameArgs, SweepArgs, SweepParam};
use crate::cli::bench::{Bench, Summary, Variant, VARIANTS};
use crate::cli::plot::{self, Figure, Line};
use crate::setup::{BadInput, FrameSetup};
use viewer::write_bytes;

/// The modes a sweep runs unless `--modes` says otherwise.
const DEFAULT_MODES: [&str; 4] = ["full", "copy", "reshade", "exact"];

/// The CSV's columns after the parameter's own.
const COLUMNS: &str =
    "mode,right_over_left_rays,right_ms,left_ms,stereo_over_mono,reprojected_pct,psnr_db,over_2_255_pct";

/// One step's measurements of one mode: a CSV row.
struct Row {
    value: f32,
    summary: Summary,
}

/// Runs the command.
pub fn run(args: &SweepArgs) -> Result<()> {
    let values = steps(args.param, args.from, args.to, args.steps)?;
    let variants = variants(args.modes.as_deref())?;
    check_conflicts(args)?;
    plot::check_outputs(args.csv.as_deref(), args.plot.as_deref())?;
    // Every step's scene and overrides are checked before any work.
    let setups = values.iter().map(|&v| FrameSetup::load(&step_args(args, v), 1)).collect::<Result<Vec<_>>>()?;

    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = Arc::clone(&stop);
        // If a handler is already installed (only in tests), Ctrl-C keeps its default.
        let _ = ctrlc::set_handler(move || stop.store(true, Ordering::SeqCst));
    }
    let bar = indicatif::ProgressBar::new(values.len() as u64).with_style(
        indicatif::ProgressStyle::with_template("{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} steps {msg}")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let (w, h) = (args.frame.width, args.frame.height);
    let threads = rayon::current_num_threads();
    let name = args.param.name();
    let mut bench = Bench::default();
    let mut tracer = Tracer::default();
    let mut rows = Vec::new();
    for (k, (&value, setup)) in values.iter().zip(&setups).enumerate() {
        if stop.load(Ordering::SeqCst) {
            break;
        }
        bar.set_message(format!("{name} = {value}"));
        let t = if args.param == SweepParam::Time { value } else { args.frame.time };
        tracer.update(&setup.scene, t);
        let measured = bench.measure(&mut tracer, (&setup.scene, &setup.camera), (w, h), &variants, args.frames, |_| t);
        rows.extend(measured.iter().map(|m| Row { value, summary: Summary::of(m, threads) }));
        bar.inc(1);
        if bar.is_hidden() {
            // No terminal for the bar: a line per step instead (logs, tests).
            eprintln!("sweep: step {}/{}: {name} = {value} done", k + 1, values.len());
        }
    }
    bar.finish_and_clear();

    let done = rows.len() / variants.len();
    let text = csv(args.param, &rows);
    match &args.csv {
        Some(path) => write_bytes(path, text.as_bytes())?,
        None => super::print_out(&text)?,
    }
    if let Some(path) = &args.plot {
        if !rows.is_empty() {
            let scene = setups[0].path.display().to_string();
            let title = format!("stereotrace sweep: {scene}, {w}×{h} per eye");
            plot::write(path, &Figure { title, x_label: args.param.axis_label(), lines: &lines(&variants, &rows) })?;
        }
    }
    let wrote =
        [args.csv.as_ref().map(|p| p.display().to_string()), args.plot.as_ref().map(|p| p.display().to_string())]
            .into_iter()
            .flatten()
            .collect::<Vec<_>>();
    let interrupted = if done < values.len() { " (interrupted)" } else { "" };
    eprintln!(
        "sweep: {done} of {} steps × {} mode{}{interrupted}: {} rows{}",
        values.len(),
        variants.len(),
        if variants.len() == 1 { "" } else { "s" },
        rows.len(),
        if wrote.is_empty() { String::new() } else { format!(", written to {}", wrote.join(" and ")) }
    );
    if done < values.len() {
        anyhow::bail!("interrupted after {done} of {} steps; the rows done were written", values.len());
    }
    Ok(())
}

impl SweepParam {
    /// The parameter's name on the command line and in the CSV header.
    fn name(self) -> &'static str {
        match self {
            SweepParam::Ipd => "ipd",
            SweepParam::Distance => "distance",
            SweepParam::Depth => "depth",
            SweepParam::Time => "time",
        }
    }

    /// The plot's axis label.
    fn axis_label(self) -> &'static str {
        match self {
            SweepParam::Ipd => "IPD e (scene units)",
            SweepParam::Distance => "zero-parallax distance d (scene units)",
            SweepParam::Depth => "reflection depth (bounces)",
            SweepParam::Time => "scene time t (s)",
        }
    }
}

/// The `n` values from `from` to `to` inclusive, evenly spaced, each checked for `param`.
fn steps(param: SweepParam, from: f64, to: f64, n: u32) -> Result<Vec<f32>, BadInput> {
    let p = param.name();
    for (flag, v) in [("--from", from), ("--to", to)] {
        if !v.is_finite() {
            return Err(BadInput(format!("{flag} {v}: must be a finite number")));
        }
    }
    if from > to {
        return Err(BadInput(format!("--from {from} --to {to}: --from must not be above --to")));
    }
    if n == 1 && from != to {
        return Err(BadInput(format!(
            "--steps 1 --from {from} --to {to}: one step is one value; give --to {from}, or --steps 2 or more"
        )));
    }
    let (lowest, allowed) = match param {
        SweepParam::Ipd => (from >= 0.0, "≥ 0 (0 gives identical eyes)"),
        SweepParam::Distance => (from > 0.0, "> 0"),
        SweepParam::Depth => (from >= 0.0, "0 to 16 bounces"),
        SweepParam::Time => (true, ""),
    };
    if !lowest {
        return Err(BadInput(format!("--param {p} --from {from}: the {p} must be {allowed}")));
    }
    if param == SweepParam::Depth && to > f64::from(MAX_DEPTH_LIMIT) {
        return Err(BadInput(format!("--param depth --to {to}: the depth must be 0 to {MAX_DEPTH_LIMIT} bounces")));
    }
    let values: Vec<f64> = (0..n)
        .map(|k| if k + 1 == n { to } else { from + (to - from) * f64::from(k) / f64::from((n - 1).max(1)) })
        .collect();
    if param == SweepParam::Depth {
        if let Some(v) = values.iter().find(|v| (*v - v.round()).abs() > 1e-9) {
            return Err(BadInput(format!(
                "--param depth --from {from} --to {to} --steps {n}: a step at depth {v} is no whole number of bounces; choose --steps so the steps are whole (e.g. --steps {})",
                (to - from).round() as u64 + 1
            )));
        }
    }
    Ok(values.into_iter().map(|v| if param == SweepParam::Depth { v.round() as f32 } else { v as f32 }).collect())
}

/// The variants `--modes` names (default: the four modes), in the order given.
fn variants(modes: Option<&[String]>) -> Result<Vec<Variant>, BadInput> {
    let names: Vec<&str> = match modes {
        Some(m) => m.iter().map(|s| s.trim()).collect(),
        None => DEFAULT_MODES.to_vec(),
    };
    let mut out: Vec<Variant> = Vec::new();
    for name in names {
        let Some(&v) = VARIANTS.iter().find(|v| v.0 == name) else {
            let known: Vec<&str> = VARIANTS.iter().map(|v| v.0).collect();
            return Err(BadInput(format!("--modes: unknown mode `{name}`: expected some of {}", known.join(", "))));
        };
        if out.iter().any(|o| o.0 == name) {
            return Err(BadInput(format!("--modes: `{name}` is given twice")));
        }
        out.push(v);
    }
    if out.is_empty() {
        return Err(BadInput("--modes: no mode given".into()));
    }
    Ok(out)
}

/// Refuses an override of the swept parameter itself.
fn check_conflicts(args: &SweepArgs) -> Result<(), BadInput> {
    let f = &args.frame;
    let clash = match args.param {
        SweepParam::Ipd => f.ipd.is_some().then_some("--ipd"),
        SweepParam::Distance => f.distance.is_some().then_some("--distance"),
        SweepParam::Depth => f.depth.is_some().then_some("--depth"),
        SweepParam::Time => (f.time != 0.0).then_some("--time"),
    };
    match clash {
        Some(flag) => Err(BadInput(format!(
            "{flag} and --param {} both set the {}: give one",
            args.param.name(),
            args.param.name()
        ))),
        None => Ok(()),
    }
}

/// The frame arguments of the step at `value`.
fn step_args(args: &SweepArgs, value: f32) -> FrameArgs {
    let mut f = args.frame.clone();
    match args.param {
        SweepParam::Ipd => f.ipd = Some(value),
        SweepParam::Distance => f.distance = Some(value),
        SweepParam::Depth => f.depth = Some(value as u32),
        SweepParam::Time => f.time = value,
    }
    f
}

/// The CSV: a header, then a row per step and mode.
fn csv(param: SweepParam, rows: &[Row]) -> String {
    let mut out = format!("{},{COLUMNS}\n", param.name());
    for r in rows {
        let s = &r.summary;
        let psnr = if s.quality.psnr_db.is_finite() { format!("{:.3}", s.quality.psnr_db) } else { "inf".into() };
        let _ = writeln!(
            out,
            "{},{},{:.6},{:.3},{:.3},{:.4},{:.3},{},{:.4}",
            r.value,
            s.name,
            s.stats.right_ray_ratio(),
            s.stats.right.ms,
            s.stats.left.ms,
            s.stereo_over_mono,
            100.0 * s.stats.pixels.reprojected_share(),
            psnr,
            100.0 * s.quality.share_over_2_255,
        );
    }
    out
}

/// The plot's lines: one per variant, in sweep order.
fn lines(variants: &[Variant], rows: &[Row]) -> Vec<Line> {
    variants
        .iter()
        .map(|&(name, ..)| {
            let mine = || rows.iter().filter(move |r| r.summary.name == name);
            let x = |r: &Row| f64::from(r.value);
            Line {
                name,
                rays: mine().map(|r| (x(r), r.summary.stats.right_ray_ratio())).collect(),
                time: mine().map(|r| (x(r), r.summary.stats.right_time_ratio())).collect(),
                psnr: mine().map(|r| (x(r), r.summary.quality.psnr_db)).collect(),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_are_evenly_spaced_and_end_on_both_bounds() {
        let v = steps(SweepParam::Ipd, 0.0, 2.0, 11).unwrap();
        assert_eq!(v.len(), 11, "eleven steps");
        assert_eq!((v[0], v[10]), (0.0, 2.0), "both ends exactly");
        assert_eq!(v[3].to_string(), "0.6", "0.6, not 0.6000000000000001");
        assert_eq!(steps(SweepParam::Time, -1.0, -1.0, 1).unwrap(), vec![-1.0], "one step at one value");
        assert_eq!(steps(SweepParam::Depth, 0.0, 4.0, 5).unwrap(), vec![0.0, 1.0, 2.0, 3.0, 4.0], "whole bounces");
    }

    #[test]
    fn bad_ranges_are_refused_with_the_flags_named() {
        let err = |p, a, b, n| steps(p, a, b, n).unwrap_err().0;
        assert_eq!(err(SweepParam::Ipd, 2.0, 0.0, 5), "--from 2 --to 0: --from must not be above --to");
        assert_eq!(
            err(SweepParam::Ipd, -0.5, 1.0, 5),
            "--param ipd --from -0.5: the ipd must be ≥ 0 (0 gives identical eyes)"
        );
        assert_eq!(err(SweepParam::Distance, 0.0, 1.0, 5), "--param distance --from 0: the distance must be > 0");
        assert_eq!(err(SweepParam::Depth, -1.0, 3.0, 5), "--param depth --from -1: the depth must be 0 to 16 bounces");
        assert_eq!(err(SweepParam::Depth, 0.0, 17.0, 18), "--param depth --to 17: the depth must be 0 to 16 bounces");
        assert!(err(SweepParam::Depth, 0.0, 3.0, 3).contains("depth 1.5 is no whole number"), "fractional depth");
        assert_eq!(err(SweepParam::Time, f64::NAN, 1.0, 5), "--from NaN: must be a finite number");
        assert_eq!(err(SweepParam::Time, 0.0, f64::INFINITY, 5), "--to inf: must be a finite number");
        assert!(
            err(SweepParam::Ipd, 0.0, 1.0, 1).starts_with("--steps 1 --from 0 --to 1: one step is one value"),
            "one step, two values"
        );
    }

    #[test]
    fn modes_are_checked_and_kept_in_order() {
        let names = |v: Vec<Variant>| v.into_iter().map(|v| v.0).collect::<Vec<_>>();
        assert_eq!(names(variants(None).unwrap()), DEFAULT_MODES, "the four modes by default");
        let given = ["exact".to_owned(), "copy+edges".to_owned()];
        assert_eq!(names(variants(Some(&given)).unwrap()), ["exact", "copy+edges"], "as given");
        let bad = ["fast".to_owned()];
        assert!(variants(Some(&bad))
            .unwrap_err()
            .0
            .starts_with("--modes: unknown mode `fast`: expected some of full, copy"));
        let twice = ["copy".to_owned(), "copy".to_owned()];
        assert_eq!(variants(Some(&twice)).unwrap_err().0, "--modes: `copy` is given twice");
    }

    #[test]
    fn the_csv_writes_inf_for_identical_images() {
        let summary = |psnr_db| Summary {
            name: "copy",
            stats: stereo::FrameStats::default(),
            quality: stereo::Quality { psnr_db, ..stereo::Quality::default() },
            stereo_ms: 0.0,
            stereo_over_mono: 1.0,
            mrays_per_core: 0.0,
            animation: None,
        };
        let rows = [Row { value: 0.0, summary: summary(f64::INFINITY) }, Row { value: 0.2, summary: summary(31.25) }];
        let text = csv(SweepParam::Ipd, &rows);
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], format!("ipd,{COLUMNS}"), "the header names the parameter");
        assert_eq!(lines[1], "0,copy,0.000000,0.000,0.000,1.0000,0.000,inf,0.0000", "infinite PSNR is `inf`");
        assert_eq!(lines[2], "0.2,copy,0.000000,0.000,0.000,1.0000,0.000,31.250,0.0000", "finite PSNR in dB");
    }
}
