//! Linear light to 8-bit sRGB and back, and the packed pixel format.
//!
//! Shading is done in linear light; a pixel is encoded to sRGB (IEC 61966-2-1) only when it
//! is written to the film. Pixels are packed as `0x00RRGGBB`, the format softbuffer shows.

use glam::Vec3;

/// Encodes one linear channel (clamped to 0..1) as an 8-bit sRGB value.
#[must_use]
pub fn linear_to_srgb8(c: f32) -> u8 {
    let c = if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
    let s = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0 + 0.5) as u8
}

/// Decodes an 8-bit sRGB value to linear light.
#[must_use]
pub fn srgb8_to_linear(v: u8) -> f32 {
    let s = f32::from(v) / 255.0;
    if s <= 0.040_45 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

/// Packs linear radiance into a `0x00RRGGBB` sRGB pixel.
#[must_use]
pub fn pack_rgb(c: Vec3) -> u32 {
    let r = u32::from(linear_to_srgb8(c.x));
    let g = u32::from(linear_to_srgb8(c.y));
    let b = u32::from(linear_to_srgb8(c.z));
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
