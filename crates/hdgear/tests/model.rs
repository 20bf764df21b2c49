//! The model assembled from terms: the study's assembly against the hand-scheduled fast path,
//! random assemblies against finite differences and an independent integration written here
//! from the equations, the derived facts, and the periodic machinery run on an assembly.

use hdgear::Params;
use hdgear::integrate::{Method, System};
use hdgear::model::terms::AnyTerm;
use hdgear::model::{Dimensionless, Model};
use hdgear::params::Param;

use crate::common::uniform;

/// A number between lo and hi from the generator `u`.
fn between(u: &mut impl FnMut() -> f64, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * u()
}

/// A random study set, off the study's line too (α·ε = 1 or not, γ across the cusp).
fn random_params(u: &mut impl FnMut() -> f64) -> Params {
    Params {
        alpha: between(u, 0.5, 30.0),
        gamma: between(u, -0.5, 20.0),
        eps: between(u, -1.0, 2.0),
        mu: between(u, -1.0, 1.0),
        delta: between(u, 0.0, 20.0),
        omega: between(u, 1e-3, 2.0),
    }
}

/// A random model: the study's terms and, with even odds each, smooth friction,
/// Coulomb–Stribeck–viscous friction (not both: they share f_c) or a piecewise-linear stiffness
/// (sharp or with rounded knees).
fn random_model(u: &mut impl FnMut() -> f64) -> Model {
    let m = Model::study(&random_params(u));
    match (u() * 4.0) as u32 {
        0 => m,
        3 => {
            let mut v: Vec<f64> = [(0.1, 5.0), (0.1, 5.0), (0.1, 5.0), (0.1, 1.0), (0.1, 1.0)]
                .iter()
                .map(|&(a, b)| between(u, a, b))
                .collect();
            v.push(between(u, -0.5, 0.5));
            // sharp knees, or knees rounded over up to a third of the first segment
            let rounding = u();
            v.push(if rounding < 0.5 {
                0.0
            } else {
                rounding * 0.3 * v[3]
            });
            m.with_term(AnyTerm::new("piecewise", &v).unwrap()).unwrap()
        }
        1 => m
            .with_term(
                AnyTerm::new("friction", &[between(u, 0.0, 0.5), between(u, 0.02, 0.5)]).unwrap(),
            )
            .unwrap(),
        _ => {
            let (fc, fs) = (between(u, 0.0, 0.3), between(u, 0.0, 0.5));
            // the static level at least the sliding one (the rule every friction law keeps)
            let values = [
                fc,
                fs.max(fc),
                between(u, 0.05, 1.0),
                between(u, 0.0, 0.5),
                between(u, 0.02, 0.5),
            ];
            m.with_term(AnyTerm::new("stribeck", &values).unwrap())
                .unwrap()
        }
    }
}

fn run<S: System<2>>(s: &S, method: Method, y0: [f64; 2], span: f64) -> [f64; 2] {
    crate::common::end_state(s, method, 1e-12, y0, span).0
}

#[test]
fn the_study_assembled_from_terms_is_the_fast_paths_model() {
    let mut u = uniform(1);
    for _ in 0..200 {
        let p = random_params(&mut u);
        let (fast, assembled) = (Dimensionless::new(p), Model::study(&p));
        let y = [between(&mut u, -2.0, 2.0), between(&mut u, -3.0, 3.0)];
        let t = between(&mut u, 0.0, 1000.0);
        let (a, b) = (fast.rhs(t, &y), assembled.rhs(t, &y));
        // the same sums in another order: rounding of the largest term, α|x|³ ≤ 240, or δ ≤ 20
        let scale = p.alpha * y[0].abs().powi(3)
            + y[0] * y[0]
            + p.gamma.abs() * (y[0].abs() + p.eps.abs())
            + p.delta
            + 4.0;
        assert!(
            (a[1] - b[1]).abs() <= 8.0 * f64::EPSILON * scale,
            "{p:?} {y:?}: {a:?} vs {b:?}"
        );
        // the Taylor rows, weighted by a step's powers h^k (h = 0.05, shorter than any step
        // the tolerances take at these magnitudes): the polynomials agree term by term to
        // 1e-14 of the scale, the rounding of the same Cauchy sums (at most 21 products a row,
        // 21·ε ≈ 4.7e-15) summed in another order: the fast path this holds is kept for its
        // speed (`cargo bench -- study_path`: 2.6–3× one trajectory, 6× sixteen lanes)
        let (mut ca, mut cb) = ([[0.0; 2]; 21], [[0.0; 2]; 21]);
        assert!(fast.taylor(t, &y, 20, &mut ca) && assembled.taylor(t, &y, 20, &mut cb));
        let h: f64 = 0.05;
        for k in 0..=20 {
            for i in 0..2 {
                let d = (ca[k][i] - cb[k][i]).abs() * h.powi(k as i32);
                assert!(
                    d <= 1e-14 * scale,
                    "{p:?} {y:?} row {k}: {:?} vs {:?}",
                    ca[k],
                    cb[k]
                );
            }
        }
    }
    // and a whole run: the default set over one jump of its first slow period
    let p = Params::default();
    let (a, b) = (
        run(&Dimensionless::new(p), Method::Taylor, [0.0, 0.0], 300.0),
        run(&Model::study(&p), Method::Taylor, [0.0, 0.0], 300.0),
    );
    assert!(
        (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9,
        "{a:?} vs {b:?}"
    );
}

#[test]
fn random_assemblies_have_the_finite_difference_jacobian_and_parameter_derivatives() {
    let mut u = uniform(2);
    for _ in 0..300 {
        let m = random_model(&mut u);
        let y = [between(&mut u, -2.0, 2.0), between(&mut u, -1.0, 1.0)];
        let t = between(&mut u, 0.0, 100.0);
        let jac = m.jacobian(t, &y).unwrap();
        // central differences at h = 1e-6: truncation h²·f'''/6 ≤ 1e-12·(1/v_s³ ≤ 1.3e5) and
        // rounding 1e-16·|f|/h ≤ 1e-8, so 1e-6 relative to the entry's scale holds both
        let h = 1e-6;
        for j in 0..2 {
            let (mut up, mut down) = (y, y);
            up[j] += h;
            down[j] -= h;
            let (fu, fd) = (m.rhs(t, &up), m.rhs(t, &down));
            for i in 0..2 {
                let fdiff = (fu[i] - fd[i]) / (2.0 * h);
                let tol = 1e-6 * (1.0 + jac[i][j].abs());
                assert!(
                    (fdiff - jac[i][j]).abs() <= tol,
                    "{m:?} {y:?} J[{i}][{j}] = {} vs {fdiff}",
                    jac[i][j]
                );
            }
        }
        let phase = m.forcing()[2] * t;
        for q in m.params().collect::<Vec<_>>() {
            let v = m.get(q);
            let dv = 1e-6 * v.abs().max(1e-3);
            let (Ok(up), Ok(down)) = (m.with(q, v + dv), m.with(q, v - dv)) else {
                continue; // at the edge of the domain (f_c = 0)
            };
            let fdiff = (up.accel(phase, y[0], y[1]) - down.accel(phase, y[0], y[1])) / (2.0 * dv);
            let exact = m.accel_derivative(q, phase, y[0], y[1]);
            assert!(
                (fdiff - exact).abs() <= 1e-5 * (1.0 + exact.abs()),
                "{q}: {exact} vs {fdiff} in {m:?}"
            );
        }
    }
}

/// Smooth and Coulomb–Stribeck–viscous friction written out here from their equations, apart
/// from the terms' code: x'' = μ + δ sin ωt − x' − αx³ + x² − γ(x − ε) − friction(x').
struct ByHand {
    p: Params,
    friction: fn(f64, &[f64]) -> f64,
    values: Vec<f64>,
}

impl System<2> for ByHand {
    fn rhs(&self, t: f64, y: &[f64; 2]) -> [f64; 2] {
        let p = &self.p;
        let (x, v) = (y[0], y[1]);
        let stiffness = p.alpha * x * x * x - x * x + p.gamma * (x - p.eps);
        let acc =
            p.mu + p.delta * (p.omega * t).sin() - v - stiffness - (self.friction)(v, &self.values);
        [v, acc]
    }
}

#[test]
fn taylor_on_an_assembly_matches_dop853_on_the_equations_written_by_hand() {
    let smooth: fn(f64, &[f64]) -> f64 = |v, c| c[0] * (v / c[1]).tanh();
    let stribeck: fn(f64, &[f64]) -> f64 =
        |v, c| (c[0] + (c[1] - c[0]) * (-(v / c[2]).powi(2)).exp()) * (v / c[4]).tanh() + c[3] * v;
    let mut u = uniform(3);
    for case in 0..12 {
        let mut p = random_params(&mut u);
        p.omega = between(&mut u, 0.01, 1.0);
        let (kind, friction, values) = if case % 2 == 0 {
            (
                "friction",
                smooth,
                vec![between(&mut u, 0.0, 0.5), between(&mut u, 0.05, 0.5)],
            )
        } else {
            let mut v: Vec<f64> = [(0.0, 0.3), (0.0, 0.5), (0.05, 1.0), (0.0, 0.5), (0.05, 0.5)]
                .iter()
                .map(|&(a, b)| between(&mut u, a, b))
                .collect();
            v[1] = v[1].max(v[0]);
            ("stribeck", stribeck, v)
        };
        let m = Model::study(&p)
            .with_term(AnyTerm::new(kind, &values).unwrap())
            .unwrap();
        let by_hand = ByHand {
            p,
            friction,
            values: values.clone(),
        };
        let y0 = [between(&mut u, -1.0, 1.0), between(&mut u, -1.0, 1.0)];
        let a = run(&m, Method::Taylor, y0, 30.0);
        let b = run(&by_hand, Method::Dop853, y0, 30.0);
        let scale = 1.0 + a[0].abs().max(a[1].abs());
        assert!(
            (a[0] - b[0]).abs() < 1e-8 * scale && (a[1] - b[1]).abs() < 1e-8 * scale,
            "{kind} {values:?} {p:?}: {a:?} vs {b:?}"
        );
    }
}

#[test]
fn the_facts_follow_from_the_terms() {
    let f = Model::study(&Params::default()).facts();
    // the study's: unit damping, no Hopf, focus above g' = 1/4, decay time 2
    assert_eq!(
        (
            f.damping_at_rest,
            f.damping_uniform,
            f.hopf_possible,
            f.focus_node_threshold,
            f.decay_time
        ),
        (1.0, true, false, 0.25, 2.0)
    );
    // smooth friction adds its slope at rest f_c/v_s; Stribeck's is f_s/v_r + c_v
    let with = |kind, values: &[f64]| {
        Model::study(&Params::default())
            .with_term(AnyTerm::new(kind, values).unwrap())
            .unwrap()
            .facts()
    };
    let f = with("friction", &[0.1, 0.05]);
    assert!(
        (f.damping_at_rest - 3.0).abs() < 1e-12 && (f.focus_node_threshold - 2.25).abs() < 1e-12
    );
    let f = with("stribeck", &[0.05, 0.08, 0.1, 0.2, 0.04]);
    assert!(
        (f.damping_at_rest - (1.0 + 2.0 + 0.2)).abs() < 1e-12,
        "{f:?}"
    );
    // the threshold is where the linearisation's eigenvalues turn complex: at g' = c²/4 ± 1e-9
    // the discriminant of λ² + cλ + g' changes sign (checked on the Jacobian the model derives)
    let c = f.damping_at_rest;
    for (dg, complex) in [(-1e-9, false), (1e-9, true)] {
        let g = f.focus_node_threshold + dg;
        let tr = -c;
        assert_eq!(tr * tr - 4.0 * g < 0.0, complex);
    }
}

#[test]
fn models_refuse_bad_assemblies_and_values_naming_them() {
    let m = Model::study(&Params::default());
    let e = m
        .with_term(AnyTerm::new("stiffness", &[1.0, 1.0, 1.0]).unwrap())
        .unwrap_err();
    assert!(e.to_string().contains("alpha is taken"), "{e}");
    let f = m
        .with_term(AnyTerm::new("friction", &[0.1, 0.1]).unwrap())
        .unwrap();
    let e = f
        .with_term(AnyTerm::new("stribeck", &[0.1, 0.1, 0.1, 0.0, 0.1]).unwrap())
        .unwrap_err();
    assert!(
        e.to_string()
            .contains("fc is taken by the model's friction"),
        "{e}"
    );
    let e = AnyTerm::new("friction", &[0.1, 0.0]).unwrap_err();
    assert!(e.to_string().contains("vs = 0:"), "{e}");
    let e = AnyTerm::new("preisach", &[]).unwrap_err();
    assert!(
        e.to_string()
            .contains("known: damping, stiffness, friction, stribeck, coulomb, lugre, boucwen"),
        "{e}"
    );
    let e = AnyTerm::new("boucwen", &[1.0, 0.5, 1.0, 0.5, 0.5, 1.5]).unwrap_err();
    assert!(e.to_string().contains("nh = 1.5"), "{e}");
    assert!(e.to_string().contains("whole number from 1 to 4"), "{e}");
    let e = AnyTerm::new("boucwen", &[1.0, 1.5, 1.0, 0.5, 0.5, 1.0]).unwrap_err();
    assert!(e.to_string().contains("rho = 1.5"), "{e}");
    // at most two terms with a state of their own
    let lugre = AnyTerm::new("lugre", &[0.05, 0.08, 0.1, 100.0, 10.0, 0.0]).unwrap();
    let bw = AnyTerm::new("boucwen", &[1.0, 0.5, 1.0, 0.5, 0.5, 1.0]).unwrap();
    let both = m.with_term(lugre).unwrap().with_term(bw).unwrap();
    assert_eq!(both.dim(), 4);
    assert_eq!(both.states(), ["x", "x'", "s", "z"]);
    let e = f.with(f.param("omega").unwrap(), -1.0).unwrap_err();
    assert!(e.to_string().contains("omega = -1:"), "{e}");
    assert!(
        f.param("nope")
            .unwrap_err()
            .to_string()
            .contains("mu, delta, omega, alpha, gamma, eps, fc, vs")
    );
}

#[test]
fn the_periodic_machinery_runs_on_an_assembly() {
    use hdgear::periodic::{ContinuationOptions, Scale, Special, continue_orbit};
    // γ = 10, δ = 15: the period-doubling near ω = 8.14, from Params (Taylor) and from the
    // assembled model (DOP853 through the same seam)
    let p = Params::default()
        .with(Param::Gamma, 10.0)
        .with(Param::Omega, 8.0);
    let opts = ContinuationOptions {
        scale: Scale::Log,
        ..ContinuationOptions::default()
    };
    fn pd<P>(b: &hdgear::periodic::OrbitBranch<P>) -> f64 {
        b.specials()
            .find(|q| q.special == Some(Special::PeriodDoubling))
            .map(|q| q.param)
            .unwrap()
    }
    let a = pd(&continue_orbit(&p, Param::Omega, 1, None, 8.3, &opts).unwrap());
    let m = Model::study(&p);
    let b = pd(&continue_orbit(&m, m.param("omega").unwrap(), 1, None, 8.3, &opts).unwrap());
    assert!((a - b).abs() < 1e-8, "{a} vs {b}");
    // with friction the same seam finds the doubling of the assembly: a multiplier −1 there
    let f = m
        .with_term(AnyTerm::new("friction", &[0.05, 0.5]).unwrap())
        .unwrap();
    let b = continue_orbit(&f, f.param("omega").unwrap(), 1, None, 9.0, &opts).unwrap();
    let q = b
        .specials()
        .find(|q| q.special == Some(Special::PeriodDoubling))
        .expect("a doubling");
    let minus_one = q
        .multipliers
        .iter()
        .find(|m| (m.arg.abs() - std::f64::consts::PI).abs() < 1e-9);
    assert!(minus_one.is_some_and(|m| m.log_abs.abs() < 1e-6), "{q:?}");
    eprintln!(
        "period doubling at omega = {a} (Params), {} (with friction)",
        q.param
    );
}

#[test]
fn the_generic_equilibrium_finder_agrees_with_the_cubics_closed_forms() {
    let mut u = uniform(4);
    for _ in 0..300 {
        let p = random_params(&mut u);
        let a = between(&mut u, -1.0, 1.0);
        let closed = hdgear::fast::stable_equilibrium(&p, a);
        let found = Model::study(&p).stable_equilibrium(a).unwrap();
        // both roots of the same cubic to the resolution of f64 (a root at a fold is ill
        // conditioned: compare the residuals there instead)
        let g = |x: f64| p.alpha * x * x * x - x * x + p.gamma * (x - p.eps) - p.mu - p.delta * a;
        let scale = p.alpha * closed.abs().powi(3)
            + closed * closed
            + p.gamma.abs() * (closed.abs() + p.eps.abs())
            + p.mu.abs()
            + p.delta;
        let slope = 3.0 * p.alpha * closed * closed - 2.0 * closed + p.gamma;
        let at_fold = slope.abs() < 1e-4 * scale;
        assert!(
            (found - closed).abs() <= 1e-9 * (1.0 + closed.abs())
                || (at_fold && g(found).abs() <= 1e-13 * scale),
            "{p:?} a = {a}: {found} vs {closed}"
        );
    }
}

/// The study's periodic orbit by its own variational recurrence (the fast path `shoot` takes on
/// a parameter set, 7× faster: `python3 bench/study_path.py`) is the assembled model's: the same
/// start to 1e-9 (Newton stops at a residual of 1e-11 on the stroboscopic map, which contracts at
/// these points) and the same multipliers' logarithms to 1e-6 relative, over the study's four γ
/// and a resonant ω.
#[test]
fn the_study_s_orbit_by_its_fast_path_is_the_assembled_model_s() {
    use hdgear::periodic::{PeriodicOptions, shoot};
    let opts = PeriodicOptions::default();
    for (gamma, omega) in [
        (30.0, 0.01),
        (10.0, 0.01),
        (1.0, 0.01),
        (0.1, 0.01),
        (10.0, 2.5),
    ] {
        let p = Params {
            gamma,
            omega,
            ..Params::default()
        };
        let (a, b) = (
            shoot(&p, 1, &opts).unwrap(),
            shoot(&Model::study(&p), 1, &opts).unwrap(),
        );
        for i in 0..2 {
            assert!(
                (a.start[i] - b.start[i]).abs() < 1e-9,
                "{p:?}: {:?} {:?}",
                a.start,
                b.start
            );
            let (la, lb) = (a.log_abs_multipliers[i], b.log_abs_multipliers[i]);
            assert!(
                (la - lb).abs() <= 1e-6 * la.abs().max(1.0),
                "{p:?}: {la} {lb}"
            );
        }
        assert_eq!(a.stable, b.stable);
    }
}
