"""What calling hdgear from Python costs, measured in one run.

1. `hdgear.simulate` called 1000 times from a Python loop (3 slow periods at the study's point,
   samples every 0.05 returned as numpy arrays) against the same 1000 simulations looped in Rust
   (`hdgear._hdgear.time_simulate_in_rust`: the same function, the same samples collected into
   vectors, no Python in between). Bar: Python ≤ 1.3× Rust.
2. `hdgear.sweep` of 1000 γ points against the CLI's `hdgear sweep --param
   gamma=0.1:30:1000:log` (the same points: taken from the CLI's output), alternated, medians.
   Bar: the Python sweep at least as fast.

    python bench/python_overhead.py [PATH/TO/hdgear]    (needs `import hdgear`; see the README)
"""
import csv
import os
import statistics
import subprocess
import sys
import tempfile
import time

import hdgear
from common import RELEASE
from hdgear import _hdgear

binary = sys.argv[1] if len(sys.argv) > 1 else str(RELEASE / "hdgear")
p = hdgear.Params.paper(gamma=0.1)
t_end = 3 * 2 * 3.141592653589793 / p.omega

N = 1000
hdgear.simulate(p, t_end=t_end)
rust = []
py = []
for rep in range(3):
    rust.append(_hdgear.time_simulate_in_rust(p, t_end, 0.05, N))
    t0 = time.perf_counter()
    for _ in range(N):
        hdgear.simulate(p, t_end=t_end, dt=0.05)
    py.append((time.perf_counter() - t0) / N)
r, q = min(rust), min(py)
print(f"simulate x {N} (3 periods, 37,701 samples each): Rust loop {r * 1e3:.3f} ms per run, "
      f"Python loop {q * 1e3:.3f} ms per run: ratio {q / r:.3f} (bar <= 1.3)")

with tempfile.TemporaryDirectory() as d:
    out = os.path.join(d, "s.csv")
    cmd = [binary, "sweep", "--param", "gamma=0.1:30:1000:log", "--out", out, "--quiet"]
    subprocess.run(cmd, check=True, stderr=subprocess.DEVNULL)
    with open(out) as f:
        gammas = [float(r["gamma"]) for r in csv.DictReader(f)]
    cli_t, py_t = [], []
    hdgear.sweep({"gamma": gammas})
    for rep in range(9):
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True, stderr=subprocess.DEVNULL)
        cli_t.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        hdgear.sweep({"gamma": gammas})
        py_t.append(time.perf_counter() - t0)
    c, s = statistics.median(cli_t), statistics.median(py_t)
    print(f"sweep of 1000 gamma points (burst analysis, all cores): CLI process {c:.3f} s, "
          f"hdgear.sweep {s:.3f} s (medians of 9, alternated): ratio {s / c:.3f} (bar <= 1)")
