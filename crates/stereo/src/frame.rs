//! A stereo frame: the left eye traced, the right eye made per [`Mode`], with statistics.

use std::time::Instant;

use rayon::prelude::*;
use tracer::{render_eye, render_rgb, Camera, Eye, EyeView, Film, PrimaryBins, RayCounts, Tracer, NO_OBJECT};

use crate::classify::{classify_row, key, GAP_KEY};
use crate::mode::{Mode, Options};
use crate::reproject::{reproject_row, NO_SOURCE};
use crate::stats::{FrameStats, PixelClass, PixelCounts};

/// An image without a visible-surface record: the right eye.
#[derive(Clone, Debug, Default)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// sRGB pixels packed `0x00RRGGBB`, row-major.
    pub rgb: Vec<u32>,
}

/// The buffers of one stereo pair, reused from frame to frame: a warm `StereoFrame` renders
/// without allocating.
#[derive(Debug, Default)]
pub struct StereoFrame {
    left: Film,
    right: Image,
    /// Screen bins of the right eye's view, for the pixels it traces.
    right_bins: PrimaryBins,
    /// For each right pixel, the left pixel that fills it, or [`NO_SOURCE`].
    src: Vec<u32>,
    mask: Vec<PixelClass>,
    stats: FrameStats,
}

/// Width in pixels of the strip at the right edge of the right image that must be retraced
/// whatever lands there.
///
/// A point in front of the window (z < 0) shifts left by e·z/(d+z), so near things the
/// left eye sees just past its right edge appear inside the right image, where the
/// reprojection can only have put the farther surfaces the left eye did see. The strip is
/// as wide as the largest such shift, from the nearest sphere point in the scene; a sphere
/// reaching the eyes' plane makes it the whole row.
fn right_border_strip(tracer: &Tracer, camera: &Camera, shift_scale: f32, w: usize) -> usize {
    let forward = camera.world_from_head() * glam::Vec3::Z;
    let Some(nearest) = tracer.nearest_depth(camera.position, forward) else { return 0 };
    if nearest <= 0.0 {
        return w;
    }
    let z = nearest - camera.distance;
    if z >= 0.0 {
        return 0;
    }
    let shift = -shift_scale * (1.0 - camera.distance / (camera.distance + z));
    if shift <= 0.0 {
        return 0;
    }
    // One pixel of margin for where the left eye's last pixel centre lands.
    (shift.ceil() as usize + 1).min(w)
}

/// Rows per band of the reprojection pass.
const BAND: usize = 16;

thread_local! {
    /// Per-thread scratch of the reprojection pass (targets, sources and keys of a band and
    /// its halo rows), kept across frames: rayon's `for_each_init` would allocate afresh
    /// for every split of the work, every frame.
    static BAND_SCRATCH: std::cell::RefCell<(Vec<i32>, Vec<u32>, Vec<u64>)> = const {
        std::cell::RefCell::new((Vec::new(), Vec::new(), Vec::new()))
    };
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
        stats.left.rays = render_eye(tracer, &lv, &mut self.left);
        stats.stages.trace_left = ms_since(t);
        stats.left.ms = stats.stages.trace_left;

        self.mask.resize(n, PixelClass::Traced);
        self.src.resize(n, NO_SOURCE);
        (self.right.width, self.right.height) = (width, height);
        self.right.rgb.resize(n, 0);
        if n == 0 {
        } else if opts.mode == Mode::Full {
            let t = Instant::now();
            stats.right.rays = render_rgb(tracer, &rv, &mut self.right_bins, &mut self.right.rgb);
            self.mask.fill(PixelClass::Traced);
            stats.stages.retrace = ms_since(t);
        } else {
            let t = Instant::now();
            self.reproject(tracer, camera, &rv, opts);
            stats.stages.reproject = ms_since(t);

            let t = Instant::now();
            self.right_bins.build(tracer, &rv);
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
    fn reproject(&mut self, tracer: &Tracer, camera: &Camera, rv: &EyeView, opts: Options) {
        let w = rv.width as usize;
        let shift_scale = camera.ipd * rv.pixels_per_unit();
        let d = camera.distance;
        let strip = right_border_strip(tracer, camera, shift_scale, w);
        // With IPD 0 every left pixel lands exactly on its own centre: the reprojection is
        // exact and no edge or shadow boundary needs a second look.
        let exact_landing = shift_scale == 0.0;
        let (edges, shadows) = (opts.edges() && !exact_landing, opts.shadow_boundaries() && !exact_landing);
        let (left, h) = (&self.left, rv.height as usize);
        // Bands of rows, each reprojected with one halo row above and below into per-worker
        // scratch and classified at once while it is in cache: one pass over the left
        // planes instead of a reprojection pass and a classification pass.
        let bands = self.src.par_chunks_mut(w * BAND).zip(self.mask.par_chunks_mut(w * BAND));
        bands.enumerate().for_each(|(b, (src_band, mask_band))| {
            BAND_SCRATCH.with_borrow_mut(|(targets, srcs, keys)| {
                let (j0, rows) = (b * BAND, src_band.len() / w);
                let (lo, hi) = (j0.saturating_sub(1), (j0 + rows + 1).min(h));
                srcs.resize((hi - lo) * w, NO_SOURCE);
                keys.resize((hi - lo) * w, GAP_KEY);
                for j in lo..hi {
                    let row = (j - lo) * w..(j - lo + 1) * w;
                    let src = &mut srcs[row.clone()];
                    reproject_row(&left.z[j * w..(j + 1) * w], shift_scale, d, (j * w) as u32, src, targets);
                    src[w - strip..].fill(NO_SOURCE);
                    for (k, &s) in keys[row].iter_mut().zip(src.iter()) {
                        *k = if s == NO_SOURCE {
                            GAP_KEY
                        } else {
                            key(left.object[s as usize], left.lights[s as usize])
                        };
                    }
                }
                src_band.copy_from_slice(&srcs[(j0 - lo) * w..(j0 - lo + rows) * w]);
                for (r, out) in mask_band.chunks_mut(w).enumerate() {
                    classify_row(keys, w, j0 - lo + r, edges, shadows, out);
                }
            });
        });
    }

    /// Stage 4: full primary rays for every pixel not reprojected.
    fn retrace(&mut self, tracer: &Tracer, rv: &EyeView) -> RayCounts {
        let w = rv.width as usize;
        let bins = &self.right_bins;
        self.right
            .rgb
            .par_chunks_mut(w)
            .zip(self.mask.par_chunks(w))
            .enumerate()
            .map(|(j, (rgb, mask))| {
                let mut counts = RayCounts::default();
                for (i, &class) in mask.iter().enumerate() {
                    if class != PixelClass::Reprojected {
                        rgb[i] = tracer.trace_primary(bins, i as u32, j as u32, &mut counts).rgb;
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
        let (left, bins) = (&self.left, &self.right_bins);
        self.right
            .rgb
            .par_chunks_mut(w)
            .zip(self.mask.par_chunks_mut(w))
            .zip(self.src.par_chunks(w))
            .enumerate()
            .map(|(j, ((rgb, mask), src))| {
                let mut counts = RayCounts::default();
                let mut tests = 0u64;
                for i in 0..w {
                    if mask[i] != PixelClass::Reprojected {
                        continue;
                    }
                    let s = src[i] as usize;
                    let object = left.object[s];
                    let hit = object != NO_OBJECT;
                    match mode {
                        Mode::Full => unreachable!("full mode does not reproject"),
                        Mode::Copy => rgb[i] = left.rgb[s],
                        Mode::Reshade => {
                            rgb[i] = if hit {
                                let dir = rv.primary_ray(i as u32, j as u32).dir;
                                tracer.reshade(dir, &left.surface(s), &mut counts)
                            } else {
                                left.rgb[s]
                            };
                        }
                        Mode::Exact => {
                            rgb[i] = if hit {
                                tests += 1;
                                let ray = rv.primary_ray(i as u32, j as u32);
                                if let Some(t) = tracer.intersect_object(&ray, object) {
                                    tracer.shade_known_visibility(rv, &ray, t, object, left.lights[s], &mut counts).rgb
                                } else {
                                    mask[i] = PixelClass::RetracedEdge;
                                    tracer.trace_primary(bins, i as u32, j as u32, &mut counts).rgb
                                }
                            } else {
                                left.rgb[s]
                            };
                        }
                    }
                }
                (counts, tests)
            })
            .reduce(|| (RayCounts::default(), 0), |a, b| (a.0 + b.0, a.1 + b.1))
    }
}

#[cfg(test)]
mod tests {
    use tracer::Scene;

    use super::*;

    #[test]
    fn retracing_every_pixel_reproduces_the_full_trace() {
        let scene = Scene::from_toml(include_str!("../../../assets/scenes/window.toml"), "window.toml").unwrap();
        let tracer = Tracer::new(&scene, 0.7);
        let (w, h) = (120, 68);
        let mut frame = StereoFrame::new();
        frame.render(&tracer, &scene.camera, w, h, Options { mode: Mode::Copy, retrace_edges: false });
        frame.mask.fill(PixelClass::RetracedGap);
        let rv = scene.camera.view(Eye::Right, w, h);
        let counts = frame.retrace(&tracer, &rv);
        let mut full = Vec::new();
        let full_counts = render_rgb(&tracer, &rv, &mut PrimaryBins::new(), &mut full);
        assert_eq!(frame.right.rgb, full);
        assert_eq!(counts, full_counts);
    }
}
