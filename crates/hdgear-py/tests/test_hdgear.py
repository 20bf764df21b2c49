"""Tests of the hdgear Python package: every function, errors, dtypes and shapes, agreement with
the command-line tool to the last bit, and the GIL released during computations.

The CLI is found at $HDGEAR_BIN (default: target/release/hdgear of this checkout).

Why one file: the package's one face, tested against the CLI with the same helpers throughout."""
import csv
import json
import math
import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import hdgear

ROOT = Path(__file__).resolve().parents[3]
BIN = os.environ.get("HDGEAR_BIN", str(ROOT / "target" / "release" / "hdgear"))


def cli(*args, tmp=None):
    out = subprocess.run([BIN, *args, "--quiet"], capture_output=True, text=True, cwd=tmp)
    return out


def cli_json(*args):
    out = cli(*args)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def same(a, b):
    """Bitwise equality of floats, NaN equal to NaN."""
    a, b = float(a), float(b)
    return (math.isnan(a) and math.isnan(b)) or a == b


# ---- Params ----------------------------------------------------------------------------------

def test_params_defaults_presets_and_replace():
    p = hdgear.Params()
    assert (p.alpha, p.gamma, p.eps, p.mu, p.delta, p.omega) == (16.0, 0.1, 0.71, 0.07, 15.0, 0.01)
    assert hdgear.Params.paper(gamma=1).gamma == 1.0
    assert hdgear.Params(preset="paper-g30").gamma == 30.0
    q = p.replace(gamma=2.5)
    assert q.gamma == 2.5 and p.gamma == 0.1 and q != p and q == hdgear.Params(gamma=2.5)
    assert p.to_dict() == {"alpha": 16.0, "gamma": 0.1, "eps": 0.71, "mu": 0.07, "delta": 15.0, "omega": 0.01}
    assert "alpha*eps" in p.warnings[0]
    assert repr(p).startswith("Params(alpha=16.0")


def test_the_stub_names_the_library_s_parameters():
    """The type stub is written by hand (type checkers read it as it stands); it must name the
    parameters the library defines, in its order, in Params(), replace() and the properties."""
    import ast
    stub = ast.parse((ROOT / "crates" / "hdgear-py" / "python" / "hdgear" / "__init__.pyi").read_text())
    params = next(c for c in stub.body if isinstance(c, ast.ClassDef) and c.name == "Params")
    methods = {f.name: f for f in params.body if isinstance(f, ast.FunctionDef)}
    names = list(hdgear.Params().to_dict())
    assert [a.arg for a in methods["__init__"].args.kwonlyargs] == names + ["preset"]
    assert [a.arg for a in methods["replace"].args.kwonlyargs] == names
    properties = [f.name for f in params.body if isinstance(f, ast.FunctionDef)
                  and any(isinstance(d, ast.Name) and d.id == "property" for d in f.decorator_list)]
    assert [n for n in properties if n != "warnings"] == names


@pytest.mark.parametrize("kw,flag", [({"gamma": float("nan")}, "--gamma=nan"), ({"omega": 0.0}, "--omega=0"),
                                     ({"alpha": -1.0}, "--alpha=-1"), ({"delta": -2.0}, "--delta=-2")])
def test_invalid_values_raise_valueerror_with_the_cli_message(kw, flag):
    with pytest.raises(ValueError) as e:
        hdgear.Params(**kw)
    out = cli("simulate", "--summary", flag)
    assert out.returncode == 2
    assert str(e.value) == out.stderr.strip().removeprefix("error: ")


def test_other_bad_input():
    with pytest.raises(ValueError, match="unknown preset 'nope'"):
        hdgear.Params(preset="nope")
    with pytest.raises(ValueError, match="rtol"):
        hdgear.simulate(rtol=0.0)
    with pytest.raises(ValueError, match="method"):
        hdgear.simulate(method="euler")
    with pytest.raises(TypeError):
        hdgear.simulate(params={"gamma": 1})
    with pytest.raises(ValueError, match="beyond the budget"):
        hdgear.simulate(t_end=1e12)
    with pytest.raises(ValueError, match="unknown drive value"):
        hdgear.Drive(k3=1.0)
    # the parameters are keywords of the library's list, each named in its error
    with pytest.raises(TypeError, match="unexpected keyword argument 'beta'"):
        hdgear.Params(beta=1.0)
    with pytest.raises(TypeError, match="argument 'gamma'"):
        hdgear.Params().replace(gamma="abc")
    with pytest.raises(TypeError):
        hdgear.Params(16.0)
    assert hdgear.Params(gamma=None) == hdgear.Params()
    with pytest.raises(ValueError, match=r"window_periods = -1: must be a whole number"):
        hdgear.bursts(window_periods=-1)



def test_limits_raise_valueerror_before_any_work():
    # each of these would otherwise ask for more memory than the machine has, or run for hours
    with pytest.raises(ValueError, match=r"invalid option points = 1000000000000: must be ≥ 2 and at most 1e7"):
        hdgear.curve(hdgear.Params(), points=10**12)
    with pytest.raises(ValueError, match=r"invalid option points = 1: must be ≥ 2"):
        hdgear.curve(hdgear.Params(), points=1)
    with pytest.raises(ValueError, match=r"more than 1e8 samples to hold in memory"):
        hdgear.simulate(t_end=1e6, dt=1e-3)
    with pytest.raises(ValueError, match=r"invalid option t_end = NaN"):
        hdgear.simulate(periods=float("nan"))
    with pytest.raises(ValueError, match=r"invalid thread count '100000': at most 1024"):
        hdgear.sweep({"gamma": [1.0]}, threads=100000)
    with pytest.raises(ValueError, match=r"more than 1e8 samples to hold in memory"):
        hdgear.Drive.catalogue("CSF-20-50").simulate(1e3, dt=1e-6)


def test_ctrl_c_stops_a_long_sweep_with_keyboardinterrupt():
    import signal
    # a long sweep (16,000 points of very slow forcing, many times the half second after which it
    # is interrupted)
    axes = {"gamma": np.geomspace(0.01, 0.1, 16000)}
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    # Python's own Ctrl-C handler, which it does not install when started with SIGINT ignored (a
    # shell's background job: `scripts/python-tests.sh &`), restored afterwards
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        t0 = time.perf_counter()
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            hdgear.sweep(axes, base=hdgear.Params(omega=0.0001), threads=2)
        elapsed = time.perf_counter() - t0
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)
    # the sweep stops at its next chunk of 16 points, long before the whole sweep would end
    assert elapsed < 20, f"returned after {elapsed:.1f} s"
    # and the next call works
    assert len(hdgear.sweep({"gamma": [30.0]})["gamma"]) == 1

# ---- simulate --------------------------------------------------------------------------------

def test_simulate_shapes_dtypes_and_the_cli_to_the_last_bit(tmp_path):
    tr = hdgear.simulate(hdgear.Params(gamma=1.0), periods=1, dt=0.5)
    n = len(tr)
    for arr in (tr.t, tr.a, tr.x, tr.xdot):
        assert arr.dtype == np.float64 and arr.shape == (n,)
    assert tr.t[0] == 0.0 and abs(tr.t[-1] - 2 * math.pi / 0.01) < 1e-9
    assert set(tr.stats) == {"steps", "rejected", "rhs_evals"} and tr.stats["steps"] > 100
    assert np.array_equal(tr.a, np.sin(0.01 * tr.t))
    out = cli("simulate", "--gamma", "1", "--periods", "1", "--dt", "0.5", "--out", str(tmp_path / "t.csv"))
    assert out.returncode == 0, out.stderr
    rows = read_csv(tmp_path / "t.csv")
    assert len(rows) == n
    for k in ("t", "a", "x", "xdot"):
        assert all(same(r[k], v) for r, v in zip(rows, getattr(tr, k))), k


def test_simulate_starts():
    rest = hdgear.simulate(t_end=10, from_rest=True)
    assert rest.x[0] == 0.0 and rest.xdot[0] == 0.0
    given = hdgear.simulate(t_end=10, x0=0.3, v0=-0.1)
    assert (given.x[0], given.xdot[0]) == (0.3, -0.1)
    with pytest.raises(ValueError):
        hdgear.simulate(t_end=10, x0=0.3, from_rest=True)
    assert hdgear.simulate(t_end=10, method="dop853").stats["rejected"] >= 0


# ---- fast subsystem --------------------------------------------------------------------------

def test_equilibria_and_curve():
    e = hdgear.equilibria(hdgear.Params(gamma=0.001), -0.00473)  # between the folds
    assert len(e.roots) == 3 and e.roots[0]["kind"] in ("stable-node", "stable-focus")
    c = hdgear.curve(hdgear.Params(), points=101)
    assert set(c) == {"a", "x", "slope", "gprime", "stable", "type", "branch"}
    assert c["a"].shape == (101,) and c["stable"].dtype == np.bool_ and c["stable"].all()
    # dx/da = δ / g'(x)
    assert np.allclose(c["slope"], 15.0 / c["gprime"], rtol=1e-12)
    with pytest.raises(ValueError):
        hdgear.curve(points=1)


def test_branches_equal_the_cli_and_the_closed_form(tmp_path):
    """With sticking Coulomb friction the loading branch is the equilibrium curve with the load
    less f_c: g(x) + f_c = mu + delta*a at every point, g written out here."""
    p = hdgear.Params(gamma=1.0)
    terms = {"coulomb": {"fc": 0.5, "fs": 0.5}}
    b = hdgear.branches(terms, p)
    (tmp_path / "b.toml").write_text("[params]\ngamma = 1.0\n\n[coulomb]\nfc = 0.5\nfs = 0.5\n")
    doc = cli_json("model", "--config", str(tmp_path / "b.toml"), "--branches", "--json")
    assert b.to_dict() == doc["branches"]
    a, x = np.array([q["a"] for q in b.loading.points]), np.array([q["x"] for q in b.loading.points])
    g = p.alpha * x**3 - x**2 + p.gamma * (x - p.eps)
    assert len(a) > 1000
    assert np.max(np.abs(g + 0.5 - p.mu - p.delta * a)) < 1e-9
    with pytest.raises(ValueError, match="unknown term pid"):
        hdgear.branches({"pid": {}}, p)
    with pytest.raises(ValueError, match="unknown key f_c in \\[coulomb\\]"):
        hdgear.branches({"coulomb": {"f_c": 0.5}}, p)
    with pytest.raises(ValueError, match="fc"):
        hdgear.branches({"coulomb": {"fc": -1.0}}, p)
    with pytest.raises(TypeError):
        hdgear.branches([("coulomb", {})], p)


def test_analyze_equals_the_cli_json():
    for g in ("30", "1", "0.1"):
        r = hdgear.analyze(hdgear.Params(gamma=float(g)))
        assert r.to_dict() == cli_json("analyze", "--json", "--gamma", g)
    r = hdgear.analyze(hdgear.Params(gamma=0.1))
    assert r.classification.bursting and r.classification.mode == "pronounced-bursting"
    assert "response" not in hdgear.analyze(response=False).to_dict()


def test_bursts_equal_the_cli(tmp_path):
    b = hdgear.bursts(hdgear.Params(gamma=0.1))
    assert cli("bursts", "--gamma", "0.1", "--out", str(tmp_path / "b.csv")).returncode == 0
    rows = read_csv(tmp_path / "b.csv")
    assert len(b["onset"]) == len(rows) == 4
    for k in ("onset", "end", "peak_abs_xdot", "overshoot"):
        assert all(same(r[k], v) for r, v in zip(rows, list(b[k]))), k
    assert [int(r["spikes"]) for r in rows] == [int(v) for v in b["spikes"]]


def test_control_equals_the_cli_and_refuses_bad_laws():
    r = hdgear.control(["vstiffness", "washout"], hdgear.Params(gamma=0.1), rel_tol=1e-2, ww=0.1)
    out = cli("control", "vstiffness", "washout", "--gamma", "0.1", "--rel-tol", "1e-2",
              "--ww", "0.1", "--json")
    assert out.returncode == 0
    doc = json.loads(out.stdout)
    assert [t.law for t in map(hdgear.Result, r.tunings)] == ["vstiffness", "washout"]
    for py, c in zip(r.tunings, doc["tunings"]):
        assert py["tuned"]["gain"] == c["tuned"]["gain"]
        assert py["tuned"]["verdict"] == "no-bursts" and py["below"]["verdict"] != "no-bursts"
    assert [x["ratio"] for x in r.robustness] == [x["ratio"] for x in doc["robustness"]]
    assert all(x["ratio"] >= 1.0 and x["plants"] == 33 for x in r.robustness)
    a = hdgear.control("washout", gain=10, ww=0.03)
    assert a.assessments[0]["verdict"] == "no-bursts"
    with pytest.raises(ValueError, match="pid"):
        hdgear.control("pid")
    with pytest.raises(ValueError, match="ww"):
        hdgear.control("vdamping", ww=0.3)


def test_robust_equals_the_cli_and_refuses_bad_tolerances(tmp_path):
    drive = hdgear.Drive(k1=2000, t_am=22)
    summary, samples = hdgear.robust(drive, samples=256, worst=False, importance=256,
                                     load_curve=True)
    doc = cli_json("physical", "--k1", "2000", "--t-am", "22", "--robust", "--samples", "256",
                   "--no-worst", "--importance", "256", "--load-curve", str(tmp_path / "l.svg"),
                   "--json", "--out", str(tmp_path / "s.csv"))
    assert summary.probability.to_dict() == doc["probability"]
    assert summary.importance.p == doc["importance"]["p"]
    assert [x["probability"]["bursting"] for x in summary.load_curve] == \
        [x["probability"]["bursting"] for x in doc["load_curve"]]
    rows = read_csv(tmp_path / "s.csv")
    assert len(samples["verdict"]) == len(rows) == 256
    assert [r["verdict"] for r in rows] == list(samples["verdict"])
    assert sum(samples["burst"]) == summary.probability.bursting
    assert summary.resonance.nominal_hz == doc["resonance"]["nominal_hz"]
    s, _ = hdgear.robust(hdgear.Params(gamma=2.2), {"gamma": "normal:10%"}, samples=64,
                         worst=False)
    assert s.probability.judged == 64
    with pytest.raises(ValueError, match="tolerances"):
        hdgear.robust(hdgear.Params())
    with pytest.raises(ValueError, match="weibull"):
        hdgear.robust(drive, {"k1": "weibull:3"})
    with pytest.raises(ValueError, match="gamma"):
        hdgear.robust(drive, {"gamma": "±1%"})


# ---- sweeps ----------------------------------------------------------------------------------

def columns_equal(py, rows):
    for k in rows[0]:
        for r, v in zip(rows, list(py[k])):
            if k in ("mode", "mechanism", "error"):
                assert r[k] == v, k
            elif k == "bursts_per_period" and r[k] == "":
                assert math.isnan(v)
            else:
                assert same(r[k], v), (k, r[k], v)


def test_sweep_equals_the_cli_to_the_last_bit(tmp_path):
    out = cli("sweep", "--param", "gamma=0.05:30:40:log", "--param", "delta=8:16:3", "--out", str(tmp_path / "s.csv"))
    assert out.returncode == 0, out.stderr
    rows = read_csv(tmp_path / "s.csv")
    gammas = [float(r["gamma"]) for r in rows[:40]]
    deltas = [float(rows[40 * j]["delta"]) for j in range(3)]
    s = hdgear.sweep({"gamma": gammas, "delta": deltas})
    assert len(s["index"]) == 120
    columns_equal(s, rows)
    # the same points zipped
    z = hdgear.sweep({"gamma": [float(r["gamma"]) for r in rows], "delta": [float(r["delta"]) for r in rows]}, grid=False)
    columns_equal(z, rows)


def test_sweep_without_pandas_gives_a_dict_of_arrays(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)  # as if pandas were not installed
    d = hdgear.sweep({"gamma": np.geomspace(0.1, 30, 7)})
    assert isinstance(d, dict) and len(d) == 18
    assert d["peak_abs_xdot"].dtype == np.float64 and d["index"].dtype == np.int64
    assert d["mode"].dtype == object and d["peak_abs_xdot"].shape == (7,)
    b = hdgear.bursts(hdgear.Params())
    assert isinstance(b, dict) and b["onset"].dtype == np.float64
    with pytest.raises(ValueError, match="same number"):
        hdgear.sweep({"gamma": [1, 2], "delta": [1]}, grid=False)
    with pytest.raises(ValueError, match="invalid parameter"):
        hdgear.sweep({"omega": [0.0]})
    with pytest.raises(ValueError, match="parameter name"):
        hdgear.sweep({"beta": [1.0]})


def test_sweep_with_pandas_gives_a_dataframe():
    pd = pytest.importorskip("pandas")
    s = hdgear.sweep({"gamma": np.geomspace(0.1, 30, 7)})
    assert isinstance(s, pd.DataFrame) and s.shape == (7, 18)
    assert s["gamma"].dtype == np.float64 and s["index"].dtype == np.int64
    assert isinstance(hdgear.bursts(hdgear.Params()), pd.DataFrame)
    assert hdgear.simulate(t_end=5).to_dataframe().shape[1] == 4


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="needs two cores")
def test_the_gil_is_released_during_a_sweep():
    g = {"gamma": np.geomspace(0.1, 30, 480)}
    hdgear.sweep(g, threads=1)  # warm up

    def spins_per_second(other):
        """How fast this thread runs Python while `other` runs."""
        n, t0 = 0, time.perf_counter()
        other.start()
        while other.is_alive():
            n += 1
        return n / (time.perf_counter() - t0)

    # the same loop beside a thread that only sleeps (sleeping releases the GIL), then beside a
    # one-thread sweep: held, the GIL would stop this thread for the whole sweep (a few
    # percent of the rate at most, from the switch before the sweep starts); released, this thread
    # runs on the other core. Not a comparison of two sweeps' times against one's: on CI two
    # one-thread sweeps side by side took 1.66-1.69x one's time although the GIL is released (the
    # machine's two virtual cores do not give twice the throughput)
    alone = spins_per_second(threading.Thread(target=time.sleep, args=(0.1,)))
    during = spins_per_second(threading.Thread(target=hdgear.sweep, args=(g,), kwargs={"threads": 1}))
    assert during > 0.25 * alone, f"{during:.0f} loops/s beside the sweep, {alone:.0f} beside a sleep"


# ---- the physical drive ----------------------------------------------------------------------

def test_drive_catalogue_reduce_simulate_and_design_check():
    d = hdgear.Drive.catalogue("CSF-20-50")
    assert d.fit["k1"] == d.k1
    r = d.reduce()
    assert isinstance(r.params, hdgear.Params)
    assert abs(r.params.alpha * r.params.eps - 1) < 1e-12
    phys = cli_json("physical", "--drive", "CSF-20-50", "--json")
    assert r.params.to_dict() == phys["reduced"] and r.to_dict()["time_scale"] == phys["time_scale"]
    assert d.to_dict() == phys["drive"] and d.fit == phys["catalogue"]["fit"]
    s = d.simulate(t_end=0.5)
    assert s.t.shape == s.theta.shape and s.t[-1] == pytest.approx(0.5)
    dc = d.design_check()
    assert dc.to_dict() == cli_json("physical", "--drive", "CSF-20-50", "--design", "--json")
    stiffer = hdgear.Drive(k1=2 * d.k1)
    assert stiffer.k1 == 2 * d.k1 and stiffer.j_in == d.j_in
    with pytest.raises(ValueError, match="CSF-99"):
        hdgear.Drive.catalogue("CSF-99")


# ---- the periodic response -------------------------------------------------------------------

def test_periodic_orbit_equals_the_cli():
    o = hdgear.periodic(hdgear.Params.paper(1.0))
    c = cli_json("periodic", "--preset", "paper-g1", "--json")
    assert o.start == c["start"] and o.multipliers[0]["log_abs"] == c["multipliers"][0]["log_abs"]
    assert o.bursts.verdict == c["bursts"]["verdict"] == "overshoot"
    assert len(o.samples) == len(c["samples"])


def test_continuation_equals_the_cli_and_finds_the_bubble(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)
    p = hdgear.Params(gamma=10.0, omega=5.0)
    b = hdgear.continuation("omega", 10.5, params=p, log=True, switch=True)
    out = cli("continue", "--param", "omega=5:10.5:log", "--gamma", "10", "--switch",
              "--out", str(tmp_path / "b.csv"))
    assert out.returncode == 0, out.stderr
    rows = read_csv(tmp_path / "b.csv")
    assert len(rows) == len(b["param"])
    assert [float(r["param"]) for r in rows] == b["param"].tolist()
    assert list(b["special"]).count("period-doubling") >= 2 and 1 in b["branch"]
    # the parent's doublings carry their normal-form coefficient (both supercritical), as the CLI's
    pd = (b["special"] == "period-doubling") & (b["branch"] == 0)
    assert pd.sum() == 2 and (b["flip_coefficient"][pd] > 0).all()
    assert np.isnan(b["flip_coefficient"][b["special"] == ""]).all()
    has = [r["flip_coefficient"] != "" for r in rows]
    assert has == (~np.isnan(b["flip_coefficient"])).tolist()
    fr = hdgear.frequency_response(hdgear.Params(gamma=30.0), omega_range=(6.0, 10.0))
    folds = fr["param"][fr["special"] == "fold"]
    assert len(folds) == 2 and 7.8 < folds.min() < 7.9 and 8.4 < folds.max() < 8.5


def test_two_parameter_curves_equal_the_cli(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)
    c = hdgear.continuation2("omega=0.3:20:log", "delta=0.5:40:log")
    out = cli("continue2", "--param", "omega=0.3:20:log", "--param", "delta=0.5:40:log",
              "--out", str(tmp_path / "c.csv"))
    assert out.returncode == 0, out.stderr
    rows = read_csv(tmp_path / "c.csv")
    assert [float(r["param1"]) for r in rows] == c["param1"].tolist()
    assert list(c["special"]).count("cusp") == 2
    assert abs(c["ln_abs_m1"]).max() < 1e-9
    assert np.isnan(c["flip_coefficient"]).all()  # fold curves have no doubling coefficient
    pd_ = hdgear.continuation2("omega=4:14:log", "mu=-5:5", params=hdgear.Params(gamma=10.0),
                               start="period-doubling")
    assert list(pd_["special"]).count("generalised-period-doubling") >= 2
    assert (pd_["flip_coefficient"] < 0).any() and (pd_["flip_coefficient"] > 0).any()
    sw = hdgear.continuation2("omega=4:14:log", "mu=-5:5", params=hdgear.Params(gamma=10.0),
                              start="period-doubling", switch=True)
    lpc = [i for i, c in enumerate(sw["curve"]) if c == 1]  # switched onto at a GPD
    assert len(lpc) > 5
    assert {sw["kind"][i] for i in lpc} == {"fold"} and {sw["subharmonic"][i] for i in lpc} == {2}
    assert max(abs(sw["ln_abs_m1"][i]) for i in lpc) < 1e-9
    with pytest.raises(ValueError, match="switch"):
        hdgear.continuation2("omega=0.3:20:log", "delta=0.5:40:log", switch=True)
    b = hdgear.boundary("omega=1e-4:0.2:log", "gamma=0.3:3:log", kinds=["predicted", "simulated"])
    out = cli("boundary", "--param", "omega=1e-4:0.2:log", "--param", "gamma=0.3:3:log",
              "--kinds", "predicted,simulated", "--out", str(tmp_path / "b.csv"))
    assert out.returncode == 0, out.stderr
    rows = read_csv(tmp_path / "b.csv")
    assert [float(r["param1"]) for r in rows] == b["param1"].tolist()
    assert sorted(set(b["kind"])) == ["predicted", "simulated"]
    with pytest.raises(ValueError, match="hopf"):
        hdgear.boundary("omega=1e-4:0.2:log", "gamma=0.3:3:log", kinds=["hopf"])
    with pytest.raises(ValueError, match="fold:9"):
        hdgear.continuation2("omega=0.3:20:log", "delta=0.5:40:log", start="fold:9")


def _sweep(noise=0.0, seed=3):
    v = np.concatenate([-np.geomspace(2, 1e-3, 30), np.geomspace(1e-3, 2, 30)])
    tau = (0.5 + 0.3 * np.exp(-(v / 0.02) ** 2)) * np.sign(v) + 0.3 * v
    return v, tau + noise * np.random.default_rng(seed).standard_normal(len(v))


FREE = {"fc": (0, 5), "fs": (0, 5), "vst": (1e-4, 1), "cv": (0, 2)}


def test_fit_returns_the_truth_and_equals_the_cli(tmp_path):
    v, tau = _sweep(noise=5e-3)
    f = hdgear.fit({"speed": v, "torque": tau}, {"coulomb": {"fc": 1.0, "fs": 1.0, "vst": 0.1}}, FREE)
    lo, hi = f.interval("fs")
    assert lo < 0.8 < hi and f.estimates[1]["name"] == "coulomb.fs"
    # the same data through the command line: the same estimates, bit for bit
    csv = tmp_path / "s.csv"
    np.savetxt(csv, np.column_stack([v, tau]), delimiter=",", header="speed [rad/s],torque [N m]", comments="")
    law = tmp_path / "law.toml"
    law.write_text("[coulomb]\nfc = 1.0\nfs = 1.0\nvst = 0.1\n")
    args = [BIN, "fit", "--data", str(csv), "--kind", "friction", "--config", str(law), "--json"]
    for k, (a, b) in FREE.items():
        args += ["--free", f"{k}={float(a)!r}:{float(b)!r}"]
    doc = json.loads(subprocess.run(args, capture_output=True, text=True, check=True).stdout)
    assert [e["value"] for e in doc["estimates"]] == [e["value"] for e in f.estimates]


def test_fit_plot_draws_data_fit_and_residuals():
    # matplotlib is optional: the environments without it (other Python versions) skip this
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    v, tau = _sweep(noise=5e-3)
    f = hdgear.fit({"speed": v, "torque": tau}, {"coulomb": {"fc": 1.0, "fs": 1.0, "vst": 0.1}}, FREE,
                   profile=False)
    top, bottom = f.plot()
    assert len(top.lines) == 2 and len(bottom.lines) == 2


def test_fit_names_bad_data_and_unseen_parameters():
    v, tau = _sweep()
    tau[3] = np.nan
    f = hdgear.fit({"speed": v, "torque": tau}, {"lugre": {"sigma0": 1e4}},
                   {"fc": (0, 5), "fs": (0, 5), "vst": (1e-4, 1), "sigma1": (0, 100)}, profile=False)
    assert any("1 rows left out" in w for w in f.warnings), f.warnings
    assert any("lugre.sigma1" in w and "do not depend" in w for w in f.warnings), f.warnings
    assert f.interval("sigma1") is None
    with pytest.raises(ValueError, match="LO < HI"):
        hdgear.fit({"speed": v, "torque": tau}, {"coulomb": {}}, {"fc": (5, 0)})
    with pytest.raises(ValueError, match="data kind"):
        hdgear.fit({"speed": v, "torque": tau}, {"coulomb": {}}, {"fc": (0, 5)}, kind="torsion")


# ---- Model -----------------------------------------------------------------------------------

LUGRE = "[params]\ngamma = 1.0\n[lugre]\nfc = 0.05\nfs = 0.08\n"
FRICTION = "[params]\ngamma = 30.0\n[friction]\nfc = 0.1\nvs = 0.05\n"


def _scenario(tmp_path, text, name="m.toml"):
    f = tmp_path / name
    f.write_text(text)
    return str(f)


def test_model_from_tables_equals_the_scenario_file_and_names_its_parameters(tmp_path):
    m = hdgear.Model.from_toml(_scenario(tmp_path, LUGRE))
    assert m == hdgear.Model(hdgear.Params(gamma=1.0), {"lugre": {"fc": 0.05, "fs": 0.08}})
    assert m["lugre.fs"] == m["fs"] == 0.08 and m["gamma"] == 1.0
    d = m.to_dict()
    assert d["lugre.sigma0"] == 100.0 and d["forcing.delta"] == 15.0
    assert m.describe()["states"] == ["x", "x'", "s"]
    r = m.replace({"lugre.fc": 0.06}, delta=12.0)
    assert (r["fc"], r["delta"], m["fc"]) == (0.06, 12.0, 0.05)
    # f_s ≥ f_c is judged on the values asked for together, and the refusal names them
    with pytest.raises(ValueError, match=r"fs = 0\.08.*fc = 0\.2"):
        m.replace({"fc": 0.2})
    assert m.replace({"fc": 0.2, "fs": 0.3})["fs"] == 0.3
    with pytest.raises(KeyError, match="nope"):
        m["nope"]
    with pytest.raises(ValueError, match="unknown table"):
        hdgear.Model.from_toml(_scenario(tmp_path, "[nope]\nfc = 1\n", "bad.toml"))
    with pytest.raises(TypeError, match="hdgear.Params or hdgear.Model"):
        hdgear.simulate("gamma=1")


def test_a_model_without_terms_runs_as_the_study_s_set_to_the_last_bit():
    p = hdgear.Params(gamma=1.0)
    a, b = hdgear.simulate(p, periods=0.25), hdgear.simulate(hdgear.Model(p), periods=0.25)
    assert np.array_equal(a.x, b.x) and np.array_equal(a.xdot, b.xdot) and b.states == {}
    assert hdgear.analyze(hdgear.Model(p)).to_dict() == hdgear.analyze(p).to_dict()


def test_model_simulate_equals_the_cli_with_its_states(tmp_path):
    f = _scenario(tmp_path, LUGRE)
    tr = hdgear.simulate(hdgear.Model.from_toml(f), t_end=150.0, dt=0.5)
    out = cli("simulate", "--config", f, "--t-end", "150", "--dt", "0.5", "--out", str(tmp_path / "t.csv"))
    assert out.returncode == 0, out.stderr
    rows = read_csv(tmp_path / "t.csv")
    assert len(rows) == len(tr) and list(tr.states) == ["s"]
    for k, v in [("t", tr.t), ("a", tr.a), ("x", tr.x), ("xdot", tr.xdot), ("s", tr.states["s"])]:
        assert all(same(r[k], w) for r, w in zip(rows, v)), k
    assert tr.summary["model"]["states"] == ["x", "x'", "s"] and tr.summary["params"]["gamma"] == 1.0
    assert "s" in tr.to_dict()


def test_model_sweep_takes_term_parameters_and_equals_the_cli(tmp_path):
    f = _scenario(tmp_path, FRICTION)
    out = cli("sweep", "--config", f, "--param", "fc=0.05:0.2:3", "--param", "delta=10:15:2",
              "--out", str(tmp_path / "s.csv"))
    assert out.returncode == 0, out.stderr
    rows = read_csv(tmp_path / "s.csv")
    m = hdgear.Model.from_toml(f)
    s = hdgear.sweep({"fc": [0.05, 0.125, 0.2], "delta": [10.0, 15.0]}, base=m)
    assert list(s)[:3] == ["index", "fc", "delta"] and len(s["index"]) == len(rows) == 6
    columns_equal(s, rows)
    # qualified names work too, and name their columns as written
    q = hdgear.sweep({"friction.fc": [0.05, 0.2], "delta": [10.0, 15.0]}, base=m, grid=False)
    assert list(q["friction.fc"]) == [0.05, 0.2]
    assert list(q["max_slope"]) == [float(rows[0]["max_slope"]), float(rows[5]["max_slope"])]
    with pytest.raises(ValueError, match="nope"):
        hdgear.sweep({"friction.nope": [1.0]}, base=m)


def test_model_analyze_periodic_and_continuation_equal_the_cli(tmp_path):
    f = _scenario(tmp_path, FRICTION)
    m = hdgear.Model.from_toml(f)
    assert hdgear.analyze(m).to_dict() == cli_json("analyze", "--config", f, "--json")
    o, c = hdgear.periodic(m), cli_json("periodic", "--config", f, "--json")
    assert o.start == c["start"] and o.multipliers == c["multipliers"] and o.samples == c["samples"]
    assert o.bursts.to_dict() == c["bursts"]
    b = hdgear.continuation("fc", 0.3, params=m)
    out = cli("continue", "--config", f, "--param", "fc=0.1:0.3", "--out", str(tmp_path / "b.csv"))
    assert out.returncode == 0, out.stderr
    rows = read_csv(tmp_path / "b.csv")
    assert [float(r["param"]) for r in rows] == b["param"].tolist()
    assert [float(r["peak_to_peak"]) for r in rows] == b["peak_to_peak"].tolist()
    # the curve of a model is its static torque's (roots found numerically) at its own damping:
    # friction adds no static torque, so it is the study's cubic's (closed form) to rounding
    np.testing.assert_allclose(hdgear.curve(m)["x"], hdgear.curve(hdgear.Params(gamma=30.0))["x"],
                               rtol=1e-12, atol=0)


def test_a_sticking_model_s_orbit_is_shot_and_equals_the_cli(tmp_path):
    # x'' + x' + 4x + 0.3·sgn x' = 2 sin 2.2τ: Den Hartog's closed form (the Rust test
    # den_hartog::stick_free_orbits_are_den_hartog_s writes it out) gives X = 0.6936453137272…
    f = _scenario(tmp_path, "[params]\nmu = 0.0\ndelta = 2.0\nomega = 2.2\n"
                            "[spring]\nklin = 4.0\n[coulomb]\nfc = 0.3\nfs = 0.3\n")
    o, c = hdgear.periodic(hdgear.Model.from_toml(f)), cli_json("periodic", "--config", f, "--json")
    assert abs(o.x_range[1] - 0.6936453137272) < 1e-8
    assert o.start == c["start"] and o.rests.to_dict() == c["rests"] and o.rests.rests == 0
    # with more friction it rests at each turn, and a rest forgets the speed: m2 = 0 exactly
    s = hdgear.periodic(hdgear.Model.from_toml(f).replace({"coulomb.fs": 1.5, "coulomb.fc": 1.5}))
    # (ln|m2| = −∞ is None, as the CLI's JSON has null)
    assert s.rests.rests == 2 and s.multipliers[1]["log_abs"] is None


def test_model_control_and_robust_equal_the_cli(tmp_path):
    f = _scenario(tmp_path, "[params]\ngamma = 0.1\n[friction]\nfc = 0.02\nvs = 0.05\n")
    m = hdgear.Model.from_toml(f)
    a = hdgear.control("washout", params=m, gain=10, ww=0.03)
    c = cli_json("control", "washout", "--config", f, "--gain", "10", "--ww", "0.03", "--json")
    assert a.to_dict() == c and len(c["assessments"]) == 1
    s, df = hdgear.robust(m, {"friction.fc": "±50%"}, samples=32, worst=False)
    doc = cli_json("robust", "--config", f, "--tolerance", "friction.fc=±50%", "--samples", "32",
                   "--no-worst", "--json", "--out", str(tmp_path / "s.csv"))
    assert s.probability.to_dict() == doc["probability"] and s.probability.judged == 32
    rows = read_csv(tmp_path / "s.csv")
    assert [r["verdict"] for r in rows] == list(df["verdict"])


def test_equilibria_refuses_a_model_and_points_to_curve(tmp_path):
    m = hdgear.Model.from_toml(_scenario(tmp_path, FRICTION))
    with pytest.raises(TypeError, match=r"hdgear\.curve\(model\)"):
        hdgear.equilibria(m, 0.1)
    with pytest.raises(ValueError, match="simulated_boundaries"):
        hdgear.analyze(m, simulated_boundaries=True)


def test_the_docstring_examples_run():
    import doctest
    result = doctest.testmod(hdgear, extraglobs={"hdgear": hdgear})
    assert result.failed == 0 and result.attempted >= 4, result
    finder, runner = doctest.DocTestFinder(), doctest.DocTestRunner()
    tests = finder.find(hdgear.Model, "hdgear.Model", globs={"hdgear": hdgear})
    for t in tests:
        runner.run(t)
    assert runner.failures == 0 and runner.tries >= 2
