//! The frame-rate log on stderr, on with `STEREOTRACE_LOG_FPS=1`: one line of `key=value`
//! fields each time the UI's rate meter closes a window (about twice a second). Soak runs
//! read the rates from it, and the window tests read the head pose, layout, swap and PSNR,
//! and wait on it: for the first rendered frame (`frame`, its number, 0 before it) and for
//! the UI to be hidden (`ui`) before they go on.

use std::time::Duration;

use crate::window::pose_meter::Medians;
use crate::window::settings::Settings;
use crate::window::timewarp::Warped;
use crate::window::worker::FrameInfo;

/// The environment variable that turns the log on (value `1`).
pub const ENV: &str = "STEREOTRACE_LOG_FPS";

/// What one line reports besides the redraw time.
#[derive(Clone, Copy, Debug)]
pub struct Report<'a> {
    /// Frames presented per second.
    pub ui_fps: f64,
    /// Stereo frames rendered per second.
    pub render_fps: f64,
    /// Window size, physical pixels.
    pub window: (u32, u32),
    /// The newest rendered frame, if any.
    pub frame: Option<&'a FrameInfo>,
    /// The settings on screen.
    pub settings: &'a Settings,
    /// Tab has hidden the UI: the frame presented with this line shows the eyes alone.
    pub ui_hidden: bool,
    /// Presented frames a second that showed a new head pose.
    pub pose_fps: f64,
    /// Median input latency and traced-frame age at present over the window.
    pub medians: Medians,
    /// What the last timewarp did, when the last frame presented was warped.
    pub warp: Option<Warped>,
}

/// The log: whether it is on, and the time spent redrawing since its last line.
#[derive(Clone, Copy, Debug, Default)]
pub struct FpsLog {
    enabled: bool,
    busy: Duration,
    redraws: u32,
}

impl FpsLog {
    /// On when [`ENV`] is `1`.
    #[must_use]
    pub fn from_env() -> Self {
        Self { enabled: std::env::var(ENV).is_ok_and(|v| v == "1"), ..Self::default() }
    }

    /// Counts one redraw that took `busy`.
    pub fn add_redraw(&mut self, busy: Duration) {
        self.busy += busy;
        self.redraws += 1;
    }

    /// Writes one line (when on), with the mean redraw time since the last one.
    pub fn write(&mut self, report: &Report<'_>) {
        if self.enabled {
            let (busy, redraws) = (std::mem::take(&mut self.busy), std::mem::take(&mut self.redraws));
            eprintln!("{}", line(report, busy, redraws));
        }
    }
}

/// One log line: the rates, the mean redraw time over `redraws` redraws that took `busy`,
/// the window, the eyes' trace times, the head pose and the view, the newest frame's number
/// and whether the UI is shown.
fn line(r: &Report<'_>, busy: Duration, redraws: u32) -> String {
    let s = r.settings;
    let (left_ms, right_ms) = r.frame.map_or((0.0, 0.0), |f| (f.stats.left.ms, f.stats.right.ms));
    let psnr = r.frame.and_then(|f| f.quality).map_or_else(|| "-".to_owned(), |q| format!("{:.2}", q.psnr_db));
    format!(
        "fps={:.1} render_fps={:.1} ui_ms={:.2} window={}x{} left_ms={left_ms:.1} right_ms={right_ms:.1} \
         head={:.3},{:.3},{:.3} yaw={:.1} pitch={:.1} layout={} swap={} psnr={psnr} pose_fps={:.1} \
         latency_ms={} age_ms={} timewarp={} warp_ms={} holes={} density={} spp={} converged={} frame={} ui={}",
        r.ui_fps,
        r.render_fps,
        busy.as_secs_f64() * 1e3 / f64::from(redraws.max(1)),
        r.window.0,
        r.window.1,
        s.position.x,
        s.position.y,
        s.position.z,
        s.yaw_deg,
        s.pitch_deg,
        s.layout,
        s.swap_eyes,
        r.pose_fps,
        optional(r.medians.latency_ms, 1),
        optional(r.medians.age_ms, 1),
        if s.timewarp { "on" } else { "off" },
        optional(r.warp.map(|w| w.ms), 2),
        optional(r.warp.map(|w| 100.0 * w.hole_share()), 3),
        r.frame.map_or(0, |f| f.sampling.density),
        r.frame.map_or(0, |f| f.sampling.spp),
        r.frame.is_some_and(|f| f.sampling.converged),
        r.frame.map_or(0, |f| f.seq),
        if r.ui_hidden { "hidden" } else { "shown" },
    )
}

/// A number with `decimals`, or `-` for none.
fn optional(value: Option<f64>, decimals: usize) -> String {
    value.map_or_else(|| "-".to_owned(), |v| format!("{v:.decimals$}"))
}

#[cfg(test)]
mod tests {
    use crate::window::worker::Sampling;
    use glam::Vec3;
    use stereo::{FrameStats, Layout, Quality};

    use super::*;

    #[test]
    fn a_line_has_every_field_the_tests_read() {
        let scene =
            tracer::Scene::from_toml("[[spheres]]\ncenter = [0.0, 0.0, 10.0]\nradius = 1.0\n", "s.toml").unwrap();
        let mut settings = Settings::from_scene(&scene);
        (settings.position, settings.yaw_deg, settings.layout, settings.swap_eyes) =
            (Vec3::new(0.5, 0.0, -1.25), 30.0, Layout::Anaglyph, true);
        let mut report = Report {
            ui_fps: 60.0,
            render_fps: 12.5,
            window: (800, 300),
            frame: None,
            settings: &settings,
            ui_hidden: false,
            pose_fps: 0.0,
            medians: Medians::default(),
            warp: None,
        };
        assert_eq!(
            line(&report, Duration::from_millis(9), 3),
            "fps=60.0 render_fps=12.5 ui_ms=3.00 window=800x300 left_ms=0.0 right_ms=0.0 \
             head=0.500,0.000,-1.250 yaw=30.0 pitch=0.0 layout=anaglyph swap=true psnr=- pose_fps=0.0 \
             latency_ms=- age_ms=- timewarp=on warp_ms=- holes=- density=0 spp=0 converged=false frame=0 ui=shown",
            "before the first frame"
        );
        let mut stats = FrameStats::default();
        (stats.left.ms, stats.right.ms) = (20.0, 5.5);
        let request = settings.request(&scene, 0.0, 8, 8);
        let quality = Some(Quality { psnr_db: f64::INFINITY, ..Quality::default() });
        let sampling = Sampling { density: 1, spp: 16, converged: true };
        let frame = FrameInfo { stats, quality, wall_ms: 30.0, sampling, ..FrameInfo::answering(7, request) };
        (report.frame, report.ui_hidden, report.pose_fps) = (Some(&frame), true, 90.04);
        report.medians = Medians { latency_ms: Some(7.25), age_ms: Some(80.0) };
        let mut warp = Warped { ms: 2.5, ..Warped::default() };
        warp.counts[0].warped = 95;
        warp.counts[1].filled = 5;
        warp.counts[1].warped = 100;
        report.warp = Some(warp);
        let l = line(&report, Duration::ZERO, 0);
        assert!(l.contains(" left_ms=20.0 right_ms=5.5 "), "{l}");
        assert!(
            l.ends_with(
                " psnr=inf pose_fps=90.0 latency_ms=7.2 age_ms=80.0 timewarp=on warp_ms=2.50 holes=2.500 density=1 spp=16 \
                 converged=true frame=7 ui=hidden"
            ),
            "{l}"
        );
    }
}
