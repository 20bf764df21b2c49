//! Interrupted runs: signals at several moments, sweeps resumed against changed settings,
//! duplicated rows and a running sweep; nothing half-written is ever left behind.

use crate::common::{files_in, hdgear, walk};
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

fn kill(pid: u32, sig: &str) {
    let ok = Command::new("kill")
        .args([sig, &pid.to_string()])
        .status()
        .unwrap()
        .success();
    assert!(ok);
}

/// Makes the processes this test process starts begin with the default actions of SIGINT and
/// SIGTERM even when this one was started with them ignored (a background job of a
/// non-interactive shell starts with SIGINT and SIGQUIT ignored, and an ignored signal stays
/// ignored across `exec`: `hdgear simulate` to stdout then rightly ran on through SIGINT): an
/// ignored signal is given a handler that only sets a flag, which `exec` resets to the default in
/// the child. Where the signal was not ignored nothing changes.
fn children_start_with_default_signals() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    let ignored = status
        .lines()
        .find_map(|l| l.strip_prefix("SigIgn:"))
        .and_then(|bits| u64::from_str_radix(bits.trim(), 16).ok())
        .unwrap_or(0);
    for sig in [SIGINT, SIGTERM] {
        if ignored & (1 << (sig - 1)) != 0 {
            let flag = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
            signal_hook::flag::register(sig, flag).unwrap();
        }
    }
}

/// Starts `hdgear ARGS` in `dir`, sends `sig` after `after`, and returns (exit code, stderr).
fn interrupt(dir: &Path, args: &[&str], sig: &str, after: Duration) -> (i32, String) {
    let child = Command::new(assert_cmd::cargo::cargo_bin("hdgear"))
        .current_dir(dir)
        .args(args)
        .arg("--quiet")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(after);
    kill(child.id(), sig);
    let out = child.wait_with_output().unwrap();
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// Runs `hdgear args` in `dir` (with its progress lines), sends `sig` as soon as a line of
/// stderr contains `marker`, and returns the exit code and everything it wrote to stderr.
fn interrupt_at(dir: &Path, args: &[&str], sig: &str, marker: &str) -> (i32, String) {
    use std::io::{BufRead, Read};
    let mut child = Command::new(assert_cmd::cargo::cargo_bin("hdgear"))
        .current_dir(dir)
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = std::io::BufReader::new(child.stderr.take().unwrap());
    let mut text = String::new();
    loop {
        let mut line = String::new();
        if err.read_line(&mut line).unwrap() == 0 {
            break;
        }
        text.push_str(&line);
        if line.contains(marker) {
            kill(child.id(), sig);
            break;
        }
    }
    err.read_to_string(&mut text).unwrap();
    let status = child.wait().unwrap();
    (status.code().unwrap_or(-1), text)
}

#[test]
fn signals_remove_every_temporary() {
    let long_sim: &[&str] = &[
        "simulate", "--dt", "0.01", "--t-end", "1e5", "--out", "big.csv",
    ];
    let long_phys: &[&str] = &[
        "physical",
        "--simulate",
        "--t-end",
        "2000",
        "--dt",
        "1e-4",
        "--out",
        "p.csv",
    ];
    for (args, target) in [(long_sim, "big.csv"), (long_phys, "p.csv")] {
        for (sig, code) in [("-INT", 130), ("-TERM", 143)] {
            for ms in [150, 600] {
                let dir = tempfile::tempdir().unwrap();
                let (c, err) = interrupt(dir.path(), args, sig, Duration::from_millis(ms));
                if c == 0 {
                    // finished before the signal: then the file must be complete
                    assert!(dir.path().join(target).exists());
                    continue;
                }
                assert_eq!(c, code, "{args:?} {sig}: {err}");
                assert!(err.contains("interrupted by SIG"), "{err}");
                assert_eq!(err.lines().count(), 1, "{err}");
                assert!(
                    files_in(dir.path()).is_empty(),
                    "{:?}",
                    files_in(dir.path())
                );
            }
        }
    }
}

/// `simulate` writing to stdout only creates no file, so it watches no signal (no thread to start
/// for a run of a few milliseconds): interrupted, it ends by the signal's default action, says
/// nothing and leaves nothing.
#[test]
fn a_stdout_only_run_ends_by_the_signal_and_leaves_nothing() {
    use std::os::unix::process::ExitStatusExt;
    children_start_with_default_signals();
    for sig in ["-INT", "-TERM"] {
        let dir = tempfile::tempdir().unwrap();
        let child = Command::new(assert_cmd::cargo::cargo_bin("hdgear"))
            .current_dir(dir.path())
            .args(["--quiet", "simulate", "--dt", "0.01", "--t-end", "1e6"])
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(Duration::from_millis(300));
        kill(child.id(), sig);
        let out = child.wait_with_output().unwrap();
        let expected = if sig == "-INT" { 2 } else { 15 };
        assert_eq!(
            out.status.signal(),
            Some(expected),
            "{sig}: {:?}",
            out.status
        );
        assert!(
            out.stderr.is_empty(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(
            files_in(dir.path()).is_empty(),
            "{:?}",
            files_in(dir.path())
        );
    }
}

/// A sweep long enough (over a second on one thread) that the signals and checks the tests below
/// send at fixed times land inside it, with room for a machine three times as fast.
const SWEEP: [&str; 7] = [
    "sweep",
    "--param",
    "gamma=0.1:30:16000:log",
    "--threads",
    "1",
    "--out",
    "s.csv",
];

#[test]
fn an_interrupted_sweep_resumes_to_the_same_file() {
    let full = tempfile::tempdir().unwrap();
    hdgear()
        .current_dir(full.path())
        .args(SWEEP)
        .arg("--quiet")
        .assert()
        .success();
    let whole = std::fs::read(full.path().join("s.csv")).unwrap();
    let dir = tempfile::tempdir().unwrap();
    let (c, err) = interrupt(dir.path(), &SWEEP, "-TERM", Duration::from_millis(400));
    assert_eq!(c, 143, "{err}");
    assert!(
        err.contains("--resume"),
        "the message says how to resume: {err}"
    );
    assert_eq!(
        files_in(dir.path()),
        ["s.csv.partial"],
        "the lock is gone, the rows kept"
    );
    // duplicate every row kept: identical duplicates are dropped on resume
    let part = dir.path().join("s.csv.partial");
    let text = std::fs::read_to_string(&part).unwrap();
    let body: Vec<&str> = text.lines().skip(2).collect();
    std::fs::write(&part, format!("{text}{}\n", body.join("\n"))).unwrap();
    hdgear()
        .current_dir(dir.path())
        .args(SWEEP)
        .args(["--resume", "--quiet"])
        .assert()
        .success()
        .stderr(predicates::str::contains(
            "wrote s.csv: 16000 rows, 0 failed",
        ));
    assert_eq!(std::fs::read(dir.path().join("s.csv")).unwrap(), whole);
}

#[test]
fn resume_refuses_other_settings_and_conflicting_rows() {
    let dir = tempfile::tempdir().unwrap();
    let (c, _) = interrupt(dir.path(), &SWEEP, "-INT", Duration::from_millis(400));
    assert_eq!(c, 130);
    for (flag, needle) in [
        (["--rtol", "1e-8"], "options.tol.rtol"),
        (["--discard", "2"], "options.discard_periods"),
        (["--window-periods", "3"], "options.periods"),
        (["--atol", "1e-9"], "options.tol.atol"),
    ] {
        hdgear()
            .current_dir(dir.path())
            .args(SWEEP)
            .args(flag)
            .args(["--resume", "--quiet"])
            .assert()
            .code(2)
            .stderr(predicates::str::contains(needle));
    }
    // a conflicting duplicate: the same index with another value
    let part = dir.path().join("s.csv.partial");
    let text = std::fs::read_to_string(&part).unwrap();
    let row = text.lines().nth(2).unwrap();
    let fields: Vec<&str> = row.split(',').collect();
    let mut changed: Vec<String> = fields.iter().map(|s| s.to_string()).collect();
    changed[12] = "123.0".into(); // peak_abs_xdot
    std::fs::write(&part, format!("{text}{}\n", changed.join(","))).unwrap();
    hdgear()
        .current_dir(dir.path())
        .args(SWEEP)
        .args(["--resume", "--quiet"])
        .assert()
        .code(2)
        .stderr(predicates::str::contains(format!(
            "two different rows for grid point {}",
            fields[0]
        )));
}

#[test]
fn a_running_sweep_is_locked() {
    let dir = tempfile::tempdir().unwrap();
    // the checks below start once the sweep's first rows are written (a fixed wait raced the
    // sweep once it got fast)
    let child = Command::new(assert_cmd::cargo::cargo_bin("hdgear"))
        .current_dir(dir.path())
        .args(SWEEP)
        .arg("--quiet")
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let partial = dir.path().join("s.csv.partial");
    let started = std::time::Instant::now();
    while std::fs::read_to_string(&partial).map_or(0, |t| t.lines().count()) < 2 {
        assert!(
            started.elapsed() < Duration::from_secs(30),
            "no rows written"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    for extra in [&[][..], &["--resume"][..]] {
        hdgear()
            .current_dir(dir.path())
            .args(SWEEP)
            .args(extra)
            .arg("--quiet")
            .assert()
            .code(2)
            .stderr(predicates::str::contains(format!(
                "another hdgear sweep is writing s.csv (pid {})",
                child.id()
            )));
    }
    let status = child.wait_with_output().unwrap().status;
    assert!(status.success(), "the first sweep was not disturbed");
    assert_eq!(files_in(dir.path()), ["s.csv"]);
}

#[test]
fn a_sweep_whose_points_all_fail_exits_1() {
    let dir = tempfile::tempdir().unwrap();
    hdgear()
        .current_dir(dir.path())
        .args([
            "sweep",
            "--param",
            "gamma=1:2:3",
            "--discard",
            "1e9",
            "--out",
            "s.csv",
        ])
        .arg("--quiet")
        .assert()
        .code(1)
        .stderr(predicates::str::contains("wrote s.csv: 3 rows, 3 failed"));
    // a failed row has no mode (not a sentinel word) and says why in `error`
    let text = std::fs::read_to_string(dir.path().join("s.csv")).unwrap();
    for row in text.lines().skip(1) {
        let cols: Vec<&str> = row.split(',').collect();
        assert_eq!((cols[7], cols[8]), ("", ""), "{row}");
        assert!(row.contains("integration steps"), "{row}");
    }
}

#[test]
fn an_interrupted_report_leaves_only_complete_files() {
    // as the physical and periodic sections start (computing; nothing written yet) and as the
    // writing starts (the files are being written): signalled when the progress line appears,
    // so the test stays inside the run however fast the report gets
    for (sig, code, marker) in [("-INT", 130, "[4/6"), ("-TERM", 143, "[6/6")] {
        let dir = tempfile::tempdir().unwrap();
        let (c, err) = interrupt_at(dir.path(), &["report", "--out", "r"], sig, marker);
        assert_eq!(c, code, "{err}");
        let left = walk(dir.path());
        assert!(left.iter().all(|f| !f.contains(".tmp-")), "{left:?}");
        // index.html comes last: an interrupted report has none
        assert!(!left.iter().any(|f| f.ends_with("index.html")), "{left:?}");
        // what is there is complete: every CSV ends with a newline, every PNG with its IEND chunk
        for f in &left {
            let bytes = std::fs::read(dir.path().join(f)).unwrap();
            if f.ends_with(".png") {
                assert!(bytes.ends_with(&[0xAE, 0x42, 0x60, 0x82]), "{f}");
            } else {
                assert!(bytes.ends_with(b"\n") || bytes.ends_with(b"}"), "{f}");
            }
        }
        // and the report can then be written there: the manifest lists what it wrote so far
        // (checked after the interruption while writing: the one that leaves files behind)
        if marker == "[6/6" {
            hdgear()
                .current_dir(dir.path())
                .args(["report", "--out", "r", "--quiet"])
                .assert()
                .success();
        }
    }
}

/// A report stopped in its first stage has written its manifest already (before any computing):
/// the directory names itself hdgear's, and a rerun takes it without --force.
#[test]
fn a_report_stopped_midway_leaves_its_manifest() {
    let dir = tempfile::tempdir().unwrap();
    let args = ["report", "--out", "r", "--threads", "1"];
    let (c, err) = interrupt_at(dir.path(), &args, "-TERM", "[1/");
    assert_eq!(c, 143, "{err}");
    assert!(err.contains("interrupted by SIG"), "{err}");
    assert!(
        dir.path().join("r").join(".hdgear-report").exists(),
        "{:?}",
        files_in(&dir.path().join("r"))
    );
}
