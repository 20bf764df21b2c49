//! `hdgear orbit-diagram`: the stroboscopic section against a parameter, swept up and down.

use crate::sink::{Sink, warn};
use anyhow::{Context, Result};
use hdgear::output::RecordWriter;
use hdgear::periodic::{DiagramOptions, DiagramPoint, orbit_diagram};
use hdgear::sweep::{Axis, Sweep};
use serde::Serialize;

use crate::sources::ParamArgs;
use clap::Args;
use std::path::PathBuf;

/// Arguments of `hdgear orbit-diagram`.
#[derive(Args, Debug)]
pub struct OrbitDiagramArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    /// NAME=START:END:COUNT[:log]: the parameter values, swept up then down.
    #[arg(long = "param", value_name = "SPEC", allow_hyphen_values = true)]
    pub axis: String,
    /// Forcing periods discarded at each value.
    #[arg(long, default_value_t = 200)]
    pub discard: u32,
    /// Forcing periods recorded at each value.
    #[arg(long, default_value_t = 32)]
    pub record: u32,
    /// Also the largest Lyapunov exponent at each value, averaged over N forcing periods after
    /// the recorded ones (Benettin).
    #[arg(long, value_name = "N", num_args = 0..=1, default_missing_value = "400")]
    pub lyapunov: Option<u32>,
    /// The section points (sweep,param,period,lyapunov,x,xdot) to a .csv, .json or .parquet file
    /// (CSV on stdout without it).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
    /// The figure to a .svg or .png file.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

/// One section point: the columns of the output.
#[derive(Serialize, hdgear::output::Record)]
struct Row {
    sweep: &'static str,
    param: f64,
    period: Option<u32>,
    lyapunov: Option<f64>,
    x: f64,
    xdot: f64,
}

#[derive(Serialize)]
struct Meta<'a, S, P> {
    axis: &'a Axis<P>,
    params: &'a S,
    options: DiagramOptions,
}

pub fn run(a: OrbitDiagramArgs) -> Result<()> {
    let (system, warnings) = a.params.resolve_system()?;
    crate::args::check_out(&a.out)?;
    if let Some(plot) = &a.plot {
        crate::args::check_plot(plot)?;
    }
    hdgear::on_subject!(&system, |p| run_on(p, &a, &warnings))
}

/// The diagram of the study's set or of a model, along one of its parameters (a model's by its
/// qualified name), written and plotted.
fn run_on<S: Sweep>(
    p: &S,
    a: &OrbitDiagramArgs,
    warnings: &[hdgear::params::Warning],
) -> Result<()> {
    let axis = Axis::parse_for(&a.axis, p).context("--param")?;
    hdgear::periodic::check_diagram_values(axis.count).context("--param")?;
    a.params
        .not_given(&axis.param.to_string(), "--param varies")?;
    let param = axis.param;
    p.check_periodic()?;
    let opts = DiagramOptions {
        discard: a.discard,
        record: a.record,
        lyapunov: a.lyapunov,
        ..DiagramOptions::default()
    };
    let mut values: Vec<f64> = (0..axis.count).map(|i| axis.value(i)).collect();
    values.sort_by(f64::total_cmp);
    values.dedup();
    warn(warnings);
    let meta = Meta {
        axis: &axis,
        params: p,
        options: opts,
    };
    let (sink, format) = Sink::open(a.out.as_deref())?;
    let mut w = RecordWriter::new(sink, format, &meta)?;
    let mut points: Vec<DiagramPoint> = Vec::new();
    let mut failure = None;
    orbit_diagram(p, param, &values, &opts, |q| {
        if failure.is_some() {
            return;
        }
        for s in &q.section {
            let row = Row {
                sweep: q.sweep.name(),
                param: q.param,
                period: q.period,
                lyapunov: q.lyapunov,
                x: s[0],
                xdot: s[1],
            };
            if let Err(e) = w.row(&row) {
                failure = Some(e);
                return;
            }
        }
        if a.plot.is_some() {
            points.push(q);
        }
    })?;
    if let Some(e) = failure {
        return Err(anyhow::Error::from(e).context("writing the output"));
    }
    let sink = w.finish().context("writing the output")?;
    // the figure before the rows are made final: where it fails, neither is left
    if let Some(plot) = &a.plot {
        let f = hdgear::figures::orbit_diagram_figure(p, param, &points);
        hdgear::output::plot::write(&f, plot)?;
    }
    sink.commit()
}
