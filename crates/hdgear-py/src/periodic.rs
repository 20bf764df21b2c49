//! Periodic responses: shooting with Floquet multipliers, and continuation.

use crate::convert::{Detection, err, record_columns, to_py};
use crate::params::Params;
use hdgear::burst::BurstOptions;
use hdgear::params::Param;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The periodic orbit of period k·2π/ω by shooting, with its burst verdict, as a dict.
#[pyfunction]
#[pyo3(signature = (params, subharmonic))]
pub(crate) fn periodic<'py>(
    py: Python<'py>,
    params: &Params,
    subharmonic: u32,
) -> PyResult<Bound<'py, PyAny>> {
    use hdgear::periodic::{PeriodicOptions, burst_verdict, shoot};
    let p = params.inner;
    let (orbit, bursts) = py
        .detach(|| {
            let o = shoot(&p, subharmonic, &PeriodicOptions::default())?;
            let b = burst_verdict(&o, &BurstOptions::default())?;
            Ok::<_, hdgear::Error>((o, b))
        })
        .map_err(err)?;
    #[derive(serde::Serialize)]
    struct Doc<'a> {
        #[serde(flatten)]
        orbit: &'a hdgear::periodic::PeriodicOrbit,
        bursts: hdgear::burst::Classification,
        samples: &'a [[f64; 3]],
    }
    let doc = Doc {
        orbit: &orbit,
        bursts,
        samples: &orbit.samples,
    };
    to_py(py, &doc)
}

/// Continuation of the periodic orbit in `name` from the value in `params` to `to` (log scale
/// when `log`), with the doubled branches when `switch`: the rows of `hdgear continue` as a dict
/// of columns. `to` of None and name "omega" with `log`: the frequency response over the default
/// range (then `params`' ω is ignored).
#[pyfunction]
#[pyo3(signature = (params, name, to, log, subharmonic, switch))]
pub(crate) fn continuation<'py>(
    py: Python<'py>,
    params: &Params,
    name: &str,
    to: Option<f64>,
    log: bool,
    subharmonic: u32,
    switch: bool,
) -> PyResult<Bound<'py, PyDict>> {
    use hdgear::periodic::{
        BranchRow, ContinuationOptions, OrbitBranch, Scale, continue_with_doubled,
        default_frequency_range as frequency_range,
    };
    let param: Param = name.parse().map_err(err)?;
    let p = params.inner;
    let opts = ContinuationOptions {
        scale: if log { Scale::Log } else { Scale::Linear },
        ..ContinuationOptions::default()
    };
    let branches: Vec<OrbitBranch<Param>> = py
        .detach(|| {
            let (start, to) = match to {
                Some(to) => (p, to),
                None => {
                    let (lo, hi) = frequency_range(&p);
                    (p.with(param, lo), hi)
                }
            };
            continue_with_doubled(&start, param, subharmonic, to, switch, &opts)
        })
        .map_err(err)?;
    let rows: Vec<BranchRow> = branches
        .iter()
        .enumerate()
        .flat_map(|(i, b)| {
            b.points
                .iter()
                .map(move |q| BranchRow::new(i, b.subharmonic, q))
        })
        .collect();
    let d = PyDict::new(py);
    let f = |g: fn(&BranchRow) -> f64| rows.iter().map(g).collect::<Vec<f64>>();
    let ints = |g: fn(&BranchRow) -> i64| rows.iter().map(g).collect::<Vec<i64>>();
    d.set_item("branch", ints(|r| r.branch as i64).into_pyarray(py))?;
    d.set_item(
        "subharmonic",
        ints(|r| i64::from(r.subharmonic)).into_pyarray(py),
    )?;
    for (col, v) in [
        ("param", f(|r| r.param)),
        ("x0", f(|r| r.x0)),
        ("xdot0", f(|r| r.xdot0)),
        ("x_min", f(|r| r.x_min)),
        ("x_max", f(|r| r.x_max)),
        ("peak_to_peak", f(|r| r.peak_to_peak)),
        ("max_abs_xdot", f(|r| r.max_abs_xdot)),
        ("ln_abs_m1", f(|r| r.ln_abs_m1)),
        ("arg_m1", f(|r| r.arg_m1)),
        ("ln_abs_m2", f(|r| r.ln_abs_m2)),
        ("arg_m2", f(|r| r.arg_m2)),
    ] {
        d.set_item(col, v.into_pyarray(py))?;
    }
    let stable: Vec<bool> = rows.iter().map(|r| r.stable).collect();
    d.set_item("stable", stable)?;
    let special: Vec<&str> = rows.iter().map(|r| r.special).collect();
    d.set_item("special", special)?;
    let flip = f(|r| r.flip_coefficient.unwrap_or(f64::NAN));
    d.set_item("flip_coefficient", flip.into_pyarray(py))?;
    Ok(d)
}

/// Two-parameter curves of folds or period doublings from the special points of a one-parameter
/// branch (`hdgear continue2`): the rows of its `--out` as a dict of columns.
#[pyfunction]
#[pyo3(signature = (params, range1, range2, start, subharmonic, switch))]
pub(crate) fn continuation2<'py>(
    py: Python<'py>,
    params: &Params,
    range1: &str,
    range2: &str,
    start: &str,
    subharmonic: u32,
    switch: bool,
) -> PyResult<Bound<'py, PyDict>> {
    use hdgear::periodic::{
        ContinuationOptions, CurveKind, CurveRow, Range, curves_at_gpds, curves_from_branch,
    };
    let ranges = [
        Range::parse(range1).map_err(err)?,
        Range::parse(range2).map_err(err)?,
    ];
    let (kind, nth) = CurveKind::parse_start(start).map_err(err)?;
    let p = params.inner;
    let opts = ContinuationOptions::default();
    let curves = py
        .detach(|| {
            let mut curves = curves_from_branch(&p, ranges, kind, nth, subharmonic, &opts)?;
            if switch {
                let more = curves_at_gpds(&p, ranges, &curves, &opts)?;
                curves.extend(more);
            }
            Ok::<_, hdgear::Error>(curves)
        })
        .map_err(err)?;
    let rows: Vec<CurveRow> = curves
        .iter()
        .enumerate()
        .flat_map(|(i, c)| CurveRow::of(i, c))
        .collect();
    record_columns(py, &rows)
}

/// The boundaries of a parameter plane as curves (`hdgear boundary`): the rows of its `--out`
/// as a dict of columns.
#[pyfunction]
#[pyo3(signature = (params, range1, range2, kinds, step, detection))]
pub(crate) fn boundary<'py>(
    py: Python<'py>,
    params: &Params,
    range1: &str,
    range2: &str,
    kinds: Vec<String>,
    step: f64,
    detection: Detection,
) -> PyResult<Bound<'py, PyDict>> {
    use hdgear::burst::{BoundaryKind, PlaneOptions, PlaneRow, plane_boundaries};
    use hdgear::periodic::{Box2, Range};
    let ranges = [
        Range::parse(range1).map_err(err)?,
        Range::parse(range2).map_err(err)?,
    ];
    let kinds: Vec<BoundaryKind> = if kinds.is_empty() {
        BoundaryKind::ALL.to_vec()
    } else {
        kinds
            .iter()
            .map(|k| k.parse())
            .collect::<Result<_, _>>()
            .map_err(err)?
    };
    let opts = PlaneOptions::with_step(step);
    let burst = detection.0;
    let p = params.inner;
    let plane = ranges.map(|r| r.param);
    let curves = py
        .detach(|| plane_boundaries(&p, plane, &Box2::of(ranges), &kinds, &opts, &burst))
        .map_err(err)?;
    let rows: Vec<PlaneRow> = curves
        .iter()
        .enumerate()
        .flat_map(|(i, c)| PlaneRow::of(i, c))
        .collect();
    record_columns(py, &rows)
}
