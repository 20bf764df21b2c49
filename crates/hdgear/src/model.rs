//! The drive's models.
//!
//! * [`Model`]: a model assembled from terms ([`terms`], [`memory`] for those with an internal
//!   state z of their own): x'' + Σ T_i(x, x', z_i) = μ + δ sin ωτ, z_i' = r_i(x, x', z_i), each
//!   term defined once with its value, derivatives, Taylor recurrence ([`jet`]) and parameters,
//!   every method of the model derived from them; [`Model::facts`] derives what the fast
//!   subsystem's analysis needs (damping at rest, focus/node threshold, decay time);
//!   [`ModelCurve`] its equilibrium curve for the burst verdict, from a root finder on its static
//!   torque where that is no study cubic.
//! * [`Dimensionless`]: the study's model x'' + x' + αx³ − x² + γ(x − ε) = μ + δ sin ωτ with its
//!   hand-scheduled Taylor recurrence on 1 and 16 lanes, the fast path every command of the
//!   study runs on; the tests hold it to [`Model::study`]'s coefficients.

pub mod branches;
pub mod control;
pub mod dahl;
pub mod delay;
pub mod delayed;
pub mod drag;
pub mod excitation;
pub mod friction;
pub mod jet;
pub mod law;
pub mod memory;
pub mod mesh;
pub mod mesh_loss;
pub mod piecewise;
mod relation;
pub mod schedule;
pub mod spring;
mod study_terms;
pub mod switching;
pub mod tables;
pub mod term;
pub mod terms;

mod assembled;
mod curve;
mod scheduled_curve;
pub use assembled::{
    Description, FORCING, Facts, MAX_STATES, MAX_TERMS, Model, ModelParam, ParamValue, Subject,
    integrate_models, integrate_switching_models, on_vector_lanes, study_param,
};
pub(crate) use curve::refusal;
pub use curve::{ModelCurve, ModelFollower, StaticTorque, Statics};
pub use scheduled_curve::{AnyCurve, ScheduledTorque};

use crate::integrate::System;
use crate::integrate::approx::mul_add;
use crate::params::Params;
use crate::simd::{Simd, dispatched};

/// The dimensionless harmonic drive model (guide: the model and its parameters) as a [`System`] with state [x, x'].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dimensionless {
    /// The parameters.
    pub p: Params,
}

impl Dimensionless {
    /// Wraps a parameter set.
    pub fn new(p: Params) -> Self {
        Dimensionless { p }
    }
}

// `libm::sin` (the Rust port of musl's, correctly rounded to within 1 ulp) instead of `f64::sin`:
// the right-hand side is dominated by the sine, and libm's inlines where the C library's is a
// call.
impl System<2> for Dimensionless {
    #[inline(always)]
    fn rhs(&self, t: f64, y: &[f64; 2]) -> [f64; 2] {
        let p = &self.p;
        [y[1], p.forcing(libm::sin(p.omega * t)) - y[1] - p.g(y[0])]
    }
    /// ∂f/∂y = [[0, 1], [−g'(x), −1]] (trace −1 everywhere).
    fn jacobian(&self, _t: f64, y: &[f64; 2]) -> Option<[[f64; 2]; 2]> {
        Some([[0.0, 1.0], [-self.p.g_prime(y[0]), -1.0]])
    }
    /// x_{k+1} = v_k/(k+1), v_{k+1} = (μ[k=0] + δ s_k − v_k − α(x³)_k + (x²)_k − γ x_k
    /// + γε[k=0])/(k+1), with (x²)_k, (x³)_k Cauchy sums and s_k the coefficients of sin ωt.
    #[inline(always)]
    fn taylor(&self, t: f64, y: &[f64; 2], order: usize, c: &mut [[f64; 2]]) -> bool {
        taylor_on(Simd::detect(), &self.p, t, y, order, c);
        true
    }
}

dispatched! {
    /// [`taylor_scalar`] on the vector unit `simd` names: on one lane it works on scalars, but
    /// with AVX-512's 32 vector registers fewer of its sums are spilled to the stack (the same
    /// results to the bit as AVX2's copy).
    fn taylor_on(p: &Params, t: f64, y: &[f64; 2], order: usize, c: &mut [[f64; 2]]) -> () = taylor_scalar::<FMA>(p, t, y, order, c)
}

/// [`System::taylor`] for one parameter set: sin ωt's coefficients in closed form, then the
/// recurrence [`taylor_rows`] on one lane.
#[inline(always)]
fn taylor_scalar<const FMA: bool>(
    p: &Params,
    t: f64,
    y: &[f64; 2],
    order: usize,
    c: &mut [[f64; 2]],
) {
    use crate::integrate::taylor::{MAX_ORDER, forcing_coefficients};
    let n = order.min(MAX_ORDER).min(c.len() - 1);
    let mut rows = Rows::<1>::default();
    forcing_coefficients(p.delta, p.omega, t, n, rows.f.as_flattened_mut());
    rows.x[0] = [y[0]];
    rows.v[0] = [y[1]];
    taylor_rows::<1, FMA>(&LaneParams::new(std::slice::from_ref(p)), n, &mut rows);
    for (k, ck) in c.iter_mut().enumerate().take(n + 1) {
        *ck = [rows.x[k][0], rows.v[k][0]];
    }
}

/// The parameters of `L` lanes, in the form the recurrence uses.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LaneParams<const L: usize> {
    neg_alpha: [f64; L],
    neg_gamma: [f64; L],
    /// μ + γε: the constant term of the acceleration.
    constant: [f64; L],
}

impl<const L: usize> LaneParams<L> {
    /// Lane l takes `points[l]`, or `points[0]` past the end (padding).
    pub(crate) fn new(points: &[Params]) -> Self {
        let get = |f: fn(&Params) -> f64| -> [f64; L] {
            std::array::from_fn(|l| f(&points[if l < points.len() { l } else { 0 }]))
        };
        LaneParams {
            neg_alpha: get(|p| -p.alpha),
            neg_gamma: get(|p| -p.gamma),
            constant: get(|p| p.mu + p.gamma * p.eps),
        }
    }

    /// The step's constants of every lane ([`Linear`]) at its start x₀.
    #[inline(always)]
    #[allow(clippy::needless_range_loop)] // lanes of parallel arrays, indexed together
    fn linear<const FMA: bool>(&self, x0: &[f64; L]) -> Linear<L> {
        let fma = mul_add::<FMA>;
        let mut lin = Linear {
            neg_slope: [0.0; L],
            square: [0.0; L],
            two_neg_alpha_x0: [0.0; L],
        };
        for l in 0..L {
            let nax0 = self.neg_alpha[l] * x0[l];
            lin.neg_slope[l] = fma(fma(3.0, nax0, 2.0), x0[l], self.neg_gamma[l]);
            lin.square[l] = nax0 + 1.0;
            lin.two_neg_alpha_x0[l] = 2.0 * nax0;
        }
        lin
    }
}

/// What a step's recurrence takes from its start x₀ on every lane, for the parts of order k
/// that are linear in x_k or in S_k (x²'s older part, [`next_order`]).
pub(crate) struct Linear<const L: usize> {
    /// −g'(x₀) = −3αx₀² + 2x₀ − γ.
    neg_slope: [f64; L],
    /// 1 − αx₀: S_k's factor in the acceleration (x²'s 1, x³'s −αx₀).
    square: [f64; L],
    /// −2αx₀: x_k's factor in −α(x²)_k.
    two_neg_alpha_x0: [f64; L],
}

/// Taylor coefficients of `L` lanes, structure of arrays: row k holds every lane's k-th
/// coefficient of x, x', the forcing δ sin ωt and −αx². Aligned to a cache line, so that no
/// row of 8 or 16 lanes straddles two (unaligned, a batch step's speed depended on where the
/// allocator put the rows).
#[derive(Clone, Debug)]
#[repr(C, align(64))]
pub(crate) struct Rows<const L: usize> {
    pub(crate) x: [[f64; L]; MAX_ROWS],
    pub(crate) v: [[f64; L]; MAX_ROWS],
    /// The forcing δ sin ωt's coefficients: filled by the caller before [`taylor_rows`].
    pub(crate) f: [[f64; L]; MAX_ROWS],
    /// −αx²'s coefficients (the cube's Cauchy sum takes them with α in, so that neither the
    /// sum nor the acceleration multiplies by α again).
    pub(crate) w: [[f64; L]; MAX_ROWS],
}

const MAX_ROWS: usize = crate::integrate::taylor::MAX_ORDER + 1;

impl<const L: usize> Default for Rows<L> {
    fn default() -> Self {
        Rows {
            x: [[0.0; L]; MAX_ROWS],
            v: [[0.0; L]; MAX_ROWS],
            f: [[0.0; L]; MAX_ROWS],
            w: [[0.0; L]; MAX_ROWS],
        }
    }
}

/// The model's Taylor recurrence on `L` lanes at once (one lane for [`System::taylor`], 16 for
/// [`crate::batch`]): from rows 0 of x, x' and rows 0..=order of the forcing δ sin ωt, rows
/// 1..=order of x and x':
///
/// x_{k+1} = v_k/(k+1), v_{k+1} = (μ[k=0] + γε[k=0] + δ s_k − v_k − α(x³)_k + (x²)_k − γ x_k)/(k+1),
///
/// (x²)_k and (x³)_k = Σ_j (x²)_j x_{k−j} by Cauchy sums (the rows keep −αx², so that α is
/// not multiplied in again at every order). The recurrence is a chain through the
/// orders, so it is kept short: the part of row k that holds this order's x_k is linear in it,
/// −g'(x₀)·x_k (`next_order`), so from x_k it is one fused step to v_{k+1}; the older products of
/// each Cauchy sum are summed from the middle out while earlier orders are computed, the newest
/// last, and the division by k + 1 is folded into the coefficients.
///
/// The orders the tolerances 1e-6 … 1e-13 pick (8 … 16) and the higher ones a caller may ask for
/// (17 … 20: the periodic machinery's Lyapunov exponents run at 20) get their own copy with
/// every order's sums written out (the order a constant), so the compiler unrolls them and drops
/// the bounds checks. One lane runs the unrolled copy too (with the linear split below it is
/// the faster one; the history is in CHANGELOG.md).
#[inline(always)]
pub(crate) fn taylor_rows<const L: usize, const FMA: bool>(
    lp: &LaneParams<L>,
    order: usize,
    r: &mut Rows<L>,
) {
    let lin = lp.linear::<FMA>(&r.x[0]);
    macro_rules! unrolled {
        ($($k:literal)*) => {
            match order {
                $($k => return unrolled_to::<L, FMA, $k>(lp, &lin, r),)*
                _ => {}
            }
        };
    }
    unrolled!(8 9 10 11 12 13 14 15 16 17 18 19 20);
    for k in 0..order {
        next_order::<L, FMA>(lp, &lin, k, r);
    }
}

/// Taylor coefficients of a tangent vector (δx, δx') of `L` lanes, structure of arrays, aligned
/// as [`Rows`] is.
#[derive(Clone, Debug)]
#[repr(C, align(64))]
pub(crate) struct TangentRows<const L: usize> {
    pub(crate) x: [[f64; L]; MAX_ROWS],
    pub(crate) v: [[f64; L]; MAX_ROWS],
    /// The Jacobian's ∂x''/∂x = −3αx² + 2x − γ.
    j: [[f64; L]; MAX_ROWS],
}

impl<const L: usize> Default for TangentRows<L> {
    fn default() -> Self {
        TangentRows {
            x: [[0.0; L]; MAX_ROWS],
            v: [[0.0; L]; MAX_ROWS],
            j: [[0.0; L]; MAX_ROWS],
        }
    }
}

/// The linearised model's recurrence on `L` lanes: from the state's rows (after
/// [`taylor_rows`]: x and −αx² up to `order − 1`) and row 0 of δx, δx', rows 1..=order of the
/// tangent:
///
/// δx_{k+1} = δv_k/(k+1), δv_{k+1} = ((J ⋆ δx)_k − δv_k)/(k+1), J = −3αx² + 2x − γ,
///
/// J's coefficients from −αx²'s and x's, (J ⋆ δx)_k by a Cauchy sum.
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lanes of parallel arrays, indexed together
pub(crate) fn tangent_rows<const L: usize, const FMA: bool>(
    lp: &LaneParams<L>,
    order: usize,
    r: &Rows<L>,
    t: &mut TangentRows<L>,
) {
    use crate::integrate::taylor::INV;
    let fma = mul_add::<FMA>;
    for k in 0..order {
        for l in 0..L {
            let linear = if k == 0 { lp.neg_gamma[l] } else { 0.0 };
            t.j[k][l] = fma(3.0, r.w[k][l], fma(2.0, r.x[k][l], linear));
        }
    }
    for k in 0..order {
        let mut sum = [0.0; L];
        for i in 0..=k {
            for l in 0..L {
                sum[l] = fma(t.j[k - i][l], t.x[i][l], sum[l]);
            }
        }
        let inv = INV[k];
        for l in 0..L {
            t.x[k + 1][l] = t.v[k][l] * inv;
            t.v[k + 1][l] = (sum[l] - t.v[k][l]) * inv;
        }
    }
}

/// Rows 1..=P, each order's step inlined with its k a constant.
#[inline(always)]
fn unrolled_to<const L: usize, const FMA: bool, const P: usize>(
    lp: &LaneParams<L>,
    lin: &Linear<L>,
    r: &mut Rows<L>,
) {
    macro_rules! orders {
        ($($k:literal)*) => {
            $(if $k < P {
                next_order::<L, FMA>(lp, lin, $k, r);
            })*
        };
    }
    orders!(0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19);
}

/// Row k + 1 of x and x' (and row k of −αx²) from rows 0..=k; `lin` holds every lane's
/// −g'(x₀) = −3αx₀² + 2x₀ − γ and the other factors from the step's start x₀.
///
/// For k ≥ 1 the terms of (x²)_k and (x³)_k that hold this order's x_k are linear in it:
/// (x²)_k = 2x₀x_k + S_k and (x³)_k = 3x₀²x_k + x₀S_k + C_k, with S_k = Σ_{j=1..k−1} x_j x_{k−j}
/// and C_k = Σ_{j=1..k−1} (x²)_j x_{k−j} made of older rows only. So the acceleration's
/// coefficient is −g'(x₀)·x_k plus a part N_k = δ s_k + S_k − α(x₀S_k + C_k) that the older rows
/// give, computed while the previous orders are: from x_k it is one fused step to v_{k+1}
/// (the Taylor recurrence is the variational equation's at order ≥ 1, with g'(x₀) as its
/// stiffness), where the products (x²)_k and (x³)_k would make it three.
///
/// Sixteen lanes are bound by the number of operations, not by the chain, so each order takes
/// as few as it can beside the sums: −αx² kept as the rows (N_k = (1 − αx₀)S_k + (δ s_k − αC_k),
/// the forcing δ s_k starting the sum of −αC_k), and v_{k+1} = (N_k − g'(x₀)x_k)/(k + 1) − x_{k+1}
/// from x_{k+1} = v_k/(k + 1), which it needs anyway (with the one-lane chain below split in
/// two).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lanes of parallel arrays, indexed together
fn next_order<const L: usize, const FMA: bool>(
    lp: &LaneParams<L>,
    lin: &Linear<L>,
    k: usize,
    r: &mut Rows<L>,
) {
    use crate::integrate::taylor::INV;
    let fma = mul_add::<FMA>;
    let inv = INV[k];
    if k == 0 {
        // row 0 of the acceleration, (μ + γε) − αx₀³ + x₀² − γx₀ − v₀ + δ s₀, the forcing
        // last: after a step it is the latest to arrive (its sine waits for the step's end, the
        // state's polynomial is shorter)
        for l in 0..L {
            let x0 = r.x[0][l];
            let sq = x0 * x0;
            let w0 = lp.neg_alpha[l] * sq;
            r.w[0][l] = w0;
            let slow = fma(lp.neg_gamma[l], x0, lp.constant[l]);
            let state = fma(w0, x0, slow + sq) - r.v[0][l];
            r.x[1][l] = r.v[0][l];
            r.v[1][l] = state + r.f[0][l];
        }
        return;
    }
    // S_k = 2·Σ_{1≤j<k/2} x_j x_{k−j} + [k even] x_{k/2}², the newest rows (small j's partners,
    // x_{k−1}) last
    let half = k.div_ceil(2);
    let mut older = [0.0; L];
    for j in (1..half).rev() {
        for l in 0..L {
            older[l] = fma(r.x[j][l], r.x[k - j][l], older[l]);
        }
    }
    let mut rest = [0.0; L];
    for l in 0..L {
        rest[l] = if k.is_multiple_of(2) {
            let m = r.x[k / 2][l];
            fma(m, m, 2.0 * older[l])
        } else {
            2.0 * older[l]
        };
    }
    // δ s_k − αC_k = f_k + Σ_{j=1..k−1} w_j x_{k−j} in one chain from the forcing (known from
    // the step's start) and the middle out, j = m, m − 1, m + 1, m − 2, …: each term in the
    // order its newer row arrives, w_{k−1}x₁ last. One lane, bound by the chain's latency,
    // takes the terms into two sums by turns (two shorter chains); sixteen lanes, bound by
    // throughput, save the sums' addition.
    let mid = k / 2;
    let mut sums = [r.f[k], [0.0; L]];
    let mut turn = 0;
    for d in 0..k {
        // (d = 0: j = m once)
        for (i, j) in [mid.wrapping_sub(d), mid + d].into_iter().enumerate() {
            if (1..k).contains(&j) && (d > 0 || i == 0) {
                let sum = &mut sums[if L == 1 { turn % 2 } else { 0 }];
                for l in 0..L {
                    sum[l] = fma(r.w[j][l], r.x[k - j][l], sum[l]);
                }
                turn += 1;
            }
        }
    }
    let mut forced = sums[0];
    if L == 1 && k > 2 {
        for l in 0..L {
            forced[l] += sums[1][l];
        }
    }
    for l in 0..L {
        let xk = r.x[k][l];
        // row k of −αx², for the later orders' sums
        r.w[k][l] = fma(lin.two_neg_alpha_x0[l], xk, lp.neg_alpha[l] * rest[l]);
        // N_k = δ s_k + S_k − α(x₀S_k + C_k) = (1 − αx₀)S_k + (δ s_k − αC_k)
        let older_part = fma(lin.square[l], rest[l], forced[l]);
        // v_{k+1} = (N_k − g'(x₀) x_k − v_k)/(k + 1) = (N_k − g'(x₀) x_k)/(k + 1) − x_{k+1}
        let acc = fma(lin.neg_slope[l], xk, older_part);
        let next = r.v[k][l] * inv;
        r.x[k + 1][l] = next;
        r.v[k + 1][l] = fma(acc, inv, -next);
    }
}
