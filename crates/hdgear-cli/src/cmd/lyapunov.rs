//! `hdgear lyapunov-map`: the largest Lyapunov exponent over a grid of one or two parameters of
//! the study's set or of a scenario's model.

use crate::cli::LyapunovMapArgs;
use crate::sink::{warn, write_records_and};
use anyhow::{Context, Result};
use hdgear::periodic::DiagramOptions;
use hdgear::sweep::{Axis, Grid, Sweep, lyapunov_map};
use serde::Serialize;

#[derive(Serialize)]
#[serde(bound = "")]
struct Meta<'a, S: Sweep> {
    grid: &'a Grid<S>,
    options: DiagramOptions,
}

pub fn run(a: LyapunovMapArgs) -> Result<()> {
    let (system, warnings) = a.params.resolve_system()?;
    crate::on_system!(system, |s| map(&a, s, &warnings))
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
    let threads = crate::cli::threads(a.threads)?;
    // a model whose orbits the variational equations cannot follow is refused once, naming
    // its term, before any point is computed
    base.check_periodic()?;
    let grid = Grid::new(base, axes).context("--param")?;
    crate::cli::check_out(&Some(a.out.clone()))?;
    if let Some(plot) = &a.plot {
        crate::cli::check_plot(plot)?;
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
