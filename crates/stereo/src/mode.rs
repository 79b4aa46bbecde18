//! How the right eye is made.

use std::fmt;
use std::str::FromStr;

/// How the right eye's reprojected pixels get their colour. Every mode produces a complete
/// right image; the retraced pixels are always traced exactly as [`Mode::Full`] would.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Mode {
    /// Trace the right eye from scratch: the reference for quality and cost.
    Full,
    /// The seed paper: reuse the left eye's final colour.
    Copy,
    /// Reuse the left hit (point, normal, object, view-independent light and light
    /// visibility); recompute the highlight and reflection for the right eye.
    Reshade,
    /// Beyond the paper: intersect the right pixel-centre ray with the one sphere the
    /// reprojection names, shade it with the reused visibility; retrace edges and shadow
    /// boundaries. Matches `Full` at 8 bits on all but a handful of pixels.
    #[default]
    Exact,
}

impl Mode {
    /// Every mode, in the order reports list them.
    pub const ALL: [Mode; 4] = [Mode::Full, Mode::Copy, Mode::Reshade, Mode::Exact];

    /// The mode's name on the command line and in reports.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Mode::Full => "full",
            Mode::Copy => "copy",
            Mode::Reshade => "reshade",
            Mode::Exact => "exact",
        }
    }
}

impl fmt::Display for Mode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Mode {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        Mode::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| format!("unknown mode `{s}`: expected one of full, copy, reshade, exact"))
    }
}

/// Per-frame choices.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Options {
    /// How reprojected pixels are filled.
    pub mode: Mode,
    /// For `copy` and `reshade`: also retrace reprojected pixels whose object differs from a
    /// neighbour's, removing the "drag" at silhouettes. `exact` always does.
    pub retrace_edges: bool,
}

impl Options {
    /// Whether object-edge pixels are retraced.
    #[must_use]
    pub fn edges(&self) -> bool {
        self.mode == Mode::Exact || self.retrace_edges
    }

    /// Whether shadow-boundary pixels are retraced (exact mode only: the other modes reuse
    /// shading that already includes the left eye's shadows).
    #[must_use]
    pub fn shadow_boundaries(&self) -> bool {
        self.mode == Mode::Exact
    }
}
