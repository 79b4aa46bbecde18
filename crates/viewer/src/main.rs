//! `stereotrace`: the stereo viewer window, and the headless `render`, `bench`, `sweep`,
//! `timewarp`, `pick` and `replay` commands.
//!
//! Exit codes: 0 success, 2 bad input (scene file, arguments), 3 `pick`'s ray hit nothing,
//! 1 any other failure.
//!
//! The sources are laid out by job: `cli/` holds the headless commands and what only they
//! use, `window/` the viewer window; what both use stays at the top. The modules, in order:
//! each uses only modules listed before it (and the package's library, `lib.rs`, for PNG
//! output).
//! - shared: `crop` (a rectangle of an eye image, the type of `render --crop`), `motion` (a
//!   head's constant motion, the type of `timewarp --motion`), `args` (the
//!   command line, clap), `setup` (a scene with the overrides applied, the memory check, the
//!   scene path resolved), `reference` (the full trace quality is measured against), `pick`
//!   (the atom a pixel's ray hits, distances and angles, where its label goes in each eye);
//! - `cli`, the headless commands: `report` (the JSON keys), `render` and `bench`; `plot`
//!   (the sweep's figure) and `sweep`, which measures with `bench`'s loop; `age_plot` and
//!   `timewarp` (warped frames scored against traces at their poses);
//! - `window`, the viewer window: `timing`, `syslibs`, `frame_times`, `input`; `worker`,
//!   `present`, `settings`, `scene_watch`, `screenshot`, `fps_log`, `ui`, `os_window`; then
//!   `app`, the event loop's handler (its parts: `chrome`, `meters`, `viewer`, `frame`,
//!   `events`);
//! - `replay`, the viewer's pipeline run headless (the window's worker, timewarp and display
//!   ticks) and scored with `cli`'s figures and metrics.
//!
//! `cli` and `window` do not use each other; `replay` uses both; `main` dispatches.

mod args;
mod cli;
mod crop;
mod motion;
mod pick;
mod reference;
mod replay;
mod setup;
mod window;

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
        Some(Command::Timewarp(args)) => cli::timewarp::run(&args),
        Some(Command::Pick(args)) => cli::pick::run(&args),
        Some(Command::Replay(args)) => replay::run(&args),
    });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("stereotrace: error: {e:#}");
            if e.downcast_ref::<tracer::SceneError>().is_some() || e.downcast_ref::<setup::BadInput>().is_some() {
                ExitCode::from(2)
            } else if e.downcast_ref::<cli::pick::Miss>().is_some() {
                ExitCode::from(3)
            } else {
                ExitCode::from(1)
            }
        }
    }
}
