//! Running the checked commands and exporting their results.

use crate::cli::{Cli, Command, SimulateRun};
use anyhow::{Context, Result};
use hdgear::output::{AtomicFile, Format, RecordWriter};
use hdgear::params::Warning;
use serde::Serialize;
use std::io::Write;

/// Exit code for an error: 1 when a computation failed on valid input (step-size underflow,
/// blow-up, step budget), 2 for everything the user can fix in the input.
pub fn exit_code(e: &anyhow::Error) -> u8 {
    match e.downcast_ref::<hdgear::Error>() {
        Some(
            hdgear::Error::StepSizeTooSmall { .. }
            | hdgear::Error::BlowUp { .. }
            | hdgear::Error::TooManySteps { .. },
        ) => 1,
        _ => 2,
    }
}

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
    }
}

fn warn(warnings: &[Warning]) {
    for w in warnings {
        eprintln!("warning: {w}");
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

/// Streams a simulation into a table on `sink`; returns the sink (for committing) and the summary.
fn simulate_into<W: Write>(
    run: &SimulateRun,
    sink: W,
    format: Format,
) -> Result<(W, hdgear::simulate::SimSummary)> {
    let p = run.params;
    let meta = serde_json::json!({ "params": p, "options": run.opts });
    let mut table = RecordWriter::new(sink, format, &meta)?;
    let mut io_err: Option<std::io::Error> = None;
    let summary = hdgear::simulate::simulate(&p, &run.opts, |t, y| {
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
        let s = hdgear::simulate::simulate(&run.params, &run.opts, |_, _| {})?;
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
    match &run.out {
        Some(path) => {
            let file = AtomicFile::create(path)?;
            let (file, _) = simulate_into(&run, file, Format::from_path(path)?)?;
            file.commit()?;
        }
        None => {
            let out = std::io::BufWriter::new(std::io::stdout().lock());
            let _ = simulate_into(&run, out, Format::Csv)?;
        }
    }
    Ok(())
}
