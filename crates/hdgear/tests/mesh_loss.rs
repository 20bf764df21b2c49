//! The torque-proportional mesh loss μ_m·|T_s(x)|·σ, σ' = x'(1 − sgn(x')σ)/θ_m, on the study's
//! cubic and on a catalogue's piecewise curve: against an independent event-driven integration
//! written here from the equations (classical RK4 with the signs of x', of T_s and of the
//! curve's kinks fixed on each piece, a restart at every sign change located by bisection on a
//! single RK4 step), the derived Jacobian against finite differences, the quasi-static branches
//! against their closed forms (1 ± μ_m)·T_s(x) = load, and a loss of 0 against the model without
//! it.

use hdgear::Params;
use hdgear::integrate::{Method, Options, System};
use hdgear::model::Model;
use hdgear::model::terms::AnyTerm;
use hdgear::simulate::{SimOptions, Start, simulate_model};

/// The elastic law written out here: the study's cubic, or the odd three-segment curve
/// [k₁, k₂, k₃, x₁, x₂] (kinks at ±x₁, ±x₂, no offset).
#[derive(Clone, Copy, Debug)]
enum Law {
    Cubic(Params),
    Segments([f64; 5]),
}

impl Law {
    /// The twists where the law changes piece.
    fn kinks(self) -> Vec<f64> {
        match self {
            Law::Cubic(_) => vec![],
            Law::Segments([.., x1, x2]) => vec![-x2, -x1, x1, x2],
        }
    }
    /// T_s(x) on the piece where sgn(x − kink_i) = `side[i]`: each kink's ramp max(0, x − c) or
    /// min(0, x + c) taken as the line of that side, so the law is a polynomial on the piece.
    fn torque(self, x: f64, side: &[f64]) -> f64 {
        match self {
            Law::Cubic(p) => p.alpha * x * x * x - x * x + p.gamma * (x - p.eps),
            Law::Segments([k1, k2, k3, x1, x2]) => {
                let ramp = |c: f64, s_minus: f64, s_plus: f64| {
                    // max(0, x − c) on side s_plus of c, min(0, x + c) on side s_minus of −c
                    let up = if s_plus > 0.0 { x - c } else { 0.0 };
                    let down = if s_minus < 0.0 { x + c } else { 0.0 };
                    up + down
                };
                k1 * x
                    + (k2 - k1) * ramp(x1, side[1], side[2])
                    + (k3 - k2) * ramp(x2, side[0], side[3])
            }
        }
    }
}

/// x'' = load(t) − x' − T_s(x) − μ_m·|T_s(x)|·σ, σ' = x'(1 − sgn(x')σ)/θ_m.
struct Reference<'a> {
    load: &'a dyn Fn(f64) -> f64,
    law: Law,
    mu_m: f64,
    theta: f64,
    h: f64,
}

/// The signs the pieces are fixed by: x', T_s, then x − c for each kink c.
type Signs = Vec<f64>;

impl Reference<'_> {
    fn rhs(&self, t: f64, y: [f64; 3], s: &Signs) -> [f64; 3] {
        let [x, v, sigma] = y;
        let ts = self.law.torque(x, &s[2..]);
        let loss = self.mu_m * s[1] * ts * sigma;
        [
            v,
            (self.load)(t) - v - ts - loss,
            v * (1.0 - s[0] * sigma) / self.theta,
        ]
    }
    /// The values whose signs fix the piece, at y on the piece `s`.
    fn watched(&self, y: [f64; 3], s: &Signs) -> Signs {
        let mut w = vec![y[1], self.law.torque(y[0], &s[2..])];
        w.extend(self.law.kinks().iter().map(|c| y[0] - c));
        w
    }
    fn rk4(&self, t: f64, y: [f64; 3], h: f64, s: &Signs) -> [f64; 3] {
        crate::common::rk4_step(|t, y| self.rhs(t, y, s), t, y, h)
    }
    /// Samples every `dt` from rest at x = 0 (σ = 0) to `t_end`.
    fn run(&self, t_end: f64, dt: f64) -> Vec<[f64; 3]> {
        let (mut t, mut y) = (0.0, [0.0; 3]);
        // at rest at 0 every sign follows from where the motion goes: x'' = load(0) − T_s(0)
        let mut s: Signs = vec![1.0, 1.0];
        s.extend(self.law.kinks().iter().map(|c| -c.signum()));
        let a0 = self.rhs(0.0, y, &s)[1];
        s[0] = a0.signum();
        s[1] = self.law.torque(0.0, &s[2..]).signum();
        let mut out = vec![y];
        let mut k = 1;
        while t < t_end {
            let next = (k as f64 * dt).min(t_end);
            let h = self.h.min(next - t);
            let y1 = self.rk4(t, y, h, &s);
            let w1 = self.watched(y1, &s);
            let crossed = (0..s.len())
                .filter(|&i| s[i] * w1[i] < 0.0)
                .map(|i| {
                    let before = |tau| s[i] * self.watched(self.rk4(t, y, tau, &s), &s)[i] > 0.0;
                    (i, crate::common::crossing(t, h, before))
                })
                .min_by(|a, b| a.1.total_cmp(&b.1));
            if let Some((i, tau)) = crossed {
                y = self.rk4(t, y, tau, &s);
                t += tau;
                if i == 0 {
                    y[1] = 0.0;
                    // x' leaves 0 along the acceleration (none of these laws sticks)
                    s[0] = -s[0];
                } else {
                    s[i] = -s[i];
                }
                continue;
            }
            (t, y) = (if h == next - t { next } else { t + h }, y1);
            if t == next {
                out.push(y);
                k += 1;
            }
        }
        out
    }
}

fn loss(mu_m: f64, theta: f64) -> AnyTerm {
    AnyTerm::new("meshloss", &[mu_m, theta]).unwrap()
}

/// The model of a case, and its reference's load and law.
fn cases() -> Vec<(Model, Law, f64, f64)> {
    let p = Params {
        delta: 3.0,
        omega: 0.7,
        gamma: 1.0,
        ..Params::default()
    };
    let study = Model::study(&p).with_term(loss(0.3, 0.05)).unwrap();
    // a catalogue-like curve swept across both kinks each way
    let (k1, k2, k3, x1, w2) = (1.0, 2.0, 4.0, 0.5, 1.0);
    let curve = AnyTerm::new("piecewise", &[k1, k2, k3, x1, w2, 0.0, 0.0]).unwrap();
    let catalogue = Model::damped(0.5, 6.0, 0.6)
        .with_term(curve)
        .unwrap()
        .with_term(loss(0.25, 0.02))
        .unwrap();
    vec![
        (study, Law::Cubic(p), 0.3, 0.05),
        (
            catalogue,
            Law::Segments([k1, k2, k3, x1, x1 + w2]),
            0.25,
            0.02,
        ),
    ]
}

fn hdgear_run(m: &Model, method: Method, t_end: f64, dt: f64) -> Vec<[f64; 3]> {
    let opts = SimOptions {
        t_end,
        dt,
        start: Start::Rest,
        tol: crate::common::tight(method),
    };
    let mut out = vec![];
    simulate_model(m, &opts, |_, y| out.push([y[0], y[1], y[2]])).unwrap();
    out
}

fn worst(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .flat_map(|(a, b)| (0..3).map(move |i| (a[i] - b[i]).abs()))
        .fold(0.0, f64::max)
}

/// Both methods against the reference at rtol = atol = 1e-13, to 1e-9 over 40 time units in
/// which x' and T_s change sign several times (counted: else the cuts would go untested); DOP853
/// on the kinked curve to 1e-7.
#[test]
fn mesh_loss_matches_an_independent_event_driven_integration() {
    let (t_end, dt) = (40.0, 0.05);
    for (m, law, mu_m, theta) in cases() {
        let [mu, delta, omega] = m.forcing();
        let load = move |t: f64| mu + delta * (omega * t).sin();
        let reference = |h| {
            Reference {
                load: &load,
                law,
                mu_m,
                theta,
                h,
            }
            .run(t_end, dt)
        };
        let (r, r2) = (reference(2e-4), reference(1e-4));
        // RK4's error is of order h⁴: the finer run's is |r − r2|/15 (Richardson)
        let own = worst(&r, &r2) / 15.0;
        assert!(own < 1e-10, "{law:?}: reference not converged: {own:e}");
        // sign changes of x' (i = 0) and of the cubic's T_s (i = 1) in the reference's samples
        let changes = |i: usize| {
            let f = |y: &[f64; 3]| if i == 0 { y[1] } else { law.torque(y[0], &[]) };
            r2.windows(2).filter(|w| f(&w[0]) * f(&w[1]) < 0.0).count()
        };
        assert!(
            changes(0) >= 4,
            "{law:?}: x' through 0 {} times",
            changes(0)
        );
        if let Law::Cubic(_) = law {
            assert!(
                changes(1) >= 4,
                "{law:?}: T_s through 0 {} times",
                changes(1)
            );
        }
        for method in Method::ALL {
            let e = worst(&hdgear_run(&m, method, t_end, dt), &r2);
            eprintln!("{law:?} {method:?}: max |Δ| {e:.2e} (reference's own {own:.1e})");
            // DOP853's steps are not cut at a curve's kinks, where its order drops: the bound
            // tests/piecewise.rs holds it to there (Taylor's steps end on every kink)
            let bound = match (law, method) {
                (Law::Segments(_), Method::Dop853) => 1e-7,
                _ => 1e-9,
            };
            assert!(e < bound, "{law:?} {method:?}: differs by {e:e}");
        }
        // at the commands' default tolerance (1e-10) too: a step that ends on a sign change of
        // T_s must not leave the next one a rounding error on the old side (it did, and the steps
        // shrank to nothing there)
        let loose = SimOptions {
            t_end,
            dt,
            start: Start::Rest,
            tol: Options {
                rtol: 1e-10,
                atol: 1e-10,
                ..Options::default()
            },
        };
        let mut out = vec![];
        simulate_model(&m, &loose, |_, y| out.push([y[0], y[1], y[2]])).unwrap();
        let e = worst(&out, &r2);
        eprintln!("{law:?} Taylor at 1e-10: max |Δ| {e:.2e}");
        assert!(e < 1e-7, "{law:?} at 1e-10: differs by {e:e}");
    }
}

/// The catalogue case's twist crosses 0 (where its T_s changes sign) and both kinks each way.
#[test]
fn the_catalogue_case_crosses_its_kinks_and_its_sign_change() {
    let (m, law, ..) = cases().pop().unwrap();
    let Law::Segments([.., x1, x2]) = law else {
        unreachable!()
    };
    let run = hdgear_run(&m, Method::Taylor, 40.0, 0.05);
    let crossings = |c: f64| {
        run.windows(2)
            .filter(|w| (w[0][0] - c) * (w[1][0] - c) < 0.0)
            .count()
    };
    for c in [-x2, -x1, 0.0, x1, x2] {
        assert!(crossings(c) >= 4, "x = {c} crossed {} times", crossings(c));
    }
}

/// The derived Jacobian equals a central finite difference of the right-hand side, away from
/// the switches, on both laws.
#[test]
fn mesh_loss_jacobian_matches_finite_differences() {
    for (m, ..) in cases() {
        for y in [
            [0.4, 0.3, 0.2],
            [-0.2, -0.8, -0.6],
            [1.7, 0.05, 0.9],
            [-1.2, 0.4, -0.3],
        ] {
            let j = System::<3>::jacobian(&m, 1.3, &y).unwrap();
            for c in 0..3 {
                let h = 1e-6 * y[c].abs().max(1.0);
                let (mut a, mut b) = (y, y);
                a[c] += h;
                b[c] -= h;
                let (fa, fb) = (m.rhs(1.3, &a), m.rhs(1.3, &b));
                for r in 0..3 {
                    let d = (fa[r] - fb[r]) / (2.0 * h);
                    let e = (d - j[r][c]).abs() / d.abs().max(1.0);
                    assert!(e < 1e-7, "at {y:?}: ∂f{r}/∂y{c} {} against {d}", j[r][c]);
                }
            }
        }
    }
}

/// Creeping with x' → 0±, σ settles at ±1 within a few θ_m of twist after each reversal, and
/// the branches are (1 ± μ_m)·T_s(x) = μ + δa (T_s > 0 here): the study's closed-form
/// equilibrium at the load scaled by 1/(1 ± μ_m). Checked where the twist has moved 30 θ_m past
/// the reversal (σ within 2e^{−30} of ±1), to the branches' RK4 balance error.
#[test]
fn mesh_loss_branches_are_the_curve_at_the_scaled_load() {
    // a load of one sign (μ > δ), so T_s keeps its sign along both branches
    let p = Params {
        gamma: 2.0,
        mu: 20.0,
        omega: 0.01,
        ..Params::default()
    };
    let (mu_m, theta) = (0.25, 1e-3);
    let b = Model::study(&p)
        .with_term(loss(mu_m, theta))
        .unwrap()
        .branches()
        .unwrap();
    let mut checked = 0;
    let mut worst: f64 = 0.0;
    for branch in [&b.loading, &b.unloading] {
        assert_eq!(branch.fold, None);
        let start = branch.points[0].x;
        for q in branch
            .points
            .iter()
            .filter(|q| (q.x - start).abs() > 30.0 * theta)
        {
            let load = p.mu + p.delta * q.a;
            let scaled = load / (1.0 + branch.side * mu_m);
            let closed = hdgear::fast::stable_equilibrium(&p, (scaled - p.mu) / p.delta);
            worst = worst.max((q.x - closed).abs());
            checked += 1;
        }
    }
    println!("mesh-loss branches against (1 ± μ_m)·g(x) = load: worst |Δx| {worst:.1e}");
    assert!(checked > 1000, "{checked} points checked");
    assert!(worst < 1e-9, "{worst:e}");
}

/// With μ_m = 0 the loss is 0 whatever σ does: x and x' are the study model's, to the two
/// runs' tolerance (the model with the term is integrated piece by piece, cut where x' = 0, so
/// its steps differ). A model with no elastic law to read, or two, is refused naming the term.
#[test]
fn a_loss_of_zero_is_the_study_model_and_bad_assemblies_are_refused() {
    let p = Params::default();
    let opts = SimOptions {
        t_end: 100.0,
        dt: 0.5,
        start: Start::Rest,
        tol: crate::common::tight(Method::Taylor),
    };
    let run = |m: &Model| {
        let mut out = vec![];
        simulate_model(m, &opts, |_, y| out.push([y[0], y[1]])).unwrap();
        out
    };
    let plain = run(&Model::study(&p));
    let lossless = run(&Model::study(&p).with_term(loss(0.0, 0.01)).unwrap());
    let e = plain
        .iter()
        .zip(&lossless)
        .flat_map(|(a, b)| [(a[0] - b[0]).abs(), (a[1] - b[1]).abs()])
        .fold(0.0, f64::max);
    println!("μ_m = 0 against the study model: max |Δ| {e:.1e}");
    assert!(e < 1e-9, "{e:e}");
    let none = Model::damped(0.1, 1.0, 0.1).with_term(loss(0.2, 0.01));
    let msg = none.unwrap_err().to_string();
    assert!(msg.contains("meshloss") && msg.contains("none"), "{msg}");
    let curve = AnyTerm::new("piecewise", &[1.0, 2.0, 4.0, 0.5, 1.0, 0.0, 0.0]).unwrap();
    let two = Model::study(&p)
        .with_term(curve)
        .unwrap()
        .with_term(loss(0.2, 0.01));
    let msg = two.unwrap_err().to_string();
    assert!(msg.contains("meshloss") && msg.contains("two"), "{msg}");
}

/// Changing the elastic law's parameter changes the transmitted torque the loss reads.
#[test]
fn the_loss_reads_the_law_after_a_parameter_change() {
    let p = Params::default();
    let m = Model::study(&p).with_term(loss(0.25, 0.01)).unwrap();
    let stiffer = m.with(m.param("gamma").unwrap(), 3.0).unwrap();
    let y = [0.9, 0.0, 1.0];
    let q = Params { gamma: 3.0, ..p };
    let expected = q.g(0.9) * 1.25;
    assert!((stiffer.torque_at(&y) - expected).abs() < 1e-13 * expected.abs());
}
