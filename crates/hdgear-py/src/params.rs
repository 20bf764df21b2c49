//! `hdgear.Params`: the six dimensionless values, checked on construction.

use crate::convert::err;
use hdgear::params::{Param, Params as LibParams};
use pyo3::exceptions::{PyAttributeError, PyRuntimeError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The dimensionless parameters α, γ, ε, μ, δ, ω (validated; see `hdgear.Params`).
#[pyclass(frozen, eq, module = "hdgear._hdgear")]
#[derive(Clone, PartialEq)]
pub(crate) struct Params {
    pub(crate) inner: LibParams,
}

/// `base` with the values named in `values` (keywords of the library's parameter list; a None
/// keeps the base's value), validated.
fn with_values(mut base: LibParams, values: Option<&Bound<'_, PyDict>>) -> PyResult<Params> {
    for (k, v) in values.into_iter().flatten() {
        let name: String = k.extract()?;
        let q: Param = name
            .parse()
            .map_err(|_| PyTypeError::new_err(format!("unexpected keyword argument '{name}'")))?;
        let v: Option<f64> = v.extract().map_err(|e: PyErr| {
            PyTypeError::new_err(format!("argument '{name}': {}", e.value(v.py())))
        })?;
        if let Some(v) = v {
            base = base.with(q, v);
        }
    }
    base.validate().map_err(err)?;
    Ok(Params { inner: base })
}

#[pymethods]
impl Params {
    /// The preset's values with those given by name (`alpha=…`, `gamma=…`, …) replaced.
    #[new]
    #[pyo3(signature = (*, preset="paper", **values))]
    fn new(preset: &str, values: Option<&Bound<'_, PyDict>>) -> PyResult<Params> {
        with_values(LibParams::preset(preset).map_err(err)?, values)
    }

    /// The study's parameter set with γ (default 0.1).
    #[staticmethod]
    #[pyo3(signature = (gamma=None))]
    fn paper(gamma: Option<f64>) -> PyResult<Params> {
        let p = LibParams::preset("paper").map_err(err)?;
        with_values(gamma.map_or(p, |g| p.with(Param::Gamma, g)), None)
    }

    /// A copy with some values replaced (validated).
    #[pyo3(signature = (**values))]
    fn replace(&self, values: Option<&Bound<'_, PyDict>>) -> PyResult<Params> {
        with_values(self.inner, values)
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

    /// `p.alpha`, `p.gamma`, …: every parameter of the library's list by its name.
    fn __getattr__(&self, name: &str) -> PyResult<f64> {
        let q: Param = name
            .parse()
            .map_err(|_| PyAttributeError::new_err(name.to_string()))?;
        Ok(self.inner.value(q))
    }

    /// The six values as a JSON object.
    fn to_json(&self) -> PyResult<String> {
        serde_json::to_string(&self.inner).map_err(|e| PyRuntimeError::new_err(e.to_string()))
    }

    fn __repr__(&self) -> String {
        let values: Vec<String> = Param::ALL
            .iter()
            .map(|&q| format!("{}={:?}", q.name(), self.inner.value(q)))
            .collect();
        format!("Params({})", values.join(", "))
    }
}
