//! `hdgear robust` and `hdgear physical --robust`: the page and the JSON agree, the samples file
//! holds one row per sample and its verdicts count to P(burst), shards join into the whole run,
//! and bad requests are refused with the value named.

use crate::common::{fails_with, hdgear, json_of, stdout_of};

const DRIVE: [&str; 5] = ["physical", "--k1", "2000", "--t-am", "22"];

/// The samples file's verdicts count to the reported P(burst), its interval is Wilson's, and
/// the text prints the JSON's numbers.
#[test]
fn robust_counts_its_samples_file() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("s.csv");
    let f = file.to_str().unwrap();
    let args = [
        &DRIVE[..],
        &["--robust", "--samples", "500", "--json", "--out", f],
    ]
    .concat();
    let doc = json_of(&args);
    let p = &doc["probability"];
    let rows: Vec<String> = std::fs::read_to_string(&file)
        .unwrap()
        .lines()
        .skip(1)
        .map(String::from)
        .collect();
    assert_eq!(rows.len(), 500);
    let bursting = rows
        .iter()
        .filter(|r| r.split(',').nth(8) == Some("1.0"))
        .count();
    assert_eq!(p["bursting"].as_u64().unwrap(), bursting as u64);
    assert!(
        bursting > 0 && bursting < 500,
        "the drive is near its boundary: {bursting}"
    );
    let (lo, hi) = hdgear::robust::wilson(bursting as u64, 500, 0.95);
    assert_eq!(p["interval"][0].as_f64().unwrap(), lo);
    assert_eq!(p["interval"][1].as_f64().unwrap(), hi);
    let w = &doc["worst"];
    assert!(w["margin"].as_f64().unwrap() < 1.0, "{w}");
    assert_eq!(w["corners"].as_array().unwrap().len(), 64);
    let text = stdout_of(&[&DRIVE[..], &["--robust", "--samples", "500"]].concat());
    assert!(
        text.contains(&format!("P(burst) = {:.4}", p["p"].as_f64().unwrap())),
        "{text}"
    );
    assert!(text.contains("closest to bursting"), "{text}");
    assert!(text.contains("hand-axis (>= 15 Hz) pass"), "{text}");
}

/// Two shards of a run write the rows of the whole run, byte for byte.
#[test]
fn robust_shards_join_into_the_whole_run() {
    let dir = tempfile::tempdir().unwrap();
    let run = |name: &str, extra: &[&str]| {
        let path = dir.path().join(name);
        let base = [
            "robust",
            "--gamma",
            "2.2",
            "--tolerance",
            "gamma=normal:10%",
        ];
        let more = [
            "--samples",
            "300",
            "--no-worst",
            "--out",
            path.to_str().unwrap(),
        ];
        hdgear()
            .args(base)
            .args(more)
            .args(extra)
            .assert()
            .success();
        std::fs::read_to_string(path).unwrap()
    };
    let whole = run("all.csv", &[]);
    let a = run("a.csv", &["--shard", "0/2"]);
    let b = run("b.csv", &["--shard", "1/2"]);
    let b_rows: String = b.lines().skip(1).map(|l| format!("{l}\n")).collect();
    assert_eq!(whole, format!("{a}{b_rows}"));
}

/// Bad tolerances, shards and options exit 2 naming the value; a study set needs tolerances.
#[test]
fn robust_bad_input_exits_2() {
    fails_with(&["robust"], "--tolerance");
    fails_with(&["robust", "--tolerance", "k1=±10%"], "k1");
    fails_with(&["robust", "--tolerance", "gamma=±x%"], "±x%");
    fails_with(&["robust", "--tolerance", "gamma"], "NAME=SPEC");
    fails_with(&["robust", "--tolerance", "gamma=weibull:2"], "weibull");
    fails_with(&["robust", "--tolerance", "gamma=5..1"], "5..1");
    let g = ["robust", "--tolerance", "gamma=±10%"];
    fails_with(&[&g[..], &["--tolerance", "gamma=±5%"]].concat(), "twice");
    fails_with(&[&g[..], &["--shard", "2/2"]].concat(), "2/2");
    fails_with(&[&g[..], &["--samples", "0"]].concat(), "samples");
    fails_with(&[&g[..], &["--level", "1"]].concat(), "level");
    fails_with(&[&g[..], &["--sampler", "lhs"]].concat(), "lhs");
    fails_with(&[&g[..], &["--sobol", "1"]].concat(), "sobol");
    fails_with(&[&g[..], &["--out", "x.txt"]].concat(), "x.txt");
    fails_with(
        &["robust", "--card", "CSF-20-50", "--tolerance", "gamma=±1%"],
        "gamma",
    );
}
