//! Sweeps of explicit parameter sets on all cores, and the bursts of one response.

use crate::convert::{Detection, err, interruptible, to_py};
use crate::params::Params;
use hdgear::burst::{Mechanism, Mode};
use hdgear::params::{Param, Params as LibParams};
use numpy::IntoPyArray;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use std::sync::atomic::Ordering;

/// The sweep of explicit points: the parameter sets are `base` with `names[k]` set to
/// `values[k][i]` for point i; rows as a dict of columns, computed in parallel without the GIL.
#[pyfunction]
#[pyo3(signature = (base, names, values, threads, detection))]
pub(crate) fn sweep<'py>(
    py: Python<'py>,
    base: &Params,
    names: Vec<String>,
    values: Vec<Vec<f64>>,
    threads: usize,
    detection: Detection,
) -> PyResult<Bound<'py, PyDict>> {
    let opts = detection.0;
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
    let pool = hdgear::sweep::pool(threads).map_err(err)?;
    // Ctrl-C stops the sweep between chunks of points
    let rows: Vec<hdgear::sweep::SweepRow> = interruptible(py, |stop| {
        pool.install(|| {
            let indexed: Vec<(usize, LibParams)> = points.into_iter().enumerate().collect();
            indexed
                .par_chunks(hdgear::batch::LANES)
                .flat_map_iter(|chunk| {
                    if stop.load(Ordering::Relaxed) {
                        Vec::new()
                    } else {
                        hdgear::sweep::run_points(chunk, &opts)
                    }
                })
                .collect()
        })
    })?;
    columns(py, &rows)
}

/// Sweep rows as a dict of columns (the CLI's CSV columns).
fn columns<'py>(py: Python<'py>, rows: &[hdgear::sweep::SweepRow]) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let f = |g: fn(&hdgear::sweep::SweepRow) -> f64| rows.iter().map(g).collect::<Vec<f64>>();
    let index: Vec<i64> = rows.iter().map(|r| r.index as i64).collect();
    d.set_item("index", index.into_pyarray(py))?;
    for q in hdgear::params::Param::ALL {
        let col: Vec<f64> = rows.iter().map(|r| r.params.value(q)).collect();
        d.set_item(q.name(), col.into_pyarray(py))?;
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

/// The bursts of a response, as a list of dicts.
#[pyfunction]
#[pyo3(signature = (params, detection))]
pub(crate) fn bursts<'py>(
    py: Python<'py>,
    params: &Params,
    detection: Detection,
) -> PyResult<Bound<'py, PyAny>> {
    let p = params.inner;
    let opts = detection.0;
    let r = py
        .detach(|| hdgear::burst::response(&p, &opts))
        .map_err(err)?;
    to_py(py, &r.bursts)
}
