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
#[inline]
fn taps(p: u32, samples: u32, pixels: u32) -> (usize, usize, u32) {
    let last = samples - 1;
    // The pixel's centre in sample coordinates, less half a sample: 0 at sample 0's centre.
    let u = ((f64::from(p) + 0.5) * f64::from(samples) / f64::from(pixels) - 0.5).max(0.0);
    let i = (u.floor() as u32).min(last);
    let w = if i == last { 0 } else { ((u - f64::from(i)) * 256.0).round() as u32 };
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
        for (x, out) in row.iter_mut().enumerate() {
            let (x0, x1, wx) = taps(x as u32, sw, dw);
            *out = lerp(lerp(top[x0], top[x1], wx), lerp(bottom[x0], bottom[x1], wx), wy);
        }
    });
}

/// `a` + (`b` − `a`)·`w`/256 per 8-bit channel, rounded.
#[inline]
fn lerp(a: u32, b: u32, w: u32) -> u32 {
    let mut out = 0;
    for shift in [0, 8, 16] {
        let (ca, cb) = ((a >> shift) & 0xFF, (b >> shift) & 0xFF);
        let c = (ca * (256 - w) + cb * w + 128) >> 8;
        out |= c << shift;
    }
    out
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
    fn the_mask_takes_the_nearest_sample() {
        let mut out = Vec::new();
        nearest(|k| k as u32, (2, 2), &mut out, (4, 4));
        assert_eq!(out, [0, 0, 1, 1, 0, 0, 1, 1, 2, 2, 3, 3, 2, 2, 3, 3]);
    }
}
