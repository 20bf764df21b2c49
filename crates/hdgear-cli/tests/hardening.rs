//! A hostile user: generated bad inputs over every subcommand, messages that name the
//! user's value, and one regression test per defect of the hardening and edges issues.

use crate::common::{hdgear, walk};
use std::path::Path;
use std::process::Command;
use std::time::Duration;

/// Hostile values for a numeric flag.
const VALUES: [&str; 13] = [
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
    assert!(vectors.len() >= 300, "only {} vectors", vectors.len());
    let mut refused = 0;
    for args in &vectors {
        let code = check_run(args);
        if code == 2 {
            refused += 1;
        }
    }
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

#[test]
fn report_never_overwrites_foreign_files() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("r");
    std::fs::create_dir_all(out.join("figures")).unwrap();
    std::fs::write(out.join("figures/slope.png"), b"mine").unwrap();
    hdgear()
        .args(["report", "--quiet", "--out"])
        .arg(&out)
        .assert()
        .code(2)
        .stderr(predicates::str::contains("figures/slope.png"));
    assert_eq!(
        std::fs::read(out.join("figures/slope.png")).unwrap(),
        b"mine"
    );
}

#[test]
fn messages_name_the_users_value_readably() {
    for (args, needle) in [
        (&["simulate", "--rtol=1e-300"][..], "rtol = 1e-300"),
        (&["analyze", "--alpha=1e-320"][..], "alpha = 1e-320"),
        (&["physical", "--backlash=1e308"][..], "backlash = 1e308"),
        (
            &["sweep", "--param", "mu=-1e308:1e308:3", "--out", "s.csv"][..],
            "mu = -1e308",
        ),
        (&["simulate", "--atol=0"][..], "atol = 0.0"),
        (
            &["plot", "slope", "--gamma", "5", "--out", "f.svg"][..],
            "--gamma does not apply",
        ),
        (
            &["bifurcation", "--gamma", "5", "--gamma-min", "0.001"][..],
            "--gamma does not apply",
        ),
        (
            &["simulate", "--config", "/dev/zero"][..],
            "/dev/zero: is not a regular file",
        ),
        (
            &["plot", "slope", "--out", "missing/x.png"][..],
            "missing/x.png",
        ),
        (&["simulate", "--out", "."][..], "'.'"),
        (
            &["bursts", "--window-periods", "1000000"][..],
            "integration steps",
        ),
        (
            &["physical", "--simulate", "--t-end", "1e9", "--summary"][..],
            "integration steps",
        ),
    ] {
        let dir = tempfile::tempdir().unwrap();
        let out = hdgear()
            .current_dir(dir.path())
            .args(args)
            .assert()
            .code(2)
            .get_output()
            .clone();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(err.len() < 400, "{args:?}: a long message: {err}");
    }
    // defaults are shown as written, not expanded
    let help = hdgear().args(["simulate", "--help"]).output().unwrap();
    assert!(String::from_utf8_lossy(&help.stdout).contains("[default: 1e-10]"));
}

#[test]
fn small_fixes_from_the_hardening_issue() {
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| {
        hdgear()
            .current_dir(dir.path())
            .args(args)
            .output()
            .unwrap()
    };
    // --summary writes no rows, so the row cap does not apply
    let o = run(&[
        "simulate",
        "--t-end",
        "1e7",
        "--dt",
        "0.01",
        "--summary",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    // upper-case extensions
    assert!(
        run(&["plot", "slope", "--out", "x.PNG", "--quiet"])
            .status
            .success()
    );
    assert!(
        run(&["equilibria", "--points", "5", "--out", "x.CSV", "--quiet"])
            .status
            .success()
    );
    // a scenario with the wrong table
    std::fs::write(dir.path().join("ph.toml"), "[physical]\nk1 = 5.0\n").unwrap();
    let o = run(&["simulate", "--config", "ph.toml"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no [params] table"));
    // presets by any case
    assert!(
        run(&["simulate", "--preset", "PAPER-G1", "--summary", "--quiet"])
            .status
            .success()
    );
    // the α·ε warning: once, short, silenced by --quiet
    let o = run(&["analyze", "--no-response"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(err.matches("alpha*eps").count(), 1, "{err}");
    assert!(err.lines().next().unwrap().len() < 160, "{err}");
    let o = run(&["analyze", "--no-response", "--quiet"]);
    assert!(o.stderr.is_empty());
    // plain `physical` prints the catalogue fit and the assumptions, no JSON fragments
    let o = run(&["physical", "--quiet"]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("twist error") && text.contains("assumed:"),
        "{text}"
    );
    assert!(!text.contains('{'), "{text}");
    // ω not slow: analyze says so, and forces no study word
    let o = run(&["analyze", "--omega", "0.2", "--gamma", "0.01", "--json"]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("not slow against the fast subsystem"));
    let doc: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(doc["classification"]["mode"], "not-fast-slow");
    assert_eq!(doc["classification"]["fast_slow_domain"], false);
    assert_eq!(doc["classification"]["bursting"], true);
    // a-range beyond [-1, 1] is warned about
    let o = run(&["equilibria", "--points", "5", "--a-range=-2:2"]);
    assert!(String::from_utf8_lossy(&o.stderr).contains("beyond [-1, 1]"));
}

/// One run in `dir`, with a minute's timeout.
fn run_in(dir: &Path, args: &[&str]) -> std::process::Output {
    hdgear()
        .current_dir(dir)
        .args(args)
        .timeout(Duration::from_secs(60))
        .output()
        .unwrap()
}

/// A run's standard error as text.
fn err(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn defects_of_the_edges_issue() {
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| run_in(dir.path(), args);
    // --threads is bounded, on every command that has it, and so is RAYON_NUM_THREADS
    for cmd in [
        &["sweep", "--param", "gamma=1:2:3", "--out", "t.csv"][..],
        &["report", "--out", "r"],
    ] {
        let o = run(&[cmd, &["--threads", "100000"]].concat());
        assert_eq!(o.status.code(), Some(2), "{cmd:?}: {}", err(&o));
        assert!(
            err(&o).contains("--threads = 100000: at most 1024"),
            "{}",
            err(&o)
        );
    }
    let o = hdgear()
        .current_dir(dir.path())
        .args(["sweep", "--param", "gamma=1:2:3", "--out", "t.csv"])
        .env("RAYON_NUM_THREADS", "100000")
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", err(&o));
    assert!(
        err(&o).contains("RAYON_NUM_THREADS '100000': at most 1024"),
        "{}",
        err(&o)
    );
    assert!(!dir.path().join("t.csv").exists());
    // merge refuses to write over one of its inputs, which stays as it was
    let o = run(&[
        "sweep",
        "--param",
        "gamma=1:2:4",
        "--shard",
        "0/2",
        "--out",
        "m.csv",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", err(&o));
    let o = run(&[
        "sweep",
        "--param",
        "gamma=1:2:4",
        "--shard",
        "1/2",
        "--out",
        "m.csv",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", err(&o));
    let shard = dir.path().join("m.shard-0-of-2.csv");
    let before = std::fs::read(&shard).unwrap();
    let o = run(&[
        "merge",
        "m.shard-0-of-2.csv",
        "m.shard-1-of-2.csv",
        "--out",
        "m.shard-0-of-2.csv",
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", err(&o));
    assert!(err(&o).contains("is the input shard"), "{}", err(&o));
    assert_eq!(std::fs::read(&shard).unwrap(), before);
}

#[test]
fn fifos_are_refused_as_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| run_in(dir.path(), args);
    // a FIFO as a scenario or a merge input is refused at once instead of blocking
    let fifo = dir.path().join("f.toml");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    let o = run(&["simulate", "--config", "f.toml", "--summary"]);
    assert_eq!(o.status.code(), Some(2), "{}", err(&o));
    assert!(err(&o).contains("not a regular file"), "{}", err(&o));
    let o = run(&["merge", "f.toml", "--out", "x.csv"]);
    assert_eq!(o.status.code(), Some(2), "{}", err(&o));
    assert!(err(&o).contains("not a regular file"), "{}", err(&o));
    // a regular file too large to be a scenario is refused by its size (what /dev/zero met
    // before devices were refused by kind)
    std::fs::write(dir.path().join("big.toml"), vec![b'#'; (1 << 20) + 1]).unwrap();
    let o = run(&["simulate", "--config", "big.toml", "--summary"]);
    assert_eq!(o.status.code(), Some(2), "{}", err(&o));
    assert!(err(&o).contains("larger than"), "{}", err(&o));
}

#[test]
fn blow_ups_and_tolerance_limited_verdicts_say_so() {
    let dir = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| run_in(dir.path(), args);
    // a blow-up is reported where it happened, not at the end time
    let o = run(&["simulate", "--x0", "1e50", "--t-end", "100", "--summary"]);
    assert_ne!(o.status.code(), Some(0));
    assert!(err(&o).contains("blew up at t = 0.0"), "{}", err(&o));
    // a verdict decided by the tolerance's noise says so, with the rtol to use
    let near = [
        "analyze",
        "--alpha=7.277",
        "--gamma=0.9367",
        "--eps=0.8274",
        "--mu=0.1801",
        "--delta=25.84",
        "--omega=0.001949",
    ];
    let o = run(&[&near[..], &["--rtol", "1e-6", "--atol", "1e-6"]].concat());
    assert!(o.status.success(), "{}", err(&o));
    let text = err(&o);
    assert!(
        text.contains("noise floor") && text.contains("rerun with --rtol"),
        "{text}"
    );
    assert!(!err(&run(&near)).contains("noise floor"));
}

/// A file-size limit (`ulimit -f`, SIGXFSZ) is a full disk: the write past it fails, the run
/// says so in one line and exits 2, and neither the output nor its temporary is left.
#[test]
fn a_file_size_limit_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let bin = assert_cmd::cargo::cargo_bin("hdgear");
    let o = Command::new("bash")
        .current_dir(dir.path())
        .arg("-c")
        .arg(format!(
            "ulimit -f 4 && exec '{}' simulate --t-end 2000 --dt 0.01 --out t.csv",
            bin.display()
        ))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", err(&o));
    let e = err(&o);
    let errors: Vec<&str> = e.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "{e}");
    assert!(
        errors[0].contains("t.csv") && !e.contains("panicked"),
        "{e}"
    );
    assert_eq!(crate::common::files_in(dir.path()), Vec::<String>::new());
}

/// A sweep stopped by a file-size limit says where its finished rows are and how to resume
/// (exit 2); `--resume` without the limit then writes the same file as an uninterrupted sweep.
#[test]
fn a_sweep_stopped_by_a_file_size_limit_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let bin = assert_cmd::cargo::cargo_bin("hdgear");
    let sweep = ["sweep", "--param", "gamma=0.1:30:60:log", "--quiet"];
    let o = Command::new("bash")
        .current_dir(dir.path())
        .arg("-c")
        .arg(format!(
            "ulimit -f 2 && exec '{}' {} --out s.csv",
            bin.display(),
            sweep.join(" ")
        ))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", err(&o));
    assert!(
        err(&o).contains("kept in s.csv.partial: rerun the same command with --resume"),
        "{}",
        err(&o)
    );
    let resumed = run_in(
        dir.path(),
        &[&sweep[..], &["--out", "s.csv", "--resume"]].concat(),
    );
    assert!(resumed.status.success(), "{}", err(&resumed));
    let whole = run_in(dir.path(), &[&sweep[..], &["--out", "w.csv"]].concat());
    assert!(whole.status.success(), "{}", err(&whole));
    let read = |f: &str| std::fs::read(dir.path().join(f)).unwrap();
    assert_eq!(read("s.csv"), read("w.csv"));
}
