//! The structure of small scenes: none. A vector of rays meets every sphere in lanes, one
//! SIMD test per sphere, which for a handful of spheres beats looking each ray up in the
//! cube maps, cones or BVH. The answer is theirs: each sphere's `t` is the same kernel on
//! the same values (`simd.rs`).

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use fearless_simd::{prelude::*, Simd};
use glam::Vec3;

use crate::simd::{mask_of, sphere_t, F, M, U};
use crate::surface::NO_OBJECT;

/// Scenes of up to this many spheres answer shadow and mirror rays by testing every sphere
/// against a vector of rays at once, instead of one ray at a time.
pub(crate) const ALL_SPHERES_MAX: usize = 16;

/// The lanes whose object is sphere `s`.
#[inline(always)]
fn is_object<S: Simd>(simd: S, objects: U<S>, s: usize) -> M<S> {
    objects.simd_eq(U::<S>::splat(simd, s as u32))
}

/// Which lanes' shadow rays (from `origin` along `l`, to `dist`) some sphere blocks, of the
/// lanes in `need`; a ray is not tested against its own sphere (`objects`), which it leaves
/// outwards.
#[inline(always)]
pub(super) fn blocked<S: Simd>(
    simd: S,
    (centers, radii): (&[Vec3], &[f32]),
    (origin, l, dist): ([F<S>; 3], [F<S>; 3], F<S>),
    objects: U<S>,
    need: u64,
) -> u64 {
    let need = mask_of(simd, need);
    let inf = F::<S>::splat(simd, f32::INFINITY);
    let mut blocked = M::<S>::splat(simd, false);
    for (s, (&center, &radius)) in centers.iter().zip(radii).enumerate() {
        let t = sphere_t(simd, origin, l, center, radius, dist);
        blocked |= t.simd_lt(inf) & !is_object(simd, objects, s);
        if (need & !blocked).all_false() {
            break;
        }
    }
    (need & blocked).to_bitmask()
}

/// Each lane's closest hit of the ray from `origin` along `dir`, among every sphere but its
/// own where it leaves that sphere outwards (`outwards`): the hit parameter (+∞ for none)
/// and the sphere ([`NO_OBJECT`] for none).
#[inline(always)]
pub(super) fn closest<S: Simd>(
    simd: S,
    (centers, radii): (&[Vec3], &[f32]),
    (origin, dir): ([F<S>; 3], [F<S>; 3]),
    objects: U<S>,
    outwards: M<S>,
) -> (F<S>, U<S>) {
    let mut t_best = F::<S>::splat(simd, f32::INFINITY);
    let mut best = U::<S>::splat(simd, NO_OBJECT);
    for (s, (&center, &radius)) in centers.iter().zip(radii).enumerate() {
        let t = sphere_t(simd, origin, dir, center, radius, t_best);
        let nearer = t.simd_lt(t_best) & !(is_object(simd, objects, s) & outwards);
        t_best = nearer.select(t, t_best);
        best = nearer.select(U::<S>::splat(simd, s as u32), best);
    }
    (t_best, best)
}
