//! The right eye's image: colour only, without the left film's visible-surface record.

/// An image without a visible-surface record: the right eye.
#[derive(Clone, Debug, Default)]
pub struct Image {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// sRGB pixels packed `0x00RRGGBB`, row-major.
    pub rgb: Vec<u32>,
}
