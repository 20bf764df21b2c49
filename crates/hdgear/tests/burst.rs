//! Bursts, modes and mechanisms at the study's point, the tables, and sweeps.
//!
//! **Why one file.** The tests of one capability, the burst verdict, in one module of the test
//! binary.

use hdgear::Params;
use hdgear::burst::{BurstOptions, Classification, Mechanism, Mode, Verdict, classify, response};
use hdgear::fast::predict;
use hdgear::sweep::{Axis, Grid};

fn paper(gamma: f64) -> Params {
    Params {
        gamma,
        ..Params::default()
    }
}

/// The 20 parameter sets of `tests/data/burst_cases.json` with their reference block.
fn reference_cases() -> Vec<(String, Params, serde_json::Value)> {
    crate::common::reference_cases("burst_cases.json")
        .into_iter()
        .map(|(id, p, c)| (id, p, c["reference"].clone()))
        .collect()
}

fn verdict_of(p: &Params, o: &BurstOptions) -> (Classification, hdgear::burst::Response) {
    let r = response(p, o).unwrap();
    (classify(p, &r), r)
}

#[test]
fn agrees_with_the_independent_reference_on_all_twenty_cases() {
    let cases = reference_cases();
    assert_eq!(cases.len(), 20);
    for (id, p, rf) in cases {
        let (c, r) = verdict_of(&p, &BurstOptions::default());
        assert_eq!(
            c.bursting,
            rf["bursts_present"].as_bool().unwrap(),
            "{id}: {c:?}"
        );
        assert_eq!(c.verdict.name(), rf["verdict"].as_str().unwrap(), "{id}");
        if c.bursting {
            assert_eq!(
                r.rates.bursts_per_period,
                rf["bursts_per_period"].as_f64(),
                "{id}"
            );
        }
        // the continuous measures are the same quantities: the largest leading lobe agrees
        // with the reference's to 1 % (both locate it on a dense output)
        let ov = rf["max_overshoot_rel"].as_f64().unwrap();
        assert!(
            (r.signatures.max_overshoot - ov).abs() <= 0.01 * ov + 1e-12,
            "{id}: overshoot {} vs {ov}",
            r.signatures.max_overshoot
        );
        assert!(
            (r.rates.peak_abs_xdot - rf["peak_abs_xdot"].as_f64().unwrap()).abs() < 1e-6,
            "{id}"
        );
        assert_eq!(
            r.signatures.jumps_per_period,
            rf["jumps_per_period"].as_f64().unwrap(),
            "{id}"
        );
        // and the prediction from the curve alone agrees too
        assert_eq!(predict(&p).bursting, c.bursting, "{id}: prediction");
        for b in &r.bursts {
            assert!(b.spikes >= 1, "{id}: {b:?}");
        }
    }
}

#[test]
fn bursts_obey_the_adiabatic_limit() {
    // Fenichel: without folds bursts vanish as ω → 0; with folds the jumps persist
    let at = |gamma: f64, omega: f64| {
        let p = Params {
            gamma,
            omega,
            ..Params::default()
        };
        (
            verdict_of(&p, &BurstOptions::default()).0.bursting,
            predict(&p).bursting,
        )
    };
    for (g, w, expect) in [
        (0.1, 1e-2, true),
        (0.1, 1e-3, true),
        (0.1, 1e-5, false),
        (0.01, 1e-1, true),
        (0.01, 1e-2, true),
        (0.01, 1e-3, true),
        (0.01, 1e-4, true),
        (1.0, 5e-3, true),
        (1.0, 1e-3, false),
    ] {
        assert_eq!(at(g, w), (expect, expect), "gamma {g}, omega {w}");
    }
}

#[test]
fn prediction_matches_the_simulated_boundaries() {
    // the boundary in γ at the study's point within 15 %, in ω at γ = 0.1 and 1 within ×1.5
    let o = BurstOptions::default();
    let b = hdgear::burst::boundaries(&Params::default(), &o).unwrap();
    let (pg, sg) = (b.predicted_gamma.unwrap(), b.simulated_gamma.unwrap());
    assert!(
        (pg / sg - 1.0).abs() < 0.15,
        "gamma: predicted {pg}, simulated {sg}"
    );
    // measured: predicted 2.265, simulated 2.199
    assert!(sg > 2.1 && sg < 2.3, "{sg}");
    let (pw, sw) = (b.predicted_omega, b.simulated_omega.unwrap());
    assert!(
        (pw / sw).max(sw / pw) < 1.5,
        "omega at gamma 0.1: {pw} vs {sw}"
    );
    let b1 = hdgear::burst::boundaries(
        &Params {
            gamma: 1.0,
            ..Params::default()
        },
        &o,
    )
    .unwrap();
    let (pw, sw) = (b1.predicted_omega, b1.simulated_omega.unwrap());
    assert!(
        (pw / sw).max(sw / pw) < 1.5,
        "omega at gamma 1: {pw} vs {sw}"
    );
    // the independent reference loses the bursts between 3e-4 and 1e-4 (γ = 0.1) and between
    // 3e-3 and 2e-3 (γ = 1) (Fenichel: a finite-ω effect)
    assert!(sw > 2e-3 && sw < 3e-3, "{sw}");
    assert!(b.simulated_omega.unwrap() > 1e-4 && b.simulated_omega.unwrap() < 3e-4);
}

#[test]
fn simulated_boundaries_are_switches_of_the_one_by_one_verdict() {
    // The search runs its rounds as batches of sixteen (Taylor) or one value at a time
    // (DOP853). Either way the boundary must be a switch of the simulated verdict: the verdict
    // of a response computed on its own changes between 2 % below and 2 % above it (the final
    // bracket is 1 % wide, and a batch may round a verdict differently only within a fraction
    // of a per cent of the switch), bursting below it in γ and above it in ω.
    use hdgear::burst::{BOUNDARY_REL_TOL, boundaries};
    use hdgear::integrate::Method;
    let o = BurstOptions::default();
    let f = 2.0 * BOUNDARY_REL_TOL;
    let bursting = |p: Params| verdict_of(&p, &o).0.bursting;
    let mut found = Vec::new();
    for gamma in [0.1, 1.0] {
        let p = Params {
            gamma,
            ..Params::default()
        };
        let b = boundaries(&p, &o).unwrap();
        let (g, w) = (b.simulated_gamma.unwrap(), b.simulated_omega.unwrap());
        let at = |gamma, omega| Params { gamma, omega, ..p };
        for (below, above, bursts_below) in [
            (at(g * (1.0 - f), p.omega), at(g * (1.0 + f), p.omega), true),
            (at(gamma, w * (1.0 - f)), at(gamma, w * (1.0 + f)), false),
        ] {
            assert_eq!(bursting(below), bursts_below, "{gamma}: {b:?}");
            assert_eq!(bursting(above), !bursts_below, "{gamma}: {b:?}");
        }
        found.push(b);
    }
    // one value at a time with DOP853 (γ = 1, where its simulations are short): the same
    // boundaries to the two brackets' widths
    let mut od = o;
    od.tol.method = Method::Dop853;
    let p1 = Params {
        gamma: 1.0,
        ..Params::default()
    };
    let d = boundaries(&p1, &od).unwrap();
    for (t, s) in [
        (found[1].simulated_gamma, d.simulated_gamma),
        (found[1].simulated_omega, d.simulated_omega),
    ] {
        let (t, s) = (t.unwrap(), s.unwrap());
        assert!(
            (t / s).ln().abs() <= 2.0 * BOUNDARY_REL_TOL,
            "taylor {t}, dop853 {s}"
        );
    }
}

#[test]
fn the_study_table_under_signatures() {
    // γ = 30 and 10: no signature at ω = 0.01 (adiabatic, x' the smooth slow wave of max 0.0035
    // and 0.013); γ = 1 and 0.1: two overshooting, ringing pulses per period of
    // max |x'| 0.14 and 0.24; γ = 0.1 creeps over a node first (g' = 0.079 < 1/4)
    for (g, verdict, mode, peak) in [
        (30.0, Verdict::NoBursts, Mode::Normal, 0.0035),
        (10.0, Verdict::NoBursts, Mode::Normal, 0.013),
        (1.0, Verdict::Overshoot, Mode::FastSlow, 0.14),
        (0.1, Verdict::Overshoot, Mode::PronouncedBursting, 0.24),
    ] {
        let p = paper(g);
        let (c, r) = verdict_of(&p, &BurstOptions::default());
        assert_eq!((c.verdict, c.mode), (verdict, mode), "gamma {g}: {r:?}");
        assert!(c.fast_slow_domain);
        assert!(
            (r.rates.peak_abs_xdot - peak).abs() < 0.06 * peak,
            "gamma {g}: {}",
            r.rates.peak_abs_xdot
        );
        if c.bursting {
            assert_eq!(c.mechanism, Mechanism::SharpQuantitativeChange);
            assert_eq!(r.rates.bursts_per_period, Some(2.0));
            for b in &r.bursts {
                assert!(b.complete && b.spikes >= 1);
                assert!(b.a_peak.abs() < 0.1, "pulses near a = 0: {b:?}");
                // the ringing decays over about ten time units
                assert!(b.duration > 5.0 && b.duration < 25.0, "{b:?}");
            }
        } else {
            assert_eq!(c.mechanism, Mechanism::None);
            assert_eq!(r.rates.bursts_per_period, Some(0.0));
            assert_eq!(r.rates.quiescent_fraction, 1.0);
            // adiabatic: the lag is the first-order adiabatic lag, the speed the quasi-static one
            assert!(
                (r.measures.lag_ratio - 1.0).abs() < 0.05,
                "{:?}",
                r.measures
            );
            assert!(
                (r.measures.speed_ratio - 1.0).abs() < 0.05,
                "{:?}",
                r.measures
            );
        }
    }
}

#[test]
fn fold_loops_count_each_jump_once() {
    // the textbook relaxation loop of the issue: both folds inside [−1, 1]
    let p = Params {
        alpha: 1.0,
        gamma: 0.1,
        eps: 1.0,
        mu: -0.141,
        delta: 0.05,
        omega: 0.01,
    };
    let (c, r) = verdict_of(&p, &BurstOptions::default());
    assert_eq!(r.rates.bursts_per_period, Some(2.0), "{:?}", r.bursts);
    assert_eq!(r.signatures.jumps_per_period, 2.0);
    assert_eq!(
        (c.verdict, c.mode, c.mechanism),
        (
            Verdict::FoldJump,
            Mode::Relaxation,
            Mechanism::FoldHysteresis
        )
    );
    assert!(r.bursts.iter().all(|b| b.spikes >= 1 && b.jumps == 1));
    let p = paper(0.01);
    let (c, r) = verdict_of(&p, &BurstOptions::default());
    assert_eq!(r.rates.bursts_per_period, Some(2.0));
    assert_eq!(c.mechanism, Mechanism::FoldHysteresis);
}

#[test]
fn no_burst_has_zero_spikes_across_a_gamma_sweep() {
    // the old rule made zero-spike "bursts" near γ = 2.3
    for i in 0..40 {
        let g = 1.5 + 0.04 * f64::from(i);
        let (_, r) = verdict_of(&paper(g), &BurstOptions::default());
        assert!(
            r.bursts.iter().all(|b| b.spikes >= 1 && b.extrema >= 1),
            "gamma {g}"
        );
    }
}

#[test]
fn outside_the_fast_slow_domain_no_word_is_forced() {
    // ω = 0.2: the slow period is 31 time units, 16 relaxation times; the fold case still jumps
    let p = Params {
        gamma: 0.01,
        omega: 0.2,
        ..Params::default()
    };
    let (c, _) = verdict_of(&p, &BurstOptions::default());
    assert!(!c.fast_slow_domain);
    assert_eq!(c.mode, Mode::NotFastSlow);
    assert!(c.bursting);
    // ω = 0.4 at γ = 0.1: the fast motion never stops: no burst count at all
    let p = Params {
        omega: 0.4,
        ..Params::default()
    };
    let (c, r) = verdict_of(&p, &BurstOptions::default());
    assert!(r.continuous_fast_motion);
    assert_eq!(r.rates.bursts_per_period, None);
    assert_eq!(c.mode, Mode::NotFastSlow);
}

/// What must not move: verdict, mode, bursts per period and, per burst, spikes, jumps and
/// whether it overshoots.
type Key = (Verdict, Mode, Option<f64>, Vec<(u32, bool)>);

fn key(p: &Params, o: &BurstOptions) -> Key {
    let (c, r) = verdict_of(p, o);
    (
        c.verdict,
        c.mode,
        r.rates.bursts_per_period,
        r.bursts
            .iter()
            .map(|b| (b.jumps, b.overshoot_lobes > 0))
            .collect::<Vec<_>>(),
    )
}

fn sweep_200() -> Vec<Params> {
    (0..200)
        .map(|i| paper(0.1 * 300f64.powf(f64::from(i) / 199.0)))
        .collect()
}

#[test]
fn verdicts_do_not_depend_on_the_tolerance() {
    // rtol = atol from 1e-6 to 1e-12, over the reference cases and a 200-point γ sweep
    let sets: Vec<Params> = reference_cases()
        .into_iter()
        .map(|c| c.1)
        .chain(sweep_200())
        .collect();
    for p in &sets {
        let base = key(p, &BurstOptions::default());
        for tol in [1e-6, 1e-8, 1e-12] {
            let mut o = BurstOptions::default();
            o.tol.rtol = tol;
            o.tol.atol = tol;
            assert_eq!(key(p, &o), base, "{p:?} at tol {tol}");
        }
    }
}

/// The lag ratio's denominator, the largest first-order lag, comes from the curve, not from the
/// steps: on the 200-point γ sweep the ratio at rtol = atol 1e-8 and 1e-12 agrees to what sampling
/// the lag itself at the step points allows (the lag is slow where the state settles: a step h
/// misses its peak by about (ωh)²/8 of it), and with a fold in range it is 0, the first-order lag
/// being unbounded.
#[test]
fn the_lag_ratio_does_not_depend_on_the_step_grid() {
    for p in sweep_200() {
        let ratio = |tol: f64| {
            let mut o = BurstOptions::default();
            o.tol.rtol = tol;
            o.tol.atol = tol;
            verdict_of(&p, &o).1.measures.lag_ratio
        };
        let (coarse, fine) = (ratio(1e-8), ratio(1e-12));
        if hdgear::fast::settled_branch(&p).must_jump {
            assert_eq!((coarse, fine), (0.0, 0.0), "{p:?}");
        } else {
            assert!(
                (coarse - fine).abs() <= 1e-3 * fine,
                "{p:?}: {coarse} vs {fine}"
            );
        }
    }
}

#[test]
fn spike_counts_do_not_depend_on_the_tolerance() {
    let spikes = |p: &Params, tol: f64| {
        let mut o = BurstOptions::default();
        o.tol.rtol = tol;
        o.tol.atol = tol;
        response(p, &o)
            .unwrap()
            .bursts
            .iter()
            .map(|b| b.spikes)
            .collect::<Vec<_>>()
    };
    // from 1e-7: at 1e-6 the noise floor (3e-4) reaches the ringing swings near γ ≈ 2
    for p in sweep_200().iter().step_by(4) {
        let base = spikes(p, 1e-10);
        for tol in [1e-7, 1e-12] {
            assert_eq!(spikes(p, tol), base, "{p:?} at tol {tol}");
        }
    }
}

#[test]
fn floors_and_gap_do_not_change_verdicts() {
    // each floor ×10 and ÷10; the gap ×10 and ÷3 (÷10 would cut the ringing apart: its
    // half-period is 2–6 time units where these cases ring)
    let d = BurstOptions::default();
    let variants = [
        BurstOptions {
            swing_floor: 1e-2,
            ..d
        },
        BurstOptions {
            swing_floor: 1e-4,
            ..d
        },
        BurstOptions {
            overshoot_floor: 1e-3,
            ..d
        },
        BurstOptions {
            overshoot_floor: 1e-5,
            ..d
        },
        BurstOptions {
            gap_decay_times: 100.0,
            ..d
        },
        BurstOptions {
            gap_decay_times: 10.0 / 3.0,
            ..d
        },
    ];
    let verdict = |p: &Params, o: &BurstOptions| {
        let (c, r) = verdict_of(p, o);
        (c.verdict, c.mode, r.rates.bursts_per_period)
    };
    for (id, p, _) in reference_cases() {
        let base = verdict(&p, &d);
        for o in &variants {
            assert_eq!(verdict(&p, o), base, "{id} with {o:?}");
        }
    }
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
        assert_eq!(r.rates.bursts_per_period, Some(2.0), "discard {discard}");
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
    // γ = 10: no signature at ω = 0.01, so "normal", where the study says "transitional"
    let agrees: Vec<bool> = t.gamma_table.iter().map(|r| r.agrees).collect();
    assert_eq!(agrees, [true, false, true, true]);
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
    assert_eq!(verdict("gamma"), hdgear::table::ClaimVerdict::Agrees);
    assert_eq!(verdict("delta"), hdgear::table::ClaimVerdict::Agrees);
    assert_eq!(verdict("omega"), hdgear::table::ClaimVerdict::Agrees);
    assert_eq!(verdict("eps"), hdgear::table::ClaimVerdict::Agrees);
    // measured: doubling alpha lowers the burst amplitude, against the study's claim
    assert_eq!(verdict("alpha"), hdgear::table::ClaimVerdict::Contradicts);
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
            &(0..g.len()).collect::<Vec<_>>(),
            threads,
            |r| rows.push(r),
        )
        .unwrap();
        runs.push(rows);
    }
    assert_eq!(runs[0].len(), 12);
    // bit-identical (compare the serialised rows: NaN-safe)
    let ser = |v: &Vec<hdgear::sweep::SweepRow>| serde_json::to_string(v).unwrap();
    assert_eq!(ser(&runs[0]), ser(&runs[1]));
    // grid order: first axis fastest
    assert_eq!(runs[0][1].params.gamma, g.point(1).gamma);
    assert_eq!(runs[0][6].params.delta, 16.0);
    assert!(runs[0].iter().all(|r| r.error.is_empty()));
}

/// Rows come in the order of the points asked for, whatever the threads and however the chunks
/// finish: what lets `hdgear sweep` stream them into its output instead of holding them. Here
/// 80 points (five chunks of 16, one worker ahead of the other) asked for odd indices first,
/// then even ones, backwards.
#[test]
fn sweep_rows_come_in_the_order_asked_for() {
    let g = Grid::new(
        Params::default(),
        vec![
            Axis::parse("gamma=0.05:20:10:log").unwrap(),
            Axis::parse("delta=8:16:8").unwrap(),
        ],
    )
    .unwrap();
    let todo: Vec<usize> = (0..g.len())
        .filter(|i| i % 2 == 1)
        .chain((0..g.len()).rev().filter(|i| i % 2 == 0))
        .collect();
    for threads in [1, 2] {
        let mut got = Vec::new();
        hdgear::sweep::run(&g, &BurstOptions::default(), &todo, threads, |r| {
            got.push(r.index);
        })
        .unwrap();
        assert_eq!(got, todo, "{threads} threads");
    }
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

#[test]
fn the_verdict_on_the_periodic_orbit_is_the_verdict_after_the_transient() {
    // the periodic orbit has no transient: measuring from its start with nothing discarded must
    // give what the default run gives after discarding one slow period, on the twenty reference
    // cases (ω from 1e-3 to 0.05) and the study's four γ
    use hdgear::periodic::{PeriodicOptions, burst_verdict, shoot};
    let mut cases = reference_cases();
    for g in [30.0, 10.0, 1.0, 0.1] {
        cases.push((
            format!("study γ = {g}"),
            Params {
                gamma: g,
                ..Params::default()
            },
            serde_json::Value::Null,
        ));
    }
    for (id, p, _) in cases {
        let o = BurstOptions::default();
        let after_transient = verdict_of(&p, &o).0;
        let orbit = shoot(&p, 1, &PeriodicOptions::default()).unwrap();
        let on_orbit = burst_verdict(&orbit, &o).unwrap();
        assert_eq!(
            on_orbit, after_transient,
            "{id}: orbit {on_orbit:?}, transient {after_transient:?}"
        );
    }
}

/// The batch path (sixteen points in lock-step, each step's polynomial scanned as it comes) gives
/// the scalar path's verdicts, counts and spikes on the 20 reference cases, the 200-point γ sweep
/// and an ω scan it was not built from, at the default tolerance and the sweeps' 1e-8; its
/// measures agree to 1e-6 relative (both runs carry errors near the tolerance, and the peak and
/// tracking error are located on interpolants, so 1e-6 is a hundred times the 1e-8 tolerance).
#[test]
fn batched_responses_equal_one_by_one_responses() {
    let omega_scan = (0..48).map(|i| Params {
        omega: 1e-3 * 1000f64.powf(f64::from(i) / 47.0),
        gamma: [0.1, 1.0, 30.0][i as usize % 3],
        ..Params::default()
    });
    let sets: Vec<Params> = reference_cases()
        .into_iter()
        .map(|c| c.1)
        .chain(sweep_200())
        .chain(omega_scan)
        .collect();
    for tol in [1e-10, hdgear::burst::CLASSIFICATION_TOL] {
        let mut o = BurstOptions::default();
        o.tol.rtol = tol;
        o.tol.atol = tol;
        let batch = hdgear::burst::responses(&sets, &o);
        assert_eq!(batch.len(), sets.len());
        for (p, b) in sets.iter().zip(batch) {
            let (b, one) = (b.unwrap(), response(p, &o).unwrap());
            let (cb, co) = (classify(p, &b), classify(p, &one));
            assert_eq!(cb, co, "{p:?} at tol {tol}");
            assert_eq!(
                b.rates.bursts_per_period, one.rates.bursts_per_period,
                "{p:?}"
            );
            let per_burst = |r: &hdgear::burst::Response| {
                r.bursts
                    .iter()
                    .map(|b| (b.spikes, b.jumps, b.overshoot_lobes > 0))
                    .collect::<Vec<_>>()
            };
            assert_eq!(per_burst(&b), per_burst(&one), "{p:?} at tol {tol}");
            for (x, y) in [
                (b.rates.peak_abs_xdot, one.rates.peak_abs_xdot),
                (b.rates.max_tracking_error, one.rates.max_tracking_error),
            ] {
                assert!((x - y).abs() <= 1e-6 * y.abs(), "{p:?}: {x} vs {y}");
            }
        }
    }
}

/// A point's batched result does not depend on the points beside it, even when one of them
/// fails: the same point alone, among others, and next to a point whose run is too long.
#[test]
fn a_batched_point_does_not_depend_on_its_neighbours() {
    let o = BurstOptions::default();
    let p = paper(1.0);
    let alone = hdgear::burst::responses(&[p], &o).remove(0).unwrap();
    let crowd: Vec<Params> = (0..20).map(|i| paper(0.1 + f64::from(i))).collect();
    let mut mixed = crowd.clone();
    mixed[3] = p;
    mixed[4] = Params { omega: 1e-9, ..p }; // too long a run: its own error
    let among = hdgear::burst::responses(&mixed, &o);
    assert_eq!(among[3].as_ref().unwrap(), &alone);
    assert!(
        matches!(among[4], Err(hdgear::Error::RunTooLong { .. })),
        "{:?}",
        among[4]
    );
    assert!(among.iter().enumerate().all(|(i, r)| i == 4 || r.is_ok()));
}

#[test]
fn a_single_fold_in_range_means_one_transient_jump_not_bursting() {
    // one fold inside a ∈ [−1, 1]: a branch spans the whole range, and the state that is on it
    // (or jumps onto it once, in the transient) stays there
    let p = crate::common::SINGLE_FOLD;
    let branch = hdgear::fast::settled_branch(&p);
    assert_eq!((branch.folds_in_range, branch.must_jump), (1, false));
    let pr = predict(&p);
    assert!(!pr.fold_in_range && !pr.bursting, "{pr:?}");
    let (c, r) = verdict_of(&p, &BurstOptions::default());
    assert!(!c.bursting && !r.signatures.jump, "{c:?}");
    // the upper branch starts at a(x+) inside the range; the lower one ends at a(x−) above it,
    // so it spans the range and the state, started on it, never leaves it
    let (xm, xp) = hdgear::fast::fold_abscissae(&p).unwrap();
    assert!(p.a_at(xm) > 1.0 && p.a_at(xp).abs() <= 1.0);
}

#[test]
fn single_fold_sets_far_from_the_study_never_jump_after_the_transient() {
    // sets built to have exactly one fold in a ∈ [−1, 1], lower- or upper-branch fold, over
    // decades of α and ω (none of them used to write the rule): (α, γ·3α, ε, a(x−), a(x+), ω)
    let cases = [
        (0.4, 0.2, 0.1, 2.1, -0.2, 2e-3),
        (3.0, 0.6, 0.7, 1.3, 0.5, 0.05),
        (25.0, 0.3, 0.04, 1.2, -0.8, 0.01),
        (1.0, 0.8, 0.5, 0.3, -2.2, 0.2),
        (8.0, 0.1, 0.9, -0.7, -1.5, 5e-3),
        (0.7, 0.5, 0.3, 0.8, -2.9, 0.03),
    ];
    for (alpha, f, eps, am, ap, omega) in cases {
        let gamma = f / (3.0 * alpha);
        let s = (1.0f64 - f).sqrt();
        let (xm, xp) = (gamma / (1.0 + s), (1.0 + s) / (3.0 * alpha));
        let g = |x: f64| alpha * x * x * x - x * x + gamma * (x - eps);
        // place the folds at a(x−) = am, a(x+) = ap: g(x) = μ + δa at both
        let delta = (g(xm) - g(xp)) / (am - ap);
        let p = Params {
            alpha,
            gamma,
            eps,
            mu: g(xm) - delta * am,
            delta,
            omega,
        };
        let branch = hdgear::fast::settled_branch(&p);
        assert_eq!(
            (branch.folds_in_range, branch.must_jump),
            (1, false),
            "{p:?}"
        );
        let pr = predict(&p);
        let (c, r) = verdict_of(&p, &BurstOptions::default());
        assert!(!r.signatures.jump, "{p:?}: {c:?}");
        assert_eq!(pr.bursting, c.bursting, "{p:?}: {pr:?} {c:?}");
    }
}

/// Near the cusp the prediction judges the node passage on the normal form, and its ω boundary
/// lands within 15 % of the simulated one (the acceptance). Measured over 124 such sets
/// (`examples/cusp_survey.rs`): predicted/simulated 0.92–1.09; κ alone gave 1.5–2.7 there.
#[test]
fn near_the_cusp_the_normal_form_predicts_the_simulated_boundary() {
    let mut checked = 0;
    // none of these sets was used to build anything: the threshold is solved from the normal
    // form alone
    for p in crate::common::cusp_sets::near_cusp_sets(12, 2026, (0.002, 0.2), 0.7) {
        let pr = predict(&p);
        let cusp = pr.cusp.expect("a passage through a node part");
        assert!((cusp.gprime_min - (p.gamma - p.critical_gamma())).abs() < 1e-12);
        let b = hdgear::burst::boundaries(&p, &BurstOptions::default()).unwrap();
        let Some(sw) = b.simulated_omega else {
            // the boundary lies beyond the fast-slow domain's edge: nothing to compare
            assert!(
                b.predicted_omega > hdgear::burst::fast_slow_omega_max(&p),
                "{p:?}"
            );
            continue;
        };
        let ratio = b.predicted_omega / sw;
        assert!(
            (0.85..1.15).contains(&ratio),
            "{p:?}: predicted/simulated ω {ratio}"
        );
        // close to the cusp the κ criterion alone puts it far higher (further out, up to
        // g'_min = 1/4, the two agree and the lower one is taken)
        let kappa_boundary = p.omega * pr.threshold / pr.forcing_rate;
        if cusp.gprime_min < 0.05 {
            assert!(kappa_boundary > 1.3 * b.predicted_omega, "{pr:?}");
        }
        checked += 1;
    }
    assert!(checked >= 9, "{checked}");
    // a curve that is a focus all along has no passage
    let pr = predict(&Params {
        gamma: 1.0,
        ..Params::default()
    });
    assert_eq!((pr.node_min_gprime, pr.cusp), (None, None));
}

/// The normal form's threshold does not hang on its numerical choices: the swing floor a decade
/// either way, the passage started and ended further out, the table against direct solves
/// between its nodes.
#[test]
fn the_cusp_threshold_does_not_depend_on_its_numerical_choices() {
    use hdgear::fast::{
        PASSAGE_GPRIME, SWING_FRACTION, TABLE_STEP, ramp_threshold, ramp_threshold_at,
    };
    for g in [0.0, 0.0125, 0.05, 0.1, 0.2] {
        let base = ramp_threshold_at(g, SWING_FRACTION, PASSAGE_GPRIME).unwrap();
        // ringing's extra extrema appear in pairs whose swing grows from zero: the floor
        // moves the threshold by little (measured 0.3–1.9 %)
        for f in [SWING_FRACTION / 10.0, SWING_FRACTION * 10.0] {
            let t = ramp_threshold_at(g, f, PASSAGE_GPRIME).unwrap();
            assert!(
                (t / base - 1.0).abs() < 0.025,
                "g'_min {g}, floor {f}: {t} vs {base}"
            );
        }
        for e in [4.0 * PASSAGE_GPRIME, 16.0 * PASSAGE_GPRIME] {
            let t = ramp_threshold_at(g, SWING_FRACTION, e).unwrap();
            assert!(
                (t / base - 1.0).abs() < 1e-3,
                "g'_min {g}, edge {e}: {t} vs {base}"
            );
        }
        let mid = g + 0.5 * TABLE_STEP;
        let direct = ramp_threshold_at(mid, SWING_FRACTION, PASSAGE_GPRIME).unwrap();
        let table = ramp_threshold(mid).unwrap();
        assert!(
            (table / direct - 1.0).abs() < 2e-3,
            "{mid}: {table} vs {direct}"
        );
    }
    assert_eq!(ramp_threshold(-0.01), None);
    assert_eq!(ramp_threshold(0.26), None);
}
