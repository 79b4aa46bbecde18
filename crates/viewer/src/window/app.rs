//! The viewer window: a winit 0.30 [`ApplicationHandler`] that shows the two eyes side by side
//! with softbuffer and an egui panel over them.
//!
//! The app is in one of two states, as in softbuffer's examples: [`State::Initial`] until
//! winit first resumes it, then [`State::Running`] with the open [`Window`]. What does not
//! depend on the window — the scene, the settings, the render worker, the clocks and meters —
//! is the [`Viewer`], which lives through both.
//!
//! The UI ticks 240 times a second (paced with `ControlFlow::WaitUntil`), so the cadence
//! never caps a renderer that keeps up with a 90 Hz headset or a 240 Hz monitor (frames that
//! reuse the last one, `stereo`'s `reuse.rs`, take about a millisecond). On a tick it redraws
//! only when there is something new to show: a finished stereo frame from the [`Worker`],
//! input, a moving head, an egui animation, or a quarter second gone by; otherwise it just
//! posts the next render request, so the two cores go to tracing rather than to repainting
//! an unchanged window. A redraw takes the newest frame, runs the egui panel, posts the
//! settings as the next render request and presents. Keys and drags are `input.rs`'s, the
//! settings and the request they make `settings.rs`'s, the stderr log `fps_log.rs`'s.
//!
//! The app also keeps what is shown over the eyes ([`Chrome`]): Tab hides the panel, the hint
//! and every other UI pixel, so both eyes are clean for stereo viewing (Tab never reaches
//! egui, which would move its focus with it); ? or F1 opens the key overlay (shown even
//! with the UI hidden, since it was asked for), which Esc closes before it quits. F11 (or
//! the panel's checkbox) switches borderless fullscreen. The scene file is watched (`scene_watch.rs`, polled on the tick): a good save reloads it
//! keeping the head where it is, a broken one keeps the last good scene and shows the error
//! in the panel (and shows the UI if it was hidden). A `.toml` file dropped on the window,
//! or picked in the panel's list, opens at its own head pose.

use std::path::Path;
use std::time::{Duration, Instant};

use anyhow::Context as _;
use tracer::Scene;
use winit::application::ApplicationHandler;
use winit::dpi::LogicalSize;
use winit::event::{ElementState, KeyEvent, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow};
use winit::window::WindowId;

use crate::args::{WindowArgs, DEFAULT_SCENE};
use crate::window::fps_log::{FpsLog, Report};
use crate::window::frame_times::{self, FrameTimes};
use crate::window::input::{self, Command, Input};
use crate::window::os_window::{self, Dump, Size, Window};
use crate::window::present;
use crate::window::scene_watch::{Change, SceneWatch};
use crate::window::screenshot::Screenshots;
use crate::window::settings::Settings;
use crate::window::syslibs;
use crate::window::timing::{RateMeter, SceneClock};
use crate::window::ui::{self, Actions, Readout, SceneReadout};
use crate::window::worker::{FrameInfo, Request, Worker};

/// Time between UI ticks (240 Hz: above VR headsets' 90 and high-refresh monitors' 144, so a
/// fast enough renderer is never held back by the tick that posts its requests).
const FRAME_INTERVAL: Duration = Duration::from_micros(4_167);

/// Longest time between redraws of an otherwise unchanged window (clocks and rates in the
/// panel keep moving).
const IDLE_REDRAW: Duration = Duration::from_millis(250);

/// How often the panel's frame numbers (times, rays, shares, the frame-time plot) are
/// refreshed: they change with every frame, and repainting their text and plot every frame
/// cost the UI thread ~1 ms a frame (egui's software rasteriser redraws whatever changed),
/// time a 2-core machine takes from the tracer; numbers are read at a few updates a second.
const READOUT_REFRESH: Duration = Duration::from_millis(250);

/// How long the hint that Tab hides the UI is shown, unless Tab is pressed first.
const HINT_SHOWN: Duration = Duration::from_secs(12);

/// Opens the window and runs until it is closed, Esc is pressed or `--frames` is reached.
pub fn run(args: &WindowArgs) -> anyhow::Result<()> {
    let scene_path = crate::setup::resolve_scene(args.scene.as_deref().unwrap_or(Path::new(DEFAULT_SCENE)));
    let scene = Scene::load(&scene_path)?;
    let backend = syslibs::backend_from_env()?;
    syslibs::check_runtime_libraries(backend)?;
    let event_loop = os_window::build_event_loop(backend)?;
    let watch = SceneWatch::new(scene_path, scene, Instant::now());
    let mut app = App { viewer: Viewer::new(args, watch)?, state: State::Initial };
    event_loop.run_app(&mut app).context("the window's event loop failed")?;
    app.viewer.finish()
}

/// The event loop's handler: the viewer, and the window once there is one.
struct App {
    viewer: Viewer,
    state: State,
}

/// Whether the window exists yet.
enum State {
    /// Before winit first resumes the app: windows cannot be created yet.
    Initial,
    /// The window is open.
    Running(Box<Window>),
}

/// The window title for a scene file's name.
fn title(name: &str) -> String {
    format!("stereotrace — {name}")
}

/// Options that do not change while the window is open.
struct Config {
    size: LogicalSize<f64>,
    /// `--frames`: stop after this many frames showing the eyes.
    frames: Option<u64>,
}

/// When to redraw: the tick's cadence, and whether anything changed since the last redraw.
struct Pacing {
    /// When the next tick is due.
    next_tick: Instant,
    /// Input arrived, or egui asked for a repaint, since the last redraw.
    dirty: bool,
    /// When the window was last redrawn.
    last_redraw: Instant,
}

/// Frames counted and rates measured as the viewer runs.
struct Meters {
    /// UI frames presented.
    presented: u64,
    /// Frames presented with both eyes of a rendered frame on screen (what `--frames` counts).
    presented_with_eyes: u64,
    /// Sequence number of the newest rendered frame seen.
    last_seq: u64,
    /// Frames presented per second.
    ui: RateMeter,
    /// Stereo frames rendered per second.
    render: RateMeter,
    /// The newest frames' times, for the panel's plot.
    history: FrameTimes,
    /// What the panel shows of them.
    shown: Shown,
}

/// The frame numbers on the panel, as last refreshed ([`READOUT_REFRESH`]).
#[derive(Clone, Debug, Default)]
struct Shown {
    /// When they were taken (`None`: not yet).
    at: Option<Instant>,
    /// The newest frame then.
    frame: Option<FrameInfo>,
    /// The frame times then.
    history: FrameTimes,
    /// The scene time then.
    time: f32,
}

impl Shown {
    /// Takes the newest numbers when the refresh is due at `now`, or at once when the frame
    /// answers another request than the one shown (a setting changed, not only the time)
    /// or `every_frame` (a scripted run, whose dump shows its last frame's numbers).
    fn refresh(
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

/// What is drawn over the eyes besides the panel's contents.
#[derive(Clone, Copy, Debug)]
struct Chrome {
    /// Tab: nothing of the UI is drawn.
    hidden: bool,
    /// The hint that Tab hides the UI shows until this time (or the first Tab).
    hint_until: Option<Instant>,
    /// ? or F1: the key overlay is open.
    keys_open: bool,
}

impl Chrome {
    fn new(now: Instant) -> Self {
        Self { hidden: false, hint_until: Some(now + HINT_SHOWN), keys_open: false }
    }

    /// Tab: hides or shows the UI; the hint has done its job.
    fn toggle_hidden(&mut self) {
        self.hidden ^= true;
        self.hint_until = None;
    }

    /// Whether the hint shows at `now`.
    fn hint(&self, now: Instant) -> bool {
        !self.hidden && self.hint_until.is_some_and(|t| now < t)
    }

    /// Esc: closes the key overlay if it is open; otherwise it means quit (returns true).
    fn escape_quits(&mut self) -> bool {
        !std::mem::take(&mut self.keys_open)
    }
}

/// Everything the viewer keeps that does not depend on the window.
struct Viewer {
    config: Config,
    /// The scene file, watched, and the last good scene from it.
    watch: SceneWatch,
    chrome: Chrome,
    settings: Settings,
    clock: SceneClock,
    worker: Worker,
    egui: egui::Context,
    input: Input,
    pacing: Pacing,
    meters: Meters,
    fps_log: FpsLog,
    screenshots: Screenshots,
    /// `--dump`: the last presented frame, written on exit.
    dump: Option<Dump>,
    /// First error met inside the event loop; `run` returns it.
    error: Option<anyhow::Error>,
}

impl Viewer {
    fn new(args: &WindowArgs, watch: SceneWatch) -> anyhow::Result<Self> {
        let now = Instant::now();
        let mut settings = Settings::from_scene(watch.scene());
        let clock = match args.time {
            Some(t) => SceneClock::paused_at(t),
            None => SceneClock::running(now),
        };
        settings.paused = clock.is_paused();
        settings.live_psnr = args.live_psnr;
        settings.reuse = !args.no_reuse;
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
            },
            worker: Worker::spawn(watch.scene().clone())?,
            watch,
            chrome: Chrome::new(now),
            settings,
            clock,
            egui,
            input: Input::new(now),
            pacing: Pacing { next_tick: now, dirty: true, last_redraw: now },
            meters: Meters {
                presented: 0,
                presented_with_eyes: 0,
                last_seq: 0,
                ui: RateMeter::new(now, 0),
                render: RateMeter::new(now, 0),
                history: FrameTimes::default(),
                shown: Shown::default(),
            },
            fps_log: FpsLog::from_env(),
            screenshots: Screenshots::default(),
            dump: args.dump.clone().map(Dump::new),
            error: None,
        })
    }

    /// After the event loop: report its error, or write the `--dump` PNG.
    fn finish(mut self) -> anyhow::Result<()> {
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        self.dump.as_ref().map_or(Ok(()), Dump::write)
    }

    /// Stops the event loop with an error that `run` will return.
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: anyhow::Error) {
        if self.error.is_none() {
            self.error = Some(error);
        }
        event_loop.exit();
    }

    /// Brings the scene clock in line with the settings (pause and orbit speed) at `now`.
    fn sync_clock(&mut self, now: Instant) {
        self.clock.set_paused(self.settings.paused, now);
        self.clock.set_speed(self.settings.orbit_speed, now);
    }

    /// Does what a key asked for.
    fn apply(&mut self, command: Command, window: &Window, event_loop: &ActiveEventLoop) {
        let s = &mut self.settings;
        match command {
            Command::Quit => {
                if self.chrome.escape_quits() {
                    event_loop.exit();
                }
            }
            Command::ToggleUi => self.chrome.toggle_hidden(),
            Command::ToggleKeys => self.chrome.keys_open ^= true,
            Command::ToggleFullscreen => window.set_fullscreen(!window.is_fullscreen()),
            Command::Save => self.screenshots.save(self.worker.current(), s.look()),
            Command::TogglePause => {
                s.paused ^= true;
                self.sync_clock(Instant::now());
            }
            Command::ToggleMask => s.show_mask ^= true,
            Command::SwapEyes => s.swap_eyes ^= true,
            Command::ResetHead => s.reset_camera(self.watch.scene()),
            Command::Layout(layout) => s.layout = layout,
        }
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
                self.settings.reset_camera(scene);
                self.settings.reset_light(scene);
                window.set_title(&title(self.watch.name()));
            }
            self.worker.set_scene(scene.clone());
        } else if self.watch.failures() > failures {
            // A load just failed: show the UI, which says why.
            self.chrome.hidden = false;
        }
        self.pacing.dirty = true;
    }

    /// Opens a scene file (dropped on the window or picked in the panel).
    fn open(&mut self, path: &Path, window: &Window) {
        let failures = self.watch.failures();
        let change = self.watch.open(path);
        self.adopt(change, failures, window);
    }

    /// Reloads the scene file when a poll is due and it was saved.
    fn poll_scene(&mut self, now: Instant, window: &Window) {
        let failures = self.watch.failures();
        let change = self.watch.poll(now);
        if change.is_some() || self.watch.failures() > failures {
            self.adopt(change, failures, window);
        }
    }

    fn on_window_event(&mut self, window: &mut Window, event_loop: &ActiveEventLoop, event: WindowEvent) {
        // Tab is the viewer's: egui would move its keyboard focus with it.
        let for_egui =
            !matches!(&event, WindowEvent::KeyboardInput { event, .. } if input::hidden_from_egui(&event.logical_key));
        if for_egui {
            window.on_event(&event);
        }
        if !matches!(event, WindowEvent::RedrawRequested) {
            self.pacing.dirty = true;
        }
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            // Focus changes send synthetic presses of the keys held: they are not the user's.
            WindowEvent::KeyboardInput {
                event: KeyEvent { logical_key, physical_key, state, repeat, .. },
                is_synthetic: false,
                ..
            } => {
                let pressed = state == ElementState::Pressed;
                let egui_wants = self.egui.egui_wants_keyboard_input();
                if let Some(command) = self.input.key(physical_key, &logical_key, pressed, repeat, egui_wants) {
                    self.apply(command, window, event_loop);
                }
            }
            WindowEvent::DroppedFile(path) => self.open(&path, window),
            WindowEvent::Focused(false) => self.input.focus_lost(),
            WindowEvent::MouseInput { state, button, .. } => {
                let on_panel = self.egui.is_pointer_over_egui() || self.egui.egui_wants_pointer_input();
                self.input.mouse_button(button, state, on_panel);
            }
            WindowEvent::CursorMoved { position, .. } => {
                if let Some((dx, dy)) = self.input.cursor_moved(position) {
                    self.settings.turn_head(dx, dy);
                }
            }
            WindowEvent::CursorLeft { .. } => self.input.cursor_left(),
            WindowEvent::RedrawRequested => {
                let started = Instant::now();
                if let Err(e) = self.redraw(window, event_loop) {
                    self.fail(event_loop, e);
                }
                self.fps_log.add_redraw(started.elapsed());
            }
            _ => {}
        }
    }

    /// One UI frame: take the newest rendered frame, run the panel, post the next render
    /// request, present. A minimised (zero-sized) window is skipped entirely.
    fn redraw(&mut self, window: &mut Window, event_loop: &ActiveEventLoop) -> anyhow::Result<()> {
        let now = Instant::now();
        self.pacing.dirty = false;
        self.pacing.last_redraw = now;
        let (direction, seconds) = self.input.walk(now);
        self.settings.walk(direction, seconds);
        let Some(size) = Size::of(window.inner_size()) else { return Ok(()) };
        let frame = self.take_frame(size, now);
        let ui = self.panel(window, frame.as_ref(), now);
        self.post_request(size.get(), now);
        self.present(window, size, ui, event_loop)
    }

    /// Swaps in the newest rendered frame and returns what is known about it; records its
    /// times, updates the rates and writes the fps log line when one is due.
    fn take_frame(&mut self, size: Size, now: Instant) -> Option<FrameInfo> {
        let m = &mut self.meters;
        let info = self.worker.latest().info;
        if let Some(info) = info.filter(|i| i.seq != m.last_seq) {
            m.last_seq = info.seq;
            m.history.push(frame_times::sample(info.wall_ms, &info.stats));
        }
        m.render.update(now, m.last_seq);
        if m.ui.update(now, m.presented) {
            self.fps_log.write(&Report {
                ui_fps: m.ui.rate(),
                render_fps: m.render.rate(),
                window: size.get(),
                frame: info.as_ref(),
                settings: &self.settings,
            });
        }
        info
    }

    /// Runs the egui panel over `frame`'s statistics (and the hint, unless the UI is hidden,
    /// and the key overlay when it is open) and applies what the user changed. Returns the
    /// UI to draw: nothing at all when it is hidden and the overlay closed.
    fn panel(&mut self, window: &mut Window, frame: Option<&FrameInfo>, now: Instant) -> egui::FullOutput {
        let raw_input = window.take_egui_input();
        let w = &self.watch;
        let m = &mut self.meters;
        m.shown.refresh(now, (frame, &m.history, self.clock.time(now)), self.config.frames.is_some());
        let readout = Readout {
            ui_fps: m.ui.rate(),
            render_fps: m.render.rate(),
            frame: m.shown.frame.as_ref(),
            time: m.shown.time,
            animated: w.scene().is_animated(),
            history: &m.shown.history,
            saved: self.screenshots.note.recent(now),
            scene: SceneReadout { name: w.name(), error: w.error(), files: w.files(), folder_error: w.folder_error() },
            fullscreen: window.is_fullscreen(),
        };
        let mut settings = self.settings;
        let mut actions = Actions::default();
        let folder = &mut self.screenshots.folder;
        let chrome = &mut self.chrome;
        let hint = chrome.hint(now);
        let mut output = self.egui.run_ui(raw_input, |ui| {
            // Asked for, the key overlay shows even with the UI hidden (until closed).
            if chrome.keys_open {
                ui::keys_overlay(ui.ctx(), &mut chrome.keys_open);
            }
            if chrome.hidden {
                return;
            }
            actions = ui::panel(ui.ctx(), &mut settings, &readout, folder);
            if hint {
                ui::tab_hint(ui.ctx());
            }
        });
        self.pacing.dirty |=
            output.viewport_output.get(&egui::ViewportId::ROOT).is_some_and(|v| v.repaint_delay.is_zero());
        window.handle_platform_output(std::mem::take(&mut output.platform_output));
        if actions.reset {
            settings.reset_camera(self.watch.scene());
        }
        if actions.reset_light {
            settings.reset_light(self.watch.scene());
        }
        self.settings = settings;
        self.sync_clock(now);
        if actions.save {
            self.screenshots.save(self.worker.current(), self.settings.look());
        }
        if actions.toggle_fullscreen {
            window.set_fullscreen(!window.is_fullscreen());
        }
        if let Some(path) = actions.open_scene.and_then(|k| self.watch.files().get(k)).cloned() {
            self.open(&path, window);
        }
        output
    }

    /// Posts the render request for a `width` × `height` window at `now` (none for a window
    /// too small to show an eye). The worker ignores a request equal to the last one.
    fn post_request(&mut self, (width, height): (u32, u32), now: Instant) {
        let (eye_w, eye_h) = present::eye_size(width, height);
        if eye_w > 0 {
            let request = self.settings.request(self.watch.scene(), self.clock.time(now), eye_w, eye_h);
            self.worker.post(request);
        }
    }

    /// Presents the frame on screen with `ui` over it, counts it, and ends the run when
    /// `--frames` is reached.
    fn present(
        &mut self,
        window: &mut Window,
        size: Size,
        ui: egui::FullOutput,
        event_loop: &ActiveEventLoop,
    ) -> anyhow::Result<()> {
        let look = self.settings.look();
        let Some(eyes) = window.present(size, self.worker.current(), look, &self.egui, ui, self.dump.as_mut())? else {
            return Ok(());
        };
        let m = &mut self.meters;
        m.presented += 1;
        let (width, height) = size.get();
        if eyes || present::eye_size(width, height).0 == 0 {
            m.presented_with_eyes += 1;
        }
        if self.config.frames.is_some_and(|n| m.presented_with_eyes >= n) {
            event_loop.exit();
        }
        Ok(())
    }

    /// A tick of the 240 Hz cadence: look at the scene file when that is due, redraw when
    /// there is something new to show, else keep the renderer fed.
    fn tick(&mut self, window: Option<&Window>, event_loop: &ActiveEventLoop) {
        if let Err(e) = self.worker.check_alive() {
            self.fail(event_loop, e);
            return;
        }
        let now = Instant::now();
        if now >= self.pacing.next_tick {
            if let Some(window) = window {
                self.poll_scene(now, window);
            }
            let p = &self.pacing;
            // A moving head alone is not a reason to repaint: until the worker has a frame
            // of the new pose there is nothing new to show, and repainting at every tick
            // would take the cores from the tracer (the head walks on every tick below).
            let due = p.dirty || self.worker.has_fresh() || now - p.last_redraw >= IDLE_REDRAW;
            if let Some(window) = window {
                if due {
                    window.request_redraw();
                } else {
                    // Nothing new to show: walk the head and keep the renderer fed (the
                    // scene clock moves on).
                    // (Walked on every tick, so the walk's clock never falls behind.)
                    let (direction, seconds) = self.input.walk(now);
                    if self.input.is_moving() {
                        self.settings.walk(direction, seconds);
                    }
                    let size = window.inner_size();
                    self.post_request((size.width, size.height), now);
                }
            }
            // Keep the cadence, but never try to catch up on missed frames.
            let p = &mut self.pacing;
            p.next_tick = (p.next_tick + FRAME_INTERVAL).max(now + FRAME_INTERVAL / 2);
        }
        event_loop.set_control_flow(ControlFlow::WaitUntil(self.pacing.next_tick));
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if let State::Running(_) = self.state {
            return;
        }
        let v = &mut self.viewer;
        match Window::open(event_loop, &title(v.watch.name()), v.config.size, &v.egui) {
            Ok(window) => {
                window.request_redraw();
                self.state = State::Running(Box::new(window));
            }
            Err(e) => v.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        if let State::Running(window) = &mut self.state {
            self.viewer.on_window_event(window, event_loop, event);
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let window = match &self.state {
            State::Initial => None,
            State::Running(window) => Some(&**window),
        };
        self.viewer.tick(window, event_loop);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use stereo::FrameStats;

    #[test]
    fn tab_hides_the_ui_and_ends_the_hint_and_esc_closes_the_overlay_first() {
        let t0 = Instant::now();
        let mut chrome = Chrome::new(t0);
        assert!(!chrome.hidden && chrome.hint(t0), "the UI and the hint show at first");
        assert!(!chrome.hint(t0 + HINT_SHOWN), "the hint goes by itself after a while");
        chrome.toggle_hidden();
        assert!(chrome.hidden && !chrome.hint(t0), "Tab hides everything");
        chrome.toggle_hidden();
        assert!(!chrome.hidden && !chrome.hint(t0), "Tab again shows the UI; the hint has done its job");
        chrome.keys_open = true;
        assert!(!chrome.escape_quits(), "Esc closes the key overlay first");
        assert!(!chrome.keys_open, "closed");
        assert!(chrome.escape_quits(), "then Esc quits");
    }

    #[test]
    fn the_panel_numbers_refresh_a_few_times_a_second_or_when_a_setting_changes() {
        let scene = Scene::from_toml("[[spheres]]\ncenter = [0.0, 0.0, 10.0]\nradius = 1.0\n", "s.toml").unwrap();
        let settings = Settings::from_scene(&scene);
        let info = |seq: u64, time: f32, width: u32| {
            let request = settings.request(&scene, time, width, 8);
            FrameInfo {
                seq,
                request,
                samples: request.samples,
                stats: FrameStats::default(),
                quality: None,
                wall_ms: 1.0,
            }
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
