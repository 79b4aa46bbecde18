//! Criterion benchmarks of the stereo passes on the seed scene at 1280×720 per eye.
#![expect(missing_docs, reason = "criterion_group! and criterion_main! generate undocumented items")]

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use stereo::{reproject_row, Mode, Options, StereoFrame};
use tracer::{Disparity, Eye, Film, Pixels, Record, Renderer, Scene, Target, Tracer};

const W: u32 = 1280;
const H: u32 = 720;

fn seed() -> (Scene, Tracer) {
    let scene = tracer::testing::scene("seed.toml");
    let tracer = Tracer::new(&scene, 0.0);
    (scene, tracer)
}

fn reprojection(c: &mut Criterion) {
    let (scene, tracer) = seed();
    let mut left = Film::new(W, H);
    Renderer::new().render(
        &tracer,
        &scene.camera.view(Eye::Left, W, H),
        Pixels::All,
        Target::film(&mut left, Record::Full),
    );
    let disparity = Disparity::in_pixels(&scene.camera, &scene.camera.view(Eye::Right, W, H));
    let mut src = vec![0u32; (W * H) as usize];
    let mut targets = Vec::new();
    c.bench_function("reproject_rows_1280x720_one_thread", |b| {
        b.iter(|| {
            for (j, (z, s)) in left.z.chunks(W as usize).zip(src.chunks_mut(W as usize)).enumerate() {
                reproject_row(black_box(z), disparity, j as u32 * W, s, &mut targets);
            }
        });
    });
}

fn right_eye(c: &mut Criterion) {
    let (scene, tracer) = seed();
    let mut frame = StereoFrame::new();
    let mut group = c.benchmark_group("stereo_frame_1280x720");
    group.sample_size(10);
    for mode in Mode::ALL {
        let opts = Options { mode, retrace_edges: false };
        frame.render(&tracer, &scene.camera, W, H, opts);
        group.bench_function(mode.name(), |b| b.iter(|| frame.render(&tracer, &scene.camera, W, H, black_box(opts))));
    }
    group.finish();
}

criterion_group!(benches, reprojection, right_eye);
criterion_main!(benches);
