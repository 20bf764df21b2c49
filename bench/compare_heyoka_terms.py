#!/usr/bin/env python3
"""hdgear's assembled model against heyoka (Taylor's method, LLVM JIT) in the same run, on the
study's model with regularised Coulomb-Stribeck-viscous friction, then with Bouc-Wen hysteresis
on the twist as well:

    x'' + x' + alpha x^3 - x^2 + gamma (x - eps)
        + (fc + (fs - fc) exp(-(x'/vst)^2)) tanh(x'/vr) + cv x' [+ kh z] = mu + delta sin(omega t)
    [z' = ah x' - betah |x'| z - gammah x' |z|]

alpha 16, gamma 0.1, eps 0.71, mu 0.07, delta 1, omega 0.5 (a sine the friction holds at times:
stick-slip), fc 0.3, fs 0.4, vst 0.1, cv 0.05, vr in {1e-2, 1e-3}; Bouc-Wen kh 0.5, ah 1,
betah 0.5, gammah 0.5 (n = 1, rho = 0). From rest (z = 0) to t = 60, final state only, best of 5
batches. hdgear runs `hdgear::model::Model` (every recurrence derived from the terms) by `cargo
run --profile dist --example time_terms` (`--hysteresis`: the |x'| and |z| exact, piece by piece);
heyoka builds its own from the expression.

Friction: error |x - x_ref| + |x' - x'_ref| at t = 60 against heyoka at tol 1e-16 with its step
capped at 2e-4 (the reference: without a cap, heyoka's own steps cross the friction's
transitions, where tanh's series converges later than the state's rows show, and at v_r = 1e-3 its
uncapped 1e-16 run is itself wrong by about 1e-6). "heyoka at equal error" is heyoka's fastest run
over the tolerances 1e-8 ... 1e-14 and step caps (none, 0.1, 0.03, 0.01, 0.003) whose error is at
most hdgear's: the two compared at equal accuracy, not only at equal tolerance.

Hysteresis: heyoka has no |.| whose series it knows to end at 0, so it runs the law two ways.
"events": the exact law piece by piece, the signs of x' and z parameters, each flipped where a
terminal event stops the run at x' = 0 or z = 0 (this script's loop; heyoka locates the events).
"smooth": |u| regularised as sqrt(u^2 + e^2), e in {1e-4, 1e-6, 1e-8}. The error (summed over x,
x', z) is against heyoka's events form at 1e-16 with its step capped at 2e-4; "heyoka at equal
error" is heyoka's fastest run of either form (tolerances and caps as above) whose error is at most
hdgear's, "regularised heyoka at equal error" the same over the smooth form alone (the form issue
39's speed criterion names; in the friction table it is the same run, friction's tanh being a
regularisation already). The last pair is the same search over the regularised form in heyoka's
batch mode (`taylor_adaptive_batch`, the SIMD width heyoka recommends for the CPU, every lane the
same run, the worst lane's error), its time per trajectory: the batch half of issue 39's
criterion. hdgear's own batch is 16 lanes of the same run, the passes on vector lanes (the
model's terms all having a copy there), each lane taking its scalar run's steps to ~1e-9:
`hdgear::model::integrate_models` for the smooth friction model, and for the hysteresis model,
which switches, `hdgear::model::integrate_switching_models` (each lane piece by piece, its
slipping pieces' passes on the lanes, its switches located on its own step).

Sticking: the same friction law not regularised, sgn x' with sticking (hdgear's `coulomb` term,
`time_terms --sticking`: steps cut at x' = 0, each rest held until the applied torque
A = mu + delta sin(omega t) - (alpha x^3 - x^2 + gamma (x - eps)) leaves the band +-fs). heyoka's
"sticking" form is the same law written here with terminal events: while it slips, the sign s of
x' a parameter and x' = 0 (s x' falling through 0) an event; there it sticks if |A| <= fs (x and
x' frozen by a parameter m = 0) and else reverses; while it sticks, |A| = fs an event where it
breaks away in the direction of A (a crossing of x' = 0 within COOLDOWN of a breakaway is the
rounding of x' starting from rest and is ignored). The error is against that form at 1e-16 with
its step capped at 2e-4. The regularised form (tanh(x'/v_r), v_r in STICKING_VRS) is searched for
equal error too: issue 38 compares hdgear's sticking integration with heyoka on the regularised
law on equal work, and a regularised law is another equation, whose distance from the sticking
one no tolerance closes.

Usage: python3 bench/compare_heyoka_terms.py [REPS]
Creates its own virtual environment (target/bench-venv) with heyoka and numpy on first use.
"""
import json
import math
import subprocess
import sys
import time

from common import RELEASE, ROOT, ensure_venv

ALPHA, GAMMA, EPS, MU, DELTA, OMEGA = 16.0, 0.1, 0.71, 0.07, 1.0, 0.5
FC, FS, VST, CV = 0.3, 0.4, 0.1, 0.05
KH, AH, BETAH, GAMMAH = 0.5, 1.0, 0.5, 0.5  # the example's HYSTERESIS (rho 0, n 1)
VRS = (1e-2, 1e-3)
T_END = 60.0
TOLS = (1e-8, 1e-10, 1e-12)
SEARCH_TOLS = (1e-8, 1e-10, 1e-12, 1e-14)
CAPS = (None, 0.1, 0.03, 0.01, 0.003)
REGULARISATIONS = (1e-4, 1e-6, 1e-8)
REF_CAP = 2e-4
# Terminal events are not looked for again within this time of firing: far below the time
# between two real switches here (the shortest is a sizeable fraction of the load's period).
COOLDOWN = 1e-9
# the regularisations searched against the sticking law
STICKING_VRS = (1e-2, 1e-3, 1e-4)


def applied(lib, x, t=None):
    """The torque on the twist but its friction and damping: A = mu + delta sin(omega t) - g(x),
    as heyoka's expression (t None: heyoka's time) or as a number (`lib` math)."""
    t = lib.time if t is None else t
    return MU + DELTA * lib.sin(OMEGA * t) - (ALPHA * x * x * x - x * x + GAMMA * (x - EPS))


def heyoka_system(form):
    """The equations for `form`: "friction" (x, x'), "sticking" (the law with sgn x' and
    sticking, x' and m parameters 1 and 2), "events" (Bouc-Wen's signs the parameters 1 and 2) or
    "smooth" (Bouc-Wen's |u| as sqrt(u^2 + e^2), e parameter 1); parameter 0 is vr."""
    import heyoka as hy
    x, v, z = hy.make_vars("x", "v", "z")
    vr = hy.par[0]
    friction = (FC + (FS - FC) * hy.exp(-(v / VST) * (v / VST))) * hy.tanh(v / vr) + CV * v
    load = applied(hy, x) - v - friction
    if form == "friction":
        return [(x, v), (v, load)]
    if form == "sticking":
        # parameter 1 the sign s of x', parameter 2 whether it moves (m = 1) or sticks (m = 0)
        s, m = hy.par[1], hy.par[2]
        level = FC + (FS - FC) * hy.exp(-(v / VST) * (v / VST))
        return [(x, m * v), (v, m * (applied(hy, x) - v - level * s - CV * v))]
    if form == "events":
        abs_v, abs_z = hy.par[1] * v, hy.par[2] * z
    else:
        e = hy.par[1]
        abs_v, abs_z = hy.sqrt(v * v + e * e), hy.sqrt(z * z + e * e)
    return [(x, v), (v, load - KH * z), (z, AH * v - BETAH * abs_v * z - GAMMAH * v * abs_z)]


class Heyoka:
    """One heyoka integrator of `form` at `tol`, run from rest to T_END."""

    def __init__(self, form, vr, tol, e=None):
        import heyoka as hy
        self.hy, self.form = hy, form
        self.dim = 2 if form in ("friction", "sticking") else 3
        events = []
        pars = [vr]
        if form == "sticking":
            x, v = hy.make_vars("x", "v")
            s, m = hy.par[1], hy.par[2]
            # slipping: s x' falls through 0; sticking: |A| rises through fs
            events = [hy.t_event(s * v + (1.0 - m), direction=hy.event_direction.negative,
                                 cooldown=COOLDOWN),
                      hy.t_event(m + (1.0 - m) * (applied(hy, x) ** 2 - FS * FS),
                                 direction=hy.event_direction.positive, cooldown=COOLDOWN)]
            pars += self.sticking_start()
        elif form == "events":
            v, z = hy.make_vars("v", "z")
            events = [hy.t_event(v, cooldown=COOLDOWN), hy.t_event(z, cooldown=COOLDOWN)]
            pars += [1.0, 1.0]
        elif form == "smooth":
            pars.append(e)
        self.pars = pars
        self.ta = hy.taylor_adaptive(heyoka_system(form), [0.0] * self.dim, tol=tol, pars=pars,
                                     t_events=events)

    def once(self, cap):
        ta = self.ta
        ta.time = 0.0
        ta.state[:] = [0.0] * self.dim
        ta.pars[:] = self.pars
        if self.form == "events":
            # from rest the load mu + gamma eps > 0 starts x' upwards, and z' = ah x' with it
            ta.reset_cooldowns()
        kw = {} if cap is None else {"max_delta_t": cap}
        if self.form == "sticking":
            return self.once_sticking(kw)
        steps = 0
        while True:
            out = ta.propagate_until(T_END, **kw)
            steps += out[3]
            if out[0] == self.hy.taylor_outcome.time_limit:
                return steps
            # terminal event i stops the run with outcome -(i + 1): flip sign i (parameter i + 1),
            # except at the start, where x' and z are 0 and their signs are the start's
            if ta.time > 0.0:
                ta.pars[-int(out[0])] *= -1.0

    @staticmethod
    def sticking_start():
        """(s, m) at rest at t = 0: stuck if |A| <= fs, else moving in A's direction."""
        a = applied(math, 0.0, 0.0)
        return [1.0, 0.0] if abs(a) <= FS else [math.copysign(1.0, a), 1.0]

    def once_sticking(self, kw):
        """The sticking form's run: each terminal event the switch the class describes."""
        ta = self.ta
        ta.pars[1:] = self.sticking_start()
        ta.reset_cooldowns()
        steps, breakaway = 0, -math.inf
        while True:
            out = ta.propagate_until(T_END, **kw)
            steps += out[3]
            if out[0] == self.hy.taylor_outcome.time_limit:
                return steps
            a = applied(math, ta.state[0], ta.time)
            if -int(out[0]) == 1:
                if ta.time - breakaway < COOLDOWN:
                    continue
                ta.state[1] = 0.0
                if abs(a) <= FS:
                    ta.pars[2] = 0.0
                else:
                    ta.pars[1] = math.copysign(1.0, a)
            else:
                breakaway = ta.time
                ta.pars[1:] = [math.copysign(1.0, a), 1.0]
                ta.state[1] = 0.0

    def timed(self, reps, cap=None, batches=5):
        best, steps = float("inf"), 0
        for _ in range(batches):
            t0 = time.perf_counter()
            for _ in range(reps):
                steps = self.once(cap)
            best = min(best, (time.perf_counter() - t0) / reps)
        return best, steps, [float(s) for s in self.ta.state]

    def measure(self, reps, cap):
        """The equal-error search's measure: best time per run of 3 batches, and [final state]."""
        t, _, end = self.timed(reps, cap=cap, batches=3)
        return t, [end]


class HeyokaBatch:
    """One heyoka batch-mode integrator (`taylor_adaptive_batch`, the SIMD width heyoka
    recommends for this CPU) of regularised `form` at `tol`, every lane the same run from rest."""

    def __init__(self, form, vr, tol, e=None):
        import heyoka as hy
        import numpy as np
        self.lanes = hy.recommended_simd_size()
        dim = 2 if form == "friction" else 3
        pars = [vr] if e is None else [vr, e]
        self.ta = hy.taylor_adaptive_batch(heyoka_system(form), np.zeros((dim, self.lanes)),
                                           tol=tol,
                                           pars=np.array([[p] * self.lanes for p in pars]))

    def measure(self, reps, cap):
        """Best time per trajectory of 3 batches of `reps` runs, and each lane's final state."""
        import numpy as np
        ta = self.ta
        kw = {} if cap is None else {"max_delta_t": [cap] * self.lanes}
        best = float("inf")
        for _ in range(3):
            t0 = time.perf_counter()
            for _ in range(reps):
                ta.set_time(0.0)
                ta.state[:] = 0.0
                ta.propagate_until(T_END, **kw)
            best = min(best, (time.perf_counter() - t0) / reps / self.lanes)
        return best, [[float(v) for v in lane] for lane in np.array(ta.state).T]


def hdgear_runs(reps, flag=None):
    """`time_terms` at every v_r and tolerance, with `flag` (--hysteresis, --sticking) if any."""
    example = RELEASE / "examples" / "time_terms"
    args = [str(example), str(reps), str(T_END), ",".join(map(str, VRS)), *map(str, TOLS)]
    lines = subprocess.run(args + ([flag] if flag else []), check=True,
                           capture_output=True, text=True).stdout.splitlines()
    return {(r["vr"], r["rtol"]): r for r in map(json.loads, lines)}


def table(reps, hysteresis):
    ours = hdgear_runs(reps, "--hysteresis" if hysteresis else None)
    form = "events" if hysteresis else "friction"
    print("| v_r | tol | hdgear taylor ms | steps | error | heyoka ms | steps | error "
          "| heyoka at equal error: ms (form, tol, cap) | heyoka / hdgear at equal error "
          "| regularised heyoka at equal error | its / hdgear "
          "| hdgear batch-16 ms per trajectory "
          "| regularised heyoka batch at equal error: ms per trajectory | batch / hdgear |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for vr in VRS:
        _, _, ref = Heyoka(form, vr, 1e-16).timed(1, cap=REF_CAP, batches=1)
        err = lambda s: sum(abs(a - b) for a, b in zip(s, ref))
        candidates = [(form, None)]
        if hysteresis:
            candidates += [("smooth", e) for e in REGULARISATIONS]
        grid = search(Heyoka, candidates, vr, reps, err)
        # the regularised form again in heyoka's batch mode
        batch_grid = search(HeyokaBatch, candidates[1:] if hysteresis else candidates, vr, reps,
                            err)
        for tol in TOLS:
            ht, hs, hy_end = Heyoka(form, vr, tol).timed(reps)
            o = ours[(vr, tol)]
            mine = err(o["y"])
            # every form, then the regularised ones alone (friction's tanh is one already)
            cells = [at_equal(grid, mine, o["seconds_per_run"], lambda name: True),
                     at_equal(grid, mine, o["seconds_per_run"],
                              lambda name: not hysteresis or name.startswith("smooth"))]
            # hdgear's batch (every model here runs in one)
            ours_batch = o["batch_seconds_per_run"] or o["seconds_per_run"]
            batch = at_equal(batch_grid, mine, ours_batch, lambda name: True)
            batch_cell = ("—" if o["batch_seconds_per_run"] is None
                          else f"{o['batch_seconds_per_run'] * 1e3:.3f}")
            print(f"| {vr:.0e} | {tol:.0e} | {o['seconds_per_run'] * 1e3:.3f} | {o['steps']} "
                  f"| {mine:.1e} | {ht * 1e3:.3f} | {hs} | {err(hy_end):.1e} "
                  f"| {cells[0][0]} | {cells[0][1]} | {cells[1][0]} | {cells[1][1]} "
                  f"| {batch_cell} | {batch[0]} | {batch[1]} |")


def sticking_table(reps):
    """hdgear's sticking run against heyoka's sticking form and the regularised law."""
    # v_r is no parameter of the sticking law: hdgear's runs are the same at every v_r
    ours = hdgear_runs(reps, "--sticking")
    _, _, ref = Heyoka("sticking", VRS[0], 1e-16).timed(1, cap=REF_CAP, batches=1)
    err = lambda s: sum(abs(a - b) for a, b in zip(s, ref))
    grid = search(Heyoka, [("sticking", None)], VRS[0], reps, err)
    regularised = []
    for vr in STICKING_VRS:
        regularised += [(t, e, f"friction v_r={vr:g}", tol, cap)
                        for t, e, _, tol, cap in search(Heyoka, [("friction", None)], vr, reps,
                                                        err)]
    closest = min(regularised, key=lambda g: (g[1], g[0]))
    print("| tol | hdgear taylor ms | steps | error | heyoka ms | steps | error "
          "| heyoka at equal error: ms (form, tol, cap) | heyoka / hdgear at equal error "
          "| regularised heyoka at equal error | its / hdgear |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for tol in TOLS:
        ht, hs, hy_end = Heyoka("sticking", VRS[0], tol).timed(reps)
        o = ours[(VRS[0], tol)]
        mine = err(o["y"])
        cells = [at_equal(grid, mine, o["seconds_per_run"], lambda name: True),
                 at_equal(regularised, mine, o["seconds_per_run"], lambda name: True)]
        print(f"| {tol:.0e} | {o['seconds_per_run'] * 1e3:.3f} | {o['steps']} | {mine:.1e} "
              f"| {ht * 1e3:.3f} | {hs} | {err(hy_end):.1e} "
              f"| {cells[0][0]} | {cells[0][1]} | {cells[1][0]} | {cells[1][1]} |")
    cap = "none" if closest[4] is None else f"{closest[4]:g}"
    print()
    print(f"The regularised law's least error from the sticking one over v_r = "
          f"{', '.join(f'{v:g}' for v in STICKING_VRS)}, tolerances and caps: {closest[1]:.1e} "
          f"({closest[2]}, {closest[3]:.0e}, cap {cap}, {closest[0] * 1e3:.3f} ms).")


def search(runner, candidates, vr, reps, err):
    """Every run of the equal-error search: `runner` (Heyoka or HeyokaBatch) of each candidate
    (form, e) at each of SEARCH_TOLS and CAPS, as (time, error, form's name, tol, cap); a batch's
    error is its worst lane's."""
    grid = []
    for f, e in candidates:
        name = f if e is None else f"{f} e={e:g}"
        for tol in SEARCH_TOLS:
            run = runner(f, vr, tol, e)
            for cap in CAPS:
                t, ends = run.measure(max(1, reps // 5), cap)
                grid.append((t, max(map(err, ends)), name, tol, cap))
    return grid


def at_equal(grid, mine, seconds, form_counts):
    """heyoka's fastest run in `grid` (time, error, form, tol, cap) of a form `form_counts`
    admits whose error is at most `mine`: its cell text and its time over hdgear's `seconds`."""
    equal = min((g for g in grid if g[1] <= mine and form_counts(g[2])), default=None)
    if equal is None:
        return "none reaches it", "—"
    cap = "none" if equal[4] is None else f"{equal[4]:g}"
    return (f"{equal[0] * 1e3:.3f} ({equal[2]}, {equal[3]:.0e}, {cap})",
            f"{equal[0] / seconds:.2f}")


def main():
    ensure_venv(__file__, ['heyoka', 'numpy'])
    reps = int(sys.argv[1]) if len(sys.argv) > 1 else 50
    subprocess.run(["cargo", "build", "--profile", "dist", "-q", "--example", "time_terms"], cwd=ROOT,
                   check=True)
    import heyoka as hy
    hy.set_logger_level_error()
    print(f"heyoka {hy.__version__}; {reps} runs per batch, best of 5 batches; t = 0 ... {T_END}")
    print()
    print("Friction:")
    print()
    table(reps, hysteresis=False)
    print()
    print("Friction and Bouc-Wen hysteresis (heyoka's own column: its events form):")
    print()
    table(reps, hysteresis=True)
    print()
    print("Friction with sticking (heyoka's own column: its sticking form):")
    print()
    sticking_table(reps)


if __name__ == "__main__":
    main()
