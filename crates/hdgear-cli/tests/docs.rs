//! Every command line shown in the README and the user guide (`docs/src/*.md`) runs here, and its
//! shown output is compared.
//!
//! A ` ```console ` block holds commands (`$ hdgear …`, or `$ cargo run --release -- …`, which is
//! the same binary) each followed by what it prints: its standard output, then its standard
//! error. In the expected output a line
//! `...` stands for any number of lines and `[..]` for any part of a line, so numbers that vary by
//! machine (timings) are never compared. A line `? N` right after a command expects exit code N
//! (0 otherwise). The commands of one block run one after the other in one fresh directory, so a
//! block may write a file and read it back; a block whose info string names `file=NAME` (a
//! ` ```toml file=friction.toml ` scenario) is written as NAME into the next console block's
//! directory. Command lines anywhere else (a `sh` block, an indented
//! block) are refused, except `hdgear serve`, which runs until stopped and has its own tests.

use std::path::{Path, PathBuf};

/// The repository's root (two levels above this crate).
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The README and every page of the guide.
fn documents() -> Vec<PathBuf> {
    let mut v = vec![root().join("README.md")];
    let mut pages: Vec<PathBuf> = std::fs::read_dir(root().join("docs/src"))
        .expect("docs/src exists")
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .collect();
    pages.sort();
    v.extend(pages);
    v
}

/// One command of a console block: its arguments, the exit code and the output expected.
#[derive(Debug)]
struct Step {
    line: usize,
    args: Vec<String>,
    code: i32,
    expected: Vec<String>,
}

/// A fenced block: its info string, first line number and lines.
struct Block {
    info: String,
    line: usize,
    lines: Vec<String>,
}

/// The fenced code blocks of a Markdown text (``` fences only; the guide uses no ~~~).
fn blocks(text: &str) -> Vec<Block> {
    let mut out = Vec::new();
    let mut open: Option<Block> = None;
    for (i, l) in text.lines().enumerate() {
        let t = l.trim_start();
        if let Some(info) = t.strip_prefix("```") {
            match open.take() {
                Some(b) => out.push(b),
                None => {
                    open = Some(Block {
                        info: info.trim().to_string(),
                        line: i + 1,
                        lines: Vec::new(),
                    })
                }
            }
        } else if let Some(b) = open.as_mut() {
            b.lines.push(l.to_string());
        }
    }
    assert!(open.is_none(), "an unclosed code block");
    out
}

/// Splits a command line as a POSIX shell would for words, single and double quotes (no
/// expansions: the guide's commands use none).
fn words(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut any = false;
    let mut chars = line.chars();
    while let Some(c) = chars.next() {
        match c {
            '\'' => {
                any = true;
                for d in chars.by_ref() {
                    if d == '\'' {
                        break;
                    }
                    cur.push(d);
                }
            }
            '"' => {
                any = true;
                while let Some(d) = chars.next() {
                    match d {
                        '"' => break,
                        '\\' => cur.extend(chars.next()),
                        _ => cur.push(d),
                    }
                }
            }
            c if c.is_whitespace() => {
                if any || !cur.is_empty() {
                    out.push(std::mem::take(&mut cur));
                    any = false;
                }
            }
            _ => cur.push(c),
        }
    }
    if any || !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// The hdgear arguments of a shown command, or `None` when it is not an hdgear command.
fn hdgear_args(command: &str) -> Option<Vec<String>> {
    let w = words(command);
    let rest = if w.first().is_some_and(|s| s == "hdgear") {
        &w[1..]
    } else if w.len() >= 4 && w[..4] == ["cargo", "run", "--release", "--"] {
        &w[4..]
    } else {
        return None;
    };
    Some(rest.to_vec())
}

/// The steps of a console block.
fn steps(doc: &Path, b: &Block) -> Vec<Step> {
    let mut out: Vec<Step> = Vec::new();
    let mut lines = b.lines.iter().enumerate().peekable();
    while let Some((i, l)) = lines.next() {
        if let Some(cmd) = l.strip_prefix("$ ") {
            let mut cmd = cmd.to_string();
            while cmd.ends_with('\\') {
                cmd.pop();
                let (_, next) = lines.next().expect("a continued line");
                cmd.push(' ');
                cmd.push_str(next.trim());
            }
            let args = hdgear_args(&cmd).unwrap_or_else(|| {
                panic!(
                    "{}:{}: a console block runs hdgear commands only: {cmd}",
                    doc.display(),
                    b.line + i + 1
                )
            });
            let mut code = 0;
            if let Some((_, q)) = lines.next_if(|(_, l)| l.starts_with("? ")) {
                code = q[2..].trim().parse().expect("`? N` takes an exit code");
            }
            out.push(Step {
                line: b.line + i + 1,
                args,
                code,
                expected: Vec::new(),
            });
        } else {
            let step = out.last_mut().unwrap_or_else(|| {
                panic!(
                    "{}:{}: output before any command",
                    doc.display(),
                    b.line + i + 1
                )
            });
            step.expected.push(l.clone());
        }
    }
    out
}

/// Whether one line matches its expected form (`[..]` matches any part of a line).
fn line_matches(expected: &str, actual: &str) -> bool {
    let parts: Vec<&str> = expected.split("[..]").collect();
    if parts.len() == 1 {
        return expected == actual;
    }
    let (first, last) = (parts[0], parts[parts.len() - 1]);
    if !actual.starts_with(first) || actual.len() < first.len() + last.len() {
        return false;
    }
    let mut rest = &actual[first.len()..];
    for p in &parts[1..parts.len() - 1] {
        match rest.find(p) {
            Some(k) => rest = &rest[k + p.len()..],
            None => return false,
        }
    }
    rest.ends_with(last)
}

/// Whether the output matches the expected lines (`...` alone matches any number of lines).
fn output_matches(expected: &[String], actual: &[&str]) -> bool {
    match expected.split_first() {
        None => actual.is_empty(),
        Some((e, rest)) if e == "..." => {
            (0..=actual.len()).any(|k| output_matches(rest, &actual[k..]))
        }
        Some((e, rest)) => {
            !actual.is_empty() && line_matches(e, actual[0]) && output_matches(rest, &actual[1..])
        }
    }
}

/// Command lines outside console blocks, which would run nowhere: in the other fenced `blocks`
/// of `text`, or in indented code outside them.
fn unchecked_commands(doc: &Path, text: &str, blocks: &[Block]) -> Vec<String> {
    let runs = |l: &str| {
        let l = l.trim_start().trim_start_matches("$ ");
        (l.starts_with("hdgear ") || l.starts_with("cargo run --release -- "))
            && !l.contains("[")
            && !l.contains(" serve")
            && !l.contains("…")
            && !l.contains('|')
    };
    // (line number, text) of every line to look at
    let fenced = blocks
        .iter()
        .filter(|b| b.info != "console")
        .flat_map(|b| (b.line + 1..).zip(b.lines.iter().map(String::as_str)));
    let in_a_block = |n: usize| {
        blocks
            .iter()
            .any(|b| (b.line..=b.line + b.lines.len() + 1).contains(&n))
    };
    let indented = (1..)
        .zip(text.lines())
        .filter(|&(n, l)| l.starts_with("    ") && !in_a_block(n));
    fenced
        .chain(indented)
        .filter(|&(_, l)| runs(l))
        .map(|(n, l)| format!("{}:{n}: {}", doc.display(), l.trim()))
        .collect()
}

#[test]
fn every_shown_command_runs_and_prints_what_is_shown() {
    let bin = env!("CARGO_BIN_EXE_hdgear");
    let mut ran = 0;
    let mut failures = Vec::new();
    let mut unchecked = Vec::new();
    for doc in documents() {
        let text = std::fs::read_to_string(&doc).unwrap();
        let blocks = blocks(&text);
        unchecked.extend(unchecked_commands(&doc, &text, &blocks));
        let mut files: Vec<(&str, String)> = Vec::new();
        for b in &blocks {
            if let Some(name) = b
                .info
                .split_whitespace()
                .find_map(|w| w.strip_prefix("file="))
            {
                files.push((name, b.lines.join("\n") + "\n"));
            }
            if b.info != "console" {
                continue;
            }
            let dir = tempfile::tempdir().unwrap();
            for (name, text) in files.drain(..) {
                std::fs::write(dir.path().join(name), text).unwrap();
            }
            for s in steps(&doc, b) {
                let out = std::process::Command::new(bin)
                    .args(&s.args)
                    .current_dir(dir.path())
                    .env_remove("RAYON_NUM_THREADS")
                    .output()
                    .unwrap();
                ran += 1;
                let stdout = String::from_utf8_lossy(&out.stdout);
                let stderr = String::from_utf8_lossy(&out.stderr);
                let actual: Vec<&str> = stdout.lines().chain(stderr.lines()).collect();
                let code = out.status.code().unwrap_or(-1);
                if code != s.code || !output_matches(&s.expected, &actual) {
                    failures.push(format!(
                        "{}:{}: hdgear {}\n  exit {code} (expected {})\n  stdout:\n{}\n  stderr:\n{}",
                        doc.display(),
                        s.line,
                        s.args.join(" "),
                        s.code,
                        stdout, stderr
                    ));
                }
            }
        }
    }
    assert!(
        unchecked.is_empty(),
        "command lines outside console blocks (put them in a ```console block with their output):\n{}",
        unchecked.join("\n")
    );
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
    assert!(ran >= 20, "only {ran} commands found in the documents");
}

#[test]
fn the_matcher_accepts_what_it_should_and_nothing_else() {
    let e = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<Vec<_>>();
    assert!(output_matches(
        &e(&["a", "...", "z"]),
        &["a", "b", "c", "z"]
    ));
    assert!(output_matches(&e(&["a", "...", "z"]), &["a", "z"]));
    assert!(!output_matches(&e(&["a", "...", "z"]), &["a", "b"]));
    assert!(output_matches(&e(&["took [..] s"]), &["took 0.6 s"]));
    assert!(!output_matches(&e(&["took [..] s"]), &["took 0.6 ms"]));
    assert!(!output_matches(&e(&["a"]), &["a", "b"]));
    assert!(output_matches(&e(&[]), &[]));
    assert_eq!(
        words(r#"a 'b c' "d \"e\"" f"#),
        ["a", "b c", "d \"e\"", "f"]
    );
    assert_eq!(
        hdgear_args("cargo run --release -- report"),
        Some(vec!["report".to_string()])
    );
    assert_eq!(hdgear_args("ls -l"), None);
}

/// The fit page's list of units is the library's ([`hdgear::fit::units_text`]), each unit in
/// the order the library reads them, so the page cannot fall behind a unit added there.
#[test]
fn the_fit_page_lists_the_units_the_library_reads() {
    let page = std::fs::read_to_string(root().join("docs/src/fit.md")).unwrap();
    let start = page.find("Units: ").expect("the fit page lists the units") + "Units: ".len();
    let end = start + page[start..].find(".\n").unwrap();
    let listed: String = page[start..end]
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ")
        .replace('`', "");
    assert_eq!(listed, hdgear::fit::units_text());
}
