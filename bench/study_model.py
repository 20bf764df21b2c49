"""The study's model for the comparison scripts: its parameters and the default start."""
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
