//! Where timewarp's warped pixels come from: a scene's stereo pair, traced at 800×600 per
//! eye with a guard band of (40, 30), warped to a few head poses a frame or so of motion
//! away, and each pose's share of pixels of each class ([`stereo::WarpClass`]) over both
//! eyes. With a directory, it also writes each pose's warped left eye and its class mask
//! as binary PPM images there (convert them with `pnmtopng`).
//!
//! `cargo run --release -p stereo --example warp_classes -- [SCENE.toml] [OUT_DIR]`
//! (default: the thousand-sphere scene).

use std::fs;
use std::io::Write as _;
use std::path::{Path, PathBuf};

use glam::Vec3;
use stereo::{Warp, WarpClass, WarpCounts, WarpSource};
use tracer::{Camera, Eye, Film, Pixels, Record, Renderer, Scene, Target, Tracer};

const W: u32 = 800;
const H: u32 = 600;
const MARGIN: (u32, u32) = (40, 30);

/// The mask's colours: own eye grey, cracks green, other eye blue, hole rule red.
fn mask(class: WarpClass) -> u32 {
    match class {
        WarpClass::Warped => 0x40_4040,
        WarpClass::Crack => 0x00_ff00,
        WarpClass::OtherEye => 0x30_60ff,
        WarpClass::Filled => 0xff_2020,
    }
}

/// Writes `pixels` (`0x00RRGGBB`, `W` × `H`) as a binary PPM image.
fn write_ppm(path: &Path, pixels: impl Iterator<Item = u32>) -> std::io::Result<()> {
    let mut bytes = format!("P6\n{W} {H}\n255\n").into_bytes();
    bytes.extend(pixels.flat_map(|p| [(p >> 16) as u8, (p >> 8) as u8, p as u8]));
    fs::File::create(path)?.write_all(&bytes)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let scene_path = args.next().map_or_else(
        || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes/thousand.toml"),
        PathBuf::from,
    );
    let out_dir = args.next().map(PathBuf::from);
    let scene = Scene::load(&scene_path)?;
    let tracer = Tracer::new(&scene, 0.0);
    let eyes = [Eye::Left, Eye::Right];
    let views = eyes.map(|eye| scene.camera.view_with_margin(eye, W, H, MARGIN));
    let films = views.map(|view| {
        let mut film = Film::new(view.width, view.height);
        Renderer::new().render(&tracer, &view, Pixels::All, Target::film(&mut film, Record::Keys));
        film
    });
    // (name, yaw in degrees, head step)
    let poses = [
        ("traced", 0.0, Vec3::ZERO),
        ("yaw1", 1.0, Vec3::ZERO),
        ("step0.05", 0.0, Vec3::new(0.05, 0.0, 0.0)),
        ("yaw1-step0.05", 1.0, Vec3::new(0.05, 0.0, 0.0)),
        ("forward0.3", 0.0, Vec3::new(0.0, 0.0, 0.3)),
        ("pitch2-step0.1", 0.0, Vec3::new(0.1, 0.1, 0.0)),
    ];
    let mut warp = Warp::new();
    let (mut left, mut right, mut left_classes, mut right_classes) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    println!("{}", scene_path.display());
    println!("{:16} {:>8} {:>8} {:>8} {:>8}   holes", "pose", "warped", "crack", "other", "filled");
    for (name, yaw, step) in poses {
        let pitch = if name.starts_with("pitch") { 2.0 } else { 0.0 };
        let moved = Camera {
            yaw_deg: scene.camera.yaw_deg + yaw,
            pitch_deg: scene.camera.pitch_deg + pitch,
            position: scene.camera.position + step,
            ..scene.camera
        };
        let targets = eyes.map(|eye| moved.view(eye, W, H));
        let sources = [0, 1].map(|e| WarpSource::from_film(views[e], &films[e]));
        let [l, r] = warp.warp(
            sources,
            [&targets[0], &targets[1]],
            [&mut left, &mut right],
            [&mut left_classes, &mut right_classes],
        );
        let c: WarpCounts = l + r;
        let pct = |n: u64| 100.0 * n as f64 / c.total() as f64;
        println!(
            "{name:16} {:7.3}% {:7.3}% {:7.3}% {:7.3}%   {:.3}%",
            pct(c.warped),
            pct(c.crack),
            pct(c.other_eye),
            pct(c.filled),
            pct(c.holes())
        );
        if let Some(dir) = &out_dir {
            fs::create_dir_all(dir)?;
            write_ppm(&dir.join(format!("{name}-left.ppm")), left.iter().copied())?;
            write_ppm(&dir.join(format!("{name}-mask.ppm")), left_classes.iter().map(|&k| mask(k)))?;
        }
    }
    Ok(())
}
