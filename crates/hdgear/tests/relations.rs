//! Rules between a term's parameters ([`hdgear::model::terms::Relation`]): a static friction
//! below its sliding level and a Bouc–Wen loop whose state escapes are refused, naming both
//! values, wherever a term is built (a term, a model parameter changed, a scenario table); the
//! Bouc–Wen rule is held to an integration of its state's equation written here and to the
//! closed forms of its loading branch.

use hdgear::Params;
use hdgear::error::Error;
use hdgear::model::Model;
use hdgear::model::terms::AnyTerm;

/// The error text of building `kind` with `values`, which must be refused.
fn refusal(kind: &str, values: &[f64]) -> String {
    match AnyTerm::new(kind, values) {
        Err(e @ Error::RelationBroken { .. }) => e.to_string(),
        other => panic!("{kind} {values:?}: expected a refusal of the rule, got {other:?}"),
    }
}

#[test]
fn static_friction_below_the_sliding_level_is_refused_by_every_friction_law() {
    // fc, fs first in each law; the rest at values each law accepts
    let laws: [(&str, &[f64]); 3] = [
        ("coulomb", &[0.3, 0.2, 0.1, 0.0]),
        ("stribeck", &[0.3, 0.2, 0.1, 0.0, 0.01]),
        ("lugre", &[0.3, 0.2, 0.1, 10.0, 1.0, 0.0]),
    ];
    for (kind, values) in laws {
        let text = refusal(kind, values);
        assert!(
            text.contains("fs = 0.2") && text.contains("fc = 0.3"),
            "{kind}: {text}"
        );
        // equal levels (no Stribeck drop) are a valid law
        let mut equal = values.to_vec();
        equal[1] = equal[0];
        AnyTerm::new(kind, &equal).unwrap();
    }
}

#[test]
fn a_model_parameter_changed_through_the_rule_is_refused() {
    let m = Model::study(&Params::default())
        .with_term(AnyTerm::new("coulomb", &[0.1, 0.2, 0.1, 0.0]).unwrap())
        .unwrap();
    let fs = m.param("fs").unwrap();
    assert!(m.with(fs, 0.1).is_ok());
    let e = m.with(fs, 0.05).unwrap_err();
    assert!(matches!(e, Error::RelationBroken { .. }), "{e}");
}

#[test]
fn a_scenario_table_with_a_static_friction_below_the_sliding_level_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.toml");
    std::fs::write(
        &path,
        "[params]\ngamma = 1.0\n[coulomb]\nfc = 0.3\nfs = 0.1\n",
    )
    .unwrap();
    let s = hdgear::scenario::Scenario::load(&path).unwrap();
    let e = s.model(&Params::default(), &path).unwrap_err().to_string();
    assert!(e.contains("fs = 0.1") && e.contains("fc = 0.3"), "{e}");
}

/// A twist rate x'(t).
type Rate = fn(f64) -> f64;

/// The largest |z| over 0 ≤ t ≤ `t_end` from z = 0 under the Bouc–Wen state's equation
/// z' = A x' − β|x'||z|ⁿ⁻¹z − γ_h x'|z|ⁿ with the twist rate x'(t) = `rate(t)`, by classical RK4
/// written here.
fn bouc_wen_peak(bw: [f64; 3], n: i32, rate: Rate, t_end: f64) -> f64 {
    let [a, beta, gamma] = bw;
    let dz = |t: f64, z: f64| {
        let v = rate(t);
        a * v - beta * v.abs() * z.abs().powi(n - 1) * z - gamma * v * z.abs().powi(n)
    };
    let h = 1e-3;
    let (mut t, mut z, mut peak) = (0.0_f64, 0.0_f64, 0.0_f64);
    while t < t_end && peak < 1e6 {
        let k1 = dz(t, z);
        let k2 = dz(t + h / 2.0, z + h / 2.0 * k1);
        let k3 = dz(t + h / 2.0, z + h / 2.0 * k2);
        let k4 = dz(t + h, z + h * k3);
        z += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        t += h;
        peak = peak.max(z.abs());
    }
    peak
}

#[test]
fn bouc_wen_is_refused_exactly_where_its_state_escapes() {
    let a = 1.0;
    // forty cycles of a unit twist x = sin t, and a steady twist x = t
    let (cyclic, steady): (Rate, Rate) = (f64::cos, |_| 1.0);
    let span = 40.0 * std::f64::consts::TAU;
    let values = |beta: f64, gamma: f64, n: i32| [0.5, 0.0, a, beta, gamma, f64::from(n)];
    for n in [1, 2] {
        // β ≥ 0 and β + γ_h > 0: |z| ≤ z* = (A/(β + γ_h))^(1/n) whatever the twist (the
        // loading branch levels off at z*, unloading only shrinks |z|); accepted
        for (beta, gamma) in [(0.5, 0.5), (0.1, 0.9), (0.0, 0.6), (0.9, -0.1)] {
            let bound = (a / (beta + gamma)).powf(1.0 / f64::from(n));
            for rate in [cyclic, steady] {
                let peak = bouc_wen_peak([a, beta, gamma], n, rate, span);
                assert!(
                    peak <= bound * (1.0 + 1e-9),
                    "n {n} β {beta} γ_h {gamma}: {peak}"
                );
            }
            AnyTerm::new("boucwen", &values(beta, gamma, n)).unwrap();
        }
        // β < 0: unloading from the loading branch's level grows |z| again, and a unit cyclic
        // twist already makes z escape; refused by β's domain
        for (beta, gamma) in [(-0.2, 0.4), (-1.0, -1.0)] {
            let peak = bouc_wen_peak([a, beta, gamma], n, cyclic, span);
            assert!(peak > 1e3, "n {n} β {beta} γ_h {gamma}: {peak}");
            let e = AnyTerm::new("boucwen", &values(beta, gamma, n)).unwrap_err();
            assert!(e.to_string().contains("betah"), "{e}");
        }
    }
    // β + γ_h = −c < 0: the loading branch is dz/dx = A + c·zⁿ. With n = 1 it is the
    // closed form (A/c)(e^{c·x} − 1), finite for every finite twist (Noël & Schoukens'
    // benchmark is such a set): accepted
    let (beta, gamma) = (0.8, -1.1);
    let c = -(beta + gamma);
    // (x = 5 is 5000 steps of the integration's 1e-3: its last step ends there to rounding)
    let x = 5.0;
    let closed = a / c * ((c * x).exp() - 1.0);
    let peak = bouc_wen_peak([a, beta, gamma], 1, steady, x - 1e-9);
    assert!((peak - closed).abs() < 1e-6 * closed, "{peak} vs {closed}");
    AnyTerm::new("boucwen", &values(beta, gamma, 1)).unwrap();
    // with n = 2 it blows up at x = π/(2√(A·c)) (z = √(A/c)·tan(√(A·c)·x)): refused, naming both
    let blow_up = std::f64::consts::FRAC_PI_2 / (a * c).sqrt();
    let peak = bouc_wen_peak([a, beta, gamma], 2, steady, 1.01 * blow_up);
    assert!(peak >= 1e6, "{peak} by x = {}", 1.01 * blow_up);
    let text = refusal("boucwen", &values(beta, gamma, 2));
    assert!(
        text.contains("betah = 0.8") && text.contains("gammah = -1.1"),
        "{text}"
    );
}
