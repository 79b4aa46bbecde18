//! A coarse frame's last step: an image traced at fewer samples than the eye has pixels
//! (the progressive viewer's frames while the head moves: one sample per k × k pixels)
//! reconstructed at the eye size.
//!
//! Colours are interpolated bilinearly between the four nearest samples, each sample
//! standing at its pixel's centre (the tent filter, pbrt-v4's `TriangleFilter` of radius
//! one sample), per channel on the 8-bit values, with 8-bit fixed-point weights: the
//! image is a stand-in shown for a few display ticks, not a measurement, and this keeps
//! the step at a few milliseconds for a 800 × 600 eye. At the edges the nearest sample is
//! repeated. Masks are not interpolated: each pixel takes its nearest sample's colour.

use rayon::prelude::*;

/// One axis of the reconstruction, for output pixel `p` of `pixels` from `samples`
/// samples: the two samples around its centre and the second one's weight in 1/256ths.
/// The centre is at u = (p + ½)·samples/pixels − ½ in samples (0 at sample 0's centre),
/// in whole 1/256ths: ((2p + 1)·samples − pixels)·128 / pixels, rounded down.
#[inline]
fn taps(p: u32, samples: u32, pixels: u32) -> (usize, usize, u64) {
    let last = u64::from(samples - 1);
    let num = (2 * i64::from(p) + 1) * i64::from(samples) - i64::from(pixels);
    let u = (num * 128 / i64::from(pixels)).max(0) as u64;
    let i = (u >> 8).min(last);
    let w = if i == last { 0 } else { u & 0xFF };
    (i as usize, (i + 1).min(last) as usize, w)
}

/// Reconstructs `src` (`src_size`, sRGB `0x00RRGGBB` row-major) at `dst_size`, at least as
/// large on both axes, into `dst` (resized, its allocation reused): bilinear on the 8-bit
/// channels (module doc). Equal sizes copy.
///
/// # Panics
///
/// If `src` does not hold `src_size`'s pixels or `dst_size` is smaller on either axis.
pub fn upsample(src: &[u32], (sw, sh): (u32, u32), dst: &mut Vec<u32>, (dw, dh): (u32, u32)) {
    assert_eq!(src.len(), sw as usize * sh as usize, "the source holds {} pixels, not {sw}×{sh}", src.len());
    assert!(dw >= sw && dh >= sh, "upsampling {sw}×{sh} to {dw}×{dh}: this filter only grows");
    dst.resize(dw as usize * dh as usize, 0);
    if dw == 0 || dh == 0 || sw == 0 || sh == 0 {
        return;
    }
    let w = sw as usize;
    dst.par_chunks_mut(dw as usize).enumerate().for_each(|(y, row)| {
        let (y0, y1, wy) = taps(y as u32, sh, dh);
        let (top, bottom) = (&src[y0 * w..][..w], &src[y1 * w..][..w]);
        let mut x_taps = Taps::new(sw, dw);
        for out in row.iter_mut() {
            let (x0, x1, wx) = x_taps.next_pixel();
            *out = lerp(lerp(top[x0], top[x1], wx), lerp(bottom[x0], bottom[x1], wx), wy);
        }
    });
}

/// [`taps`] for pixels 0, 1, 2, … in turn, without a division per pixel: the numerator
/// steps by 2·samples·128 a pixel, its quotient by pixels and remainder carried.
struct Taps {
    last: u64,
    pixels: i64,
    /// ⌊numerator / pixels⌋ and the remainder (floor division: the remainder ≥ 0).
    quotient: i64,
    remainder: i64,
    step: (i64, i64),
}

impl Taps {
    fn new(samples: u32, pixels: u32) -> Self {
        let p = i64::from(pixels);
        let num = (i64::from(samples) - p) * 128;
        let step = 2 * i64::from(samples) * 128;
        Self {
            last: u64::from(samples - 1),
            pixels: p,
            quotient: num.div_euclid(p),
            remainder: num.rem_euclid(p),
            step: (step / p, step % p),
        }
    }

    #[inline]
    fn next_pixel(&mut self) -> (usize, usize, u64) {
        let u = self.quotient.max(0) as u64;
        self.quotient += self.step.0;
        self.remainder += self.step.1;
        if self.remainder >= self.pixels {
            self.quotient += 1;
            self.remainder -= self.pixels;
        }
        let i = (u >> 8).min(self.last);
        let w = if i == self.last { 0 } else { u & 0xFF };
        (i as usize, (i + 1).min(self.last) as usize, w)
    }
}

/// `a` + (`b` − `a`)·`w`/256 per 8-bit channel, rounded: the three channels at once, each
/// in a 16-bit field of a `u64` (red and blue where they are, green moved up past them).
#[inline]
fn lerp(a: u32, b: u32, w: u64) -> u32 {
    const ROUND: u64 = 0x80 | 0x80 << 16 | 0x80 << 32;
    let spread = |c: u32| u64::from(c & 0x00FF_00FF) | u64::from(c & 0x0000_FF00) << 24;
    let m = (spread(a) * (256 - w) + spread(b) * w + ROUND) >> 8;
    (m & 0x00FF_00FF) as u32 | ((m >> 24) & 0xFF00) as u32
}

/// Each `dst_size` pixel's nearest sample, `colour(k)` of sample k of a `src_size` grid.
pub(crate) fn nearest(
    colour: impl Fn(usize) -> u32 + Sync,
    (sw, sh): (u32, u32),
    dst: &mut Vec<u32>,
    (dw, dh): (u32, u32),
) {
    dst.resize(dw as usize * dh as usize, 0);
    if dw == 0 || dh == 0 || sw == 0 || sh == 0 {
        return;
    }
    let near = |p: u32, samples: u32, pixels: u32| (u64::from(p) * u64::from(samples) / u64::from(pixels)) as usize;
    dst.par_chunks_mut(dw as usize).enumerate().for_each(|(y, row)| {
        let sy = near(y as u32, sh, dh);
        for (x, out) in row.iter_mut().enumerate() {
            *out = colour(sy * sw as usize + near(x as u32, sw, dw));
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_sizes_copy_and_a_flat_image_stays_flat() {
        let src: Vec<u32> = (0..12).map(|i| i * 0x0001_0203).collect();
        let mut out = Vec::new();
        upsample(&src, (4, 3), &mut out, (4, 3));
        assert_eq!(out, src);
        upsample(&[0x0012_3456; 6], (3, 2), &mut out, (7, 5));
        assert_eq!(out, [0x0012_3456; 35]);
    }

    #[test]
    fn doubling_a_ramp_interpolates_between_sample_centres() {
        // Two samples, 0 and 200 in blue: four pixels at ¼, ¾ of the way and the edges
        // clamped to the nearest sample.
        let mut out = Vec::new();
        upsample(&[0, 200], (2, 1), &mut out, (4, 1));
        assert_eq!(out, [0, 50, 150, 200]);
        // Channels stay apart: no carry from blue into green.
        upsample(&[0x0000_00FF, 0x00FF_0000], (2, 1), &mut out, (4, 1));
        assert_eq!(out, [0x0000_00FF, 0x0040_00BF, 0x00BF_0040, 0x00FF_0000]);
    }

    #[test]
    fn the_stepped_taps_are_the_closed_form_ones() {
        for (samples, pixels) in [(1, 7), (2, 4), (100, 800), (267, 800), (3, 1000), (50, 51), (7, 7)] {
            let mut stepped = Taps::new(samples, pixels);
            for p in 0..pixels {
                assert_eq!(stepped.next_pixel(), taps(p, samples, pixels), "{samples} → {pixels}, pixel {p}");
            }
        }
    }

    #[test]
    fn the_mask_takes_the_nearest_sample() {
        let mut out = Vec::new();
        nearest(|k| k as u32, (2, 2), &mut out, (4, 4));
        assert_eq!(out, [0, 0, 1, 1, 0, 0, 1, 1, 2, 2, 3, 3, 2, 2, 3, 3]);
    }
}
