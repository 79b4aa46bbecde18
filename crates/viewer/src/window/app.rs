//! The viewer window's application: a winit 0.30 [`ApplicationHandler`] that shows the two
//! eyes side by side with softbuffer and an egui panel over them.
//!
//! The app is in one of two states, as in softbuffer's examples: [`State::Initial`] until
//! winit first resumes it, then [`State::Running`] with the open [`Window`]. What does not
//! depend on the window — the scene, the settings, the render worker, the clocks and meters —
//! is the [`Viewer`], which lives through both.
//!
//! The app's parts, in order (each uses only those before it): `chrome` (what is drawn over
//! the eyes: Tab hides the UI, the hint, the key overlay), `meters` (frames counted, rates,
//! the panel's numbers), `viewer` (the [`Viewer`], made from the command line, and the scene
//! changes it adopts), `frame` (the 240 Hz tick and the redraw: newest frame, panel, render
//! request, present), `events` (the window's events and what keys ask for); then this
//! module, the handler that ties them to winit. Keys and drags are `input.rs`'s, the
//! settings and the request they make `settings.rs`'s, the stderr log `fps_log.rs`'s, the
//! watched scene file `scene_watch.rs`'s.

mod chrome;
mod events;
mod frame;
mod meters;
mod viewer;

use std::path::Path;
use std::time::Instant;

use anyhow::Context as _;
use tracer::Scene;
use winit::application::ApplicationHandler;
use winit::event::WindowEvent;
use winit::event_loop::ActiveEventLoop;
use winit::window::WindowId;

use self::viewer::{title, Viewer};
use crate::args::{WindowArgs, DEFAULT_SCENE};
use crate::window::os_window::{self, Window};
use crate::window::scene_watch::SceneWatch;
use crate::window::syslibs;

/// Opens the window and runs until it is closed, Esc is pressed or `--frames` is reached.
pub fn run(args: &WindowArgs) -> anyhow::Result<()> {
    let scene_path = crate::setup::resolve_scene(args.scene.as_deref().unwrap_or(Path::new(DEFAULT_SCENE)));
    let options = crate::setup::load_options(args.assembly, args.radius_scale)?;
    let scene = Scene::load_with(&scene_path, options)?;
    // Before the worker starts: the tracer's threads run below the UI's and the timewarp's.
    crate::window::worker::lower_the_tracer_pool();
    let backend = syslibs::backend_from_env()?;
    syslibs::check_runtime_libraries(backend)?;
    let event_loop = os_window::build_event_loop(backend)?;
    let watch = SceneWatch::new(scene_path, scene, options, Instant::now());
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
