//! One row of a render: the row loop every [`super::Pixels`] and [`super::Target`] share.
//! A row's pixels go tile by tile through the screen bins, their hits into one batch of the
//! thread's wavefront, shaded in the same lanes, then to the row's sink (colour only, the
//! record's keys, or the whole record) and, when marking, to the row's marks.

use std::ops::Range;

use fearless_simd::{dispatch, prelude::*, Simd};
use glam::Vec3;

use crate::accel::screen::TILE;
use crate::batch::{by_lanes, BinnedView, PixelBatch};
use crate::bits;
use crate::ray::Ray;
use crate::reuse::{Marker, MarksRow};
use crate::simd::F;
use crate::stats::RayCounts;
use crate::surface::{Hit, Shading, NO_OBJECT};
use crate::wavefront::{with_wavefront, Wavefront};

/// What a hit pixel's record keys are: depth, hit parameter, object, light bits.
type Keys = (f32, f32, u32, u32);

/// Where a row's samples go.
pub(super) trait RowSink {
    /// Pixels `span` saw only background, of colour `rgb`.
    fn background(&mut self, span: Range<usize>, rgb: u32);
    /// Pixel `i` saw a sphere: its colour, and (called only by a sink that keeps them) its
    /// record's keys and its shading entry.
    fn hit(&mut self, i: usize, rgb: u32, keys: impl FnOnce() -> Keys, shading: impl FnOnce() -> Shading);
}

/// One row of a [`Film`] without its shading entries: colour, depth, hit parameter, object
/// and light bits.
pub(super) struct KeysRow<'a> {
    pub(super) rgb: &'a mut [u32],
    pub(super) z: &'a mut [f32],
    pub(super) t: &'a mut [f32],
    pub(super) object: &'a mut [u32],
    pub(super) lights: &'a mut [u32],
}

impl KeysRow<'_> {
    /// Writes pixel `i`'s colour and keys.
    #[inline]
    fn keep(&mut self, i: usize, rgb: u32, (z, t, object, lights): Keys) {
        self.rgb[i] = rgb;
        self.z[i] = z;
        self.t[i] = t;
        self.object[i] = object;
        self.lights[i] = lights;
    }
}

impl RowSink for KeysRow<'_> {
    #[inline]
    fn background(&mut self, span: Range<usize>, rgb: u32) {
        self.rgb[span.clone()].fill(rgb);
        self.z[span.clone()].fill(f32::INFINITY);
        self.object[span.clone()].fill(NO_OBJECT);
        self.lights[span].fill(0);
    }

    #[inline]
    fn hit(&mut self, i: usize, rgb: u32, keys: impl FnOnce() -> Keys, _: impl FnOnce() -> Shading) {
        self.keep(i, rgb, keys());
    }
}

/// One row of a [`Film`]: the keys and the shading entries.
pub(super) struct FilmRow<'a> {
    pub(super) keys: KeysRow<'a>,
    pub(super) shading: &'a mut [Shading],
}

impl RowSink for FilmRow<'_> {
    #[inline]
    fn background(&mut self, span: Range<usize>, rgb: u32) {
        // The shading entries of a miss are left as they are: nothing reads them (see
        // `Film::surface`).
        self.keys.background(span, rgb);
    }

    #[inline]
    fn hit(&mut self, i: usize, rgb: u32, keys: impl FnOnce() -> Keys, shading: impl FnOnce() -> Shading) {
        self.keys.keep(i, rgb, keys());
        self.shading[i] = shading();
    }
}

/// One row of colour only.
pub(super) struct RgbRow<'a>(pub(super) &'a mut [u32]);

impl RowSink for RgbRow<'_> {
    #[inline]
    fn background(&mut self, span: Range<usize>, rgb: u32) {
        self.0[span].fill(rgb);
    }

    #[inline]
    fn hit(&mut self, i: usize, rgb: u32, _: impl FnOnce() -> Keys, _: impl FnOnce() -> Shading) {
        self.0[i] = rgb;
    }
}

/// A row's marks to keep, and the hook that makes them.
pub(super) type Marking<'a, 'm> = (MarksRow<'a>, &'m Marker<'m>);

/// Traces row `j` of `eye`, `w` pixels wide, into `sink`; the rays cast. With `marks`, each
/// traced pixel is marked with where its ray tree meets the moving spheres' swept volumes.
/// `only` (a row of [`PixelBits`]) says which pixels are traced, `None` all.
///
/// A whole row goes tile by tile: a tile whose bin is empty is background without a sphere
/// test, the others find their first hits a vector of pixels at a time. The hits are then
/// shaded together, as one batch of this thread's wavefront, in the same lanes. Chosen
/// pixels of a row go a lane group at a time, through the very rays and shading.
pub(super) fn trace_row(
    eye: &BinnedView<'_>,
    j: u32,
    w: usize,
    sink: &mut impl RowSink,
    marks: Option<Marking<'_, '_>>,
    only: Option<&[u64]>,
) -> RayCounts {
    with_wavefront(|wavefront| match only {
        None => dispatch!(crate::simd::level(), simd => trace_row_in(simd, wavefront, eye, j, w, sink, marks)),
        Some(only) => trace_only(wavefront, eye, j, sink, marks, only),
    })
}

/// [`trace_row`] of every pixel with the lanes of `simd`.
pub(super) fn trace_row_in<S: Simd>(
    simd: S,
    wavefront: &mut Wavefront,
    eye: &BinnedView<'_>,
    j: u32,
    w: usize,
    sink: &mut impl RowSink,
    mut marks: Option<Marking<'_, '_>>,
) -> RayCounts {
    let mut counts = RayCounts { primary: w as u64, ..RayCounts::default() };
    let (tile, lanes) = (TILE as usize, F::<S>::LEN);
    let (tracer, view) = (eye.tracer, eye.view);
    if let Some((marks, _)) = marks.as_mut() {
        marks.clear();
    }
    // A pixel that sees only background is marked where its ray meets a swept volume,
    // together with the others in `emit`.
    let marker = marks.as_ref().map(|(_, marker)| *marker);
    let background = |wavefront: &mut Wavefront, i: usize| {
        if marker.is_some_and(|m| m.may_meet(i as u32, j)) {
            wavefront.marks.push_background(i as u32);
        }
    };
    let (mut t, mut ids, mut d) = ([0f32; 16], [0u32; 16], [[0f32; 16]; 3]);
    for span in (0..w.div_ceil(tile)).map(|t| t * tile..((t + 1) * tile).min(w)) {
        if eye.bins.is_empty_at(span.start as u32, j) {
            sink.background(span.clone(), tracer.scene.background_rgb);
            if marker.is_some() {
                for i in span {
                    background(wavefront, i);
                }
            }
            continue;
        }
        for i0 in span.clone().step_by(lanes) {
            // A vector whose rays all hit goes into the batch whole; any other, lane by lane.
            let whole = i0 + lanes <= span.end;
            let Some((tv, idv, dv)) = simd.vectorize(
                #[inline(always)]
                || {
                    let hits = eye.hits_lanes(simd, i0 as u32, j);
                    if whole && hits.0.abs().simd_lt(F::<S>::splat(simd, f32::INFINITY)).all_true() {
                        wavefront.push_lanes(simd, view.origin, hits, i0 as u32);
                        return None;
                    }
                    Some(hits)
                },
            ) else {
                continue;
            };
            tv.store_slice(&mut t[..lanes]);
            idv.store_slice(&mut ids[..lanes]);
            for a in 0..3 {
                dv[a].store_slice(&mut d[a][..lanes]);
            }
            for l in 0..(span.end - i0).min(lanes) {
                let dir = Vec3::new(d[0][l], d[1][l], d[2][l]);
                if t[l].is_finite() {
                    wavefront.push_hit(&Ray::new(view.origin, dir), Hit { t: t[l], object: ids[l] }, (i0 + l) as u32);
                } else {
                    sink.background(i0 + l..i0 + l + 1, tracer.scene.background_rgb);
                    background(wavefront, i0 + l);
                }
            }
        }
    }
    wavefront.shade_in(simd, tracer, &mut counts);
    emit(wavefront, (eye, j), sink, marks);
    counts
}

/// [`trace_row`] of the pixels `only` names: full primary rays a lane group at a time (the
/// rays and hits of every other pass, bit for bit), shaded as one batch.
fn trace_only(
    wavefront: &mut Wavefront,
    eye: &BinnedView<'_>,
    j: u32,
    sink: &mut impl RowSink,
    mut marks: Option<Marking<'_, '_>>,
    only: &[u64],
) -> RayCounts {
    let mut counts = RayCounts::default();
    if only.iter().all(|&word| word == 0) {
        return counts;
    }
    let batch = PixelBatch::new(*eye, marks.as_ref().map(|(_, marker)| **marker));
    if let Some((marks, _)) = marks.as_mut() {
        marks.clear_only(Some(only));
    }
    by_lanes(bits::ones(only), PixelBatch::lanes(), |base, mask| {
        counts.primary += u64::from(mask.count_ones());
        batch.push_traced(wavefront, base, j, mask, &mut |i, rgb, touch| {
            sink.background(i as usize..i as usize + 1, rgb);
            if let Some((marks, _)) = marks.as_mut() {
                marks.set(i, touch);
            }
        });
    });
    wavefront.shade(eye.tracer, &mut counts);
    emit(wavefront, (eye, j), sink, marks);
    counts
}

/// Hands each sample of the shaded batch to `sink`, and marks it (when marking) with where
/// its ray tree meets the swept volumes.
fn emit(
    wavefront: &mut Wavefront,
    (eye, j): (&BinnedView<'_>, u32),
    sink: &mut impl RowSink,
    marks: Option<Marking<'_, '_>>,
) {
    let view = eye.view;
    if let Some((mut marks, marker)) = marks {
        wavefront.mark(marker, &eye.tracer.scene.lights, |i| marker.may_meet(i, j));
        for e in 0..wavefront.len() {
            let touch = wavefront.marks.touch(e);
            if touch.is_some() {
                marks.set(wavefront.tag(e), touch);
            }
        }
        wavefront.marks.mark_background(marker, view, j, &mut |i, touch| marks.set(i, touch));
    }
    for e in 0..wavefront.len() {
        let keys = || {
            let (point, t, object, lights) = wavefront.keys(e);
            (view.head_z(point), t, object, lights)
        };
        let shading = || {
            let s = wavefront.surface(e);
            Shading { point: s.point, normal: s.normal, diffuse: s.diffuse }
        };
        sink.hit(wavefront.tag(e) as usize, wavefront.rgb(e), keys, shading);
    }
}

/// Row `j` of `eye`'s depth (`z`, the row's width): each pixel's first hit through the
/// screen bins, a vector of pixels at a time, as [`crate::EyeView::head_z`] of the hit point
/// `o + t·d` (the operations the wavefront makes it with), +∞ for a miss.
pub(super) fn depth_row(eye: &BinnedView<'_>, j: u32, z: &mut [f32]) {
    dispatch!(crate::simd::level(), simd => simd.vectorize(
        #[inline(always)]
        || depth_row_in(simd, eye, j, z),
    ));
}

#[expect(clippy::inline_always, reason = "inlined into the dispatched closure, whose target features it needs")]
#[inline(always)]
fn depth_row_in<S: Simd>(simd: S, eye: &BinnedView<'_>, j: u32, z: &mut [f32]) {
    let (tile, lanes, w) = (TILE as usize, F::<S>::LEN, z.len());
    let (view, o) = (eye.view, eye.view.origin);
    let (mut t, mut d) = ([0f32; 16], [[0f32; 16]; 3]);
    for span in (0..w.div_ceil(tile)).map(|t| t * tile..((t + 1) * tile).min(w)) {
        if eye.bins.is_empty_at(span.start as u32, j) {
            z[span].fill(f32::INFINITY);
            continue;
        }
        for i0 in span.clone().step_by(lanes) {
            let (tv, _, dv) = eye.hits_lanes(simd, i0 as u32, j);
            tv.store_slice(&mut t[..lanes]);
            for a in 0..3 {
                dv[a].store_slice(&mut d[a][..lanes]);
            }
            for l in 0..(span.end - i0).min(lanes) {
                z[i0 + l] = if t[l].is_finite() {
                    let p = Vec3::new(o.x + t[l] * d[0][l], o.y + t[l] * d[1][l], o.z + t[l] * d[2][l]);
                    view.head_z(p)
                } else {
                    f32::INFINITY
                };
            }
        }
    }
}
