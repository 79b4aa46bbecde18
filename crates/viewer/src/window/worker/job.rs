//! The render thread's state between frames, and what it does with each step: a new
//! request traced (at the progressive policy's density, `progress.rs`), or the resting
//! request refined.

use std::time::Instant;

use glam::Vec3;
use stereo::{Outlined, StereoFrame};
use tracer::{Scene, Tracer};

use super::finished::{Cut, Finished};
use super::progress::{self, Progress};
use super::{build, FrameInfo, Request, Shared};
use crate::reference::Reference;
use crate::setup;
use crate::window::look::{Change, Looked};

/// The render thread's state between frames (see `render_loop`).
pub(super) struct Job {
    scene: Scene,
    memory: Option<u64>,
    tracer: Tracer,
    /// The first light's position as the scene file puts it.
    scene_light: Option<Vec3>,
    /// The first light's position the tracer was built with; `None`: build it afresh (a
    /// new scene). Otherwise a frame only advances the tracer in time: a still scene,
    /// however large, costs nothing there. The tracer just built has the scene's own light.
    #[expect(clippy::option_option, reason = "not built, or built with the scene's light or none")]
    built: Option<Option<Vec3>>,
    /// The look (colours, hidden atoms) the scene has.
    looked: Looked,
    frame: StereoFrame,
    /// The frame's eyes with the scene's outlines drawn, when it has them.
    outlined: Outlined,
    /// The outline width the frame's eyes were drawn with, in samples.
    outline: f32,
    reference: Reference,
    /// The frame being filled, swapped into the outbox when done.
    pub(super) back: Finished,
    cut: Cut,
    seq: u64,
    /// The last frame rendered, for a request that differs from it only in the overlay.
    last: Option<FrameInfo>,
    pub(super) progress: Progress,
}

impl Job {
    pub(super) fn new(shared: &Shared, scene: Scene, memory: Option<u64>) -> Self {
        let tracer = build(shared, &scene, || Tracer::new(&scene, 0.0));
        let scene_light = scene.lights.first().map(|l| l.position);
        Self {
            scene,
            memory,
            tracer,
            scene_light,
            built: Some(scene_light),
            looked: Looked::default(),
            frame: StereoFrame::new(),
            outlined: Outlined::new(),
            outline: 0.0,
            reference: Reference::default(),
            back: Finished::default(),
            cut: Cut::default(),
            seq: 0,
            last: None,
            progress: Progress::default(),
        }
    }

    /// Renders `scene` from the next request on.
    pub(super) fn set_scene(&mut self, scene: Scene) {
        self.scene = scene;
        self.scene_light = self.scene.lights.first().map(|l| l.position);
        (self.last, self.built, self.looked) = (None, None, Looked::default());
        self.progress.forget();
    }

    /// A new request: traced at the density the policy picks, or at its samples.
    pub(super) fn trace(&mut self, shared: &Shared, request: Request, posted: Instant) {
        let started = Instant::now();
        if let Some(info) = self.last.filter(|info| Request { overlay: request.overlay, ..info.request } == request) {
            // The mask switched on or off: the same frame, its overlay made or dropped.
            let rgb = self.outlined.drawn(&self.frame, self.outline);
            self.back.fill_from((&self.frame, rgb), &request, &mut self.cut);
            self.progress.paint(&self.tracer, &mut self.back.eyes, (request.anaglyph, request.swap));
            self.publish(&FrameInfo { request, wall_ms: 0.0, ..info }, started);
            return;
        }
        let only_time = self.last.is_some_and(|l| Request { time: request.time, ..l.request } == request);
        self.prepare(shared, &request);
        let density = self.progress.density(&request, only_time);
        let info = self.trace_at(request, posted, density, started);
        if density > 1 || !only_time {
            self.progress.measured(&request, density, info.wall_ms);
        }
        if only_time && self.progress.advance((request, posted), &self.tracer) {
            // The resting pair's refinement follows the orbits to this instant; what is
            // shown is its pair, the next part of its work done first, so that it also
            // refines while the orbits keep posting requests.
            self.progress.refine.step(&self.tracer);
            self.progress.paint(&self.tracer, &mut self.back.eyes, (request.anaglyph, request.swap));
            let sampling = self.progress.sampling(&request, 1);
            let wall_ms = started.elapsed().as_secs_f64() * 1e3;
            for info in [&mut self.back.info, &mut self.last].into_iter().flatten() {
                (info.sampling, info.wall_ms) = (sampling, wall_ms);
            }
            return;
        }
        let follow = followed(&self.scene, &request).map(|scene| (scene, &self.tracer));
        let outline = self.scene.render.cues.outline;
        self.progress.traced((request, posted), (density, outline), info.wall_ms, self.memory, follow);
    }

    /// No newer request: the resting request's next step, in full, then pass by pass (in
    /// parts). Returns whether it made a frame to show: a part of a pass makes none.
    pub(super) fn refine(&mut self, shared: &Shared) -> bool {
        let started = Instant::now();
        let Some((request, posted)) = self.progress.resting else { return false };
        if self.progress.coarse {
            self.progress.refine.stop();
            self.prepare(shared, &request);
            let info = self.trace_at(request, posted, 1, started);
            self.progress.measured(&request, 1, info.wall_ms);
            let follow = followed(&self.scene, &request).map(|scene| (scene, &self.tracer));
            let outline = self.scene.render.cues.outline;
            self.progress.traced((request, posted), (1, outline), info.wall_ms, self.memory, follow);
            return true;
        }
        let Some(last) = self.last else { return false };
        if !self.progress.refine.step(&self.tracer) {
            return false;
        }
        let rgb = self.outlined.drawn(&self.frame, self.outline);
        self.back.fill_from((&self.frame, rgb), &request, &mut self.cut);
        self.progress.paint(&self.tracer, &mut self.back.eyes, (request.anaglyph, request.swap));
        let sampling = self.progress.sampling(&request, 1);
        // The live PSNR stays the full pair's: the refinement traces both eyes in full.
        self.publish(&FrameInfo { sampling, ..last }, started);
        true
    }

    /// The scene and tracer as `request` asks: its light, its look, its time and depth.
    fn prepare(&mut self, shared: &Shared, request: &Request) {
        let scene = &mut self.scene;
        if let (Some(light), Some(home)) = (scene.lights.first_mut(), self.scene_light) {
            light.position = request.light.unwrap_or(home);
        }
        match self.looked.apply(scene, request.atoms) {
            Change::None => {}
            // The BVH and light maps stay: only the materials change.
            Change::Colors if self.built.is_some() => self.tracer.recolor(scene),
            Change::Colors | Change::Atoms => self.built = None,
        }
        let light = scene.lights.first().map(|l| l.position);
        if self.built == Some(light) {
            self.tracer.advance(scene, request.time);
        } else {
            let tracer = &mut self.tracer;
            build(shared, scene, || tracer.update(scene, request.time));
            self.built = Some(light);
        }
        self.tracer.set_max_depth(request.depth);
    }

    /// Traces `request`'s pair at one sample per `density` × `density` pixels (1: at its
    /// samples) and fills the back frame; returns what it says of the frame.
    fn trace_at(&mut self, request: Request, posted: Instant, density: u32, started: Instant) -> FrameInfo {
        let eye = (request.width, request.height);
        let samples = if density > 1 {
            progress::samples_at(eye, density)
        } else if request.samples == eye || setup::viewer_frame_fits(request.samples, eye, self.memory) {
            request.samples
        } else {
            eye
        };
        self.frame.set_reuse(request.reuse.then_some(&self.scene));
        // Depths for the timewarp, and the first hits the outlines read: the eyes' own passes
        // make them, where a first-hits pass of the outlines' own would trace again.
        self.frame.set_depths(request.timewarp || self.scene.render.cues.outline > 0);
        let guard = if request.timewarp { request.guard } else { (0, 0) };
        let guard = (guard.0.div_ceil(density), guard.1.div_ceil(density));
        let stats = self.frame.render_banded(&self.tracer, &request.camera, samples, guard, request.opts);
        self.outline = outline_width(self.scene.render.cues.outline, samples, eye);
        self.outlined.set_ink(outline_ink(self.scene.render.cues.outline, density));
        let rgb = self.outlined.eyes(&self.tracer, &self.frame, self.outline);
        self.back.fill_from((&self.frame, rgb), &request, &mut self.cut);
        let quality = request.psnr.then(|| {
            // A coarse frame is measured as shown, at the eye size.
            let traced = if density > 1 { eye } else { samples };
            self.reference.trace(&self.tracer, &request.camera, traced.0, traced.1);
            self.reference.compare_filtered(&self.back.eyes.right, traced, eye)
        });
        let views = *self.frame.views();
        let sampling = self.progress.sampling(&request, density);
        let info = FrameInfo { seq: 0, request, views, stats, quality, wall_ms: 0.0, posted, sampling };
        self.publish(&info, started)
    }

    /// Numbers the back frame's `info`, times it from `started`, and keeps it as the last.
    fn publish(&mut self, info: &FrameInfo, started: Instant) -> FrameInfo {
        self.seq += 1;
        let wall_ms = started.elapsed().as_secs_f64() * 1e3;
        let info = FrameInfo { seq: self.seq, wall_ms, ..*info };
        self.back.info = Some(info);
        self.last = Some(info);
        info
    }
}

/// `scene`, when `request`'s refinement can follow its orbiting spheres: the request reuses
/// what a new instant leaves unchanged, and temporal reuse's marks cover the scene's rays
/// ([`stereo::marks_cover`]).
fn followed<'a>(scene: &'a Scene, request: &Request) -> Option<&'a Scene> {
    (request.reuse && scene.is_animated() && stereo::marks_cover(scene)).then_some(scene)
}

/// The share of an outlined sample's light its line takes, for outlines `px` pixels wide
/// traced at one sample per `density` × `density` pixels: the share of the sample's area a
/// line `px` pixels wide covers (all of it in a full frame), so that a coarse frame's lines
/// are as dark on average as the image's, not `density` pixels wide and black.
fn outline_ink(px: u32, density: u32) -> f32 {
    (px as f32 / density.max(1) as f32).min(1.0)
}

/// The outline width, in samples, for outlines `px` pixels wide on an eye of `eye` pixels
/// traced at `samples`: `px` times the supersampling, as `render` draws them; a coarse
/// frame's at least one sample, so that they do not come and go as the head moves.
fn outline_width(px: u32, samples: (u32, u32), eye: (u32, u32)) -> f32 {
    if px == 0 {
        return 0.0;
    }
    if samples.0 < eye.0 {
        return 1.0;
    }
    (px * (samples.0 / eye.0.max(1))) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_coarse_frames_outline_is_one_sample_wide_and_as_dark_as_its_share() {
        // A full frame: black lines of the scene's width, times the supersampling.
        assert_eq!((outline_width(1, (800, 600), (800, 600)), outline_ink(1, 1)), (1.0, 1.0));
        assert_eq!(outline_width(2, (1600, 1200), (800, 600)), 4.0);
        // One sample per 4 × 4 pixels: a line of one sample, a quarter of its light taken.
        assert_eq!((outline_width(1, (200, 150), (800, 600)), outline_ink(1, 4)), (1.0, 0.25));
        assert_eq!(outline_ink(2, 16), 0.125);
        assert_eq!(outline_ink(3, 2), 1.0, "never more than all of it");
        assert_eq!(outline_width(0, (200, 150), (800, 600)), 0.0, "none");
    }
}
