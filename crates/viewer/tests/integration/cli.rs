//! End-to-end tests of the `stereotrace` binary's headless commands.

use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::Value;

use crate::common::{read_png, root, stereotrace, stereotrace_with, tmp};

fn png_size(path: &Path) -> (u32, u32) {
    let (w, h, _) = read_png(path);
    (w, h)
}

fn json(out: &Output) -> Value {
    assert!(out.status.success(), "failed: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("stdout is not one JSON object: {e}"))
}

fn count(v: &Value, key: &str) -> u64 {
    v[key].as_u64().unwrap_or_else(|| panic!("{key} is not a count in {v}"))
}

/// One mirror sphere on black, lit by three lights: at the eyes (IPD 0: both eyes see the
/// same image), far behind them, and far beyond the sphere. Every pixel's rays follow from
/// whether it sees the sphere: its primary ray, and where it hits, a shadow ray to each of the
/// first two lights (every point the eyes see faces them) but none to the third (no point the
/// eyes see faces it), and one mirror ray (which leaves the convex sphere and misses: nothing
/// else is there). A hit is never black (the ambient term lights it), a miss always is.
const ONE_MIRROR: &str = "[camera]\nipd = 0.0\ndistance = 10.0\nfov_deg = 40.0\n\
                          [render]\nmax_depth = 4\nbackground = [0.0, 0.0, 0.0]\nambient = 0.2\n\
                          [[lights]]\nposition = [0.0, 0.0, 0.0]\n\
                          [[lights]]\nposition = [0.0, 0.0, -50.0]\n\
                          [[lights]]\nposition = [0.0, 0.3, 1000.0]\n\
                          [[spheres]]\ncenter = [0.0, 0.3, 10.0]\nradius = 2.5\ncolor = [0.8, 0.4, 0.3]\n\
                          specular = 0.4\nreflectivity = 0.5\n";

/// The rays an eye of `ONE_MIRROR` must cast, counted from its image: [primary, shadow,
/// reflection, total].
fn one_mirror_rays(image: &Path) -> [u64; 4] {
    let (w, h, pixels) = read_png(image);
    let pixels_n = u64::from(w * h);
    let hits = pixels.iter().filter(|&&p| p != 0).count() as u64;
    assert!(hits > 0 && hits < pixels_n, "the sphere should fill part of the image: {hits} hits");
    [pixels_n, 2 * hits, hits, pixels_n + 3 * hits]
}

/// An eye's `rays` object as reported: [primary, shadow, reflection, total].
fn rays(eye: &Value) -> [u64; 4] {
    ["primary", "shadow", "reflection", "total"].map(|k| count(&eye["rays"], k))
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
    assert_eq!(png_size(&l), (160, 90), "the left eye's size");
    assert_eq!(png_size(&r), (160, 90), "the right eye's size");
    for eye in ["left", "right"] {
        assert_eq!(v[eye]["rays"]["primary"].as_u64(), Some(160 * 90), "{eye}: one primary ray per pixel");
        assert!(v[eye]["ms"].as_f64().unwrap() > 0.0, "{eye}: timed");
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
    assert_eq!(png_size(&m), (320, 180), "the mask's size");
    let px = &v["right"]["pixels"];
    let sum: u64 = ["reprojected", "retraced_gap", "retraced_edge", "retraced_shadow", "traced"]
        .iter()
        .map(|k| count(px, k))
        .sum();
    assert_eq!(sum, 320 * 180, "every right pixel has one class: {px}");
    assert!(count(px, "reprojected") > 320 * 180 / 2, "most pixels reproject: {px}");
    let (left, right) = (count(&v["left"]["rays"], "total"), count(&v["right"]["rays"], "total"));
    assert!(right < left / 2, "exact mode should cost under half the left eye's rays: {right} vs {left}");
    assert!(v["quality"]["share_not_identical"].as_f64().unwrap() < 0.001, "exact is exact: {}", v["quality"]);
}

/// The ray counts of the report against counts made independently: from the pixels the
/// rendered images show hit, and what the scene's one material and one light imply for them.
#[test]
fn the_reported_rays_are_those_the_pixels_imply() {
    let scene = tmp("one-mirror.toml");
    std::fs::write(&scene, ONE_MIRROR).unwrap();
    let (l, r) = (tmp("one-mirror-l.png"), tmp("one-mirror-r.png"));
    let out = stereotrace(&[
        "render",
        "--scene",
        scene.to_str().unwrap(),
        "--width",
        "64",
        "--height",
        "36",
        "--mode",
        "full",
        "--left",
        l.to_str().unwrap(),
        "--right",
        r.to_str().unwrap(),
        "--json",
    ]);
    let v = json(&out);
    assert_eq!(rays(&v["left"]), one_mirror_rays(&l), "left eye: [primary, shadow, reflection, total]");
    assert_eq!(rays(&v["right"]), one_mirror_rays(&r), "right eye, traced in full");
    assert_eq!(count(&v["right"]["pixels"], "traced"), 64 * 36, "full mode traces every right pixel");

    // The bench renders the same frame in every mode: the left eye is always traced in full.
    let out = stereotrace(&[
        "bench",
        "--scene",
        scene.to_str().unwrap(),
        "--width",
        "64",
        "--height",
        "36",
        "--frames",
        "1",
        "--json",
    ]);
    let v = json(&out);
    let expected = one_mirror_rays(&l);
    for mode in ["full", "copy", "copy+edges", "reshade", "reshade+edges", "exact"] {
        assert_eq!(rays(&v["modes"][mode]["left"]), expected, "{mode}: the left eye");
    }
    assert_eq!(rays(&v["modes"]["full"]["right"]), expected, "full: the right eye too");
}

#[test]
fn bench_reports_every_mode() {
    let out = stereotrace(&["bench", "--width", "96", "--height", "54", "--frames", "1", "--json"]);
    let v = json(&out);
    for mode in ["full", "copy", "copy+edges", "reshade", "reshade+edges", "exact"] {
        let m = &v["modes"][mode];
        assert_eq!(rays(&m["left"])[0], 96 * 54, "{mode}: the left eye casts one primary ray per pixel");
        assert!(rays(&m["right"])[0] <= 96 * 54, "{mode}: the right eye at most one per pixel");
        assert!(m["quality"]["share_over_2_255"].is_number(), "{mode}");
        // Each frame's stereo time includes its own left eye: never below one mono frame.
        assert!(m["stereo_over_mono"].as_f64().unwrap() >= 1.0, "{mode}");
        assert!(m["stereo_ms_over_mono_ms"].as_f64().unwrap() > 0.0, "{mode}");
    }
    let table = stereotrace(&["bench", "--width", "96", "--height", "54", "--frames", "1"]);
    assert!(table.status.success(), "the table: {}", String::from_utf8_lossy(&table.stderr));
    let text = String::from_utf8_lossy(&table.stdout);
    assert!(text.contains("reshade+edges") && text.contains("PSNR") && text.contains("reproject"), "{text}");
}

#[test]
fn a_bad_scene_file_names_file_line_and_field_and_exits_2() {
    let bad = tmp("bad.toml");
    std::fs::write(&bad, "[[spheres]]\ncenter = [0.0, 0.0, 15.0]\nradius = -2.0\n").unwrap();
    let out = stereotrace(&["render", "--scene", bad.to_str().unwrap(), "--json"]);
    assert_eq!(out.status.code(), Some(2), "bad input");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.toml:1: spheres[0].radius = -2: must be > 0"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn bad_arguments_exit_2_without_writing() {
    let out = stereotrace(&["render", "--width", "0", "--json"]);
    assert_eq!(out.status.code(), Some(2), "--width 0");
    let out = stereotrace(&["render", "--ipd", "-1", "--json"]);
    assert_eq!(out.status.code(), Some(2), "--ipd -1");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--ipd -1"), "{err}");
    let missing = tmp("no/such/dir/l.png");
    let out = stereotrace(&["render", "--width", "8", "--height", "8", "--left", missing.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "an output in a missing directory");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("does not exist"), "{err}");
    assert!(!missing.exists(), "nothing written");
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
        "--supersample",
    ] {
        assert!(text.contains(flag), "render --help lacks {flag}");
    }
    let out = stereotrace(&["--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for flag in ["--scene", "--frames", "--dump", "--render-scale", "render", "bench"] {
        assert!(text.contains(flag), "--help lacks {flag}");
    }
}

/// `STEREOTRACE_LANES` accepts 4 (the fallback, which the report names) and refuses the rest.
#[test]
fn the_lanes_variable_forces_the_fallback_and_refuses_other_values() {
    let args = ["render", "--width", "16", "--height", "8", "--json"];
    let out = stereotrace_with(&[("STEREOTRACE_LANES", "4")], &args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("the JSON report");
    assert_eq!(report["lanes"], 4, "the fallback ran");
    let out = stereotrace_with(&[("STEREOTRACE_LANES", "16")], &args);
    assert_eq!(out.status.code(), Some(2), "a width the tracer does not have is bad input");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("STEREOTRACE_LANES=16: must be 4"), "{err}");
}

/// The memory check, with the limit injected (`STEREOTRACE_MEMORY_AVAILABLE`) so the answer
/// does not depend on this machine's free memory.
#[test]
fn a_frame_too_large_for_the_memory_is_refused_before_any_work() {
    let limit = |bytes: &str| [("STEREOTRACE_MEMORY_AVAILABLE", bytes.to_owned())];
    let run = |env: &[(&str, String)], args: &[&str]| {
        let env: Vec<(&str, &str)> = env.iter().map(|(k, v)| (*k, v.as_str())).collect();
        stereotrace_with(&env, args)
    };
    let out = run(&limit("17179869184"), &["render", "--width", "16384", "--height", "16384", "--json"]);
    assert_eq!(out.status.code(), Some(2), "refused as bad input");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--width 16384 --height 16384: the frame needs 52.0 GiB but only 16.0 GiB of memory is available"),
        "{err}"
    );
    // 208 bytes per eye pixel (three films, the source map and the mask, and what temporal
    // reuse keeps): 64 × 64 needs 851968.
    let small = ["render", "--width", "64", "--height", "64", "--json"];
    assert!(run(&limit("851968"), &small).status.success(), "exactly enough memory");
    let out = run(&limit("851967"), &small);
    assert_eq!(out.status.code(), Some(2), "one byte short: {}", String::from_utf8_lossy(&out.stderr));
    let out = run(&limit("lots"), &small);
    assert_eq!(out.status.code(), Some(2), "a limit that is no number");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("STEREOTRACE_MEMORY_AVAILABLE=lots: must be a whole number of bytes"), "{err}");
}

#[test]
fn limits_are_refused_before_any_work() {
    let out = stereotrace(&["render", "--width", "20000", "--json"]);
    assert_eq!(out.status.code(), Some(2), "over the documented maximum side");
    let out = stereotrace(&["render", "--mode", "fast", "--json"]);
    assert_eq!(out.status.code(), Some(2), "an unknown mode");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("expected one of full, copy, reshade, exact"), "{err}");
    let out = stereotrace(&["render", "--layout", "over-under", "--out", "x.png"]);
    assert_eq!(out.status.code(), Some(2), "an unknown layout");
    let dir = tmp("anim-bad-fps");
    let out = stereotrace(&["render", "--frames", "2", "--fps", "0", "--out-dir", dir.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "--fps 0");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--fps 0"), "{err}");
    let out = stereotrace(&["render", "--scene", "no/such/scene.toml", "--json"]);
    assert_eq!(out.status.code(), Some(2), "a missing scene");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("no/such/scene.toml: cannot read scene file"), "{err}");
}

#[test]
fn an_unwritable_output_fails_cleanly_and_leaves_no_partial_file() {
    // /proc accepts no new files, even for root.
    let out = stereotrace(&["render", "--width", "8", "--height", "8", "--left", "/proc/stereotrace-left.png"]);
    assert_eq!(out.status.code(), Some(1), "not bad input, a failure");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("cannot write /proc/stereotrace-left.png"), "{err}");
    let leftovers: Vec<_> = std::fs::read_dir("/proc")
        .unwrap()
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().contains("stereotrace-left"))
        .collect();
    assert!(leftovers.is_empty(), "no partial file: {leftovers:?}");
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
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("wrote 6 of 6 frames"), "{err}");
    let mut names: Vec<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    assert_eq!(names, (0..6).map(|k| format!("frame_{k:05}.png")).collect::<Vec<_>>(), "numbered frames");
    for n in &names {
        assert_eq!(png_size(&dir.join(n)), (64, 18), "{n}: side by side");
    }
}

/// `--supersample 2` traces every stage at twice the size per axis and writes the eyes
/// box-filtered down: exactly the filtered images of a render at the sampled size. The mask
/// and the counts stay per sample.
#[test]
fn supersampling_traces_the_samples_and_writes_the_requested_size() {
    let paths = |tag: &str| ["l", "r", "m"].map(|eye| tmp(&format!("ss-{tag}-{eye}.png")));
    let render = |size: [&str; 2], extra: &[&str], [l, r, m]: &[PathBuf; 3]| {
        let mut args = vec!["render", "--width", size[0], "--height", size[1], "--mode", "exact", "--json"];
        args.extend_from_slice(extra);
        args.extend(["--left", l.to_str().unwrap(), "--right", r.to_str().unwrap(), "--mask", m.to_str().unwrap()]);
        json(&stereotrace(&args))
    };
    let (big, small) = (paths("big"), paths("small"));
    let at_samples = render(["320", "180"], &[], &big);
    let v = render(["160", "90"], &["--supersample", "2"], &small);
    assert_eq!(png_size(&small[0]), (160, 90), "the left eye at the requested size");
    assert_eq!(png_size(&small[1]), (160, 90), "the right eye at the requested size");
    assert_eq!(png_size(&small[2]), (320, 180), "the mask per sample");
    assert_eq!((count(&v, "width"), count(&v, "height"), count(&v, "supersample")), (160, 90, 2), "the report's sizes");
    assert_eq!((count(&v, "sample_width"), count(&v, "sample_height")), (320, 180));
    for eye in [0, 1] {
        let (_, _, samples) = read_png(&big[eye]);
        let (_, _, pixels) = read_png(&small[eye]);
        let mut filtered = Vec::new();
        stereo::downsample(&samples, (320, 180), &mut filtered, (160, 90));
        assert_eq!(pixels, filtered, "eye {eye}: the samples of a 320 × 180 render, box-filtered");
    }
    assert_eq!(read_png(&small[2]).2, read_png(&big[2]).2, "the mask is the sampled render's");
    for key in ["left", "right"] {
        assert_eq!(v[key]["rays"], at_samples[key]["rays"], "{key}: the rays of every sample");
    }
    assert_eq!(count(&v["left"]["rays"], "primary"), 320 * 180, "one primary ray per sample");
    assert_eq!(v["right"]["pixels"], at_samples["right"]["pixels"], "the classes of every sample");
    assert_eq!(v["quality_samples"], at_samples["quality"], "per sample: the sampled render's quality");
    assert!(v["quality"]["share_not_identical"].as_f64().unwrap() < 0.001, "filtered, still exact: {}", v["quality"]);
    assert_eq!(at_samples["supersample"], 1, "no supersampling by default");
    assert_eq!(at_samples["quality_samples"], at_samples["quality"], "without it, the two are one");
    // An animation's combined frames are the requested size too.
    let dir = tmp("ss-anim");
    let args = ["render", "--width", "32", "--height", "18", "--supersample", "3", "--frames", "2", "--out-dir"];
    let out = stereotrace(&[&args[..], &[dir.to_str().unwrap()]].concat());
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(png_size(&dir.join("frame_00001.png")), (64, 18), "two 32 × 18 eyes side by side");
}

#[test]
fn a_supersample_factor_outside_1_to_4_exits_2() {
    for bad in ["0", "5", "1.5", "two"] {
        let out = stereotrace(&["render", "--supersample", bad, "--json"]);
        assert_eq!(out.status.code(), Some(2), "--supersample {bad}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(&format!("invalid value '{bad}' for '--supersample <S>'")), "{err}");
        assert!(out.stdout.is_empty(), "nothing rendered for --supersample {bad}");
    }
    let out = stereotrace(&["render", "--width", "16384", "--height", "16384", "--supersample", "4", "--json"]);
    assert_eq!(out.status.code(), Some(2), "2³² samples per eye");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("65536 × 65536 samples per eye; an eye must have fewer than 4294967295 samples"), "{err}");
}

/// `render --frames` reuses each frame's unchanged pixels for the next: the files are those
/// of `--no-reuse`, byte for byte, on every bundled scene and mode, and the log says how much
/// was traced.
#[test]
fn an_animation_with_and_without_reuse_writes_the_same_files() {
    for scene in ["seed.toml", "many.toml", "window.toml", "thousand.toml"] {
        for mode in ["exact", "copy", "reshade", "full"] {
            let path = root().join("assets/scenes").join(scene);
            let run = |reuse: bool| {
                let dir = tmp(&format!("reuse-{scene}-{mode}-{reuse}"));
                let _ = std::fs::remove_dir_all(&dir);
                let mut args = vec!["render", "--scene", path.to_str().unwrap(), "--mode", mode, "--retrace-edges"];
                args.extend(["--width", "64", "--height", "36", "--frames", "8", "--fps", "20"]);
                args.extend(["--out-dir", dir.to_str().unwrap()]);
                if !reuse {
                    args.push("--no-reuse");
                }
                let out = stereotrace(&args);
                assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
                let log = String::from_utf8_lossy(&out.stderr).into_owned();
                let files: Vec<Vec<u8>> =
                    (0..8).map(|k| std::fs::read(dir.join(format!("frame_{k:05}.png"))).unwrap()).collect();
                let _ = std::fs::remove_dir_all(&dir);
                (files, log)
            };
            let ((reused, log), (fresh, fresh_log)) = (run(true), run(false));
            assert!(reused == fresh, "{scene} {mode}: the frames differ with reuse");
            assert!(fresh_log.contains("100.0% of the pixels traced (reuse off)"), "{fresh_log}");
            assert!(log.contains("of the pixels traced (the rest kept"), "{log}");
            assert!(!log.contains("100.0% of the pixels traced"), "{scene} {mode}: something was kept: {log}");
        }
    }
}
