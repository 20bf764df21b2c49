#!/usr/bin/env python3
"""A 1000-point gamma sweep: hdgear (full burst analysis) against a numba-compiled integrator
(integration only), in the same run, on 2 threads.

numba side: adaptive Dormand-Prince 5(4) (the scheme of scipy's RK45, standard controller) at
rtol = atol = 1e-10, three slow periods 3*2*pi/omega from the stable equilibrium at a = 0, for
gamma log-spaced from 0.1 to 30, in a `prange` loop (2 threads); JIT compilation excluded.
hdgear side: `hdgear sweep --param gamma=0.1:30:1000:log --threads 2` (a whole process: burst
detection and classification of every point, CSV written), best of 3.

Usage: python3 bench/compare_numba.py
Creates its own virtual environment (target/bench-venv) with numba and numpy on first use.
"""
import math
import subprocess
import tempfile
import time
from pathlib import Path

from common import RELEASE, ROOT, ensure_venv


def build_numba():
    import numba as nb
    import numpy as np
    from common import ALPHA, DELTA, EPS, MU, OMEGA

    # Dormand-Prince 5(4) tableau
    c = np.array([0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0, 1.0])
    a = np.zeros((7, 7))
    a[1, :1] = [1 / 5]
    a[2, :2] = [3 / 40, 9 / 40]
    a[3, :3] = [44 / 45, -56 / 15, 32 / 9]
    a[4, :4] = [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729]
    a[5, :5] = [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656]
    a[6, :6] = [35 / 384, 0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84]
    b = a[6].copy()
    e = b - np.array([5179 / 57600, 0, 7571 / 16695, 393 / 640, -92097 / 339200, 187 / 2100, 1 / 40])

    @nb.njit(cache=False, fastmath=False)
    def rhs(t, x, v, gamma):
        g = ALPHA * x * x * x - x * x + gamma * (x - EPS)
        return v, MU + DELTA * math.sin(OMEGA * t) - v - g

    @nb.njit(cache=False)
    def integrate(gamma, x0, t_end, tol):
        t, x, v = 0.0, x0, 0.0
        h = 1e-3
        kx = np.zeros(7)
        kv = np.zeros(7)
        steps = 0
        while t < t_end:
            if t + h > t_end:
                h = t_end - t
            for s in range(7):
                xs, vs = x, v
                for j in range(s):
                    xs += h * a[s, j] * kx[j]
                    vs += h * a[s, j] * kv[j]
                kx[s], kv[s] = rhs(t + c[s] * h, xs, vs, gamma)
            xn, vn, ex, ev = x, v, 0.0, 0.0
            for s in range(7):
                xn += h * b[s] * kx[s]
                vn += h * b[s] * kv[s]
                ex += h * e[s] * kx[s]
                ev += h * e[s] * kv[s]
            sx = tol + tol * max(abs(x), abs(xn))
            sv = tol + tol * max(abs(v), abs(vn))
            err = math.sqrt(0.5 * ((ex / sx) ** 2 + (ev / sv) ** 2))
            if err <= 1.0:
                t += h
                x, v = xn, vn
                steps += 1
            fac = 0.9 * err ** -0.2 if err > 0 else 10.0
            h *= min(10.0, max(0.2, fac))
        return x, v, steps

    @nb.njit(parallel=True, cache=False)
    def sweep(gammas, x0s, t_end, tol):
        out = np.zeros((gammas.size, 3))
        for i in nb.prange(gammas.size):
            x, v, s = integrate(gammas[i], x0s[i], t_end, tol)
            out[i, 0], out[i, 1], out[i, 2] = x, v, s
        return out

    return sweep


def main():
    ensure_venv(__file__, ['numba', 'numpy'], {'NUMBA_NUM_THREADS': '2'})
    import numpy as np
    from common import OMEGA, equilibrium
    subprocess.run(["cargo", "build", "--profile", "dist", "-q", "--bin", "hdgear"], cwd=ROOT, check=True)
    binary = RELEASE / "hdgear"
    gammas = np.geomspace(0.1, 30.0, 1000)
    x0s = np.array([equilibrium(g) for g in gammas])
    t_end = 3 * 2 * math.pi / OMEGA
    sweep = build_numba()
    sweep(gammas[:4], x0s[:4], 10.0, 1e-10)  # JIT compilation, not timed
    best_numba = float("inf")
    for _ in range(3):
        t0 = time.perf_counter()
        out = sweep(gammas, x0s, t_end, 1e-10)
        best_numba = min(best_numba, time.perf_counter() - t0)
    best_ours = float("inf")
    with tempfile.TemporaryDirectory() as d:
        for _ in range(3):
            t0 = time.perf_counter()
            subprocess.run([str(binary), "--quiet", "sweep", "--param", "gamma=0.1:30:1000:log",
                            "--threads", "2", "--out", str(Path(d) / "s.csv")], check=True,
                           capture_output=True)
            best_ours = min(best_ours, time.perf_counter() - t0)
    print(f"numba Dormand-Prince 5(4), 1000 gammas, 2 threads, integration only: {best_numba:.3f} s "
          f"({int(out[:, 2].mean())} steps per point on average)")
    print(f"hdgear sweep, 1000 gammas, 2 threads, full burst analysis, whole process: "
          f"{best_ours:.3f} s")
    print(f"hdgear is {best_numba / best_ours:.1f}x faster")


if __name__ == "__main__":
    main()
