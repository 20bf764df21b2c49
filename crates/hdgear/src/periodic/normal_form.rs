//! The normal form of a period doubling: whether the orbit of twice the period it gives birth to
//! is stable (supercritical) or unstable (subcritical). Where the sign changes along a curve of
//! period doublings is a generalised period doubling ([`super::Codim2::GeneralisedPeriodDoubling`]).
//!
//! On the stroboscopic map P (over k forcing periods) at a fixed point y with the multiplier −1,
//! A = DP(y), Aq = −q, Aᵀp = −p, ⟨p, q⟩ = 1, |q| = 1, the map restricted to its centre manifold
//! is η ↦ −η + c·η³ + … after the quadratic term is removed (Kuznetsov, *Elements of Applied
//! Bifurcation Theory*, the flip bifurcation of maps):
//!
//! c = ⟨p, C(q, q, q)⟩/6 + ⟨p, B(q, (I − A)⁻¹ B(q, q))⟩/2,
//!
//! with B and C the second and third derivatives of P. Since P∘P is η ↦ η − 2c·η³, c > 0 makes
//! the orbit attract at the doubling itself and the doubled orbit is born stable on the side
//! where the orbit is unstable (supercritical); c < 0 makes it repel, the doubled orbit unstable
//! on the stable side (subcritical: past it, the response jumps). Near the doubling the doubled
//! orbit's points are y ± η·q with η² ≈ β/c, β = −1 − (the multiplier), which the tests check.
//!
//! B and C are central differences of the monodromy DP along q (one integration of the
//! variational equations at y ± εq each): B(q, w) = (DP(y + εq) − DP(y − εq))·w/(2ε) and
//! C(q, q, q) = (DP(y + εq) − 2·DP(y) + DP(y − εq))·q/ε², both with error O(ε²).

use super::Oscillator;
use super::floquet::{Flow, flow};
use crate::error::{Error, Result};
use crate::integrate::Options;
use serde::Serialize;

/// ε of the differences along q, relative to 1 + |y|: the differences' truncation error is
/// O(ε²) ≈ 1e-6 relative and the integration's rounding, amplified by 1/ε² in C, stays below
/// it at the periodic machinery's tolerances (a decade either way changes c by under 1e-3
/// relative, tested).
pub const FLIP_FD_STEP: f64 = 1e-3;

/// How far from −1 the multiplier may be for [`flip_coefficient`] to answer: the coefficient
/// belongs to the doubling itself, and at a distance d from it the formula's value is off by
/// O(d) relative (a located doubling is within 1e-9; an orbit whose multiplier is +1, such as the
/// doubled orbit at its birth, is refused).
pub const FLIP_NEAR: f64 = 0.1;

/// Which way a period doubling goes: the sign of its normal-form coefficient.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Criticality {
    /// c > 0: the doubled orbit is born stable where the orbit loses stability (a soft
    /// transition).
    Supercritical,
    /// c < 0: the doubled orbit is unstable and lies where the orbit is stable; past the
    /// doubling the response jumps.
    Subcritical,
}

impl Criticality {
    /// From a coefficient c (None at c = 0 or not finite).
    pub fn of(c: f64) -> Option<Criticality> {
        if c > 0.0 {
            Some(Criticality::Supercritical)
        } else if c < 0.0 {
            Some(Criticality::Subcritical)
        } else {
            None
        }
    }

    /// The name written in tables.
    pub fn name(self) -> &'static str {
        match self {
            Criticality::Supercritical => "supercritical",
            Criticality::Subcritical => "subcritical",
        }
    }
}

type Mat = [[f64; 2]; 2];

/// The monodromy itself (the flow keeps it normalised with its scale apart).
fn monodromy(f: &Flow) -> Result<Mat> {
    let s = f.log_scale.exp();
    let m = f.m.map(|r| r.map(|v| v * s));
    if m.iter().flatten().all(|v| v.is_finite()) {
        Ok(m)
    } else {
        Err(Error::InvalidOption {
            name: "monodromy",
            value: f.log_scale,
            reason: "overflows (the orbit is far from a period doubling)",
        })
    }
}

fn mat_vec(m: Mat, v: [f64; 2]) -> [f64; 2] {
    [
        m[0][0] * v[0] + m[0][1] * v[1],
        m[1][0] * v[0] + m[1][1] * v[1],
    ]
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// The real eigenvalue of `a` nearest −1 with its right eigenvector q (|q| = 1) and left
/// eigenvector p (⟨p, q⟩ = 1).
fn flip_pair(a: Mat) -> Result<(f64, [f64; 2], [f64; 2])> {
    let tr = a[0][0] + a[1][1];
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let disc = tr * tr - 4.0 * det;
    let complex = || Error::InvalidOption {
        name: "multipliers",
        value: disc,
        reason: "are complex: no real multiplier near −1",
    };
    if disc.is_nan() || disc < 0.0 {
        return Err(complex());
    }
    let l = [0.5 * (tr - disc.sqrt()), 0.5 * (tr + disc.sqrt())]
        .into_iter()
        .min_by(|x, y| (x + 1.0).abs().total_cmp(&(y + 1.0).abs()))
        .unwrap_or(-1.0);
    // q ⊥ the larger row of A − λI, p ⊥ its larger column
    let rows = [[a[0][0] - l, a[0][1]], [a[1][0], a[1][1] - l]];
    let cols = [[rows[0][0], rows[1][0]], [rows[0][1], rows[1][1]]];
    let larger = |v: [[f64; 2]; 2]| {
        if dot(v[0], v[0]) >= dot(v[1], v[1]) {
            v[0]
        } else {
            v[1]
        }
    };
    let (r, c) = (larger(rows), larger(cols));
    let n = r[0].hypot(r[1]);
    let q = if n > 0.0 {
        [-r[1] / n, r[0] / n]
    } else {
        [1.0, 0.0]
    };
    let p = if dot(c, c) > 0.0 { [-c[1], c[0]] } else { q };
    let pq = dot(p, q);
    if !(pq != 0.0 && pq.is_finite()) {
        return Err(complex());
    }
    Ok((l, q, p.map(|v| v / pq)))
}

/// The monodromy of the orbit of period k·2π/ω through `y0` with its flip vectors q (M q = −q
/// at a doubling, |q| = 1) and p (⟨p, q⟩ = 1); refused when no real multiplier is within
/// [`FLIP_NEAR`] of −1.
fn flip_at<O: Oscillator>(
    o: &O,
    y0: [f64; 2],
    k: u32,
    tol: Options,
) -> Result<(Mat, [f64; 2], [f64; 2])> {
    let span = std::f64::consts::TAU * f64::from(k);
    let a = monodromy(&flow(o, None, 0.0, y0, span, tol)?)?;
    let (l, q, p) = flip_pair(a)?;
    if (l + 1.0).abs().is_nan() || (l + 1.0).abs() > FLIP_NEAR {
        return Err(Error::InvalidOption {
            name: "multiplier",
            value: l,
            reason: "is not near −1: no period doubling here",
        });
    }
    Ok((a, q, p))
}

/// The direction q (|q| = 1 in (x, x')) in which the orbit of period k·2π/ω through `y0` doubles:
/// M q = −q at a period doubling.
pub(crate) fn flip_direction<O: Oscillator>(
    o: &O,
    y0: [f64; 2],
    k: u32,
    tol: Options,
) -> Result<[f64; 2]> {
    flip_at(o, y0, k, tol).map(|(_, q, _)| q)
}

/// The period-doubling normal-form coefficient c (see the module docs) of the orbit of period
/// k·2π/ω of `o` through `y0` at phase 0, with |q| = 1 in (x, x'). c > 0: supercritical (the
/// doubled orbit is born stable); c < 0: subcritical. Meaningful where a multiplier is −1: on a
/// located period doubling or a period-doubling curve; refused when no real multiplier is within
/// [`FLIP_NEAR`] of −1.
///
/// ```
/// use hdgear::params::{Param, Params};
/// use hdgear::periodic::{ContinuationOptions, Scale, Special, continue_orbit, flip_coefficient};
/// // γ = 10, δ = 15: the period-1 response doubles near ω = 8.14 and undoubles near 9.56
/// let p = Params { gamma: 10.0, omega: 7.0, ..Params::default() };
/// let opts = ContinuationOptions { scale: Scale::Log, ..ContinuationOptions::default() };
/// let b = continue_orbit(&p, Param::Omega, 1, None, 10.0, &opts).unwrap();
/// let pd = b.specials().find(|q| q.special == Some(Special::PeriodDoubling)).unwrap();
/// let o = p.with(Param::Omega, pd.param);
/// let c = flip_coefficient(&o, pd.start, 1, opts.periodic.tol).unwrap();
/// assert_eq!(pd.flip_coefficient, Some(c));
/// assert!(c.is_finite() && c != 0.0);
/// ```
pub fn flip_coefficient<O: Oscillator>(o: &O, y0: [f64; 2], k: u32, tol: Options) -> Result<f64> {
    flip_coefficient_step(o, y0, k, tol, FLIP_FD_STEP)
}

/// [`flip_coefficient`] with the differences' relative step `step` in place of
/// [`FLIP_FD_STEP`].
pub(crate) fn flip_coefficient_step<O: Oscillator>(
    o: &O,
    y0: [f64; 2],
    k: u32,
    tol: Options,
    step: f64,
) -> Result<f64> {
    if !(step > 0.0 && step < 0.1) {
        return Err(Error::InvalidOption {
            name: "step",
            value: step,
            reason: "must be in (0, 0.1)",
        });
    }
    let span = std::f64::consts::TAU * f64::from(k);
    let at = |y: [f64; 2]| -> Result<Mat> { monodromy(&flow(o, None, 0.0, y, span, tol)?) };
    let (a, q, p) = flip_at(o, y0, k, tol)?;
    let eps = step * (1.0 + y0[0].hypot(y0[1]));
    let plus = at([y0[0] + eps * q[0], y0[1] + eps * q[1]])?;
    let minus = at([y0[0] - eps * q[0], y0[1] - eps * q[1]])?;
    let b = |w: [f64; 2]| {
        let d: Mat = std::array::from_fn(|i| std::array::from_fn(|j| plus[i][j] - minus[i][j]));
        mat_vec(d, w).map(|v| v / (2.0 * eps))
    };
    let second: Mat =
        std::array::from_fn(|i| std::array::from_fn(|j| plus[i][j] - 2.0 * a[i][j] + minus[i][j]));
    let cqqq = mat_vec(second, q).map(|v| v / (eps * eps));
    // w = (I − A)⁻¹ B(q, q)
    let bqq = b(q);
    let i_a = [[1.0 - a[0][0], -a[0][1]], [-a[1][0], 1.0 - a[1][1]]];
    let det = i_a[0][0] * i_a[1][1] - i_a[0][1] * i_a[1][0];
    let w = [
        (i_a[1][1] * bqq[0] - i_a[0][1] * bqq[1]) / det,
        (i_a[0][0] * bqq[1] - i_a[1][0] * bqq[0]) / det,
    ];
    let c = dot(p, cqqq) / 6.0 + dot(p, b(w)) / 2.0;
    if c.is_finite() {
        Ok(c)
    } else {
        Err(Error::InvalidOption {
            name: "multipliers",
            value: det,
            reason: "make I − A singular: a multiplier is +1 too",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::{Param, Params};
    use crate::periodic::{ContinuationOptions, Special, continue_orbit};

    /// The differences' step a decade either way of [`FLIP_FD_STEP`] changes c by under 1e-3
    /// relative at both doublings of the γ = 10 bubble.
    #[test]
    fn the_step_does_not_change_the_coefficient_over_a_decade() {
        let p = Params {
            gamma: 10.0,
            omega: 7.0,
            ..Params::default()
        };
        let opts = ContinuationOptions::default();
        let b = continue_orbit(&p, Param::Omega, 1, None, 10.0, &opts).unwrap();
        let mut n = 0;
        for pd in b
            .specials()
            .filter(|q| q.special == Some(Special::PeriodDoubling))
        {
            let o = p.with(Param::Omega, pd.param);
            let tol = opts.periodic.tol;
            let c = |step| flip_coefficient_step(&o, pd.start, 1, tol, step).unwrap();
            let c0 = c(FLIP_FD_STEP);
            for step in [FLIP_FD_STEP / 10.0, FLIP_FD_STEP * 10.0] {
                let rel = (c(step) / c0 - 1.0).abs();
                assert!(rel < 1e-3, "ω = {}: step {step}: {rel:e}", pd.param);
            }
            n += 1;
        }
        assert_eq!(n, 2);
    }
}
