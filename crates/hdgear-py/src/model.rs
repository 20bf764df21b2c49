//! `hdgear.Model`: the assembled model (the study's with a parameter set, and the terms of a
//! scenario file's tables), accepted wherever a parameter set is; and the one conversion every
//! function makes of either ([`subject_of`]).

use crate::convert::{err, terms_of, to_py};
use crate::params::Params;
use hdgear::model::{Model as LibModel, Subject};
use hdgear::params::{ParamOverrides, Params as LibParams};
use hdgear::scenario::Scenario;
use pyo3::exceptions::{PyKeyError, PyTypeError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// A model assembled from terms: the study's with a parameter set (`params`, default the
/// study's), plus one term per table of `terms` ({kind: {key: value}}, as a scenario file's
/// tables: friction, hysteresis, kinematic error, control laws), or a scenario file's
/// (`Model.from_toml(path)`). Accepted wherever a `Params` is; its parameters go by name, bare
/// or as `TERM.NAME` (`m["friction.fc"]`, `m.replace({"friction.fc": 0.2}, delta=12)`).
///
///     >>> m = hdgear.Model(hdgear.Params(gamma=30), {"friction": {"fc": 0.1, "vs": 0.05}})
///     >>> m["fc"], m["friction.vs"]
///     (0.1, 0.05)
#[pyclass(frozen, eq, module = "hdgear._hdgear")]
#[derive(Clone, PartialEq)]
pub(crate) struct Model {
    pub(crate) inner: LibModel,
}

/// What a function runs on, from a `Params` (the study's model) or a `Model`: the study's set
/// where the model is the study's own (the same numbers as from its `Params`), else the model.
pub(crate) fn subject_of(obj: &Bound<'_, PyAny>) -> PyResult<Subject> {
    if let Ok(p) = obj.cast::<Params>() {
        return Ok(Subject::Study(p.get().inner));
    }
    if let Ok(m) = obj.cast::<Model>() {
        return Ok(m.get().inner.subject());
    }
    Err(PyTypeError::new_err(format!(
        "expected hdgear.Params or hdgear.Model, got {}",
        obj.get_type().name()?
    )))
}

/// The study's set a model carries (its cubic stiffness and its forcing), which a summary
/// records as the CLI's does.
pub(crate) fn study_set(m: &LibModel) -> PyResult<LibParams> {
    m.study_set().ok_or_else(|| {
        PyTypeError::new_err("this model has no study stiffness: no parameter set to report")
    })
}

#[pymethods]
impl Model {
    /// The study's model with `params` (default: the study's), plus one term per table of
    /// `terms` ({kind: {key: value}}, as a scenario file's tables).
    #[new]
    #[pyo3(signature = (params=None, terms=None))]
    fn new(
        params: Option<&Params>,
        terms: Option<BTreeMap<String, BTreeMap<String, f64>>>,
    ) -> PyResult<Model> {
        let p = match params {
            Some(p) => p.inner,
            None => LibParams::preset("paper").map_err(err)?,
        };
        let mut m = LibModel::study(&p);
        for term in terms_of(&terms.unwrap_or_default())? {
            m = m.with_term(term).map_err(err)?;
        }
        Ok(Model { inner: m })
    }

    /// The model of a scenario file, as `--config FILE` reads it: its `[params]` over the
    /// study's set, and a term per term table.
    #[staticmethod]
    fn from_toml(path: PathBuf) -> PyResult<Model> {
        let s = Scenario::load(&path).map_err(err)?;
        let (p, _) =
            hdgear::params::resolve("paper", s.params.as_ref(), &ParamOverrides::default())
                .map_err(err)?;
        Ok(Model {
            inner: s.model(&p, &path).map_err(err)?,
        })
    }

    /// A copy with the parameters named in `values` ({"coulomb.fs": 0.6, "delta": 30}) and in
    /// the keywords changed at once, each checked against its domain and the terms' rules.
    #[pyo3(signature = (values=None, **keywords))]
    fn replace(
        &self,
        values: Option<&Bound<'_, PyDict>>,
        keywords: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Model> {
        let mut changes = Vec::new();
        for (k, v) in values.into_iter().chain(keywords).flatten() {
            let name: String = k.extract()?;
            let q = self.inner.param(&name).map_err(err)?;
            changes.push((q, v.extract::<f64>()?));
        }
        Ok(Model {
            inner: self.inner.with_all(&changes).map_err(err)?,
        })
    }

    /// `m["coulomb.fs"]`, `m["delta"]`: a parameter's value by its name.
    fn __getitem__(&self, name: &str) -> PyResult<f64> {
        let q = self
            .inner
            .param(name)
            .map_err(|e| PyKeyError::new_err(e.to_string()))?;
        Ok(self.inner.get(q))
    }

    /// Every parameter as {"term.name": value}, the forcing's first.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for v in self.inner.param_values() {
            d.set_item(format!("{}.{}", v.term, v.info.name), v.value)?;
        }
        Ok(d)
    }

    /// What `hdgear model --json` prints: the equation, states, terms, every parameter with its
    /// definition and value, and the fast subsystem's facts.
    fn describe<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &self.inner.describe())
    }

    /// The equation as text.
    #[getter]
    fn equation(&self) -> String {
        self.inner.equation()
    }

    fn __repr__(&self) -> String {
        format!("Model({})", self.inner.equation())
    }
}
