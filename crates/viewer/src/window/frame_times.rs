//! The frame-time history the panel plots: the last [`FrameTimes::LEN`] frames' stage times
//! in a fixed ring (nothing is allocated per frame).

use stereo::FrameStats;

/// Number of series in the history: see [`SERIES_NAMES`].
pub const SERIES_LEN: usize = 6;

/// The series, in [`Sample`] order: the whole job, each eye, and the right eye's stages (the
/// left eye's only stage is its trace).
pub const SERIES_NAMES: [&str; SERIES_LEN] = ["frame", "left eye", "right eye", "reproject", "retrace", "reshade"];

/// One frame's times, milliseconds, in [`SERIES_NAMES`] order.
pub type Sample = [f32; SERIES_LEN];

/// The times of one frame that took `wall_ms` in all, in [`SERIES_NAMES`] order.
#[must_use]
pub fn sample(wall_ms: f64, stats: &FrameStats) -> Sample {
    let st = &stats.stages;
    [wall_ms, stats.left.ms, stats.right.ms, st.reproject, st.retrace, st.reshade].map(|v| v as f32)
}

/// The last frames' times (a fixed ring, no allocation).
#[derive(Clone, Debug)]
pub struct FrameTimes {
    ms: [Sample; Self::LEN],
    head: usize,
    len: usize,
}

impl Default for FrameTimes {
    fn default() -> Self {
        Self { ms: [[0.0; SERIES_LEN]; Self::LEN], head: 0, len: 0 }
    }
}

impl FrameTimes {
    /// How many frames the history keeps.
    pub const LEN: usize = 120;

    /// Records one frame's times.
    pub fn push(&mut self, ms: Sample) {
        self.ms[self.head] = ms;
        self.head = (self.head + 1) % Self::LEN;
        self.len = (self.len + 1).min(Self::LEN);
    }

    /// Oldest first.
    pub fn iter(&self) -> impl Iterator<Item = &Sample> + '_ {
        let start = (self.head + Self::LEN - self.len) % Self::LEN;
        (0..self.len).map(move |k| &self.ms[(start + k) % Self::LEN])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_times_keep_the_last_ones_in_order() {
        let mut t = FrameTimes::default();
        for k in 0..(FrameTimes::LEN + 3) {
            t.push([k as f32; SERIES_LEN]);
        }
        let v: Vec<f32> = t.iter().map(|s| s[2]).collect();
        assert_eq!(v.len(), FrameTimes::LEN, "the ring is full");
        assert_eq!(v[0], 3.0, "the three oldest were overwritten");
        assert_eq!(*v.last().unwrap(), (FrameTimes::LEN + 2) as f32, "the newest last");
    }

    #[test]
    fn a_sample_is_in_series_order() {
        let mut stats = FrameStats::default();
        (stats.left.ms, stats.right.ms) = (1.0, 2.0);
        (stats.stages.reproject, stats.stages.retrace, stats.stages.reshade) = (3.0, 4.0, 5.0);
        assert_eq!(sample(9.0, &stats), [9.0, 1.0, 2.0, 3.0, 4.0, 5.0], "{SERIES_NAMES:?}");
    }
}
