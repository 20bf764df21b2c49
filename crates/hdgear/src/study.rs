//! Computations shared by the tables, the figures and the report, each done once.
//!
//! A [`Case`] is one parameter point: the fast-subsystem analysis, the measured response, its
//! classification and samples of its first analysed slow period, all from a single integration.
//! A [`Study`] keeps the cases, sweeps, maps and boundaries computed so far, so that a report that
//! shows the same response in a table and in three figures integrates it once.

use crate::burst::{
    Boundaries, BurstOptions, Classification, Response, boundaries, classify, response_observed,
};
use crate::error::Result;
use crate::fast::{A_RANGE, Analysis, analyze};
use crate::integrate::{self, DenseOutput};
use crate::params::{Param, Params};
use crate::sweep::{Axis, Grid, SweepRow};
use rayon::prelude::*;
use serde::Serialize;

/// Spacing of the samples kept for figures (dimensionless time).
pub const SAMPLE_DT: f64 = 0.05;

/// One parameter point, analysed and simulated once.
///
/// ```
/// use hdgear::{Params, burst::BurstOptions, study::Case};
/// let case = Case::compute(&Params::default(), &BurstOptions::default()).unwrap();
/// assert!(case.classification.bursting);
/// assert!(case.samples.len() > 1000); // one slow period, every 0.05
/// ```
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Case {
    /// The parameters.
    #[serde(skip)]
    pub params: Params,
    /// The fast subsystem over a ∈ [−1, 1].
    pub analysis: Analysis,
    /// Its classification.
    pub classification: Classification,
    /// The measured response.
    pub response: Response,
    /// (τ, x, x') every [`SAMPLE_DT`] over the first analysed slow period (from the window's
    /// start to one period later, that end included), from the same pass as `response`.
    #[serde(skip)]
    pub samples: Vec<(f64, f64, f64)>,
}

impl Case {
    /// Analyses the fast subsystem and simulates the default start once.
    pub fn compute(p: &Params, opts: &BurstOptions) -> Result<Case> {
        let analysis = analyze(p, A_RANGE)?;
        let (t0, _) = crate::burst::window(p, opts);
        let t1 = t0 + p.slow_period();
        // the run's length against the step budget first: a run refused for its length is
        // refused for that, with its step estimate, not for the samples it would have kept
        integrate::check_budget(t1, &opts.tol)?;
        // the grid k·dt from τ = 0 to the period's end, as `simulate` samples it, kept from the
        // window's start
        let mut grid = integrate::SampleGrid::new(0.0, t1, SAMPLE_DT)?;
        let mut samples = Vec::new();
        let mut push = |t: f64, y: &[f64; 2]| {
            if t >= t0 {
                samples.push((t, y[0], y[1]));
            }
        };
        let mut keep = |d: &dyn DenseOutput<2>| {
            if d.t_start() < t1 {
                let y_end = d.eval(d.t_end().min(t1));
                grid.fill(d, &y_end, &mut push);
                if d.t_end() >= t1 {
                    grid.finish(&y_end, &mut push);
                }
            }
        };
        let response = response_observed(p, opts, Some(&mut keep))?;
        let classification = classify(p, &response);
        Ok(Case {
            params: *p,
            analysis,
            classification,
            response,
            samples,
        })
    }

    /// The end of the sampled slow period.
    pub fn sample_end(&self) -> f64 {
        self.response.window_start + self.params.slow_period()
    }
}

/// A γ sweep or a (γ, δ) map: the grid and its rows in grid order.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct GridRun {
    /// The grid.
    pub grid: Grid,
    /// One row per grid point, in grid order.
    pub rows: Vec<SweepRow>,
}

/// What the figures and the report compute, each once: cases by parameter point, sweeps and maps
/// by grid, bursting boundaries by parameter point.
#[derive(Clone, Debug)]
pub struct Study {
    /// Options of single responses.
    pub opts: BurstOptions,
    /// Options of the grid runs (sweeps, maps, boundary searches), which only need verdicts and
    /// counts.
    pub grid_opts: BurstOptions,
    /// Worker threads (0: one per core).
    pub threads: usize,
    /// Points of a γ sweep.
    pub sweep_points: usize,
    /// Size of a (γ, δ) map.
    pub map_size: (usize, usize),
    cases: Vec<Case>,
    runs: Vec<GridRun>,
    boundaries: Vec<(Params, Boundaries)>,
}

/// Runs a grid on `threads` threads (0: all) and returns its rows in grid order.
pub fn run_grid(grid: &Grid, opts: &BurstOptions, threads: usize) -> Result<Vec<SweepRow>> {
    let mut rows = Vec::with_capacity(grid.len());
    crate::sweep::run(
        grid,
        opts,
        &(0..grid.len()).collect::<Vec<_>>(),
        threads,
        |r| rows.push(r),
    )?;
    Ok(rows)
}

impl Study {
    /// An empty study: `opts` for single responses, `grid_opts` for grids, sweeps of
    /// `sweep_points` and maps of `map_size`.
    pub fn new(
        opts: BurstOptions,
        grid_opts: BurstOptions,
        threads: usize,
        sweep_points: usize,
        map_size: (usize, usize),
    ) -> Study {
        Study {
            opts,
            grid_opts,
            threads,
            sweep_points,
            map_size,
            cases: Vec::new(),
            runs: Vec::new(),
            boundaries: Vec::new(),
        }
    }

    /// The cases of `points`, computing the missing ones in parallel.
    pub fn cases(&mut self, points: &[Params]) -> Result<Vec<&Case>> {
        let mut missing: Vec<Params> = Vec::new();
        for p in points {
            if !self.cases.iter().any(|c| c.params == *p) && !missing.contains(p) {
                missing.push(*p);
            }
        }
        let opts = self.opts;
        let new = missing
            .par_iter()
            .map(|p| Case::compute(p, &opts))
            .collect::<Result<Vec<_>>>()?;
        self.cases.extend(new);
        Ok(points
            .iter()
            .filter_map(|p| self.cases.iter().find(|c| c.params == *p))
            .collect())
    }

    /// The case of `p`.
    pub fn case(&mut self, p: &Params) -> Result<&Case> {
        let mut v = self.cases(std::slice::from_ref(p))?;
        Ok(v.remove(0))
    }

    /// The γ sweep around `base`: [`Study::sweep_points`] values log-spaced from 0.01 to 30.
    pub fn sweep(&mut self, base: &Params) -> Result<&GridRun> {
        let axes = vec![log_axis(Param::Gamma, 0.01, 30.0, self.sweep_points)];
        self.grid_run(Grid::new(*base, axes)?)
    }

    /// The (γ, δ) map around `base`: γ log-spaced 0.01–30, δ log-spaced 0.05–30, of
    /// [`Study::map_size`].
    pub fn map(&mut self, base: &Params) -> Result<&GridRun> {
        let (ng, nd) = self.map_size;
        let axes = vec![
            log_axis(Param::Gamma, 0.01, 30.0, ng),
            log_axis(Param::Delta, 0.05, 30.0, nd),
        ];
        self.grid_run(Grid::new(*base, axes)?)
    }

    /// The run of `grid`, computed the first time it is asked for.
    fn grid_run(&mut self, grid: Grid) -> Result<&GridRun> {
        let i = match self.runs.iter().position(|r| r.grid == grid) {
            Some(i) => i,
            None => {
                let rows = run_grid(&grid, &self.grid_opts, self.threads)?;
                self.runs.push(GridRun { grid, rows });
                self.runs.len() - 1
            }
        };
        Ok(&self.runs[i])
    }

    /// The bursting boundaries through each of `points` (predicted, and where the simulated verdict switches),
    /// the missing ones computed in parallel.
    pub fn boundaries(&mut self, points: &[Params]) -> Result<Vec<Boundaries>> {
        let missing: Vec<Params> = points
            .iter()
            .filter(|p| !self.boundaries.iter().any(|b| b.0 == **p))
            .copied()
            .collect();
        let opts = self.grid_opts;
        let new = missing
            .par_iter()
            .map(|p| Ok((*p, boundaries(p, &opts)?)))
            .collect::<Result<Vec<_>>>()?;
        self.boundaries.extend(new);
        Ok(points
            .iter()
            .filter_map(|p| self.boundaries.iter().find(|b| b.0 == *p).map(|b| b.1))
            .collect())
    }
}

/// A log-spaced axis of `count` values of `param` from `start` to `end`.
fn log_axis(param: Param, start: f64, end: f64, count: usize) -> Axis {
    Axis {
        param,
        start,
        end,
        count,
        log: true,
    }
}

/// What `hdgear analyze` reports for a parameter point: the fast subsystem, and, when asked for,
/// the measured response with its classification and the bursting boundaries.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PointAnalysis {
    /// The fast subsystem (its fields at the top level).
    #[serde(flatten)]
    pub analysis: Analysis,
    /// The measured response.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub response: Option<Response>,
    /// Its classification.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub classification: Option<Classification>,
    /// The bursting boundaries through the point.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub boundaries: Option<Boundaries>,
    /// Remarks on the parameter set, as text.
    pub warnings: Vec<String>,
}

/// What `hdgear analyze` reports for a model with terms ([`analyze_model`]): its equilibrium
/// curve's analysis at its own damping at rest and, when asked for, the measured response against
/// that curve.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelAnalysis {
    /// The model (serialised as its description).
    pub model: crate::model::Model,
    /// Its equilibrium curve's analysis.
    pub analysis: crate::fast::CurveAnalysis,
    /// The measured response.
    pub response: Option<Response>,
    /// Its classification.
    pub classification: Option<Classification>,
    /// Remarks on the parameter set, as text.
    pub warnings: Vec<String>,
}

/// The analysis of `m`'s equilibrium curve ([`crate::model::AnyCurve`]) over `a_range` and,
/// with `response` options, its measured response and classification.
///
/// ```
/// use hdgear::{Params, burst::BurstOptions, model::{Model, terms::AnyTerm}};
/// let m = Model::study(&Params::default())
///     .with_term(AnyTerm::new("friction", &[0.1, 0.05]).unwrap())
///     .unwrap();
/// let a = hdgear::study::analyze_model(&m, (-1.0, 1.0), None, Vec::new()).unwrap();
/// // the damping at rest is the unit damping plus the friction's slope f_c/v_s at rest
/// assert!((a.analysis.damping_at_rest - 3.0).abs() < 1e-12);
/// assert!(a.response.is_none() && a.analysis.folds.is_empty()); // γ = 0.1: g' > 0 throughout
/// ```
pub fn analyze_model(
    m: &crate::model::Model,
    a_range: (f64, f64),
    response: Option<&BurstOptions>,
    warnings: Vec<String>,
) -> Result<ModelAnalysis> {
    use crate::model::AnyCurve;
    let analysis = match AnyCurve::of(m)? {
        AnyCurve::Torque(c) => crate::fast::curve_analysis(&c, a_range)?,
        AnyCurve::Scheduled(c) => crate::fast::curve_analysis(&c, a_range)?,
    };
    let (response, classification) = match response {
        Some(opts) => {
            let r = crate::burst::response_model(m, opts)?;
            let c = crate::burst::classify_model(m, &r)?;
            (Some(r), Some(c))
        }
        None => (None, None),
    };
    Ok(ModelAnalysis {
        model: *m,
        analysis,
        response,
        classification,
        warnings,
    })
}
