//! Outlines (`cue/outline.rs`) drawn on one eye's first hits at 800 × 600, 1 and 2 pixels
//! wide: in place on a copy of the colours made first, as the stereo pair's outlines were
//! drawn, and onto the copy in the same pass ([`tracer::outline_from`]). 1TII (pymol-data) is
//! left out where it is not installed. Run with `RAYON_NUM_THREADS=1` to time one core.
#![expect(missing_docs, reason = "criterion_group! and criterion_main! generate undocumented items")]

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use tracer::testing::scene;
use tracer::{first_hits, outline, outline_from, Eye, Outline, Pixels, Renderer, Scene, Target, Tracer};

fn outlines(c: &mut Criterion) {
    let mut scenes = vec![("seed", scene("seed.toml"))];
    match Scene::load(Path::new("/usr/share/pymol/data/demo/1tii.pdb")) {
        Ok(s) => scenes.push(("1tii", s)),
        Err(e) => eprintln!("1tii left out: {e}"),
    }
    let (w, h) = (800, 600);
    for (name, s) in scenes {
        let tracer = Tracer::new(&s, 0.0);
        let view = s.camera.view(Eye::Right, w, h);
        let mut renderer = Renderer::new();
        let (mut object, mut z, mut rgb) = (Vec::new(), Vec::new(), Vec::new());
        first_hits(&mut renderer, &tracer, &view, &mut object, &mut z);
        renderer.render(&tracer, &view, Pixels::All, Target::colour(&mut rgb));
        let mut out = vec![0; rgb.len()];
        let mut group = c.benchmark_group(format!("outline_{name}"));
        group.sample_size(20).warm_up_time(Duration::from_millis(300)).measurement_time(Duration::from_secs(2));
        for width in [1.0, 2.0] {
            let style = Outline::of_view(&view, width);
            group.bench_function(BenchmarkId::new("copy_then_outline", width), |b| {
                b.iter(|| {
                    out.clear();
                    out.extend_from_slice(black_box(&rgb));
                    outline(&mut out, &object, &z, (w, h), style);
                });
            });
            group.bench_function(BenchmarkId::new("outline_from", width), |b| {
                b.iter(|| outline_from(black_box(&rgb), &mut out, &object, &z, (w, h), style));
            });
        }
        group.finish();
    }
}

criterion_group!(benches, outlines);
criterion_main!(benches);
