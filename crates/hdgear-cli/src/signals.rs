//! SIGINT and SIGTERM: remove every temporary this process created, say so in one line, and exit
//! with 128 + the signal number (130, 143), as a shell expects. SIGXFSZ (a file-size limit,
//! `ulimit -f`) is handled so that it does not end the process on the spot: the write that went
//! past the limit fails instead (EFBIG), and the output's writer removes its temporary and
//! reports it like a full disk.

use std::sync::Mutex;

/// What to tell the user besides the removed temporaries (e.g. how to resume a sweep).
static HINT: Mutex<Option<String>> = Mutex::new(None);

/// Sets the extra sentence printed if the process is interrupted.
pub fn set_hint(hint: String) {
    *HINT.lock().unwrap_or_else(|e| e.into_inner()) = Some(hint);
}

/// Installs the handler thread. Failing to install it is not fatal: the command still runs,
/// only without cleanup on signals (a warning says so).
pub fn install() {
    use signal_hook::consts::{SIGINT, SIGTERM, SIGXFSZ};
    let limit = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    if let Err(e) = signal_hook::flag::register(SIGXFSZ, limit) {
        eprintln!(
            "warning: cannot handle SIGXFSZ ({e}): a file-size limit may leave temporary files"
        );
    }
    let mut signals = match signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) {
        Ok(s) => s,
        Err(e) => {
            eprintln!(
                "warning: cannot watch for Ctrl-C ({e}): an interrupted run may leave temporary files"
            );
            return;
        }
    };
    std::thread::spawn(move || {
        if let Some(sig) = signals.forever().next() {
            let removed = hdgear::output::remove_temporaries();
            let name = if sig == SIGINT { "SIGINT" } else { "SIGTERM" };
            let hint = HINT
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .clone()
                .map_or(String::new(), |h| format!("; {h}"));
            eprintln!("interrupted by {name}: removed {removed} unfinished output file(s){hint}");
            std::process::exit(128 + sig);
        }
    });
}
