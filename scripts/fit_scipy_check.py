"""An independent check of `hdgear fit`: the same synthetic data fitted with scipy's
least_squares, on a model written here from the laws' equations (no hdgear code), must give
the same estimates to within hdgear's 95 % intervals. Run by scripts/python-tests.sh:

    python scripts/fit_scipy_check.py target/release/hdgear

Two sets, both with 1 % normal noise from a fixed seed:
  1. a Coulomb–Stribeck–viscous friction sweep, T = (F_c + (F_s − F_c)e^{−(v/v_s)²})·sgn v + c_v v;
  2. a quasi-static torque–twist loop of a three-segment curve with Bouc–Wen hysteresis
     (A = 1, n = 1, ρ = 0): T = P(x) + k_h z, dz/dx = A − β·s·z − γ·|z| on the side s = sgn x'.
"""

import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from scipy.optimize import least_squares

HDGEAR = sys.argv[1] if len(sys.argv) > 1 else "target/release/hdgear"
RNG = np.random.default_rng(2026)


def scv(p, v):
    fc, fs, vs, cv = p
    return (fc + (fs - fc) * np.exp(-((v / vs) ** 2))) * np.sign(v) + cv * v


def piecewise(k, x, x1=5.4e-4, w2=1.06e-3):
    k1, k2, k3 = k
    u = np.abs(x)
    s1 = np.minimum(u, x1)
    s2 = np.clip(u - x1, 0.0, w2)
    s3 = np.maximum(u - x1 - w2, 0.0)
    return np.sign(x) * (k1 * s1 + k2 * s2 + k3 * s3)


def bouc_wen_loop(p, x, steps_per_range=4000):
    """The loop's torque along the twist path x, z from 0 at the first point (RK4)."""
    k1, k2, k3, kh, beta, gamma = p
    h_max = (x.max() - x.min()) / steps_per_range
    z, out = 0.0, np.empty_like(x)
    out[0] = piecewise((k1, k2, k3), x[0])
    f = lambda s, z: 1.0 - beta * s * z - gamma * abs(z)
    for i in range(1, len(x)):
        d = x[i] - x[i - 1]
        s = 1.0 if d > 0 else -1.0
        n = max(1, int(np.ceil(abs(d) / h_max)))
        h = d / n
        for _ in range(n):
            a = f(s, z)
            b = f(s, z + 0.5 * h * a)
            c = f(s, z + 0.5 * h * b)
            e = f(s, z + h * c)
            z += h / 6.0 * (a + 2 * b + 2 * c + e)
        out[i] = piecewise((k1, k2, k3), x[i]) + kh * z
    return out


def hdgear_fit(csv, args):
    cmd = [HDGEAR, "fit", "--data", csv, "--json"] + args
    start = time.perf_counter()
    run = subprocess.run(cmd, capture_output=True, text=True, check=True)
    print(f"  hdgear fit: {time.perf_counter() - start:.2f} s (with its multistart and intervals)")
    return json.loads(run.stdout)


def scipy_fit(*args, **kwargs):
    start = time.perf_counter()
    result = least_squares(*args, **kwargs)
    print(f"  scipy least_squares: {time.perf_counter() - start:.2f} s (one start, finite differences)")
    return result


def compare(name, doc, scipy_x):
    worst = 0.0
    for e, s in zip(doc["estimates"], scipy_x):
        lo, hi = e["profile"] and (e["profile"]["lo"], e["profile"]["hi"]) or e["wald"]
        half = 0.5 * (hi - lo)
        share = abs(e["value"] - s) / half
        worst = max(worst, share)
        print(f"  {e['name']:<18} hdgear {e['value']:.8e}  scipy {s:.8e}  |difference| = {share:.1e} of the half-interval")
        assert lo <= s <= hi, f"{name}: scipy's {e['name']} = {s} outside hdgear's [{lo}, {hi}]"
    print(f"{name}: scipy's estimates inside hdgear's 95 % intervals (largest difference {worst:.1e} of a half-width)")


def main():
    tmp = tempfile.mkdtemp()
    # 1. the friction sweep
    up = 1e-3 * 2000.0 ** (np.arange(30) / 29.0)
    v = np.concatenate([-up[::-1], up])
    truth = (0.5, 0.8, 0.02, 0.3)
    tau = scv(truth, v)
    tau += 0.01 * np.abs(tau).max() * RNG.standard_normal(len(v))
    csv = os.path.join(tmp, "sweep.csv")
    np.savetxt(csv, np.column_stack([v, tau]), delimiter=",", header="speed [rad/s],torque [N m]", comments="")
    doc = hdgear_fit(csv, ["--kind", "friction", "--term", "coulomb", "--free", "fc=0:5", "--free", "fs=0:5", "--free", "vst=1e-4:1", "--free", "cv=0:2"])
    lsq = scipy_fit(lambda p: scv(p, v) - tau, x0=[1.0, 1.0, 0.1, 0.0], bounds=([0, 0, 1e-4, 0], [5, 5, 1, 2]), x_scale="jac", xtol=1e-15, ftol=1e-15, gtol=1e-15)
    compare("Stribeck sweep", doc, lsq.x)

    # 2. the Bouc–Wen loop
    amp = 3e-3
    legs = [np.linspace(a, b, 61)[1:] for a, b in [(0, amp), (amp, -amp), (-amp, amp)]]
    x = np.concatenate([[0.0]] + legs)
    truth = (1.3e4, 1.7e4, 2.5e4, 1.0e4, 3000.0, 2000.0)
    tau = bouc_wen_loop(truth, x)
    tau += 0.01 * np.abs(tau).max() * RNG.standard_normal(len(x))
    csv = os.path.join(tmp, "loop.csv")
    np.savetxt(csv, np.column_stack([x, tau]), delimiter=",", header="twist [rad],torque [N m]", comments="")
    law = os.path.join(tmp, "law.toml")
    with open(law, "w") as f:
        f.write("[piecewise]\nk1 = 1.2e4\nk2 = 1.8e4\nk3 = 2.4e4\nx1 = 5.4e-4\nw2 = 1.06e-3\n"
                "[boucwen]\nkh = 9e3\nrho = 0.0\nah = 1.0\nbetah = 2800.0\ngammah = 2200.0\nnh = 1.0\n")
    doc = hdgear_fit(csv, ["--kind", "loop", "--config", law, "--no-profile", "--starts", "4", "--free", "k1=1e3:1e5", "--free", "k2=1e3:1e5", "--free", "k3=1e3:1e5", "--free", "kh=1e2:1e5", "--free", "betah=10:1e5", "--free", "gammah=-1e4:1e4"])
    lsq = scipy_fit(lambda p: bouc_wen_loop(p, x) - tau, x0=[1.2e4, 1.8e4, 2.4e4, 9e3, 2800.0, 2200.0], x_scale="jac", xtol=1e-12, ftol=1e-12, gtol=1e-12)
    compare("Bouc–Wen loop", doc, lsq.x)


if __name__ == "__main__":
    main()
