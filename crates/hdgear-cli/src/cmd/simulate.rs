//! `hdgear simulate`: one trajectory of the dimensionless model.

use crate::cli::SimulateRun;
use crate::sink::{RunProgress, Sink, warn};
use anyhow::{Context, Result};
use hdgear::model::MAX_STATES;
use hdgear::output::{Format, Record, RecordWriter};
use serde::Serialize;
use serde::ser::SerializeStruct;
use std::io::Write;

/// One trajectory sample: the columns `t,a,x,xdot`, then one per internal state of the model's
/// terms, named as `hdgear model` names them (`s` of LuGre friction, `z` of Bouc–Wen, …).
struct Sample<'a> {
    t: f64,
    a: f64,
    /// The state, its first `dim` components used.
    y: [f64; 2 + MAX_STATES],
    dim: usize,
    states: &'a [&'static str],
}
hdgear::record!(Sample<'_>: "t", "a", "x", "xdot");

impl Serialize for Sample<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        let mut row = s.serialize_struct("Sample", 2 + self.dim)?;
        row.serialize_field("t", &self.t)?;
        row.serialize_field("a", &self.a)?;
        let names = Self::COLUMNS[2..].iter().chain(self.states);
        for (name, value) in names.zip(&self.y[..self.dim]) {
            row.serialize_field(name, value)?;
        }
        row.end()
    }
}

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
    let states = run.model.map_or_else(Vec::new, |m| m.states().split_off(2));
    let columns = Sample::COLUMNS.iter().chain(&states).copied().collect();
    let mut table = RecordWriter::<_, Sample>::with_columns(sink, format, &meta, columns)?;
    let mut io_err: Option<std::io::Error> = None;
    let mut progress = RunProgress::new(run.opts.t_end, run.opts.t_end);
    let mut each = |t: f64, y: &[f64]| {
        progress.at(t);
        let mut state = [0.0; 2 + MAX_STATES];
        state[..y.len()].copy_from_slice(y);
        if io_err.is_none()
            && let Err(e) = table.row(&Sample {
                t,
                a: (p.omega * t).sin(),
                y: state,
                dim: y.len(),
                states: &states,
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
