//! First hits of rays from one origin traced through the BVH together: an eye's primary
//! rays, a lane vector of neighbouring pixels a packet (Wald et al. 2001, "Interactive
//! rendering with coherent ray tracing": packets of coherent rays down one traversal;
//! Embree's `rtcIntersect8`, which it uses for the primary rays of a frame).
//!
//! As in the any-hit packets (`shared.rs`), the stack holds a node and the rays that
//! entered it, and a node's children are taken one at a time: each child's box against the
//! rays across the lanes, with each ray's own slab arithmetic (`slab.rs`'s differences and
//! products). For the closest hit each ray keeps its own nearest hit so far, which bounds
//! its slab tests as it bounds a single ray's. A popped node is visited by the rays whose
//! best so far is not nearer than the nearest entry into it any of them had; interior
//! children go on the stack farthest first by that nearest entry, so the nearest is visited
//! next; a leaf is tested at once for the rays that entered it, its spheres' terms that do
//! not depend on the direction made once (the rays share the origin), each ray's roots with
//! [`crate::simd::nearest_root`], as [`crate::simd::spheres_t`] makes them.
//!
//! Each ray thus tests every leaf whose box it enters no farther than its closest hit: the
//! leaf of that hit among them (its box holds the hit point). With the closest hit kept as
//! `Bvh::first_hit_in` keeps it (the smallest `t`, of equal ones the lowest sphere id,
//! whatever the order leaves are met in), each ray's answer is the single-ray traversal's,
//! bit for bit (the tests compare them on random scenes). A packet shares a node's load,
//! its stack entry and its loop among its rays, which one ray at a time pays per ray. Rays
//! that cannot hit anything before a distance (a sliced view's, short of its cut:
//! [`EyeRays::beyond`]) enter no box they leave before it.

#![expect(
    clippy::inline_always,
    reason = "the traversal is inlined into the dispatched function, whose target features it needs"
)]

use fearless_simd::{dispatch, f32x8, prelude::*, u32x8, Simd};
use glam::Vec3;

use super::slab::slabs;
use super::{
    push_sorted, Bvh, Leaf, Link, Node, Root, LEAF, MEDIUM_DEPTH, MEDIUM_STACK, SHALLOW_DEPTH, SHALLOW_STACK, STACK,
};
use crate::simd::{each3, nearest_root, origin_terms};
use crate::surface::NO_OBJECT;

/// Most rays in one packet: the widest lane vector's (AVX-512's sixteen).
pub(crate) const EYE_PACKET: usize = 16;

/// A packet of rays from one origin: ray i's unit direction is `(dirs[0][i], dirs[1][i],
/// dirs[2][i])`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct EyeRays<'a> {
    /// The rays' shared origin.
    pub(crate) origin: Vec3,
    /// The directions, by axis.
    pub(crate) dirs: &'a [[f32; EYE_PACKET]; 3],
    /// How far every hit of the rays lies at least: 0, or for the rays a sliced view's bins
    /// left open, just short of the cut (no sphere they can hit begins nearer). A box the rays
    /// leave before it is not entered.
    pub(crate) beyond: f32,
}

/// Per ray of a packet, its closest hit so far: `t` (+∞ for none) and the sphere
/// ([`NO_OBJECT`] for none).
pub(crate) type Nearest = ([f32; EYE_PACKET], [u32; EYE_PACKET]);

/// A packet's traversal stack entry: an interior node, the rays that entered it, and the
/// nearest of their entries.
#[derive(Clone, Copy, Debug, Default)]
struct Entry {
    link: Link,
    rays: u16,
    near: f32,
}

impl Bvh {
    /// Narrows each ray `rays` names (bit i: ray i) to its closest hit among every sphere:
    /// `nearest` holds what the ray has already found (a hit, or +∞ and [`NO_OBJECT`]), and
    /// becomes the nearer of that and the tree's hits, of equal `t` the lowest sphere id.
    /// Started from nothing, each ray's answer is the single-ray `Bvh::first_hit_in`'s;
    /// inside a function dispatched at `simd`'s level.
    #[inline(always)]
    pub(crate) fn first_hits_in<S: Simd>(&self, simd: S, at: EyeRays<'_>, rays: u16, nearest: &mut Nearest) {
        let mut best = nearest.1.map(|id| (id != NO_OBJECT).then_some(id));
        let t = &mut nearest.0;
        match self.root {
            Root::Empty => {}
            Root::Leaf => leaf_first_hits(simd, &self.leaves[0], at, rays, (t, &mut best)),
            Root::Node if self.depth <= SHALLOW_DEPTH => {
                self.first_hits_with::<S, SHALLOW_STACK>(simd, at, rays, (t, &mut best));
            }
            Root::Node if self.depth <= MEDIUM_DEPTH => {
                self.first_hits_with::<S, MEDIUM_STACK>(simd, at, rays, (t, &mut best));
            }
            Root::Node => self.first_hits_deep(at, rays, (t, &mut best)),
        }
        nearest.1 = best.map(|id| id.unwrap_or(NO_OBJECT));
    }

    /// [`Bvh::first_hits_in`] of a tree deeper than [`MEDIUM_DEPTH`], out of line.
    #[inline(never)]
    fn first_hits_deep(&self, at: EyeRays<'_>, rays: u16, best: Best<'_>) {
        dispatch!(crate::simd::level(), simd => simd.vectorize(
            #[inline(always)]
            || self.first_hits_with::<_, STACK>(simd, at, rays, best),
        ));
    }

    /// The packet traversal with a stack of `N` entries, `N` > 7 × `self.depth` (a node
    /// pushes at most its eight children, as for one ray).
    #[inline(always)]
    fn first_hits_with<S: Simd, const N: usize>(&self, simd: S, at: EyeRays<'_>, rays: u16, (t, best): Best<'_>) {
        let lanes = EyeLanes::new(simd, at, rays);
        let mut stack = [Entry::default(); N];
        stack[0] = Entry { link: 0, rays, near: 0.0 };
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let e = stack[sp];
            // The rays whose closest hit so far is not nearer than the node's nearest entry
            // (a hit found since it was pushed may leave none).
            let open = lanes.reaching(t, e.near) & e.rays;
            if open == 0 {
                continue;
            }
            let node = &self.nodes[e.link as usize];
            let (by_child, nearest) = lanes.enter(node, open, t);
            let base = sp;
            let mut children = node.lanes;
            while children != 0 {
                let k = children.trailing_zeros() as usize;
                children &= children - 1;
                #[expect(clippy::cast_possible_truncation, reason = "at most sixteen rays")]
                let entering = by_child[k] as u16;
                if entering == 0 {
                    continue;
                }
                let (link, near) = (node.child[k], nearest[k]);
                if link & LEAF != 0 {
                    // Leaves entered are tested at once, as for one ray.
                    leaf_first_hits(simd, self.leaf_at(link), at, entering, (t, best));
                    continue;
                }
                sp = push_sorted(&mut stack, base, sp, Entry { link, rays: entering, near }, |e| e.near);
            }
        }
    }
}

/// The rays' closest hits so far: `t` and the sphere, per ray.
type Best<'a> = (&'a mut [f32; EYE_PACKET], &'a mut [Option<u32>; EYE_PACKET]);

/// Narrows the closest hits of the rays `rays` names to a leaf's spheres: per ray
/// [`Bvh::leaf_closest`]'s answer with the lowest id of equal `t`, the terms of each sphere
/// that do not depend on the direction made once for the packet.
#[inline(always)]
fn leaf_first_hits<S: Simd>(simd: S, leaf: &Leaf, at: EyeRays<'_>, rays: u16, (t, best): Best<'_>) {
    let center = each3(|a| f32x8::from_slice(simd, &leaf.center[a]));
    let radius = f32x8::from_slice(simd, &leaf.radius);
    let ids = u32x8::from_slice(simd, &leaf.ids);
    let (oc, r2, cc) = origin_terms(each3(|a| f32x8::splat(simd, at.origin[a])), (center, radius));
    let mut each = rays;
    while each != 0 {
        let i = each.trailing_zeros() as usize;
        each &= each - 1;
        let d = each3(|a| f32x8::splat(simd, at.dirs[a][i]));
        // `t < next_up(t_best)` is `t ≤ t_best`, as `leaf_closest` bounds it.
        let roots = nearest_root(simd, oc, d, r2, cc, f32x8::splat(simd, t[i].next_up()));
        Bvh::narrow::<S, true>(simd, leaf, (roots, ids), NO_OBJECT, &mut t[i], &mut best[i]);
    }
}

/// A packet's rays made ready for box tests: the shared origin, splatted, and each ray's
/// reciprocal direction ([`slabs`], so every slab distance is finite).
struct EyeLanes<S: Simd> {
    origin: [f32x8<S>; 3],
    inv_dir: [[f32; 3]; EYE_PACKET],
    /// [`EyeRays::beyond`], the nearest entry a box test gives.
    beyond: f32x8<S>,
}

impl<S: Simd> EyeLanes<S> {
    #[inline(always)]
    fn new(simd: S, at: EyeRays<'_>, rays: u16) -> Self {
        let mut inv_dir = [[1f32; 3]; EYE_PACKET];
        let mut each = rays;
        while each != 0 {
            let i = each.trailing_zeros() as usize;
            each &= each - 1;
            let (inv, _) = slabs(Vec3::new(at.dirs[0][i], at.dirs[1][i], at.dirs[2][i]));
            inv_dir[i] = inv.to_array();
        }
        Self { origin: each3(|a| f32x8::splat(simd, at.origin[a])), inv_dir, beyond: f32x8::splat(simd, at.beyond) }
    }

    /// The rays whose closest hit so far is at `near` or beyond, as bits.
    #[inline(always)]
    fn reaching(&self, t: &[f32; EYE_PACKET], near: f32) -> u16 {
        let simd = self.origin[0].simd;
        let mut bits = 0u16;
        for h in 0..EYE_PACKET / 8 {
            let best = f32x8::from_slice(simd, &t[8 * h..8 * h + 8]);
            #[expect(clippy::cast_possible_truncation, reason = "eight lanes: the mask has eight bits")]
            let reach = best.simd_ge(f32x8::splat(simd, near)).to_bitmask() as u16;
            bits |= reach << (8 * h);
        }
        bits
    }

    /// Per child of `node` (lane k): the rays of `each` that enter its box no farther than
    /// their closest hit so far, as bits, and the nearest of their entries. Each ray's test
    /// is [`super::BoxRay::enter`]'s, the eight boxes at once: the same differences (the
    /// corners less the shared origin, made once for the packet) and products, the entry
    /// the smaller of the two distances per axis, which is the near corner's.
    #[inline(always)]
    fn enter(&self, node: &Node, each: u16, t: &[f32; EYE_PACKET]) -> ([u32; 8], [f32; 8]) {
        let simd = self.origin[0].simd;
        let lo = each3(|a| f32x8::from_slice(simd, &node.bounds[0][a]) - self.origin[a]);
        let hi = each3(|a| f32x8::from_slice(simd, &node.bounds[1][a]) - self.origin[a]);
        let (none, inf) = (u32x8::splat(simd, 0), f32x8::splat(simd, f32::INFINITY));
        let (mut rays, mut first) = (none, inf);
        let mut left = each;
        while left != 0 {
            let i = left.trailing_zeros() as usize;
            left &= left - 1;
            let mut near = self.beyond;
            let mut far = f32x8::splat(simd, t[i]);
            for a in 0..3 {
                let inv = f32x8::splat(simd, self.inv_dir[i][a]);
                let (t0, t1) = (lo[a] * inv, hi[a] * inv);
                near = t0.min(t1).max(near);
                far = t0.max(t1).min(far);
            }
            let enters = near.simd_le(far);
            rays |= enters.select(u32x8::splat(simd, 1 << i), none);
            first = enters.select(near, inf).min(first);
        }
        let (mut by_child, mut nearest) = ([0u32; 8], [0f32; 8]);
        rays.store_slice(&mut by_child);
        first.store_slice(&mut nearest);
        (by_child, nearest)
    }
}

#[cfg(test)]
mod tests {
    use fearless_simd::{dispatch, prelude::*};
    use glam::Vec3;
    use proptest::prelude::*;

    use super::{Bvh, EyeRays, Nearest, Root, EYE_PACKET, MEDIUM_STACK, STACK};
    use crate::ray::Ray;
    use crate::surface::NO_OBJECT;

    /// Each ray of `rays` one at a time through [`Bvh::first_hit_in`], the nearer of that and
    /// `seed` (of equal `t` the lower id).
    fn one_by_one(bvh: &Bvh, at: EyeRays<'_>, rays: u16, seed: &Nearest) -> Nearest {
        let mut out = *seed;
        for i in (0..EYE_PACKET).filter(|&i| rays >> i & 1 != 0) {
            let ray = Ray::new(at.origin, Vec3::new(at.dirs[0][i], at.dirs[1][i], at.dirs[2][i]));
            let hit = dispatch!(crate::simd::level(), simd => simd.vectorize(|| bvh.first_hit_in(simd, &ray)));
            if let Some(hit) = hit {
                if hit.t < out.0[i] || (hit.t == out.0[i] && hit.object < out.1[i]) {
                    (out.0[i], out.1[i]) = (hit.t, hit.object);
                }
            }
        }
        out
    }

    proptest! {
        /// On random scenes (overlapping, nested spheres, some twice, and none), packets of up
        /// to sixteen rays from a random origin, each started from nothing or from a random
        /// sphere's hit (a copy's too) as the screen bins hand them over: each ray's answer is
        /// the single-ray traversal's, at every lane width this CPU has and with every stack;
        /// and the same when the search starts just short of the packet's nearest hit.
        #[test]
        fn a_packet_finds_each_ray_s_first_hit(
            spheres in proptest::collection::vec((proptest::array::uniform3(-30.0f32..30.0), 0.05f32..4.0), 0..400),
            packets in proptest::collection::vec((
                proptest::array::uniform3(-40.0f32..40.0),
                proptest::array::uniform3(-1.0f32..1.0),
                proptest::collection::vec(proptest::array::uniform3(-0.2f32..0.2), EYE_PACKET),
                any::<u32>(),
            ), 1..24),
        ) {
            // Every fifth sphere twice, the copy last: of their equal `t`, the lower id wins.
            let twice = spheres.iter().step_by(5);
            let (centers, radii): (Vec<Vec3>, Vec<f32>) =
                spheres.iter().chain(twice).map(|&(c, r)| (Vec3::from(c), r)).unzip();
            let mut bvh = Bvh::default();
            bvh.build(&centers, &radii);
            for (k, (origin, aim, spread, seed)) in packets.iter().enumerate() {
                // A coherent packet: one aim, each ray bent by a little.
                let mut dirs = [[0f32; EYE_PACKET]; 3];
                for (i, s) in spread.iter().enumerate() {
                    let d = (Vec3::from(*aim) + Vec3::from(*s)).try_normalize().unwrap_or(Vec3::Z);
                    for a in 0..3 {
                        dirs[a][i] = d[a];
                    }
                }
                let at = EyeRays { origin: Vec3::from(*origin), dirs: &dirs, beyond: 0.0 };
                let rays = (*seed as u16).max(1);
                // Some rays start from a miss, some from a random sphere's hit, some from
                // their first hit's copy (the same `t`, a higher id).
                let mut start: Nearest = ([f32::INFINITY; EYE_PACKET], [NO_OBJECT; EYE_PACKET]);
                for i in (0..EYE_PACKET).filter(|&i| !centers.is_empty() && seed >> (16 + i) & 1 != 0) {
                    let ray = Ray::new(at.origin, Vec3::new(dirs[0][i], dirs[1][i], dirs[2][i]));
                    let s = if seed >> (i % 16) & 1 != 0 {
                        (seed >> 3) as usize * (i + 1) % centers.len()
                    } else {
                        let first = dispatch!(crate::simd::level(), simd => simd.vectorize(|| bvh.first_hit_in(simd, &ray)));
                        match first {
                            Some(hit) if hit.object % 5 == 0 && (hit.object as usize) < spheres.len() => {
                                spheres.len() + hit.object as usize / 5
                            }
                            Some(hit) => hit.object as usize,
                            None => continue,
                        }
                    };
                    if let Some(t) = bvh.intersect_one(&ray, s as u32) {
                        (start.0[i], start.1[i]) = (t, s as u32);
                    }
                }
                let want = one_by_one(&bvh, at, rays, &start);
                // As the sliced bins' open rays: the search starts just short of the nearest
                // first hit of the packet's rays (anywhere when none hits).
                let nearest = (0..EYE_PACKET).filter(|&i| rays >> i & 1 != 0).map(|i| want.0[i]).fold(f32::INFINITY, f32::min);
                let beyond = EyeRays { beyond: if nearest.is_finite() { nearest * (1.0 - 2e-4) } else { 50.0 }, ..at };
                for level in crate::simd::levels() {
                    let (got, stacks) = dispatch!(level, simd => simd.vectorize(|| {
                        let mut got = start;
                        bvh.first_hits_in(simd, at, rays, &mut got);
                        let mut later = start;
                        bvh.first_hits_in(simd, beyond, rays, &mut later);
                        assert_eq!(later, got, "packet {k}, rays {rays:016b}, from {}", beyond.beyond);
                        let mut stacks = [start; 2];
                        if matches!(bvh.root, Root::Node) {
                            let mut best = start.1.map(|id| (id != NO_OBJECT).then_some(id));
                            bvh.first_hits_with::<_, MEDIUM_STACK>(simd, at, rays, (&mut stacks[0].0, &mut best));
                            stacks[0].1 = best.map(|id| id.unwrap_or(NO_OBJECT));
                            let mut best = start.1.map(|id| (id != NO_OBJECT).then_some(id));
                            bvh.first_hits_with::<_, STACK>(simd, at, rays, (&mut stacks[1].0, &mut best));
                            stacks[1].1 = best.map(|id| id.unwrap_or(NO_OBJECT));
                        } else {
                            stacks = [got; 2];
                        }
                        (got, stacks)
                    }));
                    let bits = |n: &Nearest| (n.0.map(f32::to_bits), n.1);
                    prop_assert_eq!(bits(&got), bits(&want), "packet {}, rays {:016b}, {:?}", k, rays, level);
                    prop_assert_eq!(stacks.map(|s| bits(&s)), [bits(&want); 2], "packet {}: the medium and long stacks", k);
                }
            }
        }
    }
}
