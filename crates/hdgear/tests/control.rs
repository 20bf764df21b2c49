//! Control laws as terms (issue: burst control, quantified): virtual stiffness and virtual
//! damping against the exact open-loop reparametrisations they are, the washout's equilibria
//! and integration against an independent RK4 written here, the burst verdict of an assembled
//! model against the study's fast path, and the tuner against an independent bisection.

use hdgear::Params;
use hdgear::burst::{BurstOptions, Verdict, classify, response, response_model};
use hdgear::control::{assess, law_term, tune};
use hdgear::integrate::Options;
use hdgear::model::{Model, terms::AnyTerm};
use hdgear::simulate::{SimOptions, Start, simulate_model};

/// The study's four points, γ = 30, 10 (no bursts), 1 and 0.1 (bursts).
const GAMMAS: [f64; 4] = [30.0, 10.0, 1.0, 0.1];

fn at(gamma: f64) -> Params {
    Params {
        gamma,
        ..Params::default()
    }
}

/// Samples of x and x' every `dt` up to `t_end` from the equilibrium.
fn trajectory(m: &Model, t_end: f64, dt: f64, tol: f64) -> Vec<[f64; 2]> {
    let opts = SimOptions {
        t_end,
        dt,
        start: Start::Equilibrium,
        tol: Options {
            rtol: tol,
            atol: tol,
            ..Options::default()
        },
    };
    let mut out = Vec::new();
    simulate_model(m, &opts, |_, y| out.push([y[0], y[1]])).unwrap();
    out
}

/// ũ = −k_p·x is the open loop with γ → γ + k_p, ε → γε/(γ + k_p): over three slow periods the
/// two trajectories agree to 1e-12 (both integrated at tolerance 1e-13: what is left is the
/// rounding of γ(x − ε) + k_p·x against γ'(x − ε'), carried by the integration).
#[test]
fn virtual_stiffness_is_the_open_loop_with_gamma_and_eps_shifted() {
    let t_end = 3.0 * std::f64::consts::TAU / 0.01;
    for gamma in GAMMAS {
        let p = at(gamma);
        for kp in [0.3, 2.5] {
            let closed = Model::study(&p)
                .with_term(law_term("vstiffness", kp, &[]).unwrap())
                .unwrap();
            let q = Params {
                gamma: gamma + kp,
                eps: gamma * p.eps / (gamma + kp),
                ..p
            };
            // the fold-in reads a₁ off the static torque at x = 0 and 1: rounding of its size there
            let e = closed.equivalent_params().unwrap();
            let size = 1e-14 * (p.alpha + 1.0 + q.gamma);
            assert!(
                (e.gamma - q.gamma).abs() <= size,
                "{} vs {}",
                e.gamma,
                q.gamma
            );
            assert!((e.eps - q.eps).abs() <= size, "{} vs {}", e.eps, q.eps);
            let a = trajectory(&closed, t_end, 0.5, 1e-13);
            let b = trajectory(&Model::study(&q), t_end, 0.5, 1e-13);
            assert_eq!(a.len(), b.len());
            let worst = a
                .iter()
                .zip(&b)
                .map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs()))
                .fold(0.0, f64::max);
            assert!(worst < 1e-12, "γ = {gamma}, k_p = {kp}: {worst:e}");
        }
    }
}

/// ũ = −k_d·x' is the open loop in the time s = cτ and twist y = x/c², c = 1 + k_d:
/// α' = αc², γ' = γ/c², ε' = ε/c², μ' = μ/c⁴, δ' = δ/c⁴, ω' = ω/c (divide by c², scale x so
/// that the x² coefficient stays −1). Both integrated; x(τ) = c²·y(cτ) to 1e-9 relative.
#[test]
fn virtual_damping_is_the_open_loop_in_rescaled_time_and_twist() {
    for gamma in [1.0, 0.1] {
        let p = at(gamma);
        let kd = 0.8;
        let c = 1.0 + kd;
        let c2 = c * c;
        let closed = Model::study(&p)
            .with_term(law_term("vdamping", kd, &[]).unwrap())
            .unwrap();
        let q = Params {
            alpha: p.alpha * c2,
            gamma: p.gamma / c2,
            eps: p.eps / c2,
            mu: p.mu / (c2 * c2),
            delta: p.delta / (c2 * c2),
            omega: p.omega / c,
        };
        let t_end = 2.0 * std::f64::consts::TAU / p.omega;
        let a = trajectory(&closed, t_end, 0.5, 1e-12);
        let b = trajectory(&Model::study(&q), c * t_end, c * 0.5, 1e-12);
        let scale = a.iter().map(|y| y[0].abs()).fold(0.0, f64::max);
        let worst = a
            .iter()
            .zip(&b)
            .map(|(a, b)| (a[0] - c2 * b[0]).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-9 * scale, "γ = {gamma}: {worst:e} of {scale}");
    }
}

/// The washout's torque vanishes at every equilibrium (ξ = x at rest): the closed loop's static
/// torque is the open loop's to the bit, its equivalent parameter set is p itself, and its
/// lowest stable equilibrium is the open loop's.
#[test]
fn washout_keeps_the_equilibria() {
    for gamma in GAMMAS {
        let p = at(gamma);
        let open = Model::study(&p);
        let closed = open
            .with_term(law_term("washout", 3.0, &[0.1]).unwrap())
            .unwrap();
        assert_eq!(closed.equivalent_params(), Some(p));
        for i in 0..=200 {
            let x = -2.0 + 0.02 * f64::from(i);
            assert_eq!(closed.static_torque(x), open.static_torque(x), "x = {x}");
        }
        for a in [-1.0, 0.0, 0.5, 1.0] {
            assert_eq!(
                closed.stable_equilibrium(a).unwrap(),
                open.stable_equilibrium(a).unwrap()
            );
        }
    }
}

/// The washout closed loop integrated by hdgear (Taylor, the terms' recurrences) against a
/// classical RK4 of x'' = μ + δ sin ωτ − x' − g(x) − k_w(x − ξ), ξ' = ω_w(x − ξ) written here,
/// step 1e-3 (error ~1e-12 per unit time): agreement to 1e-8 over 200 time units through a burst.
#[test]
fn washout_integration_matches_an_independent_rk4() {
    let p = Params {
        omega: 0.05,
        ..Params::default()
    };
    let (kw, ww) = (2.0, 0.3);
    let m = Model::study(&p)
        .with_term(AnyTerm::new("washout", &[kw, ww]).unwrap())
        .unwrap();
    let f = |t: f64, y: [f64; 3]| {
        let g = p.alpha * y[0].powi(3) - y[0] * y[0] + p.gamma * (y[0] - p.eps);
        [
            y[1],
            p.mu + p.delta * (p.omega * t).sin() - y[1] - g - kw * (y[0] - y[2]),
            ww * (y[0] - y[2]),
        ]
    };
    let (t_end, h) = (200.0, 1e-3);
    let x0 = m.stable_equilibrium(0.0).unwrap();
    let y = crate::common::rk4_run(f, [x0, 0.0, x0], h, t_end);
    let last = crate::common::model_end_state(&m, t_end, 1e-13, hdgear::integrate::Method::Taylor);
    for j in 0..3 {
        assert!(
            (last[j] - y[j]).abs() < 1e-8,
            "component {j}: {} vs {}",
            last[j],
            y[j]
        );
    }
}

/// The verdict of an assembled model with no further terms is the study's fast path's: the
/// same signatures' verdict and peak |x'| to 1e-9 at the four points.
#[test]
fn the_assembled_verdict_is_the_fast_paths() {
    let opts = BurstOptions::default();
    for gamma in GAMMAS {
        let p = at(gamma);
        let a = response(&p, &opts).unwrap();
        let b = response_model(&Model::study(&p), &opts).unwrap();
        assert_eq!(
            classify(&p, &a).verdict,
            classify(&p, &b).verdict,
            "γ = {gamma}"
        );
        let (pa, pb) = (a.rates.peak_abs_xdot, b.rates.peak_abs_xdot);
        assert!((pa - pb).abs() < 1e-9 * pa, "γ = {gamma}: {pa} vs {pb}");
    }
}

/// The tuned virtual stiffness is the γ-boundary: an independent bisection of the study's
/// verdict along γ + k, γε/(γ + k) brackets the same gain (the two final brackets, each 1e-3
/// wide, overlap). At γ = 2.2, just below the boundary, the least gain is below the first gain
/// tried, and the search goes down to it.
#[test]
fn tuned_virtual_stiffness_is_the_gamma_boundary() {
    let opts = BurstOptions::default();
    for gamma in [1.0, 0.1, 2.2] {
        let p = at(gamma);
        let t = tune(&p, "vstiffness", &[], &opts, 1e-3).unwrap();
        assert_ne!(t.below.verdict, Verdict::NoBursts);
        assert_eq!(t.tuned.verdict, Verdict::NoBursts);
        let bursts = |k: f64| {
            let q = Params {
                gamma: gamma + k,
                eps: gamma * p.eps / (gamma + k),
                ..p
            };
            classify(&q, &response(&q, &opts).unwrap()).bursting
        };
        let (mut lo, mut hi) = (0.0, 0.5);
        while bursts(hi) {
            (lo, hi) = (hi, 2.0 * hi);
        }
        while hi / lo - 1.0 > 1e-3 {
            let mid = 0.5 * (lo + hi);
            if bursts(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        if gamma == 2.2 {
            assert!(t.tuned.gain < hdgear::control::GAIN_START && t.below.gain > 0.0);
        }
        // the boundary in γ' = γ + k to the boundaries' 1e-3 (at γ = 2.2 the gain itself is
        // tiny, 0.0039, and the two searches, one geometric, one arithmetic, stop at sign
        // changes of the verdict 1e-4 apart in γ')
        let (tuned, independent) = (gamma + t.tuned.gain, gamma + hi);
        assert!(
            (tuned - independent).abs() <= 1e-3 * independent,
            "γ = {gamma}: {tuned} vs {independent}"
        );
        assert!(
            gamma == 2.2 || (t.tuned.gain >= lo && t.below.gain <= hi),
            "γ = {gamma}: tuned [{}, {}], independent [{lo}, {hi}]",
            t.below.gain,
            t.tuned.gain
        );
    }
}

/// At the study's bursting points the tuned washout removes the bursts, leaves the state at the
/// load's extremes where it was (≤ 1 % of X) and lowers peak |x'|; a larger gain brings the
/// peak below 0.2 of the open loop's.
#[test]
fn washout_removes_the_bursts_and_leaves_the_load_extremes() {
    let opts = BurstOptions::default();
    for gamma in [1.0, 0.1] {
        let p = at(gamma);
        let t = tune(&p, "washout", &[0.1], &opts, 1e-2).unwrap();
        assert!(t.tuned.removes_bursts() && !t.below.removes_bursts());
        assert!(t.tuned.static_shift < 0.01, "{}", t.tuned.static_shift);
        assert!(t.tuned.peak_ratio() < 1.0, "{}", t.tuned.peak_ratio());
        assert!(t.tuned.effort_mean.abs() < 1e-3 * t.tuned.effort_rms);
        let strong = assess(&p, law_term("washout", 10.0, &[0.03]).unwrap(), &opts).unwrap();
        assert!(strong.removes_bursts() && strong.peak_ratio() < 0.2);
    }
}

/// Bad requests are refused with the value named: an unknown law, a negative gain, a point that
/// does not burst (nothing to tune).
#[test]
fn bad_control_requests_are_refused() {
    let e = law_term("pid", 1.0, &[]).unwrap_err().to_string();
    assert!(e.contains("pid") && e.contains("washout"), "{e}");
    let e = law_term("vstiffness", -1.0, &[]).unwrap_err().to_string();
    assert!(e.contains("kp") && e.contains("-1"), "{e}");
    // beyond the magnitude limit every parameter has: refused, not simulated until it blows up
    let e = law_term("washout", 1e300, &[0.03]).unwrap_err().to_string();
    assert!(e.contains("1e300") && e.contains("1e100"), "{e}");
    let e = law_term("washout", 1.0, &[1e-300]).unwrap_err().to_string();
    assert!(e.contains("1e-300") && e.contains("1e-100"), "{e}");
    let e = tune(&at(30.0), "vstiffness", &[], &BurstOptions::default(), 1e-3)
        .unwrap_err()
        .to_string();
    assert!(e.contains("does not burst"), "{e}");
    // a bracket narrower than f64 can form would never be reached: refused before any run
    let e = tune(
        &at(1.0),
        "vstiffness",
        &[],
        &BurstOptions::default(),
        1e-320,
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("rel_tol") && e.contains("8.9e-16"), "{e}");
    // both folds in range (γ = 0.01 < 1/48): a law without static torque cannot remove the
    // jumps, so the search is refused before it simulates ever stiffer loops
    for (law, rest) in [("vdamping", &[][..]), ("washout", &[0.03][..])] {
        let e = tune(&at(0.01), law, rest, &BurstOptions::default(), 1e-3)
            .unwrap_err()
            .to_string();
        assert!(e.contains("fold hysteresis") && e.contains(law), "{e}");
    }
}

/// Feed-forward's residual: δ sin ωτ − κδ sin(ωτ + Δφ) is a sine of amplitude
/// δ·√(1 − 2κ cos Δφ + κ²) (checked by its samples' largest value over a period), and the
/// tolerance's ends are what they say: the study model with δ·ρ has no bursts, with δ times the
/// bursting end it bursts; ρ shrinks as the drive softens (γ = 1 → 0.1).
#[test]
fn feedforward_tolerance_is_the_delta_boundary() {
    use hdgear::control::{feedforward, feedforward_residual};
    for (kappa, dphi) in [(1.0, 0.0), (0.9, 0.1), (1.2, -0.3), (0.0, 1.0), (1.0, 3.0)] {
        let peak = (0..20_000)
            .map(|i| {
                let t = std::f64::consts::TAU * f64::from(i) / 20_000.0;
                (t.sin() - kappa * (t + dphi).sin()).abs()
            })
            .fold(0.0, f64::max);
        let r = feedforward_residual(kappa, dphi);
        assert!(
            (peak - r).abs() < 1e-6 * r.max(1e-3),
            "{kappa} {dphi}: {peak} vs {r}"
        );
    }
    let opts = BurstOptions::default();
    let mut limits = Vec::new();
    for gamma in [1.0, 0.1] {
        let p = at(gamma);
        let f = feedforward(&p, &opts, 1e-3).unwrap();
        let bursts = |ratio: f64| {
            let q = Params {
                delta: p.delta * ratio,
                ..p
            };
            classify(&q, &response(&q, &opts).unwrap()).bursting
        };
        assert!(!bursts(f.residual_limit), "γ = {gamma}");
        assert!(bursts(f.residual_bursting), "γ = {gamma}");
        assert!(f.residual_bursting / f.residual_limit - 1.0 <= 1e-3);
        let phase = f.max_phase_error;
        assert!((feedforward_residual(1.0, phase) - f.residual_limit).abs() < 1e-12);
        limits.push(f.residual_limit);
    }
    assert!(limits[1] < limits[0], "{limits:?}");
}

/// The least gain for every plant within ±20 % is the largest of the plants' own least gains
/// (each tuned alone here): the robust search over all plants at once and the 33 separate
/// tunings bracket the same gain.
#[test]
fn robust_gain_is_the_largest_plant_least_gain() {
    use hdgear::control::{model_error_plants, robustness};
    let p = at(0.1);
    let opts = BurstOptions::default();
    let rel = 1e-3;
    let plants = model_error_plants(&p, 0.2).unwrap();
    assert_eq!(plants.len(), 33);
    // the nominal set first, then every corner a distinct ±20 % box corner
    assert_eq!(plants[0], p);
    for q in &plants[1..] {
        for (v, v0) in [
            (q.alpha, p.alpha),
            (q.gamma, p.gamma),
            (q.eps, p.eps),
            (q.mu, p.mu),
            (q.delta, p.delta),
        ] {
            assert!(((v / v0 - 1.0).abs() - 0.2).abs() < 1e-12);
        }
        assert_eq!(q.omega, p.omega);
    }
    let tuned = tune(&p, "vstiffness", &[], &opts, rel).unwrap();
    let r = robustness(&p, &tuned, 0.2, &opts, rel).unwrap();
    let worst_alone = plants
        .iter()
        .map(|q| match tune(q, "vstiffness", &[], &opts, rel) {
            Ok(t) => t.tuned.gain,
            Err(_) => 0.0, // this plant does not burst open loop
        })
        .fold(0.0, f64::max);
    assert!(r.ratio >= 1.0);
    // both searches stop on brackets of relative width 1e-3 around the same crossing
    assert!(
        (r.gain / worst_alone - 1.0).abs() <= 2.5 * rel,
        "robust {} vs largest single {}",
        r.gain,
        worst_alone
    );
    // the worst plant named bursts just below the robust gain
    let below = assess(
        &r.worst,
        law_term("vstiffness", r.gain / (1.0 + 2.0 * rel), &[]).unwrap(),
        &opts,
    )
    .unwrap();
    assert!(!below.removes_bursts());
}

/// The effort in N m: the output-referred control torque of virtual stiffness k_p is a stiffness
/// K = k_p·N²·J_i/T² on the twist, entering through the input inertia as K·θ/(N²J_i); adding the
/// equivalent K·J_eq/(N²J_i) to the drive's k1 and reducing it (an independent path through
/// `reduce`) gives γ + k_p exactly.
#[test]
fn drive_effort_scale_is_the_reductions() {
    use hdgear::control::drive::torque_scale;
    use hdgear::physical::PhysicalParams;
    let d = PhysicalParams {
        j_in: 5e-5,
        j_out: 0.05,
        ratio: 50.0,
        k1: 2000.0,
        k2: 1.7e9,
        backlash: 2.9e-4,
        c_eq: 4.3,
        t_m: 7.0,
        t_am: 112.0,
        omega: std::f64::consts::PI,
    };
    let r = d.reduce().unwrap();
    let kp = 1.7;
    // u = s·ũ = s·k_p·x = (s·k_p/L)·θ
    let k_out = torque_scale(&d, &r) * kp / r.length_scale;
    let stiffer = PhysicalParams {
        k1: d.k1 + k_out * d.j_eq() / (d.ratio * d.ratio * d.j_in),
        ..d
    };
    let g = stiffer.reduce().unwrap().params.gamma;
    assert!(
        (g - (r.params.gamma + kp)).abs() < 1e-12 * g,
        "{g} vs {}",
        r.params.gamma + kp
    );
}
