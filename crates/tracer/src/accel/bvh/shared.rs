//! Any-hit packets of rays with one origin: a point's occlusion rays traced through the BVH
//! together (Wald et al. 2001, "Interactive rendering with coherent ray tracing": packets
//! of rays down one traversal; Boulos et al. 2007, "Packet-based Whitted and distribution
//! ray tracing": shadow and ambient-occlusion rays from a shared origin as packets).
//!
//! The stack holds a node and the mask of the rays that entered it. A node is loaded and
//! made relative to the origin once for all its rays; each ray of the mask then runs its
//! own slab test against the eight boxes (`slab.rs`, the single-ray arithmetic), a leaf is
//! tested only for the rays whose own test entered it (the sphere terms that do not
//! depend on the direction made once), a blocked ray leaves every mask, and the walk stops
//! when none is left. Each ray therefore meets exactly the leaves its single-ray traversal
//! ([`Bvh::occluded_in`]) would, in the same order (children in lane order, the same
//! stack), and its answer is that traversal's, bit for bit. Measured on 1TII (4 rays a
//! hit): `docs/design/cues.md`.

#![expect(
    clippy::inline_always,
    reason = "the traversal is inlined into the dispatched function, whose target features it needs"
)]

use fearless_simd::{dispatch, f32x8, prelude::*, Simd};
use glam::Vec3;

use super::slab::{enter, relative, slabs};
use super::{Bvh, Leaf, Link, Root, LEAF, MEDIUM_DEPTH, MEDIUM_STACK, SHALLOW_DEPTH, SHALLOW_STACK, STACK, WIDTH};
use crate::simd::{each3, load, nearest_root, origin_terms, splat3, F, U};

/// Most rays in one packet: the bits of its `u8` masks, one a byte of a node's `u64` of
/// rays by child ([`by_child`]).
pub(crate) const PACKET: usize = 8;

/// A packet's rays: their shared origin, and the unit directions (at most [`PACKET`]).
type Rays<'a> = (Vec3, &'a [Vec3]);

impl Bvh {
    /// Which of the rays `rays` names (bit i: origin, `dirs[i]`) any sphere other than
    /// `skip` blocks before `t_max`: per ray [`Bvh::occluded_in`]'s answer, inside a
    /// function dispatched at `simd`'s level.
    #[inline(always)]
    pub(crate) fn occluded_packet_in<S: Simd>(&self, simd: S, at: Rays<'_>, rays: u8, t_max: f32, skip: u32) -> u8 {
        debug_assert!(at.1.len() <= PACKET && u64::from(rays) < 1 << at.1.len(), "rays {rays:b} of {}", at.1.len());
        match self.root {
            Root::Empty => 0,
            Root::Leaf => Self::leaf_blocks_packet(simd, &self.leaves[0], at, rays, t_max, skip),
            Root::Node if self.depth <= SHALLOW_DEPTH => {
                self.packet_with::<S, SHALLOW_STACK>(simd, at, rays, t_max, skip)
            }
            Root::Node if self.depth <= MEDIUM_DEPTH => {
                self.packet_with::<S, MEDIUM_STACK>(simd, at, rays, t_max, skip)
            }
            Root::Node => self.packet_deep(at, rays, t_max, skip),
        }
    }

    /// [`Bvh::occluded_packet_in`] of a tree deeper than [`MEDIUM_DEPTH`], out of line.
    #[inline(never)]
    fn packet_deep(&self, at: Rays<'_>, rays: u8, t_max: f32, skip: u32) -> u8 {
        dispatch!(crate::simd::level(), simd => simd.vectorize(
            #[inline(always)]
            || self.packet_with::<_, STACK>(simd, at, rays, t_max, skip),
        ))
    }

    /// The packet traversal with a stack of `N` entries, `N` > 7 × `self.depth` (a node
    /// pushes at most its eight children, as for one ray).
    #[inline(always)]
    fn packet_with<S: Simd, const N: usize>(&self, simd: S, at: Rays<'_>, rays: u8, t_max: f32, skip: u32) -> u8 {
        let (origin, dirs) = at;
        let o = each3(|a| f32x8::splat(simd, origin[a]));
        let mut slab = [(Vec3::ZERO, [0usize; 3]); PACKET];
        let mut each = rays;
        while each != 0 {
            let i = each.trailing_zeros() as usize;
            each &= each - 1;
            slab[i] = slabs(dirs[i]);
        }
        // The rays not yet blocked.
        let mut open = rays;
        let mut stack = [(0 as Link, 0u8); N];
        stack[0] = (0, rays);
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let (link, entered) = stack[sp];
            let mut each = entered & open;
            if each == 0 {
                continue;
            }
            let node = &self.nodes[link as usize];
            let rel = relative(simd, node, &o);
            // Byte 7 − k: the rays that enter child k, each ray's own slab test's bits
            // spread out ([`by_child`]): no branch per ray and child.
            let mut into = 0u64;
            while each != 0 {
                let i = each.trailing_zeros();
                each &= each - 1;
                let (inv, side) = slab[i as usize];
                let inv = each3(|a| f32x8::splat(simd, inv[a]));
                let (_, hit) = enter(&rel, (inv, side), node.lanes, t_max);
                into |= by_child(hit) << i;
            }
            // The children in lane order, as one ray's traversal meets them: child k's
            // byte is the highest left.
            while into != 0 {
                let lane = into.leading_zeros() / 8;
                let byte = 8 * (7 - lane);
                let entering = (into >> byte) as u8 & open;
                into &= !(0xff << byte);
                if entering == 0 {
                    continue;
                }
                let link = node.child[lane as usize];
                if link & LEAF == 0 {
                    stack[sp] = (link, entering);
                    sp += 1;
                    continue;
                }
                open &= !Self::leaf_blocks_packet(simd, self.leaf_at(link), at, entering, t_max, skip);
                if open == 0 {
                    return rays;
                }
            }
        }
        rays & !open
    }

    /// Which of the rays `rays` names one of a leaf's spheres other than `skip` blocks before
    /// `t_max`: per ray [`Bvh::leaf_blocks`]'s answer, the terms of each sphere that do not
    /// depend on the direction made once.
    #[inline(always)]
    fn leaf_blocks_packet<S: Simd>(
        simd: S,
        leaf: &Leaf,
        (origin, dirs): Rays<'_>,
        rays: u8,
        t_max: f32,
        skip: u32,
    ) -> u8 {
        let (inf, reach) = (F::<S>::splat(simd, f32::INFINITY), F::<S>::splat(simd, t_max));
        let o = splat3(simd, origin);
        let mut blocked = 0;
        // Plain loops, not iterator folds, which may not be inlined (see `leaf_blocks`).
        let mut base = 0;
        while base < WIDTH && rays & !blocked != 0 {
            let center = each3(|a| load(simd, &leaf.center[a], base));
            let (oc, r2, cc) = origin_terms(o, (center, load(simd, &leaf.radius, base)));
            let others =
                U::<S>::from_slice(simd, &leaf.ids[base..base + F::<S>::LEN]).simd_ne(U::<S>::splat(simd, skip));
            let mut each = rays & !blocked;
            while each != 0 {
                let i = each.trailing_zeros() as usize;
                each &= each - 1;
                let t = nearest_root(simd, oc, splat3(simd, dirs[i]), r2, cc, reach);
                if (t.simd_lt(inf) & others).any_true() {
                    blocked |= 1 << i;
                }
            }
            base += F::<S>::LEN;
        }
        blocked
    }
}

/// A ray's eight child bits spread one a byte, bit k to the lowest bit of byte 7 − k: the
/// eight copies the product makes, nine bits apart, never overlap, and copy 7 − k puts bit
/// k at bit 8 (7 − k) + 7.
#[inline(always)]
fn by_child(hit: u32) -> u64 {
    (u64::from(hit).wrapping_mul(0x8040_2010_0804_0201) >> 7) & 0x0101_0101_0101_0101
}

#[cfg(test)]
mod tests {
    use fearless_simd::{dispatch, prelude::*, Level};
    use glam::Vec3;
    use proptest::prelude::*;

    use super::{by_child, Bvh, Root, MEDIUM_STACK, PACKET, STACK};
    use crate::accel::{Aggregate, Origin};
    use crate::ray::{spawn_bound, spawn_ray};

    /// Unit directions from raw triples, a short one taken as +z.
    fn units(raw: &[[f32; 3]]) -> Vec<Vec3> {
        raw.iter()
            .map(|&d| Vec3::from(d).try_normalize().filter(|_| Vec3::from(d).length() > 1e-2).unwrap_or(Vec3::Z))
            .collect()
    }

    proptest! {
        /// On random scenes (overlapping, nested spheres), packets of up to eight rays from
        /// one origin, some on a sphere's surface with that sphere left out, some anywhere:
        /// the packet's answer for each ray is the single-ray traversal's, at the level's
        /// lanes and at 4, with every stack; and through the aggregate, a point's rays (some
        /// going in) answer as [`Aggregate::occluded`] answers each.
        #[test]
        fn a_packet_answers_as_its_rays_one_by_one(
            spheres in proptest::collection::vec((proptest::array::uniform3(-30.0f32..30.0), 0.05f32..4.0), 0..400),
            packets in proptest::collection::vec((
                proptest::array::uniform3(-40.0f32..40.0),
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
            for (k, (origin, raw, reach, seed)) in packets.iter().enumerate() {
                let dirs = units(raw);
                let all = ((1u16 << dirs.len()) - 1) as u8;
                let rays = (*seed as u8 & all).max(1);
                // Half the packets leave a sphere's surface, outwards along its normal there.
                let on = (!centers.is_empty() && seed & 1 << 8 != 0).then(|| (seed >> 9) as usize % centers.len());
                let (origin, skip, n) = match on {
                    Some(s) => {
                        let n = dirs[0];
                        (centers[s] + radii[s] * n, s as u32, n)
                    }
                    None => (Vec3::from(*origin), crate::surface::NO_OBJECT, Vec3::Z),
                };
                for level in [crate::simd::level(), Level::baseline()] {
                    let (packet, one, stacks) = dispatch!(level, simd => simd.vectorize(|| {
                        let one = (0..dirs.len()).fold(0u8, |m, i| {
                            let ray = crate::ray::Ray { origin, dir: dirs[i] };
                            m | u8::from(rays >> i & 1 != 0 && bvh.occluded_in(simd, &ray, *reach, skip)) << i
                        });
                        // The stacks of deeper trees, on a tree with interior nodes.
                        let stacks = if matches!(bvh.root, Root::Node) { [
                            bvh.packet_with::<_, MEDIUM_STACK>(simd, (origin, &dirs), rays, *reach, skip),
                            bvh.packet_with::<_, STACK>(simd, (origin, &dirs), rays, *reach, skip),
                        ] } else { [one; 2] };
                        (bvh.occluded_packet_in(simd, (origin, &dirs), rays, *reach, skip), one, stacks)
                    }));
                    prop_assert_eq!(packet, one, "packet {}, rays {:08b}, {:?}", k, rays, level);
                    prop_assert_eq!(stacks, [one; 2], "packet {}: the medium and long stacks", k);
                }
                if matches!(bvh.root, Root::Node) {
                    let one = bvh_one(&bvh, origin, &dirs, rays, *reach, skip);
                    prop_assert_eq!(bvh.packet_deep((origin, &dirs), rays, *reach, skip), one, "packet {}: out of line", k);
                }
                if let Some(s) = on {
                    let (p, s) = (origin, s as u32);
                    let want = (0..dirs.len()).fold(0u8, |m, i| {
                        let ray = spawn_ray(p, n, dirs[i]);
                        m | u8::from(aggregate.occluded(&ray, *reach, Origin::Surface { sphere: s, normal: n })) << i
                    });
                    prop_assert_eq!(aggregate.occluded_from(s, (p, n), &dirs, *reach), want, "packet {} from sphere {}", k, s);
                }
            }
        }
    }

    /// The single-ray answers of the rays `rays` names, as a packet's bits.
    fn bvh_one(bvh: &Bvh, origin: Vec3, dirs: &[Vec3], rays: u8, reach: f32, skip: u32) -> u8 {
        (0..dirs.len()).fold(0u8, |m, i| {
            let ray = crate::ray::Ray { origin, dir: dirs[i] };
            m | u8::from(rays >> i & 1 != 0 && bvh.occluded(&ray, reach, skip)) << i
        })
    }

    #[test]
    fn a_rays_child_bits_spread_one_a_byte() {
        for hit in 0..256u32 {
            let want = (0..8).filter(|k| hit >> k & 1 != 0).fold(0u64, |w, k| w | 1 << (8 * (7 - k)));
            assert_eq!(by_child(hit), want, "hit {hit:08b}");
        }
    }
}
