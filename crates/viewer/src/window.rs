//! The viewer window (`stereotrace` with no subcommand): two eye images side by side in a
//! winit window, presented with softbuffer, an egui panel over them, rendered on a worker
//! thread so that the UI never waits for the tracer.
//!
//! The modules, in order: each uses only those listed before it (and the shared modules at
//! the top of the crate: the arguments, the scene setup, the reference trace).
//! - `timing` (scene clock, rate meters), `syslibs` (start-up checks), `frame_times` (the
//!   frame-time history), `input` (keys and drags), `pose_meter` (new poses a second,
//!   input latency, frame age);
//! - `worker` (the render thread and its requests), `present` (a frame into the window's
//!   buffer), `picks` (clicked atoms, their rings and stereo labels, distance and angle),
//!   `timewarp` (the traced frame warped to the head pose of the present), `settings` (the
//!   settings model, head movement, the request), `display` (a display tick's decisions:
//!   redraw or not, the request posted, the picture presented; `replay`'s too), `scene_watch`
//!   (the scene file watched and reloaded, other files opened), `screenshot`, `fps_log`
//!   (the stderr log), `ui` (the panel, drawing only), `os_window` (the window and
//!   presenting into it);
//! - `app`, the event loop's handler, which ties the viewer together (its own parts are
//!   listed in its doc).

pub mod frame_times;
pub mod input;
pub mod pose_meter;
pub mod syslibs;
pub mod timing;

pub mod display;
pub mod fps_log;
pub mod look;
pub mod os_window;
pub mod picks;
pub mod present;
pub mod scene_watch;
pub mod screenshot;
pub mod settings;
pub mod timewarp;
pub mod ui;
pub mod worker;

pub mod app;
