//! The quasi-static branches x±(a) of models with friction and hysteresis
//! ([`Model::branches`]) against closed forms, and against slow simulations, which must follow
//! them more closely the slower the load.

use hdgear::Params;
use hdgear::model::Model;
use hdgear::model::branches::LoopBranch;
use hdgear::model::terms::AnyTerm;
use hdgear::simulate::{SimOptions, Start, simulate_model};

fn at(gamma: f64, omega: f64) -> Params {
    Params {
        gamma,
        omega,
        ..Params::default()
    }
}

fn with(p: &Params, kind: &str, values: &[f64]) -> Model {
    Model::study(p)
        .with_term(AnyTerm::new(kind, values).unwrap())
        .unwrap()
}

/// x on `b` at `a`, interpolated linearly between its points (a monotone along it).
fn x_on(b: &LoopBranch, a: f64) -> Option<f64> {
    b.points.windows(2).find_map(|w| {
        let (lo, hi) = (w[0].a.min(w[1].a), w[0].a.max(w[1].a));
        (lo..=hi)
            .contains(&a)
            .then(|| w[0].x + (w[1].x - w[0].x) * (a - w[0].a) / (w[1].a - w[0].a))
    })
}

/// Coulomb–Stribeck friction: creeping at x' → 0± the friction is ±f_s (the Stribeck curve at
/// rest), so the branches are the study's curve at the load shifted by ∓f_s: g(x±) = μ + δa ∓ f_s
/// (the study's closed-form root at a ∓ f_s/δ), and after each turning point the drive rests
/// until the load has crossed the band 2f_s: the breakaways at a = ±(1 − 2f_s/δ).
#[test]
fn coulomb_branches_are_the_curve_shifted_by_the_static_friction() {
    let p = at(2.0, 0.01);
    let (fc, fs) = (0.5, 0.8);
    let b = with(&p, "coulomb", &[fc, fs, 0.1, 0.0]).branches().unwrap();
    let band = 2.0 * fs / p.delta;
    let (up, down) = (b.loading.breakaway.unwrap(), b.unloading.breakaway.unwrap());
    println!("breakaways: loading {up}, unloading {down}, band {band}");
    // to the branch's own balance error (RK4 in a: about 1e-11 of the load)
    assert!((down - (1.0 - band)).abs() < 1e-10);
    assert!((up - (band - 1.0)).abs() < 1e-10);
    let mut worst: f64 = 0.0;
    for (branch, s) in [(&b.loading, 1.0), (&b.unloading, -1.0)] {
        assert_eq!(branch.fold, None);
        for q in &branch.points {
            let closed = hdgear::fast::stable_equilibrium(&p, q.a - s * fs / p.delta);
            worst = worst.max((q.x - closed).abs());
            assert!((q.stiffness - p.g_prime(q.x)).abs() < 1e-12 * p.g_prime(q.x));
        }
    }
    println!("Coulomb branches against the shifted curve: worst |Δx| {worst:.1e}");
    assert!(worst < 1e-10, "{worst:e}");
    assert!(b.closure < 1e-12);
}

/// Bouc–Wen with n = 1 and ρ = 0: on a branch of side s where z keeps its sign s_z,
/// dz/dx = A − c·z with c = β·s + γ_h·s_z, so z = A/c + (z₀ − A/c)·e^{−c(x − x₀)}. Every point
/// holds the creep balance g(x) + k_h·z = μ + δa.
#[test]
fn bouc_wen_branches_follow_the_closed_form_loop() {
    let p = at(2.0, 0.01);
    let [kh, a_h, beta, gh] = [0.5, 1.0, 0.5, 0.3];
    let b = with(&p, "boucwen", &[kh, 0.0, a_h, beta, gh, 1.0])
        .branches()
        .unwrap();
    let (mut worst_z, mut worst_balance): (f64, f64) = (0.0, 0.0);
    for (branch, s) in [(&b.loading, 1.0), (&b.unloading, -1.0)] {
        // no band without sticking: the motion leaves the reversal at once (to the branch's own
        // balance error)
        assert!((branch.breakaway.unwrap() - branch.reversal).abs() < 1e-9);
        let first = branch.points[0];
        for q in &branch.points {
            let balance = p.g(q.x) + kh * q.z[0] - p.forcing(q.a);
            worst_balance = worst_balance.max(balance.abs());
            // the closed form on the stretch where z keeps the first point's sign
            let sz = first.z[0].signum();
            if q.z[0].signum() == sz && first.z[0] != 0.0 {
                let c = beta * s + gh * sz;
                let z_inf = a_h / c;
                let closed = z_inf + (first.z[0] - z_inf) * (-c * (q.x - first.x)).exp();
                worst_z = worst_z.max((q.z[0] - closed).abs());
            }
        }
    }
    println!(
        "Bouc–Wen branches: worst |Δz| {worst_z:.1e}, worst balance {worst_balance:.1e}, closure {:.1e}",
        b.closure
    );
    assert!(
        worst_z < 1e-9 && worst_balance < 1e-9,
        "{worst_z:e} {worst_balance:e}"
    );
    assert!(b.closure < 1e-11, "{}", b.closure);
}

/// A slow simulation follows the branches: on the loading half of the fourth load cycle (a
/// rising), x(τ) stays within O(ω) of x₊(a); five times slower, five times closer (the lag
/// behind a quasi-static branch is first order in ω). Bouc–Wen hysteresis and Coulomb
/// friction, each beside the study's stiffness at γ = 2.
#[test]
fn slow_simulations_follow_the_branches_at_first_order_in_omega() {
    for (kind, values) in [
        ("boucwen", vec![0.5, 0.0, 1.0, 0.5, 0.3, 1.0]),
        ("coulomb", vec![0.5, 0.5, 0.1, 0.0]),
    ] {
        let gaps: Vec<f64> = [2e-3, 4e-4]
            .iter()
            .map(|&omega| {
                let p = at(2.0, omega);
                let m = with(&p, kind, &values);
                let b = m.branches().unwrap();
                let period = std::f64::consts::TAU / omega;
                // four cycles: the loop has settled far below the gap measured
                let opts = SimOptions {
                    t_end: 4.25 * period,
                    dt: period / 2000.0,
                    start: Start::Rest,
                    tol: hdgear::integrate::Options::default(),
                };
                let mut gap: f64 = 0.0;
                simulate_model(&m, &opts, |t, y| {
                    let (s, c) = (omega * t).sin_cos();
                    // the last loading half, clear of the rest after its turn
                    if t > 3.75 * period
                        && c > 0.0
                        && y[1] > 0.0
                        && let Some(x) = x_on(&b.loading, s)
                    {
                        gap = gap.max((y[0] - x).abs());
                    }
                })
                .unwrap();
                gap
            })
            .collect();
        let ratio = gaps[0] / gaps[1];
        println!("{kind}: largest gap to the loading branch {gaps:?}, ratio {ratio:.2}");
        assert!(
            gaps[1] < 1e-2 && (3.5..7.0).contains(&ratio),
            "{kind}: {gaps:?}"
        );
    }
}

/// The spiking areas the branches predict — each branch's steepest point (its smallest tangent
/// stiffness) and its start (the breakaway after a reversal) — are where the simulated bursts
/// start: every burst's onset a lies within 0.15 (15 % of the slow variable's amplitude) of the
/// nearest prediction on its own branch (loading while a rises), for Coulomb friction, Bouc–Wen
/// hysteresis and LuGre friction, and nearer at a load twice as slow (the onset lags the
/// steepest point by a time the slower load turns into less a).
#[test]
fn bursts_start_where_the_branches_predict_spiking() {
    let cases: [(f64, &str, &[f64]); 7] = [
        (1.0, "coulomb", &[0.5, 0.5, 0.1, 0.0]),
        (1.0, "coulomb", &[2.0, 2.0, 0.1, 0.0]),
        (0.5, "coulomb", &[1.0, 1.0, 0.1, 0.0]),
        (0.3, "coulomb", &[0.2, 0.2, 0.1, 0.0]),
        (1.0, "boucwen", &[0.5, 0.0, 1.0, 0.5, 0.5, 1.0]),
        (0.5, "boucwen", &[1.0, 0.0, 1.0, 0.5, 0.5, 2.0]),
        (1.0, "lugre", &[0.5, 0.8, 0.05, 100.0, 2.0, 0.0]),
    ];
    let opts = hdgear::burst::BurstOptions::default();
    let mut worst = Vec::new();
    for omega in [0.01, 0.005] {
        let mut max_err: f64 = 0.0;
        for (gamma, kind, values) in cases {
            let m = with(&at(gamma, omega), kind, values);
            let b = m.branches().unwrap();
            let r = hdgear::burst::response_model(&m, &opts).unwrap();
            assert!(!r.bursts.is_empty(), "γ = {gamma} {kind}: no bursts");
            for burst in &r.bursts {
                let near = b.at(burst.t_peak, omega);
                let err = (burst.a_onset - near.nearest_prediction(burst.a_onset).unwrap()).abs();
                assert!(
                    err <= 0.15,
                    "ω = {omega}, γ = {gamma} {kind}: onset {} vs {:?}",
                    burst.a_onset,
                    near.predicted_onsets()
                );
                max_err = max_err.max(err);
            }
        }
        println!("ω = {omega}: largest distance of an onset from its prediction {max_err:.4}");
        worst.push(max_err);
    }
    assert!(worst[1] < worst[0], "{worst:?}");
}

/// The steepest point of a branch, against the closed form: with Coulomb friction f_c = f_s = f
/// the branches are the study's curve shifted by ∓f, so the smallest tangent stiffness is
/// γ − 1/(3α), at x = 1/(3α) and a = (g(1/(3α)) ± f − μ)/δ. The points near a steep point lie far
/// apart in x (dx/da = δ/K_t); the parabola through the smallest and its neighbours gives K_t
/// exactly (g' is quadratic) and the Hermite interpolant of x(a) its a to a few 1e-6.
#[test]
fn the_steepest_point_is_located_between_the_points() {
    for (gamma, f) in [(1.0, 0.5), (0.1, 0.0), (0.3, 2.0)] {
        let p = at(gamma, 0.01);
        let m = with(&p, "coulomb", &[f, f, 0.1, 0.0]);
        let b = m.branches().unwrap();
        let x = 1.0 / (3.0 * p.alpha);
        let g = p.alpha * x * x * x - x * x + p.gamma * (x - p.eps);
        for (br, sign) in [(&b.loading, 1.0), (&b.unloading, -1.0)] {
            let (a, k) = br.min_stiffness.unwrap();
            let a_exact = (g + sign * f - p.mu) / p.delta;
            let k_exact = p.gamma - 1.0 / (3.0 * p.alpha);
            println!(
                "γ = {gamma}, f = {f}, side {sign}: a error {:.1e}, K_t error {:.1e}",
                a - a_exact,
                k - k_exact
            );
            assert!((a - a_exact).abs() < 1e-5, "{a} vs {a_exact}");
            assert!((k - k_exact).abs() < 1e-9 * k_exact, "{k} vs {k_exact}");
        }
    }
}
