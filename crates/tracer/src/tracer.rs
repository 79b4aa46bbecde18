//! The scene frozen at one instant, ready to trace, and its ray queries: the closest hit
//! ([`Tracer::intersect`]) and any hit ([`Tracer::occluded`]), as pbrt's `Intersect` and
//! `IntersectP`, each answered by the cheapest structure that is exact for the ray.
//!
//! Shading is in `shade.rs`, primary rays through screen bins in `primary.rs`, and the
//! services a second view uses in `second_view.rs`: all are `impl` blocks on this type's
//! data, which only this crate sees.

use glam::Vec3;

use crate::bvh::Bvh;
use crate::color::pack_rgb;
use crate::cones::Cones;
use crate::material::{Exponent, Material};
use crate::ray::{Ray, SPAWN_EPSILON};
use crate::scene::{Light, RenderSettings, Scene};
use crate::shadow::ShadowBins;
use crate::surface::{Hit, NO_OBJECT};

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
        self.lights.clear();
        self.lights.extend_from_slice(&scene.lights);
        self.settings = scene.render;
        self.background_rgb = pack_rgb(self.settings.background);
        self.bvh.build(&self.centers, &self.radii);
        // The largest offset `spawn_ray` can give a ray leaving any sphere, with room to spare.
        let reach = self.centers.iter().zip(&self.radii).map(|(c, r)| c.abs().max_element() + r).fold(0.0, f32::max);
        let spawn_offset = 2.0 * SPAWN_EPSILON * (1.0 + reach);
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

    /// Number of spheres.
    #[must_use]
    pub fn sphere_count(&self) -> usize {
        self.centers.len()
    }

    /// Closest hit in `(0, t_max)`, through the BVH.
    #[inline]
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Hit> {
        self.bvh.intersect(ray, t_max)
    }

    /// Whether anything blocks `ray` before `t_max` (any hit, early exit), through the BVH.
    #[inline]
    #[must_use]
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.bvh.occluded(ray, t_max)
    }

    /// Closest hit of `ray`, spawned (by [`crate::spawn_ray`]) from a point of sphere `from`
    /// with outward normal `n`. A ray leaving outwards cannot meet its own sphere again, so
    /// in small scenes it is tested against the direction cones to the other spheres; one
    /// going inwards (an eye inside a sphere) or a large scene goes through the BVH. The
    /// answer is the same either way.
    #[inline]
    #[must_use]
    pub(crate) fn intersect_from(&self, from: u32, n: Vec3, ray: &Ray) -> Option<Hit> {
        if ray.dir.dot(n) >= 0.0 && self.cones.is_built() {
            self.cones.intersect_from(from, ray, f32::INFINITY)
        } else {
            self.intersect(ray, f32::INFINITY)
        }
    }

    /// The shadow query: whether anything blocks `ray`, spawned (by [`crate::spawn_ray`])
    /// from the point `p` of sphere `from` (outward normal `n`) towards light `k`, with
    /// `t_max` the distance to it. Answered from the light's cube map of sphere lists,
    /// exactly as [`Tracer::occluded`] would; a cell that lists only `from` itself is
    /// skipped when the ray leaves outwards, as it cannot meet its own sphere again.
    #[inline]
    #[must_use]
    pub(crate) fn shadowed(&self, k: usize, from: u32, p: Vec3, n: Vec3, ray: &Ray, t_max: f32) -> bool {
        let own = if ray.dir.dot(n) >= 0.0 { from } else { NO_OBJECT };
        self.shadows
            .occluded(k, self.lights[k].position, p, ray, t_max, own)
            .unwrap_or_else(|| self.occluded(ray, t_max))
    }

    /// Hit parameter of `ray` against the one sphere `object`, ignoring all others: one
    /// sphere test, not a scene ray: the oracle of [`crate::SecondView::shade_on4`].
    #[cfg(test)]
    #[must_use]
    pub(crate) fn intersect_object(&self, ray: &Ray, object: u32) -> Option<f32> {
        self.bvh.intersect_one(ray, object)
    }
}
