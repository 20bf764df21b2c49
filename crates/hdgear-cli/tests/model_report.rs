//! The report of a user's model (`hdgear report --config FILE`, `--card CARD`): each section is
//! what the command that computes it prints for the same model, and a section the model does not have
//! says why, naming the term.

use crate::common::{fails_with, hdgear, json_of};
use std::path::Path;

/// Writes `text` as `name` in `dir`; its path.
fn scenario(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// Runs `hdgear report ARGS --out DIR/out` and returns the report's JSON and its HTML.
fn report(dir: &Path, args: &[&str]) -> (serde_json::Value, String) {
    let out = dir.join("out");
    hdgear()
        .arg("report")
        .args(args)
        .arg("--out")
        .arg(&out)
        .assert()
        .success();
    let json = std::fs::read_to_string(out.join("data/model-report.json")).unwrap();
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    (serde_json::from_str(&json).unwrap(), html)
}

/// Coulomb friction that sticks and slips under a load it cannot hold (the guide's stick.toml).
const STICK: &str = "[params]\ndelta = 1.0\nomega = 0.5\n[coulomb]\nfc = 0.3\nfs = 0.4\n";

#[test]
fn a_sticking_scenario_s_report_holds_what_periodic_bursts_and_frequency_response_give() {
    let dir = tempfile::tempdir().unwrap();
    let f = scenario(dir.path(), "stick.toml", STICK);
    let (r, html) = report(dir.path(), &["--config", &f]);
    // the orbit: the same start, multipliers and rests as `periodic` (the same computation on
    // the same model, so bit for bit)
    let p = json_of(&["periodic", "--config", &f, "--json"]);
    let orbit = &r["orbit"]["shown"]["orbit"];
    for key in ["start", "multipliers", "period", "rests", "peak_to_peak"] {
        assert_eq!(orbit[key], p[key], "{key}");
    }
    assert_eq!(r["orbit"]["shown"]["verdict"], p["bursts"]);
    // the fast subsystem, the verdict and the response: `analyze`'s
    let a = json_of(&["analyze", "--config", &f, "--json"]);
    assert_eq!(r["curve"]["shown"], a["analysis"]);
    assert_eq!(
        r["response"]["shown"]["classification"],
        a["classification"]
    );
    assert_eq!(r["response"]["shown"]["response"], a["response"]);
    // the frequency response: as many points as `frequency-response` writes, its folds too
    let csv = dir.path().join("fr.csv");
    hdgear()
        .args(["frequency-response", "--config", &f, "--out"])
        .arg(&csv)
        .assert()
        .success();
    let rows = std::fs::read_to_string(&csv).unwrap();
    let ours = std::fs::read_to_string(dir.path().join("out/data/frequency-response.csv")).unwrap();
    assert_eq!(ours, rows);
    // every section computed, each figure written and shown
    for id in ["model", "fast", "response", "orbit", "frequency"] {
        assert!(html.contains(&format!("<section id=\"{id}\">")), "{id}");
        assert!(
            !html.contains(&format!("data-not-applicable=\"{id}\"")),
            "{id} not computed"
        );
    }
    for fig in ["response", "fast-slow", "orbit", "frequency-response"] {
        assert!(html.contains(&format!("data-figure=\"{fig}\"")), "{fig}");
        let png = dir.path().join(format!("out/figures/{fig}.png"));
        assert!(std::fs::metadata(png).unwrap().len() > 1000, "{fig}");
    }
    // the parameter table lists the term's parameters with their values
    assert!(html.contains("data-key=\"coulomb.fs\" data-value=\"0.4\""));
    // no SI drive without a card, and it says so
    assert!(html.contains("data-not-applicable=\"drive\""));
}

#[test]
fn a_model_with_a_state_of_its_own_gets_a_report_that_says_why_it_has_no_orbit() {
    let dir = tempfile::tempdir().unwrap();
    let f = scenario(dir.path(), "l.toml", "[params]\ngamma = 1\n[lugre]\n");
    let (r, html) = report(dir.path(), &["--config", &f]);
    // the reason is the one `periodic` refuses with, word for word
    let out = hdgear().args(["periodic", "--config", &f]).assert().code(2);
    let refusal = String::from_utf8(out.get_output().stderr.clone()).unwrap();
    let why = r["orbit"]["not-applicable"].as_str().unwrap();
    assert!(why.contains("lugre"), "{why}");
    assert!(refusal.contains(why), "{refusal} / {why}");
    assert!(html.contains("data-not-applicable=\"orbit\""));
    assert!(r["frequency"]["not-applicable"].as_str().is_some());
    // the rest of the report stands: the response and its verdict, as `analyze` gives them
    let a = json_of(&["analyze", "--config", &f, "--json"]);
    assert_eq!(
        r["response"]["shown"]["classification"],
        a["classification"]
    );
    assert!(!html.contains("data-figure=\"orbit\""));
    assert!(html.contains("data-figure=\"response\""));
}

#[test]
fn a_card_s_report_carries_its_friction_and_the_design_check_physical_gives() {
    let dir = tempfile::tempdir().unwrap();
    // the built-in card: its reduced model and the same margin `physical` computes
    let (r, html) = report(dir.path(), &["--card", "CSF-20-50"]);
    let ph = json_of(&["physical", "--drive", "CSF-20-50", "--json"]);
    let check = &r["drive"]["check"];
    assert_eq!(check["gamma_margin"], ph["gamma_margin"]);
    assert_eq!(check["reduced"]["params"], ph["reduced"]);
    assert!(html.contains("<section id=\"drive\"><h2>The drive</h2><p>Card CSF-20-50"));
    // a card with a fitted friction that holds the load: the model carries the card's
    // Coulomb–Stribeck law, the orbit is the rest itself, and no branch follows from a rest
    let card = scenario(
        dir.path(),
        "joint.toml",
        "format = 1\n[sources]\ncat = { kind = \"catalogue\", cite = \"CSG-20-50\" }\n\
         rig = { kind = \"measured\", cite = \"rig\" }\n[[card]]\nname = \"JOINT-20-50\"\n\
         ratio = 50\n[card.stiffness]\nsource = \"cat\"\nt1 = 7.0\nt2 = 25.0\nk1 = 1.3e4\n\
         k2 = 1.8e4\nk3 = 2.3e4\n[card.friction]\nsource = \"rig\"\ncoulomb = 1.0\n\
         breakaway = 3.0\nstribeck_speed = 1e-3\n",
    );
    let d2 = tempfile::tempdir().unwrap();
    let (r, html) = report(d2.path(), &["--card", &card]);
    let kinds: Vec<&str> = r["model"]["terms"]
        .as_array()
        .unwrap()
        .iter()
        .map(|t| t["kind"].as_str().unwrap())
        .collect();
    assert!(kinds.contains(&"coulomb"), "{kinds:?}");
    assert_eq!(
        r["orbit"]["shown"]["orbit"]["multipliers"][0]["log_abs"],
        serde_json::json!(0.0)
    );
    assert!(html.contains("neutral (at rest all period)"));
    let why = r["frequency"]["not-applicable"].as_str().unwrap();
    assert!(why.contains("at rest all period"), "{why}");
}

#[test]
fn a_model_report_refuses_bad_sources_at_once() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let out = out.to_str().unwrap();
    fails_with(
        &["report", "--config", "no-such.toml", "--out", out],
        "no-such.toml",
    );
    fails_with(
        &["report", "--card", "NO-SUCH-CARD", "--out", out],
        "NO-SUCH-CARD",
    );
    let f = scenario(dir.path(), "bad.toml", "[coulomb]\nfc = -1\n");
    fails_with(&["report", "--config", &f, "--out", out], "fc = -1");
    // nothing was written for a refused source
    assert!(!Path::new(out).exists());
    // --card stands for the whole model: no flag beside it
    hdgear()
        .args([
            "report",
            "--card",
            "CSF-20-50",
            "--gamma",
            "1",
            "--out",
            out,
        ])
        .assert()
        .code(2);
}
