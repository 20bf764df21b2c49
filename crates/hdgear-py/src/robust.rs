//! `hdgear.robust`: the design check under manufacturing spread, its summary as `hdgear robust
//! --json` prints it and its samples as the columns of `hdgear robust --out`.

use crate::convert::{Detection, err, interruptible, record_columns, to_py};
use crate::drive::Drive;
use crate::model::subject_of;
use hdgear::model::Subject;
use hdgear::robust::{AnalysisOptions, McOptions, Nominal, SampleRow, Space, analyse};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::atomic::Ordering;

/// (summary dict, sample columns) of the analysis of `params` (a `Params` or a `Model`, whose
/// term parameters spread by name) or `drive` under `tolerances` (`NAME=SPEC` strings; a drive
/// without any takes its default bands).
#[pyfunction]
#[pyo3(signature = (params, drive, tolerances, samples, sampler, seed, level, width, sobol, worst, importance, load_curve, detection))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn robust<'py>(
    py: Python<'py>,
    params: Option<&Bound<'py, PyAny>>,
    drive: Option<&Drive>,
    tolerances: Vec<String>,
    samples: u64,
    sampler: &str,
    seed: u64,
    level: f64,
    width: f64,
    sobol: Option<usize>,
    worst: bool,
    importance: Option<u64>,
    load_curve: bool,
    detection: Detection,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyDict>)> {
    let opts = detection.0;
    let nominal = match (params, drive) {
        (_, Some(d)) => Nominal::Drive(d.inner),
        (Some(p), None) => match subject_of(p)? {
            Subject::Study(p) => Nominal::Study(p),
            Subject::Model(m) => Nominal::Model(m),
        },
        (None, None) => Nominal::Study(hdgear::Params::default()),
    };
    let tolerances = match (tolerances.is_empty(), nominal) {
        (true, Nominal::Drive(d)) => Space::drive_defaults(&d),
        (true, Nominal::Study(_) | Nominal::Model(_)) => {
            return Err(PyValueError::new_err(
                "a parameter set needs its spreads: tolerances={'gamma': '±10%'}; a drive has \
                 default bands",
            ));
        }
        (false, _) => tolerances
            .iter()
            .map(|t| Space::parse_tolerance(&nominal, t))
            .collect::<hdgear::Result<_>>()
            .map_err(err)?,
    };
    let space = Space::new(nominal, tolerances).map_err(err)?;
    let a = AnalysisOptions {
        mc: McOptions {
            samples,
            sampler: sampler.parse().map_err(err)?,
            seed,
            level,
            width,
            ..McOptions::default()
        },
        worst,
        sobol,
        importance: importance.map(|n| 0..n),
        load_curve: load_curve.then_some(samples),
        shard: None,
    };
    // Ctrl-C stops the run between blocks of samples
    let (analysis, rows) = interruptible(py, |stop| {
        let mut rows: Vec<SampleRow> = Vec::new();
        let analysis = analyse(&space, &opts, &a, |block| {
            if stop.load(Ordering::Relaxed) {
                return Err(hdgear::Error::InvalidInput {
                    what: "run",
                    text: "interrupted".into(),
                    reason: "Ctrl-C".into(),
                });
            }
            rows.extend(block.iter().map(SampleRow::from));
            Ok(())
        });
        analysis.map(|an| (an, rows))
    })?
    .map_err(err)?;
    Ok((to_py(py, &analysis)?, record_columns(py, &rows)?))
}
