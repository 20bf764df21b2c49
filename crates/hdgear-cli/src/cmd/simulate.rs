//! `hdgear simulate`: one trajectory of the dimensionless model.

use crate::cli::SimulateRun;
use crate::sink::{RunProgress, Sink, warn};
use anyhow::{Context, Result};
use hdgear::output::{Format, RecordWriter};
use serde::Serialize;
use std::io::Write;

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
fn simulate_into<W: Write + Send>(
    run: &SimulateRun,
    sink: W,
    format: Format,
) -> Result<(W, hdgear::simulate::SimSummary)> {
    let p = run.params;
    let meta = hdgear::simulate::Setup {
        params: p,
        options: run.opts,
        model: run.model.map(|m| m.describe()),
    };
    let mut table = RecordWriter::<_, Sample>::new(sink, format, &meta)?;
    let mut io_err: Option<std::io::Error> = None;
    let mut progress = RunProgress::new(run.opts.t_end, run.opts.t_end);
    let mut each = |t: f64, y: &[f64]| {
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
    };
    let summary = match &run.model {
        Some(m) => hdgear::simulate::simulate_model(m, &run.opts, &mut each)?,
        None => hdgear::simulate::simulate(&p, &run.opts, |t, y| each(t, y))?,
    };
    if let Some(e) = io_err {
        return Err(e).with_context(|| crate::sink::writing("the trajectory", run.out.as_deref()));
    }
    let sink = table
        .finish()
        .with_context(|| crate::sink::writing("the trajectory", run.out.as_deref()))?;
    Ok((sink, summary))
}

pub fn run(run: SimulateRun) -> Result<()> {
    warn(&run.warnings);
    if run.summary {
        let mut progress = RunProgress::new(run.opts.t_end, run.opts.t_end);
        let s = match &run.model {
            Some(m) => hdgear::simulate::simulate_model(m, &run.opts, |t, _| progress.at(t))?,
            None => hdgear::simulate::summarize(&run.params, &run.opts, |t| progress.at(t))?,
        };
        drop(progress);
        let mut doc = s.report(&run.params, &run.warnings);
        doc.model = run.model.map(|m| m.describe());
        crate::sink::outln!("{}", serde_json::to_string_pretty(&doc)?);
        return Ok(());
    }
    let (sink, format) = Sink::open(run.out.as_deref())?;
    let (sink, _) = simulate_into(&run, sink, format)?;
    sink.commit()
}
