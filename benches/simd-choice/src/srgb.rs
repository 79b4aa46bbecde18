//! Linear light to packed 8-bit sRGB: a copy of stereotrace's `tracer/src/color.rs` encoder
//! (exact rounding of the IEC 61966-2-1 curve via 128 buckets per octave and one threshold
//! compare), so that every kernel packs exactly as the project does.
//!
//! Note: the project does not use a 4096-entry table indexed by `c·4095`; that table would
//! round differently from the exact curve near black (its step, 1/4095, is about one 8-bit
//! level there).

#![expect(
    clippy::inline_always,
    reason = "a SIMD kernel must inline into the function that enables its target features"
)]

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
/// `powf` per channel.
///
/// `base` has one more entry than the project's, 255 for [1, ∞), which [`pack_span`]'s
/// branch-free encoding indexes for every value ≥ 1.
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

impl EncodeTable {
    #[inline]
    fn encode(&self, c: f32) -> u8 {
        if c.is_nan() || c < MIN_LINEAR {
            return 0;
        }
        if c >= 1.0 {
            return 255;
        }
        let k = self.base[((c.to_bits() >> BUCKET_SHIFT) - FIRST_BUCKET) as usize];
        k + u8::from(c >= self.thresholds[k as usize])
    }

    /// The same result as [`EncodeTable::encode`] without a branch: NaN, negative values and
    /// −0 become +0, whose bucket index saturates to 0, and values ≥ 1 saturate to the
    /// extra bucket (255). Compiles to selects, so a lane loop stays branch-free.
    #[inline(always)]
    fn encode_branchless(&self, c: f32) -> u8 {
        let x = if c > 0.0 { c } else { 0.0 };
        let b = ((x.to_bits() >> BUCKET_SHIFT).saturating_sub(FIRST_BUCKET)).min(BUCKETS as u32);
        let k = self.base[b as usize];
        k.saturating_add(u8::from(x >= self.thresholds[k as usize]))
    }
}

/// Packs linear radiance into a `0x00RRGGBB` sRGB pixel (`tracer::color::pack_rgb`).
#[inline]
#[must_use]
pub fn pack_rgb(c: Vec3) -> u32 {
    pack(c.x, c.y, c.z)
}

/// Packs one pixel from its three linear channels.
#[inline]
#[must_use]
pub fn pack(r: f32, g: f32, b: f32) -> u32 {
    let table = &*TABLE;
    (u32::from(table.encode(r)) << 16) | (u32::from(table.encode(g)) << 8) | u32::from(table.encode(b))
}

/// Packs a span of lanes: `rgb[j]` from `r[j]`, `g[j]`, `b[j]`, exactly as [`pack`] does.
/// The table look-ups are gathers, done one lane at a time by every kernel, branch-free;
/// `inline(always)` keeps the loop inside the dispatched function.
#[inline(always)]
pub fn pack_span(r: &[f32], g: &[f32], b: &[f32], rgb: &mut [u32]) {
    let table = &*TABLE;
    for (((out, &r), &g), &b) in rgb.iter_mut().zip(r).zip(g).zip(b) {
        *out = (u32::from(table.encode_branchless(r)) << 16)
            | (u32::from(table.encode_branchless(g)) << 8)
            | u32::from(table.encode_branchless(b));
    }
}

/// Forces the table's construction (outside timed code).
pub fn warm() {
    LazyLock::force(&TABLE);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_matches_rounding_the_exact_curve() {
        for bits in (0..=1.0f32.to_bits()).step_by(64) {
            let c = f32::from_bits(bits);
            let exact = (encode(f64::from(c)) * 255.0).round();
            assert_eq!(f64::from(TABLE.encode(c)), exact, "c = {c}");
        }
        assert_eq!(pack_rgb(Vec3::new(1.0, 0.0, 0.5)), 0x00FF_00BC, "known pixel");
    }

    #[test]
    fn branchless_encoding_matches_the_projects() {
        let specials =
            [0.0, -0.0, 1.0, f32::NAN, -f32::NAN, f32::INFINITY, f32::NEG_INFINITY, MIN_LINEAR, f32::MIN_POSITIVE];
        let strided = (0..=u32::MAX).step_by(251).map(f32::from_bits);
        for c in specials.into_iter().chain(strided) {
            assert_eq!(TABLE.encode_branchless(c), TABLE.encode(c), "c = {c} ({:#010x})", c.to_bits());
        }
        for t in TABLE.thresholds.iter().take(255) {
            let below = f32::from_bits(t.to_bits() - 1);
            assert_eq!(TABLE.encode_branchless(*t), TABLE.encode(*t), "threshold {t}");
            assert_eq!(TABLE.encode_branchless(below), TABLE.encode(below), "below threshold {t}");
        }
    }
}
