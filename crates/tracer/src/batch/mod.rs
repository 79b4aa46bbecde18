//! Batches of an eye's chosen pixels: what a second view is made of (Adelson & Hodges 1993,
//! "Stereoscopic ray-tracing"), and what a reused frame retraces in either eye.
//!
//! A [`BinnedView`] is one eye's view with its screen bins built. For a row's chosen pixels
//! it makes, each job in a file, into the row's sink (`sink.rs`):
//! - `trace.rs`, [`BinnedView::trace_pixels`]: full primary rays (the retrace of gaps,
//!   borders and object edges, and of what changed since the last frame), bit-for-bit the
//!   pixels [`crate::Renderer::render`] would make;
//! - `reshade.rs`, [`BinnedView::reshade`]: surfaces another view saw, re-lit for these
//!   pixels' rays: their view-independent light and light visibility kept, highlights and
//!   mirror rays recomputed (`reshade` mode);
//! - `plan.rs`, [`BinnedView::shade_row`]: a whole row by a plan, a pixel of the other view
//!   per column (or none: trace afresh, or keep): each pixel's own ray against the one
//!   sphere the other view saw there, shaded as a full trace shades it (its own shadow rays),
//!   and fully traced where it misses that sphere or the plan says so (`exact` mode).
//!
//! Every row's pixels are shaded as one batch of the thread's wavefront (`wavefront.rs`), so
//! they go through the very kernels a whole eye's do, and leave through the sink as a
//! render's do. Whoever watches the sink (temporal reuse's marks) is the sink's business:
//! these producers know nothing of it. The public face of these jobs is
//! [`crate::PixelBatch`] (`render/batch.rs`), which builds each row's sink.
//!
//! **Light bits.** Visibility travels as bits: bit k of [`crate::Surface::lights`] (and of
//! the film's `lights` plane) is set when light k reaches the point. A point of a surface is
//! the same point from either eye, so reshade's bits hold for the second view as for the
//! first; only what depends on the direction of view is recomputed. Exact mode does not
//! reuse them: its pixel's own hit point is not its source's, and a shadow thinner than a
//! pixel can fall between the two.

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

mod plan;
mod reshade;
mod trace;

use fearless_simd::{dispatch, prelude::*, Simd};
use glam::Vec3;

use crate::accel::screen::{BinnedLanes, ScreenBins, Search};
use crate::camera::EyeView;
use crate::ray::Ray;
use crate::simd::{F, U};
use crate::sink::{Columns, Observe, RowSink};
use crate::surface::Hit;
use crate::tracer::Tracer;
use crate::wavefront::Wavefront;

pub use plan::{RowPlan, KEEP, TRACE};

/// One eye's view with its screen bins built: traces that view's primary rays, and shades
/// what they hit in the scene, into a row's sink (see the module doc).
#[derive(Clone, Copy, Debug)]
pub(crate) struct BinnedView<'a> {
    /// The scene.
    pub(crate) tracer: &'a Tracer,
    /// The eye.
    pub(crate) view: &'a EyeView,
    /// `view`'s bins, built by [`ScreenBins::build`] for `tracer` and `view`.
    pub(crate) bins: &'a ScreenBins,
}

/// Groups ascending pixel columns by the aligned group of `lanes` (a power of two, at most
/// 32) they fall in: calls `group(first column, lane mask)` once per group.
pub(crate) fn by_lanes(cols: impl IntoIterator<Item = u32>, lanes: u32, mut group: impl FnMut(u32, u32)) {
    debug_assert!(lanes.is_power_of_two() && lanes <= 32, "{lanes} lanes");
    let mut current: Option<(u32, u32)> = None;
    for i in cols {
        let base = i & !(lanes - 1);
        match &mut current {
            Some((b, mask)) if *b == base => *mask |= 1 << (i - base),
            _ => {
                if let Some((b, mask)) = current.take() {
                    group(b, mask);
                }
                current = Some((base, 1 << (i - base)));
            }
        }
    }
    if let Some((b, mask)) = current {
        group(b, mask);
    }
}

/// How many columns a group of lanes holds ([`BinnedView::push_traced`]): the lane width.
pub(crate) fn lanes() -> u32 {
    crate::simd::lane_width() as u32
}

impl BinnedView<'_> {
    /// The first hits of the primary rays of pixels (i + l, j), l = 0..LEN, at least of the
    /// lanes `mask` names ([`ScreenBins::hits_lanes`]).
    #[inline(always)]
    pub(crate) fn hits_lanes<S: Simd>(&self, simd: S, at: (u32, u32, u32)) -> (F<S>, U<S>, [F<S>; 3]) {
        if self.bins.search() == Search::Bvh {
            self.hits_lanes_by::<S, true>(simd, at)
        } else {
            self.hits_lanes_by::<S, false>(simd, at)
        }
    }

    /// [`BinnedView::hits_lanes`] for a view searched through the BVH (`BVH`) or the bins.
    #[inline(always)]
    pub(crate) fn hits_lanes_by<S: Simd, const BVH: bool>(
        &self,
        simd: S,
        at: (u32, u32, u32),
    ) -> (F<S>, U<S>, [F<S>; 3]) {
        let scene = &self.tracer.scene;
        self.bins.hits_lanes::<S, BVH>(simd, (self.view, &scene.centers, &scene.radii), &self.tracer.accel, at)
    }

    /// [`ScreenBins::binned_lanes`] of a view searched through the bins: the hits the bins
    /// find, and the lanes a sliced view sends on through the BVH.
    #[inline(always)]
    pub(crate) fn binned_lanes<S: Simd>(&self, simd: S, at: (u32, u32, u32)) -> BinnedLanes<S> {
        let scene = &self.tracer.scene;
        self.bins.binned_lanes::<S, false>(simd, (self.view, &scene.centers, &scene.radii), at)
    }

    /// Pushes the pixels `mask` names of the group of [`lanes`] columns from `base` (a
    /// multiple of it) on row `j` with full primary rays, in lanes; the ones that see only
    /// background go straight to `sink`. Tags are columns.
    pub(crate) fn push_traced(
        &self,
        wavefront: &mut Wavefront,
        (base, j, mask): (u32, u32, u32),
        sink: &mut RowSink<impl Columns, impl Observe>,
    ) {
        dispatch!(crate::simd::level(), simd => simd.vectorize(
            #[inline(always)]
            || self.push_traced_in(simd, wavefront, (base, j, mask), sink),
        ));
    }

    /// [`BinnedView::push_traced`] with the lanes of `simd`.
    #[inline(always)]
    pub(crate) fn push_traced_in<S: Simd>(
        &self,
        simd: S,
        wavefront: &mut Wavefront,
        (base, j, mask): (u32, u32, u32),
        sink: &mut RowSink<impl Columns, impl Observe>,
    ) {
        let lanes = F::<S>::LEN;
        debug_assert!(
            (base as usize).is_multiple_of(lanes) && u64::from(mask) < 1 << lanes,
            "group {base}, mask {mask:b}"
        );
        if self.bins.is_empty_at((base, j), lanes) {
            let rgb = self.tracer.scene.background_rgb;
            for i in crate::bits::ones(&[u64::from(mask)]) {
                let i = (base + i) as usize;
                sink.background(i..i + 1, rgb);
            }
            return;
        }
        let hits = self.hits_lanes(simd, (base, j, mask));
        self.push_found_in(simd, wavefront, (base, mask), hits, sink);
    }

    /// Pushes the pixels `mask` names of the group of lanes from `base` of a row, whose
    /// first hits are `hits` (the bins' search: `t`, +∞ for none, sphere and ray direction
    /// per lane); the ones that see only background go to `sink`.
    #[inline(always)]
    pub(crate) fn push_found_in<S: Simd>(
        &self,
        simd: S,
        wavefront: &mut Wavefront,
        (base, mask): (u32, u32),
        hits: (F<S>, U<S>, [F<S>; 3]),
        sink: &mut RowSink<impl Columns, impl Observe>,
    ) {
        let view = self.view;
        let hit = hits.0.abs().simd_lt(F::<S>::splat(simd, f32::INFINITY)).to_bitmask() as u32;
        if mask == hit && u64::from(mask) == (1 << F::<S>::LEN) - 1 {
            // Every ray of the group hits: into the batch whole.
            wavefront.push_lanes(simd, view.origin, hits, base);
            return;
        }
        let (t, ids, d) = (hits.0.as_slice(), hits.1.as_slice(), crate::simd::each3(|a| hits.2[a].as_slice()));
        for l in crate::bits::ones(&[u64::from(mask)]) {
            let (i, k) = (base + l, l as usize);
            if hit & (1 << l) != 0 {
                let ray = Ray::new(view.origin, Vec3::new(d[0][k], d[1][k], d[2][k]));
                wavefront.push_hit(&ray, Hit { t: t[k], object: ids[k] }, i);
            } else {
                sink.background(i as usize..i as usize + 1, self.tracer.scene.background_rgb);
            }
        }
    }
}
