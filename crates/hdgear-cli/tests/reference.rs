//! Against the independent reference trajectories (scipy DOP853, rtol 1e-13, SPEC §4).

use crate::common::reference_rows;
use hdgear::Params;
use hdgear::simulate::{SimOptions, Start, simulate};

#[test]
fn paper_trajectories_reproduced_to_1e_9() {
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
            ..SimOptions::default()
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
                err <= 1e-9,
                "gamma {g}, t {t}: x {x} vs {}, xdot {v} vs {} (err {err:e})",
                r[4],
                r[5]
            );
        }
        eprintln!(
            "gamma {g}: {} samples, worst abs error {worst:e}",
            got.len()
        );
    }
}
