//! Exact temporal reuse for a stereo frame: while only the scene time moves, a frame traces
//! again only the pixels that can have changed, and is byte for byte the frame a fresh
//! trace gives (after Adelson & Hodges 1995, made exact). The tracer marks where each
//! pixel's ray tree meets the moving spheres' swept volumes (`tracer::reuse`); this module
//! keeps those marks from frame to frame and decides, per eye, what a frame makes again
//! (`right.rs` for the right eye's rule). Why it is exact: `docs/design/reuse-exactness.md`.
//!
//! [`Temporal`] is all of the bookkeeping, so that `StereoFrame::render` reads as its stages.
//! A frame enters it once, [`Temporal::frame`], which says how the frame is made ([`Made`])
//! and returns its [`FrameReuse`] (`frame_reuse.rs`): the driver follows it stage by stage,
//! asking it for each pass's pixels and marks, and [`FrameReuse::finish`] counts what the
//! frame made and remembers it for the next.

mod frame_reuse;
mod right;

use tracer::reuse::{Arc, Marks, Swept};
use tracer::{Camera, PixelBits, Scene, Tracer};

use crate::mode::Options;
use crate::reproject::Reprojection;
use crate::stats::PixelClass;

pub(crate) use frame_reuse::FrameReuse;

/// What a frame was asked for, besides the tracer: a frame may reuse the last one only if
/// this is the same and the tracer differs only in time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Asked {
    pub camera: Camera,
    pub width: u32,
    pub height: u32,
    pub margin: (u32, u32),
    pub opts: Options,
    /// Whether the frame keeps both eyes' depth and first hits: a right eye that makes its
    /// planes as it makes its pixels keeps those of the pixels it does not make again, which
    /// the last frame must have made too.
    pub depths: bool,
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
    left_retraced: PixelBits,
    /// The right pixels a reused frame made again.
    right_made: PixelBits,
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

    /// The left and the right pixels the last frame made again, if it was reused.
    pub(crate) fn made(&self) -> (&PixelBits, &PixelBits) {
        (&self.left_retraced, &self.right_made)
    }

    /// The one entry of a frame: the reuse of the frame `asked` of `tracer`, whose eyes are
    /// traced at `size` (guard band included), for the frame's driver to follow.
    pub(crate) fn frame(&mut self, tracer: &Tracer, asked: Asked, size: (u32, u32)) -> FrameReuse<'_> {
        let made = self.begin(tracer, asked);
        FrameReuse::new(self, made, (asked, tracer.generation()), size)
    }

    /// How the frame `asked` of `tracer` is made. Marking costs about two fresh frames: a
    /// frame marks only when reuse can follow, once the request has held still for a frame
    /// (or on the first frame), so a moving head pays nothing for it.
    fn begin(&mut self, tracer: &Tracer, asked: Asked) -> Made {
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
}
