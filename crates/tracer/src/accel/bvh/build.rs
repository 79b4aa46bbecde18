//! Building the BVH: a binary tree by the binned surface-area heuristic (Wald 2007), median
//! splits below [`SAH_LEVELS`], then collapsed into the 8-wide nodes that are traversed
//! (see the parent module).

use glam::Vec3;

use super::{leaf_link, Bvh, Leaf, Node, Root, KEEP_SCRATCH, SAH_LEVELS, WIDTH};

/// A node of the binary build tree: a box, and either two children (`count == 0`: `first`
/// and `first + 1`) or a leaf (`count` > 0 spheres), `leaves[first]`.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct BinNode {
    min: Vec3,
    max: Vec3,
    first: u32,
    count: u32,
}

/// Bins per axis for the surface-area heuristic.
const BINS: usize = 12;

/// Surface area of a box (half of it: only ratios matter).
fn half_area(min: Vec3, max: Vec3) -> f32 {
    let d = (max - min).max(Vec3::ZERO);
    d.x * d.y + d.y * d.z + d.z * d.x
}

/// The best split by the binned surface-area heuristic (Wald 2007): `(axis, plane)` such
/// that spheres whose centre lies below `plane` on `axis` go left. Minimises
/// N_left·A_left + N_right·A_right over 11 planes per axis. For spheres spread through a
/// deep view this splits across the view rather than into depth slabs that every ray
/// would enter.
fn sah_split(items: &[u32], centers: &[Vec3], radii: &[f32], cmin: Vec3, cmax: Vec3) -> Option<(usize, f32)> {
    let mut best: Option<(f32, usize, f32)> = None;
    for axis in 0..3 {
        let (lo, hi) = (cmin[axis], cmax[axis]);
        if hi <= lo {
            continue;
        }
        let scale = BINS as f32 / (hi - lo);
        let mut count = [0u32; BINS];
        let mut bmin = [Vec3::INFINITY; BINS];
        let mut bmax = [Vec3::NEG_INFINITY; BINS];
        for &k in items {
            let (c, r) = (centers[k as usize], radii[k as usize]);
            let b = (((c[axis] - lo) * scale) as usize).min(BINS - 1);
            count[b] += 1;
            bmin[b] = bmin[b].min(c - r);
            bmax[b] = bmax[b].max(c + r);
        }
        // Sweep from the right: cost of everything at or above each bin.
        let mut right_cost = [0.0f32; BINS];
        let (mut n, mut mn, mut mx) = (0u32, Vec3::INFINITY, Vec3::NEG_INFINITY);
        for b in (1..BINS).rev() {
            n += count[b];
            mn = mn.min(bmin[b]);
            mx = mx.max(bmax[b]);
            right_cost[b] = n as f32 * half_area(mn, mx);
        }
        let (mut n, mut mn, mut mx) = (0u32, Vec3::INFINITY, Vec3::NEG_INFINITY);
        for b in 0..BINS - 1 {
            n += count[b];
            mn = mn.min(bmin[b]);
            mx = mx.max(bmax[b]);
            let cost = n as f32 * half_area(mn, mx) + right_cost[b + 1];
            if n > 0 && (n as usize) < items.len() && best.is_none_or(|(c, ..)| cost < c) {
                best = Some((cost, axis, lo + (b + 1) as f32 / scale));
            }
        }
    }
    best.map(|(_, axis, plane)| (axis, plane))
}

/// Moves the items satisfying `left` to the front; returns how many there are.
fn partition(items: &mut [u32], left: impl Fn(u32) -> bool) -> usize {
    let mut mid = 0;
    for i in 0..items.len() {
        if left(items[i]) {
            items.swap(i, mid);
            mid += 1;
        }
    }
    mid
}

impl Bvh {
    /// Rebuilds over the spheres `(centers[k], radii[k])`, reusing the buffers.
    pub(crate) fn build(&mut self, centers: &[Vec3], radii: &[f32]) {
        self.nodes.clear();
        self.leaves.clear();
        self.items.clear();
        self.bin.clear();
        self.depth = 0;
        self.items.extend(0..centers.len() as u32);
        if centers.is_empty() {
            self.root = Root::Empty;
            return;
        }
        self.bin.push(BinNode::default());
        let mut items = std::mem::take(&mut self.items);
        self.build_node(0, 0, &mut items, centers, radii);
        self.items = items;
        if self.bin[0].count > 0 {
            self.root = Root::Leaf;
        } else {
            self.root = Root::Node;
            self.collapse(0, 1);
        }
        if centers.len() > KEEP_SCRATCH {
            (self.bin, self.items) = (Vec::new(), Vec::new());
        }
    }

    /// Splits `items` into binary node `index`, at `level`, of the build tree.
    fn build_node(&mut self, index: usize, level: usize, items: &mut [u32], centers: &[Vec3], radii: &[f32]) {
        let (mut min, mut max) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        let (mut cmin, mut cmax) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        for &k in items.iter() {
            let (c, r) = (centers[k as usize], radii[k as usize]);
            min = min.min(c - r);
            max = max.max(c + r);
            cmin = cmin.min(c);
            cmax = cmax.max(c);
        }
        if items.len() <= WIDTH {
            let first = self.leaves.len() as u32;
            let mut leaf = Leaf::EMPTY;
            for (lane, &k) in items.iter().enumerate() {
                let (c, r) = (centers[k as usize], radii[k as usize]);
                for a in 0..3 {
                    leaf.center[a][lane] = c[a];
                }
                (leaf.radius[lane], leaf.ids[lane]) = (r, k);
            }
            self.leaves.push(leaf);
            self.bin[index] = BinNode { min, max, first, count: items.len() as u32 };
            return;
        }
        let split = if level < SAH_LEVELS { sah_split(items, centers, radii, cmin, cmax) } else { None };
        let mid = match split {
            Some((axis, plane)) => partition(items, |k| centers[k as usize][axis] < plane),
            None => 0,
        };
        let mid = if mid == 0 || mid == items.len() {
            // No useful plane (e.g. coincident centres): split at the median of the longest axis.
            let extent = cmax - cmin;
            let axis = if extent.x >= extent.y && extent.x >= extent.z {
                0
            } else if extent.y >= extent.z {
                1
            } else {
                2
            };
            let mid = items.len() / 2;
            items.select_nth_unstable_by(mid, |&a, &b| centers[a as usize][axis].total_cmp(&centers[b as usize][axis]));
            mid
        } else {
            mid
        };
        let first = self.bin.len();
        self.bin[index] = BinNode { min, max, first: first as u32, count: 0 };
        self.bin.push(BinNode::default());
        self.bin.push(BinNode::default());
        let (left, right) = items.split_at_mut(mid);
        self.build_node(first, level + 1, left, centers, radii);
        self.build_node(first + 1, level + 1, right, centers, radii);
    }

    /// Appends the 8-wide node for interior binary node `b`, at `level` (the root's is 1),
    /// and depth first its subtree; returns its index. Its children are `b`'s grandchildren
    /// and deeper, found by opening the interior child of largest surface area until there
    /// are eight.
    fn collapse(&mut self, b: usize, level: usize) -> u32 {
        self.depth = self.depth.max(level);
        let parent = self.bin[b];
        let mut kids = [0; WIDTH];
        (kids[0], kids[1]) = (parent.first as usize, parent.first as usize + 1);
        let mut n = 2;
        while n < WIDTH {
            let open = (0..n)
                .filter(|&k| self.bin[kids[k]].count == 0)
                .max_by(|&x, &y| self.area(kids[x]).total_cmp(&self.area(kids[y])));
            let Some(k) = open else { break };
            let first = self.bin[kids[k]].first as usize;
            (kids[k], kids[n]) = (first, first + 1);
            n += 1;
        }
        let index = self.nodes.len();
        self.nodes.push(Node::EMPTY);
        let mut node = Node::EMPTY;
        for (lane, &k) in kids[..n].iter().enumerate() {
            let child = self.bin[k];
            for a in 0..3 {
                node.bounds[0][a][lane] = child.min[a];
                node.bounds[1][a][lane] = child.max[a];
            }
            node.lanes |= 1 << lane;
            node.child[lane] = if child.count > 0 { leaf_link(child.first) } else { self.collapse(k, level + 1) };
        }
        self.nodes[index] = node;
        index as u32
    }

    /// Levels of the binary build tree below node `k` (1 for a leaf).
    #[cfg(test)]
    pub(super) fn bin_depth(&self, k: usize) -> usize {
        let node = self.bin[k];
        if node.count > 0 {
            1
        } else {
            1 + self.bin_depth(node.first as usize).max(self.bin_depth(node.first as usize + 1))
        }
    }

    /// Surface area (half) of binary node `k`'s box.
    fn area(&self, k: usize) -> f32 {
        half_area(self.bin[k].min, self.bin[k].max)
    }
}
