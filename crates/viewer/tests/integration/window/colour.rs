//! The window's `--color` and `--hide`: the render worker's recolour and hiding give, UI
//! hidden, exactly what `stereotrace render` makes with the same flags.

use super::{clean_dump_is_render, missing, scratch};

#[test]
fn the_window_colours_and_hides_as_render_does() {
    let tii = "/usr/share/pymol/data/demo/1tii.pdb";
    if missing(&["xvfb-run", "xdotool"]) || !std::path::Path::new(tii).exists() {
        return;
    }
    let dir = scratch("colour");
    // A structure's cues on by default: occlusion, depth cueing and 1-pixel outlines, which
    // the converged window draws on its samples as render does.
    let frame = ["--scene", tii, "--color", "rainbow", "--hide", "water"];
    clean_dump_is_render(&dir, &frame, &["--width", "400", "--height", "200"], &["--width", "200", "--height", "200"]);
    let _ = std::fs::remove_dir_all(&dir);
}
