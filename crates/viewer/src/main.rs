//! `stereotrace`: the stereo viewer window, and the headless `render` and `bench` commands.
//!
//! Exit codes: 0 success, 2 bad input (scene file, arguments), 1 any other failure.

mod app;
mod cli;
mod png_out;

use std::process::ExitCode;

use clap::Parser;

use crate::cli::{Cli, Command};

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        None => app::run(&cli.window),
        Some(Command::Render(_) | Command::Bench(_)) => Ok(()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("stereotrace: error: {e:#}");
            if e.downcast_ref::<tracer::SceneError>().is_some() {
                ExitCode::from(2)
            } else {
                ExitCode::from(1)
            }
        }
    }
}
