"""A hostile user of the Python package: every numeric argument of the cheap entry points with
each of the CLI generator's hostile values. Each call must return or raise ValueError, TypeError
or OverflowError (a Rust panic would surface as pyo3's PanicException, a BaseException that
this does not catch), within the CLI hostile test's 30 s."""
import time

import pytest

import hdgear

VALUES = [float("nan"), float("inf"), float("-inf"), 0.0, -1.0, 1e300, -1e300, 1e-320, 5e-324,
          "", "abc", -0.0]
PARAMS = ["alpha", "gamma", "eps", "mu", "delta", "omega"]


def calls():
    """(label, thunk) for every hostile call."""
    out = []
    for v in VALUES:
        for name in PARAMS:
            out.append((f"Params({name}={v!r})", lambda n=name, v=v: hdgear.Params(**{n: v})))
        for kw in ["t_end", "periods", "dt", "x0", "v0", "rtol", "atol"]:
            out.append((f"simulate({kw}={v!r})", lambda kw=kw, v=v: hdgear.simulate(**{kw: v})))
        out.append((f"equilibria(a={v!r})", lambda v=v: hdgear.equilibria(hdgear.Params(), v)))
        out.append((f"curve(points={v!r})", lambda v=v: hdgear.curve(points=v)))
        out.append((f"curve(a_range=({v!r}, 1))", lambda v=v: hdgear.curve(a_range=(v, 1.0))))
        for kw in ["discard", "window_periods", "rtol", "atol"]:
            out.append((f"analyze({kw}={v!r})", lambda kw=kw, v=v: hdgear.analyze(**{kw: v})))
            out.append((f"bursts({kw}={v!r})", lambda kw=kw, v=v: hdgear.bursts(**{kw: v})))
        out.append((f"periodic(subharmonic={v!r})", lambda v=v: hdgear.periodic(subharmonic=v)))
    return out


def test_hostile_values_raise_python_errors_never_panic():
    refused = 0
    all_calls = calls()
    for label, thunk in all_calls:
        start = time.monotonic()
        try:
            thunk()
        except (ValueError, TypeError, OverflowError) as e:
            assert str(e) and "\n" not in str(e).strip(), f"{label}: {e!r}"
            refused += 1
        assert time.monotonic() - start < 30, label
    assert len(all_calls) >= 250 and refused * 2 > len(all_calls), (refused, len(all_calls))


def test_a_sobol_design_beyond_memory_raises_before_sampling():
    # 10⁹ rows of a one-parameter design are 3·10⁹ runs: refused at once, naming the option
    start = time.monotonic()
    with pytest.raises(ValueError, match="sobol"):
        hdgear.robust(hdgear.Params.paper(gamma=0.1), {"gamma": "±10%"}, samples=16, worst=False,
                      sobol=10**9)
    assert time.monotonic() - start < 30


def test_control_spread_zero_skips_the_robustness_check_as_the_cli_does():
    r = hdgear.control("vdamping", hdgear.Params.paper(gamma=0.1), spread=0)
    # no robustness checked: the result carries none (an empty list is left out of it)
    assert not r.to_dict().get("robustness") and len(r.tunings) == 1
    with pytest.raises(ValueError, match=r"\[0, 1\)"):
        hdgear.control("vdamping", hdgear.Params.paper(gamma=0.1), spread=1.5)


def test_a_sample_spacing_of_zero_is_named_as_such():
    for dt in [0.0, -1.0, float("nan")]:
        with pytest.raises(ValueError, match="dt .*must be finite and > 0"):
            hdgear.simulate(hdgear.Params.paper(gamma=1.0), dt=dt)


def test_array_axes_and_a_single_kind_are_taken_as_meant():
    import numpy as np
    with pytest.raises(ValueError, match="2-dimensional"):
        hdgear.sweep({"gamma": np.ones((2, 2))})
    one = hdgear.boundary("omega=1e-3:0.2:log", "gamma=0.3:3:log", kinds="predicted")
    both = hdgear.boundary("omega=1e-3:0.2:log", "gamma=0.3:3:log", kinds=["predicted"])
    assert len(one) == len(both) > 0
