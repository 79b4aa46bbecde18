//! `stereotrace`: the stereo viewer window, and the headless `render`, `bench` and `sweep`
//! commands.
//!
//! Exit codes: 0 success, 2 bad input (scene file, arguments), 1 any other failure.
//!
//! The modules, in order: each uses only modules listed before it (and the package's library,
//! `lib.rs`, for PNG output).
//! - `crop` (a rectangle of an eye image), `cli` (the arguments), `setup` (a scene with the overrides applied, the memory check),
//!   `report` (the JSON keys), `reference` (the full trace quality is measured against);
//! - `render_cmd` and `bench`, the headless commands; `plot` (the sweep's figure) and `sweep`,
//!   which measures with `bench`'s loop;
//! - `timing` (scene clock, rate meters), `syslibs` (start-up checks), `frame_times` (the
//!   frame-time history), `input` (keys and drags);
//! - `worker` (the render thread and its requests), `present` (a frame into the window's
//!   buffer), `settings` (the settings model, head movement, the request), `scene_watch`
//!   (the scene file watched and reloaded, other files opened), `screenshot`,
//!   `fps_log` (the stderr log), `ui` (the panel, drawing only), `window` (the window and
//!   presenting into it);
//! - `app`, the event loop's handler, which ties the viewer together.

mod args;
mod crop;
mod reference;
mod setup;

mod cli {
    pub mod bench;
    pub mod plot;
    pub mod render;
    pub mod report;
    pub mod sweep;
}

mod window {
    pub mod app;
    pub mod fps_log;
    pub mod frame_times;
    pub mod input;
    pub mod os_window;
    pub mod present;
    pub mod scene_watch;
    pub mod screenshot;
    pub mod settings;
    pub mod syslibs;
    pub mod timing;
    pub mod ui;
    pub mod worker;
}

use std::process::ExitCode;

use clap::Parser;

use crate::args::{Cli, Command};

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = setup::check_lanes_env().and_then(|()| match cli.command {
        None => window::app::run(&cli.window),
        Some(Command::Render(args)) => cli::render::run(&args),
        Some(Command::Bench(args)) => cli::bench::run(&args),
        Some(Command::Sweep(args)) => cli::sweep::run(&args),
    });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("stereotrace: error: {e:#}");
            if e.downcast_ref::<tracer::SceneError>().is_some() || e.downcast_ref::<setup::BadInput>().is_some() {
                ExitCode::from(2)
            } else {
                ExitCode::from(1)
            }
        }
    }
}
