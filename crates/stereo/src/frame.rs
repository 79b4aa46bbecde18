//! A stereo frame: the stages of the crate's pipeline in order, each timed, into buffers
//! kept from frame to frame. The left eye is traced in full (stage 1, by the tracer's
//! [`Renderer`]); the right eye is traced in full too in [`Mode::Full`], and otherwise
//! reprojected and classified (stages 2 and 3, `reproject.rs`), retraced where it must be
//! (stage 4, `retrace.rs`) and filled as the mode says (stage 5, `fill.rs`).

use std::time::Instant;

use tracer::{Camera, Eye, Film, Record, Renderer, Tracer};

use crate::fill::{fill, Fill};
use crate::image::Image;
use crate::mode::{Mode, Options};
use crate::reproject::{reproject_and_classify, Reprojection, NO_SOURCE};
use crate::retrace::retrace;
use crate::stats::{FrameStats, PixelClass, PixelCounts};

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
    mask: Vec<PixelClass>,
    stats: FrameStats,
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

        // Stage 1: the left eye, with its visible-surface record.
        let t = Instant::now();
        // Each mode keeps only what its later stages read of the left eye's record.
        let record = match opts.mode {
            Mode::Full => Record::Colour,
            Mode::Copy | Mode::Exact | Mode::Reshade => Record::Keys,
        };
        stats.left.rays = self.left_renderer.render_keeping(tracer, &lv, &mut self.left, record);
        stats.stages.trace_left = ms_since(t);
        stats.left.ms = stats.stages.trace_left;

        self.mask.resize(n, PixelClass::Traced);
        self.src.resize(n, NO_SOURCE);
        (self.right.width, self.right.height) = (width, height);
        self.right.rgb.resize(n, 0);
        if n == 0 {
            // Nothing to make.
        } else if opts.mode == Mode::Full {
            let t = Instant::now();
            stats.right.rays = self.right_renderer.render_rgb(tracer, &rv, &mut self.right.rgb);
            self.mask.fill(PixelClass::Traced);
            stats.stages.retrace = ms_since(t);
        } else {
            // Stages 2 and 3: the source map and the class of every right pixel.
            let t = Instant::now();
            let plan = Reprojection::new(tracer, camera, &rv, opts);
            reproject_and_classify(&self.left, plan, &mut self.src, &mut self.mask);
            stats.stages.reproject = ms_since(t);

            // Stage 4. The paper's mode gathers its reprojected colours in the same pass
            // over the image: it has no stage 5.
            let t = Instant::now();
            let right = self.right_renderer.second_view(tracer, &rv);
            let copy_from = (opts.mode == Mode::Copy).then_some(&self.left.rgb[..]);
            stats.right.rays = retrace(right, &self.mask, &self.src, copy_from, &mut self.right);
            stats.stages.retrace = ms_since(t);

            // Stage 5.
            if let Some(how) = Fill::of(opts.mode) {
                let t = Instant::now();
                let filled = fill(right, (&lv, &self.left), how, &mut self.mask, &self.src, &mut self.right);
                stats.stages.reshade = ms_since(t);
                stats.right.rays += filled.rays;
                stats.sphere_tests = filled.sphere_tests;
            }
        }
        stats.right.ms = stats.stages.reproject + stats.stages.retrace + stats.stages.reshade;
        stats.pixels = PixelCounts::of(&self.mask);
        self.stats = stats;
        stats
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
