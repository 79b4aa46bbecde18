//! Depth cueing, as VMD's `depthcue` (Linear and Exp2; on by default in VMD): a primary
//! hit's linear colour blends towards the background with its distance from the eye,
//! pixel by pixel, with no neighbourhood. Both shading paths call [`DepthCue::apply`].

use glam::Vec3;

use super::{DepthCue, DepthCueMode};

impl DepthCue {
    /// The share of the colour kept at distance `t` (1 near, towards 0 far).
    #[must_use]
    pub fn kept(&self, t: f32) -> f32 {
        match self.mode {
            DepthCueMode::Off => 1.0,
            DepthCueMode::Linear => ((self.end - t) / (self.end - self.start)).clamp(0.0, 1.0),
            DepthCueMode::Exp2 => {
                let s = self.density * (t - self.start).max(0.0);
                (-(s * s)).exp()
            }
        }
    }

    /// `colour` seen at distance `t`, blended towards `background`.
    #[must_use]
    pub fn apply(&self, colour: Vec3, background: Vec3, t: f32) -> Vec3 {
        if self.mode == DepthCueMode::Off {
            return colour;
        }
        let f = self.kept(t);
        colour * f + background * (1.0 - f)
    }
}
