//! The `hdgear` command: arguments → checked settings → run → export.

mod cli;
mod commands;
mod physical_cmd;
mod signals;
mod summary;
mod sweep_cmd;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args = cli::Cli::parse();
    signals::install();
    commands::QUIET.store(args.quiet, std::sync::atomic::Ordering::Relaxed);
    match commands::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        // A closed pipe (`hdgear simulate | head`) is the reader's choice, not a failure.
        Err(e) if commands::is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(commands::exit_code(&e))
        }
    }
}
