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
/// Every shadow and reflection ray goes through here. The origin is pushed off the surface
/// along the normal, on the side `dir` leaves towards (`leaves_outwards`), by a few ULPs
/// of p's largest coordinate: s = K · ulp(‖p‖∞) with K = `SPAWN_ULPS_OUT` = 16 outwards
/// and `SPAWN_ULPS_IN` = 128 inwards, so that origin = p ± s·n. Per component that is
/// bit operations (the largest exponent of the three, see `ulp_of_largest`), one select, and
/// a multiply and an add, as Wächter and Binder's integer-ULP offset ("A Fast and Robust Method
/// for Avoiding Self-Intersection", Ray Tracing Gems ch. 6), but scaled by the largest
/// coordinate rather than each one's own: p's error is shared by its components (it comes
/// from t, below), so a coordinate near zero is no more accurate than the others.
///
/// **Error analysis** (first order; u = 2⁻²⁴, so u·‖p‖∞ < ulp(‖p‖∞) ≤ 2u·‖p‖∞). A hit point
/// p = o + t·d of a ray (origin o, direction d) on the sphere (c, r), with oc = o − c, and
/// n = normalize(p − c):
/// - the stable test ([`crate::intersect_sphere`]) rounds oc, b = oc·d, the perpendicular
///   oc − b·d, Δ = r² − |perp|² and the root, so t errs by up to ≈ 3u|oc| + 7.5u·r²/√Δ + …;
///   but an error in t moves p along d, off the surface only by its component
///   |d·n| = √Δ/r, which cancels the 1/√Δ growth at grazing. Adding the rounding of oc
///   (u|oc|), d being unit only to |η| ≲ 6u (a reflected direction: |η|·|t|) and the
///   rounding of o + t·d (u(|t| + |p|)), with |t| ≤ |oc| + r: p lies off the sphere by
///   ≲ 43u·max(|oc|, r) + u|p| (≲ 36u·r + u|p| when o is inside the sphere);
/// - n is normalised from p − c, so it is within a few u of the radial direction at p, and
///   an offset s·n moves the origin off the sphere by s to second order;
/// - re-testing the spawned ray against its sphere decides the origin's side from the sign
///   of |oc′|² − r², which errs within ≈ 3.5u·r + u|p| of the surface (that rounding, oc′'s,
///   and the rounding of p ± s·n).
///
/// *Outward* rays never meet their own sphere: every lookup skips it for them
/// ([`crate::Tracer`]'s queries, the cube maps and the cones), so the offset does not have to
/// clear it. Against another sphere no offset settles a point within rounding of both
/// surfaces (where two spheres touch, one normal points into the other), so the outward
/// offset is small: 16 ULPs clear p's rounding when p is placed from the centre
/// (p = c + r·n: ≈ 6.5u·r + 2u|p| ≤ 16 ulp(‖p‖∞) for r ≤ 1.9‖p‖∞), so that even the bare
/// sphere test reports no hit, and they move shadow edges and reflections by at most
/// 2·10⁻⁶‖p‖∞ (times tan θ for light at θ from the normal), far below a pixel.
///
/// *Inward* rays (an eye inside a sphere, and the mirror rays inside it after that) must
/// start strictly inside the sphere. The ray that found p started inside too, so the budget
/// is ≲ 36u·r + u|p| + 3.5u·r + u|p| ≤ (40·r/‖p‖∞ + 3.5) ulp(‖p‖∞), which 128 ULPs cover
/// for r ≤ 3.1‖p‖∞: wherever p lies outside the cube of half-side r/3.1 about the world
/// origin, for instance everywhere on a dome centred on the origin (‖p‖∞ ≥ r/√3). Measured
/// over 3·10⁶ random inward rays at scales 10⁻³ to 10⁴, the worst case needed 6 ULPs for
/// r < ‖p‖∞, 32 for r < 8‖p‖∞ and 56 for r < 64‖p‖∞. The sphere must also be wider than
/// the offset, r > 64 ulp(‖p‖∞) (≈ 10⁻⁵‖p‖∞), or the origin passes through it. Outside
/// these bounds the inward offset can fall short or overshoot; scene files keep the eyes
/// outside every sphere, so only a scene built in code gets there.
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
