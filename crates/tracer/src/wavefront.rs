//! Batched Whitted shading: the recursion of `shade.rs` turned into a stream of queues
//! (pbrt-v4's wavefront integrator), so that each stage runs over many hits at once.
//!
//! A batch starts with the first hits of many primary rays (level 0). Each level is shaded
//! in three stages — the hit points and normals; the light at them (shadow rays, diffuse,
//! highlights); the mirror rays they cast — and the mirror rays that hit something become
//! the next level. A hit casts at most one mirror ray, so each sample's ray tree is a chain
//! (its shadow rays are leaves): once the deepest level is shaded, radiance is folded back
//! up the chain as `L = D + (S + kr · L_mirror)`, the very operations, in the very order, of
//! the recursive [`Tracer::trace_pixel`]. Every result is therefore bit-for-bit the
//! recursive one, which the tests check on every scene.
//!
//! The queues live in a [`Wavefront`] that each worker thread keeps from batch to batch, so
//! a warm renderer allocates nothing. A shaded batch leaves through the row's sink
//! (`sink.rs`), which hands it first, read-only ([`Levels`]), to whoever observes it:
//! temporal reuse marks its ray trees there. The wavefront owns no observer's state and
//! knows of none.

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use fearless_simd::{dispatch, prelude::*, Simd};
use glam::Vec3;

use crate::accel::screen::HeldRow;
use crate::accel::Origin;
use crate::camera::EyeView;
use crate::color::pack_rgb;
use crate::cue::SeedRow;
use crate::ray::{reflect, spawn_ray, Ray};
use crate::simd::{F, U};
use crate::stats::RayCounts;
use crate::surface::{Hit, Surface};
use crate::tracer::Tracer;

mod lanes;
mod level;

use level::{get3, set3};

pub(crate) use level::Level;

pub(crate) use lanes::per_object;

/// The queues of one worker, reused from batch to batch.
#[derive(Clone, Debug, Default)]
pub(crate) struct Wavefront {
    /// `levels[k]`: the hits at reflection depth k; only the first `depth` are in use.
    levels: Vec<Level>,
    /// Levels in use.
    depth: usize,
    /// A sliced view's row of first hits, held between the bins and the BVH.
    pub(crate) held: HeldRow,
}

/// A shaded batch as an observer reads it (`sink.rs`): its levels, read-only, each padded
/// to whole vectors of lanes (the entries past a level's end hold anything).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Levels<'a> {
    levels: &'a [Level],
}

impl<'a> Levels<'a> {
    /// Reflection depths shaded.
    pub(crate) fn depth(&self) -> usize {
        self.levels.len()
    }

    /// The hits at reflection depth `k`: level 0 holds the samples, in batch order.
    pub(crate) fn level(&self, k: usize) -> &'a Level {
        &self.levels[k]
    }

    /// Samples in the batch.
    pub(crate) fn len(&self) -> usize {
        self.levels.first().map_or(0, Level::len)
    }

    /// Sample `e`'s tag.
    pub(crate) fn tag(&self, e: usize) -> u32 {
        self.levels[0].parent()[e]
    }
}

impl Wavefront {
    /// Empties the batch.
    pub(crate) fn clear(&mut self) {
        if self.levels.is_empty() {
            self.levels.push(Level::default());
        }
        self.levels[0].clear();
        self.depth = 1;
    }

    /// Samples in the batch.
    pub(crate) fn len(&self) -> usize {
        self.levels.first().map_or(0, Level::len)
    }

    /// Adds a sample whose primary ray `ray` first meets `hit`, its light bits to be found by
    /// shadow rays; `tag` is the caller's (a pixel column, say).
    #[inline]
    pub(crate) fn push_hit(&mut self, ray: &Ray, hit: Hit, tag: u32) {
        self.levels[0].push(ray.origin, ray.dir, hit.t, hit.object, tag);
    }

    /// Adds a whole vector of samples whose primary rays from `origin` along `d` all meet a
    /// sphere (at `t`, sphere `objects`): those of the pixels `column + l` of a row, lane by
    /// lane, tagged with their columns; what [`Wavefront::push_hit`] would add for each, in
    /// vector stores.
    #[inline(always)]
    pub(crate) fn push_lanes<S: Simd>(
        &mut self,
        simd: S,
        origin: Vec3,
        (t, objects, d): (F<S>, U<S>, [F<S>; 3]),
        column: u32,
    ) {
        let level = &mut self.levels[0];
        let (e, lanes) = (level.used, F::<S>::LEN);
        level.reserve(e + lanes);
        let entries = e..e + lanes;
        crate::simd::store3::<S>(d, &mut level.d, e);
        crate::simd::store3::<S>(d, &mut level.v, e);
        crate::simd::store3::<S>(crate::simd::splat3(simd, origin), &mut level.o, e);
        t.store_slice(&mut level.t[entries.clone()]);
        objects.store_slice(&mut level.object[entries.clone()]);
        (U::<S>::splat(simd, column) + crate::simd::lane_index(simd)).store_slice(&mut level.parent[entries.clone()]);
        level.lights[entries.clone()].fill(0);
        level.known[entries.clone()].fill(false);
        level.reflects[entries].fill(false);
        level.used = e + lanes;
    }

    /// Adds a sample of pixel `column` of a row of this view: what the ray of pixel `source`
    /// (column, row) of another view saw meet `hit`, with light bits `known`, to be shaded
    /// as seen along this pixel's ray. The point, normal and view-independent light come out
    /// as the other view's, bit for bit, and the highlights and mirror ray are this view's.
    /// Both rays are made later, all at once, by [`Wavefront::aim_seen`].
    pub(crate) fn push_seen_at(&mut self, column: u32, source: (u32, u32), hit: Hit, known: u32) {
        let level = &mut self.levels[0];
        let e = level.used;
        level.reserve(e + 1);
        level.t[e] = hit.t;
        level.object[e] = hit.object;
        level.parent[e] = column;
        level.lights[e] = known;
        level.known[e] = true;
        level.reflects[e] = false;
        (level.source[0][e], level.source[1][e]) = source;
        level.used = e + 1;
    }

    /// Makes the rays of the samples [`Wavefront::push_seen_at`] added, in lanes: each one's
    /// ray from `other` (the view whose pixel found it), and the direction it is seen along
    /// from row `j` of `view`. Bit-for-bit the rays of [`EyeView::primary_ray`].
    pub(crate) fn aim_seen(&mut self, view: &EyeView, j: u32, other: &EyeView) {
        dispatch!(crate::simd::level(), simd => simd.vectorize(
            #[inline(always)]
            || self.aim_seen_in(simd, view, j, other),
        ));
    }

    #[inline(always)]
    fn aim_seen_in<S: Simd>(&mut self, simd: S, view: &EyeView, j: u32, other: &EyeView) {
        let level = &mut self.levels[0];
        let (n, lanes) = (level.len(), F::<S>::LEN);
        // Whole vectors: the lanes past the last sample aim at pixel (0, 0) and are ignored.
        let padded = n.div_ceil(lanes) * lanes;
        level.reserve(padded);
        level.parent[n..padded].fill(0);
        for c in &mut level.source {
            c[n..padded].fill(0);
        }
        let origin = crate::simd::splat3(simd, other.origin);
        for k in (0..n).step_by(lanes) {
            let at = |c: &[u32]| F::<S>::float_from(U::<S>::from_slice(simd, &c[k..k + lanes]));
            let own = view.primary_dirs_at(simd, at(&level.parent), j);
            let seen = other.primary_dirs_rows(simd, at(&level.source[0]), at(&level.source[1]));
            crate::simd::store3::<S>(own, &mut level.v, k);
            crate::simd::store3::<S>(seen, &mut level.d, k);
            crate::simd::store3::<S>(origin, &mut level.o, k);
        }
    }

    /// Shades every sample of the batch, counting the shadow and mirror rays cast. `row` is
    /// the row of the traced view the samples' pixels lie on (their tags are columns): a
    /// sample's occlusion rays are seeded by its pixel (a re-shaded sample's: its source's,
    /// and `row`'s band is then the source view's).
    pub(crate) fn shade(&mut self, tracer: &Tracer, row: SeedRow, counts: &mut RayCounts) {
        dispatch!(crate::simd::level(), simd => self.shade_in(simd, tracer, row, counts));
    }

    /// [`Wavefront::shade`] with the lanes of `simd`: each stage runs over whole vectors (in
    /// a function of its own with `simd`'s target features), then the scalar stage takes the
    /// entries left over.
    pub(crate) fn shade_in<S: Simd>(&mut self, simd: S, tracer: &Tracer, row: SeedRow, counts: &mut RayCounts) {
        let max_depth = tracer.scene.settings.max_depth as usize;
        self.depth = 0;
        for k in 0.. {
            if self.levels.len() < k + 2 {
                self.levels.push(Level::default());
            }
            self.levels[k + 1].clear();
            let (upper, lower) = self.levels.split_at_mut(k + 1);
            let (level, next) = (&mut upper[k], &mut lower[0]);
            if level.len() == 0 {
                break;
            }
            self.depth = k + 1;
            next.reserve(level.len());
            let first = (k == 0).then_some(row);
            let done = simd.vectorize(
                #[inline(always)]
                || lanes::shade(simd, tracer, level, first, counts),
            );
            surfaces(tracer, level, done);
            light(tracer, level, first, counts, done);
            highlights(tracer, level, done);
            if k < max_depth {
                let done = simd.vectorize(
                    #[inline(always)]
                    || lanes::mirrors(simd, tracer, level, next, counts),
                );
                mirrors(tracer, level, next, counts, done);
            }
        }
        // Radiance folds up each sample's chain, deepest level first.
        for k in (0..self.depth).rev() {
            let (upper, lower) = self.levels.split_at_mut(k);
            let level = &mut lower[0];
            let done = simd.vectorize(
                #[inline(always)]
                || lanes::radiance(simd, tracer, level),
            );
            radiance(tracer, level, done);
            if let Some(above) = upper.last_mut() {
                for e in 0..level.len() {
                    set3(&mut above.mirror, level.parent[e] as usize, get3(&level.radiance, e));
                }
            }
        }
        if tracer.scene.settings.cues.depth_cue.mode != crate::cue::DepthCueMode::Off {
            let level = &mut self.levels[0];
            for e in 0..level.len() {
                let cued = tracer.depth_cued(get3(&level.radiance, e), level.t[e]);
                set3(&mut level.radiance, e, cued);
            }
        }
    }

    /// The batch as shaded, for observers to read ([`Levels`]).
    pub(crate) fn levels(&self) -> Levels<'_> {
        Levels { levels: &self.levels[..self.depth] }
    }

    /// Sample `e`'s tag.
    #[inline]
    pub(crate) fn tag(&self, e: usize) -> u32 {
        self.levels[0].parent[e]
    }

    /// Sample `e`'s packed sRGB colour, once shaded.
    // Always inlined: called per pixel as a batch leaves through its sink (`sink.rs`), where
    // a call cost ~2 % of an eye.
    #[inline(always)]
    pub(crate) fn rgb(&self, e: usize) -> u32 {
        pack_rgb(get3(&self.levels[0].radiance, e))
    }

    /// Sample `e`'s linear radiance, once shaded.
    #[cfg(test)]
    pub(crate) fn radiance(&self, e: usize) -> Vec3 {
        get3(&self.levels[0].radiance, e)
    }

    /// Sample `e`'s hit point, hit parameter, object and light bits (its record's keys).
    // Always inlined: called per pixel as a batch leaves through a keyed sink (`sink.rs`),
    // where a call cost ~5 % of a keyed eye.
    #[inline(always)]
    pub(crate) fn keys(&self, e: usize) -> (Vec3, f32, u32, u32) {
        let level = &self.levels[0];
        (get3(&level.p, e), level.t[e], level.object[e], level.lights[e])
    }

    /// Sample `e`'s visible-surface record, once shaded.
    #[inline]
    pub(crate) fn surface(&self, e: usize) -> Surface {
        let level = &self.levels[0];
        Surface {
            point: get3(&level.p, e),
            normal: get3(&level.n, e),
            diffuse: get3(&level.diffuse, e),
            object: level.object[e],
            lights: level.lights[e],
        }
    }
}

/// Stage 1: hit points and normals, of the entries from `from` on (the scalar stages below
/// are the lanes' reference and take what is left over from whole vectors).
fn surfaces(tracer: &Tracer, level: &mut Level, from: usize) {
    for e in from..level.len() {
        let p = get3(&level.o, e) + level.t[e] * get3(&level.d, e);
        // Normalised rather than divided by r: the hit lies on the sphere only to rounding.
        let n = (p - tracer.scene.centers[level.object[e] as usize]).normalize();
        set3(&mut level.p, e, p);
        set3(&mut level.n, e, n);
    }
}

/// Stage 2: the light bits (from shadow rays, or known at level 0) and the view-independent
/// light, its ambient term occluded at level 0 (`first`: the row of its pixels).
fn light(tracer: &Tracer, level: &mut Level, first: Option<SeedRow>, counts: &mut RayCounts, from: usize) {
    for e in from..level.len() {
        let known = first.is_some() && level.known[e];
        let (p, n, object) = (get3(&level.p, e), get3(&level.n, e), level.object[e]);
        let ambient = match first {
            Some(seeds) => tracer.ambient_at(object, (p, n), seeds.shown(level.pixel(e, seeds.row)), counts),
            None => tracer.scene.settings.ambient,
        };
        let given = level.lights[e];
        let (diffuse, bits) = tracer.diffuse_light((object, p, n), ambient, |k, l, dist| {
            if known {
                given & (1 << k) != 0
            } else {
                counts.shadow += 1;
                !tracer.shadowed(k, object, p, n, &spawn_ray(p, n, l), dist)
            }
        });
        level.lights[e] = bits;
        set3(&mut level.diffuse, e, diffuse);
    }
}

/// Stage 3: Blinn–Phong highlights from the lights the bits name, seen along the ray.
fn highlights(tracer: &Tracer, level: &mut Level, from: usize) {
    for e in from..level.len() {
        let (p, n, d) = (get3(&level.p, e), get3(&level.n, e), get3(&level.v, e));
        let spec = tracer.highlight(level.object[e], p, n, d, level.lights[e]);
        set3(&mut level.spec, e, spec);
    }
}

/// Stage 4: the mirror rays of reflective hits; those that meet a sphere join `next`.
fn mirrors(tracer: &Tracer, level: &mut Level, next: &mut Level, counts: &mut RayCounts, from: usize) {
    for e in from..level.len() {
        let object = level.object[e];
        if tracer.scene.material(object as usize).reflectivity <= 0.0 {
            continue;
        }
        counts.reflection += 1;
        level.reflects[e] = true;
        set3(&mut level.mirror, e, tracer.scene.settings.background);
        let (p, n, d) = (get3(&level.p, e), get3(&level.n, e), get3(&level.v, e));
        // d and n are unit, so r is too, to rounding: no normalisation needed.
        let ray = spawn_ray(p, n, reflect(d, n));
        if let Some(hit) = tracer.accel.intersect(&ray, f32::INFINITY, Origin::Surface { sphere: object, normal: n }) {
            next.push(ray.origin, ray.dir, hit.t, hit.object, e as u32);
        }
    }
}

thread_local! {
    /// This thread's queues.
    static WAVEFRONT: std::cell::RefCell<Wavefront> = std::cell::RefCell::new(Wavefront::default());
}

/// Runs `f` with this thread's [`Wavefront`], emptied. A nested call (from inside `f`) gets
/// a fresh one of its own rather than failing.
pub(crate) fn with_wavefront<R>(f: impl FnOnce(&mut Wavefront) -> R) -> R {
    WAVEFRONT.with(|cell| {
        if let Ok(mut wavefront) = cell.try_borrow_mut() {
            wavefront.clear();
            f(&mut wavefront)
        } else {
            let mut wavefront = Wavefront::default();
            wavefront.clear();
            f(&mut wavefront)
        }
    })
}

/// The fold: entry radiance `D + (S + kr·L_mirror)`, or `D + S` where no mirror ray was cast.
fn radiance(tracer: &Tracer, level: &mut Level, from: usize) {
    for e in from..level.len() {
        let (d, s) = (get3(&level.diffuse, e), get3(&level.spec, e));
        let radiance = if level.reflects[e] {
            let kr = tracer.scene.material(level.object[e] as usize).reflectivity;
            d + (s + kr * get3(&level.mirror, e))
        } else {
            d + s
        };
        set3(&mut level.radiance, e, radiance);
    }
}
