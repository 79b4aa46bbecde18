//! What the window presents: both eyes at the eye size, the debug mask's colours over them
//! and the anaglyph. The worker's [`Finished`](super::Finished) frame holds one, made from
//! a traced pair; the timewarp (`window/timewarp.rs`) holds its own, made by warping that
//! pair. Both finish theirs the same way: each eye filtered down from its samples
//! ([`stereo::downsample`], a box filter in linear light), then the anaglyph.

use stereo::Layout;

/// Two eyes ready to present, `size` each, row-major `0x00RRGGBB`.
#[derive(Debug, Default)]
pub struct Eyes {
    /// Eye size in pixels, (0, 0) before the first frame.
    pub size: (u32, u32),
    /// The left eye.
    pub left: Vec<u32>,
    /// The right eye.
    pub right: Vec<u32>,
    /// Mask colours blended over the left eye: a warped frame's classes; empty otherwise.
    pub left_overlay: Vec<u32>,
    /// Mask colours blended over the right eye: the stereo pair's classes
    /// (`stereo::mask_color`), or a warped frame's; empty unless shown.
    pub right_overlay: Vec<u32>,
    /// The red–cyan anaglyph when asked for, else empty.
    pub anaglyph: Vec<u32>,
}

impl Eyes {
    /// The last step of finishing a pair: the anaglyph of the two eyes when `anaglyph`
    /// asks for it (red over the right eye's image when `swap`), else none.
    pub(crate) fn finish_anaglyph(&mut self, anaglyph: bool, swap: bool) {
        if anaglyph {
            // Dubois's matrices decode every channel to linear light: done once per frame,
            // on the rayon pool of whoever finishes it.
            let (w, h) = self.size;
            stereo::compose(Layout::Anaglyph, swap, &self.left, &self.right, w, h, &mut self.anaglyph);
        } else {
            self.anaglyph.clear();
        }
    }
}

/// Both eyes from `sampled` (left, right), traced or warped at `samples`, filtered down to
/// `eye` into `out`, side by side on the pool (at the same size, copies).
pub(crate) fn filter_eyes([left, right]: [&[u32]; 2], samples: (u32, u32), out: [&mut Vec<u32>; 2], eye: (u32, u32)) {
    let [left_out, right_out] = out;
    rayon::join(
        || stereo::downsample(left, samples, left_out, eye),
        || stereo::downsample(right, samples, right_out, eye),
    );
}
