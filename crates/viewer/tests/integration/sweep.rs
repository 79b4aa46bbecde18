//! End-to-end tests of `stereotrace sweep`: the CSV's rows, what reprojection predicts at
//! IPD 0, the plot files, bad arguments, and Ctrl-C keeping the rows done.

use std::collections::BTreeMap;

use crate::common::{interrupted, read_rgb_png, stereotrace, tmp};

const HEADER: &str =
    "mode,right_over_left_rays,right_ms,left_ms,stereo_over_mono,reprojected_pct,psnr_db,over_2_255_pct";

/// One CSV row: the parameter's value as written, the mode, and the other columns by name.
struct Row {
    value: String,
    mode: String,
    cols: BTreeMap<&'static str, f64>,
}

/// Parses the CSV, checking its header names `param` and the documented columns.
fn parse(csv: &str, param: &str) -> Vec<Row> {
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some(format!("{param},{HEADER}").as_str()), "the header");
    let names: Vec<&'static str> = HEADER.split(',').skip(1).collect();
    lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            assert_eq!(f.len(), names.len() + 2, "{l}: every column");
            let cols = names
                .iter()
                .zip(&f[2..])
                .map(|(&n, v)| (n, v.parse::<f64>().unwrap_or_else(|e| panic!("{n} = {v} in {l}: {e}"))))
                .collect();
            Row { value: f[0].to_owned(), mode: f[1].to_owned(), cols }
        })
        .collect()
}

#[test]
fn an_ipd_sweep_writes_a_row_per_step_and_mode_and_ipd_0_costs_least() {
    let (csv, plot) = (tmp("ipd.csv"), tmp("ipd.png"));
    let out = stereotrace(&[
        "sweep",
        "--scene",
        "assets/scenes/seed.toml",
        "--param",
        "ipd",
        "--from",
        "0",
        "--to",
        "2",
        "--steps",
        "11",
        "--width",
        "64",
        "--height",
        "36",
        "--frames",
        "1",
        "--csv",
        csv.to_str().unwrap(),
        "--plot",
        plot.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("11 of 11 steps × 4 modes: 44 rows"), "{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.lines().nth(2).is_some_and(|l| l.starts_with("0,copy,") && l.contains(",inf,")), "`inf`: {text}");
    let rows = parse(&text, "ipd");
    assert_eq!(rows.len(), 11 * 4, "11 steps × 4 modes");
    let values: Vec<&str> = rows.iter().step_by(4).map(|r| r.value.as_str()).collect();
    assert_eq!(values, ["0", "0.2", "0.4", "0.6", "0.8", "1", "1.2", "1.4", "1.6", "1.8", "2"], "the steps");
    for (k, r) in rows.iter().enumerate() {
        assert_eq!(r.mode, ["full", "copy", "reshade", "exact"][k % 4], "modes in order at each step");
    }
    let of = |mode: &'static str| rows.iter().filter(move |r| r.mode == mode);
    let rays = |r: &Row| r.cols["right_over_left_rays"];

    // IPD 0: the eyes coincide, every pixel reprojects onto itself, copy is the left image.
    let copy0 = of("copy").next().unwrap();
    assert_eq!(copy0.value, "0");
    assert!(copy0.cols["psnr_db"].is_infinite(), "copy at IPD 0 is identical to full: `inf`");
    assert_eq!(rays(copy0), 0.0, "copy at IPD 0 casts no ray for the right eye");
    for mode in ["copy", "reshade", "exact"] {
        let first = of(mode).next().unwrap();
        assert_eq!(first.cols["reprojected_pct"], 100.0, "{mode}: every pixel reprojects at IPD 0");
        for r in of(mode) {
            assert!(
                rays(first) <= rays(r),
                "{mode}: IPD 0 costs least ({} at 0, {} at {})",
                rays(first),
                rays(r),
                r.value
            );
        }
        let last = of(mode).next_back().unwrap();
        assert!(rays(last) > rays(first), "{mode}: more IPD, more gaps, more rays");
        assert!(last.cols["reprojected_pct"] < 100.0, "{mode}: gaps at IPD 2");
    }
    // Full traces the right eye whatever the IPD: exactly the left eye's rays at IPD 0.
    assert_eq!(rays(of("full").next().unwrap()), 1.0, "full at IPD 0");
    assert!(of("full").all(|r| r.cols["psnr_db"].is_infinite()), "full is its own reference");
    for (copy, exact) in of("copy").zip(of("exact")) {
        assert!(exact.cols["psnr_db"] >= copy.cols["psnr_db"], "exact is never worse than copy ({})", copy.value);
    }
    assert!(of("copy").skip(1).all(|r| r.cols["psnr_db"].is_finite()), "copy differs from full once IPD > 0");

    let (w, h, rgb) = read_rgb_png(&plot);
    assert_eq!((w, h), (1000, 900), "the plot's size");
    let has = |c: [u8; 3]| rgb.chunks_exact(3).any(|p| p == c);
    assert!(has([214, 39, 40]) && has([44, 160, 44]), "copy's and exact's lines are drawn");
}

#[test]
fn an_svg_plot_and_the_csv_on_stdout() {
    let plot = tmp("distance.svg");
    let out = stereotrace(&[
        "sweep",
        "--param",
        "distance",
        "--from",
        "6",
        "--to",
        "12",
        "--steps",
        "2",
        "--modes",
        "copy+edges,exact",
        "--width",
        "32",
        "--height",
        "18",
        "--frames",
        "1",
        "--plot",
        plot.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let rows = parse(&String::from_utf8_lossy(&out.stdout), "distance");
    let got: Vec<(&str, &str)> = rows.iter().map(|r| (r.value.as_str(), r.mode.as_str())).collect();
    assert_eq!(got, [("6", "copy+edges"), ("6", "exact"), ("12", "copy+edges"), ("12", "exact")], "rows");
    let svg = std::fs::read_to_string(&plot).unwrap();
    assert!(svg.starts_with("<svg"), "an SVG file");
    for text in ["cost of the right eye", "quality of the right eye", "copy+edges", "exact", "zero-parallax distance d"]
    {
        assert!(svg.contains(text), "the SVG names {text}");
    }
}

#[test]
fn bad_sweep_arguments_exit_2_with_a_clear_message() {
    let csv = tmp("never.csv");
    let c = csv.to_str().unwrap();
    let base = ["sweep", "--width", "8", "--height", "8", "--frames", "1", "--csv", c];
    let cases: [(&[&str], &str); 12] = [
        (&["--param", "ipd", "--from", "0", "--to", "1", "--steps", "0"], "0 is not in 1..=1000"),
        (&["--param", "ipd", "--from", "2", "--to", "0"], "--from 2 --to 0: --from must not be above --to"),
        (&["--param", "ipd", "--from", "-0.5", "--to", "1"], "--param ipd --from -0.5: the ipd must be ≥ 0"),
        (&["--param", "distance", "--from", "0", "--to", "1"], "--param distance --from 0: the distance must be > 0"),
        (&["--param", "depth", "--from", "-1", "--to", "3"], "--param depth --from -1: the depth must be 0 to 16"),
        (&["--param", "depth", "--from", "0", "--to", "3", "--steps", "3"], "depth 1.5 is no whole number"),
        (&["--param", "time", "--from", "NaN", "--to", "1"], "--from NaN: must be a finite number"),
        (&["--param", "speed", "--from", "0", "--to", "1"], "invalid value 'speed' for '--param <PARAM>'"),
        (&["--param", "ipd", "--ipd", "0.5", "--from", "0", "--to", "1"], "--ipd and --param ipd both set the ipd"),
        (&["--param", "ipd", "--from", "0", "--to", "1", "--modes", "copy,fast"], "--modes: unknown mode `fast`"),
        (
            &["--param", "ipd", "--from", "0", "--to", "1", "--plot", "no/such/dir/p.png"],
            "directory no/such/dir does not exist",
        ),
        (
            &["--param", "ipd", "--from", "0", "--to", "1", "--plot", "p.jpg"],
            "--plot p.jpg: the plot is a PNG (.png) or an SVG (.svg)",
        ),
    ];
    for (args, message) in cases {
        let all: Vec<&str> = base.iter().chain(args).copied().collect();
        let out = stereotrace(&all);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: bad input, exit 2: {err}");
        assert!(err.contains(message), "{args:?}: the message should say `{message}`: {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(!csv.exists(), "{args:?}: nothing written");
    }
}

/// Ctrl-C (SIGINT) stops the sweep after the step being measured: the CSV holds every mode of
/// each step done, and the exit code says the sweep did not finish.
#[test]
fn ctrl_c_keeps_the_rows_done() {
    let csv = tmp("interrupted.csv");
    let args = ["sweep", "--param", "time", "--from", "0", "--to", "100", "--steps", "1000", "--frames", "1"];
    let size = ["--width", "96", "--height", "54", "--csv", csv.to_str().unwrap()];
    let (status, rest) = interrupted(&[&args[..], &size[..]].concat(), "step 2/1000");
    assert_eq!(status.code(), Some(1), "an interrupted sweep did not finish: {rest}");
    assert!(rest.contains("(interrupted)") && rest.contains("interrupted after"), "{rest}");
    let rows = parse(&std::fs::read_to_string(&csv).unwrap(), "time");
    assert!(rows.len() >= 2 * 4 && rows.len() < 1000 * 4, "the steps done: {} rows", rows.len());
    assert_eq!(rows.len() % 4, 0, "whole steps only");
    let last = &rows[rows.len() - 4..];
    assert!(last.iter().all(|r| r.value == last[0].value), "the last step has all four modes");
}

#[test]
fn help_documents_every_sweep_flag() {
    let out = stereotrace(&["sweep", "--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for flag in ["--param", "--from", "--to", "--steps", "--modes", "--frames", "--csv", "--plot", "--scene", "--width"]
    {
        assert!(text.contains(flag), "sweep --help lacks {flag}");
    }
    for value in ["ipd", "distance", "depth", "time", "copy+edges"] {
        assert!(text.contains(value), "sweep --help lacks {value}");
    }
    let top = String::from_utf8_lossy(&stereotrace(&["--help"]).stdout).into_owned();
    assert!(top.contains("sweep"), "--help lists sweep: {top}");
}
