//! Taylor's method with the Jorba–Zou order and step rule (À. Jorba & M. Zou, "A software package
//! for the numerical integration of ODEs by means of high-order Taylor methods", Experimental
//! Mathematics 14 (2005) 99–117; the rule heyoka uses).
//!
//! Both models are a polynomial in the state plus a sine of time, so the normalised Taylor
//! coefficients y(t + h) = Σ c_k h^k of their solutions follow from short recurrences
//! ([`System::taylor`]): products by Cauchy sums, sin(ωt + ωh) in closed form. One step costs
//! O(p²) multiplications, never rejects, and its dense output is the polynomial itself.
//!
//! * Order: p = ⌈−ln(ε)/2 + 1⌉ with ε = rtol (13 at 1e-10), clamped to
//!   [`MIN_ORDER`]…[`MAX_ORDER`].
//! * Step: ρ = min((1/‖c_{p−1}‖)^{1/(p−1)}, (1/‖c_p‖)^{1/p}), h = ρ·e^{−2}·e^{−0.7/(p−1)}, where
//!   each component of the coefficients is divided by max(|y_i|, atol/rtol) before the max-norm —
//!   relative control where rtol·|y_i| ≥ atol, absolute below (Jorba–Zou's mixed criterion, per
//!   component as DOP853's error norm is, so that a large rigid-body angle does not loosen the
//!   control of a small torsion; with rtol = atol the switch is at |y_i| = 1, as in heyoka) — the
//!   radius of convergence estimated from the last two coefficients, scaled so the truncation
//!   error stays below ε.
//! * A given order p ([`Options::order`]): the same error model at that order, h =
//!   ρ·ε^{1/(p−1)}·e^{−0.7/(p−1)} (which is Jorba–Zou's step when p − 1 = −ln(ε)/2). A higher
//!   order takes fewer, longer steps for more work per step: it pays where each step carries
//!   other work (the variational equations of the periodic machinery, whose options ask for
//!   [`MAX_ORDER`]), not for a plain trajectory (orders 13 to 20 cost about the same there).
//!
//! **Why one file.** The Jorba–Zou order and step rule, the series helpers and the stepper that
//! uses them are one method; the batch driver (`batch.rs`) and the terms' rows (`model/jet.rs`)
//! stand on them.

use super::approx::{self, mul_add};
use super::lanes::Jet;
use super::{DenseOutput, Options, SolverError, Stats, Stepper, System};
use crate::error::{Error, Result};
use crate::simd::{Level, Simd, dispatched};

/// Lowest order used.
pub const MIN_ORDER: usize = 6;
/// Highest order used: ε down to 3e-17, below the smallest rtol [`super::Options`] accept (1e-15,
/// order 19). Every step's dense output holds this many rows plus one.
pub const MAX_ORDER: usize = 20;

/// Coefficient storage of one step: rows 0..=p.
pub type Coefficients<const N: usize> = [[f64; N]; MAX_ORDER + 1];

/// Eight rows of a system's own intermediate Taylor series (a model term's: the coefficients of
/// its inner functions, kept from order to order within one step). A term that reads another's
/// law (a mesh loss reads the stiffness's) leaves that law rows 0 to 4 and keeps its own in 5
/// to 7.
#[derive(Clone, Copy, Debug)]
pub struct Scratch(pub [[f64; MAX_ORDER + 1]; SCRATCH_ROWS]);

/// Rows in a [`Scratch`].
pub const SCRATCH_ROWS: usize = 8;

impl Default for Scratch {
    fn default() -> Self {
        Scratch([[0.0; MAX_ORDER + 1]; SCRATCH_ROWS])
    }
}

/// The sets of [`Scratch`] rows a Taylor stepper keeps for its system (one per term of a model,
/// [`crate::integrate::System::taylor_in`]): owned by the stepper, so that no step clears them.
pub type Workspace = [Scratch; WORKSPACE_SETS];

/// The number of [`Scratch`] sets in a [`Workspace`].
pub const WORKSPACE_SETS: usize = 6;

/// The order for tolerance `eps`.
pub fn order_for(eps: f64) -> usize {
    ((-eps.ln() / 2.0 + 1.0).ceil() as usize).clamp(MIN_ORDER, MAX_ORDER)
}

/// The order and step rule `opts` ask for: (p, s) with the step h = ρ·e^{−s − 0.7/(p−1)}
/// ([`step_from_norms`]): Jorba–Zou's s = 2 at their order, s = −ln(rtol)/(p − 1) at a given one.
pub(crate) fn rule(opts: &Options) -> (usize, f64) {
    match opts.order {
        None => (order_for(opts.rtol), 2.0),
        Some(p) => {
            let p = p.clamp(MIN_ORDER, MAX_ORDER);
            (p, -opts.rtol.ln() * INV[p - 2])
        }
    }
}

/// Normalised Taylor coefficients of sin(ω(t + h)) and cos(ω(t + h)) in h, up to `order`:
/// s_k = ω^k/k!·sin(ωt + kπ/2).
#[inline(always)]
pub fn sine_coefficients(omega: f64, t: f64, order: usize, s: &mut [f64]) {
    forcing_coefficients(1.0, omega, t, order, s);
}

/// [`sine_coefficients`] of a sine with amplitude `a`: s_k = a·ω^k/k!·sin(ωt + kπ/2) (at
/// a = 1 the same to the bit: each product by 1 is exact).
#[inline(always)]
pub(crate) fn forcing_coefficients(a: f64, omega: f64, t: f64, order: usize, s: &mut [f64]) {
    forcing_series(a, omega, libm::sincos(omega * t), order, s);
}

/// [`forcing_coefficients`] on any [`Jet`], from (sin ωt, cos ωt): on vector lanes each lane's
/// rows are those of its own sine, to the bit.
#[inline(always)]
pub(crate) fn forcing_series<J: Jet>(a: J, omega: J, (sn, cs): (J, J), order: usize, s: &mut [J]) {
    let cycle = [sn, cs, -sn, -cs];
    let Some((first, rest)) = s.split_first_mut() else {
        return;
    };
    *first = a * sn;
    let mut f = a * omega;
    for (k, sk) in rest.iter_mut().enumerate().take(order.min(MAX_ORDER)) {
        *sk = f * cycle[(k + 1) % 4];
        f = f * (omega * J::splat(INV[k + 1]));
    }
}

/// 1/(k + 1) for k = 0..=MAX_ORDER: the recurrences divide by these.
pub const INV: [f64; MAX_ORDER + 1] = {
    let mut t = [0.0; MAX_ORDER + 1];
    let mut k = 0;
    while k <= MAX_ORDER {
        t[k] = 1.0 / (k + 1) as f64;
        k += 1;
    }
    t
};

/// Σ_{j=0..=k} a_j b_{k−j}: the k-th coefficient of a product. (Split into several partial
/// sums it measured slower here, not faster.)
#[inline(always)]
pub fn cauchy<J: Jet>(a: &[J], b: &[J], k: usize) -> J {
    let (a, b) = (&a[..=k], &b[..=k]);
    cauchy_by(|j| a[j], |j| b[j], k)
}

/// [`cauchy`] over rows read by index (rows 0..=k of each): for rows kept where no plain slice
/// of them exists ([`crate::model::law`]'s intermediates).
#[inline(always)]
pub fn cauchy_by<J: Jet>(a: impl Fn(usize) -> J, b: impl Fn(usize) -> J, k: usize) -> J {
    // a plain loop from −0 (the sum an iterator's `sum` forms, to the bit): the iterator's fold
    // need not be inlined into a caller's recurrence
    let mut s = J::splat(-0.0);
    for j in 0..k + 1 {
        s = s + a(j) * b(k - j);
    }
    s
}

/// (a²)_k = Σ_{j=0..=k} a_j a_{k−j} by the symmetric half of the sum: 2·Σ_{j<k/2} a_j a_{k−j},
/// plus a_{k/2}² for even k.
#[inline(always)]
pub fn square_coefficient<J: Jet>(a: &[J], k: usize) -> J {
    let a = &a[..=k];
    square_by(|j| a[j], k)
}

/// [`square_coefficient`] over rows read by index, as [`cauchy_by`].
#[inline(always)]
pub fn square_by<J: Jet>(a: impl Fn(usize) -> J, k: usize) -> J {
    let mut half = J::splat(-0.0);
    for j in 0..k.div_ceil(2) {
        half = half + a(j) * a(k - j);
    }
    let middle = if k.is_multiple_of(2) {
        a(k / 2) * a(k / 2)
    } else {
        J::splat(0.0)
    };
    J::splat(2.0) * half + middle
}

/// The dense output of one Taylor step: the step polynomial.
#[derive(Clone, Copy, Debug)]
pub struct TaylorDense<const N: usize> {
    t0: f64,
    t1: f64,
    order: usize,
    c: Coefficients<N>,
    /// The state the step ended on.
    y1: [f64; N],
}

impl<const N: usize> TaylorDense<N> {
    /// The step from `t0` to `t1` with coefficients `c` (rows 0..=order used), ending on `y1`.
    pub(crate) fn new(t0: f64, t1: f64, order: usize, c: Coefficients<N>, y1: [f64; N]) -> Self {
        TaylorDense {
            t0,
            t1,
            order,
            c,
            y1,
        }
    }
}

impl<const N: usize> DenseOutput<N> for TaylorDense<N> {
    fn t_start(&self) -> f64 {
        self.t0
    }
    fn t_end(&self) -> f64 {
        self.t1
    }
    fn eval(&self, t: f64) -> [f64; N] {
        let h = t - self.t0;
        std::array::from_fn(|i| poly(|k| self.c[k][i], self.order, h))
    }
    fn end_state(&self) -> [f64; N] {
        self.y1
    }
    /// Σ_k |c_k,i|·h^k with h the step's length, by Horner's rule on the absolute values.
    fn abs_bound(&self, i: usize) -> Option<f64> {
        if i >= N {
            return None;
        }
        let c = self.c.get(..=self.order)?;
        Some(abs_horner(c, i, self.t1 - self.t0))
    }
    /// |c_0,i| − Σ_{k≥1} |c_k,i|·h^k less Horner's rounding (this module's `abs_floor`), h the
    /// step's length.
    fn abs_floor(&self, i: usize) -> Option<f64> {
        if i >= N {
            return None;
        }
        let h = self.t1 - self.t0;
        let (first, higher) = self.c.get(..=self.order)?.split_first()?;
        Some(abs_floor(first[i].abs(), abs_horner(higher, i, h) * h))
    }
}

/// Σ_k |c_k,i|·h^k over the rows `c`, by Horner's rule on the absolute values.
fn abs_horner<const N: usize>(c: &[[f64; N]], i: usize, h: f64) -> f64 {
    c.iter().rev().fold(0.0, |b, row| b * h + row[i].abs())
}

/// A bound on the rounding of Horner's rule (and of [`estrin`]), as a share of Σ_k |c_k|·|h|^k:
/// at most 2p·ε/(1 − 2p·ε) of it for order p (Higham, *Accuracy and Stability of Numerical
/// Algorithms*, §5.1), 9e-15 at [`MAX_ORDER`]; 1e-12 leaves room for the rounding of the bound
/// itself and of the argument t − t0.
const HORNER_ROUNDING: f64 = 1e-12;

/// A lower bound of |P(s)| for s in [0, h] as [`estrin`] computes it, P(s) = Σ_k c_k·s^k, from
/// |c_0| and `rest` = Σ_{k≥1} |c_k|·h^k: |c_0| − rest, less [`HORNER_ROUNDING`] of
/// |c_0| + rest. (Negative, so never a skip, where the step can reach zero.)
#[inline(always)]
pub(crate) fn abs_floor(first: f64, rest: f64) -> f64 {
    first - rest - HORNER_ROUNDING * (first + rest)
}

/// Σ_{k=0..=order} coef(k)·h^k by [`estrin`], with fused multiply-adds where the CPU has them:
/// how every step polynomial is evaluated, by [`TaylorDense::eval`] and by the batch's burst
/// scan on the batch's own rows (so both give the same values).
#[inline(always)]
pub(crate) fn poly(coef: impl Fn(usize) -> f64, order: usize, h: f64) -> f64 {
    poly_on(Simd::detect(), coef, order, h)
}

/// The Jorba–Zou step of order `p` from coefficients `c` and the [`Taylor::weights`] of the
/// step's start: the weighted max-norms of rows p − 1 and p.
#[inline(always)]
fn step_size<const FMA: bool, const N: usize>(
    p: usize,
    shift: f64,
    c: &[[f64; N]],
    scale: &[f64; N],
) -> f64 {
    let norm = |row: &[f64; N]| weighted_norm(|i| row[i], scale);
    step_from_norms::<FMA, false>(p, shift, norm(&c[p - 1]), norm(&c[p]))
}

/// max_i |`component(i)`|·`scale[i]`, the weighted max-norm of a coefficient row. A NaN component
/// (from an overflow in the recurrences) last in the row makes it NaN, where f64::max would drop
/// it and allow an infinite step.
#[inline(always)]
pub(crate) fn weighted_norm<const N: usize>(
    component: impl Fn(usize) -> f64,
    scale: &[f64; N],
) -> f64 {
    (0..N).fold(0.0f64, |m, i| {
        let v = component(i).abs() * scale[i];
        if v <= m { m } else { v }
    })
}

/// [`step_size`] capped at `h_max`.
#[inline(always)]
fn capped_step<const FMA: bool, const N: usize>(
    p: usize,
    shift: f64,
    h_max: Option<f64>,
    c: &[[f64; N]],
    scale: &[f64; N],
) -> f64 {
    cap(step_size::<FMA, N>(p, shift, c, scale), h_max)
}

/// `h`, at most `h_max` where there is one: the step rule's cap ([`Options`]' `h_max`).
#[inline(always)]
pub(crate) fn cap(h: f64, h_max: Option<f64>) -> f64 {
    h_max.map_or(h, |hm| h.min(hm))
}

dispatched! {
    /// [`estrin`] on the vector unit `simd` names.
    fn poly_on(coef: impl Fn(usize) -> f64, order: usize, h: f64) -> f64 = estrin::<FMA>(coef, order, h)
}

/// Σ_{k=0..=order} coef(k)·h^k by Estrin's scheme: the pairs c_2i + c_2i+1·h, then pairs of those
/// with h², h⁴, …: ⌈log₂(order + 1)⌉ dependent fused steps instead of Horner's `order`. Dense
/// output is evaluated one point after another by the event searches (each point depends on the
/// last), so the chain's length is what they pay: at order 13, four steps instead of thirteen.
/// Each order gets its own copy (the order a constant, so the pairs stay in registers). Its
/// rounding is of the size of Horner's rule's: a term c_k·h^k passes through at most
/// k + 2⌈log₂(order + 1)⌉ roundings (its power of h, built by squaring, and the pairings), within
/// the 2·order of Horner's rule for the orders used (≥ 6), so [`HORNER_ROUNDING`] bounds both.
#[inline(always)]
pub(crate) fn estrin<const FMA: bool>(coef: impl Fn(usize) -> f64, order: usize, h: f64) -> f64 {
    macro_rules! fixed {
        ($($p:literal)*) => {
            match order {
                $($p => estrin_to::<FMA, $p>(coef, h),)*
                _ => (0..order).rev().fold(coef(order), |y, k| mul_add::<FMA>(y, h, coef(k))),
            }
        };
    }
    fixed!(6 7 8 9 10 11 12 13 14 15 16 17 18 19 20)
}

/// [`estrin`] at the constant order P.
#[inline(always)]
fn estrin_to<const FMA: bool, const P: usize>(coef: impl Fn(usize) -> f64, h: f64) -> f64 {
    let mut b = [0.0; MAX_ORDER / 2 + 1];
    let mut m = (P + 1).div_ceil(2);
    for (i, bi) in b.iter_mut().enumerate().take(m) {
        *bi = if 2 * i < P {
            mul_add::<FMA>(coef(2 * i + 1), h, coef(2 * i))
        } else {
            coef(2 * i)
        };
    }
    let mut x = h * h;
    while m > 1 {
        let half = m.div_ceil(2);
        for i in 0..half {
            b[i] = if 2 * i + 1 < m {
                mul_add::<FMA>(b[2 * i + 1], x, b[2 * i])
            } else {
                b[2 * i]
            };
        }
        m = half;
        x *= x;
    }
    b[0]
}

/// The Taylor stepper for a system that provides [`System::taylor`].
pub struct Taylor<'s, S: ?Sized, const N: usize> {
    sys: &'s S,
    opts: Options,
    order: usize,
    /// The step rule's exponent ([`rule`]).
    shift: f64,
    t: f64,
    y: [f64; N],
    /// Coefficients of the last step (around `t_prev`).
    c: Coefficients<N>,
    /// The system's own rows ([`System::taylor_in`]).
    work: Workspace,
    t_prev: f64,
    stats: Stats,
}

impl<'s, S: System<N> + ?Sized, const N: usize> Taylor<'s, S, N> {
    /// A stepper at (t0, y0); fails when the system has no Taylor coefficients or the options
    /// are unusable.
    pub fn new(sys: &'s S, t0: f64, y0: [f64; N], opts: Options) -> Result<Self> {
        opts.validate()?;
        let (order, shift) = rule(&opts);
        let mut c = [[0.0; N]; MAX_ORDER + 1];
        if !sys.taylor(t0, &y0, order, &mut c) {
            return Err(Error::InvalidOption {
                name: "method",
                value: f64::NAN,
                reason: "taylor needs a system that provides its Taylor coefficients",
            });
        }
        Ok(Taylor {
            sys,
            opts,
            order,
            shift,
            t: t0,
            y: y0,
            c,
            work: [Scratch::default(); WORKSPACE_SETS],
            t_prev: t0,
            stats: Stats::default(),
        })
    }

    /// Starts again at (t0, y0) on the system `sys` (of the same kind, with the same options):
    /// as [`Taylor::new`] would, its work counted anew, its buffers kept (each pass writes every
    /// row it reads).
    pub(crate) fn restart(&mut self, sys: &'s S, t0: f64, y0: [f64; N]) {
        (self.sys, self.t, self.y, self.t_prev) = (sys, t0, y0, t0);
        self.stats = Stats::default();
    }

    /// The order in use.
    pub fn order(&self) -> usize {
        self.order
    }

    /// Each component's weight in the step rule, 1/max(|y_i|, atol/rtol): relative where
    /// rtol·|y_i| ≥ atol, absolute (in units of atol/rtol) below. From the state before the
    /// coefficients are computed, so that its divisions overlap the recurrence (read back from
    /// row 0 after it, they would wait for it).
    #[inline(always)]
    fn weights(&self) -> [f64; N] {
        let floor = self.opts.atol / self.opts.rtol;
        self.y.map(|y| 1.0 / y.abs().max(floor))
    }

    #[inline(always)]
    fn step_with<const FMA: bool>(&mut self, t_bound: f64) -> Result<()> {
        let Some(scale) = self.begin(t_bound)? else {
            return Ok(());
        };
        let (p, shift, h_max) = (self.order, self.shift, self.opts.h_max);
        let rule = |c: &[[f64; N]]| capped_step::<FMA, N>(p, shift, h_max, c, &scale);
        let h = if self.sys.taylor_limits_steps() {
            self.sys
                .taylor_step(
                    self.t,
                    &self.y,
                    p,
                    &mut self.c,
                    self.opts.atol,
                    &mut self.work,
                    rule,
                )
                // the system gave coefficients at the start (`Taylor::new`); without them now,
                // no step is known good
                .unwrap_or(f64::NAN)
        } else {
            // the rule alone: the recurrence and the rule stay apart, as the hot loop of a
            // polynomial model wants them
            self.sys
                .taylor_in(self.t, &self.y, p, &mut self.c, &mut self.work);
            rule(&self.c)
        };
        self.finish::<FMA>(t_bound, h)
    }

    /// The first part of a step towards `t_bound`: `None` when the stepper is there already,
    /// an error when its budget is spent, else the [`Taylor::weights`] of the step rule. The
    /// coefficients follow (the system's pass into [`Taylor::rows_mut`]), then
    /// [`Taylor::finish`] with the step they allow.
    #[inline(always)]
    pub(crate) fn begin(&self, t_bound: f64) -> Result<Option<[f64; N]>> {
        if t_bound - self.t <= 0.0 {
            return Ok(None);
        }
        if let Some(e) = self.opts.spent(self.stats.steps, self.t) {
            return Err(e.into());
        }
        Ok(Some(self.weights()))
    }

    /// The step rule on the pass's coefficients with the weights `scale` ([`Taylor::begin`]),
    /// capped at the options' largest step.
    #[inline(always)]
    pub(crate) fn rule<const FMA: bool>(&self, scale: &[f64; N]) -> f64 {
        capped_step::<FMA, N>(self.order, self.shift, self.opts.h_max, &self.c, scale)
    }

    /// The system's own rows of the last pass.
    pub(crate) fn work(&self) -> &Workspace {
        &self.work
    }

    /// Where the step starts and to which order: (t, y, p), and the coefficient rows and the
    /// system's own rows the pass fills.
    #[inline(always)]
    pub(crate) fn rows_mut(
        &mut self,
    ) -> (f64, &[f64; N], usize, &mut Coefficients<N>, &mut Workspace) {
        (self.t, &self.y, self.order, &mut self.c, &mut self.work)
    }

    /// The options the stepper runs with.
    pub(crate) fn options(&self) -> &Options {
        &self.opts
    }

    /// The last part of a step towards `t_bound`: a step of `h` (or to `t_bound` when that is
    /// nearer) on the coefficients of the pass, with its checks.
    #[inline(always)]
    pub(crate) fn finish<const FMA: bool>(&mut self, t_bound: f64, mut h: f64) -> Result<()> {
        let remaining = t_bound - self.t;
        self.stats.rhs_evals += 1;
        if h.is_nan() {
            // the coefficients overflowed: the solution leaves every bound within this step
            return Err(SolverError::BlowUp {
                t: self.t,
                value: f64::INFINITY,
            }
            .into());
        }
        let min_step = super::smallest_step(self.t, remaining);
        if !(h >= min_step || h >= remaining) {
            return Err(SolverError::StepSizeTooSmall { t: self.t, h }.into());
        }
        let last = h >= remaining;
        if last {
            h = remaining;
        }
        // Estrin's scheme: the new state is on the chain from one step to the next, and its four
        // fused steps at order 13 wait less than Horner's thirteen
        // a plain loop, not `array::from_fn`: its closure may be compiled apart from this
        // function's vector unit, where a fused multiply-add is a library call
        let mut y_new = [0.0; N];
        for (i, y) in y_new.iter_mut().enumerate() {
            *y = estrin::<FMA>(|k| self.c[k][i], self.order, h);
        }
        if let Some(v) = y_new
            .iter()
            .find(|v| !v.is_finite() || v.abs() > self.opts.blowup)
        {
            return Err(SolverError::BlowUp {
                t: self.t + h,
                value: *v,
            }
            .into());
        }
        self.t_prev = self.t;
        self.t = if last { t_bound } else { self.t + h };
        self.y = y_new;
        self.stats.steps += 1;
        Ok(())
    }
}

dispatched! {
    /// [`Taylor::step_with`] on the vector unit `simd` names (fused multiply-adds where it has
    /// them).
    fn step_on['s, S: System<N> + ?Sized, const N: usize](stepper: &mut Taylor<'s, S, N>, t_bound: f64) -> Result<()> = stepper.step_with::<FMA>(t_bound)
}

impl<'s, S: System<N> + ?Sized, const N: usize> Stepper<N> for Taylor<'s, S, N> {
    type Dense = TaylorDense<N>;

    fn t(&self) -> f64 {
        self.t
    }

    fn y(&self) -> &[f64; N] {
        &self.y
    }

    fn step(&mut self, t_bound: f64) -> Result<()> {
        // the step's own arithmetic is scalar: AVX-512's copy of it runs slower than AVX2's on the
        // CPUs measured (bench/results.py), so it stops at AVX2; the model's recurrence it calls
        // dispatches on its own
        step_on(Simd::detect().at_most(Level::Avx2), self, t_bound)
    }

    fn dense(&mut self) -> TaylorDense<N> {
        TaylorDense::new(self.t_prev, self.t, self.order, self.c, self.y)
    }

    fn stats(&self) -> Stats {
        self.stats
    }
}

/// The Jorba–Zou step for order `p` from the scaled norms of the last two coefficient rows:
/// h = e^{−s − 0.7/(p−1)}·min(n₁^{−1/(p−1)}, n₂^{−1/p}), `s` from [`rule`] (2 at Jorba–Zou's
/// order). `POLY` takes the logarithms and the exponential from the short polynomials of
/// [`approx`] (1e-9: a step rule is a heuristic), which vectorise over the batch's lanes; one
/// step alone is faster with the library's `ln` and `exp`.
#[inline(always)]
pub(crate) fn step_from_norms<const FMA: bool, const POLY: bool>(
    p: usize,
    s: f64,
    n1: f64,
    n2: f64,
) -> f64 {
    let (l1, l2) = if POLY {
        approx::ln_pair::<FMA>(n1, n2)
    } else {
        (n1.ln(), n2.ln())
    };
    let x = ln_step::<f64>(p, s, l1, l2);
    if POLY { approx::exp::<FMA>(x) } else { x.exp() }
}

/// ln h of [`step_from_norms`] from the logarithms `l1`, `l2` of the norms: ln ρ − s − 0.7/(p − 1),
/// ln ρ = min(−l₁/(p − 1), −l₂/p). On any [`Jet`]: the step rule's and the terms' own
/// ([`crate::model::jet::exp_step_limit`]) from one formula.
#[inline(always)]
pub(crate) fn ln_step<J: Jet>(p: usize, s: J, l1: J, l2: J) -> J {
    let ln_rho = (-l1 * J::splat(INV[p - 2])).min(-l2 * J::splat(INV[p - 1]));
    ln_rho - s - J::splat(0.7 * INV[p - 2])
}

#[cfg(test)]
mod tests {
    #[test]
    fn estrin_equals_horner_to_rounding() {
        // every order the steppers use (and one past the fixed copies), mixed signs and sizes,
        // h of either sign, below and above 1: Estrin's scheme and Horner's rule agree to a
        // few roundings of Σ|c_k|·|h|^k (a term left out or paired wrongly would be far off)
        for order in super::MIN_ORDER..=super::MAX_ORDER + 2 {
            let c: Vec<f64> = (0..=order)
                .map(|k| {
                    (-1f64).powi(k as i32 * (k as i32 + 1) / 2) * 1.3f64.powi(k as i32)
                        / (k + 1) as f64
                })
                .collect();
            for h in [0.0, 0.1, -0.7, 1.3, -2.9] {
                let horner = c.iter().rev().fold(0.0, |y, &ck| y * h + ck);
                let size: f64 = c
                    .iter()
                    .enumerate()
                    .map(|(k, ck)| (ck * h.powi(k as i32)).abs())
                    .sum();
                for e in [
                    super::estrin::<false>(|k| c[k], order, h),
                    super::estrin::<true>(|k| c[k], order, h),
                ] {
                    let bound = 4.0 * order as f64 * f64::EPSILON * size;
                    assert!(
                        (e - horner).abs() <= bound,
                        "order {order}, h {h}: {e} vs {horner}"
                    );
                }
            }
        }
    }
}
