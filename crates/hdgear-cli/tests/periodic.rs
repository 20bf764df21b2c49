//! The periodic-response commands: `continue`, `continue2`, `frequency-response` and
//! `orbit-diagram` write their curves, figures and report sections.

/// Rows of a CSV file as maps from column to text.
fn csv_rows(path: &std::path::Path) -> Vec<std::collections::HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let head: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            head.iter()
                .cloned()
                .zip(l.split(',').map(String::from))
                .collect()
        })
        .collect()
}

/// Runs hdgear in `dir` and returns its stdout; it must succeed.
fn run_in(dir: &std::path::Path, args: &[&str]) -> String {
    let out = crate::common::hdgear()
        .current_dir(dir)
        .args(args)
        .arg("--quiet")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn continue_writes_the_branch_and_its_doubled_branch() {
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| run_in(dir.path(), args);
    // a branch with its doubled branch
    let text = run(&[
        "continue",
        "--param",
        "omega=5:10:log",
        "--gamma",
        "10",
        "--delta",
        "15",
        "--switch",
        "--out",
        "b.csv",
    ]);
    assert!(text.contains("rejoined the parent branch"), "{text}");
    let rows = csv_rows(&dir.path().join("b.csv"));
    let count = |branch: &str, special: &str| {
        rows.iter()
            .filter(|r| r["branch"] == branch && r["special"] == special)
            .count()
    };
    assert_eq!((count("0", "fold"), count("0", "period-doubling")), (2, 2));
    assert!(
        rows.iter()
            .any(|r| r["branch"] == "1" && r["subharmonic"] == "2")
    );
    let last = rows.iter().rfind(|r| r["branch"] == "0").unwrap();
    assert_eq!(
        last["param"], "10.0",
        "the branch ends on the range's end exactly"
    );
    assert_eq!(crate::common::files_in(dir.path()), ["b.csv"]);
}

#[test]
fn frequency_response_and_orbit_diagram_write_curves_figures_and_sections() {
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| run_in(dir.path(), args);
    // the frequency response with its figure
    let text = run(&[
        "frequency-response",
        "--gamma",
        "30",
        "--omega-range",
        "6:10",
        "--out",
        "f.csv",
        "--plot",
        "f.svg",
    ]);
    assert_eq!(text.matches("fold ").count(), 2, "{text}");
    let svg = std::fs::read_to_string(dir.path().join("f.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("fold"));
    let rows = csv_rows(&dir.path().join("f.csv"));
    assert_eq!(rows.iter().filter(|r| r["special"] == "fold").count(), 2);
    // the orbit diagram: two sweeps × values × recorded periods
    run(&[
        "orbit-diagram",
        "--param",
        "omega=7.5:8.6:12",
        "--gamma",
        "30",
        "--record",
        "8",
        "--out",
        "d.csv",
    ]);
    let rows = csv_rows(&dir.path().join("d.csv"));
    assert_eq!(rows.len(), 2 * 12 * 8);
    assert!(
        rows.iter().all(|r| r["period"] == "1"),
        "every response is period 1 here"
    );
    let (up, down): (Vec<_>, Vec<_>) = rows.iter().partition(|r| r["sweep"] == "up");
    assert_eq!((up.len(), down.len()), (96, 96));
    assert_eq!(
        crate::common::files_in(dir.path()),
        ["d.csv", "f.csv", "f.svg"]
    );
}

#[test]
fn a_lyapunov_map_is_in_grid_order_whatever_the_threads() {
    let dir = tempfile::tempdir().unwrap();
    let args = |threads: &str, out: &str| {
        vec![
            "lyapunov-map".to_string(),
            "--param=omega=6:10:4".into(),
            "--param=delta=10:20:3".into(),
            "--gamma=10".into(),
            "--periods=400".into(),
            format!("--threads={threads}"),
            format!("--out={out}"),
        ]
    };
    let a: Vec<String> = args("1", "one.csv");
    let b: Vec<String> = [args("2", "two.csv"), vec!["--plot=map.svg".into()]].concat();
    run_in(
        dir.path(),
        &a.iter().map(String::as_str).collect::<Vec<_>>(),
    );
    run_in(
        dir.path(),
        &b.iter().map(String::as_str).collect::<Vec<_>>(),
    );
    let one = std::fs::read(dir.path().join("one.csv")).unwrap();
    assert_eq!(one, std::fs::read(dir.path().join("two.csv")).unwrap());
    let rows = csv_rows(&dir.path().join("one.csv"));
    assert_eq!(rows.len(), 12);
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r["index"], i.to_string());
        let l: f64 = r["lyapunov"].parse().unwrap();
        // a damped forced oscillator with trace −1: no exponent below −1/2 (both Floquet
        // exponents sum to −1 and the larger is ≥ their mean), none positive here. Benettin's
        // estimate of a focus-type orbit's −1/2 is off by up to ln κ/span (κ: the condition of
        // the monodromy's eigenvectors; the tangent's norm oscillates by that factor): measured
        // on this grid up to 0.014 below over 100 periods, 0.004 over 400
        assert!(l > -0.5 - 1e-2 && l < 0.0, "row {i}: λ = {l}");
    }
    let svg = std::fs::read_to_string(dir.path().join("map.svg")).unwrap();
    assert!(svg.contains("complex multipliers"));
}

/// `hdgear continue2` from every fold of the study's frequency response: two fold curves (the
/// four folds at δ = 15 lie two on each, traced once), each with its cusp, every row's larger
/// multiplier at +1 to 1e-9, the JSON's curves the file's rows; the figure; bad requests exit 2
/// naming the value.
#[test]
fn continue2_traces_each_fold_curve_once() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "continue2",
        "--param",
        "omega=0.3:20:log",
        "--param",
        "delta=0.5:40:log",
        "--out",
        "c.csv",
        "--plot",
        "c.svg",
    ];
    let text = run_in(dir.path(), &args);
    assert_eq!(text.matches("cusp").count(), 2, "{text}");
    assert!(text.contains("curve 1: fold"), "{text}");
    assert!(!text.contains("curve 2"), "{text}");
    let rows = csv_rows(&dir.path().join("c.csv"));
    assert!(rows.len() > 100);
    for r in &rows {
        let m: f64 = r["ln_abs_m1"].parse().unwrap();
        assert!(m.abs() < 1e-9, "{r:?}");
    }
    let cusps: Vec<_> = rows.iter().filter(|r| r["special"] == "cusp").collect();
    assert_eq!(cusps.len(), 2);
    let svg = std::fs::read_to_string(dir.path().join("c.svg")).unwrap();
    assert!(svg.contains("fold curve") && svg.contains("cusp"));
    let doc = crate::common::json_of(&[&args[..5], &["--json"]].concat());
    let n: usize = doc["curves"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["points"].as_array().unwrap().len())
        .sum();
    assert_eq!(n, rows.len());
    let base = ["continue2", "--param", "omega=0.3:20:log"];
    crate::common::fails_with(&base, "exactly twice");
    crate::common::fails_with(
        &[&base[..], &["--param", "delta=20:40"]].concat(),
        "delta=20:40",
    );
    crate::common::fails_with(&[&base[..], &["--param", "omega=1:2"]].concat(), "twice");
    let both = [&base[..], &["--param", "delta=0.5:40"]].concat();
    crate::common::fails_with(&[&both[..], &["--from", "fold:9"]].concat(), "fold:9");
    crate::common::fails_with(&[&both[..], &["--from", "hopf"]].concat(), "hopf");
    crate::common::fails_with(
        &[&both[..], &["--from", "period-doubling"]].concat(),
        "no period-doubling",
    );
}

/// `hdgear boundary` in (ω, γ): each boundary once, from edge to edge; every simulated point's
/// bracket 1 % wide and every other one's 1e-9, bursting on the high-ω side; the JSON's curves
/// the file's rows; the figure names each kind; bad requests exit 2 naming the value.
#[test]
fn boundary_writes_each_curve_once() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "boundary",
        "--param",
        "omega=1e-4:0.2:log",
        "--param",
        "gamma=0.01:3:log",
        "--out",
        "b.csv",
        "--plot",
        "b.svg",
    ];
    let text = run_in(dir.path(), &args);
    let kinds = [
        "predicted",
        "simulated",
        "a-fold-in-range",
        "both-folds-in-range",
        "fast-slow-edge",
    ];
    for (i, kind) in kinds.iter().enumerate() {
        assert!(text.contains(&format!("curve {i}: {kind}, ")), "{text}");
    }
    for kind in &kinds[..4] {
        assert!(text.contains(&format!("{kind}: 1 curve(s)")), "{text}");
    }
    // the fast-slow edge breaks at the cusp γ = 1/48: above it the path's slowest rate, that of
    // the node at the inflection (≈ γ − 1/48), goes to 0; below it the state jumps at both
    // folds and settles at the turning points
    assert!(text.contains("fast-slow-edge: 2 curve(s)"), "{text}");
    assert!(text.contains("curve 5: fast-slow-edge, "), "{text}");
    assert!(!text.contains("curve 6"), "{text}");
    let rows = csv_rows(&dir.path().join("b.csv"));
    for r in &rows {
        let f = |k: &str| r[k].parse::<f64>().unwrap();
        let tol = if r["kind"] == "simulated" { 0.01 } else { 1e-9 };
        for (o, i) in [("outside1", "inside1"), ("outside2", "inside2")] {
            assert!((f(o) / f(i) - 1.0).abs() <= tol * (1.0 + 1e-12), "{r:?}");
        }
        if r["kind"].ends_with("ed") {
            // bursting above the boundary in ω
            assert!(f("inside1") >= f("outside1"), "{r:?}");
        }
    }
    let svg = std::fs::read_to_string(dir.path().join("b.svg")).unwrap();
    assert!(kinds.iter().all(|k| svg.contains(k)));
    let some = [
        &args[..5],
        &["--kinds", "predicted,fast-slow-edge", "--json"],
    ]
    .concat();
    let doc = crate::common::json_of(&some);
    let curves = doc["curves"].as_array().unwrap();
    assert_eq!(curves.len(), 3); // one predicted, two fast-slow edges
    let n = |kind: &str| rows.iter().filter(|r| r["kind"] == kind).count();
    for kind in ["predicted", "fast-slow-edge"] {
        let points: usize = curves
            .iter()
            .filter(|c| c["kind"] == kind)
            .map(|c| c["points"].as_array().unwrap().len())
            .sum();
        assert_eq!(points, n(kind), "{kind}");
    }
    let base = &args[..5];
    crate::common::fails_with(&[base, &["--kinds", "hopf"]].concat(), "hopf");
    crate::common::fails_with(&[base, &["--step", "0.5"]].concat(), "0.5");
    crate::common::fails_with(&[base, &["--gamma", "1"]].concat(), "--gamma");
    crate::common::fails_with(&["boundary", "--param", "omega=1:2"], "exactly twice");
    crate::common::fails_with(
        &[
            "boundary",
            "--param",
            "omega=1:2",
            "--param",
            "delta=-1:2:log",
        ],
        "delta=-1:2:log",
    );
}

/// `continue2 --restart FILE:ROW` from a row of curve 1 follows curve 1 again, edge to edge (its
/// ends within 1e-8); bad restarts exit 2 with the reason.
#[test]
fn continue2_restarts_from_a_row_of_its_output() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "continue2",
        "--param",
        "omega=0.3:20:log",
        "--param",
        "delta=0.5:40:log",
        "--out",
        "c.csv",
    ];
    run_in(dir.path(), &args);
    let rows = csv_rows(&dir.path().join("c.csv"));
    let k = rows.iter().position(|r| r["curve"] == "1").unwrap() + 20;
    let row = format!("c.csv:{k}");
    let again = [&args[..5], &["--restart", &row, "--json"]].concat();
    let doc: serde_json::Value = serde_json::from_str(&run_in(dir.path(), &again)).unwrap();
    let points = doc["curves"][0]["points"].as_array().unwrap();
    // the two ends, in either order (the curve may be followed the other way)
    let ends = |ps: Vec<[f64; 2]>| {
        let mut e = [ps[0], ps[ps.len() - 1]];
        e.sort_by(|a, b| a[0].total_cmp(&b[0]));
        e
    };
    let here = ends(
        points
            .iter()
            .map(|q| [0, 1].map(|j| q["params"][j].as_f64().unwrap()))
            .collect(),
    );
    let there = ends(
        rows.iter()
            .filter(|r| r["curve"] == "1")
            .map(|r| [r["param1"].parse().unwrap(), r["param2"].parse().unwrap()])
            .collect(),
    );
    for (a, b) in here.iter().flatten().zip(there.iter().flatten()) {
        assert!((a / b - 1.0).abs() < 1e-8, "{here:?} vs {there:?}");
    }
    // bad restarts: no such row, not a continue2 file, a start off the curve
    let bad = |restart: &'static str| [&args[..5], &["--restart", restart]].concat();
    let run = |a: &[&str]| {
        crate::common::hdgear()
            .current_dir(dir.path())
            .args(a)
            .output()
            .unwrap()
    };
    let out = run(&bad("c.csv:99999"));
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no row 99999"));
    let text = std::fs::read_to_string(dir.path().join("c.csv")).unwrap();
    let off: String = text
        .lines()
        .take(2)
        .map(|l| {
            let mut f: Vec<&str> = l.split(',').collect();
            if f[0] != "curve" {
                f[5] = "3.5"; // x0 far from the orbit
            }
            f.join(",") + "\n"
        })
        .collect();
    std::fs::write(dir.path().join("off.csv"), off).unwrap();
    let out = run(&bad("off.csv:0"));
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("did not converge"));
    let out = run(&bad("c.svg:0"));
    assert_eq!(out.status.code(), Some(2));
}

/// `continue2 --from period-doubling --switch` at γ = 10 in (ω, μ): the period-doubling curve
/// with its two generalised period doublings, then one fold curve of the doubled orbits
/// (period 2), switched onto at the first and ending at the second; every row of it has a
/// multiplier at +1 to 1e-9. `--switch` from folds is refused.
#[test]
fn continue2_switches_at_generalised_period_doublings() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "continue2",
        "--gamma",
        "10",
        "--param",
        "omega=7:11:log",
        "--param",
        "mu=-5:5",
        "--from",
        "period-doubling:1",
        "--switch",
        "--out",
        "c.csv",
    ];
    let text = run_in(dir.path(), &args);
    assert!(
        text.contains("curve 0: period-doubling, period 1"),
        "{text}"
    );
    assert!(text.contains("curve 1: fold, period 2"), "{text}");
    assert!(
        text.contains(
            "switched onto at a generalised period doubling, at another generalised period doubling"
        ),
        "{text}"
    );
    assert!(!text.contains("curve 2"), "{text}");
    let rows = csv_rows(&dir.path().join("c.csv"));
    let lpc: Vec<_> = rows.iter().filter(|r| r["curve"] == "1").collect();
    assert!(lpc.len() > 5);
    for r in &lpc {
        assert_eq!(
            (r["kind"].as_str(), r["subharmonic"].as_str()),
            ("fold", "2")
        );
        let m: f64 = r["ln_abs_m1"].parse().unwrap();
        assert!(m.abs() < 1e-9, "{r:?}");
    }
    let ends = [lpc[0], lpc[lpc.len() - 1]];
    assert!(
        ends.iter()
            .all(|r| r["special"] == "generalised-period-doubling")
    );
    crate::common::fails_with(
        &[
            "continue2",
            "--param",
            "omega=0.3:20:log",
            "--param",
            "delta=0.5:40:log",
            "--switch",
        ],
        "--switch: invalid switch 'fold'",
    );
}
