//! Linear light to 8-bit sRGB and back, and the packed pixel format.
//!
//! Shading is done in linear light; a pixel is encoded to sRGB (IEC 61966-2-1) only when it
//! is written to the film. Pixels are packed as `0x00RRGGBB`, the format softbuffer shows.

use std::sync::LazyLock;

use glam::Vec3;

/// The exact sRGB transfer function, linear → encoded, in f64.
fn encode(c: f64) -> f64 {
    if c <= 0.003_130_8 {
        12.92 * c
    } else {
        1.055 * c.powf(1.0 / 2.4) - 0.055
    }
}

/// The inverse transfer function, encoded → linear, in f64.
fn decode(s: f64) -> f64 {
    if s <= 0.040_45 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

/// Smallest linear value that can encode above 0: below it every value rounds to level 0.
const MIN_LINEAR: f32 = 1.0 / 8192.0; // 2^-13
/// Buckets per octave of linear values, from the top mantissa bits of the f32.
const MANTISSA_BITS: u32 = 7;
const BUCKET_SHIFT: u32 = 23 - MANTISSA_BITS;
/// Bucket index of `MIN_LINEAR`.
const FIRST_BUCKET: u32 = MIN_LINEAR.to_bits() >> BUCKET_SHIFT;
/// Buckets from 2^-13 up to 1.
const BUCKETS: usize = (13 << MANTISSA_BITS) as usize;

/// Encoding table. `thresholds[k]` is the linear value where the nearest 8-bit sRGB level
/// changes from k to k + 1, decode((k + ½)/255). The linear range [2^-13, 1) is cut into
/// 128 buckets per octave by the float's exponent and top mantissa bits; `base[b]` is the
/// level at the start of bucket b, and no bucket holds more than one threshold, so one
/// comparison finishes the encoding. Same result as rounding the exact curve, without a
/// `powf` per channel. `base` has one entry more, 255, for every value ≥ 1, so the
/// encoding needs no branch: values below 2^-13 fall in bucket 0 (level 0, below the first
/// threshold), values ≥ 1 in the last.
struct EncodeTable {
    thresholds: [f32; 256],
    base: [u8; BUCKETS + 1],
}

static TABLE: LazyLock<EncodeTable> = LazyLock::new(|| {
    let level = |c: f32| (encode(f64::from(c)) * 255.0).round();
    let mut thresholds = [f32::INFINITY; 256];
    for (k, v) in thresholds.iter_mut().take(255).enumerate() {
        // Start from the inverse curve, then settle on the exact first f32 of level k + 1.
        let next = k as f64 + 1.0;
        let mut t = decode((k as f64 + 0.5) / 255.0) as f32;
        while level(t) < next {
            t = f32::from_bits(t.to_bits() + 1);
        }
        while level(f32::from_bits(t.to_bits() - 1)) >= next {
            t = f32::from_bits(t.to_bits() - 1);
        }
        *v = t;
    }
    let mut base = [255u8; BUCKETS + 1];
    for (b, level) in base.iter_mut().take(BUCKETS).enumerate() {
        let start = f32::from_bits((FIRST_BUCKET + b as u32) << BUCKET_SHIFT);
        *level = thresholds.iter().take_while(|&&t| t <= start).count() as u8;
    }
    EncodeTable { thresholds, base }
});

/// Encodes one linear channel (clamped to 0..1; NaN as 0) as the nearest 8-bit sRGB value.
#[inline]
#[must_use]
pub fn linear_to_srgb8(c: f32) -> u8 {
    TABLE.encode(c)
}

impl EncodeTable {
    /// The level of `c`, without a branch: NaN and negatives as 0, values ≥ 1 as 255.
    #[inline]
    fn encode(&self, c: f32) -> u8 {
        let x = if c > 0.0 { c } else { 0.0 };
        let b = ((x.to_bits() >> BUCKET_SHIFT).saturating_sub(FIRST_BUCKET)).min(BUCKETS as u32);
        let k = self.base[b as usize];
        k.saturating_add(u8::from(x >= self.thresholds[k as usize]))
    }
}

/// Decodes one 8-bit sRGB value to linear light.
#[must_use]
pub fn srgb8_to_linear(v: u8) -> f32 {
    DECODE[usize::from(v)]
}

/// `DECODE[v]` is sRGB level v in linear light.
static DECODE: LazyLock<[f32; 256]> = LazyLock::new(|| std::array::from_fn(|v| decode(v as f64 / 255.0) as f32));

/// Packs linear radiance into a `0x00RRGGBB` sRGB pixel.
#[must_use]
#[inline]
pub fn pack_rgb(c: Vec3) -> u32 {
    let table = &*TABLE;
    let r = u32::from(table.encode(c.x));
    let g = u32::from(table.encode(c.y));
    let b = u32::from(table.encode(c.z));
    (r << 16) | (g << 8) | b
}

/// Splits a `0x00RRGGBB` pixel into its sRGB bytes.
#[must_use]
pub fn unpack_rgb(p: u32) -> [u8; 3] {
    [(p >> 16) as u8, (p >> 8) as u8, p as u8]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips_every_byte() {
        for v in 0..=255u8 {
            assert_eq!(linear_to_srgb8(srgb8_to_linear(v)), v);
        }
    }

    #[test]
    fn table_matches_rounding_the_exact_curve() {
        // Every 16th float in [0, 1], and every threshold and its neighbours: the table must
        // agree with the exact curve rounded.
        let level = |c: f32| (encode(f64::from(c)) * 255.0).round();
        for bits in (0..=1.0f32.to_bits()).step_by(16) {
            let c = f32::from_bits(bits);
            assert_eq!(f64::from(linear_to_srgb8(c)), level(c), "c = {c}");
        }
        for &t in &TABLE.thresholds[..255] {
            for c in [f32::from_bits(t.to_bits() - 1), t, f32::from_bits(t.to_bits() + 1)] {
                assert_eq!(f64::from(linear_to_srgb8(c)), level(c), "c = {c} by the threshold {t}");
            }
        }
        // Out of range: every float above 1 and below 0 (a stride through their bits).
        for bits in (1.0f32.to_bits() + 1..=f32::INFINITY.to_bits()).step_by(4099) {
            assert_eq!(linear_to_srgb8(f32::from_bits(bits)), 255, "{}", f32::from_bits(bits));
        }
        for bits in ((-0.0f32).to_bits()..=f32::NEG_INFINITY.to_bits()).step_by(4099) {
            assert_eq!(linear_to_srgb8(f32::from_bits(bits)), 0, "{}", f32::from_bits(bits));
        }
    }

    #[test]
    fn no_bucket_holds_two_thresholds() {
        let t = &*TABLE;
        for b in 0..BUCKETS {
            let lo = f32::from_bits((FIRST_BUCKET + b as u32) << BUCKET_SHIFT);
            let hi = f32::from_bits((FIRST_BUCKET + b as u32 + 1) << BUCKET_SHIFT);
            let inside = t.thresholds.iter().filter(|&&x| x > lo && x < hi).count();
            assert!(inside <= 1, "bucket {b} [{lo}, {hi}) holds {inside} thresholds");
        }
    }

    #[test]
    fn known_values() {
        assert_eq!(linear_to_srgb8(0.0), 0);
        assert_eq!(linear_to_srgb8(1.0), 255);
        assert_eq!(linear_to_srgb8(2.0), 255);
        assert_eq!(linear_to_srgb8(f32::NAN), 0);
        // Linear 0.5 is sRGB 188 (0.7354 · 255).
        assert_eq!(linear_to_srgb8(0.5), 188);
        assert_eq!(pack_rgb(Vec3::new(1.0, 0.0, 0.5)), 0x00FF_00BC);
        assert_eq!(unpack_rgb(0x00FF_00BC), [255, 0, 188]);
    }
}
