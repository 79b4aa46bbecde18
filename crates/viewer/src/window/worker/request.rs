//! What the UI asks the render worker for ([`Request`]) and what it is told about the frame
//! that answers it ([`FrameInfo`]), with the views the pair was traced through.

use std::time::Instant;

use glam::Vec3;
use stereo::{FrameStats, Options, Quality, StereoViews};
use tracer::Camera;

/// Everything that determines one stereo frame.
#[derive(Clone, Copy, Debug, PartialEq)]
#[expect(clippy::struct_excessive_bools, reason = "independent switches of one request, as the panel's ticks are")]
pub struct Request {
    /// Head pose and stereo parameters (IPD and distance from the sliders).
    pub camera: Camera,
    /// Reflection depth.
    pub depth: u32,
    /// Mode and edge retracing.
    pub opts: Options,
    /// Scene time, seconds.
    pub time: f32,
    /// Eye width in pixels: the images the frame delivers.
    pub width: u32,
    /// Eye height in pixels.
    pub height: u32,
    /// The size each eye is traced at: `width` × `height`, or larger to supersample (the
    /// images are then filtered down to `width` × `height`).
    pub samples: (u32, u32),
    /// Also trace the right eye fully and measure the right image against it.
    pub psnr: bool,
    /// Also make the red–cyan anaglyph of the pair.
    pub anaglyph: bool,
    /// Also make the debug mask's colours ([`super::Eyes::right_overlay`]): only while
    /// the overlay is shown, since they cost a pass over the eye every frame.
    pub overlay: bool,
    /// Reuse the unchanged pixels of the last frame when only the scene time moved
    /// (`stereo`'s `reuse/`).
    pub reuse: bool,
    /// Exchange the eyes in the anaglyph (red over the right eye's image).
    pub swap: bool,
    /// Where the scene's first light is this frame (`None`: where the scene puts it).
    pub light: Option<Vec3>,
    /// Keep the traced eyes with their depth and a guard band for the timewarp
    /// ([`super::Finished::traced`]).
    pub timewarp: bool,
    /// The guard band, samples beyond each side of the traced size (horizontally,
    /// vertically): traced, never shown as such, for the timewarp to turn into.
    pub guard: (u32, u32),
    /// The structures' colours and hidden atoms.
    pub atoms: crate::window::look::AtomLook,
    /// Trace progressively (coarse while the head moves, refined while it rests), or, when
    /// `None`, every frame at `samples` (`--no-progressive`, `replay --policy fixed`).
    pub progressive: Option<Progressive>,
    /// The head is moving (a key held): the progressive policy spends its time budget on
    /// this request; a still head's request is traced in full and refined.
    pub moving: bool,
}

/// The progressive policy's settings: how old a traced pair may be when presented while
/// the head moves, and how far a resting view is refined.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Progressive {
    /// The age a moving head's traced pair aims at when presented, milliseconds
    /// (`--target-age-ms`).
    pub target_age_ms: f32,
    /// A resting view is refined up to S × S samples a pixel (`--max-supersample S`).
    pub max_supersample: u32,
}

impl Default for Progressive {
    /// About three ticks of a 90 Hz display; 4 × 4 samples at rest.
    fn default() -> Self {
        Self { target_age_ms: 33.0, max_supersample: 4 }
    }
}

/// How a finished frame was sampled: what the panel and the fps log say of it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sampling {
    /// One sample per `density` × `density` pixels (1: every pixel).
    pub density: u32,
    /// Samples a pixel accumulated so far (1 for a frame traced once, 0 for a coarse one).
    pub spp: u32,
    /// The resting refinement is complete: the frame is `render --supersample S`'s.
    pub converged: bool,
}

/// A builder for the tests, which ask for many requests that differ in a field or two.
#[cfg(test)]
impl Request {
    /// The default camera and options, an eye of `width` × `height` traced at that size,
    /// reflection depth 2, the mask's colours on and nothing else asked for.
    pub(crate) fn sized(width: u32, height: u32) -> Self {
        Self {
            camera: Camera::default(),
            depth: 2,
            opts: Options::default(),
            time: 0.0,
            width,
            height,
            samples: (width, height),
            psnr: false,
            anaglyph: false,
            overlay: true,
            reuse: false,
            swap: false,
            light: None,
            timewarp: false,
            guard: (0, 0),
            atoms: crate::window::look::AtomLook::default(),
            progressive: None,
            moving: false,
        }
    }

    /// At the head pose and stereo parameters `camera`.
    pub(crate) fn at(self, camera: Camera) -> Self {
        Self { camera, ..self }
    }

    /// Traced at `samples` per eye (supersampled above the eye size).
    pub(crate) fn sampled(self, samples: (u32, u32)) -> Self {
        Self { samples, ..self }
    }

    /// With the timewarp's planes, traced with the guard band `guard`.
    pub(crate) fn with_timewarp(self, guard: (u32, u32)) -> Self {
        Self { timewarp: true, guard, ..self }
    }

    /// With the live PSNR and the anaglyph, or without both.
    pub(crate) fn measured(self, on: bool) -> Self {
        Self { psnr: on, anaglyph: on, ..self }
    }
}

/// What is known about a finished frame besides its pixels.
#[derive(Clone, Copy, Debug)]
pub struct FrameInfo {
    /// 1 for the first frame the worker rendered, then counting up; 0 = no frame yet.
    pub seq: u64,
    /// The request it answers.
    pub request: Request,
    /// The views the pair was traced through, as the stereo frame kept them: the request's
    /// head pose, each eye's sampled size (`request.samples`, or the eye size when that
    /// many samples would not fit in memory) and its guard band.
    pub views: StereoViews,
    /// Time, rays and pixel classes.
    pub stats: FrameStats,
    /// The right eye against a full trace, when the request asked for it; both filtered to
    /// the eye size when supersampled.
    pub quality: Option<Quality>,
    /// Wall time of the whole job (including the PSNR reference trace, the anaglyph and the
    /// copies for the UI), milliseconds.
    pub wall_ms: f64,
    /// When the request was posted: the moment of the head pose the frame shows.
    pub posted: Instant,
    /// How it was sampled (coarse, full, or refined at rest).
    pub sampling: Sampling,
}

impl FrameInfo {
    /// The size each eye was traced at, without its guard band.
    #[must_use]
    pub fn samples(&self) -> (u32, u32) {
        self.views.shown
    }

    /// For the tests: frame `seq`, traced as `request` asks (at its samples, with its guard
    /// band), with no statistics, posted now.
    #[cfg(test)]
    pub(crate) fn answering(seq: u64, request: Request) -> Self {
        Self {
            seq,
            request,
            views: StereoViews::new(&request.camera, request.samples, request.guard),
            stats: FrameStats::default(),
            quality: None,
            wall_ms: 0.0,
            posted: Instant::now(),
            sampling: Sampling { density: 1, spp: 1, converged: false },
        }
    }
}
