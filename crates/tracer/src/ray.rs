//! Rays, mirror reflection and the one place secondary rays are spawned.

use glam::Vec3;

/// A ray `origin + t · dir` with a unit-length direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts (world space).
    pub origin: Vec3,
    /// Unit direction.
    pub dir: Vec3,
}

impl Ray {
    /// A ray from `origin` along `dir`, which must already be normalised.
    #[must_use]
    pub fn new(origin: Vec3, dir: Vec3) -> Self {
        debug_assert!((dir.length_squared() - 1.0).abs() < 1e-4, "ray direction not unit: {dir}");
        Self { origin, dir }
    }

    /// The point at parameter `t`.
    #[must_use]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.dir
    }
}

/// Mirror reflection of the incoming direction `d` about the unit normal `n`:
/// r = d − 2 (d · n) n. `d` points *towards* the surface, `r` away from it.
#[must_use]
pub fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - 2.0 * d.dot(n) * n
}

/// How far [`spawn_ray`] moves a ray that leaves its sphere outwards, in ULPs of the hit
/// point's largest coordinate (see [`spawn_ray`]'s error analysis).
pub(crate) const SPAWN_ULPS_OUT: f32 = 16.0;
/// How far [`spawn_ray`] moves a ray that goes into its sphere, in the same ULPs.
pub(crate) const SPAWN_ULPS_IN: f32 = 128.0;
/// The hit point's own distance from its sphere, in ULPs of the scene's reach, for a ray
/// whose origin lies within that reach (see [`spawn_ray`]: ≲ 43u·max(|o − c|, r) + u|p|
/// with |o − c| ≤ 2√3·reach and r ≤ reach, so about 75 ULPs).
const HIT_ULPS: f32 = 128.0;

/// Whether a ray along `dir` leaves a surface of outward normal `n` outwards: the one test
/// that picks [`spawn_ray`]'s side and lets the lookups skip the sphere the ray starts on
/// (a sphere is convex: a ray leaving it outwards cannot meet it again).
#[inline]
#[must_use]
pub(crate) fn leaves_outwards(n: Vec3, dir: Vec3) -> bool {
    dir.dot(n) >= 0.0
}

/// ulp(‖p‖∞): the spacing of `f32` at `p`'s largest coordinate, 2^(e − 23) for
/// 2^e ≤ ‖p‖∞ < 2^(e+1), from the bits (the largest |pᵢ| has the largest bit pattern; its
/// exponent field, times 2⁻²³). At least 2⁻¹⁴⁹ (for p = 0), so never zero.
#[inline]
fn ulp_of_largest(p: Vec3) -> f32 {
    const EXPONENT: u32 = 0x7f80_0000;
    let bits = p.x.abs().to_bits().max(p.y.abs().to_bits()).max(p.z.abs().to_bits());
    f32::from_bits((bits & EXPONENT).max(f32::MIN_POSITIVE.to_bits())) * f32::EPSILON
}

/// A bound on how far the origin of any ray [`spawn_ray`] makes lies from the surface of the
/// sphere it leaves, in a scene whose sphere points and ray origins (the eyes) all have
/// coordinates of magnitude ≤ `reach`: the larger offset plus the hit point's own rounding.
/// The cube maps and the cones pad their bounds by it.
#[must_use]
pub(crate) fn spawn_bound(reach: f32) -> f32 {
    // ulp(‖p‖∞) ≤ ε·‖p‖∞; twice that for a hit point rounded just past `reach`.
    (SPAWN_ULPS_IN + HIT_ULPS) * 2.0 * f32::EPSILON * reach
}

/// A secondary ray leaving the surface point `p` (unit outward normal `n`) along `dir`.
///
/// Every shadow and reflection ray goes through here. The origin moves along ±n, to the side
/// `dir` leaves towards (`leaves_outwards`), by 16 ULPs of p's largest coordinate outwards
/// (`SPAWN_ULPS_OUT`) or 128 inwards (`SPAWN_ULPS_IN`): Wächter and Binder's integer-ULP
/// offset (Ray Tracing Gems ch. 6), scaled by the largest coordinate. An outward ray is never
/// tested against its own sphere, so the offset need not clear it; an inward ray starts
/// strictly inside its sphere within stated bounds on the scene. The error analysis that
/// sizes both offsets, and those bounds: `docs/design/spawn-offset.md`.
#[inline]
#[must_use]
pub fn spawn_ray(p: Vec3, n: Vec3, dir: Vec3) -> Ray {
    let ulps = if leaves_outwards(n, dir) { SPAWN_ULPS_OUT } else { -SPAWN_ULPS_IN };
    Ray::new(p + (ulps * ulp_of_largest(p)) * n, dir)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reflection_mirrors_about_the_normal() {
        // A ray going down-right onto a floor (normal +y) leaves up-right.
        let d = Vec3::new(1.0, -1.0, 0.0).normalize();
        let r = reflect(d, Vec3::Y);
        assert!((r - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-6);
        // Head-on incidence comes straight back.
        assert_eq!(reflect(Vec3::Z, -Vec3::Z), -Vec3::Z);
        // Angle of incidence equals angle of reflection and length is kept.
        let n = Vec3::new(0.3, 0.9, -0.2).normalize();
        let d = Vec3::new(0.5, -0.7, 0.4).normalize();
        let r = reflect(d, n);
        assert!((r.length() - 1.0).abs() < 1e-6);
        assert!((r.dot(n) + d.dot(n)).abs() < 1e-6);
    }

    #[test]
    fn spawned_ray_starts_on_the_side_it_leaves_towards() {
        let p = Vec3::new(0.0, 0.0, 10.0);
        let up = spawn_ray(p, Vec3::Y, Vec3::Y);
        assert!(up.origin.y > 0.0);
        let into = spawn_ray(p, Vec3::Y, -Vec3::Y);
        assert!(into.origin.y < 0.0);
    }
}
