//! The cues that make a molecule read as a shape: ray-traced ambient occlusion (`ao.rs`),
//! depth cueing (`fog.rs`) and outlines (`outline.rs`); their settings, their limits and
//! the rule that sizes them to a scene.
//!
//! Ambient occlusion and depth cueing are part of shading (both `shade.rs` and the
//! wavefront call this module's one scalar formula for each); outlines are a post-pass over
//! an eye's colour, object and depth planes. What each computes, and its sources (QuteMol,
//! Tachyon/VMD, ChimeraX, pbrt's `AOIntegrator`): `docs/design/cues.md`.

mod ao;
mod fog;
mod outline;

use glam::Vec3;

use crate::scene::{Motion, Scene};

pub(crate) use ao::SeedRow;
pub use outline::{first_hits, outline, outline_from, Outline, OUTLINE_JUMP};

/// Most ambient occlusion rays a hit may cast ([`AmbientOcclusion::samples`]).
pub const AO_SAMPLES_MAX: u32 = 1024;
/// Widest outline, in pixels of the image shown ([`Cues::outline`]).
pub const OUTLINE_MAX: u32 = 8;

/// The cues of a scene (`[render]`'s `ambient_occlusion`, `depth_cue` and `outline`). All
/// off by default.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Cues {
    /// Ambient occlusion of the primary hits.
    pub ambient_occlusion: AmbientOcclusion,
    /// The colour's blend towards the background with distance.
    pub depth_cue: DepthCue,
    /// Outline width in pixels of the image shown (0: none; at most [`OUTLINE_MAX`]).
    pub outline: u32,
}

/// Ray-traced ambient occlusion: the ambient term at a primary hit is scaled by
/// `1 − strength · (occluded share)`, the share the cosine-weighted fraction of
/// `samples` rays of length `distance` that meet a sphere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AmbientOcclusion {
    /// Rays per hit (0: off; at most [`AO_SAMPLES_MAX`]).
    pub samples: u32,
    /// How far a sphere occludes, scene units (> 0).
    pub distance: f32,
    /// How much of the ambient term occlusion takes away, 0 to 1.
    pub strength: f32,
}

impl Default for AmbientOcclusion {
    fn default() -> Self {
        Self { samples: 0, distance: 1.0, strength: 1.0 }
    }
}

impl AmbientOcclusion {
    /// Whether any occlusion ray is cast.
    #[must_use]
    pub fn is_on(&self) -> bool {
        self.samples > 0 && self.strength > 0.0
    }
}

/// How depth cueing blends with distance (VMD's `depthcue` modes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DepthCueMode {
    /// No depth cueing.
    #[default]
    Off,
    /// `f = (end − t) / (end − start)`, clamped to 0..1.
    Linear,
    /// `f = exp(−(density · max(0, t − start))²)`.
    Exp2,
}

impl std::str::FromStr for DepthCueMode {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "off" => Ok(Self::Off),
            "linear" => Ok(Self::Linear),
            "exp2" => Ok(Self::Exp2),
            _ => Err(format!("{s:?}: must be off, linear or exp2")),
        }
    }
}

impl DepthCueMode {
    /// The mode's name, as the scene file and the command line spell it.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Off => "off",
            Self::Linear => "linear",
            Self::Exp2 => "exp2",
        }
    }
}

/// Depth cueing: a primary hit's colour c at distance t from the eye becomes
/// `f · c + (1 − f) · background`, f as [`DepthCueMode`] says.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthCue {
    /// The blend law.
    pub mode: DepthCueMode,
    /// Distance where the blend starts, scene units.
    pub start: f32,
    /// Distance where a linear blend reaches the background.
    pub end: f32,
    /// Exp2's density, per scene unit.
    pub density: f32,
}

impl Default for DepthCue {
    fn default() -> Self {
        Self { mode: DepthCueMode::Off, start: 0.0, end: 1.0, density: 1.0 }
    }
}

/// The cues' sizes for a scene whose content lies in the ball (`centre`, `radius`), seen
/// from `eye`, with `samples` occlusion rays: occlusion within a tenth of the radius but
/// at least 8 units (8 Å: a pocket's depth, for a small protein); depth cueing from the
/// ball's front, Exp2 with `f` = e^{-1.0} ≈ 0.37 at its back; outlines of 1 pixel. What a
/// structure file opens with; a TOML scene's `[render]` fields not given take these sizes
/// too (but stay off).
#[must_use]
pub fn sized((centre, radius): (Vec3, f32), eye: Vec3, samples: u32) -> Cues {
    let radius = radius.max(f32::MIN_POSITIVE);
    let front = ((centre - eye).length() - radius).max(0.0);
    Cues {
        ambient_occlusion: AmbientOcclusion { samples, distance: (0.1 * radius).max(8.0), strength: 1.0 },
        depth_cue: DepthCue {
            mode: DepthCueMode::Exp2,
            start: front,
            end: front + 2.0 * radius,
            density: 0.5 / radius,
        },
        outline: 1,
    }
}

/// Occlusion rays per hit a structure file opens with.
pub const STRUCTURE_AO_SAMPLES: u32 = 8;

/// A ball holding every sphere of `scene` at time 0 (orbits whole) and its structures: the
/// box around them, and half its diagonal. (0, 1) for an empty scene.
#[must_use]
pub fn bounds(scene: &Scene) -> (Vec3, f32) {
    let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
    for s in &scene.spheres {
        let (c, reach) = match s.motion {
            Motion::Static(c) => (c, s.radius),
            Motion::Orbit { center, radius, .. } => (center, radius + s.radius),
        };
        (lo, hi) = (lo.min(c - reach), hi.max(c + reach));
    }
    for b in scene.structures.iter().filter_map(crate::scene::Structure::bounding_sphere) {
        (lo, hi) = (lo.min(b.centre - b.radius), hi.max(b.centre + b.radius));
    }
    if lo.x > hi.x {
        return (Vec3::ZERO, 1.0);
    }
    (0.5 * (lo + hi), 0.5 * (hi - lo).length())
}

#[cfg(test)]
mod tests;
