//! The acceleration structures, and the one aggregate that answers every ray query through
//! them (pbrt-v4's `Aggregate` with `Intersect` and `IntersectP`; Embree's one call with an
//! arguments struct).
//!
//! [`Aggregate`] answers two queries: the closest hit ([`Aggregate::intersect`]) and any hit
//! ([`Aggregate::occluded`]), each in a scalar form (one ray) and a lane form (a vector of
//! rays, or one ray inside a lane kernel, inlined with its target features). The query's
//! [`Origin`] says where the ray starts, and that picks the structure inside:
//! - from anywhere (an eye, a test): the BVH (`bvh.rs`), 8-wide nodes and 8-sphere leaves;
//! - from the surface of sphere k (a mirror ray): the direction cones between spheres
//!   (`cones.rs`) in scenes of up to 64 spheres, else the BVH, leaving sphere k out when the
//!   ray leaves it outwards;
//! - towards light k (a shadow ray): the cell of the light's cube map (`lights.rs`) that the
//!   ray looked up, else the BVH;
//! - and in scenes of up to [`ALL_SPHERES_MAX`] spheres, a vector of rays meets every
//!   sphere in lanes (`flat.rs`), which beats looking each ray up.
//!
//! An eye's primary rays go through that eye's screen bins instead (`screen.rs`, built per
//! view by the renderer), unless the view has so many spheres for its pixels that binning
//! them would cost more than a BVH query per ray; then through the BVH, whose
//! [`Aggregate::first_hits_in`] breaks ties as the bins do. Every structure only chooses
//! which spheres to test; the test is the one ray–sphere kernel (`simd.rs`), so each answers
//! bit-for-bit what the BVH would, and the tests compare them on every scene.

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

mod bvh;
mod cones;
mod flat;
mod lights;
mod packet;
pub(crate) mod screen;

use fearless_simd::{dispatch, prelude::*, Simd};
use glam::Vec3;

use crate::ray::{leaves_outwards, Ray};
use crate::scene::Light;
use crate::simd::{lane3, F, U};
use crate::surface::{Hit, NO_OBJECT};

pub(crate) use bvh::{EyeRays, Nearest, Packet, EYE_PACKET, PACKET};
pub(crate) use flat::ALL_SPHERES_MAX;
pub(crate) use lights::Cell;

/// Every structure over one instant's spheres, rebuilt each frame into reused buffers.
#[derive(Clone, Debug, Default)]
pub(crate) struct Aggregate {
    bvh: bvh::Bvh,
    lights: lights::LightBins,
    cones: cones::Cones,
}

/// Where a query's ray starts. It picks the structure that answers, and the sphere the ray
/// is not tested against.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Origin {
    /// Anywhere: every sphere may be hit (the BVH).
    Anywhere,
    /// A point of sphere `sphere`'s surface, outward normal `normal` there, spawned by
    /// [`crate::spawn_ray`]: a ray leaving outwards cannot meet that sphere again and is
    /// not tested against it ([`skipped`]).
    Surface {
        /// The sphere the ray leaves.
        sphere: u32,
        /// Its outward normal where the ray leaves.
        normal: Vec3,
    },
    /// A surface point, towards a light: the cell of the light's cube map the ray looked
    /// up ([`Aggregate::towards_light`]) and the sphere it leaves out.
    Light(LightRay),
}

/// A shadow ray's lookup in its light's cube map, made apart from its test so that a batch
/// can look up all its cells before testing any (their cache misses overlap).
#[derive(Clone, Copy, Debug)]
pub(crate) struct LightRay {
    /// The cell, or `None` when the bins cannot answer (then the BVH does).
    cell: Option<Cell>,
    /// The sphere the ray is not tested against ([`skipped`]).
    skip: u32,
}

/// The sphere that a ray spawned (by [`crate::spawn_ray`]) from sphere `from`, with outward
/// normal `n` there, leaves out of its queries: `from` itself when the ray leaves outwards,
/// as a sphere is convex and the ray cannot meet it again; none ([`NO_OBJECT`]) when it goes
/// in. The one rule for every structure, so that the spawn offset never has to clear the
/// ray's own sphere outwards.
#[inline]
#[must_use]
pub(crate) fn skipped(from: u32, n: Vec3, dir: Vec3) -> u32 {
    if leaves_outwards(n, dir) {
        from
    } else {
        NO_OBJECT
    }
}

/// A vector of shadow rays towards one light: each lane leaves point `p` (outward normal
/// `n`) of sphere `objects[l]` along the unit direction `l`, for the distance `dist`.
pub(crate) struct ShadowLanes<'a, S: Simd> {
    /// The light.
    pub(crate) light: usize,
    /// The points the rays leave.
    pub(crate) p: [F<S>; 3],
    /// The outward normals there.
    pub(crate) n: [F<S>; 3],
    /// The unit directions to the light.
    pub(crate) l: [F<S>; 3],
    /// The distances to the light.
    pub(crate) dist: F<S>,
    /// The spheres the points lie on, per lane.
    pub(crate) objects: &'a [u32],
}

impl Aggregate {
    /// Rebuilds every structure for the spheres `(centers[k], radii[k])` and `lights`;
    /// `spawn_offset` bounds how far a spawned ray's origin lies off its surface point.
    pub(crate) fn build(&mut self, (centers, radii): (&[Vec3], &[f32]), lights: &[Light], spawn_offset: f32) {
        self.bvh.build(centers, radii);
        self.lights.build(centers, radii, lights, spawn_offset);
        self.cones.build(centers, radii, spawn_offset);
    }

    /// The closest hit of `ray` in `(0, t_max)`, for a ray from `origin`.
    #[must_use]
    pub(crate) fn intersect(&self, ray: &Ray, t_max: f32, origin: Origin) -> Option<Hit> {
        dispatch!(crate::simd::level(), simd => simd.vectorize(
            #[inline(always)]
            || self.intersect_in(simd, ray, t_max, origin),
        ))
    }

    /// [`Aggregate::intersect`] inside a lane kernel dispatched at `simd`'s level.
    #[inline(always)]
    #[must_use]
    pub(crate) fn intersect_in<S: Simd>(&self, simd: S, ray: &Ray, t_max: f32, origin: Origin) -> Option<Hit> {
        let skip = match origin {
            Origin::Anywhere => NO_OBJECT,
            Origin::Surface { sphere, normal } => {
                let skip = skipped(sphere, normal, ray.dir);
                if skip != NO_OBJECT && self.cones.is_built() {
                    return self.cones.intersect_from(simd, sphere, ray, t_max);
                }
                skip
            }
            Origin::Light(shadow) => shadow.skip,
        };
        self.bvh.intersect_in(simd, ray, t_max, skip)
    }

    /// The closest hits of a packet of rays from one origin (the bits of `rays`), each the
    /// nearer of the hit it holds in `nearest` and the BVH's, of equal `t` the lowest sphere
    /// id: an eye's primary rays through the BVH, bit for bit the screen bins' answers
    /// (`screen.rs`), inside a lane kernel.
    #[inline(always)]
    pub(crate) fn first_hits_in<S: Simd>(&self, simd: S, at: EyeRays<'_>, rays: u16, nearest: &mut Nearest) {
        self.bvh.first_hits_in(simd, at, rays, nearest);
    }

    /// Whether anything blocks `ray` before `t_max` (any hit, early exit), for a ray from
    /// `origin`.
    #[must_use]
    pub(crate) fn occluded(&self, ray: &Ray, t_max: f32, origin: Origin) -> bool {
        dispatch!(crate::simd::level(), simd => simd.vectorize(
            #[inline(always)]
            || self.occluded_in(simd, ray, t_max, origin),
        ))
    }

    /// [`Aggregate::occluded`] inside a lane kernel dispatched at `simd`'s level.
    #[inline(always)]
    #[must_use]
    pub(crate) fn occluded_in<S: Simd>(&self, simd: S, ray: &Ray, t_max: f32, origin: Origin) -> bool {
        let skip = match origin {
            Origin::Anywhere => NO_OBJECT,
            Origin::Surface { sphere, normal } => skipped(sphere, normal, ray.dir),
            Origin::Light(LightRay { cell: Some(cell), skip }) => {
                return self.lights.blocks(simd, cell, ray, t_max, skip);
            }
            Origin::Light(LightRay { cell: None, skip }) => skip,
        };
        self.bvh.occluded_in(simd, ray, t_max, skip)
    }

    /// Which rays of `packet` something blocks before `t_max`, bit i for `dirs[i]`: each
    /// [`Aggregate::occluded`]'s answer from [`Origin::Surface`], for rays spawned by
    /// [`crate::spawn_ray`] in groups that leave one point to one side (one origin, one
    /// sphere left out), inside a lane kernel. One walk down the BVH (`bvh/shared.rs`).
    #[inline(always)]
    #[must_use]
    pub(crate) fn occluded_packet_in<S: Simd>(&self, simd: S, packet: Packet<'_>, t_max: f32) -> u16 {
        let rays = ((1u32 << packet.dirs.len()) - 1) as u16;
        self.bvh.occluded_packet_in(simd, packet, rays, t_max)
    }

    /// The origin of a shadow ray towards light `k` (at `light`) from the point `p` of
    /// sphere `from` (outward normal `n`), leaving along `dir`: its cube-map lookup.
    #[inline]
    #[must_use]
    pub(crate) fn towards_light(
        &self,
        (k, light): (usize, Vec3),
        from: u32,
        (p, n, dir): (Vec3, Vec3, Vec3),
    ) -> LightRay {
        LightRay { cell: self.lights.cell(k, light, p), skip: skipped(from, n, dir) }
    }

    /// Whether a shadow ray's cell lists no sphere but the one it leaves, so that nothing
    /// can block it: the common case of a lit point, answered without a test.
    #[inline]
    #[must_use]
    pub(crate) fn clear(&self, ray: LightRay) -> bool {
        ray.cell.is_some_and(|cell| self.lights.clear(cell, ray.skip))
    }

    /// Which lanes of `rays` (the bits of `need`) something blocks: the lane form of
    /// [`Aggregate::occluded`] for shadow rays, each spawned by [`crate::spawn_ray`] from
    /// its point. A small scene tests every sphere against the whole vector; otherwise every
    /// lane looks up its cell first, the lanes whose cells are clear are answered at once,
    /// and the rest are tested one by one.
    #[inline(always)]
    pub(crate) fn occluded_lanes<S: Simd>(
        &self,
        simd: S,
        (centers, radii, light): (&[Vec3], &[f32], Vec3),
        rays: &ShadowLanes<'_, S>,
        mut need: u64,
    ) -> u64 {
        let (p, n, l) = (&rays.p, &rays.n, &rays.l);
        if centers.len() <= ALL_SPHERES_MAX {
            let origin = crate::simd::spawn_origins(simd, *p, *n, *l);
            let objects = U::<S>::from_slice(simd, rays.objects);
            return flat::blocked(simd, (centers, radii), (origin, *l, rays.dist), objects, need);
        }
        // Every lane's cell first, then the tests: the cells lie scattered through the cube
        // map, and looking them all up before testing any lets their cache misses overlap.
        let mut looked = [LightRay { cell: None, skip: NO_OBJECT }; 16];
        let (mut lookup, mut blocked) = (need, 0);
        while lookup != 0 {
            let lane = lookup.trailing_zeros() as usize;
            lookup &= lookup - 1;
            let at = (lane3::<S>(p, lane), lane3::<S>(n, lane), lane3::<S>(l, lane));
            let ray = self.towards_light((rays.light, light), rays.objects[lane], at);
            if self.clear(ray) {
                need &= !(1 << lane);
            }
            looked[lane] = ray;
        }
        while need != 0 {
            let lane = need.trailing_zeros() as usize;
            need &= need - 1;
            let ray = crate::ray::spawn_ray(lane3::<S>(p, lane), lane3::<S>(n, lane), lane3::<S>(l, lane));
            if self.occluded_in(simd, &ray, rays.dist.as_slice()[lane], Origin::Light(looked[lane])) {
                blocked |= 1 << lane;
            }
        }
        blocked
    }

    /// The closest hits of the mirror rays of the lanes `need` names, each leaving the
    /// surface of sphere `objects[l]` (outward normal `n`) from `origin` (spawned) along
    /// `dir`: `hit(lane, Option<Hit>)` for each, in lane order. The lane form of
    /// [`Aggregate::intersect`] from a surface: a small scene tests every sphere against the
    /// whole vector, a larger one each ray through the cones or the BVH.
    #[inline(always)]
    pub(crate) fn intersect_lanes<S: Simd>(
        &self,
        simd: S,
        (centers, radii): (&[Vec3], &[f32]),
        [origin, dir, n]: [[F<S>; 3]; 3],
        objects: &[u32],
        mut need: u64,
        mut hit: impl FnMut(usize, Option<Hit>),
    ) {
        let found = (centers.len() <= ALL_SPHERES_MAX).then(|| {
            let outwards = crate::simd::dot::<S>(dir, n).simd_ge(F::<S>::splat(simd, 0.0));
            let objects = U::<S>::from_slice(simd, objects);
            let (t, best) = flat::closest(simd, (centers, radii), (origin, dir), objects, outwards);
            let mut hits = ([0f32; 16], [0u32; 16]);
            t.store_slice(&mut hits.0[..F::<S>::LEN]);
            best.store_slice(&mut hits.1[..F::<S>::LEN]);
            hits
        });
        while need != 0 {
            let lane = need.trailing_zeros() as usize;
            need &= need - 1;
            let found = if let Some((t, best)) = &found {
                (best[lane] != NO_OBJECT).then(|| Hit { t: t[lane], object: best[lane] })
            } else {
                let ray = Ray::new(lane3::<S>(&origin, lane), lane3::<S>(&dir, lane));
                let from = Origin::Surface { sphere: objects[lane], normal: lane3::<S>(&n, lane) };
                self.intersect_in(simd, &ray, f32::INFINITY, from)
            };
            hit(lane, found);
        }
    }

    /// [`crate::Snapshot::nearest_depth`] of the spheres `(centers, radii)` the structures
    /// were built over, through the BVH, for a unit `forward`.
    #[must_use]
    pub(crate) fn nearest_depth(&self, spheres: (&[Vec3], &[f32]), origin: Vec3, forward: Vec3) -> Option<f32> {
        self.bvh.nearest_depth(spheres, origin, forward)
    }

    /// Heap bytes of the structures: the BVH, the light maps, the cones.
    pub(crate) fn heap_bytes(&self) -> [usize; 3] {
        [self.bvh.heap_bytes(), self.lights.heap_bytes(), self.cones.heap_bytes()]
    }

    /// Hit parameter of `ray` against the one sphere `object`, ignoring all others: one
    /// sphere test, in the BVH leaf's lanes (a test oracle).
    #[cfg(test)]
    #[must_use]
    pub(crate) fn intersect_one(&self, ray: &Ray, object: u32) -> Option<f32> {
        self.bvh.intersect_one(ray, object)
    }

    /// Whether the direction cones were built (the scene is small enough).
    #[cfg(test)]
    pub(crate) fn has_cones(&self) -> bool {
        self.cones.is_built()
    }
}
