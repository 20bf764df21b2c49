#!/usr/bin/env python3
"""Times scipy's solve_ivp DOP853 against hdgear on the same problem and prints the ratio.

Problem: the study's model (alpha 16, eps 0.71, mu 0.07, delta 15, omega 0.01), gamma in {30, 0.1},
three slow periods 3*2*pi/omega, start on the stable equilibrium at a = 0 with x' = 0,
rtol = atol = 1e-10, no dense output (final state only) on both sides.

Usage: python3 bench/compare_scipy.py            (runs in target/bench-venv with numpy and scipy)
The foundation issue's bar: hdgear at least 150x faster per simulation.
"""
import json
import math
import subprocess
import sys
import time
from pathlib import Path

from common import ALPHA, DELTA, EPS, MU, OMEGA, ensure_venv, equilibrium


def rhs(gamma):
    def f(t, y):
        x, v = y
        g = ALPHA * x**3 - x**2 + gamma * (x - EPS)
        return [v, MU + DELTA * math.sin(OMEGA * t) - v - g]
    return f




def time_scipy(gamma, reps=3):
    from scipy.integrate import solve_ivp
    t_end = 3 * 2 * math.pi / OMEGA
    y0 = [equilibrium(gamma), 0.0]
    best, sol = float("inf"), None
    for _ in range(reps):
        t0 = time.perf_counter()
        sol = solve_ivp(rhs(gamma), (0.0, t_end), y0, method="DOP853", rtol=1e-10, atol=1e-10)
        best = min(best, time.perf_counter() - t0)
    return best, sol


def main():
    ensure_venv(__file__, ["numpy", "scipy"])
    root = Path(__file__).resolve().parent.parent
    out = subprocess.run(
        ["cargo", "run", "--quiet", "--profile", "dist", "--example", "time_simulation"],
        cwd=root, check=True, capture_output=True, text=True,
    ).stdout
    rust = {(row["method"], row["gamma"]): row for row in map(json.loads, out.split())}
    worst_ratio = float("inf")
    for gamma in (30.0, 0.1):
        t_py, sol = time_scipy(gamma)
        for method in ("taylor", "dop853"):
            r = rust[(method, gamma)]
            ratio = t_py / r["seconds_per_run"]
            worst_ratio = min(worst_ratio, ratio)
            print(f"gamma {gamma:>5}: scipy DOP853 {t_py*1e3:8.1f} ms ({sol.nfev} rhs evals)   "
                  f"hdgear {method:6} {r['seconds_per_run']*1e3:6.3f} ms ({r['rhs_evals']} rhs "
                  f"evals, {r['steps']} steps)   ratio {ratio:6.0f}x")
    print(f"slowest ratio: {worst_ratio:.0f}x (bar: >= 150x)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
