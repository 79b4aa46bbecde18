//! One frame's temporal reuse, as [`Temporal::frame`] returns it and the frame's driver
//! follows it: the stages ask it, in order, which pixels their pass makes and where it marks
//! (the left eye, then the right eye traced in full or reprojected, classified, retraced and
//! filled), and [`FrameReuse::finish`] counts what the frame made and remembers the frame.

use tracer::reuse::{Marks, Swept};
use tracer::{Film, PixelBits, Pixels, Record, Target};

use super::right::{plan_right, Changes};
use super::{Asked, Made, Temporal};
use crate::reproject::{reproject_and_classify, reproject_and_classify_rows, Reprojection, NO_SOURCE};
use crate::stats::{PixelClass, PixelCounts, Reuse};

/// The reuse of the frame being made: how it is made, and what it has made so far.
#[derive(Debug)]
pub(crate) struct FrameReuse<'a> {
    temporal: &'a mut Temporal,
    made: Made,
    /// What the frame was asked for, of which tracer generation: remembered at the end.
    asked: (Asked, u64),
    /// Each eye's traced size, guard band included.
    size: (u32, u32),
    /// The right pixels the frame makes (all of them, unless it reuses the last frame's).
    right_made: u64,
    /// On a reused frame of a reprojecting mode, how many of the right pixels made again
    /// had each class (by discriminant) in the last frame.
    removed: Option<[u64; PixelClass::COUNT]>,
}

impl<'a> FrameReuse<'a> {
    /// The reuse of a frame made as `made`, asked for as `asked`, of `size` per eye.
    pub(super) fn new(temporal: &'a mut Temporal, made: Made, asked: (Asked, u64), size: (u32, u32)) -> Self {
        let right_made = u64::from(size.0) * u64::from(size.1);
        Self { temporal, made, asked, size, right_made, removed: None }
    }

    /// Whether the frame reuses the last one.
    pub(crate) fn reused(&self) -> bool {
        self.made == Made::Reused
    }

    /// Stage 1's pixels and target for the left `film`, keeping `record`: every pixel, or on
    /// a reused frame those that can have changed; marked when the frame marks.
    pub(crate) fn left<'b>(&'b mut self, film: &'b mut Film, record: Record) -> (Pixels<'b>, Target<'b>) {
        let t = &mut *self.temporal;
        if self.made == Made::Reused {
            t.left_marks.select([&t.hulls, &[]], &mut t.left_retraced);
        }
        let (marks, swept) = Temporal::to_mark(t.swept.as_ref(), &mut t.left_marks, self.made, self.size);
        let target = Target::film(film, record);
        let target = if let Some(swept) = swept { target.marking(marks, swept) } else { target };
        let pixels = if self.made == Made::Reused { Pixels::Only(&t.left_retraced) } else { Pixels::All };
        (pixels, target)
    }

    /// The right eye of `full` mode, traced as the left eye is: its pixels and its target
    /// `rgb`, with its first hits into `hits` (object and depth planes) if given.
    pub(crate) fn right_full<'b>(
        &'b mut self,
        rgb: &'b mut Vec<u32>,
        hits: Option<(&'b mut Vec<u32>, &'b mut Vec<f32>)>,
    ) -> (Pixels<'b>, Target<'b>) {
        let t = &mut *self.temporal;
        if self.made == Made::Reused {
            self.right_made = t.right_marks.select([&t.hulls, &[]], &mut t.right_made);
        }
        let (marks, swept) = Temporal::to_mark(t.swept.as_ref(), &mut t.right_marks, self.made, self.size);
        let target = match hits {
            Some((object, z)) => Target::colour_with_first_hits(rgb, object, z),
            None => Target::colour(rgb),
        };
        let target = if let Some(swept) = swept { target.marking(marks, swept) } else { target };
        let pixels = if self.made == Made::Reused { Pixels::Only(&t.right_made) } else { Pixels::All };
        (pixels, target)
    }

    /// Stages 2 and 3 of a reprojecting mode, from the `left` film by `plan` into `src` and
    /// `class`, with `mask` given each made pixel's stage-3 class. A fresh frame does every
    /// row. A reused one does only the rows that read a retraced left row (all of them if
    /// the plan moved), then chooses the right pixels to make again (`right.rs`).
    pub(crate) fn reproject(
        &mut self,
        left: &Film,
        plan: Reprojection,
        (src, class, mask): (&mut [u32], &mut [PixelClass], &mut [PixelClass]),
    ) {
        if self.made != Made::Reused {
            reproject_and_classify(left, plan, src, class);
            mask.copy_from_slice(class);
            self.temporal.plan = Some(plan);
            return;
        }
        let t = &mut *self.temporal;
        let n = src.len();
        let (src_was, class_was) = &mut t.was;
        let (left_rows, right_rows) = &mut t.rows;
        let same_plan = t.plan.replace(plan) == Some(plan);
        left_rows.clear();
        let bits = t.left_retraced.words().chunks(t.left_retraced.stride().max(1));
        left_rows.extend(bits.map(|row| !same_plan || row.iter().any(|&word| word != 0)));
        right_rows.resize(left.height() as usize, false);
        src_was.resize(n, NO_SOURCE);
        class_was.resize(n, PixelClass::Traced);
        let buffers = (&mut src_was[..], &mut class_was[..], &mut right_rows[..]);
        reproject_and_classify_rows(left, plan, (&mut *src, &mut *class), left_rows, buffers);
        let changes = Changes {
            now: (class, src),
            before: (class_was, src_was),
            left_retraced: &t.left_retraced,
            right_marks: &mut t.right_marks,
            wedges: [&t.hulls, &[]],
            rows: right_rows,
        };
        let (count, was) = plan_right(changes, mask, &mut t.right_made);
        (self.right_made, self.removed) = (count, Some(was));
    }

    /// Notes the reprojection plan of a fresh frame whose stages 2 to 5 run in one pass
    /// (exact mode), which does not go through [`FrameReuse::reproject`].
    pub(crate) fn reprojected_in_one_pass(&mut self, plan: Reprojection) {
        self.temporal.plan = Some(plan);
    }

    /// What stages 4 and 5 of a reprojecting mode make of the right eye: every pixel, or on
    /// a reused frame those [`FrameReuse::reproject`] chose; the right eye's marks (written
    /// by their passes when the frame marks); and the volumes they mark against.
    pub(crate) fn right(&mut self) -> (Option<&PixelBits>, &mut Marks, Option<&Swept>) {
        let (t, size) = (&mut *self.temporal, self.size);
        if self.made != Made::Reused && (t.right_marks.width(), t.right_marks.height()) != size {
            // (Every pixel of a fresh frame is marked anew.)
            t.right_marks.resize(size.0, size.1);
        }
        let (marks, swept) = Temporal::to_mark(t.swept.as_ref(), &mut t.right_marks, self.made, size);
        ((self.made == Made::Reused).then_some(&t.right_made), marks, swept)
    }

    /// Ends the frame, whose right pixels have the final classes `mask`, after a frame that
    /// counted `last` of each: what it made, and its right pixels by class. A fresh frame
    /// counts its mask; a reused one takes the last counts, less the last classes of the
    /// pixels it made again plus their new ones (kept pixels keep their classes; in full
    /// mode every pixel is traced). The frame is remembered for the next.
    pub(crate) fn finish(self, mask: &[PixelClass], last: PixelCounts) -> (Reuse, PixelCounts) {
        let Self { temporal: t, made, asked: (asked, generation), size, right_made, removed } = self;
        let n = u64::from(size.0) * u64::from(size.1);
        let reused = made == Made::Reused;
        let pixels = match (made, removed) {
            (Made::Reused, Some(removed)) => {
                let last = last.to_array();
                let added = made_classes(mask, &t.right_made);
                PixelCounts::from_array(std::array::from_fn(|c| last[c] - removed[c] + added[c]))
            }
            (Made::Reused, None) => last,
            _ => PixelCounts::of_par(mask),
        };
        let left_made = if reused { t.left_retraced.count() } else { n };
        if t.swept.is_some() {
            t.last = Some((asked, generation, made.marks()));
            std::mem::swap(&mut t.wedges.0, &mut t.wedges.1);
        }
        (Reuse { reused, made: left_made + right_made, pixels: 2 * n }, pixels)
    }
}

/// How many of the pixels `made` names have each class in `mask` (by discriminant).
fn made_classes(mask: &[PixelClass], made: &PixelBits) -> [u64; PixelClass::COUNT] {
    use rayon::prelude::*;
    let w = made.width() as usize;
    if w == 0 {
        return [0; PixelClass::COUNT];
    }
    mask.par_chunks(w)
        .enumerate()
        .map(|(j, row)| {
            let mut n = [0u64; PixelClass::COUNT];
            for i in tracer::bits::ones(made.row(j as u32)) {
                n[row[i as usize] as usize] += 1;
            }
            n
        })
        .reduce(|| [0; PixelClass::COUNT], |a, b| std::array::from_fn(|c| a[c] + b[c]))
}
