//! Spheres and the ray–sphere test.

use glam::Vec3;

use crate::ray::Ray;

/// A sphere's geometry at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre (world space).
    pub center: Vec3,
    /// Radius, > 0.
    pub radius: f32,
}

/// Nearest root `t` in `(0, t_max)` of `ray` against the sphere, if any.
///
/// Numerically stable: the discriminant is computed as r² − |oc − (oc·d)d|², which keeps
/// its precision for distant, small spheres (Haines et al., "Precision Improvements for
/// Ray/Sphere Intersection", Ray Tracing Gems ch. 7), and the two roots come from
/// q = −b − sign(b)·√Δ as c/q and q, avoiding the cancellation of (−b ± √Δ).
#[inline]
#[must_use]
pub fn intersect_sphere(ray: &Ray, center: Vec3, radius: f32, t_max: f32) -> Option<f32> {
    let oc = ray.origin - center;
    let b = oc.dot(ray.dir);
    let c = oc.length_squared() - radius * radius;
    let perp = oc - b * ray.dir;
    let disc = radius * radius - perp.length_squared();
    if disc < 0.0 {
        return None;
    }
    let sq = disc.sqrt();
    let q = if b > 0.0 { -b - sq } else { -b + sq };
    // Roots of t² + 2bt + c = 0 (unit direction): t0 · t1 = c, one of them is q.
    let (t0, t1) = if q == 0.0 { (0.0, 0.0) } else { (c / q, q) };
    let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
    if near > 0.0 && near < t_max {
        Some(near)
    } else if far > 0.0 && far < t_max {
        Some(far)
    } else {
        None
    }
}

impl Sphere {
    /// Nearest hit parameter in `(0, t_max)`.
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        intersect_sphere(ray, self.center, self.radius, t_max)
    }

    /// Unit outward normal at a point on the surface.
    #[must_use]
    pub fn normal_at(&self, p: Vec3) -> Vec3 {
        (p - self.center) / self.radius
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ray::spawn_ray;

    #[test]
    fn head_on_roots_are_the_near_and_far_surfaces() {
        // Unit sphere at z = 5, ray from the origin along +z: roots 4 and 6.
        let s = Sphere { center: Vec3::new(0.0, 0.0, 5.0), radius: 1.0 };
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        assert_eq!(s.intersect(&ray, f32::INFINITY), Some(4.0));
        assert_eq!(s.intersect(&ray, 3.9), None);
        // From inside, the far root is the hit.
        let inside = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::Z);
        assert_eq!(s.intersect(&inside, f32::INFINITY), Some(1.0));
        // Behind the ray: no hit.
        let away = Ray::new(Vec3::ZERO, -Vec3::Z);
        assert_eq!(s.intersect(&away, f32::INFINITY), None);
    }

    #[test]
    fn oblique_root_matches_closed_form() {
        // Ray along +z offset by x = 0.6 hits the unit sphere at z = 5 − √(1 − 0.36) = 4.2.
        let s = Sphere { center: Vec3::new(0.0, 0.0, 5.0), radius: 1.0 };
        let ray = Ray::new(Vec3::new(0.6, 0.0, 0.0), Vec3::Z);
        let t = s.intersect(&ray, f32::INFINITY).unwrap();
        assert!((t - 4.2).abs() < 1e-5, "t = {t}");
        // Grazing miss.
        let miss = Ray::new(Vec3::new(1.0001, 0.0, 0.0), Vec3::Z);
        assert_eq!(s.intersect(&miss, f32::INFINITY), None);
    }

    #[test]
    fn small_far_sphere_keeps_precision() {
        // A sphere of radius 0.01 at distance 10 000: the naive b² − c loses all digits.
        let s = Sphere { center: Vec3::new(0.0, 0.0, 10_000.0), radius: 0.01 };
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        let t = s.intersect(&ray, f32::INFINITY).unwrap();
        assert!((t - 9_999.99).abs() < 1e-2, "t = {t}");
    }

    #[test]
    fn spawned_ray_does_not_hit_its_own_sphere() {
        let s = Sphere { center: Vec3::new(3.0, -2.0, 40.0), radius: 2.5 };
        // Many points over the sphere, rays leaving in directions over the outer hemisphere.
        for k in 0..500 {
            let a = k as f32 * 0.618_034 * std::f32::consts::TAU;
            let z = 1.0 - 2.0 * ((k as f32 + 0.5) / 500.0);
            let r = (1.0 - z * z).sqrt();
            let n = Vec3::new(r * a.cos(), r * a.sin(), z);
            let p = s.center + s.radius * n;
            // A direction grazing the surface is the hardest case.
            let tangent = n.any_orthonormal_vector();
            for dir in [n, (tangent + 0.01 * n).normalize(), (n + tangent).normalize()] {
                let ray = spawn_ray(p, n, dir);
                assert_eq!(s.intersect(&ray, f32::INFINITY), None, "self-hit at {p} along {dir}");
            }
        }
    }
}
