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

/// Relative offset used by [`spawn_ray`], scaled by the magnitude of the hit point so
/// that it stays above f32 rounding far from the origin.
pub(crate) const SPAWN_EPSILON: f32 = 1e-4;

/// A secondary ray leaving the surface point `p` (unit outward normal `n`) along `dir`.
///
/// Every shadow and reflection ray goes through here. The origin is pushed off the surface
/// along the normal, on the side `dir` leaves towards, so the new ray cannot hit the
/// sphere it starts on because of rounding ("shadow acne").
#[must_use]
pub fn spawn_ray(p: Vec3, n: Vec3, dir: Vec3) -> Ray {
    let offset = SPAWN_EPSILON * (1.0 + p.abs().max_element());
    let side = if dir.dot(n) >= 0.0 { n } else { -n };
    Ray::new(p + offset * side, dir)
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
