//! A card's fitted friction law in its drive's reduced model ([`hdgear::physical::friction`]):
//! the law read and refused, its scaling, the sticking band's closed-form threshold, the study's
//! verdict without friction, the efficiency's mesh loss, and the load map's friction column.

use hdgear::Params;
use hdgear::burst::{BurstOptions, Verdict};
use hdgear::physical::card::{Card, Friction, builtin, builtin_card};
use hdgear::physical::check::{DampingChoice, MapGrid, check_card, load_map};
use hdgear::physical::design::{Judgement, judge, outcome_of};
use hdgear::physical::friction::{FrictionKnob, FrictionLaw, check, judge as judge_friction};
use hdgear::physical::{PhysicalParams, catalogue::assemble};

/// CSG-20-50 with a friction section (its source one the file has).
fn with_friction(f: Friction) -> Card {
    let mut c = builtin_card("CSG-20-50").unwrap().clone();
    c.friction = Some(Friction {
        source: "hd-torsional-csg".into(),
        ..f
    });
    c
}

fn fitted(coulomb: f64, breakaway: f64, stribeck_speed: f64) -> Friction {
    Friction {
        coulomb: Some(coulomb),
        breakaway: Some(breakaway),
        stribeck_speed: Some(stribeck_speed),
        ..Default::default()
    }
}

/// The law takes F_c, with F_s = F_c and c_v = 0 by default; a drop needs its speed, F_s < F_c
/// and a law without F_c are refused with the key and the value; measured torques alone are no
/// law (they are friction of the rigid-body rotation).
#[test]
fn a_cards_friction_law_is_read_and_refused() {
    let only_coulomb = with_friction(Friction {
        coulomb: Some(2.0),
        ..Default::default()
    });
    let l = only_coulomb.friction_law().unwrap().unwrap();
    assert_eq!((l.coulomb, l.breakaway, l.viscous), (2.0, 2.0, 0.0));
    let measured = with_friction(Friction {
        starting: Some(0.04),
        backdriving: Some(3.9),
        ..Default::default()
    });
    assert_eq!(measured.friction_law().unwrap(), None);
    let sources = &builtin().sources;
    for (f, key, value) in [
        (fitted(2.0, 1.0, 0.1), "friction.breakaway", "1"),
        (
            Friction {
                stribeck_speed: None,
                ..fitted(1.0, 2.0, 0.1)
            },
            "friction.stribeck_speed",
            "(absent)",
        ),
        (
            Friction {
                viscous: Some(0.3),
                ..Default::default()
            },
            "friction.coulomb",
            "(absent)",
        ),
    ] {
        let c = with_friction(f);
        let e = c.validate(sources).unwrap_err().to_string();
        assert!(
            e.contains(key) && e.contains(value) && e.contains("CSG-20-50"),
            "{e}"
        );
    }
}

/// The reduced law, against the scales written out here from the drive: a torque over
/// C⁴/(k2 φ J_eq²) (μ's scale), a speed over L/T = C³/(k2 φ J_eq²), c_v over C.
#[test]
fn the_reduced_friction_scales_as_the_load() {
    let c = with_friction(Friction {
        viscous: Some(0.29),
        ..fitted(1.0, 6.0, 0.13)
    });
    let d = assemble(&c, None, None).unwrap().drive;
    let l = c.friction_law().unwrap().unwrap();
    let n2ji = d.ratio * d.ratio * d.j_in;
    let j = n2ji * d.j_out / (n2ji + d.j_out);
    let (c4, kpj2) = (d.c_eq.powi(4), d.k2 * d.backlash * j * j);
    let r = l.reduced(&d, &d.reduce().unwrap());
    let rel = |a: f64, b: f64| ((a - b) / b).abs();
    assert!(rel(r.fc, 1.0 * kpj2 / c4) < 1e-12, "{}", r.fc);
    assert!(rel(r.fs, 6.0 * kpj2 / c4) < 1e-12, "{}", r.fs);
    assert!(
        rel(r.vst, 0.13 * kpj2 / d.c_eq.powi(3)) < 1e-12,
        "{}",
        r.vst
    );
    assert!(rel(r.cv, 0.29 / d.c_eq) < 1e-12, "{}", r.cv);
    // μ = T_m on the same scale
    let p = d.reduce().unwrap().params;
    assert!(rel(p.mu, d.t_m * kpj2 / c4) < 1e-12);
}

/// At rest the load's swing that twists the drive is T_am·J_eq/J_o (the rest swings the
/// rigid-body mode): from rest at the mean load the drive first slips when it exceeds F_s. With
/// a sharp Stribeck drop (2 N m over v_s ≪ the slip's speed) the first slip is a large burst, so
/// the T_am margin lands on that closed form within the search's resolution (12 halvings of a
/// factor-2 bracket in log2: 2^(2^-12) − 1 = 1.7e-4), the same for v_s = 1e-3 and 1e-4 rad/s;
/// below it the drive sticks throughout, above it the verdict is stick-slip.
#[test]
fn the_sticking_band_sets_the_load_of_the_first_slip() {
    let resolution = (2f64.powf(2f64.powi(-12)) - 1.0) * 1.01;
    for vs in [1e-3, 1e-4] {
        let c = with_friction(fitted(1.0, 3.0, vs));
        let d = assemble(&c, None, None).unwrap().drive;
        let r = check(&c, &d, &BurstOptions::default()).unwrap().unwrap();
        let now = r.outcome.unwrap();
        let q = r.load_over_breakaway.unwrap();
        assert!(q < 1.0, "{q}");
        assert_eq!(now.outcome.judgement.verdict, Some(Verdict::NoBursts));
        assert_eq!(now.sticking.unwrap().stuck_fraction, 1.0);
        let j_eq = d.reduce().unwrap().j_eq;
        let threshold = 3.0 * d.j_out / j_eq;
        let m = r
            .margins
            .iter()
            .find(|m| m.parameter == FrictionKnob::TAm)
            .unwrap();
        let b = m.boundary_value.unwrap();
        println!("v_s = {vs}: T_am boundary {b:.6} N m, F_s J_o/J_eq = {threshold:.6} N m");
        assert!(((b - threshold) / threshold).abs() < resolution, "{b}");
        assert_eq!(
            m.outside.unwrap().judgement.verdict,
            Some(Verdict::StickSlip)
        );
        assert_eq!(m.inside.unwrap().judgement.verdict, Some(Verdict::NoBursts));
    }
}

/// Asserts that the verdict with `law` is the study's on drives whose reduction is the study's
/// point at each γ of `gammas` with ε = 1/α (a physical drive reduces to α·ε = 1 only); returns
/// how many burst.
fn verdicts_are_the_studys(law: &FrictionLaw, gammas: &[f64]) -> usize {
    let opts = BurstOptions::default();
    let mut bursting = 0;
    for &gamma in gammas {
        let s = Params::default();
        let p = Params {
            gamma,
            eps: 1.0 / s.alpha,
            ..s
        };
        let d = PhysicalParams::from_dimensionless(&p, 5e-5, 0.05, 50.0, 2.0, 2.9e-4).unwrap();
        let study = judge(&d, &opts).unwrap();
        let with = judge_friction(&d, law, &opts).unwrap().unwrap();
        println!("γ = {gamma}: {}", study.label());
        assert_eq!(with.outcome.judgement, study, "γ = {gamma}");
        bursting += usize::from(study.bursting);
    }
    bursting
}

/// Without friction (F_c = F_s = 0) the verdict with the law is the study's, on drives whose
/// reduction is one of the study's four points, with ε = 1/α (two bursting, two not).
#[test]
fn without_friction_the_verdict_is_the_studys() {
    let law = FrictionLaw {
        coulomb: 0.0,
        breakaway: 0.0,
        stribeck_speed: 1.0,
        viscous: 0.0,
        mesh_loss: None,
    };
    assert_eq!(verdicts_are_the_studys(&law, &[30.0, 10.0, 1.0, 0.1]), 2);
}

/// A card's efficiency η is the mesh loss μ_m = 1/η − 1 with θ_m = 5e-5 rad of twist (alone, or
/// beside a fitted level); η outside (0, 1] is refused naming the key. At η = 1 (μ_m = 0) the
/// verdict is the study's on the four points of [`without_friction_the_verdict_is_the_studys`],
/// through the piecewise integration the loss's sign state needs; with a loss the drive's
/// reduced model carries it, and the check reports its margin.
#[test]
fn a_cards_efficiency_is_a_mesh_loss() {
    let eta = |e: f64| {
        with_friction(Friction {
            efficiency: Some(e),
            ..Default::default()
        })
    };
    let l = eta(0.8).friction_law().unwrap().unwrap();
    assert!((l.mesh_loss.unwrap() - 0.25).abs() < 1e-15);
    assert_eq!((l.coulomb, l.breakaway, l.viscous), (0.0, 0.0, 0.0));
    for bad in [0.0, 1.5, -0.2] {
        let e = eta(bad).friction_law().unwrap_err().to_string();
        assert!(e.contains("friction.efficiency"), "{e}");
    }
    let lossless = FrictionLaw {
        coulomb: 0.0,
        breakaway: 0.0,
        stribeck_speed: 1.0,
        viscous: 0.0,
        mesh_loss: Some(0.0),
    };
    assert_eq!(verdicts_are_the_studys(&lossless, &[30.0, 1.0]), 1);
    let opts = BurstOptions::default();
    let card = eta(0.8);
    let d = assemble(&card, None, None).unwrap().drive;
    let m = hdgear::physical::friction::drive_model(&d, &l).unwrap();
    let r = d.reduce().unwrap();
    let mum = m.get(m.param("mum").unwrap());
    let thetam = m.get(m.param("thetam").unwrap());
    assert!((mum - 0.25).abs() < 1e-15);
    assert!((thetam * r.length_scale - 5e-5).abs() < 1e-18);
    let c = check(&card, &d, &opts).unwrap().unwrap();
    assert!(
        c.margins
            .iter()
            .any(|m| m.parameter == FrictionKnob::MeshLoss)
    );
}

/// The load map gives, at each point, the verdict with the card's friction (the one
/// [`judge_friction`] gives there), and none for a card without a law.
#[test]
fn the_load_map_carries_the_friction_verdict() {
    let c = with_friction(fitted(1.0, 6.0, 0.13));
    let sources = &builtin().sources;
    let opts = BurstOptions::default();
    let grid = MapGrid {
        t_am_max: 33.0,
        amplitudes: 2,
        hz: (0.1, 0.3),
        frequencies: 2,
        coarse: 1,
    };
    let map_of = |c: &Card| {
        load_map(
            c,
            sources,
            DampingChoice::HysteresisLoss,
            &grid,
            &opts,
            None,
        )
        .unwrap()
    };
    let map = map_of(&c);
    let check = check_card(&c, sources, DampingChoice::HysteresisLoss, 0.0, &opts).unwrap();
    let l = c.friction_law().unwrap().unwrap();
    let mut slips = 0;
    for p in &map {
        let d = PhysicalParams {
            t_am: p.t_am,
            omega: std::f64::consts::TAU * p.frequency_hz,
            ..check.summary.drive
        };
        let j = judge_friction(&d, &l, &opts)
            .unwrap()
            .map(|o| o.outcome.judgement);
        assert_eq!(p.friction, j);
        slips += usize::from(j.unwrap().verdict == Some(Verdict::StickSlip));
    }
    // 16.5 and 33 N m swing the twist by far more than F_s = 6 N m: every point slips
    assert_eq!(slips, 4);
    let plain = builtin_card("CSG-20-50").unwrap();
    let map = map_of(plain);
    assert!(map.iter().all(|p| p.friction.is_none()));
}

/// The refined load map ([`MapGrid::coarse`]) equals the map simulated at every point, in every
/// verdict (the fit's, with friction, with the catalogue's curve), for a card whose friction
/// column changes with the amplitude and whose catalogue column changes with the frequency,
/// while simulating fewer points of each. The range 0.1–10 Hz holds the catalogue curve's edge of
/// the fast-slow domain and its turn from ringing to overshoot.
#[test]
fn the_refined_load_map_is_the_map_simulated_everywhere() {
    let c = with_friction(fitted(1.0, 3.0, 1e-3));
    let sources = &builtin().sources;
    let opts = BurstOptions::default();
    let grid = MapGrid {
        t_am_max: 25.0,
        amplitudes: 24,
        hz: (0.1, 10.0),
        frequencies: 24,
        coarse: 1,
    };
    let map = |coarse| {
        let g = MapGrid { coarse, ..grid };
        load_map(
            &c,
            sources,
            DampingChoice::HysteresisLoss,
            &g,
            &opts,
            Some(0.0),
        )
        .unwrap()
    };
    let every = map(1);
    assert!(
        every
            .iter()
            .all(|p| p.computed && p.friction_computed && p.catalogue_computed && p.held_computed)
    );
    let verdicts = |m: &[hdgear::physical::check::MapPoint]| -> Vec<_> {
        m.iter()
            .map(|p| (p.t_am, p.frequency_hz, p.judgement, p.friction, p.catalogue))
            .collect()
    };
    // both the friction and the catalogue column have a boundary in this grid
    type Key = Option<(bool, &'static str, bool)>;
    let differ = |of: fn(&hdgear::physical::check::MapPoint) -> Key| {
        every.iter().any(|p| of(p) != of(&every[0]))
    };
    fn key(j: Option<Judgement>) -> Key {
        j.map(|j| (j.bursting, j.label(), j.fast_slow_domain))
    }
    assert!(differ(|p| key(p.friction)));
    assert!(differ(|p| key(p.catalogue)));
    for coarse in [2, 4] {
        let refined = map(coarse);
        assert_eq!(verdicts(&refined), verdicts(&every), "coarse {coarse}");
        held_misses_only_narrow_regions(&refined, &every, coarse);
        let count = |of: fn(&hdgear::physical::check::MapPoint) -> bool| {
            refined.iter().filter(|p| of(p)).count()
        };
        for n in [
            count(|p| p.computed),
            count(|p| p.friction_computed),
            count(|p| p.catalogue_computed),
            count(|p| p.held_computed),
        ] {
            assert!(
                n < every.len() * 3 / 4,
                "coarse {coarse}: {n} of {}",
                every.len()
            );
        }
    }
    for coarse in [0, 65] {
        let g = MapGrid { coarse, ..grid };
        let e = load_map(&c, sources, DampingChoice::HysteresisLoss, &g, &opts, None);
        assert!(e.unwrap_err().to_string().contains("coarse"));
    }
}

/// The refined map's held column against the one simulated everywhere: equal at coarse 2; at
/// coarse 4 it misses only a region narrower than its blocks (the refinement's stated limit):
/// in this grid the held drive rings at 10 Hz for fewer amplitudes than a block holds, between
/// two lattice points that do not ring.
fn held_misses_only_narrow_regions(
    refined: &[hdgear::physical::check::MapPoint],
    every: &[hdgear::physical::check::MapPoint],
    coarse: usize,
) {
    let missed: Vec<_> = refined
        .iter()
        .zip(every)
        .filter(|(a, b)| a.held != b.held)
        .map(|(_, b)| (b.t_am, b.frequency_hz, b.held.label()))
        .collect();
    if coarse <= 2 {
        assert!(missed.is_empty(), "{missed:?}");
    } else {
        assert!(missed.len() < coarse, "{missed:?}");
        assert!(
            missed.iter().all(|m| m.1 == 10.0 && m.2 == "ringing"),
            "{missed:?}"
        );
    }
}

/// The held wave generator beside the free one ([`hdgear::physical::check::HeldInput`]): its
/// set is the held reduction's, its ζ below the free input's (J_o > J_eq), and the card's
/// starting torque holds the input exactly where N·T_st ≥ T_am (the disturbance a held input
/// passes whole to its friction), either side of that closed form by 1 %.
#[test]
fn the_starting_torque_decides_whether_the_input_is_held() {
    let sources = &builtin().sources;
    let opts = BurstOptions::default();
    let card = builtin_card("CSG-20-50").unwrap();
    let plain = check_card(card, sources, DampingChoice::HysteresisLoss, 0.0, &opts).unwrap();
    let d = plain.summary.drive;
    let held = &plain.held_input;
    assert_eq!(held.reduced, d.reduce_held().unwrap().params);
    assert!((held.zeta - d.c_eq / (2.0 * (d.k1 * d.j_out).sqrt())).abs() < 1e-15);
    assert!(held.zeta < plain.summary.zeta);
    assert_eq!(
        (held.starting_at_output, held.held_by_friction),
        (None, None)
    );
    for (factor, holds) in [(1.01, true), (0.99, false)] {
        let c = with_friction(Friction {
            starting: Some(factor * d.t_am / d.ratio),
            ..Default::default()
        });
        let r = check_card(&c, sources, DampingChoice::HysteresisLoss, 0.0, &opts).unwrap();
        let h = &r.held_input;
        assert_eq!(h.held_by_friction, Some(holds), "{factor}");
        let at_output = h.starting_at_output.unwrap();
        assert!((at_output - factor * d.t_am).abs() <= 1e-12 * d.t_am);
        // the starting torque decides which verdict applies, not the verdict itself
        assert_eq!(h.outcome, held.outcome);
    }
    // the map's held column: at each load the held reduction's own verdict
    let grid = MapGrid {
        coarse: 1,
        ..MapGrid::for_card(card, 3)
    };
    let map = load_map(
        card,
        sources,
        DampingChoice::HysteresisLoss,
        &grid,
        &opts,
        None,
    )
    .unwrap();
    for p in &map {
        let at = PhysicalParams {
            t_am: p.t_am,
            omega: std::f64::consts::TAU * p.frequency_hz,
            ..d
        };
        let held = outcome_of(&at.reduce_held().unwrap().params, &opts).unwrap();
        assert_eq!(
            p.held, held.judgement,
            "{} N m, {} Hz",
            p.t_am, p.frequency_hz
        );
    }
}
