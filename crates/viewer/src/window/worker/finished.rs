//! The frame the worker hands to the UI thread: both eyes cut to their shown part, filtered
//! down to the eye size, the mask's colours, the live-PSNR reference, and for the timewarp
//! each eye's colours and depths with their guard band ([`Traced`]).

use stereo::{Layout, PixelClass, StereoFrame};

use super::{FrameInfo, Request};

/// The traced eyes as the timewarp reads them: each eye's colours and depths at the sampled
/// size with the request's guard band around it, (samples.0 + 2·guard.0) × (samples.1 +
/// 2·guard.1). Empty unless the request asked for them ([`Request::timewarp`]).
#[derive(Debug, Default)]
pub struct Traced {
    /// The guard band they were traced with.
    pub guard: (u32, u32),
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
    /// Left eye, `0x00RRGGBB`, row-major.
    pub left: Vec<u32>,
    /// Right eye, `0x00RRGGBB`, row-major.
    pub right: Vec<u32>,
    /// How each right sample was made, [`Finished::samples`] in size.
    pub mask: Vec<PixelClass>,
    /// The mask's colours (`stereo::mask_color`) at the eye size, each pixel's samples
    /// filtered together as the eyes are: what the overlay shows. Empty unless the request
    /// asked for them ([`Request::overlay`]).
    pub mask_overlay: Vec<u32>,
    /// The red–cyan anaglyph (`0x00RRGGBB`) when the request asked for it, else empty.
    pub anaglyph: Vec<u32>,
    /// The timewarp's mask colours over the left eye (the right eye's are
    /// [`Finished::mask_overlay`]); empty unless a timewarp made them.
    pub left_overlay: Vec<u32>,
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
        self.info.map_or((0, 0), |i| i.samples)
    }

    /// Copies a frame rendered at `samples` in for `request`, filtered down to its eye size,
    /// reusing this frame's allocations. The metadata is the caller's to set.
    pub(super) fn fill_from(&mut self, frame: &StereoFrame, samples: (u32, u32), request: &Request, cut: &mut Cut) {
        let eye = (request.width, request.height);
        let guard = if request.timewarp { request.guard } else { (0, 0) };
        let Self { left, right, mask_overlay: overlay, mask, traced, left_overlay, .. } = self;
        left_overlay.clear();
        // Four copies of an eye's size: side by side on the pool (one after the other they
        // were ~1 ms of every frame in which the tracer's threads waited).
        let Cut { eyes: [left_cut, right_cut], mask: shown_mask } = cut;
        rayon::join(
            || {
                rayon::join(
                    || shown_eye(&frame.left().rgb, (samples, guard), left_cut, left, eye),
                    || shown_eye(&frame.right().rgb, (samples, guard), right_cut, right, eye),
                )
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
                    traced.guard = guard;
                    traced.left.extend_from_slice(&frame.left().rgb);
                    traced.left_z.extend_from_slice(&frame.left().z);
                    traced.right.extend_from_slice(&frame.right().rgb);
                    traced.right_z.extend_from_slice(frame.right_depth());
                }
            },
        );
        if request.anaglyph {
            // Dubois's matrices decode every channel to linear light: too slow for the UI
            // thread at 240 Hz, so it is done here, once per frame, on the rayon pool.
            let (w, h) = eye;
            stereo::compose(Layout::Anaglyph, request.swap, &self.left, &self.right, w, h, &mut self.anaglyph);
        } else {
            self.anaglyph.clear();
        }
    }
}

/// An eye's shown part of `image`, traced at `samples` with `guard` around it (`cut` keeps
/// the part cut out), filtered down to `eye` into `out`.
fn shown_eye(
    image: &[u32],
    (samples, guard): ((u32, u32), (u32, u32)),
    cut: &mut Vec<u32>,
    out: &mut Vec<u32>,
    eye: (u32, u32),
) {
    if guard == (0, 0) {
        stereo::downsample(image, samples, out, eye);
    } else {
        cut_band(image, samples, guard, cut);
        stereo::downsample(cut, samples, out, eye);
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
