//! The cue flags every command shares (`--ao-samples`, `--depth-cue`, `--outline`): each
//! overrides the scene's `[render]` cue (a structure file's are on, a TOML scene's off),
//! keeping the sizes the scene gives it (`tracer::sized_cues`).

use clap::Args;
use tracer::{DepthCueMode, AO_SAMPLES_MAX, OUTLINE_MAX};

/// Ambient occlusion, depth cueing and outlines, as the command line asks.
#[derive(Debug, Args, Clone, Copy, Default, PartialEq, Eq)]
pub struct CueArgs {
    /// Ambient occlusion rays per primary hit, 0 (off) to 1024 [default: the scene's: 8 for
    /// a structure file, off for a TOML scene without render.ambient_occlusion].
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(0..=i64::from(AO_SAMPLES_MAX)))]
    pub ao_samples: Option<u32>,
    /// Depth cueing: off, linear or exp2 [default: the scene's: exp2 for a structure file].
    #[arg(long, value_name = "MODE", value_parser = parse_depth_cue)]
    pub depth_cue: Option<DepthCueMode>,
    /// Outline width in pixels of the image, 0 (off) to 8 [default: the scene's: 1 for a
    /// structure file].
    #[arg(long, value_name = "PX", value_parser = clap::value_parser!(u32).range(0..=i64::from(OUTLINE_MAX)))]
    pub outline: Option<u32>,
}

impl CueArgs {
    /// `scene` with the cues asked for.
    pub fn apply(&self, scene: &mut tracer::Scene) {
        let cues = &mut scene.render.cues;
        if let Some(n) = self.ao_samples {
            cues.ambient_occlusion.samples = n;
        }
        if let Some(mode) = self.depth_cue {
            cues.depth_cue.mode = mode;
        }
        if let Some(px) = self.outline {
            cues.outline = px;
        }
    }
}

fn parse_depth_cue(s: &str) -> Result<DepthCueMode, String> {
    s.parse()
}
