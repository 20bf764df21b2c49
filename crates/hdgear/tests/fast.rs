//! The fast subsystem: equilibria (property tests), folds against AUTO-07p, slopes, the curve,
//! the bifurcation set, and spiking areas against simulated responses.

use hdgear::Params;
use hdgear::fast::{
    self, CurveBranch, EqType, analyze, curve, equilibria, fold_abscissae, fold_curves, folds,
};
use hdgear::simulate::{SimOptions, simulate};
use proptest::prelude::*;

fn paper(gamma: f64) -> Params {
    Params {
        gamma,
        ..Params::default()
    }
}

/// |F(x, a)| relative to the sum of the magnitudes of its terms.
fn rel_residual(p: &Params, x: f64, a: f64) -> f64 {
    let f = p.g(x) - p.forcing(a);
    let scale = (p.alpha * x.powi(3)).abs()
        + x * x
        + (p.gamma * x).abs()
        + (p.gamma * p.eps).abs()
        + p.mu.abs()
        + (p.delta * a).abs();
    f.abs() / scale
}

fn any_params() -> impl Strategy<Value = Params> {
    (
        -2.0f64..2.5, // log10 alpha
        -1.0f64..30.0,
        -1.0f64..1.0,
        -1.0f64..1.0,
        0.0f64..30.0,
        0.001f64..1.0,
    )
        .prop_map(|(la, gamma, eps, mu, delta, omega)| Params {
            alpha: 10f64.powf(la),
            gamma,
            eps,
            mu,
            delta,
            omega,
        })
}

/// Parameters in the fold regime (γ < 1/(3α)).
fn fold_params() -> impl Strategy<Value = Params> {
    (any_params(), 0.0f64..0.999).prop_map(|(p, frac)| Params {
        gamma: frac / (3.0 * p.alpha) - 0.5 * (1.0 - frac),
        ..p
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn roots_have_tiny_residuals_and_consistent_types(p in any_params(), a in -2.0f64..2.0) {
        let e = equilibria(&p, a);
        prop_assert!((1..=3).contains(&e.count()));
        for w in e.roots.windows(2) {
            prop_assert!(w[0].x < w[1].x, "roots sorted and distinct");
        }
        for r in &e.roots {
            prop_assert!(rel_residual(&p, r.x, a) <= 1e-12, "residual {} at x {}", rel_residual(&p, r.x, a), r.x);
            let [(re1, im1), (re2, im2)] = r.eigenvalues;
            // eigenvalues are the roots of λ² + λ + g' = 0
            prop_assert!((re1 + re2 + 1.0).abs() < 1e-12, "trace −1");
            match r.kind {
                EqType::StableFocus => prop_assert!(im1 != 0.0 && re1 < 0.0 && re2 < 0.0),
                EqType::StableNode => prop_assert!(im1 == 0.0 && im2 == 0.0 && re1 < 0.0 && re2 < 0.0),
                EqType::Saddle => prop_assert!(im1 == 0.0 && re1 > 0.0 && re2 < 0.0),
                EqType::Degenerate => prop_assert!(re1 == 0.0 && r.multiplicity >= 2),
            }
            prop_assert_eq!(r.kind.is_stable(), re1 < 0.0 && re2 < 0.0);
        }
    }

    #[test]
    fn count_agrees_with_the_discriminant(p in any_params(), a in -2.0f64..2.0) {
        let e = equilibria(&p, a);
        // the discriminant's own rounding scale: the magnitude of its largest term
        let d = -(p.gamma * p.eps + p.forcing(a));
        let terms = [
            18.0 * p.alpha * p.gamma * d,
            4.0 * d,
            p.gamma * p.gamma,
            4.0 * p.alpha * p.gamma.powi(3),
            27.0 * p.alpha * p.alpha * d * d,
        ];
        let scale = terms.iter().map(|t| t.abs()).fold(0.0, f64::max);
        prop_assume!(e.discriminant.abs() > 1e-9 * scale);
        let expect = if e.discriminant > 0.0 { 3 } else { 1 };
        prop_assert_eq!(e.count(), expect, "Δ = {}", e.discriminant);
    }

    #[test]
    fn fold_points_are_double_roots(p in fold_params()) {
        prop_assume!(p.delta > 0.0);
        let (xm, xp) = fold_abscissae(&p).unwrap();
        for f in folds(&p, (-1.0, 1.0)) {
            prop_assert!(f.x == xm || f.x == xp);
            prop_assert!(rel_residual(&p, f.x, f.a) <= 1e-12, "F = 0");
            let gp = p.g_prime(f.x);
            let gp_scale = 3.0 * p.alpha * f.x * f.x + 2.0 * f.x.abs() + p.gamma.abs();
            prop_assert!(gp.abs() <= 1e-12 * gp_scale, "dF/dx = {gp}");
        }
    }

    #[test]
    fn curve_points_lie_on_the_curve(p in any_params(), n in 2usize..400) {
        prop_assume!(p.delta > 0.0);
        let c = curve(&p, (-1.0, 1.0), n).unwrap();
        prop_assert_eq!(c.len(), n);
        for q in &c {
            prop_assert!(q.a >= -1.0 && q.a <= 1.0);
            prop_assert!(rel_residual(&p, q.x, q.a) <= 1e-12);
            prop_assert_eq!(q.branch, CurveBranch::of(&p, q.x));
        }
    }
}

#[test]
fn folds_match_auto_07p() {
    // AUTO-07p continuation at alpha 16, gamma 0.01 (eps, mu, delta of the study)
    let p = paper(0.01);
    let f = folds(&p, (-1.0, 1.0));
    let expect = [
        (-0.0051381678755, 0.0058102030189),
        (-0.0051526345936, 0.0358564636478),
    ];
    assert_eq!(f.len(), 2);
    for (got, (a, x)) in f.iter().zip(expect) {
        assert!((got.a - a).abs() < 1e-9, "a {} vs {a}", got.a);
        assert!((got.x - x).abs() < 1e-9, "x {} vs {x}", got.x);
        assert!(got.in_range);
    }
    let c = fast::cusp(&p);
    assert_eq!(c.gamma, 1.0 / 48.0);
    assert_eq!(c.x, 1.0 / 48.0);
    // at the cusp both folds coincide: the last row of the bifurcation set
    let rows = fold_curves(&p, 0.0, 50).unwrap();
    let last = rows.last().unwrap();
    assert_eq!(last.gamma, 1.0 / 48.0);
    assert!((last.x_lower - last.x_upper).abs() < 1e-15);
    assert!((last.a_lower - c.a).abs() < 1e-15);
    for r in &rows {
        let q = paper(r.gamma);
        for (a, x) in [(r.a_lower, r.x_lower), (r.a_upper, r.x_upper)] {
            assert!(rel_residual(&q, x, a) < 1e-12);
            assert!(q.g_prime(x).abs() < 1e-12);
        }
        assert!(r.x_lower <= r.x_upper && r.a_lower >= r.a_upper);
    }
}

#[test]
fn largest_slopes_of_the_study() {
    // (gamma, largest |dx/da| on [-1, 1] to 4 significant figures, where)
    for (g, value, a) in [
        (30.0, 0.4735, Some(-1.0)),
        (10.0, 1.503, None),
        (1.0, 15.32, None),
        (0.1, 189.5, Some(-0.0093)),
    ] {
        let an = analyze(&paper(g), (-1.0, 1.0)).unwrap();
        let s = an.equilibria.max_slope;
        let rel = (s.value - value).abs() / value;
        assert!(rel < 5e-4, "gamma {g}: {} vs {value}", s.value);
        if let Some(a) = a {
            assert!((s.a - a).abs() < 1e-4, "gamma {g}: at a = {}", s.a);
        }
        if g < 30.0 {
            // the steepest point x = 1/(3α) is inside the range
            assert_eq!(s.x, 1.0 / 48.0);
            let sp = an.steepest_point.unwrap();
            assert_eq!(sp.value, 15.0 / (g - 1.0 / 48.0));
        } else {
            // outside: a(1/(3α)) < −1, so the maximum sits at the end a = −1
            assert!(an.steepest_point.unwrap().a < -1.0);
        }
        assert!(an.equilibria.folds.is_empty());
        assert!(an.equilibria.stable_everywhere);
        assert_eq!((an.equilibria.min_count, an.equilibria.max_count), (1, 1));
        assert!(!an.equilibria.hopf_possible);
    }
}

#[test]
fn fold_regime_counts() {
    let an = analyze(&paper(0.01), (-1.0, 1.0)).unwrap();
    assert_eq!(an.regime, hdgear::fast::Regime::FoldHysteresis);
    assert_eq!((an.equilibria.min_count, an.equilibria.max_count), (1, 3));
    assert!(!an.equilibria.stable_everywhere);
    assert!(an.equilibria.max_slope.value.is_infinite());
    // between the fold values of a there are three equilibria: stable, saddle, stable
    let a_mid = 0.5 * (an.equilibria.folds[0].a + an.equilibria.folds[1].a);
    let e = equilibria(&paper(0.01), a_mid);
    let kinds: Vec<EqType> = e.roots.iter().map(|r| r.kind).collect();
    assert_eq!(kinds[1], EqType::Saddle);
    assert!(kinds[0].is_stable() && kinds[2].is_stable());
    // a range that avoids the folds has one equilibrium everywhere
    let an = analyze(&paper(0.01), (0.1, 1.0)).unwrap();
    assert_eq!((an.equilibria.min_count, an.equilibria.max_count), (1, 1));
    assert!(an.equilibria.stable_everywhere);
    assert!(an.equilibria.folds.iter().all(|f| !f.in_range));
}

#[test]
fn curve_resolves_the_steep_part() {
    // γ = 0.1: the curve is nearly vertical near a ≈ −0.009; sampling by x puts many points there
    let p = paper(0.1);
    let c = curve(&p, (-1.0, 1.0), 2000).unwrap();
    assert_eq!(c.first().unwrap().a, -1.0);
    assert_eq!(c.last().unwrap().a, 1.0);
    let steep = c.iter().filter(|q| q.slope > 50.0).count();
    assert!(steep > 50, "only {steep} points where |dx/da| > 50");
    // x increases monotonically along the single branch, and no gap is large in either axis
    for w in c.windows(2) {
        assert!(w[1].x > w[0].x);
        assert!(w[1].a >= w[0].a);
        assert!(w[1].x - w[0].x < 0.01 && w[1].a - w[0].a < 0.01);
    }
}

#[test]
fn spiking_areas_of_the_study() {
    for g in [30.0, 10.0] {
        let an = analyze(&paper(g), (-1.0, 1.0)).unwrap();
        assert!(an.equilibria.spiking_areas.is_empty(), "gamma {g}");
        assert_eq!(an.equilibria.quiescent_areas.len(), 1);
    }
    for g in [1.0, 0.1] {
        let an = analyze(&paper(g), (-1.0, 1.0)).unwrap();
        let areas = &an.equilibria.spiking_areas;
        assert_eq!(areas.len(), 1, "gamma {g}: {areas:?}");
        let s = areas[0];
        // around a ≈ 0, narrow, containing the steepest point
        assert!(s.a_min > -0.1 && s.a_max < 0.05, "gamma {g}: {s:?}");
        let steep_a = an.equilibria.max_slope.a;
        assert!(s.a_min < steep_a && steep_a < s.a_max);
        assert_eq!(an.equilibria.quiescent_areas.len(), 2);
    }
}

/// Peaks of |x'| (local maxima above half the largest one) after the first slow period, with the
/// slow variable and its direction at each peak.
fn pulses(p: &Params) -> (f64, Vec<(f64, f64, f64)>) {
    let mut s = Vec::new();
    simulate(
        p,
        &SimOptions {
            dt: 0.01,
            ..SimOptions::default()
        },
        |t, y| s.push((t, y[1].abs())),
    )
    .unwrap();
    let t0 = p.slow_period();
    let s: Vec<(f64, f64)> = s.into_iter().filter(|q| q.0 > t0).collect();
    let vmax = s.iter().map(|q| q.1).fold(0.0, f64::max);
    let peaks = s
        .windows(3)
        .filter(|w| w[1].1 > w[0].1 && w[1].1 >= w[2].1 && w[1].1 > 0.5 * vmax)
        .map(|w| {
            let t = w[1].0;
            ((p.omega * t).sin(), (p.omega * t).cos().signum(), t)
        })
        .collect();
    (vmax, peaks)
}

#[test]
fn simulated_pulses_fall_inside_or_just_after_the_spiking_areas() {
    for g in [1.0, 0.1] {
        let p = paper(g);
        let s = analyze(&p, (-1.0, 1.0)).unwrap().equilibria.spiking_areas[0];
        let (vmax, peaks) = pulses(&p);
        // two bursts per slow period over the two periods kept
        assert_eq!(peaks.len(), 4, "gamma {g}: {peaks:?}");
        // "just after": within 2.5 relaxation times (5 time units, Δa ≤ 5ω) past the area's
        // end in the direction a is moving
        let lag = 5.0 * p.omega;
        for (a, dir, t) in peaks {
            let ok = if dir > 0.0 {
                a >= s.a_min && a <= s.a_max + lag
            } else {
                a <= s.a_max && a >= s.a_min - lag
            };
            assert!(
                ok,
                "gamma {g}: pulse at t {t}, a {a} (moving {dir}) vs area {s:?}, vmax {vmax}"
            );
        }
    }
}

#[test]
fn no_pulses_without_spiking_areas() {
    // γ = 30 and 10: x' is a smooth slow wave, far below the bursting cases' pulses
    for (g, bound) in [(30.0, 0.005), (10.0, 0.02)] {
        let (vmax, _) = pulses(&paper(g));
        assert!(vmax < bound, "gamma {g}: max |x'| {vmax}");
    }
}

#[test]
fn the_tracker_agrees_with_the_exact_solve() {
    // warm-started Newton and the exact cubic solve give the same followed equilibrium, with and
    // without folds, along a slow sweep of a up and down
    for g in [0.1, 0.01, 30.0] {
        let p = paper(g);
        let x0 = hdgear::fast::stable_equilibrium(&p, -1.0);
        let mut tr = hdgear::fast::EquilibriumTracker::new(&p, x0);
        let mut x = x0;
        for k in 0..=4000 {
            let s = f64::from(k) / 2000.0; // 0 … 2
            let a = if s <= 1.0 {
                -1.0 + 2.0 * s
            } else {
                3.0 - 2.0 * s
            };
            let t = tr.at(a, x);
            let exact = hdgear::fast::nearest_stable_equilibrium(&p, a, x).unwrap();
            assert!(
                (t - exact).abs() <= 1e-12 * (1.0 + exact.abs()),
                "gamma {g}, a {a}: {t} vs {exact}"
            );
            x = t;
        }
    }
}
