//! `hdgear.Params`: the six dimensionless values, checked on construction.

use crate::convert::err;
use hdgear::params::{Param, ParamOverrides, Params as LibParams};
use pyo3::exceptions::{PyAttributeError, PyRuntimeError};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The dimensionless parameters α, γ, ε, μ, δ, ω (validated; see `hdgear.Params`).
#[pyclass(frozen, eq, module = "hdgear._hdgear")]
#[derive(Clone, PartialEq)]
pub(crate) struct Params {
    pub(crate) inner: LibParams,
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
