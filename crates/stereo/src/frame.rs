//! A stereo frame: the left eye traced, the right eye made per [`Mode`], with statistics.

use std::time::Instant;

use rayon::prelude::*;
use tracer::{render_eye, Camera, Eye, EyeView, Film, RayCounts, Tracer};

use crate::classify::classify_row;
use crate::mode::{Mode, Options};
use crate::reproject::{reproject_row, NO_SOURCE};
use crate::stats::{FrameStats, PixelClass, PixelCounts};

/// The buffers of one stereo pair, reused from frame to frame: a warm `StereoFrame` renders
/// without allocating.
#[derive(Debug, Default)]
pub struct StereoFrame {
    left: Film,
    right: Film,
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

    /// The right eye. Its colour is complete in every mode; its records hold the reused or
    /// recomputed surface of each pixel.
    #[must_use]
    pub fn right(&self) -> &Film {
        &self.right
    }

    /// How each right pixel was made, row-major.
    #[must_use]
    pub fn mask(&self) -> &[PixelClass] {
        &self.mask
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
        stats.left.rays = render_eye(tracer, &lv, &mut self.left);
        stats.stages.trace_left = ms_since(t);
        stats.left.ms = stats.stages.trace_left;

        self.mask.resize(n, PixelClass::Traced);
        self.src.resize(n, NO_SOURCE);
        if n == 0 {
            self.right.resize(width, height);
        } else if opts.mode == Mode::Full {
            let t = Instant::now();
            stats.right.rays = render_eye(tracer, &rv, &mut self.right);
            self.mask.fill(PixelClass::Traced);
            stats.stages.retrace = ms_since(t);
        } else {
            self.right.resize(width, height);
            let t = Instant::now();
            self.reproject(camera, &rv, opts);
            stats.stages.reproject = ms_since(t);

            let t = Instant::now();
            let retraced = self.retrace(tracer, &rv);
            stats.stages.retrace = ms_since(t);

            let t = Instant::now();
            let (filled, sphere_tests) = self.fill(tracer, &rv, opts.mode);
            stats.stages.reshade = ms_since(t);
            stats.right.rays = retraced + filled;
            stats.sphere_tests = sphere_tests;
        }
        stats.right.ms = stats.stages.reproject + stats.stages.retrace + stats.stages.reshade;
        stats.pixels = PixelCounts::of(&self.mask);
        self.stats = stats;
        stats
    }

    /// Stages 2 and 3: the source map and the class of every right pixel.
    fn reproject(&mut self, camera: &Camera, rv: &EyeView, opts: Options) {
        let w = rv.width as usize;
        let shift_scale = camera.ipd * rv.pixels_per_unit();
        let d = camera.distance;
        self.src.par_chunks_mut(w).zip(self.left.z.par_chunks(w)).enumerate().for_each(|(j, (src, z))| {
            reproject_row(z, shift_scale, d, (j * w) as u32, src);
        });
        let (src, left) = (&self.src, &self.left.surface);
        let (edges, shadows) = (opts.edges(), opts.shadow_boundaries());
        self.mask.par_chunks_mut(w).enumerate().for_each(|(j, out)| classify_row(src, left, w, j, edges, shadows, out));
    }

    /// Stage 4: full primary rays for every pixel not reprojected.
    fn retrace(&mut self, tracer: &Tracer, rv: &EyeView) -> RayCounts {
        let w = rv.width as usize;
        let right = &mut self.right;
        right
            .rgb
            .par_chunks_mut(w)
            .zip(right.z.par_chunks_mut(w))
            .zip(right.surface.par_chunks_mut(w))
            .zip(self.mask.par_chunks(w))
            .enumerate()
            .map(|(j, (((rgb, z), surface), mask))| {
                let mut counts = RayCounts::default();
                for (i, &class) in mask.iter().enumerate() {
                    if class != PixelClass::Reprojected {
                        let s = tracer.trace_pixel(rv, i as u32, j as u32, &mut counts);
                        (rgb[i], z[i], surface[i]) = (s.rgb, s.z, s.surface);
                    }
                }
                counts
            })
            .sum()
    }

    /// Stage 5: the reprojected pixels, per mode. Returns the rays cast and the number of
    /// single-sphere tests. In exact mode a pixel whose centre ray misses the named sphere
    /// is a silhouette the edge test did not catch: it is retraced and marked as an edge.
    fn fill(&mut self, tracer: &Tracer, rv: &EyeView, mode: Mode) -> (RayCounts, u64) {
        let w = rv.width as usize;
        let left = &self.left;
        let right = &mut self.right;
        right
            .rgb
            .par_chunks_mut(w)
            .zip(right.z.par_chunks_mut(w))
            .zip(right.surface.par_chunks_mut(w))
            .zip(self.mask.par_chunks_mut(w))
            .zip(self.src.par_chunks(w))
            .enumerate()
            .map(|(j, ((((rgb, z), surface), mask), src))| {
                let mut counts = RayCounts::default();
                let mut tests = 0u64;
                for i in 0..w {
                    if mask[i] != PixelClass::Reprojected {
                        continue;
                    }
                    let s = src[i] as usize;
                    let seen = &left.surface[s];
                    match mode {
                        Mode::Full => unreachable!("full mode does not reproject"),
                        Mode::Copy => {
                            (rgb[i], z[i], surface[i]) = (left.rgb[s], left.z[s], *seen);
                        }
                        Mode::Reshade => {
                            rgb[i] = if seen.is_hit() {
                                let dir = rv.primary_ray(i as u32, j as u32).dir;
                                tracer.reshade(dir, seen, &mut counts)
                            } else {
                                left.rgb[s]
                            };
                            (z[i], surface[i]) = (left.z[s], *seen);
                        }
                        Mode::Exact => {
                            let shaded = if seen.is_hit() {
                                tests += 1;
                                let ray = rv.primary_ray(i as u32, j as u32);
                                if let Some(t) = tracer.intersect_object(&ray, seen.object) {
                                    tracer.shade_known_visibility(rv, &ray, t, seen.object, seen.lights, &mut counts)
                                } else {
                                    mask[i] = PixelClass::RetracedEdge;
                                    tracer.trace_pixel(rv, i as u32, j as u32, &mut counts)
                                }
                            } else {
                                tracer.miss_sample()
                            };
                            (rgb[i], z[i], surface[i]) = (shaded.rgb, shaded.z, shaded.surface);
                        }
                    }
                }
                (counts, tests)
            })
            .reduce(|| (RayCounts::default(), 0), |a, b| (a.0 + b.0, a.1 + b.1))
    }
}
