//! End-to-end tests of `stereotrace timewarp`: a frame warped to the pose it was traced for
//! is that frame, a stale frame is not, the JSON's keys, the CSV's rows, the plot, bad
//! arguments, and Ctrl-C keeping the rows done.

use serde_json::Value;

use crate::common::{interrupted, read_rgb_png, stereotrace, tmp, with_flag};

const HEADER: &str =
    "trace_every,frame,age_frames,age_ms,method,psnr_db,share_over_2_255,share_not_identical,hole_share,ms";

const METHODS: [&str; 3] = ["none", "rotation", "depth"];

/// `timewarp` on the seed scene at a tiny size with `extra` arguments.
fn timewarp(extra: &[&str]) -> std::process::Output {
    let base = ["timewarp", "--scene", "assets/scenes/seed.toml", "--width", "48", "--height", "32"];
    stereotrace(&base.iter().chain(extra).copied().collect::<Vec<_>>())
}

fn json(extra: &[&str]) -> Value {
    let out = timewarp(&[extra, &["--json"]].concat());
    assert!(out.status.success(), "failed: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("stdout is not one JSON object: {e}"))
}

fn number(v: &Value, key: &str) -> f64 {
    v[key].as_f64().unwrap_or_else(|| panic!("{key} is not a number in {v}"))
}

/// A wall time in milliseconds: a number, finite and not negative (its size is the
/// machine's business, and a coarse clock may read 0).
fn millis(v: &Value, key: &str) -> f64 {
    let ms = number(v, key);
    assert!(ms.is_finite() && ms >= 0.0, "{key} = {ms} is no wall time, in {v}");
    ms
}

/// Traced every display frame, every frame is shown at the pose it was traced for: the
/// depth warp gives it back bit for bit (and so do the others).
#[test]
fn traced_every_frame_the_depth_warp_is_the_trace() {
    let r = json(&["--motion", "yaw=30,x=0.3", "--trace-every", "1", "--seconds", "0.05"]);
    assert_eq!(r["frames"], 5, "0.05 s at 90 Hz: {r}");
    for method in METHODS {
        let w = &r["warps"][method];
        assert_eq!((number(w, "share_not_identical"), number(w, "hole_share")), (0.0, 0.0), "{method}: {w}");
        assert!(w["psnr_db"].is_null(), "{method}: identical, PSNR null: {w}");
    }
}

/// Every key the JSON documents; and a head that moves makes a stale frame differ, which the
/// depth warp mends better than showing it as is.
#[test]
fn the_json_has_every_key_and_the_depth_warp_beats_the_stale_frame() {
    let r = json(&["--motion", "yaw=60", "--trace-every", "3", "--seconds", "0.1", "--display-hz", "60"]);
    for key in ["scene", "width", "height", "mode", "motion", "display_hz", "trace_every", "seconds", "guard"] {
        assert!(!r[key].is_null(), "{key} in {r}");
    }
    assert_eq!((&r["mode"], &r["motion"], &r["trace_every"]), (&"exact".into(), &"yaw=60".into(), &3.into()));
    assert_eq!(r["frames"], 6, "0.1 s at 60 Hz");
    assert_eq!(r["guard"], serde_json::json!([2, 2]), "5 % of 48 × 32, rounded");
    millis(&r, "trace_ms");
    millis(&r, "banded_trace_ms");
    for method in METHODS {
        let w = &r["warps"][method];
        for key in ["psnr_db", "share_over_2_255", "share_not_identical", "hole_share", "ms"] {
            assert!(w.get(key).is_some(), "warps.{method}.{key} in {r}");
        }
        millis(w, "ms");
    }
    let (none, depth) = (&r["warps"]["none"], &r["warps"]["depth"]);
    assert!(number(none, "share_not_identical") > 0.0, "a turned head sees another picture: {none}");
    assert!(number(depth, "psnr_db") > number(none, "psnr_db") + 3.0, "the warp mends it: {depth} vs {none}");
    assert_eq!(number(none, "ms"), 0.0, "showing the stale frame costs nothing");
}

/// The CSV has a row per displayed frame and method, for each --trace-every value, in order,
/// each frame's age since its trace; and the plot is drawn.
#[test]
fn the_csv_has_a_row_per_frame_and_method_and_the_plot_is_drawn() {
    let (csv, plot) = (tmp("timewarp.csv"), tmp("timewarp.png"));
    let out = timewarp(&[
        "--motion",
        "yaw=30,pitch=-5,z=1",
        "--trace-every",
        "2..3",
        "--seconds",
        "0.1",
        "--csv",
        csv.to_str().unwrap(),
        "--plot",
        plot.to_str().unwrap(),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(err.contains("18 of 18 displayed frames × 3 methods: 54 rows"), "{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(HEADER));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 2 * 9 * 3, "2 runs × 9 frames (0.1 s at 90 Hz) × 3 methods");
    for (k, r) in rows.iter().enumerate() {
        assert_eq!(r.len(), HEADER.split(',').count(), "{r:?}");
        let (every, frame) = (if k < 27 { 2 } else { 3 }, (k % 27) / 3);
        assert_eq!((r[0], r[1]), (every.to_string().as_str(), frame.to_string().as_str()), "{r:?}");
        assert_eq!(r[2], (frame % every).to_string(), "age in frames: {r:?}");
        assert_eq!(r[4], METHODS[k % 3], "methods in order: {r:?}");
        let psnr = r[5];
        assert_eq!(psnr == "inf", r[7] == "0.000000", "`inf` exactly where identical: {r:?}");
        if r[2] == "0" {
            assert_eq!(psnr, "inf", "age 0: shown as traced: {r:?}");
        }
    }
    let (w, h, rgb) = read_rgb_png(&plot);
    assert_eq!((w, h), (900, 520), "the plot's size");
    let has = |c: [u8; 3]| rgb.chunks_exact(3).any(|p| p == c);
    assert!(has([214, 39, 40]) && has([44, 160, 44]), "none's and depth's lines are drawn");
}

#[test]
fn bad_timewarp_arguments_exit_2_with_a_clear_message() {
    let csv = tmp("timewarp-never.csv");
    let c = csv.to_str().unwrap();
    let ok = ["--motion", "yaw=30", "--trace-every", "2", "--csv", c];
    let with = |flag: &'static str, value: &'static str| with_flag(&ok, flag, value);
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (with("--motion", "roll=3"), "invalid value 'roll=3' for '--motion"),
        (with("--motion", "roll=3"), "unknown key `roll`"),
        (with("--motion", "yaw=fast"), "yaw=`fast` is not a number"),
        (with("--motion", "yaw"), "`yaw` has no `=`"),
        (with("--motion", "yaw=1,yaw=2"), "`yaw` is given twice"),
        (with("--motion", "-x=1"), "unknown key `-x`"),
        (with("--display-hz", "0"), "invalid value '0' for '--display-hz <HZ>': 0 is not in 1..=240"),
        (with("--display-hz", "241"), "241 is not in 1..=240"),
        (with("--trace-every", "0"), "invalid value '0' for '--trace-every"),
        (with("--trace-every", "3..1"), "the range's first value is above its last"),
        (with("--seconds", "0"), "--seconds 0: must be more than 0 and at most 60"),
        (with("--seconds", "-1"), "--seconds -1: must be more than 0"),
        (with("--seconds", "1000"), "--seconds 1000: must be more than 0 and at most 60"),
        (with("--guard-band", "30"), "invalid value '30' for '--guard-band <PERCENT>': 30 is not in 0..=25"),
        (with("--plot", "p.jpg"), "--plot p.jpg: the plot is a PNG (.png) or an SVG (.svg)"),
        (with("--mode", "fast"), "unknown mode `fast`"),
    ];
    for (args, message) in cases {
        let out = timewarp(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: bad input, exit 2: {err}");
        assert!(err.contains(message), "{args:?}: the message should say `{message}`: {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(!csv.exists(), "{args:?}: nothing written");
    }
    let out = stereotrace(&["timewarp", "--width", "0", "--height", "8", "--motion", "yaw=1", "--trace-every", "1"]);
    assert_eq!(out.status.code(), Some(2), "a width of 0");
    assert!(String::from_utf8_lossy(&out.stderr).contains("invalid value '0' for '--width <W>'"), "named");
    let out = timewarp(&["--trace-every", "2"]);
    assert_eq!(out.status.code(), Some(2), "--motion is required");
    assert!(String::from_utf8_lossy(&out.stderr).contains("--motion"), "named");
}

/// Ctrl-C (SIGINT) stops after the displayed frame being measured: the CSV holds every
/// method of each frame done, and the exit code says the run did not finish.
#[test]
fn ctrl_c_keeps_the_rows_done() {
    let csv = tmp("timewarp-interrupted.csv");
    let args = ["timewarp", "--motion", "yaw=30", "--trace-every", "1..100", "--seconds", "60", "--display-hz", "10"];
    let size = ["--width", "64", "--height", "36", "--csv", csv.to_str().unwrap()];
    let (status, rest) = interrupted(&[&args[..], &size[..]].concat(), "frame 20/600");
    assert_eq!(status.code(), Some(1), "an interrupted run did not finish: {rest}");
    assert!(rest.contains("(interrupted)") && rest.contains("interrupted after"), "{rest}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let rows: Vec<&str> = text.lines().skip(1).collect();
    assert!(rows.len() >= 20 * 3 && rows.len() < 100 * 600 * 3, "the frames done: {} rows", rows.len());
    assert_eq!(rows.len() % 3, 0, "whole frames only");
    let last: Vec<&str> = rows[rows.len() - 3..].iter().map(|r| r.split(',').nth(4).unwrap()).collect();
    assert_eq!(last, METHODS, "the last frame has all three methods");
}

#[test]
fn help_documents_every_timewarp_flag() {
    let out = stereotrace(&["timewarp", "--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for flag in [
        "--motion",
        "--display-hz",
        "--trace-every",
        "--seconds",
        "--guard-band",
        "--mode",
        "--json",
        "--csv",
        "--plot",
        "--scene",
        "--width",
    ] {
        assert!(text.contains(flag), "timewarp --help lacks {flag}");
    }
    let top = String::from_utf8_lossy(&stereotrace(&["--help"]).stdout).into_owned();
    assert!(top.contains("timewarp"), "--help lists timewarp: {top}");
}
