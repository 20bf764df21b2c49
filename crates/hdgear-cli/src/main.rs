//! The `hdgear` command: arguments → checked settings → run → export.

mod cli;
mod cmd;
mod signals;
mod sink;
mod summary;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args = cli::Cli::parse();
    if args.command.writes_files() {
        signals::install();
    }
    sink::QUIET.store(args.quiet, std::sync::atomic::Ordering::Relaxed);
    match cmd::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        // A closed pipe (`hdgear simulate | head`) is the reader's choice, not a failure.
        Err(e) if sink::is_broken_pipe(&e) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(sink::exit_code(&e))
        }
    }
}
