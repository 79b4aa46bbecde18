//! The viewer window: a winit 0.30 [`ApplicationHandler`] that shows the two eyes side by side
//! with softbuffer and an egui panel over them.
//!
//! The UI ticks 60 times a second (paced with `ControlFlow::WaitUntil`). On a tick it redraws
//! only when there is something new to show: a finished stereo frame from the [`Worker`],
//! input, a moving head, an egui animation, or a quarter second gone by; otherwise it just
//! posts the next render request, so the two cores go to tracing rather than to repainting
//! an unchanged window. A redraw takes the newest frame, runs the egui panel, posts the
//! settings as the next render request, composes the eyes into the softbuffer frame,
//! rasterises the UI over them (`egui_software_backend`) and presents once. Tracing happens
//! only on the worker thread, never while the softbuffer buffer is held.
//!
//! Keys (ignored while egui has keyboard focus, e.g. typing a slider value): W/Up and Down
//! move the head forward and back, A/Left and D/Right sideways (held: [`ui::HEAD_SPEED`]
//! units a second along the head's own axes); R resets the head; 1, 2, 3 choose side-by-side,
//! cross-eyed, anaglyph; X swaps the eyes; M toggles the debug mask; Space pauses the
//! revolving spheres; S saves screenshots; Esc quits. Dragging with the right mouse button,
//! or the left one outside the panel, turns the head. Both eyes share the head pose, so
//! moving never breaks the reprojection.

use std::num::NonZeroU32;
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::time::{Duration, Instant, SystemTime};

use anyhow::Context as _;
use egui_software_backend::{BufferMutRef, ColorFieldOrder, EguiSoftwareRender};
use tracer::Scene;
use winit::application::ApplicationHandler;
use winit::dpi::LogicalSize;
use winit::dpi::PhysicalPosition;
use winit::event::{ElementState, KeyEvent, MouseButton, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, KeyCode, NamedKey, PhysicalKey};
use winit::window::{Window, WindowId};

use crate::cli::{WindowArgs, DEFAULT_SCENE};
use crate::present::{self, Compositor, Look};
use crate::screenshot;
use crate::syslibs::{self, Backend};
use crate::timing::{RateMeter, SceneClock};
use crate::ui::{self, FrameTimes, Readout, Settings};
use crate::worker::{Request, Worker};

/// Time between UI ticks (60 Hz).
const FRAME_INTERVAL: Duration = Duration::from_micros(16_667);

/// Longest time between redraws of an otherwise unchanged window (clocks and rates in the
/// panel keep moving).
const IDLE_REDRAW: Duration = Duration::from_millis(250);

/// Longest time step a held movement key advances the head by, so a stall does not jump.
const MAX_MOVE_STEP: f32 = 0.1;

/// How long the panel shows where the last screenshot went.
const SAVED_NOTE: Duration = Duration::from_secs(6);

/// Movement keys held down: forward, back, left, right.
#[derive(Clone, Copy, Debug, Default)]
struct HeldKeys([bool; 4]);

impl HeldKeys {
    /// The movement slot of a physical key (layout-independent, so W/A/D are where they are
    /// on a QWERTY keyboard), if it is one.
    fn slot(key: PhysicalKey) -> Option<usize> {
        match key {
            PhysicalKey::Code(KeyCode::KeyW | KeyCode::ArrowUp) => Some(0),
            PhysicalKey::Code(KeyCode::ArrowDown) => Some(1),
            PhysicalKey::Code(KeyCode::KeyA | KeyCode::ArrowLeft) => Some(2),
            PhysicalKey::Code(KeyCode::KeyD | KeyCode::ArrowRight) => Some(3),
            _ => None,
        }
    }

    /// (forward, right) in −1..=1.
    fn direction(self) -> (f32, f32) {
        let axis = |plus: bool, minus: bool| f32::from(u8::from(plus)) - f32::from(u8::from(minus));
        (axis(self.0[0], self.0[1]), axis(self.0[3], self.0[2]))
    }
}

/// Mouse state for turning the head by dragging.
#[derive(Clone, Copy, Debug, Default)]
struct Drag {
    /// Last cursor position in the window, physical pixels.
    cursor: Option<PhysicalPosition<f64>>,
    /// A turning drag is under way.
    active: bool,
}

/// Opens the window and runs until it is closed, Esc is pressed or `--frames` is reached.
pub fn run(args: &WindowArgs) -> anyhow::Result<()> {
    let scene_path = crate::setup::resolve_scene(args.scene.as_deref().unwrap_or(Path::new(DEFAULT_SCENE)));
    let scene = Scene::load(&scene_path)?;
    let backend = syslibs::backend_from_env()?;
    syslibs::check_runtime_libraries(backend)?;
    let event_loop = build_event_loop(backend)?;
    let name = scene_path.file_name().map_or_else(|| scene_path.display().to_string(), |n| n.to_string_lossy().into());
    let mut app = App::new(args, scene, format!("stereotrace — {name}"))?;
    event_loop.run_app(&mut app).context("the window's event loop failed")?;
    app.finish()
}

/// The event loop on the chosen backend, with a clear error if the display cannot be opened.
fn build_event_loop(backend: Backend) -> anyhow::Result<EventLoop<()>> {
    let mut builder = EventLoop::builder();
    #[cfg(any(
        target_os = "linux",
        target_os = "freebsd",
        target_os = "dragonfly",
        target_os = "netbsd",
        target_os = "openbsd"
    ))]
    match backend {
        Backend::X11 => {
            winit::platform::x11::EventLoopBuilderExtX11::with_x11(&mut builder);
        }
        Backend::Wayland => {
            winit::platform::wayland::EventLoopBuilderExtWayland::with_wayland(&mut builder);
        }
    }
    builder.build().with_context(|| match backend {
        Backend::X11 => format!(
            "cannot open the X11 display {:?} (is the X server running? headless: xvfb-run -a stereotrace)",
            std::env::var("DISPLAY").unwrap_or_default()
        ),
        Backend::Wayland => format!(
            "cannot connect to the Wayland display {:?}; set DISPLAY to use X11 (XWayland) instead",
            std::env::var("WAYLAND_DISPLAY").unwrap_or_default()
        ),
    })
}

/// Options that do not change while the window is open.
struct Config {
    title: String,
    size: LogicalSize<f64>,
    /// `--frames`: stop after this many frames showing the eyes.
    frames: Option<u64>,
    /// `--dump`: write the last presented frame here on exit.
    dump: Option<PathBuf>,
    /// `STEREOTRACE_LOG_FPS=1`: print the frame rates to stderr.
    log_fps: bool,
}

/// The window and everything tied to it; exists between `resumed` and exit.
struct Gfx {
    window: Rc<Window>,
    surface: softbuffer::Surface<Rc<Window>, Rc<Window>>,
    egui_winit: egui_winit::State,
}

/// The whole viewer state, owned by the event loop.
struct App {
    config: Config,
    scene: Scene,
    settings: Settings,
    clock: SceneClock,
    worker: Worker,
    gfx: Option<Gfx>,
    egui: egui::Context,
    egui_render: EguiSoftwareRender,
    compositor: Compositor,
    history: FrameTimes,
    ui_meter: RateMeter,
    render_meter: RateMeter,
    /// UI frames presented.
    presented: u64,
    /// Frames presented with both eyes of a rendered frame on screen (what `--frames` counts).
    presented_with_eyes: u64,
    /// Sequence number of the newest rendered frame seen.
    last_seq: u64,
    next_redraw: Instant,
    /// Input arrived, or egui asked for a repaint, since the last redraw.
    dirty: bool,
    /// When the window was last redrawn.
    last_redraw: Instant,
    /// Time spent in `redraw` and frames drawn since the last fps log line.
    ui_busy: (Duration, u32),
    /// Copy of the last presented frame, kept only with `--dump`.
    dump: (Vec<u32>, u32, u32),
    /// First error met inside the event loop; `run` returns it.
    error: Option<anyhow::Error>,
    held: HeldKeys,
    drag: Drag,
    /// When the head was last moved by held keys.
    last_move: Instant,
    /// Screenshot folder, as typed in the panel.
    folder: String,
    /// What the last screenshot wrote (or why it failed), and when.
    saved: Option<(String, Instant)>,
}

impl App {
    fn new(args: &WindowArgs, scene: Scene, title: String) -> anyhow::Result<Self> {
        let now = Instant::now();
        let mut settings = Settings::from_scene(&scene);
        let clock = match args.time {
            Some(t) => SceneClock::paused_at(t),
            None => SceneClock::running(now),
        };
        settings.paused = clock.is_paused();
        settings.live_psnr = args.live_psnr;
        let egui = egui::Context::default();
        ui::setup_style(&egui);
        Ok(Self {
            config: Config {
                title,
                size: LogicalSize::new(f64::from(args.width), f64::from(args.height)),
                frames: args.frames,
                dump: args.dump.clone(),
                log_fps: std::env::var("STEREOTRACE_LOG_FPS").is_ok_and(|v| v == "1"),
            },
            worker: Worker::spawn(scene.clone())?,
            scene,
            settings,
            clock,
            gfx: None,
            egui,
            egui_render: EguiSoftwareRender::new(ColorFieldOrder::Bgra),
            compositor: Compositor::default(),
            history: FrameTimes::default(),
            ui_meter: RateMeter::new(now, 0),
            render_meter: RateMeter::new(now, 0),
            presented: 0,
            presented_with_eyes: 0,
            last_seq: 0,
            next_redraw: now,
            dirty: true,
            last_redraw: now,
            ui_busy: (Duration::ZERO, 0),
            dump: (Vec::new(), 0, 0),
            error: None,
            held: HeldKeys::default(),
            drag: Drag::default(),
            last_move: now,
            folder: screenshot::DEFAULT_FOLDER.to_owned(),
            saved: None,
        })
    }

    /// After the event loop: report its error, or write the `--dump` PNG.
    fn finish(mut self) -> anyhow::Result<()> {
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        if let Some(path) = &self.config.dump {
            let (pixels, w, h) = &self.dump;
            if pixels.is_empty() {
                anyhow::bail!("no frame was presented, so there is nothing to write to {}", path.display());
            }
            viewer::write_png(path, *w, *h, pixels)?;
        }
        Ok(())
    }

    /// Stops the event loop with an error that `run` will return.
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: anyhow::Error) {
        if self.error.is_none() {
            self.error = Some(error);
        }
        event_loop.exit();
    }

    fn create_window(&self, event_loop: &ActiveEventLoop) -> anyhow::Result<Gfx> {
        let attrs = Window::default_attributes().with_title(&self.config.title).with_inner_size(self.config.size);
        let window = Rc::new(event_loop.create_window(attrs).context("cannot create the window")?);
        let context = softbuffer::Context::new(Rc::clone(&window))
            .map_err(|e| anyhow::anyhow!("cannot start softbuffer: {e}"))?;
        let surface = softbuffer::Surface::new(&context, Rc::clone(&window))
            .map_err(|e| anyhow::anyhow!("cannot create the softbuffer surface: {e}"))?;
        let egui_winit = egui_winit::State::new(
            self.egui.clone(),
            egui::ViewportId::ROOT,
            &window,
            Some(window.scale_factor() as f32),
            window.theme(),
            None,
        );
        Ok(Gfx { window, surface, egui_winit })
    }

    fn set_paused(&mut self, paused: bool) {
        self.settings.paused = paused;
        self.clock.set_paused(paused, Instant::now());
    }

    fn on_key(&mut self, key: &Key, event_loop: &ActiveEventLoop) {
        match key {
            Key::Named(NamedKey::Escape) => event_loop.exit(),
            Key::Named(NamedKey::Space) => self.set_paused(!self.settings.paused),
            Key::Character(c) if c.eq_ignore_ascii_case("m") => self.settings.show_mask ^= true,
            Key::Character(c) if c.eq_ignore_ascii_case("s") => self.save_pair(),
            Key::Character(c) if c.eq_ignore_ascii_case("x") => self.settings.swap_eyes ^= true,
            Key::Character(c) if c.eq_ignore_ascii_case("r") => self.settings.reset_camera(&self.scene),
            Key::Character(c) => {
                if let Some(&layout) = c.parse::<usize>().ok().and_then(|k| stereo::Layout::ALL.get(k.wrapping_sub(1)))
                {
                    self.settings.layout = layout;
                }
            }
            _ => {}
        }
    }

    /// Movement keys: a press counts only when egui does not want the keyboard, a release
    /// always (so a key never sticks).
    fn on_movement_key(&mut self, key: PhysicalKey, pressed: bool) {
        if let Some(slot) = HeldKeys::slot(key) {
            if !pressed || !self.egui.egui_wants_keyboard_input() {
                self.held.0[slot] = pressed;
            }
        }
    }

    /// Mouse buttons: the right one always starts a turning drag, the left one only outside
    /// the panel.
    fn on_mouse_button(&mut self, button: MouseButton, state: ElementState) {
        let starts = match button {
            MouseButton::Right => true,
            MouseButton::Left => !self.egui.is_pointer_over_egui() && !self.egui.egui_wants_pointer_input(),
            _ => return,
        };
        match state {
            ElementState::Pressed if starts => self.drag.active = true,
            ElementState::Pressed => {}
            ElementState::Released => self.drag.active = false,
        }
    }

    fn on_cursor_moved(&mut self, position: PhysicalPosition<f64>) {
        if let (true, Some(last)) = (self.drag.active, self.drag.cursor) {
            self.settings.turn_head((position.x - last.x) as f32, (position.y - last.y) as f32);
        }
        self.drag.cursor = Some(position);
    }

    /// Moves the head for the keys held since the last call.
    fn move_head(&mut self, now: Instant) {
        let dt = now.saturating_duration_since(self.last_move).as_secs_f32().min(MAX_MOVE_STEP);
        self.last_move = now;
        let (forward, right) = self.held.direction();
        if forward != 0.0 || right != 0.0 {
            let step = ui::HEAD_SPEED * dt;
            self.settings.move_head(forward * step, right * step);
        }
    }

    /// Writes the frame on screen as PNGs into the screenshot folder; the panel says where
    /// (or why not), and so does stderr. The viewer carries on either way.
    fn save_pair(&mut self) {
        let s = &self.settings;
        let folder = PathBuf::from(if self.folder.trim().is_empty() { "." } else { self.folder.trim() });
        let look = Look { layout: s.layout, swap: s.swap_eyes, show_mask: s.show_mask };
        let note = match screenshot::save(&folder, self.worker.current(), look, SystemTime::now()) {
            Ok(paths) => {
                for p in &paths {
                    eprintln!("stereotrace: saved {}", p.display());
                }
                let names: Vec<String> =
                    paths.iter().filter_map(|p| p.file_name()).map(|n| n.to_string_lossy().into_owned()).collect();
                format!("saved in {}:\n{}", folder.display(), names.join("\n"))
            }
            Err(e) => {
                eprintln!("stereotrace: {e:#}");
                format!("not saved: {e:#}")
            }
        };
        self.saved = Some((note, Instant::now()));
    }

    /// The render request for the current settings and an eye of `width` × `height` on screen.
    fn request(&self, width: u32, height: u32, now: Instant) -> Request {
        let s = &self.settings;
        let (width, height) = s.render_size(width, height);
        let anaglyph = s.layout == stereo::Layout::Anaglyph;
        Request {
            camera: s.camera(&self.scene.camera),
            depth: s.depth,
            opts: s.options(),
            time: if self.scene.is_animated() { self.clock.time(now) } else { 0.0 },
            width,
            height,
            psnr: s.live_psnr,
            anaglyph,
            swap: anaglyph && s.swap_eyes,
            light: s.light,
        }
    }

    /// Posts the render request for a `width` × `height` window at `now` (none for a
    /// minimised window). The worker ignores a request equal to the last one.
    fn post_request(&mut self, width: u32, height: u32, now: Instant) {
        let (eye_w, eye_h) = present::eye_size(width, height);
        if eye_w > 0 {
            let request = self.request(eye_w, eye_h, now);
            self.worker.post(request);
        }
    }

    /// One UI frame. A minimised (zero-sized) window is skipped entirely.
    fn redraw(&mut self, event_loop: &ActiveEventLoop) -> anyhow::Result<()> {
        let now = Instant::now();
        self.dirty = false;
        self.last_redraw = now;
        self.move_head(now);
        let Some(gfx) = self.gfx.as_mut() else { return Ok(()) };
        let size = gfx.window.inner_size();
        let (Some(nz_w), Some(nz_h)) = (NonZeroU32::new(size.width), NonZeroU32::new(size.height)) else {
            return Ok(());
        };
        let (width, height) = (size.width as usize, size.height as usize);

        // The newest rendered frame, and the rates.
        let info = self.worker.latest().info;
        if let Some(info) = info.filter(|i| i.seq != self.last_seq) {
            self.last_seq = info.seq;
            self.history.push(ui::sample(info.wall_ms, &info.stats));
        }
        self.render_meter.update(now, self.last_seq);
        if self.ui_meter.update(now, self.presented) && self.config.log_fps {
            let s = &self.settings;
            let (busy, frames) = std::mem::take(&mut self.ui_busy);
            eprintln!(
                "fps={:.1} render_fps={:.1} ui_ms={:.2} window={}x{} left_ms={:.1} right_ms={:.1} \
                 head={:.3},{:.3},{:.3} yaw={:.1} pitch={:.1} layout={} swap={} psnr={}",
                self.ui_meter.rate(),
                self.render_meter.rate(),
                busy.as_secs_f64() * 1e3 / f64::from(frames.max(1)),
                size.width,
                size.height,
                info.map_or(0.0, |i| i.stats.left.ms),
                info.map_or(0.0, |i| i.stats.right.ms),
                s.position.x,
                s.position.y,
                s.position.z,
                s.yaw_deg,
                s.pitch_deg,
                s.layout,
                s.swap_eyes,
                info.and_then(|i| i.quality).map_or_else(|| "-".to_owned(), |q| format!("{:.2}", q.psnr_db)),
            );
        }

        // The panel.
        let raw_input = gfx.egui_winit.take_egui_input(&gfx.window);
        let readout = Readout {
            ui_fps: self.ui_meter.rate(),
            render_fps: self.render_meter.rate(),
            frame: info.as_ref(),
            time: self.clock.time(now),
            animated: self.scene.is_animated(),
            history: &self.history,
            saved: self.saved.as_ref().filter(|(_, at)| now.saturating_duration_since(*at) < SAVED_NOTE).map(|s| &*s.0),
        };
        let mut settings = self.settings;
        let mut actions = ui::Actions::default();
        let folder = &mut self.folder;
        let output = self.egui.run_ui(raw_input, |ui| actions = ui::panel(ui.ctx(), &mut settings, &readout, folder));
        let repaint_now =
            output.viewport_output.get(&egui::ViewportId::ROOT).is_some_and(|v| v.repaint_delay.is_zero());
        self.dirty |= repaint_now;
        gfx.egui_winit.handle_platform_output(&gfx.window, output.platform_output);
        if actions.reset {
            settings.reset_camera(&self.scene);
        }
        if actions.reset_light {
            settings.light = Settings::from_scene(&self.scene).light;
        }
        let paused = settings.paused;
        self.settings = settings;
        self.set_paused(paused);
        self.clock.set_speed(settings.orbit_speed, now);
        if actions.save {
            self.save_pair();
        }

        // The next render request.
        let (eye_w, _) = present::eye_size(size.width, size.height);
        self.post_request(size.width, size.height, now);

        // Compose, draw the UI over the eyes, present once.
        let Some(gfx) = self.gfx.as_mut() else { return Ok(()) };
        gfx.surface.resize(nz_w, nz_h).map_err(|e| anyhow::anyhow!("cannot resize the frame buffer: {e}"))?;
        let mut buffer = gfx.surface.buffer_mut().map_err(|e| anyhow::anyhow!("cannot map the frame buffer: {e}"))?;
        if buffer.len() != width * height {
            // The surface does not match the window yet (a resize in flight): skip this frame.
            return Ok(());
        }
        let frame = self.worker.current();
        let s = &self.settings;
        let look = Look { layout: s.layout, swap: s.swap_eyes, show_mask: s.show_mask };
        let eyes = self.compositor.compose(&mut buffer, width, height, frame, look);
        let primitives = self.egui.tessellate(output.shapes, output.pixels_per_point);
        self.egui_render.render(
            &mut BufferMutRef::new(bytemuck::cast_slice_mut(&mut buffer[..]), width, height),
            &primitives,
            &output.textures_delta,
            output.pixels_per_point,
        );
        let rows = present::ui_rows(&primitives, output.pixels_per_point, height);
        present::clear_alpha(&mut buffer[rows.start * width..rows.end * width]);
        if self.config.dump.is_some() {
            let (pixels, w, h) = &mut self.dump;
            pixels.clear();
            pixels.extend_from_slice(&buffer);
            (*w, *h) = (size.width, size.height);
        }
        buffer.present().map_err(|e| anyhow::anyhow!("cannot present the frame: {e}"))?;
        self.presented += 1;
        if eyes || eye_w == 0 {
            self.presented_with_eyes += 1;
        }
        if self.config.frames.is_some_and(|n| self.presented_with_eyes >= n) {
            event_loop.exit();
        }
        Ok(())
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.gfx.is_some() {
            return;
        }
        match self.create_window(event_loop) {
            Ok(gfx) => {
                gfx.window.request_redraw();
                self.gfx = Some(gfx);
            }
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let Some(gfx) = self.gfx.as_mut() else { return };
        // egui sees every event; its `repaint` hint is not needed, the UI redraws at a fixed rate.
        let _ = gfx.egui_winit.on_window_event(&gfx.window, &event);
        if !matches!(event, WindowEvent::RedrawRequested) {
            self.dirty = true;
        }
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::KeyboardInput {
                event: KeyEvent { logical_key, physical_key, state, repeat, .. },
                is_synthetic: false,
                ..
            } => {
                let pressed = state == ElementState::Pressed;
                self.on_movement_key(physical_key, pressed);
                if pressed && !repeat && !self.egui.egui_wants_keyboard_input() {
                    self.on_key(&logical_key, event_loop);
                }
            }
            WindowEvent::Focused(false) => {
                self.held = HeldKeys::default();
                self.drag.active = false;
            }
            WindowEvent::MouseInput { state, button, .. } => self.on_mouse_button(button, state),
            WindowEvent::CursorMoved { position, .. } => self.on_cursor_moved(position),
            WindowEvent::CursorLeft { .. } => self.drag.cursor = None,
            WindowEvent::RedrawRequested => {
                let started = Instant::now();
                if let Err(e) = self.redraw(event_loop) {
                    self.fail(event_loop, e);
                }
                self.ui_busy.0 += started.elapsed();
                self.ui_busy.1 += 1;
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if let Err(e) = self.worker.check_alive() {
            self.fail(event_loop, e);
            return;
        }
        let now = Instant::now();
        if now >= self.next_redraw {
            let moving = self.held.direction() != (0.0, 0.0) || self.drag.active;
            let due = self.dirty || moving || self.worker.has_fresh() || now - self.last_redraw >= IDLE_REDRAW;
            if let Some(size) = self.gfx.as_ref().map(|gfx| gfx.window.inner_size()) {
                if due {
                    self.gfx.as_ref().inspect(|gfx| gfx.window.request_redraw());
                } else {
                    // Nothing new to show: keep the renderer fed (the scene clock moves on).
                    self.post_request(size.width, size.height, now);
                }
            }
            // Keep the cadence, but never try to catch up on missed frames.
            self.next_redraw = (self.next_redraw + FRAME_INTERVAL).max(now + FRAME_INTERVAL / 2);
        }
        event_loop.set_control_flow(ControlFlow::WaitUntil(self.next_redraw));
    }
}
