//! Every command that prints to standard output handles a closed pipe (exits 0 quietly, as `cat`
//! does) and a full disk (`/dev/full`: one line saying what could not be written, exit 2), never
//! a panic.

use std::process::{Command, Stdio};

/// Every command form that writes to standard output, on small, fast inputs.
const FORMS: &[&[&str]] = &[
    &["simulate", "--t-end", "200"],
    &["simulate", "--summary"],
    &["equilibria", "--points", "50"],
    &["analyze", "--no-response"],
    &["analyze", "--json", "--no-response"],
    &["bifurcation", "--gamma-min", "0.01", "--points", "20"],
    &["bursts", "--preset", "paper-g1"],
    &["table"],
    &["table", "--json"],
    &["periodic"],
    &["periodic", "--json"],
    &["continue", "--param", "mu=0.07:0.1"],
    &["continue", "--param", "mu=0.07:0.1", "--json"],
    &[
        "frequency-response",
        "--gamma",
        "30",
        "--omega-range",
        "6:10",
    ],
    &["physical"],
    &["physical", "--json"],
    &["physical", "--design", "--json"],
    &["physical", "--simulate", "--t-end", "0.05"],
    &["physical", "--frequency-response", "--hz", "80:130"],
    &["model"],
    &["model", "--json"],
    &[
        "continue2",
        "--gamma=10",
        "--param=omega=4:14:log",
        "--param=mu=-5:5",
        "--from=period-doubling",
    ],
    &[
        "boundary",
        "--kinds=predicted",
        "--param=gamma=0.01:1:log",
        "--param=delta=1:30:log",
        "--json",
    ],
    &[
        "orbit-diagram",
        "--param=omega=5:6:3",
        "--record=4",
        "--discard=2",
    ],
    &["card", "list"],
    &["card", "show", "csf-20-50", "--json"],
    &["card", "check", "csf-20-50"],
    &["card", "map", "csf-20-50", "--points=4"],
    &["card", "new", "mine"],
    &["control", "vstiffness", "--gain=1", "--spread=0"],
    &["control", "vstiffness", "--gain=1", "--spread=0", "--json"],
    &[
        "robust",
        "--tolerance=gamma=±10%",
        "--samples=16",
        "--no-worst",
    ],
];

fn run(args: &[&str], stdout: Stdio) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_hdgear"))
        .arg("--quiet")
        .args(args)
        .stdout(stdout)
        .stderr(Stdio::piped())
        .current_dir(std::env::temp_dir())
        .output()
        .unwrap()
}

#[test]
fn a_closed_pipe_ends_every_command_quietly() {
    for args in FORMS {
        // the reading end is closed before the command starts, so every write fails with EPIPE
        let (reader, writer) = std::io::pipe().unwrap();
        drop(reader);
        let o = run(args, writer.into());
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(0), "hdgear {}: {err}", args.join(" "));
        assert!(err.is_empty(), "hdgear {}: {err}", args.join(" "));
    }
}

#[cfg(target_os = "linux")]
#[test]
fn a_full_disk_is_one_line_and_exit_code_2() {
    for args in FORMS {
        let full = std::fs::OpenOptions::new()
            .write(true)
            .open("/dev/full")
            .unwrap();
        let o = run(args, full.into());
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "hdgear {}: {err}", args.join(" "));
        assert_eq!(err.lines().count(), 1, "hdgear {}: {err}", args.join(" "));
        assert!(
            err.starts_with("error: ") && err.contains("No space left on device"),
            "hdgear {}: {err}",
            args.join(" ")
        );
    }
}
