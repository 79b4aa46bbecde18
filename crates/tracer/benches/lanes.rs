//! Criterion benchmarks of the shading wavefront's lane kernels, batch by batch, through the
//! services a second view uses (each call shades one row's list of pixels as one batch):
//! full traces (first hits, shadow rays, highlights, the mirror chain), re-shading of known
//! surfaces (highlights and the mirror chain only) and `exact` mode's rows (each pixel's
//! own ray against the one sphere it sees, shaded with known light bits, then the mirror
//! chain). Two more isolate a kernel: the shadow batch
//! (first hits and shadow rays, no mirrors: the scene at reflection depth 0) and the mirror
//! batch (re-shading with known light bits at depth 1: highlights and one level of mirror
//! rays with their shadow rays). And the marking of temporal reuse: the full trace with
//! every ray tested against the moving spheres' swept volumes. The lane width is the process's
//! (`tracer::lane_width`, in each bench's name); run once more with `STEREOTRACE_LANES=4`
//! for the 4-lane fallback.
#![expect(missing_docs, reason = "criterion_group! and criterion_main! generate undocumented items")]

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use tracer::testing::scene;
use tracer::{lane_width, Eye, Film, Pixels, RayCounts, Record, Renderer, RowPlan, Shaded, Target, Tracer};

const W: u32 = 320;
const H: u32 = 180;

fn batches(c: &mut Criterion) {
    let lanes = lane_width();
    for name in ["seed.toml", "many.toml", "thousand.toml"] {
        let s = scene(name);
        let tracer = Tracer::new(&s, 0.0);
        let view = s.camera.view(Eye::Right, W, H);
        // What each pixel sees, traced the plain way: the inputs of the re-shading batches.
        let mut plain = RayCounts::default();
        let truth: Vec<Shaded> = (0..H)
            .flat_map(|j| (0..W).map(move |i| (i, j)))
            .map(|(i, j)| tracer.trace_pixel(&view, i, j, &mut plain))
            .collect();
        let truth = &truth;
        let hit = move |j: u32| (0..W).filter(move |&i| truth[(j * W + i) as usize].surface.is_hit());
        let mut film = Film::new(1, 1);
        Renderer::new().render(&tracer, &view, Pixels::All, Target::film(&mut film, Record::Keys));
        let film = &film;
        let mut renderer = Renderer::new();
        let second = renderer.batch(&tracer, &view);
        let mut rgb = vec![0u32; W as usize];
        let row_sum = |rgb: &[u32], sum: u32| rgb.iter().fold(sum, |s, &c| s.wrapping_add(c));
        c.bench_function(&format!("lanes{lanes}_trace_rows_{W}x{H}_{name}"), |b| {
            b.iter(|| {
                let (mut counts, mut sum) = (RayCounts::default(), 0u32);
                for j in 0..H {
                    second.trace_pixels(j, 0..W, &mut counts, (&mut rgb, None));
                    sum = row_sum(&rgb, sum);
                }
                black_box((sum, counts))
            });
        });
        c.bench_function(&format!("lanes{lanes}_reshade_rows_{W}x{H}_{name}"), |b| {
            b.iter(|| {
                let (mut counts, mut sum) = (RayCounts::default(), 0u32);
                for j in 0..H {
                    second.reshade(j, (&view, film), hit(j).map(|i| (i, j * W + i)), &mut counts, (&mut rgb, None));
                    sum = row_sum(&rgb, sum);
                }
                black_box((sum, counts))
            });
        });
        let swept = tracer::reuse::Swept::of(&s);
        let marking = second.marking(Some(&swept));
        let mut marks = tracer::reuse::Marks::new(W, 1);
        let mut marks_rows: Vec<_> =
            rayon::iter::ParallelIterator::collect(marks.rows_mut(tracer::reuse::Rewrite::All));
        c.bench_function(&format!("lanes{lanes}_trace_rows_marking_{W}x{H}_{name}"), |b| {
            b.iter(|| {
                let (mut counts, mut sum) = (RayCounts::default(), 0u32);
                for j in 0..H {
                    let row = &mut marks_rows[0];
                    row.clear();
                    marking.trace_pixels(j, 0..W, &mut counts, (&mut rgb, Some(row)));
                    sum = row_sum(&rgb, sum);
                }
                black_box((sum, counts))
            });
        });
        c.bench_function(&format!("lanes{lanes}_exact_rows_{W}x{H}_{name}"), |b| {
            // Each pixel aimed at the sphere it sees: the plan is the film itself, in column
            // order (as exact mode's reprojection hands it over).
            let mut missed = Vec::new();
            let source: Vec<u32> = (0..W * H).collect();
            b.iter(|| {
                let (mut counts, mut sum) = (RayCounts::default(), 0u32);
                for j in 0..H {
                    let row = (j * W) as usize..((j + 1) * W) as usize;
                    let plan = RowPlan { source: &source[row.clone()], object: &film.object[row] };
                    second.shade_row(j, plan, ((&mut rgb, None), None), &mut counts, &mut missed);
                    sum = rgb.iter().fold(sum, |s, &c| s.wrapping_add(c));
                }
                black_box((sum, counts))
            });
        });
        // The shadow batch: the scene without reflections.
        let mut flat = tracer.clone();
        flat.set_max_depth(0);
        let mut flat_renderer = Renderer::new();
        let flat_view = flat_renderer.batch(&flat, &view);
        c.bench_function(&format!("lanes{lanes}_shadow_batch_rows_{W}x{H}_{name}"), |b| {
            b.iter(|| {
                let (mut counts, mut sum) = (RayCounts::default(), 0u32);
                for j in 0..H {
                    flat_view.trace_pixels(j, 0..W, &mut counts, (&mut rgb, None));
                    sum = row_sum(&rgb, sum);
                }
                black_box((sum, counts))
            });
        });
        // The mirror batch: known surfaces, one level of mirror rays.
        let mut one = tracer.clone();
        one.set_max_depth(1);
        let mut one_renderer = Renderer::new();
        let one_view = one_renderer.batch(&one, &view);
        c.bench_function(&format!("lanes{lanes}_mirror_batch_rows_{W}x{H}_{name}"), |b| {
            b.iter(|| {
                let (mut counts, mut sum) = (RayCounts::default(), 0u32);
                for j in 0..H {
                    one_view.reshade(j, (&view, film), hit(j).map(|i| (i, j * W + i)), &mut counts, (&mut rgb, None));
                    sum = row_sum(&rgb, sum);
                }
                black_box((sum, counts))
            });
        });
    }
}

criterion_group!(benches, batches);
criterion_main!(benches);
