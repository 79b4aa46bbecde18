//! A stereo frame: the stages of the crate's pipeline in order, each timed, into buffers
//! kept from frame to frame. The left eye is traced in full (stage 1, by the tracer's
//! [`Renderer`]); the right eye is traced in full too in [`Mode::Full`], and otherwise
//! reprojected and classified (stages 2 and 3, `reproject.rs`), retraced where it must be
//! (stage 4, `retrace.rs`) and filled as the mode says (stage 5, `fill.rs`).
//!
//! With reuse on ([`StereoFrame::set_reuse`]), a frame whose only change is the scene time
//! makes again only what can have changed: `reuse/` keeps that bookkeeping, and each stage
//! asks it which pixels to make.

use std::time::Instant;

use tracer::{Camera, Eye, EyeView, Film, PixelBatch, PixelBits, Pixels, Record, Renderer, Scene, Target, Tracer};

use crate::fill::{fill, reproject_and_fill_exact, Fill};
use crate::image::Image;
use crate::mode::{Mode, Options};
use crate::reproject::{reproject_and_classify, Reprojection, NO_SOURCE};
use crate::retrace::{retrace, Redo};
use crate::reuse::{Asked, Made, Temporal};
use crate::stats::{FrameStats, PixelClass, PixelCounts, Reuse};

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
    /// Stage 3's classes of this frame.
    class: Vec<PixelClass>,
    /// Each right pixel's final class.
    mask: Vec<PixelClass>,
    stats: FrameStats,
    /// Temporal reuse: what the last frame was, and what this one may keep of it.
    reuse: Temporal,
    /// Whether frames keep both eyes' depth ([`StereoFrame::set_depths`]), and the right
    /// eye's.
    depths: bool,
    right_z: Vec<f32>,
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

    /// Turns reuse across frames on for the frames of `scene` (whose tracers
    /// [`StereoFrame::render`] is then given), or off (`None`; off for a new frame). With it
    /// on, a frame whose only change from the last is the scene time retraces only what can
    /// have changed: the very bytes of a fresh frame, cheaper (`reuse/`). For that the last
    /// frame must have marked where its rays meet the moving spheres' paths, which it does
    /// when the frame before it was asked the same (or it was the first): after a change,
    /// one fresh frame, one fresh frame that marks, then reused frames.
    pub fn set_reuse(&mut self, scene: Option<&Scene>) {
        self.reuse.set(scene);
    }

    /// Whether reuse is on.
    #[must_use]
    pub fn reuse(&self) -> bool {
        self.reuse.is_on()
    }

    /// Keeps both eyes' depth from now on (off for a new frame), as a timewarp reads it: the
    /// left film keeps its depth in every mode, and the right eye gets a depth pass of its
    /// own (its first hits alone, no shading: [`StereoFrame::right_depth`]).
    pub fn set_depths(&mut self, on: bool) {
        self.depths = on;
    }

    /// The right eye's head-space depth per pixel (as the left film's `z`), when frames
    /// keep depths ([`StereoFrame::set_depths`]); empty otherwise.
    #[must_use]
    pub fn right_depth(&self) -> &[f32] {
        if self.depths {
            &self.right_z
        } else {
            &[]
        }
    }

    /// The pixels of the left and the right eye that the last frame made, as opposed to
    /// kept from the frame before; `None` when it made all of them (it did not reuse).
    #[must_use]
    pub fn made(&self) -> Option<(&PixelBits, &PixelBits)> {
        self.stats.reuse.reused.then_some((&self.reuse.left_retraced, &self.reuse.right_made))
    }

    /// Heap bytes of the two eyes' screen bins (what grows with the scene, besides the
    /// tracer's own: [`tracer::Tracer::memory`]).
    #[must_use]
    pub fn bins_memory(&self) -> usize {
        self.left_renderer.memory() + self.right_renderer.memory()
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
        self.render_banded(tracer, camera, (width, height), (0, 0), opts)
    }

    /// [`StereoFrame::render`] with a guard band: each eye is traced `margin` = (mx, my)
    /// pixels wider on each side than the `width` × `height` it shows
    /// ([`tracer::Camera::view_with_margin`]), so its images are (width + 2·mx) ×
    /// (height + 2·my), the shown part bit for bit the frame without the band. A timewarp
    /// turns the head into the band.
    ///
    /// # Panics
    ///
    /// As [`StereoFrame::render`], for the traced size.
    pub fn render_banded(
        &mut self,
        tracer: &Tracer,
        camera: &Camera,
        (width, height): (u32, u32),
        margin: (u32, u32),
        opts: Options,
    ) -> FrameStats {
        let lv = camera.view_with_margin(Eye::Left, width, height, margin);
        let rv = camera.view_with_margin(Eye::Right, width, height, margin);
        let size = (lv.width, lv.height);
        let n = pixel_count(size.0, size.1);
        let asked = Asked { camera: *camera, width, height, margin, opts };
        let made = self.reuse.begin(tracer, asked);
        let mut stats = FrameStats::default();

        // Stage 1: the left eye, keeping only what the mode's later stages read of its record.
        let t = Instant::now();
        let record = if opts.mode == Mode::Full && !self.depths { Record::Colour } else { Record::Keys };
        let (pixels, target) = self.reuse.left(&mut self.left, record, made, size);
        stats.left.rays = self.left_renderer.render(tracer, &lv, pixels, target);
        stats.stages.trace_left = ms_since(t);
        stats.left.ms = stats.stages.trace_left;

        self.mask.resize(n, PixelClass::Traced);
        self.src.resize(n, NO_SOURCE);
        self.class.resize(n, PixelClass::Traced);
        (self.right.width, self.right.height) = size;
        self.right.rgb.resize(n, 0);
        // The right pixels made, and on a reused frame of a reprojecting mode the last
        // classes of the pixels made again.
        let (mut right_made, mut removed) = (n as u64, None);
        if n == 0 {
            // Nothing to make.
        } else if opts.mode == Mode::Full {
            // The right eye as the left: timed as stage 4.
            let t = Instant::now();
            let (pixels, target, count) = self.reuse.right_full(&mut self.right.rgb, made, size);
            stats.right.rays = self.right_renderer.render(tracer, &rv, pixels, target);
            right_made = count;
            self.mask.fill(PixelClass::Traced);
            stats.stages.retrace = ms_since(t);
        } else if made != Made::Reused && opts.mode == Mode::Exact {
            // Stages 2 to 5 in one banded pass.
            self.exact_in_one_pass(tracer, (camera, &rv), opts, made, &mut stats);
        } else {
            // Stages 2 and 3: the source map and the class of every right pixel (on a
            // reused frame, of the rows that can have changed).
            let t = Instant::now();
            let plan = Reprojection::new(tracer, camera, &rv, opts);
            if made == Made::Reused {
                let planes = (&mut self.src[..], &mut self.class[..], &mut self.mask[..]);
                let (count, was) = self.reuse.reproject_changed(&self.left, plan, planes);
                (right_made, removed) = (count, Some(was));
            } else {
                reproject_and_classify(&self.left, plan, &mut self.src, &mut self.class);
                self.mask.copy_from_slice(&self.class);
                self.reuse.planned(plan);
            }
            stats.stages.reproject = ms_since(t);
            // Stages 4 and 5.
            let (only, marks, swept) = self.reuse.right(made, size);
            let right = self.right_renderer.batch(tracer, &rv).marking(swept);
            let redo = Redo { only, marks, mark: swept.is_some() };
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
        if self.depths {
            // The right eye's depth, for a timewarp: its first hits alone.
            let t = Instant::now();
            self.right_renderer.render(tracer, &rv, Pixels::All, Target::depth(&mut self.right_z));
            stats.stages.depth = ms_since(t);
        }
        stats.pixels = self.pixel_counts(made, removed);
        let reused = made == Made::Reused;
        let left_made = if reused { self.reuse.left_retraced.count() } else { n as u64 };
        stats.reuse = Reuse { reused, made: left_made + right_made, pixels: 2 * n as u64 };
        self.reuse.end(tracer, asked, made);
        self.stats = stats;
        stats
    }
}

/// Stages 4 and 5 of a reprojecting `mode`, by `right` (the right eye's pixels) into `out`,
/// from the `left` film (rendered for the view `lv`), the classes in `mask` and the sources
/// in `src`, over the pixels and marks `redo` names. The paper's mode gathers its
/// reprojected colours in stage 4's pass over the image: it has no stage 5. Exact mode
/// retraces in stage 5's pass instead (`fill.rs`).
fn retrace_and_fill(
    right: PixelBatch<'_>,
    (lv, left): (&EyeView, &Film),
    mode: Mode,
    (mask, src): (&mut [PixelClass], &[u32]),
    out: &mut Image,
    redo: Redo<'_>,
    stats: &mut FrameStats,
) {
    let how = Fill::of(mode);
    let Redo { only, marks, mark } = redo;
    if how != Some(Fill::Exact) {
        let t = Instant::now();
        let copy_from = (mode == Mode::Copy).then_some(&left.rgb[..]);
        stats.right.rays = retrace(right, mask, src, copy_from, out, Redo { only, marks: &mut *marks, mark });
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

impl StereoFrame {
    /// Stages 2 to 5 of a fresh exact frame in one banded pass (`fill.rs`), for the right
    /// eye's view `rv` of `camera`, marking if `made` does. The pass's time goes to `stats`,
    /// split between the reproject and reshade stages as the thread time each part took.
    fn exact_in_one_pass(
        &mut self,
        tracer: &Tracer,
        (camera, rv): (&Camera, &EyeView),
        opts: Options,
        made: Made,
        stats: &mut FrameStats,
    ) {
        let t = Instant::now();
        let plan = Reprojection::new(tracer, camera, rv, opts);
        self.reuse.planned(plan);
        let (_, marks, swept) = self.reuse.right(made, (rv.width, rv.height));
        let right = self.right_renderer.batch(tracer, rv).marking(swept);
        let bins_s = t.elapsed().as_secs_f64();
        let planes = (&mut self.src[..], &mut self.class[..], &mut self.mask[..]);
        let cost = reproject_and_fill_exact(right, &self.left, plan, planes, &mut self.right, (marks, swept.is_some()));
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
    fn pixel_counts(&self, made: Made, removed: Option<[u64; PixelClass::COUNT]>) -> PixelCounts {
        match (made, removed) {
            (Made::Reused, Some(removed)) => {
                let last = self.stats.pixels.to_array();
                let added = made_classes(&self.mask, &self.reuse.right_made);
                PixelCounts::from_array(std::array::from_fn(|c| last[c] - removed[c] + added[c]))
            }
            (Made::Reused, None) => self.stats.pixels,
            _ => PixelCounts::of_par(&self.mask),
        }
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
