//! `hdgear simulate`: one trajectory of the dimensionless model.

use crate::sink::{RunProgress, Sink, warn};
use anyhow::{Context, Result};
use hdgear::model::MAX_STATES;
use hdgear::output::{Format, Record, RecordWriter};
use serde::Serialize;
use serde::ser::SerializeStruct;
use std::io::Write;

use crate::args::{TolArgs, check_finite, check_out, check_positive, check_rows};
use crate::sources::ParamArgs;
use clap::Args;
use hdgear::params::{Params, Warning};
use hdgear::simulate::{SimOptions, Start};
use std::path::PathBuf;

/// Arguments of `hdgear simulate`.
#[derive(Args, Debug)]
pub struct SimulateArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    #[command(flatten)]
    pub tol: TolArgs,
    /// Duration in slow periods 2π/ω.
    #[arg(
        long,
        default_value_t = 3.0,
        conflicts_with = "t_end",
        allow_negative_numbers = true
    )]
    pub periods: f64,
    /// Duration in dimensionless time (instead of --periods).
    #[arg(long, allow_negative_numbers = true)]
    pub t_end: Option<f64>,
    /// Initial x (default: the stable equilibrium at a = 0).
    #[arg(long, allow_negative_numbers = true, conflicts_with = "from_rest")]
    pub x0: Option<f64>,
    /// Initial x' (default: at rest, 0; with a kinematic error e, −e'(0), the total twist at rest).
    #[arg(long, allow_negative_numbers = true, conflicts_with = "from_rest")]
    pub v0: Option<f64>,
    /// Start at rest at x0 = 0 (x' as --v0's default).
    #[arg(long)]
    pub from_rest: bool,
    /// Output spacing (sampled from dense output).
    #[arg(long, default_value_t = 0.05, allow_negative_numbers = true)]
    pub dt: f64,
    /// Output file, .csv, .json or .parquet (CSV on stdout without it).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// Print one JSON summary object to stdout instead of the trajectory.
    #[arg(long)]
    pub summary: bool,
}

/// `hdgear simulate`, checked.
pub struct SimulateRun {
    pub params: Params,
    /// The assembled model when the scenario adds terms to the study's (`[friction]`, …).
    pub model: Option<hdgear::model::Model>,
    pub warnings: Vec<Warning>,
    pub opts: SimOptions,
    pub out: Option<PathBuf>,
    pub summary: bool,
}

impl SimulateArgs {
    /// Checks every value and resolves the parameters.
    pub fn check(&self) -> Result<SimulateRun> {
        let (params, model, warnings) = self.params.resolve_model()?;
        let subject = model.subject();
        let model = model.has_extra_terms().then_some(model);
        let tol = self.tol.options()?;
        let t_end = match self.t_end {
            Some(t) => check_positive("t-end", t)?,
            None => check_positive("periods", self.periods)? * params.slow_period(),
        };
        let mut dt = check_positive("dt", self.dt)?;
        if self.summary {
            // no rows are written: no output grid to fill
            dt = t_end;
        } else {
            check_rows(t_end / dt)?;
        }
        let start = if self.from_rest {
            Start::Rest
        } else {
            match (self.x0, self.v0) {
                (None, None) => Start::Equilibrium,
                (x0, v0) => {
                    let x0 = match x0 {
                        Some(x) => check_finite("x0", x)?,
                        None => subject.stable_equilibrium(0.0)?,
                    };
                    let rest = model.as_ref().map_or(0.0, |m| m.rest_rate());
                    let v0 = check_finite("v0", v0.unwrap_or(rest))?;
                    Start::Given { x0, v0 }
                }
            }
        };
        check_out(&self.out)?;
        Ok(SimulateRun {
            params,
            model,
            warnings,
            opts: SimOptions {
                t_end,
                dt,
                start,
                tol,
            },
            out: self.out.clone(),
            summary: self.summary,
        })
    }
}

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

/// The columns every trajectory has, which the `Serialize` below writes; the model's own states
/// follow them (its columns are known at run time, so this row's serialisation is written here,
/// not derived).
impl Record for Sample<'_> {
    const COLUMNS: &'static [&'static str] = &["t", "a", "x", "xdot"];
}

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
