//! Scheduled stiffness ([`hdgear::model::schedule::Scheduled`]): its closed-form schedule against
//! a bisection written here, the least slope it promises on the closed loop's equilibria against
//! a continuation written here, its derivatives against differences of its torque, and its
//! Taylor recurrences (with the steps cut where the gain switches) against DOP853, which reads
//! only its torque.

use hdgear::Params;
use hdgear::burst::{BurstOptions, response_model};
use hdgear::integrate::{Method, Options};
use hdgear::model::Model;
use hdgear::model::schedule::Scheduled;
use hdgear::model::terms::{AnyTerm, Term};
use hdgear::simulate::{SimOptions, Start, simulate_model};

/// The study's bursting set, sets with deeper and shallower folds, another curvature and load,
/// and one without folds (γ = 1 > 1/(3α): the schedule has little or nothing to add).
fn plants() -> Vec<Params> {
    let d = Params::default();
    vec![
        d,
        Params { gamma: 0.01, ..d },
        Params {
            gamma: 0.05,
            eps: 0.3,
            ..d
        },
        Params {
            alpha: 4.0,
            delta: 4.0,
            ..d
        },
        Params {
            mu: 1.5,
            delta: 3.0,
            ..d
        },
        Params { gamma: 1.0, ..d },
    ]
}

const TARGETS: [f64; 3] = [0.01, 0.05, 0.3];

/// The root of f in [lo, hi], where f changes sign, by bisection to the last bits.
fn bisect(f: impl Fn(f64) -> f64, (mut lo, mut hi): (f64, f64)) -> f64 {
    let below = f(lo) < 0.0;
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if (f(mid) < 0.0) == below {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The real root of αs³ + m·s = b (m > 0: monotone), by bisection.
fn reference_root(alpha: f64, m: f64, b: f64) -> f64 {
    bisect(|s| alpha * s.powi(3) + m * s - b, (-1e3, 1e3))
}

/// The term's defaults are the schedule for the study's default set with g'_min = 0.3, as its
/// documentation says.
#[test]
fn the_defaults_are_the_study_sets_schedule() {
    let defaults: Vec<f64> = Scheduled::PARAMS.iter().map(|p| p.default).collect();
    let want = Scheduled::for_plant(&Params::default(), 0.3);
    for ((d, w), p) in defaults.iter().zip(want.0).zip(Scheduled::PARAMS) {
        assert!(
            (d - w).abs() <= 1e-15 * w.abs().max(1.0),
            "{}: {d} vs {w}",
            p.name
        );
    }
}

/// The schedule's gain equals max(0, g'_min − g'(x_c) − 3α·s₀²) with s₀ bisected, to rounding.
#[test]
fn the_schedule_is_its_closed_form() {
    for p in plants() {
        let xc = 1.0 / (3.0 * p.alpha);
        for m in TARGETS {
            let law = Scheduled::for_plant(&p, m);
            for i in 0..=400 {
                let a = -1.0 + f64::from(i) / 200.0;
                let s = reference_root(p.alpha, m, p.mu - p.g(xc) + p.delta * a);
                let want = (m - p.g_prime(xc) - 3.0 * p.alpha * s * s).max(0.0);
                let got = law.gain(a);
                assert!(
                    (got - want).abs() <= 1e-12 * want.max(1.0),
                    "{p:?}, g'min {m}, a = {a}: {got} vs {want}"
                );
            }
        }
    }
}

/// The closed loop's equilibrium, followed by Newton's method from the lowest one at a = −1 up to
/// a = 1 and from the highest at a = 1 back down, never folds (each step of a, 1/2000 or halved
/// down to 2⁻⁴⁰ of it, moves x by less than a thousandth of the curve's extent) and keeps the
/// slope g'(x) + k(a) at least g'_min. The bursting plants' own curves fold, so the schedule has
/// work to do there.
#[test]
fn the_closed_loop_keeps_the_least_slope() {
    for p in plants() {
        let xc = 1.0 / (3.0 * p.alpha);
        for m in TARGETS {
            let law = Scheduled::for_plant(&p, m);
            let residual = |x: f64, a: f64| p.g(x) + law.gain(a) * (x - xc) - p.mu - p.delta * a;
            let slope = |x: f64, a: f64| p.g_prime(x) + law.gain(a);
            let roots = |a: f64| {
                // every root of the cubic in x at a, by a dense sign scan and bisection
                let (lo, hi) = (-30.0, 30.0);
                let n = 60_000;
                let x = |j: usize| lo + (hi - lo) * j as f64 / n as f64;
                (0..n)
                    .filter(|&j| residual(x(j), a).signum() != residual(x(j + 1), a).signum())
                    .map(|j| bisect(|x| residual(x, a), (x(j), x(j + 1))))
                    .collect::<Vec<f64>>()
            };
            let (low, high) = (roots(-1.0), roots(1.0));
            let extent = high[high.len() - 1] - low[0];
            // Newton from x at a; steps of a are halved where x would move by more than a
            // thousandth of the extent (the passage is steep where the slope is small), down to
            // 2⁻⁴⁰: a fold would leave no nearby root however small the step
            fn follow(
                x: f64,
                (a0, a1): (f64, f64),
                depth: u32,
                step: &impl Fn(f64, f64) -> Option<f64>,
            ) -> f64 {
                match step(x, a1) {
                    Some(next) => next,
                    None => {
                        assert!(depth < 40, "no nearby root at a = {a1}: a fold");
                        let mid = 0.5 * (a0 + a1);
                        let x = follow(x, (a0, mid), depth + 1, step);
                        follow(x, (mid, a1), depth + 1, step)
                    }
                }
            }
            let step = |x: f64, a: f64| {
                let mut next = x;
                for _ in 0..100 {
                    next -= residual(next, a) / slope(next, a);
                }
                let converged = residual(next, a).abs() <= 1e-9 * (1.0 + p.delta);
                (converged && (next - x).abs() < 1e-3 * extent).then_some(next)
            };
            for (start, from, to) in [(low[0], -1.0, 1.0), (high[high.len() - 1], 1.0, -1.0)] {
                let mut x = start;
                for i in 1..=2000 {
                    let a = |i: i32| from + (to - from) * f64::from(i) / 2000.0;
                    x = follow(x, (a(i - 1), a(i)), 0, &step);
                    let k = slope(x, a(i));
                    assert!(
                        k >= m * (1.0 - 1e-9),
                        "{p:?}, g'min {m}, a = {}: slope {k}",
                        a(i)
                    );
                }
            }
            if p.gamma < xc {
                // the open loop folds: the gain is on somewhere
                assert!(law.gain(p.a_at(xc)) > 0.0, "{p:?}");
            }
        }
    }
}

/// The term's x- and phase-gradient and its parameter derivatives equal central differences of
/// its torque (relative step 1e-6: a difference's error, about 1e-12 over the step, is far
/// below the 1e-6 allowed), away from the gain's kinks.
#[test]
fn the_derivatives_are_the_torques() {
    // g'_min = 0.3 above the study set's least slope γ − 1/(3α) ≈ 0.079: the gain is on at x_c
    let law = Scheduled::for_plant(&Params::default(), 0.3);
    let [lo, hi] = law.levels().unwrap();
    for (x, f) in [(0.3, 0.5), (-0.2, 0.3), (0.05, 0.8)] {
        let theta = (lo + f * (hi - lo)).asin();
        assert!(law.gain(libm::sin(theta)) > 0.0);
        let close = |got: f64, want: f64, what: &str| {
            assert!(
                (got - want).abs() <= 1e-6 * want.abs().max(1e-3),
                "{what} at ({x}, {theta}): {got} vs {want}"
            )
        };
        let h = 1e-6;
        let [dx, dv, dz] = law.gradient(x, 0.0, theta);
        close(
            dx,
            (law.torque(x + h, 0.0, theta) - law.torque(x - h, 0.0, theta)) / (2.0 * h),
            "∂/∂x",
        );
        assert_eq!(dv, 0.0);
        close(
            dz,
            (law.torque(x, 0.0, theta + h) - law.torque(x, 0.0, theta - h)) / (2.0 * h),
            "∂/∂θ",
        );
        for i in 0..7 {
            let v = law.0[i];
            let step = h * v.abs().max(1e-3);
            let at = |value: f64| {
                let mut w = law.0;
                w[i] = value;
                Scheduled::from_values(&w).torque(x, 0.0, theta)
            };
            let want = (at(v + step) - at(v - step)) / (2.0 * step);
            close(
                law.param_derivative(i, x, 0.0, theta),
                want,
                Scheduled::PARAMS[i].name,
            );
        }
    }
}

fn closed_loop(p: &Params, gmin: f64) -> Model {
    let law = Scheduled::for_plant(p, gmin);
    Model::study(p)
        .with_term(AnyTerm::new(Scheduled::KIND, &law.0).unwrap())
        .unwrap()
}

/// Over three slow periods of the study's bursting set with g'_min = 0.3 (the gain switching on
/// and off twice a period), Taylor at 1e-12 and DOP853 at 1e-12 agree to 1e-8 in x and x' on a
/// grid of 1 time unit. Taylor's rows of the gain come from the term's own recurrences and its
/// steps end at the gain's kinks; DOP853 reads only the torque.
#[test]
fn taylor_agrees_with_dop853_across_the_gains_kinks() {
    let p = Params::default();
    let m = closed_loop(&p, 0.3);
    let law = Scheduled::for_plant(&p, 0.3);
    let xc = 1.0 / (3.0 * p.alpha);
    assert!(law.gain(p.a_at(xc)) > 0.0 && law.gain(-1.0) == 0.0 && law.gain(1.0) == 0.0);
    let run = |method: Method| {
        let opts = SimOptions {
            t_end: 3.0 * p.slow_period(),
            dt: 1.0,
            start: Start::Rest,
            tol: Options {
                method,
                rtol: 1e-12,
                atol: 1e-12,
                ..Options::default()
            },
        };
        let mut out = vec![];
        simulate_model(&m, &opts, |t, y| out.push([t, y[0], y[1]])).unwrap();
        out
    };
    let (taylor, dop) = (run(Method::Taylor), run(Method::Dop853));
    assert_eq!(taylor.len(), dop.len());
    let worst = taylor
        .iter()
        .zip(&dop)
        .map(|(a, b)| (a[1] - b[1]).abs().max((a[2] - b[2]).abs()))
        .fold(0.0, f64::max);
    assert!(worst < 1e-8, "largest difference {worst}");
}

/// The burst verdict measures against an equilibrium curve of x alone, which a scheduled
/// stiffness does not have: refused, naming the model, rather than judged against the curve at
/// a = 0.
#[test]
fn the_burst_verdict_refuses_a_scheduled_stiffness() {
    let m = closed_loop(&Params::default(), 0.3);
    assert_eq!(m.equivalent_params(), None);
    let err = response_model(&m, &BurstOptions::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("scheduled stiffness"), "{err}");
}
