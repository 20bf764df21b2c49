//! The fast-slow domain: where the state settles (the turning points) and the slowest
//! relaxation met on the path it follows.

use hdgear::Params;
use hdgear::burst::{BurstOptions, Mode, classify, response};

fn paper(gamma: f64) -> Params {
    Params {
        gamma,
        ..Params::default()
    }
}

/// The slowest relaxation rate at g', from the linearisation e'' + e' + g' e = 0 written here:
/// 1/2 on a focus (g' > 1/4), (1 − √(1 − 4g'))/2 on a node.
fn relaxation_rate_of(gp: f64) -> f64 {
    if gp > 0.25 {
        0.5
    } else {
        0.5 * (1.0 - (1.0 - 4.0 * gp).sqrt())
    }
}

/// A set near the cusp (γ − 1/(3α) = 0.0039) that bursts with its turning points foci.
const NEAR_CUSP: Params = Params {
    alpha: 25.91,
    gamma: 0.01672,
    eps: 0.6891,
    mu: 0.01235,
    delta: 0.5183,
    omega: 0.007403,
};

/// The slowest relaxation on a monotone curve is the least over every x the state passes:
/// sampled here between the equilibria at a = ±1 on the study's line, at γ = 1 and 30, and near
/// the cusp; and the domain's edge is the smaller of a tenth of the turning points' rate and it.
#[test]
fn the_slowest_relaxation_is_the_least_over_the_traversed_curve() {
    use hdgear::burst::{fast_slow_omega_max, turning_point_rate};
    use hdgear::fast::{Along, slowest_relaxation};
    let sets = [
        NEAR_CUSP,
        paper(0.1),
        paper(1.0),
        paper(30.0),
        paper(1.0 / 48.0 + 1e-4),
        Params {
            alpha: 3.0,
            gamma: 1.0 / 9.0 + 0.01,
            eps: 0.3,
            mu: -0.2,
            delta: 0.3,
            omega: 1e-3,
        },
    ];
    for p in sets {
        let s = slowest_relaxation(&p);
        assert_eq!(s.along, Along::SettledBranch, "{p:?}");
        let (x0, x1) = (
            crate::common::monotone_equilibrium(&p, -1.0),
            crate::common::monotone_equilibrium(&p, 1.0),
        );
        let n = 100_000;
        let least = (0..=n)
            .map(|j| p.g_prime(x0 + (x1 - x0) * j as f64 / n as f64))
            .fold(f64::INFINITY, f64::min);
        // g' is a parabola of curvature 6α: sampling misses its least value by ≤ 3α(Δx/2)²
        let miss = 3.0 * p.alpha * ((x1 - x0) / n as f64 / 2.0).powi(2);
        let at = p.g_prime(s.x);
        assert!(
            at <= least + 1e-15 && at >= least - miss - 1e-15,
            "{p:?}: {s:?} against {least}"
        );
        assert!((s.rate - relaxation_rate_of(at)).abs() <= 1e-12 * s.rate);
        assert!((s.a - p.a_at(s.x)).abs() <= 1e-12 && s.a.abs() <= 1.0 + 1e-12);
        let settling = turning_point_rate(&p) / 10.0;
        assert_eq!(fast_slow_omega_max(&p), settling.min(s.rate), "{p:?}");
    }
}

/// The fast-slow domain also sees the slowest relaxation met along the traversed curve, not only
/// at a = ±1. Near the cusp the slowest point is the node at the inflection, where the rate is
/// γ − 1/(3α) to first order: [`NEAR_CUSP`] has ω/r = 1.9 there, while its turning points are
/// foci (r = 1/2, ω/r = 0.015). With both folds in range, or one, the rate is taken where the
/// module says.
#[test]
fn the_fast_slow_domain_sees_the_slowest_point_of_the_traversed_curve() {
    use hdgear::burst::{fast_slow_omega_max, turning_point_rate};
    use hdgear::fast::{Along, slowest_relaxation};
    let s = slowest_relaxation(&NEAR_CUSP);
    assert!((s.x - 1.0 / (3.0 * NEAR_CUSP.alpha)).abs() <= 1e-15);
    assert!(NEAR_CUSP.omega / s.rate > 1.8, "{s:?}");
    let c = classify(
        &NEAR_CUSP,
        &response(&NEAR_CUSP, &BurstOptions::default()).unwrap(),
    );
    assert!(!c.fast_slow_domain);
    assert_eq!(c.mode, Mode::NotFastSlow);
    // below the path's slowest rate it is in the domain again (its turning points are foci)
    let slower = Params {
        omega: 0.9 * s.rate,
        ..NEAR_CUSP
    };
    assert_eq!(turning_point_rate(&slower), 0.5);
    assert!(slower.omega <= fast_slow_omega_max(&slower));
    // the study's γ = 0.1 example passes a node (g' = 0.079, r = 0.087): ω/r = 0.12, inside
    let s = slowest_relaxation(&paper(0.1));
    assert!((s.rate - relaxation_rate_of(0.1 - 1.0 / 48.0)).abs() < 1e-12);
    assert!((0.1..0.2).contains(&(0.01 / s.rate)), "{s:?}");
    // both folds in range (γ = 0.01 < 1/48): every branch ends at a fold, where the rate is 0;
    // the state settles between jumps at a = ±1, on the branches that exist there
    let p = paper(0.01);
    let s = slowest_relaxation(&p);
    assert_eq!(s.along, Along::TurningPoints);
    assert_eq!(s.a.abs(), 1.0);
    assert!(p.g_prime(s.x) > 0.0);
    assert!((s.rate - relaxation_rate_of(p.g_prime(s.x))).abs() <= 1e-12);
    // one fold in range: the settled branch spans the range and has no fold, so its slowest
    // point is a stable equilibrium inside it
    let p = crate::common::SINGLE_FOLD;
    let s = slowest_relaxation(&p);
    assert_eq!(s.along, Along::SettledBranch);
    assert!(p.g_prime(s.x) > 0.0 && s.a.abs() <= 1.0 + 1e-12, "{s:?}");
}
