//! Criterion benchmarks of the tracer's inner loops, on fixed inputs.
#![expect(missing_docs, reason = "criterion_group! and criterion_main! generate undocumented items")]

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use glam::Vec3;
use tracer::testing::scene;
use tracer::{
    intersect_sphere, reflect, spawn_ray, Eye, Film, Hit, Pixels, Ray, RayCounts, Record, Renderer, Target, Tracer,
};

fn ray_sphere(c: &mut Criterion) {
    let rays: Vec<Ray> = (0..1024)
        .map(|k| {
            let a = k as f32 * 0.618_034;
            Ray::new(Vec3::ZERO, Vec3::new(a.sin() * 0.3, a.cos() * 0.2, 1.0).normalize())
        })
        .collect();
    c.bench_function("ray_sphere_1024", |b| {
        b.iter(|| {
            let mut hits = 0u32;
            for r in &rays {
                hits +=
                    u32::from(intersect_sphere(black_box(r), Vec3::new(0.5, 0.2, 15.0), 2.5, f32::INFINITY).is_some());
            }
            hits
        });
    });
}

/// Primary rays of a 160×90 view: BVH traversal alone (closest hit), and shading with the
/// first hit found through the BVH one pixel at a time (the recursive plain path) or
/// through the screen bins, a row at a time (the wavefront).
fn traversal_and_shading(c: &mut Criterion) {
    for name in ["seed.toml", "thousand.toml"] {
        let s = scene(name);
        let tracer = Tracer::new(&s, 0.0);
        let view = s.camera.view(Eye::Left, 160, 90);
        let rays: Vec<Ray> =
            (0..90).flat_map(|j| (0..160).map(move |i| (i, j))).map(|(i, j)| view.primary_ray(i, j)).collect();
        c.bench_function(&format!("bvh_closest_hit_160x90_{name}"), |b| {
            b.iter(|| rays.iter().filter(|r| tracer.intersect(black_box(r), f32::INFINITY).is_some()).count());
        });
        // The mirror rays of the view's first hits: what the BVH answers most in big scenes.
        let mirrors: Vec<Ray> = rays
            .iter()
            .filter_map(|r| {
                let Hit { t, object } = tracer.intersect(r, f32::INFINITY)?;
                let p = r.at(t);
                let n = (p - s.sphere_at(object as usize, 0.0).center).normalize();
                Some(spawn_ray(p, n, reflect(r.dir, n)))
            })
            .collect();
        c.bench_function(&format!("bvh_mirror_rays_160x90_{name}"), |b| {
            b.iter(|| mirrors.iter().filter(|r| tracer.intersect(black_box(r), f32::INFINITY).is_some()).count());
        });
        let mut renderer = Renderer::new();
        c.bench_function(&format!("screen_bins_build_160x90_{name}"), |b| {
            b.iter(|| {
                renderer.batch(black_box(&tracer), &view);
            });
        });
        let binned = renderer.batch(&tracer, &view);
        c.bench_function(&format!("shade_binned_160x90_{name}"), |b| {
            b.iter(|| {
                let (mut counts, mut sum, mut rgb) = (RayCounts::default(), 0u32, [0u32; 160]);
                for j in 0..90 {
                    binned.trace_pixels(j, 0..160, &mut counts, (&mut rgb, None));
                    sum = rgb.iter().fold(sum, |s, &c| s.wrapping_add(c));
                }
                (sum, counts)
            });
        });
        c.bench_function(&format!("shade_160x90_{name}"), |b| {
            b.iter(|| shade_all(|i, j, counts| tracer.trace_pixel(&view, i, j, counts).rgb));
        });
    }
}

/// Every pixel of a 160×90 view through `trace`; the pixels' sum and the rays cast.
fn shade_all(mut trace: impl FnMut(u32, u32, &mut RayCounts) -> u32) -> (u32, RayCounts) {
    let mut counts = RayCounts::default();
    let mut sum = 0u32;
    for j in 0..90 {
        for i in 0..160 {
            sum = sum.wrapping_add(trace(i, j, &mut counts));
        }
    }
    (sum, counts)
}

fn eye(c: &mut Criterion) {
    let s = scene("seed.toml");
    let tracer = Tracer::new(&s, 0.0);
    let view = s.camera.view(Eye::Left, 1280, 720);
    let mut film = Film::new(1280, 720);
    let mut renderer = Renderer::new();
    let mut group = c.benchmark_group("render_eye");
    group.sample_size(10);
    group.bench_function("seed_1280x720", |b| {
        b.iter(|| renderer.render(&tracer, black_box(&view), Pixels::All, Target::film(&mut film, Record::Full)));
    });
    group.finish();
}

criterion_group!(benches, ray_sphere, traversal_and_shading, eye);
criterion_main!(benches);
