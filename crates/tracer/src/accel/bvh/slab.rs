//! The slab test of a ray against a node's eight child boxes (Kay & Kajiya 1986; the
//! corner order of Williams et al. 2005, "An efficient and robust ray–box intersection
//! algorithm"), for one ray ([`BoxRay`]); `shared.rs` runs the same arithmetic with the
//! rays of a packet across the lanes.

#![expect(
    clippy::inline_always,
    reason = "the slab test is inlined into the dispatched lane kernels, whose target features it needs"
)]

use fearless_simd::{f32x8, prelude::*, Simd};
use glam::Vec3;

use super::Node;
use crate::ray::Ray;

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
