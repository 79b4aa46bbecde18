//! The debug colour mask (the seed paper's Fig. 2): how each right-eye pixel was made.

use crate::stats::PixelClass;

/// Mask colour of a class, `0x00RRGGBB`: reprojected green and retraced-for-gaps red as in
/// the paper; edges yellow, full traces grey.
#[must_use]
pub fn mask_color(class: PixelClass) -> u32 {
    match class {
        PixelClass::Reprojected => 0x0030_C040,
        PixelClass::RetracedGap => 0x00E0_3030,
        PixelClass::RetracedEdge => 0x00F0_D020,
        PixelClass::Traced => 0x0080_8080,
    }
}

/// Mask colour of a pixel that a reused frame kept from the frame before (`reuse/`): a
/// dark slate, so that what was made anew stands out in its class's colour.
pub const KEPT_COLOR: u32 = 0x0028_2C38;

/// The legend entry of [`KEPT_COLOR`].
pub const KEPT_LEGEND: &str = "kept from the last frame (reuse)";

/// The mask as an image: the [`mask_color`] of every pixel's class, `0x00RRGGBB`, into
/// `out` (reusing its allocation).
pub fn mask_image(mask: &[PixelClass], out: &mut Vec<u32>) {
    out.clear();
    out.extend(mask.iter().map(|&c| mask_color(c)));
}

/// The legend: each class with its colour and a short label.
pub const MASK_LEGEND: [(PixelClass, &str); PixelClass::COUNT] = [
    (PixelClass::Reprojected, "reprojected"),
    (PixelClass::RetracedGap, "retraced: gap / border"),
    (PixelClass::RetracedEdge, "retraced: object edge"),
    (PixelClass::Traced, "traced (full mode)"),
];
