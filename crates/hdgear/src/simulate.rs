//! Simulation of the dimensionless model: a sampled trajectory and its summary.

use crate::error::Result;
use crate::fast::stable_equilibrium;
use crate::integrate::events::{Detector, Direction};
use crate::integrate::{DenseOutput, Options, SampleGrid, Stats, Stepper, System, stepper};
use crate::model::delayed::Delayed;
use crate::model::switching::{Pieces, Switching, SwitchingMode};
use crate::model::{Description, Dimensionless, Model};
use crate::params::Params;
use serde::Serialize;

/// Where a simulation starts.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Start {
    /// On the stable equilibrium of the fast subsystem at a(0) = 0, at rest (see
    /// [`stable_equilibrium`]): no start-up transient beyond the slow drift. At rest is x' = 0,
    /// or for a model with a kinematic error the rate that holds the total twist at rest
    /// ([`crate::model::Model::rest_rate`]).
    Equilibrium,
    /// x = 0, at rest as above (the reference trajectories in `tests/data/` start here).
    Rest,
    /// A given (x0, x'0).
    Given {
        /// x(0)
        x0: f64,
        /// x'(0)
        v0: f64,
    },
}

impl Start {
    /// Checks a given state: both components finite and below the integration's blow-up bound
    /// ([`crate::integrate::Options::blowup`]), since a state beyond it has blown up before the
    /// first step. The other starts are always usable.
    pub fn check(self, tol: &crate::integrate::Options) -> Result<()> {
        if let Start::Given { x0, v0 } = self {
            for (name, v) in [("x0", x0), ("v0", v0)] {
                if v.is_nan() || v.abs() >= tol.blowup {
                    return crate::error::bad_option(
                        name,
                        v,
                        "must be finite and below the integration's blow-up bound in magnitude",
                    );
                }
            }
        }
        Ok(())
    }
}

/// What to simulate and how finely.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SimOptions {
    /// End time τ_end (dimensionless) > 0.
    pub t_end: f64,
    /// Output spacing > 0 (samples come from dense output; they do not change the steps).
    pub dt: f64,
    /// Initial condition.
    pub start: Start,
    /// Integrator tolerances.
    pub tol: Options,
}

impl Default for SimOptions {
    /// Three slow periods of the study's ω (3·2π/0.01), dt = 0.05, start on the equilibrium,
    /// rtol = atol = 1e-10.
    fn default() -> Self {
        SimOptions {
            t_end: 3.0 * std::f64::consts::TAU / 0.01,
            dt: 0.05,
            start: Start::Equilibrium,
            tol: Options::default(),
        }
    }
}

/// One sample of a trajectory in the plane: the columns `t,x,xdot`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, crate::output::Record)]
pub struct StateSample {
    /// τ.
    pub t: f64,
    /// x.
    pub x: f64,
    /// x'.
    pub xdot: f64,
}

impl From<[f64; 3]> for StateSample {
    /// (τ, x, x') as an orbit's samples hold them.
    fn from([t, x, xdot]: [f64; 3]) -> StateSample {
        StateSample { t, x, xdot }
    }
}

/// The outcome of a simulation besides its samples.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SimSummary {
    /// Final time.
    pub t_end: f64,
    /// Initial state [x, x'].
    pub initial: [f64; 2],
    /// Final state [x, x'].
    pub final_state: [f64; 2],
    /// Integrator work.
    pub stats: Stats,
    /// max |x'| over the run, located exactly: over step ends and at every extremum of x'
    /// (zeros of x'' found on the dense output), not just at the samples.
    pub max_abs_xdot: f64,
    /// For a model with a switching term: its switches and time at rest.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sticking: Option<Sticking>,
}

/// The initial state for a start rule.
pub fn initial_state(p: &Params, start: Start) -> [f64; 2] {
    match start {
        Start::Equilibrium => [stable_equilibrium(p, 0.0), 0.0],
        Start::Rest => [0.0, 0.0],
        Start::Given { x0, v0 } => [x0, v0],
    }
}

/// Simulates from τ = 0 to `opts.t_end`, calling `out(τ, [x, x'])` at every output time (see
/// [`crate::integrate::sample`] for the grid), and returns the summary.
pub fn simulate(
    p: &Params,
    opts: &SimOptions,
    out: impl FnMut(f64, &[f64; 2]),
) -> Result<SimSummary> {
    sampled(
        &Dimensionless::new(*p),
        opts,
        checked_start(p, opts)?,
        out,
        |_| {},
    )
}

/// [`simulate`] without the samples: the summary alone, `at(τ)` called after every step (for
/// progress). Nothing is evaluated between the steps (`simulate` evaluates the step polynomial at
/// every output time, 37,700 times for the default three slow periods at dt = 0.05).
///
/// ```
/// use hdgear::{Params, simulate::{SimOptions, simulate, summarize}};
/// let (p, opts) = (Params::default(), SimOptions::default());
/// let alone = summarize(&p, &opts, |_| {}).unwrap();
/// assert_eq!(alone, simulate(&p, &opts, |_, _| {}).unwrap());
/// ```
pub fn summarize(p: &Params, opts: &SimOptions, mut at: impl FnMut(f64)) -> Result<SimSummary> {
    let sys = Dimensionless::new(*p);
    let y0 = checked_start(p, opts)?;
    let mut solver = stepper(&sys, 0.0, y0, opts.tol)?;
    let accel = |t: f64, y: &[f64; 2]| sys.rhs(t, y)[1];
    run(&mut solver, accel, opts, y0, |d, _| at(d.t_end()))
}

/// [`simulate`] for a model assembled from terms ([`Model`]): the same grid, start rules and
/// summary, every method derived from the model's terms. The equilibrium start is the model's
/// ([`Model::stable_equilibrium`] at a = 0). A model with a switching term (Coulomb friction with
/// sticking) is integrated piece by piece ([`crate::model::switching`]) and its summary counts
/// the switches and the time spent stuck ([`Sticking`]).
///
/// ```
/// use hdgear::{Params, model::{Model, terms::AnyTerm}, simulate::{SimOptions, simulate_model}};
/// let m = Model::study(&Params::default())
///     .with_term(AnyTerm::new("friction", &[0.05, 0.01]).unwrap())
///     .unwrap();
/// let opts = SimOptions { t_end: 100.0, ..SimOptions::default() };
/// let s = simulate_model(&m, &opts, |_, _| {}).unwrap();
/// assert_eq!(s.t_end, 100.0);
/// assert!(s.sticking.is_none());
/// ```
pub fn simulate_model(
    m: &Model,
    opts: &SimOptions,
    out: impl FnMut(f64, &[f64]),
) -> Result<SimSummary> {
    simulate_model_steps(m, opts, out, |_| {})
}

/// One accepted step of a model's run, as [`simulate_model_steps`] shows it: the solution
/// anywhere in it (what an exact integral over the run reads, rather than the output grid).
pub trait ModelStep {
    /// The step's span [t0, t1].
    fn span(&self) -> (f64, f64);
    /// The state at t in the span, into `y` (the model's [`Model::dim`] components).
    fn state(&self, t: f64, y: &mut [f64]);
}

/// A step's dense output seen as a [`ModelStep`].
struct Step<'a, D, const N: usize>(&'a D);

impl<D: DenseOutput<N>, const N: usize> ModelStep for Step<'_, D, N> {
    fn span(&self) -> (f64, f64) {
        (self.0.t_start(), self.0.t_end())
    }
    fn state(&self, t: f64, y: &mut [f64]) {
        y[..N].copy_from_slice(&self.0.eval(t));
    }
}

/// [`simulate_model`], also showing every accepted step to `on_step` (in order, after the
/// output grid's points in it).
pub fn simulate_model_steps(
    m: &Model,
    opts: &SimOptions,
    out: impl FnMut(f64, &[f64]),
    on_step: impl FnMut(&dyn ModelStep),
) -> Result<SimSummary> {
    m.check()?;
    crate::integrate::check_budget(opts.t_end, &opts.tol)?;
    crate::integrate::check_rate_budget(opts.t_end, m.fastest_rate(), &opts.tol)?;
    opts.start.check(&opts.tol)?;
    let (x0, v0) = match opts.start {
        Start::Equilibrium => (m.stable_equilibrium(0.0)?, m.rest_rate()),
        Start::Rest => (0.0, m.rest_rate()),
        Start::Given { x0, v0 } => (x0, v0),
    };
    let [z0, z1] = m.rest_states(x0);
    match m.dim() {
        2 => model_run::<2>(m, opts, [x0, v0], out, on_step),
        3 => model_run::<3>(m, opts, [x0, v0, z0], out, on_step),
        _ => model_run::<4>(m, opts, [x0, v0, z0, z1], out, on_step),
    }
}

/// [`simulate_model`] on a state of N = [`Model::dim`] components (the internal states start
/// at rest at x0: [`Model::rest_states`]).
fn model_run<const N: usize>(
    m: &Model,
    opts: &SimOptions,
    y0: [f64; N],
    mut out: impl FnMut(f64, &[f64]),
    mut on_step: impl FnMut(&dyn ModelStep),
) -> Result<SimSummary> {
    let mut out = |t: f64, y: &[f64; N]| out(t, y);
    if let Some(sys) = Delayed::new(m, &y0) {
        let opts = SimOptions {
            tol: sys.options(opts.tol, opts.t_end)?,
            ..*opts
        };
        return sampled(&sys, &opts, y0, out, |d| {
            on_step(&Step(d));
            sys.push(*d);
        });
    }
    let Some(pieces) = Pieces::new(m) else {
        return sampled(m, opts, y0, out, |d| on_step(&Step(d)));
    };
    let mut grid = SampleGrid::new(0.0, opts.t_end, opts.dt)?;
    grid.start(&y0, &mut out);
    let mut sticking = Sticking::default();
    let mut solver = Switching::new(&pieces, 0.0, y0, opts.tol)?;
    let accel = |t: f64, y: &[f64; N]| pieces.model().rhs(t, y)[1];
    let mut first = true;
    let mut summary = run(&mut solver, accel, opts, y0, |d, s| {
        if d.is_stuck() {
            sticking.time_stuck += d.t_end() - d.t_start();
            // a rest the run starts in is a stick too, as its time is time stuck
            sticking.sticks += u64::from(first);
        }
        first = false;
        if let Some(w) = s.last_switch() {
            sticking.switches += 1;
            sticking.sticks += u64::from(w.to == SwitchingMode::Stuck);
        }
        grid.fill(d, s.y(), &mut out);
        on_step(&Step(d));
    })?;
    grid.finish(solver.y(), &mut out);
    summary.sticking = Some(sticking);
    Ok(summary)
}

/// How a model with a switching term moved: its switches and its time at rest.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Sticking {
    /// Changes of mode (slip → stick, stick → slip, reversals at rest).
    pub switches: u64,
    /// How many rests the motion had: each time it stuck, and a rest the run starts in.
    pub sticks: u64,
    /// The time spent at rest, over all of them.
    pub time_stuck: f64,
}

/// [`run`] on the method of `opts` for `sys`, with `out(τ, [x, x'])` called at every time of the
/// output grid, the ends included.
fn sampled<S: System<N>, const N: usize>(
    sys: &S,
    opts: &SimOptions,
    y0: [f64; N],
    mut out: impl FnMut(f64, &[f64; N]),
    mut on_step: impl FnMut(&crate::integrate::AnyDense<N>),
) -> Result<SimSummary> {
    let mut grid = SampleGrid::new(0.0, opts.t_end, opts.dt)?;
    grid.start(&y0, &mut out);
    let mut solver = stepper(sys, 0.0, y0, opts.tol)?;
    let accel = |t: f64, y: &[f64; N]| sys.rhs(t, y)[1];
    let summary = run(&mut solver, accel, opts, y0, |d, s| {
        grid.fill(d, s.y(), &mut out);
        on_step(d);
    })?;
    grid.finish(solver.y(), &mut out);
    Ok(summary)
}

/// The checks both entry points make first (usable parameters, a run the step budget can reach),
/// then the initial state.
fn checked_start(p: &Params, opts: &SimOptions) -> Result<[f64; 2]> {
    p.validate()?;
    crate::integrate::check_budget(opts.t_end, &opts.tol)?;
    opts.start.check(&opts.tol)?;
    Ok(initial_state(p, opts.start))
}

/// The integration every entry point runs from `y0` to `opts.t_end` on `solver`, showing each
/// step's dense output and the stepper after it to `each`. max |x'| comes from the step ends and
/// the extrema of x' (zeros of x'' = `accel`, located on the dense output); a step whose
/// polynomial bounds |x'| below the largest value so far
/// ([`crate::integrate::DenseOutput::abs_bound`]) cannot hold a larger one and is not searched
/// (the bound is a sum of positive terms, rounded by at most (order + 1)·2⁻⁵³ relative: 1e-14 of
/// margin covers it). That saves four evaluations of the polynomial and four sines on most steps.
fn run<St: Stepper<N>, const N: usize>(
    solver: &mut St,
    accel: impl FnMut(f64, &[f64; N]) -> f64,
    opts: &SimOptions,
    y0: [f64; N],
    mut each: impl FnMut(&St::Dense, &St),
) -> Result<SimSummary> {
    let mut extrema = Detector::new(accel, Direction::Either);
    let mut max_v = y0[1].abs();
    while solver.t() < opts.t_end {
        solver.step(opts.t_end)?;
        let d = solver.dense();
        max_v = max_v.max(solver.y()[1].abs());
        if d.abs_bound(1).is_none_or(|b| b * (1.0 + 1e-14) > max_v) {
            extrema.scan(&d, |c| max_v = max_v.max(c.y[1].abs()));
        }
        each(&d, solver);
    }
    Ok(SimSummary {
        t_end: opts.t_end,
        initial: [y0[0], y0[1]],
        final_state: [solver.y()[0], solver.y()[1]],
        stats: solver.stats(),
        max_abs_xdot: max_v,
        sticking: None,
    })
}

/// A state [x, x'] by name.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct State {
    /// x.
    pub x: f64,
    /// x'.
    pub xdot: f64,
}

/// What `hdgear simulate --summary` prints: a run's outcome with its parameters and warnings.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SummaryReport {
    /// The parameters.
    pub params: Params,
    /// Final time.
    pub t_end: f64,
    /// Final state.
    #[serde(rename = "final")]
    pub final_state: State,
    /// Integrator work.
    pub stats: Stats,
    /// max |x'| over the run (see [`SimSummary::max_abs_xdot`]).
    pub max_abs_xdot: f64,
    /// Remarks on the parameter set, as text.
    pub warnings: Vec<String>,
    /// For a model with a switching term: its switches and time at rest.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sticking: Option<Sticking>,
    /// The assembled model, when it has terms beyond the study's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model: Option<Description>,
}

impl SimSummary {
    /// The summary of a run at `params` with the parameter set's `warnings`.
    pub fn report(&self, params: &Params, warnings: &[crate::params::Warning]) -> SummaryReport {
        SummaryReport {
            params: *params,
            t_end: self.t_end,
            final_state: State {
                x: self.final_state[0],
                xdot: self.final_state[1],
            },
            stats: self.stats,
            max_abs_xdot: self.max_abs_xdot,
            warnings: warnings.iter().map(ToString::to_string).collect(),
            sticking: self.sticking,
            model: None,
        }
    }
}

/// What produced a trajectory: the `meta` of its JSON output.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Setup {
    /// The parameters.
    pub params: Params,
    /// The run's options.
    pub options: SimOptions,
    /// The assembled model, when it has terms beyond the study's.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model: Option<Description>,
}

/// Integrates `periods` slow periods from the default start (the stable equilibrium at a = 0, at
/// rest) with nothing sampled: the plain integration that benchmarks and work counts time.
/// Returns the final state and the work counters.
///
/// ```
/// use hdgear::{Params, integrate::Options, simulate::integrate_periods};
/// let (y, stats) = integrate_periods(&Params::default(), 3.0, Options::default()).unwrap();
/// assert!(y[0].is_finite() && stats.steps > 1000);
/// ```
pub fn integrate_periods(p: &Params, periods: f64, tol: Options) -> Result<([f64; 2], Stats)> {
    p.validate()?;
    let sys = Dimensionless::new(*p);
    let y0 = initial_state(p, Start::Equilibrium);
    let t_end = periods * p.slow_period();
    crate::integrate::check_budget(t_end, &tol)?;
    let mut solver = stepper(&sys, 0.0, y0, tol)?;
    while solver.t() < t_end {
        solver.step(t_end)?;
    }
    Ok((*solver.y(), solver.stats()))
}
