//! Spheres and the ray–sphere test.

use glam::Vec3;
use wide::f32x4;

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

/// Spheres per SIMD packet.
pub(crate) const LANES: usize = 4;

/// Up to four spheres in structure-of-arrays lanes (`wide::f32x4`: SSE2 on x86-64, NEON on
/// aarch64, scalar elsewhere), tested against one ray at once. Unused lanes have NaN
/// centres, which never hit.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SpherePacket {
    cx: f32x4,
    cy: f32x4,
    cz: f32x4,
    r: f32x4,
    /// Sphere id of each lane.
    pub(crate) ids: [u32; LANES],
}

/// Sets one lane of `v` to `x` (for building packets, not for hot loops).
pub(crate) fn set_lane(v: &mut f32x4, lane: usize, x: f32) {
    let mut a = v.to_array();
    a[lane] = x;
    *v = f32x4::from(a);
}

/// A vector splatted across four lanes, one `f32x4` per component.
#[inline]
pub(crate) fn splat3(v: Vec3) -> [f32x4; 3] {
    [f32x4::splat(v.x), f32x4::splat(v.y), f32x4::splat(v.z)]
}

impl SpherePacket {
    /// A packet with every lane empty.
    pub(crate) const EMPTY: Self = Self {
        cx: f32x4::splat(f32::NAN),
        cy: f32x4::splat(f32::NAN),
        cz: f32x4::splat(f32::NAN),
        r: f32x4::splat(0.0),
        ids: [u32::MAX; LANES],
    };

    /// Puts sphere `id` in `lane`.
    pub(crate) fn set(&mut self, lane: usize, id: u32, center: Vec3, radius: f32) {
        set_lane(&mut self.cx, lane, center.x);
        set_lane(&mut self.cy, lane, center.y);
        set_lane(&mut self.cz, lane, center.z);
        set_lane(&mut self.r, lane, radius);
        self.ids[lane] = id;
    }

    /// The ray's parameter against each lane (ray origin `o` and unit direction `d`
    /// splatted), +∞ where it misses or the hit is outside `(0, t_max)`.
    ///
    /// The same operations in the same order as [`intersect_sphere`], lane by lane, so a
    /// sphere's `t` is bit-for-bit the scalar one whichever packet and lane it sits in:
    /// every query that tests spheres (BVH leaves, screen tiles, single-sphere tests) agrees.
    #[inline]
    pub(crate) fn hits(&self, o: [f32x4; 3], d: [f32x4; 3], t_max: f32) -> [f32; LANES] {
        let (ox, oy, oz) = (o[0] - self.cx, o[1] - self.cy, o[2] - self.cz);
        let r2 = self.r * self.r;
        let c = (ox * ox + oy * oy + oz * oz) - r2;
        nearest_root([ox, oy, oz], d, r2, c, f32x4::splat(t_max)).to_array()
    }

    /// Whether the ray (splatted as for [`SpherePacket::hits`]) meets one of the packet's
    /// spheres other than `skip` in `(0, t_max)`.
    #[inline]
    pub(crate) fn blocks(&self, o: [f32x4; 3], d: [f32x4; 3], t_max: f32, skip: u32) -> bool {
        self.hits(o, d, t_max).iter().zip(self.ids).any(|(t, id)| t.is_finite() && id != skip)
    }
}

/// One sphere seen from a fixed ray origin, ready to test four rays from there at once:
/// the primary rays of an eye.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SphereFromOrigin {
    /// origin − centre.
    pub(crate) oc: [f32; 3],
    /// radius².
    pub(crate) r2: f32,
    /// |oc|² − radius².
    pub(crate) c: f32,
    /// The sphere's id.
    pub(crate) id: u32,
}

impl SphereFromOrigin {
    /// The sphere (`center`, `radius`) as seen from `origin`.
    pub(crate) fn new(origin: Vec3, center: Vec3, radius: f32, id: u32) -> Self {
        let oc = [origin.x - center.x, origin.y - center.y, origin.z - center.z];
        let r2 = radius * radius;
        let c = (oc[0] * oc[0] + oc[1] * oc[1] + oc[2] * oc[2]) - r2;
        Self { oc, r2, c, id }
    }
}

/// The lane-wise core of the ray–sphere test shared by every SIMD query, in the order of
/// [`intersect_sphere`]: `oc` = origin − centre, `d` unit, `r2` = r², `c` = |oc|² − r².
#[inline]
fn nearest_root(oc: [f32x4; 3], d: [f32x4; 3], r2: f32x4, c: f32x4, t_max: f32x4) -> f32x4 {
    let [ox, oy, oz] = oc;
    let b = ox * d[0] + oy * d[1] + oz * d[2];
    let (px, py, pz) = (ox - b * d[0], oy - b * d[1], oz - b * d[2]);
    let disc = r2 - (px * px + py * py + pz * pz);
    let zero = f32x4::splat(0.0);
    let touched = disc.simd_ge(zero);
    let inf = f32x4::splat(f32::INFINITY);
    if touched.to_bitmask() == 0 {
        return inf;
    }
    let sq = disc.sqrt();
    let q = b.simd_gt(zero).bitselect(-b - sq, -b + sq);
    let t0 = c / q;
    let (near, far) = (t0.min(q), t0.max(q));
    let near_ok = near.simd_gt(zero) & near.simd_lt(t_max);
    let far_ok = far.simd_gt(zero) & far.simd_lt(t_max);
    let t = near_ok.bitselect(near, far_ok.bitselect(far, inf));
    touched.bitselect(t, inf)
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
