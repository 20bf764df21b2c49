//! What every entry point shares: the library's errors as Python exceptions, results as Python
//! objects, options checked once, the limits that keep a call within memory, and Ctrl-C during
//! long computations.

use hdgear::burst::BurstOptions;
use hdgear::integrate::{Method, Options};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// The most samples a simulation may return to Python: four arrays of 10⁸ values are 3.2 GB; a
/// longer record belongs in a file (`hdgear simulate --out`), which streams.
pub(crate) const MAX_SAMPLES_IN_MEMORY: f64 = 1e8;

/// The library's error as a Python exception: a failed integration is a `RuntimeError`, every
/// other error (a value or option out of its domain) a `ValueError`, with the CLI's message.
pub(crate) fn err(e: hdgear::Error) -> PyErr {
    match e {
        hdgear::Error::Solver(_) => PyRuntimeError::new_err(e.to_string()),
        other => PyValueError::new_err(other.to_string()),
    }
}

/// Terms from their tables ({kind: {key: value}}, as a scenario file's), the keys left out at
/// their defaults.
pub(crate) fn terms_of(
    tables: &std::collections::BTreeMap<String, std::collections::BTreeMap<String, f64>>,
) -> PyResult<Vec<hdgear::model::terms::AnyTerm>> {
    tables
        .iter()
        .map(|(name, table)| {
            let named = table.iter().map(|(k, &v)| (k.as_str(), v));
            let (kind, values) = hdgear::scenario::term_values(name, named)
                .map_err(|e| PyValueError::new_err(format!("invalid terms: {e}")))?;
            hdgear::model::terms::AnyTerm::new(kind, &values).map_err(err)
        })
        .collect()
}

/// A `ValueError` naming the argument and the value given.
pub(crate) fn invalid(name: &str, value: impl std::fmt::Display, reason: &str) -> PyErr {
    PyValueError::new_err(format!("invalid {name} = {value}: {reason}"))
}

/// A serialisable result as Python objects (dicts, lists, floats, ints, strings, None), with the
/// same mapping as the JSON the CLI prints (a NaN is None there and here).
pub(crate) fn to_py<'py, T: serde::Serialize>(
    py: Python<'py>,
    v: &T,
) -> PyResult<Bound<'py, PyAny>> {
    let value = serde_json::to_value(v).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    value_to_py(py, &value)
}

/// Records as a dict of their columns ([`hdgear::output::Record::COLUMNS`], the CLI's CSV
/// columns): a numpy array of floats for a numeric column (NaN for JSON's null), a list of
/// strings otherwise.
pub(crate) fn record_columns<'py, T: hdgear::output::Record>(
    py: Python<'py>,
    rows: &[T],
) -> PyResult<Bound<'py, PyDict>> {
    use numpy::IntoPyArray;
    let values: Vec<serde_json::Value> = rows
        .iter()
        .map(serde_json::to_value)
        .collect::<Result<_, _>>()
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    let d = PyDict::new(py);
    for &name in T::COLUMNS {
        let column: Vec<&serde_json::Value> = values.iter().map(|v| &v[name]).collect();
        if column.iter().all(|v| v.is_number() || v.is_null()) {
            let f: Vec<f64> = column
                .iter()
                .map(|v| v.as_f64().unwrap_or(f64::NAN))
                .collect();
            d.set_item(name, f.into_pyarray(py))?;
        } else {
            let s: Vec<String> = column
                .iter()
                .map(|v| v.as_str().map_or_else(|| v.to_string(), str::to_string))
                .collect();
            d.set_item(name, s)?;
        }
    }
    Ok(d)
}

fn value_to_py<'py>(py: Python<'py>, v: &serde_json::Value) -> PyResult<Bound<'py, PyAny>> {
    use serde_json::Value;
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => b.into_pyobject(py)?.to_owned().into_any(),
        Value::Number(n) => match (n.as_i64(), n.as_u64()) {
            (Some(i), _) => i.into_pyobject(py)?.into_any(),
            (None, Some(u)) => u.into_pyobject(py)?.into_any(),
            _ => n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any(),
        },
        Value::String(s) => s.into_pyobject(py)?.into_any(),
        Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(value_to_py(py, item)?)?;
            }
            list.into_any()
        }
        Value::Object(map) => {
            let dict = PyDict::new(py);
            for (k, item) in map {
                dict.set_item(k, value_to_py(py, item)?)?;
            }
            dict.into_any()
        }
    })
}

/// Detection options and tolerances, validated: the native functions take them as one argument,
/// the tuple `(discard, window_periods, rtol, atol, method)` the Python wrapper's `_detection`
/// builds from its keywords.
pub(crate) struct Detection(pub(crate) BurstOptions);

impl<'a, 'py> FromPyObject<'a, 'py> for Detection {
    type Error = PyErr;

    fn extract(obj: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        let (discard, window_periods, rtol, atol, method): (f64, i64, f64, f64, String) =
            obj.extract()?;
        let periods = u32::try_from(window_periods).map_err(|_| {
            PyValueError::new_err(format!(
                "window_periods = {window_periods}: must be a whole number from 1 to {}",
                u32::MAX
            ))
        })?;
        let o = BurstOptions {
            discard_periods: discard,
            periods,
            tol: tol(rtol, atol, &method)?,
            ..BurstOptions::default()
        };
        o.validate().map_err(err)?;
        Ok(Detection(o))
    }
}

/// Integration tolerances and method from keyword values, validated.
pub(crate) fn tol(rtol: f64, atol: f64, method: &str) -> PyResult<Options> {
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

/// Refuses a record of more than [`MAX_SAMPLES_IN_MEMORY`] samples before any work.
pub(crate) fn check_samples(t_end: f64, dt: f64) -> PyResult<()> {
    // a sample spacing that is no spacing is refused as such, before its count is judged
    if !(dt.is_finite() && dt > 0.0) {
        return Err(invalid("dt", dt, "must be finite and > 0"));
    }
    let n = t_end / dt;
    if n > MAX_SAMPLES_IN_MEMORY {
        return Err(invalid(
            "dt",
            dt,
            "more than 1e8 samples to hold in memory; write them to a file with `hdgear simulate --out`",
        ));
    }
    Ok(())
}

/// Runs `work` on its own thread with the GIL released, checking for Python signals every 50
/// ms: on Ctrl-C (or any signal handler that raises) the stop flag given to `work` is set, its
/// thread is waited for, and the exception is raised. `work` checks the flag between pieces of
/// work and may return early once it is set (its result is then dropped).
pub(crate) fn interruptible<R: Send>(
    py: Python<'_>,
    work: impl FnOnce(&AtomicBool) -> R + Send,
) -> PyResult<R> {
    let stop = AtomicBool::new(false);
    std::thread::scope(|s| {
        let handle = s.spawn(|| work(&stop));
        loop {
            py.detach(|| {
                for _ in 0..10 {
                    if handle.is_finished() {
                        break;
                    }
                    std::thread::sleep(Duration::from_millis(5));
                }
            });
            if handle.is_finished() {
                return Ok(handle
                    .join()
                    .unwrap_or_else(|panic| std::panic::resume_unwind(panic)));
            }
            if let Err(e) = py.check_signals() {
                stop.store(true, Ordering::Relaxed);
                // the result of the abandoned work is dropped; a panic in it is not hidden
                if let Err(panic) = handle.join() {
                    std::panic::resume_unwind(panic);
                }
                return Err(e);
            }
        }
    })
}
