//! `hdgear control`: the laws tuned side by side (text and JSON agree), a law at a given gain,
//! and bad requests refused with the value named.

use crate::common::{fails_with, json_of, stdout_of};

/// Each law's tuned gain removes the bursts and the one below it does not; the JSON holds the
/// numbers the text prints; virtual stiffness's least gain is where γ + k_p crosses the study's
/// boundary (about 2.11 at γ = 0.1, the library test holds it to an independent bisection).
#[test]
fn control_tunes_each_law_to_its_least_gain() {
    let doc = json_of(&["control", "--json", "--rel-tol", "1e-2"]);
    let tunings = doc["tunings"].as_array().unwrap();
    let kinds: Vec<&str> = tunings.iter().map(|t| t["law"].as_str().unwrap()).collect();
    assert_eq!(kinds, hdgear::control::DEFAULT_LAWS);
    for t in tunings {
        assert_eq!(t["tuned"]["verdict"], "no-bursts", "{t}");
        assert_ne!(t["below"]["verdict"], "no-bursts", "{t}");
        let (lo, hi) = (
            t["below"]["gain"].as_f64().unwrap(),
            t["tuned"]["gain"].as_f64().unwrap(),
        );
        assert!(hi > lo && hi / lo - 1.0 <= 1e-2, "{lo} {hi}");
    }
    let kp = tunings[0]["tuned"]["gain"].as_f64().unwrap();
    assert!((kp - 2.11).abs() < 0.03, "{kp}");
    let rho = doc["feedforward"]["residual_limit"].as_f64().unwrap();
    assert!(rho > 0.0 && rho < 0.1, "{rho}");
    let text = stdout_of(&["control", "--rel-tol", "1e-2"]);
    assert!(text.contains("open loop: overshoot"), "{text}");
    assert!(text.contains("feed-forward of the load"), "{text}");
    let row = text.lines().find(|l| l.starts_with("vstiffness")).unwrap();
    assert!(row.contains(&format!("{kp:.5}")), "{row}");
}

/// `--gain` assesses instead of tuning; the washout's ω_w is taken from `--ww`.
#[test]
fn control_assesses_a_law_at_a_given_gain() {
    let doc = json_of(&[
        "control", "washout", "--gain", "10", "--ww", "0.03", "--json",
    ]);
    let a = &doc["assessments"][0];
    assert_eq!(a["term"]["kind"], "washout");
    assert_eq!(a["term"]["values"], serde_json::json!([10.0, 0.03]));
    assert_eq!(a["verdict"], "no-bursts");
    let ratio = a["peak_xdot"].as_f64().unwrap() / a["open_peak_xdot"].as_f64().unwrap();
    assert!(ratio < 0.2, "{ratio}");
    assert!(doc.get("tunings").is_none());
}

#[test]
fn control_bad_input_exits_2() {
    fails_with(&["control", "pid"], "'pid'");
    fails_with(&["control", "vstiffness", "--gain", "-1"], "-1");
    // the gain is refused as the option the user typed, for the law whose domain it leaves
    fails_with(&["control", "scheduled", "--gain", "0"], "gain = 0");
    fails_with(&["control", "washout", "--ww", "0"], "ww");
    fails_with(&["control", "vdamping", "--ww", "0.3"], "'0.3'");
    fails_with(&["control", "--gamma", "30"], "does not burst");
    fails_with(&["control", "--rel-tol", "2"], "rel_tol");
    fails_with(
        &["control", "--spread", "1.5"],
        "spread = 1.5: must lie in [0, 1) (0: no robustness check)",
    );
    fails_with(
        &["control", "--card", "SHG-20-50", "--gamma", "1"],
        "--gamma",
    );
    fails_with(&["control", "--card", "NOPE-1"], "NOPE-1");
    // a catalogue drive with its own assumptions has no folds: nothing to control
    fails_with(&["control", "--card", "SHG-20-50"], "does not burst");
}

/// On a drive: each row's torque in N m is the reduced effort times L·N²·J_in/T² (from the
/// printed reduction's scales), the motor's is that over N, and the robustness search ran.
#[test]
fn control_on_a_drive_reads_the_effort_in_newton_metres() {
    let doc = json_of(&[
        "physical",
        "--k1",
        "2000",
        "--t-am",
        "112",
        "--control",
        "--json",
        "--discard",
        "1",
    ]);
    let r = &doc["reduction"];
    let d = &doc["drive"];
    let f = |v: &serde_json::Value| v.as_f64().unwrap();
    let (n, j_in) = (f(&d["ratio"]), f(&d["j_in"]));
    let scale = f(&r["length_scale"]) * n * n * j_in / f(&r["time_scale"]).powi(2);
    assert!((f(&doc["torque_scale"]) / scale - 1.0).abs() < 1e-12);
    let tunings = doc["comparison"]["tunings"].as_array().unwrap();
    let efforts = doc["efforts"].as_array().unwrap();
    let laws = hdgear::control::DEFAULT_LAWS.len();
    assert_eq!(efforts.len(), laws);
    assert_eq!(
        doc["comparison"]["robustness"].as_array().unwrap().len(),
        laws
    );
    for (t, e) in tunings.iter().zip(efforts) {
        let out = scale * f(&t["tuned"]["effort_peak"]);
        assert!((f(&e["output_peak"]) / out - 1.0).abs() < 1e-12, "{e}");
        assert!((f(&e["motor_peak"]) * n / out - 1.0).abs() < 1e-12, "{e}");
        // the report's drive's card has no ratings: no fractions
        assert!(e["of_repeated_peak"].is_null());
    }
    let text = stdout_of(&["physical", "--k1", "2000", "--t-am", "112", "--control"]);
    assert!(text.contains("no ratings to check"), "{text}");
}
