//! End-to-end tests of the `stereotrace` binary's headless commands.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn stereotrace(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_stereotrace")).args(args).current_dir(root()).output().expect("runs stereotrace")
}

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("stereotrace-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir.join(name)
}

fn png_size(path: &Path) -> (u32, u32) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).expect("PNG exists")));
    let reader = decoder.read_info().expect("valid PNG");
    (reader.info().width, reader.info().height)
}

fn json(out: &Output) -> Value {
    assert!(out.status.success(), "failed: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).expect("stdout is one JSON object")
}

fn rays_add_up(v: &Value) -> u64 {
    let r = &v["rays"];
    let total = r["total"].as_u64().unwrap();
    assert_eq!(
        total,
        r["primary"].as_u64().unwrap() + r["shadow"].as_u64().unwrap() + r["reflection"].as_u64().unwrap()
    );
    total
}

#[test]
fn render_full_writes_both_eyes_and_a_consistent_report() {
    let (l, r) = (tmp("full_l.png"), tmp("full_r.png"));
    let out = stereotrace(&[
        "render",
        "--scene",
        "assets/scenes/seed.toml",
        "--width",
        "160",
        "--height",
        "90",
        "--mode",
        "full",
        "--left",
        l.to_str().unwrap(),
        "--right",
        r.to_str().unwrap(),
        "--json",
    ]);
    let v = json(&out);
    assert_eq!(png_size(&l), (160, 90));
    assert_eq!(png_size(&r), (160, 90));
    for eye in ["left", "right"] {
        assert_eq!(v[eye]["rays"]["primary"].as_u64(), Some(160 * 90), "{eye}");
        rays_add_up(&v[eye]);
        assert!(v[eye]["ms"].as_f64().unwrap() > 0.0);
    }
    assert_eq!(v["quality"]["share_not_identical"].as_f64(), Some(0.0));
    assert!(v["quality"]["psnr_db"].is_null(), "identical images have infinite PSNR, reported as null");
}

#[test]
fn render_exact_with_mask_reprojects_most_pixels() {
    let (r, m) = (tmp("exact_r.png"), tmp("exact_m.png"));
    let out = stereotrace(&[
        "render",
        "--width",
        "320",
        "--height",
        "180",
        "--mode",
        "exact",
        "--right",
        r.to_str().unwrap(),
        "--mask",
        m.to_str().unwrap(),
        "--json",
    ]);
    let v = json(&out);
    assert_eq!(png_size(&m), (320, 180));
    let px = &v["right"]["pixels"];
    let sum: u64 = ["reprojected", "retraced_gap", "retraced_edge", "retraced_shadow", "traced"]
        .iter()
        .map(|k| px[k].as_u64().unwrap())
        .sum();
    assert_eq!(sum, 320 * 180);
    assert!(px["reprojected"].as_u64().unwrap() > 320 * 180 / 2);
    let (left, right) = (rays_add_up(&v["left"]), rays_add_up(&v["right"]));
    assert!(right < left / 2, "exact mode should cost under half the left eye's rays: {right} vs {left}");
    assert!(v["quality"]["share_not_identical"].as_f64().unwrap() < 0.001);
}

#[test]
fn bench_reports_every_mode() {
    let out = stereotrace(&["bench", "--width", "96", "--height", "54", "--frames", "1", "--json"]);
    let v = json(&out);
    for mode in ["full", "copy", "copy+edges", "reshade", "reshade+edges", "exact"] {
        let m = &v["modes"][mode];
        rays_add_up(&m["left"]);
        rays_add_up(&m["right"]);
        assert!(m["quality"]["share_over_2_255"].is_number(), "{mode}");
        // Each frame's stereo time includes its own left eye: never below one mono frame.
        assert!(m["stereo_over_mono"].as_f64().unwrap() >= 1.0, "{mode}");
        assert!(m["stereo_ms_over_mono_ms"].as_f64().unwrap() > 0.0, "{mode}");
    }
    let table = stereotrace(&["bench", "--width", "96", "--height", "54", "--frames", "1"]);
    assert!(table.status.success());
    let text = String::from_utf8_lossy(&table.stdout);
    assert!(text.contains("reshade+edges") && text.contains("PSNR") && text.contains("reproject"), "{text}");
}

#[test]
fn a_bad_scene_file_names_file_line_and_field_and_exits_2() {
    let bad = tmp("bad.toml");
    std::fs::write(&bad, "[[spheres]]\ncenter = [0.0, 0.0, 15.0]\nradius = -2.0\n").unwrap();
    let out = stereotrace(&["render", "--scene", bad.to_str().unwrap(), "--json"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.toml:1: spheres[0].radius = -2: must be > 0"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn bad_arguments_exit_2_without_writing() {
    let out = stereotrace(&["render", "--width", "0", "--json"]);
    assert_eq!(out.status.code(), Some(2));
    let out = stereotrace(&["render", "--ipd", "-1", "--json"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--ipd -1"));
    let missing = tmp("no/such/dir/l.png");
    let out = stereotrace(&["render", "--width", "8", "--height", "8", "--left", missing.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("does not exist"));
    assert!(!missing.exists());
}

#[test]
fn help_documents_every_flag() {
    let out = stereotrace(&["render", "--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for flag in [
        "--scene",
        "--width",
        "--height",
        "--ipd",
        "--distance",
        "--depth",
        "--mode",
        "--retrace-edges",
        "--time",
        "--left",
        "--right",
        "--mask",
        "--json",
    ] {
        assert!(text.contains(flag), "render --help lacks {flag}");
    }
    let out = stereotrace(&["--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for flag in ["--scene", "--frames", "--dump", "render", "bench"] {
        assert!(text.contains(flag), "--help lacks {flag}");
    }
}

#[test]
fn limits_are_refused_before_any_work() {
    // 16384² per eye cannot fit in this machine's memory: refused before allocating.
    let out = stereotrace(&["render", "--width", "16384", "--height", "16384", "--json"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("GiB") && err.contains("--width 16384"), "{err}");
    let out = stereotrace(&["render", "--width", "20000", "--json"]);
    assert_eq!(out.status.code(), Some(2), "over the documented maximum side");
    let out = stereotrace(&["render", "--mode", "fast", "--json"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("expected one of full, copy, reshade, exact"));
    let out = stereotrace(&["render", "--layout", "over-under", "--out", "x.png"]);
    assert_eq!(out.status.code(), Some(2));
    let dir = tmp("anim-bad-fps");
    let out = stereotrace(&["render", "--frames", "2", "--fps", "0", "--out-dir", dir.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--fps 0"));
    let out = stereotrace(&["render", "--scene", "no/such/scene.toml", "--json"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no/such/scene.toml: cannot read scene file"));
}

#[test]
fn an_unwritable_output_fails_cleanly_and_leaves_no_partial_file() {
    // /proc accepts no new files, even for root.
    let out = stereotrace(&["render", "--width", "8", "--height", "8", "--left", "/proc/stereotrace-left.png"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("cannot write /proc/stereotrace-left.png"), "{err}");
    let leftovers: Vec<_> = std::fs::read_dir("/proc")
        .unwrap()
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().contains("stereotrace-left"))
        .collect();
    assert!(leftovers.is_empty());
}

#[test]
fn layouts_and_an_animation_export() {
    let dir = tmp("anim");
    let _ = std::fs::remove_dir_all(&dir);
    for (layout, size) in [("side-by-side", (64, 18)), ("cross-eyed", (64, 18)), ("anaglyph", (32, 18))] {
        let pair = tmp(&format!("pair-{layout}.png"));
        let out = stereotrace(&[
            "render",
            "--width",
            "32",
            "--height",
            "18",
            "--layout",
            layout,
            "--out",
            pair.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        assert_eq!(png_size(&pair), size, "{layout}");
    }
    let out = stereotrace(&[
        "render",
        "--width",
        "32",
        "--height",
        "18",
        "--frames",
        "6",
        "--fps",
        "12",
        "--out-dir",
        dir.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(String::from_utf8_lossy(&out.stderr).contains("wrote 6 of 6 frames"));
    let mut names: Vec<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    assert_eq!(names, (0..6).map(|k| format!("frame_{k:05}.png")).collect::<Vec<_>>());
    for n in &names {
        assert_eq!(png_size(&dir.join(n)), (64, 18));
    }
}
