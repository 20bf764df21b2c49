//! The integrator against closed forms: convergence order, dense output, events, accounting.
//!
//! **Why one file.** The tests of one capability, the integrators, in one module of the test
//! binary.

use hdgear::Params;
use hdgear::integrate::events::{Detector, Direction};
use hdgear::integrate::{DenseOutput, Dop853, Method, Options, Stepper, System, sample};
use hdgear::model::Dimensionless;
use std::f64::consts::{FRAC_PI_2, PI};

/// y' = cos(t)·y, y(0) = 1  ⇒  y = exp(sin t). Non-autonomous, so a stage evaluated at the wrong
/// time shows up as a lost order.
struct ExpSin;
impl System<1> for ExpSin {
    fn rhs(&self, t: f64, y: &[f64; 1]) -> [f64; 1] {
        [t.cos() * y[0]]
    }
}

/// y'' = −y: y = sin t.
struct Osc;
impl System<2> for Osc {
    fn rhs(&self, _t: f64, y: &[f64; 2]) -> [f64; 2] {
        [y[1], -y[0]]
    }
}

/// Fixed steps h: tolerances so loose that no step is rejected, h_init = h_max = h.
fn fixed(h: f64) -> Options {
    Options {
        rtol: 1.0,
        atol: 1e3,
        h_init: Some(h),
        h_max: Some(h),
        ..Options::default()
    }
}

fn observed_order(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

/// Max error at the step ends over [0, 16] with fixed steps h.
fn max_step_error<S: System<N>, const N: usize>(
    sys: &S,
    y0: [f64; N],
    exact: impl Fn(f64) -> f64,
    h: f64,
) -> f64 {
    let mut s = Dop853::new(sys, 0.0, y0, fixed(h)).unwrap();
    let mut worst: f64 = 0.0;
    while s.t() < 16.0 {
        s.step(16.0).unwrap();
        worst = worst.max((s.y()[0] - exact(s.t())).abs());
    }
    assert_eq!(s.stats().rejected, 0);
    assert_eq!(s.stats().steps, (16.0 / h).round() as u64);
    worst
}

/// Least-squares slope of log2(error) against log2(h).
fn fitted_order(hs: &[f64], errors: &[f64]) -> f64 {
    let xs: Vec<f64> = hs.iter().map(|h| h.log2()).collect();
    let ys: Vec<f64> = errors.iter().map(|e| e.log2()).collect();
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}

#[test]
fn global_error_converges_with_order_8() {
    // Steps 1.6 … 0.2: errors from ~1e-4 down to ~1e-12, above rounding (~1e-14).
    let hs = [1.6, 0.8, 0.4, 0.2];
    let osc: Vec<f64> = hs
        .iter()
        .map(|&h| max_step_error(&Osc, [0.0, 1.0], f64::sin, h))
        .collect();
    let orders = observed_order(&osc);
    eprintln!("oscillator errors {osc:?}, pairwise orders {orders:?}");
    for p in orders {
        assert!((7.7..=8.3).contains(&p), "observed order {p}");
    }
    // Non-autonomous: a stage evaluated at the wrong time would drop the order to 1 or 2.
    let exps: Vec<f64> = hs
        .iter()
        .map(|&h| max_step_error(&ExpSin, [1.0], |t| t.sin().exp(), h))
        .collect();
    let p = fitted_order(&hs, &exps);
    eprintln!("exp(sin t) errors {exps:?}, fitted order {p}");
    assert!((7.5..=8.7).contains(&p), "fitted order {p}");
}

#[test]
fn dense_output_converges_with_order_at_least_7() {
    // max error of the interpolant at 7 interior points of every step, fixed steps
    let t_end = 8.0;
    let mut errors = Vec::new();
    for h in [0.8, 0.4, 0.2] {
        let mut s = Dop853::new(&ExpSin, 0.0, [1.0], fixed(h)).unwrap();
        let mut worst: f64 = 0.0;
        while s.t() < t_end {
            s.step(t_end).unwrap();
            let d = s.dense();
            for j in 1..8 {
                let t = d.t_start() + (d.t_end() - d.t_start()) * j as f64 / 8.0;
                worst = worst.max((d.eval(t)[0] - t.sin().exp()).abs());
            }
        }
        errors.push(worst);
    }
    let orders = observed_order(&errors);
    eprintln!("dense errors {errors:?}, observed orders {orders:?}");
    for p in orders {
        assert!(p >= 6.5, "observed dense order {p}");
    }
}

#[test]
fn adaptive_error_tracks_tolerance() {
    for tol in [1e-6, 1e-8, 1e-10, 1e-12] {
        let o = Options {
            rtol: tol,
            atol: tol,
            ..Options::default()
        };
        let mut s = Dop853::new(&Osc, 0.0, [0.0, 1.0], o).unwrap();
        s.integrate_to(50.0).unwrap();
        let err = (s.y()[0] - 50f64.sin()).abs();
        // global error over ~8 periods stays within a modest multiple of the local tolerance
        assert!(err < 100.0 * tol, "tol {tol}: error {err:e}");
    }
}

#[test]
fn sampling_does_not_change_the_steps() {
    for method in [Method::Taylor, Method::Dop853] {
        sampling_leaves_steps_alone(method);
    }
}

fn sampling_leaves_steps_alone(method: Method) {
    let p = Params::default();
    let sys = Dimensionless::new(p);
    let o = Options {
        method,
        ..Options::default()
    };
    let mut plain = hdgear::integrate::stepper(&sys, 0.0, [0.0, 0.0], o).unwrap();
    while plain.t() < 300.0 {
        plain.step(300.0).unwrap();
    }
    for dt in [0.05, 1.0, 7.0] {
        let mut n = 0;
        let (y, st) = sample(&sys, 0.0, [0.0, 0.0], 300.0, dt, o, |_, _| n += 1).unwrap();
        assert_eq!(st.steps, plain.stats().steps, "dt {dt}");
        assert_eq!(
            y,
            *plain.y(),
            "dt {dt}: the final state must be bit-identical"
        );
        assert_eq!(
            n,
            (300.0 / dt + 1e-9).floor() as usize + 1 + usize::from(dt == 7.0)
        );
    }
}

#[test]
fn rhs_evaluations_are_counted_exactly() {
    // A counting wrapper: the solver's own statistics must equal the true count.
    struct Counting<'a>(&'a std::cell::Cell<u64>, Dimensionless);
    impl System<2> for Counting<'_> {
        fn rhs(&self, t: f64, y: &[f64; 2]) -> [f64; 2] {
            self.0.set(self.0.get() + 1);
            self.1.rhs(t, y)
        }
    }
    let calls = std::cell::Cell::new(0);
    let sys = Counting(&calls, Dimensionless::new(Params::default()));
    let mut s = Dop853::new(&sys, 0.0, [0.0, 0.0], Options::default()).unwrap();
    while s.t() < 200.0 {
        s.step(200.0).unwrap();
        if s.stats().steps % 3 == 0 {
            s.dense();
            s.dense(); // cached: no further evaluations
        }
    }
    assert_eq!(s.stats().rhs_evals, calls.get());
}

#[test]
fn events_locate_zero_crossings() {
    // zeros of sin t at kπ, falling at odd k
    let mut s = Dop853::new(&Osc, 0.0, [0.0, 1.0], Options::default()).unwrap();
    let mut det = Detector::new(|_t, y: &[f64; 2]| y[0], Direction::Falling);
    let mut found = Vec::new();
    while s.t() < 20.0 {
        s.step(20.0).unwrap();
        let d = s.dense();
        det.scan(&d, |c| found.push(c));
    }
    let expect: Vec<f64> = (0..7)
        .map(|k| (2 * k + 1) as f64 * std::f64::consts::PI)
        .filter(|t| *t < 20.0)
        .collect();
    assert_eq!(found.len(), expect.len());
    for (c, t) in found.iter().zip(expect) {
        assert!(!c.rising);
        assert!((c.t - t).abs() < 1e-9, "{} vs {t}", c.t);
        assert!(c.y[0].abs() < 1e-9);
    }
}

#[test]
fn roots_are_bracketed_to_the_tolerance_in_few_evaluations() {
    use hdgear::integrate::events::refine_root;
    // closed-form roots, rising and falling, near 0 and at t ≈ 1000 (the tolerance is relative
    // there), steep ones, one in a flat stretch and multiple roots (where interpolation converges
    // slowly and bisection must take over), each with the most evaluations it may take: a few
    // for a simple root (Brent's method converges superlinearly), more for the multiple ones
    // (name, f, a, b, the root, the most evaluations)
    type Case = (&'static str, fn(f64) -> f64, f64, f64, f64, usize);
    let cases: [Case; 10] = [
        ("linear", |t| 3.0 * t - 1.0, 0.0, 1.0, 1.0 / 3.0, 1),
        ("sqrt 2", |t| t * t - 2.0, 1.0, 2.0, 2f64.sqrt(), 8),
        ("falling", |t| (-t).exp() - 0.5, 0.0, 3.0, 2f64.ln(), 10),
        (
            "cos at 1000",
            |t| (t - 1000.0).cos(),
            1000.5,
            1002.5,
            1000.0 + FRAC_PI_2,
            8,
        ),
        (
            "steep",
            |t| (t - 0.3).tanh() * 1e6 - 1.0,
            0.0,
            1.0,
            0.3 + (1e-6f64).atanh(),
            8,
        ),
        (
            "exponential",
            |t| (50.0 * (t - 0.6)).exp() - 1.0,
            0.0,
            1.0,
            0.6,
            20,
        ),
        ("sine", |t| t.sin(), 3.0, 3.3, PI, 6),
        (
            "flat stretch",
            |t| (t - 0.7).powi(5) + 1e-12 * (t - 0.7),
            0.0,
            1.0,
            0.7,
            40,
        ),
        ("triple", |t| (t - 0.25).powi(3), 0.0, 1.0, 0.25, 150),
        ("ninefold", |t| (t - 0.123).powi(9), 0.0, 1.0, 0.123, 150),
    ];
    for (name, f, a, b, root, most) in cases {
        let calls = std::cell::Cell::new(0usize);
        let g = |t: f64| {
            calls.set(calls.get() + 1);
            f(t)
        };
        let t = refine_root(g, a, f(a), b, f(b));
        let tol = 1e-13 * a.abs().max(1.0);
        // the result is an end of a bracket at most tol wide around the root (f's sign is
        // right to the last bit in every case, so the bracket holds the true root)
        assert!((t - root).abs() <= tol, "{name}: {t} vs {root}");
        assert!(calls.get() <= most, "{name}: {} evaluations", calls.get());
    }
    // a root at either end is returned without evaluating f
    let never = |_: f64| -> f64 { panic!("evaluated") };
    assert_eq!(refine_root(never, 1.0, 0.0, 2.0, 5.0), 1.0);
    assert_eq!(refine_root(never, 1.0, -5.0, 2.0, 0.0), 2.0);
}

#[test]
fn paper_runs_stay_within_the_evaluation_budget() {
    // The foundation issue's bar: ≤ 130k right-hand-side evaluations for 3 slow periods at
    // rtol = atol = 1e-10 (no dense output). A work count, not a timing.
    for gamma in [30.0, 0.1] {
        let p = Params {
            gamma,
            ..Params::default()
        };
        let o = Options {
            method: Method::Dop853,
            ..Options::default()
        };
        let (_, st) = hdgear::simulate::integrate_periods(&p, 3.0, o).unwrap();
        eprintln!("gamma {gamma}: {st:?}");
        assert!(st.rhs_evals <= 130_000, "gamma {gamma}: {st:?}");
    }
}

#[test]
fn invalid_options_are_rejected_by_name() {
    for (o, name) in [
        (
            Options {
                rtol: 0.0,
                ..Options::default()
            },
            "rtol",
        ),
        (
            Options {
                atol: f64::NAN,
                ..Options::default()
            },
            "atol",
        ),
    ] {
        let e = Dop853::new(&Osc, 0.0, [0.0, 1.0], o).err().unwrap();
        assert!(e.to_string().contains(name), "{e}");
    }
}

#[test]
fn blow_up_is_a_typed_error_with_its_time() {
    // y' = y²: y = 1/(1 − t) escapes at t = 1
    struct Riccati;
    impl System<1> for Riccati {
        fn rhs(&self, _t: f64, y: &[f64; 1]) -> [f64; 1] {
            [y[0] * y[0]]
        }
    }
    let mut s = Dop853::new(&Riccati, 0.0, [1.0], Options::default()).unwrap();
    match s.integrate_to(2.0) {
        Err(hdgear::Error::Solver(
            hdgear::error::SolverError::BlowUp { t, .. }
            | hdgear::error::SolverError::StepSizeTooSmall { t, .. },
        )) => {
            assert!((t - 1.0).abs() < 1e-3, "reported at t = {t}");
        }
        other => panic!("expected a blow-up, got {other:?}"),
    }
}

#[test]
fn the_models_jacobian_matches_finite_differences() {
    let sys = hdgear::model::Dimensionless::new(hdgear::Params::default());
    let (t, y) = (3.7, [0.31, -0.02]);
    let j = sys
        .jacobian(t, &y)
        .expect("the model provides its Jacobian");
    for k in 0..2 {
        let h = 1e-6;
        let (mut yp, mut ym) = (y, y);
        yp[k] += h;
        ym[k] -= h;
        let (fp, fm) = (sys.rhs(t, &yp), sys.rhs(t, &ym));
        for i in 0..2 {
            let fd = (fp[i] - fm[i]) / (2.0 * h);
            assert!(
                (j[i][k] - fd).abs() < 1e-7,
                "J[{i}][{k}] = {} vs {fd}",
                j[i][k]
            );
        }
    }
}

/// y'' = −y with its Taylor coefficients (x_{k+1} = v_k/(k+1), v_{k+1} = −x_k/(k+1)): y = sin t.
struct TaylorOsc;
impl System<2> for TaylorOsc {
    fn rhs(&self, _t: f64, y: &[f64; 2]) -> [f64; 2] {
        [y[1], -y[0]]
    }
    fn taylor(&self, _t: f64, y: &[f64; 2], order: usize, c: &mut [[f64; 2]]) -> bool {
        c[0] = *y;
        for k in 0..order {
            let inv = 1.0 / (k + 1) as f64;
            c[k + 1] = [c[k][1] * inv, -c[k][0] * inv];
        }
        true
    }
}

fn taylor_opts(tol: f64) -> Options {
    Options {
        rtol: tol,
        atol: tol,
        method: Method::Taylor,
        ..Options::default()
    }
}

#[test]
fn taylor_order_follows_jorba_zou() {
    use hdgear::integrate::taylor::order_for;
    // p = ⌈−ln ε / 2 + 1⌉
    assert_eq!(order_for(1e-10), 13);
    assert_eq!(order_for(1e-6), 8);
    assert_eq!(order_for(1e-16), 20);
    assert_eq!(order_for(1.0), hdgear::integrate::taylor::MIN_ORDER);
}

#[test]
fn taylor_tracks_the_closed_form_and_its_tolerance() {
    // over 50 periods of sin t the global error stays within a small multiple of the tolerance,
    // at the step ends and (through the step polynomial) in between
    for tol in [1e-6, 1e-9, 1e-12] {
        let mut s =
            hdgear::integrate::stepper(&TaylorOsc, 0.0, [0.0, 1.0], taylor_opts(tol)).unwrap();
        let (mut worst, mut worst_dense) = (0.0f64, 0.0f64);
        let t_end = 100.0 * std::f64::consts::PI;
        while s.t() < t_end {
            s.step(t_end).unwrap();
            worst = worst.max((s.y()[0] - s.t().sin()).abs());
            let d = s.dense();
            for f in [0.25, 0.5, 0.75] {
                let t = d.t_start() + f * (d.t_end() - d.t_start());
                worst_dense = worst_dense.max((d.eval(t)[1] - t.cos()).abs());
            }
        }
        eprintln!(
            "tol {tol:e}: steps {}, error {worst:e}, dense {worst_dense:e}",
            s.stats().steps
        );
        assert!(worst < 50.0 * tol, "tol {tol}: {worst:e}");
        assert!(worst_dense < 50.0 * tol, "tol {tol}: dense {worst_dense:e}");
        assert_eq!(s.stats().rejected, 0, "Taylor steps are never rejected");
    }
}

#[test]
fn the_models_taylor_coefficients_are_its_derivatives() {
    // c1 = f(t, y) and c2 = (J f + ∂f/∂t)/2 exactly, with ∂f/∂t = (0, δω cos ωt)
    let p = Params::default();
    let sys = Dimensionless::new(p);
    for (t, y) in [
        (0.0, [0.3, -0.2]),
        (123.4, [-0.07, 0.5]),
        (900.0, [0.6, 0.01]),
    ] {
        let mut c = [[0.0; 2]; 14];
        assert!(sys.taylor(t, &y, 13, &mut c));
        let f = sys.rhs(t, &y);
        let j = sys.jacobian(t, &y).unwrap();
        let ft = [0.0, p.delta * p.omega * (p.omega * t).cos()];
        for i in 0..2 {
            assert!((c[1][i] - f[i]).abs() < 1e-14 * (1.0 + f[i].abs()));
            let second = 0.5 * (j[i][0] * f[0] + j[i][1] * f[1] + ft[i]);
            assert!(
                (c[2][i] - second).abs() < 1e-12 * (1.0 + second.abs()),
                "{t}: {} vs {second}",
                c[2][i]
            );
        }
    }
}

#[test]
fn events_work_on_the_taylor_polynomial() {
    // the same zeros as DOP853 locates on its interpolant, to 1e-9 (both at tolerance 1e-12)
    let p = Params::default();
    let sys = Dimensionless::new(p);
    let zeros = |method: Method| {
        let o = Options {
            method,
            ..taylor_opts(1e-12)
        };
        // released far from equilibrium: x' changes sign at every swing of the damped ringing
        let mut s = hdgear::integrate::stepper(&sys, 0.0, [0.9, 0.0], o).unwrap();
        let mut det = Detector::new(|_t, y: &[f64; 2]| y[1], Direction::Either);
        let mut found = Vec::new();
        let t_end = 60.0;
        while s.t() < t_end {
            s.step(t_end).unwrap();
            det.scan(&s.dense(), |c| found.push(c.t));
        }
        found
    };
    let (a, b) = (zeros(Method::Taylor), zeros(Method::Dop853));
    eprintln!("{} zeros of x'", a.len());
    assert!(a.len() >= 5);
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() < 1e-9, "{x} vs {y}");
    }
}

/// The step polynomial's bounds on |x'|, above and below, hold on every step (checked at 1024
/// points each; the lower one is useful, above zero, on most steps), and
/// max |x'| of a summary, which skips the steps that bound puts below the largest value so far,
/// is the largest |x'| on the polynomials (to 1e-7, the sampling's own resolution: the located
/// extrema lie between the samples, and 64 samples a step missed one by 1.6e-6) and agrees with DOP853's, whose dense output gives no bound
/// and is searched on every step (to 1e-8: both at rtol 1e-10). Over the regimes of the reference
/// cases: folds (γ = 0.01), the study's bursts (0.1), smooth (30), and a faster drive.
#[test]
fn the_bound_that_skips_steps_loses_no_maximum() {
    use hdgear::simulate::{SimOptions, Start, summarize};
    for (gamma, omega) in [(0.01, 0.01), (0.1, 0.01), (30.0, 0.01), (0.1, 0.05)] {
        let p = Params {
            gamma,
            omega,
            ..Params::default()
        };
        let sys = Dimensionless::new(p);
        let opts = SimOptions {
            t_end: 2.0 * p.slow_period(),
            start: Start::Rest,
            ..SimOptions::default()
        };
        let mut s = hdgear::integrate::stepper(&sys, 0.0, [0.0, 0.0], opts.tol).unwrap();
        let mut sampled = 0.0f64;
        let (mut steps, mut floored) = (0, 0);
        while s.t() < opts.t_end {
            s.step(opts.t_end).unwrap();
            let d = s.dense();
            let bound = d.abs_bound(1).expect("Taylor's polynomial bounds itself");
            let floor = d.abs_floor(1).expect("and from below");
            let (t0, t1) = (d.t_start(), d.t_end());
            for j in 0..=1024 {
                let v = d.eval(t0 + (t1 - t0) * f64::from(j) / 1024.0)[1].abs();
                assert!(
                    v <= bound * (1.0 + 1e-14),
                    "γ = {gamma}: {v} > bound {bound}"
                );
                assert!(v >= floor, "γ = {gamma}: {v} < floor {floor}");
                sampled = sampled.max(v);
            }
            steps += 1;
            floored += usize::from(floor > 0.0);
        }
        assert!(floored * 2 > steps, "γ = {gamma}: {floored} of {steps}");
        let taylor = summarize(&p, &opts, |_| {}).unwrap().max_abs_xdot;
        let dop = SimOptions {
            tol: Options {
                method: Method::Dop853,
                ..opts.tol
            },
            ..opts
        };
        let dop = summarize(&p, &dop, |_| {}).unwrap().max_abs_xdot;
        eprintln!("γ = {gamma}, ω = {omega}: max |x'| {taylor} (sampled {sampled}, DOP853 {dop})");
        assert!(
            taylor >= sampled && taylor <= sampled * (1.0 + 1e-7),
            "γ = {gamma}"
        );
        assert!(
            (taylor - dop).abs() <= 1e-8 * taylor,
            "γ = {gamma}: {taylor} vs {dop}"
        );
    }
}

#[test]
fn taylor_refuses_a_system_without_coefficients() {
    let e = hdgear::integrate::stepper(&Osc, 0.0, [0.0, 1.0], taylor_opts(1e-10))
        .err()
        .unwrap();
    assert!(e.to_string().contains("method"), "{e}");
}

#[test]
fn the_physical_model_agrees_across_methods() {
    use hdgear::physical::simulate::simulate_physical;
    let (d, _) = hdgear::physical::catalogue::preset("CSF-20-50", None).unwrap();
    let run = |method: Method| {
        let mut out = Vec::new();
        let o = Options {
            method,
            ..taylor_opts(1e-12)
        };
        simulate_physical(&d, 0.5, 1e-3, o, |s| out.push(s.theta)).unwrap();
        out
    };
    let (a, b) = (run(Method::Taylor), run(Method::Dop853));
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = a
        .iter()
        .zip(&b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale;
    eprintln!("physical Taylor vs DOP853: {worst:e} relative");
    assert!(worst < 1e-9, "{worst:e}");
}

/// A deadline that has passed (`Options::deadline`: how the explorer stops work it has given up
/// on) stops both integrators within `DEADLINE_EVERY` steps, with `SolverError::Deadline` at the
/// time reached, and every lane of a batch the same way. Without it the same run finishes.
#[test]
fn a_passed_deadline_stops_every_integrator() {
    use hdgear::error::SolverError;
    use hdgear::simulate::{SimOptions, simulate};
    let p = Params::default();
    let past = Some(std::time::Instant::now());
    let stopped = |r: hdgear::Result<()>| match r {
        Err(hdgear::Error::Solver(SolverError::Deadline { t })) => t,
        other => panic!("{other:?}"),
    };
    for method in [Method::Taylor, Method::Dop853] {
        let opts = |deadline| SimOptions {
            t_end: 1e7,
            dt: 1e3,
            tol: Options {
                method,
                deadline,
                ..Options::default()
            },
            ..SimOptions::default()
        };
        let t = stopped(simulate(&p, &opts(past), |_, _| {}).map(|_| ()));
        assert!((0.0..1e7).contains(&t), "{method}: t = {t}");
        let short = SimOptions {
            t_end: 100.0,
            ..opts(None)
        };
        assert!(simulate(&p, &short, |_, _| {}).is_ok(), "{method}");
    }
    let mut o = hdgear::burst::BurstOptions::default();
    o.tol.deadline = past;
    let sets: Vec<Params> = (0..16)
        .map(|i| Params {
            gamma: 0.5 + 0.1 * f64::from(i),
            ..p
        })
        .collect();
    for r in hdgear::burst::responses(&sets, &o) {
        stopped(r.map(|_| ()));
    }
}
