//! Many models at once ([`integrate_models`]): random smooth models assembled from every term
//! hdgear has, in batches that cross a chunk of sixteen lanes, against the scalar Taylor stepper
//! run here one model at a time (each lane must take its steps to the bit, or on vector lanes to
//! the ~1e-9 of their step rule) and against DOP853 (to the tolerance); each kind's rows and step
//! limits on lanes against its scalar ones; bad input refused naming it (by this batch and by
//! that of switching models); a failing lane alone.

use hdgear::Params;
use hdgear::batch::LANES;
use hdgear::integrate::{DenseOutput, Method, Options, Stepper, stepper};
use hdgear::model::terms::{AnyTerm, Domain, ParamInfo};
use hdgear::model::{Model, integrate_models, integrate_switching_models, on_vector_lanes};

use crate::common::uniform;

/// A random smooth model: the study's terms at random parameters and up to three more terms of
/// random kinds, each parameter drawn inside its domain about its default ([`draw`]);
/// kinds that switch (sgn x', |z|) or delay, and assemblies a model refuses, are drawn again.
/// Returns the model with its dimension.
fn random_smooth_model(u: &mut impl FnMut() -> f64) -> Model {
    let mut m = Model::study(&random_params(u));
    let extra = (u() * 4.0) as usize;
    let mut tries = 0;
    while m.terms().count() < 2 + extra && tries < 50 {
        tries += 1;
        let kinds = AnyTerm::KINDS;
        let (kind, _, _) = kinds[((u() * kinds.len() as f64) as usize).min(kinds.len() - 1)];
        let values = draw_values(kind, u);
        let Ok(term) = AnyTerm::new(kind, &values) else {
            continue;
        };
        let Ok(next) = m.with_term(term) else {
            continue;
        };
        if !next.switches() && next.delay().is_none() {
            m = next;
        }
    }
    m
}

/// The study's parameters at random, over ranges that hold folds, single-branch curves and
/// both signs of the load.
pub(crate) fn random_params(u: &mut impl FnMut() -> f64) -> Params {
    Params {
        alpha: 0.5 + 20.0 * u(),
        gamma: -0.5 + 5.0 * u(),
        eps: -1.0 + 3.0 * u(),
        mu: -1.0 + 2.0 * u(),
        delta: 10.0 * u(),
        omega: 0.01 + u(),
    }
}

/// A value of parameter `q`: a whole number from 1 to 4 for an exponent or a line, up to 0.5
/// for a default of 0 (a term present, not switched off), else the default times a factor in
/// [0.5, 1.5], clamped to [0, 1] for a fraction.
pub(crate) fn draw(q: &ParamInfo, u: &mut impl FnMut() -> f64) -> f64 {
    match q.domain {
        Domain::Exponent | Domain::Line => 1.0 + (u() * 4.0).floor().min(3.0),
        _ if q.default == 0.0 => 0.5 * u(),
        Domain::Fraction => (q.default * (0.5 + u())).min(1.0),
        _ => q.default * (0.5 + u()),
    }
}

/// Values for a term of kind `kind`, each drawn about its default ([`draw`]), with a friction
/// law's static level put at or above its sliding level (the rule every such law keeps).
pub(crate) fn draw_values(kind: &str, u: &mut impl FnMut() -> f64) -> Vec<f64> {
    let params = AnyTerm::params_of(kind).unwrap();
    let mut values: Vec<f64> = params.iter().map(|q| draw(q, u)).collect();
    let friction = params.len() > 1 && params[0].name == "fc" && params[1].name == "fs";
    if friction && values[1] < values[0] {
        values.swap(0, 1);
    }
    values
}

/// The scalar Taylor stepper on `m` from `y0` over `(from, t_end)`: its final state, its step
/// count and the ends and end states of its steps after `from`.
#[allow(clippy::type_complexity)]
fn scalar<const N: usize>(
    m: &Model,
    y0: [f64; N],
    (from, t_end): (f64, f64),
    o: Options,
) -> ([f64; N], u64, Vec<(f64, [f64; N])>) {
    let mut s = stepper(m, 0.0, y0, o).unwrap();
    let mut shown = Vec::new();
    while s.t() < t_end {
        s.step(t_end).unwrap();
        if s.t() > from {
            let d = s.dense();
            shown.push((d.t_end(), d.eval(d.t_end())));
        }
    }
    (*s.y(), s.stats().steps, shown)
}

/// Runs `models` (all of dimension N) in one batch and checks every lane against the scalar
/// stepper and DOP853.
fn check_batch<const N: usize>(models: &[Model], u: &mut impl FnMut() -> f64) {
    let o = Options {
        rtol: 1e-12,
        atol: 1e-12,
        ..Options::default()
    };
    let starts: Vec<[f64; N]> = models
        .iter()
        .map(|m| {
            let mut y = [0.0; N];
            y[0] = -1.0 + 2.0 * u();
            y[1] = -1.0 + 2.0 * u();
            // the internal states from a rest at x (a phase, a filter's state)
            for (i, z) in m.rest_states(y[0]).iter().enumerate().take(N - 2) {
                y[2 + i] = *z;
            }
            y
        })
        .collect();
    let spans: Vec<(f64, f64)> = (0..models.len())
        .map(|_| {
            let t_end = 5.0 + 25.0 * u();
            (t_end * u(), t_end)
        })
        .collect();
    let mut shown: Vec<Vec<(f64, [f64; N])>> = vec![Vec::new(); models.len()];
    let ends = integrate_models(models, &starts, &spans, o, |i, d| {
        shown[i].push((d.t_end(), d.eval(d.t_end())));
    })
    .unwrap();
    let vector = on_vector_lanes(models);
    for (i, m) in models.iter().enumerate() {
        let end = ends[i].as_ref().unwrap();
        let (y, steps, steps_shown) = scalar(m, starts[i], spans[i], o);
        let scale = 1.0 + y.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        if vector {
            // (the states to the tolerance, as with DOP853 below)
            let run = (&y, steps, steps_shown.len());
            agree_on_vector_lanes(i, m, run, (end, &shown[i]), spans[i], true);
        } else {
            assert_eq!(end.y, y, "lane {i} {}: final state", m.equation());
            assert_eq!(end.steps, steps, "lane {i}: steps");
            assert_eq!(shown[i], steps_shown, "lane {i}: the steps shown");
        }
        // DOP853 on the same equations, to the tolerance
        let mut d = stepper(
            m,
            0.0,
            starts[i],
            Options {
                method: Method::Dop853,
                ..o
            },
        )
        .unwrap();
        while d.t() < spans[i].1 {
            d.step(spans[i].1).unwrap();
        }
        let worst = y
            .iter()
            .zip(d.y())
            .fold(0.0f64, |a, (p, q)| a.max((p - q).abs()));
        assert!(
            worst < 1e-8 * scale,
            "lane {i} {}: Taylor and DOP853 differ by {worst:e}",
            m.equation()
        );
    }
}

/// Lane i of a batch on vector lanes against its scalar run (`run`: final state, steps, steps
/// shown) on model `m` over `span`: the state to 1e-8 of its size, the step counts (and the
/// steps shown) to 1 %, every step after the span's start shown in order (`strictly` later than
/// the one before, or not earlier), the last at the end with the end state. The passes are the
/// same to the bit, the step rule's and the limits' logarithms and exponentials to ~1e-9: a
/// limit halves a step where the reach of a series crosses a threshold, a jump in the state, so
/// a difference at the rounding level can move a step across one and the steps after it fall
/// elsewhere (measured: 4 in 772, the states then within 1e-14); a limit that did not shorten,
/// or shortened wrongly, changes them by far more.
pub(crate) fn agree_on_vector_lanes<const N: usize>(
    i: usize,
    m: &Model,
    (y, steps, shown_alone): (&[f64; N], u64, usize),
    (end, shown): (&hdgear::batch::LaneResult<N>, &[(f64, [f64; N])]),
    span: (f64, f64),
    strictly: bool,
) {
    let scale = 1.0 + y.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let worst = y
        .iter()
        .zip(&end.y)
        .fold(0.0f64, |a, (p, q)| a.max((p - q).abs()));
    assert!(worst < 1e-8 * scale, "lane {i} {}: {worst:e}", m.equation());
    let near = |a: usize, b: usize| a.abs_diff(b) as f64 <= 1.0 + 1e-2 * b as f64;
    assert!(
        near(end.steps as usize, steps as usize),
        "lane {i}: {} against {steps} steps",
        end.steps
    );
    let times: Vec<f64> = shown.iter().map(|s| s.0).collect();
    let ordered = |w: &[f64]| if strictly { w[0] < w[1] } else { w[0] <= w[1] };
    assert!(
        times.windows(2).all(ordered) && times[0] > span.0,
        "lane {i}"
    );
    assert_eq!(*shown.last().unwrap(), (span.1, end.y), "lane {i}");
    assert!(near(shown.len(), shown_alone), "lane {i}: shown");
}

#[test]
fn random_smooth_models_take_the_scalar_steppers_steps_on_the_lanes() {
    let mut u = uniform(11);
    // the kinds that run in the batch
    let smooth: Vec<&str> = AnyTerm::KINDS
        .iter()
        .map(|k| k.0)
        .filter(|kind| {
            Model::study(&Params::default())
                .with_term(AnyTerm::new(kind, &defaults(kind)).unwrap())
                .is_ok_and(|m| !m.switches() && m.delay().is_none())
        })
        .collect();
    assert!(smooth.len() >= 8, "{smooth:?}");
    // more models than a chunk of lanes of each dimension the terms give, and each kind that
    // runs in the batch in some model
    let mut by_dim: [Vec<Model>; 3] = Default::default();
    let missing = |by_dim: &[Vec<Model>; 3]| {
        smooth
            .iter()
            .filter(|kind| {
                !by_dim
                    .iter()
                    .flatten()
                    .any(|m| m.terms().any(|t| t.kind() == **kind))
            })
            .count()
    };
    for _ in 0..5000 {
        if by_dim.iter().all(|v| v.len() >= LANES + 5) && missing(&by_dim) == 0 {
            break;
        }
        let m = random_smooth_model(&mut u);
        let before = missing(&by_dim);
        let v = &mut by_dim[m.dim() - 2];
        if v.len() < LANES + 5 {
            v.push(m);
        } else {
            v.push(m);
            if missing(&by_dim) == before {
                by_dim[m.dim() - 2].pop();
            }
        }
    }
    assert_eq!(missing(&by_dim), 0, "some kinds were never drawn");
    check_batch::<2>(&by_dim[0], &mut u);
    check_batch::<3>(&by_dim[1], &mut u);
    check_batch::<4>(&by_dim[2], &mut u);
}

/// [`LANES`] terms of kind `kind` at random values ([`draw_values`]), each on a piece of its law
/// (a switching kind's signs at random; kept where its lane shape is the first's), with their
/// lane values side by side.
fn lane_terms(
    kind: &str,
    u: &mut impl FnMut() -> f64,
) -> (
    Vec<AnyTerm>,
    [hdgear::model::jet::Lanes; hdgear::model::terms::LANE_PARAMS],
) {
    use hdgear::model::jet::{Jet, Lanes};
    use hdgear::model::terms::{LANE_PARAMS, Side};
    let mut sign = || if u() < 0.5 { -1.0 } else { 1.0 };
    let sides: Vec<Side> = (0..LANES)
        .map(|_| Side {
            v: sign(),
            z: sign(),
        })
        .collect();
    let terms: Vec<AnyTerm> = sides
        .iter()
        .map(|&side| {
            AnyTerm::new(kind, &draw_values(kind, u))
                .unwrap()
                .directed(side)
        })
        .collect();
    // (an exponent the recurrence unrolls is the same on every lane)
    let terms: Vec<AnyTerm> = terms
        .iter()
        .filter(|t| t.lane_shape() == terms[0].lane_shape())
        .copied()
        .collect();
    let mut values = [Lanes::splat(0.0); LANE_PARAMS];
    for (l, t) in terms.iter().enumerate() {
        for (v, p) in values.iter_mut().zip(t.lane_values()) {
            v.0[l] = p;
        }
    }
    (terms, values)
}

/// The default values of kind `kind`'s parameters.
pub(crate) fn defaults(kind: &str) -> Vec<f64> {
    AnyTerm::params_of(kind)
        .unwrap()
        .iter()
        .map(|q| q.default)
        .collect()
}

#[test]
fn both_batches_refuse_bad_input_naming_it() {
    // the batch of smooth models and that of switching ones, each refusing the other's
    let study = Model::study(&Params::default());
    let with = |kind: &str| {
        study
            .with_term(AnyTerm::new(kind, &defaults(kind)).unwrap())
            .unwrap()
    };
    let coulomb = with("coulomb");
    let o = Options::default();
    for switching in [false, true] {
        let run = |models: &[Model], starts: &[[f64; 2]], spans: &[(f64, f64)]| {
            let ends = if switching {
                integrate_switching_models(models, starts, spans, o, |_, _| {})
            } else {
                integrate_models(models, starts, spans, o, |_, _| {})
            };
            ends.unwrap_err().to_string()
        };
        let (good, other) = if switching {
            (coulomb, study)
        } else {
            (study, coulomb)
        };
        let e = run(&[good, other], &[[0.0; 2]; 2], &[(0.0, 1.0); 2]);
        assert!(e.contains("switch") && e.contains(&other.equation()), "{e}");
        let e = run(&[good], &[[0.0; 2]; 2], &[(0.0, 1.0)]);
        assert!(e.contains("2 starts"), "{e}");
        let e = run(&[good], &[[0.0; 2]], &[(0.0, f64::NAN)]);
        assert!(e.contains("NaN"), "{e}");
        // a model with an internal state asked for as N = 2
        let stateful = with(if switching { "boucwen" } else { "washout" });
        let e = run(&[stateful], &[[0.0; 2]], &[(0.0, 1.0)]);
        assert!(e.contains("3 state components"), "{e}");
    }
}

#[test]
fn a_lane_that_blows_up_fails_alone() {
    let o = Options::default();
    let calm = Model::study(&Params::default());
    let models = [calm; 3];
    // a twist of 1e60 in the middle lane: its time scale, 1/(√α·x), is below any step the
    // span allows (or its speed, √(α/2)·x², beyond the blow-up bound)
    let starts = [[0.1, 0.0], [1e60, 0.0], [0.2, 0.0]];
    let spans = [(0.0, 20.0); 3];
    let ends = integrate_models(&models, &starts, &spans, o, |_, _| {}).unwrap();
    assert!(ends[1].is_err(), "{:?}", ends[1]);
    // its neighbours as in a batch without it, to the bit
    let alone = integrate_models(
        &models[..2],
        &[starts[0], starts[2]],
        &spans[..2],
        o,
        |_, _| {},
    )
    .unwrap();
    for (i, a) in [(0, &alone[0]), (2, &alone[1])] {
        let (end, a) = (ends[i].as_ref().unwrap(), a.as_ref().unwrap());
        assert_eq!((end.y, end.steps), (a.y, a.steps), "lane {i}");
    }
}

#[test]
fn models_of_one_structure_take_the_scalar_steppers_steps_on_vector_lanes() {
    // each structure of the kinds with a copy on lanes, at random parameters: 21 models, so a
    // full chunk of sixteen and a part one, each lane against the scalar stepper (its steps to
    // ~1e-9, `check_batch`)
    let on_lanes: Vec<&str> = AnyTerm::KINDS
        .iter()
        .map(|k| k.0)
        .filter(|kind| AnyTerm::new(kind, &defaults(kind)).unwrap().on_lanes())
        .collect();
    assert!(
        ["damping", "stiffness", "friction", "stribeck"]
            .iter()
            .all(|k| on_lanes.contains(k)),
        "{on_lanes:?}"
    );
    let mut u = uniform(23);
    // (one friction law per model: the laws share their parameters' names)
    for extra in [&[][..], &["friction"], &["stribeck"]] {
        let models: Vec<Model> = (0..LANES + 5)
            .map(|_| {
                let p = random_params(&mut u);
                extra.iter().fold(Model::study(&p), |m, kind| {
                    let values = draw_values(kind, &mut u);
                    m.with_term(AnyTerm::new(kind, &values).unwrap()).unwrap()
                })
            })
            .collect();
        assert!(on_vector_lanes(&models), "{extra:?}");
        check_batch::<2>(&models, &mut u);
    }
}

#[test]
fn each_kind_on_lanes_gives_every_lane_its_scalar_row() {
    // for every kind: a copy on lanes exactly where the kind says so, and each lane's rows
    // (the torque's, the state's rate's and the term's own) those of the scalar recurrence on
    // that lane's term and series, bit for bit, at every order; each term on a piece of its law
    // (a switching kind's signs at random, which its lane values carry)
    use hdgear::integrate::taylor::{SCRATCH_ROWS, Scratch};
    use hdgear::model::jet::{Jet, Lanes};
    use hdgear::model::terms::{LaneRows, MAX_ROWS};
    let mut u = uniform(29);
    for (kind, _, _) in AnyTerm::KINDS {
        let (terms, values) = lane_terms(kind, &mut u);
        // random series of x, v and z on each lane, shrinking with the order
        let mut series = [[Lanes::splat(0.0); MAX_ROWS]; 3];
        for k in 0..MAX_ROWS {
            for l in 0..LANES {
                for s in &mut series {
                    s[k].0[l] = (-1.0 + 2.0 * u()) * 0.7f64.powi(k as i32);
                }
            }
        }
        let [x, v, z] = &series;
        let mut rows: LaneRows = [[Lanes::splat(0.0); MAX_ROWS]; SCRATCH_ROWS];
        let mut scalar = vec![Scratch::default(); LANES];
        let lane = |rows: &[Lanes; MAX_ROWS], l: usize| rows.map(|r| r.0[l]);
        for k in 0..MAX_ROWS {
            let rate = terms[0].rate_taylor_lanes(&values, k, x, v, z, &mut rows);
            let on = terms[0].taylor_lanes(&values, k, x, v, z, &mut rows);
            assert_eq!(on.is_some(), terms[0].on_lanes(), "{kind}");
            let Some(on) = on else { break };
            for (l, t) in terms.iter().enumerate() {
                let (xl, vl, zl) = (lane(x, l), lane(v, l), lane(z, l));
                let want_rate = t.rate_taylor(k, &xl, &vl, &zl, &mut scalar[l]);
                let want = t.taylor(k, &xl, &vl, &zl, &mut scalar[l]);
                assert_eq!(
                    rate.0[l].to_bits(),
                    want_rate.to_bits(),
                    "{kind} rate k {k} lane {l}"
                );
                assert_eq!(on.0[l].to_bits(), want.to_bits(), "{kind} k {k} lane {l}");
                for (on_row, row) in rows.iter().zip(&scalar[l].0) {
                    assert_eq!(on_row[k].0[l].to_bits(), row[k].to_bits(), "{kind} k {k}");
                }
            }
        }
        if !terms[0].on_lanes() {
            continue;
        }
        // the step limits on those rows: each lane's its scalar limit's, to the ~1e-9 of the
        // lanes' logarithms and exponentials (a halving decided the other way would be a factor
        // of 2); the series above (|v₀| up to 1 against velocity scales about 0.01) make the
        // limits of the friction laws shorten the steps on many lanes
        let mut shortened = 0;
        for order in [8, 13, 20] {
            for h in [0.01, 0.3, 2.0] {
                let negligible = 1e-10 / f64::max(h, 1.0);
                let on = terms[0].step_limit_lanes(
                    &values,
                    &rows,
                    order,
                    Lanes::splat(h),
                    Lanes::splat(negligible),
                );
                for (l, t) in terms.iter().enumerate() {
                    let want = t.step_limit(&scalar[l], order, h, negligible);
                    let got = on.0[l];
                    assert!(
                        (got - want).abs() <= 1e-8 * want,
                        "{kind} order {order} h {h} lane {l}: {got} against {want}"
                    );
                    shortened += usize::from(want < h);
                }
            }
        }
        assert_eq!(
            shortened > 0,
            terms[0].limits_steps(),
            "{kind}: {shortened}"
        );
    }
}
