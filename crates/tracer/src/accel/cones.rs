//! Direction cones between spheres: which spheres a ray leaving sphere k can reach, for
//! scenes small enough to list every pair.
//!
//! A reflection ray starts within r_k + ε of sphere k's centre (ε bounds how far a spawned
//! origin lies off its sphere: [`crate::spawn_ray`]'s offset plus the hit point's rounding,
//! a few hundred ULPs of the scene's extent). Moving its origin to that centre moves every point of the ray by at most
//! r_k + ε, so if the ray meets sphere j (centre at distance D, radius r_j), the same
//! direction from k's centre passes within R = r_j + r_k + ε of j's centre; for D > R that
//! needs an angle of at most asin(R/D) between the direction and the line of centres. Each
//! sphere keeps the others in SIMD packets of four together with those cones (axis and
//! cosine, padded); a ray tests a packet's spheres only when its direction falls in one of
//! the packet's cones, and then with the same lane arithmetic as the BVH, so the answer is
//! the BVH's. In the seed scene most mirror rays leave into the sky and skip every packet.
//! A sphere's own surface is not in its list: a ray leaving it outwards cannot meet it
//! again (see [`super::Aggregate::intersect`], which sends inward rays to the BVH).
//!
//! The lists grow as the square of the sphere count, so they are built only up to
//! [`MAX_SPHERES`]; larger scenes use the BVH.

#![expect(
    clippy::inline_always,
    reason = "a helper that is not inlined into the dispatched function loses its target features, and then every SIMD operation in it becomes a call"
)]

use fearless_simd::{f32x4, prelude::*, Simd};
use glam::Vec3;

use super::packet::{packet_ray, SpherePacket, LANES};
use crate::ray::Ray;
use crate::surface::Hit;

/// Largest scene for which the cones are built.
pub(crate) const MAX_SPHERES: usize = 64;
/// Widening of each cone's half-angle, in radians.
const ANGLE_MARGIN: f32 = 1e-4;

/// Four other spheres and the cones of directions towards them from one sphere.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
struct ConePacket {
    spheres: SpherePacket,
    axis: [[f32; LANES]; 3],
    /// Cosine of each cone's half-angle; −2 (always in) for a sphere that touches.
    cos: [f32; LANES],
}

/// For each sphere, the others behind their cones. Empty for scenes above [`MAX_SPHERES`].
#[derive(Clone, Debug, Default)]
pub(crate) struct Cones {
    /// Sphere k's packets are `packets[first[k]..first[k + 1]]`.
    first: Vec<u32>,
    packets: Vec<ConePacket>,
}

impl Cones {
    /// Heap bytes held (capacities).
    pub(crate) fn heap_bytes(&self) -> usize {
        use crate::stats::heap;
        heap(&self.first) + heap(&self.packets)
    }
    /// Rebuilds for the spheres `(centers[k], radii[k])`; `spawn_offset` bounds how far a
    /// spawned ray's origin lies off its sphere.
    pub(crate) fn build(&mut self, centers: &[Vec3], radii: &[f32], spawn_offset: f32) {
        self.first.clear();
        self.packets.clear();
        if centers.len() > MAX_SPHERES {
            return;
        }
        let empty = ConePacket { spheres: SpherePacket::EMPTY, axis: [[0.0; LANES]; 3], cos: [f32::INFINITY; LANES] };
        for (k, (&ck, &rk)) in centers.iter().zip(radii).enumerate() {
            self.first.push(self.packets.len() as u32);
            let others = (0..centers.len()).filter(|&j| j != k);
            let mut lane = LANES;
            for j in others {
                if lane == LANES {
                    self.packets.push(empty);
                    lane = 0;
                }
                let (cj, rj) = (centers[j], radii[j]);
                let to = cj - ck;
                let dist = to.length();
                let reach = (rj + rk + spawn_offset) * (1.0 + 1e-4);
                let (axis, cos) = if dist > reach && dist.is_finite() {
                    (to / dist, ((reach / dist).asin() + ANGLE_MARGIN).min(std::f32::consts::PI).cos())
                } else {
                    (Vec3::ZERO, -2.0)
                };
                let last = self.packets.len() - 1;
                let p = &mut self.packets[last];
                p.spheres.set(lane, j as u32, cj, rj);
                for a in 0..3 {
                    p.axis[a][lane] = axis[a];
                }
                p.cos[lane] = cos;
                lane += 1;
            }
        }
        self.first.push(self.packets.len() as u32);
    }

    /// Whether the cones were built (the scene is small enough).
    pub(crate) fn is_built(&self) -> bool {
        !self.first.is_empty()
    }

    /// Closest hit in `(0, t_max)` of `ray`, which leaves sphere `from` outwards (its origin
    /// within the spawn offset of that sphere's surface), among the other spheres.
    ///
    /// # Panics
    /// If the cones were not built ([`Cones::is_built`]).
    #[inline(always)]
    pub(crate) fn intersect_from<S: Simd>(&self, simd: S, from: u32, ray: &Ray, t_max: f32) -> Option<Hit> {
        let k = from as usize;
        let lanes = packet_ray(simd, ray);
        let d = lanes.1;
        let (mut t_best, mut best) = (t_max, None);
        for p in &self.packets[self.first[k] as usize..self.first[k + 1] as usize] {
            let axis = |a: usize| f32x4::from_slice(simd, &p.axis[a]);
            let along = d[0] * axis(0) + d[1] * axis(1) + d[2] * axis(2);
            if !along.simd_ge(f32x4::from_slice(simd, &p.cos)).any_true() {
                continue;
            }
            let t = p.spheres.hits(simd, lanes, t_best);
            for (lane, &t) in t.as_slice().iter().enumerate() {
                if t < t_best {
                    (t_best, best) = (t, Some(p.spheres.ids[lane]));
                }
            }
        }
        best.map(|object| Hit { t: t_best, object })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::{skipped, Origin};
    use crate::ray::{reflect, spawn_ray};
    use crate::scene::Scene;
    use crate::testing::scene;
    use crate::tracer::Tracer;

    /// Rays leaving points spread over every sphere, in directions over the outer
    /// hemisphere: the cones answer as the BVH does (leaving out the sphere left). Returns
    /// how many rays hit something.
    fn assert_same_as_bvh(scene: &Scene) -> usize {
        let tracer = Tracer::new(scene, 0.4);
        let mut hits = 0;
        for k in 0..tracer.sphere_count() {
            let (c, r) = (tracer.scene.centers[k], tracer.scene.radii[k]);
            for i in 0..60 {
                let z = 1.0 - 2.0 * (i as f32 + 0.5) / 60.0;
                let a = i as f32 * 2.399_963;
                let n = Vec3::new((1.0 - z * z).sqrt() * a.cos(), (1.0 - z * z).sqrt() * a.sin(), z);
                let p = c + r * n;
                for incoming in
                    [Vec3::Z, Vec3::new(0.3, -0.2, 1.0).normalize(), -n, (-n + n.any_orthonormal_vector()).normalize()]
                {
                    let ray = spawn_ray(p, n, reflect(incoming, n));
                    let want = tracer.accel.bvh.intersect(&ray, f32::INFINITY, skipped(k as u32, n, ray.dir));
                    let got =
                        tracer.accel.intersect(&ray, f32::INFINITY, Origin::Surface { sphere: k as u32, normal: n });
                    assert_eq!(
                        got.map(|h| (h.t.to_bits(), h.object)),
                        want.map(|h| (h.t.to_bits(), h.object)),
                        "sphere {k}, point {i}"
                    );
                    hits += usize::from(want.is_some());
                }
            }
        }
        hits
    }

    #[test]
    fn cones_answer_like_the_bvh() {
        for name in ["seed.toml", "window.toml"] {
            assert!(assert_same_as_bvh(&scene(name)) > 0, "{name}: some rays hit");
        }
        // The first 64 spheres of a crowded scene, and touching spheres.
        let mut many = scene("many.toml");
        many.spheres.truncate(MAX_SPHERES);
        assert!(assert_same_as_bvh(&many) > 0);
        many.spheres[1].motion = many.spheres[0].motion;
        assert_same_as_bvh(&many);
    }

    #[test]
    fn cones_are_built_only_for_small_scenes() {
        let tracer = Tracer::new(&scene("many.toml"), 0.0);
        assert!(tracer.sphere_count() > MAX_SPHERES);
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        assert!(!tracer.accel.has_cones());
        let from = Origin::Surface { sphere: 0, normal: Vec3::Z };
        assert_eq!(
            tracer.accel.intersect(&ray, f32::INFINITY, from),
            tracer.accel.bvh.intersect(&ray, f32::INFINITY, 0)
        );
    }
}
