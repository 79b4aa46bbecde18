//! One row of a render: the row loop every [`super::Pixels`] and [`super::Target`] share.
//!
//! A row's pixels go tile by tile through the screen bins, a group of lanes at a time (every
//! group, or those the row's selection names). A tile whose bin is empty is background
//! without a sphere test; the others find their first hits in lanes (or, for a view
//! searched through the BVH, ray by ray the lanes chosen; for a sliced view, the whole row
//! binned first and the rays its bins leave open sent through the BVH sixteen at a time,
//! `accel/screen/held.rs`) and push them into one batch of the thread's wavefront, shaded
//! together, then emitted into the row's [`RowSink`] (`sink.rs`), whose observer marks them
//! when the render marks. A sink that does not shade (depth) takes each first hit's depth
//! instead, and the batch stays empty.

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use fearless_simd::{dispatch, prelude::*, Simd};
use glam::Vec3;

use crate::accel::screen::{Search, TILE};
use crate::batch::BinnedView;
use crate::bits;
use crate::camera::EyeView;
use crate::simd::{F, U};
use crate::sink::{Columns, Observe, RowSink};
use crate::stats::RayCounts;
use crate::surface::NO_OBJECT;
use crate::wavefront::{with_wavefront, Wavefront};

/// Traces row `j` of `eye`, `w` pixels wide, into `sink`; the rays cast. `only` (a row of
/// [`crate::PixelBits`]) says which pixels are traced, `None` all.
pub(super) fn trace_row<C: Columns, O: Observe>(
    eye: &BinnedView<'_>,
    j: u32,
    w: usize,
    sink: &mut RowSink<C, O>,
    only: Option<&[u64]>,
) -> RayCounts {
    if only.is_some_and(|row| row.iter().all(|&word| word == 0)) {
        return RayCounts::default();
    }
    let bvh = eye.bins.search() == Search::Bvh;
    with_wavefront(|wavefront| {
        dispatch!(crate::simd::level(), simd => if bvh {
            trace_row_in::<_, _, _, true>(simd, wavefront, eye, j, w, sink, only)
        } else {
            trace_row_in::<_, _, _, false>(simd, wavefront, eye, j, w, sink, only)
        })
    })
}

/// [`trace_row`] with the lanes of `simd`, for a view searched through the BVH (`BVH`) or
/// the bins.
pub(super) fn trace_row_in<S: Simd, C: Columns, O: Observe, const BVH: bool>(
    simd: S,
    wavefront: &mut Wavefront,
    eye: &BinnedView<'_>,
    j: u32,
    w: usize,
    sink: &mut RowSink<C, O>,
    only: Option<&[u64]>,
) -> RayCounts {
    let mut counts = RayCounts::default();
    // A span is a tile, or as many as a vector's lanes cover (16 lanes: two tiles).
    let lanes = F::<S>::LEN;
    let span_width = lanes.max(TILE as usize);
    let (tracer, view) = (eye.tracer, eye.view);
    let background = tracer.scene.background_rgb;
    // The pixels to trace of the `n` (at most a span) from column `i0`, as a mask. A span
    // lies within one word of a row of bits.
    let chosen = |i0: usize, n: usize| {
        let all = (1u32 << n) - 1;
        only.map_or(all, |row| (row[i0 / 64] >> (i0 % 64)) as u32 & all)
    };
    let spans = || (0..w.div_ceil(span_width)).map(|t| t * span_width..((t + 1) * span_width).min(w));
    // A sliced view's row is binned first, its open rays then searched together, sixteen
    // at a time (`accel/screen/held.rs`); its groups below take their hits from there.
    let held = !BVH && eye.bins.is_sliced();
    if held {
        wavefront.held.clear();
        for span in spans() {
            for i0 in span.clone().step_by(lanes) {
                let mask = chosen(i0, (span.end - i0).min(lanes));
                if mask != 0 {
                    let binned = simd.vectorize(
                        #[inline(always)]
                        || eye.binned_lanes::<S>(simd, (i0 as u32, j, mask)),
                    );
                    wavefront.held.hold::<S>(binned);
                }
            }
        }
        wavefront.held.search(eye.bins, &tracer.accel, view.origin);
    }
    let mut group = 0;
    for span in spans() {
        if !BVH && eye.bins.bin_is_empty_at((span.start as u32, j), span.len()) {
            let mask = chosen(span.start, span.len());
            counts.primary += u64::from(mask.count_ones());
            if only.is_none() {
                sink.background(span, background);
            } else {
                for i in bits::ones(&[u64::from(mask)]).map(|l| span.start + l as usize) {
                    sink.background(i..i + 1, background);
                }
            }
            continue;
        }
        for i0 in span.clone().step_by(lanes) {
            let mask = chosen(i0, (span.end - i0).min(lanes));
            if mask == 0 {
                continue;
            }
            counts.primary += u64::from(mask.count_ones());
            simd.vectorize(
                #[inline(always)]
                || {
                    let hits = if held {
                        wavefront.held.hits(simd, group)
                    } else {
                        eye.hits_lanes_by::<S, BVH>(simd, (i0 as u32, j, mask))
                    };
                    if C::SHADES {
                        eye.push_found_in(simd, wavefront, (i0 as u32, mask), hits, sink);
                    } else {
                        first_hits::<S>(view, (i0, mask), hits, sink);
                    }
                },
            );
            group += 1;
        }
    }
    if C::SHADES {
        wavefront.shade_in(simd, tracer, crate::cue::SeedRow::of(view, j), &mut counts);
        sink.emit(wavefront, view, true);
    }
    counts
}

/// Hands `sink` the first hit of each pixel `mask` names of the group of lanes from column
/// `i0`, whose first hits are `hits`: its sphere, and [`EyeView::head_z`] of the hit point
/// `o + t·d` (the operations the wavefront makes it with); +∞ and [`NO_OBJECT`] for a miss.
#[inline(always)]
fn first_hits<S: Simd>(
    view: &EyeView,
    (i0, mask): (usize, u32),
    (t, ids, d): (F<S>, U<S>, [F<S>; 3]),
    sink: &mut RowSink<impl Columns, impl Observe>,
) {
    let o = view.origin;
    let (t, ids, d) = (t.as_slice(), ids.as_slice(), crate::simd::each3(|a| d[a].as_slice()));
    for l in bits::ones(&[u64::from(mask)]).map(|l| l as usize) {
        let (z, object) = if t[l].is_finite() {
            (view.head_z(Vec3::new(o.x + t[l] * d[0][l], o.y + t[l] * d[1][l], o.z + t[l] * d[2][l])), ids[l])
        } else {
            (f32::INFINITY, NO_OBJECT)
        };
        sink.columns.first_hit(i0 + l, z, object);
    }
}
