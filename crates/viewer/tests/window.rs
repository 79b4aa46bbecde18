//! Window smoke test: the real viewer under Xvfb shows five frames and dumps the last one
//! (eyes and egui panel) to PNG, which must show the seed scene in both halves.
//!
//! Needs `xvfb-run` (Debian: xvfb xauth). Without it the test passes with a loud SKIPPED
//! message, except when `CI` is set: CI installs it, so there a missing `xvfb-run` fails.

use std::fs::File;
use std::io::BufReader;
use std::os::unix::process::CommandExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const WIDTH: u32 = 800;
const HEIGHT: u32 = 300;
const TIMEOUT: Duration = Duration::from_secs(120);

fn on_path(exe: &str) -> bool {
    std::env::var_os("PATH").is_some_and(|p| std::env::split_paths(&p).any(|d| d.join(exe).is_file()))
}

fn seed_scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes/seed.toml")
}

/// Decodes an 8-bit RGB PNG: (width, height, bytes).
fn read_rgb_png(path: &Path) -> (u32, u32, Vec<u8>) {
    let file = File::open(path).unwrap_or_else(|e| panic!("cannot open {}: {e}", path.display()));
    let mut reader = png::Decoder::new(BufReader::new(file)).read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.color_type, info.bit_depth), (png::ColorType::Rgb, png::BitDepth::Eight));
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
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
    if !on_path("xvfb-run") {
        assert!(std::env::var_os("CI").is_none(), "xvfb-run not found, but CI must install xvfb and xauth");
        eprintln!("SKIPPED: xvfb-run not found — install xvfb xauth");
        return;
    }
    let dir = std::env::temp_dir().join(format!("stereotrace-window-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let dump = dir.join("dump.png");
    let log = dir.join("stderr.txt");
    let mut child = Command::new("xvfb-run")
        .args(["-a", "-s", "-screen 0 1920x1080x24", env!("CARGO_BIN_EXE_stereotrace")])
        .arg("--scene")
        .arg(seed_scene())
        .args(["--frames", "5", "--time", "1.0", "--width", &WIDTH.to_string(), "--height", &HEIGHT.to_string()])
        .arg("--dump")
        .arg(&dump)
        .current_dir(&dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(File::create(&log).unwrap())
        // Its own process group, so a timeout can kill xvfb-run, Xvfb and the viewer together.
        .process_group(0)
        .spawn()
        .expect("cannot start xvfb-run");
    let started = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if started.elapsed() > TIMEOUT {
            let _ = Command::new("kill").args(["-KILL", &format!("-{}", child.id())]).status();
            let _ = child.wait();
            panic!("the viewer did not exit within {TIMEOUT:?}; stderr:\n{}", std::fs::read_to_string(&log).unwrap());
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let stderr = std::fs::read_to_string(&log).unwrap();
    assert!(status.success(), "viewer failed ({status}); stderr:\n{stderr}");

    let (w, h, rgb) = read_rgb_png(&dump);
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
    // The egui panel is drawn into the dump, over the left eye's top-left corner.
    let corner = &rgb[((20 * w + 20) * 3) as usize..][..3];
    assert!(corner.iter().all(|&c| c < 100), "the panel should be dark at (20, 20): {corner:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
