//! One reflection depth of a [`super::Wavefront`]: its hits as columns.

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use glam::Vec3;

/// The most lanes a kernel runs with: every level's capacity is a multiple of it, so that
/// an observer may read whole vectors past a level's end.
const WIDEST: usize = 16;

/// Structure-of-arrays columns of three.
pub(crate) type Column3 = [Vec<f32>; 3];

pub(super) fn get3(c: &Column3, e: usize) -> Vec3 {
    Vec3::new(c[0][e], c[1][e], c[2][e])
}

pub(super) fn set3(c: &mut Column3, e: usize, v: Vec3) {
    (c[0][e], c[1][e], c[2][e]) = (v.x, v.y, v.z);
}

/// The hits of one reflection depth, one entry per hit in each column.
///
/// Every column is as long as the level's capacity, a whole number of vectors of the
/// widest lanes; the first [`Level::len`] entries are in use. Entries are written in place
/// (no per-column push), and the columns only ever grow, so a warm level allocates
/// nothing. Outside the wavefront a level is only read, by observers of a shaded batch
/// ([`super::Levels`]), through the accessors below.
#[derive(Clone, Debug, Default)]
pub(crate) struct Level {
    /// Entries in use.
    pub(super) used: usize,
    /// The ray's direction (unit).
    pub(super) d: Column3,
    /// The direction the hit is seen along (unit): the ray's, except for a sample that
    /// re-shades for one view what another view's ray found.
    pub(super) v: Column3,
    /// The ray's origin.
    pub(super) o: Column3,
    /// The ray's hit parameter.
    pub(super) t: Vec<f32>,
    /// The sphere hit.
    pub(super) object: Vec<u32>,
    /// Level 0: the caller's tag of the sample; deeper: the entry of the level above whose
    /// mirror ray this is.
    pub(super) parent: Vec<u32>,
    /// Level 0: whether the entry's light bits are known (not traced).
    pub(super) known: Vec<bool>,
    /// Hit point.
    pub(super) p: Column3,
    /// Unit outward normal.
    pub(super) n: Column3,
    /// Light bits: given (at level 0, for a pixel whose bits another view found) or found.
    pub(super) lights: Vec<u32>,
    /// View-independent light D.
    pub(super) diffuse: Column3,
    /// Highlights S.
    pub(super) spec: Column3,
    /// Radiance of the mirror ray, once known (background until a hit is shaded).
    pub(super) mirror: Column3,
    /// Whether the entry cast a mirror ray.
    pub(super) reflects: Vec<bool>,
    /// The entry's radiance, once folded.
    pub(super) radiance: Column3,
    /// Level 0 of a re-shaded batch, until aimed ([`super::Wavefront::aim_seen`]): the pixel of
    /// the other view whose ray found the entry, as column and row.
    pub(super) source: [Vec<u32>; 2],
}

impl Level {
    pub(super) fn clear(&mut self) {
        self.used = 0;
    }

    /// Entries in use.
    pub(crate) fn len(&self) -> usize {
        self.used
    }

    /// Entries every column holds: at least [`Level::len`], in whole vectors of lanes.
    pub(crate) fn capacity(&self) -> usize {
        self.t.len()
    }

    /// Makes every column at least `n` entries long (doubling, so growth is rare), and a
    /// whole number of vectors of [`WIDEST`] lanes.
    pub(super) fn reserve(&mut self, n: usize) {
        if self.t.len() >= n {
            return;
        }
        let n = n.max(2 * self.t.len()).max(64).next_multiple_of(WIDEST);
        let columns = [
            &mut self.d,
            &mut self.v,
            &mut self.o,
            &mut self.p,
            &mut self.n,
            &mut self.diffuse,
            &mut self.spec,
            &mut self.mirror,
            &mut self.radiance,
        ];
        for c in columns.into_iter().flatten() {
            c.resize(n, 0.0);
        }
        self.t.resize(n, 0.0);
        self.object.resize(n, 0);
        self.parent.resize(n, 0);
        self.lights.resize(n, 0);
        self.known.resize(n, false);
        self.reflects.resize(n, false);
        for c in &mut self.source {
            c.resize(n, 0);
        }
    }

    /// Adds a hit: ray (`o`, `d`) meets `object` at `t`, its light bits to be found by shadow
    /// rays.
    // Always inlined: called per primary and mirror hit from the lane kernels; out of line,
    // its arguments go through the stack and the loads that read them back stall (10 % of a
    // frame).
    #[inline(always)]
    pub(super) fn push(&mut self, o: Vec3, d: Vec3, t: f32, object: u32, parent: u32) {
        let e = self.used;
        self.reserve(e + 1);
        set3(&mut self.o, e, o);
        set3(&mut self.d, e, d);
        set3(&mut self.v, e, d);
        self.t[e] = t;
        self.object[e] = object;
        self.parent[e] = parent;
        self.lights[e] = 0;
        self.known[e] = false;
        self.reflects[e] = false;
        self.used = e + 1;
    }
}

impl Level {
    /// Level 0: the pixel of the traced view (column, row) whose occlusion rays entry `e`
    /// casts, on row `row`: its own (its tag is its column), or for an entry re-shaded from
    /// another view's pixel, that pixel (so its light is that pixel's, bit for bit).
    pub(super) fn pixel(&self, e: usize, row: u32) -> (u32, u32) {
        if self.known[e] {
            (self.source[0][e], self.source[1][e])
        } else {
            (self.parent[e], row)
        }
    }
}

/// The columns of a shaded level an observer reads (the marking of temporal reuse): its
/// rays and where they hit, read-only.
impl Level {
    /// The rays' origins.
    pub(crate) fn o(&self) -> &Column3 {
        &self.o
    }

    /// The rays' unit directions.
    pub(crate) fn d(&self) -> &Column3 {
        &self.d
    }

    /// The rays' hit parameters.
    pub(crate) fn t(&self) -> &[f32] {
        &self.t
    }

    /// The directions the hits are seen along.
    pub(crate) fn v(&self) -> &Column3 {
        &self.v
    }

    /// The hit points.
    pub(crate) fn p(&self) -> &Column3 {
        &self.p
    }

    /// The unit outward normals.
    pub(crate) fn n(&self) -> &Column3 {
        &self.n
    }

    /// Level 0: the samples' tags; deeper: the entries above whose mirror rays these are.
    pub(crate) fn parent(&self) -> &[u32] {
        &self.parent
    }

    /// Level 0: whether an entry's light bits were known (no shadow rays cast).
    pub(crate) fn known(&self) -> &[bool] {
        &self.known
    }

    /// Whether an entry cast a mirror ray.
    pub(crate) fn reflects(&self) -> &[bool] {
        &self.reflects
    }
}
