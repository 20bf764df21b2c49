//! `hdgear.fit`: a law of the model's terms fitted to measured data, as `hdgear fit --json`
//! prints the result.

use crate::convert::{err, terms_of, to_py};
use hdgear::fit::{Data, FitLaw, FitOptions, Free};
use pyo3::prelude::*;
use std::collections::BTreeMap;

/// (result dict, data warnings) of the fit of `terms` ({kind: {key: value}}) to torques
/// measured against `x` (speeds or twists, SI), the parameters `free` (`NAME=LO:HI`) freed.
#[pyfunction]
#[pyo3(signature = (kind, x, torque, sd, terms, free, starts, seed, profile, repeat))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn fit<'py>(
    py: Python<'py>,
    kind: &str,
    x: Vec<f64>,
    torque: Vec<f64>,
    sd: Option<Vec<f64>>,
    terms: BTreeMap<String, BTreeMap<String, f64>>,
    free: Vec<String>,
    starts: usize,
    seed: u64,
    profile: bool,
    repeat: usize,
) -> PyResult<(Bound<'py, PyAny>, Vec<String>)> {
    let kind = kind.parse().map_err(err)?;
    let law = FitLaw::new(terms_of(&terms)?).map_err(err)?;
    let free: Vec<Free> = free
        .iter()
        .map(|f| f.parse())
        .collect::<hdgear::Result<_>>()
        .map_err(err)?;
    if x.len() != torque.len() || sd.as_ref().is_some_and(|s| s.len() != x.len()) {
        return Err(pyo3::exceptions::PyValueError::new_err(
            "the data's columns must have one length",
        ));
    }
    let (data, warnings) = Data::new(kind, x, torque, sd).map_err(err)?;
    let options = FitOptions {
        starts,
        seed,
        profile,
        repeat,
    };
    let result = py
        .detach(|| hdgear::fit::fit(&law, &data, &free, &options))
        .map_err(err)?;
    let warnings = warnings
        .iter()
        .chain(&result.warnings)
        .map(|w| w.to_string())
        .collect();
    Ok((to_py(py, &result)?, warnings))
}
