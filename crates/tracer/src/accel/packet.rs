//! Packets of four spheres in structure-of-arrays lanes: what a light's cube-map cell and a
//! sphere's direction cones list, each tested against one ray in one SIMD test.

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use fearless_simd::{f32x4, prelude::*, u32x4, Simd};
use glam::Vec3;

use crate::ray::Ray;
use crate::simd::{each3, spheres_t};

/// Spheres per [`SpherePacket`].
pub(crate) const LANES: usize = 4;

/// Up to four spheres in structure-of-arrays lanes, tested against one ray at once (four
/// lanes of `fearless_simd` at whatever level the caller's kernel runs). Unused lanes have
/// NaN centres, which never hit, and the id `u32::MAX`.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub(crate) struct SpherePacket {
    center: [[f32; LANES]; 3],
    radius: [f32; LANES],
    /// Sphere id of each lane.
    pub(crate) ids: [u32; LANES],
}

/// A ray splatted across a packet's four lanes: origin and unit direction.
pub(crate) type PacketRay<S> = ([f32x4<S>; 3], [f32x4<S>; 3]);

/// `ray` splatted across four lanes.
#[inline(always)]
pub(crate) fn packet_ray<S: Simd>(simd: S, ray: &Ray) -> PacketRay<S> {
    let splat = |v: Vec3| each3(|a| f32x4::splat(simd, v[a]));
    (splat(ray.origin), splat(ray.dir))
}

impl SpherePacket {
    /// A packet with every lane empty.
    pub(crate) const EMPTY: Self =
        Self { center: [[f32::NAN; LANES]; 3], radius: [0.0; LANES], ids: [u32::MAX; LANES] };

    /// Puts sphere `id` in `lane`.
    pub(crate) fn set(&mut self, lane: usize, id: u32, center: Vec3, radius: f32) {
        for a in 0..3 {
            self.center[a][lane] = center[a];
        }
        self.radius[lane] = radius;
        self.ids[lane] = id;
    }

    /// The ray's parameter against each lane, +∞ where it misses or the hit is outside
    /// `(0, t_max)`.
    #[inline(always)]
    pub(crate) fn hits<S: Simd>(&self, simd: S, (o, d): PacketRay<S>, t_max: f32) -> f32x4<S> {
        let center = each3(|a| f32x4::from_slice(simd, &self.center[a]));
        let radius = f32x4::from_slice(simd, &self.radius);
        spheres_t(simd, o, d, (center, radius), f32x4::splat(simd, t_max))
    }

    /// Whether the ray meets one of the packet's spheres other than `skip` in `(0, t_max)`.
    #[inline(always)]
    pub(crate) fn blocks<S: Simd>(&self, simd: S, ray: PacketRay<S>, t_max: f32, skip: u32) -> bool {
        let t = self.hits(simd, ray, t_max);
        let others = u32x4::from_slice(simd, &self.ids).simd_ne(u32x4::splat(simd, skip));
        (t.simd_lt(f32x4::splat(simd, f32::INFINITY)) & others).any_true()
    }
}
