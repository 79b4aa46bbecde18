//! The marking the observer (`observer.rs`) runs once a batch is shaded: where each
//! sample's ray tree meets the swept volumes — its ray, its shadow rays, its mirror ray
//! and, at every depth, theirs.
//! A sample whose tree meets none of the moving spheres' wedges at two instants has the same
//! tree, colour and record at both (`docs/design/reuse-exactness.md`).
//!
//! The marks of each level are folded up the chains as the radiance is: a level's entries
//! first take their subtrees' marks (their mirror rays' entries one level down), then add
//! their own segments, in lanes (`lanes.rs`), the entries left over from whole vectors in
//! scalar code.

use std::cell::RefCell;

use fearless_simd::Simd;
use glam::Vec3;

use super::level::{LevelMarks, LevelRays};
use super::{lanes, Marker, Swept, Touch};
use crate::camera::EyeView;
use crate::ray::reflect;
use crate::scene::Light;
use crate::wavefront::Levels;

/// A worker's marks of its batch: the marker's scratch, one per thread, kept from batch to
/// batch ([`with_tree_marks`]).
#[derive(Clone, Debug, Default)]
pub(super) struct TreeMarks {
    levels: Vec<LevelMarks>,
    /// Tags of samples whose primary rays met nothing, to be marked together
    /// ([`TreeMarks::mark_background`]).
    background: Vec<u32>,
}

impl TreeMarks {
    /// Marks the levels of the shaded `batch` against `marker`'s volumes, with the scene's
    /// `lights`. `incoming(tag)` says whether a sample's own ray (the first segment of its
    /// tree) can meet a volume at all: `false` for a primary ray outside the volumes' screen
    /// bound, or for a ray another view cast (whose pixel carries that ray's marks). Read the
    /// marks with [`TreeMarks::touch`].
    pub(super) fn mark(
        &mut self,
        (marker, lights): (&Marker<'_>, &[Light]),
        batch: Levels<'_>,
        incoming: impl Fn(u32) -> bool,
    ) {
        let (depth, levels) = (batch.depth(), |k| LevelRays::of(batch, k));
        while self.levels.len() < depth {
            self.levels.push(LevelMarks::default());
        }
        for k in (0..depth).rev() {
            let (upper, lower) = self.levels.split_at_mut(k + 1);
            let (marks, level) = (&mut upper[k], levels(k));
            let n = level.len;
            marks.reserve(level.capacity);
            marks.touch[..n].fill(Touch::NONE);
            if marker.swept.is_empty() {
                continue;
            }
            // The mirror rays that hit are those an entry of the level below names; a
            // subtree's meetings are its root's.
            marks.mirror_hit[..n].fill(false);
            if k + 1 < depth {
                let below = levels(k + 1);
                for c in 0..below.len {
                    let parent = below.parent[c] as usize;
                    marks.mirror_hit[parent] = true;
                    marks.touch[parent] = marks.touch[parent].union(lower[0].touch[c]);
                }
            }
            for e in 0..n {
                marks.own[e] = k > 0 || incoming(level.parent[e]);
            }
            let done = fearless_simd::dispatch!(crate::simd::level(), simd => simd.vectorize(
                #[inline(always)]
                || lanes::mark(simd, (marker.swept, lights), &level, marks, k == 0),
            ));
            for e in done..n {
                let touch = own_segments(marker.swept, lights, (&level, &*marks), e, k == 0);
                marks.touch[e] = marks.touch[e].union(touch);
            }
        }
    }

    /// Where sample `e`'s ray tree meets the volumes, once marked.
    #[inline]
    pub(super) fn touch(&self, e: usize) -> Touch {
        self.levels[0].touch[e]
    }

    /// Notes that the sample `tag` (a pixel's column) saw only background, for
    /// [`TreeMarks::mark_background`].
    pub(super) fn push_background(&mut self, tag: u32) {
        self.background.push(tag);
    }

    /// Marks the pixels [`TreeMarks::push_background`] noted, of row `j` of `view`, in lanes:
    /// `out(tag, touch)` for each whose primary ray meets a volume; then forgets them.
    pub(super) fn mark_background(
        &mut self,
        marker: &Marker<'_>,
        view: &EyeView,
        j: u32,
        out: &mut impl FnMut(u32, Touch),
    ) {
        if !self.background.is_empty() {
            lanes::mark_background(marker.swept, view, (j, &self.background), out);
            self.background.clear();
        }
    }
}

thread_local! {
    /// This thread's marks.
    static TREE_MARKS: RefCell<TreeMarks> = RefCell::new(TreeMarks::default());
}

/// Runs `f` with this thread's [`TreeMarks`], with no background noted. A nested call (from
/// inside `f`) gets fresh marks of its own rather than failing.
pub(super) fn with_tree_marks<R>(f: impl FnOnce(&mut TreeMarks) -> R) -> R {
    TREE_MARKS.with(|cell| match cell.try_borrow_mut() {
        Ok(mut marks) => {
            marks.background.clear();
            f(&mut marks)
        }
        Err(_) => f(&mut TreeMarks::default()),
    })
}

/// Where the rays entry `e` itself casts meet the volumes: the ray that found it, up to the
/// hit; its shadow rays (those it traced, towards the lights it faces), up to the light;
/// its mirror ray, if that met nothing, to infinity. (A mirror ray that hit is the ray of an
/// entry one level down.) The tests are conservative (`swept.rs`), so the spawn offsets and
/// the rounding of these rays do not matter. The scalar reference of `lanes::mark`.
fn own_segments(
    swept: &Swept,
    lights: &[Light],
    (level, marks): (&LevelRays<'_>, &LevelMarks),
    e: usize,
    first: bool,
) -> Touch {
    let get = |c: &[Vec<f32>; 3]| Vec3::new(c[0][e], c[1][e], c[2][e]);
    let (p, n) = (get(level.p), get(level.n));
    let mut touch = if marks.own[e] { swept.touch(get(level.o), get(level.d), level.t[e]) } else { Touch::NONE };
    if !(first && level.known[e]) {
        for light in lights {
            // The segment to the light, as p + s·(light − p), 0 ≤ s ≤ 1.
            let to = light.position - p;
            if n.dot(to) > 0.0 {
                touch = touch.union(swept.touch(p, to, 1.0));
            }
        }
    }
    if level.reflects[e] && !marks.mirror_hit[e] {
        touch = touch.union(swept.touch(p, reflect(get(level.v), n), f32::INFINITY));
    }
    touch
}
