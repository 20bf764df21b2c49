//! `hdgear model` and the scenario's term tables: the assembled model printed, simulated, and
//! refused where a command runs the study's model only.

use crate::common::{hdgear, json_of, stdout_of};
use predicates::prelude::*;

fn scenario(dir: &std::path::Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_string()
}

/// `hdgear bursts --config` on the scenario `text` (written in `dir`): its JSON output.
fn bursts_of_scenario(dir: &std::path::Path, text: &str) -> serde_json::Value {
    let f = scenario(dir, "scenario.toml", text);
    let out = dir.join("bursts.json");
    hdgear()
        .args(["bursts", "--config", &f, "--out"])
        .arg(&out)
        .assert()
        .success();
    serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap()
}

#[test]
fn model_prints_the_study_and_its_derived_facts() {
    let d = json_of(&["model", "--json"]);
    assert_eq!(
        d["equation"],
        "x'' + x' + αx³ − x² + γ(x − ε) = μ + δ sin ωτ"
    );
    let f = &d["facts"];
    assert_eq!(f["damping_at_rest"], 1.0);
    assert_eq!(f["focus_node_threshold"], 0.25);
    assert_eq!(f["decay_time"], 2.0);
    assert_eq!(f["hopf_possible"], false);
    let names: Vec<&str> = d["parameters"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["mu", "delta", "omega", "alpha", "gamma", "eps"]);
    hdgear()
        .args(["model"])
        .assert()
        .success()
        .stdout(predicate::str::contains("focus above g' = c²/4 = 0.25"));
}

#[test]
fn a_friction_table_adds_the_term_to_model_and_simulate() {
    let dir = tempfile::tempdir().unwrap();
    let f = scenario(
        dir.path(),
        "f.toml",
        "[params]\ngamma = 1\n[friction]\nfc = 0.1\nvs = 0.05\n",
    );
    let d = json_of(&["model", "--json", "--config", &f]);
    assert_eq!(d["facts"]["damping_at_rest"], 3.0);
    assert!(d["equation"].as_str().unwrap().contains("f_c·tanh(x'/v_s)"));
    // a missing key takes its default
    let g = scenario(dir.path(), "g.toml", "[friction]\nfc = 0.2\n");
    let d = json_of(&["model", "--json", "--config", &g]);
    assert_eq!(d["parameters"][7]["value"], 0.01);
    // simulate runs the assembled model; with f_c = 0 it is the study's to the tolerance
    let zero = scenario(
        dir.path(),
        "z.toml",
        "[params]\ngamma = 1\n[friction]\nfc = 0\n",
    );
    let run = |cfg: Option<&str>| {
        let mut args = vec!["simulate", "--summary", "--gamma", "1", "--t-end", "500"];
        if let Some(c) = cfg {
            args.extend(["--config", c]);
        }
        json_of(&args)
    };
    let (a, b, c) = (run(None), run(Some(&zero)), run(Some(&f)));
    assert!(a.get("model").is_none() && b["model"]["terms"][2]["kind"] == "friction");
    for key in ["x", "xdot"] {
        let (x, y) = (
            a["final"][key].as_f64().unwrap(),
            b["final"][key].as_f64().unwrap(),
        );
        assert!((x - y).abs() < 1e-8, "{key}: {x} vs {y}");
    }
    // friction lowers the largest rate
    assert!(c["max_abs_xdot"].as_f64().unwrap() < a["max_abs_xdot"].as_f64().unwrap());
}

/// A smooth-friction scenario (γ = 1, f_c = 0.1, v_s = 0.05) written in `dir`: its path.
fn friction_scenario(dir: &std::path::Path) -> String {
    scenario(
        dir,
        "f.toml",
        "[params]\ngamma = 1\n[friction]\nfc = 0.1\nvs = 0.05\n",
    )
}

#[test]
fn the_fast_subsystem_and_the_periodic_machinery_run_on_a_friction_scenario() {
    let dir = tempfile::tempdir().unwrap();
    let f = friction_scenario(dir.path());
    // analyze: the curve at the model's own damping c = 1 + f_c/v_s, and the measured response
    let d = json_of(&["analyze", "--json", "--config", &f]);
    assert_eq!(d["analysis"]["damping_at_rest"], 3.0);
    assert_eq!(d["model"]["terms"][2]["kind"], "friction");
    assert!(d["classification"]["verdict"].is_string());
    // equilibria: λ1 + λ2 = −c at every point
    let csv = stdout_of(&["equilibria", "--config", &f, "--points", "20", "--quiet"]);
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        "a,x,slope,gprime,re1,im1,re2,im2,type,branch"
    );
    for line in lines {
        let v: Vec<f64> = line
            .split(',')
            .take(8)
            .map(|t| t.parse().unwrap())
            .collect();
        assert!((v[4] + v[6] + 3.0).abs() < 1e-12, "{line}");
    }
    // periodic: the orbit and its verdict, the model in the document
    let d = json_of(&["periodic", "--json", "--config", &f]);
    assert!(d["residual"].as_f64().unwrap() < 1e-9);
    assert_eq!(d["params"]["terms"][2]["kind"], "friction");
    // continue in a term's parameter by its qualified name; frequency-response
    let d = json_of(&[
        "continue",
        "--json",
        "--config",
        &f,
        "--param",
        "friction.fc=0.1:0.3",
    ]);
    assert_eq!(d["range"]["param"], "fc");
    assert!(d["branches"][0]["points"].as_array().unwrap().len() > 2);
    let d = json_of(&[
        "frequency-response",
        "--json",
        "--config",
        &f,
        "--omega-range",
        "0.5:2",
    ]);
    assert!(d["points"].as_array().unwrap().len() > 2);
}

#[test]
fn orbit_diagram_control_and_coulomb_orbits_run_on_friction_scenarios() {
    let dir = tempfile::tempdir().unwrap();
    let f = friction_scenario(dir.path());
    // orbit-diagram: the stroboscopic section of the model against a study parameter
    let csv = dir.path().join("d.csv");
    hdgear()
        .args([
            "orbit-diagram",
            "--config",
            &f,
            "--param",
            "omega=1:2:3",
            "--out",
        ])
        .arg(&csv)
        .assert()
        .success();
    let text = std::fs::read_to_string(&csv).unwrap();
    assert!(
        text.starts_with("sweep,param,period,lyapunov,x,xdot"),
        "{text}"
    );
    assert!(text.lines().count() > 6);
    // control adds its law to the model: the friction term stays in the closed loop's document
    let d = json_of(&[
        "control",
        "vdamping",
        "--json",
        "--config",
        &f,
        "--rel-tol",
        "1e-2",
    ]);
    assert_eq!(d["params"]["terms"][2]["kind"], "friction");
    assert!(d["tunings"][0]["tuned"]["gain"].as_f64().unwrap() > 0.0);
    // a sticking Coulomb term: the analysis runs, and the orbit is shot switch by switch
    let c = scenario(
        dir.path(),
        "c.toml",
        "[params]\ngamma = 1\n[coulomb]\nfc = 0.1\nfs = 0.15\n",
    );
    hdgear()
        .args(["analyze", "--config", &c, "--no-response"])
        .assert()
        .success();
    let orbit = json_of(&["periodic", "--config", &c, "--json"]);
    let rests = orbit["rests"]["rests"]
        .as_u64()
        .expect("a sticking model counts its rests");
    // a rest forgets the speed: then the second multiplier is 0 (ln = −∞, null in JSON)
    assert_eq!(
        orbit["multipliers"][1]["log_abs"].is_null(),
        rests > 0,
        "{orbit}"
    );
    let fr = json_of(&[
        "frequency-response",
        "--config",
        &c,
        "--json",
        "--omega-range",
        "0.5:2",
    ]);
    assert!(fr["points"].as_array().unwrap().len() > 2);
    // a term with a state of its own has orbits outside the plane: refused in one line
    let l = scenario(dir.path(), "l.toml", "[params]\ngamma = 1\n[lugre]\n");
    hdgear()
        .args(["periodic", "--config", &l])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("its lugre term's s"));
}

#[test]
fn term_tables_are_refused_where_they_would_be_ignored_and_bad_ones_named() {
    let dir = tempfile::tempdir().unwrap();
    let f = scenario(dir.path(), "f.toml", "[friction]\nfc = 0.1\n");
    for (args, needle) in [
        (
            vec!["bifurcation", "--config", &f, "--gamma-min", "0.01"],
            "[friction] table is a term of the model",
        ),
        (
            vec!["physical", "--config", &f],
            "[friction] table is a term of the dimensionless model",
        ),
    ] {
        hdgear()
            .args(&args)
            .assert()
            .code(2)
            .stderr(predicate::str::contains(needle));
    }
    // the tables a scenario knows: its own two, then every term kind beyond the study's
    let kinds = hdgear::model::terms::AnyTerm::KINDS
        .iter()
        .map(|k| k.0)
        .filter(|k| hdgear::model::Model::is_extra_kind(k));
    let known: Vec<&str> = ["params", "physical"].into_iter().chain(kinds).collect();
    let unknown = format!("unknown table [frction] (known: {})", known.join(", "));
    for (text, needle) in [
        ("[frction]\nfc = 1\n", unknown.as_str()),
        (
            "[friction]\nv = 1\n",
            "unknown key v in [friction] (known: fc, vs)",
        ),
        ("[friction]\nfc = \"x\"\n", "[friction] fc must be a number"),
        ("[friction]\nfc = -1\n", "fc = -1:"),
        ("[stiffness]\nalpha = 1\n", "unknown table [stiffness]"),
        ("friction = 3\n", "[friction] must be a table"),
    ] {
        let s = scenario(dir.path(), "s.toml", text);
        hdgear()
            .args(["model", "--config", &s])
            .assert()
            .code(2)
            .stderr(predicate::str::contains(needle));
    }
}

#[test]
fn the_trajectory_has_a_column_per_internal_state() {
    let dir = tempfile::tempdir().unwrap();
    let f = scenario(
        dir.path(),
        "s.toml",
        "[params]\ngamma = 1\n[lugre]\n[dither]\ndd = 1\nwd = 20\n",
    );
    let args = ["simulate", "--quiet", "--config", &f, "--t-end", "2"];
    let text = crate::common::stdout_of(&args);
    let mut csv = csv::Reader::from_reader(text.as_bytes());
    // the columns follow the model's states, as `hdgear model` lists them
    let states = json_of(&["model", "--json", "--quiet", "--config", &f])["states"].clone();
    let own: Vec<&str> = states.as_array().unwrap()[2..]
        .iter()
        .map(|s| s.as_str().unwrap())
        .collect();
    assert_eq!(own.len(), 2);
    let header: Vec<String> = csv.headers().unwrap().iter().map(String::from).collect();
    assert_eq!(header[..4], ["t", "a", "x", "xdot"]);
    assert_eq!(header[4..], own[..]);
    let theta = header.iter().position(|c| *c == "theta").unwrap();
    let mut rows = 0;
    for rec in csv.records() {
        let rec = rec.unwrap();
        let (t, th): (f64, f64) = (rec[0].parse().unwrap(), rec[theta].parse().unwrap());
        // the dither's phase θ' = Ω_d from θ = 0: exactly Ω_d·t, to the integration's rounding
        assert!(
            (th - 20.0 * t).abs() < 1e-12 * (1.0 + th),
            "t = {t}: θ = {th}"
        );
        rows += 1;
    }
    assert_eq!(rows, 41);
    // JSON rows name the same columns
    let out = dir.path().join("s.json");
    let mut json_args = args.to_vec();
    json_args.extend(["--out", out.to_str().unwrap()]);
    crate::common::hdgear().args(&json_args).assert().success();
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let mut keys: Vec<&str> = doc["rows"][3]
        .as_object()
        .unwrap()
        .keys()
        .map(|k| k.as_str())
        .collect();
    let mut columns: Vec<&str> = header.iter().map(String::as_str).collect();
    keys.sort_unstable();
    columns.sort_unstable();
    assert_eq!(keys, columns);
}

/// `hdgear bursts` judges a scenario's model: with sticking friction its JSON `meta` gives the
/// stick-slip classification and the rests; the study's model alone has no `sticking` in it
/// (its output is what it was), and a switching model with a dither is refused with one line.
#[test]
fn bursts_judges_a_scenario_with_sticking_friction() {
    let dir = tempfile::tempdir().unwrap();
    let doc = bursts_of_scenario(
        dir.path(),
        "[params]\ngamma = 30.0\n\n[coulomb]\nfc = 0.5\nfs = 2.0\nvst = 0.001\n",
    );
    let meta = &doc["meta"];
    assert_eq!(meta["classification"]["verdict"], "stick-slip");
    assert_eq!(meta["classification"]["mechanism"], "stick-slip");
    let sticking = &meta["sticking"];
    assert!(
        sticking["sticks_per_period"].as_f64().unwrap() > 2.0,
        "{sticking}"
    );
    assert_eq!(sticking["slip_dominates"], true);

    let study = dir.path().join("study.json");
    hdgear()
        .args(["bursts", "--gamma", "30", "--out"])
        .arg(&study)
        .assert()
        .success();
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&study).unwrap()).unwrap();
    assert!(doc["meta"].get("sticking").is_none(), "{}", doc["meta"]);
    assert_eq!(doc["meta"]["classification"]["verdict"], "no-bursts");

    let d = scenario(
        dir.path(),
        "dither.toml",
        "[coulomb]\nfc = 0.5\nfs = 1.0\n\n[dither]\ndd = 1.0\nwd = 20.0\n",
    );
    hdgear()
        .args(["bursts", "--config", &d])
        .assert()
        .code(2)
        .stderr(predicate::str::contains(
            "takes neither a dither nor a delay",
        ));
}

/// `hdgear bursts` judges a scenario whose stiffness is no study cubic (a piecewise law whose
/// kink at x = 3.5 the equilibria pass at δ = 800) against the model's own equilibrium curve: a
/// verdict and bursts, where it used to refuse the model.
#[test]
fn bursts_judges_a_piecewise_stiffness_against_its_own_curve() {
    let dir = tempfile::tempdir().unwrap();
    let doc = bursts_of_scenario(
        dir.path(),
        "[params]\ndelta = 800.0\n\n[piecewise]\nk1 = 0.5\nk2 = 3.0\nk3 = 9.0\nx1 = 3.5\nw2 = 1.0\nx0 = 0.0\n",
    );
    let meta = &doc["meta"];
    assert_eq!(meta["params"]["delta"], 800.0);
    let verdict = meta["classification"]["verdict"].as_str().unwrap();
    assert!(
        ["no-bursts", "ringing", "overshoot", "fold-jump"].contains(&verdict),
        "{meta}"
    );
}

/// `model --branches` summarises the quasi-static branches (and gives every point in JSON):
/// with Coulomb friction f the drive leaves rest after a reversal once the load has moved 2f.
#[test]
fn model_prints_the_quasi_static_branches() {
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("c.toml");
    std::fs::write(&f, "[params]\ngamma = 1.0\n[coulomb]\nfc = 0.5\nfs = 0.5\n").unwrap();
    let p = f.to_str().unwrap();
    let text = stdout_of(&["model", "--config", p, "--branches"]);
    assert!(
        text.contains("loading   leaves rest at a = -0.933333"),
        "{text}"
    );
    let j = json_of(&["model", "--config", p, "--branches", "--json"]);
    let b = &j["branches"]["unloading"];
    assert!((b["breakaway"].as_f64().unwrap() - (1.0 - 1.0 / 15.0)).abs() < 1e-9);
    assert!(b["points"].as_array().unwrap().len() > 1000);
    assert!(
        json_of(&["model", "--config", p, "--json"])
            .get("branches")
            .is_none()
    );
}

/// `hdgear sweep` on a sticking Coulomb scenario over a term's parameter and the load amplitude:
/// the columns name the swept parameters, and each row's verdict is what `hdgear bursts` says
/// of the scenario with that point's values written in. Sharding such a sweep is refused in one
/// line.
#[test]
fn sweep_maps_a_coulomb_scenario_over_its_friction_level_as_bursts_sees_each_point() {
    let dir = tempfile::tempdir().unwrap();
    let text = |fs: f64, delta: f64| {
        format!("[params]\ngamma = 0.1\ndelta = {delta:?}\n[coulomb]\nfc = 0.05\nfs = {fs:?}\n")
    };
    let f = scenario(dir.path(), "c.toml", &text(0.1, 15.0));
    let out = dir.path().join("map.csv");
    let sweep = ["sweep", "--config", &f, "--param", "coulomb.fs=0.05:0.45:3"];
    hdgear()
        .args(sweep)
        .args(["--param", "delta=2:14:2", "--quiet", "--out"])
        .arg(&out)
        .assert()
        .success();
    let csv = std::fs::read_to_string(&out).unwrap();
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(head[..4], ["index", "fs", "delta", "mode"]);
    let col = |name: &str| head.iter().position(|h| *h == name).unwrap();
    let rows: Vec<Vec<String>> = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    assert_eq!(rows.len(), 6);
    for row in &rows {
        let (fs, delta): (f64, f64) = (row[1].parse().unwrap(), row[2].parse().unwrap());
        let b = bursts_of_scenario(dir.path(), &text(fs, delta));
        let c = &b["meta"]["classification"];
        assert_eq!(row[col("mode")], c["mode"].as_str().unwrap(), "{row:?}");
        assert_eq!(row[col("mechanism")], c["mechanism"].as_str().unwrap());
        let per_period = b["meta"]["bursts_per_period"].as_f64().unwrap_or(f64::NAN);
        let here: f64 = row[col("bursts_per_period")].parse().unwrap();
        assert!(here == per_period || (here.is_nan() && per_period.is_nan()));
    }
    // the Lyapunov map takes the sticking model too, its tangent carried across each switch by
    // the saltation matrix: each point's exponent is its periodic orbit's ln|m1|/T
    let ly = dir.path().join("ly.csv");
    hdgear()
        .args([
            "lyapunov-map",
            "--config",
            &f,
            "--param",
            "coulomb.fs=0.1:0.3:2",
            "--quiet",
            "--out",
        ])
        .arg(&ly)
        .assert()
        .success();
    let csv = std::fs::read_to_string(&ly).unwrap();
    let rows: Vec<Vec<&str>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    assert_eq!(rows.len(), 2);
    for row in rows {
        let (fs, lyapunov): (f64, f64) = (row[1].parse().unwrap(), row[2].parse().unwrap());
        assert_eq!((row[3], row[4]), ("1", ""), "{row:?}: a period-1 response");
        let orbit = json_of(&[
            "periodic",
            "--config",
            &scenario(dir.path(), "o.toml", &text(fs, 15.0)),
            "--json",
        ]);
        let per_time = orbit["floquet_exponents"][0].as_f64().unwrap();
        assert!(
            (lyapunov - per_time).abs() < 1e-6 * per_time.abs(),
            "fs {fs}: Benettin {lyapunov} against the orbit's {per_time}"
        );
    }
    hdgear()
        .args(sweep)
        .args(["--shard", "0/2", "--out"])
        .arg(&out)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--shard: a sweep of a model"));
}

/// `robust` spreads a friction scenario's own parameters: each row of `--out` names them, and its
/// verdict is what `hdgear bursts` says of that row's scenario; `--importance` and `--cloud`,
/// which need the study's closed-form curve, are refused in one line each, leaving no file.
#[test]
fn robust_spreads_a_friction_scenarios_parameters_as_bursts_sees_each_sample() {
    let dir = tempfile::tempdir().unwrap();
    let text =
        |gamma: f64, fc: f64| format!("[params]\ngamma = {gamma:?}\n[friction]\nfc = {fc:?}\n");
    let f = scenario(dir.path(), "f.toml", &text(2.0, 0.1));
    let out = dir.path().join("samples.csv");
    let spread = [
        "robust",
        "--config",
        &f,
        "--tolerance",
        "friction.fc=0.02..0.5",
        "--tolerance",
        "gamma=±40%",
        "--samples",
        "8",
        "--no-worst",
    ];
    let out_arg = out.to_str().unwrap();
    let args: Vec<&str> = spread
        .iter()
        .copied()
        .chain(["--json", "--out", out_arg])
        .collect();
    let page = json_of(&args);
    assert_eq!(page["probability"]["samples"], 8);
    assert_eq!(page["space"]["nominal"]["kind"], "model");
    let csv = std::fs::read_to_string(&out).unwrap();
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(head[..4], ["index", "fc", "gamma", "verdict"]);
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 8);
    for row in rows.iter().take(3) {
        let (fc, gamma): (f64, f64) = (row[1].parse().unwrap(), row[2].parse().unwrap());
        let b = bursts_of_scenario(dir.path(), &text(gamma, fc));
        assert_eq!(row[3], b["meta"]["classification"]["verdict"], "{row:?}");
    }
    for (flag, needle) in [
        ("--importance", "no curve-only prediction"),
        ("--cloud", "reduced (γ, δ) plane"),
    ] {
        let value = if flag == "--cloud" { "cloud.svg" } else { "64" };
        let partial = dir.path().join("refused.csv");
        hdgear()
            .args(spread)
            .args([flag, value, "--out"])
            .arg(&partial)
            .current_dir(dir.path())
            .assert()
            .code(2)
            .stderr(predicate::str::contains(needle));
        assert!(!partial.exists() && !dir.path().join("cloud.svg").exists());
    }
}

/// `boundary` traces a friction scenario's simulated boundary in any two of its parameters and
/// says, in one line, which kinds are not defined for a model (the study's closed forms); asking
/// for one of them is refused naming it.
#[test]
fn boundary_traces_a_friction_scenarios_simulated_boundary() {
    let dir = tempfile::tempdir().unwrap();
    let f = scenario(
        dir.path(),
        "f.toml",
        "[params]\ngamma = 2.0\n[friction]\nfc = 0.1\n",
    );
    let plane = [
        "boundary",
        "--config",
        &f,
        "--param",
        "friction.fc=0.02:0.5",
        "--param",
        "gamma=1:3",
        "--step",
        "0.1",
    ];
    let page = stdout_of(&plane);
    assert!(
        page.contains(
            "predicted, a-fold-in-range, both-folds-in-range, fast-slow-edge: not traced"
        ),
        "{page}"
    );
    assert!(page.contains("curve 0: simulated"), "{page}");
    let doc = json_of(&[&plane[..], &["--json"]].concat());
    assert_eq!(
        doc["curves"][0]["params"],
        serde_json::json!(["fc", "gamma"])
    );
    hdgear()
        .args(plane)
        .args(["--kinds", "predicted"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("'predicted'").and(predicate::str::contains("cubic")));
}
