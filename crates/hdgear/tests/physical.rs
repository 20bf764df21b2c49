//! The physical drive: reduction (hand values, α·ε = 1), two-inertia simulation against the
//! reduced model, catalogue fits.

use hdgear::Params;
use hdgear::integrate::Options;
use hdgear::physical::PhysicalParams;
use hdgear::physical::catalogue::{CatalogueDrive, cubic_twist, fit};
use hdgear::physical::simulate::{check_reduction, simulate_physical};
use proptest::prelude::*;

/// A drive near the bursting regime: the dimensionless set (α 16, ε 1/16, γ 1, μ 0.07,
/// δ 15, ω 0.01) mapped back with J_i = 1e-4, J_o = 1, N = 50, C = 5, φ = 1e-3.
fn near_bursting() -> PhysicalParams {
    let p = Params {
        alpha: 16.0,
        gamma: 1.0,
        eps: 1.0 / 16.0,
        ..Params::default()
    };
    PhysicalParams::from_dimensionless(&p, 1e-4, 1.0, 50.0, 5.0, 1e-3).unwrap()
}

#[test]
fn reduction_matches_hand_computation() {
    // J_i = 2e-4, J_o = 0.5, N = 100: N²J_i = 2, J_eq = 2·0.5/2.5 = 0.4; C = 2, k1 = 30,
    // k2 = 4e7, φ = 5e-4, T_m = 3, T_am = 1, Ω = 0.25
    let d = PhysicalParams {
        j_in: 2e-4,
        j_out: 0.5,
        ratio: 100.0,
        k1: 30.0,
        k2: 4e7,
        backlash: 5e-4,
        c_eq: 2.0,
        t_m: 3.0,
        t_am: 1.0,
        omega: 0.25,
    };
    let r = d.reduce().unwrap();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-13 * b.abs();
    assert!(close(r.j_eq, 0.4));
    assert!(close(r.time_scale, 0.2)); // J/C
    // L = C²/(J k2 φ) = 4/(0.4·4e7·5e-4) = 4/8000 = 5e-4
    assert!(close(r.length_scale, 5e-4));
    // α = C²/(k2 φ² J) = 4/(4e7·2.5e-7·0.4) = 4/4 = 1
    assert!(close(r.params.alpha, 1.0));
    // γ = k1 J/C² = 30·0.4/4 = 3
    assert!(close(r.params.gamma, 3.0));
    // ε = k2 φ² J/C² = 4/4 = 1
    assert!(close(r.params.eps, 1.0));
    // μ = k2 φ J² T_m/C⁴ = 4e7·5e-4·0.16·3/16 = 600
    assert!(close(r.params.mu, 600.0));
    // δ = k2 φ J³ T_am/(J_o C⁴) = 4e7·5e-4·0.064·1/(0.5·16) = 160
    assert!(close(r.params.delta, 160.0));
    // ω = Ω J/C = 0.25·0.2 = 0.05
    assert!(close(r.params.omega, 0.05));
}

fn any_drive() -> impl Strategy<Value = PhysicalParams> {
    (
        (-6.0f64..-1.0, -2.0f64..2.0, 0.5f64..2.5),
        (0.0f64..6.0, 4.0f64..12.0, -5.0f64..-2.0),
        (-2.0f64..2.0, -2.0f64..2.0, -2.0f64..1.0, -1.0f64..1.5),
    )
        .prop_map(
            |((ji, jo, n), (k1, k2, phi), (c, tm, tam, om))| PhysicalParams {
                j_in: 10f64.powf(ji),
                j_out: 10f64.powf(jo),
                ratio: 10f64.powf(n),
                k1: 10f64.powf(k1),
                k2: 10f64.powf(k2),
                backlash: 10f64.powf(phi),
                c_eq: 10f64.powf(c),
                t_m: 10f64.powf(tm),
                t_am: 10f64.powf(tam),
                omega: 10f64.powf(om),
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]
    #[test]
    fn alpha_times_eps_is_one_for_every_drive(d in any_drive()) {
        let r = d.reduce().unwrap();
        prop_assert!((r.params.alpha * r.params.eps - 1.0).abs() < 1e-12);
        prop_assert!(r.params.validate().unwrap().is_empty(), "no α·ε warning for a physical set");
        // the way back recovers the drive
        let back = PhysicalParams::from_dimensionless(&r.params, d.j_in, d.j_out, d.ratio, d.c_eq, d.backlash).unwrap();
        for (a, b) in [(back.k1, d.k1), (back.k2, d.k2), (back.t_m, d.t_m), (back.t_am, d.t_am), (back.omega, d.omega)] {
            prop_assert!((a - b).abs() <= 1e-12 * b.abs(), "{a} vs {b}");
        }
    }
}

#[test]
fn two_inertia_torsion_equals_the_reduced_model() {
    let d = near_bursting();
    let r = d.reduce().unwrap();
    assert!((r.params.gamma - 1.0).abs() < 1e-12);
    // 400 dimensionless time units (through a burst near a ≈ 0), both at rtol = atol = 1e-12:
    // the models are the same equations in other units, so they agree to the tolerance
    let c = check_reduction(&d, 400.0, 0.5, 1e-12).unwrap();
    eprintln!("relative deviation: {c:?}");
    assert!(c.time < 1e-9, "sample times: {}", c.time);
    assert!(c.theta < 1e-8, "theta: {:e}", c.theta);
    assert!(c.theta_dot < 1e-8, "theta_dot: {:e}", c.theta_dot);
}

#[test]
fn catalogue_fits_reproduce_the_twist() {
    for name in ["CSF-14-50", "CSF-20-50", "CSF-32-50", "CSF-32-30"] {
        let d = CatalogueDrive::by_name(name).unwrap();
        let f = fit(&d, d.t2).unwrap();
        eprintln!(
            "{}: k1 {:.4e} k2 {:.4e}; twist error at T1 {:.2} %, at T2 {:.2} %, max torque error {:.2} % of T2",
            d.name,
            f.k1,
            f.k2,
            100.0 * f.twist_error_t1,
            100.0 * f.twist_error_t2,
            100.0 * f.max_torque_error
        );
        assert!(f.k1 > 0.0 && f.k2 > 0.0, "{}: stiffening curve", d.name);
        // the stated bar: the fitted law gives the catalogue twist at T1 and T2 within 5 %
        // (measured: 3.0–4.5 % at T1, 3.0–3.7 % at T2)
        assert!(f.twist_error_t1 < 0.05, "{}: {}", d.name, f.twist_error_t1);
        assert!(f.twist_error_t2 < 0.05, "{}: {}", d.name, f.twist_error_t2);
        // the fit evaluates what it claims: cubic_twist inverts the fitted law
        let th = cubic_twist(f.k1, f.k2, d.t2);
        assert!((f.k1 * th + f.k2 * th.powi(3) - d.t2).abs() < 1e-9 * d.t2);
    }
    // with a third segment above T2 and no rating, the curve is used up to 2·T2
    let d = CatalogueDrive::by_name("csf-32-30").unwrap();
    assert!(fit(&d, 1.5 * d.t2).is_ok());
    assert!(fit(&CatalogueDrive::by_name("CSF-14-50").unwrap(), 14.0).is_err());
    // with a rating, up to the momentary peak torque
    let d = CatalogueDrive::by_name("CSG-20-50").unwrap();
    assert!(fit(&d, 127.0).is_ok() && fit(&d, 128.0).is_err());
}

#[test]
fn zero_backlash_or_linear_stiffness_has_no_reduction() {
    let mut d = near_bursting();
    d.backlash = 0.0;
    let e = d.reduce().unwrap_err().to_string();
    assert!(
        e.contains("backlash = 0") && e.contains("simulate the physical model"),
        "{e}"
    );
    // ...while the physical model still simulates
    let s = simulate_physical(&d, 1.0, 0.1, Options::default(), |_| {}).unwrap();
    assert!(s.final_state.theta.is_finite());
    let mut d = near_bursting();
    d.k2 = 0.0;
    assert!(d.reduce().unwrap_err().to_string().contains("k2 = 0"));
}

#[test]
fn every_design_margin_of_the_bursting_variant_is_real() {
    // the report's bursting variant of CSF-20-50: each reported factor f is checked by simulating
    // the drive at 0.97 f and 1.03 f: the verdicts must differ (bursting inside, not outside)
    use hdgear::burst::BurstOptions;
    use hdgear::physical::design::{design_check, judge};
    let (d, _) = hdgear::physical::catalogue::preset("CSF-20-50", None).unwrap();
    let d = PhysicalParams {
        k1: 2000.0,
        t_am: 112.0,
        ..d
    };
    let o = BurstOptions::default();
    let c = design_check(&d, &o).unwrap();
    assert!(c.judgement.bursting);
    let mut checked = 0;
    for m in &c.margins {
        let Some(f) = m.factor else { continue };
        let at = |g: f64| judge(&d.with(m.parameter, m.current * g), &o).unwrap();
        // inside is the side nearer to the current value
        let (near, far) = if f > 1.0 {
            (0.97 * f, 1.03 * f)
        } else {
            (1.03 * f, 0.97 * f)
        };
        let (jn, jf) = (at(near), at(far));
        assert!(
            jn.bursting && !jf.bursting,
            "{}: x{near} {jn:?}, x{far} {jf:?}",
            m.parameter
        );
        assert!(m.inside.unwrap().judgement.bursting);
        assert!(!m.outside.unwrap().judgement.bursting);
        checked += 1;
    }
    assert_eq!(checked, 6, "{:?}", c.margins);
}

/// The twist range over the last two disturbance periods of a two-inertia simulation from rest
/// at `hz`, long enough (100 decay times J_eq/C) for the transient to be gone.
fn simulated_twist_range(d: &PhysicalParams, hz: f64) -> (f64, f64) {
    let d = PhysicalParams {
        omega: std::f64::consts::TAU * hz,
        ..*d
    };
    let period = 1.0 / hz;
    let t_end = ((100.0 * d.j_eq() / d.c_eq) / period).ceil() * period + 2.0 * period;
    let tol = Options {
        rtol: 1e-11,
        atol: 1e-13,
        ..Options::default()
    };
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    simulate_physical(&d, t_end, period / 4000.0, tol, |s| {
        if s.t >= t_end - 2.0 * period {
            lo = lo.min(s.theta);
            hi = hi.max(s.theta);
        }
    })
    .unwrap();
    (lo, hi)
}

#[test]
fn a_drives_frequency_response_in_si_units_is_what_the_two_inertia_model_does() {
    use hdgear::periodic::{ContinuationOptions, physical_frequency_response};
    let (drive, _) = hdgear::physical::catalogue::preset("CSF-20-50", None).unwrap();
    // the catalogue drive near its resonance, and the softer, harder-driven variant of the
    // report on its upper (resonant) branch
    let variant = PhysicalParams {
        k1: 2000.0,
        t_am: 112.0,
        ..drive
    };
    for (d, hz) in [(drive, 104.3), (variant, 150.0)] {
        // the curve from hz/2 up to hz: its last point is at hz exactly
        let r =
            physical_frequency_response(&d, Some((hz / 2.0, hz)), &ContinuationOptions::default())
                .unwrap();
        let q = r.points.last().unwrap();
        assert!((q.frequency_hz - hz).abs() < 1e-9 * hz && q.stable);
        let (lo, hi) = simulated_twist_range(&d, hz);
        // sampling 4000 times a period misses an extremum by at most (π/4000)²/2 ≈ 3e-7 of the
        // amplitude; 1e-5 of the peak-to-peak bounds that and the tolerances
        let tol = 1e-5 * q.twist_peak_to_peak;
        assert!(
            (lo - q.twist_range[0]).abs() < tol && (hi - q.twist_range[1]).abs() < tol,
            "{hz} Hz: simulated {lo:e} … {hi:e}, curve {:e} … {:e}",
            q.twist_range[0],
            q.twist_range[1]
        );
        // the torque range is the stiffness law's range on the twist range
        let t = |th: f64| (d.k1 + d.k2 * th * th) * (th - d.backlash);
        assert!(q.torque_range[1] >= t(hi) - 1e-9 * t(hi).abs());
    }
}

/// The largest difference of column `i` of two equally sampled records, relative to the largest
/// magnitude of the second.
fn gap(a: &[[f64; 2]], b: &[[f64; 2]], i: usize) -> f64 {
    assert_eq!(a.len(), b.len());
    let peak = b.iter().map(|q| q[i].abs()).fold(0.0, f64::max);
    let worst = a
        .iter()
        .zip(b)
        .map(|(p, q)| (p[i] - q[i]).abs())
        .fold(0.0, f64::max);
    worst / peak
}

/// Friction across the compliance, in the two-inertia model (a term of its twist model, in the
/// drive's units) and in the reduced model (the same law in the reduction's units): the
/// reduction is exact for torques across the compliance, so θ(t) = L·x(t/T) to the tolerance,
/// as without friction. Two integrations of different systems, one the other's check.
#[test]
fn friction_across_the_compliance_is_the_reduced_models_friction() {
    use hdgear::integrate::sample;
    use hdgear::model::Model;
    use hdgear::model::terms::AnyTerm;
    use hdgear::physical::model::Physical;
    use hdgear::physical::simulate::simulate_drive;
    let d = near_bursting();
    let r = d.reduce().unwrap();
    let sys = Physical::new(d);
    let tight = Options {
        rtol: 1e-12,
        atol: 1e-12,
        ..Options::default()
    };
    // a sizeable friction: 2 % of the mean torque, regularised over a tenth of the rates the
    // burst reaches (F [N m], v [rad/s]); the Stribeck law limits the steps by its own series
    let (f, v) = (0.02 * d.t_m, 0.1 * r.theta_dot(1.0));
    let laws = [
        ("friction", [f, v].to_vec(), [true, false].to_vec()),
        (
            "stribeck",
            [f, 1.5 * f, v, 0.01 * d.c_eq, 0.1 * v].to_vec(),
            [true, true, false, false, false].to_vec(),
        ),
    ];
    for (kind, si, is_torque) in laws {
        // in units of: the torque's U (drive) or unit (reduction); v's T_c (drive) or T/L
        let scaled = |torque: f64, speed: f64, damping: f64| -> Vec<f64> {
            si.iter()
                .zip(&is_torque)
                .enumerate()
                .map(|(i, (&x, &t))| match (t, kind, i) {
                    (true, _, _) => x / torque,
                    (false, "stribeck", 3) => x / damping,
                    _ => x * speed,
                })
                .collect()
        };
        let in_drive = scaled(sys.unit(), sys.t_c(), d.c_eq);
        let in_reduction = scaled(r.torque_unit(), r.time_scale / r.length_scale, d.c_eq);
        let four = sys
            .with_twist(AnyTerm::new(kind, &in_drive).unwrap())
            .unwrap();
        // the SI law converts into the same twist model (to the rounding of its products)
        let si_law = sys.with_twist_friction(AnyTerm::new(kind, &si).unwrap());
        let converted = *si_law.unwrap().twist().terms().last().unwrap();
        for (a, b) in converted.values().iter().zip(&in_drive) {
            assert!((a - b).abs() <= 1e-15 * b.abs(), "{kind}: {a} against {b}");
        }
        let one = Model::study(&r.params)
            .with_term(AnyTerm::new(kind, &in_reduction).unwrap())
            .unwrap();
        let (tau_end, dtau) = (150.0, 0.5);
        let mut theta = Vec::new();
        simulate_drive(&four, r.time(tau_end), r.time(dtau), tight, |s| {
            theta.push([s.theta, s.theta_dot]);
        })
        .unwrap();
        let mut x = Vec::new();
        sample(&one, 0.0, [0.0; 2], tau_end, dtau, tight, |_, y| {
            x.push([r.theta(y[0]), r.theta_dot(y[1])]);
        })
        .unwrap();
        let (th, th_dot) = (gap(&theta, &x, 0), gap(&theta, &x, 1));
        eprintln!("{kind}: theta {th:e}, theta_dot {th_dot:e}");
        assert!(th < 1e-8 && th_dot < 1e-8, "{kind}");
        // and the friction matters: without it the twist differs by far more
        let mut free = Vec::new();
        simulate_drive(&sys, r.time(tau_end), r.time(dtau), tight, |s| {
            free.push([s.theta, s.theta_dot]);
        })
        .unwrap();
        let bare = gap(&free, &x, 0);
        assert!(
            bare > 1e-4,
            "{kind}: friction changes the twist by {bare:e} only"
        );
    }
}

/// The two-inertia model takes only what it integrates correctly across the compliance, and
/// says which term it refused; the spring in the reduction's units is the study's stiffness
/// where α·ε = 1.
#[test]
fn the_twist_refuses_states_switches_and_loads_and_its_spring_is_the_studys() {
    use hdgear::model::terms::{AnyTerm, Spring, Stiffness, Term};
    use hdgear::physical::model::Physical;
    let sys = Physical::new(near_bursting());
    for kind in [
        "coulomb",
        "lugre",
        "boucwen",
        "dither",
        "multisine",
        "kinematic",
    ] {
        let values: Vec<f64> = AnyTerm::params_of(kind)
            .unwrap()
            .iter()
            .map(|p| p.default)
            .collect();
        let e = sys
            .with_twist(AnyTerm::new(kind, &values).unwrap())
            .unwrap_err()
            .to_string();
        assert!(e.contains(kind), "{e}");
    }
    let friction = AnyTerm::new("friction", &[0.1, 0.2]).unwrap();
    let stribeck = AnyTerm::new("stribeck", &[0.1, 0.2, 0.1, 0.0, 0.01]).unwrap();
    let piecewise = AnyTerm::new(
        "piecewise",
        &AnyTerm::params_of("piecewise")
            .unwrap()
            .iter()
            .map(|p| p.default)
            .collect::<Vec<_>>(),
    )
    .unwrap();
    let full = sys
        .with_twist(friction)
        .unwrap()
        .with_twist(piecewise)
        .unwrap();
    assert!(
        full.with_twist(stribeck)
            .unwrap_err()
            .to_string()
            .contains("at most")
    );
    let (alpha, gamma) = (16.0, 0.7);
    let spring = Spring::from_values(&[gamma, alpha, 1.0 / alpha]);
    let study = Stiffness::from_values(&[alpha, gamma, 1.0 / alpha]);
    for x in [-2.0, -0.3, 0.0, 0.05, 1.0, 3.0] {
        let (a, b) = (spring.torque(x, 0.0, 0.0), study.torque(x, 0.0, 0.0));
        assert!((a - b).abs() <= 1e-13 * (1.0 + b.abs()), "{x}: {a} {b}");
        let (ga, gb) = (
            spring.gradient(x, 0.0, 0.0)[0],
            study.gradient(x, 0.0, 0.0)[0],
        );
        assert!(
            (ga - gb).abs() <= 1e-13 * (1.0 + gb.abs()),
            "{x}: {ga} {gb}"
        );
    }
}

/// The held wave generator's reduction ([`PhysicalParams::reduce_held`]) against the held
/// drive's own equation, J_o θ'' + C θ' + (k1 + k2θ²)(θ − φ) = T_m + T_am sin Ωt, integrated
/// here by the classic Runge–Kutta rule at a fixed step h = T/4000 (its error falls as h⁴: 2.6e-9,
/// 1.6e-10 and 6.3e-13 of the peak at 8h, 4h and h): the reduced model's θ = L·x(t/T) at
/// tolerance 1e-12 meets it to 1e-11 of the peak, and the free input's reduction is another
/// motion.
#[test]
fn the_held_inputs_reduction_is_the_held_drives_own_equation() {
    use hdgear::simulate::{SimOptions, Start, simulate};
    let d = near_bursting();
    let (held, free) = (d.reduce_held().unwrap(), d.reduce().unwrap());
    let (t_end, samples) = (held.time(150.0), 300);
    let dt = t_end / f64::from(samples);
    let tight = Options {
        rtol: 1e-12,
        atol: 1e-12,
        ..Options::default()
    };
    let run = |r: &hdgear::physical::Reduction| {
        let mut out = Vec::new();
        let opts = SimOptions {
            t_end: r.tau(t_end),
            dt: r.tau(dt),
            start: Start::Rest,
            tol: tight,
        };
        simulate(&r.params, &opts, |_, y| {
            out.push([r.theta(y[0]), r.theta_dot(y[1])])
        })
        .unwrap();
        out
    };
    // the held drive's equation, by RK4 from rest
    let f = |t: f64, [th, w]: [f64; 2]| {
        let spring = (d.k1 + d.k2 * th * th) * (th - d.backlash);
        let load = d.t_m + d.t_am * (d.omega * t).sin();
        [w, (load - d.c_eq * w - spring) / d.j_out]
    };
    let steps_per_sample = 2000;
    let h = dt / f64::from(steps_per_sample);
    let mut y = [0.0; 2];
    let mut own = vec![y];
    for sample in 0..samples {
        for step in 0..steps_per_sample {
            // the time by a product, not by a sum of steps, which would drift by its roundings
            let t = f64::from(sample) * dt + f64::from(step) * h;
            let add = |a: [f64; 2], b: [f64; 2], s: f64| [a[0] + s * b[0], a[1] + s * b[1]];
            let k1 = f(t, y);
            let k2 = f(t + 0.5 * h, add(y, k1, 0.5 * h));
            let k3 = f(t + 0.5 * h, add(y, k2, 0.5 * h));
            let k4 = f(t + h, add(y, k3, h));
            for i in 0..2 {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
        }
        own.push(y);
    }
    let reduced = run(&held);
    assert_eq!(reduced.len(), own.len());
    for i in 0..2 {
        let g = gap(&reduced, &own, i);
        assert!(g < 1e-11, "component {i}: {g:e}");
    }
    // the free input's reduction is another motion: the disturbance reaches its twist in part
    assert!(gap(&run(&free)[..], &own, 0) > 1e-3);
}
