//! Integrators behind one seam: a [`System`] (right-hand side, optionally its Jacobian and Taylor
//! coefficients) is stepped by a [`Stepper`] — Taylor's method ([`taylor`], the default) or
//! DOP853 ([`Dop853`], the independent cross-check) — with [`Options`] validated once, [`Stats`],
//! dense output ([`DenseOutput`]), output grids ([`SampleGrid`], [`sample`]) and zero-crossing events
//! ([`events`]). States are `[f64; N]` on the stack.
//!
//! ```
//! use hdgear::integrate::{Dop853, Options, System};
//! // y'' = −y, y(0) = 0, y'(0) = 1  ⇒  y(t) = sin t
//! struct Osc;
//! impl System<2> for Osc {
//!     fn rhs(&self, _t: f64, y: &[f64; 2]) -> [f64; 2] { [y[1], -y[0]] }
//! }
//! let mut s = Dop853::new(&Osc, 0.0, [0.0, 1.0], Options::default()).unwrap();
//! s.integrate_to(10.0).unwrap();
//! assert!((s.y()[0] - 10f64.sin()).abs() < 1e-9);
//! ```
//!
//! **Why one file.** The seam of every integrator (`System`, `Stepper`, `DenseOutput`), the options
//! validated once and the budgets are one contract; each method (Taylor, DOP853, RK4, events) lives
//! in its own file behind it.

pub(crate) mod approx;
mod dop853;
pub mod events;
mod rk4;
pub(crate) use rk4::rk4_step;
pub(crate) mod lanes;
mod stages;
pub mod taylor;

pub use dop853::{Dense, Dop853};

pub use taylor::{Scratch, Taylor, TaylorDense, Workspace};

use crate::error::{Error, Result, SolverError};
use serde::{Deserialize, Serialize};

/// A first-order system y' = f(t, y) with a fixed-size state.
pub trait System<const N: usize> {
    /// The right-hand side f(t, y).
    fn rhs(&self, t: f64, y: &[f64; N]) -> [f64; N];
    /// The Jacobian ∂f/∂y at (t, y), for methods and analyses that need it (variational
    /// equations, implicit steps); `None` when the system does not provide it.
    fn jacobian(&self, _t: f64, _y: &[f64; N]) -> Option<[[f64; N]; N]> {
        None
    }
    /// Fills `c[0..=order]` with the normalised Taylor coefficients of the solution through
    /// (t, y): y(t + h) = Σ_k c\[k\]·h^k, c\[0\] = y (for [`Method::Taylor`]). Returns false, the
    /// default, when the system does not provide them.
    fn taylor(&self, _t: f64, _y: &[f64; N], _order: usize, _c: &mut [[f64; N]]) -> bool {
        false
    }
    /// [`System::taylor`] with the stepper's [`Workspace`] for the system's own intermediate rows
    /// (the default ignores it): a system that keeps such rows uses the stepper's instead of
    /// clearing its own on every step.
    fn taylor_in(
        &self,
        t: f64,
        y: &[f64; N],
        order: usize,
        c: &mut [[f64; N]],
        _work: &mut Workspace,
    ) -> bool {
        self.taylor(t, y, order, c)
    }
    /// Whether [`System::taylor_step`] may shorten the step rule's step (false, the default:
    /// the stepper takes the rule's step on [`System::taylor`]'s rows).
    fn taylor_limits_steps(&self) -> bool {
        false
    }
    /// [`System::taylor`]'s coefficients and the step they allow, in one pass: `step` is the
    /// integrator's rule on the state's rows (Jorba–Zou's); a system that knows more shortens it
    /// to the longest step on which the polynomial stays accurate to `atol` (a factor of its
    /// right-hand side whose own series converges later than the state's rows show,
    /// [`crate::model::jet::exp_step_limit`]). `None` when the system has no coefficients; the
    /// default is `step` on [`System::taylor`]'s rows.
    // one pass: where (t, y), how far (order, atol), into what (c, work), by which rule
    #[allow(clippy::too_many_arguments)]
    fn taylor_step<F: FnOnce(&[[f64; N]]) -> f64>(
        &self,
        t: f64,
        y: &[f64; N],
        order: usize,
        c: &mut [[f64; N]],
        _atol: f64,
        work: &mut Workspace,
        step: F,
    ) -> Option<f64> {
        self.taylor_in(t, y, order, c, work).then(|| step(c))
    }
}

/// The solution over one accepted step, as a continuous function of t: what events, output
/// grids and burst detection read, whatever the method.
pub trait DenseOutput<const N: usize> {
    /// Start of the step.
    fn t_start(&self) -> f64;
    /// End of the step.
    fn t_end(&self) -> f64;
    /// The interpolated state at `t` (meant for t in the step).
    fn eval(&self, t: f64) -> [f64; N];
    /// The state the step ended on: the integrator's own, where it keeps it (the next step
    /// starts from it), else the interpolant at [`DenseOutput::t_end`].
    fn end_state(&self) -> [f64; N] {
        self.eval(self.t_end())
    }
    /// An upper bound of |y_i| over the whole step, where the dense output gives one cheaply
    /// (Taylor's step polynomial: Σ_k |c_k,i|·h^k), else `None` (the default). Lets a caller
    /// that looks for a largest value skip a step that cannot hold one.
    fn abs_bound(&self, _i: usize) -> Option<f64> {
        None
    }
    /// A lower bound of |y_i| over the whole step as [`DenseOutput::eval`] computes it
    /// (rounding included), where the dense output gives one cheaply (Taylor's step polynomial:
    /// |c_0,i| − Σ_{k≥1} |c_k,i|·h^k, less a margin for the rounding of its evaluation), else
    /// `None` (the default). Lets a caller that looks for where |y_i| falls below a level skip a
    /// step where it cannot.
    fn abs_floor(&self, _i: usize) -> Option<f64> {
        None
    }
}

/// A one-step integrator positioned at (t, y): the seam every driver (simulation, burst
/// detection, the physical model, figures) uses, so a second method plugs in behind
/// [`Method`].
pub trait Stepper<const N: usize> {
    /// The dense output of one step.
    type Dense: DenseOutput<N> + Copy;
    /// Current time.
    fn t(&self) -> f64;
    /// Current state.
    fn y(&self) -> &[f64; N];
    /// Advances by one accepted step, never past `t_bound`.
    fn step(&mut self, t_bound: f64) -> Result<()>;
    /// The dense output of the last accepted step.
    fn dense(&mut self) -> Self::Dense;
    /// Work counters so far.
    fn stats(&self) -> Stats;
}

/// The integration method.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Method {
    /// Taylor's method with the Jorba–Zou order and step rule ([`Taylor`]), for systems that
    /// provide [`System::taylor`] (both models do).
    #[default]
    Taylor,
    /// Dormand–Prince 8(5,3) with 7th-order dense output ([`Dop853`]).
    Dop853,
}

impl Method {
    /// Every method.
    pub const ALL: [Method; 2] = [Method::Taylor, Method::Dop853];

    /// The name users write (and the serde name).
    pub fn name(self) -> &'static str {
        match self {
            Method::Taylor => "taylor",
            Method::Dop853 => "dop853",
        }
    }

    /// The method in words, for reports.
    pub fn describe(self) -> &'static str {
        match self {
            Method::Taylor => {
                "Taylor's method of order ⌈−ln(tol)/2 + 1⌉ with the Jorba–Zou step rule, the step \
                 polynomial as dense output"
            }
            Method::Dop853 => {
                "adaptive Dormand–Prince 8(5,3) (Hairer's DOP853) with 7th-order dense output"
            }
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

impl std::str::FromStr for Method {
    type Err = Error;
    fn from_str(name: &str) -> Result<Method> {
        crate::error::by_name(&Method::ALL, Method::name, "method", name)
    }
}

/// Tolerances and limits of the integrator.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Options {
    /// Relative tolerance (per component). Must be > 0 and finite. Default 1e-10.
    pub rtol: f64,
    /// Absolute tolerance (per component). Must be > 0 and finite. Default 1e-10.
    pub atol: f64,
    /// First step; `None` uses Hairer's initial-step heuristic.
    pub h_init: Option<f64>,
    /// Largest step; `None` means unlimited.
    pub h_max: Option<f64>,
    /// Most accepted + rejected steps before giving up with [`SolverError::TooManySteps`]. Default 10⁸.
    pub max_steps: u64,
    /// A state component whose magnitude exceeds this is a blow-up ([`SolverError::BlowUp`]).
    /// Default 1e100: far beyond any physical motion, yet below overflow in a cubic right-hand side.
    pub blowup: f64,
    /// The method ([`stepper`] builds it). Default [`Method::Taylor`].
    #[serde(default)]
    pub method: Method,
    /// Taylor's order ([`MIN_ORDER`](taylor::MIN_ORDER)…[`MAX_ORDER`](taylor::MAX_ORDER)).
    /// `None` (the default) takes the Jorba–Zou order for `rtol` ([`taylor::order_for`]); a
    /// given order keeps the same error per step with a step to match
    /// ([`taylor`]'s module documentation). Ignored by DOP853.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub order: Option<usize>,
    /// A wall-clock time past which the integration stops with [`SolverError::Deadline`] (looked
    /// at every [`DEADLINE_EVERY`] steps): how a caller that has given up on the result (the
    /// explorer, after its timeout) stops the work. Not serialised. Default `None`.
    #[serde(skip)]
    pub deadline: Option<std::time::Instant>,
    /// A flag that, once set, stops the integration as a passed deadline does (looked at as
    /// often): how a caller stops work whose result is no longer wanted before its deadline
    /// (the explorer, when its client hangs up). Not serialised. Default `None`.
    #[serde(skip)]
    pub cancel: Option<Cancel>,
}

/// A `static` the caller owns and the library reads or adds to while it runs: a [`Cancel`]
/// flag, a [`crate::periodic::Counter`] of traced points. Holding a `'static` reference keeps
/// the options that carry it `Copy`; two are equal when they are the same static.
#[derive(Debug)]
pub struct Shared<T: 'static>(pub &'static T);

impl<T> Clone for Shared<T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T> Copy for Shared<T> {}

impl<T> PartialEq for Shared<T> {
    fn eq(&self, other: &Shared<T>) -> bool {
        std::ptr::eq(self.0, other.0)
    }
}

/// A flag that stops the integrations that carry it ([`Options::cancel`]) once set (a server
/// keeps a fixed set, one per computation in flight).
///
/// ```
/// use std::sync::atomic::{AtomicBool, Ordering};
/// use hdgear::{Params, integrate::{Options, Shared}, simulate::integrate_periods};
/// static STOP: AtomicBool = AtomicBool::new(true);
/// let tol = Options { cancel: Some(Shared(&STOP)), ..Options::default() };
/// assert!(integrate_periods(&Params::default(), 3.0, tol).is_err()); // stopped at once
/// STOP.store(false, Ordering::Relaxed);
/// assert!(integrate_periods(&Params::default(), 3.0, tol).is_ok());
/// ```
pub type Cancel = Shared<std::sync::atomic::AtomicBool>;

impl Cancel {
    /// Whether the flag is set.
    pub fn is_set(self) -> bool {
        self.0.load(std::sync::atomic::Ordering::Relaxed)
    }
}

/// Steps between two looks at the clock for [`Options::deadline`]. A look costs about as much
/// as a few of one step's arithmetic operations, so one per 256 steps is lost in the noise,
/// and a deadline is overrun by at most 256 steps (well under a millisecond at the study's
/// points).
pub const DEADLINE_EVERY: u64 = 256;

impl Default for Options {
    fn default() -> Self {
        Options {
            rtol: 1e-10,
            atol: 1e-10,
            h_init: None,
            h_max: None,
            max_steps: 100_000_000,
            blowup: 1e100,
            method: Method::default(),
            order: None,
            deadline: None,
            cancel: None,
        }
    }
}

impl Options {
    /// Whether an integration at time `t` after `steps` steps must stop:
    /// [`SolverError::TooManySteps`] at `max_steps`, [`SolverError::Deadline`] past the
    /// deadline.
    pub(crate) fn spent(&self, steps: u64, t: f64) -> Option<SolverError> {
        if steps >= self.max_steps {
            return Some(SolverError::TooManySteps {
                t,
                max_steps: self.max_steps,
            });
        }
        self.past_deadline(steps)
            .then_some(SolverError::Deadline { t })
    }

    /// Whether the deadline has passed or the cancel flag is set, looked at only when `count`
    /// is a multiple of [`DEADLINE_EVERY`].
    pub(crate) fn past_deadline(&self, count: u64) -> bool {
        count.is_multiple_of(DEADLINE_EVERY)
            && (self.cancel.is_some_and(Cancel::is_set)
                || self
                    .deadline
                    .is_some_and(|d| std::time::Instant::now() >= d))
    }

    /// Checks that the tolerances and limits are usable.
    pub fn validate(&self) -> Result<()> {
        let bad = |name: &'static str, value: f64, reason: &'static str| {
            Err(Error::InvalidOption {
                name,
                value,
                reason,
            })
        };
        if !(self.rtol.is_finite() && self.rtol > 0.0) {
            return bad("rtol", self.rtol, "must be finite and > 0");
        }
        if self.rtol > 1.0 {
            return bad(
                "rtol",
                self.rtol,
                "must be ≤ 1 (a relative error above 1 controls nothing)",
            );
        }
        if self.rtol < 1e-15 {
            return bad(
                "rtol",
                self.rtol,
                "must be ≥ 1e-15 (below that, rounding dominates)",
            );
        }
        if !(self.atol.is_finite() && self.atol > 0.0) {
            return bad(
                "atol",
                self.atol,
                "must be finite and > 0 (a purely relative tolerance cannot control a component \
                 that passes through 0, such as x' at rest)",
            );
        }
        if self.atol < MIN_ATOL {
            return bad(
                "atol",
                self.atol,
                "must be ≥ 1e-100 (the error norm squares error/atol, which overflows below that \
                 and every step is then rejected)",
            );
        }
        if let Some(h) = self.h_init
            && !(h.is_finite() && h > 0.0)
        {
            return bad("h_init", h, "must be finite and > 0");
        }
        if let Some(h) = self.h_max
            && !(h.is_finite() && h > 0.0)
        {
            return bad("h_max", h, "must be finite and > 0");
        }
        if !(self.blowup.is_finite() && self.blowup > 0.0) {
            return bad("blowup", self.blowup, "must be finite and > 0");
        }
        if let Some(p) = self.order
            && !(taylor::MIN_ORDER..=taylor::MAX_ORDER).contains(&p)
        {
            return bad("order", p as f64, "must be 6 to 20");
        }
        Ok(())
    }
}

/// The least absolute tolerance. The error norm squares error/(atol + rtol·|y|); with a
/// component at 0 (x' at rest) that square overflows once the error exceeds atol·1.3e154, and
/// every step is then rejected down to an underflow. Measured at t_end = 10 from the study's
/// start: atol = 1e-165 ran, 1e-175 failed at t = 0 (errors of a first step are near 1e-20).
/// 1e-100, the bound on every parameter's magnitude, leaves errors up to 1e54 room.
pub const MIN_ATOL: f64 = 1e-100;

/// An optimistic step size (dimensionless time) for budget estimates: at rtol = 1e-10 the model
/// takes steps of 0.1–0.25 time units, and explicit stability caps them near 1 on the stiff
/// branches; with 0.5 only runs that certainly exceed the budget are refused.
pub const OPTIMISTIC_STEP: f64 = 0.5;

/// Refuses, before any work, a run over `span` dimensionless time units that would need more
/// steps than `opts.max_steps` even at [`OPTIMISTIC_STEP`], or whose span is not a finite
/// length ≥ 0.
pub fn check_budget(span: f64, opts: &Options) -> Result<()> {
    if !(span.is_finite() && span >= 0.0) {
        return Err(Error::InvalidOption {
            name: "t_end",
            value: span,
            reason: "the run's length must be finite and ≥ 0",
        });
    }
    let estimated_steps = span / OPTIMISTIC_STEP;
    if estimated_steps > opts.max_steps as f64 {
        return Err(Error::RunTooLong {
            span,
            estimated_steps,
            budget: opts.max_steps as f64,
        });
    }
    Ok(())
}

/// Refuses, before any work, a run over `span` of a model whose fastest rate is `rate` (from
/// its term `term`: [`crate::model::Model::fastest_rate`]) that would need more steps than
/// `opts.max_steps` even if every step crossed a whole turn 2π/rate: no method follows a motion
/// or load at that rate in longer steps (a Taylor step of order p holds |rate·h| to a few
/// radians for accuracy and stability alike).
pub fn check_rate_budget(
    span: f64,
    (rate, term): (f64, &'static str),
    opts: &Options,
) -> Result<()> {
    let estimated_steps = span * rate / std::f64::consts::TAU;
    if estimated_steps > opts.max_steps as f64 {
        return Err(Error::RateTooHigh {
            rate,
            term,
            span,
            estimated_steps,
            budget: opts.max_steps as f64,
        });
    }
    Ok(())
}

/// The smallest step either method takes at `t` with `remaining` to go: ten rounding units of
/// the larger of the two (a smaller step would not change t).
pub(crate) fn smallest_step(t: f64, remaining: f64) -> f64 {
    10.0 * f64::EPSILON * t.abs().max(remaining.abs()).max(1e-300)
}

/// Work counters of an integration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Stats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected step attempts.
    pub rejected: u64,
    /// Right-hand-side evaluations, including those of the initial-step guess and dense output
    /// (for Taylor's method: evaluations of the Taylor coefficients, one per step).
    pub rhs_evals: u64,
}

/// The most samples an output grid may have (10¹⁰: beyond any file, and hours of callbacks).
pub const MAX_SAMPLES: f64 = 1e10;

/// An output grid t0 + k·dt (k = 0, 1, …) up to `t_end`, filled from dense output.
///
/// Samples are at t0 + k·dt for every k with t0 + k·dt ≤ t_end (a relative slack of 1e-9 of dt),
/// plus `t_end` itself when the grid does not land on it. Samples come from the dense output,
/// never from shortened steps, so `dt` does not change the steps taken.
#[derive(Clone, Copy, Debug)]
pub struct SampleGrid {
    t0: f64,
    t_end: f64,
    dt: f64,
    n_grid: u64,
    next: u64,
}

impl SampleGrid {
    /// A grid over [t0, t_end] with spacing dt.
    pub fn new(t0: f64, t_end: f64, dt: f64) -> Result<SampleGrid> {
        if !(t_end.is_finite() && t_end > t0) {
            return Err(Error::InvalidOption {
                name: "t_end",
                value: t_end,
                reason: "must be finite and after the start time",
            });
        }
        if !(dt.is_finite() && dt > 0.0) {
            return Err(Error::InvalidOption {
                name: "dt",
                value: dt,
                reason: "must be finite and > 0",
            });
        }
        let n = (t_end - t0) / dt;
        if n > MAX_SAMPLES {
            return Err(Error::InvalidOption {
                name: "dt",
                value: dt,
                reason: "too small for the span: more than 1e10 samples",
            });
        }
        let n_grid = (n + 1e-9).floor() as u64;
        Ok(SampleGrid {
            t0,
            t_end,
            dt,
            n_grid,
            next: 0,
        })
    }

    /// Total number of samples the grid produces.
    pub fn len(&self) -> u64 {
        let extra = u64::from(self.has_extra_end());
        self.n_grid + 1 + extra
    }

    /// Never empty (t0 is always a sample); here for API completeness.
    pub fn is_empty(&self) -> bool {
        false
    }

    fn has_extra_end(&self) -> bool {
        self.t_end - (self.t0 + self.n_grid as f64 * self.dt) > 1e-9 * self.dt
    }

    /// Emits the initial sample.
    pub fn start<const N: usize>(&mut self, y0: &[f64; N], out: &mut impl FnMut(f64, &[f64; N])) {
        out(self.t0, y0);
        self.next = 1;
    }

    /// True when the step ending at `t_step_end` contains samples still to emit.
    pub fn wants(&self, t_step_end: f64) -> bool {
        self.next <= self.n_grid && self.t0 + self.next as f64 * self.dt <= t_step_end
    }

    /// Emits the samples inside the step described by `d` (whose end state is `y_end`).
    pub fn fill<const N: usize>(
        &mut self,
        d: &(impl DenseOutput<N> + ?Sized),
        y_end: &[f64; N],
        out: &mut impl FnMut(f64, &[f64; N]),
    ) {
        while self.next <= self.n_grid {
            let tk = self.t0 + self.next as f64 * self.dt;
            if tk > d.t_end() {
                break;
            }
            if self.next == self.n_grid && (tk - self.t_end).abs() <= 1e-9 * self.dt {
                out(self.t_end, y_end);
            } else {
                out(tk, &d.eval(tk));
            }
            self.next += 1;
        }
    }

    /// Emits the final sample at `t_end` if the grid did not land on it.
    pub fn finish<const N: usize>(
        &mut self,
        y_end: &[f64; N],
        out: &mut impl FnMut(f64, &[f64; N]),
    ) {
        if self.has_extra_end() {
            out(self.t_end, y_end);
        }
    }
}

/// The stepper of `opts.method` for `sys` at (t0, y0).
pub fn stepper<'s, S: System<N> + ?Sized, const N: usize>(
    sys: &'s S,
    t0: f64,
    y0: [f64; N],
    opts: Options,
) -> Result<AnyStepper<'s, S, N>> {
    Ok(match opts.method {
        Method::Taylor => AnyStepper::Taylor(Taylor::new(sys, t0, y0, opts)?),
        Method::Dop853 => AnyStepper::Dop853(Dop853::new(sys, t0, y0, opts)?),
    })
}

/// A stepper of either method (what [`stepper`] returns).
// a Taylor stepper keeps its system's rows on the stack: boxing them would allocate in every run
#[allow(clippy::large_enum_variant)]
pub enum AnyStepper<'s, S: ?Sized, const N: usize> {
    /// Taylor's method.
    Taylor(Taylor<'s, S, N>),
    /// DOP853.
    Dop853(Dop853<'s, S, N>),
}

/// The dense output of either method.
#[derive(Clone, Copy, Debug)]
pub enum AnyDense<const N: usize> {
    /// The step polynomial of Taylor's method.
    Taylor(TaylorDense<N>),
    /// DOP853's continuous extension.
    Dop853(Dense<N>),
}

impl<const N: usize> DenseOutput<N> for AnyDense<N> {
    fn t_start(&self) -> f64 {
        match self {
            AnyDense::Taylor(d) => d.t_start(),
            AnyDense::Dop853(d) => d.t_start(),
        }
    }
    fn t_end(&self) -> f64 {
        match self {
            AnyDense::Taylor(d) => d.t_end(),
            AnyDense::Dop853(d) => d.t_end(),
        }
    }
    fn end_state(&self) -> [f64; N] {
        match self {
            AnyDense::Taylor(d) => d.end_state(),
            AnyDense::Dop853(d) => d.end_state(),
        }
    }
    #[inline]
    fn eval(&self, t: f64) -> [f64; N] {
        match self {
            AnyDense::Taylor(d) => d.eval(t),
            AnyDense::Dop853(d) => d.eval(t),
        }
    }
    fn abs_bound(&self, i: usize) -> Option<f64> {
        match self {
            AnyDense::Taylor(d) => d.abs_bound(i),
            AnyDense::Dop853(d) => d.abs_bound(i),
        }
    }
    fn abs_floor(&self, i: usize) -> Option<f64> {
        match self {
            AnyDense::Taylor(d) => d.abs_floor(i),
            AnyDense::Dop853(d) => d.abs_floor(i),
        }
    }
}

impl<'s, S: System<N> + ?Sized, const N: usize> Stepper<N> for AnyStepper<'s, S, N> {
    type Dense = AnyDense<N>;
    fn t(&self) -> f64 {
        match self {
            AnyStepper::Taylor(s) => s.t(),
            AnyStepper::Dop853(s) => s.t(),
        }
    }
    fn y(&self) -> &[f64; N] {
        match self {
            AnyStepper::Taylor(s) => s.y(),
            AnyStepper::Dop853(s) => s.y(),
        }
    }
    fn step(&mut self, t_bound: f64) -> Result<()> {
        match self {
            AnyStepper::Taylor(s) => s.step(t_bound),
            AnyStepper::Dop853(s) => s.step(t_bound),
        }
    }
    fn dense(&mut self) -> AnyDense<N> {
        match self {
            AnyStepper::Taylor(s) => AnyDense::Taylor(s.dense()),
            AnyStepper::Dop853(s) => AnyDense::Dop853(s.dense()),
        }
    }
    fn stats(&self) -> Stats {
        match self {
            AnyStepper::Taylor(s) => s.stats(),
            AnyStepper::Dop853(s) => s.stats(),
        }
    }
}

/// Integrates from (t0, y0) to `t_end` and calls `out(t, y)` on the [`SampleGrid`] t0 + k·dt.
/// Returns the final state and the work counters.
pub fn sample<S: System<N> + ?Sized, const N: usize>(
    sys: &S,
    t0: f64,
    y0: [f64; N],
    t_end: f64,
    dt: f64,
    opts: Options,
    mut out: impl FnMut(f64, &[f64; N]),
) -> Result<([f64; N], Stats)> {
    let mut grid = SampleGrid::new(t0, t_end, dt)?;
    let mut solver = stepper(sys, t0, y0, opts)?;
    grid.start(&y0, &mut out);
    while solver.t() < t_end {
        solver.step(t_end)?;
        if grid.wants(solver.t()) {
            let d = solver.dense();
            grid.fill(&d, solver.y(), &mut out);
        }
    }
    grid.finish(solver.y(), &mut out);
    Ok((*solver.y(), solver.stats()))
}
