//! The command line: formats, row counts, summary keys, and every bad input.
//!
//! **Why one file.** What every command shares (formats, row counts, summary keys, bad input),
//! tested in one module of the test binary.

use crate::common::{fails_with, files_in, hdgear, json_of, stdout_of};
use predicates::prelude::*;

#[test]
fn simulate_csv_header_and_row_count() {
    let text = stdout_of(&["simulate", "--t-end", "10", "--dt", "0.5"]);
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,a,x,xdot"));
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 21); // t = 0, 0.5, …, 10
    assert_eq!(rows[0][0], 0.0);
    assert_eq!(rows[20][0], 10.0);
    for r in &rows {
        assert_eq!(r.len(), 4);
        assert!((r[1] - (0.01 * r[0]).sin()).abs() < 1e-15, "a = sin(ωt)");
    }
    // t_end off the grid: the final time is appended
    let text = stdout_of(&["simulate", "--t-end", "1.25", "--dt", "0.5"]);
    let ts: Vec<f64> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(ts, [0.0, 0.5, 1.0, 1.25]);
}

#[test]
fn simulate_writes_csv_and_json_files() {
    let dir = tempfile::tempdir().unwrap();
    let csv = dir.path().join("run.csv");
    let json = dir.path().join("run.json");
    for f in [&csv, &json] {
        hdgear()
            .args([
                "simulate", "--preset", "paper-g1", "--t-end", "20", "--dt", "1", "--out",
            ])
            .arg(f)
            .assert()
            .success()
            .stdout("");
    }
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(text.lines().count(), 22);
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let rows = doc["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 21);
    for key in ["t", "a", "x", "xdot"] {
        assert!(rows[3][key].is_f64(), "{key}");
    }
    assert_eq!(doc["meta"]["params"]["gamma"], 1.0);
    // the CSV and JSON carry the same numbers
    let last_csv: f64 = text
        .lines()
        .last()
        .unwrap()
        .split(',')
        .nth(2)
        .unwrap()
        .parse()
        .unwrap();
    assert_eq!(rows[20]["x"].as_f64().unwrap(), last_csv);
    assert_eq!(files_in(dir.path()), ["run.csv", "run.json"]);
}

#[test]
fn simulate_summary_has_the_documented_keys() {
    let doc = json_of(&["simulate", "--summary", "--periods", "0.1"]);
    for key in [
        "params",
        "t_end",
        "final",
        "stats",
        "max_abs_xdot",
        "warnings",
    ] {
        assert!(doc.get(key).is_some(), "missing {key} in {doc}");
    }
    for key in ["alpha", "gamma", "eps", "mu", "delta", "omega"] {
        assert!(doc["params"][key].is_f64(), "params.{key}");
    }
    for key in ["x", "xdot"] {
        assert!(doc["final"][key].is_f64());
    }
    for key in ["steps", "rejected", "rhs_evals"] {
        assert!(doc["stats"][key].is_u64());
    }
    let t_end = doc["t_end"].as_f64().unwrap();
    assert!((t_end - 0.1 * std::f64::consts::TAU / 0.01).abs() < 1e-9);
    // the study's α·ε = 11.36 is flagged
    assert!(doc["warnings"][0].as_str().unwrap().contains("alpha*eps"));
}

#[test]
fn parameter_sources_override_in_order() {
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("s.toml");
    std::fs::write(&cfg, "[params]\ngamma = 2.5\ndelta = 10\n").unwrap();
    let out = hdgear()
        .args([
            "simulate",
            "--summary",
            "--t-end",
            "1",
            "--preset",
            "paper-g30",
            "--config",
        ])
        .arg(&cfg)
        .args(["--delta", "12"])
        .assert()
        .success()
        .get_output()
        .stdout
        .clone();
    let doc: serde_json::Value = serde_json::from_slice(&out).unwrap();
    assert_eq!(doc["params"]["gamma"], 2.5); // file over preset
    assert_eq!(doc["params"]["delta"], 12.0); // flag over file
    assert_eq!(doc["params"]["alpha"], 16.0); // preset
}

/// Runs a bad command with `--out` into an empty directory: exit 2, the message names the
/// offending value, and the directory stays empty.
fn rejects(args: &[&str], needle: &str) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out.csv");
    hdgear()
        .args(args)
        .arg("--out")
        .arg(&out)
        .assert()
        .code(2)
        .stderr(predicate::str::contains(needle))
        .stderr(predicate::str::contains("panicked").not());
    assert!(
        files_in(dir.path()).is_empty(),
        "{args:?} left {:?}",
        files_in(dir.path())
    );
}

#[test]
fn bad_parameters_exit_2_naming_the_value() {
    rejects(&["simulate", "--alpha", "nan"], "alpha = NaN");
    rejects(&["simulate", "--gamma", "inf"], "gamma = inf");
    rejects(&["simulate", "--alpha", "0"], "alpha = 0");
    rejects(&["simulate", "--alpha=-3"], "alpha = -3");
    rejects(&["simulate", "--omega", "0"], "omega = 0");
    rejects(&["simulate", "--delta=-1"], "delta = -1");
    rejects(&["simulate", "--mu=-inf"], "mu = -inf");
    rejects(&["simulate", "--preset", "paper-g2"], "paper-g2");
}

#[test]
fn bad_options_exit_2_naming_the_value() {
    rejects(&["simulate", "--t-end", "0"], "t-end = 0");
    rejects(&["simulate", "--t-end=-5"], "t-end = -5");
    rejects(&["simulate", "--periods", "nan"], "periods = NaN");
    rejects(&["simulate", "--rtol", "0"], "--rtol = 0:");
    rejects(&["simulate", "--rtol=-1e-8"], "--rtol = -1e-8");
    rejects(&["simulate", "--atol", "nan"], "atol = NaN");
    rejects(&["simulate", "--dt", "0"], "dt = 0");
    rejects(&["simulate", "--x0", "nan"], "x0 = NaN");
    rejects(&["simulate", "--gamma", "abc"], "abc");
    // absurd sizes are refused before any work
    rejects(&["simulate", "--dt", "1e-300", "--t-end", "1"], "rows");
    rejects(
        &["equilibria", "--points", "1000000000"],
        "points = 1000000000",
    );
}

#[test]
fn bad_config_files_exit_2_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let unknown = dir.path().join("unknown.toml");
    std::fs::write(&unknown, "[params]\ngamma = 1\nbeta = 2\n").unwrap();
    let malformed = dir.path().join("malformed.toml");
    std::fs::write(&malformed, "[params\ngamma = 1\n").unwrap();
    let wrong_type = dir.path().join("type.toml");
    std::fs::write(&wrong_type, "[params]\ngamma = \"one\"\n").unwrap();
    let nan = dir.path().join("nan.toml");
    std::fs::write(&nan, "[params]\nalpha = nan\n").unwrap();
    for (f, needle) in [
        (&unknown, "beta"),
        (&malformed, "malformed.toml"),
        (&wrong_type, "type.toml"),
        (&nan, "alpha = NaN"),
    ] {
        rejects(&["simulate", "--config", f.to_str().unwrap()], needle);
    }
    rejects(
        &["simulate", "--config", "/nonexistent/x.toml"],
        "/nonexistent/x.toml",
    );
}

#[test]
fn unwritable_output_exits_2_and_leaves_nothing() {
    hdgear()
        .args([
            "simulate",
            "--t-end",
            "1",
            "--out",
            "/nonexistent-dir/run.csv",
        ])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("/nonexistent-dir/run.csv"));
    let dir = tempfile::tempdir().unwrap();
    hdgear()
        .args(["simulate", "--t-end", "1", "--out"])
        .arg(dir.path().join("run.txt"))
        .assert()
        .code(2)
        .stderr(predicate::str::contains("run.txt"));
    assert!(files_in(dir.path()).is_empty());
}

#[test]
fn equilibria_writes_the_documented_columns() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("curve.csv");
    hdgear()
        .args([
            "equilibria",
            "--preset",
            "paper-g1",
            "--points",
            "301",
            "--out",
        ])
        .arg(&out)
        .assert()
        .success();
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("a,x,slope,gprime,re1,im1,re2,im2,type,branch")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 301);
    assert!(rows.iter().all(|r| r[9] == "single"));
    assert!(
        rows.iter()
            .all(|r| r[8] == "stable-focus" || r[8] == "stable-node")
    );
    // the fold regime has three branches and saddles on the middle one
    let text = stdout_of(&[
        "equilibria",
        "--gamma",
        "0.01",
        "--a-range",
        "-0.01:0",
        "--points",
        "500",
    ]);
    for (branch, kind) in [
        ("lower", "stable"),
        ("middle", "saddle"),
        ("upper", "stable"),
    ] {
        assert!(
            text.lines()
                .any(|l| l.ends_with(&format!(",{branch}")) && l.contains(kind)),
            "{branch}"
        );
    }
}

#[test]
fn analyze_json_has_the_documented_keys() {
    let doc = json_of(&["analyze", "--json", "--gamma", "0.01"]);
    assert!((doc["critical_gamma"].as_f64().unwrap() - 1.0 / 48.0).abs() < 1e-15);
    for k in ["gamma", "a", "x"] {
        assert!(doc["cusp"][k].is_f64(), "cusp.{k}");
    }
    let e = &doc["equilibria"];
    assert_eq!(e["min_count"], 1);
    assert_eq!(e["max_count"], 3);
    assert_eq!(e["stable_everywhere"], false);
    assert_eq!(e["hopf_possible"], false);
    assert_eq!(e["folds"].as_array().unwrap().len(), 2);
    for k in ["a", "x"] {
        assert!(e["folds"][0][k].is_f64());
    }
    assert!(e["max_slope"]["value"].is_null(), "infinite at a fold");
    assert!(e["spiking_areas"][0]["a_min"].is_f64());
    // the readable form says the same
    hdgear()
        .args(["analyze", "--preset", "paper-g1"])
        .assert()
        .success()
        .stdout(predicate::str::contains(
            "largest |dx/da| on the range: 15.31",
        ))
        .stdout(predicate::str::contains("Hopf bifurcation possible: no"))
        .stdout(predicate::str::contains("spiking area: a in"));
}

#[test]
fn bifurcation_writes_the_fold_curves() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("folds.csv");
    hdgear()
        .args([
            "bifurcation",
            "--gamma-min",
            "0.001",
            "--points",
            "11",
            "--out",
        ])
        .arg(&out)
        .assert()
        .success();
    let text = std::fs::read_to_string(&out).unwrap();
    assert_eq!(
        text.lines().next(),
        Some("gamma,a_lower,x_lower,a_upper,x_upper")
    );
    assert_eq!(text.lines().count(), 12);
    let last: Vec<f64> = text
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    assert_eq!(last[0], 1.0 / 48.0);
    assert_eq!(last[2], last[4]);
}

#[test]
fn analysis_bad_input_exits_2() {
    rejects(&["bifurcation", "--gamma-min", "0.5"], "gamma-min = 0.5");
    rejects(
        &["bifurcation", "--gamma-min", "0", "--points", "1"],
        "points = 1",
    );
    rejects(&["equilibria", "--a-range", "1:-1"], "'1:-1'");
    rejects(&["equilibria", "--a-range", "nan:1"], "'nan:1'");
    rejects(&["equilibria", "--points", "1"], "points = 1");
    hdgear()
        .args(["analyze", "--delta", "0"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("delta = 0"));
    hdgear()
        .args(["analyze", "--a-range", "0"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("'0'"));
}

#[test]
fn analyze_json_gains_response_and_classification() {
    let doc = json_of(&["analyze", "--json", "--preset", "paper-g1"]);
    for k in [
        "bursts_per_period",
        "spikes_per_burst",
        "peak_abs_xdot",
        "quiescent_fraction",
        "max_tracking_error",
    ] {
        assert!(doc["response"][k].is_f64(), "response.{k}");
    }
    assert_eq!(doc["response"]["bursts_per_period"], 2.0);
    assert_eq!(doc["classification"]["mode"], "fast-slow");
    assert_eq!(
        doc["classification"]["mechanism"],
        "sharp-quantitative-change"
    );
    let doc = json_of(&["analyze", "--json", "--no-response"]);
    assert!(doc.get("response").is_none());
}

#[test]
fn bursts_lists_one_burst_per_row() {
    let text = stdout_of(&["bursts", "--preset", "paper-g0.1"]);
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some(
            "onset,end,a_onset,duration,t_peak,a_peak,peak_abs_xdot,spikes,extrema,ringing_swing,overshoot,overshoot_lobes,jumps,complete"
        )
    );
    assert_eq!(lines.count(), 4); // 2 per period over the 2 analysed periods
    let text = stdout_of(&["bursts", "--preset", "paper-g30"]);
    assert_eq!(
        text.lines().count(),
        1,
        "no bursts, only the header: {text}"
    );
}

#[test]
fn table_formats_agree() {
    let json = json_of(&["table", "--json"]);
    let rows = json["gamma_table"].as_array().unwrap();
    assert_eq!(rows.len(), 4);
    let modes: Vec<&str> = rows.iter().map(|r| r["mode"].as_str().unwrap()).collect();
    assert_eq!(
        modes,
        ["normal", "normal", "fast-slow", "pronounced-bursting"]
    );
    assert_eq!(json["effects_table"].as_array().unwrap().len(), 5);
    let md = stdout_of(&["table"]);
    assert!(md.contains("| 0.1 | extremely steep, near-vertical | 189.4737 |"));
    assert!(md.contains("**contradicts**"));
    let csv = stdout_of(&["table", "--csv"]);
    assert!(csv.starts_with("gamma,shape,max_slope,"));
    assert!(csv.contains("\n\nparameter,low,high,"));
}

fn lines(path: &std::path::Path) -> usize {
    std::fs::read_to_string(path)
        .map(|t| t.lines().count())
        .unwrap_or(0)
}

#[test]
fn a_killed_sweep_resumes_to_the_same_rows() {
    let dir = tempfile::tempdir().unwrap();
    let full = dir.path().join("full.csv");
    let spec = "gamma=0.1:30:400:log";
    hdgear()
        .args(["sweep", "--param", spec, "--threads", "2", "--out"])
        .arg(&full)
        .assert()
        .success();
    assert_eq!(lines(&full), 401);

    let out = dir.path().join("cut.csv");
    let partial = dir.path().join("cut.csv.partial");
    let mut child = std::process::Command::new(assert_cmd::cargo::cargo_bin("hdgear"))
        .args(["sweep", "--param", spec, "--threads", "1", "--out"])
        .arg(&out)
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let t0 = std::time::Instant::now();
    while lines(&partial) < 40 && t0.elapsed().as_secs() < 60 {
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    let kept = lines(&partial);
    assert!(
        !out.exists(),
        "the sweep finished before it could be killed"
    );
    assert!(kept > 1 && kept < 401, "partial rows: {kept}");

    // without --resume, the partial file is not silently overwritten
    hdgear()
        .args(["sweep", "--param", spec, "--out"])
        .arg(&out)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("--resume"));
    hdgear()
        .args([
            "sweep",
            "--param",
            spec,
            "--threads",
            "2",
            "--resume",
            "--out",
        ])
        .arg(&out)
        .assert()
        .success();
    assert!(!partial.exists());
    assert_eq!(
        std::fs::read_to_string(&out).unwrap(),
        std::fs::read_to_string(&full).unwrap()
    );
}

#[test]
fn sweep_writes_json_in_grid_order() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("s.json");
    hdgear()
        .args([
            "sweep",
            "--param",
            "gamma=0.5:2:3",
            "--param",
            "omega=0.01:0.02:2",
            "--out",
        ])
        .arg(&out)
        .assert()
        .success();
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let rows = doc["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 6);
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r["index"], i);
        for k in ["alpha", "gamma", "eps", "mu", "delta", "omega"] {
            assert!(r["params"].get(k).is_some(), "params.{k}");
        }
        for k in [
            "bursts_per_period",
            "spikes_per_burst",
            "peak_abs_xdot",
            "quiescent_fraction",
            "max_tracking_error",
        ] {
            assert!(r["rates"].get(k).is_some(), "rates.{k}");
        }
        for k in ["mode", "mechanism", "max_slope", "error"] {
            assert!(r.get(k).is_some(), "{k}");
        }
    }
    assert_eq!(rows[4]["params"]["gamma"], 1.25);
    assert_eq!(rows[4]["params"]["omega"], 0.02);
    assert_eq!(files_in(dir.path()), ["s.json"]);
}

#[test]
fn sweep_bad_input_exits_2() {
    rejects(&["sweep", "--param", "gamma=1:2"], "gamma=1:2");
    rejects(&["sweep", "--param", "zeta=1:2:3"], "zeta");
    rejects(&["sweep", "--param", "omega=-1:1:3"], "omega = -1");
    rejects(
        &["sweep", "--param", "gamma=1:2:3", "--param", "gamma=1:2:3"],
        "different parameters",
    );
    rejects(
        &["sweep", "--param", "gamma=1:2:3", "--threads", "0"],
        "threads = 0",
    );
}

#[test]
fn physical_json_has_the_documented_keys() {
    let doc = json_of(&["physical", "--json", "--drive", "CSF-14-50"]);
    for k in ["alpha", "gamma", "eps", "mu", "delta", "omega"] {
        assert!(doc["reduced"][k].is_f64(), "reduced.{k}");
    }
    for k in [
        "time_scale",
        "length_scale",
        "j_eq",
        "alpha_eps",
        "critical_gamma",
        "gamma_margin",
        "zeta",
        "three_alpha_gamma",
    ] {
        assert!(doc[k].is_f64(), "{k}");
    }
    // the preset's assumed 10 % damping, and the fold distance its stiffness law implies
    let (zeta, g) = (
        doc["zeta"].as_f64().unwrap(),
        doc["reduced"]["gamma"].as_f64().unwrap(),
    );
    assert!((zeta - 0.1).abs() < 1e-12 && (4.0 * zeta * zeta * g - 1.0).abs() < 1e-12);
    assert!((doc["alpha_eps"].as_f64().unwrap() - 1.0).abs() < 1e-12);
    assert!(doc["predicted"]["mode"].is_string());
    assert!(doc["predicted"]["mechanism"].is_string());
    assert_eq!(doc["drive"]["ratio"], 50.0);
    assert!(doc["catalogue"]["fit"]["twist_error_t1"].as_f64().unwrap() < 0.05);
}

#[test]
fn physical_simulation_summary_and_file() {
    let doc = json_of(&["physical", "--simulate", "--t-end", "0.5", "--summary"]);
    assert_eq!(doc["t_end"], 0.5);
    for k in ["theta", "theta_dot", "theta_in", "theta_out"] {
        assert!(doc["final"][k].is_f64(), "final.{k}");
    }
    for k in ["steps", "rejected", "rhs_evals"] {
        assert!(doc["stats"][k].is_u64());
    }
    let dir = tempfile::tempdir().unwrap();
    let f = dir.path().join("drive.csv");
    hdgear()
        .args([
            "physical",
            "--simulate",
            "--t-end",
            "0.1",
            "--dt",
            "0.01",
            "--out",
        ])
        .arg(&f)
        .assert()
        .success();
    let text = std::fs::read_to_string(&f).unwrap();
    assert_eq!(
        text.lines().next(),
        Some("t,theta_in,theta_out,theta,theta_dot")
    );
    assert_eq!(text.lines().count(), 12);
    // θ = θo − θi/N on every row (N = 50)
    for l in text.lines().skip(1) {
        let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
        assert!((v[3] - (v[2] - v[1] / 50.0)).abs() <= 1e-12 * v[2].abs().max(1e-9));
    }
}

#[test]
fn physical_design_check_names_the_changes() {
    let doc = json_of(&[
        "physical", "--design", "--json", "--t-am", "112", "--k1", "2000",
    ]);
    assert_eq!(doc["judgement"]["bursting"], true);
    let margins = doc["margins"].as_array().unwrap();
    let names: Vec<&str> = margins
        .iter()
        .map(|m| m["parameter"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["k1", "k2", "c_eq", "t_am", "backlash", "t_m"]);
    let k1 = &margins[0];
    assert_eq!(k1["effect"], "leaves bursting");
    assert_eq!(k1["inside"]["judgement"]["bursting"], true);
    assert_eq!(k1["outside"]["judgement"]["bursting"], false);
    // raising k1 ends the bursts: check the boundary through the plain command on both sides
    let f = k1["factor"].as_f64().unwrap();
    assert!(f > 1.0);
    for (factor, bursts) in [(f * 0.97, true), (f * 1.03, false)] {
        let k1 = (2000.0 * factor).to_string();
        let doc = json_of(&["physical", "--json", "--t-am", "112", "--k1", &k1]);
        assert_eq!(doc["predicted"]["bursting"], bursts, "k1 x{factor}");
    }
}

#[test]
fn physical_bad_input_exits_2() {
    fails_with(&["physical", "--j-in", "0"], "j_in = 0");
    fails_with(&["physical", "--c-eq=-1"], "c_eq = -1");
    fails_with(&["physical", "--k2=-5"], "k2 = -5");
    fails_with(&["physical", "--omega", "nan"], "omega = NaN");
    fails_with(&["physical", "--backlash", "0"], "backlash = 0");
    fails_with(
        &["physical", "--backlash", "0", "--design"],
        "simulate the physical model",
    );
    fails_with(&["physical", "--drive", "CSF-99"], "CSF-99");
    fails_with(&["physical", "--simulate"], "--t-end");
    let dir = tempfile::tempdir().unwrap();
    let cfg = dir.path().join("d.toml");
    std::fs::write(&cfg, "[physical]\nj_in = 1e-4\ninertia = 2\n").unwrap();
    fails_with(&["physical", "--config", cfg.to_str().unwrap()], "inertia");
    // φ = 0 still simulates
    hdgear()
        .args([
            "physical",
            "--backlash",
            "0",
            "--simulate",
            "--t-end",
            "0.1",
            "--summary",
        ])
        .assert()
        .success();
}

#[test]
fn plot_writes_svg_and_png_and_rejects_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    for (kind, file) in [("slope", "s.svg"), ("phase-plane", "p.png")] {
        hdgear()
            .args(["plot", kind, "--preset", "paper-g1", "--out"])
            .arg(dir.path().join(file))
            .assert()
            .success();
    }
    let svg = std::fs::read_to_string(dir.path().join("s.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("|dx/da|"));
    let png = std::fs::read(dir.path().join("p.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    assert_eq!(files_in(dir.path()), ["p.png", "s.svg"]);
    let bad = dir.path().join("x.pdf");
    hdgear()
        .args(["plot", "slope", "--out"])
        .arg(&bad)
        .assert()
        .code(2)
        .stderr(predicate::str::contains("x.pdf"));
    hdgear()
        .args(["plot", "spectrum", "--out", "a.svg"])
        .assert()
        .code(2)
        .stderr(predicate::str::contains("spectrum"));
    assert_eq!(files_in(dir.path()), ["p.png", "s.svg"]);
}
