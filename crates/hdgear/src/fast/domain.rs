//! Where the fast-slow picture is weakest: the slowest relaxation of the fast subsystem on the
//! path the state follows while a = sin ωτ sweeps [−1, 1] (`burst::fast_slow_domain` needs ω
//! below it).
//!
//! The relaxation rate is smallest where g' is smallest: at the inflection x = 1/(3α) of a
//! monotone curve near the cusp (g' = γ − 1/(3α)), or at a branch's end close to a fold. So the
//! rate is taken as the least over the stable branch the response settles on
//! ([`super::settled_branch`]), which spans the whole range when the state need not jump.
//!
//! When both folds lie in the range (the state must leave each branch at its fold) every
//! branch ends at a fold, where the rate is 0 by definition: that passage is the jump itself, the
//! relaxation mechanism, whose fast-slow character rests on the normally hyperbolic part before
//! it. The rate is then taken where the state settles between jumps, at the turning points
//! a = ±1 ([`turning_point_relaxation`]). The same holds without a moving equilibrium (δ = 0):
//! the state rests at one point.

use super::StaticCurve;
use super::equilibria::equilibria;
use super::predict::settled_branch;
use super::static_curve::{Along, SlowestRelaxation, relaxation_rate_with};
use crate::params::Params;

/// The slowest relaxation met on the path the state follows (see the module docs).
///
/// ```
/// use hdgear::{Params, fast::{Along, slowest_relaxation}};
/// // just above the cusp (γ − 1/(3α) = 0.002): the curve is monotone and the slowest point is
/// // its inflection x = 1/(3α), a node with rate ≈ γ − 1/(3α)
/// let p = Params { alpha: 16.0, gamma: 1.0 / 48.0 + 0.002, ..Default::default() };
/// let s = slowest_relaxation(&p);
/// assert_eq!(s.along, Along::SettledBranch);
/// assert!((s.x - 1.0 / 48.0).abs() < 1e-12);
/// assert!((s.rate - 0.002).abs() < 1e-5);
/// ```
pub fn slowest_relaxation(p: &Params) -> SlowestRelaxation {
    let branch = (p.delta > 0.0).then(|| settled_branch(p));
    match branch {
        Some(b) if !b.must_jump && !b.intervals.is_empty() => {
            let (gp, x) = super::predict::least_gprime(p, &b.intervals);
            SlowestRelaxation {
                rate: relaxation_rate_with(gp, p.damping()),
                a: p.a_at(x),
                x,
                along: Along::SettledBranch,
            }
        }
        _ => turning_point_relaxation(p),
    }
}

/// The slowest relaxation at the stable equilibria at a = ±1, where the equilibrium stands still
/// and the state settles.
pub fn turning_point_relaxation(p: &Params) -> SlowestRelaxation {
    let mut best = SlowestRelaxation {
        rate: f64::INFINITY,
        a: f64::NAN,
        x: f64::NAN,
        along: Along::TurningPoints,
    };
    for a in [-1.0, 1.0] {
        for r in equilibria(p, a).roots {
            let rate = relaxation_rate_with(p.g_prime(r.x), p.damping());
            if r.kind.is_stable() && rate < best.rate {
                best = SlowestRelaxation {
                    rate,
                    a,
                    x: r.x,
                    along: Along::TurningPoints,
                };
            }
        }
    }
    best
}
