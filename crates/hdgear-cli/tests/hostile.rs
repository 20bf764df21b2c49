//! A hostile user: generated bad inputs over every subcommand (each flag with each hostile
//! value, malformed specs, names and paths), every run checked for a panic, its exit code and
//! anything left behind.

use crate::common::{hdgear, walk};
use std::time::Duration;

/// Hostile values for a numeric flag.
pub(crate) const VALUES: [&str; 13] = [
    "nan", "inf", "-inf", "0", "-1", "1e300", "-1e300", "1e-320", "5e-324", "", "abc", "1e400",
    "-0",
];

/// Runs one argument vector in a fresh directory and checks the invariants: no panic, an exit
/// code of 0, 1 or 2 (2 for refused input), and no file left behind but a complete requested
/// output. Returns the exit code.
fn check_run(args: &[String]) -> i32 {
    let dir = tempfile::tempdir().unwrap();
    let out = hdgear()
        .current_dir(dir.path())
        .args(args)
        .arg("--quiet")
        .timeout(Duration::from_secs(30))
        .output()
        .unwrap();
    let code = out.status.code().unwrap_or(-1);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !stderr.contains("panicked") && code != 101,
        "{args:?} panicked: {stderr}"
    );
    assert!(
        [0, 1, 2].contains(&code),
        "{args:?} exited {code} (timeout or signal?): {stderr}"
    );
    if code != 0 {
        // one line naming the problem
        let lines: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error")).collect();
        assert_eq!(lines.len(), 1, "{args:?}: {stderr}");
    }
    let left: Vec<String> = walk(dir.path());
    for f in &left {
        assert!(
            !f.contains(".tmp-") && !f.ends_with(".lock"),
            "{args:?} left {f} behind"
        );
        if code != 0 {
            assert!(
                f.starts_with("pre-"),
                "{args:?} failed but left {f} (files: {left:?})"
            );
        }
    }
    code
}

/// Bad a-ranges and sweep specs.
fn range_and_spec_vectors(v: &mut Vec<Vec<String>>) {
    for range in [
        "-1e-200:1e-200",
        "0:5e-324",
        "-1e300:1e300",
        "1:-1",
        "nan:1",
        "1",
        "",
        "a:b",
        "-1:inf",
        "0:0",
        "-2:2",
    ] {
        v.push(vec![
            "equilibria".into(),
            "--points".into(),
            "5".into(),
            format!("--a-range={range}"),
        ]);
        v.push(vec![
            "analyze".into(),
            "--no-response".into(),
            format!("--a-range={range}"),
        ]);
    }
    for spec in [
        "gamma=1:2:0",
        "gamma=1:2:3",
        "mu=-1e308:1e308:3",
        "gamma=0:1:3:log",
        "beta=1:2:3",
        "gamma=nan:1:3",
        "gamma=1:2:99999999999",
        "alpha=-1:1:3",
        "gamma=1:2",
        "",
    ] {
        v.push(vec![
            "sweep".into(),
            format!("--param={spec}"),
            "--out".into(),
            "s.csv".into(),
        ]);
    }
}

/// Bad continuation ranges, frequency ranges, orbit-diagram axes and their counts.
fn periodic_vectors(v: &mut Vec<Vec<String>>) {
    for spec in [
        "omega=1:2:3",
        "omega=0:2:log",
        "omega=1e-300:1",
        "omega=-1:1",
        "omega=1:1",
        "mu=-1e308:1e308",
        "gamma=nan:1",
        "beta=1:2",
        "omega=5e-324:1:log",
        "delta=15:1e300",
        "",
    ] {
        v.push(vec!["continue".into(), format!("--param={spec}")]);
        v.push(vec![
            "orbit-diagram".into(),
            format!("--param={spec}:3"),
            "--record=2".into(),
            "--discard=1".into(),
        ]);
    }
    for val in VALUES {
        v.push(vec![
            "continue".into(),
            "--param=mu=0.07:0.08".into(),
            format!("--subharmonic={val}"),
        ]);
        v.push(vec![
            "frequency-response".into(),
            format!("--omega-range={val}:10"),
        ]);
        v.push(vec![
            "frequency-response".into(),
            format!("--omega-range=1:{val}"),
        ]);
        for flag in ["--record", "--discard", "--lyapunov"] {
            v.push(vec![
                "orbit-diagram".into(),
                "--param=omega=5:6:3".into(),
                "--record=4".into(),
                "--discard=2".into(),
                format!("{flag}={val}"),
            ]);
        }
    }
    v.push(vec![
        "continue".into(),
        "--param=omega=1:2".into(),
        "--omega=3".into(),
    ]);
    v.push(vec!["frequency-response".into(), "--omega=3".into()]);
    for val in VALUES {
        v.push(vec![
            "physical".into(),
            "--frequency-response".into(),
            format!("--hz={val}:100"),
        ]);
        v.push(vec![
            "lyapunov-map".into(),
            "--param=omega=5:6:2".into(),
            "--out=l.csv".into(),
            "--discard=2".into(),
            "--record=2".into(),
            format!("--periods={val}"),
        ]);
    }
    v.push(vec!["physical".into(), "--out=x.csv".into()]);
    v.push(vec!["physical".into(), "--hz=1:2".into()]);
    v.push(vec![
        "lyapunov-map".into(),
        "--param=omega=1e-9:1e-8:2".into(),
        "--out=l.csv".into(),
    ]);
    v.push(vec![
        "frequency-response".into(),
        "--omega-range=5:6".into(),
        "--plot=f.txt".into(),
    ]);
}

/// Bad shards, cluster settings and merges.
fn shard_vectors(v: &mut Vec<Vec<String>>) {
    let sweep = |extra: &[String]| {
        let mut a: Vec<String> = ["sweep", "--param", "gamma=1:2:3", "--out", "s.csv"]
            .map(String::from)
            .to_vec();
        a.extend(extra.iter().cloned());
        a
    };
    for k in [
        "",
        "1",
        "2/2",
        "-1/2",
        "1/-2",
        "a/b",
        "0/0",
        "1e3/2",
        "0/99999999999999999999",
        "0/4",
    ] {
        v.push(sweep(&[format!("--shard={k}")]));
    }
    for val in VALUES.iter().chain(&["4", "3"]) {
        v.push(sweep(&[format!("--slurm={val}")]));
        v.push(sweep(&[
            "--slurm=2".into(),
            format!("--cpus-per-task={val}"),
        ]));
        v.push(sweep(&["--slurm=2".into(), format!("--time={val}")]));
        v.push(sweep(&["--slurm=2".into(), format!("--partition={val}")]));
    }
    for files in [
        &[""][..],
        &["nope.csv"],
        &["/"],
        &["."],
        &["pre-dir"],
        &["a.shard-0-of-1.csv"],
        &["pre-dir", "--out=x.csv"],
    ] {
        let mut a = vec!["merge".to_string()];
        a.extend(files.iter().map(|s| s.to_string()));
        v.push(a);
    }
}

/// Pushes `base` followed by `flag=value` for every hostile value (a `flag` without `=` is a
/// positional argument: the value stands alone).
fn each_value(v: &mut Vec<Vec<String>>, base: &[&str], flag: &str, values: &[&str]) {
    for val in values {
        let mut a: Vec<String> = base.iter().map(|s| s.to_string()).collect();
        a.push(if flag.is_empty() {
            val.to_string()
        } else {
            format!("{flag}={val}")
        });
        v.push(a);
    }
}

/// The commands added after the generator was first written: model, periodic, continue2,
/// boundary, card, control and robust, each with every hostile value in its own flags and
/// malformed specs, names and files.
fn newer_command_vectors(v: &mut Vec<Vec<String>>) {
    for flag in ["--alpha", "--omega", "--delta"] {
        each_value(v, &["model", "--json"], flag, &VALUES);
    }
    for flag in ["--subharmonic", "--omega", "--gamma", "--rtol"] {
        each_value(v, &["periodic", "--lyapunov"], flag, &VALUES);
    }
    each_value(
        v,
        &["periodic"],
        "--out",
        &["x.txt", "dir/", "missing/x.csv", "."],
    );
    let c2 = ["continue2", "--gamma=10", "--param=omega=4:14:log"];
    let specs = [
        "mu=-5:5:3",
        "mu=5:-5",
        "mu=nan:1",
        "omega=1:2",
        "beta=1:2",
        "mu=-1e308:1e308",
        "delta=0:1:log",
        "",
    ];
    each_value(v, &c2, "--param", &specs);
    let c2pd = [
        "continue2",
        "--gamma=10",
        "--param=omega=4:14:log",
        "--param=mu=-5:5",
    ];
    for (flag, values) in [
        (
            "--from",
            &[
                "",
                "nope",
                "fold:0",
                "fold:-1",
                "fold:x",
                "period-doubling:99999999999999999999",
            ][..],
        ),
        (
            "--restart",
            &["", "nope.csv:0", "x", "/:1", ".:0", "f.csv:-1"][..],
        ),
        ("--subharmonic", &VALUES[..]),
        ("--out", &["x.txt", "dir/", "."][..]),
        ("--plot", &["x.txt", "missing/x.svg"][..]),
    ] {
        each_value(v, &c2pd, flag, values);
    }
    let bd = [
        "boundary",
        "--kinds=both-folds-in-range",
        "--param=gamma=0.01:1:log",
    ];
    each_value(v, &bd, "--param", &specs);
    let bd2 = [
        "boundary",
        "--param=gamma=0.01:1:log",
        "--param=delta=1:30:log",
    ];
    each_value(v, &bd2, "--step", &VALUES);
    each_value(
        v,
        &bd2,
        "--kinds",
        &["", "nope", "predicted,nope", "PREDICTED", ",,"],
    );
    card_control_robust_vectors(v);
}

/// Malformed card names and files, for every command that reads a card.
const CARDS: [&str; 7] = [
    "",
    "nope",
    "CSF-99-50",
    "/",
    "/dev/zero",
    "x.toml#",
    "x.toml#nope",
];

/// The commands of the real-drives round: card, control and robust.
fn card_control_robust_vectors(v: &mut Vec<Vec<String>>) {
    let cards = CARDS;
    for sub in ["show", "check", "map"] {
        each_value(v, &["card", sub], "", &cards);
    }
    each_value(v, &["card", "new"], "", &["", "a/b", "csf-20-50"]);
    each_value(v, &["card", "new", "mine", "--from"], "", &cards);
    each_value(
        v,
        &["card", "new", "mine"],
        "--out",
        &["x.txt", "dir/", "."],
    );
    for flag in ["--points", "--t-am-max", "--damping"] {
        each_value(v, &["card", "map", "csf-20-50"], flag, &VALUES);
    }
    each_value(
        v,
        &["card", "map", "csf-20-50"],
        "--hz",
        &["0:1", "1:0", "nan:2", "1e-300:1e300", "x"],
    );
    each_value(
        v,
        &["card", "check", "csf-20-50", "--design"],
        "--damping",
        &VALUES,
    );
    for (flag, base) in [
        ("--gain", &["control", "vstiffness", "--spread=0"][..]),
        (
            "--ww",
            &["control", "washout", "--gain=1", "--spread=0"][..],
        ),
        (
            "--rel-tol",
            &["control", "vstiffness", "--spread=0", "--gamma=1"][..],
        ),
        ("--spread", &["control", "vstiffness", "--gamma=1"][..]),
    ] {
        each_value(v, base, flag, &VALUES);
    }
    each_value(
        v,
        &["control", "--spread=0"],
        "",
        &["pid", "", "VSTIFFNESS"],
    );
    each_value(v, &["control", "vstiffness", "--gain=1"], "--card", &cards);
    robust_vectors(v);
}

/// Bad spreads, sample counts, levels and files of `robust`.
fn robust_vectors(v: &mut Vec<Vec<String>>) {
    let rb = ["robust", "--samples=16", "--no-worst"];
    each_value(
        v,
        &rb,
        "--tolerance",
        &[
            "gamma=±10%",
            "gamma=±1e300%",
            "gamma=normal:nan",
            "gamma=normal:-1",
            "beta=±10%",
            "gamma",
            "gamma=",
            "gamma=uniform:2:1",
            "",
        ],
    );
    let rbg = ["robust", "--no-worst", "--tolerance=gamma=±10%"];
    for flag in [
        "--samples",
        "--level",
        "--width",
        "--seed",
        "--sobol",
        "--importance",
    ] {
        each_value(v, &rbg, flag, &VALUES);
    }
    each_value(v, &rbg, "--sampler", &["", "nope", "SOBOL"]);
    each_value(v, &rbg, "--shard", &["", "2/2", "a/b", "0/0"]);
    each_value(v, &rbg, "--out", &["x.txt", "dir/", "."]);
    each_value(
        v,
        &["robust", "--no-worst", "--samples=16"],
        "--card",
        &CARDS,
    );
}

/// Bad output paths for each command that writes a file.
fn output_vectors(v: &mut Vec<Vec<String>>) {
    for out in [
        "dir.csv/",
        "x.CSV",
        "x.JSON",
        "x.txt",
        "",
        "pre-dir",
        "missing/x.csv",
        ".",
        "..",
        "/",
    ] {
        for cmd in [
            &["simulate", "--t-end", "5"][..],
            &["equilibria", "--points", "5"][..],
            &["bursts"][..],
        ] {
            let mut a: Vec<String> = cmd.iter().map(|s| s.to_string()).collect();
            a.push(format!("--out={out}"));
            v.push(a);
        }
        v.push(vec![
            "plot".into(),
            "slope".into(),
            format!("--out={}", out.replace("csv", "png").replace("json", "svg")),
        ]);
    }
}

/// The argument vectors: each subcommand with each flag set to each hostile value, plus bad
/// paths and specs.
fn hostile_vectors() -> Vec<Vec<String>> {
    let mut v: Vec<Vec<String>> = Vec::new();
    let flags: [(&str, &[&str], &str); 19] = [
        ("simulate", &["--summary"], "--gamma"),
        ("simulate", &["--summary"], "--alpha"),
        ("simulate", &["--summary"], "--omega"),
        ("simulate", &["--summary"], "--delta"),
        ("simulate", &["--summary"], "--dt"),
        ("simulate", &["--summary"], "--t-end"),
        ("simulate", &["--summary"], "--rtol"),
        ("simulate", &["--summary"], "--atol"),
        ("simulate", &["--summary"], "--x0"),
        ("equilibria", &["--points", "50"], "--mu"),
        ("analyze", &["--no-response"], "--eps"),
        ("bifurcation", &["--points", "20"], "--gamma-min"),
        ("bursts", &[], "--discard"),
        ("physical", &[], "--k2"),
        ("physical", &[], "--backlash"),
        ("physical", &[], "--j-in"),
        ("physical", &["--simulate", "--summary"], "--t-end"),
        (
            "physical",
            &["--simulate", "--summary", "--t-end", "0.5"],
            "--dt",
        ),
        ("table", &["--json"], "--gamma"),
    ];
    for (cmd, extra, flag) in flags {
        for val in VALUES {
            let mut a: Vec<String> = vec![cmd.into()];
            a.extend(extra.iter().map(|s| s.to_string()));
            a.push(format!("{flag}={val}"));
            v.push(a);
        }
    }
    range_and_spec_vectors(&mut v);
    periodic_vectors(&mut v);
    output_vectors(&mut v);
    for kind in ["", "nope", "MAP", "slope --gamma 5", "map --delta=3"] {
        let mut a = vec!["plot".to_string()];
        a.extend(kind.split(' ').filter(|s| !s.is_empty()).map(String::from));
        a.push("--out=f.svg".into());
        v.push(a);
    }
    for p in ["nope", "PAPER", "paper-g30", ""] {
        v.push(vec![
            "simulate".into(),
            "--summary".into(),
            format!("--preset={p}"),
        ]);
    }
    shard_vectors(&mut v);
    newer_command_vectors(&mut v);
    for bad in [
        "--bind=nope",
        "--bind=",
        "--port=-1",
        "--port=70000",
        "--port=x",
    ] {
        v.push(vec!["serve".into(), bad.into()]);
    }
    for d in ["csf-20-50", "CSF-99-50", ""] {
        v.push(vec!["physical".into(), format!("--drive={d}")]);
    }
    v
}

#[test]
fn hostile_inputs_never_panic_nor_leave_files() {
    let vectors = hostile_vectors();
    assert!(vectors.len() >= 500, "only {} vectors", vectors.len());
    let mut refused = 0;
    for args in &vectors {
        let code = check_run(args);
        if code == 2 {
            refused += 1;
        }
    }
    eprintln!(
        "ran {} hostile argument vectors, {refused} refused",
        vectors.len()
    );
    // most of them are bad input
    assert!(
        refused * 2 > vectors.len(),
        "{refused} of {}",
        vectors.len()
    );
}

/// 10,000 random combinations of the same pieces (run with `cargo test --release -- --ignored
/// many_hostile`).
#[test]
#[ignore]
fn many_hostile_inputs() {
    let pieces = hostile_vectors();
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut next = |n: usize| {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state % n as u64) as usize
    };
    let mut count = 0;
    for _ in 0..10_000 {
        // a base vector with one or two more flags taken from other vectors of the same command
        let base = &pieces[next(pieces.len())];
        let mut args = base.clone();
        for _ in 0..next(3) {
            let other = &pieces[next(pieces.len())];
            if other[0] == args[0]
                && let Some(last) = other.last()
            {
                args.push(last.clone());
            }
        }
        check_run(&args);
        count += 1;
    }
    eprintln!("ran {count} generated hostile argument vectors");
}
