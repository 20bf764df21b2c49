//! The burst verdict on a model with sticking friction ([`hdgear::burst::response_model`] on a
//! switching model): the same scan run piece by piece, its rests measured ([`StickSlip`]), and
//! stick-slip as a signature and a mechanism.

use hdgear::Params;
use hdgear::burst::{
    BurstOptions, Mechanism, Response, StickSlip, Verdict, classify, response, response_model,
};
use hdgear::model::Model;
use hdgear::model::terms::AnyTerm;

/// The study's model at `p` with Coulomb–Stribeck friction f_c, f_s, v_st (no viscous part),
/// judged.
fn judged(p: &Params, fc: f64, fs: f64, vst: f64) -> (Response, StickSlip) {
    let m = Model::study(p)
        .with_term(AnyTerm::new("coulomb", &[fc, fs, vst, 0.0]).unwrap())
        .unwrap();
    let r = response_model(&m, &BurstOptions::default()).unwrap();
    let k = r
        .sticking
        .expect("a switching model's response measures its rests");
    (r, k)
}

fn at(gamma: f64, omega: f64) -> Params {
    Params {
        gamma,
        omega,
        ..Params::default()
    }
}

/// With no friction the piece-by-piece run (steps cut wherever x' passes 0) is the study's model:
/// at the study's four points (γ = 30, 10: no bursts; 1, 0.1: bursts) the verdict and the burst
/// count are the study's, and the peak |x'| agrees within the integration tolerance's reach.
#[test]
fn without_friction_the_piecewise_verdict_is_the_study_s() {
    for gamma in [30.0, 10.0, 1.0, 0.1] {
        let p = at(gamma, 0.01);
        let study = response(&p, &BurstOptions::default()).unwrap();
        let (r, k) = judged(&p, 0.0, 0.0, 0.1);
        assert_eq!(classify(&p, &r), classify(&p, &study), "γ = {gamma}");
        assert_eq!(r.rates.bursts_per_period, study.rates.bursts_per_period);
        let peak = study.rates.peak_abs_xdot;
        let diff = (r.rates.peak_abs_xdot - peak).abs() / peak;
        println!("γ = {gamma}: peak |x'| {peak:.6}, relative difference {diff:.1e}");
        assert!(diff < 1e-6, "γ = {gamma}: {diff:e}");
        assert_eq!((k.sticks_per_period, k.stuck_fraction), (0.0, 0.0));
        assert!(!k.stick_slip() && !k.slip_dominates);
    }
}

/// With f_c = f_s = f the drive sticks at each turning point of the load and breaks away once the
/// load has fallen by 2f: as ω → 0 the rest lasts acos(1 − 2f/δ)/ω (the quasi-static limit,
/// whatever the stiffness). The measured rest converges to it at first order in ω (the stop comes
/// a fast time after the turning point): the error falls 5× when ω does.
#[test]
fn a_rest_at_the_load_s_turning_point_lasts_as_the_quasi_static_limit_says() {
    for (gamma, f) in [(2.0, 0.5), (30.0, 0.5), (10.0, 1.0)] {
        let errors: Vec<f64> = [0.01, 0.002]
            .iter()
            .map(|&omega| {
                let p = at(gamma, omega);
                let (_, k) = judged(&p, f, f, 0.1);
                assert_eq!(k.sticks_per_period, 2.0, "one rest per turning point");
                let limit = (1.0 - 2.0 * f / p.delta).acos() / omega;
                (k.max_stick - limit) / limit
            })
            .collect();
        println!("γ = {gamma}, f = {f}: relative errors {errors:?}");
        assert!(errors[1].abs() < 2e-4, "{errors:?}");
        let order = (errors[0] / errors[1]).ln() / 5f64.ln();
        assert!((0.8..1.2).contains(&order), "order {order}");
    }
}

/// Static friction above the kinetic (f_s > f_c) with a sharp Stribeck drop (v_st = 1e-3): each
/// breakaway releases Δ = f_s − f_c at once on the spring, the slip of a damped oscillator
/// u'' + u' + k·u = Δ from rest, k = g'(x) there. Its speed peaks at t* = atan(2ω_d)/ω_d
/// (ω_d = √(k − 1/4)) at Δ·e^{−t*/2}/√k. At the study's stiff point γ = 30 (no bursts without
/// friction) the slips are the bursts: stick-slip, the motion sticking many times per period
/// (chatter), not only at the load's two turning points, and the largest slip within the closed
/// form's range over the traversed k, widened by the equilibrium's own speed (≤ ωδ/k) and the
/// drop's width (v_st).
#[test]
fn a_drop_from_static_to_kinetic_friction_makes_the_slips_the_bursts() {
    let p = at(30.0, 0.01);
    let study = classify(&p, &response(&p, &BurstOptions::default()).unwrap());
    assert_eq!(study.verdict, Verdict::NoBursts);
    let (fc, vst) = (0.5, 1e-3);
    let peaks: Vec<f64> = [0.5, 1.0, 2.0]
        .iter()
        .map(|&fs| judged(&p, fc, fs, vst).1.slip_peak_speed)
        .collect();
    println!("slip peak speeds for f_s = 0.5, 1, 2: {peaks:.4?}");
    // the released slip is linear in the drop Δ: 1.5 against 0.5
    assert!((peaks[2] / peaks[1] / 3.0 - 1.0).abs() < 0.05, "{peaks:?}");
    let fs = 2.0;
    let (r, k) = judged(&p, fc, fs, vst);
    let c = classify(&p, &r);
    assert_eq!(
        (c.verdict, c.mechanism),
        (Verdict::StickSlip, Mechanism::StickSlip)
    );
    assert!(k.slip_dominates && k.sticks_per_period > 2.0, "{k:?}");
    // the largest slip is the window's largest |x'|
    assert_eq!(k.slip_peak_speed, r.rates.peak_abs_xdot);
    // the closed form over the stiffness the motion traverses (x within the loads' reach)
    let peak = |k: f64| {
        let wd = (k - 0.25).sqrt();
        let t = (2.0 * wd).atan() / wd;
        (fs - fc) * (-t / 2.0).exp() / k.sqrt()
    };
    let (lo, hi) = (p.mu - p.delta - fs, p.mu + p.delta + fs);
    let xs: Vec<f64> = (0..=1000)
        .map(|i| lo + (hi - lo) * f64::from(i) / 1000.0)
        .map(|load| hdgear::fast::stable_equilibrium(&p, (load - p.mu) / p.delta))
        .collect();
    let ks: Vec<f64> = xs.iter().map(|&x| p.g_prime(x)).collect();
    let (kmin, kmax) = ks
        .iter()
        .fold((f64::MAX, 0.0_f64), |(a, b), &k| (a.min(k), b.max(k)));
    let slack = p.omega * p.delta / kmin + vst;
    println!(
        "largest slip {:.5}; closed form {:.5} … {:.5} for k in {kmin:.2} … {kmax:.2}, ± {slack:.5}",
        k.slip_peak_speed,
        peak(kmax),
        peak(kmin)
    );
    assert!(k.slip_peak_speed >= peak(kmax) - slack && k.slip_peak_speed <= peak(kmin) + slack);
}
