//! One model everywhere: the periodic machinery, the frequency response, continuation and the
//! fast subsystem's analysis on a model with terms beyond the study's, each checked against an
//! integration written here (classical RK4 on the equation as a user would write it) or against
//! closed forms.

use hdgear::Params;
use hdgear::fast::{A_RANGE, StaticCurve, curve, curve_analysis};
use hdgear::model::{Model, ModelCurve, terms::AnyTerm};
use hdgear::periodic::{
    ContinuationOptions, Periodic, PeriodicOptions, Range, frequency_response, shoot,
};

/// γ = 1, δ = 1, ω = 1 (a short period, so the multipliers e^{−c·T}-small stay representable
/// for finite differences) with smooth friction f_c·tanh(x'/v_s), f_c = 0.1, v_s = 0.05.
fn friction_model() -> (Params, f64, f64, Model) {
    let p = Params {
        gamma: 1.0,
        delta: 1.0,
        omega: 1.0,
        ..Params::default()
    };
    let (fc, vs) = (0.1, 0.05);
    let m = Model::study(&p)
        .with_term(AnyTerm::new("friction", &[fc, vs]).unwrap())
        .unwrap();
    (p, fc, vs, m)
}

/// x'' = μ + δ sin ωτ − x' − (αx³ − x² + γ(x − ε)) − f_c·tanh(x'/v_s), written out here.
fn accel(p: &Params, fc: f64, vs: f64, t: f64, x: f64, v: f64) -> f64 {
    p.mu + p.delta * (p.omega * t).sin()
        - v
        - (p.alpha * x.powi(3) - x * x + p.gamma * (x - p.eps))
        - fc * (v / vs).tanh()
}

/// The flow over [0, T] from y by classical RK4 with n equal steps.
fn rk4(p: &Params, fc: f64, vs: f64, y: [f64; 2], period: f64, n: usize) -> [f64; 2] {
    let h = period / n as f64;
    let f = |t: f64, y: [f64; 2]| [y[1], accel(p, fc, vs, t, y[0], y[1])];
    let mut y = y;
    for i in 0..n {
        y = crate::common::rk4_step(&f, i as f64 * h, y, h);
    }
    y
}

#[test]
fn a_smooth_friction_orbit_is_a_fixed_point_of_an_independent_flow() {
    let (p, fc, vs, m) = friction_model();
    let orbit = shoot(&m, 1, &PeriodicOptions::default()).unwrap();
    let period = std::f64::consts::TAU / p.omega;
    assert!((orbit.period - period).abs() < 1e-12);
    // RK4 with 2e5 steps over 2π: its error ~ (h·|λ|max)⁴ ≈ 1e-13 per unit time (|λ| ≤ 20 from
    // the friction's slope f_c/v_s = 2 and √g' ≤ 7), so 1e-9 leaves room and the shooting's
    // own 1e-11 Newton tolerance is well inside
    let back = rk4(&p, fc, vs, orbit.start, period, 200_000);
    let scale = 1.0 + orbit.start[0].hypot(orbit.start[1]);
    let miss = (back[0] - orbit.start[0]).hypot(back[1] - orbit.start[1]);
    assert!(miss < 1e-9 * scale, "RK4 returns {miss:e} away");

    // the monodromy by central differences of the same RK4 flow (step 1e-5: truncation 1e-10,
    // integration error / step 1e-8); its eigenvalues against the variational equations'
    let d = 1e-5;
    let mut mono = [[0.0; 2]; 2];
    for j in 0..2 {
        let mut plus = orbit.start;
        let mut minus = orbit.start;
        plus[j] += d;
        minus[j] -= d;
        let (a, b) = (
            rk4(&p, fc, vs, plus, period, 20_000),
            rk4(&p, fc, vs, minus, period, 20_000),
        );
        for i in 0..2 {
            mono[i][j] = (a[i] - b[i]) / (2.0 * d);
        }
    }
    let tr = mono[0][0] + mono[1][1];
    let det = mono[0][0] * mono[1][1] - mono[0][1] * mono[1][0];
    let [m1, m2] = orbit.multipliers;
    // trace and determinant of the multipliers' pair: m1 + m2 and m1·m2 (complex pair or real)
    let modulus = |q: &hdgear::periodic::Multiplier| q.log_abs.exp();
    let (r1, r2) = (modulus(&m1), modulus(&m2));
    let sum = r1 * m1.arg.cos() + r2 * m2.arg.cos();
    let product = r1 * r2 * (m1.arg + m2.arg).cos();
    let size = r1.max(r2);
    assert!(
        (sum - tr).abs() < 1e-6 * size && (product - det).abs() < 1e-6 * size * size,
        "multipliers {m1:?} {m2:?} against finite differences: trace {tr}, det {det}"
    );
    // friction adds damping: the orbit is more stable than the study's with the same set
    let study = shoot(&p, 1, &PeriodicOptions::default()).unwrap();
    assert!(orbit.log_abs_multipliers[0] < study.log_abs_multipliers[0]);
}

#[test]
fn continuation_takes_a_terms_parameter_by_name() {
    let (_, _, _, m) = friction_model();
    let r = Range::parse_for("friction.fc=0.1:0.3", &m).unwrap();
    assert_eq!(r.param, m.param("fc").unwrap());
    let err = Range::parse_for("friction.alpha=0:1", &m)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("friction.alpha") && err.contains("fc, vs"),
        "{err}"
    );
    // the study's set knows only its six
    let err = Range::parse_for("fc=0:1", &Params::default())
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("'fc'") && err.contains("alpha, gamma"),
        "{err}"
    );
    // along f_c the orbit at each point is the one shooting finds there
    let from = m.with(r.param, r.from).unwrap();
    let b = hdgear::periodic::continue_orbit(
        &from,
        r.param,
        1,
        None,
        r.to,
        &ContinuationOptions::default(),
    )
    .unwrap();
    let last = b.points.last().unwrap();
    assert!(
        last.param > 0.25,
        "the branch stopped at f_c = {}",
        last.param
    );
    let there = shoot(
        &m.with(r.param, last.param).unwrap(),
        1,
        &PeriodicOptions::default(),
    )
    .unwrap();
    let miss = (last.start[0] - there.start[0]).hypot(last.start[1] - there.start[1]);
    assert!(miss < 1e-8, "continued and shot orbits differ by {miss:e}");
}

#[test]
fn a_frequency_response_of_a_model_runs_and_its_default_range_is_the_studys_for_its_curve() {
    let (p, _, _, m) = friction_model();
    // friction has no static torque: the default ω range comes from the same stiffest slope
    let (lo, hi) = m.frequency_range();
    let (plo, phi) = p.frequency_range();
    assert!((lo - plo).abs() < 1e-9 * plo && (hi - phi).abs() < 1e-9 * phi);
    let b = frequency_response(&m, Some((0.5, 2.0)), &ContinuationOptions::default()).unwrap();
    assert!(b.points.len() > 5);
    assert!(b.points.iter().all(|q| q.param >= 0.5 * (1.0 - 1e-12)));
}

/// A model with an internal state (LuGre's bristles) has orbits outside the plane: shooting
/// refuses it in one line. Friction that sticks is shot switch by switch (`den_hartog.rs` holds
/// it to the closed form): the orbit counts its rests.
#[test]
fn memory_models_are_refused_by_shooting_and_sticking_ones_shot() {
    let p = Params::default();
    let with = |kind: &str, values: &[f64]| {
        Model::study(&p)
            .with_term(AnyTerm::new(kind, values).unwrap())
            .unwrap()
    };
    let lugre = with("lugre", &[0.05, 0.08, 0.1, 100.0, 10.0, 0.0]);
    let e = shoot(&lugre, 1, &PeriodicOptions::default())
        .unwrap_err()
        .to_string();
    assert!(!e.contains('\n'), "{e}");
    assert!(
        e.contains("no periodic orbit") && e.contains("lugre term"),
        "{e}"
    );
    let coulomb = with("coulomb", &[0.1, 0.15, 0.05, 0.0]);
    let o = shoot(&coulomb, 1, &PeriodicOptions::default()).unwrap();
    assert!(o.rests.is_some() && o.residual < 1e-10, "{:?}", o.rests);
}

#[test]
fn a_models_equilibrium_curve_has_its_own_damping() {
    let (_, fc, vs, m) = friction_model();
    let c = ModelCurve::new(&m).unwrap();
    let damping = 1.0 + fc / vs; // unit damping plus the friction's slope at rest
    assert!((c.damping() - damping).abs() < 1e-12);
    for q in curve(&c, A_RANGE, 200).unwrap() {
        // λ² + cλ + g' = 0: λ1 + λ2 = −c, λ1·λ2 = g'
        let sum = q.re1 + q.re2;
        let product = q.re1 * q.re2 - q.im1 * q.im2;
        assert!((sum + damping).abs() < 1e-12, "{q:?}");
        assert!(
            (product - q.gprime).abs() < 1e-9 * (1.0 + q.gprime.abs()),
            "{q:?}"
        );
        assert_eq!(q.kind.is_stable(), q.gprime > 0.0);
    }
    // the study's fold set at γ = 0.01 (fold hysteresis): the friction moves no equilibrium, so
    // the folds are the cubic's closed forms
    let p = Params {
        gamma: 0.01,
        ..Params::default()
    };
    let mf = Model::study(&p)
        .with_term(AnyTerm::new("friction", &[fc, vs]).unwrap())
        .unwrap();
    let an = curve_analysis(&ModelCurve::new(&mf).unwrap(), A_RANGE).unwrap();
    let study = hdgear::fast::analyze(&p, A_RANGE).unwrap();
    assert_eq!(an.folds.len(), 2);
    assert_eq!(an.folds.len(), study.equilibria.folds.len());
    for (a, b) in an.folds.iter().zip(&study.equilibria.folds) {
        assert!(
            (a.x - b.x).abs() < 1e-9 && (a.a - b.a).abs() < 1e-9,
            "{a:?} {b:?}"
        );
    }
    assert_eq!(
        (an.min_count, an.max_count),
        (study.equilibria.min_count, study.equilibria.max_count)
    );
}

#[test]
fn the_study_as_a_model_is_recognised_so_its_fast_paths_run() {
    let p = Params::default();
    assert_eq!(Model::study(&p).study_params(), Some(p));
    let damped = Model::damped(p.mu, p.delta, p.omega);
    assert_eq!(damped.study_params(), None);
}

#[test]
fn control_on_the_study_as_a_model_is_control_on_the_set() {
    use hdgear::burst::BurstOptions;
    use hdgear::control::tune;
    let p = Params::default(); // γ = 0.1: bursting
    let opts = BurstOptions::default();
    // the same open loop either way, so the same bisection and the same measures, bit for bit
    let from_set = tune(&p, "vdamping", &[], &opts, 1e-2).unwrap();
    let from_model = tune(&Model::study(&p), "vdamping", &[], &opts, 1e-2).unwrap();
    assert_eq!(from_set.tuned, from_model.tuned);
    assert_eq!(from_set.below, from_model.below);
}

#[test]
fn friction_lowers_the_damping_a_law_must_add() {
    use hdgear::burst::{BurstOptions, classify_model, response_model};
    use hdgear::control::{law_term, tune};
    let p = Params::default();
    let opts = BurstOptions::default();
    let study = tune(&p, "vdamping", &[], &opts, 1e-2).unwrap();
    // smooth friction with slope f_c/v_s = 0.5 at rest: it dissipates on top of the unit damping
    // wherever the twist moves, so the virtual damping needed can only fall
    let m = Model::study(&p)
        .with_term(AnyTerm::new("friction", &[0.05, 0.1]).unwrap())
        .unwrap();
    let t = tune(&m, "vdamping", &[], &opts, 1e-2).unwrap();
    assert!(
        t.tuned.gain < study.tuned.gain,
        "{} vs {}",
        t.tuned.gain,
        study.tuned.gain
    );
    // the tuned closed loop holds the friction term and the law, and does not burst
    let closed = m
        .with_term(law_term("vdamping", t.tuned.gain, &[]).unwrap())
        .unwrap();
    assert_eq!(closed.terms().count(), 4);
    let r = response_model(&closed, &opts).unwrap();
    assert!(!classify_model(&closed, &r).unwrap().bursting);
}

/// The fold curve of a friction model in (ω, δ), started from its frequency response's folds
/// (`hdgear continue2 --config`): at points along it, the one-parameter frequency response at
/// that δ (a different continuation, in ln ω, whose folds are sign changes of its tangent) has a
/// fold at that ω. The response runs over its default range, from a low ω where the orbit is
/// unique, so it passes through both folds of the bend. Both locate the fold to the shooting's
/// 1e-11 and the curve's residual is below 1e-10, so 1e-6 relative holds with room; friction's
/// damping moves the cusp up in δ.
#[test]
fn a_friction_models_fold_curve_is_made_of_its_frequency_responses_folds() {
    use hdgear::periodic::{CurveKind, Special, curves_from_branch};
    let p = Params {
        gamma: 1.0,
        ..Params::default()
    };
    let m = Model::study(&p)
        .with_term(AnyTerm::new("friction", &[0.1, 0.05]).unwrap())
        .unwrap();
    let ranges = [
        Range::parse_for("omega=0.3:20:log", &m).unwrap(),
        Range::parse_for("delta=0.5:40:log", &m).unwrap(),
    ];
    let opts = ContinuationOptions::default();
    let curves = curves_from_branch(&m, ranges, CurveKind::Fold, None, 1, &opts).unwrap();
    assert_eq!(curves.len(), 1);
    let c = &curves[0];
    let delta = m.param("delta").unwrap();
    // away from the cusp (δ ≈ 1.82), where the response's two folds are a step of its own
    // continuation apart and pass unseen between two of its points
    let away: Vec<_> = c
        .points
        .iter()
        .filter(|q| (5.0..30.0).contains(&q.params[1]))
        .collect();
    assert!(away.len() >= 3);
    for q in [away[0], away[away.len() / 2], away[away.len() - 1]] {
        let [w, d] = q.params;
        let at = m.with(delta, d).unwrap();
        let r = frequency_response(&at, None, &opts).unwrap();
        let nearest = r
            .specials()
            .filter(|f| f.special == Some(Special::Fold))
            .map(|f| (f.param - w).abs() / w)
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest < 1e-6,
            "no fold of the response at δ = {d} near ω = {w}: {nearest:e}"
        );
    }
    // the study's own curve through the same box has its cusp lower in δ: friction's damping
    // takes a larger forcing to fold the response
    let study = curves_from_branch(
        &p,
        [
            Range::parse("omega=0.3:20:log").unwrap(),
            Range::parse("delta=0.5:40:log").unwrap(),
        ],
        CurveKind::Fold,
        None,
        1,
        &opts,
    )
    .unwrap();
    let lowest = |points: &[hdgear::periodic::CurvePoint2]| {
        points
            .iter()
            .map(|q| q.params[1])
            .fold(f64::INFINITY, f64::min)
    };
    let study_low = study
        .iter()
        .map(|s| lowest(&s.points))
        .fold(f64::INFINITY, f64::min);
    let here = lowest(&c.points);
    assert!(here > study_low, "{here} vs {study_low}");
}
