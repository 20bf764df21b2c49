"""The study's main figure from the Python API: x'(τ) for γ = 30, 10, 1, 0.1 (one slow period
after the transient), and the transformed phase portrait (a, x) with the equilibrium curves.

    python examples/python/study.py [OUTDIR]      (writes OUTDIR/study-xdot.png, study-phase.png)
"""
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import hdgear  # noqa: E402

out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
out.mkdir(parents=True, exist_ok=True)
GAMMAS = [30, 10, 1, 0.1]

fig, axes = plt.subplots(4, 1, figsize=(8, 9), sharex=True)
phase, ax2 = plt.subplots(figsize=(7, 5))
for ax, g in zip(axes, GAMMAS):
    p = hdgear.Params.paper(gamma=g)
    period = 2 * math.pi / p.omega
    tr = hdgear.simulate(p, t_end=2 * period)
    keep = tr.t >= period  # the second period: the transient is gone
    verdict = hdgear.analyze(p).classification
    ax.plot(tr.t[keep] - period, tr.xdot[keep], lw=0.8)
    ax.set_ylabel("x'")
    ax.set_title(f"γ = {g}: {verdict.mode}", fontsize=10, loc="left")
    c = hdgear.curve(p, points=801)
    line, = ax2.plot(c["a"], c["x"], lw=1.2, label=f"γ = {g}")
    ax2.plot(tr.a[keep], tr.x[keep], lw=0.6, color=line.get_color(), alpha=0.6)
axes[-1].set_xlabel("τ − T (one slow period)")
fig.tight_layout()
fig.savefig(out / "study-xdot.png", dpi=110)
ax2.set_xlabel("a = sin ωτ")
ax2.set_ylabel("x")
ax2.set_title("transformed phase portrait: equilibrium curves and trajectories")
ax2.legend()
phase.tight_layout()
phase.savefig(out / "study-phase.png", dpi=110)
print(f"wrote {out / 'study-xdot.png'} and {out / 'study-phase.png'}")
