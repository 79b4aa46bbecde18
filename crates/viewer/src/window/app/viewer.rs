//! The [`Viewer`]: everything the window shows that does not depend on the window itself —
//! the options, the scene file (watched) and the settings, the render worker, the clocks and
//! meters, the UI over the eyes — made from the command line, and the scene changes it
//! adopts: a good save of the file reloads it keeping the head where it is, a broken one
//! keeps the last good scene and shows the error in the panel (and shows the UI if it was
//! hidden); a scene file dropped on the window, or picked in the panel's list, opens at its
//! own head pose and scale.

use std::path::Path;
use std::time::{Duration, Instant};

use winit::dpi::LogicalSize;
use winit::event_loop::ActiveEventLoop;

use super::chrome::Chrome;
use super::meters::Meters;
use crate::args::WindowArgs;
use crate::window::fps_log::FpsLog;
use crate::window::input::Input;
use crate::window::os_window::{Dump, Window};
use crate::window::picks::Picks;
use crate::window::scene_watch::{Change, SceneWatch};
use crate::window::screenshot::Screenshots;
use crate::window::settings::Settings;
use crate::window::timewarp::Timewarp;
use crate::window::timing::SceneClock;
use crate::window::ui;
use crate::window::worker::{Progressive, Worker};

/// The window title for a scene file's name.
pub(super) fn title(name: &str) -> String {
    format!("stereotrace — {name}")
}

/// Options that do not change while the window is open.
pub(super) struct Config {
    pub(super) size: LogicalSize<f64>,
    /// `--frames`: stop after this many frames showing the eyes.
    pub(super) frames: Option<u64>,
    /// With the timewarp on, the time between display ticks (`--display-hz`).
    pub(super) display_interval: Duration,
}

/// When to redraw: the tick's cadence, and whether anything changed since the last redraw.
pub(super) struct Pacing {
    /// When the next tick is due.
    pub(super) next_tick: Instant,
    /// Input arrived, or egui asked for a repaint, since the last redraw.
    pub(super) dirty: bool,
    /// When the window was last redrawn.
    pub(super) last_redraw: Instant,
}

/// Everything the viewer keeps that does not depend on the window.
pub(super) struct Viewer {
    pub(super) config: Config,
    /// The scene file, watched, and the last good scene from it.
    pub(super) watch: SceneWatch,
    pub(super) chrome: Chrome,
    pub(super) settings: Settings,
    pub(super) clock: SceneClock,
    pub(super) worker: Worker,
    pub(super) timewarp: Timewarp,
    pub(super) egui: egui::Context,
    pub(super) input: Input,
    pub(super) pacing: Pacing,
    pub(super) meters: Meters,
    pub(super) fps_log: FpsLog,
    pub(super) screenshots: Screenshots,
    /// The picked atoms, and the pose and scene time of the picture on screen that the
    /// next click picks in (set at each redraw).
    pub(super) picks: Picks,
    pub(super) shown: Option<(tracer::Camera, f32)>,
    /// The cursor's last position in the window (physical pixels), while it is in it.
    pub(super) cursor: Option<(f64, f64)>,
    /// `--dump`: the last presented frame, written on exit.
    pub(super) dump: Option<Dump>,
    /// First error met inside the event loop; `run` returns it.
    error: Option<anyhow::Error>,
}

impl Viewer {
    pub(super) fn new(args: &WindowArgs, watch: SceneWatch) -> anyhow::Result<Self> {
        let now = Instant::now();
        let mut settings = Settings::from_scene(watch.scene());
        let clock = match args.time {
            Some(t) => SceneClock::paused_at(t),
            None => SceneClock::running(now),
        };
        settings.paused = clock.is_paused();
        settings.live_psnr = args.live_psnr;
        settings.atoms = crate::window::look::AtomLook::from_args(&args.look);
        // The panel's cues start as the scene's, with the command line's flags.
        let mut scene = tracer::Scene { render: watch.scene().render, ..tracer::Scene::default() };
        args.look.cues.apply(&mut scene);
        settings.atoms.cues = Some(crate::window::look::CueLook::of(&scene.render.cues));
        settings.reuse = !args.no_reuse;
        settings.timewarp = !args.no_timewarp;
        settings.guard_band = args.guard_band as f32 / 100.0;
        let p = args.progressive;
        settings.progressive = (!p.no_progressive)
            .then_some(Progressive { target_age_ms: p.target_age_ms as f32, max_supersample: p.max_supersample });
        if let Some(percent) = args.render_scale {
            settings.render_scale = percent as f32 / 100.0;
        }
        let egui = egui::Context::default();
        ui::setup_style(&egui);
        if args.frames.is_some() {
            // A scripted run (`--frames`, with `--dump`) shows the panel settled: no fade-in,
            // however fast its few frames come.
            egui.all_styles_mut(|style| style.animation_time = 0.0);
        }
        Ok(Self {
            config: Config {
                size: LogicalSize::new(f64::from(args.width), f64::from(args.height)),
                frames: args.frames,
                display_interval: Duration::from_secs(1) / args.display_hz.max(1),
            },
            worker: Worker::spawn(watch.scene().clone())?,
            timewarp: Timewarp::new()?,
            watch,
            chrome: Chrome::new(now),
            settings,
            clock,
            egui,
            input: Input::new(now),
            pacing: Pacing { next_tick: now, dirty: true, last_redraw: now },
            meters: Meters::new(now),
            fps_log: FpsLog::from_env(),
            screenshots: Screenshots::default(),
            picks: Picks::default(),
            shown: None,
            cursor: None,
            dump: args.dump.clone().map(Dump::new),
            error: None,
        })
    }

    /// After the event loop: report its error, or write the `--dump` PNG.
    pub(super) fn finish(mut self) -> anyhow::Result<()> {
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        self.dump.as_ref().map_or(Ok(()), Dump::write)
    }

    /// Stops the event loop with an error that `run` will return.
    pub(super) fn fail(&mut self, event_loop: &ActiveEventLoop, error: anyhow::Error) {
        if self.error.is_none() {
            self.error = Some(error);
        }
        event_loop.exit();
    }

    /// Brings the scene clock in line with the settings (pause and orbit speed) at `now`.
    pub(super) fn sync_clock(&mut self, now: Instant) {
        self.clock.set_paused(self.settings.paused, now);
        self.clock.set_speed(self.settings.orbit_speed, now);
    }

    /// Makes a new scene current: the worker renders it from the next request on; a reload
    /// of the same file keeps the head (and what the file did not change), another file
    /// starts at its own camera and light. Without a new scene, a load that failed since
    /// `failures` (the watch's count of failed loads before the attempt) shows the UI.
    fn adopt(&mut self, change: Option<Change>, failures: u64, window: &Window) {
        if let Some(Change { previous, same_file }) = change {
            let scene = self.watch.scene();
            if same_file {
                self.settings.follow_reload(&previous, scene);
            } else {
                self.settings.adopt_scene(scene);
                window.set_title(&title(self.watch.name()));
            }
            self.worker.set_scene(scene.clone());
        } else if self.watch.failures() > failures {
            // A load just failed: show the UI, which says why.
            self.chrome.hidden = false;
        }
        self.pacing.dirty = true;
    }

    /// Opens a scene file (dropped on the window or picked in the panel): it is read on a
    /// thread of its own, and adopted by the poll that finds it read.
    pub(super) fn open(&mut self, path: &Path) {
        self.watch.open(path);
        self.pacing.dirty = true;
    }

    /// Adopts a scene file read since the last poll, and starts reading the scene file
    /// again when a poll is due and it was saved.
    pub(super) fn poll_scene(&mut self, now: Instant, window: &Window) {
        let failures = self.watch.failures();
        let change = self.watch.poll(now);
        if change.is_some() || self.watch.failures() > failures {
            self.adopt(change, failures, window);
        }
    }
}
