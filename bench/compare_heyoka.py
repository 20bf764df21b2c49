#!/usr/bin/env python3
"""hdgear against heyoka (Taylor's method, LLVM JIT) in the same run, on the same problem.

Problem: the study's model (alpha 16, eps 0.71, mu 0.07, delta 15, omega 0.01), gamma in {30, 0.1}.
  * Time: three slow periods 3*2*pi/omega from the stable equilibrium at a = 0 (x' = 0), final
    state only, best of 5 batches; heyoka scalar, heyoka batch of 8 (time per trajectory), and
    hdgear's Taylor, DOP853 and Taylor batch of 16 lanes (gamma 30 and 0.1 alternating, time per
    trajectory) from `cargo run --profile dist --example time_simulation`.
  * Error: the largest |x - x_ref|, |x' - x'_ref| on the 5-unit grid of
    crates/hdgear/tests/data/paper_trajectories.csv (scipy DOP853 at rtol 1e-13, from rest), heyoka by
    propagate_grid and hdgear by `hdgear simulate --x0 0 --v0 0 --dt 5`.
  * Work-precision: tolerance 1e-6 ... 1e-13 for Taylor, DOP853 and heyoka.

Usage: python3 bench/compare_heyoka.py [REPS]
Creates its own virtual environment (target/bench-venv) with heyoka and numpy on first use.
"""
import csv
import json
import math
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from common import RELEASE, ROOT, ensure_venv
from common import ALPHA, DELTA, EPS, MU, OMEGA, equilibrium
GAMMAS = (30.0, 0.1)
TOLS = (1e-6, 1e-8, 1e-10, 1e-12, 1e-13)


def reference():
    path = ROOT / "crates" / "hdgear" / "tests" / "data" / "paper_trajectories.csv"
    rows = {}
    with open(path) as f:
        for r in csv.DictReader(f):
            rows.setdefault(float(r["gamma"]), []).append(
                (float(r["t"]), float(r["x"]), float(r["xdot"]), float(r["x0"]), float(r["v0"])))
    return rows




def heyoka_system():
    import heyoka as hy
    x, v = hy.make_vars("x", "v")
    a, g, e, m, d, w = (hy.par[i] for i in range(6))
    # x*x*x, not x**3: heyoka's pow goes through log(x), which is NaN for x <= 0
    return [(x, v), (v, m + d * hy.sin(w * hy.time) - v - (a * x * x * x - x * x + g * (x - e)))]


def heyoka_scalar(sys_, gamma, tol, reps):
    import heyoka as hy
    ta = hy.taylor_adaptive(sys_, [0.0, 0.0], tol=tol)
    ta.pars[:] = [ALPHA, gamma, EPS, MU, DELTA, OMEGA]
    t_end = 3 * 2 * math.pi / OMEGA
    x0 = equilibrium(gamma)
    best, steps = float("inf"), 0
    for _ in range(5):
        t0 = time.perf_counter()
        for _ in range(reps):
            ta.time = 0.0
            ta.state[:] = [x0, 0.0]
            out = ta.propagate_until(t_end)
        best = min(best, (time.perf_counter() - t0) / reps)
        steps = out[3]
    return best, steps, ta.order


def heyoka_batch(sys_, tol, reps, lanes=8):
    import heyoka as hy
    import numpy as np
    gammas = [GAMMAS[i % 2] for i in range(lanes)]
    state0 = np.array([[equilibrium(g) for g in gammas], [0.0] * lanes])
    ta = hy.taylor_adaptive_batch(sys_, state0.copy(), tol=tol)
    ta.pars[:] = np.array([[ALPHA] * lanes, gammas, [EPS] * lanes, [MU] * lanes,
                           [DELTA] * lanes, [OMEGA] * lanes])
    t_end = 3 * 2 * math.pi / OMEGA
    best = float("inf")
    for _ in range(5):
        t0 = time.perf_counter()
        for _ in range(reps):
            ta.set_time(0.0)
            ta.state[:] = state0
            ta.propagate_until(t_end)
        best = min(best, (time.perf_counter() - t0) / reps / lanes)
    return best


def heyoka_error(sys_, ref, tol):
    import heyoka as hy
    import numpy as np
    worst = 0.0
    for gamma, rows in ref.items():
        ta = hy.taylor_adaptive(sys_, [rows[0][3], rows[0][4]], tol=tol)
        ta.pars[:] = [ALPHA, gamma, EPS, MU, DELTA, OMEGA]
        grid = np.array([r[0] for r in rows])
        states = ta.propagate_grid(grid)[-1]
        for (t, x, v, _, _), s in zip(rows, states):
            worst = max(worst, abs(s[0] - x), abs(s[1] - v))
    return worst


def hdgear_error(binary, ref, tol, method):
    worst = 0.0
    with tempfile.TemporaryDirectory() as d:
        for gamma, rows in ref.items():
            out = Path(d) / "traj.csv"
            subprocess.run([str(binary), "--quiet", "simulate", "--gamma", str(gamma),
                            "--x0", str(rows[0][3]), "--v0", str(rows[0][4]), "--dt", "5",
                            "--t-end", str(rows[-1][0]), "--rtol", str(tol), "--atol", str(tol),
                            "--method", method, "--out", str(out)], check=True)
            with open(out) as f:
                got = list(csv.DictReader(f))
            for (t, x, v, _, _), g in zip(rows, got):
                worst = max(worst, abs(float(g["x"]) - x), abs(float(g["xdot"]) - v))
    return worst


def main():
    ensure_venv(__file__, ['heyoka', 'numpy'])
    reps = int(sys.argv[1]) if len(sys.argv) > 1 else 100
    subprocess.run(["cargo", "build", "--profile", "dist", "-q", "--example", "time_simulation",
                    "--bin", "hdgear"], cwd=ROOT, check=True)
    binary = RELEASE / "hdgear"
    example = RELEASE / "examples" / "time_simulation"
    lines = subprocess.run([str(example), str(reps), *map(str, TOLS)], check=True,
                           capture_output=True, text=True).stdout.splitlines()
    ours = {(r["method"], r["gamma"], r["rtol"]): r for r in map(json.loads, lines)}
    import heyoka as hy
    sys_ = heyoka_system()
    ref = reference()
    print(f"heyoka {hy.__version__}; {reps} runs per batch, best of 5 batches; 3 slow periods")
    print()
    print("| tol | gamma | hdgear taylor ms | steps | hdgear dop853 ms | steps | heyoka ms | steps "
          "| hdgear batch-16 ms/traj | heyoka batch-8 ms/traj |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for tol in TOLS:
        batch = heyoka_batch(sys_, tol, max(reps // 4, 5))
        for gamma in GAMMAS:
            ht, hs, _ = heyoka_scalar(sys_, gamma, tol, reps)
            t = ours[("taylor", gamma, tol)]
            d = ours[("dop853", gamma, tol)]
            ours_batch = ours[("taylor-batch", 0.1, tol)]["seconds_per_run"]
            print(f"| {tol:.0e} | {gamma} | {t['seconds_per_run'] * 1e3:.3f} | {t['steps']} "
                  f"| {d['seconds_per_run'] * 1e3:.3f} | {d['steps']} | {ht * 1e3:.3f} | {hs} "
                  f"| {ours_batch * 1e3:.3f} | {batch * 1e3:.3f} |")
    print()
    print("max error against the reference trajectories (both gammas of the reference, 4 in all):")
    print()
    print("| tol | hdgear taylor | hdgear dop853 | heyoka |")
    print("|---|---|---|---|")
    for tol in TOLS:
        print(f"| {tol:.0e} | {hdgear_error(binary, ref, tol, 'taylor'):.1e} "
              f"| {hdgear_error(binary, ref, tol, 'dop853'):.1e} | {heyoka_error(sys_, ref, tol):.1e} |")


if __name__ == "__main__":
    main()
