//! The fast subsystem (equilibria, the equilibrium curve) and the point analysis.

use crate::convert::{Detection, err, invalid, terms_of, to_py};
use crate::model::subject_of;
use crate::params::Params;
use hdgear::model::Subject;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::collections::BTreeMap;

/// The equilibria at `a`, as a dict.
#[pyfunction]
pub(crate) fn equilibria<'py>(
    py: Python<'py>,
    params: &Params,
    a: f64,
) -> PyResult<Bound<'py, PyAny>> {
    if !a.is_finite() {
        return Err(invalid("a", format!("{a:?}"), "must be finite"));
    }
    to_py(py, &hdgear::fast::equilibria(&params.inner, a))
}

/// The equilibrium curve of a `Params` (the cubic's) or a `Model` (its static torque's at its
/// own damping at rest, [`hdgear::model::AnyCurve`]) as a dict of arrays.
#[pyfunction]
pub(crate) fn curve<'py>(
    py: Python<'py>,
    params: &Bound<'py, PyAny>,
    points: usize,
    a0: f64,
    a1: f64,
) -> PyResult<Bound<'py, PyDict>> {
    use hdgear::fast::curve;
    use hdgear::model::AnyCurve;
    let subject = subject_of(params)?;
    let c = py
        .detach(|| match subject {
            Subject::Study(p) => curve(&p, (a0, a1), points),
            Subject::Model(m) => match AnyCurve::of(&m)? {
                AnyCurve::Torque(c) => curve(&c, (a0, a1), points),
                AnyCurve::Scheduled(c) => curve(&c, (a0, a1), points),
            },
        })
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

/// The quasi-static branches of a `Params` or a `Model` with extra `terms` ({kind: {key:
/// value}}, as a scenario file's tables), as `hdgear model --branches --json` prints them.
#[pyfunction]
#[pyo3(signature = (params, terms))]
pub(crate) fn branches<'py>(
    py: Python<'py>,
    params: &Bound<'py, PyAny>,
    terms: BTreeMap<String, BTreeMap<String, f64>>,
) -> PyResult<Bound<'py, PyAny>> {
    let mut model = subject_of(params)?.model();
    for term in terms_of(&terms)? {
        model = model.with_term(term).map_err(err)?;
    }
    let b = py.detach(|| model.branches()).map_err(err)?;
    to_py(py, &b)
}

/// What `hdgear analyze --json` prints for a `Params` or a `Model`, as a dict.
#[pyfunction]
#[pyo3(signature = (params, response, simulated_boundaries, detection))]
pub(crate) fn analyze<'py>(
    py: Python<'py>,
    params: &Bound<'py, PyAny>,
    response: bool,
    simulated_boundaries: bool,
    detection: Detection,
) -> PyResult<Bound<'py, PyAny>> {
    let opts = detection.0;
    let p = match subject_of(params)? {
        Subject::Study(p) => p,
        Subject::Model(m) => {
            if simulated_boundaries {
                return Err(invalid(
                    "simulated_boundaries",
                    "True",
                    "the switch of the verdict is searched in the study's gamma and omega, not \
                     for a model with terms",
                ));
            }
            let range = hdgear::fast::A_RANGE;
            // the study set's remarks, as the CLI gives them for a scenario's [params]
            let remarks: Vec<String> = m
                .study_warnings()
                .unwrap_or_default()
                .iter()
                .map(ToString::to_string)
                .collect();
            let doc = py
                .detach(|| {
                    hdgear::study::analyze_model(&m, range, response.then_some(&opts), remarks)
                })
                .map_err(err)?;
            return to_py(py, &doc);
        }
    };
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
    to_py(py, &doc)
}
