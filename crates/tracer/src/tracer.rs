//! The scene at one instant, ready to trace: its plain data ([`Snapshot`]) and the
//! aggregate built over it (`accel/`), which answers its ray queries.
//!
//! Shading is in `shade.rs` (the plain path) and `wavefront.rs` (the batched one), both
//! `impl` blocks and functions over this type's data, which only this crate sees.

use std::sync::atomic::{AtomicU64, Ordering};

use glam::Vec3;

use crate::accel::{Aggregate, Origin};
use crate::camera::Eye;
use crate::ray::{spawn_bound, Ray};
use crate::scene::{RenderSettings, Scene};
use crate::snapshot::Snapshot;
use crate::surface::Hit;

/// A scene at one instant, laid out for tracing. Build it once and [`Tracer::update`] it each
/// frame: the buffers are reused, so a warm viewer does not allocate per frame.
#[derive(Clone, Debug, Default)]
pub struct Tracer {
    /// Where every sphere is now, and what it is made of.
    pub(crate) scene: Snapshot,
    /// The acceleration structures over `scene`.
    pub(crate) accel: Aggregate,
    /// Which scene this is, save for the time ([`Tracer::generation`]).
    generation: u64,
}

/// Heap bytes a [`Tracer`] holds, by part ([`Tracer::memory`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TracerMemory {
    /// The scene at the instant: centres, radii, material ids, palette.
    pub snapshot: usize,
    /// The BVH's nodes and leaves.
    pub bvh: usize,
    /// The lights' cube maps of sphere packets.
    pub light_maps: usize,
    /// The direction cones (small scenes only).
    pub cones: usize,
}

impl TracerMemory {
    /// All of it.
    #[must_use]
    pub fn total(&self) -> usize {
        self.snapshot + self.bvh + self.light_maps + self.cones
    }
}

/// The last generation given out; each [`Tracer::update`] takes the next.
static GENERATIONS: AtomicU64 = AtomicU64::new(0);

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
        self.scene.update(scene, t);
        self.build(scene);
        self.generation = GENERATIONS.fetch_add(1, Ordering::Relaxed) + 1;
    }

    /// Which scene this tracer holds, save for the time: a number that changes with every
    /// [`Tracer::update`] (and a new reflection depth) and with nothing else, so two frames
    /// of equal generations differ only in where the orbiting spheres are
    /// ([`Tracer::advance`]): what temporal reuse asks before it keeps a pixel. 0 for a
    /// tracer never updated.
    #[must_use]
    pub fn generation(&self) -> u64 {
        self.generation
    }

    /// The same scene (its spheres, structures, lights and settings as at the last
    /// [`Tracer::update`]) at time `t`: only the orbiting spheres move, and the structures
    /// are rebuilt only if one did. A still scene (a molecule) costs nothing, however large.
    pub fn advance(&mut self, scene: &Scene, t: f32) {
        if self.scene.advance(scene, t) {
            self.build(scene);
        }
    }

    /// Rebuilds the aggregate for the snapshot, with the spawn offset of `scene`'s reach.
    fn build(&mut self, scene: &Scene) {
        // How far a spawned ray's origin can lie off its sphere: sphere points and the eyes
        // lie within `reach` of the origin in every coordinate.
        let s = &self.scene;
        let spheres = s.centers.iter().zip(&s.radii).map(|(c, r)| c.abs().max_element() + r);
        let eyes = [Eye::Left, Eye::Right].map(|eye| scene.camera.eye_position(eye).abs().max_element());
        let spawn_offset = spawn_bound(spheres.chain(eyes).fold(0.0, f32::max));
        self.accel.build((&s.centers, &s.radii), &s.lights, spawn_offset);
    }

    /// The heap memory this tracer holds, by part: what the scale of a scene costs.
    #[must_use]
    pub fn memory(&self) -> TracerMemory {
        let [bvh, light_maps, cones] = self.accel.heap_bytes();
        TracerMemory { snapshot: self.scene.heap_bytes(), bvh, light_maps, cones }
    }

    /// The scene at this instant.
    #[must_use]
    pub fn snapshot(&self) -> &Snapshot {
        &self.scene
    }

    /// [`Snapshot::nearest_depth`], the same value, found through the BVH instead of a scan
    /// of every sphere: the smallest depth along `forward` from `origin` of any sphere point
    /// in front of that plane. A `forward` that is not a unit vector is scanned.
    #[must_use]
    pub fn nearest_depth(&self, origin: Vec3, forward: Vec3) -> Option<f32> {
        let spheres = (&self.scene.centers[..], &self.scene.radii[..]);
        if (forward.length() - 1.0).abs() > 1e-3 {
            return crate::snapshot::nearest_depth_of(spheres.0, spheres.1, origin, forward);
        }
        self.accel.nearest_depth(spheres, origin, forward)
    }

    /// The render settings in force (reflection depth, background, ambient).
    #[must_use]
    pub fn settings(&self) -> &RenderSettings {
        &self.scene.settings
    }

    /// Takes the next generation: the scene changed without a rebuild.
    pub(crate) fn bump_generation(&mut self) {
        self.generation = GENERATIONS.fetch_add(1, Ordering::Relaxed) + 1;
    }

    /// Overrides the reflection depth (the viewer's slider); a new depth is a new
    /// [`Tracer::generation`].
    pub fn set_max_depth(&mut self, depth: u32) {
        if depth != self.scene.settings.max_depth {
            self.scene.settings.max_depth = depth;
            self.generation = GENERATIONS.fetch_add(1, Ordering::Relaxed) + 1;
        }
    }

    /// Number of spheres.
    #[must_use]
    pub fn sphere_count(&self) -> usize {
        self.scene.centers.len()
    }

    /// The closest hit of `ray` in `(0, t_max)` (pbrt's `Intersect`), from anywhere.
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        self.accel.intersect(ray, t_max, Origin::Anywhere)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::{DVec3, Vec3};

    use crate::ray::leaves_outwards;

    use crate::accel::Origin;
    use crate::material::Material;
    use crate::scene::Light;
    use crate::surface::Hit;

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
        Scene { camera: Camera::default(), render: RenderSettings::default(), lights, spheres, structures: Vec::new() }
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
        let (c, r) = (tracer.scene.centers[0], tracer.scene.radii[0]);
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
    fn the_generation_changes_with_the_scene_not_with_the_time() {
        let scene = lone_sphere(Vec3::new(0.0, 0.0, 10.0), 1.0, 3);
        let mut tracer = Tracer::new(&scene, 0.0);
        let first = tracer.generation();
        assert!(first > 0, "an updated tracer has a generation");
        tracer.advance(&scene, 1.5);
        assert_eq!(tracer.generation(), first, "another instant of the same scene");
        tracer.set_max_depth(tracer.settings().max_depth);
        assert_eq!(tracer.generation(), first, "the same depth");
        tracer.set_max_depth(tracer.settings().max_depth + 1);
        let deeper = tracer.generation();
        assert_ne!(deeper, first, "another depth");
        tracer.update(&scene, 1.5);
        assert!(tracer.generation() != deeper && tracer.generation() != first, "an update, even of the same scene");
        assert_ne!(Tracer::new(&scene, 0.0).generation(), tracer.generation(), "another tracer");
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
                assert_eq!(tracer.accel.has_cones(), fillers < 64);
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
                            let from = Origin::Surface { sphere: 0, normal: n };
                            let hit = tracer.accel.intersect(&ray, f32::INFINITY, from);
                            assert_ne!(hit.map(|h| h.object), Some(0), "{c} {r}: self-hit at {p} along {dir}");
                            assert!(!tracer.accel.occluded(&ray, f32::INFINITY, from));
                            outward += 1;
                        }
                        for (k, light) in tracer.scene.lights.iter().enumerate() {
                            let (l, dist) = ((light.position - p).normalize(), light.position.distance(p));
                            if n.dot(l) > 0.0 {
                                let ray = spawn_ray(p, n, l);
                                assert!(!tracer.shadowed(k, 0, p, n, &ray, dist), "{c} {r}: shadowed at {p}");
                                let from = Origin::Surface { sphere: 0, normal: n };
                                assert!(!tracer.accel.occluded(&ray, dist, from), "{c} {r}: occluded at {p}");
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
                        let hit = tracer.accel.intersect(&ray, f32::INFINITY, Origin::Surface { sphere: 0, normal: n });
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
                structures: Vec::new(),
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
                    let from = Origin::Surface { sphere: 0, normal: n };
                    assert_eq!(tracer.accel.occluded(&ray, dist, from), shadowed, "{at}");
                    checked += 1;
                }
            }
        }
        assert_eq!(checked, 72);
    }
}
