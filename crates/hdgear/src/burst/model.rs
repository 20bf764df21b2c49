//! The burst verdict on a model assembled from terms ([`Model`]): the same scan and
//! classification as the study's model, of a model whose equilibria are a study parameter set's
//! ([`Model::equivalent_params`]): its further terms (friction, control laws) act on the motion
//! and enter its own x'', measured against that set's equilibrium curve.
//!
//! **Why one file.** The projections of a model's state onto the scan (on a piece, averaged over a
//! fast torque) and the verdict built on them are read together; the scan itself is `scan.rs`.

use super::scan::{History, Pivot, Scan, ScanStep};
use super::{BurstOptions, Plan, Response, StickSlip};
use crate::error::Result;
use crate::fast::StaticCurve;
use crate::integrate::{AnyDense, DenseOutput, Stepper, stepper};
use crate::model::ScheduledTorque;
use crate::model::delayed::Delayed;
use crate::model::switching::{Pieces, Switching, SwitchingDense};
use crate::model::{MAX_STATES, Model, ModelCurve, refusal};
use std::collections::VecDeque;
use std::f64::consts::TAU;

/// A step of the model's N-component dense output `D` read as x, x' and the model's own x''.
#[derive(Clone, Copy, Debug)]
struct Projected<'m, C, D, const N: usize> {
    inner: D,
    model: &'m Model,
    params: &'m C,
    /// Which piece the step lies on.
    piece: OnPiece,
}

/// The piece a step of a model lies on, which decides its torque.
#[derive(Clone, Copy, Debug)]
enum OnPiece {
    /// A smooth model: its own torque.
    Smooth,
    /// A switching model at rest: x'' = 0.
    Rest,
    /// A switching model slipping with sgn x' = ±1: the torque of that piece.
    Slip(f64),
}

impl<C: StaticCurve, D, const N: usize> Projected<'_, C, D, N> {
    /// x'' at t and y: the curve's forcing less the model's torque (read directly, so a curve
    /// whose g takes a solve, [`ScheduledTorque`]'s, is not evaluated for it).
    fn accel_at(&self, t: f64, y: &[f64; N]) -> f64 {
        let p = self.params;
        let forcing = || p.forcing((p.omega() * t).sin());
        match self.piece {
            OnPiece::Smooth => forcing() - self.model.torque_at(y),
            // at rest x'' = 0: the friction takes up whatever the rest leaves
            OnPiece::Rest => 0.0,
            OnPiece::Slip(s) => forcing() - self.model.directed(s, [0.0; MAX_STATES]).torque_at(y),
        }
    }
}

impl<C: StaticCurve, D: DenseOutput<N>, const N: usize> DenseOutput<2> for Projected<'_, C, D, N> {
    fn t_start(&self) -> f64 {
        self.inner.t_start()
    }
    fn t_end(&self) -> f64 {
        self.inner.t_end()
    }
    fn eval(&self, t: f64) -> [f64; 2] {
        let y = self.inner.eval(t);
        [y[0], y[1]]
    }
    fn end_state(&self) -> [f64; 2] {
        let y = self.inner.end_state();
        [y[0], y[1]]
    }
    fn abs_bound(&self, i: usize) -> Option<f64> {
        self.inner.abs_bound(i)
    }
    fn abs_floor(&self, i: usize) -> Option<f64> {
        self.inner.abs_floor(i)
    }
}

impl<C: StaticCurve, D: DenseOutput<N>, const N: usize> ScanStep for Projected<'_, C, D, N> {
    fn state_at(&self, t: f64) -> ([f64; 2], Option<f64>) {
        let y = self.inner.eval(t);
        ([y[0], y[1]], Some(self.accel_at(t, &y)))
    }
    fn end(&self) -> ([f64; 2], Option<f64>) {
        let y = self.inner.end_state();
        ([y[0], y[1]], Some(self.accel_at(self.inner.t_end(), &y)))
    }
}

/// 8-point Gauss–Legendre nodes on [0, 1] (the positive half of the symmetric rule on [−1, 1])
/// and their weights: exact for polynomials of degree 15. A DOP853 step's dense output is of
/// degree 7; a Taylor step's rows beyond that are within the step's own tolerance.
const GAUSS8: [(f64, f64); 4] = [
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
    (0.960_289_856_497_536_3, 0.101_228_536_290_376_3),
];

/// (∫ x, ∫ (s − lo)·x) over [lo, hi] in the step `d`, by [`GAUSS8`].
fn gauss_moments<const N: usize>(d: &AnyDense<N>, lo: f64, hi: f64) -> [f64; 2] {
    let (mid, half) = (0.5 * (lo + hi), 0.5 * (hi - lo));
    let mut m = [0.0; 2];
    for (node, weight) in GAUSS8 {
        for s in [mid - half * node, mid + half * node] {
            let x = d.eval(s)[0];
            m[0] += weight * half * x;
            m[1] += weight * half * (s - lo) * x;
        }
    }
    m
}

/// A step of the run with its moments over the whole step ([`gauss_moments`]).
#[derive(Clone, Copy, Debug)]
struct Piece<const N: usize> {
    d: AnyDense<N>,
    moments: [f64; 2],
}

/// A step of a dithered model's motion averaged twice over the dither's period T (a triangular
/// window 2T wide): x̿(t) = (1/T²)∫ K(t − s)·x(s) ds with K(u) = u on [0, T] and 2T − u on
/// [T, 2T], so x̿' = (∫_{t−T}^{t} x − ∫_{t−2T}^{t−T} x)/T² and
/// x̿'' = (x(t) − 2x(t − T) + x(t − 2T))/T².
///
/// Each average over one period removes a ripple of constant amplitude, and every harmonic of
/// it, exactly. The second removes what the first leaves of a ripple whose amplitude changes
/// along the motion (A(t)·sin Ω_d t averaged once leaves −A'(t)·cos(Ω_d t)/Ω_d, whose slope
/// A'·sin would give x̿'' a sign change every half period where the motion is slow). A slower
/// swing of angular frequency ν keeps sinc²(πν/Ω_d) of its size: 0.99 at ν/Ω_d = 0.05. Read as
/// x̿, x̿' and, for the scan, x̿''.
#[derive(Clone, Debug)]
struct Averaged<const N: usize> {
    /// The run's steps from the one holding t_start − 2T to this one (the last).
    pieces: Vec<Piece<N>>,
    period: f64,
}

impl<const N: usize> Averaged<N> {
    fn piece(&self, t: f64) -> &AnyDense<N> {
        &self
            .pieces
            .iter()
            .rev()
            .find(|p| p.d.t_start() <= t)
            .unwrap_or(&self.pieces[0])
            .d
    }

    /// (∫ x, ∫ (s − a)·x) over [a, b]: each step's part of it by [`GAUSS8`], a whole step's
    /// from its [`Piece`].
    fn moments(&self, a: f64, b: f64) -> [f64; 2] {
        let mut m = [0.0; 2];
        for p in &self.pieces {
            let (t0, t1) = (p.d.t_start(), p.d.t_end());
            let (lo, hi) = (t0.max(a), t1.min(b));
            if lo >= hi {
                continue;
            }
            // ∫ (s − a)·x = ∫ (s − lo)·x + (lo − a)·∫ x
            let [whole, first] = if (lo, hi) == (t0, t1) {
                p.moments
            } else {
                gauss_moments(&p.d, lo, hi)
            };
            m[0] += whole;
            m[1] += first + (lo - a) * whole;
        }
        m
    }

    /// (x̿, x̿', x̿'') at t.
    fn averaged(&self, t: f64) -> [f64; 3] {
        let period = self.period;
        let (t1, t2) = (t - period, t - 2.0 * period);
        let [near, near_moment] = self.moments(t1, t);
        let [far, far_moment] = self.moments(t2, t1);
        let x = |s: f64| self.piece(s).eval(s)[0];
        let inv = 1.0 / (period * period);
        [
            (period * near - near_moment + far_moment) * inv,
            (near - far) * inv,
            (x(t) - 2.0 * x(t1) + x(t2)) * inv,
        ]
    }

    fn scanned(&self, t: f64) -> ([f64; 2], Option<f64>) {
        let [x, v, acc] = self.averaged(t);
        ([x, v], Some(acc))
    }
}

impl<const N: usize> DenseOutput<2> for Averaged<N> {
    fn t_start(&self) -> f64 {
        self.pieces[self.pieces.len() - 1].d.t_start()
    }
    fn t_end(&self) -> f64 {
        self.pieces[self.pieces.len() - 1].d.t_end()
    }
    fn eval(&self, t: f64) -> [f64; 2] {
        let [x, v, _] = self.averaged(t);
        [x, v]
    }
}

impl<const N: usize> ScanStep for Averaged<N> {
    fn state_at(&self, t: f64) -> ([f64; 2], Option<f64>) {
        self.scanned(t)
    }
    fn end(&self) -> ([f64; 2], Option<f64>) {
        self.scanned(self.t_end())
    }
}

/// Simulates the model from its lowest stable equilibrium at a = 0 (at rest, its internal
/// states at rest there: [`Model::rest_states`]) and measures the response as [`super::response`]
/// does the study's: the signatures against the equilibrium curve of
/// [`Model::equivalent_params`] where the model's static torque is a study cubic, else against
/// the model's own curve ([`ModelCurve`]: a catalogue's piecewise-linear stiffness, a cubic with
/// an end stop); x'' the model's own. Classify it with [`classify_model`].
///
/// A dithered model ([`Model::dither`]) is scanned on its motion averaged twice over the
/// dither's period T (a triangular window 2T wide, which removes the ripple and its harmonics),
/// against the averaged model's equilibria: the ripple is the control's own motion, not a burst.
///
/// A model with switching terms (sticking friction, LuGre, Bouc–Wen) is run piece by piece
/// ([`Switching`]) and scanned on its pieces, at rest with x'' = 0; its rests are measured
/// ([`Response::sticking`]), and a burst released by a breakaway is a slip ([`StickSlip`]).
///
/// A model with a scheduled stiffness ([`Model::is_scheduled`]) is measured against its closed
/// loop's curve ([`ModelCurve::scheduled`]), whose equilibria move with the load through the
/// gain as well.
///
/// Refused for a switching model with a dither or a delay, for a dithered model whose static
/// torque is no study cubic (its averaged equilibria are not known), and where
/// [`ModelCurve::new`] or [`ModelCurve::scheduled`] refuses the model's curve.
///
/// ```
/// use hdgear::{Params, burst::{BurstOptions, Verdict, classify, response_model}};
/// use hdgear::{control::law_term, model::Model};
/// let p = Params::default(); // γ = 0.1: bursting
/// let opts = BurstOptions::default();
/// let open = response_model(&Model::study(&p), &opts).unwrap();
/// assert_eq!(classify(&p, &open).verdict, Verdict::Overshoot);
/// // with virtual damping k_d = 3 the overshoot and ringing are gone
/// let m = Model::study(&p).with_term(law_term("vdamping", 3.0, &[]).unwrap()).unwrap();
/// let closed = response_model(&m, &opts).unwrap();
/// assert_eq!(classify(&p, &closed).verdict, Verdict::NoBursts);
/// ```
pub fn response_model(m: &Model, opts: &BurstOptions) -> Result<Response> {
    match verdict_curve(m)? {
        Curve::Study(p) => response_model_on(m, &p, opts),
        Curve::Torque(c) => response_model_on(m, &c, opts),
        Curve::Scheduled(c) => response_model_on(m, &c, opts),
    }
}

/// The curve [`response_model`] measures `m` against, once `m` is checked and a model whose
/// averaged equilibria are unknown is refused.
fn verdict_curve(m: &Model) -> Result<Curve> {
    m.check()?;
    if m.dither().is_some() && m.equivalent_params().is_none() {
        return Err(refusal(
            m,
            "the burst verdict on a dithered model needs its averaged equilibria, known only for a static torque that is a study cubic",
        ));
    }
    Curve::of(m)
}

/// The x-extent X of the equilibrium curve a model's response is measured against
/// ([`response_model`]) and whether the state must jump at its folds (its settled branch's
/// equilibrium speed is infinite): what the control searches read of a model plant.
pub fn model_curve_facts(m: &Model) -> Result<(f64, bool)> {
    fn facts(c: &impl StaticCurve) -> (f64, bool) {
        (c.x_extent(), c.max_equilibrium_speed().is_infinite())
    }
    Ok(match Curve::of(m)? {
        Curve::Study(p) => facts(&p),
        Curve::Torque(c) => facts(&c),
        Curve::Scheduled(c) => facts(&c),
    })
}

/// The stiffness range of the equilibrium a model's state follows
/// ([`StaticCurve::stiffness_range`]), on the curve its response is measured against.
pub fn model_stiffness_range(m: &Model) -> Result<(f64, f64)> {
    Ok(match Curve::of(m)? {
        Curve::Study(p) => p.stiffness_range(),
        Curve::Torque(c) => c.stiffness_range(),
        Curve::Scheduled(c) => c.stiffness_range(),
    })
}

/// What a sweep row records of a point: its classification, its response, and the largest
/// |dx/da| on the equilibrium curve it traverses over a ∈ [−1, 1] (∞ with a fold in range).
pub type PointVerdict = (super::Classification, Response, f64);

/// The [`PointVerdict`] of a model: its response ([`response_model`]) classified against the
/// curve it was measured on ([`classify_model`]), and that curve's steepest slope δ/min g'.
///
/// ```
/// use hdgear::{Params, burst::{BurstOptions, verdict_model}, model::Model};
/// let p = Params::default(); // γ = 0.1: no folds, steepest at x = 1/(3α)
/// let (_, _, slope) = verdict_model(&Model::study(&p), &BurstOptions::default()).unwrap();
/// assert!((slope - p.delta / (p.gamma - p.critical_gamma())).abs() < 1e-9 * slope);
/// ```
pub fn verdict_model(m: &Model, opts: &BurstOptions) -> Result<PointVerdict> {
    // the curve built once, the response measured and classified on it
    fn verdict(m: &Model, c: &impl StaticCurve, opts: &BurstOptions) -> Result<PointVerdict> {
        let r = response_model_on(m, c, opts)?;
        let slope = c.delta().abs() / c.min_traversed_gprime();
        Ok((super::classify(c, &r), r, slope))
    }
    match verdict_curve(m)? {
        Curve::Study(p) => verdict(m, &p, opts),
        Curve::Torque(c) => verdict(m, &c, opts),
        Curve::Scheduled(c) => verdict(m, &c, opts),
    }
}

/// The equilibrium curve a model's response is measured against: the equivalent study set's
/// where there is one ([`Model::equivalent_params`]), the closed loop's of a scheduled stiffness
/// ([`ModelCurve::scheduled`]), else the model's static torque's ([`ModelCurve::new`]).
enum Curve {
    Study(crate::Params),
    Torque(ModelCurve),
    Scheduled(ModelCurve<ScheduledTorque>),
}

impl Curve {
    fn of(m: &Model) -> Result<Curve> {
        Ok(match m.equivalent_params() {
            Some(p) => Curve::Study(p),
            None if m.is_scheduled() => Curve::Scheduled(ModelCurve::scheduled(m)?),
            None => Curve::Torque(ModelCurve::new(m)?),
        })
    }
}

/// The error refusing model `m` a verdict, for `reason`.
/// The classification ([`super::classify`]) of a model's response ([`response_model`]), against
/// the same equilibrium curve the response was measured on ([`response_model`]).
///
/// ```
/// use hdgear::burst::{BurstOptions, classify_model, response_model};
/// use hdgear::model::{Model, terms::AnyTerm};
/// // a soft middle (slope 0.05 for |x| ≤ 0.3) between stiffer segments: no cubic, one curve
/// let law = AnyTerm::new("piecewise", &[0.05, 0.5, 5.0, 0.3, 0.5, 0.0, 0.0]).unwrap();
/// let m = Model::damped(0.0, 1.0, 0.01).with_term(law).unwrap();
/// assert_eq!(m.equivalent_params(), None);
/// let r = response_model(&m, &BurstOptions::default()).unwrap();
/// let c = classify_model(&m, &r).unwrap();
/// assert!(c.fast_slow_domain); // ω = 0.01 below the soft middle's relaxation rate 0.053
/// ```
pub fn classify_model(m: &Model, r: &Response) -> Result<super::Classification> {
    Ok(match Curve::of(m)? {
        Curve::Study(p) => super::classify(&p, r),
        Curve::Torque(c) => super::classify(&c, r),
        Curve::Scheduled(c) => super::classify(&c, r),
    })
}

/// [`response_model`] measured against the equilibrium curve `p` (whose x'' the scan reads is the
/// model's own whatever `p`; the signatures are measured against `p`'s equilibria): for a study
/// model both [`crate::Params`] and [`ModelCurve`] apply, which the tests compare.
pub fn response_model_on<C: StaticCurve>(
    m: &Model,
    p: &C,
    opts: &BurstOptions,
) -> Result<Response> {
    response_on(m, p, opts, None)
}

/// [`response_model`] from `start` = (x, x') at τ = 0 (each internal state at rest there)
/// instead of the default start: the verdict on a periodic orbit from its own start
/// ([`crate::periodic::burst_verdict`]).
pub fn response_model_from(m: &Model, opts: &BurstOptions, start: [f64; 2]) -> Result<Response> {
    if !start.iter().all(|v| v.is_finite()) {
        return Err(crate::Error::InvalidOption {
            name: "start",
            value: start[0] + start[1],
            reason: "must be finite",
        });
    }
    match Curve::of(m)? {
        Curve::Study(p) => response_on(m, &p, opts, Some(start)),
        Curve::Torque(c) => response_on(m, &c, opts, Some(start)),
        Curve::Scheduled(c) => response_on(m, &c, opts, Some(start)),
    }
}

/// [`response_model_on`] from `start`, or from the curve's default start at rest.
fn response_on<C: StaticCurve>(
    m: &Model,
    p: &C,
    opts: &BurstOptions,
    start: Option<[f64; 2]>,
) -> Result<Response> {
    m.check()?;
    if m.switches() && (m.dither().is_some() || m.delay().is_some()) {
        return Err(refusal(
            m,
            "the burst verdict on a switching model (integrated piece by piece) takes neither a dither nor a delay",
        ));
    }
    // a term too fast for the step budget over the scan is refused before the run
    let span = super::window(p, opts).1 + p.slow_period();
    crate::integrate::check_rate_budget(span, m.fastest_rate(), &opts.tol)?;
    let [x0, v0] = start.unwrap_or_else(|| [p.start(), m.rest_rate()]);
    let z: [f64; MAX_STATES] = m.rest_states(x0);
    match (m.dim(), m.switches()) {
        (2, false) => run::<C, 2>(m, p, opts, [x0, v0]),
        (3, false) => run::<C, 3>(m, p, opts, [x0, v0, z[0]]),
        (_, false) => run::<C, 4>(m, p, opts, [x0, v0, z[0], z[1]]),
        (2, true) => run_switching::<C, 2>(m, p, opts, [x0, v0]),
        (3, true) => run_switching::<C, 3>(m, p, opts, [x0, v0, z[0]]),
        (_, true) => run_switching::<C, 4>(m, p, opts, [x0, v0, z[0], z[1]]),
    }
}

/// The scan of the model's run from `y0`: by the method of steps for a delayed model
/// ([`Delayed`]), of the motion averaged over the dither's period for a dithered one
/// ([`Averaged`]), of the motion itself otherwise ([`Projected`]).
fn run<C: StaticCurve, const N: usize>(
    m: &Model,
    p: &C,
    opts: &BurstOptions,
    y0: [f64; N],
) -> Result<Response> {
    let plan = Plan::new(p, opts)?;
    match Delayed::new(m, &y0) {
        Some(sys) => {
            let tol = sys.options(opts.tol, plan.scan.1)?;
            let solver = stepper(&sys, 0.0, y0, tol)?;
            scan_model(&plan, solver, m, p, opts, y0[0], Some(&|d| sys.push(d)))
        }
        None => {
            let solver = stepper(m, 0.0, y0, opts.tol)?;
            scan_model(&plan, solver, m, p, opts, y0[0], None)
        }
    }
}

/// [`run`] on `solver`'s steps, each shown to `taken` where given (a delayed model's history).
fn scan_model<C: StaticCurve, St: Stepper<N, Dense = AnyDense<N>>, const N: usize>(
    plan: &Plan,
    solver: St,
    m: &Model,
    p: &C,
    opts: &BurstOptions,
    x0: f64,
    taken: Option<&dyn Fn(AnyDense<N>)>,
) -> Result<Response> {
    let Some([_, wd]) = m.dither() else {
        let project = |d: AnyDense<N>, scanned: bool| {
            if let Some(f) = taken {
                f(d);
            }
            scanned.then_some(Projected {
                inner: d,
                model: m,
                params: p,
                piece: OnPiece::Smooth,
            })
        };
        let scan = scan_steps(
            plan,
            solver,
            p,
            opts,
            x0,
            taken.is_some(),
            |_| None,
            project,
        )?;
        return Ok(plan.assemble(p, opts, scan));
    };
    let period = TAU / wd;
    let mut pieces: VecDeque<Piece<N>> = VecDeque::new();
    let average = |d: AnyDense<N>, scanned: bool| {
        if let Some(f) = taken {
            f(d);
        }
        let (t0, t1) = (d.t_start(), d.t_end());
        pieces.push_back(Piece {
            d,
            moments: gauss_moments(&d, t0, t1),
        });
        // keep the step holding t0 − 2T and those after it
        while pieces.len() > 1 && pieces[1].d.t_start() <= t0 - 2.0 * period {
            pieces.pop_front();
        }
        (scanned && t0 >= 2.0 * period).then(|| Averaged {
            pieces: pieces.iter().copied().collect(),
            period,
        })
    };
    let scan = scan_steps(plan, solver, p, opts, x0, true, |_| None, average)?;
    Ok(plan.assemble(p, opts, scan))
}

/// The scan over `solver`'s steps to the plan's end: each step's dense output, with whether it
/// ends inside the scanned span, goes to `view`, and what `view` returns is scanned. Steps before
/// the span are shown only when `every_step` (a view or a history that needs them). `rest` is
/// shown every step first, and returns the raw extremum of x' the step starts on where the sign
/// test on x'' cannot see it ([`Rests::see`]).
#[allow(clippy::too_many_arguments)]
fn scan_steps<C: StaticCurve, St: Stepper<N>, V: ScanStep, const N: usize>(
    plan: &Plan,
    mut solver: St,
    p: &C,
    opts: &BurstOptions,
    x0: f64,
    every_step: bool,
    mut rest: impl FnMut(&St::Dense) -> Option<(f64, bool)>,
    mut view: impl FnMut(St::Dense, bool) -> Option<V>,
) -> Result<Scan> {
    let mut scanner = plan.scanner(p, opts, x0);
    let mut history = History::new(plan.history_span());
    while solver.t() < plan.scan.1 {
        solver.step(plan.scan.1)?;
        let scanned = solver.t() > plan.scan.0;
        let d = solver.dense();
        let extremum = rest(&d);
        if !scanned && !every_step {
            continue;
        }
        if let Some(v) = view(d, scanned) {
            if let Some((t, is_max)) = extremum {
                scanner.extremum(t, 0.0, is_max, &history);
            }
            history.push(v);
            if let Some(d) = history.latest() {
                scanner.push(d, &history);
            }
        }
    }
    Ok(scanner.finish(&history))
}

/// The rests of a switching model's run, seen step by step ([`Rests::see`]).
#[derive(Clone, Debug, Default)]
struct Rests {
    /// (start, breakaway) of every rest that ended.
    ended: Vec<(f64, f64)>,
    /// The start of the rest under way.
    open: Option<f64>,
    /// sgn x' of the last slipping step (0 before the first).
    side: f64,
}

impl Rests {
    /// Records step `d` and returns the raw extremum of x' it starts on, if any: a slip that
    /// leaves a rest in the direction the motion came from starts on a minimum of |x'| (x' = 0
    /// at the breakaway; a maximum of x' when x' < 0), which the sign test on x'' misses (x'' = 0
    /// throughout the rest).
    fn see<const N: usize>(&mut self, d: &SwitchingDense<N>) -> Option<(f64, bool)> {
        if d.is_stuck() {
            self.open.get_or_insert(d.t_start());
            return None;
        }
        let side = slip_side(d);
        let arrived = std::mem::replace(&mut self.side, side);
        let t0 = self.open.take()?;
        let tb = d.t_start();
        self.ended.push((t0, tb));
        (arrived == side).then_some((tb, side < 0.0))
    }

    /// The measures over the window `(w0, w1)` of `periods` slow periods, from the scan's
    /// extrema of x' and the response's bursts.
    fn measure(
        &self,
        (w0, w1): (f64, f64),
        periods: f64,
        pivots: &[Pivot],
        r: &Response,
    ) -> StickSlip {
        let broke: Vec<(f64, f64)> = self
            .ended
            .iter()
            .copied()
            .filter(|&(_, tb)| tb >= w0 && tb <= w1)
            .collect();
        let durations = || broke.iter().map(|(t0, tb)| tb - t0);
        let open = self.open.map(|t0| (t0, w1));
        let at_rest = self
            .ended
            .iter()
            .chain(open.iter())
            .fold(0.0, |sum, &(t0, t1)| {
                sum + (t1.min(w1) - t0.max(w0)).max(0.0)
            });
        // each breakaway's first extremum of x' after it: the slip it released
        let firsts: Vec<Pivot> = broke
            .iter()
            .filter_map(|&(_, tb)| pivots.iter().find(|q| q.t > tb).copied())
            .collect();
        let is_slip = |b: &&super::Burst| firsts.iter().any(|q| q.t == b.t_peak);
        let slips = r.bursts.iter().filter(is_slip).count();
        let largest = r
            .bursts
            .iter()
            .max_by(|a, b| a.peak_abs_xdot.total_cmp(&b.peak_abs_xdot));
        StickSlip {
            sticks_per_period: broke.len() as f64 / periods,
            mean_stick: if broke.is_empty() {
                0.0
            } else {
                durations().sum::<f64>() / broke.len() as f64
            },
            max_stick: durations().fold(0.0, f64::max),
            stuck_fraction: at_rest / (w1 - w0),
            slip_peak_speed: firsts.iter().fold(0.0, |m: f64, q| m.max(q.v.abs())),
            slip_bursts_per_period: slips as f64 / periods,
            slip_dominates: largest.as_ref().is_some_and(is_slip),
        }
    }
}

/// sgn x' on a slipping step (x' keeps one sign inside it: steps end where it reaches 0).
fn slip_side<const N: usize>(d: &SwitchingDense<N>) -> f64 {
    let mid = 0.5 * (d.t_start() + d.t_end());
    let v = d.eval(mid)[1];
    if v == 0.0 {
        d.end_state()[1].signum()
    } else {
        v.signum()
    }
}

/// The scan of a switching model's run from `y0`, piece by piece ([`Switching`]), with its rests
/// measured ([`StickSlip`]).
fn run_switching<C: StaticCurve, const N: usize>(
    m: &Model,
    p: &C,
    opts: &BurstOptions,
    y0: [f64; N],
) -> Result<Response> {
    let plan = Plan::new(p, opts)?;
    let pieces = Pieces::new(m).expect("a switching model has pieces");
    let solver = Switching::new(&pieces, 0.0, y0, opts.tol)?;
    let mut rests = Rests::default();
    let view = |d: SwitchingDense<N>, scanned: bool| {
        scanned.then(|| Projected {
            inner: d,
            model: m,
            params: p,
            piece: if d.is_stuck() {
                OnPiece::Rest
            } else {
                OnPiece::Slip(slip_side(&d))
            },
        })
    };
    let scan = scan_steps(&plan, solver, p, opts, y0[0], true, |d| rests.see(d), view)?;
    let pivots = scan.pivots.clone();
    let mut r = plan.assemble(p, opts, scan);
    let window = (r.window_start, r.window_end);
    r.sticking = Some(rests.measure(window, f64::from(opts.periods), &pivots, &r));
    Ok(r)
}
