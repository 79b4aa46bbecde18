//! Criterion benchmark of timewarp's warp stage: the seed scene's stereo pair, traced once
//! at 800×600 per eye with a guard band of (40, 30), warped to a head pose turned 1° and
//! stepped 0.05 sideways. Compare with a full stereo trace of the same scene and size
//! (`stereotrace bench --scene assets/scenes/seed.toml --width 800 --height 600 --json`,
//! `modes.full.stereo_ms`): the warp's budget is a quarter of it.
#![expect(missing_docs, reason = "criterion_group! and criterion_main! generate undocumented items")]

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use glam::Vec3;
use stereo::{Mode, Options, StereoFrame, Warp, WarpSource};
use tracer::{Camera, Eye, Film, Pixels, Record, Renderer, Target, Tracer};

const W: u32 = 800;
const H: u32 = 600;
const MARGIN: (u32, u32) = (40, 30);

fn warp(c: &mut Criterion) {
    let scene = tracer::testing::scene("seed.toml");
    let tracer = Tracer::new(&scene, 0.0);
    let eyes = [Eye::Left, Eye::Right];
    let views = eyes.map(|eye| scene.camera.view_with_margin(eye, W, H, MARGIN));
    let films = views.map(|view| {
        let mut film = Film::new(view.width, view.height);
        Renderer::new().render(&tracer, &view, Pixels::All, Target::film(&mut film, Record::Keys));
        film
    });
    let moved = Camera {
        yaw_deg: scene.camera.yaw_deg + 1.0,
        position: scene.camera.position + Vec3::new(0.05, 0.0, 0.0),
        ..scene.camera
    };
    let targets = eyes.map(|eye| moved.view(eye, W, H));
    let mut warp = Warp::new();
    let (mut left, mut right) = (Vec::new(), Vec::new());
    let (mut left_classes, mut right_classes) = (Vec::new(), Vec::new());
    let mut run = || {
        let sources = [0, 1].map(|e| WarpSource::from_film(views[e], &films[e]));
        warp.warp(
            black_box(sources),
            [&targets[0], &targets[1]],
            [&mut left, &mut right],
            [&mut left_classes, &mut right_classes],
        )
    };
    let counts = run();
    eprintln!("warp counts (left, right): {counts:?}");
    c.bench_function("warp_stereo_800x600_turn1deg_step0.05", |b| b.iter(&mut run));
}

/// The budget's yardstick, in the same process: a full stereo trace of the same scene and
/// size (both eyes traced, as `stereotrace bench`'s `modes.full`).
fn trace(c: &mut Criterion) {
    let scene = tracer::testing::scene("seed.toml");
    let tracer = Tracer::new(&scene, 0.0);
    let mut frame = StereoFrame::new();
    let opts = Options { mode: Mode::Full, retrace_edges: false };
    frame.render(&tracer, &scene.camera, W, H, opts);
    let mut group = c.benchmark_group("trace");
    group.sample_size(20);
    group.bench_function("stereo_full_800x600", |b| {
        b.iter(|| frame.render(&tracer, &scene.camera, W, H, black_box(opts)));
    });
    group.finish();
}

criterion_group!(benches, warp, trace);
criterion_main!(benches);
