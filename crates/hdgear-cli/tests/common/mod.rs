//! Helpers shared by the test modules.

use std::path::PathBuf;

/// `../shared/` beside the checkout (read-only reference material): the first `shared/`
/// directory found walking up from this crate.
pub fn shared_dir() -> PathBuf {
    let here = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    here.ancestors()
        .map(|d| d.join("shared"))
        .find(|d| d.join("reference").is_dir())
        .unwrap_or_else(|| here.join("../../../shared"))
}

/// The reference trajectories of SPEC §4: rows (gamma, x0, v0, t, x, xdot).
pub fn reference_rows() -> Vec<[f64; 6]> {
    let path = shared_dir().join("reference/paper_trajectories.csv");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap().trim(), "gamma,x0,v0,t,x,xdot");
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|s| s.trim().parse().unwrap()).collect();
            [v[0], v[1], v[2], v[3], v[4], v[5]]
        })
        .collect()
}

/// The `hdgear` binary under test.
pub fn hdgear() -> assert_cmd::Command {
    assert_cmd::Command::cargo_bin("hdgear").unwrap()
}

/// Files in a directory (to check that nothing, not even a temporary, was left behind).
pub fn files_in(dir: &std::path::Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Runs `hdgear ARGS`, expects success, and returns stdout.
pub fn stdout_of(args: &[&str]) -> String {
    let out = hdgear().args(args).assert().success();
    String::from_utf8(out.get_output().stdout.clone()).unwrap()
}

/// Runs `hdgear ARGS`, expects success, and parses stdout as JSON.
pub fn json_of(args: &[&str]) -> serde_json::Value {
    serde_json::from_str(&stdout_of(args)).unwrap()
}

/// A Chromium to drive: `HDGEAR_CHROMIUM`, or the first of chromium, chromium-browser,
/// google-chrome that answers `--version`.
pub fn chromium() -> Option<String> {
    if let Ok(c) = std::env::var("HDGEAR_CHROMIUM") {
        return Some(c);
    }
    ["chromium", "chromium-browser", "google-chrome"]
        .into_iter()
        .find(|c| {
            std::process::Command::new(c)
                .arg("--version")
                .output()
                .is_ok_and(|o| o.status.success())
        })
        .map(str::to_string)
}
