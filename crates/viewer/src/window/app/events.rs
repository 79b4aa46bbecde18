//! The window's events: keys and drags (`input.rs` turns them into commands and head
//! movement), a dropped scene file, focus, and the redraw winit asks for. Tab never reaches
//! egui, which would move its keyboard focus with it; F11 switches borderless fullscreen.

use std::time::Instant;

use winit::event::{ElementState, KeyEvent, MouseButton, WindowEvent};
use winit::event_loop::ActiveEventLoop;

use super::viewer::Viewer;
use crate::window::input::{self, Command, Input};
use crate::window::os_window::Window;

impl Viewer {
    /// Handles one event of the window.
    pub(super) fn on_window_event(&mut self, window: &mut Window, event_loop: &ActiveEventLoop, event: WindowEvent) {
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
                if pressed && !egui_wants && Input::moves_head(physical_key) {
                    // A press or a repeat: the head moves from the next walk on.
                    self.meters.pose.input(Instant::now());
                }
                if let Some(command) = self.input.key(physical_key, &logical_key, pressed, repeat, egui_wants) {
                    self.apply(command, window, event_loop);
                }
            }
            WindowEvent::DroppedFile(path) => self.open(&path),
            WindowEvent::Focused(false) => self.input.focus_lost(),
            WindowEvent::MouseInput { state, button, .. } => {
                let on_panel = self.egui.is_pointer_over_egui() || self.egui.egui_wants_pointer_input();
                self.input.mouse_button(button, state, on_panel);
                if button == MouseButton::Left {
                    self.left_button(window, state == ElementState::Pressed, on_panel);
                }
            }
            WindowEvent::CursorMoved { position, .. } => {
                self.cursor = Some((position.x, position.y));
                if let Some((dx, dy)) = self.input.cursor_moved(position) {
                    self.settings.turn_head(dx, dy);
                    self.meters.pose.input(Instant::now());
                }
            }
            WindowEvent::CursorLeft { .. } => {
                self.input.cursor_left();
                self.cursor = None;
            }
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

    /// Does what a key asked for.
    fn apply(&mut self, command: Command, window: &Window, event_loop: &ActiveEventLoop) {
        let s = &mut self.settings;
        match command {
            // Esc closes the key overlay, else clears the picks, else quits.
            Command::Quit => {
                if self.chrome.escape_quits() && !self.picks.clear() {
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
            Command::ToggleTimewarp => s.timewarp ^= true,
            Command::SwapEyes => s.swap_eyes ^= true,
            Command::CycleColor => s.atoms.cycle(),
            Command::ResetHead => s.reset_camera(self.watch.scene()),
            Command::Layout(layout) => s.layout = layout,
        }
    }
}

impl Viewer {
    /// The left button went down or up: a click (a release near its press, off the panel)
    /// picks in the picture on screen.
    fn left_button(&mut self, window: &Window, pressed: bool, on_panel: bool) {
        let Some(at) = self.picks.button(pressed, on_panel, self.cursor) else { return };
        let Some((camera, time)) = self.shown else { return };
        let size = window.inner_size();
        let look = self.settings.look();
        // The scene the worker traces: without the hidden atoms, whose object ids the
        // picture's are (a copy per click while atoms are hidden, none otherwise).
        let hide = self.settings.atoms.hide;
        let hidden = (!hide.is_empty()).then(|| self.watch.scene().hidden(hide));
        let scene = hidden.as_ref().unwrap_or_else(|| self.watch.scene());
        let Some((eye, (i, j), object)) = self.picks.click((scene, time, &camera), (size.width, size.height), look, at)
        else {
            return;
        };
        self.pacing.dirty = true;
        let eye = if eye == tracer::Eye::Left { "left" } else { "right" };
        match (object, self.picks.picked.last()) {
            (Some(object), Some(p)) => eprintln!("pick: {eye} eye pixel ({i}, {j}): sphere {object} {}", p.label),
            _ => eprintln!("pick: {eye} eye pixel ({i}, {j}): nothing (picks cleared)"),
        }
    }
}
