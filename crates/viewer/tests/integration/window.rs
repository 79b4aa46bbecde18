//! The real viewer under Xvfb: it shows the seed scene in both eyes with the egui panel over
//! the left one, keys move the head, switch the layout and save screenshots, Tab leaves both
//! eyes clean, a render scale of 200 % shows the supersampled eyes, and a click picks the
//! atom `stereotrace pick` reports at that pixel.
//!
//! Each test starts its own X server ([`XSession`]) and waits only for conditions — the
//! window mapped, a line of the viewer's fps log (`STEREOTRACE_LOG_FPS=1`), the `saved`
//! lines of a screenshot, the viewer's exit after `--frames` — each within a generous
//! timeout whose failure says what it waited for and shows the viewer's stderr.
//!
//! Needs `xvfb-run` (Debian: xvfb xauth) and, to drive the keys, `xdotool`. Without them the
//! tests pass with a loud SKIPPED message, except when `CI` is set: CI installs them, so
//! there a missing tool fails.

mod colour;
mod x_session;

use std::ffi::OsStr;
use std::path::{Path, PathBuf};
use std::process::Command;

use self::x_session::{Viewer, XSession};
use crate::common::{read_rgb_png, seed_scene};

const WIDTH: u32 = 800;
const HEIGHT: u32 = 300;

fn on_path(exe: &str) -> bool {
    std::env::var_os("PATH").is_some_and(|p| std::env::split_paths(&p).any(|d| d.join(exe).is_file()))
}

/// Whether a tool the test needs is missing: then it says SKIPPED (and fails under CI,
/// which installs them all).
fn missing(tools: &[&str]) -> bool {
    let absent: Vec<&str> = tools.iter().copied().filter(|t| !on_path(t)).collect();
    if absent.is_empty() {
        return false;
    }
    assert!(std::env::var_os("CI").is_none(), "{absent:?} not found, but CI must install them");
    tracer::testing::skipped(&format!("{absent:?} not found — install xvfb xauth xdotool"));
    true
}

/// A fresh scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("stereotrace-{name}-test-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display()));
    dir
}

/// Runs the viewer with `frame` and `size` in `dir`, hides the UI with Tab, and quits once a
/// converged frame is presented without it (`--dump dump.png`); then renders the same frame
/// headless (`frame` and `eye_size`, exact mode and 4 × 4 samples a pixel: the viewer's
/// defaults at rest) and asserts that each half of the dump is that eye, pixel for pixel:
/// the resting view converged to the render byte for byte, and no UI pixel covers an eye.
fn clean_dump_is_render(dir: &Path, frame: &[&str], size: &[&str], eye_size: &[&str]) {
    let x = XSession::start();
    let args: Vec<&OsStr> = frame.iter().chain(size).chain(&["--dump", "dump.png"]).map(OsStr::new).collect();
    let mut viewer = x.viewer(dir, &args, &[("STEREOTRACE_LOG_FPS", "1")]);
    x.focus_window(&viewer);
    x.xdotool(&viewer, "press Tab", &["key", "Tab"]);
    // The line is written as a redraw begins, and that redraw presents what it says.
    // At rest the viewer refines the pose to 4 × 4 samples a pixel (the progressive policy's
    // default): converged, it is `render --supersample 4`'s pair.
    viewer.wait_for_line("a converged frame presented with the UI hidden", |l| {
        field(l, "ui") == Some("hidden") && has_frame(l) && field(l, "converged") == Some("true")
    });
    x.xdotool(&viewer, "press Esc", &["key", "Escape"]);
    viewer.wait_exit();

    let render = Command::new(env!("CARGO_BIN_EXE_stereotrace"))
        .arg("render")
        .args(frame)
        .args(eye_size)
        .args(["--mode", "exact", "--supersample", "4", "--left", "left.png", "--right", "right.png"])
        .current_dir(dir)
        .output()
        .unwrap_or_else(|e| panic!("stereotrace render: {e}"));
    assert!(render.status.success(), "render failed: {}", String::from_utf8_lossy(&render.stderr));
    let (w, h, dump) = read_rgb_png(&dir.join("dump.png"));
    assert_eq!((w, h), (400, 200), "the window's size");
    let (_, _, left) = read_rgb_png(&dir.join("left.png"));
    let (_, _, right) = read_rgb_png(&dir.join("right.png"));
    for (name, half, eye) in [("left", columns(&dump, w, 0, 200), left), ("right", columns(&dump, w, 200, 400), right)]
    {
        assert_eq!(half.len(), eye.len(), "the {name} half is eye-sized");
        let first = half.chunks_exact(3).zip(eye.chunks_exact(3)).position(|(a, b)| a != b);
        assert_eq!(first.map(|k| (k % 200, k / 200)), None, "the {name} half differs from the {name} eye at (x, y)");
    }
}

/// Starts the viewer on the seed scene with `args` on `x`, in `dir`, with `env` set.
fn viewer(x: &XSession, dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Viewer {
    let scene = seed_scene();
    let args: Vec<&OsStr> =
        ["--scene".as_ref(), scene.as_os_str()].into_iter().chain(args.iter().map(OsStr::new)).collect();
    x.viewer(dir, &args, env)
}

/// Runs the viewer on the seed scene with `args` and `--dump` under Xvfb (scratch in `dir`)
/// until it exits by itself (`args` has `--frames`), and returns the dumped frame: width,
/// height, RGB bytes.
fn dumped(dir: &Path, args: &[&str]) -> (u32, u32, Vec<u8>) {
    let x = XSession::start();
    let dump = dir.join("dump.png");
    let dump_arg = dump.to_str().unwrap_or_else(|| panic!("{} is not UTF-8", dump.display()));
    let args: Vec<&str> = args.iter().copied().chain(["--dump", dump_arg]).collect();
    viewer(&x, dir, &args, &[]).wait_exit();
    read_rgb_png(&dump)
}

/// The value of `key` in a line of the fps log, if it is one and has the key.
fn field<'a>(line: &'a str, key: &str) -> Option<&'a str> {
    let prefix = format!("{key}=");
    line.starts_with("fps=").then(|| line.split_whitespace().find_map(|f| f.strip_prefix(prefix.as_str()))).flatten()
}

/// The last value of `key` in the fps log lines of `log`.
fn last_logged<'a>(log: &'a str, key: &str) -> Option<&'a str> {
    log.lines().rev().find_map(|l| field(l, key))
}

/// The head position (x, y, z) of an fps log line.
fn head(line: &str) -> Option<[f32; 3]> {
    let xyz: Vec<f32> = field(line, "head")?.split(',').map(|v| v.parse().ok()).collect::<Option<_>>()?;
    xyz.try_into().ok()
}

/// Whether the fps log line shows a rendered frame (`frame` ≥ 1).
fn has_frame(line: &str) -> bool {
    field(line, "frame").and_then(|n| n.parse::<u64>().ok()).is_some_and(|n| n >= 1)
}

/// Pixel statistics of the columns `x0..x1` of an RGB image `width` wide.
#[derive(Debug)]
struct Region {
    pixels: usize,
    /// Near-white: the seed scene's background (and the white sphere's brightest parts).
    white: usize,
    /// Clearly coloured and not dark: sphere pixels.
    colored: usize,
    /// Green dominant: the green sphere.
    green: usize,
}

fn region(rgb: &[u8], width: u32, x0: u32, x1: u32) -> Region {
    let mut r = Region { pixels: 0, white: 0, colored: 0, green: 0 };
    for (k, p) in rgb.chunks_exact(3).enumerate() {
        let x = k as u32 % width;
        if x < x0 || x >= x1 {
            continue;
        }
        let (cr, cg, cb) = (i32::from(p[0]), i32::from(p[1]), i32::from(p[2]));
        let (max, min) = (cr.max(cg).max(cb), cr.min(cg).min(cb));
        r.pixels += 1;
        r.white += usize::from(min >= 245);
        r.colored += usize::from(max - min > 60 && max > 120);
        r.green += usize::from(cg > cr + 40 && cg > cb + 20 && cg > 100);
    }
    r
}

fn columns(rgb: &[u8], width: u32, x0: u32, x1: u32) -> Vec<u8> {
    rgb.chunks_exact(3)
        .enumerate()
        .filter(|(k, _)| (x0..x1).contains(&(*k as u32 % width)))
        .flat_map(|(_, p)| p.iter().copied())
        .collect()
}

#[test]
fn window_shows_both_eyes_under_xvfb() {
    if missing(&["xvfb-run"]) {
        return;
    }
    let dir = scratch("window");
    let (width, height) = (WIDTH.to_string(), HEIGHT.to_string());
    let (w, h, rgb) = dumped(&dir, &["--frames", "5", "--time", "1.0", "--width", &width, "--height", &height]);
    assert_eq!((w, h), (WIDTH, HEIGHT), "the dump has the window's size (Xvfb scale factor 1)");
    let half = w / 2;
    // The panel covers the top-left of the left eye; the strip right of it shows the scene.
    let strip = half / 5;
    let left_strip = region(&rgb, w, half - strip, half);
    let right_eye = region(&rgb, w, half, w);
    let right_strip = region(&rgb, w, w - strip, w);
    let report = format!("left strip {left_strip:?}, right eye {right_eye:?}, right strip {right_strip:?}");
    eprintln!("{report}");
    for r in [&left_strip, &right_eye] {
        assert!(r.white * 4 > r.pixels, "a quarter should be the white background: {report}");
        assert!(r.colored * 100 > r.pixels, "sphere pixels should show: {report}");
    }
    assert!(right_eye.green * 500 > right_eye.pixels, "the green sphere should show in the right eye: {report}");
    assert_ne!(
        columns(&rgb, w, half - strip, half),
        columns(&rgb, w, w - strip, w),
        "the same strip of the two eyes should differ by the disparity"
    );
    // The egui panel is drawn into the dump, over the left eye's top-left corner, 8 points
    // from the window's edges (its frame's left margin, below the title bar, is dark).
    // (A few pixels around (12, 60), as a label's antialiased edge may fall on one of them.)
    let pixel = |x: u32, y: u32| &rgb[((y * w + x) * 3) as usize..][..3];
    let dark =
        (55..66).flat_map(|y| (9..15).map(move |x| (x, y))).filter(|&(x, y)| pixel(x, y).iter().all(|&c| c < 100));
    assert!(dark.count() > 10, "the panel should be dark around (12, 60): {:?}", pixel(12, 60));
    let outside = &rgb[((60 * w + 4) * 3) as usize..][..3];
    assert!(outside.iter().all(|&c| c > 200), "the scene's white shows left of the panel at (4, 60): {outside:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Keys driven with xdotool: Up held moves the head forward (and only while held), 3 picks
/// the anaglyph, X swaps the eyes, F12 saves screenshots; exact mode stays identical to a
/// full trace while moving.
#[test]
fn keys_move_the_head_switch_layouts_and_save_screenshots() {
    if missing(&["xvfb-run", "xdotool"]) {
        return;
    }
    let dir = scratch("keys");
    let x = XSession::start();
    let args = ["--width", "400", "--height", "200", "--live-psnr", "--time", "1.0"];
    let mut viewer = viewer(&x, &dir, &args, &[("STEREOTRACE_LOG_FPS", "1")]);
    x.focus_window(&viewer);
    // Up held until the log shows the head half a unit forward (at 2 units/s), then let go.
    x.xdotool(&viewer, "hold Up", &["keydown", "Up"]);
    viewer.wait_for_line("the head to move forward with Up held", |l| head(l).is_some_and(|[_, _, z]| z >= 0.5));
    x.xdotool(&viewer, "let Up go", &["keyup", "Up"]);
    x.xdotool(&viewer, "press 3 and X", &["key", "3", "x"]);
    let shown = viewer.wait_for_line("the anaglyph with swapped eyes and a frame measured against a full trace", |l| {
        field(l, "layout") == Some("anaglyph") && field(l, "swap") == Some("true") && field(l, "psnr") != Some("-")
    });
    // Up was let go before 3 was pressed: from then on the head stands where it is.
    let later = viewer.wait_for_line("the next line of the fps log", |l| l.starts_with("fps="));
    let [x0, _, z] = head(&shown).unwrap_or_else(|| panic!("no head in {shown}"));
    assert_eq!(head(&later), head(&shown), "the head stopped when Up was let go:\n{shown}\n{later}");
    // Straight along +z (the seed scene looks along +z), about as far as held.
    assert!((0.5..4.0).contains(&z) && x0.abs() < 1e-3, "the head moved forward: {shown}");
    x.xdotool(&viewer, "press F12", &["key", "F12"]);
    for k in 1..=3 {
        viewer.wait_for_line(&format!("screenshot {k} of 3 (left, right, pair) to be saved"), |l| {
            l.starts_with("stereotrace: saved ")
        });
    }
    x.xdotool(&viewer, "press Esc", &["key", "Escape"]);
    let stderr = viewer.wait_exit();

    assert_eq!(last_logged(&stderr, "layout"), Some("anaglyph"), "{stderr}");
    assert_eq!(last_logged(&stderr, "swap"), Some("true"), "{stderr}");
    assert_eq!(last_logged(&stderr, "psnr"), Some("inf"), "exact mode is identical to a full trace:\n{stderr}");

    let shots = dir.join("screenshots");
    let mut names: Vec<String> = std::fs::read_dir(&shots)
        .unwrap_or_else(|e| panic!("no screenshots folder ({e}); stderr:\n{stderr}"))
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names.len(), 3, "left, right, pair (no mask unless shown): {names:?}");
    for (name, kind) in names.iter().zip(["left", "pair", "right"]) {
        // stereotrace-YYYYmmdd-HHMMSS-<kind>.png
        let stamp = name.strip_prefix("stereotrace-").and_then(|n| n.strip_suffix(&format!("-{kind}.png")));
        let stamp = stamp.unwrap_or_else(|| panic!("unexpected name {name}"));
        assert!(
            stamp.len() == 15
                && stamp.chars().enumerate().all(|(k, c)| if k == 8 { c == '-' } else { c.is_ascii_digit() }),
            "{name}"
        );
    }
    let (lw, lh, _) = read_rgb_png(&shots.join(&names[0]));
    let (pw, ph, pair) = read_rgb_png(&shots.join(&names[1]));
    assert_eq!((pw, ph), (lw, lh), "the anaglyph pair is eye-sized");
    assert!(pair.chunks_exact(3).any(|p| p[0] != p[1] || p[1] != p[2]), "the anaglyph has colour fringes");
    let _ = std::fs::remove_dir_all(&dir);
}

/// At a render scale of 200 % the window shows the eyes supersampled: the right eye on
/// screen is, pixel for pixel, what `render --supersample 2` writes for the same view (the
/// panel covers only the left eye), and differs from the eye traced at 100 %.
#[test]
fn a_render_scale_of_200_shows_the_supersampled_eyes() {
    if missing(&["xvfb-run"]) {
        return;
    }
    let dir = scratch("scale");
    let args = ["--frames", "3", "--time", "1.0", "--render-scale", "200", "--width", "800", "--height", "300"];
    let (w, h, rgb) = dumped(&dir, &args);
    assert_eq!((w, h), (800, 300));
    let shown = columns(&rgb, w, 400, 800);
    let render = |supersample: &str| {
        let right = dir.join(format!("right-{supersample}.png"));
        let out = Command::new(env!("CARGO_BIN_EXE_stereotrace"))
            .args(["render", "--width", "400", "--height", "300", "--time", "1.0", "--supersample", supersample])
            .arg("--scene")
            .arg(seed_scene())
            .arg("--right")
            .arg(&right)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        read_rgb_png(&right).2
    };
    // The rows above the hint at the bottom centre ("Tab hides the UI"), which reaches into
    // the right eye until the first Tab.
    let top = |rgb: Vec<u8>| rgb[..(400 * 240 * 3) as usize].to_vec();
    let shown = top(shown);
    assert!(shown == top(render("2")), "the right eye on screen is the supersampled render");
    assert!(shown != top(render("1")), "and not the render at one sample per pixel");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Tab hides the whole UI: after it, the presented frame (`--dump`) is in both halves
/// exactly what `stereotrace render` makes of the same frame, so no UI pixel covers an eye.
#[test]
fn tab_hides_the_ui_and_leaves_both_eyes_clean() {
    if missing(&["xvfb-run", "xdotool"]) {
        return;
    }
    let dir = scratch("tab");
    let scene = seed_scene();
    let scene = scene.to_str().unwrap();
    let frame = ["--scene", scene, "--time", "1.0"];
    clean_dump_is_render(&dir, &frame, &["--width", "400", "--height", "200"], &["--width", "200", "--height", "200"]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A click on an atom of 1TII in either eye picks the atom `stereotrace pick` reports at
/// that pixel (the viewer logs each click on stderr); Esc clears the picks before it quits.
#[test]
fn a_click_picks_the_atom_pick_reports_at_that_pixel() {
    const TII: &str = "/usr/share/pymol/data/demo/1tii.pdb";
    if missing(&["xvfb-run", "xdotool"]) {
        return;
    }
    if !Path::new(TII).is_file() {
        tracer::testing::skipped(&format!("{TII} is not installed"));
        return;
    }
    let dir = scratch("pick");
    let x = XSession::start();
    let args = ["--scene", TII, "--width", "1200", "--height", "400", "--time", "0"];
    let args: Vec<&OsStr> = args.iter().map(OsStr::new).collect();
    let mut viewer = x.viewer(&dir, &args, &[("STEREOTRACE_LOG_FPS", "1")]);
    let id = x.focus_window(&viewer);
    viewer.wait_for_line("a rendered frame", has_frame);
    let geometry = x.xdotool(&viewer, "the window's place", &["getwindowgeometry", "--shell", &id]);
    let at = |key: &str| -> i64 {
        geometry.lines().find_map(|l| l.strip_prefix(&format!("{key}="))?.parse().ok()).unwrap_or(0)
    };
    let (wx, wy) = (at("X"), at("Y"));
    // Eyes of 600 × 400; the panel covers the left eye's left 330 columns, the picks window
    // (once there are picks) the right eye's bottom-right corner.
    // Pixels over the molecule in each eye, a few apart, so that a pixel off by one in the
    // window's mapping would pick another atom somewhere.
    let pixels = (0..6).map(|k| (270 + 11 * k, 170 + 7 * k));
    let clicks =
        pixels.clone().map(|p| ("right", p, 600 + p.0)).chain(pixels.map(|p| ("left", (p.0 + 140, p.1), p.0 + 140)));
    let mut matched = 0;
    for (eye, (px, py), window_x) in clicks {
        let (sx, sy) = ((wx + i64::from(window_x)).to_string(), (wy + i64::from(py)).to_string());
        x.xdotool(&viewer, "click", &["mousemove", "--sync", &sx, &sy, "click", "1"]);
        let line = viewer.wait_for_line("the click's pick", |l| l.starts_with("pick: "));
        assert!(line.starts_with(&format!("pick: {eye} eye pixel ({px}, {py}): ")), "{line}");
        let object: Option<u64> =
            line.split_once("): sphere ").and_then(|(_, r)| r.split_whitespace().next()?.parse().ok());
        let out = crate::common::stereotrace(&[
            "pick",
            "--scene",
            TII,
            "--width",
            "600",
            "--height",
            "400",
            "--eye",
            eye,
            "--at",
            &format!("{px},{py}"),
            "--json",
        ]);
        let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(report["object"].as_u64(), object, "{eye} ({px}, {py}): window {line}; pick {report}");
        matched += usize::from(object.is_some());
    }
    assert!(matched >= 8, "most clicks are on atoms: {matched} of 12");
    // Esc clears the picks first: the viewer still runs, and answers the next click.
    let (sx, sy) = ((wx + 900).to_string(), (wy + 200).to_string());
    for step in ["a pick before Esc", "a pick after Esc"] {
        x.xdotool(&viewer, step, &["mousemove", "--sync", &sx, &sy, "click", "1"]);
        viewer.wait_for_line(step, |l| l.starts_with("pick: right eye pixel (300, 200): sphere "));
        if step.ends_with("before Esc") {
            x.xdotool(&viewer, "press Esc", &["key", "Escape"]);
        }
    }
    x.xdotool(&viewer, "press Esc twice", &["key", "Escape", "Escape"]);
    viewer.wait_exit();
    let _ = std::fs::remove_dir_all(&dir);
}
