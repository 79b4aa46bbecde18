//! The film: one eye's colour plus the visible-surface record of every pixel (pbrt's film
//! with its visible-surface buffer, kept apart from the camera).

use crate::surface::{Shading, Surface, NO_OBJECT};

/// Which parts of a [`Film`]'s visible-surface record a render keeps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Record {
    /// Colour only: a mono image, or an eye nothing is reprojected from.
    Colour,
    /// Colour, depth, hit parameter, object and light bits: what reprojection, edge
    /// classification, `exact` and `reshade` modes read (the light bits, `reshade` alone).
    Keys,
    /// Everything, the shading entries (point, normal, view-independent light) too.
    #[default]
    Full,
}

/// A `width` × `height` image plus its per-pixel visible-surface records, row-major, row 0
/// at the top.
///
/// The record is split into planes (structure of arrays) so that each pass touches only
/// what it needs: reprojection reads `z`, edge tests read `object`, reshade reads `lights`,
/// and only re-shading reads the 36-byte `shading` entries.
#[derive(Clone, Debug, Default)]
pub struct Film {
    width: u32,
    height: u32,
    /// What the last render kept; the other planes are stale.
    record: Record,
    /// sRGB pixels packed `0x00RRGGBB`.
    pub rgb: Vec<u32>,
    /// Head-space depth beyond the window (the paper's z) of each pixel's hit; +∞ for a miss.
    pub z: Vec<f32>,
    /// Ray parameter of each pixel's hit along its primary ray (unspecified for a miss):
    /// with the ray, the hit point and normal again, bit for bit.
    pub t: Vec<f32>,
    /// Sphere seen by each pixel, or [`NO_OBJECT`].
    pub object: Vec<u32>,
    /// Per-light visibility bits at each pixel's hit (see [`Surface::lights`]).
    pub lights: Vec<u32>,
    /// Hit point, normal and view-independent light of each pixel that hit a sphere;
    /// unspecified where `object` is [`NO_OBJECT`].
    pub shading: Vec<Shading>,
}

impl Film {
    /// A film of the given size, black, every pixel a miss.
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        let mut film = Self::default();
        film.resize(width, height);
        film
    }

    /// Changes the size, reusing the allocations where they are large enough.
    pub fn resize(&mut self, width: u32, height: u32) {
        let n = width as usize * height as usize;
        self.width = width;
        self.height = height;
        self.rgb.resize(n, 0);
        self.z.resize(n, f32::INFINITY);
        self.t.resize(n, f32::INFINITY);
        self.object.resize(n, NO_OBJECT);
        self.lights.resize(n, 0);
        self.shading.resize(n, Shading::MISS);
    }

    /// What the last render kept of the record ([`Record::Full`] for a new film).
    #[must_use]
    pub fn record(&self) -> Record {
        self.record
    }

    /// Notes what a render is about to keep.
    pub(crate) fn set_record(&mut self, record: Record) {
        self.record = record;
    }

    /// The whole visible-surface record of pixel `k` (row-major index); [`Surface::MISS`]
    /// for a pixel that saw only background. Needs a film rendered with [`Record::Full`].
    #[must_use]
    pub fn surface(&self, k: usize) -> Surface {
        debug_assert_eq!(self.record, Record::Full, "the film's shading entries were not kept");
        if self.object[k] == NO_OBJECT {
            return Surface::MISS;
        }
        let s = &self.shading[k];
        Surface { point: s.point, normal: s.normal, diffuse: s.diffuse, object: self.object[k], lights: self.lights[k] }
    }

    /// Width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }
}
