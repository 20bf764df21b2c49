//! A hostile user: messages that name the user's value, and one regression test per defect of
//! the hardening and edges issues (the generated inputs are in `hostile.rs`).

use crate::common::hdgear;
use std::path::Path;
use std::process::Command;
use std::time::Duration;

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
        .stderr(predicates::str::contains("figures/slope.png"))
        // the library says what to do, the command names its flags
        .stderr(predicates::str::contains(
            "choose another directory, or let the report overwrite them (--out DIR, or --force)",
        ));
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
        (&["simulate", "--atol=0"][..], "atol = 0:"),
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
    // a note on the set, not a warning (the study's own set is one)
    assert!(err.starts_with("note: alpha*eps"), "{err}");
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
    // a start beyond the blow-up bound itself is bad input, not a failed computation (found by
    // the Python package's hostile pass: it came back as a RuntimeError)
    for x0 in ["--x0=1e300", "--v0=-1e300"] {
        let o = run(&["simulate", x0, "--t-end", "10", "--summary"]);
        assert_eq!(o.status.code(), Some(2), "{}", err(&o));
        assert!(err(&o).contains("blow-up bound"), "{}", err(&o));
    }
    // so is an atol whose error norm overflows (it used to fail as a step-size underflow at
    // t = 0, exit 1); the least one accepted runs
    let o = run(&["simulate", "--atol=1e-200", "--t-end", "10", "--summary"]);
    assert_eq!(o.status.code(), Some(2), "{}", err(&o));
    assert!(err(&o).contains("≥ 1e-100"), "{}", err(&o));
    let o = run(&["simulate", "--atol=1e-100", "--t-end", "10", "--summary"]);
    assert_eq!(o.status.code(), Some(0), "{}", err(&o));
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

/// One run in `dir` under a file-size limit (`ulimit -f blocks`).
fn run_with_file_limit(dir: &Path, blocks: u32, args: &[&str]) -> std::process::Output {
    let bin = assert_cmd::cargo::cargo_bin("hdgear");
    Command::new("bash")
        .current_dir(dir)
        .arg("-c")
        .arg(format!(
            "ulimit -f {blocks} && exec '{}' {}",
            bin.display(),
            args.join(" ")
        ))
        .output()
        .unwrap()
}

/// A file-size limit (`ulimit -f`, SIGXFSZ) is a full disk: the write past it fails, the run
/// says so in one line and exits 2, and neither the output nor its temporary is left.
#[test]
fn a_file_size_limit_leaves_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let o = run_with_file_limit(
        dir.path(),
        4,
        &[
            "simulate", "--t-end", "2000", "--dt", "0.01", "--out", "t.csv",
        ],
    );
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
    let sweep = ["sweep", "--param", "gamma=0.1:30:60:log", "--quiet"];
    let o = run_with_file_limit(dir.path(), 2, &[&sweep[..], &["--out", "s.csv"]].concat());
    assert_eq!(o.status.code(), Some(2), "{}", err(&o));
    let e = err(&o);
    assert!(
        e.contains("kept in s.csv.partial: rerun the same command with --resume"),
        "{e}"
    );
    // the failure first, then what to do about it
    let at = |part: &str| e.find(part).unwrap_or_else(|| panic!("no '{part}' in {e}"));
    assert!(at("writing ") < at("kept in"), "{e}");
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

/// A run that writes rows and a figure, stopped by a full disk at the figure (a file-size limit
/// the small CSV fits in and the PNG does not), leaves neither: the rows are made final only
/// after the figure is written. Each command writing both through its own path is tried.
#[test]
fn rows_and_figure_are_left_together_or_not_at_all() {
    for args in [
        &[
            "lyapunov-map",
            "--gamma",
            "10",
            "--param",
            "omega=4:6:3",
            "--param",
            "delta=10:20:2",
            "--discard",
            "5",
            "--periods",
            "5",
            "--out",
            "l.csv",
            "--plot",
            "l.png",
        ][..],
        &[
            "orbit-diagram",
            "--gamma",
            "10",
            "--param",
            "omega=4:6:3",
            "--discard",
            "5",
            "--out",
            "d.csv",
            "--plot",
            "d.png",
        ],
        &[
            "boundary",
            "--param",
            "omega=1e-4:20:log",
            "--param",
            "delta=0.5:40:log",
            "--kinds",
            "predicted",
            "--out",
            "b.csv",
            "--plot",
            "b.png",
        ],
    ] {
        let dir = tempfile::tempdir().unwrap();
        let o = run_with_file_limit(dir.path(), 16, args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", err(&o));
        // the figure's failure in words, not the drawing library's debug form
        assert!(
            err(&o).contains("File too large") && !err(&o).contains("Custom {"),
            "{args:?}: {}",
            err(&o)
        );
        assert_eq!(
            crate::common::files_in(dir.path()),
            Vec::<String>::new(),
            "{args:?}: {}",
            err(&o)
        );
    }
}
