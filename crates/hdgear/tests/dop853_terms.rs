//! DOP853 on every kind of term: within 1e-8 of Taylor's method (each state's difference over
//! its range, both at 1e-12) on a sharp case of each (issue 96: before its steps were held to
//! the terms' features and its dense output to the equation, a Stribeck breakaway over
//! v_st = 1e-3 with sticking was 3.1e-5 off and LuGre 2.1e-4, with no warning). Taylor's
//! method is the reference: its terms' series are exact and its steps are cut where a term's
//! series stops converging ([`hdgear::model::terms::Term::step_limit`]), which the term tests
//! check against independent integrations.

use hdgear::Params;
use hdgear::integrate::Method;
use hdgear::model::Model;
use hdgear::model::terms::AnyTerm;

/// Sharper than the defaults where a kind has a feature scale: a Stribeck breakaway over
/// v_st = 1e-3 (the audit's case) and a tanh regularisation over v_r = 1e-3.
const SHARP: [(&str, f64); 3] = [("vst", 1e-3), ("vr", 1e-3), ("vs", 1e-3)];

/// The kinds left out, with the reason: a delayed model has no Taylor series (it always runs
/// DOP853 on the history: `tests/delay.rs` checks it against an integration written there).
const NO_TAYLOR: [&str; 1] = ["delay"];

/// The kind at its defaults, sharpened by [`SHARP`].
fn sharp_term(kind: &str) -> AnyTerm {
    let values: Vec<f64> = AnyTerm::params_of(kind)
        .unwrap()
        .iter()
        .map(|p| {
            SHARP
                .iter()
                .find(|s| s.0 == p.name)
                .map_or(p.default, |s| s.1)
        })
        .collect();
    AnyTerm::new(kind, &values).unwrap()
}

/// Each state's largest difference between the two runs over that state's range in the Taylor run.
fn worst_relative(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    let dim = a[0].len();
    (0..dim)
        .map(|i| {
            let (lo, hi) = a
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), y| {
                    (l.min(y[i]), h.max(y[i]))
                });
            let range = (hi - lo).max(1e-300);
            a.iter()
                .zip(b)
                .map(|(a, b)| (a[i] - b[i]).abs() / range)
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

#[test]
fn dop853_agrees_with_taylor_on_every_kind_of_term() {
    // stick-slip under a slow sine (the friction tests' first case)
    let p = Params {
        delta: 1.0,
        omega: 0.5,
        ..Params::default()
    };
    let (t_end, dt, tol) = (60.0, 0.05, 1e-12);
    let mut report = Vec::new();
    let mut failed = Vec::new();
    for &(kind, _, _) in AnyTerm::KINDS {
        if NO_TAYLOR.contains(&kind) {
            continue;
        }
        // the study's model holds a damping and a stiffness term already: those kinds are its own
        let study = Model::study(&p);
        let m = if study.terms().any(|t| t.kind() == kind) {
            study
        } else {
            study
                .with_term(sharp_term(kind))
                .unwrap_or_else(|e| panic!("{kind}: {e}"))
        };
        let taylor = crate::common::states_from_rest(&m, Method::Taylor, tol, t_end, dt);
        let dop853 = crate::common::states_from_rest(&m, Method::Dop853, tol, t_end, dt);
        let e = worst_relative(&taylor, &dop853);
        report.push(format!("{kind}: {e:.1e}"));
        if e >= 1e-8 {
            failed.push(format!(
                "{kind}: DOP853 off Taylor by {e:e} of a state's range"
            ));
        }
    }
    eprintln!("{}", report.join(", "));
    assert!(failed.is_empty(), "{failed:#?}");
}

/// On LuGre's stiff bristles (they relax at σ₀|x'|/g(x'), 200 per time unit here) DOP853
/// converges with its tolerance: each run within 1e3·tol of a state's range of Taylor's at 1e-14
/// (the global error of 60 time units at a per-step tolerance), and tighter tolerances closer.
/// Before its dense output was held to the equation it did not: 9.6e-5, 3.9e-4, 4.9e-5 at 1e-8,
/// 1e-10, 1e-12, steps at the stability limit ending within the tolerance while the
/// interpolant between them oscillated.
#[test]
fn dop853_converges_on_stiff_bristles() {
    let p = Params {
        delta: 1.0,
        omega: 0.5,
        ..Params::default()
    };
    let m = Model::study(&p).with_term(sharp_term("lugre")).unwrap();
    let run = |method, tol| crate::common::states_from_rest(&m, method, tol, 60.0, 0.05);
    let reference = run(Method::Taylor, 1e-14);
    let mut last = f64::INFINITY;
    for tol in [1e-8, 1e-10, 1e-12] {
        let e = worst_relative(&reference, &run(Method::Dop853, tol));
        eprintln!("DOP853 at {tol:e}: {e:.1e} of a state's range off");
        assert!(
            e < 1e3 * tol && e < last,
            "at {tol:e}: {e:e} (before: {last:e})"
        );
        last = e;
    }
}
