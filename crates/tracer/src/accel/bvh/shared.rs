//! Any-hit packets of rays in groups of one origin: the occlusion rays of a vector of hits
//! traced through the BVH together (Wald et al. 2001, "Interactive rendering with coherent
//! ray tracing": packets of rays down one traversal; Boulos et al. 2007, "Packet-based
//! Whitted and distribution ray tracing": shadow and ambient-occlusion rays from a shared
//! origin as packets).
//!
//! The stack holds a node and the mask of the rays that entered it. The rays lie across
//! the lanes, eight to a vector ([`RayLanes`]), and a node's children are taken one at a
//! time: each child's box against all the node's rays at once, with each ray's own slab
//! arithmetic (`slab.rs`'s: the same differences and products, so the same bits). Before
//! that, one test of the node's eight boxes against the box around the packet's origins,
//! grown by the rays' reach ([`NearPacket`]), skips the children no ray can enter: on
//! 1TII's occlusion rays a visited node has about six children, four within reach and two
//! entered. A leaf is tested only for the rays whose own test entered it (the sphere terms
//! that do not depend on the direction made once a group), a blocked ray leaves every mask,
//! and the walk stops when none is left. Each ray therefore meets exactly the leaves its
//! single-ray traversal ([`Bvh::occluded_in`]) would, and its answer is that traversal's,
//! bit for bit. Measured on 1TII (4 rays a hit, four hits a packet): `docs/design/cues.md`.

#![expect(
    clippy::inline_always,
    reason = "the traversal is inlined into the dispatched function, whose target features it needs"
)]

use fearless_simd::{dispatch, f32x8, prelude::*, u32x8, Simd};
use glam::Vec3;

use super::slab::slabs;
use super::{Bvh, Leaf, Link, Node, Root, LEAF, MEDIUM_DEPTH, MEDIUM_STACK, SHALLOW_DEPTH, SHALLOW_STACK, STACK};
use crate::simd::{each3, has_root, origin_terms};

/// Most rays in one packet: the bits of its `u16` masks; rays 0–7 and 8–15 each a byte of
/// one of a node's two `u64`s of rays by child ([`by_child`]).
pub(crate) const PACKET: usize = 16;

/// A packet's rays: the unit directions (at most [`PACKET`]), in groups that share an
/// origin and the sphere left out (a hit's rays; a packet may hold several hits').
#[derive(Clone, Copy, Debug)]
pub(crate) struct Packet<'a> {
    /// Ray i's direction.
    pub(crate) dirs: &'a [Vec3],
    /// Per group: its rays' origin, the sphere they leave out, and the bits of its rays.
    pub(crate) groups: &'a [(Vec3, u32, u16)],
}

impl Bvh {
    /// Which of the rays `rays` names (bit i: `dirs[i]` from its group's origin) any sphere
    /// other than its group's blocks before `t_max`: per ray [`Bvh::occluded_in`]'s answer,
    /// inside a function dispatched at `simd`'s level.
    #[inline(always)]
    pub(crate) fn occluded_packet_in<S: Simd>(&self, simd: S, at: Packet<'_>, rays: u16, t_max: f32) -> u16 {
        debug_assert!(
            at.dirs.len() <= PACKET && u64::from(rays) < 1 << at.dirs.len(),
            "rays {rays:b} of {}",
            at.dirs.len()
        );
        match self.root {
            Root::Empty => 0,
            Root::Leaf => Self::leaf_blocks_packet(simd, &self.leaves[0], at, rays, t_max),
            Root::Node if self.depth <= SHALLOW_DEPTH => self.packet_with::<S, SHALLOW_STACK>(simd, at, rays, t_max),
            Root::Node if self.depth <= MEDIUM_DEPTH => self.packet_with::<S, MEDIUM_STACK>(simd, at, rays, t_max),
            Root::Node => self.packet_deep(at, rays, t_max),
        }
    }

    /// [`Bvh::occluded_packet_in`] of a tree deeper than [`MEDIUM_DEPTH`], out of line.
    #[inline(never)]
    fn packet_deep(&self, at: Packet<'_>, rays: u16, t_max: f32) -> u16 {
        dispatch!(crate::simd::level(), simd => simd.vectorize(
            #[inline(always)]
            || self.packet_with::<_, STACK>(simd, at, rays, t_max),
        ))
    }

    /// The packet traversal with a stack of `N` entries, `N` > 7 × `self.depth` (a node
    /// pushes at most its eight children, as for one ray).
    #[inline(always)]
    fn packet_with<S: Simd, const N: usize>(&self, simd: S, at: Packet<'_>, rays: u16, t_max: f32) -> u16 {
        let lanes = RayLanes::new(simd, at, rays);
        let near_packet = NearPacket::new(simd, at, rays, t_max);
        // The rays not yet blocked.
        let mut open = rays;
        let mut stack = [(0 as Link, 0u16); N];
        stack[0] = (0, rays);
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let (link, entered) = stack[sp];
            let each = entered & open;
            if each == 0 {
                continue;
            }
            let node = &self.nodes[link as usize];
            // The children in lane order, as one ray's traversal meets them; only those
            // whose box comes within reach of the packet's origins can be entered.
            let mut children = near_packet.children(node);
            while children != 0 {
                let k = children.trailing_zeros() as usize;
                children &= children - 1;
                let entering = lanes.enter(node, k, each & open, t_max);
                if entering == 0 {
                    continue;
                }
                let link = node.child[k];
                if link & LEAF == 0 {
                    stack[sp] = (link, entering);
                    sp += 1;
                    continue;
                }
                open &= !Self::leaf_blocks_packet(simd, self.leaf_at(link), at, entering, t_max);
                if open == 0 {
                    return rays;
                }
            }
        }
        rays & !open
    }

    /// Which of the rays `rays` names one of a leaf's spheres other than its group's blocks
    /// before `t_max`: per ray [`Bvh::leaf_blocks`]'s answer, the terms of each sphere that
    /// do not depend on the direction made once a group.
    #[inline(always)]
    fn leaf_blocks_packet<S: Simd>(simd: S, leaf: &Leaf, at: Packet<'_>, rays: u16, t_max: f32) -> u16 {
        let reach = f32x8::splat(simd, t_max);
        let mut blocked = 0;
        let center = each3(|a| f32x8::from_slice(simd, &leaf.center[a]));
        let radius = f32x8::from_slice(simd, &leaf.radius);
        let ids = u32x8::from_slice(simd, &leaf.ids);
        for &(origin, skip, members) in at.groups {
            let mut each = rays & !blocked & members;
            if each == 0 {
                continue;
            }
            let (oc, r2, cc) = origin_terms(each3(|a| f32x8::splat(simd, origin[a])), (center, radius));
            let others = ids.simd_ne(u32x8::splat(simd, skip));
            // The sphere left out, and those wholly beyond the reach (by a margin far above
            // the rounding), can answer nothing: a negative square radius makes them miss
            // every ray, so that a leaf none of whose other spheres a ray's line meets is
            // left at the first test.
            let beyond = radius + reach;
            let near = (cc + r2).simd_le(beyond * beyond * f32x8::splat(simd, 1.0 + 1.0 / 1024.0));
            let r2 = (others & near).select(r2, f32x8::splat(simd, -1.0));
            while each != 0 {
                let i = each.trailing_zeros() as usize;
                each &= each - 1;
                let d = each3(|a| f32x8::splat(simd, at.dirs[i][a]));
                if has_root(simd, oc, d, r2, cc, reach) {
                    blocked |= 1 << i;
                }
            }
        }
        blocked
    }
}

/// A packet's rays across SIMD lanes, ray i in lane i % 8 of vector i / 8: its group's
/// origin and its reciprocal direction ([`slabs`], so every slab distance is finite).
struct RayLanes<S: Simd> {
    origin: [[f32x8<S>; 3]; 2],
    inv_dir: [[f32x8<S>; 3]; 2],
}

impl<S: Simd> RayLanes<S> {
    #[inline(always)]
    fn new(simd: S, at: Packet<'_>, rays: u16) -> Self {
        let mut origin = [[0f32; PACKET]; 3];
        let mut inv_dir = [[1f32; PACKET]; 3];
        for &(o, _, members) in at.groups {
            let mut each = members & rays;
            while each != 0 {
                let i = each.trailing_zeros() as usize;
                each &= each - 1;
                let (inv, _) = slabs(at.dirs[i]);
                for a in 0..3 {
                    origin[a][i] = o[a];
                    inv_dir[a][i] = inv[a];
                }
            }
        }
        let half = |v: &[[f32; PACKET]; 3], h: usize| each3(|a| f32x8::from_slice(simd, &v[a][8 * h..8 * h + 8]));
        Self { origin: [half(&origin, 0), half(&origin, 1)], inv_dir: [half(&inv_dir, 0), half(&inv_dir, 1)] }
    }

    /// The rays of `each` that enter child `k` of `node` before `t_max`: per ray the slab
    /// test of [`enter`] (the entry and exit distances per axis, each the same product of
    /// the same difference; the smaller of the two is the one the ray's near corner gives),
    /// eight rays at a time against the child's box.
    #[inline(always)]
    fn enter(&self, node: &Node, k: usize, each: u16, t_max: f32) -> u16 {
        let simd = self.origin[0][0].simd;
        let corner = |s: usize| each3(|a| f32x8::splat(simd, node.bounds[s][a][k]));
        let (lo, hi) = (corner(0), corner(1));
        let mut entering = 0u16;
        for h in 0..2 {
            let half = (each >> (8 * h)) as u8;
            if half == 0 {
                continue;
            }
            let (origin, inv) = (&self.origin[h], &self.inv_dir[h]);
            let mut near = f32x8::splat(simd, 0.0);
            let mut far = f32x8::splat(simd, t_max);
            for a in 0..3 {
                let t0 = (lo[a] - origin[a]) * inv[a];
                let t1 = (hi[a] - origin[a]) * inv[a];
                near = t0.min(t1).max(near);
                far = t0.max(t1).min(far);
            }
            #[expect(clippy::cast_possible_truncation, reason = "eight lanes: the mask has eight bits")]
            let hit = near.simd_le(far).to_bitmask() as u16;
            entering |= hit << (8 * h);
        }
        entering & each
    }
}

/// The box around a packet's origins grown by its reach: a child box apart from it on some
/// axis is entered by none of the packet's rays, so its slab tests are skipped.
///
/// A ray (unit direction) that enters a box before `t_max` meets it within `t_max` of its
/// origin on every axis. The slab test's rounding (a few units in the last place of the
/// distances and coordinates) is covered by a margin far above it: `t_max` / 1024 and
/// 2⁻¹⁶ of the largest origin coordinate, so the skip never changes a ray's answer.
struct NearPacket<S: Simd> {
    min: [f32x8<S>; 3],
    max: [f32x8<S>; 3],
}

impl<S: Simd> NearPacket<S> {
    #[inline(always)]
    fn new(simd: S, at: Packet<'_>, rays: u16, t_max: f32) -> Self {
        let (mut min, mut max) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for &(origin, _, members) in at.groups {
            if members & rays != 0 {
                (min, max) = (min.min(origin), max.max(origin));
            }
        }
        let scale = min.abs().max(max.abs()).max_element().max(1.0);
        let reach = t_max + t_max / 1024.0 + scale / 65536.0;
        let (min, max) = (min - Vec3::splat(reach), max + Vec3::splat(reach));
        Self { min: each3(|a| f32x8::splat(simd, min[a])), max: each3(|a| f32x8::splat(simd, max[a])) }
    }

    /// The children of `node` whose boxes meet the packet's reach, as lane bits.
    #[inline(always)]
    fn children(&self, node: &Node) -> u32 {
        let simd = self.min[0].simd;
        let mut apart = f32x8::splat(simd, 0.0).simd_lt(f32x8::splat(simd, 0.0));
        for a in 0..3 {
            let lo = f32x8::from_slice(simd, &node.bounds[0][a]);
            let hi = f32x8::from_slice(simd, &node.bounds[1][a]);
            apart = apart | lo.simd_gt(self.max[a]) | hi.simd_lt(self.min[a]);
        }
        #[expect(clippy::cast_possible_truncation, reason = "eight lanes: the mask has eight bits")]
        let apart = apart.to_bitmask() as u32;
        node.lanes & !apart
    }
}

#[cfg(test)]
mod tests {
    use fearless_simd::{dispatch, prelude::*};
    use glam::Vec3;
    use proptest::prelude::*;

    use super::{Bvh, Packet, Root, MEDIUM_STACK, PACKET, STACK};
    use crate::accel::{skipped, Aggregate, Origin};
    use crate::ray::{spawn_bound, spawn_ray};

    /// Unit directions from raw triples, a short one taken as +z.
    fn units(raw: &[[f32; 3]]) -> Vec<Vec3> {
        raw.iter()
            .map(|&d| Vec3::from(d).try_normalize().filter(|_| Vec3::from(d).length() > 1e-2).unwrap_or(Vec3::Z))
            .collect()
    }

    proptest! {
        /// On random scenes (overlapping, nested spheres), packets of up to sixteen rays in up
        /// to three groups, each from its own origin (on a sphere's surface with that sphere
        /// left out, or anywhere): the packet's answer for each ray is the single-ray
        /// traversal's, at the level's lanes and at 4, with every stack; and through the
        /// aggregate, rays spawned from points on spheres, grouped by point and side as the
        /// occlusion rays are, answer as [`Aggregate::occluded`] answers each.
        #[test]
        fn a_packet_answers_as_its_rays_one_by_one(
            spheres in proptest::collection::vec((proptest::array::uniform3(-30.0f32..30.0), 0.05f32..4.0), 0..400),
            packets in proptest::collection::vec((
                proptest::collection::vec(proptest::array::uniform3(-40.0f32..40.0), 1..=3),
                proptest::collection::vec(proptest::array::uniform3(-1.0f32..1.0), 1..=PACKET),
                0.5f32..80.0,
                any::<u32>(),
            ), 1..24),
        ) {
            let (centers, radii): (Vec<Vec3>, Vec<f32>) = spheres.iter().map(|&(c, r)| (Vec3::from(c), r)).unzip();
            let mut bvh = Bvh::default();
            bvh.build(&centers, &radii);
            let mut aggregate = Aggregate::default();
            aggregate.build((&centers, &radii), &[], spawn_bound(120.0));
            for (k, (points, raw, reach, seed)) in packets.iter().enumerate() {
                let dirs = units(raw);
                let all = ((1u32 << dirs.len()) - 1) as u16;
                let rays = (*seed as u16 & all).max(1);
                // Group g's origin and the sphere it leaves out: on a sphere's surface (normal
                // `units(points)[g]`) when the seed says so, else anywhere.
                let normals = units(points);
                let on = |g: usize| {
                    (!centers.is_empty() && seed >> (8 + g) & 1 != 0).then(|| (seed >> 12) as usize * (g + 1) % centers.len())
                };
                let mut groups: Vec<(Vec3, u32, u16)> = (0..points.len())
                    .map(|g| match on(g) {
                        Some(s) => (centers[s] + radii[s] * normals[g], s as u32, 0),
                        None => (Vec3::from(points[g]), crate::surface::NO_OBJECT, 0),
                    })
                    .collect();
                for i in 0..dirs.len() {
                    groups[(seed >> (16 + i % 16)) as usize % points.len()].2 |= 1 << i;
                }
                let packet = Packet { dirs: &dirs, groups: &groups };
                let one = bvh_one(&bvh, packet, rays, *reach);
                for level in crate::simd::levels() {
                    let (got, stacks) = dispatch!(level, simd => simd.vectorize(|| {
                        // The stacks of deeper trees, on a tree with interior nodes.
                        let stacks = if matches!(bvh.root, Root::Node) { [
                            bvh.packet_with::<_, MEDIUM_STACK>(simd, packet, rays, *reach),
                            bvh.packet_with::<_, STACK>(simd, packet, rays, *reach),
                        ] } else { [one; 2] };
                        (bvh.occluded_packet_in(simd, packet, rays, *reach), stacks)
                    }));
                    prop_assert_eq!(got, one, "packet {}, rays {:08b}, {:?}", k, rays, level);
                    prop_assert_eq!(stacks, [one; 2], "packet {}: the medium and long stacks", k);
                }
                if matches!(bvh.root, Root::Node) {
                    prop_assert_eq!(bvh.packet_deep(packet, rays, *reach), one, "packet {}: out of line", k);
                }
                // Through the aggregate: each ray spawned from its group's point, the groups
                // split by the side each ray leaves to.
                if centers.is_empty() {
                    continue;
                }
                let (mut spawned, mut want) = (Vec::<(Vec3, u32, u16)>::new(), 0u16);
                let mut keys = Vec::new();
                for (i, &dir) in dirs.iter().enumerate() {
                    let g = (seed >> (16 + i % 16)) as usize % points.len();
                    let s = on(g).unwrap_or(g % centers.len());
                    let (p, n) = (centers[s] + radii[s] * normals[g], normals[g]);
                    let ray = spawn_ray(p, n, dir);
                    want |= u16::from(aggregate.occluded(&ray, *reach, Origin::Surface { sphere: s as u32, normal: n })) << i;
                    let key = (g, crate::ray::leaves_outwards(n, dir));
                    let at = keys.iter().position(|&k| k == key).unwrap_or_else(|| {
                        keys.push(key);
                        spawned.push((ray.origin, skipped(s as u32, n, dir), 0));
                        keys.len() - 1
                    });
                    spawned[at].2 |= 1 << i;
                }
                let got = dispatch!(crate::simd::level(), simd => simd.vectorize(|| {
                    aggregate.occluded_packet_in(simd, Packet { dirs: &dirs, groups: &spawned }, *reach)
                }));
                prop_assert_eq!(got, want, "packet {} through the aggregate", k);
            }
        }
    }

    /// The single-ray answers of the rays `rays` names, as a packet's bits.
    fn bvh_one(bvh: &Bvh, packet: Packet<'_>, rays: u16, reach: f32) -> u16 {
        let mut bits = 0;
        for &(origin, skip, members) in packet.groups {
            for i in (0..packet.dirs.len()).filter(|&i| (rays & members) >> i & 1 != 0) {
                let ray = crate::ray::Ray { origin, dir: packet.dirs[i] };
                bits |= u16::from(bvh.occluded(&ray, reach, skip)) << i;
            }
        }
        bits
    }
}
