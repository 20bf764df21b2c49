//! The `hdgear` command: arguments → checked settings → run → export.

#![forbid(unsafe_code)]

mod args;
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
    let args = match cli::Cli::try_parse() {
        Ok(args) => args,
        Err(e) => return refused_arguments(&e),
    };
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

/// clap's refusal of the arguments in one line, as every other refusal (its tip and the usage
/// line folded in), exit code 2; help and version print as clap prints them.
fn refused_arguments(e: &clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp
            | ErrorKind::DisplayVersion
            | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        let _ = e.print();
        return ExitCode::from(if e.use_stderr() { 2 } else { 0 });
    }
    let text = e.render().to_string();
    let mut line = String::new();
    for part in text.lines().map(str::trim).filter(|l| !l.is_empty()) {
        if let Some(tip) = part.strip_prefix("tip: ") {
            line.push_str(&format!("; {tip}"));
        } else if let Some(usage) = part.strip_prefix("Usage: ") {
            line.push_str(&format!(" (usage: {usage})"));
        } else if part.starts_with("For more information") {
            continue;
        } else {
            if !line.is_empty() {
                line.push(' ');
            }
            line.push_str(part);
        }
    }
    eprintln!("{line}");
    ExitCode::from(2)
}
