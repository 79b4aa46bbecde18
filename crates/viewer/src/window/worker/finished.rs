//! The frame the worker hands to the UI thread: both eyes cut to their shown part and
//! filtered down to the eye size with the mask's colours ([`Eyes`]), the class mask per
//! sample, and for the timewarp each eye's colours and depths with their guard band
//! ([`Traced`]), which a warp reads with the views the pair was traced through
//! ([`FrameInfo::views`]).

use stereo::{PixelClass, StereoFrame, WarpSource};

use super::eyes::{filter_eyes, Eyes};
use super::{FrameInfo, Request};

/// The traced eyes as the timewarp reads them: each eye's colours and depths as traced,
/// guard band included (the views' size, [`stereo::StereoViews::traced_pixels`] each).
/// Empty unless the request asked for them ([`Request::timewarp`]).
#[derive(Debug, Default)]
pub struct Traced {
    /// Left colours, `0x00RRGGBB`.
    pub left: Vec<u32>,
    /// Left depths beyond the window (the film's `z`), +∞ for background.
    pub left_z: Vec<f32>,
    /// Right colours.
    pub right: Vec<u32>,
    /// Right depths.
    pub right_z: Vec<f32>,
}

impl Traced {
    /// Whether there are eyes to warp.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.left.is_empty()
    }

    fn clear(&mut self) {
        self.left.clear();
        self.left_z.clear();
        self.right.clear();
        self.right_z.clear();
    }
}

/// A finished stereo frame: both eyes and the right eye's mask colours, `width × height`
/// each, and its class mask per sample.
#[derive(Debug, Default)]
pub struct Finished {
    /// Metadata; `None` until the first frame arrives.
    pub info: Option<FrameInfo>,
    /// The eyes to present: the right eye's overlay is the mask's colours
    /// (`stereo::mask_color`) at the eye size, each pixel's samples filtered together as the
    /// eyes are, and empty unless the request asked for them ([`Request::overlay`]); the
    /// anaglyph is there when the request asked for it.
    pub eyes: Eyes,
    /// How each right sample was made, [`Finished::samples`] in size.
    pub mask: Vec<PixelClass>,
    /// The eyes as traced, with depth and guard band, when the request asked for them.
    pub traced: Traced,
}

/// The worker's scratch for a frame traced with a guard band: each eye's shown part cut out
/// of the band, before it is filtered, and the mask's.
#[derive(Debug, Default)]
pub(super) struct Cut {
    eyes: [Vec<u32>; 2],
    mask: Vec<PixelClass>,
}

impl Finished {
    /// Eye size in pixels, (0, 0) before the first frame.
    #[must_use]
    pub fn size(&self) -> (u32, u32) {
        self.info.map_or((0, 0), |i| (i.request.width, i.request.height))
    }

    /// The size the eyes were traced at (of [`Finished::mask`]), (0, 0) before the first
    /// frame.
    #[must_use]
    pub fn samples(&self) -> (u32, u32) {
        self.info.map_or((0, 0), |i| i.samples())
    }

    /// What a warp of this frame reads: each eye's view as traced, with its colours and
    /// depths; `None` for a frame traced without them (or none yet).
    #[must_use]
    pub fn warp_sources(&self) -> Option<[WarpSource<'_>; 2]> {
        let views = self.info?.views;
        let t = &self.traced;
        let n = views.traced_pixels();
        if t.is_empty() || [t.left.len(), t.left_z.len(), t.right.len(), t.right_z.len()] != [n; 4] {
            return None;
        }
        let [lv, rv] = views.eyes;
        Some([
            WarpSource { view: lv, rgb: &t.left, z: &t.left_z },
            WarpSource { view: rv, rgb: &t.right, z: &t.right_z },
        ])
    }

    /// Copies `frame`, rendered for `request`, in: its eyes' shown part filtered to the
    /// request's eye size, reusing this frame's allocations. The eyes' colours are `rgb`:
    /// the frame's own, or with outlines drawn ([`stereo::Outlined`]). The metadata is the
    /// caller's to set.
    pub(super) fn fill_from(&mut self, (frame, rgb): (&StereoFrame, [&[u32]; 2]), request: &Request, cut: &mut Cut) {
        let views = frame.views();
        let (samples, guard) = (views.shown, views.margin);
        let eye = (request.width, request.height);
        let Self { eyes, mask, traced, .. } = self;
        eyes.size = eye;
        let Eyes { left, right, left_overlay, right_overlay: overlay, .. } = eyes;
        left_overlay.clear();
        // Four copies of an eye's size: side by side on the pool (one after the other they
        // were ~1 ms of every frame in which the tracer's threads waited).
        let Cut { eyes: [left_cut, right_cut], mask: shown_mask } = cut;
        rayon::join(
            || {
                let traced = rgb;
                if guard == (0, 0) {
                    filter_eyes(traced, samples, [left, right], eye);
                } else {
                    rayon::join(
                        || cut_band(traced[0], samples, guard, left_cut),
                        || cut_band(traced[1], samples, guard, right_cut),
                    );
                    filter_eyes([left_cut, right_cut], samples, [left, right], eye);
                }
            },
            || {
                mask.clear();
                if guard == (0, 0) {
                    mask.extend_from_slice(frame.mask());
                } else {
                    cut_band(frame.mask(), samples, guard, shown_mask);
                    mask.extend_from_slice(shown_mask);
                }
                // The shown part's classes, and the right pixels a reused frame kept in the
                // mask's "kept" colour. (With the timewarp, the frame is shown as traced, with
                // these colours, while the head is still; a warped frame shows the warp's.)
                if request.overlay {
                    let made = frame.made().map(|(_, right)| right);
                    stereo::downsample_mask_kept_banded(frame.mask(), made, (samples, guard), overlay, eye);
                } else {
                    overlay.clear();
                }
                traced.clear();
                if request.timewarp {
                    traced.left.extend_from_slice(rgb[0]);
                    traced.left_z.extend_from_slice(&frame.left().z);
                    traced.right.extend_from_slice(rgb[1]);
                    traced.right_z.extend_from_slice(frame.right_depth());
                }
            },
        );
        // Dubois's matrices are too slow for the UI thread at 240 Hz: the anaglyph is made
        // here, once per frame, on the rayon pool.
        self.eyes.finish_anaglyph(request.anaglyph, request.swap);
    }
}

/// The `size` part of `image` inside a guard band of `guard` pixels each side, into `out`.
fn cut_band<T: Copy>(image: &[T], size: (u32, u32), guard: (u32, u32), out: &mut Vec<T>) {
    let (w, h, gx, gy) = (size.0 as usize, size.1 as usize, guard.0 as usize, guard.1 as usize);
    let stride = w + 2 * gx;
    debug_assert_eq!(image.len(), stride * (h + 2 * gy), "the image is the size with its band");
    out.clear();
    for row in image.chunks_exact(stride).skip(gy).take(h) {
        out.extend_from_slice(&row[gx..gx + w]);
    }
}
