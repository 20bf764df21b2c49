//! Terms derived from one declaration ([`hdgear::model::law`]), and every kind of term held to
//! its own value: each kind's Jacobian and parameter derivatives (derived for a declared law,
//! written by hand for the others) against central finite differences of its torque and rate;
//! each kind's Taylor rows, summed along a motion whose series is known, against its torque and
//! rate evaluated along that motion; and the declared quadratic damping integrated by Taylor's
//! method against a Runge–Kutta integration of its equation written here.

use hdgear::Params;
use hdgear::integrate::Method;
use hdgear::integrate::taylor::{SCRATCH_ROWS, Scratch};
use hdgear::model::Model;
use hdgear::model::law::{Declared, Law, Num, Vars};
use hdgear::model::terms::{AnyTerm, Domain, MAX_ROWS, ParamInfo, Side, Term};

use crate::common::uniform;

/// Each kind at its parameters' defaults moved by a random factor in [0.7, 1.3] (whole-number
/// parameters at their defaults, a default of 0 drawn in (0, 0.5]) so no derivative vanishes by
/// a parameter being 0.
fn random_term(kind: &str, u: &mut impl FnMut() -> f64) -> Option<AnyTerm> {
    let values: Vec<f64> = AnyTerm::params_of(kind)?
        .iter()
        .map(|q| match q.domain {
            Domain::Exponent | Domain::Line => q.default,
            _ if q.default == 0.0 => 0.05 + 0.45 * u(),
            Domain::Fraction => (q.default * (0.7 + 0.6 * u())).min(1.0),
            _ => q.default * (0.7 + 0.6 * u()),
        })
        .collect();
    AnyTerm::new(kind, &values).ok()
}

/// A random point (x, v, z) with v and z away from 0 (a switching law is smooth on its piece
/// there), and the term on that point's piece.
fn point_on_piece(t: AnyTerm, u: &mut impl FnMut() -> f64) -> (AnyTerm, [f64; 3]) {
    let away = |r: f64| (0.2 + 0.8 * r) * if r < 0.5 { -1.0 } else { 1.0 };
    let at = [-1.0 + 2.0 * u(), away(u()), 0.5 * away(u())];
    let side = Side {
        v: at[1].signum(),
        z: at[2].signum(),
    };
    (t.directed(side), at)
}

/// A term's torque or rate at (x, v, z).
type Function = fn(AnyTerm, [f64; 3]) -> f64;

/// The fourth-order central difference of `g` at 0 with step `h`:
/// (8(g(h) − g(−h)) − (g(2h) − g(−2h)))/(12h), in error ~h⁴·|g⁽⁵⁾|/30 + ε·|g|/h.
fn difference(g: impl Fn(f64) -> f64, h: f64) -> f64 {
    (8.0 * (g(h) - g(-h)) - (g(2.0 * h) - g(-2.0 * h))) / (12.0 * h)
}

/// [`difference`] of `f` along coordinate `i` of `at`.
fn central(f: impl Fn([f64; 3]) -> f64, at: [f64; 3], i: usize, h: f64) -> f64 {
    difference(
        |d| {
            let mut p = at;
            p[i] += d;
            f(p)
        },
        h,
    )
}

#[test]
fn every_kind_has_the_finite_difference_jacobian_and_parameter_derivatives() {
    // the fourth-order difference with h = 1e-4 errs by ~h⁴·|f⁽⁵⁾|/30 + ε·|f|/h ≈ 1e-12 for the
    // unit-scale laws here, and on the laws with scales of 1e-2…1e-3 (v_r, a mesh loss's θ_m)
    // by ~1e-8 relative: 1e-6 relative to the derivative's scale is 100 times above that
    let mut u = uniform(41);
    let mut checked = 0;
    for &(kind, _, params) in AnyTerm::KINDS {
        for _ in 0..5 {
            let Some(t) = random_term(kind, &mut u) else {
                continue;
            };
            let (t, at) = point_on_piece(t, &mut u);
            let h = 1e-4;
            let fns: [(&str, Function); 2] = [
                ("torque", |t, [x, v, z]| t.torque(x, v, z)),
                ("rate", |t, [x, v, z]| t.rate(x, v, z)),
            ];
            for (name, f) in &fns {
                if kind == "delay" && *name == "rate" {
                    // x_d' = x'(τ − τ_d) is the history's: NaN by design
                    continue;
                }
                let [x, v, z] = at;
                let grad = if *name == "torque" {
                    t.gradient(x, v, z)
                } else {
                    t.rate_gradient(x, v, z)
                };
                for (i, g) in grad.iter().enumerate() {
                    let fd = central(|p| f(t, p), at, i, h);
                    let scale = 1.0 + fd.abs();
                    assert!(
                        (g - fd).abs() < 1e-6 * scale,
                        "{kind} {name} ∂/∂{}: derived {g}, differenced {fd} at {at:?}",
                        ["x", "x'", "z"][i]
                    );
                }
                for (i, q) in params.iter().enumerate() {
                    // whole numbers have no derivative; a delay's τ_d acts through the run's
                    // history, not through the torque (its derivative is NaN by design)
                    if matches!(q.domain, Domain::Exponent | Domain::Line)
                        || (kind == "delay" && q.name == "taud")
                    {
                        continue;
                    }
                    let derived = if *name == "torque" {
                        t.param_derivative(i, x, v, z)
                    } else {
                        t.rate_param_derivative(i, x, v, z)
                    };
                    let with = |dp: f64| {
                        let mut values = t.values().to_vec();
                        values[i] += dp;
                        let moved = AnyTerm::new(kind, &values).unwrap().directed(Side {
                            v: v.signum(),
                            z: z.signum(),
                        });
                        f(moved, at)
                    };
                    let fd = difference(with, h * (1.0 + t.values()[i].abs()));
                    assert!(
                        (derived - fd).abs() < 1e-6 * (1.0 + fd.abs()),
                        "{kind} {name} ∂/∂{}: derived {derived}, differenced {fd}",
                        q.name
                    );
                }
            }
            checked += 1;
        }
    }
    assert!(checked >= 5 * (AnyTerm::KINDS.len() - 1), "{checked}");
}

/// A motion's x(t) and v(t): polynomials of degree 4 with random coefficients, and z(0); v and z
/// away from 0 at t = 0 so a short span stays on the piece. (z's later rows follow from the
/// term's own rate, as in a run.)
fn motion(u: &mut impl FnMut() -> f64) -> [[f64; MAX_ROWS]; 3] {
    let mut s = [[0.0; MAX_ROWS]; 3];
    let away = |u: &mut dyn FnMut() -> f64| (0.5 + 0.5 * u()) * if u() < 0.5 { -1.0 } else { 1.0 };
    for row in &mut s[..2] {
        for (k, c) in row.iter_mut().enumerate().take(5) {
            *c = (-1.0 + 2.0 * u()) * 0.5f64.powi(k as i32);
        }
    }
    s[1][0] = away(u);
    s[2][0] = away(u);
    s
}

fn horner(c: &[f64], t: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, c| acc * t + c)
}

#[test]
fn every_kind_s_taylor_rows_sum_to_its_value_along_a_known_motion() {
    // along a motion x(t), v(t) given by its series, with z(t) following the term's own rate
    // z' = r(x, v, z) row by row as in a run, the torque's rows summed at t give
    // T(x(t), v(t), z(t)) and the rate's give r(…), on the step Taylor's method would take:
    // to rounding, 1e-11 relative to the value's scale (summing ~MAX_ROWS rows of a few
    // times the value each costs some 1e-15)
    let mut u = uniform(43);
    for &(kind, _, _) in AnyTerm::KINDS {
        if kind == "delay" {
            // its state is the twist τ_d ago, which only the run's history gives
            continue;
        }
        for _ in 0..5 {
            let Some(t) = random_term(kind, &mut u) else {
                continue;
            };
            let [x, v, mut z] = motion(&mut u);
            let t = t.directed(Side {
                v: v[0].signum(),
                z: z[0].signum(),
            });
            let mut rows = Scratch([[0.0; MAX_ROWS]; SCRATCH_ROWS]);
            let (mut torque, mut rate) = ([0.0; MAX_ROWS], [0.0; MAX_ROWS]);
            for k in 0..MAX_ROWS {
                rate[k] = t.rate_taylor(k, &x, &v, &z, &mut rows);
                torque[k] = t.taylor(k, &x, &v, &z, &mut rows);
                if k + 1 < MAX_ROWS {
                    z[k + 1] = rate[k] / (k + 1) as f64;
                }
            }
            // the step Taylor's method would take on these rows (its last two rows of the
            // state, the torque and the rate each below 1e-16 of their size), then the term's
            // own limit: on it the series are accurate by the stepper's own rule
            let reach = |c: &[f64; MAX_ROWS]| {
                let size = 1.0 + c[0].abs();
                [MAX_ROWS - 2, MAX_ROWS - 1]
                    .iter()
                    .map(|&j| (1e-16 * size / c[j].abs()).powf(1.0 / j as f64))
                    .fold(f64::INFINITY, f64::min)
            };
            let h = [&x, &v, &z, &torque, &rate]
                .iter()
                .map(|c| reach(c))
                .fold(0.05, f64::min);
            let h = t.step_limit(&rows, MAX_ROWS - 1, h, 1e-16);
            for tau in [h / 4.0, h / 2.0, h] {
                let at = [horner(&x, tau), horner(&v, tau), horner(&z, tau)];
                let direct = t.torque(at[0], at[1], at[2]);
                let summed = horner(&torque, tau);
                assert!(
                    (summed - direct).abs() < 1e-11 * (1.0 + direct.abs()),
                    "{kind} torque at t = {tau}: rows give {summed}, the law {direct}"
                );
                if t.state().is_some() && t.rate_text().is_some() {
                    let direct = t.rate(at[0], at[1], at[2]);
                    let summed = horner(&rate, tau);
                    assert!(
                        (summed - direct).abs() < 1e-11 * (1.0 + direct.abs()),
                        "{kind} rate at t = {tau}: rows give {summed}, the law {direct}"
                    );
                }
            }
        }
    }
}

#[test]
fn declared_drag_follows_its_equation_integrated_here() {
    // x'' + x' + αx³ − x² + γ(x − ε) + c_q·x'|x'| = μ + δ sin ωτ, by classical RK4 at h = 1e-3
    // (its error ~h⁴ ≈ 1e-12 per unit time on the smooth stretches; x'|x'| has a jump in its
    // second derivative at x' = 0, where a step errs by ~h³·|x''|: ~1e-9 at most) against
    // Taylor's method at 1e-12 on the model with the declared term
    let p = Params {
        delta: 1.0,
        omega: 0.5,
        ..Params::default()
    };
    let cq = 0.8;
    let m = Model::study(&p)
        .with_term(AnyTerm::new("drag", &[cq]).unwrap())
        .unwrap();
    let (t_end, dt) = (30.0, 0.5);
    let taylor = crate::common::states_from_rest(&m, Method::Taylor, 1e-12, t_end, dt);
    let accel = |t: f64, [x, v]: [f64; 2]| {
        p.mu + p.delta * (p.omega * t).sin()
            - v
            - (p.alpha * x * x * x - x * x + p.gamma * (x - p.eps))
            - cq * v * v.abs()
    };
    let f = |t: f64, y: [f64; 2]| [y[1], accel(t, y)];
    let mut y = [taylor[0][0], taylor[0][1]];
    let h = 1e-3;
    let per_sample = (dt / h).round() as usize;
    let mut worst: f64 = 0.0;
    let mut crossings = 0;
    for (n, row) in taylor.iter().enumerate().skip(1) {
        for i in 0..per_sample {
            let t = (n - 1) as f64 * dt + i as f64 * h;
            let before = y[1];
            y = crate::common::rk4_step(&f, t, y, h);
            crossings += usize::from(before.signum() != y[1].signum());
        }
        worst = worst.max((row[0] - y[0]).abs()).max((row[1] - y[1]).abs());
    }
    assert!(crossings >= 4, "the motion reverses: {crossings} crossings");
    assert!(worst < 1e-7, "Taylor against RK4: {worst:e}");
}

/// A law's friction written in the declaration's vocabulary, here: f_c·tanh(x'/v_s).
#[derive(Clone, Copy, Debug, PartialEq)]
struct TanhFriction;

impl Law for TanhFriction {
    const KIND: &'static str = "tanh-friction";
    const ABOUT: &'static str = "f_c·tanh(x'/v_s), declared";
    const PARAMS: &'static [ParamInfo] = &[FRICTION_PARAM, FRICTION_PARAM];
    const TEXT: &'static str = " + f_c·tanh(x'/v_s)";
    const LATEX: &'static str = r" + f_c \tanh(\dot x / v_s)";
    const LIMITS_STEPS: bool = true;
    #[inline(always)]
    fn torque<N: Num>(s: &Vars<N>, p: &[N]) -> N {
        p[0] * (s.v / p[1]).tanh(p[0])
    }
}

/// The Stribeck law without its viscous part, (f_c + (f_s − f_c)e^{−(x'/v_st)²})·tanh(x'/v_r),
/// declared: its e^q scaled by |f_s − f_c|, its tanh by f_s (≥ f_c).
#[derive(Clone, Copy, Debug, PartialEq)]
struct DeclaredStribeck;

impl Law for DeclaredStribeck {
    const KIND: &'static str = "declared-stribeck";
    const ABOUT: &'static str = "Stribeck friction, declared";
    const PARAMS: &'static [ParamInfo] = &[FRICTION_PARAM; 4];
    const TEXT: &'static str = " + (f_c + (f_s − f_c)·exp(−(x'/v_st)²))·tanh(x'/v_r)";
    const LATEX: &'static str = r" + g(\dot x) \tanh(\dot x / v_r)";
    const LIMITS_STEPS: bool = true;
    #[inline(always)]
    fn torque<N: Num>(s: &Vars<N>, p: &[N]) -> N {
        let [fc, fs, vst, vr] = [p[0], p[1], p[2], p[3]];
        let e = (s.v * s.v / -(vst * vst)).exp(fs - fc);
        let t = (s.v / vr).tanh(fs);
        fc * t + (fs - fc) * (e * t)
    }
}

const FRICTION_PARAM: ParamInfo = ParamInfo {
    name: "f",
    symbol: "f",
    latex: "f",
    meaning: "a friction parameter",
    domain: Domain::Positive,
    default: 0.1,
    si: "-",
};

#[test]
fn declared_tanh_and_exp_give_the_hand_written_friction_rows_and_steps_to_the_bit() {
    // the declaration's tanh and exp run the recurrences and step rules the hand-written
    // friction terms run, on the same rows in the same order: every row, the value at the
    // start and the step limit agree exactly, at speeds from deep in the regularisation
    // (|x'| ≪ v) to far outside it (where the step rule is what keeps the step short)
    let mut u = uniform(47);
    for case in 0..40 {
        let [fc, fs, vst, vr] = [
            0.05 + 0.3 * u(),
            0.4 + 0.3 * u(),
            0.05 + 0.1 * u(),
            [1e-2, 1e-3, 1e-4][case % 3],
        ];
        let [x, mut v, z] = motion(&mut u);
        v[0] *= [1e-3, 1e-2, 0.1, 1.0][case % 4];
        let hands = [
            AnyTerm::new("friction", &[fc, vr]).unwrap(),
            AnyTerm::new("stribeck", &[fc, fs, vst, 0.0, vr]).unwrap(),
        ];
        for (i, hand) in hands.iter().enumerate() {
            let mut rows = Scratch([[0.0; MAX_ROWS]; SCRATCH_ROWS]);
            let mut ours = Scratch([[0.0; MAX_ROWS]; SCRATCH_ROWS]);
            let (tanh, stribeck) = (
                Declared::<TanhFriction>::from_values(&[fc, vr]),
                Declared::<DeclaredStribeck>::from_values(&[fc, fs, vst, vr]),
            );
            for k in 0..MAX_ROWS {
                let want = hand.taylor(k, &x, &v, &z, &mut rows);
                let got = if i == 0 {
                    tanh.taylor(k, &x, &v, &z, &mut ours)
                } else {
                    stribeck.taylor(k, &x, &v, &z, &mut ours)
                };
                assert_eq!(want.to_bits(), got.to_bits(), "case {case} law {i} row {k}");
            }
            for order in [8, 16, MAX_ROWS - 1] {
                let want = hand.step_limit(&rows, order, 1.0, 1e-12);
                let got = if i == 0 {
                    tanh.step_limit(&ours, order, 1.0, 1e-12)
                } else {
                    stribeck.step_limit(&ours, order, 1.0, 1e-12)
                };
                assert_eq!(want, got, "case {case} law {i} order {order}");
            }
            let (want, got) = if i == 0 {
                (hand.torque(0.0, v[0], 0.0), tanh.torque(0.0, v[0], 0.0))
            } else {
                (hand.torque(0.0, v[0], 0.0), stribeck.torque(0.0, v[0], 0.0))
            };
            assert!(
                (want - got).abs() <= 1e-15 * (1.0 + want.abs()),
                "{want} {got}"
            );
        }
    }
}
