//! Parameter sweeps: one- or two-parameter grids run in parallel, one [`SweepRow`] per point.
//!
//! Every point is computed independently and deterministically (same input, same bits), so the
//! result does not depend on the number of threads or on the order in which points finish.
//! Rows are handed to the caller as they finish (for streaming and resuming); the caller puts
//! them in grid order at the end.

use crate::burst::{BurstOptions, Mechanism, Mode, Rates, classify, response};
use crate::error::{Error, Result};
use crate::fast;
use crate::params::{Param, Params};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};
use std::sync::atomic::{AtomicUsize, Ordering};

pub mod refine;
mod shard;
pub use shard::{MergeError, Plan, Shard, plan};

/// One axis of a grid: `NAME=START:END:COUNT[:log]`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    /// The swept parameter (serialised as `name`: alpha, gamma, eps, mu, delta, omega).
    #[serde(rename = "name")]
    pub param: Param,
    /// First value.
    pub start: f64,
    /// Last value.
    pub end: f64,
    /// Number of values (≥ 1).
    pub count: usize,
    /// Logarithmic spacing (START and END > 0).
    pub log: bool,
}

impl Axis {
    /// Parses `NAME=START:END:COUNT[:log]`; errors name the offending text.
    ///
    /// ```
    /// let ax = hdgear::sweep::Axis::parse("gamma=0.05:30:200:log").unwrap();
    /// assert_eq!((ax.count, ax.log), (200, true));
    /// assert!((ax.value(199) - 30.0).abs() < 1e-12);
    /// ```
    pub fn parse(text: &str) -> Result<Axis> {
        let bad = |reason: &str| Error::InvalidInput {
            what: "sweep axis",
            text: text.to_string(),
            reason: reason.to_string(),
        };
        let (name, spec) = text
            .split_once('=')
            .ok_or_else(|| bad("expected NAME=START:END:COUNT[:log]"))?;
        let name = name.trim();
        let param: Param = name.parse().map_err(|_| {
            bad(&format!(
                "unknown parameter '{name}' (expected one of {})",
                Param::ALL.map(Param::name).join(", ")
            ))
        })?;
        let parts: Vec<&str> = spec.split(':').map(str::trim).collect();
        if !(parts.len() == 3 || parts.len() == 4) {
            return Err(bad("expected NAME=START:END:COUNT[:log]"));
        }
        let num = |s: &str, what: &str| {
            s.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(&format!("{what} '{s}' is not a finite number")))
        };
        let start = num(parts[0], "START")?;
        let end = num(parts[1], "END")?;
        let count: usize = parts[2]
            .parse()
            .ok()
            .filter(|&c| c >= 1)
            .ok_or_else(|| bad(&format!("COUNT '{}' is not a whole number ≥ 1", parts[2])))?;
        let log = match parts.get(3) {
            None => false,
            Some(&"log") => true,
            Some(other) => {
                return Err(bad(&format!(
                    "'{other}': the fourth field can only be 'log'"
                )));
            }
        };
        if log && !(start > 0.0 && end > 0.0) {
            return Err(bad("a log axis needs START > 0 and END > 0"));
        }
        if count == 1 && start != end {
            return Err(bad("COUNT 1 needs START = END"));
        }
        Ok(Axis {
            param,
            start,
            end,
            count,
            log,
        })
    }

    /// The i-th value (the ends exactly).
    pub fn value(&self, i: usize) -> f64 {
        if self.count == 1 || i == 0 {
            return self.start;
        }
        if i == self.count - 1 {
            return self.end;
        }
        let f = i as f64 / (self.count - 1) as f64;
        if self.log {
            (self.start.ln() + f * (self.end.ln() - self.start.ln())).exp()
        } else {
            self.start + f * (self.end - self.start)
        }
    }
}

/// A grid of one or two axes over a base parameter set. Index i runs over the first axis fastest.
///
/// Deserialising does not check it: pass a grid read from a file through [`Grid::new`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Grid {
    /// The parameters not swept.
    pub base: Params,
    /// One or two axes with distinct names.
    pub axes: Vec<Axis>,
}

impl Grid {
    /// Checks the axes (one or two, distinct) and that every grid point is a valid parameter set,
    /// so an impossible range fails before any work is done.
    pub fn new(base: Params, axes: Vec<Axis>) -> Result<Grid> {
        if axes.is_empty() || axes.len() > 2 {
            return Err(Error::InvalidInput {
                what: "sweep axis",
                text: format!("{} axes", axes.len()),
                reason: "give one or two axes".into(),
            });
        }
        if axes.len() == 2 && axes[0].param == axes[1].param {
            return Err(Error::InvalidInput {
                what: "sweep axis",
                text: axes[1].param.to_string(),
                reason: "the two axes must sweep different parameters".into(),
            });
        }
        let g = Grid { base, axes };
        let total = g.axes.iter().map(|a| a.count as f64).product::<f64>();
        if total > 1e7 {
            return Err(Error::InvalidInput {
                what: "sweep axis",
                text: format!("{total} grid points"),
                reason: "at most 10000000 points per sweep".into(),
            });
        }
        for i in 0..g.len() {
            g.point(i).validate()?;
        }
        Ok(g)
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.axes.iter().map(|a| a.count).product()
    }

    /// True for an empty grid (never, after [`Grid::new`]).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The parameter set at index i.
    pub fn point(&self, i: usize) -> Params {
        let mut p = self.base;
        let mut rest = i;
        for ax in &self.axes {
            let j = rest % ax.count;
            rest /= ax.count;
            p = p.with(ax.param, ax.value(j));
        }
        p
    }
}

/// One sweep result: the CSV columns of `hdgear sweep` (nested structs are written as their
/// fields in order, so the columns stay flat; JSON keeps the nesting).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SweepRow {
    /// Grid index (first axis fastest).
    pub index: usize,
    /// The point's parameters.
    pub params: Params,
    /// Oscillation mode (empty when the point failed: see `error`).
    pub mode: Option<Mode>,
    /// Mechanism (empty when the point failed).
    pub mechanism: Option<Mechanism>,
    /// The burst statistics (unknown when the point failed).
    pub rates: Rates,
    /// Largest |dx/da| on a ∈ [−1, 1] (inf with folds in range).
    pub max_slope: f64,
    /// Empty, or the error that stopped this point (its metrics are then NaN).
    pub error: String,
}

/// Runs one point.
pub fn run_point(index: usize, p: &Params, opts: &BurstOptions) -> SweepRow {
    row(index, p, response(p, opts))
}

/// The rows of (index, parameters) pairs, measured together through the batch integrator
/// ([`crate::burst::responses`]): what [`run`] computes for each chunk of
/// [`LANES`](crate::batch::LANES) points, for callers that hold their own points (the Python
/// package). A row is the same whichever points it is computed with.
pub fn run_points(points: &[(usize, Params)], opts: &BurstOptions) -> Vec<SweepRow> {
    let params: Vec<Params> = points.iter().map(|&(_, p)| p).collect();
    let responses = crate::burst::responses(&params, opts);
    points
        .iter()
        .zip(responses)
        .map(|(&(i, p), r)| row(i, &p, r))
        .collect()
}

/// The row of point `index` from its measured response (or the error that stopped it).
fn row(index: usize, p: &Params, result: Result<crate::burst::Response>) -> SweepRow {
    let result = result.map(|r| {
        let slope = fast::max_slope(p, fast::A_RANGE).value;
        (classify(p, &r), r, slope)
    });
    let mut row = SweepRow {
        index,
        params: *p,
        mode: None,
        mechanism: None,
        rates: Rates::unknown(),
        max_slope: f64::NAN,
        error: String::new(),
    };
    match result {
        Ok((c, r, slope)) => {
            row.mode = Some(c.mode);
            row.mechanism = Some(c.mechanism);
            row.rates = r.rates;
            row.max_slope = slope;
        }
        Err(e) => row.error = e.to_string(),
    }
    row
}

/// Runs the grid points `todo` (indices) on `threads` worker threads (0: one per core) and calls
/// `on_row` from the calling thread with each point's row in `todo` order, as soon as it and
/// every point before it are done (the workers take the points in that order, so few wait and
/// memory stays flat however large the grid). Returns when all are done. Points run
/// [`LANES`](crate::batch::LANES) at a time through the batch integrator
/// ([`crate::burst::responses`]).
pub fn run(
    grid: &Grid,
    opts: &BurstOptions,
    todo: &[usize],
    threads: usize,
    on_row: impl FnMut(SweepRow),
) -> Result<()> {
    opts.validate()?;
    let rows = |chunk: &[(usize, Params)]| run_points(chunk, opts);
    run_chunked(grid, todo, crate::batch::LANES, threads, rows, on_row)
}

/// Runs `point(i, parameters of i)` for the grid points `todo` on `threads` worker threads (0:
/// one per core) and calls `on_row` from the calling thread with each result in `todo` order, as
/// [`run`] does: the one parallel loop of sweeps, maps and Lyapunov maps.
pub fn run_with<R: Send>(
    grid: &Grid,
    todo: &[usize],
    threads: usize,
    point: impl Fn(usize, &Params) -> R + Sync,
    on_row: impl FnMut(R),
) -> Result<()> {
    let each = |chunk: &[(usize, Params)]| chunk.iter().map(|(i, p)| point(*i, p)).collect();
    run_chunked(grid, todo, 1, threads, each, on_row)
}

/// The most worker threads a pool may have: beyond the cores of any single node, more threads
/// only add memory (a stack each) and scheduling, never speed.
pub const MAX_THREADS: usize = 1024;

/// Checks a thread count (0: one per core, or `RAYON_NUM_THREADS` when set), refusing more than
/// [`MAX_THREADS`], from the argument or from the environment.
pub fn check_threads(threads: usize) -> Result<()> {
    let from_env = std::env::var("RAYON_NUM_THREADS").ok();
    let (what, text) = match (threads, from_env) {
        (0, Some(env)) => ("RAYON_NUM_THREADS", env),
        _ => ("thread count", threads.to_string()),
    };
    match text.trim().parse::<usize>() {
        Ok(n) if n > MAX_THREADS => Err(Error::InvalidInput {
            what,
            text,
            reason: format!("at most {MAX_THREADS}"),
        }),
        _ => Ok(()),
    }
}

/// A pool of `threads` worker threads (0: one per core), at most [`MAX_THREADS`]; the error names
/// the count.
pub fn pool(threads: usize) -> Result<rayon::ThreadPool> {
    check_threads(threads)?;
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Error::InvalidInput {
            what: "thread count",
            text: threads.to_string(),
            reason: e.to_string(),
        })
}

/// [`run_with`] for work done `chunk` points at a time: `points` gets up to `chunk` (index,
/// parameters) pairs and returns their results. Each worker takes the next chunk of `todo`; the
/// results of a chunk that finishes before an earlier one wait until that one is passed on.
pub fn run_chunked<R: Send>(
    grid: &Grid,
    todo: &[usize],
    chunk: usize,
    threads: usize,
    points: impl Fn(&[(usize, Params)]) -> Vec<R> + Sync,
    mut on_row: impl FnMut(R),
) -> Result<()> {
    let pool = pool(threads)?;
    let chunks: Vec<&[usize]> = todo.chunks(chunk.max(1)).collect();
    let next = AtomicUsize::new(0);
    let workers = pool.current_num_threads();
    let (tx, rx) = std::sync::mpsc::channel::<(usize, Vec<R>)>();
    std::thread::scope(|s| {
        let (points, chunks, next) = (&points, &chunks, &next);
        s.spawn(move || {
            pool.scope(|sc| {
                for _ in 0..workers {
                    let tx = tx.clone();
                    // each worker takes the next chunk in `todo` order, so chunks finish
                    // nearly in that order and few wait below to be passed on
                    sc.spawn(move |_| {
                        loop {
                            let c = next.fetch_add(1, Ordering::Relaxed);
                            let Some(indices) = chunks.get(c) else { break };
                            let work: Vec<(usize, Params)> =
                                indices.iter().map(|&i| (i, grid.point(i))).collect();
                            // the receiver only goes away if the caller panicked
                            if tx.send((c, points(&work))).is_err() {
                                break;
                            }
                        }
                    });
                }
            });
        });
        // results passed on in `todo` order: a chunk waits until every chunk before it is done
        let mut waiting: BTreeMap<usize, Vec<R>> = BTreeMap::new();
        let mut due = 0;
        for (c, rows) in rx {
            waiting.insert(c, rows);
            while let Some(rows) = waiting.remove(&due) {
                due += 1;
                for row in rows {
                    on_row(row);
                }
            }
        }
    });
    Ok(())
}

/// Everything that changes a sweep's rows: hdgear's version, the grid and the options, and for a
/// part of a sharded sweep, which part. The `meta` of a sweep's JSON output, and the settings line
/// of partial and shard files that resuming and merging check.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    /// hdgear's version.
    pub version: String,
    /// The grid.
    pub grid: Grid,
    /// Detection options and tolerances.
    pub options: BurstOptions,
    /// The part of the grid computed (absent for a whole sweep).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<Shard>,
}

impl Settings {
    /// The settings of the whole `grid` run with `options` by this version.
    pub fn new(grid: &Grid, options: &BurstOptions) -> Settings {
        Settings {
            version: env!("CARGO_PKG_VERSION").to_string(),
            grid: grid.clone(),
            options: *options,
            shard: None,
        }
    }

    /// The same settings for one shard of the grid.
    pub fn with_shard(mut self, shard: Option<Shard>) -> Settings {
        self.shard = shard;
        self
    }

    /// The grid points these settings compute, in grid order: the whole grid, or its shard.
    pub fn indices(&self) -> Vec<usize> {
        match self.shard {
            Some(s) => s.indices(self.grid.len()).collect(),
            None => (0..self.grid.len()).collect(),
        }
    }

    /// The first setting in which `self` and `other` differ (keys as paths into the JSON form,
    /// e.g. `grid.axes[0].end`), or `None` when they agree.
    pub fn first_difference(&self, other: &Settings) -> Option<Difference> {
        let (mut a, mut b) = (BTreeMap::new(), BTreeMap::new());
        flatten("", &serde_json::to_value(self).ok()?, &mut a);
        flatten("", &serde_json::to_value(other).ok()?, &mut b);
        let keys: BTreeSet<&String> = a.keys().chain(b.keys()).collect();
        keys.into_iter().find_map(|k| {
            let (x, y) = (a.get(k), b.get(k));
            let text = |v: Option<&String>| v.map_or_else(|| "absent".to_string(), Clone::clone);
            (x != y).then(|| Difference {
                key: k.clone(),
                here: text(x),
                there: text(y),
            })
        })
    }

    /// Checks one row read back from a file written with these settings: a point these settings
    /// compute (index in the grid and in the shard) with that point's parameters.
    pub fn check_row(&self, row: &SweepRow) -> std::result::Result<(), RowError> {
        let i = row.index;
        if i >= self.grid.len() {
            return Err(RowError::OutsideGrid {
                index: i,
                len: self.grid.len(),
            });
        }
        if let Some(s) = self.shard.filter(|s| !s.contains(i)) {
            return Err(RowError::OutsideShard { index: i, shard: s });
        }
        let want = self.grid.point(i);
        if want != row.params {
            return Err(RowError::OtherParameters {
                index: i,
                found: Box::new(row.params),
                grid: Box::new(want),
            });
        }
        Ok(())
    }
}

/// One setting in which two [`Settings`] differ.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Difference {
    /// The setting: a path into the JSON form, e.g. `grid.axes[0].end`.
    pub key: String,
    /// Its value (JSON text) in the first settings, or `absent`.
    pub here: String,
    /// Its value in the second, or `absent`.
    pub there: String,
}

/// A row that does not belong to the file's settings.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RowError {
    /// The row's index is beyond the grid.
    #[error("row index {index} is outside the grid of {len} points")]
    OutsideGrid {
        /// The row's index.
        index: usize,
        /// Points in the grid.
        len: usize,
    },
    /// The row's index is in another shard.
    #[error("grid point {index} is not in shard {shard}")]
    OutsideShard {
        /// The row's index.
        index: usize,
        /// The file's shard.
        shard: Shard,
    },
    /// The row's parameters are not the grid's at its index.
    #[error("row {index} has {}", differing(found, grid))]
    OtherParameters {
        /// The row's index.
        index: usize,
        /// The row's parameters.
        found: Box<Params>,
        /// The grid's parameters at that index.
        grid: Box<Params>,
    },
}

/// "gamma = 0.2 (the grid has 0.1 there)" for each parameter in which `found` differs from
/// `grid`.
fn differing(found: &Params, grid: &Params) -> String {
    Param::ALL
        .iter()
        .filter(|&&q| found.value(q).to_bits() != grid.value(q).to_bits())
        .map(|&q| {
            format!(
                "{q} = {:?} (the grid has {:?} there)",
                found.value(q),
                grid.value(q)
            )
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// Flattens a JSON value into `path → scalar text`.
fn flatten(prefix: &str, v: &serde_json::Value, out: &mut BTreeMap<String, String>) {
    match v {
        serde_json::Value::Object(m) => {
            for (k, x) in m {
                let key = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                flatten(&key, x, out);
            }
        }
        serde_json::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                flatten(&format!("{prefix}[{i}]"), x, out);
            }
        }
        other => {
            out.insert(prefix.to_string(), other.to_string());
        }
    }
}

crate::record!(SweepRow: "index", ..crate::params::Param::NAMES, "mode", "mechanism", "bursts_per_period", "spikes_per_burst", "burst_amplitude", "peak_abs_xdot", "quiescent_duration", "quiescent_fraction", "max_tracking_error", "max_slope", "error");
