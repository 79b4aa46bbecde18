//! The film: one eye's colour plus the visible-surface record of every pixel.

use glam::Vec3;

/// Object id of a pixel whose primary ray missed everything.
pub const NO_OBJECT: u32 = u32::MAX;

/// What the primary ray of one pixel saw (pbrt's "visible surface"), kept so that a second
/// view can reuse it: `stereo` reads this, it never re-derives it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// World-space hit point.
    pub point: Vec3,
    /// Unit outward normal at the hit.
    pub normal: Vec3,
    /// View-independent light at the hit, linear: colour · (ambient + diffuse · Σ visible
    /// lights · n·l). Reusable from any eye.
    pub diffuse: Vec3,
    /// Index of the sphere hit, or [`NO_OBJECT`].
    pub object: u32,
    /// Bit k set when light k reaches the point (faces it and is not in shadow).
    pub lights: u32,
}

impl Surface {
    /// The record of a pixel that saw only background.
    pub const MISS: Self =
        Self { point: Vec3::ZERO, normal: Vec3::ZERO, diffuse: Vec3::ZERO, object: NO_OBJECT, lights: 0 };

    /// Whether the primary ray hit a sphere.
    #[must_use]
    pub fn is_hit(&self) -> bool {
        self.object != NO_OBJECT
    }
}

/// The part of a [`Surface`] that only re-shading reads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shading {
    /// World-space hit point.
    pub point: Vec3,
    /// Unit outward normal at the hit.
    pub normal: Vec3,
    /// View-independent light at the hit (see [`Surface::diffuse`]).
    pub diffuse: Vec3,
}

/// A `width` × `height` image plus its per-pixel visible-surface records, row-major, row 0
/// at the top.
///
/// The record is split into planes (structure of arrays) so that each pass touches only
/// what it needs: reprojection reads `z`, edge and shadow-boundary tests read `object` and
/// `lights`, and only re-shading reads the 36-byte `shading` entries.
#[derive(Clone, Debug, Default)]
pub struct Film {
    width: u32,
    height: u32,
    /// sRGB pixels packed `0x00RRGGBB`.
    pub rgb: Vec<u32>,
    /// Head-space depth beyond the window (the paper's z) of each pixel's hit; +∞ for a miss.
    pub z: Vec<f32>,
    /// Sphere seen by each pixel, or [`NO_OBJECT`].
    pub object: Vec<u32>,
    /// Per-light visibility bits at each pixel's hit (see [`Surface::lights`]).
    pub lights: Vec<u32>,
    /// Hit point, normal and view-independent light of each pixel that hit a sphere;
    /// unspecified where `object` is [`NO_OBJECT`].
    pub shading: Vec<Shading>,
    /// Screen bins of the view last rendered into this film, kept for their buffers.
    pub(crate) bins: crate::primary::PrimaryBins,
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
        self.object.resize(n, NO_OBJECT);
        self.lights.resize(n, 0);
        self.shading.resize(n, Shading { point: Vec3::ZERO, normal: Vec3::ZERO, diffuse: Vec3::ZERO });
    }

    /// The whole visible-surface record of pixel `k` (row-major index); [`Surface::MISS`]
    /// for a pixel that saw only background.
    #[must_use]
    pub fn surface(&self, k: usize) -> Surface {
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

    /// Index of pixel (i, j).
    #[must_use]
    pub fn index(&self, i: u32, j: u32) -> usize {
        j as usize * self.width as usize + i as usize
    }

    /// The sRGB bytes, 3 per pixel, row-major (for PNG output).
    #[must_use]
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.rgb.iter().flat_map(|&p| crate::color::unpack_rgb(p)).collect()
    }
}
