//! Simulations of the dimensionless model, returned as numpy arrays.

use crate::convert::{check_samples, err, to_py, tol};
use crate::params::Params;
use hdgear::params::Params as LibParams;
use hdgear::simulate::{SimOptions, Start};
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

type Arrays<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyAny>,
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

/// One simulation: (t, a, x, xdot, summary dict).
#[pyfunction]
#[pyo3(signature = (params, t_end, dt, x0, v0, from_rest, rtol, atol, method))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn simulate<'py>(
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
    // a run beyond the step budget is refused as such, before its record is sized
    hdgear::integrate::check_budget(t_end, &opts.tol).map_err(err)?;
    check_samples(t_end, dt)?;
    let (cols, summary) = py.detach(|| run_simulation(&p, &opts)).map_err(err)?;
    let [t, a, x, v] = cols;
    Ok((
        t.into_pyarray(py),
        a.into_pyarray(py),
        x.into_pyarray(py),
        v.into_pyarray(py),
        to_py(py, &summary.report(&p, &[]))?,
    ))
}

/// The same simulation `n` times in Rust, samples collected by the same function as
/// `simulate` and dropped: seconds per run (the reference of the Python overhead benchmark).
#[pyfunction]
pub(crate) fn time_simulate_in_rust(
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
    check_samples(t_end, dt)?;
    py.detach(|| {
        let t0 = std::time::Instant::now();
        for _ in 0..n {
            std::hint::black_box(run_simulation(&p, &opts)?);
        }
        Ok(t0.elapsed().as_secs_f64() / n.max(1) as f64)
    })
    .map_err(err)
}
