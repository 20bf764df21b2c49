#!/usr/bin/env python3
"""The study's hand-scheduled fast path against the generic path of the model assembled from
terms, on the same work (`cargo bench --bench hdgear -- study_path`): three slow periods of the
default start at rtol = atol = 1e-10 by Taylor's method, one trajectory at γ = 30 and 0.1, and
sixteen on the vector lanes; and the periodic orbit by shooting. Issue 94 keeps a specialised path only where it is ≥ 1.2× faster.

    python3 bench/study_path.py         # prints a Markdown table
"""
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
UNITS = {"ns": 1e-6, "µs": 1e-3, "us": 1e-3, "ms": 1.0, "s": 1e3}


def main():
    run = subprocess.run(
        ["cargo", "bench", "--quiet", "--bench", "hdgear", "--", "study_path",
         "--warm-up-time", "1", "--measurement-time", "4"],
        cwd=ROOT, capture_output=True, text=True)
    if run.returncode != 0:
        print(run.stderr[-2000:], file=sys.stderr)
        return 1
    text = run.stdout + run.stderr
    # "study_path/NAME\n    time:   [lo UNIT mid UNIT hi UNIT]": the median estimate, in ms
    times = {}
    for name, mid, unit in re.findall(
            r"study_path/(\S+)\s+time:\s+\[\S+ \S+ (\S+) (\S+) \S+ \S+\]", text):
        times[name] = float(mid) * UNITS[unit]
    steps = re.findall(r"(gamma \S+: steps specialised \d+, generic \d+; final x differs by \S+)", text)
    print("| work | specialised ms | generic ms | generic / specialised |")
    print("|---|---|---|---|")
    for case in sorted({n.split("/", 1)[1] for n in times if n.startswith("scalar")}) + ["batch16", "shoot"]:
        fast = times.get(f"scalar-specialised/{case}", times.get(f"{case}-specialised"))
        slow = times.get(f"scalar-generic/{case}", times.get(f"{case}-generic"))
        if fast is None or slow is None:
            continue
        label = {"batch16": "16 trajectories on the lanes",
                 "shoot": "the periodic orbit by shooting, study's point"}.get(
            case, f"one trajectory, {case.replace('gamma=', 'γ = ')}")
        print(f"| {label} | {fast:.3f} | {slow:.3f} | {slow / fast:.2f} |")
    print()
    for s in steps:
        print(f"- {s}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
