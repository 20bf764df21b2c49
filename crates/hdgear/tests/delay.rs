//! Delayed feedback ũ = K·(x(τ − τ_d) − x(τ)) (issue: burst control, quantified): hdgear's method
//! of steps against an independent one written here, and the limit τ_d → 0.

use hdgear::Params;
use hdgear::integrate::Options;
use hdgear::model::{Model, terms::AnyTerm};
use hdgear::simulate::{SimOptions, Start, simulate_model};

fn delayed(p: &Params, k: f64, tau: f64) -> Model {
    Model::study(p)
        .with_term(AnyTerm::new("delay", &[k, tau]).unwrap())
        .unwrap()
}

/// x and x' at `t_end` from the equilibrium at rtol = atol = `tol`.
fn end_state(m: &Model, t_end: f64, tol: f64) -> [f64; 2] {
    let y = crate::common::model_end_state(m, t_end, tol, hdgear::integrate::Method::Dop853);
    [y[0], y[1]]
}

/// An independent method of steps: classical RK4 with step h = τ_d/m, the history kept at every
/// grid point (x and x'), and x(τ − τ_d) at a stage's half step by the cubic Hermite interpolant
/// of its two neighbours (error h⁴/384·|x''''|, the order of RK4's own). Rest at x0 before 0.
fn method_of_steps(p: &Params, k: f64, tau: f64, h: f64, t_end: f64, x0: f64) -> [f64; 2] {
    let m = (tau / h).round() as usize;
    assert!(
        (m as f64 * h - tau).abs() < 1e-12,
        "τ_d a whole number of steps"
    );
    let steps = (t_end / h).round() as usize;
    let mut hist: Vec<[f64; 2]> = Vec::with_capacity(steps + 1);
    hist.push([x0, 0.0]);
    // the history at grid index i − m (rest before the run), and halfway to the next
    let at = |hist: &[[f64; 2]], i: isize| -> [f64; 2] {
        if i < 0 { [x0, 0.0] } else { hist[i as usize] }
    };
    let half = |hist: &[[f64; 2]], i: isize| -> f64 {
        let (a, b) = (at(hist, i), at(hist, i + 1));
        0.5 * (a[0] + b[0]) + h / 8.0 * (a[1] - b[1])
    };
    let f = |t: f64, y: [f64; 2], xd: f64| {
        let g = p.alpha * y[0].powi(3) - y[0] * y[0] + p.gamma * (y[0] - p.eps);
        [
            y[1],
            p.mu + p.delta * (p.omega * t).sin() - y[1] - g - k * (y[0] - xd),
        ]
    };
    let mut y = [x0, 0.0];
    for i in 0..steps {
        let t = i as f64 * h;
        let j = i as isize - m as isize;
        // the delayed twist at the stage's time: the step's start, its middle or its end
        let delayed = [at(&hist, j)[0], half(&hist, j), at(&hist, j + 1)[0]];
        let stage = |s: f64| delayed[(2.0 * (s - t) / h).round() as usize];
        y = crate::common::rk4_step(|s, y| f(s, y, stage(s)), t, y, h);
        hist.push(y);
    }
    y
}

/// Three delays, through a burst (ω = 0.05, 200 time units): hdgear's DOP853 with the history's
/// dense output at 1e-13 against the RK4 method of steps above at h = 1e-3 agree to 1e-8.
#[test]
fn delayed_feedback_matches_an_independent_method_of_steps() {
    let p = Params {
        omega: 0.05,
        ..Params::default()
    };
    let (k, t_end) = (2.0, 200.0);
    for tau in [0.5, 1.7, 3.0] {
        let m = delayed(&p, k, tau);
        let x0 = m.stable_equilibrium(0.0).unwrap();
        let reference = method_of_steps(&p, k, tau, 1e-3, t_end, x0);
        let ours = end_state(&m, t_end, 1e-13);
        for c in 0..2 {
            assert!(
                (ours[c] - reference[c]).abs() < 1e-8,
                "τ_d = {tau}, component {c}: {} vs {}",
                ours[c],
                reference[c]
            );
        }
    }
}

/// As τ_d → 0, K·(x − x(τ − τ_d)) = Kτ_d·x' − Kτ_d²·x''/2 + …: the delayed loop approaches the
/// open loop at first order in τ_d, and the loop with virtual damping k_d = Kτ_d at second order.
/// Over 50 time units (γ = 1, ω = 0.05), each tenfold shorter delay from 0.1 to 1e-3 brings the
/// first distance down by 10 and the second by 100, each within 5 % (the second is 4e-11 at
/// 1e-3; below that it meets the two runs' own tolerance, some 3e-13).
#[test]
fn a_vanishing_delay_recovers_the_undelayed_loop() {
    let p = Params {
        gamma: 1.0,
        omega: 0.05,
        ..Params::default()
    };
    let (k, t_end, tol) = (2.0, 50.0, 1e-13);
    let open = end_state(&Model::study(&p), t_end, tol);
    let distance = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    let mut last: Option<(f64, f64)> = None;
    for tau in [1e-1, 1e-2, 1e-3] {
        let ours = end_state(&delayed(&p, k, tau), t_end, tol);
        let damped = Model::study(&p)
            .with_term(AnyTerm::new("vdamping", &[k * tau]).unwrap())
            .unwrap();
        let (first, second) = (
            distance(ours, open),
            distance(ours, end_state(&damped, t_end, tol)),
        );
        if let Some((f0, s0)) = last {
            let (r1, r2) = (f0 / first, s0 / second);
            assert!(
                (r1 / 10.0 - 1.0).abs() < 0.05,
                "τ_d = {tau}: open-loop ratio {r1}"
            );
            assert!(
                (r2 / 100.0 - 1.0).abs() < 0.05,
                "τ_d = {tau}: damped ratio {r2}"
            );
        }
        last = Some((first, second));
    }
}

/// A delay as long as the run, one too short for the step budget, or a negative gain is refused
/// naming the value.
#[test]
fn bad_delays_are_refused() {
    let p = Params::default();
    let opts = SimOptions {
        t_end: 5.0,
        dt: 1.0,
        start: Start::Equilibrium,
        tol: Options::default(),
    };
    let e = simulate_model(&delayed(&p, 1.0, 5.0), &opts, |_, _| {}).unwrap_err();
    assert!(
        e.to_string().contains("taud") && e.to_string().contains('5'),
        "{e}"
    );
    let e = simulate_model(&delayed(&p, 1.0, 1e-12), &opts, |_, _| {}).unwrap_err();
    assert!(e.to_string().contains("too short"), "{e}");
    let e = AnyTerm::new("delay", &[-1.0, 1.0]).unwrap_err();
    assert!(e.to_string().contains("kdelay"), "{e}");
}

/// A delay comparable to the fast mode's period destabilises the loop before it damps it: at
/// the study's γ = 0.1 with τ_d = 1 and K = 20 the closed loop oscillates by itself (its fast
/// motion never settles, peak |x'| many times the open loop's). The assessment says unstable and
/// does not count it as removing the bursts; with τ_d = 0.3 the tuned gain removes them, with
/// K·τ_d within a factor of 2 of the least virtual damping (what a vanishing delay becomes).
#[test]
fn an_unstable_delayed_loop_is_reported_as_such() {
    use hdgear::burst::BurstOptions;
    use hdgear::control::{assess, law_term, tune};
    let p = Params::default();
    let opts = BurstOptions::default();
    let a = assess(&p, law_term("delay", 20.0, &[1.0]).unwrap(), &opts).unwrap();
    assert!(a.unstable && !a.removes_bursts(), "{a:?}");
    assert!(a.peak_ratio() > 10.0, "{}", a.peak_ratio());
    let t = tune(&p, "delay", &[0.3], &opts, 1e-2).unwrap();
    assert!(t.tuned.removes_bursts() && !t.tuned.unstable, "{t:?}");
    assert!(!t.below.removes_bursts());
    // the small-delay limit is virtual damping k_d = K·τ_d: the same order of gain
    let kd = tune(&p, "vdamping", &[], &opts, 1e-2).unwrap().tuned.gain;
    let ratio = t.tuned.gain * 0.3 / kd;
    assert!((0.5..2.0).contains(&ratio), "K·τ_d/k_d = {ratio}");
}

/// The facts of a delayed loop allow a Hopf bifurcation (the unstable loop above has one),
/// whatever its damping at rest; a zero gain leaves the open loop's facts.
#[test]
fn a_delayed_loop_may_have_a_hopf_bifurcation() {
    let p = Params::default();
    let f = delayed(&p, 2.0, 1.0).facts();
    assert!(f.hopf_possible && f.damping_at_rest > 0.0, "{f:?}");
    assert_eq!(delayed(&p, 0.0, 1.0).facts(), Model::study(&p).facts());
}

/// A delayed loop with a dither as well is scanned by the method of steps on the averaged
/// motion: with a dither too small to move it (D = 1e-3 at Ω_d = 30), its verdict is the delayed
/// loop's.
#[test]
fn a_delayed_and_dithered_loop_is_scanned() {
    use hdgear::burst::{BurstOptions, classify, response_model};
    let opts = BurstOptions::default();
    for gamma in [0.1, 10.0] {
        let p = Params {
            gamma,
            ..Params::default()
        };
        let m = delayed(&p, 2.0, 0.3);
        let both = m
            .with_term(AnyTerm::new("dither", &[1e-3, 30.0]).unwrap())
            .unwrap();
        let verdict = |m: &Model| {
            let r = response_model(m, &opts).unwrap();
            classify(&m.equivalent_params().unwrap(), &r).verdict
        };
        assert_eq!(verdict(&both), verdict(&m), "γ = {gamma}");
    }
}

/// The linear loop y'' + y' + (k + K)·y − K·y(t − τ_d) = 0 from y = 1, y' = 0 (rest at 0 before
/// t = 0, a kick at the start), by RK4 with step τ_d/200 and the delayed value linearly
/// interpolated between grid points: the largest |y| over the last fifth of [0, t_end] over the
/// largest over the first fifth. Below 1: the loop decays; above: it grows.
fn linear_growth(k: f64, gain: f64, tau: f64, t_end: f64) -> f64 {
    let m = 200;
    let h = tau / m as f64;
    let n = (t_end / h).round() as usize;
    let mut ys: Vec<f64> = vec![1.0];
    let mut y = [1.0, 0.0];
    let past = |ys: &Vec<f64>, t: f64| -> f64 {
        if t <= 0.0 {
            return 0.0;
        }
        let i = (t / h).floor() as usize;
        let f = t / h - i as f64;
        let a = ys[i];
        let b = ys.get(i + 1).copied().unwrap_or(a);
        a + f * (b - a)
    };
    for j in 0..n {
        let t = j as f64 * h;
        let rate = |t: f64, y: [f64; 2], ys: &Vec<f64>| -> [f64; 2] {
            [y[1], -y[1] - (k + gain) * y[0] + gain * past(ys, t - tau)]
        };
        let k1 = rate(t, y, &ys);
        let k2 = rate(
            t + 0.5 * h,
            [y[0] + 0.5 * h * k1[0], y[1] + 0.5 * h * k1[1]],
            &ys,
        );
        let k3 = rate(
            t + 0.5 * h,
            [y[0] + 0.5 * h * k2[0], y[1] + 0.5 * h * k2[1]],
            &ys,
        );
        let k4 = rate(t + h, [y[0] + h * k3[0], y[1] + h * k3[1]], &ys);
        for i in 0..2 {
            y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        ys.push(y[0]);
    }
    let fifth = ys.len() / 5;
    let peak = |s: &[f64]| s.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    peak(&ys[ys.len() - fifth..]) / peak(&ys[..fifth])
}

/// The crossing gain from the characteristic roots is where an independent integration of the
/// linear delayed loop turns from decaying to growing: 10 % below it decays, 10 % above it
/// grows, at a soft, a medium and a stiff equilibrium and two delays.
#[test]
fn the_delay_crossing_gain_is_where_the_linear_loop_turns_unstable() {
    for (k, tau) in [(0.1, 1.0), (14.6, 1.0), (3.0, 0.3), (50.0, 0.3)] {
        let (gain, w) = hdgear::control::crossing_gain(k, tau);
        assert!(gain.is_finite() && gain > 0.0 && w > 0.0, "k = {k}: {gain}");
        let (below, above) = (
            linear_growth(k, 0.9 * gain, tau, 400.0),
            linear_growth(k, 1.1 * gain, tau, 400.0),
        );
        assert!(
            below < 0.5 && above > 2.0,
            "k = {k}, τ_d = {tau}: K = {gain}: growth {below} below, {above} above"
        );
    }
}

/// At the default delay τ_d = 1 the delayed feedback cannot remove the study's bursts while the
/// loop is stable: the tuner says so from the characteristic roots, without simulating the
/// unstable loops above the limit (which took minutes), and the limit is the crossing gain at
/// the stiffness it names. With τ_d = 0.3 a stable gain removes them, below that limit.
#[test]
fn the_delay_law_is_refused_above_its_stability_limit() {
    let p = Params::default();
    let opts = hdgear::burst::BurstOptions::default();
    let limit = hdgear::control::delay_limit(&p, 1.0).unwrap().unwrap();
    assert_eq!(
        hdgear::control::crossing_gain(limit.stiffness, 1.0).0,
        limit.gain
    );
    // the least over the stiffness range the state meets: no sampled stiffness is lower
    let (k_lo, k_hi) = hdgear::control::Plant::stiffness_range(&p).unwrap();
    for j in 0..=1000 {
        let k = k_lo.max(1e-12) + (k_hi - k_lo) * f64::from(j) / 1000.0;
        assert!(hdgear::control::crossing_gain(k, 1.0).0 >= limit.gain * (1.0 - 1e-9));
    }
    match hdgear::control::tune(&p, "delay", &[1.0], &opts, 1e-3) {
        Err(hdgear::Error::NoGain { law, reason }) => {
            assert_eq!(law, "delay");
            assert!(reason.contains("unstable from K"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
    let t = hdgear::control::tune(&p, "delay", &[0.3], &opts, 1e-3).unwrap();
    let short = hdgear::control::delay_limit(&p, 0.3).unwrap().unwrap();
    assert!(t.tuned.gain < short.gain && t.tuned.removes_bursts());
}
