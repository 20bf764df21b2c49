//! Maps over a grid other than the burst verdict's: the largest Lyapunov exponent
//! ([`lyapunov_map`]), on the same parallel loop as the sweeps.

use super::{Grid, Sweep};
use crate::error::Result;
use crate::periodic::{DiagramOptions, LyapunovRow};

/// [`lyapunov_point`](crate::periodic::lyapunov_point) at every point of `grid` on `threads`
/// worker threads (0: one per core): the study's [`LANES`](crate::batch::LANES) points at a time
/// ([`lyapunov_points`](crate::periodic::lyapunov_points)), a model's one by one
/// ([`lyapunov_of`](crate::periodic::lyapunov_of)), the rows in grid order whatever the thread
/// count.
pub fn lyapunov_map<S: Sweep>(
    grid: &Grid<S>,
    opts: &DiagramOptions,
    threads: usize,
) -> Result<Vec<LyapunovRow<S::Point>>> {
    opts.tol.validate()?;
    let mut rows = Vec::with_capacity(grid.len());
    let todo: Vec<usize> = (0..grid.len()).collect();
    super::run_chunked(
        grid,
        &todo,
        S::CHUNK,
        threads,
        |chunk| S::lyapunov_rows(chunk, &grid.axes, opts),
        |r| rows.push(r),
    )?;
    Ok(rows)
}
