//! `hdgear lyapunov-map`: the largest Lyapunov exponent over a grid of one or two parameters of
//! the study's set or of a scenario's model.

use crate::sink::{warn, write_records_and};
use anyhow::{Context, Result};
use hdgear::periodic::DiagramOptions;
use hdgear::sweep::{Axis, Grid, Sweep, lyapunov_map};
use serde::Serialize;

use crate::args::GridAxes;
use crate::sources::ParamArgs;
use clap::Args;
use std::path::PathBuf;

/// Arguments of `hdgear lyapunov-map`.
#[derive(Args, Debug)]
pub struct LyapunovMapArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    #[command(flatten)]
    pub grid: GridAxes,
    /// Forcing periods discarded at each point (from the default start).
    #[arg(long, default_value_t = 200)]
    pub discard: u32,
    /// Forcing periods recorded to find the response's period.
    #[arg(long, default_value_t = 32)]
    pub record: u32,
    /// Forcing periods Benettin's average runs over.
    #[arg(long, default_value_t = 400)]
    pub periods: u32,
    /// Worker threads (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// The rows (index,alpha,…,omega,lyapunov,period,error), in grid order, to a .csv, .json or
    /// .parquet file.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// The figure (a map for two axes, a curve for one) to a .svg or .png file.
    #[arg(long, value_name = "FILE")]
    pub plot: Option<PathBuf>,
}

#[derive(Serialize)]
#[serde(bound = "")]
struct Meta<'a, S: Sweep> {
    grid: &'a Grid<S>,
    options: DiagramOptions,
}

pub fn run(a: LyapunovMapArgs) -> Result<()> {
    let (system, warnings) = a.params.resolve_system()?;
    hdgear::on_subject!(system, |s| map(&a, s, &warnings))
}

/// The map over `base`, the study's set or a model, whose parameters the axes name.
fn map<S: Sweep>(a: &LyapunovMapArgs, base: S, warnings: &[hdgear::params::Warning]) -> Result<()> {
    let axes = a
        .grid
        .axes
        .iter()
        .map(|t| Axis::parse_for(t, &base))
        .collect::<hdgear::Result<Vec<_>>>()
        .context("--param")?;
    for ax in &axes {
        a.params
            .not_given(&ax.param.to_string(), "an axis varies")?;
    }
    let threads = crate::args::threads(a.threads)?;
    // a model whose orbits the variational equations cannot follow is refused once, naming
    // its term, before any point is computed
    base.check_periodic()?;
    let grid = Grid::new(base, axes).context("--param")?;
    crate::args::check_out(&Some(a.out.clone()))?;
    if let Some(plot) = &a.plot {
        crate::args::check_plot(plot)?;
    }
    let opts = DiagramOptions {
        discard: a.discard,
        record: a.record.max(2),
        lyapunov: Some(a.periods.max(1)),
        ..DiagramOptions::default()
    };
    warn(warnings);
    // rows come in grid order, so the file is the same whatever the thread count
    let rows = lyapunov_map(&grid, &opts, threads)?;
    let failed = rows.iter().filter(|r| !r.error.is_empty()).count();
    if failed == rows.len() {
        return Err(crate::sink::ComputationFailed(format!(
            "every one of the {failed} points failed (first: {})",
            rows[0].error
        ))
        .into());
    }
    let meta = Meta {
        grid: &grid,
        options: opts,
    };
    let columns = hdgear::sweep::columns::<S, hdgear::periodic::LyapunovRow>(&grid.axes);
    write_records_and(
        Some(&a.out),
        &meta,
        columns,
        rows.iter().cloned(),
        || match &a.plot {
            Some(plot) => {
                let f = hdgear::figures::lyapunov_figure(&grid, &rows);
                Ok(hdgear::output::plot::write(&f, plot)?)
            }
            None => Ok(()),
        },
    )
}
