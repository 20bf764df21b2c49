"""hdgear: fast-slow dynamics of harmonic drive gears, from Python.

The model x'' + x' + αx³ − x² + γ(x − ε) = μ + δ sin ωτ (the study's dimensionless harmonic
drive), its fast subsystem, bursting verdicts, sweeps and the physical drive, computed by the Rust
library (the GIL is released during every computation) and returned as numpy arrays, dicts, or
pandas DataFrames when pandas is installed. A model with friction, hysteresis or control terms is
a :class:`Model` (``Model(params, {"coulomb": {...}})`` or ``Model.from_toml(path)``), taken
wherever a :class:`Params` is.

    >>> import hdgear, numpy as np
    >>> tr = hdgear.simulate(hdgear.Params.paper(gamma=0.1))
    >>> tr.xdot.shape == tr.t.shape
    True
    >>> hdgear.analyze(hdgear.Params(gamma=30)).classification.bursting
    False

Errors: bad values raise ``ValueError`` with the command-line tool's message; a failed
integration raises ``RuntimeError``; Ctrl-C during a sweep raises ``KeyboardInterrupt``.
"""
import math as _math

import numpy as _np

from . import _hdgear
from ._hdgear import Model, Params

__version__ = _hdgear.__version__
__all__ = ["Params", "Model", "Trajectory", "Result", "Drive", "simulate", "equilibria", "curve", "branches",
           "analyze", "bursts", "sweep", "periodic", "continuation", "continuation2",
           "frequency_response", "boundary", "control", "robust", "fit", "Fit"]


class Result:
    """A nested result with attribute access (``r.classification.mode``) and ``to_dict()``."""

    def __init__(self, data):
        self._data = data
        for k, v in data.items():
            setattr(self, k, Result(v) if isinstance(v, dict) else v)

    def to_dict(self):
        """The result as plain dicts, lists and numbers (JSON's null as None)."""
        return self._data

    def __repr__(self):
        keys = ", ".join(self._data)
        return f"Result({keys})"


def _frame(columns):
    """A pandas DataFrame of the columns when pandas is installed, else the dict itself."""
    try:
        import pandas as pd
    except ImportError:
        return columns
    return pd.DataFrame(columns)


class Trajectory:
    """A simulation: numpy arrays ``t, a, x, xdot`` (a = sin ωτ), ``states`` (a dict of arrays:
    a model's terms' own states by name, ``s`` of LuGre, ``z`` of Bouc–Wen; empty for the
    study's model), ``stats`` (integrator work: steps, rejected, rhs_evals) and ``summary``
    (initial and final state, max |x'|; a model's description and sticking)."""

    def __init__(self, t, a, x, xdot, summary, states=None):
        self.t, self.a, self.x, self.xdot = t, a, x, xdot
        self.states = {} if states is None else states
        self.summary = summary
        self.stats = summary["stats"]

    def __len__(self):
        return len(self.t)

    def to_dict(self):
        """The columns as a dict of arrays."""
        return {"t": self.t, "a": self.a, "x": self.x, "xdot": self.xdot, **self.states}

    def to_dataframe(self):
        """The columns as a pandas DataFrame (needs pandas)."""
        import pandas as pd
        return pd.DataFrame(self.to_dict())

    def __repr__(self):
        return f"Trajectory({len(self)} samples, t = {self.t[0]}…{self.t[-1]})"


def _params(p):
    """What a function runs on: a :class:`Params` or a :class:`Model` (the study's set by
    default)."""
    if p is None:
        return Params()
    if not isinstance(p, (Params, Model)):
        raise TypeError(f"expected hdgear.Params or hdgear.Model, got {type(p).__name__}")
    return p


def simulate(params=None, t_end=None, periods=3.0, dt=0.05, x0=None, v0=None, from_rest=False,
             rtol=1e-10, atol=1e-10, method="taylor"):
    """Simulates the study's model (a :class:`Params`) or an assembled one (a :class:`Model`)
    from τ = 0 to ``t_end`` (default ``periods`` slow periods 2π/ω), sampled every ``dt``; starts
    on the stable equilibrium at a = 0 (or at ``x0``, ``v0``, or at rest). Returns a
    :class:`Trajectory`, with a model's internal states in ``states``."""
    p = _params(params)
    if t_end is None:
        t_end = periods * 2 * _math.pi / p["omega"] if isinstance(p, Model) else \
            periods * 2 * _math.pi / p.omega
    t, a, x, xdot, states, summary = _hdgear.simulate(p, float(t_end), float(dt), x0, v0,
                                                      bool(from_rest), float(rtol), float(atol),
                                                      method)
    return Trajectory(t, a, x, xdot, summary, states)


def equilibria(params, a):
    """The equilibria of the fast subsystem at the slow value ``a``: a Result with ``x`` (array),
    their ``types`` and ``stable`` flags."""
    if isinstance(params, Model):
        raise TypeError("equilibria takes hdgear.Params (the study's cubic, in closed form), not "
                        "a Model: hdgear.curve(model) gives a model's equilibrium curve")
    return Result(_hdgear.equilibria(_params(params), float(a)))


def curve(params=None, points=401, a_range=(-1.0, 1.0)):
    """The equilibrium curve x*(a) sampled at ``points`` points over ``a_range``: a dict of
    arrays ``a, x, slope (dx/da), gprime, stable`` and lists ``type, branch``."""
    return _hdgear.curve(_params(params), int(points), float(a_range[0]), float(a_range[1]))


def branches(terms, params=None):
    """The quasi-static branches x±(a) that replace the equilibrium curve when the model has
    friction or hysteresis: the study's model with ``params`` and the extra ``terms``, a dict
    ``{kind: {key: value}}`` as a scenario file's tables (``{"coulomb": {"fc": 0.5, "fs": 0.5}}``;
    keys left out take their defaults). Returns a :class:`Result` with ``loading`` and
    ``unloading`` (each with ``breakaway``, ``fold``, ``min_stiffness`` and ``points``) and
    ``closure``, as ``hdgear model --branches --json`` prints them.

        >>> import hdgear
        >>> p = hdgear.Params(gamma=2.0)
        >>> b = hdgear.branches({"coulomb": {"fc": 0.5, "fs": 0.5}}, p)
        >>> round((1.0 - b.unloading.breakaway) * p.delta, 9)  # the load falls by 2 f_s first
        1.0
    """
    return Result(_hdgear.branches(_params(params), _tables(terms)))


def _tables(terms):
    """Term tables {kind: {key: value}} checked and as floats."""
    if not isinstance(terms, dict):
        raise TypeError(f"terms: expected a dict {{kind: {{key: value}}}}, got {type(terms).__name__}")
    tables = {}
    for kind, table in terms.items():
        if not isinstance(table, dict):
            raise TypeError(f"terms[{kind!r}]: expected a dict {{key: value}}, got {type(table).__name__}")
        tables[str(kind)] = {str(k): float(v) for k, v in table.items()}
    return tables


class Fit(Result):
    """The result of :func:`fit`: ``estimates`` (each with ``name``, ``value``, ``std_error``,
    ``wald`` and ``profile`` intervals), ``covariance``, ``correlation``, ``x``, ``measured``,
    ``predicted``, ``residuals``, ``noise``, ``dof``, ``law`` and ``warnings``, as ``hdgear fit
    --json`` prints them; :meth:`plot` draws the data, the fitted law and the residuals."""

    def interval(self, name):
        """The reported 95 % interval of parameter ``name`` (``fs`` or ``coulomb.fs``): the
        profile likelihood's where computed, else JᵀJ's; None where the data do not determine it."""
        for e in self._data["estimates"]:
            if e["name"] == name or e["name"].split(".", 1)[1] == name:
                p = e.get("profile")
                return (p["lo"], p["hi"]) if p else (tuple(e["wald"]) if e["wald"] else None)
        raise KeyError(name)

    def plot(self, axes=None):
        """Measured and fitted torque against speed or twist, and the residuals below (matplotlib;
        returns the two axes)."""
        import matplotlib.pyplot as plt
        if axes is None:
            _, axes = plt.subplots(2, 1, sharex=True, figsize=(7, 6))
        x = _np.asarray(self._data["x"])
        order = _np.argsort(x) if self._data["kind"] == "friction" else _np.arange(len(x))
        axes[0].plot(x[order], _np.asarray(self._data["measured"])[order], ".", label="measured")
        axes[0].plot(x[order], _np.asarray(self._data["predicted"])[order], "-", label="fitted")
        axes[0].set_ylabel("torque [N m]")
        axes[0].legend()
        axes[1].plot(x[order], _np.asarray(self._data["residuals"])[order], ".")
        axes[1].axhline(0.0, color="gray", lw=0.5)
        axes[1].set_ylabel("residual")
        axes[1].set_xlabel("speed [rad/s]" if self._data["kind"] == "friction" else "twist [rad]")
        return axes


def fit(data, terms, free, kind="friction", x=None, torque="torque", sd=None, starts=16, seed=1,
        profile=True, repeat=0):
    """Fits the ``free`` parameters of a law to measured data (what ``hdgear fit`` does).

    ``data`` is a DataFrame or a dict of columns in SI units: ``x`` (default ``speed`` for
    ``kind="friction"``, ``twist`` for ``kind="loop"``) and ``torque``, and the torques' standard
    deviations ``sd`` if given. ``terms`` are the law's term tables as a scenario file's
    (``{"coulomb": {"fc": 1.0}}``: the start values; keys left out at their defaults); ``free``
    maps names to bounds (``{"fc": (0, 5)}``). Returns a :class:`Fit`; its data warnings and
    the fit's are in ``warnings``.

        >>> import hdgear, numpy as np
        >>> v = np.concatenate([-np.geomspace(2, 1e-3, 30), np.geomspace(1e-3, 2, 30)])
        >>> tau = (0.5 + 0.3 * np.exp(-(v / 0.02) ** 2)) * np.sign(v) + 0.3 * v
        >>> f = hdgear.fit({"speed": v, "torque": tau}, {"coulomb": {}},
        ...                {"fc": (0, 5), "fs": (0, 5), "vst": (1e-4, 1), "cv": (0, 2)})
        >>> round(f.estimates[1]["value"], 9)
        0.8
    """
    column = x or {"friction": "speed", "loop": "twist"}.get(kind, "speed")
    xs = _np.asarray(data[column], dtype=float).tolist()
    ts = _np.asarray(data[torque], dtype=float).tolist()
    sds = None if sd is None else _np.asarray(data[sd], dtype=float).tolist()
    bounds = [f"{k}={float(lo)!r}:{float(hi)!r}" for k, (lo, hi) in dict(free).items()]
    result, warnings = _hdgear.fit(str(kind), xs, ts, sds, _tables(terms), bounds, int(starts),
                                   int(seed), bool(profile), int(repeat))
    result["warnings"] = warnings
    return Fit(result)


def _detection(discard, window_periods, rtol, atol, method):
    """The detection options every burst verdict takes, as the native functions read them."""
    return (float(discard), int(window_periods), float(rtol), float(atol), str(method))


def analyze(params=None, response=True, simulated_boundaries=False, discard=1.0,
            window_periods=2, rtol=1e-10, atol=1e-10, method="taylor"):
    """The fast-subsystem analysis, the measured response and its classification (what
    ``hdgear analyze --json`` prints), as a :class:`Result`."""
    data = _hdgear.analyze(_params(params), bool(response), bool(simulated_boundaries),
                           _detection(discard, window_periods, rtol, atol, method))
    return Result(data)


def bursts(params=None, discard=1.0, window_periods=2, rtol=1e-10, atol=1e-10, method="taylor"):
    """The bursts of the response, one row each (onset, end, a_onset, duration, t_peak, a_peak,
    peak_abs_xdot, spikes, extrema, ringing_swing, overshoot, overshoot_lobes, jumps, complete):
    a DataFrame, or a dict of arrays without pandas."""
    rows = _hdgear.bursts(_params(params), _detection(discard, window_periods, rtol, atol, method))
    keys = ["onset", "end", "a_onset", "duration", "t_peak", "a_peak", "peak_abs_xdot", "spikes",
            "extrema", "ringing_swing", "overshoot", "overshoot_lobes", "jumps", "complete"]
    cols = {k: _np.array([r[k] for r in rows]) for k in keys}
    return _frame(cols)


def control(laws=None, params=None, gain=None, ww=None, wd=None, taud=None, rel_tol=1e-3, spread=0.2, discard=1.0,
            window_periods=2, rtol=1e-10, atol=1e-10, method="taylor"):
    """Feedback laws against the bursts (what ``hdgear control --json`` prints), as a
    :class:`Result`: each of ``laws`` ("vstiffness", "vdamping", "washout", "dither", "delay",
    "scheduled"; all but "dither" and "delay" by default)
    tuned to its least gain that removes the bursts (``tunings``: the tuned gain and the one below
    it, each assessed), or assessed at ``gain`` (``assessments``); ``ww`` is the washout's corner
    frequency; "dither" (run only on request) is ``wd``'s dither at amplitude ``gain``, "delay"
    (on request) the feedback K·(x(τ − ``taud``) − x(τ)) with K = ``gain``, "scheduled" (on
    request) the stiffness scheduled on the load's phase for ``params``, whose gain is the least
    slope g'_min it keeps; with ``spread`` (0.2: ±20 %, as ``hdgear control``; 0 or None: not checked) each tuned law's
    ``robustness``, the least gain
    that keeps every plant within that model error of α, γ, ε, μ, δ burst-free."""
    laws = [] if laws is None else ([laws] if isinstance(laws, str) else list(laws))
    data = _hdgear.control(_params(params), laws, None if gain is None else float(gain),
                           None if ww is None else float(ww),
                           None if wd is None else float(wd),
                           None if taud is None else float(taud), float(rel_tol),
                           None if spread is None else float(spread),
                           _detection(discard, window_periods, rtol, atol, method))
    return Result(data)


def robust(nominal=None, tolerances=None, samples=4096, sampler="sobol", seed=1, level=0.95,
           width=0.02, sobol=None, worst=True, importance=None, load_curve=False, discard=1.0,
           window_periods=2, rtol=1e-10, atol=1e-10, method="taylor"):
    """The design check under manufacturing spread (what ``hdgear robust --json`` and ``hdgear
    physical --robust --json`` print): returns ``(summary, samples)``.

    ``nominal`` is a :class:`Params`, a :class:`Model` (any of its parameters spreads by name,
    ``{"friction.fc": "±20%"}``) or a :class:`Drive` (the study's set by default);
    ``tolerances`` maps parameter names to spreads as the CLI writes them (``{"k1": "±15%",
    "c_eq": "normal:10%"}``; a drive without any takes the default bands, marked as assumptions).
    ``summary`` is a :class:`Result` with ``probability`` (P(burst), its Wilson interval at
    ``level``), ``worst`` (the worst corner and margin; None with ``worst=False``),
    ``importance`` (P(burst) by importance sampling from ``importance`` samples drawn around the
    predicted boundary, with its variance reduction, when given), ``sensitivity`` (Sobol indices
    from a Saltelli design of ``sobol`` rows, when given), ``load_curve`` (P(burst) at 1/4 … 2
    times the load amplitude, ``samples`` each, with ``load_curve=True``) and
    ``resonance`` (drives). ``samples`` holds one row per sample, the columns of ``hdgear robust
    --out``, as a DataFrame (a dict of columns without pandas). The same ``seed`` gives the same
    samples on any thread count."""
    tol = [] if tolerances is None else [f"{k}={v}" for k, v in dict(tolerances).items()]
    params = drive = None
    if isinstance(nominal, Drive):
        drive = nominal._native
    elif nominal is not None:
        params = _params(nominal)
    summary, cols = _hdgear.robust(params, drive, tol, int(samples), sampler, int(seed),
                                   float(level), float(width),
                                   None if sobol is None else int(sobol), bool(worst),
                                   None if importance is None else int(importance),
                                   bool(load_curve),
                                   _detection(discard, window_periods, rtol, atol, method))
    for k in ("verdict", "error"):
        cols[k] = _np.array(cols[k], dtype=object)
    return Result(summary), _frame(cols)


def sweep(axes, base=None, grid=True, threads=0, discard=1.0, window_periods=2, rtol=1e-10,
          atol=1e-10, method="taylor"):
    """Runs the burst analysis at many parameter sets in parallel (all cores, ``threads=0``)
    with the GIL released.

    ``axes`` maps parameter names to values, e.g. ``{"gamma": np.geomspace(0.1, 30, 1000)}``;
    ``base`` is a :class:`Params` or a :class:`Model`, whose parameters sweep by name
    (``{"coulomb.fs": …, "delta": …}``).
    With ``grid=True`` the points are every combination, the first name varying fastest (the
    order of ``hdgear sweep``); with ``grid=False`` the arrays are zipped (equal lengths) and
    each position is one point. Returns the columns of ``hdgear sweep`` (index, the six
    parameters, mode, mechanism, the rates, max_slope, error; NaN and '' for a failed point) as a
    DataFrame, or a dict of numpy arrays without pandas. A model's rows hold the swept parameters,
    as named, in place of the six."""
    if not axes:
        raise ValueError("give at least one parameter to sweep")
    names = list(axes)
    vals = [_np.asarray(axes[k], dtype=float) for k in names]
    for k, v in zip(names, vals):
        if v.ndim > 1:
            raise ValueError(f"invalid axis {k}: {v.ndim}-dimensional (shape {v.shape}); give its "
                             "values as a 1-D array (or set grid=False with equal lengths)")
    vals = [v.ravel() for v in vals]
    if grid:
        mesh = _np.meshgrid(*vals, indexing="ij")
        # first name fastest: transpose so the first axis varies fastest in C order
        vals = [m.transpose(tuple(reversed(range(len(vals))))).ravel() for m in mesh]
    cols = _hdgear.sweep(_params(base), names, [v.tolist() for v in vals], int(threads),
                         _detection(discard, window_periods, rtol, atol, method))
    for k in ("mode", "mechanism", "error"):
        cols[k] = _np.array(cols[k], dtype=object)
    return _frame(cols)


def periodic(params=None, subharmonic=1):
    """The periodic orbit of period ``subharmonic``·2π/ω by shooting (Newton on the stroboscopic
    map, monodromy from the variational equations): ``start``, ``period``, ``multipliers``
    (``log_abs``, ``arg``), ``floquet_exponents``, ``stable``, the amplitudes, ``bursts`` (the
    burst verdict on the orbit itself) and ``samples`` ((τ, x, x') every 0.05) as a Result. A
    model whose friction sticks is shot switch by switch (saltation matrices) and has ``rests``
    (rests and switches per period, time at rest); an orbit that rests has a second multiplier of
    exactly 0 (``log_abs`` None, for ln 0 = −∞, as the CLI's JSON has null)."""
    return Result(_hdgear.periodic(_params(params), int(subharmonic)))


def _branch_frame(cols):
    for k in ("special",):
        cols[k] = _np.array(cols[k], dtype=object)
    cols["stable"] = _np.array(cols["stable"], dtype=bool)
    return _frame(cols)


def continuation(param, to, params=None, log=False, subharmonic=1, switch=False):
    """Follows the periodic orbit in ``param`` from its value in ``params`` to ``to``
    (pseudo-arclength; in the logarithm of the parameter with ``log=True``), locating folds and
    period doublings, and with ``switch=True`` the doubled branches. Returns the columns of
    ``hdgear continue`` (branch, subharmonic, param, x0, xdot0, x_min, x_max, peak_to_peak,
    max_abs_xdot, ln_abs_m1, arg_m1, ln_abs_m2, arg_m2, stable, special, flip_coefficient: the
    normal-form coefficient at a period doubling, NaN elsewhere) as a DataFrame, or a dict of
    numpy arrays without pandas."""
    return _branch_frame(_hdgear.continuation(_params(params), str(param), float(to), bool(log),
                                              int(subharmonic), bool(switch)))


def continuation2(range1, range2, params=None, start="fold", subharmonic=1, switch=False):
    """Curves of folds (``start="fold"``) or period doublings (``"period-doubling"``) in two
    parameters, as ``hdgear continue2`` follows them: ``range1`` and ``range2`` are its
    ``--param`` specs (``"omega=0.3:20:log"``); the curves start from the special points of the
    one-parameter branch in the first parameter (``"fold:2"``: from the second only). With
    ``switch=True`` (period doublings only), also the fold curves of the doubled orbits born at
    the generalised period doublings found (``--switch``). Returns the columns of its ``--out``
    (curve, kind, subharmonic, param1, param2, x0, xdot0, peak_to_peak, max_abs_xdot, ln_abs_m1,
    arg_m1, ln_abs_m2, arg_m2, special, flip_coefficient: the period doubling's normal-form
    coefficient, NaN on fold curves) as a DataFrame, or a dict of numpy arrays without pandas."""
    return _frame(_hdgear.continuation2(_params(params), str(range1), str(range2), str(start),
                                        int(subharmonic), bool(switch)))


def boundary(range1, range2, params=None, kinds=None, step=0.02, discard=1.0, window_periods=2,
             rtol=1e-10, atol=1e-10, method="taylor"):
    """Boundaries in two parameters as curves, as ``hdgear boundary`` follows them:
    ``range1`` and ``range2`` are its ``--param`` specs (``"omega=1e-4:0.2:log"``), ``kinds`` a
    list of predicted, simulated, a-fold-in-range, both-folds-in-range, fast-slow-edge (all
    by default). Returns the columns of its ``--out`` (curve, kind, param1, param2, outside1,
    outside2, inside1, inside2: each point and its bracket's ends) as a DataFrame, or a dict of
    numpy arrays without pandas."""
    kinds = [] if kinds is None else [kinds] if isinstance(kinds, str) else [str(k) for k in kinds]
    return _frame(_hdgear.boundary(_params(params), str(range1), str(range2), kinds,
                                   float(step),
                                   _detection(discard, window_periods, rtol, atol, method)))


def frequency_response(params=None, omega_range=None, switch=False):
    """The frequency-response curve: continuation in ln ω over ``omega_range`` (default: from
    1/20 to 3 times the stiffest static frequency), same columns as :func:`continuation`
    (``param`` is ω)."""
    p = _params(params)
    if omega_range is None:
        cols = _hdgear.continuation(p, "omega", None, True, 1, bool(switch))
    else:
        lo, hi = (float(v) for v in omega_range)
        cols = _hdgear.continuation(p.replace(omega=lo), "omega", hi, True, 1, bool(switch))
    return _branch_frame(cols)


class Drive:
    """A harmonic drive in SI units (j_in, j_out [kg m²], ratio, k1 [N m/rad], k2 [N m/rad³],
    backlash [rad], c_eq [N m s/rad], t_m, t_am [N m], omega [rad/s]).

    ``Drive.catalogue("CSF-20-50")`` takes the stiffness from the catalogue curve and documented
    assumptions for the rest; ``Drive(**values)`` starts from CSF-20-50 and replaces values."""

    def __init__(self, **values):
        base = _hdgear.Drive.catalogue("CSF-20-50")[0].to_dict()
        unknown = set(values) - set(base)
        if unknown:
            raise ValueError(f"unknown drive value(s) {sorted(unknown)}: expected {sorted(base)}")
        base.update({k: float(v) for k, v in values.items()})
        self._native = _hdgear.Drive.from_dict(base)
        self.fit = None

    @classmethod
    def catalogue(cls, name, fit_torque=None):
        """A drive from a built-in card (``hdgear card list``: Harmonic Drive CSG, HFUC, SHG,
        HFUS and CSF drives); ``fit`` holds the stiffness fit."""
        native, fit = _hdgear.Drive.catalogue(name, fit_torque)
        d = cls.__new__(cls)
        d._native = native
        d.fit = fit
        return d

    def to_dict(self):
        """The ten values."""
        return self._native.to_dict()

    def __getattr__(self, name):
        values = object.__getattribute__(self, "_native").to_dict()
        if name in values:
            return values[name]
        raise AttributeError(name)

    def reduce(self):
        """The reduction to the dimensionless model: a Result with ``params`` (an
        :class:`hdgear.Params`), ``time_scale`` [s], ``length_scale`` [rad] and ``j_eq``."""
        params, data = self._native.reduce()
        r = Result(data)
        r.params = params
        return r

    def simulate(self, t_end, dt=None, rtol=1e-10, atol=1e-10):
        """The two-inertia model from rest to ``t_end`` seconds, every ``dt`` seconds (default
        J_eq/C/20): a Result of arrays ``t, theta_in, theta_out, theta, theta_dot`` and
        ``summary``."""
        if dt is None:
            r = self.reduce()
            dt = r.time_scale / 20
        cols, summary = self._native.simulate(float(t_end), float(dt), float(rtol), float(atol))
        out = Result({"summary": summary})
        for k, c in zip(["t", "theta_in", "theta_out", "theta", "theta_dot"], cols):
            setattr(out, k, c)
        return out

    def twist_torque(self, theta, theta_dot):
        """The torque across the compliance [N m] at the twist ``theta`` = θo − θi/N [rad] and its
        rate [rad/s]: the spring (k1 + k2θ²)(θ − φ) and the damping C·θ', the torque the drive
        transmits (``hdgear.mujoco`` applies it between two joints)."""
        return self._native.twist_torque(float(theta), float(theta_dot))

    def design_check(self, discard=1.0, window_periods=2, rtol=1e-10, atol=1e-10):
        """The distance to the bursting regime and the single changes that cross it (what
        ``hdgear physical --design --json`` prints), as a Result."""
        return Result(self._native.design_check(
            _detection(discard, window_periods, rtol, atol, "taylor")))

    def __repr__(self):
        return "Drive(" + ", ".join(f"{k}={v!r}" for k, v in self.to_dict().items()) + ")"
