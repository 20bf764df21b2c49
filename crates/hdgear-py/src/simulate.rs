//! Simulations of the study's model or an assembled one, returned as numpy arrays.

use crate::convert::{check_samples, err, to_py, tol};
use crate::model::{study_set, subject_of};
use crate::params::Params;
use hdgear::model::Subject;
use hdgear::simulate::{SimOptions, Start};
use numpy::{IntoPyArray, PyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

type Arrays<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyDict>,
    Bound<'py, PyAny>,
);

/// Samples t, a = sin ωt and each state component (x, x', then the terms' own) of one
/// simulation, in vectors sized for them.
fn run_simulation(
    s: &Subject,
    opts: &SimOptions,
) -> hdgear::Result<(Vec<Vec<f64>>, hdgear::simulate::SimSummary)> {
    let m = s.model();
    let omega = m.forcing()[2];
    let mut cols: Vec<Vec<f64>> = vec![Vec::new(); 2 + m.dim()];
    let n = (opts.t_end / opts.dt).ceil() as usize + 2;
    cols.iter_mut().for_each(|c| c.reserve(n.min(1 << 26)));
    let mut each = |t: f64, y: &[f64]| {
        cols[0].push(t);
        cols[1].push((omega * t).sin());
        for (c, &v) in cols[2..].iter_mut().zip(y) {
            c.push(v);
        }
    };
    let summary = match s {
        Subject::Study(p) => hdgear::simulate::simulate(p, opts, |t, y| each(t, y))?,
        Subject::Model(m) => hdgear::simulate::simulate_model(m, opts, &mut each)?,
    };
    Ok((cols, summary))
}

/// One simulation of a `Params` or a `Model`: (t, a, x, xdot, {state: values} of the terms'
/// own states, summary dict).
#[pyfunction]
#[pyo3(signature = (params, t_end, dt, x0, v0, from_rest, rtol, atol, method))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn simulate<'py>(
    py: Python<'py>,
    params: &Bound<'py, PyAny>,
    t_end: f64,
    dt: f64,
    x0: Option<f64>,
    v0: Option<f64>,
    from_rest: bool,
    rtol: f64,
    atol: f64,
    method: &str,
) -> PyResult<Arrays<'py>> {
    let subject = subject_of(params)?;
    let m = subject.model();
    let start = match (x0, v0, from_rest) {
        (None, None, false) => Start::Equilibrium,
        (None, None, true) => Start::Rest,
        (x, v, false) => Start::Given {
            x0: match x {
                Some(x) => x,
                None => subject.stable_equilibrium(0.0).map_err(err)?,
            },
            v0: v.unwrap_or(m.rest_rate()),
        },
        _ => return Err(PyValueError::new_err("give x0/v0 or from_rest, not both")),
    };
    let opts = SimOptions {
        t_end,
        dt,
        start,
        tol: tol(rtol, atol, method)?,
    };
    // a run beyond the step budget is refused as such, before its record is sized
    hdgear::integrate::check_budget(t_end, &opts.tol).map_err(err)?;
    check_samples(t_end, dt)?;
    let (cols, summary) = py.detach(|| run_simulation(&subject, &opts)).map_err(err)?;
    let report = match subject {
        Subject::Study(p) => summary.report(&p, &[]),
        Subject::Model(m) => hdgear::simulate::SummaryReport {
            model: Some(m.describe()),
            ..summary.report(&study_set(&m)?, &[])
        },
    };
    let mut cols = cols.into_iter();
    let mut next = || cols.next().unwrap_or_default().into_pyarray(py);
    let (t, a, x, v) = (next(), next(), next(), next());
    let states = PyDict::new(py);
    for name in m.states().into_iter().skip(2) {
        states.set_item(name, next())?;
    }
    Ok((t, a, x, v, states, to_py(py, &report)?))
}

/// The same simulation `n` times in Rust, samples collected by the same function as
/// `simulate` and dropped: seconds per run (the reference of the Python overhead benchmark).
#[pyfunction]
pub(crate) fn time_simulate_in_rust(
    py: Python<'_>,
    params: &Params,
    t_end: f64,
    dt: f64,
    n: usize,
) -> PyResult<f64> {
    let s = Subject::Study(params.inner);
    let opts = SimOptions {
        t_end,
        dt,
        ..SimOptions::default()
    };
    check_samples(t_end, dt)?;
    py.detach(|| {
        let t0 = std::time::Instant::now();
        for _ in 0..n {
            std::hint::black_box(run_simulation(&s, &opts)?);
        }
        Ok(t0.elapsed().as_secs_f64() / n.max(1) as f64)
    })
    .map_err(err)
}
