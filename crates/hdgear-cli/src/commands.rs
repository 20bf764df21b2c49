//! Running the checked commands and exporting their results.

use crate::cli::{
    AnalyzeArgs, BifurcationArgs, BurstsArgs, Cli, Command, EquilibriaArgs, SimulateRun, TableArgs,
    check_out, parse_range,
};
use anyhow::{Context, Result};
use hdgear::output::{AtomicFile, Format, RecordWriter};
use hdgear::params::Warning;
use serde::Serialize;
use std::io::Write;
use std::path::Path;

/// Exit code for an error: 1 when a computation failed on valid input (step-size underflow,
/// blow-up, step budget), 2 for everything the user can fix in the input.
pub fn exit_code(e: &anyhow::Error) -> u8 {
    if e.downcast_ref::<ComputationFailed>().is_some() {
        return 1;
    }
    match e.downcast_ref::<hdgear::Error>() {
        Some(
            hdgear::Error::StepSizeTooSmall { .. }
            | hdgear::Error::BlowUp { .. }
            | hdgear::Error::TooManySteps { .. },
        ) => 1,
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

/// True when the error is a write to a closed pipe.
pub fn is_broken_pipe(e: &anyhow::Error) -> bool {
    e.chain().any(|c| {
        c.downcast_ref::<std::io::Error>()
            .is_some_and(|io| io.kind() == std::io::ErrorKind::BrokenPipe)
    })
}

/// Dispatches a parsed command line.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Simulate(a) => simulate(a.check()?),
        Command::Equilibria(a) => equilibria(a),
        Command::Analyze(a) => analyze(a),
        Command::Bifurcation(a) => bifurcation(a),
        Command::Bursts(a) => bursts(a),
        Command::Table(a) => table(a),
        Command::Sweep(a) => crate::sweep_cmd::sweep(a),
        Command::Physical(a) => crate::physical_cmd::physical(a),
        Command::Plot(a) => plot(a),
        Command::Report(a) => report(a),
    }
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

/// Prints one warning line unless `--quiet`.
pub fn note(text: &str) {
    if !QUIET.load(std::sync::atomic::Ordering::Relaxed) {
        eprintln!("warning: {text}");
    }
}

/// Warns when an a-range reaches beyond [−1, 1], which a = sin ωτ never leaves.
fn warn_range(range: (f64, f64)) {
    if range.0 < -1.0 || range.1 > 1.0 {
        note(&format!(
            "--a-range {:?}:{:?} reaches beyond [-1, 1]: a = sin(omega t) never goes there",
            range.0, range.1
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
            eprintln!("warning: {text}");
            seen.push(text);
        }
    }
}

/// One trajectory sample: the CSV columns `t,a,x,xdot`.
#[derive(Serialize)]
struct Sample {
    t: f64,
    a: f64,
    x: f64,
    xdot: f64,
}
hdgear::record!(Sample: "t", "a", "x", "xdot");

/// Streams a simulation into a table on `sink`; returns the sink (for committing) and the summary.
fn simulate_into<W: Write>(
    run: &SimulateRun,
    sink: W,
    format: Format,
) -> Result<(W, hdgear::simulate::SimSummary)> {
    let p = run.params;
    let meta = serde_json::json!({ "params": p, "options": run.opts });
    let mut table = RecordWriter::<_, Sample>::new(sink, format, &meta)?;
    let mut io_err: Option<std::io::Error> = None;
    let mut progress = RunProgress::new(run.opts.t_end, run.opts.t_end);
    let summary = hdgear::simulate::simulate(&p, &run.opts, |t, y| {
        progress.at(t);
        if io_err.is_none()
            && let Err(e) = table.row(&Sample {
                t,
                a: (p.omega * t).sin(),
                x: y[0],
                xdot: y[1],
            })
        {
            io_err = Some(e);
        }
    })?;
    if let Some(e) = io_err {
        return Err(e).context("writing the trajectory");
    }
    let sink = table.finish().context("writing the trajectory")?;
    Ok((sink, summary))
}

fn simulate(run: SimulateRun) -> Result<()> {
    warn(&run.warnings);
    if run.summary {
        let mut progress = RunProgress::new(run.opts.t_end, run.opts.t_end);
        let s = hdgear::simulate::simulate(&run.params, &run.opts, |t, _| progress.at(t))?;
        drop(progress);
        let doc = serde_json::json!({
            "params": run.params,
            "t_end": s.t_end,
            "final": { "x": s.final_state[0], "xdot": s.final_state[1] },
            "stats": s.stats,
            "max_abs_xdot": s.max_abs_xdot,
            "warnings": run.warnings.iter().map(|w| w.to_string()).collect::<Vec<_>>(),
        });
        println!("{}", serde_json::to_string_pretty(&doc)?);
        return Ok(());
    }
    let (sink, format) = Sink::open(run.out.as_deref())?;
    let (sink, _) = simulate_into(&run, sink, format)?;
    sink.commit()
}

/// Where records go: an atomic file, or stdout.
pub enum Sink {
    File(AtomicFile),
    Stdout(std::io::BufWriter<std::io::StdoutLock<'static>>),
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
                Sink::Stdout(std::io::BufWriter::new(std::io::stdout().lock())),
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
    meta: &serde_json::Value,
    rows: impl IntoIterator<Item = T>,
) -> Result<()> {
    let (sink, format) = Sink::open(out)?;
    let mut w = RecordWriter::new(sink, format, meta)?;
    for r in rows {
        w.row(&r).context("writing the output")?;
    }
    w.finish().context("writing the output")?.commit()
}

fn equilibria(a: EquilibriaArgs) -> Result<()> {
    let (p, warnings) = a.params.resolve()?;
    let range = parse_range(&a.a_range)?;
    check_out(&a.out)?;
    crate::cli::check_points(a.points)?;
    warn(&warnings);
    warn_range(range);
    let curve = hdgear::fast::curve(&p, range, a.points)?;
    let meta = serde_json::json!({ "params": p, "a_range": [range.0, range.1] });
    write_records(a.out.as_deref(), &meta, curve)
}

fn bifurcation(a: BifurcationArgs) -> Result<()> {
    if a.params.given("gamma") {
        anyhow::bail!(
            "--gamma does not apply to bifurcation: it varies gamma from --gamma-min to the cusp"
        );
    }
    let (p, warnings) = a.params.resolve()?;
    check_out(&a.out)?;
    crate::cli::check_points(a.points)?;
    warn(&warnings);
    let rows = hdgear::fast::fold_curves(&p, a.gamma_min, a.points)?;
    let cusp = hdgear::fast::cusp(&p);
    let meta = serde_json::json!({ "params": p, "cusp": cusp });
    write_records(a.out.as_deref(), &meta, rows)
}

fn analyze(a: AnalyzeArgs) -> Result<()> {
    let (p, warnings) = a.params.resolve()?;
    let range = parse_range(&a.a_range)?;
    let opts = a.burst.options()?;
    let an = hdgear::fast::analyze(&p, range)?;
    warn_range(range);
    let measured = if a.no_response {
        None
    } else {
        let r = hdgear::burst::response(&p, &opts)?;
        let c = hdgear::burst::classify(&p, &r);
        if !c.fast_slow_domain {
            note(&format!(
                "omega = {:?} is not slow against the fast subsystem (omega > r/10, r = {:.3} the \
                 relaxation rate at a = ±1{}): the fast-slow picture does not apply, mode not-fast-slow",
                p.omega,
                hdgear::burst::turning_point_rate(&p),
                if r.continuous_fast_motion {
                    ", and the fast motion never stops"
                } else {
                    ""
                }
            ));
        }
        Some((r, c))
    };
    let bounds = if a.simulated_boundaries {
        Some(hdgear::burst::boundaries(&p, &opts)?)
    } else {
        None
    };
    if a.json {
        let mut doc = serde_json::to_value(&an)?;
        if let Some((r, c)) = &measured {
            doc["response"] = serde_json::to_value(r)?;
            doc["classification"] = serde_json::to_value(c)?;
        }
        if let Some(b) = &bounds {
            doc["boundaries"] = serde_json::to_value(b)?;
        }
        doc["warnings"] =
            serde_json::json!(warnings.iter().map(|w| w.to_string()).collect::<Vec<_>>());
        println!("{}", serde_json::to_string_pretty(&doc)?);
    } else {
        warn(&warnings);
        print!("{}", crate::summary::analysis_text(&an));
        if let Some((r, c)) = &measured {
            print!("{}", crate::summary::response_text(r, c));
        }
        if let Some(b) = &bounds {
            let g = |v: Option<f64>| v.map_or("none".to_string(), |v| format!("{v:.4}"));
            let w = |v: Option<f64>| v.map_or("none".to_string(), |v| format!("{v:.4e}"));
            println!(
                "bursting boundary in gamma: predicted {}, simulated {}; in omega: predicted {}, simulated {}",
                g(b.predicted_gamma),
                g(b.simulated_gamma),
                w(Some(b.predicted_omega)),
                w(b.simulated_omega)
            );
        }
    }
    Ok(())
}

fn bursts(a: BurstsArgs) -> Result<()> {
    let (p, warnings) = a.params.resolve()?;
    let opts = a.burst.options()?;
    check_out(&a.out)?;
    warn(&warnings);
    let r = hdgear::burst::response(&p, &opts)?;
    let c = hdgear::burst::classify(&p, &r);
    let meta = serde_json::json!({
        "params": p,
        "options": opts,
        "classification": c,
        "bursts_per_period": r.bursts_per_period,
        "window": [r.window_start, r.window_end],
    });
    write_records(a.out.as_deref(), &meta, r.bursts)
}

fn table(a: TableArgs) -> Result<()> {
    let (p, warnings) = a.params.resolve()?;
    let opts = a.burst.options()?;
    warn(&warnings);
    let t = hdgear::table::tables(&p, &opts)?;
    let text = if a.json {
        serde_json::to_string_pretty(&t)? + "\n"
    } else if a.csv {
        hdgear::output::tables::csv(&t)?
    } else {
        hdgear::output::tables::markdown(&t)
    };
    print!("{text}");
    Ok(())
}

fn plot(a: crate::cli::PlotArgs) -> Result<()> {
    let (p, warnings) = a.params.resolve()?;
    let opts = a.burst.options()?;
    if !hdgear::figures::KINDS.contains(&a.kind.as_str()) {
        anyhow::bail!(
            "invalid figure kind '{}': expected one of {}",
            a.kind,
            hdgear::figures::KINDS.join(", ")
        );
    }
    match a
        .out
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("svg" | "png") => {}
        _ => anyhow::bail!(
            "--out {}: the extension must be .svg or .png",
            a.out.display()
        ),
    }
    hdgear::output::check_output_path(&a.out)?;
    // figures that vary a parameter themselves would silently ignore its flag
    let varied: &[&str] = match a.kind.as_str() {
        "xdot-gamma" | "slope" | "sweep" => &["gamma"],
        "map" => &["gamma", "delta"],
        _ => &[],
    };
    for name in varied {
        if a.params.given(name) {
            anyhow::bail!(
                "--{name} does not apply to plot {}: the figure varies {name} itself",
                a.kind
            );
        }
    }
    if a.threads == Some(0) {
        anyhow::bail!("invalid option --threads = 0: must be ≥ 1");
    }
    warn(&warnings);
    let f = hdgear::figures::by_kind(&a.kind, &p, &opts, a.threads.unwrap_or(0))?;
    hdgear::output::plot::write(&f, &a.out)?;
    Ok(())
}

fn report(a: crate::cli::ReportArgs) -> Result<()> {
    if a.threads == Some(0) {
        anyhow::bail!("invalid option --threads = 0: must be ≥ 1");
    }
    let opts = hdgear::report::ReportOptions {
        threads: a.threads.unwrap_or(0),
        force: a.force,
        ..Default::default()
    };
    let start = std::time::Instant::now();
    let mut step = 0;
    let summary = hdgear::report::build(&a.out, &opts, &mut |stage| {
        step += 1;
        eprintln!("[{step}/8 {:5.1} s] {stage}", start.elapsed().as_secs_f64());
    })
    .with_context(|| format!("writing the report to {}", a.out.display()))?;
    eprintln!(
        "wrote {} files in {:.1} s; open {}",
        summary.files.len(),
        start.elapsed().as_secs_f64(),
        a.out.join("index.html").display()
    );
    Ok(())
}
