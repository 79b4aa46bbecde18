//! The window's `--color` and `--hide`: the render worker's recolour and hiding give, UI
//! hidden, exactly what `stereotrace render` makes with the same flags.

use std::ffi::OsStr;
use std::process::Command;

use super::x_session::XSession;
use super::{columns, field, has_frame, missing, scratch};
use crate::common::read_rgb_png;

#[test]
fn the_window_colours_and_hides_as_render_does() {
    let tii = "/usr/share/pymol/data/demo/1tii.pdb";
    if missing(&["xvfb-run", "xdotool"]) || !std::path::Path::new(tii).exists() {
        return;
    }
    let dir = scratch("colour");
    let x = XSession::start();
    let look = ["--color", "rainbow", "--hide", "water"];
    let args: Vec<&OsStr> = ["--scene", tii, "--width", "400", "--height", "200", "--dump", "dump.png"]
        .into_iter()
        .chain(look)
        .map(OsStr::new)
        .collect();
    let mut viewer = x.viewer(&dir, &args, &[("STEREOTRACE_LOG_FPS", "1")]);
    x.focus_window(&viewer);
    x.xdotool(&viewer, "press Tab", &["key", "Tab"]);
    viewer.wait_for_line("a rendered frame presented with the UI hidden", |l| {
        field(l, "ui") == Some("hidden") && has_frame(l)
    });
    x.xdotool(&viewer, "press Esc", &["key", "Escape"]);
    viewer.wait_exit();

    let render = Command::new(env!("CARGO_BIN_EXE_stereotrace"))
        .args(["render", "--scene", tii, "--width", "200", "--height", "200", "--mode", "exact"])
        .args(look)
        .args(["--left", "left.png", "--right", "right.png"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(render.status.success(), "render failed: {}", String::from_utf8_lossy(&render.stderr));
    let (w, _, dump) = read_rgb_png(&dir.join("dump.png"));
    let (_, _, left) = read_rgb_png(&dir.join("left.png"));
    let (_, _, right) = read_rgb_png(&dir.join("right.png"));
    for (name, half, eye) in [("left", columns(&dump, w, 0, 200), left), ("right", columns(&dump, w, 200, 400), right)]
    {
        let first = half.chunks_exact(3).zip(eye.chunks_exact(3)).position(|(a, b)| a != b);
        assert_eq!(first.map(|k| (k % 200, k / 200)), None, "the {name} half differs from the {name} eye at (x, y)");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
