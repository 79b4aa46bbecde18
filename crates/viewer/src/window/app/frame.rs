//! The viewer's frame loop: a tick of the 240 Hz cadence (paced with
//! `ControlFlow::WaitUntil`, so the cadence never caps a renderer that keeps up with a 90 Hz
//! headset or a 240 Hz monitor: frames that reuse the last one, `stereo`'s `reuse/`, take
//! about a millisecond) redraws only when there is something new to show — a finished stereo
//! frame from the [`Worker`](crate::window::worker::Worker), input, a moving head, an egui
//! animation, or a quarter second gone by; otherwise it just posts the next render request,
//! so the two cores go to tracing rather than to repainting an unchanged window. A redraw
//! walks the head once, takes the newest frame, runs the egui panel, posts the settings as
//! the next render request and presents; the request's head pose is the redraw's one pose,
//! which the timewarp warps the newest frame to.

use std::time::{Duration, Instant};

use tracer::Camera;
use winit::event_loop::{ActiveEventLoop, ControlFlow};

use super::viewer::Viewer;
use crate::window::display::{self, Tick};
use crate::window::fps_log::Report;
use crate::window::frame_times;
use crate::window::os_window::{Size, Window};
use crate::window::present;
use crate::window::ui::{self, Actions, Motion, Readout, SceneReadout};
use crate::window::worker::{FrameInfo, Request};

/// Time between UI ticks (240 Hz: above VR headsets' 90 and high-refresh monitors' 144, so a
/// fast enough renderer is never held back by the tick that posts its requests).
const FRAME_INTERVAL: Duration = Duration::from_micros(4_167);

impl Viewer {
    /// One UI frame: walk the head, take the newest rendered frame, run the panel, post the
    /// next render request, present. A minimised (zero-sized) window is skipped entirely.
    pub(super) fn redraw(&mut self, window: &mut Window, event_loop: &ActiveEventLoop) -> anyhow::Result<()> {
        let now = Instant::now();
        self.pacing.dirty = false;
        self.pacing.last_redraw = now;
        // The input step: the head walks once, for the time since its last walk.
        let (direction, seconds) = self.input.walk(now);
        self.settings.walk(direction, seconds);
        let Some(size) = Size::of(window.inner_size()) else { return Ok(()) };
        let frame = self.take_frame(size, now);
        self.shown = self.shown_pose(frame.as_ref(), now);
        let ui = self.panel(window, frame.as_ref(), now);
        // The redraw's head pose, with what the panel changed: asked of the tracer, and
        // what the timewarp shows (none when the window is too small for an eye).
        let pose = self.post_request(size.get(), now).map(|request| request.camera);
        self.present(window, size, pose, ui, event_loop)
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
            m.pose.update(now);
            self.fps_log.write(&Report {
                ui_fps: m.ui.rate(),
                render_fps: m.render.rate(),
                window: size.get(),
                frame: info.as_ref(),
                settings: &self.settings,
                ui_hidden: self.chrome.hidden,
                pose_fps: m.pose.rate(),
                medians: m.pose.medians(),
                warp: self.settings.timewarp.then(|| self.timewarp.last()),
            });
        }
        info
    }

    /// The pose and scene time of the picture this redraw shows: with the timewarp, the
    /// head's pose now (the frame is warped to it); without it, the pose the frame was
    /// traced at. Picks and their labels are projected through it.
    fn shown_pose(&self, frame: Option<&FrameInfo>, now: Instant) -> Option<(Camera, f32)> {
        let time = frame.map_or_else(|| self.clock.time(now), |f| f.request.time);
        if self.settings.timewarp {
            Some((self.settings.camera(&self.watch.scene().camera), time))
        } else {
            frame.map(|f| (f.views.camera, time))
        }
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
            motion: Motion {
                pose_fps: m.pose.rate(),
                medians: m.pose.medians(),
                warp: self.settings.timewarp.then(|| self.timewarp.last()),
            },
        };
        let mut settings = self.settings;
        let mut actions = Actions::default();
        let folder = &mut self.screenshots.folder;
        let chrome = &mut self.chrome;
        let hint = chrome.hint(now);
        let note = super::chrome::progress(w.loading(), self.worker.building(), now);
        let (picks, shown, look) = (&mut self.picks, self.shown, self.settings.look());
        let inner = window.inner_size();
        let mut output = self.egui.run_ui(raw_input, |ui| {
            if let Some(note) = &note {
                ui::progress(ui.ctx(), note);
            }
            // The picks' rings and labels belong to the stereo picture: drawn with the UI
            // hidden too.
            if let Some((camera, _)) = shown {
                picks.draw(ui.ctx(), &camera, (inner.width, inner.height), look);
            }
            // Asked for, the key overlay shows even with the UI hidden (until closed).
            if chrome.keys_open {
                ui::keys_overlay(ui.ctx(), &mut chrome.keys_open);
            }
            if chrome.hidden {
                return;
            }
            actions = ui::panel(ui.ctx(), &mut settings, &readout, folder);
            picks.panel(ui.ctx());
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
            self.open(&path);
        }
        output
    }

    /// Posts the render request for a `width` × `height` window at `now`, and returns it
    /// (none for a window too small to show an eye), as `display::post` does for every tick.
    fn post_request(&mut self, (width, height): (u32, u32), now: Instant) -> Option<Request> {
        let eye = present::eye_size(width, height);
        let moving = self.input.is_moving();
        display::post(&mut self.worker, &self.settings, (self.watch.scene(), self.clock.time(now)), eye, moving)
    }

    /// Presents the frame on screen with `ui` over it — with the timewarp on, the traced
    /// frame warped to `pose`, the redraw's head pose — counts it, and ends the run when
    /// `--frames` is reached.
    fn present(
        &mut self,
        window: &mut Window,
        size: Size,
        pose: Option<Camera>,
        ui: egui::FullOutput,
        event_loop: &ActiveEventLoop,
    ) -> anyhow::Result<()> {
        let look = self.settings.look();
        let pose = pose.filter(|_| self.settings.timewarp);
        let shown = display::show(self.worker.current(), &mut self.timewarp, pose, look);
        let Some(eyes) = window.present(size, shown.eyes, look, &self.egui, ui, self.dump.as_mut())? else {
            return Ok(());
        };
        let m = &mut self.meters;
        m.presented += 1;
        if let (true, Some((pose, pose_at)), Some(info)) = (eyes, shown.pose, shown.info) {
            m.pose.presented(&pose, pose_at, info.posted, Instant::now());
        }
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
    pub(super) fn tick(&mut self, window: Option<&Window>, event_loop: &ActiveEventLoop) {
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
            // (The head walks on every tick below, redrawn or not.)
            let timewarp = self.settings.timewarp;
            let due = display::due(Tick {
                dirty: p.dirty,
                fresh: self.worker.has_fresh(),
                since_redraw: now - p.last_redraw,
                timewarp,
                moving: self.input.is_moving(),
            });
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
            // Keep the cadence (the display's with the timewarp), but never try to catch up
            // on missed frames.
            let interval = if timewarp { self.config.display_interval } else { FRAME_INTERVAL };
            let p = &mut self.pacing;
            p.next_tick = display::next_tick(p.next_tick, now, interval);
        }
        event_loop.set_control_flow(ControlFlow::WaitUntil(self.pacing.next_tick));
    }
}
