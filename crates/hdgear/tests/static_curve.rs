//! The equilibrium curve of a model assembled from terms ([`hdgear::model::ModelCurve`]: a root
//! finder on its static torque) against the study cubic's closed forms, and the burst verdict
//! measured against it: on the study's model the same as against the cubic; on a linear spring
//! (a catalogue law whose kinks lie beyond the traversed range) the linear oscillator's closed
//! form; on a cubic whose outer part is a stiffer piecewise law, the folds of the cubic it equals
//! near them.

use hdgear::Params;
use hdgear::burst::{
    BurstOptions, Mode, Verdict, classify, classify_model, response, response_model,
    response_model_on,
};
use hdgear::fast::{Follower, StaticCurve, fold_abscissae, nearest_stable_equilibrium};
use hdgear::model::{Model, ModelCurve, terms::AnyTerm};

/// Sets across the regimes, far from the study's line too: monotone and bursting (the default),
/// both folds in range, stiff, just above the cusp, one fold in range, both folds out of range,
/// α·ε = 1, small and large ω, and a set with other α, ε, μ and δ.
fn sets() -> Vec<Params> {
    let d = Params::default();
    // one fold in range: the lower branch ends at a = −0.4321, the upper starts at a = −1.4321
    // (off the grids of a below)
    let f = Params { gamma: 0.015, ..d };
    let (xm, xp) = fold_abscissae(&f).unwrap();
    let (gm, gp) = (f.g(xm), f.g(xp));
    let one_fold = Params {
        mu: gm + 0.4321 * (gm - gp),
        delta: gm - gp,
        ..f
    };
    vec![
        d,
        Params { gamma: 0.01, ..d },
        Params { gamma: 30.0, ..d },
        Params {
            gamma: 1.0 / 48.0 + 0.002,
            ..d
        },
        one_fold,
        Params {
            gamma: 0.015,
            mu: 1.0,
            delta: 0.5,
            ..d
        },
        Params {
            eps: 1.0 / 16.0,
            ..d
        },
        Params { omega: 1e-4, ..d },
        Params { omega: 0.2, ..d },
        Params {
            alpha: 2.0,
            gamma: 0.05,
            eps: 0.5,
            mu: 0.0,
            delta: 0.3,
            omega: 0.01,
        },
    ]
}

/// |a − b| within `rel` of their size (1 at least), or both the same infinity.
fn close(a: f64, b: f64, rel: f64) -> bool {
    a == b || (a - b).abs() <= rel * a.abs().max(b.abs()).max(1.0)
}

/// Every fact the verdict reads, from the root finder and from the cubic's closed forms, agree:
/// to rounding where both solve the same equation (1e-12: the equilibria, the x-extent, the
/// turning points' rates, the folds), to 1e-9 where both search an interval for an extremum (the
/// least slope, the equilibrium's largest speed and its largest first-order lag: a golden-section
/// search locates x to √ε ≈ 1e-8 of the interval, which moves a quadratic extremum's value by ε).
#[test]
fn the_model_curve_of_a_study_model_is_the_cubic_closed_forms() {
    for p in sets() {
        let c = ModelCurve::new(&Model::study(&p)).unwrap();
        let at = format!("{p:?}");
        assert!(close(c.x_extent(), p.x_extent(), 1e-12), "{at}");
        assert!(close(c.start(), p.start(), 1e-12), "{at}");
        assert_eq!(c.focus_gprime(), p.focus_gprime(), "{at}");
        assert_eq!(c.decay_time(), p.decay_time(), "{at}");
        let (gm, gp) = (c.min_traversed_gprime(), p.min_traversed_gprime());
        assert!(close(gm, gp, 1e-9), "{at}: least g' {gm} vs {gp}");
        let (vm, vp) = (c.max_equilibrium_speed(), p.max_equilibrium_speed());
        assert!(close(vm, vp, 1e-9), "{at}: speed {vm} vs {vp}");
        let (lm, lp) = (c.max_first_order_lag(), p.max_first_order_lag());
        assert!(close(lm, lp, 1e-9), "{at}: first-order lag {lm} vs {lp}");
        let (sm, sp) = (c.slowest_relaxation(), p.slowest_relaxation());
        assert_eq!(sm.along, sp.along, "{at}");
        assert!(close(sm.rate, sp.rate, 1e-9), "{at}: {sm:?} vs {sp:?}");
        let (tm, tp) = (c.turning_point_relaxation(), p.turning_point_relaxation());
        assert!(
            close(tm.rate, tp.rate, 1e-12) && close(tm.x, tp.x, 1e-12),
            "{at}"
        );
        // the folds, where the traversed range holds them (beyond it no state goes)
        let x_lo = c.start() - c.x_extent();
        match (c.fold_band(), p.fold_band()) {
            (Some((m1, p1)), Some((m2, p2))) => {
                assert!(close(m1, m2, 1e-12) && close(p1, p2, 1e-12), "{at}")
            }
            (None, Some((m2, _))) => {
                let a = p.a_at(m2);
                assert!(!(-1.0..=1.0).contains(&a), "{at}: fold at a = {a} missed")
            }
            (m, q) => assert_eq!(m, q, "{at}"),
        }
        // the equilibrium a state follows: the nearest stable one, at states across the range
        let mut follower = c.follower(c.start());
        for i in 0..=40 {
            let a = -1.0 + 0.05 * f64::from(i);
            for j in 0..=20 {
                let x = x_lo + 3.0 * c.x_extent() * f64::from(j) / 20.0;
                let Some(want) = nearest_stable_equilibrium(&p, a, x) else {
                    continue;
                };
                let got = follower.at(a, x);
                assert!(
                    close(got, want, 1e-12),
                    "{at}: a = {a}, x = {x}: {got} vs {want}"
                );
            }
        }
    }
}

/// The burst scan against the root finder's curve gives the study model the verdict, bursts and
/// measures it gives against the cubic's. The two runs start from the same equilibrium found by
/// two solvers (equal to rounding), and their step sequences drift apart over thousands of steps,
/// so what is compared is what the scan locates on the dense output, to 1e-8 (the tolerance is
/// 1e-10): the bursts' peaks and sizes, the peak speed and the largest lag, and the lag ratio,
/// whose denominator (the largest first-order lag) both take from their curves.
#[test]
fn the_verdict_against_the_model_curve_is_the_cubics() {
    let opts = BurstOptions::default();
    let d = Params::default();
    for p in [
        d,
        Params { gamma: 0.01, ..d },
        Params { gamma: 30.0, ..d },
        Params {
            gamma: 1.0 / 48.0 + 0.002,
            ..d
        },
        Params {
            eps: 1.0 / 16.0,
            ..d
        },
        Params {
            gamma: 0.3,
            omega: 1e-3,
            ..d
        },
        Params { omega: 0.05, ..d },
    ] {
        let m = Model::study(&p);
        let c = ModelCurve::new(&m).unwrap();
        let (rp, rc) = (
            response_model_on(&m, &p, &opts).unwrap(),
            response_model_on(&m, &c, &opts).unwrap(),
        );
        let at = format!("{p:?}");
        assert_eq!(classify(&p, &rp), classify(&c, &rc), "{at}");
        assert_eq!(rp.bursts.len(), rc.bursts.len(), "{at}");
        for (a, b) in rp.bursts.iter().zip(&rc.bursts) {
            assert_eq!((a.jumps, a.spikes), (b.jumps, b.spikes), "{at}");
            assert!(close(a.t_peak, b.t_peak, 1e-8), "{at}");
            assert!(close(a.overshoot, b.overshoot, 1e-8), "{at}");
        }
        let (mp, mc) = (rp.measures, rc.measures);
        assert!(close(mp.speed_ratio, mc.speed_ratio, 1e-8), "{at}");
        assert!(close(mp.relative_lag, mc.relative_lag, 1e-8), "{at}");
        assert!(close(mp.lag_ratio, mc.lag_ratio, 1e-8), "{at}");
        let (sp, sc) = (rp.signatures, rc.signatures);
        assert_eq!(
            (sp.jump, sp.overshoot, sp.ringing, sp.jumps_per_period),
            (sc.jump, sc.overshoot, sc.ringing, sc.jumps_per_period),
            "{at}"
        );
        assert!(close(sp.max_overshoot, sc.max_overshoot, 1e-8), "{at}");
    }
}

/// A catalogue law whose kinks lie beyond the traversed range is a linear spring k there, and
/// x'' + x' + kx = μ + δ sin ωτ has the closed form x = (μ + δ·Im(k·H·e^{iωτ}))/k with
/// H = 1/(k − ω² + iω): no bursts, the peak speed k|H| times the equilibrium's ωδ/k, the lag
/// δ|H − 1/k| over the extent 2δ/k, and over the largest first-order lag ωδ/k² it is
/// k|kH − 1|/ω. The window starts a slow period in, where the free motion
/// has decayed by e^{−157}; what is left is the integration's error (tolerance 1e-10).
#[test]
fn a_linear_spring_has_the_linear_oscillators_closed_form_verdict() {
    let (k, mu, delta, omega) = (2.0, 0.3, 1.0, 0.02);
    let law = AnyTerm::new("piecewise", &[k, 3.0, 4.0, 10.0, 1.0, 0.0, 0.0]).unwrap();
    let m = Model::damped(mu, delta, omega).with_term(law).unwrap();
    assert_eq!(m.equivalent_params(), None);
    let c = ModelCurve::new(&m).unwrap();
    assert!(close(c.x_extent(), 2.0 * delta / k, 1e-12));
    assert!(close(c.max_equilibrium_speed(), omega * delta / k, 1e-12));
    assert!(close(
        c.max_first_order_lag(),
        omega * delta / (k * k),
        1e-12
    ));
    let r = response_model(&m, &BurstOptions::default()).unwrap();
    let v = classify_model(&m, &r).unwrap();
    assert_eq!((v.verdict, v.mode), (Verdict::NoBursts, Mode::Normal));
    // k·H = k/(k − ω² + iω)
    let (re, im) = (k - omega * omega, omega);
    let kh = k / re.hypot(im);
    let (khr, khi) = (k * re / (re * re + im * im), -k * im / (re * re + im * im));
    let lag = (khr - 1.0).hypot(khi) / 2.0;
    let speed = r.measures.speed_ratio;
    assert!(close(speed, kh, 1e-7), "speed ratio {speed} vs {kh}");
    let rel = r.measures.relative_lag;
    assert!(
        (rel - lag).abs() <= 1e-7 * lag,
        "relative lag {rel} vs {lag}"
    );
    let (ratio, want) = (r.measures.lag_ratio, 2.0 * k * lag / omega);
    assert!(close(ratio, want, 1e-7), "lag ratio {ratio} vs {want}");
}

/// A cubic with folds whose outer part (beyond |x| = 0.3, past both folds) is stiffened by a
/// piecewise law is no study cubic, but near its folds it is the cubic with γ + k₁ (the law's
/// inner slope): the curve's folds are that cubic's to rounding, and the state jumps at each, twice
/// a period as that cubic's does.
#[test]
fn a_cubic_with_a_stiffer_outer_part_keeps_the_folds_of_its_inner_cubic() {
    let p = Params {
        gamma: 0.005,
        ..Params::default()
    };
    let k1 = 0.004;
    let law = AnyTerm::new("piecewise", &[k1, 0.5, 1.0, 0.3, 0.2, 0.0, 0.0]).unwrap();
    let m = Model::study(&p).with_term(law).unwrap();
    assert_eq!(m.equivalent_params(), None);
    let inner = Params {
        gamma: p.gamma + k1,
        eps: p.gamma * p.eps / (p.gamma + k1),
        ..p
    };
    let (xm, xp) = fold_abscissae(&inner).unwrap();
    assert!(xp < 0.3);
    let c = ModelCurve::new(&m).unwrap();
    let (cm, cp) = c.fold_band().unwrap();
    assert!(
        close(cm, xm, 1e-12) && close(cp, xp, 1e-12),
        "{cm} {cp} vs {xm} {xp}"
    );
    let opts = BurstOptions::default();
    let r = response_model(&m, &opts).unwrap();
    assert_eq!(classify_model(&m, &r).unwrap().verdict, Verdict::FoldJump);
    let jumps = |bursts: &[hdgear::burst::Burst]| bursts.iter().map(|b| b.jumps).sum::<u32>();
    let cubic = response(&inner, &opts).unwrap();
    assert_eq!(jumps(&r.bursts), jumps(&cubic.bursts));
    assert_eq!(jumps(&r.bursts), 2 * opts.periods);
}

/// A dithered model whose static torque is no study cubic is refused (its averaged equilibria
/// are known only for the cubic), naming the model.
#[test]
fn a_dithered_model_without_a_cubic_is_refused() {
    let law = AnyTerm::new("piecewise", &[1.0, 2.0, 4.0, 0.5, 1.0, 0.0, 0.0]).unwrap();
    let dither = AnyTerm::new("dither", &[0.5, 50.0]).unwrap();
    let m = Model::damped(0.0, 1.0, 0.01)
        .with_term(law)
        .and_then(|m| m.with_term(dither))
        .unwrap();
    let e = response_model(&m, &BurstOptions::default()).unwrap_err();
    assert!(e.to_string().contains("dithered"), "{e}");
}

/// The independent reference's twenty burst cases (`tests/data/burst_cases.json`, not used to
/// build the root finder's curve), judged against that curve on the study's model: the
/// reference's verdict, and its bursts per period where it bursts.
#[test]
fn the_model_curve_verdict_agrees_with_the_independent_reference() {
    let cases = crate::common::reference_cases("burst_cases.json");
    assert_eq!(cases.len(), 20);
    let opts = BurstOptions::default();
    for (id, p, case) in cases {
        let rf = &case["reference"];
        let m = Model::study(&p);
        let c = ModelCurve::new(&m).unwrap();
        let r = response_model_on(&m, &c, &opts).unwrap();
        let v = classify(&c, &r);
        assert_eq!(v.verdict.name(), rf["verdict"].as_str().unwrap(), "{id}");
        if v.bursting {
            assert_eq!(
                r.rates.bursts_per_period,
                rf["bursts_per_period"].as_f64(),
                "{id}"
            );
        }
    }
}

/// The follower on a catalogue law (three straight segments with an offset, no folds) finds the
/// law's inverse, written here segment by segment, at every level of the load's swing (all three
/// segments on both sides of the offset) and from states anywhere around it.
#[test]
fn the_follower_inverts_a_catalogue_law() {
    let (k, x1, w2, eps) = ([0.05, 0.5, 5.0], 0.3, 0.5, 0.1);
    let law = AnyTerm::new("piecewise", &[k[0], k[1], k[2], x1, w2, eps, 0.0]).unwrap();
    let (mu, delta) = (0.2, 3.0);
    let c = ModelCurve::new(&Model::damped(mu, delta, 0.01).with_term(law).unwrap()).unwrap();
    // the twist u = x − ε at which the law's torque is t
    let inverse = |t: f64| {
        let (t1, t2) = (k[0] * x1, k[0] * x1 + k[1] * w2);
        let m = t.abs();
        let u = if m <= t1 {
            m / k[0]
        } else if m <= t2 {
            x1 + (m - t1) / k[1]
        } else {
            x1 + w2 + (m - t2) / k[2]
        };
        eps + u.copysign(t)
    };
    let mut follower = c.follower(c.start());
    for i in 0..=40 {
        let a = -1.0 + 0.05 * f64::from(i);
        let want = inverse(mu + delta * a);
        for j in 0..=20 {
            let x = want - 2.0 + 0.2 * f64::from(j);
            let got = follower.at(a, x);
            assert!(
                (got - want).abs() <= 1e-12 * (1.0 + want.abs()),
                "a = {a}, x = {x}: {got} vs {want}"
            );
        }
    }
}
