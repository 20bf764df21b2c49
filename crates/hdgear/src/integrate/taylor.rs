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

use super::{DenseOutput, Options, SolverError, Stats, Stepper, System};
use crate::error::{Error, Result};

/// Lowest order used.
pub const MIN_ORDER: usize = 6;
/// Highest order used (ε down to 1e-20).
pub const MAX_ORDER: usize = 24;

/// Coefficient storage of one step: rows 0..=p.
pub type Coefficients<const N: usize> = [[f64; N]; MAX_ORDER + 1];

/// The order for tolerance `eps`.
pub fn order_for(eps: f64) -> usize {
    ((-eps.ln() / 2.0 + 1.0).ceil() as usize).clamp(MIN_ORDER, MAX_ORDER)
}

/// Normalised Taylor coefficients of sin(ω(t + h)) and cos(ω(t + h)) in h, up to `order`:
/// s_k = ω^k/k!·sin(ωt + kπ/2).
pub fn sine_coefficients(omega: f64, t: f64, order: usize, s: &mut [f64]) {
    let (sn, cs) = libm::sincos(omega * t);
    let cycle = [sn, cs, -sn, -cs];
    let mut f = 1.0;
    for (k, sk) in s
        .iter_mut()
        .enumerate()
        .take((order + 1).min(MAX_ORDER + 1))
    {
        *sk = f * cycle[k % 4];
        f *= omega * INV[k];
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
pub fn cauchy(a: &[f64], b: &[f64], k: usize) -> f64 {
    a[..=k]
        .iter()
        .zip(b[..=k].iter().rev())
        .map(|(x, y)| x * y)
        .sum()
}

/// The dense output of one Taylor step: the step polynomial.
#[derive(Clone, Copy, Debug)]
pub struct TaylorDense<const N: usize> {
    t0: f64,
    t1: f64,
    order: usize,
    c: Coefficients<N>,
}

impl<const N: usize> TaylorDense<N> {
    /// The step from `t0` to `t1` with coefficients `c` (rows 0..=order used).
    pub(crate) fn new(t0: f64, t1: f64, order: usize, c: Coefficients<N>) -> Self {
        TaylorDense { t0, t1, order, c }
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
        horner(&self.c, self.order, t - self.t0)
    }
}

#[inline(always)]
fn horner<const N: usize>(c: &Coefficients<N>, order: usize, h: f64) -> [f64; N] {
    let mut y = c[order];
    for k in (0..order).rev() {
        for i in 0..N {
            y[i] = y[i] * h + c[k][i];
        }
    }
    y
}

/// The Taylor stepper for a system that provides [`System::taylor`].
pub struct Taylor<'s, S: ?Sized, const N: usize> {
    sys: &'s S,
    opts: Options,
    order: usize,
    t: f64,
    y: [f64; N],
    /// Coefficients of the last step (around `t_prev`).
    c: Coefficients<N>,
    t_prev: f64,
    stats: Stats,
}

impl<'s, S: System<N> + ?Sized, const N: usize> Taylor<'s, S, N> {
    /// A stepper at (t0, y0); fails when the system has no Taylor coefficients or the options
    /// are unusable.
    pub fn new(sys: &'s S, t0: f64, y0: [f64; N], opts: Options) -> Result<Self> {
        opts.validate()?;
        let order = order_for(opts.rtol);
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
            t: t0,
            y: y0,
            c,
            t_prev: t0,
            stats: Stats::default(),
        })
    }

    /// The order in use.
    pub fn order(&self) -> usize {
        self.order
    }

    /// The Jorba–Zou step from the coefficients in `self.c`.
    fn step_size(&self) -> f64 {
        let p = self.order;
        // per component: relative where rtol·|y_i| ≥ atol, absolute (in units of atol/rtol) below
        let floor = self.opts.atol / self.opts.rtol;
        let y = &self.c[0];
        let norm = |row: &[f64; N]| {
            (0..N).fold(0.0f64, |m, i| m.max(row[i].abs() / y[i].abs().max(floor)))
        };
        // ln ρ_k = −ln(‖c_k‖)/k; ρ = min over k = p − 1, p
        let ln_rho = |k: usize| -norm(&self.c[k]).ln() / k as f64;
        (ln_rho(p - 1).min(ln_rho(p)) - 2.0 - 0.7 / (p - 1) as f64).exp()
    }
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
        let remaining = t_bound - self.t;
        if remaining <= 0.0 {
            return Ok(());
        }
        if self.stats.steps >= self.opts.max_steps {
            return Err(SolverError::TooManySteps {
                t: self.t,
                max_steps: self.opts.max_steps,
            }
            .into());
        }
        self.sys.taylor(self.t, &self.y, self.order, &mut self.c);
        self.stats.rhs_evals += 1;
        let mut h = self.step_size();
        if let Some(hm) = self.opts.h_max {
            h = h.min(hm);
        }
        let min_step = super::smallest_step(self.t, remaining);
        if !(h >= min_step || h >= remaining) {
            return Err(SolverError::StepSizeTooSmall { t: self.t, h }.into());
        }
        let last = h >= remaining;
        if last {
            h = remaining;
        }
        let y_new = horner(&self.c, self.order, h);
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

    fn dense(&mut self) -> TaylorDense<N> {
        TaylorDense {
            t0: self.t_prev,
            t1: self.t,
            order: self.order,
            c: self.c,
        }
    }

    fn stats(&self) -> Stats {
        self.stats
    }
}
