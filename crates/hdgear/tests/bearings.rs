//! Friction at the bearings of the two-inertia drive (output bearing on θo', wave generator on
//! θi'), checked against references written here from the equations: the closed-form steady
//! response of the linear drive with viscous bearings, and a fourth-order Runge–Kutta run of
//! the drive with Stribeck friction at both bearings, in the raw coordinates (θi, θi', θo, θo'),
//! with its energy balance.

use crate::common::rk4_run;
use hdgear::integrate::Options;
use hdgear::model::terms::AnyTerm;
use hdgear::physical::PhysicalParams;
use hdgear::physical::model::{Bearings, Physical};
use hdgear::physical::simulate::{PhysicalSample, simulate_drive, simulate_physical};

/// Tight tolerances: the references below are accurate to ~1e-12 of the response.
fn tight() -> Options {
    Options {
        rtol: 1e-13,
        atol: 1e-13,
        ..Options::default()
    }
}

/// A drive whose rigid-body mode the bearings damp: J_o = N²J_i = 0.25 kg m² (N = 50), a
/// torsional mode of √(k1/J_eq) = 89 rad/s damped by C = 5 N m s/rad.
fn drive(k2: f64, t_m: f64) -> PhysicalParams {
    PhysicalParams {
        j_in: 1e-4,
        j_out: 0.25,
        ratio: 50.0,
        k1: 1e3,
        k2,
        backlash: if k2 > 0.0 { 1e-3 } else { 0.0 },
        c_eq: 5.0,
        t_m,
        t_am: 1.0,
        omega: 3.0,
    }
}

/// A Stribeck law (f_c, f_s, v_st, c_v, v_r) as a bearing's term.
fn stribeck(v: [f64; 5]) -> AnyTerm {
    AnyTerm::new("stribeck", &v).unwrap()
}

/// Complex numbers, as far as the closed form needs them.
type C = (f64, f64);
fn mul(a: C, b: C) -> C {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}
fn div(a: C, b: C) -> C {
    let n = b.0 * b.0 + b.1 * b.1;
    ((a.0 * b.0 + a.1 * b.1) / n, (a.1 * b.0 - a.0 * b.1) / n)
}
fn sub(a: C, b: C) -> C {
    (a.0 - b.0, a.1 - b.1)
}

/// Viscous bearings (c_o on θo', c_i on θi') on the linear drive (k2 = φ = T_m = 0): the
/// steady response to T_am sin Ωt is Im(Θ e^{iΩt}) with (Θo, Θi) from
/// [−Ω²J_o + iΩ(C + c_o) + k1]Θo − [(iΩC + k1)/N]Θi = T_am and
/// −[(iΩC + k1)/N]Θo + [−Ω²J_i + iΩ(C/N² + c_i) + k1/N²]Θi = 0. After five periods (10.5
/// seconds of drive time) the transients (rates 4/s and faster) are below 1e-17 of it.
#[test]
fn viscous_bearings_give_the_closed_form_steady_response() {
    let d = drive(0.0, 0.0);
    let (c_o, c_i) = (1.0, 4e-4);
    // f_c = f_s = 0: the law is c_v·v alone
    let b = Bearings::new(
        Some(stribeck([0.0, 0.0, 1.0, c_o, 1.0])),
        Some(stribeck([0.0, 0.0, 1.0, c_i, 1.0])),
    )
    .unwrap();
    let (w, n) = (d.omega, d.ratio);
    let coupling = (d.k1 / n, w * d.c_eq / n);
    let a11 = (d.k1 - w * w * d.j_out, w * (d.c_eq + c_o));
    let a22 = (
        d.k1 / (n * n) - w * w * d.j_in,
        w * (d.c_eq / (n * n) + c_i),
    );
    // Cramer: det = a11·a22 − coupling², Θo = T·a22/det, Θi = T·coupling/det
    let det = sub(mul(a11, a22), mul(coupling, coupling));
    let (out, inp) = (div((d.t_am, 0.0), det), div((d.t_am, 0.0), det));
    let (out, inp) = (mul(out, a22), mul(inp, coupling));
    let at = |z: C, t: f64| z.0 * (w * t).sin() + z.1 * (w * t).cos();
    let twist = sub(out, div(inp, (n, 0.0)));
    let amplitude = |z: C| z.0.hypot(z.1);
    let period = std::f64::consts::TAU / w;
    let (t_end, dt) = (5.0 * period, period / 64.0);
    // the 64 samples of the last period, its end left out: (t, θo, θi, θ)
    let last = |s: &PhysicalSample| {
        let within = s.t > t_end - period - dt / 2.0 && s.t < t_end - dt / 2.0;
        within.then_some([s.t, s.theta_out, s.theta_in, s.theta])
    };
    let mut rows = Vec::new();
    let sys = Physical::with_bearings(d, b);
    simulate_drive(&sys, t_end, dt, tight(), |s| rows.extend(last(s))).unwrap();
    assert_eq!(rows.len(), 64);
    // nothing restores the rigid-body rotation: θo and θi keep the offset the start left them
    // (the same θo − θi/N), the mean of the samples over a period less the response's mean 0
    let offset = |i: usize, z: C| rows.iter().map(|r| r[i] - at(z, r[0])).sum::<f64>() / 64.0;
    let (off_out, off_in) = (offset(1, out), offset(2, inp));
    let mut worst: f64 = 0.0;
    for r in &rows {
        worst = worst
            .max((r[1] - off_out - at(out, r[0])).abs() / amplitude(out))
            .max((r[2] - off_in - at(inp, r[0])).abs() / amplitude(inp))
            .max((r[3] - at(twist, r[0])).abs() / amplitude(twist));
    }
    assert!(
        worst < 1e-9,
        "largest error over the response amplitude {worst:e}"
    );
    assert!((off_out - off_in / n).abs() < 1e-9 * amplitude(twist));
    // without the bearings the twist responds otherwise: the check can tell them apart
    let mut apart: f64 = 0.0;
    simulate_physical(&d, t_end, dt, tight(), |s| {
        if let Some(r) = last(s) {
            apart = apart.max((r[3] - at(twist, r[0])).abs() / amplitude(twist));
        }
    })
    .unwrap();
    // 1.5e-3: six orders above the agreement with the closed form
    assert!(apart > 1e-4, "the bearings change the twist: {apart:e}");
}

/// The raw two-inertia equations with friction F_o, F_i at the bearings, plus the work put in
/// and the energy dissipated as two more states: y = (θi, θi', θo, θo', W, D).
fn raw(d: &PhysicalParams, b: &Bearings, t: f64, y: [f64; 6]) -> [f64; 6] {
    let [thi, wi, tho, wo, ..] = y;
    let (th, thd) = (tho - thi / d.ratio, wo - wi / d.ratio);
    let spring = (d.k1 + d.k2 * th * th) * (th - d.backlash);
    let across = d.c_eq * thd + spring;
    let [f_o, f_i] = b.torques(wo, wi);
    let load = d.t_m + d.t_am * (d.omega * t).sin();
    [
        wi,
        (-d.t_m / d.ratio + across / d.ratio - f_i) / d.j_in,
        wo,
        (load - across - f_o) / d.j_out,
        load * wo - d.t_m / d.ratio * wi,
        d.c_eq * thd * thd + f_o * wo + f_i * wi,
    ]
}

/// Stribeck friction at both bearings of the cubic drive under a mean and a slow torque: the
/// response equals the reference run to 1e-9 of its scale, and energy balances: the stored
/// energy at the end is the work put in less the dissipation (friction a good share of it).
#[test]
fn stribeck_bearings_match_an_independent_run_and_balance_energy() {
    let d = drive(2e8, 2.0);
    let b = Bearings::new(
        Some(stribeck([0.3, 0.45, 0.05, 0.02, 5e-3])),
        Some(stribeck([0.01, 0.015, 2.0, 1e-5, 0.25])),
    )
    .unwrap();
    let t_end = 2.0;
    let s = simulate_drive(
        &Physical::with_bearings(d, b),
        t_end,
        t_end,
        tight(),
        |_| {},
    )
    .unwrap();
    let f = |t, y| raw(&d, &b, t, y);
    let (r, half) = (
        rk4_run(f, [0.0; 6], 1e-5, t_end),
        rk4_run(f, [0.0; 6], 5e-6, t_end),
    );
    // the reference's own error, from halving its step (RK4: 1/16 of the difference)
    let scale = r[2].abs().max(r[0].abs() / d.ratio);
    for i in 0..4 {
        assert!((r[i] - half[i]).abs() < 1e-10 * scale.max(r[1].abs()));
    }
    let [
        theta_in,
        theta_in_dot,
        theta_out,
        theta_out_dot,
        work,
        dissipated,
    ] = half;
    let got = s.report().final_state;
    let theta = theta_out - theta_in / d.ratio;
    for (a, b, what) in [
        (got.theta_out, theta_out, "θo"),
        (got.theta_in / d.ratio, theta_in / d.ratio, "θi/N"),
        (got.theta_out_dot, theta_out_dot, "θo'"),
        (got.theta_in_dot / d.ratio, theta_in_dot / d.ratio, "θi'/N"),
    ] {
        let scale = theta_out.abs().max(theta_out_dot.abs());
        assert!((a - b).abs() < 1e-9 * scale, "{what}: {a} against {b}");
    }
    assert!(
        (got.theta - theta).abs() < 1e-9 * theta.abs(),
        "θ: {} against {theta}",
        got.theta
    );
    // energy: ½J_oθo'² + ½J_iθi'² + ∫T(θ)dθ, from hdgear's final state
    let potential = |x: f64| {
        d.k1 * (x * x / 2.0 - d.backlash * x)
            + d.k2 * (x.powi(4) / 4.0 - d.backlash * x.powi(3) / 3.0)
    };
    let stored = 0.5 * d.j_out * got.theta_out_dot.powi(2)
        + 0.5 * d.j_in * got.theta_in_dot.powi(2)
        + potential(got.theta)
        - potential(0.0);
    assert!(
        (stored - (work - dissipated)).abs() < 1e-8 * work.abs(),
        "stored {stored} against work {work} − dissipated {dissipated}"
    );
    let damper = {
        let frictionless = Bearings::default();
        let f = |t, y| raw(&d, &frictionless, t, y);
        rk4_run(f, [0.0; 6], 1e-5, t_end)[5]
    };
    assert!(
        dissipated > 0.0 && damper > 0.0 && (dissipated - damper).abs() > 0.1 * damper,
        "friction dissipates a share: {dissipated} with it, {damper} without"
    );
}

/// Bearings whose laws vanish (every coefficient 0) leave the drive's response as it is
/// without them, and a bearing refuses a law that is not of the velocity alone.
#[test]
fn vanishing_bearings_change_nothing_and_other_terms_are_refused() {
    let d = drive(2e8, 2.0);
    let zero = stribeck([0.0, 0.0, 1.0, 0.0, 1.0]);
    let with = simulate_drive(
        &Physical::with_bearings(d, Bearings::new(Some(zero), Some(zero)).unwrap()),
        0.5,
        0.5,
        tight(),
        |_| {},
    )
    .unwrap();
    let without = simulate_physical(&d, 0.5, 0.5, tight(), |_| {}).unwrap();
    assert_eq!(with.final_state, without.final_state);
    for kind in ["stiffness", "coulomb", "lugre"] {
        let params = AnyTerm::params_of(kind).unwrap();
        let values: Vec<f64> = params.iter().map(|p| p.default).collect();
        let term = AnyTerm::new(kind, &values).unwrap();
        let e = Bearings::new(None, Some(term)).unwrap_err().to_string();
        assert!(e.contains(kind) && e.contains("input"), "{e}");
    }
}
