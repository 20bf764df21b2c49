//! Sweeps of a model assembled from terms: a grid over any of its parameters, by name, each row
//! the burst verdict `hdgear bursts` gives on that point's model built from its scenario text.

use hdgear::burst::{BurstOptions, classify_model, response_model};
use hdgear::model::Model;
use hdgear::scenario::Scenario;
use hdgear::sweep::{Axis, Grid, SweepRow, Values, run};
use std::path::Path;

/// A sticking Coulomb drive on the study's curve at γ = 0.1, with `fs` and `delta` as given.
fn scenario(fs: f64, delta: f64) -> String {
    format!("[params]\ngamma = 0.1\ndelta = {delta:?}\n\n[coulomb]\nfc = 0.05\nfs = {fs:?}\n")
}

/// The model a user's scenario file with that text gives (as `hdgear bursts --config` reads it).
fn model_of(text: &str) -> Model {
    let path = Path::new("point.toml");
    let s = Scenario::parse(text, path).unwrap();
    let (p, _) = hdgear::params::resolve("paper", s.params.as_ref(), &Default::default()).unwrap();
    s.model(&p, path).unwrap()
}

/// 20 distinct indices of `0..n` from a fixed linear congruential sequence, in grid order.
fn random_indices(n: usize) -> Vec<usize> {
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut picked = std::collections::BTreeSet::new();
    while picked.len() < 20 {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        picked.insert((state >> 33) as usize % n);
    }
    picked.into_iter().collect()
}

/// The 100 × 100 map of `coulomb.fs × delta` at 20 random points: each row's point is the grid's
/// (the values of the axes, by name), and its verdict, statistics and slope are those of the
/// model built afresh from that point's scenario text, measured as `hdgear bursts` measures it.
/// Bit for bit: the same model (compared) goes through the same integration.
#[test]
fn coulomb_map_rows_equal_bursts_at_twenty_random_points() {
    let base = model_of(&scenario(0.1, 15.0));
    let axes = vec![
        Axis::parse_for("coulomb.fs=0.05:0.5:100", &base).unwrap(),
        Axis::parse_for("delta=1:20:100", &base).unwrap(),
    ];
    let grid = Grid::new(base, axes).unwrap();
    assert_eq!(grid.len(), 10_000);
    let todo = random_indices(grid.len());
    let opts = BurstOptions::default();
    let mut rows: Vec<SweepRow<Values>> = Vec::new();
    run(&grid, &opts, &todo, 2, |r| rows.push(r)).unwrap();
    assert_eq!(rows.iter().map(|r| r.index).collect::<Vec<_>>(), todo);
    let p = hdgear::Params {
        gamma: 0.1,
        ..Default::default()
    };
    let mut modes = std::collections::BTreeSet::new();
    for row in &rows {
        let (fs, delta) = (
            grid.axes[0].value(row.index % 100),
            grid.axes[1].value(row.index / 100),
        );
        let named: Vec<(&str, f64)> = row.params.iter().collect();
        assert_eq!(named, [("fs", fs), ("delta", delta)]);
        let m = model_of(&scenario(fs, delta));
        assert_eq!(grid.at(row.index).unwrap(), m, "point {}", row.index);
        let r = response_model(&m, &opts).unwrap();
        let c = classify_model(&m, &r).unwrap();
        assert!(row.error.is_empty(), "{}", row.error);
        assert_eq!(row.mode, Some(c.mode), "point {}", row.index);
        assert_eq!(row.mechanism, Some(c.mechanism));
        assert_eq!(
            serde_json::to_string(&row.rates).unwrap(),
            serde_json::to_string(&r.rates).unwrap()
        );
        // friction has no static torque: the curve is the study's, no folds at γ = 0.1, so the
        // steepest |dx/da| is δ/(γ − γ_c) at x = 1/(3α)
        let slope = delta / (p.gamma - p.critical_gamma());
        assert!((row.max_slope - slope).abs() < 1e-9 * slope);
        modes.insert(format!("{:?}", c.mode));
    }
    // the map is not one verdict everywhere: the random points see more than one mode
    assert!(modes.len() >= 2, "{modes:?}");
}

/// The study's model as a [`Model`] sweeps to the same rows as the study's set: the model path
/// measures point by point what the study's batches 16 at a time, and both classify on the
/// study's curve.
#[test]
fn the_study_as_a_model_sweeps_as_the_study() {
    let p = hdgear::Params::default();
    let m = Model::study(&p);
    let study = Grid::new(p, vec![Axis::parse("delta=5:15:5").unwrap()]).unwrap();
    let model = Grid::new(m, vec![Axis::parse_for("delta=5:15:5", &m).unwrap()]).unwrap();
    let opts = BurstOptions::default();
    let todo: Vec<usize> = (0..5).collect();
    let (mut a, mut b) = (Vec::new(), Vec::new());
    run(&study, &opts, &todo, 1, |r| a.push(r)).unwrap();
    run(&model, &opts, &todo, 1, |r| b.push(r)).unwrap();
    for (x, y) in a.iter().zip(&b) {
        assert_eq!((x.mode, x.mechanism), (y.mode, y.mechanism));
        assert_eq!(y.params.iter().next(), Some(("delta", x.params.delta)));
        let (u, v) = (x.rates.peak_abs_xdot, y.rates.peak_abs_xdot);
        // the same equation through the scalar and the batch integrator: equal to their
        // tolerance (rtol 1e-10), not bit for bit
        assert!((u - v).abs() <= 1e-8 * u.abs().max(1e-12), "{u} vs {v}");
        assert!((x.max_slope - y.max_slope).abs() < 1e-9 * x.max_slope);
    }
}

/// A name the model does not have is refused, naming it and listing the model's.
#[test]
fn an_unknown_model_parameter_is_refused_by_name() {
    let base = model_of(&scenario(0.1, 15.0));
    let e = Axis::parse_for("coulomb.fx=0:1:3", &base)
        .unwrap_err()
        .to_string();
    assert!(e.contains("coulomb.fx") && e.contains("fs"), "{e}");
    // a value outside the term's domain fails before any work, naming it
    let ax = Axis::parse_for("coulomb.fs=0.01:0.2:3", &base).unwrap();
    let e = Grid::new(base, vec![ax]).unwrap_err().to_string();
    assert!(e.contains("fs"), "{e}");
}

/// A Lyapunov map over a smooth friction model's friction level: at each point Benettin's
/// exponent of the response (400 forcing periods of tangent dynamics from the default start)
/// is the largest Floquet exponent of the periodic orbit the shooting finds there, ln|μ|/T from
/// its monodromy. Benettin's estimate converges like 1/span: over 400 periods it lies within
/// 0.005 of the limit (the periodic module's own check on the study), so 0.01 holds it.
#[test]
fn a_friction_models_lyapunov_map_is_its_largest_floquet_exponent() {
    use hdgear::model::terms::AnyTerm;
    use hdgear::periodic::{DiagramOptions, PeriodicOptions, shoot};
    use hdgear::sweep::lyapunov_map;
    let p = hdgear::Params {
        gamma: 1.0,
        delta: 1.0,
        omega: 1.0,
        ..Default::default()
    };
    let m = Model::study(&p)
        .with_term(AnyTerm::new("friction", &[0.1, 0.05]).unwrap())
        .unwrap();
    let axis = Axis::parse_for("friction.fc=0.02:0.3:4", &m).unwrap();
    let grid = Grid::new(m, vec![axis]).unwrap();
    let opts = DiagramOptions {
        lyapunov: Some(400),
        ..DiagramOptions::default()
    };
    let rows = lyapunov_map(&grid, &opts, 2).unwrap();
    assert_eq!(rows.len(), 4);
    for row in &rows {
        assert!(row.error.is_empty(), "{}", row.error);
        assert_eq!(row.period, Some(1));
        let orbit = shoot(&grid.at(row.index).unwrap(), 1, &PeriodicOptions::default()).unwrap();
        let floquet = orbit.floquet_exponents[0].max(orbit.floquet_exponents[1]);
        assert!(
            (row.lyapunov - floquet).abs() < 0.01,
            "fc = {:?}: Benettin {} against Floquet {floquet}",
            row.params.iter().next(),
            row.lyapunov
        );
    }
    // more friction, more damping at rest (1 + f_c/v_s): the exponent is not one value
    assert!(rows[3].lyapunov < rows[0].lyapunov);
}

/// Two axes under one rule of a term (f_s ≥ f_c): each grid point is judged as the pair it is.
/// From the base f_s = 0.1, raising f_c to 0.2 alone would break the rule; the grid's points,
/// f_c ∈ {0.2, 0.3} with f_s ∈ {0.35, 0.5}, all keep it and are all accepted.
#[test]
fn two_axes_of_one_rule_are_set_together() {
    let base = model_of(&scenario(0.1, 15.0));
    let axes = vec![
        Axis::parse_for("coulomb.fc=0.2:0.3:2", &base).unwrap(),
        Axis::parse_for("coulomb.fs=0.35:0.5:2", &base).unwrap(),
    ];
    let grid = Grid::new(base, axes).unwrap();
    let (fc, fs) = (base.param("fc").unwrap(), base.param("fs").unwrap());
    let points: Vec<(f64, f64)> = (0..grid.len())
        .map(|i| {
            let m = grid.at(i).unwrap();
            (m.get(fc), m.get(fs))
        })
        .collect();
    assert_eq!(points, [(0.2, 0.35), (0.3, 0.35), (0.2, 0.5), (0.3, 0.5)]);
    // a point that breaks the rule is refused before any runs, naming the parameter
    let axes = vec![Axis::parse_for("coulomb.fc=0.05:0.2:2", &base).unwrap()];
    let e = Grid::new(base, axes).unwrap_err().to_string();
    assert!(e.contains("fs") || e.contains("fc"), "{e}");
}
