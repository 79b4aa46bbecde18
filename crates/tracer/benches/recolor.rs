//! Recolouring a large structure without rebuilding its BVH (issue 35): the structure's
//! kinds recomputed for a scheme (`Scene::recolor`) and the tracer's materials updated
//! (`Tracer::recolor`), on 2BTV's 2.9-million-atom assembly (`../shared/molecules/2btv.pdb.gz`
//! beside the repository), or 1TII when that is missing.
#![expect(missing_docs, reason = "criterion_group! and criterion_main! generate undocumented items")]

use std::hint::black_box;
use std::path::Path;

use criterion::{criterion_group, criterion_main, Criterion};
use tracer::{ColorBy, Coloring, LoadOptions, Scene, Tracer};

fn recolor(c: &mut Criterion) {
    let btv = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../../shared/molecules/2btv.pdb.gz"));
    let (path, options, name) = if btv.exists() {
        (btv, LoadOptions { assembly: true, ..LoadOptions::default() }, "2btv_assembly")
    } else {
        (Path::new("/usr/share/pymol/data/demo/1tii.pdb"), LoadOptions::default(), "1tii")
    };
    let mut scene = match Scene::load_with(path, options) {
        Ok(scene) => scene,
        Err(e) => {
            eprintln!("recolor: skipped, {e}");
            return;
        }
    };
    let mut tracer = Tracer::new(&scene, 0.0);
    eprintln!("{name}: {} atoms", scene.sphere_count());
    let mut group = c.benchmark_group("recolor");
    group.sample_size(10);
    for by in [ColorBy::Chain, ColorBy::Rainbow, ColorBy::BFactor] {
        group.bench_function(format!("{name}_{by}_scene_and_tracer"), |b| {
            b.iter(|| {
                scene.recolor(black_box(&Coloring { by, range: None }));
                tracer.recolor(&scene);
            });
        });
    }
    group.bench_function(format!("{name}_tracer_only"), |b| b.iter(|| tracer.recolor(black_box(&scene))));
    group.finish();
}

criterion_group!(benches, recolor);
criterion_main!(benches);
