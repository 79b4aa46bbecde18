//! The fast reprojection pass ([`reproject_and_classify`]: keys carried by a block-wise
//! scan, banded, branch-free classification) against a plain reference, bit for bit: on
//! random left films built to have runs, stretches, overlaps, points in front of the window
//! and clipped rows, and on every scene at several IPDs.

use tracer::testing::{scene, XorShift};
use tracer::{Disparity, Eye, Film, Pixels, Record, Renderer, Target, Tracer, NO_OBJECT};

use super::{reproject_and_classify, reproject_row, right_border_strip, Reprojection, NO_SOURCE};
use crate::classify::Edges;
use crate::mode::{Mode, Options};
use crate::stats::PixelClass;

/// The reprojection and classification one pixel at a time, as the per-pixel rules in
/// `reproject/scanline.rs` and `classify.rs` state them and as they were first written: a scalar
/// scan per row, then each right pixel's 64-bit key (its source's object) gathered by
/// source index, then a branchy per-pixel classification over the whole image.
mod reference {
    use super::{Disparity, Edges, Film, PixelClass, Reprojection, NO_SOURCE};

    /// Key of a pixel without a source.
    const GAP_KEY: u64 = u64::MAX;

    /// The right pixel left pixel `i` at depth `z` lands in: (i + ½ + e) − e·d/(d+z)
    /// clamped to [−1, `w`], rounded down, one pixel at a time.
    fn target(i: usize, z: f32, disparity: Disparity, w: usize) -> i32 {
        let x = ((i as f32 + (0.5 + disparity.scale)) - disparity.shortfall(z)).clamp(-1.0, w as f32);
        (x + 1.0) as i32 - 1
    }

    /// The source map of one row.
    pub(super) fn reproject_row(z: &[f32], disparity: Disparity, row_base: u32) -> Vec<u32> {
        let w = z.len();
        let mut src = vec![NO_SOURCE; w];
        let mut oldx = -1;
        for (i, &zi) in z.iter().enumerate() {
            let j = target(i, zi, disparity, w);
            if j - oldx > 1 {
                for s in &mut src[(oldx + 1).max(0) as usize..j as usize] {
                    *s = NO_SOURCE;
                }
            }
            if (0..w as i32).contains(&j) {
                src[j as usize] = row_base + i as u32;
            }
            oldx = j;
        }
        if oldx + 1 < w as i32 {
            for s in &mut src[(oldx + 1).max(0) as usize..] {
                *s = NO_SOURCE;
            }
        }
        src
    }

    /// The source map and the classes of the whole right image.
    pub(super) fn reproject_and_classify(left: &Film, p: Reprojection) -> (Vec<u32>, Vec<PixelClass>) {
        let (w, h) = (left.width() as usize, left.height() as usize);
        let mut src = Vec::with_capacity(w * h);
        for (j, z) in left.z.chunks(w).enumerate() {
            let mut row = reproject_row(z, p.disparity, (j * w) as u32);
            row[w - p.strip..].fill(NO_SOURCE);
            src.extend(row);
        }
        let key_of = |s: u32| {
            if s == NO_SOURCE {
                GAP_KEY
            } else {
                u64::from(left.object[s as usize])
            }
        };
        let keys: Vec<u64> = src.iter().map(|&s| key_of(s)).collect();
        let key = |i: usize, j: usize| keys[j * w + i];
        // Beyond a row's ends: the key of the end pixel's source's neighbour on that side in
        // its left row, a gap where there is none.
        let beyond = |i: usize, j: usize, step: isize| {
            let s = src[j * w + i];
            let column = (s as usize % w) as isize + step;
            if s == NO_SOURCE || column < 0 || column >= w as isize {
                GAP_KEY
            } else {
                key_of(s - (s % w as u32) + column as u32)
            }
        };
        let mut mask = Vec::with_capacity(w * h);
        for j in 0..h {
            for i in 0..w {
                let me = key(i, j);
                if me == GAP_KEY {
                    mask.push(PixelClass::RetracedGap);
                    continue;
                }
                let (up, down) = (j.saturating_sub(1), (j + 1).min(h - 1));
                // The diagonal neighbours; beyond a row's ends, the pixel above or below.
                let diagonal = |row: usize, step: isize| match i.checked_add_signed(step) {
                    Some(c) if c < w => key(c, row),
                    _ => key(i, row),
                };
                let neighbours = [
                    if i == 0 { beyond(i, j, -1) } else { key(i - 1, j) },
                    if i + 1 == w { beyond(i, j, 1) } else { key(i + 1, j) },
                    key(i, up),
                    key(i, down),
                    diagonal(up, -1),
                    diagonal(up, 1),
                    diagonal(down, -1),
                    diagonal(down, 1),
                ];
                let mut edge = false;
                for (k, n) in neighbours.into_iter().enumerate() {
                    // The diagonal neighbours count in exact mode only.
                    let counts = match p.edges {
                        Edges::Off => false,
                        Edges::Sides => k < 4,
                        Edges::Around => true,
                    };
                    edge |= counts && n != me;
                }
                mask.push(if edge { PixelClass::RetracedEdge } else { PixelClass::Reprojected });
            }
        }
        (src, mask)
    }
}

/// A random left film that obeys the tracer's invariants (a miss is at +∞ with no object;
/// a hit names one of a few spheres): rows of segments that are misses, flat,
/// slanted, noisy, on the window or in front of it, each segment one sphere; half the rows
/// repeat the row above, so that there are vertical runs of equal keys too.
fn random_film(rng: &mut XorShift, w: usize, h: usize, distance: f32) -> Film {
    let mut film = Film::new(w as u32, h as u32);
    for j in 0..h {
        if j > 0 && rng.below(2) == 0 {
            film.object.copy_within((j - 1) * w..j * w, j * w);
            film.z.copy_within((j - 1) * w..j * w, j * w);
            continue;
        }
        let mut i = 0;
        while i < w {
            let len = 1 + rng.below((w - i).min(48));
            let kind = rng.below(7);
            let object = rng.below(4) as u32;
            let (z0, z1) = (rng.range(-0.95 * distance, 6.0 * distance), rng.range(-0.5 * distance, 3.0 * distance));
            for k in 0..len {
                let t = k as f32 / len as f32;
                let z = match kind {
                    0 => f32::INFINITY,
                    1 => z0,
                    2 => z0 + (z1 - z0) * t,
                    3 => rng.range(-0.9 * distance, 10.0 * distance),
                    4 => 0.0,
                    5 => -distance * rng.range(0.5, 0.99),
                    _ => z1 * t * t,
                };
                let at = j * w + i + k;
                film.z[at] = z;
                film.object[at] = if z == f32::INFINITY { NO_OBJECT } else { object };
            }
            i += len;
        }
    }
    film
}

/// Runs the fast pass on `left`, in a pool of `threads` threads.
fn fast(left: &Film, p: Reprojection, threads: usize) -> (Vec<u32>, Vec<PixelClass>) {
    let n = (left.width() * left.height()) as usize;
    let (mut src, mut mask) = (vec![0; n], vec![PixelClass::Traced; n]);
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    pool.install(|| reproject_and_classify(left, p, &mut src, &mut mask));
    (src, mask)
}

#[test]
fn the_fast_pass_equals_the_reference_on_random_films() {
    let mut rng = XorShift::new(0x5EED_CAFE);
    let widths = [1, 2, 3, 4, 5, 7, 8, 9, 31, 64, 101, 250];
    let heights = [1, 2, 3, 15, 16, 17, 33, 40];
    for case in 0..300 {
        let (w, h) = (widths[rng.below(widths.len())], heights[rng.below(heights.len())]);
        let distance = rng.range(2.0, 30.0);
        let scale = [0.0, 0.3, 1.0, 2.5, 7.0, rng.range(0.0, 120.0)][rng.below(6)];
        let disparity = Disparity { scale, distance };
        let strip = [0, 0, 1, rng.below(w + 1), w][rng.below(5)];
        let left = random_film(&mut rng, w, h, distance);
        for edges in [Edges::Off, Edges::Sides, Edges::Around] {
            let p = Reprojection { disparity, strip, edges };
            let expected = reference::reproject_and_classify(&left, p);
            let threads = 1 + case % 3;
            let (src, mask) = fast(&left, p, threads);
            assert!(src == expected.0, "case {case}: {w}×{h}, {p:?}, {threads} threads: source maps differ");
            assert!(mask == expected.1, "case {case}: {w}×{h}, {p:?}, {threads} threads: classes differ");
        }
        // The public one-row function, without the border strip.
        for (j, z) in left.z.chunks(w).enumerate() {
            let mut src = vec![0; w];
            reproject_row(z, disparity, (j * w) as u32, &mut src, &mut Vec::new());
            assert_eq!(src, reference::reproject_row(z, disparity, (j * w) as u32), "case {case}, row {j}");
        }
    }
}

#[test]
fn the_fast_pass_equals_the_reference_on_every_scene() {
    // Not multiples of the band height or of the scan's block.
    let (w, h) = (203, 115);
    let (mut left, mut renderer) = (Film::default(), Renderer::new());
    for name in ["seed.toml", "many.toml", "thousand.toml", "window.toml"] {
        let scene = scene(name);
        for ipd in [0.0, 0.05, scene.camera.ipd, 1.7] {
            for t in [0.0, 2.7] {
                let camera = tracer::Camera { ipd, ..scene.camera };
                let tracer = Tracer::new(&scene, t);
                renderer.render(
                    &tracer,
                    &camera.view(Eye::Left, w, h),
                    Pixels::All,
                    Target::film(&mut left, Record::Full),
                );
                let rv = camera.view(Eye::Right, w, h);
                let disparity = Disparity::in_pixels(&camera, &rv);
                let strip = right_border_strip(&tracer, &camera, disparity, w as usize);
                let p = |edges| Reprojection { disparity, strip, edges };
                // Through the stage as the frame calls it (edges off at IPD 0)…
                for opts in [
                    Options { mode: Mode::Copy, retrace_edges: false },
                    Options { mode: Mode::Reshade, retrace_edges: true },
                    Options { mode: Mode::Exact, retrace_edges: false },
                ] {
                    let n = (w * h) as usize;
                    let (mut src, mut mask) = (vec![0; n], vec![PixelClass::Traced; n]);
                    reproject_and_classify(&left, Reprojection::new(&tracer, &camera, &rv, opts), &mut src, &mut mask);
                    let moved = ipd != 0.0;
                    let expected =
                        reference::reproject_and_classify(&left, p(if moved { opts.edges() } else { Edges::Off }));
                    let at = format!("{name}, IPD {ipd}, t = {t}, {opts:?}");
                    assert!(src == expected.0, "{at}: source maps differ");
                    assert!(mask == expected.1, "{at}: classes differ");
                }
                // …and every choice of edges directly.
                for edges in [Edges::Off, Edges::Sides, Edges::Around] {
                    let expected = reference::reproject_and_classify(&left, p(edges));
                    let got = fast(&left, p(edges), 2);
                    assert!(got == expected, "{name}, IPD {ipd}, t = {t}, edges {edges:?}: differ");
                }
            }
        }
    }
}
