//! The scene frozen at one instant, ready to trace, and its ray queries: the closest hit
//! ([`Tracer::intersect`]) and any hit ([`Tracer::occluded`]), as pbrt's `Intersect` and
//! `IntersectP`, each answered by the cheapest structure that is exact for the ray.
//!
//! Shading is in `shade.rs`, primary rays through screen bins in `primary.rs`, and the
//! services a second view uses in `second_view.rs`: all are `impl` blocks on this type's
//! data, which only this crate sees.

use glam::Vec3;

use crate::bvh::Bvh;
use crate::camera::Eye;
use crate::color::pack_rgb;
use crate::cones::Cones;
use crate::material::{Exponent, Material};
use crate::ray::{leaves_outwards, spawn_bound, Ray};
use crate::scene::{Light, RenderSettings, Scene};
use crate::shadow::{Cell, ShadowBins};
use crate::surface::{Hit, NO_OBJECT};
use crate::swept::{Arc, SweptRing, Touch};

/// A scene at one instant, laid out for tracing. Build it once and [`Tracer::update`] it each
/// frame: the buffers are reused, so a warm viewer does not allocate per frame.
#[derive(Clone, Debug, Default)]
pub struct Tracer {
    pub(crate) centers: Vec<Vec3>,
    pub(crate) radii: Vec<f32>,
    pub(crate) materials: Vec<Material>,
    /// How each material's highlight exponent is evaluated.
    pub(crate) exponents: Vec<Exponent>,
    pub(crate) lights: Vec<Light>,
    pub(crate) settings: RenderSettings,
    /// The background, encoded once per update.
    pub(crate) background_rgb: u32,
    bvh: Bvh,
    shadows: ShadowBins,
    pub(crate) cones: Cones,
    /// The swept volume of each moving sphere (`swept.rs`): where it can be at any time.
    rings: Vec<SweptRing>,
}

impl Tracer {
    /// The scene at time `t` seconds.
    #[must_use]
    pub fn new(scene: &Scene, t: f32) -> Self {
        let mut tracer = Self::default();
        tracer.update(scene, t);
        tracer
    }

    /// Re-resolves the scene at time `t`, reusing this tracer's buffers.
    pub fn update(&mut self, scene: &Scene, t: f32) {
        self.centers.clear();
        self.radii.clear();
        self.materials.clear();
        self.exponents.clear();
        for (k, s) in scene.spheres.iter().enumerate() {
            let g = scene.sphere_at(k, t);
            self.centers.push(g.center);
            self.radii.push(g.radius);
            self.materials.push(s.material);
            self.exponents.push(Exponent::of(s.material.shininess));
        }
        self.rings.clear();
        for (k, s) in scene.spheres.iter().enumerate() {
            if let Some(ring) = SweptRing::of(k as u32, s.radius, &s.motion) {
                // The invariant temporal reuse rests on: a moving sphere never leaves its
                // bound. (Checked here in debug builds, and by the tests of `swept.rs`.)
                debug_assert!(
                    ring.holds(self.centers[k], self.radii[k]),
                    "sphere {k} at {} lies outside its swept volume {ring:?}",
                    self.centers[k]
                );
                self.rings.push(ring);
            }
        }
        self.lights.clear();
        self.lights.extend_from_slice(&scene.lights);
        self.settings = scene.render;
        self.background_rgb = pack_rgb(self.settings.background);
        self.bvh.build(&self.centers, &self.radii);
        // How far a spawned ray's origin can lie off its sphere: sphere points and the eyes
        // lie within `reach` of the origin in every coordinate.
        let spheres = self.centers.iter().zip(&self.radii).map(|(c, r)| c.abs().max_element() + r);
        let eyes = [Eye::Left, Eye::Right].map(|eye| scene.camera.eye_position(eye).abs().max_element());
        let spawn_offset = spawn_bound(spheres.chain(eyes).fold(0.0, f32::max));
        self.shadows.build(&self.centers, &self.radii, &self.lights, spawn_offset);
        self.cones.build(&self.centers, &self.radii, spawn_offset);
    }

    /// The render settings in force (reflection depth, background, ambient).
    #[must_use]
    pub fn settings(&self) -> &RenderSettings {
        &self.settings
    }

    /// Overrides the reflection depth (the viewer's slider).
    pub fn set_max_depth(&mut self, depth: u32) {
        self.settings.max_depth = depth;
    }

    /// The swept volumes of the moving spheres (none for a still scene).
    #[must_use]
    pub fn swept(&self) -> &[SweptRing] {
        &self.rings
    }

    /// Where the segment `o + s·d`, 0 ≤ s ≤ `s_max`, meets the swept volumes of the moving
    /// spheres ([`Touch::NONE`] if nowhere: then it meets the same spheres at every
    /// instant; see `swept.rs`).
    #[inline]
    #[must_use]
    pub fn touch_moving(&self, o: Vec3, d: Vec3, s_max: f32) -> Touch {
        let mut touch = Touch::NONE;
        for (k, ring) in self.rings.iter().enumerate() {
            if let Some(arc) = ring.touch(o, d, s_max) {
                touch = touch.union(Touch { ring: k as u32, arc });
            }
        }
        touch
    }

    /// The wedge of its ring that each moving sphere fills now, in the order of
    /// [`Tracer::swept`], into `out` (cleared first).
    pub fn wedges(&self, out: &mut Vec<Arc>) {
        out.clear();
        out.extend(self.rings.iter().map(|ring| {
            let k = ring.object as usize;
            ring.wedge(self.centers[k], self.radii[k])
        }));
    }

    /// Writes into `out` (cleared first) everything of this tracer that a frame depends on
    /// except where the moving spheres are: the still spheres' centres, every radius,
    /// material and swept volume, the lights and the render settings, as bits. Two tracers
    /// of one scene at two instants give the same words; change anything else and they
    /// differ. Nothing is allocated once `out` has grown to size.
    pub fn fingerprint(&self, out: &mut Vec<u32>) {
        out.clear();
        let v3 = |out: &mut Vec<u32>, v: Vec3| out.extend(v.to_array().map(f32::to_bits));
        out.push(self.centers.len() as u32);
        let mut rings = self.rings.iter().peekable();
        for (k, (&c, m)) in self.centers.iter().zip(&self.materials).enumerate() {
            match rings.next_if(|ring| ring.object as usize == k) {
                Some(ring) => {
                    v3(out, ring.center);
                    out.extend([ring.half_height, ring.inner, ring.outer].map(f32::to_bits));
                }
                None => v3(out, c),
            }
            out.push(self.radii[k].to_bits());
            v3(out, m.color);
            out.extend([m.diffuse, m.specular, m.shininess, m.reflectivity].map(f32::to_bits));
        }
        out.push(self.lights.len() as u32);
        for light in &self.lights {
            v3(out, light.position);
            v3(out, light.color);
        }
        out.push(self.settings.max_depth);
        v3(out, self.settings.background);
        out.push(self.settings.ambient.to_bits());
    }

    /// Number of spheres.
    #[must_use]
    pub fn sphere_count(&self) -> usize {
        self.centers.len()
    }

    /// Closest hit in `(0, t_max)`, through the BVH.
    #[inline]
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        self.bvh.intersect(ray, t_max, NO_OBJECT)
    }

    /// Whether anything blocks `ray` before `t_max` (any hit, early exit), through the BVH.
    #[inline]
    #[must_use]
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.bvh.occluded(ray, t_max, NO_OBJECT)
    }

    /// The sphere that the queries of a ray spawned (by [`crate::spawn_ray`]) from sphere
    /// `from`, with outward normal `n` there, leave out: `from` itself when the ray leaves
    /// outwards, as a sphere is convex and the ray cannot meet it again; none
    /// ([`NO_OBJECT`]) when it goes in. The one rule for every structure (BVH, cones, cube
    /// maps), so that the spawn offset never has to clear the ray's own sphere outwards.
    #[inline]
    #[must_use]
    pub(crate) fn skipped(from: u32, n: Vec3, dir: Vec3) -> u32 {
        if leaves_outwards(n, dir) {
            from
        } else {
            NO_OBJECT
        }
    }

    /// Closest hit in `(0, t_max)` among the spheres other than `skip`, through the BVH.
    #[inline]
    #[must_use]
    pub(crate) fn intersect_skipping(&self, ray: &Ray, t_max: f32, skip: u32) -> Option<Hit> {
        self.bvh.intersect(ray, t_max, skip)
    }

    /// Whether a sphere other than `skip` blocks `ray` before `t_max`, through the BVH.
    #[inline]
    #[must_use]
    pub(crate) fn occluded_skipping(&self, ray: &Ray, t_max: f32, skip: u32) -> bool {
        self.bvh.occluded(ray, t_max, skip)
    }

    /// Closest hit of `ray`, spawned (by [`crate::spawn_ray`]) from a point of sphere `from`
    /// with outward normal `n`, leaving out the sphere [`Tracer::skipped`] names. A ray
    /// leaving outwards is tested in small scenes against the direction cones to the other
    /// spheres; one going inwards (an eye inside a sphere) or one in a large scene goes
    /// through the BVH. The answer is the same either way.
    #[inline]
    #[must_use]
    pub(crate) fn intersect_from(&self, from: u32, n: Vec3, ray: &Ray) -> Option<Hit> {
        let skip = Self::skipped(from, n, ray.dir);
        if skip != NO_OBJECT && self.cones.is_built() {
            self.cones.intersect_from(from, ray, f32::INFINITY)
        } else {
            self.intersect_skipping(ray, f32::INFINITY, skip)
        }
    }

    /// [`Tracer::intersect_from`] inside a lane kernel dispatched at `simd`'s level: the
    /// BVH's traversal is inlined into it, with its target features.
    #[expect(clippy::inline_always, reason = "inlined into the dispatched lane kernel, whose target features it needs")]
    #[inline(always)]
    #[must_use]
    pub(crate) fn intersect_from_in<S: fearless_simd::Simd>(
        &self,
        simd: S,
        from: u32,
        n: Vec3,
        ray: &Ray,
    ) -> Option<Hit> {
        let skip = Self::skipped(from, n, ray.dir);
        if skip != NO_OBJECT && self.cones.is_built() {
            self.cones.intersect_from(from, ray, f32::INFINITY)
        } else {
            self.bvh.intersect_in(simd, ray, f32::INFINITY, skip)
        }
    }

    /// The shadow query: whether anything blocks `ray`, spawned (by [`crate::spawn_ray`])
    /// from the point `p` of sphere `from` (outward normal `n`) towards light `k`, with
    /// `t_max` the distance to it, leaving out the sphere [`Tracer::skipped`] names.
    /// Answered from the light's cube map of sphere lists, exactly as the BVH would.
    #[inline]
    #[must_use]
    pub(crate) fn shadowed(&self, k: usize, from: u32, p: Vec3, n: Vec3, ray: &Ray, t_max: f32) -> bool {
        self.shadowed_in(self.shadow_cell(k, p), Self::skipped(from, n, ray.dir), ray, t_max)
    }

    /// The first half of [`Tracer::shadowed`]: the cell of light `k`'s cube map that the
    /// shadow ray from `p` looks up (`None` if the bins cannot answer it). A batch of shadow
    /// rays looks up all its cells first, so their cache misses overlap.
    #[inline]
    #[must_use]
    pub(crate) fn shadow_cell(&self, k: usize, p: Vec3) -> Option<Cell> {
        self.shadows.cell(k, self.lights[k].position, p)
    }

    /// Whether the shadow ray of `cell`, leaving the sphere `skip` ([`Tracer::skipped`]),
    /// has nothing to test: no sphere in the cell but `skip` (see [`ShadowBins::clear`]).
    #[inline]
    #[must_use]
    pub(crate) fn shadow_clear(&self, cell: Cell, skip: u32) -> bool {
        self.shadows.clear(cell, skip)
    }

    /// The second half of [`Tracer::shadowed`], given its `cell` and the sphere `skip` the
    /// ray leaves ([`Tracer::skipped`]).
    #[inline]
    #[must_use]
    pub(crate) fn shadowed_in(&self, cell: Option<Cell>, skip: u32, ray: &Ray, t_max: f32) -> bool {
        match cell {
            Some(cell) => self.shadows.blocks(cell, ray, t_max, skip),
            None => self.occluded_skipping(ray, t_max, skip),
        }
    }

    /// Hit parameter of `ray` against the one sphere `object`, ignoring all others: one
    /// sphere test, not a scene ray: the oracle of [`crate::SecondView::shade_row`].
    #[cfg(test)]
    #[must_use]
    pub(crate) fn intersect_object(&self, ray: &Ray, object: u32) -> Option<f32> {
        self.bvh.intersect_one(ray, object)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    use crate::camera::Camera;
    use crate::ray::{reflect, spawn_ray};
    use crate::scene::{Motion, SceneSphere};
    use crate::sphere::intersect_sphere;

    /// A scene of one sphere (c, r), sphere 0, plus `fillers` tiny spheres in a tight cluster
    /// 10³ radii away (so that more than 64 spheres turn the cones off) and four lights 20
    /// radii away in tetrahedral directions.
    fn lone_sphere(c: Vec3, r: f32, fillers: usize) -> Scene {
        let material = Material::default();
        let far = c + Vec3::new(0.6, 0.0, 0.8) * (1e3 * r);
        let filler = |k: usize| SceneSphere {
            radius: 1e-3 * r,
            motion: Motion::Static(far + Vec3::X * (k as f32 * 0.01 * r)),
            material,
        };
        let mut spheres = vec![SceneSphere { radius: r, motion: Motion::Static(c), material }];
        spheres.extend((0..fillers).map(filler));
        let lights = [[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, -1.0, 1.0]]
            .map(|v| Light { position: c + Vec3::from(v).normalize() * (20.0 * r), color: Vec3::ONE })
            .to_vec();
        Scene { camera: Camera::default(), render: RenderSettings::default(), lights, spheres }
    }

    /// 500 unit normals spread over the sphere (a Fibonacci lattice).
    fn lattice() -> impl Iterator<Item = Vec3> {
        (0..500).map(|k| {
            let a = k as f32 * 0.618_034 * std::f32::consts::TAU;
            let z = 1.0 - 2.0 * ((k as f32 + 0.5) / 500.0);
            let r = (1.0 - z * z).sqrt();
            Vec3::new(r * a.cos(), r * a.sin(), z)
        })
    }

    /// Hits on sphere 0 of `tracer` (centre c, radius r) of rays from `o` aimed at the
    /// lattice points, as shading finds them: p = o + t·d and n = normalize(p − c).
    fn hits_from(tracer: &Tracer, o: Vec3) -> impl Iterator<Item = (Vec3, Vec3, Vec3)> + '_ {
        let (c, r) = (tracer.centers[0], tracer.radii[0]);
        lattice().filter_map(move |m| {
            let ray = Ray::new(o, (c + r * m - o).normalize());
            let hit = tracer.intersect(&ray, f32::INFINITY)?;
            (hit.object == 0).then(|| {
                let p = ray.at(hit.t);
                (p, (p - c).normalize(), ray.dir)
            })
        })
    }

    #[test]
    fn a_ray_spawned_from_a_hit_never_meets_its_sphere_again() {
        let spheres = [
            (Vec3::new(3.0, -2.0, 40.0), 2.5),
            (Vec3::new(1000.0, -20.0, 30.0), 2.5),
            (Vec3::new(-300.0, 1e4, 2000.0), 2.5),
            (Vec3::new(3.0, -2.0, 40.0), 1e-3),
            (Vec3::new(1000.0, 1000.0, 1000.0), 1e-2),
            (Vec3::ZERO, 50.0),
        ];
        let (mut outward, mut inward) = (0, 0);
        for (c, r) in spheres {
            // Through the cones and the BVH (a small scene), and through the BVH alone.
            for fillers in [3, 70] {
                let tracer = Tracer::new(&lone_sphere(c, r, fillers), 0.0);
                assert_eq!(tracer.cones.is_built(), fillers < 64);
                // Hits seen from outside, near and from far away (a far origin leaves p
                // far more than the spawn offset off the surface: only the skip holds).
                let eyes = [c + Vec3::new(0.0, 0.6, -0.8) * (3.0 * r), c + Vec3::new(-0.8, 0.0, 0.6) * 1e5];
                for o in eyes.into_iter().filter(|&o| (o - c).length() > r) {
                    for (p, n, d) in hits_from(&tracer, o) {
                        let tangent = n.any_orthonormal_vector();
                        for dir in [reflect(d, n), n, (tangent + 0.01 * n).normalize()] {
                            // A mirror ray at a grazing hit may go in, to rounding: that
                            // is the inward case, below.
                            if !leaves_outwards(n, dir) {
                                continue;
                            }
                            let ray = spawn_ray(p, n, dir);
                            let hit = tracer.intersect_from(0, n, &ray);
                            assert_ne!(hit.map(|h| h.object), Some(0), "{c} {r}: self-hit at {p} along {dir}");
                            assert!(!tracer.occluded_skipping(&ray, f32::INFINITY, Tracer::skipped(0, n, dir)));
                            outward += 1;
                        }
                        for (k, light) in tracer.lights.iter().enumerate() {
                            let (l, dist) = ((light.position - p).normalize(), light.position.distance(p));
                            if n.dot(l) > 0.0 {
                                let ray = spawn_ray(p, n, l);
                                assert!(!tracer.shadowed(k, 0, p, n, &ray, dist), "{c} {r}: shadowed at {p}");
                                assert!(!tracer.occluded_skipping(&ray, dist, 0), "{c} {r}: occluded at {p}");
                            }
                        }
                    }
                }
                // Hits seen from inside (an eye in the sphere), where mirror rays go inwards
                // and meet the far side. Not for the tiny spheres (see `spawn_ray`).
                if r < 0.1 {
                    continue;
                }
                for (p, n, d) in hits_from(&tracer, c + Vec3::new(0.3, -0.4, 0.0) * r) {
                    for dir in [reflect(d, n), -n] {
                        let ray = spawn_ray(p, n, dir);
                        let far = intersect_sphere(&ray, c, r, f32::INFINITY).filter(|&t| t > 0.5 * r * dir.dot(-n));
                        assert!(far.is_some(), "{c} {r}: the far side is at least r·|d·n| away");
                        let hit = tracer.intersect_from(0, n, &ray);
                        assert_eq!(hit, far.map(|t| Hit { t, object: 0 }), "{c} {r}: from {p} along {dir}");
                        inward += 1;
                    }
                }
            }
        }
        assert!(outward > 10_000 && inward > 2_000, "{outward} rays out, {inward} in");
    }

    /// Where the generator of the tangent cone from `light` to the sphere (c, r), at angle
    /// `alpha` from the cone's axis and azimuth `phi` around it, first meets the sphere
    /// (`rc`, `rr`) beyond the tangent points, in double precision.
    fn on_cone(light: DVec3, (c, r): (DVec3, f64), (rc, rr): (DVec3, f64), alpha: f64, phi: f64) -> DVec3 {
        let axis = (c - light).normalize();
        let (e1, e2) = axis.any_orthonormal_pair();
        let g = alpha.cos() * axis + alpha.sin() * (phi.cos() * e1 + phi.sin() * e2);
        let oc = light - rc;
        let b = oc.dot(g);
        let s = -b - (b * b - oc.length_squared() + rr * rr).sqrt();
        assert!(s > (c - light).length() + r, "the receiver lies beyond the occluder");
        light + s * g
    }

    #[test]
    fn a_cast_shadow_edge_lands_where_the_tangent_cone_puts_it() {
        // A light, an occluder (sphere 1) and a receiver (sphere 0) below it: the shadow's
        // edge on the receiver is where the tangent cone from the light to the occluder
        // meets it. Light from above, from 43° to the receiver's normal, and that scene far
        // from the origin.
        let receiver = (Vec3::new(0.0, -10.0, 30.0), 10.0);
        let overhead = (Vec3::new(0.0, 12.0, 30.0), (Vec3::new(0.0, 4.0, 30.0), 1.0));
        let oblique = (Vec3::new(8.0, 12.0, 30.0), (Vec3::new(2.0, 4.0, 30.0), 1.0));
        let far = Vec3::new(1000.0, -500.0, 2000.0);
        let far_oblique = (oblique.0 + far, (oblique.1 .0 + far, 1.0));
        let mut checked = 0;
        for (k, (light, occluder)) in [overhead, oblique, far_oblique].into_iter().enumerate() {
            let receiver = if k == 2 { (receiver.0 + far, receiver.1) } else { receiver };
            let material = Material::default();
            let sphere = |(c, r): (Vec3, f32)| SceneSphere { radius: r, motion: Motion::Static(c), material };
            let scene = Scene {
                camera: Camera::default(),
                render: RenderSettings::default(),
                lights: vec![Light { position: light, color: Vec3::ONE }],
                spheres: vec![sphere(receiver), sphere(occluder)],
            };
            let tracer = Tracer::new(&scene, 0.0);
            // The scene's scale: its largest coordinate.
            let scale = [light.abs().max_element(), receiver.0.abs().max_element() + receiver.1]
                .into_iter()
                .fold(occluder.0.abs().max_element() + occluder.1, f32::max);
            let (l, o, rc) = (light.as_dvec3(), (occluder.0.as_dvec3(), f64::from(occluder.1)), receiver);
            let rc = (rc.0.as_dvec3(), f64::from(rc.1));
            let alpha = (o.1 / (o.0 - l).length()).asin();
            for phi in (0..12).map(|i| f64::from(i) * std::f64::consts::TAU / 12.0) {
                // Two points on the receiver 10⁻⁵ of the scale apart, on either side of the
                // edge: just inside the cone and just outside it.
                let step = |da: f64| on_cone(l, o, rc, alpha + da, phi);
                let probe = 1e-7;
                let da = probe * 1e-5 * f64::from(scale) / (step(probe) - step(-probe)).length();
                for (point, shadowed) in [(step(-da), true), (step(da), false)] {
                    let p = point.as_vec3();
                    // As shading does: the normal, the light's direction and distance.
                    let n = (p - receiver.0).normalize();
                    let v = light - p;
                    let dist = v.length();
                    let ray = spawn_ray(p, n, v * dist.recip());
                    assert!(n.dot(ray.dir) > 0.2, "the receiver faces the light at {p}");
                    let at = format!("scene {k}, azimuth {phi:.2}, {p} (edge at {})", step(0.0));
                    assert_eq!(tracer.shadowed(0, 0, p, n, &ray, dist), shadowed, "{at}");
                    assert_eq!(tracer.occluded_skipping(&ray, dist, 0), shadowed, "{at}");
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 72);
    }
}
