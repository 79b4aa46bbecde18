//! The scene as plain data: camera, render settings, point lights, spheres and molecular
//! structures.
//!
//! Loaded by [`Scene::load`] from TOML (see `scene_file.rs` for the format and its checks)
//! or from a structure file (`structure.rs`). Spheres may revolve: an `orbit` sphere is at
//! `center + radius · (sin θ, 0, −cos θ)` with θ = phase + 2π·t/period. A structure's atoms
//! are spheres too, numbered after the scene's own, stored compactly (a position and a
//! one-byte kind each, the kinds resolved to radii and materials when read) as molecules
//! have millions of them.

use glam::Vec3;

use crate::camera::Camera;
use crate::cue::Cues;
use crate::material::Material;
use crate::sphere::Sphere;

/// Most lights a scene may have: each light takes one bit of [`crate::Surface::lights`].
pub const MAX_LIGHTS: usize = 32;
/// Largest allowed reflection depth.
pub const MAX_DEPTH_LIMIT: u32 = 16;

/// How a sphere's centre moves.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Motion {
    /// Fixed centre.
    Static(Vec3),
    /// Revolves in a horizontal circle.
    Orbit {
        /// Centre of the circle.
        center: Vec3,
        /// Radius of the circle, ≥ 0.
        radius: f32,
        /// Seconds per revolution, > 0.
        period_s: f32,
        /// Angle at t = 0, degrees.
        phase_deg: f32,
    },
}

impl Motion {
    /// Centre at time `t` seconds.
    #[must_use]
    pub fn center_at(&self, t: f32) -> Vec3 {
        match *self {
            Motion::Static(c) => c,
            Motion::Orbit { center, radius, period_s, phase_deg } => {
                // Reduce t modulo the period first so long-running viewers keep precision.
                let turns = (t / period_s).rem_euclid(1.0);
                let theta = phase_deg.to_radians() + std::f32::consts::TAU * turns;
                center + radius * Vec3::new(theta.sin(), 0.0, -theta.cos())
            }
        }
    }
}

/// A sphere as the scene describes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneSphere {
    /// Radius, > 0.
    pub radius: f32,
    /// Where its centre is over time.
    pub motion: Motion,
    /// Its material.
    pub material: Material,
}

/// A point light; no fall-off with distance.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// World position.
    pub position: Vec3,
    /// Linear intensity per channel, ≥ 0.
    pub color: Vec3,
}

/// Global render settings (`[render]`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    /// Reflection bounces; 0 = no reflections.
    pub max_depth: u32,
    /// Linear colour of rays that miss everything.
    pub background: Vec3,
    /// Global ambient term, multiplied by each surface's colour (and, with ambient
    /// occlusion on, by the open share at a primary hit).
    pub ambient: f32,
    /// Ambient occlusion, depth cueing and outlines (all off by default).
    pub cues: Cues,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self { max_depth: 3, background: Vec3::new(0.05, 0.05, 0.08), ambient: 0.1, cues: Cues::default() }
    }
}

/// A molecular structure placed in a scene: its atoms are still spheres. What an atom is
/// made of is resolved when the structure is read (`structure.rs`): each kind of atom (an
/// element, there) has its radius and material, and each atom keeps a one-byte index into
/// them, as molecules have millions of atoms and a dozen kinds.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Structure {
    /// Where it was read from, as given.
    pub source: String,
    /// Atom centres, scene space (the file's coordinates mapped to left-handed space, then
    /// placed).
    pub positions: Vec<Vec3>,
    /// Each atom's kind, an index into [`Structure::kinds`].
    pub kind_ids: Vec<u8>,
    /// The kinds of atom, in the order their first atom comes (at most 256).
    pub kinds: Vec<AtomKind>,
    /// What the file says of each atom (chain, residue, names, B-factor…), shared between
    /// the scene's copies; `None` for atoms made in code.
    pub records: Option<Records>,
    /// What was added to every atom's position when it was placed (scene units).
    pub offset: Vec3,
    /// With atoms hidden ([`Structure::hidden`]), each atom's index into the records;
    /// `None`: atom k is record k.
    pub shown: Option<Vec<u32>>,
}

/// A structure's [`molecule::AtomRecords`], shared: copies of a scene point to one, and two
/// are equal when they are the same one.
#[derive(Clone, Debug)]
pub struct Records(pub std::sync::Arc<molecule::AtomRecords>);

impl PartialEq for Records {
    fn eq(&self, other: &Self) -> bool {
        std::sync::Arc::ptr_eq(&self.0, &other.0)
    }
}

impl Structure {
    /// All the file says of atom `k` of this structure, with the file's own coordinates;
    /// `None` past its atoms, or for atoms made in code.
    #[must_use]
    pub fn atom(&self, k: usize) -> Option<molecule::Atom<'_>> {
        let records = &self.records.as_ref()?.0;
        records.atom(self.record_index(k), *self.positions.get(k)? - self.offset)
    }
}

/// A kind of atom of a [`Structure`]: the sphere's radius and material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AtomKind {
    /// The sphere's radius, > 0.
    pub radius: f32,
    /// Its material.
    pub material: Material,
}

impl Structure {
    /// Atom `k`'s kind.
    ///
    /// # Panics
    /// If `k` is not below the number of atoms.
    #[must_use]
    pub fn kind(&self, k: usize) -> &AtomKind {
        &self.kinds[usize::from(self.kind_ids[k])]
    }

    /// Each atom as a sphere: its centre and radius.
    pub fn atom_spheres(&self) -> impl Iterator<Item = (Vec3, f32)> + Clone + '_ {
        self.positions.iter().zip(&self.kind_ids).map(|(&p, &id)| (p, self.kinds[usize::from(id)].radius))
    }

    /// A sphere around every atom's sphere, centred on their bounding box (see
    /// [`molecule::enclosing_sphere`]); `None` without atoms.
    #[must_use]
    pub fn bounding_sphere(&self) -> Option<molecule::Sphere> {
        molecule::enclosing_sphere(self.atom_spheres())
    }
}

/// A whole scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Scene {
    /// The head pose and stereo parameters.
    pub camera: Camera,
    /// Global settings.
    pub render: RenderSettings,
    /// Point lights (at most [`MAX_LIGHTS`]; none means ambient only).
    pub lights: Vec<Light>,
    /// Spheres; their index is the object id in the visible-surface record.
    pub spheres: Vec<SceneSphere>,
    /// Molecular structures; their atoms are the spheres after [`Scene::spheres`], in order.
    pub structures: Vec<Structure>,
}

impl Scene {
    /// How many spheres the scene has: its own and every structure's atoms.
    #[must_use]
    pub fn sphere_count(&self) -> usize {
        self.spheres.len() + self.structures.iter().map(|s| s.positions.len()).sum::<usize>()
    }

    /// Geometry of sphere `k` at time `t` (an atom's for `k` past the scene's own spheres).
    ///
    /// # Panics
    /// If `k` is not below [`Scene::sphere_count`].
    #[must_use]
    pub fn sphere_at(&self, k: usize, t: f32) -> Sphere {
        if let Some(s) = self.spheres.get(k) {
            return Sphere { center: s.motion.center_at(t), radius: s.radius };
        }
        let mut k = k - self.spheres.len();
        for s in &self.structures {
            if let (Some(&center), Some(&id)) = (s.positions.get(k), s.kind_ids.get(k)) {
                return Sphere { center, radius: s.kinds[usize::from(id)].radius };
            }
            k -= s.positions.len();
        }
        panic!("sphere {k} past the scene's {} spheres", self.sphere_count());
    }

    /// Whether any sphere moves (the viewer only animates such scenes).
    #[must_use]
    pub fn is_animated(&self) -> bool {
        self.spheres.iter().any(|s| matches!(s.motion, Motion::Orbit { .. }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orbit_follows_the_documented_parametrisation() {
        let m = Motion::Orbit { center: Vec3::new(0.0, 1.2, 15.0), radius: 2.0, period_s: 8.0, phase_deg: 0.0 };
        // θ = 0: centre + r·(0, 0, −1); a quarter period later θ = 90°: centre + r·(1, 0, 0).
        assert!((m.center_at(0.0) - Vec3::new(0.0, 1.2, 13.0)).length() < 1e-5);
        assert!((m.center_at(2.0) - Vec3::new(2.0, 1.2, 15.0)).length() < 1e-5);
        assert!((m.center_at(8.0) - m.center_at(0.0)).length() < 1e-5);
        let phased = Motion::Orbit { center: Vec3::ZERO, radius: 1.0, period_s: 8.0, phase_deg: 90.0 };
        assert!((phased.center_at(0.0) - Vec3::X).length() < 1e-6);
    }
}
