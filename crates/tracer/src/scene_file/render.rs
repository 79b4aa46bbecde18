//! The `[render]` table of a TOML scene: reflection depth, background, ambient, and the
//! cues (`cue/`): `ambient_occlusion = { samples, distance, strength }`, `depth_cue = {
//! mode, start, end, density }` and `outline` (pixels). The cues are off unless given; a
//! cue's fields not given take the sizes [`crate::cue::sized`] gives the scene's extent.

use serde::Deserialize;
use toml::Spanned;

use super::Checker;
use crate::cue::{AmbientOcclusion, Cues, DepthCue, DepthCueMode, AO_SAMPLES_MAX, OUTLINE_MAX};
use crate::error::SceneError;
use crate::scene::{RenderSettings, Scene, MAX_DEPTH_LIMIT};

#[derive(Deserialize)]
#[serde(deny_unknown_fields, default)]
pub(super) struct RenderDef {
    max_depth: i64,
    background: [f32; 3],
    ambient: f32,
    ambient_occlusion: Option<AoDef>,
    depth_cue: Option<DepthCueDef>,
    outline: Option<i64>,
}

impl Default for RenderDef {
    fn default() -> Self {
        let r = RenderSettings::default();
        Self {
            max_depth: i64::from(r.max_depth),
            background: r.background.to_array(),
            ambient: r.ambient,
            ambient_occlusion: None,
            depth_cue: None,
            outline: None,
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct AoDef {
    samples: i64,
    distance: Option<f32>,
    strength: Option<f32>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct DepthCueDef {
    mode: String,
    start: Option<f32>,
    end: Option<f32>,
    density: Option<f32>,
}

/// The render settings of `[render]` (`r`, or the defaults without one), its cues sized to
/// `scene` (whose other parts are read): off unless given, but sized, so that turning one
/// on later (`--ao-samples`, `--depth-cue`) finds its sizes.
pub(super) fn render(
    ck: &Checker,
    r: Option<&Spanned<RenderDef>>,
    scene: &Scene,
) -> Result<RenderSettings, SceneError> {
    let sized = crate::cue::sized(crate::cue::bounds(scene), scene.camera.position, 0);
    let off = Cues {
        ambient_occlusion: AmbientOcclusion { samples: 0, ..sized.ambient_occlusion },
        depth_cue: DepthCue { mode: DepthCueMode::Off, ..sized.depth_cue },
        outline: 0,
    };
    let Some(r) = r else { return Ok(RenderSettings { cues: off, ..RenderSettings::default() }) };
    let at = r.span().start;
    let r = r.get_ref();
    if !(0..=i64::from(MAX_DEPTH_LIMIT)).contains(&r.max_depth) {
        let allowed = format!("must be 0 to {MAX_DEPTH_LIMIT} reflection bounces");
        return Err(ck.invalid(at, "render.max_depth", r.max_depth, &allowed));
    }
    Ok(RenderSettings {
        max_depth: r.max_depth as u32,
        background: ck.color(at, "render.background", r.background, 1.0)?,
        ambient: ck.range(at, "render.ambient", r.ambient, 0.0, 1.0, "must be 0 to 1")?,
        cues: cues(ck, at, r, off)?,
    })
}

/// The cues of `[render]` (at `at`), `sized`'s where a field is not given.
fn cues(ck: &Checker, at: usize, r: &RenderDef, sized: Cues) -> Result<Cues, SceneError> {
    let mut cues = sized;
    if let Some(ao) = &r.ambient_occlusion {
        let d = sized.ambient_occlusion;
        if !(0..=i64::from(AO_SAMPLES_MAX)).contains(&ao.samples) {
            let allowed = format!("must be 0 (off) to {AO_SAMPLES_MAX} rays a hit");
            return Err(ck.invalid(at, "render.ambient_occlusion.samples", ao.samples, &allowed));
        }
        let distance = ao.distance.unwrap_or(d.distance);
        let field = "render.ambient_occlusion.distance";
        // Finite, so not NaN: `<= 0` is the whole rest.
        if ck.finite(at, field, distance)? <= 0.0 {
            return Err(ck.invalid(at, field, distance, "must be a finite distance > 0"));
        }
        let strength = ao.strength.unwrap_or(d.strength);
        let strength = ck.range(at, "render.ambient_occlusion.strength", strength, 0.0, 1.0, "must be 0 to 1")?;
        cues.ambient_occlusion = AmbientOcclusion { samples: ao.samples as u32, distance, strength };
    }
    if let Some(c) = &r.depth_cue {
        let d = sized.depth_cue;
        let mode = c.mode.parse::<DepthCueMode>().map_err(|e| ck.invalid(at, "render.depth_cue.mode", &c.mode, &e))?;
        let start = ck.range(at, "render.depth_cue.start", c.start.unwrap_or(d.start), 0.0, f32::MAX, "must be ≥ 0")?;
        let end = ck.finite(at, "render.depth_cue.end", c.end.unwrap_or(d.end))?;
        if end <= start {
            return Err(ck.invalid(at, "render.depth_cue.end", end, &format!("must be beyond start ({start})")));
        }
        let density = c.density.unwrap_or(d.density);
        let density = ck.range(at, "render.depth_cue.density", density, 0.0, f32::MAX, "must be ≥ 0")?;
        cues.depth_cue = DepthCue { mode, start, end, density };
    }
    if let Some(px) = r.outline {
        if !(0..=i64::from(OUTLINE_MAX)).contains(&px) {
            let allowed = format!("must be 0 (off) to {OUTLINE_MAX} pixels");
            return Err(ck.invalid(at, "render.outline", px, &allowed));
        }
        cues.outline = px as u32;
    }
    Ok(cues)
}
