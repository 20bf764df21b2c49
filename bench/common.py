"""Shared by the comparison scripts: the study's model (its parameters and the default start)
and the virtual environment the scripts run in."""
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
VENV = ROOT / "target" / "bench-venv"
# where `cargo build --profile dist` (run in ROOT) puts its binaries: CARGO_TARGET_DIR if set
RELEASE = ROOT / os.environ.get("CARGO_TARGET_DIR", "target") / "dist"

ALPHA, EPS, MU, DELTA, OMEGA = 16.0, 0.71, 0.07, 15.0, 0.01


def equilibrium(gamma):
    """The stable equilibrium of the fast subsystem at a = 0 (the default start)."""
    import numpy as np
    roots = np.roots([ALPHA, -1.0, gamma, -(gamma * EPS + MU)])
    real = sorted(r.real for r in roots if abs(r.imag) < 1e-12)
    for r in real:
        if 3 * ALPHA * r * r - 2 * r + gamma > 0:
            return r
    return real[0]


def ensure_venv(script, modules, extra_env=None):
    """Re-runs `script` inside target/bench-venv, installing `modules` (pip names) there first if
    they cannot be imported; returns at once when already inside."""
    if os.environ.get("HDGEAR_BENCH_VENV") == "1":
        return
    py = VENV / "bin" / "python"
    if not py.exists():
        subprocess.run([sys.executable, "-m", "venv", str(VENV)], check=True)
    probe = "; ".join(f"import {m}" for m in modules)
    if subprocess.run([str(py), "-c", probe], capture_output=True).returncode != 0:
        subprocess.run([str(py), "-m", "pip", "install", "-q", *modules], check=True)
    env = dict(os.environ, HDGEAR_BENCH_VENV="1", **(extra_env or {}))
    sys.exit(subprocess.run([str(py), script, *sys.argv[1:]], env=env).returncode)
