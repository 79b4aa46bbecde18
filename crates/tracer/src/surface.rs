//! What a ray found: the closest [`Hit`] of a scene query, and the per-pixel visible-surface
//! record ([`Surface`], pbrt's "visible surface") that a second view reuses.
//!
//! A leaf module: the film stores these records, shading makes them, `stereo` reads them.

use glam::Vec3;

/// Object id of a pixel whose primary ray missed everything.
pub const NO_OBJECT: u32 = u32::MAX;

/// The closest hit of a ray: its parameter and the sphere it met.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the hit point, in the query's `(0, t_max)`.
    pub t: f32,
    /// Index of the sphere hit (never [`NO_OBJECT`]).
    pub object: u32,
}

/// What the primary ray of one pixel saw, kept so that a second view can reuse it: `stereo`
/// reads this, it never re-derives it.
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
    /// Light visibility: bit k is set when light k reaches the point (the surface faces it
    /// and no sphere shadows it). At most [`crate::MAX_LIGHTS`] lights, so the bits fit.
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

impl Shading {
    /// The entry of a pixel that saw only background (nothing reads it).
    pub const MISS: Self = Self { point: Vec3::ZERO, normal: Vec3::ZERO, diffuse: Vec3::ZERO };
}
