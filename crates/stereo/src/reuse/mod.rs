//! Exact temporal reuse for a stereo frame: while only the scene time moves, a frame traces
//! again only the pixels that can have changed, and is byte for byte the frame a fresh
//! trace gives (after Adelson & Hodges 1995, made exact). The tracer marks where each
//! pixel's ray tree meets the moving spheres' swept volumes (`tracer::reuse`); this module
//! keeps those marks from frame to frame and decides, per eye, what a frame makes again
//! (`right.rs` for the right eye's rule). Why it is exact: `docs/design/reuse-exactness.md`.
//!
//! [`Temporal`] is all of the bookkeeping, so that `StereoFrame::render` reads as its stages:
//! [`Temporal::begin`] says how a frame is made ([`Made`]), the stages ask it for their
//! targets and selections, and [`Temporal::end`] remembers the frame.

mod right;

use tracer::reuse::{Arc, Marks, Swept};
use tracer::{Camera, Film, PixelBits, Pixels, Record, Scene, Target, Tracer};

use crate::mode::Options;
use crate::reproject::{reproject_and_classify_rows, Reprojection, NO_SOURCE};
use crate::stats::PixelClass;

pub(crate) use right::{plan_right, Changes};

/// What a frame was asked for, besides the tracer: a frame may reuse the last one only if
/// this is the same and the tracer differs only in time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Asked {
    pub camera: Camera,
    pub width: u32,
    pub height: u32,
    pub margin: (u32, u32),
    pub opts: Options,
}

/// How a frame is made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Made {
    /// Afresh, unmarked: reuse is off, or the request has just changed.
    Fresh,
    /// Afresh, and marked for the frames that follow.
    Marked,
    /// From the last frame: only what can have changed is made again.
    Reused,
}

impl Made {
    /// Whether the frame marks the pixels it makes (a reused frame marks the ones it makes
    /// again).
    #[must_use]
    pub(crate) fn marks(self) -> bool {
        self != Self::Fresh
    }
}

/// The reuse state of a [`crate::StereoFrame`]: the swept volumes, the last frame's request,
/// both eyes' marks, and this frame's selections (see the module doc).
#[derive(Debug, Default)]
pub(crate) struct Temporal {
    /// The moving spheres' volumes; `None` while reuse is off.
    swept: Option<Swept>,
    /// What the last frame was asked for, of which tracer generation, and whether it marked.
    last: Option<(Asked, u64, bool)>,
    /// The moving spheres' wedges in the last frame, and in this one.
    wedges: (Vec<Arc>, Vec<Arc>),
    /// Per ring, the arc that holds both.
    hulls: Vec<Arc>,
    /// Where each eye's pixels' own ray trees meet the volumes.
    left_marks: Marks,
    right_marks: Marks,
    /// The left pixels a reused frame traced again.
    pub left_retraced: PixelBits,
    /// The right pixels a reused frame made again.
    pub right_made: PixelBits,
    /// The last frame's sources and classes, of the rows redone.
    was: (Vec<u32>, Vec<PixelClass>),
    /// Per left row, whether a pixel of it was retraced; per right row, whether stages 2
    /// and 3 redid it.
    rows: (Vec<bool>, Vec<bool>),
    /// The last frame's reprojection plan.
    plan: Option<Reprojection>,
}

impl Temporal {
    /// Reuse on for `scene`'s frames, or off (`None`). Turning it on or off makes the next
    /// frame fresh.
    pub(crate) fn set(&mut self, scene: Option<&Scene>) {
        if scene.is_some() != self.swept.is_some() {
            self.last = None;
        }
        match (scene, &mut self.swept) {
            (Some(scene), Some(swept)) => swept.update(scene),
            (Some(scene), None) => self.swept = Some(Swept::of(scene)),
            (None, _) => self.swept = None,
        }
    }

    /// Whether reuse is on.
    pub(crate) fn is_on(&self) -> bool {
        self.swept.is_some()
    }

    /// How the frame `asked` of `tracer` is made. Marking costs about two fresh frames: a
    /// frame marks only when reuse can follow, once the request has held still for a frame
    /// (or on the first frame), so a moving head pays nothing for it.
    pub(crate) fn begin(&mut self, tracer: &Tracer, asked: Asked) -> Made {
        let Some(swept) = &self.swept else { return Made::Fresh };
        // The same request of the same scene, only its time moved.
        let same = self.last.is_some_and(|(last, generation, _)| last == asked && generation == tracer.generation());
        swept.wedges(tracer.snapshot(), &mut self.wedges.1);
        // Each ring's two wedges as one arc (the shortest that holds both: one test per
        // pixel instead of two, and hardly larger, as a sphere moves little in a frame).
        self.hulls.clear();
        if self.wedges.0.len() == self.wedges.1.len() {
            self.hulls.extend(self.wedges.0.iter().zip(&self.wedges.1).map(|(a, b)| a.hull(*b)));
        } else {
            // (Never on a reused frame, whose rings are the last frame's; but if so, every
            // marked pixel is retraced.)
            self.hulls.extend(self.wedges.1.iter().map(|_| Arc::FULL));
        }
        if same && self.last.is_some_and(|(_, _, marked)| marked) {
            Made::Reused
        } else if same || self.last.is_none() {
            Made::Marked
        } else {
            Made::Fresh
        }
    }

    /// Remembers the frame `asked` of `tracer`, made as `made`.
    pub(crate) fn end(&mut self, tracer: &Tracer, asked: Asked, made: Made) {
        if self.swept.is_some() {
            self.last = Some((asked, tracer.generation(), made.marks()));
            std::mem::swap(&mut self.wedges.0, &mut self.wedges.1);
        }
    }

    /// `made`'s marks of `marks` before a pass of the tracer over `size` pixels, and the
    /// volumes the pass marks against: none for a frame that does not mark, nor for a still
    /// scene, whose marks are all empty with no trace to make them (nothing moves, so no ray
    /// meets a moving sphere; the tracer's reuse layer is never called for it).
    fn to_mark<'a>(
        swept: Option<&'a Swept>,
        marks: &'a mut Marks,
        made: Made,
        (width, height): (u32, u32),
    ) -> (&'a mut Marks, Option<&'a Swept>) {
        let swept = swept.filter(|_| made.marks());
        if made == Made::Marked && swept.is_some_and(Swept::is_empty) {
            marks.resize(width, height);
        }
        (marks, swept.filter(|swept| !swept.is_empty()))
    }

    /// Stage 1's pixels and target for the left `film` of `size`, keeping `record`: every
    /// pixel, or on a reused frame those that can have changed; marked when the frame marks.
    pub(crate) fn left<'a>(
        &'a mut self,
        film: &'a mut Film,
        record: Record,
        made: Made,
        size: (u32, u32),
    ) -> (Pixels<'a>, Target<'a>) {
        if made == Made::Reused {
            self.left_marks.select([&self.hulls, &[]], &mut self.left_retraced);
        }
        let (marks, swept) = Self::to_mark(self.swept.as_ref(), &mut self.left_marks, made, size);
        let target = Target::film(film, record);
        let target = if let Some(swept) = swept { target.marking(marks, swept) } else { target };
        let pixels = if made == Made::Reused { Pixels::Only(&self.left_retraced) } else { Pixels::All };
        (pixels, target)
    }

    /// The right eye of `full` mode, traced as the left eye is: its pixels and its target
    /// `rgb`, of `size`, and how many pixels it makes.
    pub(crate) fn right_full<'a>(
        &'a mut self,
        rgb: &'a mut Vec<u32>,
        made: Made,
        size: (u32, u32),
    ) -> (Pixels<'a>, Target<'a>, u64) {
        let mut count = u64::from(size.0) * u64::from(size.1);
        if made == Made::Reused {
            count = self.right_marks.select([&self.hulls, &[]], &mut self.right_made);
        }
        let (marks, swept) = Self::to_mark(self.swept.as_ref(), &mut self.right_marks, made, size);
        let target = Target::colour(rgb);
        let target = if let Some(swept) = swept { target.marking(marks, swept) } else { target };
        let pixels = if made == Made::Reused { Pixels::Only(&self.right_made) } else { Pixels::All };
        (pixels, target, count)
    }

    /// What stages 4 and 5 of a reprojecting mode make of the right eye of `size`: every
    /// pixel, or on a reused frame those [`Temporal::reproject_changed`] chose; the right
    /// eye's marks (written by their passes when the frame marks); and the volumes they mark
    /// against.
    pub(crate) fn right(&mut self, made: Made, size: (u32, u32)) -> (Option<&PixelBits>, &mut Marks, Option<&Swept>) {
        if made != Made::Reused && (self.right_marks.width(), self.right_marks.height()) != size {
            // (Every pixel of a fresh frame is marked anew.)
            self.right_marks.resize(size.0, size.1);
        }
        let (marks, swept) = Self::to_mark(self.swept.as_ref(), &mut self.right_marks, made, size);
        ((made == Made::Reused).then_some(&self.right_made), marks, swept)
    }

    /// Notes the reprojection plan of a fresh frame.
    pub(crate) fn planned(&mut self, plan: Reprojection) {
        self.plan = Some(plan);
    }

    /// Stages 2 and 3 of a reused frame, from the `left` film into `src` and `class`: only
    /// the rows that read a retraced left row (all of them if the plan moved), then the
    /// right pixels to make again (`right.rs`) into `right_made`, each given its stage-3
    /// class in `mask`. Returns how many, and how many of each class (by discriminant) they
    /// had in the last frame.
    pub(crate) fn reproject_changed(
        &mut self,
        left: &Film,
        plan: Reprojection,
        (src, class, mask): (&mut [u32], &mut [PixelClass], &mut [PixelClass]),
    ) -> (u64, [u64; PixelClass::COUNT]) {
        let n = src.len();
        let (src_was, class_was) = &mut self.was;
        let (left_rows, right_rows) = &mut self.rows;
        let same_plan = self.plan.replace(plan) == Some(plan);
        left_rows.clear();
        let bits = self.left_retraced.words().chunks(self.left_retraced.stride().max(1));
        left_rows.extend(bits.map(|row| !same_plan || row.iter().any(|&word| word != 0)));
        right_rows.resize(left.height() as usize, false);
        src_was.resize(n, NO_SOURCE);
        class_was.resize(n, PixelClass::Traced);
        let buffers = (&mut src_was[..], &mut class_was[..], &mut right_rows[..]);
        reproject_and_classify_rows(left, plan, (&mut *src, &mut *class), left_rows, buffers);
        let changes = Changes {
            now: (class, src),
            before: (class_was, src_was),
            left_retraced: &self.left_retraced,
            right_marks: &mut self.right_marks,
            wedges: [&self.hulls, &[]],
            rows: right_rows,
        };
        plan_right(changes, mask, &mut self.right_made)
    }
}
