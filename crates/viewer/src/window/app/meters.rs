//! What the viewer counts and measures as it runs: frames presented and rendered, their
//! rates, the frame-time history, and the numbers the panel shows of them, refreshed a few
//! times a second rather than every frame.

use std::time::{Duration, Instant};

use crate::window::frame_times::FrameTimes;
use crate::window::pose_meter::PoseMeter;
use crate::window::timing::RateMeter;
use crate::window::worker::{FrameInfo, Request};

/// How often the panel's frame numbers (times, rays, shares, the frame-time plot) are
/// refreshed: they change with every frame, and repainting their text and plot every frame
/// cost the UI thread ~1 ms a frame (egui's software rasteriser redraws whatever changed),
/// time a 2-core machine takes from the tracer; numbers are read at a few updates a second.
const READOUT_REFRESH: Duration = Duration::from_millis(250);

/// Frames counted and rates measured as the viewer runs.
pub(super) struct Meters {
    /// UI frames presented.
    pub(super) presented: u64,
    /// Frames presented with both eyes of a rendered frame on screen (what `--frames` counts).
    pub(super) presented_with_eyes: u64,
    /// Sequence number of the newest rendered frame seen.
    pub(super) last_seq: u64,
    /// Frames presented per second.
    pub(super) ui: RateMeter,
    /// Stereo frames rendered per second.
    pub(super) render: RateMeter,
    /// The newest frames' times, for the panel's plot.
    pub(super) history: FrameTimes,
    /// What the panel shows of them.
    pub(super) shown: Shown,
    /// New poses a second, input latency and frame age.
    pub(super) pose: PoseMeter,
}

impl Meters {
    /// Nothing counted yet, the rate meters starting at `now`.
    pub(super) fn new(now: Instant) -> Self {
        Self {
            presented: 0,
            presented_with_eyes: 0,
            last_seq: 0,
            ui: RateMeter::new(now, 0),
            render: RateMeter::new(now, 0),
            history: FrameTimes::default(),
            shown: Shown::default(),
            pose: PoseMeter::new(now),
        }
    }
}

/// The frame numbers on the panel, as last refreshed ([`READOUT_REFRESH`]).
#[derive(Clone, Debug, Default)]
pub(super) struct Shown {
    /// When they were taken (`None`: not yet).
    at: Option<Instant>,
    /// The newest frame then.
    pub(super) frame: Option<FrameInfo>,
    /// The frame times then.
    pub(super) history: FrameTimes,
    /// The scene time then.
    pub(super) time: f32,
}

impl Shown {
    /// Takes the newest numbers when the refresh is due at `now`, or at once when the frame
    /// answers another request than the one shown (a setting changed, not only the time)
    /// or `every_frame` (a scripted run, whose dump shows its last frame's numbers).
    pub(super) fn refresh(
        &mut self,
        now: Instant,
        (frame, history, time): (Option<&FrameInfo>, &FrameTimes, f32),
        every_frame: bool,
    ) {
        let other =
            |a: &FrameInfo, b: &FrameInfo| Request { time: 0.0, ..a.request } != Request { time: 0.0, ..b.request };
        let changed = match (&self.frame, frame) {
            (Some(a), Some(b)) => other(a, b),
            (a, b) => a.is_some() != b.is_some(),
        };
        if every_frame || changed || self.at.is_none_or(|at| now - at >= READOUT_REFRESH) {
            *self = Self { at: Some(now), frame: frame.copied(), history: history.clone(), time };
        }
    }
}

#[cfg(test)]
mod tests {
    use tracer::Scene;

    use super::*;
    use crate::window::settings::Settings;

    #[test]
    fn the_panel_numbers_refresh_a_few_times_a_second_or_when_a_setting_changes() {
        let scene = Scene::from_toml("[[spheres]]\ncenter = [0.0, 0.0, 10.0]\nradius = 1.0\n", "s.toml").unwrap();
        let settings = Settings::from_scene(&scene);
        let info = |seq: u64, time: f32, width: u32| {
            let request = settings.request(&scene, time, width, 8);
            FrameInfo { wall_ms: 1.0, ..FrameInfo::answering(seq, request) }
        };
        let (t0, history) = (Instant::now(), FrameTimes::default());
        let mut shown = Shown::default();
        shown.refresh(t0, (None, &history, 0.0), false);
        assert!(shown.frame.is_none() && shown.at == Some(t0), "taken at once");
        let first = info(1, 0.1, 8);
        shown.refresh(t0, (Some(&first), &history, 0.1), false);
        assert_eq!(shown.frame.map(|f| f.seq), Some(1), "the first frame shows at once");
        let later = READOUT_REFRESH / 2;
        shown.refresh(t0 + later, (Some(&info(2, 0.2, 8)), &history, 0.2), false);
        assert_eq!((shown.frame.map(|f| f.seq), shown.time), (Some(1), 0.1), "only the time moved: kept");
        shown.refresh(t0 + later, (Some(&info(3, 0.2, 8)), &history, 0.2), true);
        assert_eq!(shown.frame.map(|f| f.seq), Some(3), "a scripted run shows every frame's numbers");
        shown.refresh(t0 + later, (Some(&info(4, 0.2, 16)), &history, 0.2), false);
        assert_eq!(shown.frame.map(|f| f.seq), Some(4), "another eye size shows at once");
        shown.refresh(t0 + later + READOUT_REFRESH, (Some(&info(5, 0.3, 16)), &history, 0.3), false);
        assert_eq!((shown.frame.map(|f| f.seq), shown.time), (Some(5), 0.3), "refreshed when due");
    }
}
