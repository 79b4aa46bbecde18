//! Screen-space bins for one eye's primary rays: which spheres each tile of pixels can see.
//!
//! Every primary ray of an eye starts at the eye, so before tracing we can bound where each
//! sphere can appear on screen, as a rasteriser would, and give each 8 × 8 tile of pixels
//! the short list of spheres whose bound covers it (the "tile binning" of sort-middle
//! rasterisers, used here to cull a ray tracer's first hits). A pixel whose tile lists no
//! sphere is background without a single sphere test; the others test just their tile's
//! spheres, a vector of pixels at a time: the rays share the eye as origin, so each sphere's
//! origin terms are computed once per frame (in a sliced view, kept in the tiles' lists
//! beside its id, `screen/tile_sphere.rs`, so that a tile's spheres are read in a row, not
//! gathered from a scene too large for the caches), and the rays fill the SIMD lanes.
//! Secondary rays, which start anywhere, go through the BVH.
//!
//! Where each sphere can appear on screen, and why that bound never misses a hit the tests
//! would report, is `screen/bound.rs`.
//!
//! **Bins or the BVH.** Binning costs every sphere's bound, every frame, whatever the
//! pixels: on a 2.9M-atom capsid ~0.5 s an eye even at 50 × 38. A BVH query per ray
//! costs the rays. Between the two, a view of up to [`SLICED_SPHERES_PER_RAY`] spheres a
//! pixel bins only the nearest, by their distance from the eye, until they cover the screen
//! about twice (`screen/cut.rs`, cut at a histogram's bin edge): a hit nearer than the cut
//! is the first hit, since no other sphere begins before it, and only the other rays go
//! through the BVH, held back for the row and sent sixteen at a time (`screen/held.rs`).
//! Beyond that (or above [`SLICED_MAX_SPHERES`]), a view is not binned at all: each
//! primary ray goes through the aggregate's BVH instead ([`Aggregate::first_hits_in`], a
//! lane vector of rays a packet), which breaks ties as the bins do (of equal `t`, the lowest
//! sphere id), so the pixels are the same bit for bit (`render/both_ways.rs` tests it). The
//! ratio is where the measured crossover lies (`docs/performance-notes.md`, benchmark
//! `first_hits`): the bundled scenes stay on the bins at every size down to 50 × 38, a
//! structure goes to the sliced bins or the BVH at small sizes, the capsid to the BVH at
//! every size.

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use fearless_simd::{prelude::*, Simd};
use glam::Vec3;
use rayon::prelude::*;

mod bound;
mod cut;
mod held;
mod tile_sphere;

pub(crate) use bound::pixel_rect;
use bound::{tile_rect, NO_RECT};
pub(crate) use held::HeldRow;
use tile_sphere::{test_sphere, TileSphere};

use super::{Aggregate, EyeRays, Nearest, EYE_PACKET};
use crate::camera::EyeView;
use crate::simd::{F, U};
use crate::surface::NO_OBJECT;

/// A group of lanes' first hits: per lane the hit parameter (+∞ for none), the sphere
/// ([`NO_OBJECT`] for none) and the primary ray's direction.
pub(crate) type LaneHits<S> = (F<S>, U<S>, [F<S>; 3]);

/// [`ScreenBins::binned_lanes`]'s answer: the hits the bins find, and the lanes (bits) that
/// go on through the BVH.
pub(crate) type BinnedLanes<S> = (LaneHits<S>, u32);

/// Tile edge in pixels.
pub(crate) const TILE: u32 = 8;

/// How an eye's primary rays find their first hits.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum Search {
    /// Through the screen bins: each tile's spheres tested in lanes.
    #[default]
    Bins,
    /// Through screen bins of the nearest spheres alone ([`ScreenBins::build`]), and for
    /// the rays that meet none of them nearer than the rest can be, the BVH.
    Sliced,
    /// Through the aggregate's BVH, a lane vector of rays a packet
    /// ([`Aggregate::first_hits_in`]).
    Bvh,
}

impl Search {
    /// The cheaper search for `spheres` spheres and `rays` primary rays (see the module
    /// doc): the bins up to [`BINS_SPHERES_PER_RAY`] spheres a ray, the sliced bins up to
    /// [`SLICED_SPHERES_PER_RAY`] (and [`SLICED_MAX_SPHERES`]), the BVH beyond.
    #[must_use]
    pub(crate) fn cheaper(spheres: usize, rays: u64) -> Self {
        let per_ray = spheres as f64 / rays.max(1) as f64;
        if per_ray <= BINS_SPHERES_PER_RAY {
            Self::Bins
        } else if per_ray <= SLICED_SPHERES_PER_RAY && spheres <= SLICED_MAX_SPHERES {
            Self::Sliced
        } else {
            Self::Bvh
        }
    }
}

/// Spheres per primary ray up to which the nearest spheres are binned and the other rays go
/// through the BVH ([`Search::Sliced`]).
pub(crate) const SLICED_SPHERES_PER_RAY: f64 = 2.0;

/// Most spheres a view slices: its bins keep a rectangle of 8 bytes for every sphere.
pub(crate) const SLICED_MAX_SPHERES: usize = 1 << 21;

/// Spheres per primary ray above which the BVH finds an eye's first hits faster than
/// binning every sphere for the frame would (measured: `docs/performance-notes.md`).
pub(crate) const BINS_SPHERES_PER_RAY: f64 = 0.6;

/// Screen tiles of one eye's view, each with the packets of spheres its pixels can hit; or,
/// when the view is searched through the BVH, no tiles at all.
///
/// Built by [`ScreenBins::build`] into buffers reused from frame to frame; traced through
/// by [`BinnedView`].
#[derive(Clone, Debug, Default)]
pub(crate) struct ScreenBins {
    /// How this view's first hits are found; with [`Search::Bvh`] the tiles are not built.
    search: Search,
    tiles_x: u32,
    /// Tile t's spheres are `spheres[first[t]..first[t + 1]]`, ids in id order; in a sliced
    /// view, `terms[first[t]..first[t + 1]]` instead.
    first: Vec<u32>,
    spheres: Vec<u32>,
    terms: Vec<TileSphere>,
    /// Per sphere: its inclusive tile rectangle `[x0, y0, x1, y1]`, or [`NO_RECT`] when it
    /// is behind the eye or off screen. (Tiles of 8 pixels: 16 bits hold any image side.)
    rects: Vec<[u16; 4]>,
    /// Scratch: spheres placed so far in each tile.
    fill: Vec<u32>,
    /// Scratch of a sliced view: how near the eye each sphere begins (`cut::nearest`).
    near: Vec<f32>,
    /// With [`Search::Sliced`], the distance from the eye beyond which no binned sphere
    /// begins (+∞ when every sphere is binned): a hit nearer than it (with a margin) is the
    /// first, any other ray goes through the BVH.
    cut: f32,
}

/// A hit nearer than this share of the cut is nearer than any unbinned sphere can be hit,
/// whatever the rounding of either.
const CUT_MARGIN: f32 = 1.0 - 1e-4;

impl ScreenBins {
    /// Heap bytes held (capacities).
    pub(crate) fn heap_bytes(&self) -> usize {
        use crate::stats::heap;
        heap(&self.first)
            + heap(&self.spheres)
            + heap(&self.terms)
            + heap(&self.rects)
            + heap(&self.fill)
            + heap(&self.near)
    }
    /// Bins the spheres `(centers[k], radii[k])` for the primary rays of `view`, reusing the
    /// buffers; or, for [`Search::Bvh`], leaves the bins empty (their buffers kept) and
    /// sends every primary ray through the BVH.
    pub(crate) fn build(&mut self, (centers, radii): (&[Vec3], &[f32]), view: &EyeView, search: Search) {
        self.search = search;
        self.cut = f32::INFINITY;
        if search == Search::Bvh {
            return;
        }
        self.tiles_x = view.width.div_ceil(TILE);
        let tiles_y = view.height.div_ceil(TILE);
        let tiles = (self.tiles_x * tiles_y) as usize;
        if search == Search::Sliced {
            self.cut = cut::sliced_cut((centers, radii), view, &mut self.near);
        }
        let cut = self.cut;
        self.rects.clear();
        self.rects.resize(centers.len(), NO_RECT);
        let near = &self.near;
        let spheres = centers.par_iter().zip(radii).enumerate();
        self.rects.par_iter_mut().zip(spheres).for_each(|(rect, (k, (&c, &r)))| {
            if cut == f32::INFINITY || near[k] < cut {
                *rect = tile_rect(view, c, r);
            }
        });
        // Counting sort of the spheres into tiles.
        self.fill.clear();
        self.fill.resize(tiles, 0);
        for &[x0, y0, x1, y1] in self.rects.iter().filter(|&&r| r != NO_RECT) {
            for ty in u32::from(y0)..=u32::from(y1) {
                let row = (ty * self.tiles_x) as usize;
                for n in &mut self.fill[row + x0 as usize..=row + x1 as usize] {
                    *n += 1;
                }
            }
        }
        self.first.clear();
        self.first.reserve(tiles + 1);
        let mut total = 0u32;
        for &n in &self.fill {
            self.first.push(total);
            total += n;
        }
        self.first.push(total);
        self.fill.fill(0);
        let (lists, o) = ((&self.rects[..], &self.first[..], self.tiles_x), view.origin);
        if cut == f32::INFINITY {
            place(lists, &mut self.fill, |k| k as u32, &mut self.spheres);
        } else {
            place(lists, &mut self.fill, |k| TileSphere::new(k as u32, o, centers[k], radii[k]), &mut self.terms);
        }
    }

    /// The spheres of the tile holding pixel (i, j), of a view binned in full.
    #[inline]
    pub(crate) fn spheres_at(&self, i: u32, j: u32) -> &[u32] {
        &self.spheres[self.tile_span(i, j)]
    }

    /// The spheres of the tile holding pixel (i, j), of a sliced view.
    #[inline]
    fn terms_at(&self, i: u32, j: u32) -> &[TileSphere] {
        &self.terms[self.tile_span(i, j)]
    }

    /// Where the list of the tile holding pixel (i, j) lies.
    #[inline]
    fn tile_span(&self, i: u32, j: u32) -> std::ops::Range<usize> {
        let t = ((j / TILE) * self.tiles_x + i / TILE) as usize;
        self.first[t] as usize..self.first[t + 1] as usize
    }

    /// How this view's first hits are found.
    #[inline]
    #[must_use]
    pub(crate) fn search(&self) -> Search {
        self.search
    }

    /// Whether the tiles of pixels (i..i + n, j) list no sphere: their primary rays see only
    /// background. (Never, when the view is searched through the BVH.)
    #[inline]
    #[must_use]
    pub(crate) fn is_empty_at(&self, (i, j): (u32, u32), n: usize) -> bool {
        self.search != Search::Bvh && self.bin_is_empty_at((i, j), n)
    }

    /// [`ScreenBins::is_empty_at`] for bins built ([`Search::Bins`]).
    #[inline]
    #[must_use]
    pub(crate) fn bin_is_empty_at(&self, (i, j): (u32, u32), n: usize) -> bool {
        debug_assert_ne!(self.search, Search::Bvh, "bins built");
        let last = (i + n as u32 - 1).min(self.tiles_x * TILE - 1);
        self.cut == f32::INFINITY && (i..=last).step_by(TILE as usize).all(|i| self.spheres_at(i, j).is_empty())
    }

    /// The first hits of the primary rays of `view` (for which the bins were built) through
    /// pixels (i + l, j), l = 0..LEN, which lie in one tile, or from the start of a tile
    /// over whole tiles (and in the image, where lanes are wanted): per lane the hit
    /// parameter (+∞ for none), the sphere, and the ray's direction: [`EyeView::primary_ray`]'s
    /// rays and the BVH's hits, bit for bit (each sphere's `t` is the same kernel on the same
    /// values; a test compares the two). The
    /// closest hit wins, of equal `t` the lowest sphere id (the bins list their spheres in
    /// id order, and keep the first of equal `t`). Through the BVH ([`Search::Bvh`]) only
    /// the lanes `mask` names are traced, the others left as misses; the bins fill them all.
    /// `BVH` must say whether the view is searched through the BVH ([`ScreenBins::search`]):
    /// a constant, so that the bins' lane loop, inlined into its callers, carries no trace
    /// of the other way.
    #[inline(always)]
    pub(crate) fn hits_lanes<S: Simd, const BVH: bool>(
        &self,
        simd: S,
        scene: (&EyeView, &[Vec3], &[f32]),
        accel: &Aggregate,
        at: (u32, u32, u32),
    ) -> (F<S>, U<S>, [F<S>; 3]) {
        let ((t, ids, d), open) = self.binned_lanes::<S, BVH>(simd, scene, at);
        if open == 0 {
            return (t, ids, d);
        }
        let beyond = if BVH { 0.0 } else { self.beyond() };
        let (t, ids) = through_bvh(simd, accel, (scene.0.origin, &d, beyond), open, (t, ids));
        (t, ids, d)
    }

    /// [`ScreenBins::hits_lanes`] before the BVH: the hits the bins find (none through the
    /// BVH's bins), and the lanes that must go on through the BVH from
    /// [`ScreenBins::beyond`] (every lane `mask` names, through the BVH's bins; none,
    /// through the bins).
    #[inline(always)]
    pub(crate) fn binned_lanes<S: Simd, const BVH: bool>(
        &self,
        simd: S,
        (view, centers, radii): (&EyeView, &[Vec3], &[f32]),
        (i, j, mask): (u32, u32, u32),
    ) -> BinnedLanes<S> {
        debug_assert_eq!(BVH, self.search == Search::Bvh, "the search the bins were built for");
        let d = view.primary_dirs_lanes(simd, i, j);
        let every = ((1u64 << F::<S>::LEN) - 1) as u32;
        if BVH {
            let none = (F::<S>::splat(simd, f32::INFINITY), U::<S>::splat(simd, NO_OBJECT));
            return ((none.0, none.1, d), mask & every);
        }
        let mut t_best = F::<S>::splat(simd, f32::INFINITY);
        let mut best = U::<S>::splat(simd, NO_OBJECT);
        // The lanes' pixels lie in one tile, but sixteen lanes span two: each tile's spheres
        // then answer for its own lanes alone (the others' bound is 0, which no root is
        // below), and the lanes are merged.
        let n = F::<S>::LEN;
        let tiles = n.div_ceil(TILE as usize);
        for tile in 0..tiles {
            let (first, column) = (tile * TILE as usize, i + tile as u32 * TILE);
            if column / TILE >= self.tiles_x {
                break; // lanes past the row's end
            }
            let ours = if tiles == 1 {
                None
            } else {
                let lanes = crate::simd::lane_index(simd);
                let from = |l: usize| U::<S>::splat(simd, l as u32);
                Some(lanes.simd_ge(from(first)) & lanes.simd_lt(from(first + TILE as usize)))
            };
            let mut t_tile = ours.map_or(t_best, |ours| ours.select(t_best, F::<S>::splat(simd, 0.0)));
            let mut best_tile = best;
            if self.is_sliced() {
                for &sphere in self.terms_at(column, j) {
                    test_sphere(simd, sphere, d, (&mut t_tile, &mut best_tile));
                }
            } else {
                // The sphere's terms seen from the eye, once for the lanes.
                for &k in self.spheres_at(column, j) {
                    let sphere = TileSphere::new(k, view.origin, centers[k as usize], radii[k as usize]);
                    test_sphere(simd, sphere, d, (&mut t_tile, &mut best_tile));
                }
            }
            (t_best, best) = match ours {
                None => (t_tile, best_tile),
                Some(ours) => (ours.select(t_tile, t_best), ours.select(best_tile, best)),
            };
        }
        // Sliced: the lanes whose hit is not surely nearer than every unbinned sphere search
        // again, through the BVH, from the binned hit they have (a real sphere's: the nearer
        // of the two, of equal `t` the lower id, is the whole search's).
        let open = if self.is_sliced() {
            t_best.simd_ge(F::<S>::splat(simd, self.cut * CUT_MARGIN)).to_bitmask() as u32 & mask & every
        } else {
            0
        };
        ((t_best, best, d), open)
    }

    /// How near the eye a sliced view's open rays ([`ScreenBins::binned_lanes`]) begin their
    /// search: just short of the cut, since no sphere such a ray can hit begins before it
    /// (it would be binned, and its hit nearer than the cut).
    #[inline]
    pub(crate) fn beyond(&self) -> f32 {
        self.cut * CUT_MARGIN * CUT_MARGIN
    }

    /// Whether this view bins only its nearest spheres ([`Search::Sliced`] with a finite
    /// cut), so that some rays go on through the BVH.
    #[inline]
    pub(crate) fn is_sliced(&self) -> bool {
        self.cut < f32::INFINITY
    }
}

/// The counting sort's second pass: each sphere with a rectangle of `rects` placed in every
/// tile it covers, as `entry(k)`, in id order within a tile (`first` from the first pass,
/// `fill` zeroed), into `out`.
fn place<T: Copy + Default>(
    (rects, first, tiles_x): (&[[u16; 4]], &[u32], u32),
    fill: &mut [u32],
    entry: impl Fn(usize) -> T,
    out: &mut Vec<T>,
) {
    out.clear();
    out.resize(first.last().map_or(0, |&n| n as usize), T::default());
    for (k, &[x0, y0, x1, y1]) in rects.iter().enumerate().filter(|&(_, &r)| r != NO_RECT) {
        let e = entry(k);
        for ty in u32::from(y0)..=u32::from(y1) {
            for tx in u32::from(x0)..=u32::from(x1) {
                let t = (ty * tiles_x + tx) as usize;
                out[(first[t] + fill[t]) as usize] = e;
                fill[t] += 1;
            }
        }
    }
}

/// The lanes' first hits, those `open` names searched through the BVH ([`bvh_hits`]) from
/// the hits `(t, ids)` they hold and no nearer than `beyond` ([`EyeRays::beyond`]), the
/// others left as they are.
#[inline(always)]
fn through_bvh<S: Simd>(
    simd: S,
    accel: &Aggregate,
    (o, d, beyond): (Vec3, &[F<S>; 3], f32),
    open: u32,
    (t, ids): (F<S>, U<S>),
) -> (F<S>, U<S>) {
    let n = F::<S>::LEN;
    let mut dirs = [[0f32; EYE_PACKET]; 3];
    for (a, lanes) in dirs.iter_mut().enumerate() {
        d[a].store_slice(&mut lanes[..n]);
    }
    let mut nearest: Nearest = ([0f32; EYE_PACKET], [0u32; EYE_PACKET]);
    t.store_slice(&mut nearest.0[..n]);
    ids.store_slice(&mut nearest.1[..n]);
    bvh_hits(accel, EyeRays { origin: o, dirs: &dirs, beyond }, open, &mut nearest);
    (F::<S>::from_slice(simd, &nearest.0[..n]), U::<S>::from_slice(simd, &nearest.1[..n]))
}

/// The first hits of the rays of `at` that `mask` names, through the BVH in one packet,
/// each the nearer of that and the hit `nearest` holds for it (+∞ and [`NO_OBJECT`] for
/// none): out of line, so that the bins' lane loop, into which [`ScreenBins::hits_lanes`]
/// is inlined, does not carry a BVH traversal in its code.
#[inline(never)]
fn bvh_hits(accel: &Aggregate, at: EyeRays<'_>, mask: u32, nearest: &mut Nearest) {
    #[expect(clippy::cast_possible_truncation, reason = "at most sixteen lanes")]
    let rays = mask as u16;
    fearless_simd::dispatch!(crate::simd::level(), simd => simd.vectorize(
        #[inline(always)]
        || accel.first_hits_in(simd, at, rays, nearest),
    ));
}

#[cfg(test)]
mod tests {
    use super::bound::{screen_bound, Bound};
    use super::*;
    use crate::camera::{Camera, Eye};
    use crate::scene::Scene;
    use crate::surface::Hit;
    use crate::testing::scene;
    use crate::tracer::Tracer;

    /// Every pixel's first hit through the bins is the BVH's, a vector of lanes at a time
    /// (the last group short where the row ends), and the rays are the view's.
    fn assert_same_as_bvh(scene: &Scene, camera: &Camera, t: f32, w: u32, h: u32) {
        assert_same_with_margin(scene, camera, t, (w, h), (0, 0));
    }

    /// [`assert_same_as_bvh`] for views with a guard band of `margin` (the view is the
    /// bigger by twice the margin).
    fn assert_same_with_margin(scene: &Scene, camera: &Camera, t: f32, (w, h): (u32, u32), margin: (u32, u32)) {
        let tracer = Tracer::new(scene, t);
        let lanes = crate::simd::lane_width() as u32;
        for eye in [Eye::Left, Eye::Right] {
            let view = camera.view_with_margin(eye, w, h, margin);
            let (w, h) = (view.width, view.height);
            let mut bins = ScreenBins::default();
            bins.build((&tracer.scene.centers, &tracer.scene.radii), &view, Search::Bins);
            let mut hits = 0;
            for j in 0..h {
                for i in (0..w).step_by(lanes as usize) {
                    let (t, ids, d) = fearless_simd::dispatch!(crate::simd::level(), simd => simd.vectorize(|| {
                        let scene = (&view, &tracer.scene.centers[..], &tracer.scene.radii[..]);
                        let (t, ids, d) = bins.hits_lanes::<_, false>(simd, scene, &tracer.accel, (i, j, u32::MAX));
                        let mut out = ([0f32; 16], [0u32; 16], [[0f32; 16]; 3]);
                        let n = t.as_slice().len();
                        out.0[..n].copy_from_slice(t.as_slice());
                        out.1[..n].copy_from_slice(ids.as_slice());
                        for (column, v) in out.2.iter_mut().zip(&d) {
                            column[..n].copy_from_slice(v.as_slice());
                        }
                        out
                    }));
                    for k in 0..(w - i).min(lanes) as usize {
                        let ray = view.primary_ray(i + k as u32, j);
                        let want = tracer.intersect(&ray, f32::INFINITY);
                        let got = t[k].is_finite().then(|| Hit { t: t[k], object: ids[k] });
                        let key = |h: Option<Hit>| h.map(|h| (h.t.to_bits(), h.object));
                        assert_eq!(key(got), key(want), "{eye:?} pixel ({i} + {k}, {j})");
                        let dir = Vec3::new(d[0][k], d[1][k], d[2][k]);
                        assert_eq!(dir, ray.dir, "{eye:?} pixel ({i} + {k}, {j}): the view's ray");
                        hits += usize::from(got.is_some());
                    }
                }
            }
            assert!(hits > 0 || scene.spheres.is_empty(), "{eye:?}: the view sees spheres");
        }
    }

    #[test]
    fn bins_trace_every_scene_like_the_bvh() {
        for name in ["seed.toml", "many.toml", "thousand.toml", "window.toml"] {
            let scene = scene(name);
            assert_same_as_bvh(&scene, &scene.camera, 1.3, 160, 90);
        }
    }

    #[test]
    fn bins_hold_for_a_guard_band() {
        for name in ["seed.toml", "many.toml"] {
            let scene = scene(name);
            let camera = Camera { yaw_deg: 8.0, ..scene.camera };
            assert_same_with_margin(&scene, &camera, 0.4, (96, 54), (13, 7));
        }
    }

    #[test]
    fn bins_hold_for_turned_heads_spheres_around_the_eye_and_odd_sizes() {
        let mut scene = scene("many.toml");
        let camera = Camera { yaw_deg: 35.0, pitch_deg: -20.0, position: Vec3::new(1.0, 0.5, 4.0), ..scene.camera };
        assert_same_as_bvh(&scene, &camera, 0.0, 67, 41);
        // A sphere around the eye and one straddling the eye's plane go in every tile.
        scene.spheres[0].motion = crate::scene::Motion::Static(camera.position);
        scene.spheres[1].motion = crate::scene::Motion::Static(camera.position + Vec3::new(3.0, 0.0, 0.2));
        assert_same_as_bvh(&scene, &camera, 0.0, 33, 17);
    }

    #[test]
    fn unpadded_bound_is_tight_around_every_hit_pixel() {
        // With no margin at all the bound is the exact tangent rectangle: every pixel whose
        // centre ray touches the sphere lies inside it, to rounding. (Shrinking the radius
        // by 1 % breaks this.)
        let scene = scene("many.toml");
        let tracer = Tracer::new(&scene, 0.0);
        let camera = Camera { yaw_deg: 10.0, pitch_deg: 5.0, ..scene.camera };
        let view = camera.view(Eye::Right, 320, 180);
        let mut checked = 0;
        for k in 0..tracer.sphere_count() as u32 {
            let Bound::Pixels([i0, j0, i1, j1]) =
                screen_bound(&view, tracer.scene.centers[k as usize], tracer.scene.radii[k as usize], 0.0)
            else {
                continue;
            };
            for j in 0..view.height {
                for i in 0..view.width {
                    if tracer.accel.intersect_one(&view.primary_ray(i, j), k).is_some() {
                        let (x, y) = (f64::from(i), f64::from(j));
                        assert!(
                            x >= i0 - 1e-3 && x <= i1 + 1e-3 && y >= j0 - 1e-3 && y <= j1 + 1e-3,
                            "sphere {k} at ({i}, {j}) outside [{i0}, {i1}] × [{j0}, {j1}]"
                        );
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked > 1000, "the scene's spheres cover pixels: {checked}");
    }

    #[test]
    fn bound_covers_the_projected_disc_and_little_more() {
        // A unit sphere 10 ahead, seen head-on by a mono eye: its silhouette has angular
        // radius asin(1/10), so on a 90° window (half-width d) it spans ±d·tan(asin 0.1).
        let camera = Camera { ipd: 0.0, distance: 1.0, fov_deg: 90.0, ..Camera::default() };
        let mut scene = scene("seed.toml");
        scene.spheres.truncate(1);
        scene.spheres[0].radius = 1.0;
        scene.spheres[0].motion = crate::scene::Motion::Static(Vec3::new(0.0, 0.0, 10.0));
        let tracer = Tracer::new(&scene, 0.0);
        let (w, h) = (800, 800);
        let view = camera.view(Eye::Left, w, h);
        let mut bins = ScreenBins::default();
        bins.build((&tracer.scene.centers, &tracer.scene.radii), &view, Search::Bins);
        let half = (0.1f64.asin().tan() * 400.0) as u32; // ≈ 40 pixels
        let [x0, y0, x1, y1] = bins.rects[0].map(u32::from);
        assert_ne!(bins.rects[0], NO_RECT, "visible");
        assert_eq!(screen_bound(&view, Vec3::new(0.0, 0.0, -10.0), 1.0, 0.0), Bound::Nowhere);
        assert_eq!(screen_bound(&view, Vec3::new(5.0, 0.0, 0.5), 1.0, 0.0), Bound::Everywhere);
        assert!(x0 * TILE <= 400 - half && (x1 + 1) * TILE >= 400 + half, "{x0}..{x1}");
        assert!(y0 * TILE <= 400 - half && (y1 + 1) * TILE >= 400 + half, "{y0}..{y1}");
        assert!((x1 - x0 + 1) * TILE <= 2 * half + 3 * TILE, "no more than a tile of slack per side");
        assert!(bins.is_empty_at((0, 0), 1) && !bins.is_empty_at((400, 400), 1));
    }
}
