//! The slab test of a ray against a node's eight child boxes (Kay & Kajiya 1986; the
//! corner order of Williams et al. 2005, "An efficient and robust ray–box intersection
//! algorithm"), for one ray ([`BoxRay`]) and for the rays of a shared-origin packet
//! (`shared.rs`), in the same arithmetic.

#![expect(
    clippy::inline_always,
    reason = "the slab test is inlined into the dispatched lane kernels, whose target features it needs"
)]

use fearless_simd::{f32x8, prelude::*, Simd};
use glam::Vec3;

use super::Node;
use crate::ray::Ray;
use crate::simd::each3;

/// A direction made ready for the slab test: its reciprocal, and per axis which corner of a
/// box the ray meets first: 0 (minimum) where the direction is positive, 1 where negative.
#[inline(always)]
pub(super) fn slabs(dir: Vec3) -> (Vec3, [usize; 3]) {
    // A zero direction component becomes ±10⁻³⁰: its slabs stay finite (±10³⁰·gap, or
    // 0 for an origin on the plane) instead of ∞ and 0·∞ = NaN.
    let safe = |x: f32| if x.abs() < 1e-30 { 1e-30f32.copysign(x) } else { x };
    let dir = Vec3::new(safe(dir.x), safe(dir.y), safe(dir.z));
    let side = |x: f32| usize::from(x.is_sign_negative());
    (dir.recip(), [side(dir.x), side(dir.y), side(dir.z)])
}

/// The slab test of one ray, of reciprocal direction `inv_dir` (splatted) and corners
/// `near_side` ([`slabs`]), against a node's eight boxes less the ray's origin (`rel[s][a]`:
/// the corners `s` on axis `a`, minus the origin): per lane the entry distance, and the bits
/// of the children the ray meets before `t_max`.
///
/// Per axis the slab is entered at the corner `near_side` names and left at the other: the
/// same two distances a min/max of both would order, one operation fewer each. Every value
/// is finite (see [`slabs`]), so `min` and `max` need no NaN rule.
#[inline(always)]
pub(super) fn enter<S: Simd>(
    rel: &[[f32x8<S>; 3]; 2],
    (inv_dir, near_side): ([f32x8<S>; 3], [usize; 3]),
    lanes: u32,
    t_max: f32,
) -> (f32x8<S>, u32) {
    let simd = inv_dir[0].simd;
    let mut near = f32x8::splat(simd, 0.0);
    let mut far = f32x8::splat(simd, t_max);
    for a in 0..3 {
        let side = near_side[a];
        let t_in = rel[side][a] * inv_dir[a];
        let t_out = rel[1 - side][a] * inv_dir[a];
        near = t_in.max(near);
        far = t_out.min(far);
    }
    #[expect(clippy::cast_possible_truncation, reason = "eight lanes: the mask has eight bits")]
    let hit = near.simd_le(far).to_bitmask() as u32;
    (near, hit & lanes)
}

/// A node's boxes less `origin` (splatted), as [`enter`] takes them.
#[inline(always)]
pub(super) fn relative<S: Simd>(simd: S, node: &Node, origin: &[f32x8<S>; 3]) -> [[f32x8<S>; 3]; 2] {
    // `each3`, not `array::map`, whose closure may not be inlined (each lane operation
    // then becomes a call).
    let side = |s: usize| each3(|a| f32x8::from_slice(simd, &node.bounds[s][a]) - origin[a]);
    [side(0), side(1)]
}

/// A ray prepared for box tests, splatted across the eight child lanes.
pub(super) struct BoxRay<S: Simd> {
    origin: [f32x8<S>; 3],
    inv_dir: [f32x8<S>; 3],
    /// Per axis, the corner of a box the ray meets first ([`slabs`]).
    near_side: [usize; 3],
}

impl<S: Simd> BoxRay<S> {
    #[inline(always)]
    pub(super) fn new(simd: S, ray: &Ray) -> Self {
        let (inv, near_side) = slabs(ray.dir);
        let splat = |v: Vec3| [v.x, v.y, v.z].map(|x| f32x8::splat(simd, x));
        Self { origin: splat(ray.origin), inv_dir: splat(inv), near_side }
    }

    /// The slab test against `node`'s eight child boxes: [`enter`]'s arithmetic, each
    /// corner loaded and less the origin where it is used.
    #[inline(always)]
    pub(super) fn enter(&self, node: &Node, t_max: f32) -> (f32x8<S>, u32) {
        let simd = self.origin[0].simd;
        let mut near = f32x8::splat(simd, 0.0);
        let mut far = f32x8::splat(simd, t_max);
        for a in 0..3 {
            let side = self.near_side[a];
            let t_in = (f32x8::from_slice(simd, &node.bounds[side][a]) - self.origin[a]) * self.inv_dir[a];
            let t_out = (f32x8::from_slice(simd, &node.bounds[1 - side][a]) - self.origin[a]) * self.inv_dir[a];
            near = t_in.max(near);
            far = t_out.min(far);
        }
        #[expect(clippy::cast_possible_truncation, reason = "eight lanes: the mask has eight bits")]
        let hit = near.simd_le(far).to_bitmask() as u32;
        (near, hit & node.lanes)
    }
}
