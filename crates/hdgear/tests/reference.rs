//! Against the independent reference trajectories (scipy DOP853, rtol 1e-13: `tests/data/README.md`).

use crate::common::reference_rows;
use hdgear::Params;
use hdgear::integrate::{Method, Options};
use hdgear::simulate::{SimOptions, Start, simulate};

/// Both methods at their default tolerance (rtol = atol = 1e-10): DOP853 to 1e-9 (its global
/// error is a few times the tolerance), Taylor to 1e-10 (its truncation error per step is far
/// below the tolerance, as Jorba–Zou's rule intends).
#[test]
fn paper_trajectories_reproduced_by_both_methods() {
    for (method, bar) in [(Method::Taylor, 1e-10), (Method::Dop853, 1e-9)] {
        let tol = Options {
            method,
            ..Options::default()
        };
        let worst = reproduce(tol, bar);
        eprintln!("{method:?}: worst abs error {worst:e} (bar {bar:e})");
    }
}

/// A given Taylor order (`Options::order`) keeps the tolerance: at rtol = atol = 1e-10 every order
/// from 8 to 20 reproduces the reference trajectories to the same 1e-10 as Jorba–Zou's order 13,
/// and the step grows with the order (fewer steps over the same span: the rule trades steps for
/// work per step, it does not loosen the error); an order outside 6…20 is refused by name.
#[test]
fn a_given_taylor_order_keeps_the_tolerance_in_fewer_steps() {
    use hdgear::integrate::{Stepper, stepper};
    use hdgear::model::Dimensionless;
    let mut steps = Vec::new();
    for order in [8, 13, 16, 20] {
        let tol = Options {
            order: Some(order),
            ..Options::default()
        };
        let worst = reproduce(tol, 1e-10);
        let sys = Dimensionless::new(Params::default());
        let mut s = stepper(&sys, 0.0, [0.0, 0.0], tol).unwrap();
        while s.t() < 1000.0 {
            s.step(1000.0).unwrap();
        }
        steps.push(s.stats().steps);
        eprintln!(
            "order {order}: worst abs error {worst:e}, {} steps",
            s.stats().steps
        );
    }
    assert!(steps.windows(2).all(|w| w[1] < w[0]), "steps {steps:?}");
    for bad in [5, 21] {
        let tol = Options {
            order: Some(bad),
            ..Options::default()
        };
        let e = tol.validate().unwrap_err();
        assert!(
            matches!(e, hdgear::Error::InvalidOption { name: "order", .. }),
            "{e}"
        );
        assert!(e.to_string().contains(&bad.to_string()), "{e}");
    }
}

fn reproduce(tol: Options, bar: f64) -> f64 {
    let method = tol.method;
    let mut overall: f64 = 0.0;
    let rows = reference_rows();
    let mut gammas: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    gammas.dedup();
    assert_eq!(gammas, vec![30.0, 10.0, 1.0, 0.1]);
    for g in gammas {
        let refs: Vec<&[f64; 6]> = rows.iter().filter(|r| r[0] == g).collect();
        let (x0, v0) = (refs[0][1], refs[0][2]);
        let t_end = refs.last().unwrap()[3];
        let p = Params {
            gamma: g,
            ..Params::default()
        };
        let opts = SimOptions {
            t_end,
            dt: 5.0,
            start: Start::Given { x0, v0 },
            tol,
        };
        let mut got = Vec::new();
        simulate(&p, &opts, |t, y| got.push((t, y[0], y[1]))).unwrap();
        assert_eq!(got.len(), refs.len(), "gamma {g}: sample count");
        let mut worst: f64 = 0.0;
        for ((t, x, v), r) in got.iter().zip(&refs) {
            assert!((t - r[3]).abs() < 1e-9, "gamma {g}: time {t} vs {}", r[3]);
            let err = (x - r[4]).abs().max((v - r[5]).abs());
            worst = worst.max(err);
            assert!(
                err <= bar,
                "{method:?}, gamma {g}, t {t}: x {x} vs {}, xdot {v} vs {} (err {err:e})",
                r[4],
                r[5]
            );
        }
        eprintln!(
            "{method:?} gamma {g}: {} samples, worst abs error {worst:e}",
            got.len()
        );
        overall = overall.max(worst);
    }
    overall
}

/// Each step's dense output ends on the state the integrator ended on (the scan samples the step's
/// end there), and its polynomial agrees with it at the step's end to rounding: for the scalar
/// Taylor stepper and for every lane of a batch, whose last step ends on the lane's final state.
#[test]
fn dense_outputs_end_on_the_integrators_state() {
    use hdgear::batch::integrate_batch_observed;
    use hdgear::integrate::{DenseOutput, Method, Stepper, stepper};
    use hdgear::model::Dimensionless;
    let close = |a: [f64; 2], b: [f64; 2]| {
        (0..2).all(|i| (a[i] - b[i]).abs() <= 1e-13 * (1.0 + b[i].abs()))
    };
    for gamma in [0.1, 30.0] {
        let p = Params {
            gamma,
            ..Params::default()
        };
        let o = Options {
            method: Method::Taylor,
            ..Options::default()
        };
        let sys = Dimensionless::new(p);
        let mut s = stepper(&sys, 0.0, [0.0, 0.0], o).unwrap();
        for _ in 0..500 {
            s.step(1e4).unwrap();
            let d = s.dense();
            assert_eq!(d.end_state(), *s.y(), "gamma {gamma}");
            assert!(close(d.eval(d.t_end()), *s.y()), "gamma {gamma}");
        }
    }
    let points: Vec<Params> = [0.1, 1.0, 30.0]
        .iter()
        .map(|&gamma| Params {
            gamma,
            ..Params::default()
        })
        .collect();
    let mut last = vec![None; points.len()];
    let spans = vec![(0.0, 300.0); points.len()];
    let out = integrate_batch_observed(
        &points,
        &[[0.0; 2]; 3],
        &spans,
        Options::default(),
        |i, d| {
            assert!(close(d.eval(d.t_end()), d.end_state()), "lane {i}");
            last[i] = Some(d.end_state());
        },
    )
    .unwrap();
    for (r, l) in out.iter().zip(&last) {
        assert_eq!(Some(r.as_ref().unwrap().y), *l);
    }
}

/// Lanes that end at different times: a lane at its end takes steps of 0 while the others go on,
/// and those leave it exactly as it was. Each lane's final state and step count are the same to
/// the bit as the same point's integrated alone (its batch padded with copies of itself, which all
/// end together).
#[test]
fn a_lane_at_its_end_waits_unchanged_for_the_others() {
    use hdgear::batch::integrate_batch_observed;
    let points: Vec<Params> = [0.1, 1.0, 30.0, 3.0, 0.3]
        .iter()
        .map(|&gamma| Params {
            gamma,
            ..Params::default()
        })
        .collect();
    // ends from 20 to 320: the first lane waits through most of the others' steps
    let ends: Vec<f64> = (0..points.len()).map(|i| 20.0 + 75.0 * i as f64).collect();
    let run = |pts: &[Params], ends: &[f64]| {
        let spans: Vec<(f64, f64)> = ends.iter().map(|&e| (e, e)).collect();
        let starts = vec![[0.2, -0.1]; pts.len()];
        integrate_batch_observed(pts, &starts, &spans, Options::default(), |_, _| {}).unwrap()
    };
    let together = run(&points, &ends);
    for (i, r) in together.iter().enumerate() {
        let alone = run(&points[i..=i], &ends[i..=i]);
        assert_eq!(r.as_ref().unwrap(), alone[0].as_ref().unwrap(), "lane {i}");
    }
    // and the first lane did wait: it ended after a fraction of the steps of the longest
    let steps: Vec<u64> = together.iter().map(|r| r.as_ref().unwrap().steps).collect();
    assert!(3 * steps[0] < *steps.iter().max().unwrap(), "{steps:?}");
}

/// A lane that blows up and one that runs out of steps stop with their own errors, and the lane
/// beside them gives, to the bit, what it gives alone (the batch's step that some lane fails
/// goes lane by lane).
#[test]
fn failing_lanes_stop_alone_in_a_batch() {
    use hdgear::batch::integrate_batch_observed;
    use hdgear::error::SolverError;
    let o = Options {
        max_steps: 300,
        blowup: 10.0,
        ..Options::default()
    };
    let run = |points: &[Params], starts: &[[f64; 2]], ends: &[f64]| {
        let spans: Vec<(f64, f64)> = ends.iter().map(|&e| (e, e)).collect();
        integrate_batch_observed(points, starts, &spans, o, |_, _| {}).unwrap()
    };
    let p = Params::default();
    // lane 1 starts beyond the blow-up bound; lane 2, forced fast (its steps a few hundredths
    // long), passes the up-front budget estimate of its span (280 steps) but not the 300
    let fast = Params { omega: 5.0, ..p };
    let out = run(
        &[p, p, fast],
        &[[0.2, -0.1], [50.0, 0.0], [0.2, -0.1]],
        &[20.0, 20.0, 140.0],
    );
    let alone = run(&[p], &[[0.2, -0.1]], &[20.0]);
    assert_eq!(out[0].as_ref().unwrap(), alone[0].as_ref().unwrap());
    assert!(
        matches!(
            out[1],
            Err(hdgear::Error::Solver(SolverError::BlowUp { .. }))
        ),
        "{:?}",
        out[1]
    );
    assert!(
        matches!(
            out[2],
            Err(hdgear::Error::Solver(SolverError::TooManySteps {
                max_steps: 300,
                ..
            }))
        ),
        "{:?}",
        out[2]
    );
}

/// The batch integrator (lanes in lock-step, sine carried as state, approximate logarithm in the
/// step rule) lands on the reference's final states as closely as the scalar Taylor method, for
/// the four γ in one batch padded to the lane count, at Jorba–Zou's order and at a given one.
#[test]
fn batch_lanes_reach_the_reference_final_states() {
    use hdgear::batch::{LANES, integrate_batch};
    let rows = reference_rows();
    let mut gammas: Vec<f64> = rows.iter().map(|r| r[0]).collect();
    gammas.dedup();
    let points: Vec<Params> = gammas
        .iter()
        .map(|&gamma| Params {
            gamma,
            ..Params::default()
        })
        .collect();
    let first = |g: f64| rows.iter().find(|r| r[0] == g).unwrap();
    let last = |g: f64| rows.iter().rev().find(|r| r[0] == g).unwrap();
    let starts: Vec<[f64; 2]> = gammas.iter().map(|&g| [first(g)[1], first(g)[2]]).collect();
    let t_end = last(gammas[0])[3];
    assert!(gammas.len() < LANES, "the batch is padded");
    // Jorba–Zou's order, and the highest order with its longer steps (`Options::order`)
    for order in [None, Some(20)] {
        let tol = Options {
            order,
            ..Options::default()
        };
        let out = integrate_batch(&points, &starts, t_end, tol).unwrap();
        assert_eq!(out.len(), gammas.len());
        for (g, r) in gammas.iter().zip(&out) {
            let want = last(*g);
            let err = (r.y[0] - want[4]).abs().max((r.y[1] - want[5]).abs());
            eprintln!(
                "batch gamma {g}, order {order:?}: {} steps, final-state error {err:e}",
                r.steps
            );
            assert!(err <= 1e-10, "gamma {g}, order {order:?}: {err:e}");
        }
    }
    // bad input is refused by name, as everywhere
    let bad = [Params {
        alpha: -1.0,
        ..Params::default()
    }];
    let e = integrate_batch(&bad, &[[0.0, 0.0]], 10.0, Options::default()).unwrap_err();
    assert!(e.to_string().contains("alpha"), "{e}");
}
