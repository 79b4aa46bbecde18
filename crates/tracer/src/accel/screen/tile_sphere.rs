//! A sphere as a sliced view's tiles list it, and its test against a group of lanes.

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use fearless_simd::{prelude::*, Simd};
use glam::Vec3;

use crate::simd::{each3, nearest_root, F, U};

/// A sphere as a sliced view's tile lists it: its terms seen from the eye, made once a frame
/// by `spheres_t`'s own operations (so its `t` is bit for bit every other query's), and its
/// id. A tile's lanes read its spheres in a row instead of gathering each from the scene's
/// arrays: on a million spheres those gathers missed the cache (the first 1M field's frame
/// took 8 % less). Six times the bytes of an id, so only a sliced view, whose bins hold at
/// most a sphere a pixel, lists them; full bins list ids (2BTV's assembly, binned in full
/// at its converged 4 × 4 samples a pixel, peaked 440 MB higher in the window with terms).
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct TileSphere {
    /// The eye less the centre.
    oc: [f32; 3],
    /// The radius squared.
    r2: f32,
    /// |oc|² − r².
    cc: f32,
    id: u32,
}

impl TileSphere {
    /// Sphere `id`, centre `c` and radius `r`, seen from the eye at `o`.
    #[inline]
    pub(super) fn new(id: u32, o: Vec3, c: Vec3, r: f32) -> Self {
        let oc = [o.x - c.x, o.y - c.y, o.z - c.z];
        let r2 = r * r;
        let cc = (oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2]) - r2;
        Self { oc, r2, cc, id }
    }
}

/// One sphere's test against the lanes' rays from the eye along `d`: where it is hit nearer
/// than `t` (no farther on a tie, which keeps the earlier, lower id), `t` and `ids` take it.
#[inline(always)]
pub(super) fn test_sphere<S: Simd>(simd: S, s: TileSphere, d: [F<S>; 3], (t, ids): (&mut F<S>, &mut U<S>)) {
    let oc = each3(|a| F::<S>::splat(simd, s.oc[a]));
    let (r2, cc) = (F::<S>::splat(simd, s.r2), F::<S>::splat(simd, s.cc));
    let root = nearest_root(simd, oc, d, r2, cc, *t);
    let nearer = root.simd_lt(*t);
    *t = nearer.select(root, *t);
    *ids = nearer.select(U::<S>::splat(simd, s.id), *ids);
}
