//! Parameter sweeps: one- or two-parameter grids run in parallel, one [`SweepRow`] per point.
//!
//! Every point is computed independently and deterministically (same input, same bits), so the
//! result does not depend on the number of threads or on the order in which points finish.
//! Rows are handed to the caller as they finish (for streaming and resuming); the caller puts
//! them in grid order at the end.
//!
//! **Why one file.** The axis, the grid, the `Sweep` seam (the study's set and a model) and the row
//! a point gives are one vocabulary that every sweep command and the maps use; the maps and the
//! shards live apart.

use crate::burst::{BurstOptions, Mechanism, Mode, PlaneSystem, Rates, classify, response};
use crate::error::{Error, Result};
use crate::fast;
use crate::model::{Model, ModelParam};
use crate::output::Record;
use crate::params::{Param, Params};
use crate::periodic::{DiagramOptions, LyapunovRow};
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, BTreeSet};
use std::sync::atomic::{AtomicUsize, Ordering};

pub use crate::refine;
mod maps;
pub use maps::lyapunov_map;
mod shard;
pub use shard::{MergeError, Plan, Shard, plan};

/// One axis of a grid: `NAME=START:END:COUNT[:log]`, NAME one of the study's parameters
/// ([`Axis::parse`]) or any of a model's ([`Axis::parse_for`]: `coulomb.fs`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Axis<P = Param> {
    /// The swept parameter (serialised as `name`: alpha, gamma, eps, mu, delta, omega, or a
    /// model's parameter name).
    #[serde(rename = "name")]
    pub param: P,
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
    /// Parses `NAME=START:END:COUNT[:log]` with NAME one of the study's parameters; errors name
    /// the offending text.
    ///
    /// ```
    /// let ax = hdgear::sweep::Axis::parse("gamma=0.05:30:200:log").unwrap();
    /// assert_eq!((ax.count, ax.log), (200, true));
    /// assert!((ax.value(199) - 30.0).abs() < 1e-12);
    /// ```
    pub fn parse(text: &str) -> Result<Axis> {
        Axis::parse_with(text, |name| {
            name.parse().map_err(|_| {
                format!(
                    "unknown parameter '{name}' (expected one of {})",
                    Param::ALL.map(Param::name).join(", ")
                )
            })
        })
    }
}

impl<P> Axis<P> {
    /// Parses `NAME=START:END:COUNT[:log]` with NAME any parameter of `system` (a model's `fs`
    /// or `coulomb.fs`, [`crate::model::Model::param`]).
    ///
    /// ```
    /// use hdgear::{Params, model::{Model, terms::AnyTerm}, sweep::Axis};
    /// let m = Model::study(&Params::default())
    ///     .with_term(AnyTerm::new("friction", &[0.1, 0.05]).unwrap())
    ///     .unwrap();
    /// let ax = Axis::parse_for("friction.fc=0:0.5:11", &m).unwrap();
    /// assert_eq!((ax.param.name(), ax.count), ("fc", 11));
    /// assert!(Axis::parse_for("friction.nope=0:1:2", &m).is_err());
    /// ```
    pub fn parse_for<S: Sweep<Param = P>>(text: &str, system: &S) -> Result<Axis<P>> {
        Axis::parse_with(text, |name| crate::periodic::lookup_in(system, name))
    }

    /// Parses `NAME=START:END:COUNT[:log]`, NAME by `lookup` (its error is the reason shown).
    fn parse_with(
        text: &str,
        lookup: impl FnOnce(&str) -> std::result::Result<P, String>,
    ) -> Result<Axis<P>> {
        let bad = |reason: &str| Error::InvalidInput {
            what: "sweep axis",
            text: text.to_string(),
            reason: reason.to_string(),
        };
        let (name, spec) = text
            .split_once('=')
            .ok_or_else(|| bad("expected NAME=START:END:COUNT[:log]"))?;
        let param = lookup(name.trim()).map_err(|reason| bad(&reason))?;
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

/// What a grid sweeps: the study's parameter set ([`Params`], its rows measured 16 at a time by
/// the batch integrator) or a model assembled from terms ([`Model`], any of its parameters on an
/// axis), each row the burst verdict on one point.
///
/// A grid point is set and checked as a plane's point is ([`PlaneSystem::set`],
/// [`PlaneSystem::check`]).
pub trait Sweep:
    crate::periodic::Periodic
    + PlaneSystem<Axis = <Self as crate::periodic::Oscillator>::Param>
    + PartialEq
{
    /// What a row records of its point: the study's six parameters, or a model's swept values.
    type Point: Serialize + Copy + PartialEq + std::fmt::Debug + Send;
    /// The record of a point swept on `axes`.
    fn point_of(&self, axes: &[Axis<Self::Param>]) -> Self::Point;
    /// The rows of (index, point) pairs measured with `opts`.
    fn rows(
        points: &[(usize, Self)],
        axes: &[Axis<Self::Param>],
        opts: &BurstOptions,
    ) -> Vec<SweepRow<Self::Point>>;
    /// The Lyapunov map's rows of (index, point) pairs ([`lyapunov_map`]).
    fn lyapunov_rows(
        points: &[(usize, Self)],
        axes: &[Axis<Self::Param>],
        opts: &DiagramOptions,
    ) -> Vec<LyapunovRow<Self::Point>>;
    /// How many points a worker takes at once (the batch integrator's lanes for the study).
    const CHUNK: usize;
    /// The column names of a point swept on `axes`: the study's six, or the swept parameters'.
    fn point_columns(axes: &[Axis<Self::Param>]) -> Vec<&'static str>;
    /// The (name, value) of each parameter a point records.
    fn entries(point: &Self::Point) -> Vec<(&'static str, f64)>;
    /// A row read back by position from a CSV record with the columns of [`columns`].
    fn read_row(
        record: &csv::StringRecord,
        axes: &[Axis<Self::Param>],
    ) -> std::result::Result<SweepRow<Self::Point>, csv::Error>;
}

/// The column names, in field order, of rows of the kind `R` (a [`SweepRow`], a
/// [`LyapunovRow`]) of a grid over `axes`: `index`, the point's ([`Sweep::point_columns`]), then
/// the row's own after the study's six.
pub fn columns<S: Sweep, R: Record>(axes: &[Axis<S::Param>]) -> Vec<&'static str> {
    let (index, rest) = R::COLUMNS.split_at(1);
    let own = &rest[Param::ALL.len()..];
    let point = S::point_columns(axes);
    index
        .iter()
        .copied()
        .chain(point)
        .chain(own.iter().copied())
        .collect()
}

impl Sweep for Params {
    type Point = Params;
    fn point_of(&self, _axes: &[Axis]) -> Params {
        *self
    }
    fn rows(points: &[(usize, Params)], _axes: &[Axis], opts: &BurstOptions) -> Vec<SweepRow> {
        run_points(points, opts)
    }
    fn lyapunov_rows(
        points: &[(usize, Params)],
        _axes: &[Axis],
        opts: &DiagramOptions,
    ) -> Vec<LyapunovRow> {
        crate::periodic::lyapunov_points(points, opts)
    }
    const CHUNK: usize = crate::batch::LANES;
    fn point_columns(_axes: &[Axis]) -> Vec<&'static str> {
        Param::NAMES.to_vec()
    }
    fn entries(point: &Params) -> Vec<(&'static str, f64)> {
        Param::ALL.map(|q| (q.name(), point.value(q))).to_vec()
    }
    fn read_row(record: &csv::StringRecord, _axes: &[Axis]) -> csv::Result<SweepRow> {
        record.deserialize(None)
    }
}

impl Sweep for Model {
    type Point = Values;
    fn point_of(&self, axes: &[Axis<ModelParam>]) -> Values {
        Values::of(axes, axes.iter().map(|ax| self.get(ax.param)))
    }
    fn rows(
        points: &[(usize, Model)],
        axes: &[Axis<ModelParam>],
        opts: &BurstOptions,
    ) -> Vec<SweepRow<Values>> {
        points
            .iter()
            .map(|(i, m)| row(*i, m.point_of(axes), crate::burst::verdict_model(m, opts)))
            .collect()
    }
    fn lyapunov_rows(
        points: &[(usize, Model)],
        axes: &[Axis<ModelParam>],
        opts: &DiagramOptions,
    ) -> Vec<LyapunovRow<Values>> {
        points
            .iter()
            .map(|(i, m)| {
                let measured = crate::periodic::lyapunov_of(m, opts).map_err(|e| e.to_string());
                LyapunovRow::new(*i, m.point_of(axes), measured)
            })
            .collect()
    }
    const CHUNK: usize = 1;
    fn point_columns(axes: &[Axis<ModelParam>]) -> Vec<&'static str> {
        axes.iter().map(|a| a.param.name()).collect()
    }
    fn entries(point: &Values) -> Vec<(&'static str, f64)> {
        point.iter().collect()
    }
    fn read_row(
        record: &csv::StringRecord,
        axes: &[Axis<ModelParam>],
    ) -> csv::Result<SweepRow<Values>> {
        // by position: the index, one value per axis, then the verdict's columns (read as one
        // tuple whose nested statistics are flat columns, as a study row's are)
        let k = axes.len().min(2);
        let head = csv::StringRecord::from(record.iter().take(1 + k).collect::<Vec<_>>());
        let (index, values): (usize, Vec<f64>) = head.deserialize(None)?;
        let tail = csv::StringRecord::from(record.iter().skip(1 + k).collect::<Vec<_>>());
        let (mode, mechanism, rates, max_slope, error) = tail.deserialize(None)?;
        Ok(SweepRow {
            index,
            params: Values::of(axes, values),
            mode,
            mechanism,
            rates,
            max_slope,
            error,
        })
    }
}

/// A model grid point's record: the values of the swept parameters, written as columns named
/// by the parameters (`fs`, `delta`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Values {
    names: [&'static str; 2],
    values: [f64; 2],
    len: usize,
}

impl Values {
    /// The values of the parameters of `axes` (at most two), in axis order.
    fn of(axes: &[Axis<ModelParam>], values: impl IntoIterator<Item = f64>) -> Values {
        let mut v = Values {
            names: [""; 2],
            values: [0.0; 2],
            len: axes.len().min(2),
        };
        for (k, (ax, value)) in axes.iter().zip(values).take(2).enumerate() {
            v.names[k] = ax.param.name();
            v.values[k] = value;
        }
        v
    }

    /// (name, value) of each swept parameter, in axis order.
    pub fn iter(&self) -> impl Iterator<Item = (&'static str, f64)> + '_ {
        self.names[..self.len]
            .iter()
            .copied()
            .zip(self.values[..self.len].iter().copied())
    }
}

impl Serialize for Values {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut out = s.serialize_struct("Values", self.len)?;
        for (name, value) in self.iter() {
            out.serialize_field(name, &value)?;
        }
        out.end()
    }
}

/// A grid of one or two axes over a base system (the study's parameter set, or a model). Index i
/// runs over the first axis fastest.
///
/// Deserialising does not check it: pass a grid read from a file through [`Grid::new`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(bound(
    serialize = "S: Serialize, S::Param: Serialize",
    deserialize = "S: Deserialize<'de>, S::Param: Deserialize<'de>"
))]
pub struct Grid<S: Sweep = Params> {
    /// The parameters not swept.
    pub base: S,
    /// One or two axes with distinct names.
    pub axes: Vec<Axis<S::Param>>,
}

impl<S: Sweep> Grid<S> {
    /// Checks the axes (one or two, distinct) and that every grid point is a valid parameter set,
    /// so an impossible range fails before any work is done.
    pub fn new(base: S, axes: Vec<Axis<S::Param>>) -> Result<Grid<S>> {
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
            g.at(i)?;
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

    /// The system at index i, checked.
    pub fn at(&self, i: usize) -> Result<S> {
        let p = self.set_axes(i)?;
        PlaneSystem::check(&p)?;
        Ok(p)
    }

    /// The base with each axis set to its value at index i ([`PlaneSystem::set`]).
    fn set_axes(&self, i: usize) -> Result<S> {
        let mut rest = i;
        let changes: Vec<(S::Param, f64)> = self
            .axes
            .iter()
            .map(|ax| {
                let j = rest % ax.count;
                rest /= ax.count;
                (ax.param, ax.value(j))
            })
            .collect();
        self.base.set(&changes)
    }
}

impl Grid {
    /// The parameter set at index i (unchecked: [`Grid::new`] checked every point).
    pub fn point(&self, i: usize) -> Params {
        // setting a study parameter cannot fail ([`PlaneSystem::set`] for `Params`)
        self.set_axes(i).unwrap_or(self.base)
    }
}

/// One sweep result: the CSV columns of `hdgear sweep` (nested structs are written as their
/// fields in order, so the columns stay flat; JSON keeps the nesting).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, crate::output::Record)]
pub struct SweepRow<V = Params> {
    /// Grid index (first axis fastest).
    pub index: usize,
    /// The point's parameters (the study's six; a model's swept ones, [`Values`]).
    #[record(nested)]
    pub params: V,
    /// Oscillation mode (empty when the point failed: see `error`).
    pub mode: Option<Mode>,
    /// Mechanism (empty when the point failed).
    pub mechanism: Option<Mechanism>,
    /// The burst statistics (unknown when the point failed).
    #[record(nested)]
    pub rates: Rates,
    /// Largest |dx/da| on a ∈ [−1, 1] (inf with folds in range).
    pub max_slope: f64,
    /// Empty, or the error that stopped this point (its metrics are then NaN).
    pub error: String,
}

/// Runs one point.
pub fn run_point(index: usize, p: &Params, opts: &BurstOptions) -> SweepRow {
    row_of(index, p, response(p, opts))
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
        .map(|(&(i, p), r)| row_of(i, &p, r))
        .collect()
}

/// The row of point `index` from its measured response (or the error that stopped it).
fn row_of(index: usize, p: &Params, result: Result<crate::burst::Response>) -> SweepRow {
    let verdict = result.map(|r| {
        let slope = fast::max_slope(p, fast::A_RANGE).value;
        (classify(p, &r), r, slope)
    });
    row(index, *p, verdict)
}

/// The row of point `index` recorded as `point` from its classification, response and largest
/// |dx/da| (or the error that stopped it).
fn row<V>(index: usize, point: V, verdict: Result<crate::burst::PointVerdict>) -> SweepRow<V> {
    let mut row = SweepRow {
        index,
        params: point,
        mode: None,
        mechanism: None,
        rates: Rates::unknown(),
        max_slope: f64::NAN,
        error: String::new(),
    };
    match verdict {
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
pub fn run<S: Sweep>(
    grid: &Grid<S>,
    opts: &BurstOptions,
    todo: &[usize],
    threads: usize,
    on_row: impl FnMut(SweepRow<S::Point>),
) -> Result<()> {
    opts.validate()?;
    let rows = |chunk: &[(usize, S)]| S::rows(chunk, &grid.axes, opts);
    run_chunked(grid, todo, S::CHUNK, threads, rows, on_row)
}

/// Runs `point(i, parameters of i)` for the grid points `todo` on `threads` worker threads (0:
/// one per core) and calls `on_row` from the calling thread with each result in `todo` order, as
/// [`run`] does: the one parallel loop of sweeps, maps and Lyapunov maps.
pub fn run_with<S: Sweep, R: Send>(
    grid: &Grid<S>,
    todo: &[usize],
    threads: usize,
    point: impl Fn(usize, &S) -> R + Sync,
    on_row: impl FnMut(R),
) -> Result<()> {
    let each = |chunk: &[(usize, S)]| chunk.iter().map(|(i, p)| point(*i, p)).collect();
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
pub fn run_chunked<S: Sweep, R: Send>(
    grid: &Grid<S>,
    todo: &[usize],
    chunk: usize,
    threads: usize,
    points: impl Fn(&[(usize, S)]) -> Vec<R> + Sync,
    mut on_row: impl FnMut(R),
) -> Result<()> {
    // every point checked before any work (a grid's fields are public, so it may not have come
    // through Grid::new): the workers below then set them without a failure to pass on
    for &i in todo {
        grid.at(i)?;
    }
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
                            let work: Vec<(usize, S)> = indices
                                .iter()
                                .filter_map(|&i| Some((i, grid.at(i).ok()?)))
                                .collect();
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
#[serde(bound(
    serialize = "S: Serialize, S::Param: Serialize",
    deserialize = "S: Deserialize<'de>, S::Param: Deserialize<'de>"
))]
pub struct Settings<S: Sweep = Params> {
    /// hdgear's version.
    pub version: String,
    /// The grid.
    pub grid: Grid<S>,
    /// Detection options and tolerances.
    pub options: BurstOptions,
    /// The part of the grid computed (absent for a whole sweep).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<Shard>,
}

impl<S: Sweep> Settings<S> {
    /// The settings of the whole `grid` run with `options` by this version.
    pub fn new(grid: &Grid<S>, options: &BurstOptions) -> Settings<S> {
        Settings {
            version: env!("CARGO_PKG_VERSION").to_string(),
            grid: grid.clone(),
            options: *options,
            shard: None,
        }
    }

    /// The same settings for one shard of the grid.
    pub fn with_shard(mut self, shard: Option<Shard>) -> Settings<S> {
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
    pub fn first_difference(&self, other: &Settings<S>) -> Option<Difference> {
        first_difference(
            &serde_json::to_value(self).ok()?,
            &serde_json::to_value(other).ok()?,
        )
    }

    /// Checks one row read back from a file written with these settings: a point these settings
    /// compute (index in the grid and in the shard) with that point's parameters.
    pub fn check_row(&self, row: &SweepRow<S::Point>) -> std::result::Result<(), RowError> {
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
        let want = self
            .grid
            .set_axes(i)
            .ok()
            .map(|p| p.point_of(&self.grid.axes));
        if want.as_ref() != Some(&row.params) {
            return Err(RowError::OtherParameters {
                index: i,
                found: S::entries(&row.params),
                grid: want.map(|w| S::entries(&w)).unwrap_or_default(),
            });
        }
        Ok(())
    }
}

/// The first setting in which the JSON forms `here` and `there` of two [`Settings`] differ (keys
/// as paths, e.g. `grid.axes[0].end`): how a file's settings line is compared with a sweep's
/// whatever it sweeps (a model's settings are written, not read back).
pub fn first_difference(here: &serde_json::Value, there: &serde_json::Value) -> Option<Difference> {
    let (mut a, mut b) = (BTreeMap::new(), BTreeMap::new());
    flatten("", here, &mut a);
    flatten("", there, &mut b);
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
#[non_exhaustive]
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
        /// The row's parameters, (name, value).
        found: Vec<(&'static str, f64)>,
        /// The grid's parameters at that index (none when the grid cannot set them).
        grid: Vec<(&'static str, f64)>,
    },
}

/// "gamma = 0.2 (the grid has 0.1 there)" for each parameter in which `found` differs from
/// `grid`.
fn differing(found: &[(&'static str, f64)], grid: &[(&'static str, f64)]) -> String {
    found
        .iter()
        .zip(grid)
        .filter(|((_, f), (_, g))| f.to_bits() != g.to_bits())
        .map(|((name, f), (_, g))| format!("{name} = {f:?} (the grid has {g:?} there)"))
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
