//! Dither as a control law (issue: burst control, quantified): the dithered model's integration
//! against an independent RK4 written here, a zero dither against the open loop, and the
//! simulated bursting boundary in γ against first-order averaging's prediction.

use hdgear::Params;
use hdgear::burst::{BurstOptions, classify, response_model};
use hdgear::model::{Model, terms::AnyTerm};

fn dithered(p: &Params, d: f64, wd: f64) -> Model {
    Model::study(p)
        .with_term(AnyTerm::new("dither", &[d, wd]).unwrap())
        .unwrap()
}

/// The dithered model integrated by hdgear (Taylor, with the sine's recurrence, and DOP853)
/// against a classical RK4 of x'' = μ + δ sin ωτ − x' − g(x) + D sin Ω_dτ written here, step
/// 2e-4 (hΩ_d = 4e-3: error ~1e-11 over the run): agreement to 1e-8 over 100 time units.
#[test]
fn dither_integration_matches_an_independent_rk4() {
    let p = Params {
        omega: 0.05,
        ..Params::default()
    };
    let (d, wd) = (80.0, 20.0);
    let m = dithered(&p, d, wd);
    let f = |t: f64, y: [f64; 2]| {
        let g = p.alpha * y[0].powi(3) - y[0] * y[0] + p.gamma * (y[0] - p.eps);
        [
            y[1],
            p.mu + p.delta * (p.omega * t).sin() - y[1] - g + d * (wd * t).sin(),
        ]
    };
    let (t_end, h): (f64, f64) = (100.0, 2e-4);
    let x0 = m.stable_equilibrium(0.0).unwrap();
    let y = crate::common::rk4_run(f, [x0, 0.0], h, t_end);
    crate::common::assert_both_methods_reach(&m, t_end, y, 1e-8, wd);
}

/// A dither of amplitude 0 is the open loop: the same equivalent parameters, verdict and peak
/// |x'| (to 1e-9: the extra phase state changes the steps' error norm, not the motion).
#[test]
fn a_zero_dither_is_the_open_loop() {
    let opts = BurstOptions::default();
    for gamma in [0.1, 1.0, 10.0] {
        let p = Params {
            gamma,
            ..Params::default()
        };
        let m = dithered(&p, 0.0, 30.0);
        assert_eq!(m.equivalent_params(), Some(p));
        let (open, closed) = (
            response_model(&Model::study(&p), &opts).unwrap(),
            response_model(&m, &opts).unwrap(),
        );
        assert_eq!(classify(&p, &open).verdict, classify(&p, &closed).verdict);
        let (a, b) = (open.rates.peak_abs_xdot, closed.rates.peak_abs_xdot);
        assert!((a - b).abs() <= 1e-9 * a, "γ = {gamma}: {a} vs {b}");
    }
}

/// Whether the model bursts, by the verdict on its motion (averaged over a dither's period).
fn bursts(m: &Model) -> bool {
    let r = response_model(m, &BurstOptions::default()).unwrap();
    classify(&m.equivalent_params().unwrap(), &r).bursting
}

/// The γ at which `bursts` changes from true to false in [lo, hi], bisected to 2e-3 relative:
/// the bracket's upper end.
fn boundary(lo: f64, hi: f64, bursts: impl Fn(f64) -> bool) -> f64 {
    assert!(bursts(lo) && !bursts(hi), "no boundary in [{lo}, {hi}]");
    let (mut lo, mut hi) = (lo, hi);
    while hi - lo > 2e-3 * hi {
        let mid = 0.5 * (lo + hi);
        if bursts(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// A dither stiffens the averaged cubic by 1.5αA² (A its ripple on the twist) and shifts the
/// load by A²/2, so the bursting boundary in γ moves down. The simulated boundary of the
/// dithered model (its verdict on the averaged motion) moves as the open loop's boundary of the
/// averaged model predicts, within 15 % of the shift (the figure), at the study's point
/// with Ω_d = 20 and at a set far from it (α = 4, δ = 2) with Ω_d = 10. Both have Ω_d at least
/// 2.9 times the fast mode's largest frequency on the traversed curve, which averaging needs.
/// The dither amplitude is D = 0.2·Ω_d² (A ≈ 0.2).
#[test]
fn dither_moves_the_gamma_boundary_as_averaging_predicts() {
    for (alpha, delta, wd) in [(16.0, 15.0, 20.0), (4.0, 2.0, 10.0)] {
        let at = |gamma: f64| Params {
            alpha,
            delta,
            gamma,
            ..Params::default()
        };
        let d = 0.2 * wd * wd;
        let open = boundary(0.01, 6.0, |g| bursts(&Model::study(&at(g))));
        let averaged = |g: f64| dithered(&at(g), d, wd).equivalent_params().unwrap();
        let predicted = boundary(0.01, 6.0, |g| bursts(&Model::study(&averaged(g))));
        let simulated = boundary(0.01, 6.0, |g| bursts(&dithered(&at(g), d, wd)));
        let (shift_pred, shift_sim) = (open - predicted, open - simulated);
        assert!(
            shift_pred > 0.2,
            "α = {alpha}: a shift too small to test ({shift_pred})"
        );
        assert!(
            (shift_sim / shift_pred - 1.0).abs() <= 0.15,
            "α = {alpha}, δ = {delta}, Ω_d = {wd}: boundary {open} → simulated {simulated}, \
             predicted {predicted}"
        );
    }
}
