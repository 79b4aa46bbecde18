//! A sphere, and the ray–sphere test one ray at a time.
//!
//! The test itself is written once, over SIMD lanes (`simd.rs`'s `spheres_t`): the scalar
//! [`intersect_sphere`] is its lane 0, so every query reports bit-for-bit the same `t` for a
//! sphere.

use fearless_simd::{dispatch, f32x4, prelude::*, Simd};
use glam::Vec3;

use crate::ray::Ray;
use crate::simd::{each3, spheres_t};

/// A sphere's geometry at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre (world space).
    pub center: Vec3,
    /// Radius, > 0.
    pub radius: f32,
}

/// Nearest root `t` in `(0, t_max)` of `ray` against the sphere, if any: lane 0 of the lane
/// test (`simd.rs`'s `spheres_t`, which has the numerics), at the lanes `simd.rs` chose.
#[must_use]
pub fn intersect_sphere(ray: &Ray, center: Vec3, radius: f32, t_max: f32) -> Option<f32> {
    fn lane0<S: Simd>(simd: S, ray: &Ray, center: Vec3, radius: f32, t_max: f32) -> f32 {
        let splat = |v: Vec3| each3(|a| f32x4::splat(simd, v[a]));
        let r = f32x4::splat(simd, radius);
        spheres_t(simd, splat(ray.origin), splat(ray.dir), (splat(center), r), f32x4::splat(simd, t_max))[0]
    }
    let t = dispatch!(crate::simd::level(), simd => lane0(simd, ray, center, radius, t_max));
    t.is_finite().then_some(t)
}

impl Sphere {
    /// Nearest hit parameter in `(0, t_max)`.
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        intersect_sphere(ray, self.center, self.radius, t_max)
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

    /// 500 points spread over the sphere (a Fibonacci lattice) and their outward normals,
    /// placed from the centre as c + r·n.
    fn lattice(s: Sphere) -> impl Iterator<Item = (Vec3, Vec3)> {
        (0..500).map(move |k| {
            let a = k as f32 * 0.618_034 * std::f32::consts::TAU;
            let z = 1.0 - 2.0 * ((k as f32 + 0.5) / 500.0);
            let r = (1.0 - z * z).sqrt();
            let n = Vec3::new(r * a.cos(), r * a.sin(), z);
            (s.center + s.radius * n, n)
        })
    }

    /// Spheres near and far from the origin, large and tiny, a dome around the origin.
    const SPHERES: [Sphere; 7] = [
        Sphere { center: Vec3::new(3.0, -2.0, 40.0), radius: 2.5 },
        Sphere { center: Vec3::new(1000.0, -20.0, 30.0), radius: 2.5 },
        Sphere { center: Vec3::new(-300.0, 1e4, 2000.0), radius: 2.5 },
        Sphere { center: Vec3::new(3.0, -2.0, 40.0), radius: 1e-3 },
        Sphere { center: Vec3::new(1000.0, 1000.0, 1000.0), radius: 1e-2 },
        Sphere { center: Vec3::new(0.0, 0.0, 1e4), radius: 1e-2 },
        Sphere { center: Vec3::ZERO, radius: 50.0 },
    ];

    #[test]
    fn spawned_ray_does_not_hit_its_own_sphere() {
        // Rays leaving outwards in directions over the outer hemisphere miss the sphere, even
        // the bare sphere test that does not skip it; a direction grazing the surface is the
        // hardest case.
        for s in SPHERES {
            for (p, n) in lattice(s) {
                let tangent = n.any_orthonormal_vector();
                for dir in [n, (tangent + 0.01 * n).normalize(), (n + tangent).normalize()] {
                    let ray = spawn_ray(p, n, dir);
                    assert_eq!(s.intersect(&ray, f32::INFINITY), None, "self-hit of {s:?} at {p} along {dir}");
                }
            }
        }
    }

    #[test]
    fn a_ray_spawned_inwards_meets_the_far_side() {
        // Rays going into the sphere (an eye inside it) start inside: their hit is the far
        // side, about a chord of 2r·|d·n| away, never the surface they start on. The tiny spheres
        // far out are too small for it: 128 ULPs of their coordinates exceed their radius.
        for s in SPHERES.into_iter().filter(|s| s.radius > 0.1) {
            for (p, n) in lattice(s) {
                let tangent = n.any_orthonormal_vector();
                for dir in [-n, (tangent - 0.05 * n).normalize(), (tangent - n).normalize()] {
                    let ray = spawn_ray(p, n, dir);
                    // The far root from the spawned origin, in double precision.
                    let (oc, d) = ((ray.origin - s.center).as_dvec3(), dir.as_dvec3());
                    let b = oc.dot(d);
                    let far = -b + (b * b - oc.length_squared() + f64::from(s.radius).powi(2)).sqrt();
                    let t = s.intersect(&ray, f32::INFINITY).map(f64::from);
                    assert!(
                        t.is_some_and(|t| (t - far).abs() < 1e-4 * far),
                        "{s:?} at {p} along {dir}: {t:?}, not {far}"
                    );
                }
            }
        }
    }
}
