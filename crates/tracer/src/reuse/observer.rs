//! The reuse layer's observer: a marking render's sinks carry a marks column
//! ([`MarksColumn`]) that watches each shaded batch, as Embree's intersection filter
//! callbacks watch hits, and writes where each pixel's ray tree meets the swept volumes.
//! The producers (`render/row.rs`, `batch/`) and the wavefront never know it is there: the
//! sink (`sink.rs`) tells it of the pixels that saw only background, and hands it each
//! batch once, shaded; it keeps its per-thread scratch ([`TreeMarks`]) to itself.

use std::ops::Range;

use super::tree::{with_tree_marks, TreeMarks};
use super::{MarksRow, Swept};
use crate::accel::screen::pixel_rect;
use crate::camera::EyeView;
use crate::scene::Light;
use crate::sink::Observe;
use crate::wavefront::Levels;

/// What a view's pixels are marked against: the volumes, the scene's lights, the view, and
/// where on its screen a primary ray can meet a volume.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Marker<'a> {
    /// The volumes.
    pub(crate) swept: &'a Swept,
    /// The lights, whose shadow rays are segments of each tree.
    pub(crate) lights: &'a [Light],
    /// The view whose pixels are marked.
    pub(crate) view: &'a EyeView,
    /// The inclusive pixel rectangle `[i0, j0, i1, j1]` outside which no primary ray of
    /// the view can meet a volume, or `None` if none can.
    screen: Option<[u32; 4]>,
}

impl<'a> Marker<'a> {
    /// The marker of the pixels of `view`, in a scene lit by `lights`.
    pub(crate) fn new(swept: &'a Swept, view: &'a EyeView, lights: &'a [Light]) -> Self {
        let screen = swept
            .rings()
            .iter()
            .filter_map(|ring| pixel_rect(view, ring.center, ring.bounding_radius()))
            .reduce(|[a0, b0, a1, b1], [c0, d0, c1, d1]| [a0.min(c0), b0.min(d0), a1.max(c1), b1.max(d1)]);
        Self { swept, lights, view, screen }
    }

    /// Whether the primary ray of pixel (i, j) might meet a volume (if `false`, it cannot).
    #[inline]
    #[must_use]
    pub(crate) fn may_meet(&self, i: u32, j: u32) -> bool {
        self.screen.is_some_and(|[i0, j0, i1, j1]| (i0..=i1).contains(&i) && (j0..=j1).contains(&j))
    }
}

/// Row `j`'s marks as a column of its sink: each pixel a batch makes is marked where its
/// ray tree meets the marker's volumes. The pixels it is handed must have been unmarked
/// first ([`MarksRow::clear_only`]): a pixel that saw only background and meets no volume
/// is left as it is.
#[derive(Debug)]
pub(crate) struct MarksColumn<'r, 'a> {
    marks: &'r mut MarksRow<'a>,
    marker: &'r Marker<'r>,
    j: u32,
    /// This thread's scratch, borrowed for the row.
    scratch: &'r mut TreeMarks,
}

/// Runs `f` with row `j`'s marks column — the row `marks`, marked through `marker` — when
/// both are given, else with `None`.
pub(crate) fn with_marks<R>(
    marks: Option<&mut MarksRow<'_>>,
    marker: Option<&Marker<'_>>,
    j: u32,
    f: impl FnOnce(Option<MarksColumn<'_, '_>>) -> R,
) -> R {
    match marks.zip(marker) {
        Some((marks, marker)) => with_tree_marks(|scratch| f(Some(MarksColumn { marks, marker, j, scratch }))),
        None => f(None),
    }
}

impl Observe for MarksColumn<'_, '_> {
    #[inline]
    fn escaped(&mut self, span: Range<usize>) {
        // Marked later, together, in lanes (`TreeMarks::mark_background`).
        for i in span {
            if self.marker.may_meet(i as u32, self.j) {
                self.scratch.push_background(i as u32);
            }
        }
    }

    fn shaded(&mut self, batch: Levels<'_>, own: bool) {
        let Self { marks, marker, j, scratch } = self;
        let (marker, j) = (*marker, *j);
        scratch.mark((marker, marker.lights), batch, |tag| own && marker.may_meet(tag, j));
        for e in 0..batch.len() {
            marks.set(batch.tag(e), scratch.touch(e));
        }
        scratch.mark_background(marker, marker.view, j, &mut |i, touch| marks.set(i, touch));
    }
}
