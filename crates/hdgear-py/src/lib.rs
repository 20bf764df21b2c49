//! The native part of the `hdgear` Python package (`hdgear._hdgear`). The Python layer
//! (`python/hdgear/__init__.py`) gives it its documented API; this module turns Python values
//! into the library's checked types, runs the library with the GIL released, and hands back numpy
//! arrays (numbers) or JSON (nested results, which the Python layer turns into objects).
//!
//! Errors: the library's input errors become `ValueError` with the CLI's message; a failed
//! integration (step-size underflow, blow-up, step budget) a `RuntimeError`.

#![forbid(unsafe_code)]

use hdgear::burst::{BurstOptions, Mechanism, Mode};
use hdgear::integrate::{Method, Options};
use hdgear::params::{Param, ParamOverrides, Params as LibParams};
use hdgear::physical::PhysicalParams;
use hdgear::simulate::{SimOptions, Start};
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;

fn err(e: hdgear::Error) -> PyErr {
    match e {
        hdgear::Error::Solver(_) => PyRuntimeError::new_err(e.to_string()),
        other => PyValueError::new_err(other.to_string()),
    }
}

fn json<T: serde::Serialize>(v: &T) -> PyResult<String> {
    serde_json::to_string(v).map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// The dimensionless parameters α, γ, ε, μ, δ, ω (validated; see `hdgear.Params`).
#[pyclass(frozen, eq, module = "hdgear._hdgear")]
#[derive(Clone, PartialEq)]
struct Params {
    inner: LibParams,
}

#[pymethods]
impl Params {
    #[new]
    #[pyo3(signature = (alpha=None, gamma=None, eps=None, mu=None, delta=None, omega=None, preset="paper"))]
    fn new(
        alpha: Option<f64>,
        gamma: Option<f64>,
        eps: Option<f64>,
        mu: Option<f64>,
        delta: Option<f64>,
        omega: Option<f64>,
        preset: &str,
    ) -> PyResult<Params> {
        let o = ParamOverrides {
            alpha,
            gamma,
            eps,
            mu,
            delta,
            omega,
        };
        let (inner, _) = hdgear::params::resolve(preset, None, &o).map_err(err)?;
        Ok(Params { inner })
    }

    /// The study's parameter set with γ (default 0.1).
    #[staticmethod]
    #[pyo3(signature = (gamma=None))]
    fn paper(gamma: Option<f64>) -> PyResult<Params> {
        Params::new(None, gamma, None, None, None, None, "paper")
    }

    /// A copy with some values replaced (validated).
    #[pyo3(signature = (alpha=None, gamma=None, eps=None, mu=None, delta=None, omega=None))]
    fn replace(
        &self,
        alpha: Option<f64>,
        gamma: Option<f64>,
        eps: Option<f64>,
        mu: Option<f64>,
        delta: Option<f64>,
        omega: Option<f64>,
    ) -> PyResult<Params> {
        let mut p = self.inner;
        ParamOverrides {
            alpha,
            gamma,
            eps,
            mu,
            delta,
            omega,
        }
        .apply(&mut p);
        p.validate().map_err(err)?;
        Ok(Params { inner: p })
    }

    /// The six values as a dict.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for q in Param::ALL {
            d.set_item(q.name(), self.inner.value(q))?;
        }
        Ok(d)
    }

    /// Warnings of this set (α·ε ≠ 1, …), as sentences.
    #[getter]
    fn warnings(&self) -> PyResult<Vec<String>> {
        Ok(self
            .inner
            .validate()
            .map_err(err)?
            .iter()
            .map(ToString::to_string)
            .collect())
    }

    #[getter]
    fn alpha(&self) -> f64 {
        self.inner.alpha
    }
    #[getter]
    fn gamma(&self) -> f64 {
        self.inner.gamma
    }
    #[getter]
    fn eps(&self) -> f64 {
        self.inner.eps
    }
    #[getter]
    fn mu(&self) -> f64 {
        self.inner.mu
    }
    #[getter]
    fn delta(&self) -> f64 {
        self.inner.delta
    }
    #[getter]
    fn omega(&self) -> f64 {
        self.inner.omega
    }

    /// The six values as a JSON object.
    fn to_json(&self) -> PyResult<String> {
        json(&self.inner)
    }

    fn __repr__(&self) -> String {
        let p = self.inner;
        format!(
            "Params(alpha={:?}, gamma={:?}, eps={:?}, mu={:?}, delta={:?}, omega={:?})",
            p.alpha, p.gamma, p.eps, p.mu, p.delta, p.omega
        )
    }
}

/// Detection options and tolerances from keyword values.
fn burst_options(
    discard: f64,
    window_periods: u32,
    rtol: f64,
    atol: f64,
    method: &str,
) -> PyResult<BurstOptions> {
    let o = BurstOptions {
        discard_periods: discard,
        periods: window_periods,
        tol: tol(rtol, atol, method)?,
        ..BurstOptions::default()
    };
    o.validate().map_err(err)?;
    Ok(o)
}

fn tol(rtol: f64, atol: f64, method: &str) -> PyResult<Options> {
    let method: Method = method.parse().map_err(err)?;
    let o = Options {
        rtol,
        atol,
        method,
        ..Options::default()
    };
    o.validate().map_err(err)?;
    Ok(o)
}

type Arrays<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    String,
);

/// Samples t, a, x, x' of one simulation, in vectors sized for them.
fn run_simulation(
    p: &LibParams,
    opts: &SimOptions,
) -> hdgear::Result<([Vec<f64>; 4], hdgear::simulate::SimSummary)> {
    let mut cols: [Vec<f64>; 4] = Default::default();
    let n = (opts.t_end / opts.dt).ceil() as usize + 2;
    cols.iter_mut().for_each(|c| c.reserve(n.min(1 << 26)));
    let summary = hdgear::simulate::simulate(p, opts, |t, y| {
        cols[0].push(t);
        cols[1].push((p.omega * t).sin());
        cols[2].push(y[0]);
        cols[3].push(y[1]);
    })?;
    Ok((cols, summary))
}

/// One simulation: (t, a, x, xdot, summary JSON).
#[pyfunction]
#[pyo3(signature = (params, t_end, dt, x0, v0, from_rest, rtol, atol, method))]
#[allow(clippy::too_many_arguments)]
fn simulate<'py>(
    py: Python<'py>,
    params: &Params,
    t_end: f64,
    dt: f64,
    x0: Option<f64>,
    v0: Option<f64>,
    from_rest: bool,
    rtol: f64,
    atol: f64,
    method: &str,
) -> PyResult<Arrays<'py>> {
    let p = params.inner;
    let start = match (x0, v0, from_rest) {
        (None, None, false) => Start::Equilibrium,
        (None, None, true) => Start::Rest,
        (x, v, false) => Start::Given {
            x0: x.unwrap_or_else(|| hdgear::fast::stable_equilibrium(&p, 0.0)),
            v0: v.unwrap_or(0.0),
        },
        _ => return Err(PyValueError::new_err("give x0/v0 or from_rest, not both")),
    };
    let opts = SimOptions {
        t_end,
        dt,
        start,
        tol: tol(rtol, atol, method)?,
    };
    let (cols, summary) = py.detach(|| run_simulation(&p, &opts)).map_err(err)?;
    let [t, a, x, v] = cols;
    Ok((
        t.into_pyarray(py),
        a.into_pyarray(py),
        x.into_pyarray(py),
        v.into_pyarray(py),
        json(&summary.report(&p, &[]))?,
    ))
}

/// The same simulation `n` times in Rust, samples collected by the same function as
/// `simulate` and dropped: seconds per run (the reference of the Python overhead benchmark).
#[pyfunction]
fn time_simulate_in_rust(
    py: Python<'_>,
    params: &Params,
    t_end: f64,
    dt: f64,
    n: usize,
) -> PyResult<f64> {
    let p = params.inner;
    let opts = SimOptions {
        t_end,
        dt,
        ..SimOptions::default()
    };
    py.detach(|| {
        let t0 = std::time::Instant::now();
        for _ in 0..n {
            std::hint::black_box(run_simulation(&p, &opts)?);
        }
        Ok(t0.elapsed().as_secs_f64() / n.max(1) as f64)
    })
    .map_err(err)
}

/// The equilibria at `a`, as JSON.
#[pyfunction]
fn equilibria(params: &Params, a: f64) -> PyResult<String> {
    if !a.is_finite() {
        return Err(PyValueError::new_err(format!(
            "invalid a = {a:?}: must be finite"
        )));
    }
    json(&hdgear::fast::equilibria(&params.inner, a))
}

/// The equilibrium curve as a dict of arrays.
#[pyfunction]
fn curve<'py>(
    py: Python<'py>,
    params: &Params,
    points: usize,
    a0: f64,
    a1: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let p = params.inner;
    if points < 2 {
        return Err(PyValueError::new_err(format!(
            "invalid points = {points}: must be ≥ 2"
        )));
    }
    let c = py
        .detach(|| hdgear::fast::curve(&p, (a0, a1), points))
        .map_err(err)?;
    let d = PyDict::new(py);
    let col = |f: fn(&hdgear::fast::CurvePoint) -> f64| c.iter().map(f).collect::<Vec<f64>>();
    d.set_item("a", col(|c| c.a).into_pyarray(py))?;
    d.set_item("x", col(|c| c.x).into_pyarray(py))?;
    d.set_item("slope", col(|c| c.slope).into_pyarray(py))?;
    d.set_item("gprime", col(|c| c.gprime).into_pyarray(py))?;
    let stable: Vec<bool> = c.iter().map(|c| c.kind.is_stable()).collect();
    d.set_item("stable", stable.into_pyarray(py))?;
    let kind: Vec<&str> = c.iter().map(|c| c.kind.name()).collect();
    d.set_item("type", kind)?;
    let branch: Vec<String> = c
        .iter()
        .map(|c| {
            serde_json::to_value(c.branch)
                .ok()
                .and_then(|v| v.as_str().map(String::from))
                .unwrap_or_default()
        })
        .collect();
    d.set_item("branch", branch)?;
    Ok(d)
}

/// `hdgear analyze --json` as a JSON string.
#[pyfunction]
#[pyo3(signature = (params, response, simulated_boundaries, discard, window_periods, rtol, atol, method))]
#[allow(clippy::too_many_arguments)]
fn analyze(
    py: Python<'_>,
    params: &Params,
    response: bool,
    simulated_boundaries: bool,
    discard: f64,
    window_periods: u32,
    rtol: f64,
    atol: f64,
    method: &str,
) -> PyResult<String> {
    let p = params.inner;
    let opts = burst_options(discard, window_periods, rtol, atol, method)?;
    let doc = py
        .detach(|| -> hdgear::Result<_> {
            let analysis = hdgear::fast::analyze(&p, hdgear::fast::A_RANGE)?;
            let (response, classification) = if response {
                let r = hdgear::burst::response(&p, &opts)?;
                let c = hdgear::burst::classify(&p, &r);
                (Some(r), Some(c))
            } else {
                (None, None)
            };
            let boundaries = if simulated_boundaries {
                Some(hdgear::burst::boundaries(&p, &opts)?)
            } else {
                None
            };
            Ok(hdgear::study::PointAnalysis {
                analysis,
                response,
                classification,
                boundaries,
                warnings: p.validate()?.iter().map(ToString::to_string).collect(),
            })
        })
        .map_err(err)?;
    json(&doc)
}

/// The sweep of explicit points: the parameter sets are `base` with `names[k]` set to
/// `values[k][i]` for point i; rows as a dict of columns, computed in parallel without the GIL.
#[pyfunction]
#[pyo3(signature = (base, names, values, threads, discard, window_periods, rtol, atol, method))]
#[allow(clippy::too_many_arguments)]
fn sweep<'py>(
    py: Python<'py>,
    base: &Params,
    names: Vec<String>,
    values: Vec<Vec<f64>>,
    threads: usize,
    discard: f64,
    window_periods: u32,
    rtol: f64,
    atol: f64,
    method: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let opts = burst_options(discard, window_periods, rtol, atol, method)?;
    let params: Vec<Param> = names
        .iter()
        .map(|n| n.parse().map_err(err))
        .collect::<PyResult<_>>()?;
    let n = values.first().map_or(0, Vec::len);
    if values.iter().any(|v| v.len() != n) {
        return Err(PyValueError::new_err(
            "every parameter needs the same number of values",
        ));
    }
    let points: Vec<LibParams> = (0..n)
        .map(|i| {
            params
                .iter()
                .zip(&values)
                .fold(base.inner, |p, (&q, v)| p.with(q, v[i]))
        })
        .collect();
    for p in &points {
        p.validate().map_err(err)?;
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| PyValueError::new_err(format!("invalid threads = {threads}: {e}")))?;
    let rows: Vec<hdgear::sweep::SweepRow> = py.detach(|| {
        pool.install(|| {
            let indexed: Vec<(usize, LibParams)> = points.into_iter().enumerate().collect();
            indexed
                .par_chunks(hdgear::batch::LANES)
                .flat_map_iter(|chunk| hdgear::sweep::run_points(chunk, &opts))
                .collect()
        })
    });
    columns(py, &rows)
}

/// Sweep rows as a dict of columns (the CLI's CSV columns).
fn columns<'py>(py: Python<'py>, rows: &[hdgear::sweep::SweepRow]) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let f = |g: fn(&hdgear::sweep::SweepRow) -> f64| rows.iter().map(g).collect::<Vec<f64>>();
    let index: Vec<i64> = rows.iter().map(|r| r.index as i64).collect();
    d.set_item("index", index.into_pyarray(py))?;
    for (name, col) in [
        ("alpha", f(|r| r.params.alpha)),
        ("gamma", f(|r| r.params.gamma)),
        ("eps", f(|r| r.params.eps)),
        ("mu", f(|r| r.params.mu)),
        ("delta", f(|r| r.params.delta)),
        ("omega", f(|r| r.params.omega)),
    ] {
        d.set_item(name, col.into_pyarray(py))?;
    }
    let mode: Vec<&str> = rows.iter().map(|r| r.mode.map_or("", Mode::name)).collect();
    let mech: Vec<&str> = rows
        .iter()
        .map(|r| r.mechanism.map_or("", Mechanism::name))
        .collect();
    d.set_item("mode", mode)?;
    d.set_item("mechanism", mech)?;
    for (name, col) in [
        (
            "bursts_per_period",
            f(|r| r.rates.bursts_per_period.unwrap_or(f64::NAN)),
        ),
        ("spikes_per_burst", f(|r| r.rates.spikes_per_burst)),
        ("burst_amplitude", f(|r| r.rates.burst_amplitude)),
        ("peak_abs_xdot", f(|r| r.rates.peak_abs_xdot)),
        ("quiescent_duration", f(|r| r.rates.quiescent_duration)),
        ("quiescent_fraction", f(|r| r.rates.quiescent_fraction)),
        ("max_tracking_error", f(|r| r.rates.max_tracking_error)),
        ("max_slope", f(|r| r.max_slope)),
    ] {
        d.set_item(name, col.into_pyarray(py))?;
    }
    let errors: Vec<&str> = rows.iter().map(|r| r.error.as_str()).collect();
    d.set_item("error", errors)?;
    Ok(d)
}

/// The bursts of a response, as JSON.
#[pyfunction]
#[pyo3(signature = (params, discard, window_periods, rtol, atol, method))]
fn bursts(
    py: Python<'_>,
    params: &Params,
    discard: f64,
    window_periods: u32,
    rtol: f64,
    atol: f64,
    method: &str,
) -> PyResult<String> {
    let p = params.inner;
    let opts = burst_options(discard, window_periods, rtol, atol, method)?;
    let r = py
        .detach(|| hdgear::burst::response(&p, &opts))
        .map_err(err)?;
    json(&r.bursts)
}

/// A drive in SI units (see `hdgear.Drive`).
#[pyclass(frozen, module = "hdgear._hdgear")]
#[derive(Clone)]
struct Drive {
    inner: PhysicalParams,
}

#[pymethods]
impl Drive {
    /// A drive from a JSON object of all ten values (validated).
    #[staticmethod]
    fn from_json(text: &str) -> PyResult<Drive> {
        let inner: PhysicalParams = serde_json::from_str(text)
            .map_err(|e| PyValueError::new_err(format!("invalid drive: {e}")))?;
        inner.validate().map_err(err)?;
        Ok(Drive { inner })
    }

    /// A catalogue drive with the documented assumptions, and the fit, as (drive, fit JSON).
    #[staticmethod]
    #[pyo3(signature = (name, fit_torque=None))]
    fn catalogue(name: &str, fit_torque: Option<f64>) -> PyResult<(Drive, String)> {
        let (inner, fit) = hdgear::physical::catalogue::preset(name, fit_torque).map_err(err)?;
        Ok((Drive { inner }, json(&fit)?))
    }

    /// The ten values as JSON.
    fn to_json(&self) -> PyResult<String> {
        json(&self.inner)
    }

    /// The reduction to the dimensionless model: (Params, reduction JSON).
    fn reduce(&self) -> PyResult<(Params, String)> {
        let r = self.inner.reduce().map_err(err)?;
        Ok((Params { inner: r.params }, json(&r)?))
    }

    /// The two-inertia simulation from rest: (t, theta_in, theta_out, theta, theta_dot, summary).
    #[pyo3(signature = (t_end, dt, rtol, atol))]
    #[allow(clippy::type_complexity)]
    fn simulate<'py>(
        &self,
        py: Python<'py>,
        t_end: f64,
        dt: f64,
        rtol: f64,
        atol: f64,
    ) -> PyResult<(Vec<Bound<'py, PyArray1<f64>>>, String)> {
        let d = self.inner;
        let t = tol(rtol, atol, "taylor")?;
        let (cols, s) = py
            .detach(|| {
                let mut cols: [Vec<f64>; 5] = Default::default();
                hdgear::physical::simulate::simulate_physical(&d, t_end, dt, t, |s| {
                    for (c, v) in
                        cols.iter_mut()
                            .zip([s.t, s.theta_in, s.theta_out, s.theta, s.theta_dot])
                    {
                        c.push(v);
                    }
                })
                .map(|s| (cols, s))
            })
            .map_err(err)?;
        Ok((
            cols.into_iter().map(|c| c.into_pyarray(py)).collect(),
            json(&s.report())?,
        ))
    }

    /// The design check as JSON.
    #[pyo3(signature = (discard, window_periods, rtol, atol))]
    fn design_check(
        &self,
        py: Python<'_>,
        discard: f64,
        window_periods: u32,
        rtol: f64,
        atol: f64,
    ) -> PyResult<String> {
        let d = self.inner;
        let opts = burst_options(discard, window_periods, rtol, atol, "taylor")?;
        let c = py
            .detach(|| hdgear::physical::design::design_check(&d, &opts))
            .map_err(err)?;
        json(&c)
    }
}

/// The periodic orbit of period k·2π/ω by shooting, with its burst verdict, as JSON.
#[pyfunction]
#[pyo3(signature = (params, subharmonic))]
fn periodic(py: Python<'_>, params: &Params, subharmonic: u32) -> PyResult<String> {
    use hdgear::periodic::{PeriodicOptions, burst_verdict, shoot};
    let p = params.inner;
    let (orbit, bursts) = py
        .detach(|| {
            let o = shoot(&p, subharmonic, &PeriodicOptions::default())?;
            let b = burst_verdict(&o, &BurstOptions::default())?;
            Ok::<_, hdgear::Error>((o, b))
        })
        .map_err(err)?;
    #[derive(serde::Serialize)]
    struct Doc<'a> {
        #[serde(flatten)]
        orbit: &'a hdgear::periodic::PeriodicOrbit,
        bursts: hdgear::burst::Classification,
        samples: &'a [[f64; 3]],
    }
    json(&Doc {
        orbit: &orbit,
        bursts,
        samples: &orbit.samples,
    })
}

/// Continuation of the periodic orbit in `name` from the value in `params` to `to` (log scale
/// when `log`), with the doubled branches when `switch`: the rows of `hdgear continue` as a dict
/// of columns. `to` of None and name "omega" with `log`: the frequency response over the default
/// range (then `params`' ω is ignored).
#[pyfunction]
#[pyo3(signature = (params, name, to, log, subharmonic, switch))]
fn continuation<'py>(
    py: Python<'py>,
    params: &Params,
    name: &str,
    to: Option<f64>,
    log: bool,
    subharmonic: u32,
    switch: bool,
) -> PyResult<Bound<'py, PyDict>> {
    use hdgear::periodic::{
        Branch, BranchRow, ContinuationOptions, Scale, continue_with_doubled,
        default_frequency_range as frequency_range,
    };
    let param: Param = name.parse().map_err(err)?;
    let p = params.inner;
    let opts = ContinuationOptions {
        scale: if log { Scale::Log } else { Scale::Linear },
        ..ContinuationOptions::default()
    };
    let branches: Vec<Branch<Param>> = py
        .detach(|| {
            let (start, to) = match to {
                Some(to) => (p, to),
                None => {
                    let (lo, hi) = frequency_range(&p);
                    (p.with(param, lo), hi)
                }
            };
            continue_with_doubled(&start, param, subharmonic, to, switch, &opts)
        })
        .map_err(err)?;
    let rows: Vec<BranchRow> = branches
        .iter()
        .enumerate()
        .flat_map(|(i, b)| {
            b.points
                .iter()
                .map(move |q| BranchRow::new(i, b.subharmonic, q))
        })
        .collect();
    let d = PyDict::new(py);
    let f = |g: fn(&BranchRow) -> f64| rows.iter().map(g).collect::<Vec<f64>>();
    let ints = |g: fn(&BranchRow) -> i64| rows.iter().map(g).collect::<Vec<i64>>();
    d.set_item("branch", ints(|r| r.branch as i64).into_pyarray(py))?;
    d.set_item(
        "subharmonic",
        ints(|r| i64::from(r.subharmonic)).into_pyarray(py),
    )?;
    for (col, v) in [
        ("param", f(|r| r.param)),
        ("x0", f(|r| r.x0)),
        ("xdot0", f(|r| r.xdot0)),
        ("x_min", f(|r| r.x_min)),
        ("x_max", f(|r| r.x_max)),
        ("peak_to_peak", f(|r| r.peak_to_peak)),
        ("max_abs_xdot", f(|r| r.max_abs_xdot)),
        ("ln_abs_m1", f(|r| r.ln_abs_m1)),
        ("arg_m1", f(|r| r.arg_m1)),
        ("ln_abs_m2", f(|r| r.ln_abs_m2)),
        ("arg_m2", f(|r| r.arg_m2)),
    ] {
        d.set_item(col, v.into_pyarray(py))?;
    }
    let stable: Vec<bool> = rows.iter().map(|r| r.stable).collect();
    d.set_item("stable", stable)?;
    let special: Vec<&str> = rows.iter().map(|r| r.special).collect();
    d.set_item("special", special)?;
    Ok(d)
}

/// The native module.
#[pymodule]
fn _hdgear(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Params>()?;
    m.add_class::<Drive>()?;
    for f in [
        wrap_pyfunction!(simulate, m)?,
        wrap_pyfunction!(time_simulate_in_rust, m)?,
        wrap_pyfunction!(equilibria, m)?,
        wrap_pyfunction!(curve, m)?,
        wrap_pyfunction!(analyze, m)?,
        wrap_pyfunction!(sweep, m)?,
        wrap_pyfunction!(bursts, m)?,
        wrap_pyfunction!(periodic, m)?,
        wrap_pyfunction!(continuation, m)?,
    ] {
        m.add_function(f)?;
    }
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
