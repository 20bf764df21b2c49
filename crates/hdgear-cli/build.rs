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
        for n in names {
            let candidate = dir.join(n);
            // watch the place it would be installed, so installing it later rebuilds the tests
            println!("cargo::rerun-if-changed={}", candidate.display());
            found |= candidate.is_file();
        }
    }
    if !found && std::env::var_os("CI").is_none() {
        println!("cargo::rustc-cfg=hdgear_no_chromium");
    }
}
