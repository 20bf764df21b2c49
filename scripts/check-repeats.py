#!/usr/bin/env python3
"""Fails when a block of six or more lines of code stands twice, to the letter, outside tests,
benchmarks and generated code (the DOP853 stage formulas): such a block belongs in one function.

Lines are compared without their indentation. Skipped, so that a block counts only what runs:
blank lines, lines of punctuation alone (`}`, `});`, `)?;`), comments, attributes (`#[arg(…)]`:
they declare, they do not run) and the lines of a field list, where a struct's fields are
declared or filled (`pub x0: f64,`, `Row {`, `x0: q.start[0],`, `x0,`):
record types of different output files share columns (a branch table and a curve table both
carry an orbit's start and multipliers), and serde cannot nest them into one struct without
changing the files. What is left, statements and expressions, must not stand twice."""
import re
import subprocess
import sys
from collections import defaultdict

MIN_LINES = 6
SKIP = re.compile(r"(^|/)(tests?|benches|bench)/|^crates/hdgear/src/integrate/stages\.rs$")


FIELD = re.compile(r"^((pub(\([a-z]+\))? )?[a-z_][a-z0-9_]*(: [^=]+)?,|[A-Z][A-Za-z0-9_]* \{)$")


def without_attributes(lines):
    """The lines outside Rust attributes (`#[arg(long, …)]`, over as many lines as it takes):
    an attribute declares, it does not run."""
    depth = 0
    for n, l in lines:
        if depth == 0 and not l.startswith("#["):
            yield n, l
            continue
        depth += l.count("[") - l.count("]")


def counted(line):
    if re.search(r"[A-Za-z0-9]", line) is None:
        return False
    if line.startswith(("//", "#")) and not line.startswith(("#[", "#![")):
        return False
    return not FIELD.match(line)


def main():
    files = subprocess.run(["git", "ls-files", "*.rs", "*.py", "*.js", "*.sh"], check=True,
                           capture_output=True, text=True).stdout.split()
    seen = defaultdict(list)
    for path in files:
        if SKIP.search(path):
            continue
        with open(path, encoding="utf-8") as f:
            lines = [(n + 1, l.strip()) for n, l in enumerate(f)]
        lines = [(n, l) for n, l in without_attributes(lines) if counted(l)]
        for i in range(len(lines) - MIN_LINES + 1):
            window = lines[i:i + MIN_LINES]
            text = tuple(l for _, l in window)
            seen[text].append((path, window[0][0]))
    repeats = [(text, places) for text, places in seen.items() if len(places) > 1]
    for text, places in repeats:
        print("repeated block of %d lines at %s:" % (MIN_LINES, ", ".join(f"{p}:{n}" for p, n in places)))
        for l in text:
            print("    " + l)
    if repeats:
        sys.exit(1)
    print(f"no block of {MIN_LINES} lines stands twice ({len(files)} files)")


if __name__ == "__main__":
    main()
