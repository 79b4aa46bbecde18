//! A stereo frame: the stages of the crate's pipeline in order, each timed, into buffers
//! kept from frame to frame. The left eye is traced in full (stage 1, by the tracer's
//! [`Renderer`]); the right eye is traced in full too in [`Mode::Full`], and otherwise
//! reprojected and classified (stages 2 and 3, `reproject.rs`), retraced where it must be
//! (stage 4, `retrace.rs`) and filled as the mode says (stage 5, `fill.rs`).
//!
//! The pair keeps the views it was traced through ([`StereoFrame::views`], made once per
//! frame by `views.rs`), so a warp reads them from the pair ([`StereoFrame::warp_sources`])
//! rather than deriving them again from the pose.
//!
//! With reuse on ([`StereoFrame::set_reuse`]), a frame whose only change is the scene time
//! makes again only what can have changed: `reuse/` keeps that bookkeeping. The frame enters
//! it once, and each stage asks the frame's reuse which pixels to make.
//!
//! A frame that keeps depths ([`StereoFrame::set_depths`]) keeps each eye's first hits
//! (object and head-space depth planes, what outlines and a timewarp read). The left film
//! keeps them as part of its record; the right eye's come out of its own pass where that
//! pass traces or exactly shades every pixel it makes (full and exact modes: the pixel's own
//! ray's first hit, as pbrt-v4's film keeps its visible surface), and from a first-hits pass
//! of their own where it copies or re-shades colours (copy and reshade modes).

use std::time::Instant;

use tracer::{
    Camera, Eye, EyeView, Film, PixelBatch, PixelBits, Pixels, Record, Renderer, Scene, Target, Tracer, NO_OBJECT,
};

use crate::fill::{fill, reproject_and_fill_exact, Fill, HitPlanes};
use crate::image::Image;
use crate::mode::{Mode, Options};
use crate::reproject::{Reprojection, NO_SOURCE};
use crate::retrace::{retrace, Redo};
use crate::reuse::{Asked, FrameReuse, Temporal};
use crate::stats::{FrameStats, PixelClass};
use crate::views::StereoViews;
use crate::warp::WarpSource;

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
    /// eye's first hits: its depth and object planes (kept between frames: a reused frame
    /// writes those of the pixels it makes again).
    depths: bool,
    right_z: Vec<f32>,
    right_object: Vec<u32>,
    /// The views the last frame was traced through.
    views: StereoViews,
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
    ///
    /// A scene with ambient occlusion and moving spheres is always traced afresh: the marks
    /// do not follow occlusion rays (`tracer`'s `cue/`), so a kept pixel could miss a
    /// sphere that moved into its occlusion rays' reach.
    pub fn set_reuse(&mut self, scene: Option<&Scene>) {
        self.reuse.set(scene.filter(|s| !s.is_animated() || marks_cover(s)));
    }

    /// Whether reuse is on.
    #[must_use]
    pub fn reuse(&self) -> bool {
        self.reuse.is_on()
    }

    /// Keeps both eyes' depth from now on (off for a new frame), as a timewarp reads it: the
    /// left film keeps its depth in every mode, and the right eye its first hits, from the
    /// pass that makes it in full and exact modes, else from a first-hits pass of its own (no
    /// shading) ([`StereoFrame::right_depth`]). Both eyes then have their first hits' planes
    /// ([`StereoFrame::first_hits`]), which outlines read. A change of this makes the next
    /// frame fresh, as a change of the request does.
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

    /// `eye`'s first hits in the last frame, (object, depth) per pixel, as
    /// [`tracer::first_hits`] gives them, bit for bit: the left film's planes when it kept
    /// them, the right eye's when frames keep depths ([`StereoFrame::set_depths`]).
    #[must_use]
    pub fn first_hits(&self, eye: Eye) -> Option<(&[u32], &[f32])> {
        match eye {
            Eye::Left => (self.left.record() != Record::Colour).then(|| (&self.left.object[..], &self.left.z[..])),
            Eye::Right => self.depths.then(|| (&self.right_object[..], &self.right_z[..])),
        }
    }

    /// The pixels of the left and the right eye that the last frame made, as opposed to
    /// kept from the frame before; `None` when it made all of them (it did not reuse).
    #[must_use]
    pub fn made(&self) -> Option<(&PixelBits, &PixelBits)> {
        self.stats.reuse.reused.then(|| self.reuse.made())
    }

    /// The views the last frame was traced through, guard band included (the default
    /// camera's, of no pixels, before the first frame).
    #[must_use]
    pub fn views(&self) -> &StereoViews {
        &self.views
    }

    /// What a warp of the last frame reads: each eye's view as traced, with its colours and
    /// depths. `None` unless frames keep both eyes' depth ([`StereoFrame::set_depths`]).
    #[must_use]
    pub fn warp_sources(&self) -> Option<[WarpSource<'_>; 2]> {
        self.depths.then(|| {
            let [lv, rv] = self.views.eyes;
            [WarpSource::from_film(lv, &self.left), WarpSource { view: rv, rgb: &self.right.rgb, z: &self.right_z }]
        })
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
    /// ([`StereoViews::new`]), so its images are (width + 2·mx) × (height + 2·my), the shown
    /// part bit for bit the frame without the band. A timewarp turns the head into the band.
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
        self.views = StereoViews::new(camera, (width, height), margin);
        let Self {
            left,
            right,
            left_renderer,
            right_renderer,
            src,
            class,
            mask,
            stats: last,
            reuse,
            depths,
            right_z,
            right_object,
            views,
        } = self;
        let [lv, rv] = &views.eyes;
        let size = (lv.width, lv.height);
        let n = pixel_count(size.0, size.1);
        let asked = Asked { camera: *camera, width, height, margin, opts, depths: *depths };
        let mut reuse = reuse.frame(tracer, asked, size);
        let mut stats = FrameStats::default();

        // Stage 1: the left eye, keeping only what the mode's later stages read of its record.
        let t = Instant::now();
        let record = if opts.mode == Mode::Full && !*depths { Record::Colour } else { Record::Keys };
        let (pixels, target) = reuse.left(left, record);
        stats.left.rays = left_renderer.render(tracer, lv, pixels, target);
        stats.stages.trace_left = ms_since(t);
        stats.left.ms = stats.stages.trace_left;

        mask.resize(n, PixelClass::Traced);
        src.resize(n, NO_SOURCE);
        class.resize(n, PixelClass::Traced);
        (right.width, right.height) = size;
        right.rgb.resize(n, 0);
        // The right eye's first hits, made with its pixels in full and exact modes.
        let hits_in_pass = *depths && matches!(opts.mode, Mode::Full | Mode::Exact);
        if hits_in_pass {
            right_object.resize(n, NO_OBJECT);
            right_z.resize(n, f32::INFINITY);
        }
        let hits = hits_in_pass.then_some((&mut *right_object, &mut *right_z));
        let planes = (&mut src[..], &mut class[..], &mut mask[..]);
        if n == 0 {
            // Nothing to make.
        } else if opts.mode == Mode::Full {
            // The right eye as the left: timed as stage 4.
            let t = Instant::now();
            let (pixels, target) = reuse.right_full(&mut right.rgb, hits);
            stats.right.rays = right_renderer.render(tracer, rv, pixels, target);
            planes.2.fill(PixelClass::Traced);
            stats.stages.retrace = ms_since(t);
        } else if !reuse.reused() && opts.mode == Mode::Exact {
            // Stages 2 to 5 in one banded pass.
            let hits = hits.map(|(object, z)| (&mut object[..], &mut z[..]));
            let right_eye = (&mut *right_renderer, rv, (&mut *right, hits));
            exact_in_one_pass(tracer, camera, (left, right_eye), planes, opts, &mut reuse, &mut stats);
        } else {
            // Stages 2 and 3: the source map and the class of every right pixel (on a
            // reused frame, of the rows that can have changed).
            let t = Instant::now();
            reuse.reproject(left, Reprojection::new(tracer, camera, rv, opts), planes);
            stats.stages.reproject = ms_since(t);
            // Stages 4 and 5.
            let (only, marks, swept) = reuse.right();
            let right_eye = right_renderer.batch(tracer, rv).marking(swept);
            let redo = Redo { only, marks, mark: swept.is_some() };
            let hits = hits.map(|(object, z)| (&mut object[..], &mut z[..]));
            retrace_and_fill(right_eye, (lv, left), opts.mode, (mask, src), (right, hits), redo, &mut stats);
        }
        stats.right.ms = stats.stages.reproject + stats.stages.retrace + stats.stages.reshade;
        if *depths && !hits_in_pass {
            // The right eye's first hits, where its pass copied or re-shaded colours: a
            // first-hits pass alone.
            let t = Instant::now();
            right_renderer.render(tracer, rv, Pixels::All, Target::first_hits(right_object, right_z));
            stats.stages.depth = ms_since(t);
        }
        (stats.reuse, stats.pixels) = reuse.finish(mask, last.pixels);
        *last = stats;
        stats
    }
}

/// Stages 4 and 5 of a reprojecting `mode`, by `right` (the right eye's pixels) into `out`,
/// from the `left` film (rendered for the view `lv`), the classes in `mask` and the sources
/// in `src`, over the pixels and marks `redo` names, with the right eye's first hits into
/// `hits` in exact mode if given. The paper's mode gathers its reprojected colours in stage
/// 4's pass over the image: it has no stage 5. Exact mode retraces in stage 5's pass
/// instead (`fill.rs`).
fn retrace_and_fill(
    right: PixelBatch<'_>,
    (lv, left): (&EyeView, &Film),
    mode: Mode,
    (mask, src): (&mut [PixelClass], &[u32]),
    (out, hits): (&mut Image, HitPlanes<'_>),
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
        let filled = fill(right, (lv, left), how, (mask, src), (out, hits), Redo { only, marks, mark });
        stats.stages.reshade = ms_since(t);
        stats.right.rays += filled.rays;
        stats.sphere_tests = filled.sphere_tests;
    }
}

/// Stages 2 to 5 of a fresh exact frame in one banded pass (`fill.rs`): from the `left`
/// film into the right eye (its renderer, its view `rv` of `camera`, its image and, if
/// kept, its first hits) and the `planes` (sources, stage-3 classes, final classes),
/// marking if `reuse` does. The pass's
/// time goes to `stats`, split between the reproject and reshade stages as the thread time
/// each part took.
fn exact_in_one_pass(
    tracer: &Tracer,
    camera: &Camera,
    (left, (renderer, rv, out)): (&Film, (&mut Renderer, &EyeView, (&mut Image, HitPlanes<'_>))),
    planes: (&mut [u32], &mut [PixelClass], &mut [PixelClass]),
    opts: Options,
    reuse: &mut FrameReuse<'_>,
    stats: &mut FrameStats,
) {
    let t = Instant::now();
    let plan = Reprojection::new(tracer, camera, rv, opts);
    reuse.reprojected_in_one_pass(plan);
    let (_, marks, swept) = reuse.right();
    let right = renderer.batch(tracer, rv).marking(swept);
    let bins_s = t.elapsed().as_secs_f64();
    let cost = reproject_and_fill_exact(right, left, plan, planes, out, (marks, swept.is_some()));
    let (ms, fill_s) = (ms_since(t), cost.fill_s + bins_s);
    let share = cost.reproject_s / (cost.reproject_s + fill_s).max(f64::MIN_POSITIVE);
    (stats.stages.reproject, stats.stages.reshade) = (ms * share, ms * (1.0 - share));
    stats.right.rays = cost.filled.rays;
    stats.sphere_tests = cost.filled.sphere_tests;
}

/// Whether temporal reuse's marks cover every ray of `scene`'s pixels, so that a pixel they
/// leave unmarked is unchanged at another instant: not with ambient occlusion, whose rays
/// they do not follow (`tracer`'s `cue/`). What [`StereoFrame::set_reuse`] and the viewer's
/// refinement that follows orbiting spheres rest on.
#[must_use]
pub fn marks_cover(scene: &Scene) -> bool {
    !scene.render.cues.ambient_occlusion.is_on()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::warp::Warp;

    /// The pair keeps the views it was traced through, and with its depths offers a warp
    /// what it needs: warped to the very pose it was traced at, it gives back its shown part.
    #[test]
    fn a_pair_carries_its_views_and_warps_back_to_itself() {
        let scene = Scene::from_toml(include_str!("../../../assets/scenes/seed.toml"), "seed.toml").unwrap();
        let tracer = Tracer::new(&scene, 0.0);
        let camera = Camera { yaw_deg: 3.0, ..scene.camera };
        let mut frame = StereoFrame::new();
        frame.render_banded(&tracer, &camera, (40, 24), (3, 2), Options::default());
        let views = frame.views();
        assert_eq!((views.camera, views.shown, views.margin), (camera, (40, 24), (3, 2)));
        assert_eq!((frame.left().width(), frame.right().width), (views.left().width, views.right().width));
        assert!(frame.warp_sources().is_none(), "no depths kept: nothing to warp");
        frame.set_depths(true);
        frame.render_banded(&tracer, &camera, (40, 24), (3, 2), Options::default());
        let sources = frame.warp_sources().unwrap();
        assert_eq!(
            sources.map(|s| (s.view.eye, s.view.margin, s.rgb.len(), s.z.len())),
            [(tracer::Eye::Left, (3, 2), 46 * 28, 46 * 28), (tracer::Eye::Right, (3, 2), 46 * 28, 46 * 28),]
        );
        let targets = frame.views().warped_to(&camera);
        let (mut out, mut classes) = (<[Vec<u32>; 2]>::default(), <[Vec<_>; 2]>::default());
        let [lo, ro] = &mut out;
        let [lc, rc] = &mut classes;
        Warp::new().warp(sources, [&targets[0], &targets[1]], [lo, ro], [lc, rc]);
        let shown =
            |rgb: &[u32]| -> Vec<u32> { rgb.chunks(46).skip(2).take(24).flat_map(|r| r[3..43].to_vec()).collect() };
        assert_eq!(out[0], shown(&frame.left().rgb), "the left eye's shown part");
        assert_eq!(out[1], shown(&frame.right().rgb), "the right eye's shown part");
    }

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
