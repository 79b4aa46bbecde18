//! End-to-end tests of `stereotrace replay`: the JSON's keys and types, a row of the CSV per
//! presented frame, the plot, a still head converging to the reference (and a single-sample
//! frame not converging to a supersampled one), bad arguments, and Ctrl-C keeping what was
//! recorded.

use serde_json::Value;

use crate::common::{interrupted, read_rgb_png, stereotrace, tmp, with_flag};

const HEADER: &str = "frame,t_s,phase,seq,age_ms,guessed_share,warped,density,spp,converged,yaw_deg,pitch_deg,x,y,z,psnr_db,share_over_2_255,fresh_psnr_db";

/// `replay` on the seed scene at a tiny size with `extra` arguments.
fn replay(extra: &[&str]) -> std::process::Output {
    let base = ["replay", "--scene", "assets/scenes/seed.toml", "--width", "48", "--height", "32"];
    stereotrace(&base.iter().chain(extra).copied().collect::<Vec<_>>())
}

fn json(extra: &[&str]) -> Value {
    let out = replay(&[extra, &["--json"]].concat());
    assert!(out.status.success(), "failed: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("stdout is not one JSON object: {e}"))
}

/// A number or null (a PSNR of identical frames, or of none).
fn number_or_null(v: &Value, path: &str) {
    assert!(v.is_number() || v.is_null(), "{path} = {v} is neither a number nor null");
}

/// The documented keys, with their types, of `presented` and of each part.
fn check_part(p: &Value, name: &str) {
    for (key, tail) in [("psnr_db", "median"), ("psnr_db", "p10"), ("share_over_2_255", "median")] {
        number_or_null(&p[key][tail], &format!("{name}.{key}.{tail}"));
    }
    for tail in ["median", "p10"] {
        number_or_null(&p["fresh"]["psnr_db"][tail], &format!("{name}.fresh.psnr_db.{tail}"));
    }
    for (key, tail) in [("age_ms", "median"), ("age_ms", "p90"), ("guessed_share", "median")] {
        let v = p[key][tail].as_f64().unwrap_or_else(|| panic!("{name}.{key}.{tail} is not a number: {p}"));
        assert!(v.is_finite() && v >= 0.0, "{name}.{key}.{tail} = {v}");
    }
    assert!(p["sampling"]["density"]["median"].is_number(), "{name}.sampling: {p}");
}

/// Every key the issue asks for, of its type; the moving and resting parts add up.
#[test]
fn the_json_has_every_key_with_its_type() {
    let r = json(&["--motion", "yaw=30,x=0.5", "--seconds", "0.3", "--still", "0.3", "--score-every", "4"]);
    assert_eq!(r["policy"], "progressive", "the default policy: {r}");
    let frames = r["frames"].as_u64().unwrap_or_else(|| panic!("frames: {r}"));
    let scored = r["scored"].as_u64().unwrap_or_else(|| panic!("scored: {r}"));
    assert!(frames >= 10, "0.3 s moving at 90 Hz presents every tick: {r}");
    assert_eq!(scored, frames.div_ceil(4), "every 4th frame scored: {r}");
    check_part(&r["presented"], "presented");
    for part in ["moving", "resting"] {
        check_part(&r[part], part);
    }
    assert_eq!(r["moving"]["frames"].as_u64().unwrap() + r["resting"]["frames"].as_u64().unwrap(), frames);
    number_or_null(&r["converge_s"], "converge_s");
    number_or_null(&r["first_full_s"], "first_full_s");
    assert!(r["memory"]["accumulation"].is_u64(), "the refinement's bytes: {r}");
    for key in ["scene", "width", "height", "mode", "motion", "seconds", "still", "display_hz", "ticks"] {
        assert!(!r[key].is_null(), "{key} in {r}");
    }
    assert_eq!((&r["max_supersample"], &r["target_age_ms"], &r["mode"]), (&4.into(), &33.0.into(), &"exact".into()));
    let psnr = r["moving"]["psnr_db"]["median"].as_f64().unwrap_or_else(|| panic!("a moving head's frames: {r}"));
    assert!(psnr > 10.0 && psnr < 80.0, "warped frames against a supersampled trace: {psnr} dB");
    assert_eq!(json(&["--motion", "yaw=30", "--seconds", "0.1", "--policy", "fixed"])["target_age_ms"], Value::Null);
}

/// A still head at full resolution shows the frame `render --supersample 1` makes, byte for
/// byte: it has converged at S = 1, under either policy; at S = 2 a single-sample frame
/// never equals the reference.
#[test]
fn a_resting_head_converges_to_the_reference() {
    let still = ["--motion", "yaw=0", "--seconds", "0.05", "--still", "0.4", "--score-every", "1"];
    for policy in ["fixed", "progressive"] {
        let r = json(&[&still[..], &["--policy", policy, "--max-supersample", "1"]].concat());
        let s = r["converge_s"].as_f64().unwrap_or_else(|| panic!("{policy}: converge_s is a number: {r}"));
        assert!((0.0..0.4).contains(&s), "{policy}: {s}");
        assert_eq!(r["resting"]["psnr_db"]["median"], Value::Null, "{policy}: identical at rest: {r}");
        assert_eq!(r["resting"]["share_over_2_255"]["median"], 0.0, "{policy}: {r}");
    }
    let r = json(&[&still[..], &["--policy", "fixed", "--max-supersample", "2"]].concat());
    assert_eq!(r["converge_s"], Value::Null, "one sample a pixel is not the 2 × 2 picture: {r}");
    assert!(r["resting"]["psnr_db"]["median"].is_number(), "{r}");
    // At rest, `fixed` shows the pose traced at one sample a pixel: `fresh`'s own score.
    assert_eq!(r["resting"]["psnr_db"], r["resting"]["fresh"]["psnr_db"], "{r}");
    // The progressive policy refines the resting pose to 2 × 2 samples a pixel: the
    // reference, byte for byte.
    let r = json(&[&still[..], &["--policy", "progressive", "--max-supersample", "2"]].concat());
    let s = r["converge_s"].as_f64().unwrap_or_else(|| panic!("progressive at 2 × 2 converges: {r}"));
    assert!((0.0..0.4).contains(&s), "{s}");
    // Two eyes of 2 × 2 samples (4 bytes) and three sums (4 bytes each) per pixel, at least.
    let bytes = r["memory"]["accumulation"].as_u64().unwrap();
    let (w, h) = (r["width"].as_u64().unwrap(), r["height"].as_u64().unwrap());
    assert!(bytes >= 2 * (4 * 4 + 12) * w * h, "the accumulation is counted: {bytes} B");
}

/// The CSV has a row per presented frame, in time order, scored every k-th; and the plot is
/// drawn.
#[test]
fn the_csv_has_a_row_per_presented_frame_and_the_plot_is_drawn() {
    let (csv, plot) = (tmp("replay.csv"), tmp("replay.png"));
    let r = json(&[
        "--motion",
        "yaw=20,x=1.5",
        "--seconds",
        "0.3",
        "--still",
        "0.3",
        "--score-every",
        "3",
        "--csv",
        csv.to_str().unwrap(),
        "--plot",
        plot.to_str().unwrap(),
    ]);
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(HEADER));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len() as u64, r["frames"].as_u64().unwrap(), "a row per presented frame");
    let mut last_t = -1.0;
    for (k, row) in rows.iter().enumerate() {
        assert_eq!(row.len(), HEADER.split(',').count(), "{row:?}");
        assert_eq!(row[0], k.to_string(), "{row:?}");
        let t: f64 = row[1].parse().unwrap();
        assert!(t > last_t, "in time order: {row:?}");
        last_t = t;
        assert_eq!(row[2], if t < 0.3 { "moving" } else { "resting" }, "{row:?}");
        assert_eq!(row[15].is_empty(), k % 3 != 0, "every 3rd frame scored: {row:?}");
        assert_eq!(row[17].is_empty(), row[15].is_empty(), "a scored frame's fresh trace too: {row:?}");
    }
    let (w, h, rgb) = read_rgb_png(&plot);
    assert_eq!((w, h), (1000, 760), "the plot's size");
    let has = |c: [u8; 3]| rgb.chunks_exact(3).any(|p| p == c);
    assert!(has([31, 119, 180]) && has([44, 160, 44]), "moving and resting frames drawn");
}

#[test]
fn bad_replay_arguments_exit_2_naming_the_flag() {
    let csv = tmp("replay-never.csv");
    let c = csv.to_str().unwrap();
    let ok = ["--motion", "yaw=30", "--seconds", "0.1", "--csv", c];
    let with = |flag: &'static str, value: &'static str| with_flag(&ok, flag, value);
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (with("--seconds", "0"), "--seconds 0: must be more than 0 and at most 60"),
        (with("--seconds", "-1"), "--seconds -1: must be more than 0"),
        (with("--seconds", "61"), "--seconds 61: must be more than 0 and at most 60"),
        (with("--still", "-1"), "--still -1: must be 0 to 600 seconds"),
        (with("--display-hz", "0"), "invalid value '0' for '--display-hz <HZ>': 0 is not in 1..=240"),
        (with("--score-every", "0"), "invalid value '0' for '--score-every <K>': 0 is not in 1..=10000"),
        (with("--max-supersample", "0"), "invalid value '0' for '--max-supersample <S>': 0 is not in 1..=4"),
        (with("--max-supersample", "5"), "invalid value '5' for '--max-supersample <S>': 5 is not in 1..=4"),
        (with("--policy", "lazy"), "invalid value 'lazy' for '--policy <POLICY>'"),
        (with("--target-age-ms", "0"), "--target-age-ms 0: must be more than 0 and at most 1000"),
        (with("--motion", "roll=3"), "unknown key `roll`"),
        (with("--motion", "yaw=fast"), "yaw=`fast` is not a number"),
        (with("--plot", "p.jpg"), "--plot p.jpg: the plot is a PNG (.png) or an SVG (.svg)"),
        (with("--mode", "fast"), "unknown mode `fast`"),
    ];
    for (args, message) in cases {
        let out = replay(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: bad input, exit 2: {err}");
        assert!(err.contains(message), "{args:?}: the message should say `{message}`: {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(!csv.exists(), "{args:?}: nothing written");
    }
    let out = replay(&["--seconds", "0.1"]);
    assert_eq!(out.status.code(), Some(2), "--motion is required");
    assert!(String::from_utf8_lossy(&out.stderr).contains("--motion"), "named");
}

/// Ctrl-C (SIGINT) stops the run: the frames recorded are still scored and written, and the
/// exit code says the run did not finish.
#[test]
fn ctrl_c_keeps_what_was_recorded() {
    let csv = tmp("replay-interrupted.csv");
    let args = ["replay", "--motion", "yaw=30", "--seconds", "60", "--width", "32", "--height", "24"];
    let (status, rest) = interrupted(&[&args[..], &["--csv", csv.to_str().unwrap()]].concat(), "the head moves");
    assert_eq!(status.code(), Some(1), "an interrupted run did not finish: {rest}");
    assert!(rest.contains("(interrupted)") && rest.contains("interrupted;"), "{rest}");
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(text.starts_with(HEADER), "{text}");
}

#[test]
fn help_documents_every_replay_flag() {
    let out = stereotrace(&["replay", "--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for flag in [
        "--motion",
        "--seconds",
        "--still",
        "--display-hz",
        "--score-every",
        "--max-supersample",
        "--policy",
        "--target-age-ms",
        "--guard-band",
        "--mode",
        "--json",
        "--csv",
        "--plot",
        "--scene",
        "--width",
    ] {
        assert!(text.contains(flag), "replay --help lacks {flag}");
    }
    let top = String::from_utf8_lossy(&stereotrace(&["--help"]).stdout).into_owned();
    assert!(top.contains("replay"), "--help lists replay: {top}");
}
