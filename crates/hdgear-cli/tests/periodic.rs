//! The periodic response (issue 16, first part): shooting against long simulations, the monodromy
//! against finite differences, Liouville's formula, and Benettin's Lyapunov exponent against the
//! largest Floquet exponent.

use hdgear::Params;
use hdgear::integrate::{Method, Options};
use hdgear::periodic::{PeriodicOptions, lyapunov, shoot};
use hdgear::simulate::{SimOptions, Start, simulate};

fn tight() -> Options {
    Options {
        rtol: 1e-12,
        atol: 1e-12,
        method: Method::Dop853,
        ..Options::default()
    }
}

/// The study's point with γ.
fn paper(g: f64) -> Params {
    Params::default().with(hdgear::params::Param::Gamma, g)
}

/// The state at τ = `t_end` from (0, y0).
fn state_at(p: &Params, y0: [f64; 2], t_end: f64) -> [f64; 2] {
    let opts = SimOptions {
        t_end,
        dt: t_end,
        start: Start::Given {
            x0: y0[0],
            v0: y0[1],
        },
        tol: tight(),
    };
    simulate(p, &opts, |_, _| {}).unwrap().final_state
}

#[test]
fn shooting_finds_the_orbit_a_long_simulation_settles_on() {
    for g in [30.0, 1.0, 0.1] {
        let p = paper(g);
        let orbit = shoot(&p, 1, &PeriodicOptions::default()).unwrap();
        assert!(
            orbit.residual < 1e-10,
            "γ = {g}: residual {:e}",
            orbit.residual
        );
        // five slow periods from the default start, ending at the same phase (τ = 5T)
        let y0 = hdgear::simulate::initial_state(&p, Start::Equilibrium);
        let y = state_at(&p, y0, 5.0 * p.slow_period());
        let d = (y[0] - orbit.start[0]).hypot(y[1] - orbit.start[1]);
        assert!(
            d < 1e-9,
            "γ = {g}: orbit {:?}, simulation {y:?}, distance {d:e}",
            orbit.start
        );
        assert!(orbit.stable && orbit.peak_to_peak > 0.0 && orbit.samples.len() > 1000);
    }
}

#[test]
fn liouville_the_product_of_the_multipliers_is_exp_minus_the_period() {
    for g in [30.0, 1.0, 0.1, 0.01] {
        for omega in [0.01, 0.1, 0.5] {
            let p = paper(g).with(hdgear::params::Param::Omega, omega);
            let o = shoot(&p, 1, &PeriodicOptions::default()).unwrap();
            let sum = o.log_abs_multipliers[0] + o.log_abs_multipliers[1];
            // trace J = −1 everywhere: det M = e^{−T}
            assert!(
                (sum + o.period).abs() < 1e-10 * o.period,
                "γ = {g}, ω = {omega}: ln|m1 m2| = {sum}, −T = {}",
                -o.period
            );
        }
    }
}

#[test]
fn the_multipliers_agree_with_a_finite_difference_monodromy() {
    // ω = 0.3: T = 21, multipliers ~e^{−10}, large enough for differences of the flow to resolve
    // (at the study's ω = 0.01 they are e^{−314}, below any difference of two trajectories)
    for g in [30.0, 1.0, 0.1] {
        let p = paper(g).with(hdgear::params::Param::Omega, 0.3);
        let o = shoot(&p, 1, &PeriodicOptions::default()).unwrap();
        let h = 1e-5;
        let mut fd = [[0.0; 2]; 2];
        for j in 0..2 {
            let mut plus = o.start;
            let mut minus = o.start;
            plus[j] += h;
            minus[j] -= h;
            let (a, b) = (state_at(&p, plus, o.period), state_at(&p, minus, o.period));
            for i in 0..2 {
                fd[i][j] = (a[i] - b[i]) / (2.0 * h);
            }
        }
        let tr = fd[0][0] + fd[1][1];
        let det = fd[0][0] * fd[1][1] - fd[0][1] * fd[1][0];
        let disc = tr * tr - 4.0 * det;
        let fd_abs: [f64; 2] = if disc < 0.0 {
            [det.abs().sqrt(); 2]
        } else {
            let big = 0.5 * (tr + tr.signum() * disc.sqrt());
            [big.abs(), (det / big).abs()]
        };
        for (k, (q, fd_k)) in o.multipliers.iter().zip(fd_abs).enumerate() {
            let m = q.log_abs.exp();
            assert!(
                (m - fd_k).abs() < 1e-6,
                "γ = {g}: |m{k}| = {m:e} from the variational equations, {fd_k:e} by differences"
            );
        }
        // the larger one to 1e-4 relative as well
        let m0 = o.multipliers[0].log_abs.exp();
        assert!(
            (m0 - fd_abs[0]).abs() < 1e-4 * m0,
            "γ = {g}: {m0:e} vs {:e}",
            fd_abs[0]
        );
    }
}

#[test]
fn lyapunov_exponents_are_negative_and_equal_the_largest_floquet_exponent() {
    for g in [30.0, 10.0, 1.0, 0.1] {
        let p = paper(g);
        let o = shoot(&p, 1, &PeriodicOptions::default()).unwrap();
        let t = p.slow_period();
        // with a complex pair (a focus all along) the tangent vector's norm oscillates within a
        // bounded factor, so the average converges like 1/span: at γ = 1 the error was 3.4e-4,
        // 1.6e-4, 8.3e-5, 2.9e-5 after 5, 20, 40, 80 periods; 50 periods keep it under 1e-4
        let l = lyapunov(&p, o.start, t, 50.0 * t, tight()).unwrap();
        let floquet = o.floquet_exponents[0];
        assert!(l < 0.0, "γ = {g}: λ = {l}");
        assert!(
            (l - floquet).abs() < 1e-4,
            "γ = {g}: Benettin {l}, Floquet {floquet}"
        );
    }
}

#[test]
fn a_subharmonic_request_reports_the_least_period() {
    let p = paper(1.0).with(hdgear::params::Param::Omega, 0.3);
    let o = shoot(&p, 2, &PeriodicOptions::default()).unwrap();
    assert_eq!((o.subharmonic, o.minimal_subharmonic), (2, 1));
    let one = shoot(&p, 1, &PeriodicOptions::default()).unwrap();
    assert!((o.start[0] - one.start[0]).abs() < 1e-9 && (o.start[1] - one.start[1]).abs() < 1e-9);
    // the period-2 multipliers are the squares of the period-1 ones
    assert!((o.log_abs_multipliers[0] - 2.0 * one.log_abs_multipliers[0]).abs() < 1e-8);
    assert!(matches!(
        shoot(&p, 0, &PeriodicOptions::default()),
        Err(hdgear::Error::InvalidOption {
            name: "subharmonic",
            ..
        })
    ));
}
