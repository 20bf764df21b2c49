//! Helpers shared by the test modules.

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

/// Runs `hdgear ARGS` and expects the exit status 2 of bad input, `needle` in its message and
/// no panic.
pub fn fails_with(args: &[&str], needle: &str) {
    use predicates::prelude::*;
    hdgear()
        .args(args)
        .assert()
        .code(2)
        .stderr(predicate::str::contains(needle))
        .stderr(predicate::str::contains("panicked").not());
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

/// Every file below `dir`, relative, sorted.
pub fn walk(dir: &std::path::Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push(p.strip_prefix(dir).unwrap().display().to_string());
            }
        }
    }
    out.sort();
    out
}
