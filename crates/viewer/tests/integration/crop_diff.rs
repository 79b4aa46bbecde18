//! End-to-end tests of `render --crop` and `render --diff`, the options the paper figures
//! (`scripts/paper-figures.sh`) use.

use std::path::{Path, PathBuf};

use crate::common::{read_png, stereotrace, tmp};

fn s(p: &Path) -> &str {
    p.to_str().unwrap_or_else(|| panic!("{} is not UTF-8", p.display()))
}

const RED: u32 = 0x00D0_1010;
const AMBER: u32 = 0x00F0_A020;

#[test]
fn a_crop_is_the_same_rectangle_of_every_eye_image() {
    let size = ["--width", "96", "--height", "54", "--mode", "copy"];
    let whole: Vec<PathBuf> = ["l", "r", "m", "d"].iter().map(|n| tmp(&format!("whole-{n}.png"))).collect();
    let cut: Vec<PathBuf> = ["l", "r", "m", "d"].iter().map(|n| tmp(&format!("cut-{n}.png"))).collect();
    for (files, crop) in [(&whole, None), (&cut, Some("30,20,40,16"))] {
        let mut args: Vec<&str> = vec!["render"];
        args.extend(size);
        for (flag, f) in ["--left", "--right", "--mask", "--diff"].into_iter().zip(files.iter()) {
            args.extend([flag, s(f)]);
        }
        if let Some(c) = crop {
            args.extend(["--crop", c]);
        }
        let out = stereotrace(&args);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    }
    for (w, c) in whole.iter().zip(&cut) {
        let (ww, _, big) = read_png(w);
        let (cw, ch, small) = read_png(c);
        assert_eq!((cw, ch), (40, 16), "{}: the crop's size", c.display());
        let expected: Vec<u32> =
            (20..36).flat_map(|y| big[(y * ww + 30) as usize..(y * ww + 70) as usize].to_vec()).collect();
        assert_eq!(small, expected, "{}: columns 30–69, rows 20–35 of the whole image", c.display());
    }
}

#[test]
fn the_difference_image_is_clean_for_exact_and_red_for_copy() {
    let count = |mode: &str| {
        let d = tmp(&format!("diff-{mode}.png"));
        let out = stereotrace(&["render", "--width", "160", "--height", "90", "--mode", mode, "--diff", s(&d)]);
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let (w, h, px) = read_png(&d);
        assert_eq!((w, h), (160, 90), "the eye's size");
        (px.iter().filter(|&&p| p == RED).count(), px.iter().filter(|&&p| p == AMBER).count())
    };
    assert_eq!(count("full"), (0, 0), "full is its own reference");
    assert_eq!(count("exact"), (0, 0), "exact matches full on the seed scene");
    let (red, _) = count("copy");
    assert!(red > 0, "copy's reused highlights are off by more than 2/255 somewhere");
}

#[test]
fn bad_crops_exit_2() {
    let r = tmp("bad-crop.png");
    let out = stereotrace(&["render", "--width", "16", "--height", "8", "--right", s(&r), "--crop", "10,0,8,8"]);
    assert_eq!(out.status.code(), Some(2), "outside the image");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--crop 10,0,8,8: the rectangle must lie inside the 16×8 eye image"), "{err}");
    let out = stereotrace(&["render", "--right", s(&r), "--crop", "0,0,0,8"]);
    assert_eq!(out.status.code(), Some(2), "an empty rectangle");
    assert!(String::from_utf8_lossy(&out.stderr).contains("expected X,Y,W,H"), "the form is named");
    let out = stereotrace(&["render", "--out", s(&r), "--crop", "0,0,4,4"]);
    assert_eq!(out.status.code(), Some(2), "--crop does not apply to the combined pair");
    assert!(!r.exists(), "nothing written");
}
