#!/usr/bin/env python3
"""Ringing after a slow load crosses a knee of a piecewise-linear stiffness, sharp or rounded.

The first knee of CSF-20-50's catalogue law in the reduced units of `hdgear card check CSF-20-50`
(damping from the hysteresis loss): slopes k1 -> k2 at x1, the load mu + delta sin(omega t).
The knee is rounded over a twist width w (the slope a logistic blend of k1 and k2; w = 0 is the
corner). Classic RK4 at h = 2e-3 from the quasi-static state at a = mu - delta/2 to the load's
maximum; prints the largest |x' - quasi-static x'| after the start-up (t > 20). Used for the table
in docs/src/cards.md ("With the catalogue's own curve"). Pure Python, about a minute.
"""
import math
k1, k2, x1 = 59.34, 82.17, 1.211
mu, delta, omega = 71.86, 12.83, 0.0401
def gp(u, w):
    if w == 0: return k1 if u < x1 else k2
    return k1 + (k2 - k1) / (1 + math.exp(-(u - x1) / w))
def g(u, w):
    if w == 0: return k1 * u if u < x1 else k1 * x1 + k2 * (u - x1)
    # integral of gp: k1 u + (k2-k1) w softplus((u-x1)/w), offset so g(0) matches
    sp = lambda z: z + math.log1p(math.exp(-z)) if z > 0 else math.log1p(math.exp(z))
    return k1 * u + (k2 - k1) * w * (sp((u - x1) / w) - sp(-x1 / w))
def run(w):
    # start on the quasi-static state at a = mu - delta/2 (below the knee), load rising
    h = 2e-3; t = -math.asin(0.5) / omega
    f = lambda t, x, v: (mu + delta * math.sin(omega * t) - v - g(x, w))
    # quasi-static start
    a0 = mu + delta * math.sin(omega * t); lo, hi = 0.0, 5.0
    for _ in range(100):
        m = 0.5 * (lo + hi)
        (lo, hi) = (m, hi) if g(m, w) < a0 else (lo, m)
    x = lo; v = delta * omega * math.cos(omega * t) / gp(x, w)
    peak = 0.0; t0 = t; t_end = t + 0.5 * math.pi / omega
    while t < t_end:
        k1x, k1v = v, f(t, x, v)
        k2x, k2v = v + h/2*k1v, f(t+h/2, x+h/2*k1x, v+h/2*k1v)
        k3x, k3v = v + h/2*k2v, f(t+h/2, x+h/2*k2x, v+h/2*k2v)
        k4x, k4v = v + h*k3v, f(t+h, x+h*k3x, v+h*k3v)
        x += h/6*(k1x+2*k2x+2*k3x+k4x); v += h/6*(k1v+2*k2v+2*k3v+k4v); t += h
        # deviation of x' from the quasi-static rate
        qs = delta * omega * math.cos(omega * t) / gp(x, w)
        if t > t0 + 20: peak = max(peak, abs(v - qs))
    return peak
for w in [0, 1e-3, 1e-2, 3e-2, 1e-1, 3e-1]:
    print(f"w {w:7.0e}  largest |x' - quasi-static x'| after the knee {run(w):.3e}")
