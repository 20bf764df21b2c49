//! Scheduled stiffness ([`hdgear::model::schedule::Scheduled`]): its closed-form schedule against
//! a bisection written here, the least slope it promises on the closed loop's equilibria against
//! a continuation written here, its derivatives against differences of its torque, and its
//! Taylor recurrences (with the steps cut where the gain switches) against DOP853, which reads
//! only its torque.

use hdgear::Params;
use hdgear::burst::{BurstOptions, Verdict, classify_model, response_model};
use hdgear::fast::{Follower, StaticCurve};
use hdgear::integrate::{Method, Options};
use hdgear::model::Model;
use hdgear::model::ModelCurve;
use hdgear::model::schedule::{RAMP_DEFAULT, Scheduled};
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
    let want = Scheduled::for_plant(&Params::default(), 0.3, RAMP_DEFAULT);
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
            let least = Scheduled::for_plant(&p, m, 0.0);
            let ramped = Scheduled::for_plant(&p, m, RAMP_DEFAULT);
            let d = m - p.g_prime(xc);
            let w = RAMP_DEFAULT * d.max(0.0);
            for i in 0..=400 {
                let a = -1.0 + f64::from(i) / 200.0;
                let s = reference_root(p.alpha, m, p.mu - p.g(xc) + p.delta * a);
                let kappa = d - 3.0 * p.alpha * s * s;
                // the ramp: 0, (κ + w)²/(4w), κ
                let ramp = if kappa <= -w {
                    0.0
                } else if kappa < w {
                    (kappa + w).powi(2) / (4.0 * w)
                } else {
                    kappa
                };
                for (law, want) in [(least, kappa.max(0.0)), (ramped, ramp)] {
                    let got = law.gain(a);
                    assert!(
                        (got - want).abs() <= 1e-12 * want.max(1.0),
                        "{p:?}, g'min {m}, ρ {}, a = {a}: {got} vs {want}",
                        law.0[7]
                    );
                }
                assert!(ramped.gain(a) >= least.gain(a));
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
        for (m, rho) in TARGETS
            .into_iter()
            .flat_map(|m| [(m, 0.0), (m, RAMP_DEFAULT)])
        {
            let law = Scheduled::for_plant(&p, m, rho);
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
    for rho in [0.0, RAMP_DEFAULT] {
        derivatives_are_the_torques(Scheduled::for_plant(&Params::default(), 0.3, rho));
    }
}

fn derivatives_are_the_torques(law: Scheduled) {
    let levels = law.levels();
    let (lo, hi) = (levels[0], levels[levels.len() - 1]);
    for (x, f) in [(0.3, 0.5), (-0.2, 0.3), (0.05, 0.8), (0.1, 0.1)] {
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
        for i in 0..8 {
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

fn closed_loop(p: &Params, gmin: f64, rho: f64) -> Model {
    let law = Scheduled::for_plant(p, gmin, rho);
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
    for rho in [0.0, RAMP_DEFAULT] {
        taylor_agrees_with_dop853(rho);
    }
}

fn taylor_agrees_with_dop853(rho: f64) {
    let p = Params::default();
    let m = closed_loop(&p, 0.3, rho);
    let law = Scheduled::for_plant(&p, 0.3, rho);
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
    assert!(worst < 1e-8, "ρ {rho}: largest difference {worst}");
}

/// The closed loop's curve ([`ModelCurve::scheduled`]) against the frozen closed loop written
/// here: at 81 loads on each plant, the followed equilibrium solves
/// g(x) + k(a)·(x − x_c) = μ + δa to 1e-12 of its terms, the curve gives back its load to 1e-10,
/// and the curve's speed δ/g'_curve equals a central difference of the followed equilibrium
/// away from the gain's levels (step 1e-6 in a: its error, 1e-12/6 times the third derivative,
/// measured 2.3e-7 of 15.6 at the steepest point, where it converges as h² to the curve's
/// value, is far below the 1e-6 allowed).
#[test]
fn the_closed_loop_curve_is_the_frozen_closed_loops() {
    for p in plants() {
        let xc = 1.0 / (3.0 * p.alpha);
        for (m, rho) in [(0.3, 0.0), (0.3, RAMP_DEFAULT), (3.0, RAMP_DEFAULT)] {
            let law = Scheduled::for_plant(&p, m, rho);
            let c = ModelCurve::scheduled(&closed_loop(&p, m, rho)).unwrap();
            let mut f = c.follower(c.start());
            let mut at = |a: f64| f.at(a, c.start());
            for i in 0..=80 {
                let a = -0.99 + 1.98 * f64::from(i) / 80.0;
                let x = at(a);
                let k = law.gain(a);
                let residual = p.g(x) + k * (x - xc) - p.mu - p.delta * a;
                let size = p.alpha * x.abs().powi(3)
                    + x * x
                    + (p.gamma.abs() + k) * x.abs()
                    + p.mu.abs()
                    + p.delta;
                let at_ = format!("{p:?}, g'min {m}, ρ {rho}, a = {a}");
                assert!(residual.abs() <= 1e-12 * size, "{at_}: {residual}");
                assert!((c.a_at(x) - a).abs() <= 1e-10, "{at_}: {}", c.a_at(x));
                // a difference across a level, where dk/da kinks (ρ = 0) or d²k/da² jumps, has
                // an error of the step's order: none within 1e-4 of one
                let h = 1e-6;
                if law.levels().iter().any(|l| (l - a).abs() < 1e-4) {
                    continue;
                }
                let fd = (at(a + h) - at(a - h)) / (2.0 * h);
                let speed = c.delta() / c.g_prime(x);
                assert!(
                    (fd - speed).abs() <= 1e-6 * fd.abs().max(1e-3),
                    "{at_}: {fd} vs {speed}"
                );
                assert!((c.stiffness(x) - (p.g_prime(x) + k)).abs() <= 1e-12 * (1.0 + k));
            }
        }
    }
}

/// With g'_min below the plant's least slope the gain is 0 everywhere, and the closed loop's
/// curve is the plant's: its facts equal the cubic's closed forms.
#[test]
fn without_a_gain_the_curve_is_the_plants() {
    let d = Params::default();
    for p in [
        Params { gamma: 1.0, ..d },
        Params {
            gamma: 3.0,
            delta: 4.0,
            ..d
        },
    ] {
        let least = p.gamma - 1.0 / (3.0 * p.alpha);
        let c = ModelCurve::scheduled(&closed_loop(&p, 0.3 * least, RAMP_DEFAULT)).unwrap();
        let close = |got: f64, want: f64, what: &str| {
            assert!(
                (got - want).abs() <= 1e-9 * want.abs().max(1e-9),
                "{what}: {got} vs {want}"
            );
        };
        assert_eq!(c.fold_band(), None);
        close(
            c.min_traversed_gprime(),
            p.min_traversed_gprime(),
            "least slope",
        );
        close(
            c.max_equilibrium_speed(),
            p.max_equilibrium_speed(),
            "speed",
        );
        close(c.max_first_order_lag(), p.max_first_order_lag(), "lag");
        close(
            c.slowest_relaxation().rate,
            p.slowest_relaxation().rate,
            "relaxation",
        );
        close(
            c.turning_point_relaxation().rate,
            p.turning_point_relaxation().rate,
            "turning points",
        );
    }
}

/// The ramp is C¹: dk/da on either side of each of its levels agrees (to 1e-3 of the largest
/// |dk/da| at a step of 1e-9), where the least gain's slope jumps there by a finite amount.
#[test]
fn the_ramp_has_no_kink() {
    let p = Params::default();
    for (rho, kinked) in [(0.0, true), (RAMP_DEFAULT, false), (0.3, false)] {
        let law = Scheduled::for_plant(&p, 3.0, rho);
        let scale = (0..=2000)
            .map(|i| law.gain_slope(-1.0 + f64::from(i) / 1000.0)[1].abs())
            .fold(0.0, f64::max);
        let levels = law.levels();
        let inner = if rho < 1.0 { 4 } else { 2 };
        assert_eq!(levels.len(), if rho == 0.0 { 2 } else { inner });
        for a in levels.into_iter().filter(|a| a.abs() < 1.0) {
            let h = 1e-9;
            let jump = (law.gain_slope(a + h)[1] - law.gain_slope(a - h)[1]).abs();
            assert_eq!(
                jump > 1e-3 * scale,
                kinked,
                "ρ {rho} at a = {a}: jump {jump} of {scale}"
            );
        }
    }
}

/// A passage of the cubic has one hump of the equilibrium's speed dx*/dτ (three sets without a
/// fold); the scheduled closed loop, stiffest at the soft middle, has two and a dip between,
/// which the ringing rule must not count as ringing.
#[test]
fn the_equilibriums_speed_has_one_hump_on_the_cubic_and_two_with_a_schedule() {
    for gamma in [1.0, 10.0, 30.0] {
        let p = Params {
            gamma,
            ..Params::default()
        };
        let half = 0.5 * p.slow_period();
        // the rising passage, a from −1 to 1
        let humps = p.speed_extrema(1.5 * half, 2.5 * half);
        assert_eq!(humps.len(), 1, "γ = {gamma}: {humps:?}");
    }
    let p = Params::default();
    let c = ModelCurve::scheduled(&closed_loop(&p, 3.0, RAMP_DEFAULT)).unwrap();
    let half = 0.5 * p.slow_period();
    let humps = c.speed_extrema(1.5 * half, 2.5 * half);
    let kinds: Vec<bool> = humps.iter().map(|h| h.2).collect();
    assert_eq!(kinds, [true, false, true], "{humps:?}");
}

/// At the study's bursting set with g'_min = 3 (every slope of the closed loop's curve at least
/// 3, past the open loop's boundary γ ≈ 2.2): the least gain, which kinks where it switches,
/// overshoots, each burst starting near a switching level; the ramped gain removes the bursts.
#[test]
fn the_ramped_schedule_removes_the_bursts_the_kinked_one_leaves() {
    let p = Params::default();
    let opts = BurstOptions::default();
    let kinked = closed_loop(&p, 3.0, 0.0);
    let r = response_model(&kinked, &opts).unwrap();
    assert_eq!(
        classify_model(&kinked, &r).unwrap().verdict,
        Verdict::Overshoot
    );
    let levels = Scheduled::for_plant(&p, 3.0, 0.0).levels();
    for b in &r.bursts {
        let near = levels
            .iter()
            .map(|l| (b.a_onset - l).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(near < 0.02, "onset at a = {} vs {levels:?}", b.a_onset);
    }
    let ramped = closed_loop(&p, 3.0, RAMP_DEFAULT);
    let r = response_model(&ramped, &opts).unwrap();
    assert_eq!(
        classify_model(&ramped, &r).unwrap().verdict,
        Verdict::NoBursts
    );
}

/// The closed loop's curve is refused, naming the model, where it is not known: the schedule's
/// phase running at another ω than the load's (its gain is no function of a), or a plant whose
/// static torque is not a study cubic.
#[test]
fn the_curve_is_refused_where_it_is_not_known() {
    let p = Params::default();
    let mut law = Scheduled::for_plant(&p, 0.3, RAMP_DEFAULT);
    law.0[6] *= 1.2;
    let m = Model::study(&p).with_term(AnyTerm::Scheduled(law)).unwrap();
    let err = response_model(&m, &BurstOptions::default())
        .unwrap_err()
        .to_string();
    assert!(err.contains("no function of the load"), "{err}");
    let piecewise = AnyTerm::new("piecewise", &[0.05, 0.5, 5.0, 0.3, 0.5, 0.0, 0.0]).unwrap();
    let law = Scheduled::for_plant(&p, 0.3, RAMP_DEFAULT);
    let m = Model::damped(p.mu, p.delta, p.omega)
        .with_term(piecewise)
        .unwrap()
        .with_term(AnyTerm::Scheduled(law))
        .unwrap();
    let err = ModelCurve::scheduled(&m).unwrap_err().to_string();
    assert!(err.contains("study cubic"), "{err}");
}

/// The tuner on the scheduled law ([`hdgear::control::tune`]) at the study's bursting set: the
/// least g'_min lies between the verdict table's last bursting and first burst-free targets
/// (2 and 3 with the default ramp), its lower end still bursts, and the tuned schedule leaves the
/// state where the open loop has it at the load's extremes (its gain is zero there).
#[test]
fn the_tuner_finds_the_least_target() {
    use hdgear::control::{ControlOptions, law_rest, tune};
    let p = Params::default();
    let rest = law_rest(Scheduled::KIND, &p, &ControlOptions::default()).unwrap();
    assert_eq!(rest, Scheduled::for_plant(&p, 1.0, RAMP_DEFAULT).0[1..]);
    let t = tune(&p, Scheduled::KIND, &rest, &BurstOptions::default(), 1e-2).unwrap();
    assert!(
        2.0 < t.below.gain && t.tuned.gain <= 3.0,
        "{} {}",
        t.below.gain,
        t.tuned.gain
    );
    assert!(!t.below.removes_bursts() && t.tuned.removes_bursts());
    assert!(t.tuned.static_shift < 1e-6, "{}", t.tuned.static_shift);
}
