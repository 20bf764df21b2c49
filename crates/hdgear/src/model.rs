//! Right-hand sides of the models.
//!
//! The dimensionless model in first-order form, with state (x, v = x'):
//!
//! x' = v,  v' = μ + δ sin(ω τ) − v − g(x),  g(x) = α x³ − x² + γ (x − ε).

use crate::integrate::System;
use crate::integrate::taylor::mul_add;
use crate::params::Params;

/// The dimensionless harmonic drive model (SPEC §2) as a [`System`] with state [x, x'].
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
// the right-hand side is dominated by the sine, and libm's inlines to about 60 % of the glibc
// call's time here (measured: 0.66 ms vs 1.13 ms per 127k calls).
impl System<2> for Dimensionless {
    #[inline(always)]
    fn rhs(&self, t: f64, y: &[f64; 2]) -> [f64; 2] {
        let p = &self.p;
        [y[1], p.forcing(libm::sin(p.omega * t)) - y[1] - p.g(y[0])]
    }
    /// ∂f/∂y = [[0, 1], [−g'(x), −1]] (trace −1 everywhere: SPEC §3).
    fn jacobian(&self, _t: f64, y: &[f64; 2]) -> Option<[[f64; 2]; 2]> {
        Some([[0.0, 1.0], [-self.p.g_prime(y[0]), -1.0]])
    }
    /// x_{k+1} = v_k/(k+1), v_{k+1} = (μ[k=0] + δ s_k − v_k − α(x³)_k + (x²)_k − γ x_k
    /// + γε[k=0])/(k+1), with (x²)_k, (x³)_k Cauchy sums and s_k the coefficients of sin ωt.
    #[inline(always)]
    fn taylor(&self, t: f64, y: &[f64; 2], order: usize, c: &mut [[f64; 2]]) -> bool {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("fma") {
            if std::arch::is_x86_feature_detected!("avx512f") {
                // SAFETY: the CPU has AVX-512F and FMA (checked just above).
                unsafe { taylor_avx512(&self.p, t, y, order, c) };
                return true;
            }
            // SAFETY: the CPU has FMA (checked just above).
            unsafe { taylor_fma(&self.p, t, y, order, c) };
            return true;
        }
        taylor_scalar::<false>(&self.p, t, y, order, c);
        true
    }
}

/// The recurrence compiled for AVX-512, for its 32 vector registers: on one lane it works on
/// scalars, and with 16 registers more of its sums are spilled to the stack (one 3-period run
/// 0.303 → 0.277 ms, AMD EPYC Zen 4, same results to the bit).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,fma")]
#[inline]
fn taylor_avx512(p: &Params, t: f64, y: &[f64; 2], order: usize, c: &mut [[f64; 2]]) {
    taylor_scalar::<true>(p, t, y, order, c);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
#[inline]
fn taylor_fma(p: &Params, t: f64, y: &[f64; 2], order: usize, c: &mut [[f64; 2]]) {
    taylor_scalar::<true>(p, t, y, order, c);
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
    use crate::integrate::taylor::{MAX_ORDER, sine_coefficients};
    let n = order.min(MAX_ORDER).min(c.len() - 1);
    let mut rows = Rows::<1>::default();
    sine_coefficients(p.omega, t, n, rows.s.as_flattened_mut());
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
    delta: [f64; L],
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
            delta: get(|p| p.delta),
            constant: get(|p| p.mu + p.gamma * p.eps),
        }
    }

    /// −g'(x₀) = −3αx₀² + 2x₀ − γ on every lane.
    #[inline(always)]
    fn neg_slope<const FMA: bool>(&self, x0: &[f64; L]) -> [f64; L] {
        let fma = mul_add::<FMA>;
        let mut s = [0.0; L];
        for (l, sl) in s.iter_mut().enumerate() {
            *sl = fma(
                fma(3.0 * self.neg_alpha[l], x0[l], 2.0),
                x0[l],
                self.neg_gamma[l],
            );
        }
        s
    }
}

/// Taylor coefficients of `L` lanes, structure of arrays: row k holds every lane's k-th
/// coefficient of x, x', sin ωt and x². Aligned to a cache line, so that no row of 8 or 16
/// lanes straddles two (a batch step measured 0.055 or 0.072 ms per trajectory depending on
/// where the allocator put it).
#[derive(Clone, Debug)]
#[repr(C, align(64))]
pub(crate) struct Rows<const L: usize> {
    pub(crate) x: [[f64; L]; MAX_ROWS],
    pub(crate) v: [[f64; L]; MAX_ROWS],
    /// sin ωt's coefficients: filled by the caller before [`taylor_rows`].
    pub(crate) s: [[f64; L]; MAX_ROWS],
    pub(crate) x2: [[f64; L]; MAX_ROWS],
}

const MAX_ROWS: usize = crate::integrate::taylor::MAX_ORDER + 1;

impl<const L: usize> Default for Rows<L> {
    fn default() -> Self {
        Rows {
            x: [[0.0; L]; MAX_ROWS],
            v: [[0.0; L]; MAX_ROWS],
            s: [[0.0; L]; MAX_ROWS],
            x2: [[0.0; L]; MAX_ROWS],
        }
    }
}

/// The model's Taylor recurrence on `L` lanes at once (one lane for [`System::taylor`], 16 for
/// [`crate::batch`]): from rows 0 of x, x' and rows 0..=order of sin ωt, rows
/// 1..=order of x and x':
///
/// x_{k+1} = v_k/(k+1), v_{k+1} = (μ[k=0] + γε[k=0] + δ s_k − v_k − α(x³)_k + (x²)_k − γ x_k)/(k+1),
///
/// (x²)_k and (x³)_k = Σ_j (x²)_j x_{k−j} by Cauchy sums. The recurrence is a chain through the
/// orders, so it is kept short: the part of row k that holds this order's x_k is linear in it,
/// −g'(x₀)·x_k (`next_order`), so from x_k it is one fused step to v_{k+1}; the older products of
/// each Cauchy sum are summed from the middle out while earlier orders are computed, the newest
/// last, and the division by k + 1 is folded into the coefficients.
///
/// The orders the tolerances 1e-6 … 1e-13 pick (8 … 16) and the higher ones a caller may ask for
/// (17 … 20: the periodic machinery's Lyapunov exponents run at 20) get their own copy with
/// every order's sums written out (the order a constant), so the compiler unrolls them and drops
/// the bounds checks: 16 lanes 0.069 → 0.058 ms per trajectory at order 13, the 640-point
/// Lyapunov map at order 20 0.57 → 0.23 s. One lane runs the unrolled copy too: with the linear
/// split it measured 0.313 against the loop's 0.339 ms per 3-period run (AMD EPYC, Zen 4;
/// without the split, on an Intel Xeon, the loop had been the faster, 0.48 against 0.53 ms).
#[inline(always)]
pub(crate) fn taylor_rows<const L: usize, const FMA: bool>(
    lp: &LaneParams<L>,
    order: usize,
    r: &mut Rows<L>,
) {
    let neg_slope = lp.neg_slope::<FMA>(&r.x[0]);
    macro_rules! unrolled {
        ($($k:literal)*) => {
            match order {
                $($k => return unrolled_to::<L, FMA, $k>(lp, &neg_slope, r),)*
                _ => {}
            }
        };
    }
    unrolled!(8 9 10 11 12 13 14 15 16 17 18 19 20);
    for k in 0..order {
        next_order::<L, FMA>(lp, &neg_slope, k, r);
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
/// [`taylor_rows`]: x and x² up to `order − 1`) and row 0 of δx, δx', rows 1..=order of the
/// tangent:
///
/// δx_{k+1} = δv_k/(k+1), δv_{k+1} = ((J ⋆ δx)_k − δv_k)/(k+1), J = −3αx² + 2x − γ,
///
/// J's coefficients from x²'s and x's, (J ⋆ δx)_k by a Cauchy sum.
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
            t.j[k][l] = fma(
                3.0 * lp.neg_alpha[l],
                r.x2[k][l],
                fma(2.0, r.x[k][l], linear),
            );
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
    neg_slope: &[f64; L],
    r: &mut Rows<L>,
) {
    macro_rules! orders {
        ($($k:literal)*) => {
            $(if $k < P {
                next_order::<L, FMA>(lp, neg_slope, $k, r);
            })*
        };
    }
    orders!(0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15 16 17 18 19);
}

/// Row k + 1 of x and x' (and row k of x²) from rows 0..=k; `neg_slope` is every lane's
/// −g'(x₀) = −3αx₀² + 2x₀ − γ at the step's start.
///
/// For k ≥ 1 the terms of (x²)_k and (x³)_k that hold this order's x_k are linear in it:
/// (x²)_k = 2x₀x_k + S_k and (x³)_k = 3x₀²x_k + x₀S_k + C_k, with S_k = Σ_{j=1..k−1} x_j x_{k−j}
/// and C_k = Σ_{j=1..k−1} (x²)_j x_{k−j} made of older rows only. So the acceleration's
/// coefficient is −g'(x₀)·x_k plus a part N_k = δ s_k + S_k − α(x₀S_k + C_k) that the older rows
/// give, computed while the previous orders are: from x_k it is one fused step to v_{k+1}
/// (the Taylor recurrence is the variational equation's at order ≥ 1, with g'(x₀) as its
/// stiffness), where the products (x²)_k and (x³)_k had made it three (with one lane on the
/// unrolled copy: 0.339 → 0.313 ms per 3-period run, AMD EPYC Zen 4).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // lanes of parallel arrays, indexed together
fn next_order<const L: usize, const FMA: bool>(
    lp: &LaneParams<L>,
    neg_slope: &[f64; L],
    k: usize,
    r: &mut Rows<L>,
) {
    use crate::integrate::taylor::INV;
    let fma = mul_add::<FMA>;
    let inv = INV[k];
    if k == 0 {
        // row 0 of the acceleration, (μ + γε) − αx₀³ + x₀² − γx₀ − v₀ + δ s₀, the sine last:
        // after a step it is the latest to arrive (its sine waits for the step's end, the
        // state's polynomial is shorter), so from it to v₁ is one fused step
        for l in 0..L {
            let x0 = r.x[0][l];
            let sq = x0 * x0;
            r.x2[0][l] = sq;
            let slow = fma(lp.neg_gamma[l], x0, lp.constant[l]);
            let state = fma(lp.neg_alpha[l] * x0, sq, slow + sq) - r.v[0][l];
            r.x[1][l] = r.v[0][l];
            r.v[1][l] = fma(lp.delta[l], r.s[0][l], state);
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
        let m = if k.is_multiple_of(2) {
            r.x[k / 2][l]
        } else {
            0.0
        };
        rest[l] = fma(m, m, 2.0 * older[l]);
    }
    // C_k in two chains from the middle out: (x²)_j x_{k−j} for j = m..k−1 ((x²) newest last)
    // and for j = m−1 down to 1 (x newest last)
    let mid = k / 2;
    let (mut hi, mut lo) = ([0.0; L], [0.0; L]);
    for j in mid.max(1)..k {
        for l in 0..L {
            hi[l] = fma(r.x2[j][l], r.x[k - j][l], hi[l]);
        }
    }
    for j in (1..mid).rev() {
        for l in 0..L {
            lo[l] = fma(r.x2[j][l], r.x[k - j][l], lo[l]);
        }
    }
    for l in 0..L {
        let x0 = r.x[0][l];
        let xk = r.x[k][l];
        // row k of x², for the later orders' sums
        r.x2[k][l] = fma(2.0 * x0, xk, rest[l]);
        let cube = fma(x0, rest[l], hi[l] + lo[l]);
        let older_part = fma(lp.neg_alpha[l], cube, fma(lp.delta[l], r.s[k][l], rest[l]));
        // v_{k+1} = (N_k − g'(x₀) x_k − v_k)/(k + 1)
        let acc = fma(neg_slope[l], xk, older_part);
        r.x[k + 1][l] = r.v[k][l] * inv;
        r.v[k + 1][l] = fma(r.v[k][l], -inv, acc * inv);
    }
}
