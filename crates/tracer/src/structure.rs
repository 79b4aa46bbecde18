//! A scene made from a molecular structure file (`molecule` reads PDB, mmCIF, GRO and XYZ):
//! every atom a sphere, and a camera, lights and settings chosen so that the stereo pair is
//! framed and comfortable at once.
//!
//! **Framing.** The structure's bounding sphere (centre c, radius R, atom radii included)
//! fills the view: the head looks along +z at c from the distance D at which the sphere
//! touches the top and bottom of a 4:3 eye (the default window's) with 5 % to spare.
//!
//! **The stereo rule** (the stereographers' 1/30 rule): the IPD is 1/30 of the distance from
//! the eyes to the nearest atom, D − R, and the zero-parallax window passes through c
//! (d = D), so the front half of the structure stands out of the screen and the back half
//! behind it. The largest parallax is then e·R/(D − R) = R/30 in front and about R/60
//! behind, 1.3 % and 0.7 % of the window's width at the default field of view: well inside
//! the 2–3 % comfort limit of stereo displays.
//!
//! **Lights.** A key light above, left of and in front of the structure and a dimmer fill
//! light from the right, both on the viewer's side, so the side facing the eyes is lit and
//! shadows fall behind.
//!
//! **Cues.** Ambient occlusion (8 rays a hit, within max(8, R/10)), Exp2 depth cueing from
//! the sphere's front and 1-pixel outlines are on (`cue::sized`; `docs/design/cues.md`).

use std::path::Path;
use std::sync::Arc;

use glam::Vec3;

use crate::camera::Camera;
use crate::error::SceneError;
use crate::material::Material;
use crate::scene::{AtomKind, Light, Records, RenderSettings, Scene, Structure};

/// The look of atoms read from a structure file: matte with a soft highlight, no mirror.
pub const ATOM_MATERIAL: Material =
    Material { color: Vec3::ONE, diffuse: 0.75, specular: 0.3, shininess: 40.0, reflectivity: 0.0 };

/// The radius scale of a structure file opened as a scene: van der Waals spheres.
pub const DEFAULT_RADIUS_SCALE: f32 = 1.0;

/// How a structure is read and drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StructureOptions {
    /// Atom radius = van der Waals radius × this.
    pub radius_scale: f32,
    /// Build the first biological assembly the file lists.
    pub assembly: bool,
    /// Added to every atom's position (scene units, Å).
    pub offset: Vec3,
    /// The atoms' material (its colour is the element's unless `color` is set).
    pub material: Material,
    /// One colour for every atom.
    pub color: Option<Vec3>,
}

impl Default for StructureOptions {
    fn default() -> Self {
        Self {
            radius_scale: DEFAULT_RADIUS_SCALE,
            assembly: false,
            offset: Vec3::ZERO,
            material: ATOM_MATERIAL,
            color: None,
        }
    }
}

/// Reads the structure file at `path` (bounded: see the `molecule` crate) into a
/// [`Structure`], its atoms placed as `options` say and each element resolved to a kind of
/// atom (its van der Waals radius × the scale, its Jmol colour unless `options` give one).
pub fn read_structure(path: &Path, options: &StructureOptions) -> Result<Structure, SceneError> {
    let read = molecule::ReadOptions { assembly: options.assembly, ..molecule::ReadOptions::default() };
    let molecule = molecule::read(path, &read)?;
    let source = molecule.source().to_owned();
    let (mut positions, records) = molecule.into_parts();
    if options.offset != Vec3::ZERO {
        for p in &mut positions {
            *p += options.offset;
        }
    }
    let (kind_ids, kinds) = resolve(records.elements(), options);
    let records = Some(Records(Arc::new(records)));
    Ok(Structure { source, positions, kind_ids, kinds, records, offset: options.offset, shown: None })
}

/// Each atom's kind (an index into the kinds), and the kinds: one per element present, in
/// the order its first atom comes.
fn resolve(elements: &[molecule::Element], options: &StructureOptions) -> (Vec<u8>, Vec<AtomKind>) {
    // An element's kind, by atomic number (a byte, so there are at most 256 kinds).
    let mut ids = [None::<u8>; 256];
    let mut kinds = Vec::new();
    let kind_ids = elements
        .iter()
        .map(|&element| {
            *ids[usize::from(element.atomic_number())].get_or_insert_with(|| {
                let color = options.color.unwrap_or_else(|| element.linear_colour());
                kinds.push(AtomKind {
                    radius: element.radius() * options.radius_scale,
                    material: Material { color, ..options.material },
                });
                (kinds.len() - 1) as u8
            })
        })
        .collect();
    (kind_ids, kinds)
}

/// How a structure file opened as a scene is read ([`Scene::load_with`]); TOML scenes say
/// it in their `[[structures]]` tables instead.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LoadOptions {
    /// Build the file's first biological assembly (PDB `REMARK 350` BIOMT, mmCIF
    /// `_pdbx_struct_assembly_gen`) rather than its atoms as they are.
    pub assembly: bool,
    /// Atom radius = van der Waals radius × this.
    pub radius_scale: f32,
}

impl Default for LoadOptions {
    fn default() -> Self {
        Self { assembly: false, radius_scale: DEFAULT_RADIUS_SCALE }
    }
}

impl Scene {
    /// The scene of one structure file: its atoms, framed, with the stereo rule and lights
    /// of the module doc.
    pub fn from_structure_file(path: &Path, options: LoadOptions) -> Result<Self, SceneError> {
        let read = StructureOptions {
            assembly: options.assembly,
            radius_scale: options.radius_scale,
            ..StructureOptions::default()
        };
        Ok(Self::framing(read_structure(path, &read)?))
    }

    /// A scene of `structure` alone, framed (see the module doc).
    #[must_use]
    pub fn framing(structure: Structure) -> Self {
        let sphere = structure.bounding_sphere();
        let (c, r) = sphere.map_or((Vec3::ZERO, 1.0), |s| (s.centre, s.radius.max(f32::MIN_POSITIVE)));
        let fov_deg = Camera::default().fov_deg;
        // The vertical half-angle of a 4:3 eye with this horizontal field of view.
        let half_v = ((0.5 * fov_deg).to_radians().tan() * 0.75).atan();
        let distance = 1.05 * r / half_v.sin();
        let camera = Camera {
            ipd: (distance - r) / 30.0,
            distance,
            fov_deg,
            position: c - Vec3::Z * distance,
            yaw_deg: 0.0,
            pitch_deg: 0.0,
        };
        let lights = vec![
            Light { position: c + Vec3::new(-0.8, 1.2, -2.0) * r, color: Vec3::splat(0.7) },
            Light { position: c + Vec3::new(1.6, 0.2, -1.2) * r, color: Vec3::splat(0.25) },
        ];
        // The cues on, sized to the structure (`cue::sized`).
        let cues = crate::cue::sized((c, r), camera.position, crate::cue::STRUCTURE_AO_SAMPLES);
        let render = RenderSettings { max_depth: 1, background: Vec3::new(0.02, 0.02, 0.03), ambient: 0.35, cues };
        Self { camera, render, lights, spheres: Vec::new(), structures: vec![structure] }
    }

    /// A head speed (scene units a second) for walking through this scene: 2 for scenes of
    /// spheres, and a quarter of a structure's bounding radius a second for molecules, so a
    /// 5 Å peptide and a 700 Å virus both take a few seconds to cross.
    #[must_use]
    pub fn head_speed(&self) -> f32 {
        let radius =
            self.structures.iter().filter_map(Structure::bounding_sphere).map(|s| s.radius).fold(0.0f32, f32::max);
        (0.25 * radius).max(2.0)
    }
}
