#!/usr/bin/env python3
"""Independent burst verdicts for the study's model with friction or hysteresis.

Writes friction_cases.json beside this file. Nothing here comes from hdgear's code: the model is
integrated with scipy's solve_ivp (DOP853, rtol = atol = 1e-12), sticking friction by an own
event-driven stick/slip loop, and the signatures are written from their definitions in hdgear's
guide (docs/src/bursts.md: jump, overshoot, ringing, stick-slip; group gap, floors, window).

    x'' + x' + alpha x^3 - x^2 + gamma (x - eps) + T(x', z) = mu + delta sin(omega t)

The cases are drawn at random (seed below) from ranges set before any was run: the study's
stiffness line and physical sets with alpha*eps = 1, five laws (smooth Coulomb, regularised
Stribeck, Coulomb-Stribeck with sticking, Bouc-Wen, LuGre), friction levels from 1e-3 to about
the load's swing. Usage: python3 friction_cases.py [N] (default 36 cases).
"""

import json
import math
import sys

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

RTOL = ATOL = 1e-12
SEED = 20261128


def stiffness(p, x):
    return p["alpha"] * x**3 - x**2 + p["gamma"] * (x - p["eps"])


def level(fc, fs, vst, v):
    return fc + (fs - fc) * math.exp(-((v / vst) ** 2))


def term_torque(kind, q, v, z):
    """Torque of a smooth term at rate v and internal state z (its x part is in static_part)."""
    if kind == "friction":
        return q["fc"] * math.tanh(v / q["vs"])
    if kind == "stribeck":
        return level(q["fc"], q["fs"], q["vst"], v) * math.tanh(v / q["vr"]) + q["cv"] * v
    if kind == "boucwen":
        return q["kh"] * (1 - q["rho"]) * z
    if kind == "lugre":
        g = level(q["fc"], q["fs"], q["vst"], v)
        zdot = v - q["sigma0"] * abs(v) * z / g
        return q["sigma0"] * z + q["sigma1"] * zdot + q["sigma2"] * v
    return 0.0


def static_part(kind, q):
    """The term's torque linear in x (Bouc-Wen's elastic share), as a slope."""
    return q["kh"] * q["rho"] if kind == "boucwen" else 0.0


def state_rate(kind, q, v, z):
    if kind == "boucwen":
        n = q["nh"]
        return q["ah"] * v - q["betah"] * abs(v) * abs(z) ** (n - 1) * z - q["gammah"] * v * abs(z) ** n
    if kind == "lugre":
        return v - q["sigma0"] * abs(v) * z / level(q["fc"], q["fs"], q["vst"], v)
    return None


def equivalent(p, kind, q):
    """The study's set whose curve is the model's at rest (a linear static torque folds into gamma)."""
    k = static_part(kind, q)
    g = p["gamma"] + k
    return dict(p, gamma=g, eps=p["gamma"] * p["eps"] / g)


def roots(p, a):
    """Real equilibria of the equivalent set at a, ascending, with stability (g' > 0)."""
    c = [p["alpha"], -1.0, p["gamma"], -p["gamma"] * p["eps"] - p["mu"] - p["delta"] * a]
    r = np.roots(c)
    xs = sorted(float(v.real) for v in r if abs(v.imag) < 1e-9 * max(1.0, abs(v)))
    return [(x, 3 * p["alpha"] * x * x - 2 * x + p["gamma"] > 0) for x in xs]


def folds(p):
    """Fold abscissae (g' = 0), or None."""
    d = 4 - 12 * p["alpha"] * p["gamma"]
    if d <= 0:
        return None
    s = math.sqrt(d)
    return ((2 - s) / (6 * p["alpha"]), (2 + s) / (6 * p["alpha"]))


class Piece:
    """A dense piece of the trajectory on [t0, t1]: sol(t) -> (x, v), or a rest at x."""

    def __init__(self, t0, t1, sol=None, x=None):
        self.t0, self.t1, self.sol, self.x = t0, t1, sol, x

    def xv(self, t):
        if self.sol is None:
            return np.array([np.full_like(t, self.x), np.zeros_like(t)])
        return self.sol(t)[:2]


def integrate_smooth(p, kind, q, x0, t_end):
    def f(t, y):
        x, v = y[0], y[1]
        z = y[2] if len(y) > 2 else 0.0
        load = p["mu"] + p["delta"] * math.sin(p["omega"] * t)
        acc = load - v - stiffness(p, x) - static_part(kind, q) * x - term_torque(kind, q, v, z)
        out = [v, acc]
        if len(y) > 2:
            out.append(state_rate(kind, q, v, z))
        return out

    def acc_event(t, y):
        return f(t, y)[1]

    y0 = [x0, 0.0] + ([0.0] if kind in ("boucwen", "lugre") else [])
    s = solve_ivp(f, (0, t_end), y0, method="DOP853", rtol=RTOL, atol=ATOL,
                  dense_output=True, events=acc_event)
    assert s.status == 0, s.message
    ext = [(float(t), float(y[1])) for t, y in zip(s.t_events[0], s.y_events[0])]
    return [Piece(0.0, t_end, s.sol)], ext, []


def integrate_sticking(p, q, x0, t_end):
    """Coulomb-Stribeck-viscous friction with sticking: slips with a fixed sgn x', rests held."""
    fc, fs, vst, cv = q["fc"], q["fs"], q["vst"], q["cv"]
    load = lambda t: p["mu"] + p["delta"] * math.sin(p["omega"] * t)
    pieces, ext, rests = [], [], []
    t, x, side, entered = 0.0, x0, 0, 0
    while t < t_end:
        if side == 0:
            rest = lambda s: abs(load(s) - stiffness(p, x)) - fs
            if rest(t) > 0:
                side = 1 if load(t) - stiffness(p, x) > 0 else -1
            else:
                h = 2 * math.pi / p["omega"] / 4000
                s1 = t
                while s1 < t_end and rest(min(s1 + h, t_end)) <= 0:
                    s1 = min(s1 + h, t_end)
                if s1 >= t_end:
                    pieces.append(Piece(t, t_end, x=x))
                    break
                tb = brentq(rest, s1, min(s1 + h, t_end), xtol=1e-13, rtol=1e-15)
                pieces.append(Piece(t, tb, x=x))
                side = 1 if load(tb) - stiffness(p, x) > 0 else -1
                rests.append((t, tb))
                if side == entered:  # a rest left the way it was entered: an extremum at 0
                    ext.append((tb, 0.0))
                t = tb
            continue
        sgn = side

        def f(s, y, sgn=sgn):
            v = y[1]
            acc = load(s) - v - stiffness(p, y[0]) - sgn * level(fc, fs, vst, v) - cv * v
            return [v, acc]

        def stop(s, y):
            return y[1]

        stop.terminal, stop.direction = True, -sgn

        def acc_event(s, y, f=f):
            return f(s, y)[1]

        sol = solve_ivp(f, (t, t_end), [x, 0.0], method="DOP853", rtol=RTOL, atol=ATOL,
                        dense_output=True, events=[stop, acc_event],
                        first_step=1e-8)
        ext += [(float(a), float(b[1])) for a, b in zip(sol.t_events[1], sol.y_events[1])
                if a > t + 1e-9]
        t1 = float(sol.t[-1])
        pieces.append(Piece(t, t1, sol.sol))
        x = float(sol.y[0, -1])
        t = t1
        if sol.status == 1:  # x' back at 0: stick, or slip on the other side
            a = load(t) - stiffness(p, x)
            entered = sgn
            side = 0 if abs(a) <= fs else (1 if a > 0 else -1)
    return pieces, sorted(ext), rests


def classify(p_eq, omega, pieces, ext, rests):
    period = 2 * math.pi / omega
    gap = min(20.0, period / 8)
    span = [-1.0, 1.0]
    xs = [x for a in span for x, _ in roots(p_eq, a)] + [r[0] for a in np.linspace(-1, 1, 201)
                                                          for r in roots(p_eq, a)]
    extent = max(xs) - min(xs)
    k0 = math.ceil((omega * period - math.pi / 2) / math.pi)
    w0 = (math.pi / 2 + k0 * math.pi) / omega
    w1 = w0 + 2 * period
    margin = min(period / 4, 5 * gap)
    lo, hi = w0 - margin, w1 + margin
    # dense samples of x, x'
    ts, xs_, vs = [], [], []
    for pc in pieces:
        a, b = max(pc.t0, lo), min(pc.t1, hi)
        if a >= b:
            continue
        n = max(2, int((b - a) / 0.02))
        t = np.linspace(a, b, n)
        x, v = pc.xv(t)
        ts.append(t), xs_.append(x), vs.append(v)
    t, x, v = np.concatenate(ts), np.concatenate(xs_), np.concatenate(vs)
    # extrema of x' in the scan, pruned: the pair with the smallest swing below the floor goes
    e = [(a, b) for a, b in ext if lo <= a <= hi]
    floor = 1e-3 * omega * extent
    while len(e) >= 2:
        sw = [abs(e[i + 1][1] - e[i][1]) for i in range(len(e) - 1)]
        i = int(np.argmin(sw))
        if sw[i] >= floor:
            break
        del e[i:i + 2]
    events = [(a, "ext", abs(b)) for a, b in e]
    # the followed equilibrium and the leading lobes of e = x - x*
    fl = folds(p_eq)
    a_t = np.sin(omega * t)
    xstar = np.empty_like(x)
    for i in range(len(t)):
        st = [r for r, stable in roots(p_eq, a_t[i]) if stable]
        xstar[i] = min(st, key=lambda r: abs(r - x[i]))
    err = x - xstar
    cosw = np.cos(omega * t)
    sign = np.sign(err)
    zeros = np.nonzero(sign[1:] * sign[:-1] < 0)[0]
    for j in range(len(zeros) - 1):
        i0, i1 = zeros[j] + 1, zeros[j + 1]
        if i1 < i0:
            continue
        seg = slice(i0, i1 + 1)
        lead = err[seg] * cosw[seg]
        if np.all(lead > 0):
            k = i0 + int(np.argmax(np.abs(err[seg])))
            if abs(err[k]) >= 1e-4 * extent:
                events.append((t[k], "lobe", abs(v[k])))
    # jumps: x crosses the far fold abscissa after being beyond the near one
    if fl:
        below = x < fl[0]
        above = x > fl[1]
        state = 0
        for i in range(len(t)):
            if below[i]:
                if state == 1:
                    events.append((t[i], "jump", abs(v[i])))
                state = -1
            elif above[i]:
                if state == -1:
                    events.append((t[i], "jump", abs(v[i])))
                state = 1
    events.sort()
    groups, cur = [], []
    for ev in events:
        if cur and ev[0] - cur[-1][0] > gap:
            groups.append(cur)
            cur = []
        cur.append(ev)
    if cur:
        groups.append(cur)
    breakaways = [b for _, b in rests]
    bursts = []
    for g in groups:
        n_ext = sum(1 for ev in g if ev[1] == "ext")
        lobe = any(ev[1] == "lobe" for ev in g)
        jump = any(ev[1] == "jump" for ev in g)
        if not (n_ext >= 3 or lobe or jump):
            continue
        exts = [ev for ev in g if ev[1] == "ext"] or g
        pulse = max(exts, key=lambda ev: ev[2])
        # a slip burst: its pulse is the first extremum of x' after a breakaway
        prior = [b for b in breakaways if b <= pulse[0]]
        slip = False
        if prior:
            after = [a for a, _ in ext if a > prior[-1] + 1e-9]
            slip = bool(after) and abs(after[0] - pulse[0]) < 1e-9
        bursts.append(dict(t=pulse[0], pulse=pulse[2], ringing=n_ext >= 3, overshoot=lobe,
                           jump=jump, slip=slip, long=g[-1][0] - g[0][0] > period / 2))
    inw = [b for b in bursts if w0 <= b["t"] < w1]
    jump = any(b["jump"] for b in inw)
    slip_dom = bool(inw) and max(inw, key=lambda b: b["pulse"])["slip"]
    if jump:
        verdict = "fold-jump"
    elif slip_dom:
        verdict = "stick-slip"
    elif any(b["overshoot"] for b in inw):
        verdict = "overshoot"
    elif any(b["ringing"] for b in inw):
        verdict = "ringing"
    else:
        verdict = "no-bursts"
    # fast motion that never stops (a group longer than T/2) has no count
    continuous = any(b["long"] for b in bursts)
    return dict(verdict=verdict, bursts_per_period=None if continuous else len(inw) / 2,
                slip_bursts_per_period=sum(b["slip"] for b in inw) / 2,
                continuous_fast_motion=continuous,
                peak_abs_xdot=float(np.max(np.abs(v[(t >= w0) & (t < w1)]))))


def draw(rng):
    physical = rng.random() < 0.3
    gamma = float(10 ** rng.uniform(-1, math.log10(30)))
    p = dict(alpha=16.0, gamma=gamma, eps=0.71, mu=0.07, delta=15.0,
             omega=float(rng.choice([0.01, 0.005, 0.02])))
    if physical:
        p["eps"] = float(rng.choice([0.3, 0.5, 1.0]))
        p["alpha"] = 1 / p["eps"]
        p["gamma"] = float(10 ** rng.uniform(math.log10(0.5 / p["alpha"]), math.log10(30)))
        p["delta"] = float(rng.choice([2.0, 5.0, 15.0]))
    kind = str(rng.choice(["friction", "stribeck", "coulomb", "coulomb", "boucwen", "lugre"]))
    f = float(10 ** rng.uniform(-3, math.log10(0.4 * p["delta"])))
    if kind == "friction":
        q = dict(fc=f, vs=float(10 ** rng.uniform(-2, -0.5)))
    elif kind == "stribeck":
        q = dict(fc=f, fs=f * float(rng.uniform(1, 3)), vst=float(10 ** rng.uniform(-2, -0.5)),
                 cv=float(rng.choice([0.0, 0.2])), vr=float(10 ** rng.uniform(-2.5, -1.5)))
    elif kind == "coulomb":
        q = dict(fc=f, fs=f * float(rng.uniform(1, 3)), vst=float(10 ** rng.uniform(-3, -0.5)),
                 cv=float(rng.choice([0.0, 0.2])))
    elif kind == "boucwen":
        q = dict(kh=float(10 ** rng.uniform(-1, 1)), rho=float(rng.uniform(0, 0.5)), ah=1.0,
                 betah=0.5, gammah=0.5, nh=int(rng.choice([1, 2])))
    else:
        q = dict(fc=f, fs=f * float(rng.uniform(1, 2)), vst=float(10 ** rng.uniform(-2, -1)),
                 sigma0=float(10 ** rng.uniform(1, 2)), sigma1=0.0, sigma2=0.0)
        q["sigma1"] = float(2 * 0.1 * math.sqrt(q["sigma0"]))
    return p, kind, q


ORDER = {
    "friction": ["fc", "vs"],
    "stribeck": ["fc", "fs", "vst", "cv", "vr"],
    "coulomb": ["fc", "fs", "vst", "cv"],
    "boucwen": ["kh", "rho", "ah", "betah", "gammah", "nh"],
    "lugre": ["fc", "fs", "vst", "sigma0", "sigma1", "sigma2"],
}


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 36
    rng = np.random.default_rng(SEED)
    cases = []
    for i in range(n):
        p, kind, q = draw(rng)
        p_eq = equivalent(p, kind, q)
        x0 = next(r for r, stable in roots(p_eq, 0.0) if stable)
        period = 2 * math.pi / p["omega"]
        t_end = 3.75 * period + 60
        if kind == "coulomb":
            pieces, ext, rests = integrate_sticking(p, q, x0, t_end)
        else:
            pieces, ext, rests = integrate_smooth(p, kind, q, x0, t_end)
        ref = classify(p_eq, p["omega"], pieces, ext, rests)
        cases.append(dict(id=f"case-{i:02d}-{kind}", params=p, term=kind,
                          values=[q[k] for k in ORDER[kind]], reference=ref))
        print(cases[-1]["id"], ref["verdict"], ref["bursts_per_period"], file=sys.stderr)
    meta = dict(
        model="x'' + x' + alpha x^3 - x^2 + gamma (x - eps) + T(x', z) = mu + delta sin(omega t)",
        integrator="scipy solve_ivp DOP853, rtol = atol = 1e-12; sticking friction by an own "
                   "stick/slip loop (slip pieces end at x' = 0 as a terminal event; a rest ends "
                   "where |mu + delta sin(omega t) - g(x)| reaches f_s, by brentq)",
        initial_state="lowest stable equilibrium of the equivalent set at a = 0, x' = 0, "
                      "internal state 0",
        window="discard 1 slow period, then 2 slow periods from the next turning point of a",
        detectors="docs/src/bursts.md: extrema of x' (a rest left the way it was entered is one), "
                  "pruned below 1e-3 omega X; leading lobes of x - x*(a) from 1e-4 X, not "
                  "touching a turning point; jumps across the fold band; groups closer than "
                  "min(20, T/8); a slip burst's pulse is the first extremum after a breakaway",
        verdicts="fold-jump > stick-slip > overshoot > ringing > no-bursts",
        seed=SEED,
        terms={k: v for k, v in ORDER.items()},
    )
    out = __file__.replace(".py", ".json")
    with open(out, "w") as fh:
        json.dump(dict(meta=meta, cases=cases), fh, indent=1)


if __name__ == "__main__":
    main()
