//! Against the independent reference trajectories (scipy DOP853, rtol 1e-13, SPEC §4).

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
        let worst = reproduce(method, bar);
        eprintln!("{method:?}: worst abs error {worst:e} (bar {bar:e})");
    }
}

fn reproduce(method: Method, bar: f64) -> f64 {
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
            tol: Options {
                method,
                ..Options::default()
            },
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
