//! Sweeps of explicit points of a parameter set or a model on all cores, and the bursts of one
//! response.

use crate::convert::{Detection, err, interruptible, to_py};
use crate::model::subject_of;
use hdgear::burst::{BurstOptions, Mechanism, Mode, PlaneSystem};
use hdgear::model::Subject;
use hdgear::sweep::{Sweep, SweepRow};
use numpy::IntoPyArray;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rayon::prelude::*;
use std::sync::atomic::Ordering;

/// The sweep of explicit points: the points are `base` (a `Params` or a `Model`) with
/// `names[k]` (any of its parameters, `coulomb.fs` of a model) set to `values[k][i]` for point
/// i, each checked; rows as a dict of columns, computed in parallel without the GIL.
#[pyfunction]
#[pyo3(signature = (base, names, values, threads, detection))]
pub(crate) fn sweep<'py>(
    py: Python<'py>,
    base: &Bound<'py, PyAny>,
    names: Vec<String>,
    values: Vec<Vec<f64>>,
    threads: usize,
    detection: Detection,
) -> PyResult<Bound<'py, PyDict>> {
    let n = values.first().map_or(0, Vec::len);
    if values.iter().any(|v| v.len() != n) {
        return Err(PyValueError::new_err(
            "every parameter needs the same number of values",
        ));
    }
    let subject = subject_of(base)?;
    hdgear::on_subject!(&subject, |s| {
        let rows = sweep_on(py, s, &names, &values, threads, &detection.0)?;
        columns(py, s, &rows, &names, &values)
    })
}

/// The rows of the points of `base` with each of `names` at its values, in point order.
fn sweep_on<S: Sweep>(
    py: Python<'_>,
    base: &S,
    names: &[String],
    values: &[Vec<f64>],
    threads: usize,
    opts: &BurstOptions,
) -> PyResult<Vec<SweepRow<S::Point>>> {
    let params: Vec<S::Param> = names
        .iter()
        .map(|n| base.param_named(n).map_err(err))
        .collect::<PyResult<_>>()?;
    let n = values.first().map_or(0, Vec::len);
    let points: Vec<(usize, S)> = (0..n)
        .map(|i| {
            let changes: Vec<(S::Param, f64)> =
                params.iter().zip(values).map(|(&q, v)| (q, v[i])).collect();
            let p = base.set(&changes)?;
            PlaneSystem::check(&p)?;
            Ok((i, p))
        })
        .collect::<hdgear::Result<_>>()
        .map_err(err)?;
    let pool = hdgear::sweep::pool(threads).map_err(err)?;
    // Ctrl-C stops the sweep between chunks of points
    interruptible(py, |stop| {
        pool.install(|| {
            points
                .par_chunks(S::CHUNK.max(1))
                .flat_map_iter(|chunk| {
                    if stop.load(Ordering::Relaxed) {
                        Vec::new()
                    } else {
                        S::rows(chunk, &[], opts)
                    }
                })
                .collect()
        })
    })
}

/// Sweep rows as a dict of columns (the CLI's CSV columns): the index, the parameters each row
/// records (the study's six), each swept parameter not among them as named, then the verdict's.
fn columns<'py, S: Sweep>(
    py: Python<'py>,
    _base: &S,
    rows: &[SweepRow<S::Point>],
    names: &[String],
    values: &[Vec<f64>],
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let f = |g: fn(&SweepRow<S::Point>) -> f64| rows.iter().map(g).collect::<Vec<f64>>();
    let index: Vec<i64> = rows.iter().map(|r| r.index as i64).collect();
    d.set_item("index", index.into_pyarray(py))?;
    let recorded: Vec<&str> = rows
        .first()
        .map(|r| S::entries(&r.params).into_iter().map(|(k, _)| k).collect())
        .unwrap_or_default();
    for (k, name) in recorded.iter().enumerate() {
        let col: Vec<f64> = rows.iter().map(|r| S::entries(&r.params)[k].1).collect();
        d.set_item(name, col.into_pyarray(py))?;
    }
    for (name, v) in names.iter().zip(values) {
        if !recorded.contains(&name.as_str()) {
            let col: Vec<f64> = rows.iter().map(|r| v[r.index]).collect();
            d.set_item(name, col.into_pyarray(py))?;
        }
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

/// The bursts of the response of a `Params` or a `Model`, as a list of dicts.
#[pyfunction]
#[pyo3(signature = (params, detection))]
pub(crate) fn bursts<'py>(
    py: Python<'py>,
    params: &Bound<'py, PyAny>,
    detection: Detection,
) -> PyResult<Bound<'py, PyAny>> {
    let opts = detection.0;
    let r = match subject_of(params)? {
        Subject::Study(p) => py.detach(|| hdgear::burst::response(&p, &opts)),
        Subject::Model(m) => py.detach(|| hdgear::burst::response_model(&m, &opts)),
    }
    .map_err(err)?;
    to_py(py, &r.bursts)
}
