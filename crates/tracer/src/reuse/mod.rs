//! Temporal reuse, as one layer over the tracer: while only the orbits move, a frame is made
//! from the last one by tracing again only the pixels that can have changed, and comes out
//! byte for byte the frame a fresh trace gives (Adelson & Hodges 1995, "Generating exact
//! ray-traced animation frames by reprojection", made exact).
//!
//! - `swept.rs`: where each moving sphere can ever be (a washer about its orbit), the arcs
//!   of it a ray crosses ([`Touch`]), and the wedge the sphere fills at an instant.
//! - `marks.rs`: per pixel, where its ray tree meets those volumes ([`Marks`]), and the
//!   pixels that can differ between two instants ([`Marks::select`]).
//! - `observer.rs`: the layer's one seam with the renderer. A marking render's row sinks
//!   (`sink.rs`) carry a marks column (`MarksColumn`) that observes each shaded batch, as
//!   Embree's filter callbacks observe hits: the producers and the wavefront never know it.
//! - `tree.rs`, `lanes.rs` and `level.rs`: what the observer runs, once per batch, with its
//!   per-thread scratch: every ray of each sample's tree (primary, shadow and mirror, at
//!   every depth) marked against the volumes, in SIMD lanes, reading the wavefront's levels
//!   through their read-only view.
//!
//! A render marks only when its caller asks (`Target::marking`), and a scene with no
//! moving sphere is never marked: without reuse, no code here runs. The argument that the
//! reuse is exact is in `docs/design/reuse-exactness.md` and `docs/design/swept-volumes.md`;
//! in short, a pixel whose tree meets no moving sphere's wedge at either instant is the
//! same tree, colour and record at both.

mod lanes;
mod level;
mod marks;
mod observer;
mod swept;
mod tree;

use glam::Vec3;

use crate::scene::Scene;
use crate::snapshot::Snapshot;

pub use marks::{Marks, MarksBand, MarksRow, Rewrite};
pub(crate) use observer::{with_marks, Marker, MarksColumn};
pub use swept::{Arc, SweptRing, Touch};

/// The swept volumes of a scene's moving spheres: where each can be at any instant.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Swept {
    rings: Vec<SweptRing>,
}

impl Swept {
    /// The volumes of `scene`'s moving spheres (none for a still scene).
    #[must_use]
    pub fn of(scene: &Scene) -> Self {
        let mut swept = Self::default();
        swept.update(scene);
        swept
    }

    /// Rebuilds for `scene`, reusing the allocation.
    pub fn update(&mut self, scene: &Scene) {
        self.rings.clear();
        self.rings
            .extend(scene.spheres.iter().enumerate().filter_map(|(k, s)| SweptRing::of(k as u32, s.radius, &s.motion)));
    }

    /// The volumes, one per moving sphere, in sphere order.
    #[must_use]
    pub fn rings(&self) -> &[SweptRing] {
        &self.rings
    }

    /// Whether no sphere moves.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.rings.is_empty()
    }

    /// Where the segment `o + s·d`, 0 ≤ s ≤ `s_max`, meets the volumes ([`Touch::NONE`] if
    /// nowhere: then it meets the same spheres at every instant).
    #[must_use]
    pub fn touch(&self, o: Vec3, d: Vec3, s_max: f32) -> Touch {
        let mut touch = Touch::NONE;
        for (k, ring) in self.rings.iter().enumerate() {
            if let Some(arc) = ring.touch(o, d, s_max) {
                touch = touch.union(Touch { ring: k as u32, arc });
            }
        }
        touch
    }

    /// The wedge of its ring that each moving sphere fills at `scene`'s instant, in the
    /// order of [`Swept::rings`], into `out` (cleared first).
    pub fn wedges(&self, scene: &Snapshot, out: &mut Vec<Arc>) {
        out.clear();
        out.extend(self.rings.iter().map(|ring| {
            let (c, r) = (scene.centers[ring.object as usize], scene.radii[ring.object as usize]);
            // The invariant the reuse rests on: a moving sphere never leaves its volume.
            debug_assert!(ring.holds(c, r), "sphere {} at {c} lies outside its swept volume {ring:?}", ring.object);
            ring.wedge(c, r)
        }));
    }
}
