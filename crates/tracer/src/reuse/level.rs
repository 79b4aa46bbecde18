//! One level of a shaded batch as the marking reads it ([`LevelRays`], taken from the
//! wavefront's read-only [`Levels`]) and the marks the marking keeps for it
//! ([`LevelMarks`]): the reuse layer's own view of the wavefront, which knows nothing of it.

use super::swept::Touch;
use crate::wavefront::{Level, Levels};

/// One level of a shaded batch, as the marking reads it: the wavefront's columns of the
/// rays of that reflection depth (an entry per hit), padded to whole vectors of lanes.
#[derive(Clone, Copy, Debug)]
pub(super) struct LevelRays<'a> {
    /// Entries in use.
    pub len: usize,
    /// Entries the columns hold (at least `len`, rounded up to whole vectors).
    pub capacity: usize,
    /// The ray's origin and unit direction, and its hit parameter.
    pub o: &'a [Vec<f32>; 3],
    pub d: &'a [Vec<f32>; 3],
    pub t: &'a [f32],
    /// The direction the hit is seen along.
    pub v: &'a [Vec<f32>; 3],
    /// The hit point and unit outward normal.
    pub p: &'a [Vec<f32>; 3],
    pub n: &'a [Vec<f32>; 3],
    /// Level 0: the sample's tag; deeper: the entry above whose mirror ray this is.
    pub parent: &'a [u32],
    /// Level 0: whether the light bits were known (no shadow rays were cast).
    pub known: &'a [bool],
    /// Whether the entry cast a mirror ray.
    pub reflects: &'a [bool],
}

/// One level's marks, an entry per entry of the wavefront's level.
#[derive(Clone, Debug, Default)]
pub(super) struct LevelMarks {
    /// Where the entry's tree meets the volumes.
    pub(super) touch: Vec<Touch>,
    /// Whether the entry's mirror ray hit a sphere (then that subtree is marked one level
    /// down, and the ray itself is a segment of it).
    pub(super) mirror_hit: Vec<bool>,
    /// Whether the entry's own ray is to be tested.
    pub(super) own: Vec<bool>,
}

impl LevelMarks {
    /// Makes every column at least `n` entries long.
    pub(super) fn reserve(&mut self, n: usize) {
        if self.touch.len() < n {
            self.touch.resize(n, Touch::NONE);
            self.mirror_hit.resize(n, false);
            self.own.resize(n, false);
        }
    }
}

impl<'a> LevelRays<'a> {
    /// Reflection depth `k` of the shaded `batch`.
    pub(super) fn of(batch: Levels<'a>, k: usize) -> Self {
        let level: &'a Level = batch.level(k);
        Self {
            len: level.len(),
            capacity: level.capacity(),
            o: level.o(),
            d: level.d(),
            t: level.t(),
            v: level.v(),
            p: level.p(),
            n: level.n(),
            parent: level.parent(),
            known: level.known(),
            reflects: level.reflects(),
        }
    }
}
