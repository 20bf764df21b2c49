//! `hdgear robust` and `hdgear physical --robust`: the page and the JSON agree, the samples file
//! holds one row per sample and its verdicts count to P(burst), shards join into the whole run
//! (their rows, and their summaries through hdgear merge), and bad requests are refused with the
//! value named.

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

/// The tolerance cloud is drawn with both verdicts' samples and the predicted boundary, the
/// Sobol bars with each tolerance, the load curve with its intervals; the load curve's point at
/// the nominal load is the run's own P(burst) (the same points and space, so the same counts),
/// and P(burst) at 2^(j/4) times the load is that factor's load.
#[test]
fn robust_draws_its_figures() {
    let dir = tempfile::tempdir().unwrap();
    let path = |name: &str| dir.path().join(name).to_str().unwrap().to_string();
    let (cloud, bars, load) = (path("cloud.svg"), path("bars.svg"), path("load.svg"));
    let args = [
        &DRIVE[..],
        &[
            "--robust",
            "--samples",
            "512",
            "--no-worst",
            "--sobol",
            "64",
            "--json",
        ],
        &["--cloud", &cloud, "--bars", &bars, "--load-curve", &load],
    ]
    .concat();
    let doc = json_of(&args);
    let curve = doc["load_curve"].as_array().unwrap();
    assert_eq!(curve.len(), 13);
    assert_eq!(curve[8]["factor"], 1.0);
    assert_eq!(curve[8]["probability"], doc["probability"]);
    for (j, point) in curve.iter().enumerate() {
        let want = 22.0 * 2f64.powf((j as f64 - 8.0) / 4.0);
        assert!((point["load"].as_f64().unwrap() - want).abs() < 1e-12 * want);
    }
    let read = |p: &str| std::fs::read_to_string(p).unwrap();
    for (file, labels) in [
        (
            &cloud,
            &[
                "burst-free sample",
                "bursting sample",
                "predicted boundary",
                "nominal",
            ][..],
        ),
        (&bars, &["k1", "t_am", "first-order index", "bootstrap"][..]),
        (&load, &["P(burst)", "Wilson", "nominal load"][..]),
    ] {
        let text = read(file);
        for label in labels {
            assert!(text.contains(label), "{file}: {label}");
        }
    }
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

/// The --json summaries of three shards, given in any order, merge into the whole run's: the
/// same counts and P(burst), the importance sampling's sums equal to rounding (added in another
/// order), part 0's worst case; a part missing or given twice is refused.
#[test]
fn robust_summaries_merge_into_the_whole_run() {
    let dir = tempfile::tempdir().unwrap();
    let base = [
        "physical",
        "--k1",
        "2000",
        "--t-am",
        "18",
        "--robust",
        "--samples",
        "600",
        "--importance",
        "600",
        "--json",
    ];
    let whole = json_of(&base);
    let mut paths = Vec::new();
    for k in [2, 0, 1] {
        let shard = format!("{k}/3");
        let doc = stdout_of(&[&base[..], &["--shard", &shard]].concat());
        let path = dir.path().join(format!("p{k}.json"));
        std::fs::write(&path, doc).unwrap();
        paths.push(path.to_str().unwrap().to_string());
    }
    let out = dir.path().join("m.json");
    let args: Vec<&str> = ["merge", "--out", out.to_str().unwrap()]
        .into_iter()
        .chain(paths.iter().map(String::as_str))
        .collect();
    hdgear().args(&args).assert().success();
    let merged: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    for key in ["space", "probability", "sampling", "worst", "shard"] {
        assert_eq!(merged[key], whole[key], "{key}");
    }
    let (a, b) = (&merged["importance"], &whole["importance"]);
    assert_eq!(a["bursting"], b["bursting"]);
    assert_eq!(a["design"], b["design"]);
    let (pa, pb) = (a["p"].as_f64().unwrap(), b["p"].as_f64().unwrap());
    assert!(pb > 0.0 && (pa - pb).abs() <= 1e-12 * pb, "{pa} {pb}");
    fails_with(&["merge", &paths[0], &paths[1]], "every part");
    fails_with(&["merge", &paths[0], &paths[1], &paths[1]], "every part");
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
    fails_with(&[&g[..], &["--importance", "0"]].concat(), "importance");
    fails_with(&[&g[..], &["--out", "x.txt"]].concat(), "x.txt");
    fails_with(&[&g[..], &["--cloud", "x.pdf"]].concat(), "x.pdf");
    fails_with(&[&g[..], &["--load-curve", "x.pdf"]].concat(), "x.pdf");
    fails_with(&[&g[..], &["--bars", "x.svg"]].concat(), "--sobol");
    fails_with(
        &["robust", "--card", "CSF-20-50", "--tolerance", "gamma=±1%"],
        "gamma",
    );
}

/// A card file with a `[card.tolerance]` table: its bands replace the defaults for the
/// parameters it names (with the card's source), the defaults stay for the rest, its
/// application's resonance requirement is checked (f_n ≈ 81 Hz against 200 Hz); a band on a
/// parameter that is not the drive's is refused naming it.
#[test]
fn robust_takes_a_cards_tolerances() {
    use hdgear::physical::card::{Application, CardFile, Source, SourceKind, Tolerances, builtin};
    let dir = tempfile::tempdir().unwrap();
    let write = |bands: &[(&str, &str)]| {
        let mut f: CardFile = builtin().clone();
        f.card.retain(|c| c.name == "CSF-20-50");
        f.sources.insert(
            "batch".into(),
            Source {
                kind: SourceKind::Measured,
                cite: "a measured batch".into(),
            },
        );
        f.card[0].application = Some(Application {
            source: "batch".into(),
            resonance_required: Some(200.0),
            ..Application::default()
        });
        f.card[0].tolerance = Some(Tolerances {
            source: "batch".into(),
            bands: bands
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect(),
        });
        let path = dir.path().join(format!("card{}.toml", bands.len()));
        std::fs::write(&path, f.to_toml()).unwrap();
        path.to_str().unwrap().to_string()
    };
    let path = write(&[("k1", "±5%"), ("t_m", "normal:2%")]);
    let doc = json_of(&[
        "robust",
        "--card",
        &path,
        "--samples",
        "64",
        "--no-worst",
        "--json",
    ]);
    let tol = doc["space"]["tolerances"].as_array().unwrap();
    let of = |name: &str| tol.iter().find(|t| t["target"] == name).unwrap();
    assert_eq!(of("k1")["distribution"]["kind"], "uniform");
    let lo = of("k1")["distribution"]["lo"].as_f64().unwrap();
    let k1 = doc["space"]["nominal"]["values"]["k1"].as_f64().unwrap();
    assert!((lo / k1 - 0.95).abs() < 1e-12);
    assert!(
        of("k1")["source"]
            .as_str()
            .unwrap()
            .contains("a measured batch")
    );
    assert_eq!(of("t_m")["distribution"]["kind"], "normal");
    assert!(
        of("c_eq")["source"]
            .as_str()
            .unwrap()
            .starts_with("assumption")
    );
    assert_eq!(tol.len(), 7);
    assert_eq!(doc["resonance"]["required_hz"], 200.0);
    let text = stdout_of(&["robust", "--card", &path, "--samples", "16", "--no-worst"]);
    assert!(
        text.contains("the card's application needs 200 Hz: FAIL"),
        "{text}"
    );
    let bad = write(&[("k1", "±5%"), ("gamma", "±1%"), ("t_m", "±1%")]);
    fails_with(&["robust", "--card", &bad], "gamma");
}
