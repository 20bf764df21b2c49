#!/usr/bin/env python3
"""What each term kind costs per Taylor step: the study's model with one term of each kind, per
step on one trajectory and per lane-step on 16 lanes, beside the floor (the study's
hand-scheduled recurrence), by `cargo run --profile dist --example term_costs`.

    python3 bench/term_costs.py [REPS]   # prints a Markdown table
"""
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def main():
    reps = sys.argv[1] if len(sys.argv) > 1 else "20"
    run = subprocess.run(
        ["cargo", "run", "--quiet", "--profile", "dist", "--example", "term_costs", reps],
        cwd=ROOT, capture_output=True, text=True)
    if run.returncode != 0:
        print(run.stderr[-2000:], file=sys.stderr)
        return 1
    print(run.stdout.strip())
    return 0


if __name__ == "__main__":
    sys.exit(main())
