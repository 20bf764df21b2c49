//! Taylor's method on [`LANES`] parameter sets of the dimensionless model at once, in lock-step:
//! structure of arrays (every coefficient is a `[f64; LANES]`), each lane with its own time, step
//! and end, so the compiler turns each operation into one vector instruction over the lanes. The
//! recurrence is the model's own ([`crate::model`]'s `taylor_rows`, the one the scalar stepper runs
//! on a single lane).
//!
//! The same order and step rule as [`crate::integrate::Taylor`], with two differences that keep
//! the lanes in vector registers: sin ωt and cos ωt are carried as two more state components, so
//! no lane calls a sine (sin ω(t + h)'s coefficients are ω^k/k!·(±sin ωt or ±cos ωt), products
//! with no chain through the orders; the new values by the addition theorems from cos ωh and
//! sin ωh to the step's order); and the step's logarithm and exponential are evaluated by short
//! polynomials to ~1e-9 (the step size is a heuristic: a relative change of 1e-9 in h changes
//! nothing measurable).
//!
//! Each step's bookkeeping (blow-up, step budget, which lanes to show) is checked over all lanes
//! at once; only a step where some lane fails goes lane by lane.
//!
//! [`integrate_batch_observed`] shows every lane's steps as their polynomials: sweeps and maps
//! scan them for bursts as they come ([`crate::burst::responses`]), nothing is integrated twice.
//!
//! The shipped binary picks the widest vector unit the CPU has at run time (AVX-512 with FMA,
//! AVX2 with FMA, else the portable SSE2 path). The two FMA paths compute bit-identical results;
//! the portable one rounds each product separately, so it differs from them at the rounding
//! level (a relative 1e-16 per operation, far below the tolerance).
//!
//! **Why one file.** The lock-step lanes, their Taylor series, step rule and tangent are one loop's
//! state, kept in registers together; splitting the loop's pieces across files would hide what is
//! vectorised with what.

use crate::error::Result;
use crate::error::SolverError;
use crate::integrate::Options;
use crate::integrate::approx::mul_add;
use crate::integrate::approx::{exponent, pow2};
use crate::integrate::lanes::check_inputs;
use crate::integrate::taylor::{INV, MAX_ORDER, TaylorDense, rule, step_from_norms};
use crate::model::{LaneParams, Rows, TangentRows, tangent_rows, taylor_rows};
use crate::params::Params;
use crate::simd::{Simd, dispatched};

pub use crate::integrate::lanes::{LANES, LaneResult};

type V = [f64; LANES];

/// Integrates each of `points` from its start `y0` at τ = 0 to `t_end`, [`LANES`] at a time, and
/// returns the final states in order.
///
/// ```
/// use hdgear::{Params, batch::integrate_batch, integrate::Options};
/// let points: Vec<Params> = [30.0, 10.0, 1.0, 0.1]
///     .iter()
///     .map(|&gamma| Params { gamma, ..Params::default() })
///     .collect();
/// let starts = vec![[0.0, 0.0]; 4];
/// let out = integrate_batch(&points, &starts, 100.0, Options::default()).unwrap();
/// assert_eq!(out.len(), 4);
/// ```
pub fn integrate_batch(
    points: &[Params],
    starts: &[[f64; 2]],
    t_end: f64,
    tol: Options,
) -> Result<Vec<LaneResult>> {
    let spans = vec![(t_end, t_end); points.len()];
    integrate_batch_observed(points, starts, &spans, tol, |_, _| {})?
        .into_iter()
        .collect()
}

/// [`integrate_batch`] with a time span per point, showing the steps: `spans[i] = (from, t_end)`
/// integrates point i to its own `t_end` and calls `observe(i, step)` with every step that ends
/// after `from`, in order, as its polynomial (the same [`TaylorDense`] the scalar Taylor stepper
/// gives). This is how sweeps run their burst analysis on sixteen points at once. Fails as a whole
/// only on bad input; a point that blows up or runs out of steps gets its own error, and its
/// neighbours' results are the same as without it.
///
/// ```
/// use hdgear::{Params, batch::integrate_batch_observed, integrate::{DenseOutput, Options}};
/// let points = vec![Params::default(), Params { gamma: 30.0, ..Params::default() }];
/// let mut peak = [0.0f64; 2];
/// let spans = [(0.0, 100.0), (50.0, 200.0)];
/// let out = integrate_batch_observed(&points, &[[0.0; 2]; 2], &spans, Options::default(), |i, step| {
///     assert!(step.t_end() > spans[i].0 && step.t_end() <= spans[i].1);
///     peak[i] = peak[i].max(step.eval(step.t_end())[1].abs());
/// })
/// .unwrap();
/// assert!(out.iter().all(|r| r.is_ok()));
/// assert!(peak[0] > 0.0 && peak[1] > 0.0);
/// ```
pub fn integrate_batch_observed(
    points: &[Params],
    starts: &[[f64; 2]],
    spans: &[(f64, f64)],
    tol: Options,
    mut observe: impl FnMut(usize, &TaylorDense<2>),
) -> Result<Vec<Result<LaneResult>>> {
    let steps = |c: usize, step: &StepLanes<'_>| {
        for l in step.shown() {
            observe(c * LANES + l, &step.dense(l));
        }
    };
    integrate_batch_steps(points, starts, spans, tol, steps)
}

/// [`integrate_batch_observed`] showing each step of a chunk of [`LANES`] points as one
/// [`StepLanes`] (structure of arrays, the batch's own rows): `observe(c, step)` for chunk `c`
/// (points `c·LANES ..`). For scanners that work on every lane at once.
pub(crate) fn integrate_batch_steps(
    points: &[Params],
    starts: &[[f64; 2]],
    spans: &[(f64, f64)],
    tol: Options,
    mut observe: impl FnMut(usize, &StepLanes<'_>),
) -> Result<Vec<Result<LaneResult>>> {
    check_inputs(points, starts.len(), spans, &tol, valid)?;
    let mut out = Vec::with_capacity(points.len());
    for (c, chunk) in points.chunks(LANES).enumerate() {
        let range = c * LANES..c * LANES + chunk.len();
        let mut show = |step: &StepLanes<'_>| observe(c, step);
        let mut b = Lanes::new(chunk, &starts[range.clone()], &spans[range], &tol);
        let lanes = run_chunk(&mut b, &tol, &mut show);
        out.extend(lanes.into_iter().take(chunk.len()));
    }
    Ok(out)
}

/// The check of a point's parameters [`check_inputs`] makes (their warnings are for the caller
/// to show, not a refusal).
fn valid(p: &Params) -> Result<()> {
    p.validate().map(drop)
}

/// The outcome of one lane integrated with a tangent vector ([`integrate_batch_tangent`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentResult {
    /// Final state [x, x'].
    pub y: [f64; 2],
    /// The final tangent vector's direction, scaled by a power of two (largest component in
    /// [1, 2)).
    pub tangent: [f64; 2],
    /// ln(|δ(t_end)| / |δ(t0)|): the tangent's growth over the span (Euclidean norms).
    pub ln_growth: f64,
    /// Steps taken by this lane.
    pub steps: u64,
}

/// Integrates each of `points` from `starts[i] = [x, x', δx, δx']` at `spans[i] = (t0, t_end)`
/// to `t_end`, together with the tangent vector δ of the flow (the linearised model
/// δx'' = (−3αx² + 2x − γ)·δx − δx', its Taylor coefficients from the state's by one more Cauchy
/// sum per order), [`LANES`] at a time. The step is chosen from the state's and the tangent's
/// coefficients together (from the state's alone it is far too long near a rest point, where
/// the state hardly moves while the tangent turns); the tangent is rescaled by an exact power
/// of two after every step, so it neither overflows nor underflows over any span, and its
/// growth is returned as a logarithm. Benettin's Lyapunov
/// exponents in [`crate::periodic::lyapunov_many`] are built on it.
///
/// ```
/// use hdgear::{Params, batch::integrate_batch_tangent, integrate::Options};
/// let p = Params::default();
/// let x0 = hdgear::fast::stable_equilibrium(&p, 0.0);
/// let out = integrate_batch_tangent(&[p], &[[x0, 0.0, 1.0, 0.0]], &[(0.0, 50.0)], Options::default())
///     .unwrap();
/// let r = out[0].as_ref().unwrap();
/// // at a stable equilibrium both eigenvalues have a negative real part (their sum is the
/// // Jacobian's trace, −1): the tangent decays
/// assert!(r.ln_growth < 0.0);
/// ```
pub fn integrate_batch_tangent(
    points: &[Params],
    starts: &[[f64; 4]],
    spans: &[(f64, f64)],
    tol: Options,
) -> Result<Vec<Result<TangentResult>>> {
    check_inputs(points, starts.len(), spans, &tol, valid)?;
    let mut out = Vec::with_capacity(points.len());
    for (c, chunk) in points.chunks(LANES).enumerate() {
        let range = c * LANES..c * LANES + chunk.len();
        let state: Vec<[f64; 2]> = starts[range.clone()].iter().map(|s| [s[0], s[1]]).collect();
        // nothing is shown: every step ends before the "shown after" time +∞
        let ends: Vec<(f64, f64)> = spans[range.clone()]
            .iter()
            .map(|&(_, end)| (f64::INFINITY, end))
            .collect();
        let mut b = Lanes::new(chunk, &state, &ends, &tol);
        let t0: Vec<f64> = spans[range.clone()].iter().map(|s| s.0).collect();
        b.start_at(chunk, &t0);
        let mut tangent = Box::<Tangent>::default();
        let pick = |l: usize| starts[range.start + if l < chunk.len() { l } else { 0 }];
        tangent.rows.x[0] = std::array::from_fn(|l| pick(l)[2]);
        tangent.rows.v[0] = std::array::from_fn(|l| pick(l)[3]);
        b.tangent = Some(tangent);
        let lanes = run_chunk(&mut b, &tol, &mut |_| {});
        let tg = b.tangent.take().unwrap_or_default();
        out.extend(
            lanes
                .into_iter()
                .take(chunk.len())
                .enumerate()
                .map(|(l, r)| {
                    r.and_then(|r| {
                        let s = pick(l);
                        let d = [tg.rows.x[0][l], tg.rows.v[0][l]];
                        let ln_growth = d[0].hypot(d[1]).ln() - s[2].hypot(s[3]).ln()
                            + tg.log2_scale[l] * std::f64::consts::LN_2;
                        if ln_growth.is_finite() {
                            Ok(TangentResult {
                                y: r.y,
                                tangent: d,
                                ln_growth,
                                steps: r.steps,
                            })
                        } else {
                            Err(crate::Error::NoConvergence {
                                what: "the tangent vector (zero or not finite)",
                                iterations: r.steps as usize,
                                residual: ln_growth,
                            })
                        }
                    })
                }),
        );
    }
    Ok(out)
}

/// One step of every lane of a chunk, as the batch holds it: what [`integrate_batch_steps`]
/// shows. Rows `0..=order` of x and x' are the step's Taylor coefficients in (t − t0).
pub(crate) struct StepLanes<'a> {
    /// The Taylor order.
    pub order: usize,
    /// Each lane's step start.
    pub t0: &'a V,
    /// Each lane's step end.
    pub t1: &'a V,
    /// x's coefficient rows.
    pub x: &'a [V],
    /// x''s coefficient rows.
    pub v: &'a [V],
    /// The state each lane ended on.
    pub end: (&'a V, &'a V),
    /// sin ωt and cos ωt at each lane's step end (the batch's carried values).
    pub sin_cos: (&'a V, &'a V),
    /// Lanes whose step is shown (they moved, past their `from`, and hold a point).
    pub shown: [bool; LANES],
}

impl StepLanes<'_> {
    /// The shown lanes, in order.
    pub(crate) fn shown(&self) -> impl Iterator<Item = usize> + '_ {
        (0..LANES).filter(|&l| self.shown[l])
    }

    /// Lane `l`'s step as its polynomial (the same [`TaylorDense`] the scalar stepper gives).
    pub(crate) fn dense(&self, l: usize) -> TaylorDense<2> {
        let mut c = [[0.0; 2]; MAX_ORDER + 1];
        for (k, ck) in c.iter_mut().enumerate().take(self.order + 1) {
            *ck = [self.x[k][l], self.v[k][l]];
        }
        TaylorDense::new(
            self.t0[l],
            self.t1[l],
            self.order,
            c,
            [self.end.0[l], self.end.1[l]],
        )
    }
}

/// What a chunk shows its steps to.
type Show<'a> = &'a mut dyn FnMut(&StepLanes<'_>);

/// Runs one chunk's lanes to their ends, on the widest vector unit available.
/// With a tangent the chunk runs its own copy of the loop (the tangent a constant): a run-time
/// test in the one loop made the plain batch a quarter slower.
fn run_chunk(b: &mut Lanes, tol: &Options, show: Show<'_>) -> Outcomes {
    let simd = Simd::detect();
    if b.tangent.is_some() {
        run_tangent(simd, b, tol, show)
    } else {
        run_plain(simd, b, tol, show)
    }
}

dispatched! {
    /// [`run`] without a tangent, on the vector unit `simd` names.
    fn run_plain(b: &mut Lanes, tol: &Options, show: Show<'_>) -> Outcomes = run::<FMA, false>(b, tol, show)
}

dispatched! {
    /// [`run`] with a tangent, on the vector unit `simd` names.
    fn run_tangent(b: &mut Lanes, tol: &Options, show: Show<'_>) -> Outcomes = run::<FMA, true>(b, tol, show)
}

/// Every lane's x and x' at its own `h` from their coefficient rows `x` and `v` (lowest order
/// first, as many of each), by Horner's rule: the two chains interleaved and sixteen lanes at
/// once, so the chains' length is not what it pays, and Horner's rule takes the fewest
/// operations (the scalar stepper, bound by latency, takes Estrin's scheme instead). Each order
/// the tolerances pick (and half of it, for [`Series::rotate`]) has its rows written out
/// (`countdown!`).
#[inline(always)]
pub(crate) fn horner_lanes<const FMA: bool>(x: &[V], v: &[V], h: &V) -> (V, V) {
    let p = x.len().min(v.len()).saturating_sub(1);
    macro_rules! fixed {
        ($($p:literal)*) => {
            match p {
                $($p => horner_to::<FMA, $p>(x, v, h),)*
                _ => horner_rows::<FMA>(x, v, h, p),
            }
        };
    }
    // (3 … 10: the rotation's series in h², to half the order)
    fixed!(3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20)
}

/// [`horner_lanes`] at the constant order P.
#[inline(always)]
fn horner_to<const FMA: bool, const P: usize>(x: &[V], v: &[V], h: &V) -> (V, V) {
    let (mut yx, mut yv) = (x[P], v[P]);
    countdown!(P, |k| horner_row::<FMA>(
        (&mut yx, &mut yv),
        (&x[k], &v[k]),
        h
    ));
    (yx, yv)
}

/// [`horner_lanes`] at any order, a loop.
#[inline(always)]
fn horner_rows<const FMA: bool>(x: &[V], v: &[V], h: &V, p: usize) -> (V, V) {
    let (mut yx, mut yv) = (x[p], v[p]);
    for k in (0..p).rev() {
        horner_row::<FMA>((&mut yx, &mut yv), (&x[k], &v[k]), h);
    }
    (yx, yv)
}

/// One row of Horner's rule on both sums: y ← y·h + c.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lanes of parallel arrays, indexed together
fn horner_row<const FMA: bool>((yx, yv): (&mut V, &mut V), (cx, cv): (&V, &V), h: &V) {
    for l in 0..LANES {
        yx[l] = mul_add::<FMA>(yx[l], h[l], cx[l]);
        yv[l] = mul_add::<FMA>(yv[l], h[l], cv[l]);
    }
}

/// `$body` for `$k` = `$p` − 1 down to 0 (`$p` a constant ≤ 21), written out: each with its `$k`
/// a constant. A loop over the rows that carries sums of all lanes from one row to the next gives
/// the compiler no store to start vectorising from: in the batch step's rotation of sin ωt it
/// kept the sums lane by lane in scalar registers (and one of them in memory); written out, most
/// of each row is one vector operation. (A macro, not a function taking a closure: a closure not
/// inlined is not compiled for the caller's vector unit, and its fused multiply-adds became
/// library calls, 3.6 times slower.)
macro_rules! countdown {
    ($p:expr, |$k:ident| $body:expr) => {
        countdown!(@each $p, $k, $body, 0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19 20)
    };
    (@each $p:expr, $k:ident, $body:expr, $($i:literal)*) => {
        $(if $i < $p {
            let $k = $p - 1 - $i;
            $body;
        })*
    };
}
pub(crate) use countdown;

/// What a chunk gives: one outcome per lane.
type Outcomes = [Result<LaneResult>; LANES];

/// Steps every lane to its end. A lane that blows up or runs out of steps stops there with its
/// error; the others go on, so a point's outcome never depends on the points beside it.
#[inline(always)]
fn run<const FMA: bool, const TANGENT: bool>(
    b: &mut Lanes,
    tol: &Options,
    show: Show<'_>,
) -> Outcomes {
    let mut failed: [Option<crate::Error>; LANES] = std::array::from_fn(|_| None);
    let mut count = 0u64;
    while (0..LANES).any(|l| b.t[l] < b.t_end[l]) {
        b.step::<FMA, TANGENT>();
        count += 1;
        let late = tol.past_deadline(count);
        let Step {
            t0,
            h,
            x: nx,
            v: nv,
        } = &b.last;
        // the common case checked over all lanes at once: no lane blew up or ran out of steps
        let (mut trouble, mut shown) = (false, false);
        let (mut blown, mut spent) = ([false; LANES], [false; LANES]);
        for l in 0..LANES {
            let moved = h[l] > 0.0;
            blown[l] = !(nx[l].abs() <= tol.blowup && nv[l].abs() <= tol.blowup);
            spent[l] = (b.steps[l] >= tol.max_steps || late) && b.t[l] < b.t_end[l];
            trouble |= moved & (blown[l] | spent[l]);
            shown |= moved & (b.t[l] > b.from[l]);
        }
        if trouble {
            settle_trouble(b, tol, &(blown, spent), &mut failed, show);
            continue;
        }
        if shown {
            let lanes = std::array::from_fn(|l| l < b.live && h[l] > 0.0 && b.t[l] > b.from[l]);
            show(&b.view(t0, (nx, nv), lanes));
        }
        let (x0, v0) = (b.rows.x[0], b.rows.v[0]);
        let (mut x, mut v) = ([0.0; LANES], [0.0; LANES]);
        for l in 0..LANES {
            let moved = h[l] > 0.0;
            x[l] = if moved { nx[l] } else { x0[l] };
            v[l] = if moved { nv[l] } else { v0[l] };
        }
        (b.rows.x[0], b.rows.v[0]) = (x, v);
    }
    std::array::from_fn(|l| match failed[l].take() {
        Some(e) => Err(e),
        None => Ok(LaneResult {
            y: [b.rows.x[0][l], b.rows.v[0][l]],
            steps: b.steps[l],
        }),
    })
}

/// `run`'s step when some lane blew up or ran out of steps (`failing`: which lanes did, as `run`
/// found them): lane by lane, each failing lane stops with its error, the others are shown and
/// move on. The step is the one in `b.last`.
#[cold]
fn settle_trouble(
    b: &mut Lanes,
    tol: &Options,
    failing: &([bool; LANES], [bool; LANES]),
    failed: &mut [Option<crate::Error>; LANES],
    show: Show<'_>,
) {
    // a copy: the lanes below change `b`
    let Step {
        t0,
        h,
        x: nx,
        v: nv,
    } = b.last;
    let (blown, spent) = failing;
    let mut lanes = [false; LANES];
    for l in 0..LANES {
        if h[l] <= 0.0 {
            continue;
        }
        let error = if blown[l] {
            let value = if nx[l].abs() > nv[l].abs() {
                nx[l]
            } else {
                nv[l]
            };
            Some(SolverError::BlowUp { t: b.t[l], value })
        } else if spent[l] {
            // out of steps, or else (the loop's clock said so) past the deadline
            Some(
                tol.spent(b.steps[l], b.t[l])
                    .unwrap_or(SolverError::Deadline { t: b.t[l] }),
            )
        } else {
            None
        };
        if let Some(e) = error {
            failed[l] = Some(e.into());
            b.t_end[l] = b.t[l];
            continue;
        }
        lanes[l] = l < b.live && b.t[l] > b.from[l];
    }
    if lanes.contains(&true) {
        show(&b.view(&t0, (&nx, &nv), lanes));
    }
    for l in 0..LANES {
        if h[l] > 0.0 && failed[l].is_none() {
            (b.rows.x[0][l], b.rows.v[0][l]) = (nx[l], nv[l]);
        }
    }
}

/// The lanes' parameters, states and coefficients; like [`Rows`], aligned to a cache line.
#[repr(C, align(64))]
struct Lanes {
    params: LaneParams<LANES>,
    t: V,
    t_end: V,
    /// Steps ending after this are shown.
    from: V,
    /// Lanes that hold a point (the rest are padding).
    live: usize,
    /// sin ωt and cos ωt, carried as state.
    sin: V,
    cos: V,
    /// ±ω^k/k!, the Taylor coefficients of cos ωh and sin ωh ([`Series`]).
    series: Box<Series>,
    steps: [u64; LANES],
    order: usize,
    /// The step rule's exponent ([`rule`]).
    shift: f64,
    floor: f64,
    h_max: f64,
    /// Taylor coefficients of x, x', sin ωt; row 0 of x and x' is the state between steps.
    rows: Box<Rows<LANES>>,
    /// The tangent vector's coefficients, when one is carried ([`integrate_batch_tangent`]).
    tangent: Option<Box<Tangent>>,
    /// The last step ([`Lanes::step`]).
    last: Step,
}

/// Every lane's last step: its start, size (0 for a lane at its end) and end state. Kept in
/// the batch's memory, not returned: returned by value, the sixteen lanes were written piece
/// by piece (one, eight, four, two and one lanes) and read back as vectors, each read waiting
/// on the pieces' stores.
#[derive(Clone, Copy, Default)]
#[repr(C, align(64))]
struct Step {
    t0: V,
    h: V,
    x: V,
    v: V,
}

/// A tangent vector carried by every lane: its coefficient rows (row 0 the vector between
/// steps, rescaled after each step by 2^−e) and each lane's total e.
#[derive(Default)]
struct Tangent {
    rows: TangentRows<LANES>,
    log2_scale: V,
}

impl Lanes {
    fn new(points: &[Params], starts: &[[f64; 2]], spans: &[(f64, f64)], tol: &Options) -> Lanes {
        let pick = |l: usize| if l < points.len() { l } else { 0 };
        let (order, shift) = rule(tol);
        let mut rows = Box::<Rows<LANES>>::default();
        rows.x[0] = std::array::from_fn(|l| starts[pick(l)][0]);
        rows.v[0] = std::array::from_fn(|l| starts[pick(l)][1]);
        Lanes {
            params: LaneParams::new(points),
            t: [0.0; LANES],
            t_end: std::array::from_fn(|l| spans[pick(l)].1),
            from: std::array::from_fn(|l| spans[pick(l)].0),
            live: points.len(),
            sin: [0.0; LANES],
            cos: [1.0; LANES],
            series: Box::new(Series::new(points, order)),
            steps: [0; LANES],
            order,
            shift,
            // ≥ 1e-150 so that [`row_norms`]' product of two scales stays normal; a state
            // below that in both components is far under any tolerance the options allow
            floor: (tol.atol / tol.rtol).max(1e-150),
            h_max: tol.h_max.unwrap_or(f64::INFINITY),
            rows,
            tangent: None,
            last: Step::default(),
        }
    }

    /// Starts lane l at time `t0[l]` instead of 0 (padding lanes at `t0[0]`).
    fn start_at(&mut self, points: &[Params], t0: &[f64]) {
        for l in 0..LANES {
            let i = if l < points.len() { l } else { 0 };
            self.t[l] = t0[i];
            (self.sin[l], self.cos[l]) = libm::sincos(points[i].omega * t0[i]);
        }
    }

    /// One step of every lane still short of its end: leaves the lanes' start times, steps (0
    /// for a lane already at its end) and new x, x' in `last`, and the step's coefficients in
    /// `rows` (row 0 still the old state, for [`Lanes::view`]; `run` writes the new one after).
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lanes of parallel arrays, indexed together
    fn step<const FMA: bool, const TANGENT: bool>(&mut self) {
        let p = self.order;
        let r = &mut *self.rows;
        self.series
            .forcing_rows(p, (&self.sin, &self.cos), &mut r.f);
        taylor_rows::<LANES, FMA>(&self.params, p, r);
        let mut norms = row_norms(p, self.floor, &r.x[..=p], &r.v[..=p]);
        if let Some(tg) = self.tangent.as_deref_mut().filter(|_| TANGENT) {
            // the tangent's own coefficients count too: near a rest point the state's are tiny
            // (it hardly moves) while the tangent turns at the linearisation's frequency
            tangent_rows::<LANES, FMA>(&self.params, p, r, &mut tg.rows);
            let (n1, n2) = row_norms(p, self.floor, &tg.rows.x[..=p], &tg.rows.v[..=p]);
            for l in 0..LANES {
                norms.0[l] = norms.0[l].max(n1[l]);
                norms.1[l] = norms.1[l].max(n2[l]);
            }
        }
        let h = step_sizes::<FMA>((p, self.shift), self.h_max, &self.t, &self.t_end, norms);
        self.last.h = h;
        (self.last.x, self.last.v) = horner_lanes::<FMA>(&r.x[..=p], &r.v[..=p], &h);
        if let Some(tg) = self.tangent.as_deref_mut().filter(|_| TANGENT) {
            let (dx, dv) = horner_lanes::<FMA>(&tg.rows.x[..=p], &tg.rows.v[..=p], &h);
            // rescaled by 2^−e, e the exponent of the larger component: exact, and the
            // vector stays near 1 whatever its growth (e kept in ±1000 so 2^−e is normal)
            for l in 0..LANES {
                let e = exponent(dx[l].abs().max(dv[l].abs())).clamp(-1000.0, 1000.0);
                let scale = pow2(-e);
                tg.rows.x[0][l] = dx[l] * scale;
                tg.rows.v[0][l] = dv[l] * scale;
                tg.log2_scale[l] += e;
            }
        }
        let (ns, nc) = self.series.rotate::<FMA>(&h, (&self.sin, &self.cos));
        self.last.t0 = self.t;
        // no selects: a lane at its end has h = 0, and a step of 0 leaves the values of t,
        // sin ωt and cos ωt as they are (cos 0 = 1, sin 0 = 0 in [`Series::rotate`]). Selects there
        // were compiled into a branch per lane, stores lane by lane that the next step's
        // vector loads waited on
        for l in 0..LANES {
            self.t[l] = (self.t[l] + h[l]).min(self.t_end[l]);
            self.steps[l] += u64::from(h[l] > 0.0);
            self.sin[l] = ns[l];
            self.cos[l] = nc[l];
        }
    }

    /// The last step of every lane (started at `t0`, ended on `end`), `shown` the lanes to show:
    /// row 0 of x and x' must still be the old state.
    fn view<'a>(&'a self, t0: &'a V, end: (&'a V, &'a V), shown: [bool; LANES]) -> StepLanes<'a> {
        let rows = self.order + 1;
        StepLanes {
            order: self.order,
            t0,
            t1: &self.t,
            x: &self.rows.x[..rows],
            v: &self.rows.v[..rows],
            end,
            sin_cos: (&self.sin, &self.cos),
            shown,
        }
    }
}

/// The coefficients of cos ωh = Σ_i (−1)^i ω^{2i}/(2i)!·h^{2i} and sin ωh/h =
/// Σ_i (−1)^i ω^{2i+1}/(2i+1)!·h^{2i} of every lane, to the step's order p (`cos[i]`, `sin[i]` for
/// i = 0..=p/2; a term past p is 0), with their signs: how each lane's sin ωt and cos ωt move on
/// by a step ([`Series::rotate`]).
#[repr(C, align(64))]
struct Series {
    cos: [V; MAX_ORDER / 2 + 1],
    sin: [V; MAX_ORDER / 2 + 1],
    /// δ·`cos` and δ·`sin`: the forcing δ sin ω(t + h)'s ([`Series::forcing_rows`]).
    forcing_cos: [V; MAX_ORDER / 2 + 1],
    forcing_sin: [V; MAX_ORDER / 2 + 1],
    /// p/2: the highest i.
    top: usize,
}

impl Series {
    fn new(points: &[Params], order: usize) -> Series {
        let point = |l: usize| &points[if l < points.len() { l } else { 0 }];
        // ω^k/k! with the sign (−1)^⌊k/2⌋, 0 past the order
        let term = |k: usize, l: usize| {
            let f = (0..k).fold(1.0, |f, j| f * point(l).omega * INV[j]);
            let sign = if (k / 2).is_multiple_of(2) { 1.0 } else { -1.0 };
            if k <= order { sign * f } else { 0.0 }
        };
        let cos = std::array::from_fn(|i| std::array::from_fn(|l| term(2 * i, l)));
        let sin = std::array::from_fn(|i| std::array::from_fn(|l| term(2 * i + 1, l)));
        let forcing = |rows: &[V; MAX_ORDER / 2 + 1]| {
            std::array::from_fn(|i| std::array::from_fn(|l| point(l).delta * rows[i][l]))
        };
        Series {
            forcing_cos: forcing(&cos),
            forcing_sin: forcing(&sin),
            cos,
            sin,
            top: order / 2,
        }
    }

    /// Rows 0..=p of the forcing δ sin ω(t + h)'s Taylor coefficients in h from sin ωt and
    /// cos ωt (`sin_cos`): by the addition theorem, (−1)^i δω^{2i}/(2i)!·sin ωt for order 2i
    /// and (−1)^i δω^{2i+1}/(2i+1)!·cos ωt for order 2i + 1: each row a product, no chain
    /// through the orders.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lanes of parallel arrays, indexed together
    fn forcing_rows(&self, p: usize, (sin, cos): (&V, &V), f: &mut [V]) {
        for i in 0..=p / 2 {
            let mut row = [0.0; LANES];
            for l in 0..LANES {
                row[l] = self.forcing_cos[i][l] * sin[l];
            }
            f[2 * i] = row;
            if 2 * i < p {
                for l in 0..LANES {
                    row[l] = self.forcing_sin[i][l] * cos[l];
                }
                f[2 * i + 1] = row;
            }
        }
    }

    /// sin ω(t + h) and cos ω(t + h) of every lane from sin ωt and cos ωt (`sin_cos`): cos ωh and
    /// sin ωh/h by Horner's rule in h² ([`horner_lanes`]), then the addition theorems. (The series'
    /// signs are in their coefficients and each order is written out: with the signs applied in a
    /// loop, the compiler kept one of the two sums in memory and split the lanes between scalar
    /// and vector code.)
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lanes of parallel arrays, indexed together
    fn rotate<const FMA: bool>(&self, h: &V, (sin, cos): (&V, &V)) -> (V, V) {
        let mut h2 = [0.0; LANES];
        for l in 0..LANES {
            h2[l] = h[l] * h[l];
        }
        let top = self.top;
        let (ch, sh) = horner_lanes::<FMA>(&self.cos[..=top], &self.sin[..=top], &h2);
        let (mut ns, mut nc) = ([0.0; LANES], [0.0; LANES]);
        for l in 0..LANES {
            let s = sh[l] * h[l];
            ns[l] = mul_add::<FMA>(sin[l], ch[l], cos[l] * s);
            nc[l] = mul_add::<FMA>(cos[l], ch[l], -(sin[l] * s));
        }
        (ns, nc)
    }
}

/// The scaled max-norms of rows p − 1 and p of each lane's coefficients (`x`, `v`),
/// each component divided by max(|its value|, `floor`) as the scalar stepper does
/// ([`crate::integrate::Taylor`]): one division per lane for both scales.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lanes of parallel arrays, indexed together
fn row_norms(p: usize, floor: f64, x: &[V], v: &[V]) -> (V, V) {
    let (mut n1, mut n2) = ([0.0; LANES], [0.0; LANES]);
    for l in 0..LANES {
        // 1/ax and 1/av from one division (ax, av ≥ floor ≥ 1e-150: the product is normal)
        let (ax, av) = (x[0][l].abs().max(floor), v[0][l].abs().max(floor));
        let inv = 1.0 / (ax * av);
        let (sx, sv) = (av * inv, ax * inv);
        n1[l] = (x[p - 1][l].abs() * sx).max(v[p - 1][l].abs() * sv);
        n2[l] = (x[p][l].abs() * sx).max(v[p][l].abs() * sv);
    }
    (n1, n2)
}

/// The Jorba–Zou step of each lane from its norms ([`row_norms`]; 0 for a lane already at its
/// end), at most `h_max`, clipped to the lane's end; the logarithms of both norms from one
/// division ([`step_from_norms`]).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lanes of parallel arrays, indexed together
fn step_sizes<const FMA: bool>(
    (p, shift): (usize, f64),
    h_max: f64,
    t: &V,
    t_end: &V,
    n: (V, V),
) -> V {
    // a loop, not `array::from_fn`: its closure is not inlined into the vector paths
    let mut h = [0.0; LANES];
    for l in 0..LANES {
        let hl = step_from_norms::<FMA, true>(p, shift, n.0[l], n.1[l]).min(h_max);
        let remaining = t_end[l] - t[l];
        h[l] = if remaining > 0.0 {
            hl.min(remaining)
        } else {
            0.0
        };
    }
    h
}
