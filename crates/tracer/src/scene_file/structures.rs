//! The `[[structures]]` tables of a TOML scene: structure files placed beside its spheres,
//! each with its radius scale, offset and material.

use std::path::Path;

use glam::Vec3;
use serde::Deserialize;
use toml::Spanned;

use super::{Checker, MAX_SPHERES};
use crate::color_by::{ColorBy, Coloring};
use crate::error::SceneError;
use crate::scene::Structure;
use crate::structure::{read_structure, StructureOptions};

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct StructureDef {
    path: String,
    radius_scale: Option<f32>,
    #[serde(default)]
    assembly: bool,
    pub(super) offset: Option<[f32; 3]>,
    color: Option<[f32; 3]>,
    color_by: Option<String>,
    diffuse: Option<f32>,
    specular: Option<f32>,
    shininess: Option<f32>,
    reflectivity: Option<f32>,
}

/// The `[[structures]]` tables, read and placed, refusing a scene of more than
/// [`MAX_SPHERES`] spheres (`spheres` of its own).
pub(super) fn structures(
    ck: &Checker,
    defs: &[Spanned<StructureDef>],
    spheres: usize,
) -> Result<Vec<Structure>, SceneError> {
    let mut structures = Vec::with_capacity(defs.len());
    let mut count = spheres;
    for (k, s) in defs.iter().enumerate() {
        let structure = structure(ck, k, s.span().start, s.get_ref())?;
        count += structure.positions.len();
        if count > MAX_SPHERES {
            let why = format!("the scene would have {count} spheres, above the limit of {MAX_SPHERES}");
            return Err(ck.invalid(s.span().start, &format!("structures[{k}].path"), &s.get_ref().path, &why));
        }
        structures.push(structure);
    }
    Ok(structures)
}

/// A `[[structures]]` table: the file (relative to the scene file's folder) read and placed.
fn structure(ck: &Checker, k: usize, at: usize, s: &StructureDef) -> Result<Structure, SceneError> {
    let f = |name: &str| format!("structures[{k}].{name}");
    let d = StructureOptions::default();
    let radius_scale = ck.finite(at, &f("radius_scale"), s.radius_scale.unwrap_or(d.radius_scale))?;
    if radius_scale <= 0.0 {
        return Err(ck.invalid(
            at,
            &f("radius_scale"),
            radius_scale,
            "must be > 0 (1 for van der Waals spheres, 0.25 for CPK balls)",
        ));
    }
    let options = StructureOptions {
        radius_scale,
        assembly: s.assembly,
        offset: s.offset.map(|o| ck.vec3(at, &f("offset"), o)).transpose()?.unwrap_or(Vec3::ZERO),
        material: ck.shading(at, f, [s.diffuse, s.specular, s.shininess, s.reflectivity], d.material)?,
        color: s.color.map(|c| ck.color(at, &f("color"), c, 1.0)).transpose()?,
    };
    let by = s.color_by.as_deref().map(str::parse::<ColorBy>).transpose();
    let by = by.map_err(|why| ck.invalid(at, &f("color_by"), s.color_by.as_deref().unwrap_or(""), &why))?;
    let file = ck.path.parent().unwrap_or_else(|| Path::new("")).join(&s.path);
    let mut structure =
        read_structure(&file, &options).map_err(|e| ck.invalid(at, &f("path"), &s.path, &e.to_string()))?;
    // `color_by`: the scheme's colours for the kinds (`element` with `color` keeps `color`).
    if let Some(by) = by.filter(|&by| by != ColorBy::Element || s.color.is_none()) {
        structure.recolor(&Coloring { by, range: None });
    }
    Ok(structure)
}
