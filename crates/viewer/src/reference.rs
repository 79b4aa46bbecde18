//! The right eye's quality: a stereo frame's right image against a full trace of the same eye
//! (the reference), as `render --json`, `bench` and the viewer's live PSNR report it, and
//! `render --diff`'s picture of where it differs. This is the viewer's one use of the
//! tracer's [`Renderer`].

use stereo::{downsample, Quality};
use tracer::{Camera, Eye, Pixels, Renderer, Target, Tracer};

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
        self.renderer.render(
            tracer,
            &camera.view(Eye::Right, width, height),
            Pixels::All,
            Target::colour(&mut self.rgb),
        );
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

    /// `render --diff`: where `right` differs from the last trace, into `out` (reusing its
    /// allocation). A pixel off by more than 2/255 on any channel (the threshold of
    /// [`Quality::share_over_2_255`]) is [`DIFF_OVER`], one off by 1 or 2 levels
    /// [`DIFF_SLIGHT`]; an identical pixel shows the reference in pale grey, for context.
    pub fn difference(&self, right: &[u32], out: &mut Vec<u32>) {
        difference(right, &self.rgb, out);
    }

    /// [`Reference::difference`] for a supersampled frame's right image, filtered from
    /// `samples` down to `out_size`, against the last trace (of `samples`) filtered alike.
    pub fn difference_filtered(
        &mut self,
        right: &[u32],
        (samples, out_size): ((u32, u32), (u32, u32)),
        out: &mut Vec<u32>,
    ) {
        if samples == out_size {
            return self.difference(right, out);
        }
        downsample(&self.rgb, samples, &mut self.filtered, out_size);
        difference(right, &self.filtered, out);
    }
}

/// Where `right` differs from `reference` (see [`Reference::difference`]), into `out`.
fn difference(right: &[u32], reference: &[u32], out: &mut Vec<u32>) {
    assert_eq!(right.len(), reference.len(), "images differ in size");
    out.clear();
    out.extend(right.iter().zip(reference).map(|(&a, &b)| {
        let [ar, ag, ab] = tracer::unpack_rgb(a);
        let [br, bg, bb] = tracer::unpack_rgb(b);
        match ar.abs_diff(br).max(ag.abs_diff(bg)).max(ab.abs_diff(bb)) {
            0 => {
                let luma = (3 * u32::from(br) + 6 * u32::from(bg) + u32::from(bb)) / 10;
                let v = 160 + luma * 95 / 255;
                (v << 16) | (v << 8) | v
            }
            1 | 2 => DIFF_SLIGHT,
            _ => DIFF_OVER,
        }
    }));
}

/// `render --diff`'s colour for a pixel off by more than 2/255 on some channel: red.
pub const DIFF_OVER: u32 = 0x00D0_1010;

/// `render --diff`'s colour for a pixel off by 1 or 2 levels at most: amber.
pub const DIFF_SLIGHT: u32 = 0x00F0_A020;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_difference_image_sorts_pixels_by_their_largest_error() {
        let reference =
            Reference { rgb: vec![0x0000_0000, 0x00FF_FFFF, 0x0010_2030, 0x0010_2030], ..Reference::default() };
        let right = [0x0000_0000, 0x00FF_FFFF, 0x0010_2232, 0x0010_2033];
        let mut out = Vec::new();
        reference.difference(&right, &mut out);
        assert_eq!(out, [0x00A0_A0A0, 0x00FF_FFFF, DIFF_SLIGHT, DIFF_OVER], "black and white pale; off by 2; off by 3");
    }
}
