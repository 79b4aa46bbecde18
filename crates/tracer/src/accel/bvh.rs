//! An 8-wide bounding-volume hierarchy over the spheres, with 8-sphere SIMD leaves.
//!
//! Built from scratch each frame (a revolving sphere moves; for a thousand spheres the
//! build takes well under a millisecond) into buffers reused from frame to frame. The tree
//! is first split in two at every level by the binned surface-area heuristic (median split
//! as a fallback), then collapsed into nodes of up to eight children (Wald et al. 2008,
//! "Getting rid of packets"; Dammertz et al. 2008, "Shallow bounding volume hierarchies";
//! Embree's BVH8): a node keeps its children's boxes in structure-of-arrays lanes, so one
//! ray meets all eight boxes in one slab test of `fearless_simd`'s `f32x8` (one AVX2
//! instruction per step at the 8-lane level, two 4-lane halves at the fallback level, at
//! the level `simd.rs` chose), and a thousand spheres are ~3 levels deep instead of ~8.
//! Leaves hold up to eight spheres in structure-of-arrays lanes, tested against a ray in the
//! lane kernels' own arithmetic (`simd.rs`'s `spheres_t`): one 8-lane test with AVX2, two
//! 4-lane halves at the fallback. The closest of a leaf's hits is found in the lanes too (a
//! horizontal minimum, the lowest lane on a tie, as a scan in lane order would pick), not
//! lane by lane. A scene of eight spheres or fewer is one leaf: a flat SIMD loop. An eye's
//! primary rays (`Bvh::first_hit_in`, and the packets of `first.rs`) take of equal `t` the
//! lowest sphere id instead, as the screen bins do, whatever leaf each sphere is in.
//!
//! The closest-hit traversal tests the leaves among the children a node's ray enters at
//! once, visits the interior ones nearest first, and drops any whose entry lies beyond the
//! closest hit so far. The lane kernels call it inside their own dispatched function
//! ([`Bvh::intersect_in`]); other callers through [`Bvh::intersect`], which dispatches.
//! [`Bvh::intersect_one`] tests a single sphere through the same lane arithmetic, so the
//! `t` it reports for a sphere is bit-for-bit the one the closest-hit query reports (what
//! `stereo`'s exact mode relies on); both equal the scalar [`crate::intersect_sphere`],
//! and a ray's `t` for a sphere does not depend on the `t_max` it is tested with (a
//! nearer bound only turns a farther root into a miss), so testing a leaf with the closest
//! hit so far as its bound finds what a test of every sphere would.
//! The collapse keeps the binary tree's boxes and only skips levels, so every sphere the
//! binary traversal would reach is still reached: the answer is the same.

#![expect(
    clippy::inline_always,
    reason = "the traversal is inlined into the dispatched lane kernels, whose target features it needs"
)]

use fearless_simd::{dispatch, f32x8, prelude::*, u32x8, Simd};

use crate::ray::Ray;
use crate::simd::{each3, spheres_t};
use crate::surface::Hit;

mod ahead;
mod build;
mod first;
mod shared;
mod slab;

use build::BinNode;
pub(crate) use first::{EyeRays, Nearest, EYE_PACKET};
pub(crate) use shared::{Packet, PACKET};
use slab::BoxRay;

/// Children per node, and spheres per leaf.
const WIDTH: usize = 8;
/// Binary levels split by the surface-area heuristic; below them the median split takes
/// over, which bounds the depth at `SAH_LEVELS` + log2(spheres) < 56 whatever the scene.
const SAH_LEVELS: usize = 24;
/// Traversal stack depth: a node pushes at most seven interior children besides the one
/// visited next (leaves are tested where they are met), and no path has more than 56 nodes.
const STACK: usize = (WIDTH - 1) * 56 + 1;
/// Deepest tree (in 8-wide levels) traversed with the short stack [`SHALLOW_STACK`]; a
/// cloud of a thousand spheres is well within it (the tests check). The stack is cleared
/// for every ray, and the long one's 3 kB would cost a `memset` call per ray.
const SHALLOW_DEPTH: usize = 6;
/// Stack for trees up to [`SHALLOW_DEPTH`] levels.
const SHALLOW_STACK: usize = (WIDTH - 1) * SHALLOW_DEPTH + 1;
/// Deepest tree traversed inline with the medium stack [`MEDIUM_STACK`]: millions of
/// spheres (a virus capsid's atoms) are 8 to 10 levels deep.
const MEDIUM_DEPTH: usize = 12;
/// Stack for trees up to [`MEDIUM_DEPTH`] levels.
const MEDIUM_STACK: usize = (WIDTH - 1) * MEDIUM_DEPTH + 1;
/// Spheres up to which the build keeps its scratch (the binary tree, the item list) from
/// frame to frame, so that a scene whose spheres move rebuilds without allocating; a larger
/// scene is still and built once, and gives the memory back.
const KEEP_SCRATCH: usize = 1 << 16;

/// A node of the traversed tree: up to eight children, their boxes in SIMD lanes.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Node {
    /// The children's boxes: `bounds[0]` the minimum corners, `bounds[1]` the maximum, one
    /// lane per child for each axis.
    bounds: [[[f32; WIDTH]; 3]; 2],
    /// Per lane: the child, as a [`Link`].
    child: [Link; WIDTH],
    /// Bit k set when lane k holds a child.
    lanes: u32,
}

impl Node {
    const EMPTY: Self = Self { bounds: [[[0.0; WIDTH]; 3]; 2], child: [0; WIDTH], lanes: 0 };
}

/// A leaf: up to eight spheres in structure-of-arrays lanes. Unused lanes have NaN centres,
/// which never hit, and the id `u32::MAX`.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Leaf {
    center: [[f32; WIDTH]; 3],
    radius: [f32; WIDTH],
    ids: [u32; WIDTH],
}

impl Leaf {
    const EMPTY: Self = Self { center: [[f32::NAN; WIDTH]; 3], radius: [0.0; WIDTH], ids: [u32::MAX; WIDTH] };

    /// Each sphere's `t` (+∞ where it misses or lies outside `(0, t_max)`), in lane order,
    /// and the spheres' ids: the eight lanes at once, at every level.
    #[inline(always)]
    fn hits<S: Simd>(&self, simd: S, (o, d): LaneRay<S>, t_max: f32) -> (f32x8<S>, u32x8<S>) {
        let center = each3(|a| f32x8::from_slice(simd, &self.center[a]));
        let radius = f32x8::from_slice(simd, &self.radius);
        let t = spheres_t(simd, o, d, (center, radius), f32x8::splat(simd, t_max));
        (t, u32x8::from_slice(simd, &self.ids))
    }
}

/// A ray splatted across a leaf's eight lanes: its origin and unit direction.
type LaneRay<S> = ([f32x8<S>; 3], [f32x8<S>; 3]);

/// [`LaneRay`] of `ray`.
#[inline(always)]
fn splat_ray<S: Simd>(simd: S, ray: &Ray) -> LaneRay<S> {
    let splat = |v: glam::Vec3| each3(|a| f32x8::splat(simd, v[a]));
    (splat(ray.origin), splat(ray.dir))
}

/// Where traversal starts.
#[derive(Clone, Copy, Debug, Default)]
enum Root {
    /// No spheres.
    #[default]
    Empty,
    /// The whole scene is one leaf, `leaves[0]`.
    Leaf,
    /// `nodes[0]`.
    Node,
}

/// The hierarchy. Empty until [`Bvh::build`].
#[derive(Clone, Debug, Default)]
pub(crate) struct Bvh {
    root: Root,
    nodes: Vec<Node>,
    leaves: Vec<Leaf>,
    items: Vec<u32>,
    /// Levels of 8-wide nodes on the longest path from the root (0 unless `Root::Node`).
    depth: usize,
    /// Scratch: the binary build tree.
    bin: Vec<BinNode>,
}

/// A child of a node in one word: an interior node's index, or [`LEAF`] | a leaf's index.
/// Scenes stay far below the 2³¹ leaves this leaves room for.
type Link = u32;
/// Marks a [`Link`] to a leaf.
const LEAF: Link = 1 << 31;

/// The link to leaf `index`.
fn leaf_link(index: u32) -> Link {
    debug_assert!(index < LEAF, "leaf {index} does not fit a link");
    LEAF | index
}

/// A closest-hit traversal stack entry: an interior node and where the ray enters it.
/// Eight bytes, so the stack a ray starts with is cheap to clear.
#[derive(Clone, Copy, Debug, Default)]
struct Entry {
    link: Link,
    near: f32,
}

/// Pushes `entry` on `stack[..sp]`, keeping the entries from `base` up (one node's children)
/// sorted farthest first by `near` (an insertion sort of at most eight), so that the nearest
/// is popped next; returns the new top.
#[inline(always)]
fn push_sorted<T: Copy>(stack: &mut [T], base: usize, sp: usize, entry: T, near: impl Fn(&T) -> f32) -> usize {
    let mut k = sp;
    while k > base && near(&stack[k - 1]) < near(&entry) {
        stack[k] = stack[k - 1];
        k -= 1;
    }
    stack[k] = entry;
    sp + 1
}

impl Bvh {
    /// Heap bytes held (capacities).
    pub(crate) fn heap_bytes(&self) -> usize {
        use crate::stats::heap;
        heap(&self.nodes) + heap(&self.leaves) + heap(&self.items) + heap(&self.bin)
    }
    /// Hit parameter in `(0, ∞)` of the ray against sphere `k` alone (a test oracle).
    #[cfg(test)]
    pub(crate) fn intersect_one(&self, ray: &Ray, k: u32) -> Option<f32> {
        fn lane_t<S: Simd>(simd: S, leaf: &Leaf, ray: &Ray, lane: usize) -> f32 {
            leaf.hits(simd, splat_ray(simd, ray), f32::INFINITY).0.as_slice()[lane]
        }
        let (leaf, lane) = self
            .leaves
            .iter()
            .find_map(|leaf| leaf.ids.iter().position(|&id| id == k).map(|lane| (leaf, lane)))
            .expect("every sphere is in a leaf");
        let t = dispatch!(crate::simd::level(), simd => lane_t(simd, leaf, ray, lane));
        t.is_finite().then_some(t)
    }

    /// The leaf a [`Link`] names.
    #[inline(always)]
    fn leaf_at(&self, link: Link) -> &Leaf {
        &self.leaves[(link & !LEAF) as usize]
    }

    /// Narrows `(t_best, best)` to the closest hit among a leaf's spheres other than `skip`:
    /// the smallest `t`, and of equal ones the lowest lane; with `LOWEST_ID`, a hit at
    /// `t_best` itself too, and of equal `t` the lowest sphere id, here and against `best`.
    #[inline(always)]
    fn leaf_closest<S: Simd, const LOWEST_ID: bool>(
        simd: S,
        leaf: &Leaf,
        ray: LaneRay<S>,
        skip: u32,
        t_best: &mut f32,
        best: &mut Option<u32>,
    ) {
        // `t < next_up(t_best)` is `t ≤ t_best` (and +∞ stays +∞).
        let bound = if LOWEST_ID { t_best.next_up() } else { *t_best };
        Self::narrow::<S, LOWEST_ID>(simd, leaf, leaf.hits(simd, ray, bound), skip, t_best, best);
    }

    /// [`Bvh::leaf_closest`] with a leaf's `t` (each below the bound it asks for) and ids
    /// made: the packets' (`first.rs`) make them apart.
    #[inline(always)]
    fn narrow<S: Simd, const LOWEST_ID: bool>(
        simd: S,
        leaf: &Leaf,
        (t, ids): (f32x8<S>, u32x8<S>),
        skip: u32,
        t_best: &mut f32,
        best: &mut Option<u32>,
    ) {
        let inf = f32x8::splat(simd, f32::INFINITY);
        // Every finite `t` is below the test's bound.
        let t = ids.simd_eq(u32x8::splat(simd, skip)).select(inf, t);
        if t.simd_lt(inf).any_true() {
            let nearest = t.reduce_min();
            let at = t.simd_eq(f32x8::splat(simd, nearest)).to_bitmask();
            if !LOWEST_ID {
                (*t_best, *best) = (nearest, Some(leaf.ids[at.trailing_zeros() as usize]));
                return;
            }
            let id = crate::bits::ones(&[at]).map(|l| leaf.ids[l as usize]).min();
            let tie = |id| nearest == *t_best && best.is_none_or(|b| id < b);
            if let Some(id) = id.filter(|&id| nearest < *t_best || tie(id)) {
                (*t_best, *best) = (nearest, Some(id));
            }
        }
    }

    /// Whether any of a leaf's spheres other than `skip` is hit before `t_max`.
    #[inline(always)]
    fn leaf_blocks<S: Simd>(simd: S, leaf: &Leaf, ray: LaneRay<S>, t_max: f32, skip: u32) -> bool {
        let (t, ids) = leaf.hits(simd, ray, t_max);
        (t.simd_lt(f32x8::splat(simd, f32::INFINITY)) & ids.simd_ne(u32x8::splat(simd, skip))).any_true()
    }

    /// Closest hit in `(0, t_max)` among the spheres other than `skip` (`NO_OBJECT`: none
    /// left out), at the lanes `simd.rs` chose.
    #[cfg(test)]
    pub(crate) fn intersect(&self, ray: &Ray, t_max: f32, skip: u32) -> Option<Hit> {
        dispatch!(crate::simd::level(), simd => simd.vectorize(
            #[inline(always)]
            || self.intersect_in(simd, ray, t_max, skip),
        ))
    }

    /// [`Bvh::intersect`] inside a function dispatched at `simd`'s level (a lane kernel).
    #[inline(always)]
    pub(crate) fn intersect_in<S: Simd>(&self, simd: S, ray: &Ray, t_max: f32, skip: u32) -> Option<Hit> {
        self.closest_in::<S, false>(simd, ray, t_max, skip)
    }

    /// The closest hit in `(0, ∞)` of a ray from anywhere, of equal `t` the lowest sphere
    /// id, as a scan of every sphere in id order finds it: the first hit of a primary ray
    /// as the screen bins (`screen.rs`) find it, bit for bit, inside a lane kernel.
    #[cfg(test)]
    #[inline(always)]
    pub(crate) fn first_hit_in<S: Simd>(&self, simd: S, ray: &Ray) -> Option<Hit> {
        self.closest_in::<S, true>(simd, ray, f32::INFINITY, crate::surface::NO_OBJECT)
    }

    /// The closest hit, ties broken as `LOWEST_ID` says ([`Bvh::leaf_closest`]).
    #[inline(always)]
    fn closest_in<S: Simd, const LOWEST_ID: bool>(&self, simd: S, ray: &Ray, t_max: f32, skip: u32) -> Option<Hit> {
        if self.depth <= SHALLOW_DEPTH {
            self.intersect_with::<S, SHALLOW_STACK, LOWEST_ID>(simd, ray, t_max, skip)
        } else if self.depth <= MEDIUM_DEPTH {
            self.intersect_with::<S, MEDIUM_STACK, LOWEST_ID>(simd, ray, t_max, skip)
        } else {
            self.intersect_deep::<LOWEST_ID>(ray, t_max, skip)
        }
    }

    /// [`Bvh::intersect`] of a tree deeper than [`SHALLOW_DEPTH`] (rare: a lopsided scene),
    /// out of line so the kernels inline only the short stack's traversal.
    #[inline(never)]
    fn intersect_deep<const LOWEST_ID: bool>(&self, ray: &Ray, t_max: f32, skip: u32) -> Option<Hit> {
        dispatch!(crate::simd::level(), simd => simd.vectorize(
            #[inline(always)]
            || self.intersect_with::<_, STACK, LOWEST_ID>(simd, ray, t_max, skip),
        ))
    }

    /// [`Bvh::intersect`] with a traversal stack of `N` entries, `N` > 7 × `self.depth`.
    #[inline(always)]
    fn intersect_with<S: Simd, const N: usize, const LOWEST_ID: bool>(
        &self,
        simd: S,
        ray: &Ray,
        t_max: f32,
        skip: u32,
    ) -> Option<Hit> {
        let lane_ray = splat_ray(simd, ray);
        let (mut t_best, mut best) = (t_max, None);
        match self.root {
            Root::Empty => return None,
            Root::Leaf => {
                // A small scene is one leaf: its lanes are the whole test, no box needed.
                Self::leaf_closest::<S, LOWEST_ID>(simd, &self.leaves[0], lane_ray, skip, &mut t_best, &mut best);
                return best.map(|object| Hit { t: t_best, object });
            }
            Root::Node => {}
        }
        let br = BoxRay::new(simd, ray);
        let mut stack = [Entry::default(); N];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let e = stack[sp];
            // Entered beyond a hit found since it was pushed: nothing in it is nearer.
            if e.near > t_best {
                continue;
            }
            // Only interior nodes are pushed (leaves are tested where they are met), the
            // root first.
            let node = &self.nodes[e.link as usize];
            let (near, mut hit) = br.enter(node, t_best);
            let near = near.as_slice();
            // Leaves entered are tested at once (cheaper than a trip through the stack);
            // interior children go on the stack sorted farthest first (insertion sort of
            // ≤ 8), so the nearest is visited next.
            let base = sp;
            while hit != 0 {
                let lane = hit.trailing_zeros() as usize;
                hit &= hit - 1;
                let entry = Entry { link: node.child[lane], near: near[lane] };
                if entry.link & LEAF != 0 {
                    let leaf = self.leaf_at(entry.link);
                    Self::leaf_closest::<S, LOWEST_ID>(simd, leaf, lane_ray, skip, &mut t_best, &mut best);
                    continue;
                }
                sp = push_sorted(&mut stack, base, sp, entry, |e| e.near);
            }
        }
        best.map(|object| Hit { t: t_best, object })
    }

    /// Whether any sphere other than `skip` blocks the ray before `t_max` (early exit).
    #[cfg(test)]
    pub(crate) fn occluded(&self, ray: &Ray, t_max: f32, skip: u32) -> bool {
        dispatch!(crate::simd::level(), simd => simd.vectorize(
            #[inline(always)]
            || self.occluded_in(simd, ray, t_max, skip),
        ))
    }

    /// [`Bvh::occluded`] inside a function dispatched at `simd`'s level (a lane kernel).
    #[inline(always)]
    pub(crate) fn occluded_in<S: Simd>(&self, simd: S, ray: &Ray, t_max: f32, skip: u32) -> bool {
        if self.depth <= SHALLOW_DEPTH {
            self.occluded_with::<S, SHALLOW_STACK>(simd, ray, t_max, skip)
        } else if self.depth <= MEDIUM_DEPTH {
            self.occluded_with::<S, MEDIUM_STACK>(simd, ray, t_max, skip)
        } else {
            self.occluded_deep(ray, t_max, skip)
        }
    }

    /// [`Bvh::occluded`] of a tree deeper than [`MEDIUM_DEPTH`], out of line.
    #[inline(never)]
    fn occluded_deep(&self, ray: &Ray, t_max: f32, skip: u32) -> bool {
        dispatch!(crate::simd::level(), simd => simd.vectorize(
            #[inline(always)]
            || self.occluded_with::<_, STACK>(simd, ray, t_max, skip),
        ))
    }

    /// [`Bvh::occluded`] with a traversal stack of `N` entries, `N` > 7 × `self.depth`.
    #[inline(always)]
    fn occluded_with<S: Simd, const N: usize>(&self, simd: S, ray: &Ray, t_max: f32, skip: u32) -> bool {
        let lane_ray = splat_ray(simd, ray);
        match self.root {
            Root::Empty => return false,
            Root::Leaf => return Self::leaf_blocks(simd, &self.leaves[0], lane_ray, t_max, skip),
            Root::Node => {}
        }
        let br = BoxRay::new(simd, ray);
        let mut stack = [0u32; N];
        let mut sp = 1;
        while sp > 0 {
            sp -= 1;
            let node = &self.nodes[stack[sp] as usize];
            let (_, mut hit) = br.enter(node, t_max);
            while hit != 0 {
                let lane = hit.trailing_zeros() as usize;
                hit &= hit - 1;
                let link = node.child[lane];
                if link & LEAF != 0 {
                    if Self::leaf_blocks(simd, self.leaf_at(link), lane_ray, t_max, skip) {
                        return true;
                    }
                } else {
                    stack[sp] = link;
                    sp += 1;
                }
            }
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use super::*;
    use crate::sphere::intersect_sphere;
    use crate::surface::NO_OBJECT;

    /// A deterministic cloud of spheres.
    fn cloud(n: usize) -> (Vec<Vec3>, Vec<f32>) {
        let mut rng = crate::testing::XorShift::new(0x2545_F491);
        let centers =
            (0..n).map(|_| Vec3::new(rng.range(-20.0, 20.0), rng.range(-10.0, 10.0), rng.range(5.0, 65.0))).collect();
        let radii = (0..n).map(|_| rng.range(0.2, 1.7)).collect();
        (centers, radii)
    }

    /// The closest hit among all spheres but `skip`, one by one.
    fn brute(ray: &Ray, t_max: f32, centers: &[Vec3], radii: &[f32], skip: u32) -> Option<Hit> {
        let mut best = None;
        let mut t_best = t_max;
        for (k, (&c, &r)) in centers.iter().zip(radii).enumerate() {
            if k as u32 == skip {
                continue;
            }
            if let Some(t) = intersect_sphere(ray, c, r, t_best) {
                (t_best, best) = (t, Some(Hit { t, object: k as u32 }));
            }
        }
        best
    }

    #[test]
    fn matches_brute_force_bit_for_bit() {
        for n in [1, 3, 4, 5, 8, 9, 17, 33, 300, 1000] {
            let (centers, radii) = cloud(n);
            let mut bvh = Bvh::default();
            bvh.build(&centers, &radii);
            // Clouds this size take the short stack (the lopsided test below, the long one).
            assert!(bvh.depth <= SHALLOW_DEPTH, "n = {n}: depth {}", bvh.depth);
            for k in 0..2000 {
                let a = k as f32 * 0.618_034;
                let dir = Vec3::new((a * 7.3).sin() * 0.6, (a * 3.1).cos() * 0.35, 1.0).normalize();
                let ray = Ray::new(Vec3::new(0.0, 0.0, -2.0), dir);
                let got = bvh.intersect(&ray, f32::INFINITY, NO_OBJECT);
                let want = brute(&ray, f32::INFINITY, &centers, &radii, NO_OBJECT);
                assert_eq!(
                    got.map(|h| (h.t.to_bits(), h.object)),
                    want.map(|h| (h.t.to_bits(), h.object)),
                    "n = {n}, ray {k}"
                );
                // Leaving out the sphere hit (as for a ray leaving it outwards) gives the
                // next one behind it, and leaves the occlusion answer to the others.
                if let Some(first) = want {
                    let skip = first.object;
                    let behind = brute(&ray, f32::INFINITY, &centers, &radii, skip);
                    let got = bvh.intersect(&ray, f32::INFINITY, skip);
                    assert_eq!(got.map(|h| (h.t.to_bits(), h.object)), behind.map(|h| (h.t.to_bits(), h.object)));
                    let blocked = brute(&ray, 30.0, &centers, &radii, skip).is_some();
                    assert_eq!(bvh.occluded(&ray, 30.0, skip), blocked, "n = {n}, ray {k}, skipping {skip}");
                }
                for s in 0..n as u32 {
                    let one = bvh.intersect_one(&ray, s).map(f32::to_bits);
                    let scalar = intersect_sphere(&ray, centers[s as usize], radii[s as usize], f32::INFINITY);
                    assert_eq!(one, scalar.map(f32::to_bits), "n = {n}, ray {k}, sphere {s}");
                }
                let blocked = brute(&ray, 30.0, &centers, &radii, NO_OBJECT).is_some();
                assert_eq!(bvh.occluded(&ray, 30.0, NO_OBJECT), blocked, "n = {n}, ray {k}");
            }
        }
    }

    #[test]
    fn first_hits_take_of_equal_t_the_lowest_id_at_both_lane_widths() {
        // Copies of spheres (equal `t`, other ids) among a cloud: the nearest hit, of equal
        // `t` the lowest id, as a scan in id order keeps the first; at 8 lanes (a leaf in one
        // test) and at the 4-lane baseline (a leaf in two halves).
        let (mut centers, mut radii) = cloud(300);
        for k in (0..300).step_by(5) {
            let at = (k * 7) % centers.len();
            let (c, r) = (centers[k], radii[k]);
            centers.insert(at, c);
            radii.insert(at, r);
        }
        let mut bvh = Bvh::default();
        bvh.build(&centers, &radii);
        let (mut ties, mut hits) = (0, 0);
        for k in 0..3000 {
            let a = k as f32 * 0.618_034;
            let dir = Vec3::new((a * 7.3).sin() * 0.6, (a * 3.1).cos() * 0.35, 1.0).normalize();
            let ray = Ray::new(Vec3::new(0.0, 0.0, -2.0), dir);
            let mut want: Option<(u32, u32)> = None;
            for (id, (&c, &r)) in centers.iter().zip(&radii).enumerate() {
                let t = intersect_sphere(&ray, c, r, f32::INFINITY);
                if let Some(t) = t.filter(|&t| want.is_none_or(|(b, _)| t < f32::from_bits(b))) {
                    want = Some((t.to_bits(), id as u32));
                }
            }
            let key = |h: Option<Hit>| h.map(|h| (h.t.to_bits(), h.object));
            let wide = dispatch!(crate::simd::level(), simd => simd.vectorize(|| bvh.first_hit_in(simd, &ray)));
            let narrow =
                dispatch!(fearless_simd::Level::baseline(), simd => simd.vectorize(|| bvh.first_hit_in(simd, &ray)));
            assert_eq!((key(wide), key(narrow)), (want, want), "ray {k}: lanes of the level, then 4");
            hits += usize::from(want.is_some());
            ties += usize::from(want.is_some_and(|(t, id)| {
                centers.iter().zip(&radii).enumerate().any(|(o, (&c, &r))| {
                    o as u32 != id && intersect_sphere(&ray, c, r, f32::INFINITY).map(f32::to_bits) == Some(t)
                })
            }));
        }
        assert!(hits > 1000 && ties > 50, "{hits} hits, {ties} ties");
    }

    #[test]
    fn a_lopsided_scene_stays_within_the_stack() {
        // Spheres at doubling distances along a line: each binned-SAH split peels off only
        // the last few, so the heuristic alone would build a chain; the median split below
        // `SAH_LEVELS` must cap the depth (which bounds the traversal stack).
        let n = 120;
        let centers: Vec<Vec3> = (0..n).map(|k| Vec3::new(2f32.powi(k), 0.0, 0.0)).collect();
        let radii: Vec<f32> = (0..n).map(|k| 2f32.powi(k) * 0.01).collect();
        let mut bvh = Bvh::default();
        bvh.build(&centers, &radii);
        let depth = bvh.bin_depth(0);
        assert!(depth <= SAH_LEVELS + (n as f32).log2().ceil() as usize + 1, "depth {depth}");
        assert!(bvh.depth <= SAH_LEVELS + 7, "depth {} in 8-wide levels", bvh.depth);
        for k in 0..200 {
            let a = k as f32 * 1e-4;
            let ray = Ray::new(Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, a.sin(), a.cos() * 1e-3).normalize());
            let got = bvh.intersect(&ray, f32::INFINITY, NO_OBJECT);
            let want = brute(&ray, f32::INFINITY, &centers, &radii, NO_OBJECT);
            assert_eq!(got.map(|h| (h.t.to_bits(), h.object)), want.map(|h| (h.t.to_bits(), h.object)), "ray {k}");
            // The long stack's traversal, which trees deeper than `SHALLOW_DEPTH` take.
            let deep = bvh.intersect_deep::<false>(&ray, f32::INFINITY, NO_OBJECT);
            assert_eq!(deep.map(|h| (h.t.to_bits(), h.object)), want.map(|h| (h.t.to_bits(), h.object)), "ray {k}");
            assert_eq!(bvh.occluded(&ray, 1e30, NO_OBJECT), want.is_some(), "ray {k}");
            assert_eq!(bvh.occluded_deep(&ray, 1e30, NO_OBJECT), want.is_some(), "ray {k}: the long stack");
            // The medium stack's, which trees deeper than `SHALLOW_DEPTH` take up to
            // `MEDIUM_DEPTH` levels.
            if bvh.depth <= MEDIUM_DEPTH {
                let (hit, blocked) = dispatch!(crate::simd::level(), simd => simd.vectorize(|| (
                    bvh.intersect_with::<_, MEDIUM_STACK, false>(simd, &ray, f32::INFINITY, NO_OBJECT),
                    bvh.occluded_with::<_, MEDIUM_STACK>(simd, &ray, 1e30, NO_OBJECT),
                )));
                let key = |h: Option<Hit>| h.map(|h| (h.t.to_bits(), h.object));
                assert_eq!((key(hit), blocked), (key(want), want.is_some()), "ray {k}: the medium stack");
            }
        }
    }

    /// A tree's nodes and leaves as bits: what two builds must agree on.
    fn tree_bits(bvh: &Bvh) -> (Vec<u32>, Vec<u32>) {
        let nodes = bvh
            .nodes
            .iter()
            .flat_map(|n| n.bounds.iter().flatten().flatten().map(|x| x.to_bits()).chain(n.child).chain([n.lanes]));
        let leaves = bvh
            .leaves
            .iter()
            .flat_map(|l| l.center.iter().flatten().chain(&l.radius).map(|x| x.to_bits()).chain(l.ids));
        (nodes.collect(), leaves.collect())
    }

    proptest::proptest! {
        /// On random scenes (overlapping, nested and repeated spheres) and incoherent rays,
        /// some from inside the cloud: the closest hit, the first hit (of equal `t` the lowest
        /// id), and the any-hit answer with a short or long reach and a sphere left out, all
        /// as a scan of every sphere gives them, at the level's lanes and at 4; and a second
        /// build of the same spheres is the same tree, bit for bit.
        #[test]
        fn every_query_is_a_scan_of_every_sphere(
            spheres in proptest::collection::vec((proptest::array::uniform3(-30.0f32..30.0), 0.05f32..4.0), 0..400),
            repeat in 0usize..4,
            rays in proptest::collection::vec(
                (proptest::array::uniform3(-40.0f32..40.0), proptest::array::uniform3(-1.0f32..1.0), 0.5f32..80.0),
                1..40,
            ),
        ) {
            let (mut centers, mut radii): (Vec<Vec3>, Vec<f32>) =
                spheres.iter().map(|&(c, r)| (Vec3::from(c), r)).unzip();
            for k in (0..centers.len()).step_by(repeat + 3).take(repeat * 5) {
                centers.push(centers[k]);
                radii.push(radii[k]);
            }
            let mut bvh = Bvh::default();
            bvh.build(&centers, &radii);
            let mut again = Bvh::default();
            again.build(&centers, &radii);
            proptest::prop_assert!(tree_bits(&bvh) == tree_bits(&again), "the build is deterministic");
            let key = |h: Option<Hit>| h.map(|h| (h.t.to_bits(), h.object));
            for (k, &(o, d, reach)) in rays.iter().enumerate() {
                let d = Vec3::from(d);
                proptest::prop_assume!(d.length() > 1e-2);
                let ray = Ray::new(Vec3::from(o), d.normalize());
                let skip = (k % (centers.len() + 1)) as u32;
                let skip = if skip as usize == centers.len() { NO_OBJECT } else { skip };
                // The closest hit: its `t`, and a sphere hit there (of equal `t`, any).
                let closest = brute(&ray, f32::INFINITY, &centers, &radii, skip);
                let got = bvh.intersect(&ray, f32::INFINITY, skip);
                proptest::prop_assert_eq!(got.map(|h| h.t.to_bits()), closest.map(|h| h.t.to_bits()));
                if let Some(h) = got {
                    let own = intersect_sphere(&ray, centers[h.object as usize], radii[h.object as usize], f32::INFINITY);
                    proptest::prop_assert!(h.object != skip && own == Some(h.t), "sphere {} is hit at {}", h.object, h.t);
                }
                let blocked = brute(&ray, reach, &centers, &radii, skip).is_some();
                proptest::prop_assert_eq!(bvh.occluded(&ray, reach, skip), blocked, "reach {}", reach);
                let mut first: Option<(u32, u32)> = None;
                for (id, (&c, &r)) in centers.iter().zip(&radii).enumerate() {
                    let t = intersect_sphere(&ray, c, r, f32::INFINITY);
                    if let Some(t) = t.filter(|&t| first.is_none_or(|(b, _)| t < f32::from_bits(b))) {
                        first = Some((t.to_bits(), id as u32));
                    }
                }
                let (wide, narrow) = (
                    dispatch!(crate::simd::level(), simd => simd.vectorize(|| (
                        bvh.first_hit_in(simd, &ray), bvh.occluded_in(simd, &ray, reach, skip),
                    ))),
                    dispatch!(fearless_simd::Level::baseline(), simd => simd.vectorize(|| (
                        bvh.first_hit_in(simd, &ray), bvh.occluded_in(simd, &ray, reach, skip),
                    ))),
                );
                proptest::prop_assert_eq!((key(wide.0), wide.1), (first, blocked), "the level's lanes");
                proptest::prop_assert_eq!((key(narrow.0), narrow.1), (first, blocked), "4 lanes");
            }
        }
    }

    #[test]
    fn one_sphere_is_a_leaf_at_the_root() {
        let mut bvh = Bvh::default();
        bvh.build(&[Vec3::new(0.0, 0.0, 5.0)], &[1.0]);
        assert!(matches!(bvh.root, Root::Leaf));
        let hit = bvh.intersect(&Ray::new(Vec3::ZERO, Vec3::Z), f32::INFINITY, NO_OBJECT);
        assert_eq!(hit.map(|h| (h.t, h.object)), Some((4.0, 0)));
        assert_eq!(bvh.intersect(&Ray::new(Vec3::ZERO, Vec3::Z), f32::INFINITY, 0), None, "left out");
        assert!(bvh.occluded(&Ray::new(Vec3::ZERO, Vec3::Z), 4.5, NO_OBJECT));
        assert!(!bvh.occluded(&Ray::new(Vec3::ZERO, Vec3::Z), 3.5, NO_OBJECT), "beyond the reach");
        assert!(!bvh.occluded(&Ray::new(Vec3::ZERO, Vec3::X), f32::INFINITY, NO_OBJECT));
    }

    #[test]
    fn rebuild_reuses_and_handles_empty() {
        let mut bvh = Bvh::default();
        bvh.build(&[], &[]);
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        assert_eq!(bvh.intersect(&ray, f32::INFINITY, NO_OBJECT), None);
        assert!(!bvh.occluded(&ray, f32::INFINITY, NO_OBJECT));
        let (c, r) = cloud(50);
        bvh.build(&c, &r);
        let cap = bvh.nodes.capacity();
        bvh.build(&c, &r);
        assert_eq!(bvh.nodes.capacity(), cap);
    }
}
