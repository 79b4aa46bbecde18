//! One eye's render (full record, left eye) with its first hits found through the screen
//! bins and through the BVH, across sizes and scenes: the crossover that
//! `accel/screen.rs`'s rule (`BINS_SPHERES_PER_RAY`) is set from. Structure files that are
//! not on this machine (1TII from pymol-data, the 2BTV assembly from `../shared/molecules`)
//! are left out. Filter by name, e.g. `cargo bench --bench first_hits -- 2btv`.
#![expect(missing_docs, reason = "criterion_group! and criterion_main! generate undocumented items")]

use std::hint::black_box;
use std::path::Path;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use tracer::testing::scene;
use tracer::{Eye, Film, FirstHits, LoadOptions, Pixels, Record, Renderer, Scene, Target, Tracer};

const SIZES: [(u32, u32); 6] = [(50, 38), (100, 75), (200, 150), (400, 300), (800, 600), (1280, 720)];

fn scenes() -> Vec<(&'static str, Scene)> {
    let mut scenes: Vec<_> = ["seed.toml", "many.toml", "thousand.toml"].map(|n| (n, scene(n))).into();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let files = [
        ("1tii", Path::new("/usr/share/pymol/data/demo/1tii.pdb").to_path_buf(), false),
        ("2btv_assembly", root.join("../shared/molecules/2btv.pdb.gz"), true),
    ];
    for (name, path, assembly) in files {
        match Scene::from_structure_file(&path, LoadOptions { assembly, ..LoadOptions::default() }) {
            Ok(s) => scenes.push((name, s)),
            Err(e) => eprintln!("{name} left out: {e}"),
        }
    }
    scenes
}

fn first_hits(c: &mut Criterion) {
    for (name, s) in scenes() {
        let tracer = Tracer::new(&s, 0.0);
        let mut group = c.benchmark_group(format!("first_hits_{name}"));
        group.sample_size(10).warm_up_time(Duration::from_millis(300)).measurement_time(Duration::from_secs(2));
        for (w, h) in SIZES {
            let view = s.camera.view(Eye::Left, w, h);
            for (way, first_hits) in [("bins", FirstHits::Bins), ("bvh", FirstHits::Bvh)] {
                let mut renderer = Renderer::new().with_first_hits(first_hits);
                let mut film = Film::new(w, h);
                group.bench_function(BenchmarkId::new(way, format!("{w}x{h}")), |b| {
                    b.iter(|| {
                        renderer.render(black_box(&tracer), &view, Pixels::All, Target::film(&mut film, Record::Full))
                    });
                });
            }
        }
        group.finish();
    }
}

criterion_group!(benches, first_hits);
criterion_main!(benches);
