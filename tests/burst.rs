//! Bursts, modes and mechanisms at the study's point, the tables, and sweeps.

use hdgear::Params;
use hdgear::burst::{BurstOptions, Mechanism, Mode, classify, response};
use hdgear::sweep::{Axis, Grid};
use std::collections::HashSet;

fn paper(gamma: f64) -> Params {
    Params {
        gamma,
        ..Params::default()
    }
}

#[test]
fn the_study_gammas_give_the_study_modes() {
    for (g, bursts, mode) in [
        (30.0, 0.0, Mode::Normal),
        (10.0, 0.0, Mode::Transitional),
        (1.0, 2.0, Mode::FastSlow),
        (0.1, 2.0, Mode::PronouncedBursting),
    ] {
        let p = paper(g);
        let r = response(&p, &BurstOptions::default()).unwrap();
        let c = classify(&p, &r);
        assert_eq!(r.bursts_per_period, bursts, "gamma {g}: {:?}", r.bursts);
        assert_eq!(c.mode, mode, "gamma {g}: {r:?}");
        let expect_mech = if bursts > 0.0 {
            Mechanism::SharpQuantitativeChange
        } else {
            Mechanism::None
        };
        assert_eq!(c.mechanism, expect_mech, "gamma {g}");
        if bursts > 0.0 {
            // the independent measurement of SPEC §4: pulses of max |x'| ≈ 0.14 and 0.24
            let expect = if g == 1.0 { 0.14 } else { 0.24 };
            assert!(
                (r.peak_abs_xdot - expect).abs() < 0.005,
                "gamma {g}: {}",
                r.peak_abs_xdot
            );
            for b in &r.bursts {
                assert!(b.complete);
                assert!(b.spikes >= 1);
                assert!(b.a_onset.abs() < 0.1, "bursts start near a = 0: {b:?}");
                // the ringing decays over about ten time units (SPEC §4)
                assert!(b.duration > 5.0 && b.duration < 25.0, "{b:?}");
            }
            assert!(r.quiescent_fraction > 0.9 && r.quiescent_fraction < 1.0);
        } else {
            // the smooth slow wave: max |x'| ≈ 0.0035 and 0.013 (SPEC §4)
            let expect = if g == 30.0 { 0.0035 } else { 0.013 };
            assert!(
                (r.peak_abs_xdot - expect).abs() < 0.001,
                "gamma {g}: {}",
                r.peak_abs_xdot
            );
            assert_eq!(r.quiescent_fraction, 1.0);
            assert_eq!(r.spikes_per_burst, 0.0);
        }
    }
}

#[test]
fn folds_inside_the_range_mean_fold_hysteresis() {
    let p = paper(0.01);
    let r = response(&p, &BurstOptions::default()).unwrap();
    let c = classify(&p, &r);
    assert_eq!(r.bursts_per_period, 2.0);
    assert_eq!(c.mechanism, Mechanism::FoldHysteresis);
}

#[test]
fn burst_count_does_not_depend_on_the_window_phase() {
    // discarding 1, 1.1 or 1.5 periods moves the window start; the count must not change
    for discard in [1.0, 1.1, 1.5, 2.0] {
        let o = BurstOptions {
            discard_periods: discard,
            ..Default::default()
        };
        let r = response(&paper(1.0), &o).unwrap();
        assert_eq!(r.bursts_per_period, 2.0, "discard {discard}");
        assert!(r.window_start >= discard * paper(1.0).slow_period());
    }
}

#[test]
fn tables_reproduce_the_study() {
    let t = hdgear::table::tables(&Params::default(), &BurstOptions::default()).unwrap();
    let words: Vec<&str> = t.gamma_table.iter().map(|r| r.shape).collect();
    assert_eq!(
        words,
        [
            "smooth and gradual",
            "moderately steep",
            "very steep, sharp turn",
            "extremely steep, near-vertical"
        ]
    );
    assert!(t.gamma_table.iter().all(|r| r.agrees));
    // slopes at a = 0 grow as gamma falls
    for w in t.gamma_table.windows(2) {
        assert!(w[1].slope_at_a0 > w[0].slope_at_a0);
        assert!(w[1].max_slope > w[0].max_slope);
    }
    let verdict = |name: &str| {
        t.effects_table
            .iter()
            .find(|r| r.parameter == name)
            .unwrap()
            .verdict
    };
    assert_eq!(verdict("gamma"), "agrees");
    assert_eq!(verdict("delta"), "agrees");
    assert_eq!(verdict("omega"), "agrees");
    assert_eq!(verdict("eps"), "agrees");
    // measured: doubling alpha lowers the burst amplitude, against the study's claim
    assert_eq!(verdict("alpha"), "contradicts");
}

fn grid() -> Grid {
    Grid::new(
        Params::default(),
        vec![
            Axis::parse("gamma=0.05:20:6:log").unwrap(),
            Axis::parse("delta=8:16:2").unwrap(),
        ],
    )
    .unwrap()
}

#[test]
fn sweeps_are_identical_on_one_and_two_threads() {
    let g = grid();
    let mut runs = Vec::new();
    for threads in [1, 2] {
        let mut rows = Vec::new();
        hdgear::sweep::run(
            &g,
            &BurstOptions::default(),
            &HashSet::new(),
            threads,
            |r| rows.push(r),
        )
        .unwrap();
        rows.sort_by_key(|r| r.index);
        runs.push(rows);
    }
    assert_eq!(runs[0].len(), 12);
    // bit-identical (compare the serialised rows: NaN-safe)
    let ser = |v: &Vec<hdgear::sweep::SweepRow>| serde_json::to_string(v).unwrap();
    assert_eq!(ser(&runs[0]), ser(&runs[1]));
    // grid order: first axis fastest
    assert_eq!(runs[0][1].gamma, g.point(1).gamma);
    assert_eq!(runs[0][6].delta, 16.0);
    assert!(runs[0].iter().all(|r| r.error.is_empty()));
}

#[test]
fn axis_specs_are_checked() {
    for (spec, needle) in [
        ("gamma=1:2", "expected"),
        ("beta=1:2:3", "beta"),
        ("gamma=0:1:5:log", "log axis"),
        ("gamma=1:nan:5", "nan"),
        ("gamma=1:2:0", "COUNT"),
        ("gamma=1:2:3:lin", "lin"),
    ] {
        let e = Axis::parse(spec).unwrap_err().to_string();
        assert!(e.contains(needle), "{spec}: {e}");
    }
    // an impossible range: alpha through zero
    let e = Grid::new(
        Params::default(),
        vec![Axis::parse("alpha=-1:1:3").unwrap()],
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("alpha = -1"), "{e}");
}
