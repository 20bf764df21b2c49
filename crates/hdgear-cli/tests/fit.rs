//! `hdgear fit`: the files it writes (residuals, plot, law, card) read back, and bad data or
//! options refused in one line with exit 2 and nothing written.

use crate::common::{fails_with, files_in, hdgear};

/// A Coulomb–Stribeck–viscous sweep (F_c 0.5, F_s 0.8, v_s 0.02, c_v 0.3) at 24 speeds, with a
/// small deterministic ripple standing in for noise.
fn sweep() -> String {
    let mut s = String::from("speed [rad/s],torque [N m]\n");
    for i in 0..24 {
        let v = 2e-3 * 1.3f64.powi(i % 12) * if i < 12 { -1.0 } else { 1.0 };
        let t = (0.5 + 0.3 * (-(v / 0.02f64).powi(2)).exp()) * v.signum() + 0.3 * v;
        s += &format!("{v},{}\n", t + 2e-3 * (i as f64 * 1.7).sin());
    }
    s
}

const FREE: [&str; 8] = [
    "--free",
    "fc=0:5",
    "--free",
    "fs=0:5",
    "--free",
    "vst=1e-4:1",
    "--free",
    "cv=0:2",
];

#[test]
fn a_fit_writes_its_residuals_plot_law_and_card() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.csv"), sweep()).unwrap();
    let mut args = vec![
        "fit", "--data", "s.csv", "--kind", "friction", "--term", "coulomb",
    ];
    args.extend(FREE);
    args.extend([
        "--residuals",
        "r.csv",
        "--plot",
        "f.svg",
        "--law-out",
        "law.toml",
        "--card",
        "CSG-20-50",
        "--card-out",
        "card.toml",
        "--json",
    ]);
    let out = hdgear()
        .current_dir(dir.path())
        .args(&args)
        .assert()
        .success();
    let doc: serde_json::Value = serde_json::from_slice(&out.get_output().stdout).unwrap();
    let fs = doc["estimates"][1]["value"].as_f64().unwrap();
    assert!((fs - 0.8).abs() < 0.01, "{fs}");
    let residuals = std::fs::read_to_string(dir.path().join("r.csv")).unwrap();
    assert_eq!(residuals.lines().count(), 25);
    assert!(
        std::fs::read_to_string(dir.path().join("f.svg"))
            .unwrap()
            .contains("<svg")
    );
    // the law file is a scenario the next fit reads as its start
    let mut again = vec![
        "fit", "--data", "s.csv", "--kind", "friction", "--config", "law.toml", "--starts", "1",
        "--json",
    ];
    again.extend(FREE);
    let out = hdgear()
        .current_dir(dir.path())
        .args(&again)
        .assert()
        .success();
    let doc2: serde_json::Value = serde_json::from_slice(&out.get_output().stdout).unwrap();
    assert_eq!(doc2["estimates"][1]["value"].as_f64().unwrap(), fs);
    // the card reads back, its friction the fit's
    let out = hdgear()
        .current_dir(dir.path())
        .args(["card", "show", "card.toml"])
        .assert()
        .success();
    let shown = String::from_utf8_lossy(&out.get_output().stdout).to_string();
    assert!(
        shown.contains("breakaway") && shown.contains("fit"),
        "{shown}"
    );
    // and the design check runs the drive with the fitted law, named by the fit's source
    let out = hdgear()
        .current_dir(dir.path())
        .args(["card", "check", "card.toml", "--json", "--quiet"])
        .assert()
        .success();
    let check: serde_json::Value = serde_json::from_slice(&out.get_output().stdout).unwrap();
    let friction = &check["friction"];
    assert_eq!(friction["law"]["breakaway"].as_f64().unwrap(), fs);
    assert!(
        friction["source"]
            .as_str()
            .unwrap()
            .starts_with("fit-friction-"),
        "{friction}"
    );
    assert!(friction["outcome"]["verdict"].is_string(), "{friction}");
}

#[test]
fn bad_fits_are_refused_in_a_line_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let data = dir.path().join("s.csv");
    std::fs::write(&data, sweep()).unwrap();
    let d = data.to_str().unwrap();
    let card = dir.path().join("card.toml");
    let c = card.to_str().unwrap();
    let base = ["fit", "--data", d, "--kind", "friction"];
    let with = |extra: &[&str]| -> Vec<String> {
        base.iter().chain(extra).map(|s| s.to_string()).collect()
    };
    for (extra, needle) in [
        (&["--term", "coulomb", "--free", "fc=1:0"][..], "LO < HI"),
        (&["--term", "coulomb", "--free", "f_c=0:1"], "coulomb.fc"),
        (
            &["--term", "lugre", "--term", "lugre", "--free", "fc=0:1"],
            "each kind of term may appear once",
        ),
        (
            &["--term", "nonsense", "--free", "fc=0:1"],
            "unknown term nonsense",
        ),
        (&["--free", "fc=0:1"], "give the law to fit"),
        (
            &[
                "--term",
                "coulomb",
                "--free",
                "fc=0:1",
                "--unit",
                "speed=furlong/s",
            ],
            "furlong/s",
        ),
        (
            &[
                "--term", "coulomb", "--free", "fc=0:1", "--column", "twist=x",
            ],
            "friction data have the quantities speed, torque",
        ),
        (
            &[
                "--term",
                "coulomb",
                "--free",
                "fc=0:1",
                "--card",
                "NOPE-1",
                "--card-out",
                c,
            ],
            "NOPE-1",
        ),
    ] {
        let args = with(extra);
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        fails_with(&args, needle);
    }
    fails_with(
        &[
            "fit",
            "--data",
            "/nonexistent/s.csv",
            "--kind",
            "friction",
            "--term",
            "coulomb",
            "--free",
            "fc=0:1",
        ],
        "/nonexistent/s.csv",
    );
    fails_with(
        &[
            "fit", "--data", d, "--kind", "torsion", "--term", "coulomb", "--free", "fc=0:1",
        ],
        "torsion",
    );
    assert_eq!(files_in(dir.path()), ["s.csv"]);
}

/// Hostile values in every flag of `hdgear fit`, with a real data file beside them: each run
/// ends in 0 or a one-line refusal (2), within seconds, never a panic, and leaves no temporary.
#[test]
fn hostile_values_in_every_flag() {
    let values = [
        "",
        "0",
        "-1",
        "nan",
        "inf",
        "1e309",
        "18446744073709551615",
        "x",
        "1:2",
        "=",
        "-1e308",
    ];
    let base = [
        "fit", "--data", "s.csv", "--kind", "friction", "--term", "coulomb", "--free", "fc=0:5",
    ];
    let mut vectors: Vec<Vec<String>> = Vec::new();
    for flag in [
        "--starts", "--seed", "--repeat", "--free", "--unit", "--column", "--plot", "--kind",
        "--term", "--card",
    ] {
        for v in values {
            let mut a: Vec<String> = base.iter().map(|s| s.to_string()).collect();
            let v = match flag {
                "--free" => format!("fs={v}:5"),
                "--unit" => format!("speed={v}"),
                "--column" => format!("speed={v}"),
                _ => v.to_string(),
            };
            a.push(format!("{flag}={v}"));
            vectors.push(a);
        }
    }
    for args in &vectors {
        let dir = tempfile::tempdir().unwrap();
        std::fs::write(dir.path().join("s.csv"), sweep()).unwrap();
        let out = hdgear()
            .current_dir(dir.path())
            .args(args)
            .arg("--quiet")
            .timeout(std::time::Duration::from_secs(30))
            .output()
            .unwrap();
        let code = out.status.code().unwrap_or(-1);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!([0, 2].contains(&code), "{args:?} exited {code}: {stderr}");
        if code == 2 {
            assert_eq!(
                stderr.lines().filter(|l| l.starts_with("error")).count(),
                1,
                "{args:?}: {stderr}"
            );
        }
        let left = files_in(dir.path());
        assert!(
            left.iter().all(|f| !f.contains(".tmp")),
            "{args:?} left {left:?}"
        );
    }
}
