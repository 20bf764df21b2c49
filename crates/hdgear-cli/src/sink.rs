//! The bottom layer of the binary: where results go (an atomic file or stdout), what the user is
//! told besides them (warnings, progress), and how errors map to exit codes. Every command uses
//! it; it uses none of them.

use anyhow::{Context, Result};
use hdgear::output::{AtomicFile, Format, RecordWriter};
use hdgear::params::Warning;
use std::io::Write;
use std::path::Path;

/// Exit code for an error: 1 when a computation failed on valid input (step-size underflow,
/// blow-up, step budget), 2 for everything the user can fix in the input.
pub fn exit_code(e: &anyhow::Error) -> u8 {
    if e.downcast_ref::<ComputationFailed>().is_some() {
        return 1;
    }
    match e.downcast_ref::<hdgear::Error>() {
        Some(hdgear::Error::Solver(_) | hdgear::Error::NoConvergence { .. }) => 1,
        _ => 2,
    }
}

/// A computation that failed on valid input, reported by the binary itself (exit code 1).
#[derive(Debug)]
pub struct ComputationFailed(pub String);

impl std::fmt::Display for ComputationFailed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ComputationFailed {}

/// `print!` to standard output that returns the write's error (a closed pipe, a full disk) to
/// the caller's `?` instead of panicking. `outln!` is its `println!`.
macro_rules! out {
    ($($arg:tt)*) => {
        std::io::Write::write_fmt(&mut std::io::stdout().lock(), format_args!($($arg)*))
            .map_err($crate::sink::stdout_error)?
    };
}
pub(crate) use out;

/// `println!` that returns the write's error instead of panicking (see [`out!`]).
macro_rules! outln {
    () => { $crate::sink::out!("\n") };
    ($($arg:tt)*) => { $crate::sink::out!("{}\n", format_args!($($arg)*)) };
}
pub(crate) use outln;

/// A failed write to standard output, with the context the user sees.
pub fn stdout_error(e: std::io::Error) -> anyhow::Error {
    anyhow::Error::new(e).context("cannot write to standard output")
}

/// True when the error is a write to a closed pipe.
pub fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// Set by `--quiet`: no warnings on stderr.
pub static QUIET: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// A progress bar on stderr for a long single run (from 0 to `t_end`), shown only on a
/// terminal and only when the run is long enough to wait for: more than
/// `2e6 × OPTIMISTIC_STEP` time units (about a second of integration).
pub struct RunProgress {
    bar: Option<indicatif::ProgressBar>,
    t_end: f64,
    shown: u64,
}

impl RunProgress {
    /// A bar for a run over `span` dimensionless time units ending at `t_end` (in the caller's
    /// time unit).
    pub fn new(span: f64, t_end: f64) -> RunProgress {
        use std::io::IsTerminal;
        let long = span > 2e6 * hdgear::integrate::OPTIMISTIC_STEP;
        let bar = (long && std::io::stderr().is_terminal()).then(|| {
            let b = indicatif::ProgressBar::new(1000);
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "{bar:40} {percent:>3} %  {elapsed} elapsed, eta {eta}",
            ) {
                b.set_style(style);
            }
            b
        });
        RunProgress {
            bar,
            t_end,
            shown: 0,
        }
    }

    /// Reports that the run reached `t`.
    pub fn at(&mut self, t: f64) {
        if let Some(b) = &self.bar {
            let k = ((t / self.t_end).clamp(0.0, 1.0) * 1000.0) as u64;
            if k > self.shown {
                self.shown = k;
                b.set_position(k);
            }
        }
    }
}

impl Drop for RunProgress {
    fn drop(&mut self) {
        if let Some(b) = &self.bar {
            b.finish_and_clear();
        }
    }
}

/// The count of points the run's trace adds to ([`PointsProgress::counter`]; one trace per run).
static TRACED: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// A spinner on stderr for a trace of unknown length: the points traced so far
/// ([`PointsProgress::counter`]) and the time elapsed, refreshed five times a second by a thread
/// (woken to stop at once), shown only on a terminal and not with `--quiet`; cleared when
/// dropped.
pub struct PointsProgress {
    stop: std::sync::Arc<std::sync::atomic::AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl PointsProgress {
    /// The spinner, `what` naming what is traced ("continue2"), its count at zero.
    pub fn new(what: &str) -> PointsProgress {
        use std::io::IsTerminal;
        use std::sync::atomic::Ordering;
        let count = &TRACED;
        count.store(0, Ordering::Relaxed);
        let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let shown = std::io::stderr().is_terminal() && !QUIET.load(Ordering::Relaxed);
        let thread = shown.then(|| {
            let bar = indicatif::ProgressBar::new_spinner();
            let template = format!("{{spinner}} {what}: {{pos}} points traced, {{elapsed}}");
            if let Ok(style) = indicatif::ProgressStyle::with_template(&template) {
                bar.set_style(style);
            }
            let stop = stop.clone();
            std::thread::spawn(move || {
                while !stop.load(Ordering::Relaxed) {
                    bar.set_position(count.load(Ordering::Relaxed));
                    bar.tick();
                    // woken early by the drop, so a short trace is not held up by the spinner
                    std::thread::park_timeout(std::time::Duration::from_millis(200));
                }
                bar.finish_and_clear();
            })
        });
        PointsProgress { stop, thread }
    }

    /// The count the trace adds to: a continuation's [`hdgear::periodic::ContinuationOptions`]
    /// `progress`.
    pub fn counter(&self) -> hdgear::periodic::Counter {
        hdgear::integrate::Shared(&TRACED)
    }
}

impl Drop for PointsProgress {
    fn drop(&mut self) {
        self.stop.store(true, std::sync::atomic::Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            t.thread().unpark();
            let _ = t.join();
        }
    }
}

/// Prints one warning line unless `--quiet`.
pub fn note(text: &str) {
    if !QUIET.load(std::sync::atomic::Ordering::Relaxed) {
        eprintln!("warning: {text}");
    }
}

/// Says when the tolerance, not the physics, decided what counted as motion in a response
/// (unless `--quiet`).
pub fn tolerance_note(r: &hdgear::burst::Response, tol: &hdgear::integrate::Options) {
    if let Some(limit) = &r.tolerance_limited {
        note(&format!(
            "at --rtol {:e} --atol {:e} {limit}",
            tol.rtol, tol.atol
        ));
    }
}

/// Prints each warning once per process (a command that resolves its parameters twice does not
/// repeat them), unless `--quiet`.
pub fn warn(warnings: &[Warning]) {
    static SEEN: std::sync::Mutex<Vec<String>> = std::sync::Mutex::new(Vec::new());
    if QUIET.load(std::sync::atomic::Ordering::Relaxed) {
        return;
    }
    let mut seen = SEEN.lock().unwrap_or_else(|e| e.into_inner());
    for w in warnings {
        let text = w.to_string();
        if !seen.contains(&text) {
            // a remark on the set, not a fault: the study's own set is one
            eprintln!("note: {text}");
            seen.push(text);
        }
    }
}

/// The context of a failed write of `what` to `out`: `writing the trajectory to t.csv` (or `to
/// stdout`), so that the one-line error names the file.
pub fn writing(what: &str, out: Option<&Path>) -> String {
    match out {
        Some(p) => format!("writing {what} to {}", p.display()),
        None => format!("writing {what} to stdout"),
    }
}

/// Where records go: an atomic file, or stdout.
pub enum Sink {
    File(AtomicFile),
    Stdout(std::io::BufWriter<std::io::Stdout>),
}

impl Sink {
    /// The file (format from its extension) or stdout (CSV).
    pub fn open(out: Option<&Path>) -> Result<(Sink, Format)> {
        Ok(match out {
            Some(path) => (
                Sink::File(AtomicFile::create(path)?),
                Format::from_path(path)?,
            ),
            None => (
                Sink::Stdout(std::io::BufWriter::new(std::io::stdout())),
                Format::Csv,
            ),
        })
    }

    /// Makes the output final (renames the file into place; flushes stdout).
    pub fn commit(self) -> Result<()> {
        match self {
            Sink::File(f) => Ok(f.commit()?),
            Sink::Stdout(mut s) => Ok(s.flush()?),
        }
    }
}

impl Write for Sink {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        match self {
            Sink::File(f) => f.write(buf),
            Sink::Stdout(s) => s.write(buf),
        }
    }
    fn flush(&mut self) -> std::io::Result<()> {
        match self {
            Sink::File(f) => f.flush(),
            Sink::Stdout(s) => s.flush(),
        }
    }
}

/// Writes `rows` as records to `--out` (or stdout), atomically.
pub fn write_records<T: hdgear::output::Record>(
    out: Option<&Path>,
    meta: &impl serde::Serialize,
    rows: impl IntoIterator<Item = T>,
) -> Result<()> {
    write_records_with(out, meta, T::COLUMNS.to_vec(), rows)
}

/// [`write_records`] of rows whose columns are known only at run time (a model's swept
/// parameters): `columns` names the fields `T` writes, in order.
pub fn write_records_with<T: serde::Serialize>(
    out: Option<&Path>,
    meta: &impl serde::Serialize,
    columns: Vec<&'static str>,
    rows: impl IntoIterator<Item = T>,
) -> Result<()> {
    write_records_and(out, meta, columns, rows, || Ok(()))
}

/// [`write_records_with`], with `also` (the run's other output: its figure) written after the
/// rows and before they are made final, so that where either fails (a full disk) neither is
/// left behind.
pub fn write_records_and<T: serde::Serialize>(
    out: Option<&Path>,
    meta: &impl serde::Serialize,
    columns: Vec<&'static str>,
    rows: impl IntoIterator<Item = T>,
    also: impl FnOnce() -> Result<()>,
) -> Result<()> {
    let (sink, format) = Sink::open(out)?;
    let mut w = RecordWriter::with_columns(sink, format, meta, columns)?;
    for r in rows {
        w.row(&r).context("writing the output")?;
    }
    let sink = w.finish().context("writing the output")?;
    also()?;
    sink.commit()
}

/// Warns when an a-range reaches beyond [−1, 1], which a = sin ωτ never leaves.
pub fn warn_range(range: (f64, f64)) {
    if range.0 < -1.0 || range.1 > 1.0 {
        note(&format!(
            "--a-range {:?}:{:?} reaches beyond [-1, 1]: a = sin(omega t) never goes there",
            range.0, range.1
        ));
    }
}

/// Refuses an output path that is one of the run's inputs, the same file under any name (an
/// output that does not exist yet is none of them): writing it would destroy what the run reads.
/// `what` names the input's option (`--restart`, "the input shard").
pub fn check_not_input<'a>(
    out: &std::path::Path,
    inputs: impl IntoIterator<Item = &'a std::path::Path>,
    what: &str,
) -> Result<()> {
    let Ok(target) = std::fs::canonicalize(out) else {
        return Ok(());
    };
    if let Some(input) = inputs
        .into_iter()
        .find(|p| std::fs::canonicalize(p).is_ok_and(|p| p == target))
    {
        anyhow::bail!(
            "invalid option --out '{}': it is {what} {}; write the output elsewhere",
            out.display(),
            input.display()
        );
    }
    Ok(())
}
