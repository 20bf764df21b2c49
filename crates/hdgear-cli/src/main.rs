//! The `hdgear` command: arguments → checked settings → run → export.

#![forbid(unsafe_code)]

mod cli;
mod cmd;
mod export;
mod signals;
mod sink;
mod sources;
mod summary;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args = cli::Cli::parse();
    if args.command.writes_files() {
        signals::install();
    }
    sink::QUIET.store(args.quiet, std::sync::atomic::Ordering::Relaxed);
    // stdout is flushed here so that a full disk or a closed pipe at the last line is reported
    // like any other failed write (Rust's own flush at exit would drop the error)
    let flushed = |()| std::io::Write::flush(&mut std::io::stdout()).map_err(sink::stdout_error);
    match cmd::run(args).and_then(flushed) {
        Ok(()) => ExitCode::SUCCESS,
        // A closed pipe (`hdgear simulate | head`) is the reader's choice, not a failure.
        Err(e) if sink::is_broken_pipe(&e) => ExitCode::SUCCESS,
        // A signal's handler is removing the temporaries and ends the process with 128 + n: an
        // output it refused meanwhile is not this run's error (nor its exit code 2).
        Err(_) if hdgear::output::interrupting() => loop {
            std::thread::park();
        },
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(sink::exit_code(&e))
        }
    }
}
