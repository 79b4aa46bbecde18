//! A stereo frame: the stages of the crate's pipeline in order, each timed, into buffers
//! kept from frame to frame. The left eye is traced in full (stage 1, by the tracer's
//! [`Renderer`]); the right eye is traced in full too in [`Mode::Full`], and otherwise
//! reprojected and classified (stages 2 and 3, `reproject.rs`), retraced where it must be
//! (stage 4, `retrace.rs`) and filled as the mode says (stage 5, `fill.rs`).
//!
//! With reuse on ([`StereoFrame::set_reuse`]), a frame whose only change is the scene time
//! retraces only what can have changed (`reuse.rs` has the rule and why it is exact).

use std::time::Instant;

use tracer::{Arc, Camera, Eye, EyeView, Film, Marks, PixelBits, Record, Renderer, SecondView, Tracer};

use crate::fill::{fill, reproject_and_fill_exact, Fill};
use crate::image::Image;
use crate::mode::{Mode, Options};
use crate::reproject::{reproject_and_classify, reproject_and_classify_rows, Reprojection, NO_SOURCE};
use crate::retrace::{retrace, Redo};
use crate::reuse::{plan_right, Changes};
use crate::stats::{FrameStats, PixelClass, PixelCounts, Reuse};

/// What a frame was asked for, besides the tracer: a frame may reuse the last one only if
/// this is the same and the tracer differs only in time.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Asked {
    camera: Camera,
    width: u32,
    height: u32,
    opts: Options,
}

/// The buffers of one stereo pair, reused from frame to frame: a warm `StereoFrame` renders
/// without allocating.
#[derive(Debug, Default)]
pub struct StereoFrame {
    left: Film,
    right: Image,
    /// The left eye's renderer.
    left_renderer: Renderer,
    /// The right eye's renderer, for the pixels it traces.
    right_renderer: Renderer,
    /// For each right pixel, the left pixel that fills it, or [`NO_SOURCE`].
    src: Vec<u32>,
    /// Each right pixel's final class.
    mask: Vec<PixelClass>,
    stats: FrameStats,
    /// Whether frames may reuse the last one.
    reuse: bool,
    /// What the last frame was asked for, and whether it was marked for reuse.
    last: Option<(Asked, bool)>,
    /// The last frame's tracer fingerprint, and this frame's.
    print: (Vec<u32>, Vec<u32>),
    /// Stage 3's classes of this frame, and the last frame's sources and classes (of the
    /// rows redone).
    class: Vec<PixelClass>,
    was: (Vec<u32>, Vec<PixelClass>),
    /// The last frame's reprojection plan.
    plan: Option<Reprojection>,
    /// Per left row, whether a pixel of it was retraced; per right row, whether stages 2
    /// and 3 redid it.
    rows: (Vec<bool>, Vec<bool>),
    /// Where the right pixels' own rays meet the moving spheres' swept volumes.
    right_marks: Marks,
    /// The moving spheres' wedges in the last frame, and in this one.
    wedges: (Vec<Arc>, Vec<Arc>),
    /// Per ring, the arc that holds both.
    wedge_hulls: Vec<Arc>,
    /// The left pixels retraced this frame.
    left_retraced: PixelBits,
    /// The right pixels made this frame (all of them unless it reused the last).
    right_made: PixelBits,
}

/// Pixels per eye of a `width` × `height` frame, which must be fewer than `u32::MAX`: the
/// source map names a left pixel by a `u32`, and [`NO_SOURCE`] is `u32::MAX`.
fn pixel_count(width: u32, height: u32) -> usize {
    let n = u64::from(width) * u64::from(height);
    assert!(n < u64::from(NO_SOURCE), "{width}×{height} pixels per eye: a pixel's index must be below u32::MAX");
    n as usize
}

/// Milliseconds since `t`.
fn ms_since(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

impl StereoFrame {
    /// Empty buffers; the first [`StereoFrame::render`] sizes them.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The left eye, fully traced, with its visible-surface record.
    #[must_use]
    pub fn left(&self) -> &Film {
        &self.left
    }

    /// The right eye, complete in every mode.
    #[must_use]
    pub fn right(&self) -> &Image {
        &self.right
    }

    /// How each right pixel was made, row-major.
    #[must_use]
    pub fn mask(&self) -> &[PixelClass] {
        &self.mask
    }

    /// For each right pixel, the index of the left pixel reprojected into it, or
    /// [`NO_SOURCE`] (not meaningful in full mode).
    #[must_use]
    pub fn sources(&self) -> &[u32] {
        &self.src
    }

    /// Turns reuse across frames on or off (off for a new frame). With it on, a frame whose
    /// only change from the last is the scene time retraces only what can have changed:
    /// the very bytes of a fresh frame, cheaper (`reuse.rs`). For that the last frame must
    /// have marked where its rays meet the moving spheres' paths, which it does when the
    /// frame before it was asked the same (or it was the first): after a change, one fresh
    /// frame, one fresh frame that marks, then reused frames.
    pub fn set_reuse(&mut self, on: bool) {
        if on != self.reuse {
            self.last = None;
        }
        self.reuse = on;
    }

    /// Whether reuse is on.
    #[must_use]
    pub fn reuse(&self) -> bool {
        self.reuse
    }

    /// The pixels of the left and the right eye that the last frame made, as opposed to
    /// kept from the frame before; `None` when it made all of them (it did not reuse).
    #[must_use]
    pub fn made(&self) -> Option<(&PixelBits, &PixelBits)> {
        self.stats.reuse.reused.then_some((&self.left_retraced, &self.right_made))
    }

    /// The last frame's statistics.
    #[must_use]
    pub fn stats(&self) -> &FrameStats {
        &self.stats
    }

    /// Renders one stereo pair of `width` × `height` per eye.
    ///
    /// # Panics
    ///
    /// If an eye has `u32::MAX` pixels or more: the source map names a left pixel by a
    /// `u32`. (Such a frame would need hundreds of gigabytes.)
    pub fn render(&mut self, tracer: &Tracer, camera: &Camera, width: u32, height: u32, opts: Options) -> FrameStats {
        let n = pixel_count(width, height);
        let (lv, rv) = (camera.view(Eye::Left, width, height), camera.view(Eye::Right, width, height));
        let mut stats = FrameStats::default();
        let asked = Asked { camera: *camera, width, height, opts };
        tracer.fingerprint(&mut self.print.1);
        let same = self.last.is_some_and(|(last, _)| last == asked) && self.print.0 == self.print.1;
        let reused = self.reuse && same && self.last.is_some_and(|(_, marked)| marked);
        // Marking costs about two fresh frames: it is done only when reuse can follow,
        // once the request has held still for a frame (or on the first frame), so a
        // moving head pays nothing for it.
        let mark = self.reuse && (same || self.last.is_none());
        std::mem::swap(&mut self.print.0, &mut self.print.1);
        // The wedges are taken out for the frame, and put back (swapped) at its end.
        let mut wedge_lists = std::mem::take(&mut self.wedges);
        tracer.wedges(&mut wedge_lists.1);
        // Each ring's two wedges as one arc (the shortest that holds both: one test per
        // pixel instead of two, and hardly larger, as a sphere moves little in a frame).
        let mut hulls = std::mem::take(&mut self.wedge_hulls);
        hulls.clear();
        if wedge_lists.0.len() == wedge_lists.1.len() {
            hulls.extend(wedge_lists.0.iter().zip(&wedge_lists.1).map(|(a, b)| a.hull(*b)));
        } else {
            // (Never on a reused frame, whose rings are the last frame's; but if so, every
            // marked pixel is retraced.)
            hulls.extend(wedge_lists.1.iter().map(|_| Arc::FULL));
        }
        let wedges: [&[Arc]; 2] = [&hulls, &[]];

        // Stage 1: the left eye, with its visible-surface record.
        let t = Instant::now();
        // Each mode keeps only what its later stages read of the left eye's record.
        let record = match opts.mode {
            Mode::Full => Record::Colour,
            Mode::Copy | Mode::Exact | Mode::Reshade => Record::Keys,
        };
        let left = &mut self.left;
        stats.left.rays = if reused {
            left.dynamic.select(wedges, &mut self.left_retraced);
            self.left_renderer.retrace_only(tracer, &lv, left, &self.left_retraced)
        } else if mark {
            self.left_renderer.render_marking(tracer, &lv, left, record)
        } else {
            self.left_renderer.render_keeping(tracer, &lv, left, record)
        };
        stats.stages.trace_left = ms_since(t);
        stats.left.ms = stats.stages.trace_left;

        self.mask.resize(n, PixelClass::Traced);
        self.src.resize(n, NO_SOURCE);
        (self.right.width, self.right.height) = (width, height);
        self.right.rgb.resize(n, 0);
        if !reused && (self.right_marks.width(), self.right_marks.height()) != (width, height) {
            // (Every pixel of a fresh frame is marked anew.)
            self.right_marks.resize(width, height);
        }
        let mut made = n as u64;
        // On a reused frame of a reprojecting mode: the last classes of the pixels made again.
        let mut removed = None;
        if n == 0 {
            // Nothing to make.
        } else if opts.mode == Mode::Full {
            let t = Instant::now();
            let (renderer, rgb, marks) = (&mut self.right_renderer, &mut self.right.rgb, &mut self.right_marks);
            stats.right.rays = if reused {
                made = marks.select(wedges, &mut self.right_made);
                renderer.retrace_rgb_only(tracer, &rv, rgb, (marks, &self.right_made))
            } else if mark {
                renderer.render_rgb_marking(tracer, &rv, rgb, marks)
            } else {
                renderer.render_rgb(tracer, &rv, rgb)
            };
            self.mask.fill(PixelClass::Traced);
            stats.stages.retrace = ms_since(t);
        } else if !reused && opts.mode == Mode::Exact {
            self.exact_in_one_pass(tracer, (camera, &rv), opts, mark, &mut stats);
        } else {
            // Stages 2 and 3: the source map and the class of every right pixel.
            let t = Instant::now();
            let plan = Reprojection::new(tracer, camera, &rv, opts);
            self.class.resize(n, PixelClass::Traced);
            let only = if reused {
                let was;
                (made, was) = self.reproject_changed(plan, wedges);
                removed = Some(was);
                Some(&self.right_made)
            } else {
                reproject_and_classify(&self.left, plan, &mut self.src, &mut self.class);
                self.mask.copy_from_slice(&self.class);
                None
            };
            self.plan = Some(plan);
            stats.stages.reproject = ms_since(t);

            let right = self.right_renderer.second_view(tracer, &rv).marking(mark);
            let redo = (only, &mut self.right_marks, mark);
            retrace_and_fill(
                right,
                (&lv, &self.left),
                opts.mode,
                (&mut self.mask, &self.src),
                &mut self.right,
                redo,
                &mut stats,
            );
        }
        stats.right.ms = stats.stages.reproject + stats.stages.retrace + stats.stages.reshade;
        stats.pixels = self.pixel_counts(reused, removed);
        let left_made = if reused { self.left_retraced.count() } else { n as u64 };
        stats.reuse = Reuse { reused, made: left_made + made, pixels: 2 * n as u64 };
        self.last = Some((asked, mark));
        self.wedges = (wedge_lists.1, wedge_lists.0);
        self.wedge_hulls = hulls;
        self.stats = stats;
        stats
    }
}

/// Stages 4 and 5 of a reprojecting `mode`, by `right` (the right eye's view) into `out`,
/// from the `left` film (rendered for the view `lv`), the classes in `mask` and the sources
/// in `src`, over the pixels `only` names (`None`: all), marking them in `marks` if `mark`.
/// The paper's mode gathers its reprojected colours in stage 4's pass over the image: it
/// has no stage 5. Exact mode retraces in stage 5's pass instead (`fill.rs`).
fn retrace_and_fill(
    right: SecondView<'_>,
    (lv, left): (&EyeView, &Film),
    mode: Mode,
    (mask, src): (&mut [PixelClass], &[u32]),
    out: &mut Image,
    (only, marks, mark): (Option<&PixelBits>, &mut Marks, bool),
    stats: &mut FrameStats,
) {
    let how = Fill::of(mode);
    if how != Some(Fill::Exact) {
        let t = Instant::now();
        let copy_from = (mode == Mode::Copy).then_some(&left.rgb[..]);
        stats.right.rays = retrace(right, mask, src, copy_from, out, Redo { only, marks, mark });
        stats.stages.retrace = ms_since(t);
    }
    if let Some(how) = how {
        let t = Instant::now();
        let filled = fill(right, (lv, left), how, (mask, src), out, Redo { only, marks, mark });
        stats.stages.reshade = ms_since(t);
        stats.right.rays += filled.rays;
        stats.sphere_tests = filled.sphere_tests;
    }
}

/// How many of the pixels `made` names have each class in `mask` (by discriminant).
fn made_classes(mask: &[PixelClass], made: &PixelBits) -> [u64; 5] {
    use rayon::prelude::*;
    let w = made.width() as usize;
    if w == 0 {
        return [0; 5];
    }
    mask.par_chunks(w)
        .enumerate()
        .map(|(j, row)| {
            let mut n = [0u64; 5];
            for i in tracer::bits::ones(made.row(j as u32)) {
                n[row[i as usize] as usize] += 1;
            }
            n
        })
        .reduce(|| [0; 5], |a, b| std::array::from_fn(|c| a[c] + b[c]))
}

impl StereoFrame {
    /// Stages 2 to 5 of a fresh exact frame in one banded pass (`fill.rs`), for the right
    /// eye's view `rv` of `camera`, marking if `mark`. The pass's time goes to `stats`,
    /// split between the reproject and reshade stages as the thread time each part took.
    fn exact_in_one_pass(
        &mut self,
        tracer: &Tracer,
        (camera, rv): (&Camera, &EyeView),
        opts: Options,
        mark: bool,
        stats: &mut FrameStats,
    ) {
        let t = Instant::now();
        let plan = Reprojection::new(tracer, camera, rv, opts);
        self.plan = Some(plan);
        self.class.resize(self.mask.len(), PixelClass::Traced);
        let right = self.right_renderer.second_view(tracer, rv).marking(mark);
        let bins_s = t.elapsed().as_secs_f64();
        let planes = (&mut self.src[..], &mut self.class[..], &mut self.mask[..]);
        let marks = (&mut self.right_marks, mark);
        let cost = reproject_and_fill_exact(right, &self.left, plan, planes, &mut self.right, marks);
        let (ms, fill_s) = (ms_since(t), cost.fill_s + bins_s);
        let share = cost.reproject_s / (cost.reproject_s + fill_s).max(f64::MIN_POSITIVE);
        (stats.stages.reproject, stats.stages.reshade) = (ms * share, ms * (1.0 - share));
        stats.right.rays = cost.filled.rays;
        stats.sphere_tests = cost.filled.sphere_tests;
    }

    /// The right pixels by class. A fresh frame counts its mask; a reused one takes the
    /// last frame's counts, less the last classes of the pixels it made again (`removed`,
    /// `None` in full mode, where every pixel is traced) plus their new ones: kept pixels
    /// keep their classes.
    fn pixel_counts(&self, reused: bool, removed: Option<[u64; 5]>) -> PixelCounts {
        match (reused, removed) {
            (true, Some(removed)) => {
                let last = self.stats.pixels.to_array();
                let added = made_classes(&self.mask, &self.right_made);
                PixelCounts::from_array(std::array::from_fn(|c| last[c] - removed[c] + added[c]))
            }
            (true, None) => self.stats.pixels,
            (false, _) => PixelCounts::of_par(&self.mask),
        }
    }

    /// Stages 2 and 3 of a reused frame: only the rows that read a retraced left row (all
    /// of them if the plan moved), then the right pixels to make again (`reuse.rs`) into
    /// `right_made`. Returns how many.
    fn reproject_changed(&mut self, plan: Reprojection, wedges: [&[Arc]; 2]) -> (u64, [u64; 5]) {
        let n = self.src.len();
        let (src_was, class_was) = &mut self.was;
        let (left_rows, right_rows) = &mut self.rows;
        let same_plan = self.plan == Some(plan);
        left_rows.clear();
        let bits = self.left_retraced.words().chunks(self.left_retraced.stride().max(1));
        left_rows.extend(bits.map(|row| !same_plan || row.iter().any(|&word| word != 0)));
        right_rows.resize(self.left.height() as usize, false);
        src_was.resize(n, NO_SOURCE);
        class_was.resize(n, PixelClass::Traced);
        let buffers = (&mut src_was[..], &mut class_was[..], &mut right_rows[..]);
        reproject_and_classify_rows(&self.left, plan, (&mut self.src, &mut self.class), left_rows, buffers);
        let changes = Changes {
            now: (&self.class, &self.src),
            before: (class_was, src_was),
            left_retraced: &self.left_retraced,
            right_marks: &mut self.right_marks,
            wedges,
            rows: right_rows,
        };
        plan_right(changes, &mut self.mask, &mut self.right_made)
    }
}

#[cfg(test)]
mod tests {
    use super::pixel_count;

    #[test]
    fn an_eye_just_below_u32_max_pixels_is_accepted() {
        assert_eq!(pixel_count(65_535, 65_536), 65_535 * 65_536);
        assert_eq!(pixel_count(0, 7), 0);
    }

    #[test]
    #[should_panic(expected = "must be below u32::MAX")]
    fn an_eye_of_u32_max_pixels_is_refused() {
        // 65 535 × 65 537 = 2³² − 1 = u32::MAX, the value that marks "no source".
        pixel_count(65_535, 65_537);
    }
}
