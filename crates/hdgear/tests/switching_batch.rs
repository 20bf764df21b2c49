//! Many switching models at once ([`integrate_switching_models`]): random models with Coulomb
//! friction (sticking), Bouc–Wen and Dahl hysteresis, LuGre friction and the mesh loss, in batches that cross a chunk of
//! sixteen lanes, against the scalar switching integration run here one model at a time (on
//! vector lanes to the tolerance, with the steps to ~1 %; otherwise to the bit). Its refusals
//! are tested beside the smooth batch's (`model_batch`).

use hdgear::batch::LANES;
use hdgear::integrate::{DenseOutput, Options, Stepper};
use hdgear::model::switching::{Pieces, Switching};
use hdgear::model::terms::AnyTerm;
use hdgear::model::{Model, integrate_switching_models, on_vector_lanes};

use crate::common::uniform;
use crate::model_batch::{agree_on_vector_lanes, draw_values, random_params};

/// What one run gives: its final state, its step count, the end times and states of its steps
/// after the span's start, and how many of those were at rest.
type Run<const N: usize> = ([f64; N], u64, Vec<(f64, [f64; N])>, usize);

/// The scalar switching integration of `m` from `y0` over `(from, t_end)`.
fn scalar<const N: usize>(
    m: &Model,
    y0: [f64; N],
    (from, t_end): (f64, f64),
    o: Options,
) -> hdgear::Result<Run<N>> {
    let pieces = Pieces::new(m).unwrap();
    let mut s = Switching::<N>::new(&pieces, 0.0, y0, o)?;
    let (mut shown, mut at_rest) = (Vec::new(), 0);
    while s.t() < t_end {
        s.step(t_end)?;
        if s.t() > from {
            let d = s.dense();
            shown.push((d.t_end(), d.end_state()));
            at_rest += usize::from(d.is_stuck());
        }
    }
    Ok((*s.y(), s.stats().steps, shown, at_rest))
}

/// `count` models: the study's at random parameters with the terms `kinds`, each parameter
/// drawn about its default ([`draw_values`]); a Bouc–Wen or Dahl exponent `n` where given (else drawn).
fn models(kinds: &[&str], n: Option<f64>, count: usize, u: &mut impl FnMut() -> f64) -> Vec<Model> {
    (0..count)
        .map(|_| {
            let mut p = random_params(u);
            // loads that move the drive through rest and back (sticking where it can)
            p.delta = 0.5 + 3.0 * u();
            kinds.iter().fold(Model::study(&p), |m, kind| {
                let mut values = draw_values(kind, u);
                match (n, *kind) {
                    (Some(n), "boucwen") => values[5] = n,
                    (Some(n), "dahl") => values[2] = n,
                    _ => {}
                }
                m.with_term(AnyTerm::new(kind, &values).unwrap()).unwrap()
            })
        })
        .collect()
}

/// Runs `models` (all of dimension N) in one batch and checks every lane against the scalar
/// switching integration; returns how many shown steps were at rest, over all lanes.
fn check_batch<const N: usize>(models: &[Model], u: &mut impl FnMut() -> f64) -> usize {
    let o = Options {
        rtol: 1e-12,
        atol: 1e-12,
        ..Options::default()
    };
    // every third model starts at rest (its mode from the applied torque), the others slipping
    let starts: Vec<[f64; N]> = (0..models.len())
        .map(|i| {
            let mut y = [0.0; N];
            y[0] = -1.0 + 2.0 * u();
            y[1] = if i % 3 == 0 { 0.0 } else { -1.0 + 2.0 * u() };
            y
        })
        .collect();
    let spans: Vec<(f64, f64)> = (0..models.len())
        .map(|_| {
            let t_end = 10.0 + 30.0 * u();
            (t_end * u(), t_end)
        })
        .collect();
    let mut shown: Vec<Vec<(f64, [f64; N])>> = vec![Vec::new(); models.len()];
    let ends = integrate_switching_models(models, &starts, &spans, o, |i, d| {
        shown[i].push((d.t_end(), d.end_state()));
    })
    .unwrap();
    let vector = on_vector_lanes(models);
    let mut at_rest = 0;
    for (i, m) in models.iter().enumerate() {
        let alone = scalar(m, starts[i], spans[i], o);
        let (end, (y, steps, steps_shown, rest)) = match (&ends[i], alone) {
            (Ok(end), Ok(alone)) => (end, alone),
            (Err(a), Err(b)) => {
                assert_eq!(a.to_string(), b.to_string(), "lane {i}");
                continue;
            }
            (a, b) => panic!("lane {i} {}: {a:?} against {b:?}", m.equation()),
        };
        at_rest += rest;
        if vector {
            // the switches are located on steps that differ at the ~1e-9 of the lanes' step rule,
            // each to 1e-13: the states agree to the tolerance over the run. (A switch may end
            // a step where a rest of no length begins: the steps shown are in order, not
            // strictly.)
            let run = (&y, steps, steps_shown.len());
            agree_on_vector_lanes(i, m, run, (end, &shown[i]), spans[i], false);
        } else {
            assert_eq!(end.y, y, "lane {i} {}: final state", m.equation());
            assert_eq!(end.steps, steps, "lane {i}: steps");
            assert_eq!(shown[i], steps_shown, "lane {i}: the steps shown");
        }
    }
    at_rest
}

#[test]
fn switching_models_of_one_structure_run_on_vector_lanes_as_each_runs_alone() {
    let mut u = uniform(31);
    let count = LANES + 5;
    // Coulomb friction with sticking, alone and with hysteresis: the lanes stick and slip
    let coulomb = models(&["coulomb"], None, count, &mut u);
    assert!(on_vector_lanes(&coulomb));
    assert!(check_batch::<2>(&coulomb, &mut u) > 0, "no lane stuck");
    let both = models(&["coulomb", "boucwen"], Some(1.0), count, &mut u);
    assert!(on_vector_lanes(&both));
    assert!(check_batch::<3>(&both, &mut u) > 0, "no lane stuck");
    // regularised Stribeck friction with Bouc–Wen hysteresis (the benchmark's model), at each
    // exponent the recurrence unrolls
    for n in [1.0, 2.0, 3.0] {
        let models = models(&["stribeck", "boucwen"], Some(n), count, &mut u);
        assert!(on_vector_lanes(&models), "n = {n}");
        check_batch::<3>(&models, &mut u);
    }
    // LuGre friction (its bristle state's quotient by the Stribeck curve), and Dahl hysteresis
    // at each exponent
    let lugre = models(&["lugre"], None, count, &mut u);
    assert!(on_vector_lanes(&lugre));
    check_batch::<3>(&lugre, &mut u);
    for n in [1.0, 2.0, 3.0] {
        let dahl = models(&["dahl"], Some(n), count, &mut u);
        assert!(on_vector_lanes(&dahl), "n = {n}");
        check_batch::<3>(&dahl, &mut u);
    }
}

#[test]
fn switching_models_of_other_structures_run_alone_to_the_bit() {
    let mut u = uniform(37);
    let count = LANES + 3;
    // the mesh loss has no copy on lanes; Bouc–Wen or Dahl exponents that differ are two
    // structures
    let mesh = models(&["meshloss"], None, count, &mut u);
    assert!(!on_vector_lanes(&mesh));
    check_batch::<3>(&mesh, &mut u);
    for kind in ["boucwen", "dahl"] {
        let mixed: Vec<Model> = (0..count)
            .map(|i| models(&[kind], Some(1.0 + (i % 2) as f64), 1, &mut u)[0])
            .collect();
        assert!(!on_vector_lanes(&mixed), "{kind}");
        check_batch::<3>(&mixed, &mut u);
    }
}
