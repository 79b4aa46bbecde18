//! The scene at one instant as plain structure-of-arrays data: where each sphere is, how
//! big, what it is made of; the lights and the render settings. Everything that traces
//! reads it; nothing in it knows how rays are answered (`accel/`) or what moves (`scene.rs`
//! and `reuse/`).

use glam::Vec3;

use crate::color::pack_rgb;
use crate::material::{Exponent, Material};
use crate::scene::{Light, Motion, RenderSettings, Scene};

/// The scene at one instant, a column per property (sphere k is entry k of each).
///
/// Materials are a palette: a molecule's million atoms share a dozen kinds' materials, so
/// each sphere keeps an index into it (20 bytes a sphere in all).
#[derive(Clone, Debug, Default)]
pub struct Snapshot {
    pub(crate) centers: Vec<Vec3>,
    pub(crate) radii: Vec<f32>,
    /// Each sphere's material, an index into `palette`.
    pub(crate) material_ids: Vec<u32>,
    /// The materials, and how each one's highlight exponent is evaluated.
    pub(crate) palette: Vec<Material>,
    pub(crate) exponents: Vec<Exponent>,
    pub(crate) lights: Vec<Light>,
    pub(crate) settings: RenderSettings,
    /// The background, encoded once per update.
    pub(crate) background_rgb: u32,
}

impl Snapshot {
    /// Heap bytes held (capacities).
    pub(crate) fn heap_bytes(&self) -> usize {
        use crate::stats::heap;
        heap(&self.centers)
            + heap(&self.radii)
            + heap(&self.material_ids)
            + heap(&self.palette)
            + heap(&self.exponents)
            + heap(&self.lights)
    }
    /// Re-resolves `scene` at time `t`, reusing the columns.
    pub(crate) fn update(&mut self, scene: &Scene, t: f32) {
        let n = scene.sphere_count();
        self.radii.clear();
        self.radii.reserve(n);
        self.centers.clear();
        self.centers.reserve(n);
        self.material_ids.clear();
        self.material_ids.reserve(n);
        self.palette.clear();
        for (k, s) in scene.spheres.iter().enumerate() {
            self.centers.push(s.motion.center_at(t));
            self.radii.push(s.radius);
            self.material_ids.push(k as u32);
            self.palette.push(s.material);
        }
        for s in &scene.structures {
            // The structure's kinds of atom, resolved when it was read, join the palette.
            let first = self.palette.len() as u32;
            self.palette.extend(s.kinds.iter().map(|kind| kind.material));
            for (&p, &id) in s.positions.iter().zip(&s.kind_ids) {
                self.centers.push(p);
                self.radii.push(s.kinds[usize::from(id)].radius);
                self.material_ids.push(first + u32::from(id));
            }
        }
        self.exponents.clear();
        self.exponents.extend(self.palette.iter().map(|m| Exponent::of(m.shininess)));
        self.lights.clear();
        self.lights.extend_from_slice(&scene.lights);
        self.settings = scene.render;
        self.background_rgb = pack_rgb(self.settings.background);
    }

    /// Takes the materials of `scene` (the scene of the last update, recoloured): the
    /// palette, the exponents and the atoms' material ids; nothing moves.
    pub(crate) fn recolor(&mut self, scene: &Scene) {
        debug_assert_eq!(self.centers.len(), scene.sphere_count(), "recoloured with another scene");
        self.palette.truncate(scene.spheres.len());
        let mut at = scene.spheres.len();
        for s in &scene.structures {
            let first = self.palette.len() as u32;
            self.palette.extend(s.kinds.iter().map(|kind| kind.material));
            for (id, &kind) in self.material_ids[at..at + s.kind_ids.len()].iter_mut().zip(&s.kind_ids) {
                *id = first + u32::from(kind);
            }
            at += s.kind_ids.len();
        }
        self.exponents.clear();
        self.exponents.extend(self.palette.iter().map(|m| Exponent::of(m.shininess)));
    }

    /// Moves the orbiting spheres of `scene`, the scene this was last updated from, to time
    /// `t`; returns whether any sphere moved (a still scene: none, at no cost).
    pub(crate) fn advance(&mut self, scene: &Scene, t: f32) -> bool {
        debug_assert_eq!(self.centers.len(), scene.sphere_count(), "advanced with another scene");
        let mut moved = false;
        for (k, s) in scene.spheres.iter().enumerate() {
            if let Motion::Orbit { .. } = s.motion {
                self.centers[k] = s.motion.center_at(t);
                moved = true;
            }
        }
        moved
    }

    /// Sphere `k`'s material.
    #[inline]
    #[must_use]
    pub fn material(&self, k: usize) -> &Material {
        &self.palette[self.material_ids[k] as usize]
    }

    /// How sphere `k`'s highlight exponent is evaluated.
    #[inline]
    #[must_use]
    pub(crate) fn exponent(&self, k: usize) -> Exponent {
        self.exponents[self.material_ids[k] as usize]
    }

    /// Each sphere's centre, by id.
    #[must_use]
    pub fn centers(&self) -> &[Vec3] {
        &self.centers
    }

    /// Each sphere's radius, by id.
    #[must_use]
    pub fn radii(&self) -> &[f32] {
        &self.radii
    }

    /// The lights.
    #[must_use]
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// The render settings (reflection depth, background, ambient).
    #[must_use]
    pub fn settings(&self) -> &RenderSettings {
        &self.settings
    }

    /// The smallest depth along `forward` from `origin` of any sphere point in front of
    /// that plane: min over spheres of (forward·(c − origin) − r), ignoring spheres wholly
    /// behind it. `None` if no sphere is in front. Negative when a sphere straddles the
    /// plane. With `origin` the head and `forward` its view axis, the nearest thing either
    /// eye can see is no nearer than this.
    #[must_use]
    pub fn nearest_depth(&self, origin: Vec3, forward: Vec3) -> Option<f32> {
        nearest_depth_of(&self.centers, &self.radii, origin, forward)
    }
}

/// [`Snapshot::nearest_depth`] of the spheres `(centers[k], radii[k])`: a scan of every
/// sphere ([`crate::Tracer::nearest_depth`] asks the BVH the same, bit for bit).
pub(crate) fn nearest_depth_of(centers: &[Vec3], radii: &[f32], origin: Vec3, forward: Vec3) -> Option<f32> {
    centers
        .iter()
        .zip(radii)
        .map(|(&c, &r)| (forward.dot(c - origin), r))
        .filter(|&(w, r)| w + r > 0.0)
        .map(|(w, r)| w - r)
        .reduce(f32::min)
}

#[cfg(test)]
mod tests {
    use glam::Vec3;

    use crate::testing::scene;
    use crate::tracer::Tracer;

    #[test]
    fn nearest_depth_is_the_nearest_sphere_point_ahead() {
        let mut scene = scene("seed.toml");
        scene.spheres.truncate(2);
        scene.spheres[0].motion = crate::scene::Motion::Static(Vec3::new(0.0, 0.0, 10.0));
        scene.spheres[0].radius = 1.0;
        scene.spheres[1].motion = crate::scene::Motion::Static(Vec3::new(3.0, 0.0, -4.0));
        scene.spheres[1].radius = 1.0;
        let tracer = Tracer::new(&scene, 0.0);
        assert_eq!(tracer.snapshot().nearest_depth(Vec3::ZERO, Vec3::Z), Some(9.0), "the sphere behind is ignored");
        assert_eq!(tracer.snapshot().nearest_depth(Vec3::new(0.0, 0.0, 10.5), Vec3::Z), Some(-1.5), "straddling");
        assert_eq!(tracer.snapshot().nearest_depth(Vec3::new(0.0, 0.0, 20.0), Vec3::Z), None, "nothing ahead");
    }
}
