//! End-to-end tests of the `stereotrace` binary's headless commands: what they write and
//! report; bad input is `bad_input`'s.

mod bad_input;
mod pick;

use std::path::{Path, PathBuf};
use std::process::Output;

use serde_json::Value;

use crate::common::{read_png, root, stereotrace, tmp};

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

/// The bench's modes, as its report names them.
const MODES: [&str; 6] = ["full", "copy", "copy+edges", "reshade", "reshade+edges", "exact"];

/// The number at `path` in `v`.
fn ms(v: &Value, path: &[&str]) -> f64 {
    path.iter().fold(v, |v, key| &v[key]).as_f64().unwrap_or_else(|| panic!("{path:?} is not a number in {v}"))
}

/// Equal but for what a number's trip through JSON's decimal form may round off.
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-12 * a.abs().max(b.abs())
}

/// The README's promises about a frame report's times: the left eye is stage 1 (its trace),
/// the right eye the sum of stages 2 to 5 (reprojection, retrace, reshade), and their ratio
/// is `ratios.right_ms_over_left`.
fn assert_times_add_up(v: &Value, what: &str) {
    let (left, right) = (ms(v, &["left", "ms"]), ms(v, &["right", "ms"]));
    let stage = |name: &str| ms(v, &["stages", name]);
    assert!(close(left, stage("trace_left_ms")), "{what}: left.ms {left} should equal stages.trace_left_ms: {v}");
    let stages = stage("reproject_ms") + stage("retrace_ms") + stage("reshade_ms");
    assert!(close(right, stages), "{what}: right.ms {right} should equal reproject + retrace + reshade, {stages}: {v}");
    let ratio = ms(v, &["ratios", "right_ms_over_left"]);
    assert!(
        close(ratio, right / left),
        "{what}: ratios.right_ms_over_left {ratio} should equal right.ms / left.ms, {right} / {left}"
    );
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
    }
    assert_times_add_up(&v, "render full");
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
    assert_eq!(count(px, "retraced_shadow"), 0, "no mode retraces shadow boundaries: {px}");
    // Exact mode saves primary rays; its pixels cast the full trace's shadow and mirror rays.
    let (left, right) = (count(&v["left"]["rays"], "primary"), count(&v["right"]["rays"], "primary"));
    assert!(right < left / 2, "exact mode should cast under half the left eye's primary rays: {right} vs {left}");
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
    for mode in MODES {
        assert_eq!(rays(&v["modes"][mode]["left"]), expected, "{mode}: the left eye");
    }
    assert_eq!(rays(&v["modes"]["full"]["right"]), expected, "full: the right eye too");
}

#[test]
fn bench_reports_every_mode_and_its_times_add_up() {
    let out = stereotrace(&["bench", "--width", "96", "--height", "54", "--frames", "1", "--json"]);
    let v = json(&out);
    // mono_ms is the median left eye over every mode's frames: here, of six modes' one frame.
    let mut lefts: Vec<f64> = MODES.iter().map(|mode| ms(&v["modes"][mode], &["left", "ms"])).collect();
    lefts.sort_by(f64::total_cmp);
    let mono = ms(&v, &["mono_ms"]);
    assert!(
        close(mono, 0.5 * (lefts[2] + lefts[3])),
        "mono_ms {mono} should be the median of the modes' left.ms, {lefts:?}"
    );
    for mode in MODES {
        let m = &v["modes"][mode];
        assert_eq!(rays(&m["left"])[0], 96 * 54, "{mode}: the left eye casts one primary ray per pixel");
        assert!(rays(&m["right"])[0] <= 96 * 54, "{mode}: the right eye at most one per pixel");
        assert!(m["quality"]["share_over_2_255"].is_number(), "{mode}");
        assert_times_add_up(m, mode);
        // One frame: every median is that frame's own value.
        let (left, right) = (ms(m, &["left", "ms"]), ms(m, &["right", "ms"]));
        let stereo = ms(m, &["stereo_ms"]);
        assert!(
            close(stereo, left + right),
            "{mode}: stereo_ms {stereo} should equal left.ms {left} + right.ms {right}"
        );
        let over_mono = ms(m, &["stereo_over_mono"]);
        assert!(
            close(over_mono, stereo / left),
            "{mode}: stereo_over_mono {over_mono} should equal (left.ms + right.ms) / left.ms, {stereo} / {left}"
        );
        let over = ms(m, &["stereo_ms_over_mono_ms"]);
        assert!(
            close(over, stereo / mono),
            "{mode}: stereo_ms_over_mono_ms {over} should equal stereo_ms / mono_ms, {stereo} / {mono}"
        );
    }
    let table = stereotrace(&["bench", "--width", "96", "--height", "54", "--frames", "1"]);
    assert!(table.status.success(), "the table: {}", String::from_utf8_lossy(&table.stderr));
    let text = String::from_utf8_lossy(&table.stdout);
    assert!(text.contains("reshade+edges") && text.contains("PSNR") && text.contains("reproject"), "{text}");
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

/// `--color` and `--hide` change the picture of a structure; `--color element` and no flag
/// give the same bytes.
#[test]
fn colour_and_hide_flags_change_the_picture() {
    let tii = "/usr/share/pymol/data/demo/1tii.pdb";
    if !Path::new(tii).exists() {
        return;
    }
    let render = |name: &str, extra: &[&str]| {
        let l = tmp(name);
        let mut args = vec!["render", "--scene", tii, "--width", "96", "--height", "72", "--mode", "full"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--left", l.to_str().unwrap()]);
        let out = stereotrace(&args);
        assert!(out.status.success(), "{extra:?}: {}", String::from_utf8_lossy(&out.stderr));
        std::fs::read(&l).unwrap()
    };
    let plain = render("look_plain.png", &[]);
    assert_eq!(render("look_element.png", &["--color", "element"]), plain, "--color element is the default");
    assert_ne!(render("look_chain.png", &["--color", "chain"]), plain, "by chain");
    assert_ne!(render("look_range.png", &["--color-range", "0,40"]), plain, "--color-range alone is bfactor");
    assert_ne!(render("look_hide.png", &["--hide", "water,hydrogen,hetero"]), plain, "waters hidden");
}

/// The progressive policy's flags are checked before a window opens: out of range, exit 2
/// with clap's message naming the flag and the range.
#[test]
fn the_progressive_flags_out_of_range_exit_2() {
    for (flag, value, range) in [
        ("--target-age-ms", "4", "5..=1000"),
        ("--target-age-ms", "2000", "5..=1000"),
        ("--max-supersample", "0", "1..=8"),
        ("--max-supersample", "9", "1..=8"),
    ] {
        let out = stereotrace(&[flag, value]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{flag} {value}: {err}");
        assert!(
            err.contains(&format!("invalid value '{value}' for '{flag}")) && err.contains(range),
            "{flag} {value}: {err}"
        );
    }
}
