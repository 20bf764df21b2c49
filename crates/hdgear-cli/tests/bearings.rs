//! Friction at the bearings of the two-inertia drive on the command line: `hdgear physical
//! --simulate` with `--output-bearing`, `--input-bearing` and a scenario's `[bearings]` tables.

use crate::common::{fails_with, json_of};

/// Friction at the bearings reaches the two-inertia run from the flags and from a scenario's
/// `[bearings]` tables alike (the physics is the library's `tests/bearings.rs`); a vanishing law
/// is the drive without one; refusals name the user's law, key or table.
#[test]
fn physical_bearing_friction_from_flags_and_scenario() {
    let run = |extra: &[&str]| {
        let mut args = vec!["physical", "--simulate", "--t-end", "0.3", "--summary"];
        args.extend_from_slice(extra);
        json_of(&args)
    };
    let output = "stribeck:fc=0.8,fs=1.2,vst=0.05,cv=0.01,vr=1e-3";
    let input = "friction:fc=0.02,vs=0.01";
    let flags = run(&["--output-bearing", output, "--input-bearing", input]);
    let dir = tempfile::tempdir().unwrap();
    let toml = dir.path().join("bearings.toml");
    std::fs::write(
        &toml,
        "[physical]\n\
         [bearings.output.stribeck]\nfc = 0.8\nfs = 1.2\nvst = 0.05\ncv = 0.01\nvr = 1e-3\n\
         [bearings.input.friction]\nfc = 0.02\nvs = 0.01\n",
    )
    .unwrap();
    let file = run(&["--config", toml.to_str().unwrap()]);
    assert_eq!(flags["final"], file["final"]);
    assert_eq!(flags["bearings"], file["bearings"]);
    // the laws as given, in SI units
    let text = flags["bearings"].to_string();
    for needle in ["stribeck", "0.8", "1.2", "0.001", "friction", "0.02"] {
        assert!(text.contains(needle), "{needle} in {text}");
    }
    // the friction changes the run; a law of no torque does not
    let none = run(&[]);
    assert!(none["bearings"]["output"].is_null() && none["bearings"]["input"].is_null());
    let moved = |a: &serde_json::Value, b: &serde_json::Value| {
        (a["final"]["theta_out_dot"].as_f64().unwrap()
            - b["final"]["theta_out_dot"].as_f64().unwrap())
        .abs()
    };
    assert!(moved(&flags, &none) > 1e-6, "{flags} {none}");
    let idle = run(&["--output-bearing", "friction:fc=0,vs=1e-3"]);
    assert_eq!(idle["final"], none["final"]);
    // a flag replaces its side of the scenario's table
    let replaced = run(&[
        "--config",
        toml.to_str().unwrap(),
        "--input-bearing",
        "friction:fc=0,vs=0.01",
    ]);
    let output_only = run(&["--output-bearing", output]);
    assert_eq!(replaced["final"], output_only["final"]);
}

/// A bearing law that is not one, misses a key, has a bad number or leaves its domain, a law
/// outside `--simulate`, and a scenario table that misses a key or holds two laws are refused,
/// naming what the user wrote.
#[test]
fn physical_bearing_friction_refusals_name_the_law() {
    let input = "friction:fc=0.02,vs=0.01";
    let dir = tempfile::tempdir().unwrap();
    let toml = dir.path().join("bearings.toml");
    fails_with(&briefly(&["--output-bearing", "coulomb:fc=1"]), "coulomb");
    fails_with(
        &briefly(&["--output-bearing", "friction:fc=0.8"]),
        "vs missing",
    );
    fails_with(
        &briefly(&["--input-bearing", "friction:fc=x,vs=1"]),
        "friction:fc=x,vs=1",
    );
    fails_with(
        &briefly(&["--input-bearing", "friction:fc=-1,vs=1"]),
        "--input-bearing",
    );
    fails_with(&["physical", "--output-bearing", input], "only --simulate");
    // scenario tables: one key missing, two laws on one side
    for (table, needle) in [
        (
            "[bearings.output.friction]\nfc = 0.8\n",
            "[bearings.output.friction]",
        ),
        (
            "[bearings.input.friction]\nfc = 0.8\nvs = 1\n[bearings.input.stribeck]\nfc = 0.8\n",
            "holds one law",
        ),
    ] {
        std::fs::write(&toml, table).unwrap();
        fails_with(&briefly(&["--config", toml.to_str().unwrap()]), needle);
    }
}

/// Friction across the compliance reaches the two-inertia run from `--twist-friction` in SI
/// units (the physics against the reduced model is the library's `tests/physical.rs`): it is
/// recorded as given, it slows the twist's rate, a law of no torque is the drive without one,
/// and refusals name the user's law.
#[test]
fn physical_twist_friction_from_the_flag() {
    let run = |extra: &[&str]| {
        let mut args = vec!["physical", "--simulate", "--t-end", "0.3", "--summary"];
        args.extend_from_slice(extra);
        json_of(&args)
    };
    let none = run(&[]);
    assert!(none["twist_friction"].is_null());
    let law = "stribeck:fc=0.8,fs=1.2,vst=0.05,cv=0.01,vr=1e-3";
    let with = run(&["--twist-friction", law]);
    let text = with["twist_friction"].to_string();
    for needle in ["stribeck", "0.8", "1.2", "0.05", "0.01", "0.001"] {
        assert!(text.contains(needle), "{needle} in {text}");
    }
    let twist = |v: &serde_json::Value| v["final"]["theta"].as_f64().unwrap();
    assert!(
        (twist(&with) - twist(&none)).abs() > 1e-6 * twist(&none).abs(),
        "{with} against {none}"
    );
    let idle = run(&["--twist-friction", "friction:fc=0,vs=1e-3"]);
    // to the tolerance: the law's step limit may place the steps differently
    assert!((twist(&idle) - twist(&none)).abs() <= 1e-7 * twist(&none).abs());
    fails_with(
        &briefly(&["--twist-friction", "coulomb:fc=1"]),
        "invalid friction across the compliance 'twist: coulomb'",
    );
    fails_with(
        &briefly(&["--twist-friction", "friction:fc=0.8"]),
        "vs missing",
    );
    fails_with(
        &briefly(&["--twist-friction", "friction:fc=x,vs=1"]),
        "friction:fc=x,vs=1",
    );
    fails_with(
        &["physical", "--twist-friction", "friction:fc=0.8,vs=1e-3"],
        "only --simulate",
    );
}

/// A short `physical --simulate` run's arguments with `extra` flags.
fn briefly<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    [
        &["physical", "--simulate", "--t-end", "0.1", "--summary"][..],
        extra,
    ]
    .concat()
}
