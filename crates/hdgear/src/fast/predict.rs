//! A prediction of bursting from the equilibrium curve alone (no simulation).
//!
//! The fast mode is forced by the motion of the equilibrium it follows: linearising about x*(a(τ)),
//! the deviation e = x − x* obeys e'' + e' + g'(x*) e = −(x*'' + x*'). Where that forcing changes
//! slowly the deviation is the adiabatic lag and nothing rings; where it changes on the time
//! scale of the fast mode itself, the fast mode is excited. The rate at which it changes is the
//! log-derivative of the equilibrium's speed,
//!
//! κ(x) = |d/dτ ln|dx*/dτ|| = |g''(x)|·|dx*/dτ| / g'(x) = |g''(x)|·ω·δ·√(1 − a²) / g'(x)²,
//!
//! taken where a = sin ωτ passes fastest through a (|da/dτ| = ω√(1 − a²)). The fast mode can only
//! ring where it is oscillatory, a focus (g' > 1/4): on a node part the state creeps after the
//! equilibrium without ringing and only the following focus part can ring. So the prediction is
//!
//! * with both folds in the traversed range: bursting (the state must leave each branch at its
//!   fold, a jump every half period, at every ω);
//! * otherwise bursting iff max κ over the focus part of the branch the response settles on
//!   ([`settled_branch`]) exceeds [`FORCING_RATE_THRESHOLD`]. With one fold in range the state
//!   jumps at most once, in the transient, onto the stable branch that spans all of a ∈ [−1, 1],
//!   and stays there.
//!
//! κ is proportional to ω, so the predicted ω boundary is a closed form, ω_b = ω·κ_c/max κ,
//! and bursts vanish as ω → 0 on a normally hyperbolic branch, as Fenichel's theorem requires.

use super::StaticCurve;
use super::curve::x_intervals;
use super::equilibria::fold_abscissae;
use super::passage::CuspPassage;
use crate::params::Params;
use crate::simd::{Simd, dispatched};
use serde::Serialize;

/// The threshold κ_c on the forcing rate: bursting is predicted where the equilibrium's speed
/// changes by a factor e in less than 1/κ_c = 5 time units (two and a half decay times of the
/// fast mode, whose oscillations decay as e^(−τ/2)).
///
/// Where the number comes from, and how it was checked: along the study's line (α = 16,
/// ε = 0.71, μ = 0.07, δ = 15) the simulated boundary (first ringing) was located by bisection at
/// eleven points (γ from 0.05 to 5.3, ω from 6.7e-5 to 0.05); on it max κ is 0.16–0.27 for
/// γ ≥ 0.1 (0.10 at γ = 0.05, where the prediction is a factor 1.9 early). 0.2 is the middle.
/// It was then checked, not tuned, on the 20 independent reference cases of
/// `tests/data/burst_cases.json` (other α, δ, μ, ε, ω, physical sets with α·ε = 1, fold
/// loops): the prediction agrees with the reference on all 20 (`tests/burst.rs`). Unlike the
/// detection floors this constant *is* the boundary's location, so it cannot be free over a
/// decade; the nearest reference cases sit at κ = 0.17 (no bursts) and 0.31 (ringing).
pub const FORCING_RATE_THRESHOLD: f64 = 0.2;

/// The prediction and its evidence.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Prediction {
    /// Bursting predicted.
    pub bursting: bool,
    /// Both folds lie in the traversed range a ∈ [−1, 1]: the state must leave each branch at
    /// its fold (a jump every half period is predicted).
    pub fold_in_range: bool,
    /// How many folds lie in a ∈ [−1, 1] (0, 1 or 2; with one the state jumps at most once, in
    /// the transient, onto the branch that spans the range).
    pub folds_in_range: usize,
    /// max κ over the focus part of the traversed stable curve (0 when it has none; infinite with
    /// a fold in range).
    pub forcing_rate: f64,
    /// The threshold κ_c.
    pub threshold: f64,
    /// a and x where κ is largest (NaN with a fold in range or without a focus part).
    pub at_a: f64,
    /// See `at_a`.
    pub at_x: f64,
    /// The predicted ω boundary: bursting predicted for ω above it (0 with a fold in range: at
    /// every ω).
    pub omega_boundary: f64,
    /// The least g' on the settled branch when it is below 1/4 there (the branch passes a node
    /// part, near the cusp), else `None`. κ sees the focus part only, so the excitation the state
    /// carries out of the node part is missed and the ω boundary comes out too high: measured on
    /// 24 sets near the cusp (γ − 1/(3α) from 0.002 to 0.04, α 1–30, δ 0.3–30), κ at the
    /// simulated boundary was 0.07–0.12 instead of [`FORCING_RATE_THRESHOLD`], the predicted ω
    /// boundary 1.7–2.7 times the simulated one. Where the settled branch passes the inflection
    /// inside the range, [`Prediction::cusp`] judges that passage instead.
    pub node_min_gprime: Option<f64>,
    /// The passage through a node part about the inflection (g'_min < 1/4 there, with the
    /// inflection's load inside the range), judged on the normal form
    /// ([`super::passage`]); `None` when the settled branch has no such passage.
    pub cusp: Option<CuspPassage>,
}

/// κ(x) at abscissa x (see the module docs).
pub fn forcing_rate(p: &Params, x: f64) -> f64 {
    let gp = p.g_prime(x);
    let a = p.a_at(x);
    let gpp = 6.0 * p.alpha * x - 2.0;
    gpp.abs() * p.omega * p.delta * (1.0 - a * a).max(0.0).sqrt() / (gp * gp)
}

/// The stable branch a response settles on while a sweeps [−1, 1], as x-intervals (increasing),
/// the number of folds in that range, and whether the state must leave its branch there.
#[derive(Clone, Debug, PartialEq)]
pub struct SettledBranch {
    /// The x-intervals of the branch (all of the traversed stable curve when it must jump).
    pub intervals: Vec<(f64, f64)>,
    /// Folds with a ∈ [−1, 1].
    pub folds_in_range: usize,
    /// Both folds are in range: no stable branch spans [−1, 1], the state jumps every half period.
    pub must_jump: bool,
}

/// Which stable branch the response settles on over a ∈ [−1, 1] (δ > 0). Without folds, the one
/// curve. With folds at x− < x+ (the lower branch ends at a(x−), the upper one starts at a(x+)):
/// a branch that spans [−1, 1] keeps the state once it is on it; the response starts on the lower
/// branch (the default start), so it stays there when the lower branch spans the range, and
/// otherwise, when the upper one does, jumps once onto it and stays. When neither spans the
/// range (both folds in it) the state must jump at each fold.
pub fn settled_branch(p: &Params) -> SettledBranch {
    let all = x_intervals(p, crate::fast::A_RANGE);
    let Some((xm, xp)) = fold_abscissae(p) else {
        return SettledBranch {
            intervals: all,
            folds_in_range: 0,
            must_jump: false,
        };
    };
    let (am, ap) = (p.a_at(xm), p.a_at(xp));
    let folds_in_range = usize::from(am.abs() <= 1.0) + usize::from(ap.abs() <= 1.0);
    let keep = |f: &dyn Fn(f64) -> bool| -> Vec<(f64, f64)> {
        all.iter()
            .copied()
            .filter(|&(l, r)| f(0.5 * (l + r)))
            .collect()
    };
    if am > 1.0 {
        SettledBranch {
            intervals: keep(&|x| x < xm),
            folds_in_range,
            must_jump: false,
        }
    } else if ap < -1.0 {
        SettledBranch {
            intervals: keep(&|x| x > xp),
            folds_in_range,
            must_jump: false,
        }
    } else {
        SettledBranch {
            intervals: keep(&|x| x < xm || x > xp),
            folds_in_range,
            must_jump: true,
        }
    }
}

/// The x-pieces of the settled branch ([`settled_branch`]) on which the fast subsystem is a stable
/// focus (g' > 1/4), in increasing x.
pub fn focus_pieces(p: &Params) -> Vec<(f64, f64)> {
    focus_pieces_of(p, &settled_branch(p))
}

/// [`focus_pieces`] of a branch already found.
fn focus_pieces_of(p: &Params, branch: &SettledBranch) -> Vec<(f64, f64)> {
    // g' = 1/4 at the roots of 3αx² − 2x + γ − 1/4
    let disc = 1.0 - 3.0 * p.alpha * (p.gamma - 0.25);
    let cuts: Vec<f64> = if disc > 0.0 {
        let s = disc.sqrt();
        vec![(1.0 - s) / (3.0 * p.alpha), (1.0 + s) / (3.0 * p.alpha)]
    } else {
        Vec::new()
    };
    let mut out = Vec::new();
    for &(l, r) in &branch.intervals {
        let mut pts = vec![l, r];
        pts.extend(cuts.iter().copied().filter(|&c| c > l && c < r));
        pts.sort_by(f64::total_cmp);
        for w in pts.windows(2) {
            if p.g_prime(0.5 * (w[0] + w[1])) > p.focus_gprime() {
                out.push((w[0], w[1]));
            }
        }
    }
    out
}

/// The least g' over x-intervals: at an end or at the inflection x = 1/(3α), where g'' = 0
/// (0 where it is negative).
pub(crate) fn min_gprime(p: &Params, intervals: &[(f64, f64)]) -> f64 {
    least_gprime(p, intervals).0.max(0.0)
}

/// The least g' over x-intervals and the x where it is met (an end, or the inflection
/// x = 1/(3α) where g'' = 0); (∞, NaN) without intervals.
pub(crate) fn least_gprime(p: &Params, intervals: &[(f64, f64)]) -> (f64, f64) {
    let xc = p.critical_gamma(); // g'' = 0 at x = 1/(3α)
    intervals
        .iter()
        .flat_map(|&(lo, hi)| {
            [lo, hi]
                .into_iter()
                .chain((xc > lo && xc < hi).then_some(xc))
        })
        .map(|x| (p.g_prime(x), x))
        .fold(
            (f64::INFINITY, f64::NAN),
            |m, c| if c.0 < m.0 { c } else { m },
        )
}

/// The largest κ on [l, r], with its x: a dense scan, then golden-section refinement around the
/// best sample (κ is smooth on a focus piece).
pub(crate) fn max_on(f: impl Fn(f64) -> f64, l: f64, r: f64) -> (f64, f64) {
    const N: usize = 512;
    let x = |j: usize| l + (r - l) * j as f64 / N as f64;
    // every sample first (independent evaluations, which the compiler vectorises: on the widest
    // vector unit, the scan was 2–3 % of a (γ, δ) map's time), then the first largest
    let mut values = [0.0; N + 1];
    #[inline(always)]
    fn fill(f: &impl Fn(f64) -> f64, x: &impl Fn(usize) -> f64, values: &mut [f64]) {
        for (j, v) in values.iter_mut().enumerate() {
            *v = f(x(j));
        }
    }
    dispatched! {
        fn fill_on(f: &impl Fn(f64) -> f64, x: &impl Fn(usize) -> f64, values: &mut [f64]) -> () = fill(f, x, values)
    }
    fill_on(Simd::detect(), &f, &x, &mut values);
    // the largest by eight running maxima, each started at the first sample (one chain of
    // comparisons was most of a call), then the first sample that equals it: the first largest,
    // as comparing them one by one would give (a NaN never compares larger)
    let mut tops = [values[0]; 8];
    for chunk in values[1..].chunks(8) {
        for (t, &v) in tops.iter_mut().zip(chunk) {
            *t = if v > *t { v } else { *t };
        }
    }
    let bv = tops
        .iter()
        .fold(values[0], |m, &t| if t > m { t } else { m });
    let bx = values.iter().position(|&v| v == bv).map_or(l, x);
    let h = (r - l) / N as f64;
    let (mut lo, mut hi) = ((bx - h).max(l), (bx + h).min(r));
    // golden section: each round keeps one inner point and its value and evaluates one new one
    // (the chain of evaluations, a square root and a division each, was most of a call)
    let phi = 0.5 * (5f64.sqrt() - 1.0);
    let (mut m1, mut m2) = (hi - phi * (hi - lo), lo + phi * (hi - lo));
    let (mut f1, mut f2) = (f(m1), f(m2));
    for _ in 0..60 {
        if f1 < f2 {
            (lo, m1, f1) = (m1, m2, f2);
            m2 = lo + phi * (hi - lo);
            f2 = f(m2);
        } else {
            (hi, m2, f2) = (m2, m1, f1);
            m1 = hi - phi * (hi - lo);
            f1 = f(m1);
        }
    }
    let xm = 0.5 * (lo + hi);
    if f(xm) > bv { (xm, f(xm)) } else { (bx, bv) }
}

/// The largest speed of the equilibrium, max |dx*/dτ| = max ω·δ·√(1 − a²)/g'(x) over the settled
/// branch (a ∈ [−1, 1]): the quasi-static bound on |x'| (infinite when the state must jump).
pub fn max_equilibrium_speed(p: &Params) -> f64 {
    let branch = settled_branch(p);
    max_speed_on(p, &branch.intervals, branch.must_jump)
}

/// The largest first-order adiabatic lag |e₁| = |dx*/dτ|/g'(x) over the settled branch (a ∈
/// [−1, 1], unit damping): what the lag x − x* tends to as ω → 0 on a normally hyperbolic branch
/// (infinite when the state must jump). Taken from the curve, so it does not depend on where a
/// response happens to be sampled.
pub fn max_first_order_lag(p: &Params) -> f64 {
    let branch = settled_branch(p);
    max_first_order_lag_on(p, &branch.intervals, branch.must_jump)
}

/// [`max_equilibrium_speed`] of any curve, over the x-intervals of the branch it settles on
/// (infinite when the state must jump).
pub(crate) fn max_speed_on(
    c: &impl super::StaticCurve,
    intervals: &[(f64, f64)],
    must_jump: bool,
) -> f64 {
    max_on_branch(c, intervals, must_jump, |speed, _| speed)
}

/// The largest first-order adiabatic lag |e₁| = c·|dx*/dτ|/k(x) over the x-intervals of the
/// branch a curve settles on, k the fast stiffness (infinite when the state must jump):
/// x = x* + e in x'' + c·x' + G(x) = 0 gives c·dx*/dτ + k(x*)·e₁ = 0 at first order in ω.
pub(crate) fn max_first_order_lag_on(
    c: &impl super::StaticCurve,
    intervals: &[(f64, f64)],
    must_jump: bool,
) -> f64 {
    let damping = c.damping();
    max_on_branch(c, intervals, must_jump, |speed, x| {
        damping * speed / c.stiffness(x)
    })
}

/// The largest f(|dx*/dτ|, x) over the settled branch's x-intervals, |dx*/dτ| =
/// ω·δ·√(1 − a²)/g'(x) (infinite when the state must jump).
fn max_on_branch(
    c: &impl super::StaticCurve,
    intervals: &[(f64, f64)],
    must_jump: bool,
    f: impl Fn(f64, f64) -> f64,
) -> f64 {
    if must_jump {
        return f64::INFINITY;
    }
    let value = |x: f64| {
        let a = c.a_at(x);
        f(
            c.omega() * c.delta() * (1.0 - a * a).max(0.0).sqrt() / c.g_prime(x),
            x,
        )
    };
    intervals
        .iter()
        .fold(0.0, |best: f64, &(l, r)| best.max(max_on(value, l, r).1))
}

/// Predicts bursting from the equilibrium curve (δ > 0).
///
/// ```
/// use hdgear::{Params, fast::predict};
/// assert!(predict(&Params { gamma: 0.1, ..Params::default() }).bursting);
/// assert!(!predict(&Params { gamma: 30.0, ..Params::default() }).bursting);
/// // Fenichel: no fold, so no bursts as ω → 0
/// assert!(!predict(&Params { gamma: 0.1, omega: 1e-5, ..Params::default() }).bursting);
/// ```
pub fn predict(p: &Params) -> Prediction {
    let branch = settled_branch(p);
    let (fold_in_range, folds_in_range) = (branch.must_jump, branch.folds_in_range);
    if fold_in_range {
        return Prediction {
            bursting: true,
            fold_in_range,
            folds_in_range,
            forcing_rate: f64::INFINITY,
            threshold: FORCING_RATE_THRESHOLD,
            at_a: f64::NAN,
            at_x: f64::NAN,
            omega_boundary: 0.0,
            node_min_gprime: None,
            cusp: None,
        };
    }
    let (mut bx, mut bv) = (f64::NAN, 0.0f64);
    for (l, r) in focus_pieces_of(p, &branch) {
        let (x, v) = max_on(|x| forcing_rate(p, x), l, r);
        if v > bv {
            (bx, bv) = (x, v);
        }
    }
    let cusp = cusp_passage(p, &branch);
    let kappa_boundary = if bv > 0.0 {
        p.omega * FORCING_RATE_THRESHOLD / bv
    } else {
        f64::INFINITY
    };
    let cusp_boundary = cusp.map_or(f64::INFINITY, |c| p.omega * c.threshold / c.ramp_rate);
    Prediction {
        bursting: bv > FORCING_RATE_THRESHOLD || cusp.is_some_and(|c| c.rings()),
        fold_in_range,
        folds_in_range,
        forcing_rate: bv,
        threshold: FORCING_RATE_THRESHOLD,
        at_a: if bx.is_nan() { f64::NAN } else { p.a_at(bx) },
        at_x: bx,
        omega_boundary: kappa_boundary.min(cusp_boundary),
        node_min_gprime: Some(min_gprime(p, &branch.intervals)).filter(|&g| g < p.focus_gprime()),
        cusp,
    }
}

/// The passage of the settled branch through a node part about the inflection x_i = 1/(3α):
/// `Some` when x_i lies inside the branch with 0 ≤ g'(x_i) < 1/4 and its load a_i inside the
/// open range (−1, 1), where the sine's rate √(1 − a_i²) is what the normal form linearises.
fn cusp_passage(p: &Params, branch: &SettledBranch) -> Option<CuspPassage> {
    let xi = p.critical_gamma(); // the inflection, 1/(3α)
    let gprime_min = p.g_prime(xi);
    let inside = branch.intervals.iter().any(|&(l, r)| l < xi && xi < r);
    if !inside || !(0.0..p.focus_gprime()).contains(&gprime_min) {
        return None;
    }
    let at_a = p.a_at(xi);
    if at_a.abs() >= 1.0 {
        return None;
    }
    let ramp_rate = (3.0 * p.alpha).sqrt() * p.delta * p.omega * (1.0 - at_a * at_a).sqrt();
    Some(CuspPassage {
        gprime_min,
        at_a,
        ramp_rate,
        threshold: super::ramp_threshold(gprime_min)?,
    })
}

/// The predicted γ boundary with the other parameters of `p`: the γ above which no bursting is
/// predicted, by bisection in log γ between the cusp 1/(3α) (folds below it: always bursting)
/// and 10⁶·(1/(3α) + 1). `None` when bursting is predicted nowhere or everywhere in that range.
pub fn predicted_gamma_boundary(p: &Params) -> Option<f64> {
    let at = |g: f64| predict(&Params { gamma: g, ..*p }).bursting;
    let lo = p.critical_gamma() * (1.0 + 1e-9);
    let hi = 1e6 * (p.critical_gamma() + 1.0);
    crate::roots::bisect_log(lo, hi, at)
}
