//! `stereotrace`: the stereo viewer window, and the headless `render` and `bench` commands.
//!
//! Exit codes: 0 success, 2 bad input (scene file, arguments), 1 any other failure.

mod app;
mod bench;
mod cli;
mod fps_log;
mod frame_times;
mod input;
mod present;
mod reference;
mod render_cmd;
mod report;
mod screenshot;
mod settings;
mod setup;
mod syslibs;
mod timing;
mod ui;
mod window;
mod worker;

use std::process::ExitCode;

use clap::Parser;

use crate::cli::{Cli, Command};

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        None => app::run(&cli.window),
        Some(Command::Render(args)) => render_cmd::run(&args),
        Some(Command::Bench(args)) => bench::run(&args),
    };
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
