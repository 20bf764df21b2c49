#!/usr/bin/env python3
"""hdgear's assembled model against heyoka (Taylor's method, LLVM JIT) in the same run, on the
study's model with regularised Coulomb-Stribeck-viscous friction:

    x'' + x' + alpha x^3 - x^2 + gamma (x - eps)
        + (fc + (fs - fc) exp(-(x'/vst)^2)) tanh(x'/vr) + cv x' = mu + delta sin(omega t)

alpha 16, gamma 0.1, eps 0.71, mu 0.07, delta 1, omega 0.5 (a sine the friction holds at times:
stick-slip), fc 0.3, fs 0.4, vst 0.1, cv 0.05, vr in {1e-2, 1e-3}; from rest to t = 60, final
state only, best of 5 batches. hdgear runs `hdgear::model::Model` (every recurrence derived from
the terms) by `cargo run --release --example time_terms`; heyoka builds its own from the
expression. Error: |x - x_ref| + |x' - x'_ref| at t = 60 against heyoka at tol 1e-16 with its
step capped at 2e-4 (the reference: without a cap, heyoka's own steps cross the friction's
transitions, where tanh's series converges later than the state's rows show, and at v_r = 1e-3 its
uncapped 1e-16 run is itself wrong by about 1e-6). "heyoka at equal error" is heyoka's fastest run
over the tolerances 1e-8 ... 1e-14 and step caps (none, 0.1, 0.03, 0.01, 0.003) whose error is at
most hdgear's: the two compared at equal accuracy, not only at equal tolerance.

Usage: python3 bench/compare_heyoka_terms.py [REPS]
Creates its own virtual environment (target/bench-venv) with heyoka and numpy on first use.
"""
import json
import subprocess
import sys
import time

from common import ROOT, ensure_venv

ALPHA, GAMMA, EPS, MU, DELTA, OMEGA = 16.0, 0.1, 0.71, 0.07, 1.0, 0.5
FC, FS, VST, CV = 0.3, 0.4, 0.1, 0.05
VRS = (1e-2, 1e-3)
T_END = 60.0
TOLS = (1e-8, 1e-10, 1e-12)
SEARCH_TOLS = (1e-8, 1e-10, 1e-12, 1e-14)
CAPS = (None, 0.1, 0.03, 0.01, 0.003)
REF_CAP = 2e-4


def heyoka_system():
    import heyoka as hy
    x, v = hy.make_vars("x", "v")
    vr = hy.par[0]
    friction = (FC + (FS - FC) * hy.exp(-(v / VST) * (v / VST))) * hy.tanh(v / vr) + CV * v
    stiffness = ALPHA * x * x * x - x * x + GAMMA * (x - EPS)
    return [(x, v), (v, MU + DELTA * hy.sin(OMEGA * hy.time) - v - stiffness - friction)]


def heyoka_run(sys_, vr, tol, reps, cap=None, batches=5):
    import heyoka as hy
    ta = hy.taylor_adaptive(sys_, [0.0, 0.0], tol=tol, pars=[vr])
    best, steps = float("inf"), 0
    kw = {} if cap is None else {"max_delta_t": cap}
    for _ in range(batches):
        t0 = time.perf_counter()
        for _ in range(reps):
            ta.time = 0.0
            ta.state[:] = [0.0, 0.0]
            out = ta.propagate_until(T_END, **kw)
        best = min(best, (time.perf_counter() - t0) / reps)
        steps = out[3]
    return best, steps, (float(ta.state[0]), float(ta.state[1]))


def main():
    ensure_venv(__file__, ['heyoka', 'numpy'])
    reps = int(sys.argv[1]) if len(sys.argv) > 1 else 50
    subprocess.run(["cargo", "build", "--release", "-q", "--example", "time_terms"], cwd=ROOT,
                   check=True)
    example = ROOT / "target" / "release" / "examples" / "time_terms"
    lines = subprocess.run([str(example), str(reps), str(T_END), ",".join(map(str, VRS)),
                            *map(str, TOLS)], check=True, capture_output=True,
                           text=True).stdout.splitlines()
    ours = {(r["vr"], r["rtol"]): r for r in map(json.loads, lines)}
    import heyoka as hy
    sys_ = heyoka_system()
    print(f"heyoka {hy.__version__}; {reps} runs per batch, best of 5 batches; t = 0 ... {T_END}")
    print()
    print("| v_r | tol | hdgear taylor ms | steps | error | heyoka ms | steps | error "
          "| heyoka at equal error: ms (tol, cap) | heyoka / hdgear at equal error |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for vr in VRS:
        _, _, ref = heyoka_run(sys_, vr, 1e-16, 1, cap=REF_CAP, batches=1)
        err = lambda s: abs(s[0] - ref[0]) + abs(s[1] - ref[1])
        grid = []
        for tol in SEARCH_TOLS:
            for cap in CAPS:
                t, _, end = heyoka_run(sys_, vr, tol, max(1, reps // 5), cap=cap, batches=3)
                grid.append((t, err(end), tol, cap))
        for tol in TOLS:
            ht, hs, hy_end = heyoka_run(sys_, vr, tol, reps)
            o = ours[(vr, tol)]
            mine = err((o["x"], o["xdot"]))
            equal = min((g for g in grid if g[1] <= mine), default=None)
            if equal is None:
                at_equal, ratio = "none reaches it", "—"
            else:
                cap = "none" if equal[3] is None else f"{equal[3]:g}"
                at_equal = f"{equal[0] * 1e3:.3f} ({equal[2]:.0e}, {cap})"
                ratio = f"{equal[0] / o['seconds_per_run']:.2f}"
            print(f"| {vr:.0e} | {tol:.0e} | {o['seconds_per_run'] * 1e3:.3f} | {o['steps']} "
                  f"| {mine:.1e} | {ht * 1e3:.3f} | {hs} | {err(hy_end):.1e} "
                  f"| {at_equal} | {ratio} |")


if __name__ == "__main__":
    main()
