//! Burst control: the laws tuned or assessed side by side ([`hdgear::control::compare`]).

use crate::convert::{Detection, err, to_py};
use crate::model::subject_of;
use pyo3::prelude::*;

/// What `hdgear control --json` prints for a `Params` or a `Model` (its laws added to the
/// model's terms), as a dict.
#[pyfunction]
#[pyo3(signature = (params, laws, gain, ww, wd, taud, rel_tol, spread, detection))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn control<'py>(
    py: Python<'py>,
    params: &Bound<'py, PyAny>,
    laws: Vec<String>,
    gain: Option<f64>,
    ww: Option<f64>,
    wd: Option<f64>,
    taud: Option<f64>,
    rel_tol: f64,
    spread: Option<f64>,
    detection: Detection,
) -> PyResult<Bound<'py, PyAny>> {
    let opts = detection.0;
    let laws: Vec<&str> = laws.iter().map(String::as_str).collect();
    let c = hdgear::control::ControlOptions {
        gain,
        ww,
        wd,
        taud,
        rel_tol,
        spread,
    };
    hdgear::on_subject!(&subject_of(params)?, |p| {
        let doc = py
            .detach(|| hdgear::control::compare(p, &laws, &c, &opts))
            .map_err(err)?;
        to_py(py, &doc)
    })
}
