//! A stereo frame: the left eye traced, the right eye made per [`Mode`], with statistics.

use std::time::Instant;

use rayon::prelude::*;
use tracer::{Camera, Eye, EyeView, Film, RayCounts, Renderer, SecondView, Tracer, NO_OBJECT};

use crate::classify::{classify_row, KeyRows, GAP_LIGHTS, GAP_OBJECT};
use crate::mode::{Mode, Options};
use crate::reproject::{reproject_row_keyed, KeyedRow, NO_SOURCE};
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
    /// The left eye's renderer.
    left_renderer: Renderer,
    /// The right eye's renderer, for the pixels it traces.
    right_renderer: Renderer,
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

/// Rows per band of the reprojection pass: each band reprojects two halo rows, but the
/// band's keys stay in the core's L2 cache (16 measured faster than 8 or 32 at 1280×720).
const BAND: usize = 16;

/// Per-thread scratch of the reprojection pass, kept across frames: rayon's
/// `for_each_init` would allocate afresh for every split of the work, every frame.
struct BandScratch {
    /// Targets of the row being reprojected.
    targets: Vec<i32>,
    /// Object key plane of a band and its halo rows.
    object: Vec<u32>,
    /// Lights key plane of a band and its halo rows.
    lights: Vec<u32>,
    /// Source map of a halo row; a band's own rows are written straight into the output.
    halo_src: Vec<u32>,
}

thread_local! {
    /// This thread's [`BandScratch`].
    static BAND_SCRATCH: std::cell::RefCell<BandScratch> = const {
        std::cell::RefCell::new(BandScratch {
            targets: Vec::new(),
            object: Vec::new(),
            lights: Vec::new(),
            halo_src: Vec::new(),
        })
    };
}

/// How one frame is reprojected and classified (see [`reproject_and_classify`]).
#[derive(Clone, Copy, Debug)]
struct Reprojection {
    /// e·W/w: the shift in pixels of a point at infinity.
    shift_scale: f32,
    /// d, the distance from the eyes to the window.
    distance: f32,
    /// Width of the right border strip that is always retraced.
    strip: usize,
    /// Whether object edges (and pixels next to gaps) are retraced.
    edges: bool,
    /// Whether shadow boundaries are retraced.
    shadows: bool,
}

/// Stages 2 and 3 over the whole image: the source map `src` and the class `mask` of every
/// right pixel, from the left film's `z`, `object` and `lights` planes.
///
/// The rows go in bands, each reprojected with one halo row above and below into per-thread
/// scratch and classified at once while its keys are in cache: one pass over the left planes
/// instead of a reprojection pass and a classification pass. A band's own source rows go
/// straight into `src`; of a halo row only the keys are kept. The bands are independent, so
/// the result does not depend on the number of threads.
fn reproject_and_classify(left: &Film, p: Reprojection, src: &mut [u32], mask: &mut [PixelClass]) {
    let w = left.width() as usize;
    let h = src.len() / w;
    let bands = src.par_chunks_mut(w * BAND).zip(mask.par_chunks_mut(w * BAND));
    bands.enumerate().for_each(|(b, (src_band, mask_band))| {
        BAND_SCRATCH.with_borrow_mut(|scratch| {
            let BandScratch { targets, object, lights, halo_src } = scratch;
            let (j0, rows) = (b * BAND, src_band.len() / w);
            let (lo, hi) = (j0.saturating_sub(1), (j0 + rows + 1).min(h));
            object.resize((hi - lo) * w, GAP_OBJECT);
            lights.resize((hi - lo) * w, GAP_LIGHTS);
            halo_src.resize(w, NO_SOURCE);
            let key_rows = object.chunks_exact_mut(w).zip(lights.chunks_exact_mut(w));
            for (j, (object, lights)) in (lo..hi).zip(key_rows) {
                let src = if (j0..j0 + rows).contains(&j) {
                    &mut src_band[(j - j0) * w..(j - j0 + 1) * w]
                } else {
                    &mut halo_src[..]
                };
                let left_row = j * w..(j + 1) * w;
                let row = KeyedRow {
                    left_object: &left.object[left_row.clone()],
                    left_lights: &left.lights[left_row.clone()],
                    src: &mut *src,
                    object: &mut *object,
                    lights: &mut *lights,
                };
                reproject_row_keyed(&left.z[left_row], p.shift_scale, p.distance, (j * w) as u32, row, targets);
                src[w - p.strip..].fill(NO_SOURCE);
                object[w - p.strip..].fill(GAP_OBJECT);
                lights[w - p.strip..].fill(GAP_LIGHTS);
            }
            let last = hi - lo - 1;
            for (r, out) in mask_band.chunks_mut(w).enumerate() {
                // This row's index in the scratch, and its neighbours' (itself at the edges).
                let k = j0 - lo + r;
                let at = [k.saturating_sub(1), k, (k + 1).min(last)].map(|k| k * w..(k + 1) * w);
                let rows = KeyRows { object: at.clone().map(|r| &object[r]), lights: at.map(|r| &lights[r]) };
                classify_row(rows, p.edges, p.shadows, out);
            }
        });
    });
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
            self.reproject(tracer, camera, &rv, opts);
            stats.stages.reproject = ms_since(t);

            let t = Instant::now();
            let right = self.right_renderer.second_view(tracer, &rv);
            // The paper's mode gathers its reprojected colours in the same pass over the
            // image as the retrace: nothing is left for stage 5.
            let copy = opts.mode == Mode::Copy;
            let retraced = retrace(right, &self.left, &mut self.right, &self.mask, &self.src, copy);
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

    /// Stages 2 and 3: the source map and the class of every right pixel.
    fn reproject(&mut self, tracer: &Tracer, camera: &Camera, rv: &EyeView, opts: Options) {
        let w = rv.width as usize;
        let shift_scale = camera.ipd * rv.pixels_per_unit();
        let strip = right_border_strip(tracer, camera, shift_scale, w);
        // With IPD 0 every left pixel lands exactly on its own centre: the reprojection is
        // exact and no edge or shadow boundary needs a second look.
        let exact_landing = shift_scale == 0.0;
        let (edges, shadows) = (opts.edges() && !exact_landing, opts.shadow_boundaries() && !exact_landing);
        // The object key plane marks gaps with a value no sphere index (below the count) takes.
        assert!(tracer.sphere_count() <= GAP_OBJECT as usize, "too many spheres for the gap marker");
        let p = Reprojection { shift_scale, distance: camera.distance, strip, edges, shadows };
        reproject_and_classify(&self.left, p, &mut self.src, &mut self.mask);
    }
}

/// Stage 4: full primary rays for every pixel not reprojected; with `copy`, also the
/// paper's stage 5 in the same pass: each reprojected pixel takes its source's colour.
fn retrace(
    right: SecondView<'_>,
    left: &Film,
    out: &mut Image,
    mask: &[PixelClass],
    src: &[u32],
    copy: bool,
) -> RayCounts {
    let w = out.width as usize;
    let left = &left.rgb;
    out.rgb
        .par_chunks_mut(w)
        .zip(mask.par_chunks(w))
        .zip(src.par_chunks(w))
        .enumerate()
        .map(|(j, ((rgb, mask), src))| {
            let mut counts = RayCounts::default();
            if copy {
                for i in 0..w {
                    if mask[i] == PixelClass::Reprojected {
                        rgb[i] = left[src[i] as usize];
                    }
                }
            }
            let traced = (0..w as u32).filter(|&i| mask[i as usize] != PixelClass::Reprojected);
            right.trace_pixels(j as u32, traced, &mut counts, |i, c| rgb[i as usize] = c);
            counts
        })
        .sum()
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

#[cfg(test)]
mod equivalence;

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
        let mut renderer = Renderer::new();
        let right = renderer.second_view(&tracer, &rv);
        let counts = retrace(right, &frame.left, &mut frame.right, &frame.mask, &frame.src, false);
        let mut full = Vec::new();
        let full_counts = Renderer::new().render_rgb(&tracer, &rv, &mut full);
        assert_eq!(frame.right.rgb, full);
        assert_eq!(counts, full_counts);
    }
}
