//! The right eye's quality: a stereo frame's right image against a full trace of the same eye
//! (the reference), as `render --json`, `bench` and the viewer's live PSNR report it. This is
//! the viewer's one use of the tracer's [`Renderer`].

use stereo::{downsample, Quality};
use tracer::{Camera, Eye, Renderer, Tracer};

/// The reference image and its renderer, reused from frame to frame.
#[derive(Debug, Default)]
pub struct Reference {
    renderer: Renderer,
    rgb: Vec<u32>,
    /// The trace filtered down to the output size, for a supersampled frame.
    filtered: Vec<u32>,
}

impl Reference {
    /// Traces the right eye of `camera` at `width` × `height` in full (colour only).
    pub fn trace(&mut self, tracer: &Tracer, camera: &Camera, width: u32, height: u32) {
        self.renderer.render_rgb(tracer, &camera.view(Eye::Right, width, height), &mut self.rgb);
    }

    /// Measures `right`, a stereo frame's right image of the same view, against the last
    /// trace.
    #[must_use]
    pub fn compare(&self, right: &[u32]) -> Quality {
        Quality::compare(right, &self.rgb)
    }

    /// Measures `right`, a supersampled frame's right image filtered down to `out`, against
    /// the last trace (of `samples`) filtered alike: the images as they are shown. At the
    /// same size, [`Reference::compare`].
    pub fn compare_filtered(&mut self, right: &[u32], samples: (u32, u32), out: (u32, u32)) -> Quality {
        if samples == out {
            return self.compare(right);
        }
        downsample(&self.rgb, samples, &mut self.filtered, out);
        Quality::compare(right, &self.filtered)
    }
}
