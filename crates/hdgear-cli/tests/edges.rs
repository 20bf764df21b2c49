//! The edges issue, third pass: one regression test per defect (counts beyond what the machine
//! can hold, outputs that would overwrite their own inputs, messages that name the wrong thing).

use crate::common::hdgear;
use std::path::Path;
use std::time::{Duration, Instant};

/// Runs `args` in `dir` and returns its exit code and standard error (a run that hangs past the
/// timeout fails the test).
fn run_in(dir: &Path, args: &[&str]) -> (Option<i32>, String) {
    let o = hdgear()
        .current_dir(dir)
        .args(args)
        .timeout(Duration::from_secs(30))
        .output()
        .unwrap();
    (
        o.status.code(),
        String::from_utf8_lossy(&o.stderr).into_owned(),
    )
}

#[test]
fn counts_beyond_what_can_be_held_are_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    for (args, needle) in [
        (
            &[
                "orbit-diagram",
                "--param",
                "omega=7:9:1000000000000",
                "--out",
                "d.csv",
            ][..],
            "values = 1000000000000: at most 100000",
        ),
        (
            &[
                "orbit-diagram",
                "--param",
                "omega=7:9:100000000",
                "--out",
                "d.csv",
            ],
            "values = 100000000: at most 100000",
        ),
        (
            &[
                "robust",
                "--tolerance",
                "gamma=±10%",
                "--sobol",
                "1000000000000",
            ],
            "sobol = 1000000000000: N(k + 2) runs",
        ),
        (
            &[
                "robust",
                "--tolerance",
                "gamma=±10%",
                "--sobol",
                "18446744073709551615",
            ],
            "sobol = 1.8446744073709552e19",
        ),
    ] {
        let start = Instant::now();
        let (code, err) = run_in(dir.path(), args);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(start.elapsed() < Duration::from_secs(10), "{args:?}");
    }
    assert!(!dir.path().join("d.csv").exists());
}

#[test]
fn outputs_never_overwrite_their_own_inputs() {
    let dir = tempfile::tempdir().unwrap();
    // robust parts: refused before they are read, so any text stands for one
    for name in ["part-0.json", "part-1.json"] {
        std::fs::write(dir.path().join(name), "{}\n").unwrap();
    }
    let (code, err) = run_in(
        dir.path(),
        &[
            "merge",
            "part-0.json",
            "part-1.json",
            "--out",
            "part-0.json",
        ],
    );
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("is the input part part-0.json"), "{err}");
    assert_eq!(
        std::fs::read_to_string(dir.path().join("part-0.json")).unwrap(),
        "{}\n"
    );
    // continue2 --restart FILE:ROW with --out FILE
    std::fs::write(dir.path().join("curves.csv"), "mine\n").unwrap();
    let (code, err) = run_in(
        dir.path(),
        &[
            "continue2",
            "--param",
            "omega=0.3:20:log",
            "--param",
            "delta=0.5:40:log",
            "--restart",
            "curves.csv:60",
            "--out",
            "./curves.csv",
        ],
    );
    assert_eq!(code, Some(2), "{err}");
    assert!(err.contains("is the --restart file curves.csv"), "{err}");
    assert_eq!(
        std::fs::read_to_string(dir.path().join("curves.csv")).unwrap(),
        "mine\n"
    );
}

#[test]
fn sampling_refusals_name_the_option_that_asked() {
    let dir = tempfile::tempdir().unwrap();
    let base = ["robust", "--card", "CSF-20-50", "--no-worst"];
    for (extra, needle) in [
        (
            &["--samples", "16", "--importance", "5000000000"][..],
            "importance = 5000000000: the sampler's sequence has fewer points",
        ),
        (
            &["--samples", "5000000000", "--shard", "1/2"],
            "samples = 5000000000: the sampler's sequence has fewer points",
        ),
    ] {
        let args = [&base[..], extra].concat();
        let (code, err) = run_in(dir.path(), &args);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

#[test]
fn spreads_that_leave_the_parameters_domain_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    for (args, needle) in [
        (
            &["robust", "--card", "CSF-20-50", "--tolerance", "k1=±1000%"][..],
            "invalid tolerance 'k1': its spread reaches -",
        ),
        (
            &[
                "robust",
                "--gamma",
                "1",
                "--tolerance",
                "gamma=1e300..1e301",
            ],
            "invalid tolerance 'gamma': its spread reaches 1e300",
        ),
        (
            &[
                "robust",
                "--gamma",
                "1",
                "--tolerance",
                "gamma=lognormal:1e300%",
            ],
            "invalid tolerance 'gamma': its spread reaches",
        ),
    ] {
        let (code, err) = run_in(dir.path(), args);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!err.contains("NaN"), "{args:?}: {err}");
    }
}

#[test]
fn terms_too_fast_for_the_step_budget_are_refused_at_once() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("ms.toml"),
        "[params]\ngamma = 1.0\n[multisine]\nmsw = 1e6\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("ke.toml"),
        "[params]\ngamma = 1.0\n[kinematic]\nwin = 1e9\n",
    )
    .unwrap();
    std::fs::write(
        dir.path().join("di.toml"),
        "[params]\ngamma = 1.0\n[dither]\nwd = 1e9\n",
    )
    .unwrap();
    for (args, needle) in [
        (
            &["control", "vdamping", "--gain", "1e6"][..],
            "(its vdamping term)",
        ),
        (
            &["control", "washout", "--gain", "1e6", "--ww", "1e6"],
            "(its washout term)",
        ),
        (
            &[
                "control", "dither", "--wd", "1e6", "--gain", "1", "--spread", "0",
            ],
            "(its dither term)",
        ),
        (&["bursts", "--config", "ms.toml"], "(its multisine term)"),
        (
            &["simulate", "--config", "ke.toml", "--summary"],
            "(its kinematic term)",
        ),
        (&["bursts", "--config", "di.toml"], "(its dither term)"),
    ] {
        let start = Instant::now();
        let (code, err) = run_in(dir.path(), args);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert!(
            err.contains(needle) && err.contains("fastest rate"),
            "{args:?}: {err}"
        );
        assert!(start.elapsed() < Duration::from_secs(10), "{args:?}");
    }
}

/// Requests whose answer is known before any long computation: the delayed feedback at the
/// default τ_d = 1 is unstable before any gain removes the bursts (its characteristic roots say
/// so; the search used to simulate unstable loops up to the largest gain, for minutes), and a
/// two-parameter box down to ω = 1e-6 holds orbits of 6.3e6 time units (hours to trace). Each
/// is answered within the helper's timeout, with exit 2 and a line that says why.
#[test]
fn answers_known_in_advance_come_at_once() {
    let dir = tempfile::tempdir().unwrap();
    for (args, needle) in [
        (
            &["control", "delay"][..],
            "no gain of delay removes the bursts: with τ_d = 1 the closed loop is unstable from K",
        ),
        (
            &[
                "continue2",
                "--param",
                "omega=1e-6:1e6:log",
                "--param",
                "delta=1e-6:1e6:log",
            ],
            "invalid parameter box 'ω down to 1e-6': its longest orbit lasts 6.283e6 time units",
        ),
    ] {
        let (code, err) = run_in(dir.path(), args);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert!(err.contains(needle), "{args:?}: {err}");
    }
}

/// clap's own refusals (an unknown flag, a malformed number, a missing argument, a misspelt
/// command) are one line naming what the user wrote, as every other refusal, with exit code 2;
/// help is still printed whole.
#[test]
fn argument_refusals_are_one_line() {
    let dir = tempfile::tempdir().unwrap();
    for (args, needle) in [
        (&["lyapunov-map", "--lyapunov"][..], "'--lyapunov'"),
        (&["simulate", "--gamma", "abc"][..], "'abc'"),
        (&["plot"][..], "--out <FILE>"),
        (&["simulat"][..], "'simulate'"),
    ] {
        let (code, err) = run_in(dir.path(), args);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(
            err.starts_with("error: ") && err.contains(needle),
            "{args:?}: {err}"
        );
    }
    let help = hdgear().args(["simulate", "--help"]).output().unwrap();
    assert_eq!(help.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&help.stdout).contains("Usage: hdgear simulate"));
}

/// A long two-parameter trace shows its progress on a terminal: under `script` (a pseudo-
/// terminal) the spinner's count of traced points rises while the trace runs; without a
/// terminal nothing but the summary is printed.
#[test]
fn a_long_trace_shows_its_progress_on_a_terminal() {
    let bin = assert_cmd::cargo::cargo_bin("hdgear");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("c.csv");
    let args = format!(
        "{} continue2 --param omega=1e-4:1e3:log --param delta=1e-3:1e4:log --out {}",
        bin.display(),
        out.display()
    );
    let Ok(run) = std::process::Command::new("script")
        .args(["-qec", &args, "/dev/null"])
        .output()
    else {
        assert!(
            std::env::var_os("CI").is_none(),
            "no `script` (util-linux) to give the run a terminal"
        );
        return;
    };
    assert!(run.status.success(), "{run:?}");
    let tty = String::from_utf8_lossy(&run.stdout);
    let counts: Vec<u64> = tty
        .split(['\r', '\n'])
        .filter_map(|l| l.split("continue2: ").nth(1))
        .filter_map(|l| l.split(' ').next()?.parse().ok())
        .collect();
    assert!(
        counts.windows(2).all(|w| w[0] <= w[1]) && counts.iter().any(|&c| c > 100),
        "{counts:?}"
    );
    let plain = hdgear()
        .args(["continue2", "--param", "omega=1e-4:1e3:log"])
        .args(["--param", "delta=1e-3:1e4:log", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(plain.status.success());
    assert!(!String::from_utf8_lossy(&plain.stderr).contains("points traced"));
}
