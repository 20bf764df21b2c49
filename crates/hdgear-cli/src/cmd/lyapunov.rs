//! `hdgear lyapunov-map`: the largest Lyapunov exponent over a grid of one or two parameters.

use crate::cli::LyapunovMapArgs;
use crate::sink::{warn, write_records};
use anyhow::{Context, Result};
use hdgear::periodic::{DiagramOptions, lyapunov_map};
use hdgear::sweep::{Axis, Grid};
use serde::Serialize;

#[derive(Serialize)]
struct Meta<'a> {
    grid: &'a Grid,
    options: DiagramOptions,
}

pub fn run(a: LyapunovMapArgs) -> Result<()> {
    let axes = a
        .grid
        .axes
        .iter()
        .map(|t| Axis::parse(t))
        .collect::<hdgear::Result<Vec<_>>>()
        .context("--param")?;
    for ax in &axes {
        if a.params.given(ax.param) {
            anyhow::bail!("--{0} does not apply: an axis varies {0}", ax.param);
        }
    }
    let threads = crate::cli::threads(a.threads)?;
    let (p, warnings) = a.params.resolve()?;
    let grid = Grid::new(p, axes).context("--param")?;
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
    warn(&warnings);
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
    write_records(Some(&a.out), &meta, rows.iter().cloned())?;
    if let Some(plot) = &a.plot {
        let f = hdgear::figures::lyapunov_figure(&grid, &rows);
        hdgear::output::plot::write(&f, plot)?;
    }
    Ok(())
}
