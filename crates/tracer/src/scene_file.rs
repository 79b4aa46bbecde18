//! The TOML scene format and its validation.
//!
//! Every table rejects unknown fields. Parse errors carry the parser's line; range errors
//! name the line of the table, the dotted field, the value and what is allowed. See the
//! README for the defaults of every optional field.

use std::fmt::Display;
use std::path::{Path, PathBuf};

use glam::Vec3;
use serde::Deserialize;
use toml::Spanned;

use crate::camera::{Camera, Eye};
use crate::error::SceneError;
use crate::material::Material;
use crate::scene::{Light, Motion, RenderSettings, Scene, SceneSphere, MAX_LIGHTS};
use crate::structure::LoadOptions;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SceneFile {
    camera: Option<Spanned<CameraDef>>,
    render: Option<Spanned<render::RenderDef>>,
    #[serde(default)]
    lights: Vec<Spanned<LightDef>>,
    #[serde(default)]
    spheres: Vec<Spanned<SphereDef>>,
    #[serde(default)]
    structures: Vec<Spanned<structures::StructureDef>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields, default)]
struct CameraDef {
    ipd: f32,
    distance: f32,
    fov_deg: f32,
    position: [f32; 3],
    yaw_deg: f32,
    pitch_deg: f32,
}

impl Default for CameraDef {
    fn default() -> Self {
        let c = Camera::default();
        Self {
            ipd: c.ipd,
            distance: c.distance,
            fov_deg: c.fov_deg,
            position: c.position.to_array(),
            yaw_deg: c.yaw_deg,
            pitch_deg: c.pitch_deg,
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct LightDef {
    position: [f32; 3],
    #[serde(default = "one3")]
    color: [f32; 3],
}

fn one3() -> [f32; 3] {
    [1.0; 3]
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SphereDef {
    radius: f32,
    center: Option<[f32; 3]>,
    orbit: Option<OrbitDef>,
    color: Option<[f32; 3]>,
    diffuse: Option<f32>,
    specular: Option<f32>,
    shininess: Option<f32>,
    reflectivity: Option<f32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct OrbitDef {
    center: [f32; 3],
    radius: f32,
    period_s: f32,
    #[serde(default)]
    phase_deg: f32,
}

/// Turns byte offsets into line numbers and builds errors that name the file.
struct Checker<'a> {
    path: &'a Path,
    src: &'a str,
}

impl Checker<'_> {
    fn line(&self, offset: usize) -> usize {
        self.src[..offset.min(self.src.len())].bytes().filter(|&b| b == b'\n').count() + 1
    }

    fn invalid(&self, offset: usize, field: &str, value: impl Display, reason: &str) -> SceneError {
        SceneError::Invalid {
            path: self.path.to_path_buf(),
            line: self.line(offset),
            field: field.to_owned(),
            value: value.to_string(),
            reason: reason.to_owned(),
        }
    }

    fn finite(&self, at: usize, field: &str, v: f32) -> Result<f32, SceneError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.invalid(at, field, v, "must be a finite number"))
        }
    }

    fn range(&self, at: usize, field: &str, v: f32, lo: f32, hi: f32, what: &str) -> Result<f32, SceneError> {
        let v = self.finite(at, field, v)?;
        if v >= lo && v <= hi {
            Ok(v)
        } else {
            Err(self.invalid(at, field, v, what))
        }
    }

    fn vec3(&self, at: usize, field: &str, v: [f32; 3]) -> Result<Vec3, SceneError> {
        for (k, x) in v.iter().enumerate() {
            if !x.is_finite() {
                return Err(self.invalid(at, &format!("{field}[{k}]"), x, "must be a finite number"));
            }
        }
        Ok(Vec3::from_array(v))
    }

    fn color(&self, at: usize, field: &str, v: [f32; 3], hi: f32) -> Result<Vec3, SceneError> {
        let c = self.vec3(at, field, v)?;
        for (k, x) in v.iter().enumerate() {
            if *x < 0.0 || *x > hi {
                let allowed = if hi.is_finite() {
                    format!("colour channels are linear, 0 to {hi}")
                } else {
                    "must be ≥ 0".to_owned()
                };
                return Err(self.invalid(at, &format!("{field}[{k}]"), x, &allowed));
            }
        }
        Ok(c)
    }

    /// The shading terms of a sphere's or a structure's table (its keys named by `field`):
    /// `diffuse`, `specular`, `shininess` and `reflectivity` as given, else `d`'s; the colour
    /// is `d`'s.
    fn shading(
        &self,
        at: usize,
        field: impl Fn(&str) -> String,
        [diffuse, specular, shininess, reflectivity]: [Option<f32>; 4],
        d: Material,
    ) -> Result<Material, SceneError> {
        let unit = |name: &str, v: Option<f32>, dv: f32| {
            self.range(at, &field(name), v.unwrap_or(dv), 0.0, 1.0, "must be 0 to 1")
        };
        let shininess = shininess.unwrap_or(d.shininess);
        Ok(Material {
            color: d.color,
            diffuse: unit("diffuse", diffuse, d.diffuse)?,
            specular: unit("specular", specular, d.specular)?,
            shininess: self.range(at, &field("shininess"), shininess, 1.0, 10_000.0, "must be 1 to 10000")?,
            reflectivity: unit("reflectivity", reflectivity, d.reflectivity)?,
        })
    }
}

fn format_vec(v: [f32; 3]) -> String {
    format!("[{}, {}, {}]", v[0], v[1], v[2])
}

/// The largest TOML scene file read (a hundred thousand spheres take about 15 MiB).
pub const MAX_TOML_BYTES: u64 = 64 << 20;

/// The most spheres a scene may have, its own and its structures' atoms together (the
/// structure readers' own limit).
pub const MAX_SPHERES: usize = 16 << 20;

/// Whether `path` is named as a scene file: `.toml`, or a structure file that
/// [`Scene::load`] reads (`.pdb`, `.ent`, `.cif`, `.mmcif`, `.gro`, `.xyz`, each optionally
/// `.gz`).
#[must_use]
pub fn is_scene_file_name(path: &Path) -> bool {
    path.extension().is_some_and(|e| e.eq_ignore_ascii_case("toml")) || molecule::Format::from_path(path).is_some()
}

impl Scene {
    /// Reads and validates a scene file: TOML (`.toml`), or a structure file (`.pdb`,
    /// `.ent`, `.cif`, `.mmcif`, `.gro`, `.xyz`, each optionally `.gz`) framed as a scene of
    /// its own (`structure.rs`). A path that is not a regular file, a TOML file above
    /// [`MAX_TOML_BYTES`] and a scene of more than [`MAX_SPHERES`] spheres are refused
    /// before they are read.
    pub fn load(path: impl AsRef<Path>) -> Result<Self, SceneError> {
        Self::load_with(path, LoadOptions::default())
    }

    /// [`Scene::load`], a structure file read as `options` say (they do not apply to TOML).
    pub fn load_with(path: impl AsRef<Path>, options: LoadOptions) -> Result<Self, SceneError> {
        let path = path.as_ref();
        if molecule::Format::from_path(path).is_some() {
            return Self::from_structure_file(path, options);
        }
        let meta = std::fs::metadata(path).map_err(|source| SceneError::Io { path: path.to_path_buf(), source })?;
        let not_a_scene = |reason: String| SceneError::NotAScene { path: path.to_path_buf(), reason };
        if !meta.is_file() {
            return Err(not_a_scene(format!("not a regular file ({})", read::file_kind(&meta))));
        }
        if meta.len() > MAX_TOML_BYTES {
            return Err(not_a_scene(format!(
                "{} bytes, above the limit of {MAX_TOML_BYTES} for a TOML scene",
                meta.len()
            )));
        }
        if path.extension().is_some_and(|e| !e.eq_ignore_ascii_case("toml")) {
            return Err(not_a_scene(
                "not a scene file: name it .toml, or a structure .pdb, .ent, .cif, .mmcif, .gro or .xyz (optionally .gz)"
                    .to_owned(),
            ));
        }
        let src = read::read_bounded(path, MAX_TOML_BYTES)?;
        Self::from_toml(&src, path)
    }

    /// Parses and validates scene TOML; `path` is used only in error messages.
    pub fn from_toml(src: &str, path: impl AsRef<Path>) -> Result<Self, SceneError> {
        let path = path.as_ref();
        let ck = Checker { path, src };
        let file: SceneFile = toml::from_str(src).map_err(|e| parse_error(&ck, &e, path.to_path_buf()))?;

        let camera = match &file.camera {
            None => Camera::default(),
            Some(c) => {
                let at = c.span().start;
                let c = c.get_ref();
                let camera = Camera {
                    ipd: ck.range(at, "camera.ipd", c.ipd, 0.0, f32::MAX, "must be ≥ 0 (0 gives identical eyes)")?,
                    distance: ck.range(
                        at,
                        "camera.distance",
                        c.distance,
                        f32::MIN_POSITIVE,
                        f32::MAX,
                        "must be > 0",
                    )?,
                    fov_deg: ck.finite(at, "camera.fov_deg", c.fov_deg)?,
                    position: ck.vec3(at, "camera.position", c.position)?,
                    yaw_deg: ck.finite(at, "camera.yaw_deg", c.yaw_deg)?,
                    pitch_deg: ck.range(
                        at,
                        "camera.pitch_deg",
                        c.pitch_deg,
                        -89.0,
                        89.0,
                        "must be within −89 to 89 degrees",
                    )?,
                };
                if !(camera.fov_deg > 0.0 && camera.fov_deg < 180.0) {
                    return Err(ck.invalid(
                        at,
                        "camera.fov_deg",
                        c.fov_deg,
                        "must be strictly between 0 and 180 degrees",
                    ));
                }
                camera
            }
        };

        if file.lights.len() > MAX_LIGHTS {
            let at = file.lights[MAX_LIGHTS].span().start;
            return Err(ck.invalid(at, "lights", file.lights.len(), &format!("at most {MAX_LIGHTS} lights")));
        }
        let mut lights = Vec::with_capacity(file.lights.len());
        for (k, l) in file.lights.iter().enumerate() {
            let at = l.span().start;
            let l = l.get_ref();
            lights.push(Light {
                position: ck.vec3(at, &format!("lights[{k}].position"), l.position)?,
                color: ck.color(at, &format!("lights[{k}].color"), l.color, f32::INFINITY)?,
            });
        }

        let mut spheres = Vec::with_capacity(file.spheres.len());
        for (k, s) in file.spheres.iter().enumerate() {
            spheres.push(sphere(&ck, k, s.span().start, s.get_ref())?);
        }

        let structures = structures::structures(&ck, &file.structures, spheres.len())?;
        if spheres.is_empty() && structures.is_empty() {
            return Err(ck.invalid(
                src.len(),
                "spheres",
                "[]",
                "a scene needs at least one [[spheres]] or [[structures]] table",
            ));
        }
        let mut scene = Scene { camera, render: RenderSettings::default(), lights, spheres, structures };
        scene.render = render::render(&ck, file.render.as_ref(), &scene)?;
        check_camera_outside_spheres(&ck, &file, &scene)?;
        Ok(scene)
    }
}

fn sphere(ck: &Checker, k: usize, at: usize, s: &SphereDef) -> Result<SceneSphere, SceneError> {
    let f = |name: &str| format!("spheres[{k}].{name}");
    let radius = ck.finite(at, &f("radius"), s.radius)?;
    if radius <= 0.0 {
        return Err(ck.invalid(at, &f("radius"), radius, "must be > 0"));
    }
    let motion = match (&s.center, &s.orbit) {
        (Some(c), None) => Motion::Static(ck.vec3(at, &f("center"), *c)?),
        (None, Some(o)) => {
            let period_s = ck.finite(at, &f("orbit.period_s"), o.period_s)?;
            if period_s <= 0.0 {
                return Err(ck.invalid(at, &f("orbit.period_s"), period_s, "must be > 0 seconds"));
            }
            Motion::Orbit {
                center: ck.vec3(at, &f("orbit.center"), o.center)?,
                radius: ck.range(at, &f("orbit.radius"), o.radius, 0.0, f32::MAX, "must be ≥ 0")?,
                period_s,
                phase_deg: ck.finite(at, &f("orbit.phase_deg"), o.phase_deg)?,
            }
        }
        (Some(c), Some(_)) => {
            return Err(ck.invalid(
                at,
                &f("center"),
                format_vec(*c),
                "a sphere has either `center` or `orbit`, not both",
            ))
        }
        (None, None) => return Err(ck.invalid(at, &f("center"), "(missing)", "a sphere needs `center` or `orbit`")),
    };
    let shading = ck.shading(at, f, [s.diffuse, s.specular, s.shininess, s.reflectivity], Material::default())?;
    let material = Material {
        color: match s.color {
            Some(c) => ck.color(at, &f("color"), c, 1.0)?,
            None => shading.color,
        },
        ..shading
    };
    Ok(SceneSphere { radius, motion, material })
}

/// An eye inside a sphere sees only its inside: reject it rather than render black.
/// Orbiting spheres are checked over a full revolution, atoms where they are.
fn check_camera_outside_spheres(ck: &Checker, file: &SceneFile, scene: &Scene) -> Result<(), SceneError> {
    let eyes = [scene.camera.eye_position(Eye::Left), scene.camera.eye_position(Eye::Right)];
    for (k, s) in scene.structures.iter().enumerate() {
        for (p, r) in s.atom_spheres() {
            if let Some(eye) = eyes.into_iter().find(|e| (*e - p).length() <= r) {
                return Err(ck.invalid(
                    file.structures[k].span().start,
                    &format!("structures[{k}].offset"),
                    format_vec(file.structures[k].get_ref().offset.unwrap_or_default()),
                    &format!("the camera's eye at {eye} is inside an atom at {p}; move the camera or the structure"),
                ));
            }
        }
    }
    for (k, s) in scene.spheres.iter().enumerate() {
        let samples = if matches!(s.motion, Motion::Orbit { .. }) { 360 } else { 1 };
        for n in 0..samples {
            let t = match s.motion {
                Motion::Orbit { period_s, .. } => period_s * n as f32 / samples as f32,
                Motion::Static(_) => 0.0,
            };
            let c = s.motion.center_at(t);
            for eye in eyes {
                if (eye - c).length() <= s.radius {
                    let at = file.spheres[k].span().start;
                    let where_ = if samples > 1 { format!(" (on its orbit at t = {t:.2} s)") } else { String::new() };
                    return Err(ck.invalid(
                        at,
                        &format!("spheres[{k}].radius"),
                        s.radius,
                        &format!(
                            "the camera's eye at {eye} is inside this sphere{where_}; move the camera or the sphere"
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

fn parse_error(ck: &Checker, e: &toml::de::Error, path: PathBuf) -> SceneError {
    let (line, excerpt) = match e.span() {
        Some(span) => {
            let line = ck.line(span.start);
            let text = ck.src.lines().nth(line - 1).unwrap_or("").trim();
            (line, if text.is_empty() { String::new() } else { format!(" (at `{text}`)") })
        }
        None => (0, String::new()),
    };
    SceneError::Parse { path, line, message: format!("{}{excerpt}", e.message().trim_end()) }
}

mod read;
mod render;
mod structures;
#[cfg(test)]
mod tests;
