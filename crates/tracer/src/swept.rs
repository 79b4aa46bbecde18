//! Where moving spheres can ever be: a conservative swept volume per orbit, and the test of
//! a ray segment against it. The ground of exact temporal reuse (after Adelson & Hodges
//! 1995, "Generating exact ray-traced animation frames by reprojection", IEEE CG&A 15(3),
//! made exact): a ray that never meets any moving sphere's swept volume meets the same
//! spheres, at the same parameters, at every instant.
//!
//! An `orbit` sphere of radius r revolves in a horizontal circle of radius R about a centre
//! c (`scene.rs`), so it sweeps a torus. Its bound is the washer that holds the torus: the
//! slab |y − c.y| ≤ r between two horizontal planes, intersected with the annulus
//! R − r ≤ ρ ≤ R + r, ρ the distance from the vertical axis through c. Unlike one ball
//! about the whole circle, the washer leaves out what stands inside the ring (the seed
//! scene's white sphere) and what is above or below it. Every limit is widened by a margin
//! ([`SweptRing::margin`]) far above the float error of the sphere's position and of the
//! test itself, so rounding can only make the test say "meets" more often.

use glam::Vec3;

use crate::scene::Motion;

/// Relative size of the margin: against the largest coordinate involved, ~1700× the f32
/// epsilon, far above the few roundings in a centre from `Motion::center_at` or in a hit
/// point on the sphere.
const MARGIN: f32 = 1e-4;

/// The swept volume of one orbiting sphere: a washer about a vertical axis (see the module
/// doc), its limits already widened by the margin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweptRing {
    /// Centre of the orbit.
    pub center: Vec3,
    /// Half-height of the slab: the sphere's radius plus the margin.
    pub half_height: f32,
    /// Inner radius of the annulus (R − r − margin, at least 0).
    pub inner: f32,
    /// Outer radius of the annulus (R + r + margin).
    pub outer: f32,
    /// The widening each limit has.
    pub margin: f32,
    /// The sphere (its index in the scene) that moves in it.
    pub object: u32,
}

impl SweptRing {
    /// The bound of sphere `object`, of radius `radius`, moving as `motion`; `None` for a
    /// sphere that does not move.
    #[must_use]
    pub fn of(object: u32, radius: f32, motion: &Motion) -> Option<Self> {
        let Motion::Orbit { center, radius: ring, .. } = *motion else { return None };
        let margin = MARGIN * (1.0 + center.abs().max_element() + ring + radius);
        Some(Self {
            center,
            half_height: radius + margin,
            inner: (ring - radius - margin).max(0.0),
            outer: ring + radius + margin,
            margin,
            object,
        })
    }

    /// Radius of a ball about [`SweptRing::center`] that holds the washer.
    #[must_use]
    pub fn bounding_radius(&self) -> f32 {
        self.outer.hypot(self.half_height)
    }

    /// Whether the sphere of centre `c` and radius `r` lies in the washer. Every position of
    /// the orbit's sphere does, with the margin to spare; this is the invariant the reuse of
    /// frames rests on, asserted whenever a tracer places a moving sphere.
    #[must_use]
    pub fn holds(&self, c: Vec3, r: f32) -> bool {
        let q = c - self.center;
        let rho = q.x.hypot(q.z);
        q.y.abs() + r <= self.half_height && rho + r <= self.outer && (self.inner == 0.0 || rho - r >= self.inner)
    }

    /// Whether the segment `o + s·d`, 0 ≤ s ≤ `s_max` (+∞ for a ray), meets the washer.
    /// `d` need not be unit. Conservative: never `false` for a segment that meets it.
    #[must_use]
    pub fn meets(&self, o: Vec3, d: Vec3, s_max: f32) -> bool {
        let q = o - self.center;
        // The slab: the part of the segment between the planes y = ±half_height.
        let (mut lo, mut hi) = (0.0f32, s_max);
        if d.y == 0.0 {
            if q.y.abs() > self.half_height {
                return false;
            }
        } else {
            let (a, b) = ((-self.half_height - q.y) / d.y, (self.half_height - q.y) / d.y);
            lo = lo.max(a.min(b));
            hi = hi.min(a.max(b));
            if lo > hi {
                return false;
            }
        }
        // The annulus: ρ²(s) = a·s² + 2b·s + k is convex, so over [lo, hi] it takes every
        // value between its least (at the vertex, clamped) and its greatest (at an end).
        let (a, b, k) = (d.x * d.x + d.z * d.z, q.x * d.x + q.z * d.z, q.x * q.x + q.z * q.z);
        let rho2 = |s: f32| if s.is_finite() { (a * s + 2.0 * b) * s + k } else { f32::INFINITY };
        let vertex = if a > 0.0 { (-b / a).clamp(lo, hi) } else { lo };
        let least = rho2(vertex);
        let greatest = if a > 0.0 { rho2(lo).max(rho2(hi)) } else { k };
        least <= self.outer * self.outer && greatest >= self.inner * self.inner
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;

    fn orbit(center: Vec3, radius: f32) -> Motion {
        Motion::Orbit { center, radius, period_s: 8.0, phase_deg: 30.0 }
    }

    #[test]
    fn a_static_sphere_has_no_bound() {
        assert_eq!(SweptRing::of(0, 1.0, &Motion::Static(Vec3::ZERO)), None);
    }

    #[test]
    fn the_washer_leaves_out_the_middle_and_what_is_above() {
        // A ring of radius 2.5 about a sphere in its middle, swept by a sphere of 0.5.
        let ring = SweptRing::of(3, 0.5, &orbit(Vec3::new(0.0, 1.0, 15.0), 2.5)).unwrap();
        let down = Vec3::new(0.0, -1.0, 0.0);
        // Straight down through the centre (inside the hole) and down beside the ring.
        assert!(!ring.meets(Vec3::new(0.0, 10.0, 15.0), down, f32::INFINITY));
        assert!(!ring.meets(Vec3::new(3.5, 10.0, 15.0), down, f32::INFINITY));
        // Down through the ring itself, and a ray that ends just above it.
        assert!(ring.meets(Vec3::new(2.5, 10.0, 15.0), down, f32::INFINITY));
        assert!(!ring.meets(Vec3::new(2.5, 10.0, 15.0), down, 8.4));
        assert!(ring.meets(Vec3::new(2.5, 10.0, 15.0), down, 8.6));
        // Horizontal, above the slab and in it; a horizontal chord through the hole still
        // crosses the ring twice.
        let x = Vec3::X;
        assert!(!ring.meets(Vec3::new(-10.0, 1.6, 15.0), x, f32::INFINITY));
        assert!(ring.meets(Vec3::new(-10.0, 1.4, 15.0), x, f32::INFINITY));
        // A segment wholly inside the hole, and one wholly outside the ring.
        assert!(!ring.meets(Vec3::new(-1.0, 1.0, 15.0), x, 2.0));
        assert!(!ring.meets(Vec3::new(3.5, 1.0, 15.0), x, 5.0));
        // Pointing away.
        assert!(!ring.meets(Vec3::new(-10.0, 1.0, 15.0), -x, f32::INFINITY));
    }

    #[test]
    fn a_sphere_off_its_path_is_not_held() {
        let motion = orbit(Vec3::new(1.0, 2.0, 3.0), 2.0);
        let ring = SweptRing::of(0, 0.5, &motion).unwrap();
        let c = motion.center_at(1.3);
        assert!(ring.holds(c, 0.5));
        assert!(!ring.holds(c + Vec3::new(0.0, 2.0 * ring.margin, 0.0), 0.5), "raised out of the slab");
        assert!(!ring.holds(c + (c - Vec3::new(1.0, 2.0, 3.0)) * 0.01, 0.5), "pushed out of the annulus");
        assert!(!ring.holds(c, 0.5 + 2.0 * ring.margin), "grown");
    }

    proptest! {
        /// Every position of the orbit is held, and every ray through a point of the moving
        /// sphere, or ending on it, meets the bound.
        #[test]
        fn the_bound_holds_the_sphere_and_every_ray_to_it(
            c in prop::array::uniform3(-50.0f32..50.0),
            ring in 0.0f32..10.0,
            r in 0.01f32..3.0,
            t in -100.0f32..100.0,
            on in prop::array::uniform3(-1.0f32..1.0),
            from in prop::array::uniform3(-100.0f32..100.0),
        ) {
            let motion = orbit(Vec3::from(c), ring);
            let bound = SweptRing::of(0, r, &motion).unwrap();
            let centre = motion.center_at(t);
            prop_assert!(bound.holds(centre, r));
            let on = Vec3::from(on);
            prop_assume!(on.length() > 1e-3);
            let p = centre + r * on.normalize();
            let o = Vec3::from(from);
            let d = (p - o).normalize();
            prop_assert!(bound.meets(o, d, (p - o).length()), "a segment ending on the sphere");
            prop_assert!(bound.meets(o, p - o, f32::INFINITY), "a ray through the sphere");
        }
    }
}
