//! How the right eye is made.

use std::fmt;
use std::str::FromStr;

use crate::classify::Edges;

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
    /// reprojection names, and shade that point with shadow rays of its own; retrace edges
    /// (eight neighbours). Matches `Full` bit for bit wherever the sphere named is the one
    /// the pixel centre sees first, which the edges make all but certain: a sphere that
    /// slips between all nine pixel centres of the left eye is missed.
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
    /// Which neighbours make a pixel an edge: all eight in exact mode, the four beside,
    /// above and below with `retrace_edges`, none otherwise.
    pub(crate) fn edges(self) -> Edges {
        match (self.mode, self.retrace_edges) {
            (Mode::Exact, _) => Edges::Around,
            (_, true) => Edges::Sides,
            _ => Edges::Off,
        }
    }
}
