//! The catalogue's piecewise-linear stiffness ([`hdgear::model::piecewise::Piecewise`]) against
//! its exact solution: on each segment x'' + x' + k·x = c + δ sin ωt is linear, solved here in
//! closed form (the forced response plus the damped free one), and the kinks are located on
//! that closed form by bisection, independently of hdgear's polynomial.

use hdgear::Params;
use hdgear::burst::{BurstOptions, response_model};
use hdgear::integrate::{Method, Options};
use hdgear::model::Model;
use hdgear::model::terms::AnyTerm;
use hdgear::simulate::{SimOptions, Start, simulate_model, simulate_model_steps};

/// The law's values [k₁, k₂, k₃, x₁, w₂, x₀, x_r] (sharp knees); every slope above 1/4, so each
/// segment's free motion is a damped oscillation (the closed form below has that case only).
const LAW: [f64; 7] = [1.0, 2.5, 6.0, 0.4, 0.6, 0.15, 0.0];
/// μ, δ, ω: the load swings x across both kinks on both sides.
const FORCING: [f64; 3] = [0.6, 3.2, 0.4];
const T_END: f64 = 80.0;

/// The segment of u = x − x₀ (0 … 4 from below) for a state moving in `direction` on a kink.
fn segment(u: f64, direction: f64) -> usize {
    let [_, _, _, x1, w2, ..] = LAW;
    let edges = [-(x1 + w2), -x1, x1, x1 + w2];
    edges
        .iter()
        .filter(|&&e| {
            if (u - e).abs() < 1e-12 {
                direction > 0.0
            } else {
                e < u
            }
        })
        .count()
}

/// The line P(u) = k·u + b on segment i.
fn line(i: usize) -> (f64, f64) {
    let [k1, k2, k3, x1, w2, ..] = LAW;
    let b2 = (k1 - k2) * x1;
    let b3 = b2 + (k2 - k3) * (x1 + w2);
    [(k3, -b3), (k2, -b2), (k1, 0.0), (k2, b2), (k3, b3)][i]
}

/// The exact motion on segment i from (t0, x0, v0): x(t) and x'(t).
#[derive(Clone, Copy)]
struct Piece {
    t0: f64,
    /// The forced response: x_p = m + B sin ωt + C cos ωt.
    m: f64,
    b: f64,
    c: f64,
    /// The free response e^{−s/2}(a1 cos βs + a2 sin βs), s = t − t0.
    beta: f64,
    a1: f64,
    a2: f64,
}

impl Piece {
    fn new(i: usize, t0: f64, x0: f64, v0: f64) -> Piece {
        let [mu, delta, w] = FORCING;
        let (k, b_line) = line(i);
        // x'' + x' + k(x − x₀) + b = μ + δ sin ωt
        let m = (mu - b_line) / k + LAW[5];
        let d = (k - w * w).powi(2) + w * w;
        let (b, c) = (delta * (k - w * w) / d, -delta * w / d);
        let beta = (4.0 * k - 1.0).sqrt() / 2.0;
        let (s, co) = (w * t0).sin_cos();
        let (xp, vp) = (m + b * s + c * co, w * (b * co - c * s));
        let a1 = x0 - xp;
        // x_h'(t0) = −a1/2 + β·a2
        let a2 = (v0 - vp + 0.5 * a1) / beta;
        Piece {
            t0,
            m,
            b,
            c,
            beta,
            a1,
            a2,
        }
    }

    fn state(&self, t: f64) -> [f64; 2] {
        let w = FORCING[2];
        let (s, co) = (w * t).sin_cos();
        let tau = t - self.t0;
        let e = (-0.5 * tau).exp();
        let (sb, cb) = (self.beta * tau).sin_cos();
        let h = e * (self.a1 * cb + self.a2 * sb);
        let dh =
            e * (-0.5 * (self.a1 * cb + self.a2 * sb) + self.beta * (-self.a1 * sb + self.a2 * cb));
        [
            self.m + self.b * s + self.c * co + h,
            w * (self.b * co - self.c * s) + dh,
        ]
    }
}

/// The interval of u on segment i.
fn bounds(i: usize) -> (f64, f64) {
    let [_, _, _, x1, w2, ..] = LAW;
    let edges = [
        f64::NEG_INFINITY,
        -(x1 + w2),
        -x1,
        x1,
        x1 + w2,
        f64::INFINITY,
    ];
    (edges[i], edges[i + 1])
}

/// The exact run from rest at x = 0: samples (t, x, x') every `dt` and the kink crossings
/// (t, x). The closed form is scanned every 1e-3 for leaving its segment, then bisected.
fn exact(dt: f64) -> (Vec<[f64; 3]>, Vec<(f64, f64)>) {
    let x0 = LAW[5];
    let (mut t, mut y) = (0.0, [0.0, 0.0]);
    let mut seg = segment(y[0] - x0, y[1]);
    let mut piece = Piece::new(seg, t, y[0], y[1]);
    let (mut samples, mut kinks) = (vec![[0.0, 0.0, 0.0]], vec![]);
    let mut next = dt;
    let mut record = |upto: f64, piece: &Piece, next: &mut f64| {
        while *next <= upto.min(T_END) + 1e-12 {
            let s = piece.state(*next);
            samples.push([*next, s[0], s[1]]);
            *next += dt;
        }
    };
    while t < T_END {
        let t1 = (t + 1e-3).min(T_END);
        let (lo_u, hi_u) = bounds(seg);
        let inside = |ts: f64| (lo_u..=hi_u).contains(&(piece.state(ts)[0] - x0));
        if inside(t1) {
            record(t1, &piece, &mut next);
            t = t1;
            continue;
        }
        // the crossing: bisection on the closed form to the last bits of t
        let (mut lo, mut hi) = (t, t1);
        while hi - lo > 2.0 * f64::EPSILON * hi {
            let mid = 0.5 * (lo + hi);
            if inside(mid) { lo = mid } else { hi = mid }
        }
        record(lo, &piece, &mut next);
        t = lo;
        y = piece.state(t);
        kinks.push((t, y[0]));
        // on the kink: the segment the motion enters
        seg = segment(y[0] - x0, y[1]);
        piece = Piece::new(seg, t, y[0], y[1]);
    }
    (samples, kinks)
}

fn model() -> Model {
    let [mu, delta, w] = FORCING;
    Model::damped(mu, delta, w)
        .with_term(AnyTerm::new("piecewise", &LAW).unwrap())
        .unwrap()
}

fn opts(method: Method, tol: f64, dt: f64) -> SimOptions {
    SimOptions {
        t_end: T_END,
        dt,
        start: Start::Rest,
        tol: Options {
            method,
            rtol: tol,
            atol: tol,
            ..Options::default()
        },
    }
}

/// hdgear's samples of (t, x, x') on the grid.
fn run(method: Method, tol: f64, dt: f64) -> Vec<[f64; 3]> {
    let mut out = vec![];
    simulate_model(&model(), &opts(method, tol, dt), |t, y| {
        out.push([t, y[0], y[1]])
    })
    .unwrap();
    out
}

fn worst(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(p, q)| {
            assert!((p[0] - q[0]).abs() < 1e-9, "{p:?} {q:?}");
            (p[1] - q[1]).abs().max((p[2] - q[2]).abs())
        })
        .fold(0.0, f64::max)
}

/// The Taylor steps end on the kinks: the trajectory equals the closed form to 1e-12 (integrated
/// at 1e-12; 41 crossings in 80 time units, each located to the last bits of t on both sides,
/// and the closed form's own rounding in its exponentials), and every crossing of the closed
/// form is the end of one of hdgear's steps, to 1e-9 in t. Without the cuts the error is 0.23.
#[test]
fn taylor_steps_end_on_the_kinks_and_follow_the_exact_solution() {
    let (reference, kinks) = exact(0.5);
    assert!(kinks.len() >= 12, "{} crossings", kinks.len());
    let [_, _, _, x1, w2, x0, _] = LAW;
    for (_, x) in &kinks {
        let u = (x - x0).abs();
        assert!((u - x1).abs() < 1e-12 || (u - x1 - w2).abs() < 1e-12, "{x}");
    }
    // both kinks on both sides are crossed
    for kink in [-(x1 + w2), -x1, x1, x1 + w2] {
        assert!(
            kinks.iter().any(|(_, x)| (x - x0 - kink).abs() < 1e-12),
            "{kink}"
        );
    }
    let taylor = run(Method::Taylor, 1e-12, 0.5);
    let err = worst(&taylor, &reference);
    assert!(err < 1e-12, "Taylor against the closed form: {err:e}");

    let mut ends = vec![];
    simulate_model_steps(
        &model(),
        &opts(Method::Taylor, 1e-12, 0.5),
        |_, _| {},
        |s| ends.push(s.span().1),
    )
    .unwrap();
    for (tk, _) in &kinks {
        let nearest = ends
            .iter()
            .map(|e| (e - tk).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest < 1e-9,
            "crossing at {tk}: nearest step end {nearest:e} away"
        );
    }
}

/// DOP853, whose steps are not cut at the kinks, follows the closed form to its tolerance's
/// order (1e-7 at 1e-10, measured 1.4e-8: its error control shortens the steps about each kink,
/// where its order drops, and the local errors of the 41 crossings add up).
#[test]
fn dop853_follows_the_exact_solution_to_its_tolerance() {
    let (reference, _) = exact(0.5);
    let err = worst(&run(Method::Dop853, 1e-10, 0.5), &reference);
    assert!(err < 1e-7, "DOP853 against the closed form: {err:e}");
}

/// The static law: continuous at the kinks, odd about x₀, with the catalogue's torques at the
/// kinks (k₁x₁ and k₁x₁ + k₂w₂), and the Jacobian's slope that of the segment.
#[test]
fn the_law_is_the_catalogue_curve() {
    let t = AnyTerm::new("piecewise", &LAW).unwrap();
    let [k1, k2, k3, x1, w2, x0, _] = LAW;
    let p = |u: f64| t.torque(x0 + u, 0.0, 0.0);
    assert_eq!(p(0.0), 0.0);
    assert!((p(x1) - k1 * x1).abs() < 1e-15);
    assert!((p(x1 + w2) - (k1 * x1 + k2 * w2)).abs() < 1e-14);
    for u in [0.1, 0.5, 0.9, 1.3, 3.0] {
        assert_eq!(p(-u), -p(u));
        let slope = if u <= x1 {
            k1
        } else if u <= x1 + w2 {
            k2
        } else {
            k3
        };
        assert_eq!(t.gradient(x0 + u, 0.0, 0.0)[0], slope);
        // a central difference within the segment
        let fd = (p(u + 1e-7) - p(u - 1e-7)) / 2e-7;
        assert!((fd - slope).abs() < 1e-6, "{u}: {fd}");
    }
    for e in [x1, x1 + w2] {
        let (below, above) = (p(e - 1e-12), p(e + 1e-12));
        assert!((above - below).abs() < 1e-10, "continuous at {e}");
    }
}

/// A piecewise stiffness on the study's model is linear where its kinks are far, and the study's
/// verdict then holds with γ + k₁: its equilibria are a parameter set's only while they stay on
/// the first segment. Kinks at |x| = 3.5, beyond every fixed sample point: a load that keeps the
/// equilibria within |x| < 1.2 gives γ' = γ + k₁; one that takes them past the kink (δ = 800,
/// x* ≈ 3.7 at a = 1) gives no set, and the burst verdict is judged against the model's own
/// curve, not the cubic's.
#[test]
fn the_study_set_of_a_piecewise_model_holds_only_where_its_equilibria_lie() {
    let law = AnyTerm::new("piecewise", &[0.5, 3.0, 9.0, 3.5, 1.0, 0.0, 0.0]).unwrap();
    let p = Params::default();
    let m = Model::study(&p).with_term(law).unwrap();
    let q = m
        .equivalent_params()
        .expect("equilibria on the first segment");
    assert_eq!(
        (q.alpha, q.eps),
        (p.alpha, p.gamma * p.eps / (p.gamma + 0.5))
    );
    assert!((q.gamma - (p.gamma + 0.5)).abs() < 1e-15);
    let far = Model::study(&Params { delta: 800.0, ..p })
        .with_term(law)
        .unwrap();
    let top = far.stable_equilibrium(1.0).unwrap();
    assert!(top > 3.5, "{top}");
    assert_eq!(far.equivalent_params(), None);
    // the verdict is measured against the model's own curve: its extent runs from the lowest
    // equilibrium at a = −1 to the highest at a = 1, past the kink
    let r = response_model(&far, &BurstOptions::default()).unwrap();
    let [mu, delta, _] = far.forcing();
    let lo = far.equilibria_at(mu - delta).unwrap()[0];
    let hi = *far.equilibria_at(mu + delta).unwrap().last().unwrap();
    assert!(
        (r.x_extent - (hi - lo)).abs() <= 1e-12 * (hi - lo),
        "{} vs {}",
        r.x_extent,
        hi - lo
    );
    hdgear::burst::classify_model(&far, &r).unwrap();
}

/// A start a rounding error past a kink, with the acceleration pointing back across it (a drive
/// whose mean load is its knee torque, the quasi-static start rounding to the far side): the
/// Taylor steps start on the segment the motion enters rather than stalling at the edge, and
/// follow DOP853 to 1e-8.
#[test]
fn a_start_a_rounding_error_past_a_kink_steps_on() {
    let kink = LAW[3] + LAW[5];
    let x0 = kink + 2.0 * f64::EPSILON * kink.abs().max(1.0);
    let probe = AnyTerm::new("piecewise", &LAW).unwrap();
    // the mean load a little below the torque at x0: x'' < 0 at the start, the sine then rising
    let mu = probe.torque(x0, 0.0, 0.0) - 1e-13;
    let m = Model::damped(mu, 0.3, 0.05)
        .with_term(AnyTerm::new("piecewise", &LAW).unwrap())
        .unwrap();
    let run = |method| {
        let mut o = opts(method, 1e-11, 0.5);
        o.t_end = 20.0;
        o.start = Start::Given { x0, v0: 0.0 };
        let mut out = vec![];
        simulate_model(&m, &o, |t, y| out.push([t, y[0], y[1]])).unwrap();
        out
    };
    let (taylor, dop) = (run(Method::Taylor), run(Method::Dop853));
    assert!(worst(&taylor, &dop) < 1e-8, "{}", worst(&taylor, &dop));
}

/// The rounded law written out here from its definition, apart from the term's code: each
/// max(y, 0) = (y + |y|)/2 of the sharp law with |y| replaced by √(y² + r²),
/// P_r(u) = k₁u + (k₂ − k₁)(h(u − x₁) − h(−u − x₁)) + (k₃ − k₂)(h(u − x₂) − h(−u − x₂)).
fn rounded_by_hand(u: f64, r: f64) -> f64 {
    let [k1, k2, k3, x1, w2, ..] = LAW;
    let h = |y: f64| 0.5 * (y + (y * y + r * r).sqrt());
    let x2 = x1 + w2;
    k1 * u + (k2 - k1) * (h(u - x1) - h(-u - x1)) + (k3 - k2) * (h(u - x2) - h(-u - x2))
}

/// The law with its knees rounded over `r`.
fn rounded(r: f64) -> [f64; 7] {
    let mut law = LAW;
    law[6] = r;
    law
}

/// x'' + x' + P_r(x − x₀) = μ + δ sin ωt by hand.
struct RoundedByHand(f64);

impl hdgear::integrate::System<2> for RoundedByHand {
    fn rhs(&self, t: f64, y: &[f64; 2]) -> [f64; 2] {
        let [mu, delta, w] = FORCING;
        let torque = rounded_by_hand(y[0] - LAW[5], self.0);
        [y[1], mu + delta * (w * t).sin() - y[1] - torque]
    }
}

/// The rounded law is its definition (to rounding, over both knees on both sides), and within
/// (|k₂ − k₁| + |k₃ − k₂|)·x_r of the sharp law everywhere: each |y| moves by at most x_r.
#[test]
fn rounded_knees_are_their_definition_and_near_the_sharp_law() {
    let sharp = AnyTerm::new("piecewise", &LAW).unwrap();
    let [k1, k2, k3, x1, w2, x0, _] = LAW;
    for r in [0.2, 0.01, 1e-4] {
        let term = AnyTerm::new("piecewise", &rounded(r)).unwrap();
        for i in 0..=400 {
            let u = -3.0 + 6.0 * f64::from(i) / 400.0;
            let t = term.torque(u + x0, 0.0, 0.0);
            let by_hand = rounded_by_hand(u, r);
            assert!(
                (t - by_hand).abs() < 1e-13 * (1.0 + t.abs()),
                "{u}: {t} vs {by_hand}"
            );
            let gap = (t - sharp.torque(u + x0, 0.0, 0.0)).abs();
            assert!(
                gap <= ((k2 - k1).abs() + (k3 - k2).abs()) * r * (1.0 + 1e-12),
                "{u}: {gap}"
            );
        }
        // at the first knee the gap is about half the slope change times the rounding
        let knee = term.torque(x1 + x0, 0.0, 0.0) - sharp.torque(x1 + x0, 0.0, 0.0);
        let x2 = x1 + w2;
        let expected = 0.5 * (k2 - k1) * (r - ((2.0 * x1).powi(2) + r * r).sqrt() + 2.0 * x1)
            + 0.5
                * (k3 - k2)
                * (((x1 - x2).powi(2) + r * r).sqrt()
                    - ((x1 + x2).powi(2) + r * r).sqrt()
                    - (x2 - x1)
                    + (x1 + x2));
        assert!((knee - expected).abs() < 1e-12, "{knee} vs {expected}");
    }
}

/// The state at T_END from rest of `sys` with `method` at 1e-12.
fn final_state<S: hdgear::integrate::System<2>>(sys: &S, method: Method) -> [f64; 2] {
    crate::common::end_state(sys, method, 1e-12, [0.0, 0.0], T_END).0
}

/// Taylor's method on the rounded law (√'s recurrence, no events) against DOP853 on the law
/// written by hand, both at 1e-12, over the run that crosses both knees on both sides.
#[test]
fn rounded_knees_follow_their_equation_written_by_hand() {
    let [mu, delta, w] = FORCING;
    for r in [0.2, 0.02] {
        let m = Model::damped(mu, delta, w)
            .with_term(AnyTerm::new("piecewise", &rounded(r)).unwrap())
            .unwrap();
        let a = final_state(&m, Method::Taylor);
        let b = final_state(&RoundedByHand(r), Method::Dop853);
        let scale = 1.0 + a[0].abs().max(a[1].abs());
        assert!(
            (a[0] - b[0]).abs().max((a[1] - b[1]).abs()) < 1e-8 * scale,
            "x_r {r}: {a:?} vs {b:?}"
        );
    }
}

/// As the rounding shrinks the trajectory converges to the sharp law's closed form: at least
/// first order in x_r (the torques differ by O(x_r) within O(x_r) of a knee, by O(x_r²) off it).
#[test]
fn rounded_knees_converge_to_the_sharp_law() {
    let (exact_samples, _) = exact(0.5);
    let [mu, delta, w] = FORCING;
    let errors: Vec<f64> = [1e-2, 1e-3, 1e-4]
        .iter()
        .map(|&r| {
            let m = Model::damped(mu, delta, w)
                .with_term(AnyTerm::new("piecewise", &rounded(r)).unwrap())
                .unwrap();
            let mut out = vec![];
            simulate_model(&m, &opts(Method::Taylor, 1e-12, 0.5), |t, y| {
                out.push([t, y[0], y[1]])
            })
            .unwrap();
            worst(&out, &exact_samples)
        })
        .collect();
    for pair in errors.windows(2) {
        assert!(pair[1] < pair[0] / 3.0, "{errors:?}");
    }
}

/// The smallest rounding accepted (the magnitude limit 1e-100; below it the value is refused,
/// naming `xr`), started exactly on a knee at rest, where the law's √ is x_r: the series' radius
/// is x_r's size there, and the run ends with a result or a typed error, never a panic or a
/// non-finite state taken for a result.
#[test]
fn a_vanishing_rounding_started_on_a_knee_fails_cleanly() {
    use hdgear::integrate::{Stepper, stepper};
    let refused = AnyTerm::new("piecewise", &rounded(1e-200)).unwrap_err();
    assert!(refused.to_string().contains("xr"), "{refused}");
    let [mu, delta, w] = FORCING;
    let m = Model::damped(mu, delta, w)
        .with_term(AnyTerm::new("piecewise", &rounded(1e-100)).unwrap())
        .unwrap();
    let knee = LAW[3] + LAW[5];
    let o = Options {
        rtol: 1e-10,
        atol: 1e-10,
        max_steps: 100_000,
        ..Options::default()
    };
    let outcome = stepper(&m, 0.0, [knee, 0.0], o).and_then(|mut s| {
        while s.t() < 1.0 {
            s.step(1.0)?;
        }
        Ok(*s.y())
    });
    if let Ok(y) = outcome {
        assert!(y.iter().all(|v| v.is_finite()), "{y:?}");
    }
}
