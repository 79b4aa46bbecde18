//! How a stereo pair reaches the viewer's eyes: the layouts stereo viewers such as Bino offer.
//!
//! [`Layout::slots`] is the one place that says which eye goes where; [`compose`] (the
//! exported pairs) and the viewer's window both arrange the eyes by it.

use std::fmt;
use std::str::FromStr;

use rayon::prelude::*;
use tracer::{linear_to_srgb8, srgb8_to_linear, Eye};

/// Arrangement of the two eye images in one output image.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Layout {
    /// Left eye on the left: VR viewers and parallel free-viewing.
    #[default]
    SideBySide,
    /// Right eye on the left: cross-eyed free-viewing.
    CrossEyed,
    /// Red-cyan anaglyph with Dubois's least-squares matrices: red glass over the left eye.
    Anaglyph,
}

impl Layout {
    /// Every layout, in menu order.
    pub const ALL: [Layout; 3] = [Layout::SideBySide, Layout::CrossEyed, Layout::Anaglyph];

    /// Name on the command line.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Layout::SideBySide => "side-by-side",
            Layout::CrossEyed => "cross-eyed",
            Layout::Anaglyph => "anaglyph",
        }
    }

    /// Which eye's image fills each of the layout's two slots: the left and right halves of
    /// a pair, or the anaglyph's red and cyan parts. `swap` exchanges the eyes (for viewers
    /// who see the pair the other way round); cross-eyed is side by side with the eyes
    /// exchanged.
    #[must_use]
    pub fn slots(self, swap: bool) -> [Eye; 2] {
        if (self == Layout::CrossEyed) == swap {
            [Eye::Left, Eye::Right]
        } else {
            [Eye::Right, Eye::Left]
        }
    }

    /// Size of the composed image for eyes of `w` × `h`.
    #[must_use]
    pub fn size(self, w: u32, h: u32) -> (u32, u32) {
        match self {
            Layout::SideBySide | Layout::CrossEyed => (2 * w, h),
            Layout::Anaglyph => (w, h),
        }
    }
}

impl fmt::Display for Layout {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Layout {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Layout::ALL
            .into_iter()
            .find(|l| l.name() == s)
            .ok_or_else(|| format!("unknown layout `{s}`: expected side-by-side, cross-eyed or anaglyph"))
    }
}

/// Dubois's red-cyan matrices (linear RGB in, linear RGB out), left eye then right eye.
const DUBOIS_LEFT: [[f32; 3]; 3] = [[0.456, 0.500, 0.176], [-0.040, -0.038, -0.016], [-0.015, -0.021, -0.005]];
const DUBOIS_RIGHT: [[f32; 3]; 3] = [[-0.043, -0.088, -0.002], [0.378, 0.734, -0.018], [-0.072, -0.113, 1.226]];

fn linear(p: u32) -> [f32; 3] {
    [srgb8_to_linear((p >> 16) as u8), srgb8_to_linear((p >> 8) as u8), srgb8_to_linear(p as u8)]
}

/// One anaglyph pixel from a left and a right `0x00RRGGBB` pixel.
#[must_use]
pub fn anaglyph_pixel(left: u32, right: u32) -> u32 {
    let (l, r) = (linear(left), linear(right));
    let mut out = 0u32;
    for (row, shift) in [16, 8, 0].into_iter().enumerate() {
        let mut c = 0.0;
        for k in 0..3 {
            c += DUBOIS_LEFT[row][k] * l[k] + DUBOIS_RIGHT[row][k] * r[k];
        }
        out |= u32::from(linear_to_srgb8(c)) << shift;
    }
    out
}

/// Composes two `w` × `h` eye images (`0x00RRGGBB`) into `out`, resized to
/// [`Layout::size`], with the eyes in [`Layout::slots`]. The anaglyph, which decodes every
/// channel to linear light, is made in parallel over rows (on rayon's pool).
pub fn compose(layout: Layout, swap: bool, left: &[u32], right: &[u32], w: u32, h: u32, out: &mut Vec<u32>) {
    let [a, b] = layout.slots(swap).map(|eye| match eye {
        Eye::Left => left,
        Eye::Right => right,
    });
    let (ow, oh) = layout.size(w, h);
    let n = ow as usize * oh as usize;
    let w = (w as usize).max(1);
    out.clear();
    match layout {
        Layout::SideBySide | Layout::CrossEyed => {
            out.reserve(n);
            for (ra, rb) in a.chunks_exact(w).zip(b.chunks_exact(w)) {
                out.extend_from_slice(ra);
                out.extend_from_slice(rb);
            }
        }
        Layout::Anaglyph => {
            out.resize(n, 0);
            out.par_chunks_mut(w).zip(a.par_chunks(w).zip(b.par_chunks(w))).for_each(|(o, (a, b))| {
                for (o, (&l, &r)) in o.iter_mut().zip(a.iter().zip(b)) {
                    *o = anaglyph_pixel(l, r);
                }
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn side_by_side_and_cross_eyed_place_the_eyes() {
        let (l, r) = ([1, 2, 3, 4], [5, 6, 7, 8]);
        let mut out = Vec::new();
        compose(Layout::SideBySide, false, &l, &r, 2, 2, &mut out);
        assert_eq!(out, vec![1, 2, 5, 6, 3, 4, 7, 8], "side by side: the left eye on the left");
        compose(Layout::CrossEyed, false, &l, &r, 2, 2, &mut out);
        assert_eq!(out, vec![5, 6, 1, 2, 7, 8, 3, 4], "cross-eyed: the right eye on the left");
        compose(Layout::SideBySide, true, &l, &r, 2, 2, &mut out);
        assert_eq!(out, vec![5, 6, 1, 2, 7, 8, 3, 4], "swapped side by side is cross-eyed");
        compose(Layout::CrossEyed, true, &l, &r, 2, 2, &mut out);
        assert_eq!(out, vec![1, 2, 5, 6, 3, 4, 7, 8], "cross-eyed and swapped is side by side");
    }

    #[test]
    fn anaglyph_puts_the_left_eye_in_red_and_the_right_in_cyan() {
        let white = 0x00FF_FFFF;
        // Only the left eye lit: red dominates. Only the right: green and blue dominate.
        let left_only = anaglyph_pixel(white, 0);
        let [r, g, b] = tracer::unpack_rgb(left_only);
        assert!(r > 200 && g == 0 && b == 0, "{left_only:06x}");
        let right_only = anaglyph_pixel(0, white);
        let [r, g, b] = tracer::unpack_rgb(right_only);
        assert!(r == 0 && g > 200 && b > 200, "{right_only:06x}");
        let mut out = Vec::new();
        compose(Layout::Anaglyph, false, &[white, 0], &[0, white], 2, 1, &mut out);
        assert_eq!(out, vec![left_only, right_only]);
        compose(Layout::Anaglyph, true, &[white, 0], &[0, white], 2, 1, &mut out);
        assert_eq!(out, vec![right_only, left_only], "swapped: red shows the right eye");
        assert_eq!(Layout::Anaglyph.size(4, 3), (4, 3), "the anaglyph is eye-sized");
        assert_eq!("cross-eyed".parse::<Layout>(), Ok(Layout::CrossEyed), "layouts parse by name");
    }
}
