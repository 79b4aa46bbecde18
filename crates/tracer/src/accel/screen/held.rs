//! A sliced view's open rays, held back along a row and sent through the BVH sixteen at a
//! time.
//!
//! A sliced view (`cut.rs`) sends on through the BVH the rays whose binned hit is not surely
//! nearer than every unbinned sphere: on the first 1M field of `benches/embree-anchor`
//! about a fifth of the primary rays, scattered, one or two to a group of lanes. Searched a
//! group at a time, such a packet of one or two rays paid a whole descent of the tree: 34
//! nodes and 16 leaves for 2.1 rays. Held back until the row's groups are all binned, the
//! open rays go down the tree in packets of [`EYE_PACKET`] neighbours of the row (Wald et
//! al. 2001's coherence: rays from one eye through nearby pixels, all begun at the cut),
//! which share each node's loads and loop.
//!
//! **The same hits.** A packet shares only the walk: each ray tests each box and sphere
//! as it would alone, and keeps of equal `t` the lowest sphere id, so its hit does not
//! depend on the rays it travels with (`bvh/first.rs`'s proptest), and a row held back
//! finds the hits [`ScreenBins::hits_lanes`] finds group by group: `render/both_ways.rs`
//! renders sliced views, rows held back, against the BVH's, and fails when a hit goes back
//! to another lane.

use fearless_simd::{prelude::*, Simd};
use glam::Vec3;

use super::{bvh_hits, BinnedLanes, LaneHits, ScreenBins};
use crate::accel::{Aggregate, EyeRays, Nearest, EYE_PACKET};
use crate::bits;
use crate::simd::{F, U};

/// One group of lanes as the bins left it: each lane's hit so far (`t`, +∞ for none, and
/// the sphere), its direction, and the lanes that go on through the BVH.
#[derive(Clone, Copy, Debug)]
struct Group {
    t: [f32; EYE_PACKET],
    ids: [u32; EYE_PACKET],
    dirs: [[f32; EYE_PACKET]; 3],
    open: u32,
}

/// A row's groups of lanes, held between the bins and the BVH; reused from row to row.
#[derive(Clone, Debug, Default)]
pub(crate) struct HeldRow {
    groups: Vec<Group>,
}

impl HeldRow {
    /// Forgets the last row's groups (keeping the buffer).
    pub(crate) fn clear(&mut self) {
        self.groups.clear();
    }

    /// Holds the next group's hits from the bins, `open` naming the lanes still to search
    /// ([`ScreenBins::binned_lanes`]).
    #[inline(always)]
    pub(crate) fn hold<S: Simd>(&mut self, ((t, ids, d), open): BinnedLanes<S>) {
        let n = F::<S>::LEN;
        let mut group = Group { t: [0.0; EYE_PACKET], ids: [0; EYE_PACKET], dirs: [[0.0; EYE_PACKET]; 3], open };
        t.store_slice(&mut group.t[..n]);
        ids.store_slice(&mut group.ids[..n]);
        for (axis, lanes) in group.dirs.iter_mut().zip(&d) {
            lanes.store_slice(&mut axis[..n]);
        }
        self.groups.push(group);
    }

    /// Searches every held open ray through the BVH from `bins`' cut, [`EYE_PACKET`] at a
    /// time in the row's order, each from the hit the bins gave it; `origin` is the eye.
    pub(crate) fn search(&mut self, bins: &ScreenBins, accel: &Aggregate, origin: Vec3) {
        let mut dirs = [[0f32; EYE_PACKET]; 3];
        let mut nearest: Nearest = ([0.0; EYE_PACKET], [0; EYE_PACKET]);
        // Where each ray of the packet came from: its group and lane.
        let mut slots = [(0usize, 0usize); EYE_PACKET];
        let mut n = 0;
        let beyond = bins.beyond();
        for g in 0..self.groups.len() {
            for lane in bits::ones(&[u64::from(self.groups[g].open)]).map(|l| l as usize) {
                let group = &self.groups[g];
                for (packet, axis) in dirs.iter_mut().zip(&group.dirs) {
                    packet[n] = axis[lane];
                }
                (nearest.0[n], nearest.1[n]) = (group.t[lane], group.ids[lane]);
                slots[n] = (g, lane);
                n += 1;
                if n == EYE_PACKET {
                    self.search_packet(accel, EyeRays { origin, dirs: &dirs, beyond }, &slots[..n], &mut nearest);
                    n = 0;
                }
            }
        }
        if n > 0 {
            self.search_packet(accel, EyeRays { origin, dirs: &dirs, beyond }, &slots[..n], &mut nearest);
        }
    }

    /// One packet's search, its hits put back in their groups.
    fn search_packet(&mut self, accel: &Aggregate, at: EyeRays<'_>, slots: &[(usize, usize)], nearest: &mut Nearest) {
        let rays = (1u32 << slots.len()) - 1;
        bvh_hits(accel, at, rays, nearest);
        for (k, &(g, lane)) in slots.iter().enumerate() {
            (self.groups[g].t[lane], self.groups[g].ids[lane]) = (nearest.0[k], nearest.1[k]);
        }
    }

    /// Group `g`'s first hits, as [`ScreenBins::hits_lanes`] gives them, once searched.
    #[inline(always)]
    pub(crate) fn hits<S: Simd>(&self, simd: S, g: usize) -> LaneHits<S> {
        let (group, n) = (&self.groups[g], F::<S>::LEN);
        let d = crate::simd::each3(|a| F::<S>::from_slice(simd, &group.dirs[a][..n]));
        (F::<S>::from_slice(simd, &group.t[..n]), U::<S>::from_slice(simd, &group.ids[..n]), d)
    }
}
