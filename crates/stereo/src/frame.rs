//! A stereo frame: the left eye traced, the right eye made per [`Mode`], with statistics.

use std::time::Instant;

use rayon::prelude::*;
use tracer::{Camera, Eye, Film, RayCounts, Renderer, SecondView, Tracer, NO_OBJECT};

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
    pub fn render(&mut self, tracer: &Tracer, camera: &Camera, width: u32, height: u32, opts: Options) -> FrameStats {
        let n = width as usize * height as usize;
        let lv = camera.view(Eye::Left, width, height);
        let rv = camera.view(Eye::Right, width, height);
        let mut stats = FrameStats::default();

        let t = Instant::now();
        stats.left.rays = self.left_renderer.render(tracer, &lv, &mut self.left);
        stats.stages.trace_left = ms_since(t);
        stats.left.ms = stats.stages.trace_left;

        self.mask.resize(n, PixelClass::Traced);
        self.src.resize(n, NO_SOURCE);
        (self.right.width, self.right.height) = (width, height);
        self.right.rgb.resize(n, 0);
        if n == 0 {
        } else if opts.mode == Mode::Full {
            let t = Instant::now();
            stats.right.rays = self.right_renderer.render_rgb(tracer, &rv, &mut self.right.rgb);
            self.mask.fill(PixelClass::Traced);
            stats.stages.retrace = ms_since(t);
        } else {
            let t = Instant::now();
            let p = Reprojection::new(tracer, camera, &rv, opts);
            reproject_and_classify(&self.left, p, &mut self.src, &mut self.mask);
            stats.stages.reproject = ms_since(t);

            let t = Instant::now();
            let right = self.right_renderer.second_view(tracer, &rv);
            // The paper's mode gathers its reprojected colours in the same pass over the
            // image as the retrace: nothing is left for stage 5.
            let copy = opts.mode == Mode::Copy;
            let copy_from = copy.then_some(&self.left.rgb[..]);
            let retraced = retrace(right, &self.mask, &self.src, copy_from, &mut self.right);
            stats.stages.retrace = ms_since(t);

            if copy {
                stats.right.rays = retraced;
            } else {
                let t = Instant::now();
                let (filled, sphere_tests) =
                    fill(right, &self.left, &mut self.right, &mut self.mask, &self.src, opts.mode);
                stats.stages.reshade = ms_since(t);
                stats.right.rays = retraced + filled;
                stats.sphere_tests = sphere_tests;
            }
        }
        stats.right.ms = stats.stages.reproject + stats.stages.retrace + stats.stages.reshade;
        stats.pixels = PixelCounts::of(&self.mask);
        self.stats = stats;
        stats
    }
}

/// Stage 5: the reprojected pixels, per mode. Returns the rays cast and the number of
/// single-sphere tests. In exact mode a pixel whose centre ray misses the named sphere
/// is a silhouette the edge test did not catch: it is retraced and marked as an edge.
fn fill(
    right: SecondView<'_>,
    left: &Film,
    out: &mut Image,
    mask: &mut [PixelClass],
    src: &[u32],
    mode: Mode,
) -> (RayCounts, u64) {
    debug_assert!(!matches!(mode, Mode::Full | Mode::Copy), "full and copy modes have no stage 5");
    let w = out.width as usize;
    out.rgb
        .par_chunks_mut(w)
        .zip(mask.par_chunks_mut(w))
        .zip(src.par_chunks(w))
        .enumerate()
        .map(|(j, ((rgb, mask), src))| {
            let mut counts = RayCounts::default();
            let j = j as u32;
            // Reprojected pixels whose source saw background keep its colour; the rest are
            // shaded as one list.
            let mut named = 0u64;
            for i in 0..w {
                if mask[i] == PixelClass::Reprojected {
                    let s = src[i] as usize;
                    if left.object[s] == NO_OBJECT {
                        rgb[i] = left.rgb[s];
                    } else {
                        named += 1;
                    }
                }
            }
            let mask = std::cell::Cell::from_mut(mask).as_slice_of_cells();
            let sources = (0..w as u32).filter_map(|i| {
                let s = src[i as usize] as usize;
                (mask[i as usize].get() == PixelClass::Reprojected && left.object[s] != NO_OBJECT).then_some((i, s))
            });
            if mode == Mode::Reshade {
                let items = sources.map(|(i, s)| (i, left.surface(s)));
                right.reshade(j, items, &mut counts, |i, c| rgb[i as usize] = c);
                return (counts, 0);
            }
            // Exact: each pixel's own ray against the sphere its source saw.
            let items = sources.map(|(i, s)| (i, left.object[s], left.lights[s]));
            right.shade_on(j, items, &mut counts, |i, c, retraced| {
                rgb[i as usize] = c;
                if retraced {
                    mask[i as usize].set(PixelClass::RetracedEdge);
                }
            });
            (counts, named)
        })
        .reduce(|| (RayCounts::default(), 0), |a, b| (a.0 + b.0, a.1 + b.1))
}
