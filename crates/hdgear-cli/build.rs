//! Build script: tells the test binary whether a Chromium is installed, so that the report's
//! browser test is reported as *ignored* (visible in the test summary) where none is, instead of
//! passing without having run. Under `CI=true` the test always runs (and fails without Chromium).

fn main() {
    println!("cargo::rustc-check-cfg=cfg(hdgear_no_chromium)");
    println!("cargo::rerun-if-env-changed=HDGEAR_CHROMIUM");
    println!("cargo::rerun-if-env-changed=CI");
    println!("cargo::rerun-if-env-changed=PATH");
    let names = ["chromium", "chromium-browser", "google-chrome"];
    let path = std::env::var_os("PATH").unwrap_or_default();
    let mut found = std::env::var_os("HDGEAR_CHROMIUM").is_some();
    for dir in std::env::split_paths(&path) {
        // Watch each existing directory of PATH (its mtime changes when a program is installed
        // into it), so installing Chromium later rebuilds the tests. Not the candidate files
        // themselves: cargo takes a watched file that does not exist as changed on every build,
        // which rebuilt the binary on every `cargo run`.
        if dir.is_dir() {
            println!("cargo::rerun-if-changed={}", dir.display());
        }
        for n in names {
            found |= dir.join(n).is_file();
        }
    }
    if !found && std::env::var_os("CI").is_none() {
        println!("cargo::rustc-cfg=hdgear_no_chromium");
    }
}
