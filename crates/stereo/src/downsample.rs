//! Supersampling's last step: an image traced at S × S samples per pixel (or at any size at
//! least the output's) filtered down to the output size by a box filter in linear light.
//!
//! Each output pixel covers a rectangle of the sample grid — exactly S × S samples for an
//! integer factor S, and for any other ratio the samples its footprint overlaps, each
//! weighted by the area it shares with the footprint (the box filter of the output pixel,
//! as pbrt-v4's `BoxFilter` of radius ½ pixel, integrated over each sample's area). The
//! samples are 8-bit sRGB, as the film stores them: each is decoded to linear light
//! ([`tracer::srgb8_to_linear`]), the weighted mean is taken per channel, and the mean is
//! encoded back to the nearest 8-bit sRGB level ([`tracer::linear_to_srgb8`]).
//!
//! Why linear light: a pixel's colour stands for the light its footprint receives, and light
//! adds linearly. Averaging the encoded bytes would darken every edge: a pixel half black
//! and half white would come out as byte 128, 22 % of white's light, where the light that
//! reaches it is 50 %, byte 188. The samples were rounded to 8 bits before the mean, which
//! shifts each by at most half a level; averaging the tracer's radiance before it is
//! encoded would avoid that, but the film keeps only the encoded colour.
//!
//! Weights are whole numbers (overlaps on a grid fine enough to hold both the sample and
//! the output edges), so an integer factor weighs every sample exactly 1 and divides by
//! S², and S = 1 decodes and re-encodes every byte unchanged (sRGB round-trips every 8-bit
//! value). [`downsample`] copies an image whose size already matches instead of filtering
//! it.

use rayon::prelude::*;

use tracer::PixelBits;

use crate::mask::{mask_color, KEPT_COLOR};
use crate::stats::PixelClass;

/// Filters `src`, `src_size` = (width, height) sRGB pixels `0x00RRGGBB` row-major, down to
/// `dst_size` into `dst` (resized, its allocation reused) with a box filter in linear light
/// (see the module doc). A `dst_size` equal to `src_size` copies the image; a zero side gives
/// an empty image. A `dst_size` at least as large on both axes (a coarse frame, traced at
/// fewer samples than pixels) is reconstructed by [`crate::upsample`] instead.
///
/// # Panics
///
/// If `src` does not hold `src_size`'s pixels, or `dst_size` is larger than `src_size` on
/// one axis and smaller on the other.
pub fn downsample(src: &[u32], src_size: (u32, u32), dst: &mut Vec<u32>, dst_size: (u32, u32)) {
    if grows(src_size, dst_size) {
        crate::upsample::upsample(src, src_size, dst, dst_size);
        return;
    }
    check_sizes(src.len(), src_size, dst_size);
    if src_size == dst_size {
        dst.clear();
        dst.extend_from_slice(src);
    } else {
        filter(|i| src[i], src_size, dst, dst_size);
    }
}

/// The debug mask of a supersampled right eye as an image of `dst_size`: every sample's
/// [`mask_color`], filtered as [`downsample`] filters colours (a pixel whose samples were made
/// in different ways shows their colours mixed by share). At the same size it is exactly the
/// mask's colours.
///
/// # Panics
///
/// As [`downsample`].
pub fn downsample_mask(mask: &[PixelClass], src_size: (u32, u32), dst: &mut Vec<u32>, dst_size: (u32, u32)) {
    downsample_mask_kept(mask, None, src_size, dst, dst_size);
}

/// [`downsample_mask`], with the samples a reused frame kept from the one before (those not
/// in `made`, when given) in [`KEPT_COLOR`].
pub fn downsample_mask_kept(
    mask: &[PixelClass],
    made: Option<&PixelBits>,
    src_size: (u32, u32),
    dst: &mut Vec<u32>,
    dst_size: (u32, u32),
) {
    downsample_mask_kept_banded(mask, made, (src_size, (0, 0)), dst, dst_size);
}

/// [`downsample_mask_kept`] of the shown part of a frame traced with a guard band: `mask`
/// and `made` cover `src_size` plus `guard` samples beyond each side, and only the
/// `src_size` samples inside the band are filtered.
///
/// # Panics
///
/// As [`downsample`], with the band's size for the mask's.
pub fn downsample_mask_kept_banded(
    mask: &[PixelClass],
    made: Option<&PixelBits>,
    ((sw, sh), (gx, gy)): ((u32, u32), (u32, u32)),
    dst: &mut Vec<u32>,
    dst_size: (u32, u32),
) {
    let (stride, rows) = (sw as usize + 2 * gx as usize, sh as usize + 2 * gy as usize);
    assert_eq!(mask.len(), stride * rows, "the mask holds {} samples, not {stride}×{rows}", mask.len());
    // The colour of the sample at `k` in the band.
    let colour = |k: usize| match made {
        Some(made) if !made.get_index(k) => KEPT_COLOR,
        _ => mask_color(mask[k]),
    };
    if grows((sw, sh), dst_size) {
        let (w, gx, gy) = (sw as usize, gx as usize, gy as usize);
        crate::upsample::nearest(|i| colour((i / w + gy) * stride + i % w + gx), (sw, sh), dst, dst_size);
        return;
    }
    check_sizes(sw as usize * sh as usize, (sw, sh), dst_size);
    let (src_size, (sw, gx, gy)) = ((sw, sh), (sw as usize, gx as usize, gy as usize));
    if src_size == dst_size {
        // Row by row: no division per sample.
        dst.clear();
        for row in gy..gy + sh as usize {
            let first = row * stride + gx;
            dst.extend((first..first + sw).map(colour));
        }
    } else if (gx, gy) == (0, 0) {
        filter(colour, src_size, dst, dst_size);
    } else {
        filter(|i| colour((i / sw + gy) * stride + i % sw + gx), src_size, dst, dst_size);
    }
}

/// Whether `dst` is larger than `src` (a coarse frame shown at the eye size): on one axis
/// and at least as large on the other.
fn grows((sw, sh): (u32, u32), (dw, dh): (u32, u32)) -> bool {
    dw >= sw && dh >= sh && (dw, dh) != (sw, sh)
}

fn check_sizes(len: usize, (sw, sh): (u32, u32), (dw, dh): (u32, u32)) {
    assert_eq!(len, sw as usize * sh as usize, "the source holds {len} pixels, not {sw}×{sh}");
    assert!(dw <= sw && dh <= sh, "downsampling {sw}×{sh} to {dw}×{dh}: the filter only shrinks");
}

/// Greatest common divisor.
fn gcd(mut a: u64, mut b: u64) -> u64 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// One axis of the filter: `samples` samples onto `pixels` pixels. On a grid of
/// `samples · pixels / g` units (g = their gcd), a sample is `pixels / g` units wide and a
/// pixel `samples / g`: every edge of either lies on the grid, so overlaps are whole units.
#[derive(Clone, Copy, Debug)]
struct Axis {
    /// A sample's width, in units.
    sample: u64,
    /// A pixel's width, in units.
    pixel: u64,
}

impl Axis {
    fn new(samples: u32, pixels: u32) -> Self {
        let g = gcd(u64::from(samples), u64::from(pixels)).max(1);
        Self { sample: u64::from(pixels) / g, pixel: u64::from(samples) / g }
    }

    /// Calls `each(sample index, overlap in units)` for every sample pixel `p` overlaps, in
    /// order.
    #[inline]
    fn for_each(self, p: usize, mut each: impl FnMut(usize, f32)) {
        let (start, end) = (p as u64 * self.pixel, (p as u64 + 1) * self.pixel);
        let (first, last) = (start / self.sample, (end - 1) / self.sample);
        for s in first..=last {
            let overlap = end.min((s + 1) * self.sample) - start.max(s * self.sample);
            each(s as usize, overlap as f32);
        }
    }
}

/// The box filter in linear light, parallel over output rows; `sample(i)` is source pixel i.
fn filter(sample: impl Fn(usize) -> u32 + Sync, (sw, sh): (u32, u32), dst: &mut Vec<u32>, (dw, dh): (u32, u32)) {
    dst.resize(dw as usize * dh as usize, 0);
    if dw == 0 || dh == 0 {
        return;
    }
    let (x_axis, y_axis) = (Axis::new(sw, dw), Axis::new(sh, dh));
    // A pixel's area in units²; with an integer factor S, S².
    let scale = 1.0 / (x_axis.pixel as f32 * y_axis.pixel as f32);
    let sw = sw as usize;
    dst.par_chunks_mut(dw as usize).enumerate().for_each(|(y, row)| {
        for (x, out) in row.iter_mut().enumerate() {
            let mut sum = [0.0f32; 3];
            y_axis.for_each(y, |sy, wy| {
                x_axis.for_each(x, |sx, wx| {
                    let [r, g, b] = tracer::unpack_rgb(sample(sy * sw + sx));
                    let w = wx * wy;
                    sum[0] += w * tracer::srgb8_to_linear(r);
                    sum[1] += w * tracer::srgb8_to_linear(g);
                    sum[2] += w * tracer::srgb8_to_linear(b);
                });
            });
            let [r, g, b] = sum.map(|c| u32::from(tracer::linear_to_srgb8(c * scale)));
            *out = (r << 16) | (g << 8) | b;
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const BLACK: u32 = 0;
    const WHITE: u32 = 0x00FF_FFFF;

    #[test]
    fn a_2x2_block_averages_in_linear_light() {
        // Half the samples white: half the light, which sRGB encodes as 188 (0.7354 · 255),
        // not the 128 of averaging the bytes.
        let mut out = Vec::new();
        downsample(&[BLACK, WHITE, WHITE, BLACK], (2, 2), &mut out, (1, 1));
        assert_eq!(out, [0x00BC_BCBC]);
        // Red, green, blue and white: each channel is full in two of four samples.
        downsample(&[0x00FF_0000, 0x0000_FF00, 0x0000_00FF, WHITE], (2, 2), &mut out, (1, 1));
        assert_eq!(out, [0x00BC_BCBC]);
        // One white sample of four: a quarter of the light, sRGB 137 (0.5371 · 255).
        downsample(&[WHITE, BLACK, BLACK, BLACK], (2, 2), &mut out, (1, 1));
        assert_eq!(out, [0x0089_8989]);
        assert_eq!(tracer::linear_to_srgb8(0.25), 0x89, "the closed form above");
    }

    #[test]
    fn each_output_pixel_takes_its_own_block() {
        // 4 × 2 samples to 2 × 1: the left block is black, the right one white.
        let src = [BLACK, BLACK, WHITE, WHITE, BLACK, BLACK, WHITE, WHITE];
        let mut out = Vec::new();
        downsample(&src, (4, 2), &mut out, (2, 1));
        assert_eq!(out, [BLACK, WHITE]);
        // 3 × 3 blocks, one white sample each: a ninth of the light.
        let mut src = vec![BLACK; 6 * 3];
        src[6 + 1] = WHITE; // the middle of the first block
        src[3 * 6 - 1] = WHITE; // the corner of the second
        downsample(&src, (6, 3), &mut out, (2, 1));
        let ninth = u32::from(tracer::linear_to_srgb8(1.0 / 9.0));
        assert_eq!(out, [ninth * 0x0001_0101; 2]);
    }

    #[test]
    fn a_fractional_ratio_weighs_samples_by_overlap() {
        // 3 samples onto 2 pixels: pixel 0 covers sample 0 and half of sample 1, pixel 1
        // the other half of sample 1 and sample 2.
        let mut out = Vec::new();
        downsample(&[WHITE, BLACK, BLACK], (3, 1), &mut out, (2, 1));
        let two_thirds = u32::from(tracer::linear_to_srgb8(2.0 / 3.0));
        assert_eq!(out, [two_thirds * 0x0001_0101, BLACK]);
        downsample(&[BLACK, WHITE, BLACK], (3, 1), &mut out, (2, 1));
        let third = u32::from(tracer::linear_to_srgb8(1.0 / 3.0));
        assert_eq!(out, [third * 0x0001_0101; 2]);
    }

    #[test]
    fn the_mask_mixes_its_class_colours() {
        let mut out = Vec::new();
        let mask = [PixelClass::Reprojected; 4];
        downsample_mask(&mask, (2, 2), &mut out, (1, 1));
        assert_eq!(out, [mask_color(PixelClass::Reprojected)], "one class keeps its colour");
        let mask = [PixelClass::Reprojected, PixelClass::RetracedGap];
        downsample_mask(&mask, (2, 1), &mut out, (2, 1));
        assert_eq!(out, mask.map(mask_color), "the same size: the colours themselves");
        let mut mixed = Vec::new();
        downsample(&mask.map(mask_color), (2, 1), &mut mixed, (1, 1));
        downsample_mask(&mask, (2, 1), &mut out, (1, 1));
        assert_eq!(out, mixed, "two classes: their colours, filtered as an image");
    }

    #[test]
    fn a_banded_mask_shows_its_shown_part_only() {
        // 4 × 2 shown samples inside a band of 1 and 2: the band's samples are edges, the
        // shown ones alternate reprojected and gaps, and one of them was kept.
        let (shown, guard) = ((4u32, 2u32), (1u32, 2u32));
        let (stride, rows) = (6u32, 6u32);
        let inside = |i: u32, j: u32| (1..5).contains(&i) && (2..4).contains(&j);
        let mut mask = Vec::new();
        let mut made = tracer::PixelBits::new(stride, rows);
        let mut cut = Vec::new();
        let mut cut_made = tracer::PixelBits::new(shown.0, shown.1);
        for j in 0..rows {
            for i in 0..stride {
                let class = if !inside(i, j) {
                    PixelClass::RetracedEdge
                } else if (i + j) % 2 == 0 {
                    PixelClass::Reprojected
                } else {
                    PixelClass::RetracedGap
                };
                let kept = (i, j) == (2, 3);
                mask.push(class);
                made.set(i, j, !kept);
                if inside(i, j) {
                    cut.push(class);
                    cut_made.set(i - guard.0, j - guard.1, !kept);
                }
            }
        }
        for dst in [(4, 2), (2, 1), (3, 2)] {
            let (mut banded, mut plain) = (Vec::new(), Vec::new());
            downsample_mask_kept_banded(&mask, Some(&made), (shown, guard), &mut banded, dst);
            downsample_mask_kept(&cut, Some(&cut_made), shown, &mut plain, dst);
            assert_eq!(banded, plain, "to {dst:?}");
        }
        let mut out = Vec::new();
        downsample_mask_kept_banded(&mask, Some(&made), (shown, guard), &mut out, shown);
        assert!(out.contains(&KEPT_COLOR) && !out.contains(&mask_color(PixelClass::RetracedEdge)), "{out:x?}");
    }

    #[test]
    fn empty_sizes_give_empty_images() {
        let mut out = vec![7];
        downsample(&[], (0, 0), &mut out, (0, 0));
        assert!(out.is_empty());
        downsample(&[WHITE; 4], (2, 2), &mut out, (0, 1));
        assert!(out.is_empty());
    }

    #[test]
    #[should_panic(expected = "the filter only shrinks")]
    fn growing_one_axis_and_shrinking_the_other_is_refused() {
        downsample(&[WHITE; 2], (1, 2), &mut Vec::new(), (2, 1));
    }

    #[test]
    fn a_larger_size_is_reconstructed_and_the_mask_takes_its_nearest_sample() {
        let mut out = Vec::new();
        downsample(&[BLACK, WHITE], (2, 1), &mut out, (4, 2));
        let mut grown = Vec::new();
        crate::upsample(&[BLACK, WHITE], (2, 1), &mut grown, (4, 2));
        assert_eq!(out, grown);
        let mask = [PixelClass::Reprojected, PixelClass::RetracedGap];
        downsample_mask(&mask, (2, 1), &mut out, (4, 1));
        let [a, b] = mask.map(mask_color);
        assert_eq!(out, [a, a, b, b]);
    }

    proptest! {
        /// S = 1 is the identity: through the copy, and through the filter itself (weights
        /// of 1, sRGB round-tripping every byte).
        #[test]
        fn one_sample_per_pixel_is_the_identity(
            (w, h, src) in (1u32..9, 1u32..9).prop_flat_map(|(w, h)| {
                (Just(w), Just(h), proptest::collection::vec(0u32..=0x00FF_FFFF, (w * h) as usize))
            })
        ) {
            let mut out = Vec::new();
            downsample(&src, (w, h), &mut out, (w, h));
            prop_assert_eq!(&out, &src);
            filter(|i| src[i], (w, h), &mut out, (w, h));
            prop_assert_eq!(&out, &src);
        }

        /// A block of one colour keeps it, at every factor.
        #[test]
        fn a_uniform_block_keeps_its_colour(s in 1u32..=4, c in 0u32..=0x00FF_FFFF, w in 1u32..4, h in 1u32..4) {
            let src = vec![c; (w * s * h * s) as usize];
            let mut out = Vec::new();
            filter(|i| src[i], (w * s, h * s), &mut out, (w, h));
            prop_assert_eq!(out, vec![c; (w * h) as usize]);
        }
    }
}
