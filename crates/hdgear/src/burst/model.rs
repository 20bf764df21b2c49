//! The burst verdict on a model assembled from terms ([`Model`]): the same scan and
//! classification as the study's model, of a model whose equilibria are a study parameter set's
//! ([`Model::equivalent_params`]): its further terms (friction, control laws) act on the motion
//! and enter x'' as an extra torque, measured against that set's equilibrium curve.

use super::scan::{History, ScanStep};
use super::{BurstOptions, Plan, Response};
use crate::error::{Error, Result};
use crate::integrate::{AnyDense, DenseOutput, Stepper, stepper};
use crate::model::delay::Delayed;
use crate::model::{MAX_STATES, Model};
use std::collections::VecDeque;
use std::f64::consts::TAU;

/// A step of the model's N-component dense output read as x, x' and the torque of its terms
/// beyond the equivalent parameter set's cubic and unit damping.
#[derive(Clone, Copy, Debug)]
struct Projected<'m, const N: usize> {
    inner: AnyDense<N>,
    model: &'m Model,
    params: &'m crate::Params,
}

impl<const N: usize> Projected<'_, N> {
    fn extra_at(&self, y: &[f64; N]) -> f64 {
        // the model's torque less the study's x' + g(x)
        self.model.torque_at(y) - y[1] - self.params.g(y[0])
    }
}

impl<const N: usize> DenseOutput<2> for Projected<'_, N> {
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

impl<const N: usize> ScanStep for Projected<'_, N> {
    fn state_at(&self, t: f64) -> ([f64; 2], f64) {
        let y = self.inner.eval(t);
        ([y[0], y[1]], self.extra_at(&y))
    }
    fn end(&self) -> ([f64; 2], f64) {
        let y = self.inner.end_state();
        ([y[0], y[1]], self.extra_at(&y))
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
/// x̿, x̿' and, for the scan, the torque that makes x̿'' the scan's x'' against `params` (the
/// averaged model's).
#[derive(Clone, Debug)]
struct Averaged<'p, const N: usize> {
    /// The run's steps from the one holding t_start − 2T to this one (the last).
    pieces: Vec<Piece<N>>,
    period: f64,
    params: &'p crate::Params,
}

impl<const N: usize> Averaged<'_, N> {
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

    fn scanned(&self, t: f64) -> ([f64; 2], f64) {
        let [x, v, acc] = self.averaged(t);
        let p = self.params;
        let extra = p.forcing((p.omega * t).sin()) - v - p.g(x) - acc;
        ([x, v], extra)
    }
}

impl<const N: usize> DenseOutput<2> for Averaged<'_, N> {
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

impl<const N: usize> ScanStep for Averaged<'_, N> {
    fn state_at(&self, t: f64) -> ([f64; 2], f64) {
        self.scanned(t)
    }
    fn end(&self) -> ([f64; 2], f64) {
        self.scanned(self.t_end())
    }
}

/// Simulates the model from its lowest stable equilibrium at a = 0 (at rest, its internal
/// states at rest there: [`Model::rest_states`]) and measures the response as [`super::response`]
/// does the study's: the signatures against the equilibrium curve of
/// [`Model::equivalent_params`], x'' the model's own.
///
/// A dithered model ([`Model::dither`]) is scanned on its motion averaged twice over the
/// dither's period T (a triangular window 2T wide, which removes the ripple and its harmonics),
/// against the averaged model's equilibria: the ripple is the control's own motion, not a burst.
///
/// Refused for a model whose static torque is not a study cubic (its equilibria are not a
/// parameter set's) and for one integrated piece by piece (sticking friction): its verdict would
/// need the scan to follow the pieces.
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
    m.check()?;
    let refuse = |reason: &str| Error::InvalidInput {
        what: "model",
        text: m.equation(),
        reason: reason.into(),
    };
    if m.switches() {
        return Err(refuse(
            "the burst verdict needs a smooth model (a term with sticking is integrated piece by piece)",
        ));
    }
    let p = m.equivalent_params().ok_or_else(|| {
        refuse("its static torque is not a study cubic αx³ − x² + γ(x − ε), so its equilibria are no parameter set's")
    })?;
    let x0 = crate::fast::stable_equilibrium(&p, 0.0);
    let z: [f64; MAX_STATES] = m.rest_states(x0);
    let v0 = m.rest_rate();
    match m.dim() {
        2 => run::<2>(m, &p, opts, [x0, v0]),
        3 => run::<3>(m, &p, opts, [x0, v0, z[0]]),
        _ => run::<4>(m, &p, opts, [x0, v0, z[0], z[1]]),
    }
}

/// The scan of the model's run from `y0`: by the method of steps for a delayed model
/// ([`Delayed`]), of the motion averaged over the dither's period for a dithered one
/// ([`Averaged`]), of the motion itself otherwise ([`Projected`]).
fn run<const N: usize>(
    m: &Model,
    p: &crate::Params,
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
fn scan_model<St: Stepper<N, Dense = AnyDense<N>>, const N: usize>(
    plan: &Plan,
    solver: St,
    m: &Model,
    p: &crate::Params,
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
            })
        };
        return scan_steps(plan, solver, p, opts, x0, taken.is_some(), project);
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
            params: p,
        })
    };
    scan_steps(plan, solver, p, opts, x0, true, average)
}

/// The scan over `solver`'s steps to the plan's end: each step's dense output, with whether it
/// ends inside the scanned span, goes to `view`, and what `view` returns is scanned. Steps before
/// the span are shown only when `every_step` (a view or a history that needs them).
fn scan_steps<St: Stepper<N, Dense = AnyDense<N>>, V: ScanStep, const N: usize>(
    plan: &Plan,
    mut solver: St,
    p: &crate::Params,
    opts: &BurstOptions,
    x0: f64,
    every_step: bool,
    mut view: impl FnMut(AnyDense<N>, bool) -> Option<V>,
) -> Result<Response> {
    let mut scanner = plan.scanner(p, opts, x0);
    let mut history = History::new(plan.history_span());
    while solver.t() < plan.scan.1 {
        solver.step(plan.scan.1)?;
        let scanned = solver.t() > plan.scan.0;
        if !scanned && !every_step {
            continue;
        }
        if let Some(v) = view(solver.dense(), scanned) {
            history.push(v);
            if let Some(d) = history.latest() {
                scanner.push(d, &history);
            }
        }
    }
    Ok(plan.assemble(p, opts, scanner.finish(&history)))
}
