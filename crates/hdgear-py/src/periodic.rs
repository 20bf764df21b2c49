//! Periodic responses: shooting with Floquet multipliers, and continuation.

use crate::convert::{Detection, err, record_columns, to_py};
use crate::model::subject_of;
use hdgear::burst::BurstOptions;
use hdgear::periodic::{Periodic, Range};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The periodic orbit of period k·2π/ω of a `Params` or a `Model` by shooting, with its burst
/// verdict, as a dict.
#[pyfunction]
#[pyo3(signature = (params, subharmonic))]
pub(crate) fn periodic<'py>(
    py: Python<'py>,
    params: &Bound<'py, PyAny>,
    subharmonic: u32,
) -> PyResult<Bound<'py, PyAny>> {
    hdgear::on_subject!(&subject_of(params)?, |s| orbit_doc(py, s, subharmonic))
}

/// The orbit of `s` and its verdict as `hdgear periodic --json` prints them.
fn orbit_doc<'py, S: Periodic>(
    py: Python<'py>,
    s: &S,
    subharmonic: u32,
) -> PyResult<Bound<'py, PyAny>> {
    use hdgear::periodic::{PeriodicOptions, burst_verdict, shoot};
    let (orbit, bursts) = py
        .detach(|| {
            let o = shoot(s, subharmonic, &PeriodicOptions::default())?;
            let b = burst_verdict(&o, &BurstOptions::default())?;
            Ok::<_, hdgear::Error>((o, b))
        })
        .map_err(err)?;
    #[derive(serde::Serialize)]
    struct Doc<'a, S: serde::Serialize> {
        #[serde(flatten)]
        orbit: &'a hdgear::periodic::PeriodicOrbit<S>,
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
    params: &Bound<'py, PyAny>,
    name: &str,
    to: Option<f64>,
    log: bool,
    subharmonic: u32,
    switch: bool,
) -> PyResult<Bound<'py, PyDict>> {
    use hdgear::periodic::{
        BranchRow, ContinuationOptions, OrbitPoint, Oscillator, Scale, continue_with_doubled,
    };
    let opts = ContinuationOptions {
        scale: if log { Scale::Log } else { Scale::Linear },
        ..ContinuationOptions::default()
    };
    // each branch's number, subharmonic and points, whichever parameter type it was followed in
    let branches: Vec<(u32, Vec<OrbitPoint>)> = hdgear::on_subject!(&subject_of(params)?, |p| {
        let param = p.param_named(name).map_err(err)?;
        py.detach(|| {
            let (start, to) = match to {
                Some(to) => (*p, to),
                None => {
                    let (lo, hi) = p.frequency_range();
                    (Oscillator::with(p, param, lo)?, hi)
                }
            };
            continue_with_doubled(&start, param, subharmonic, to, switch, &opts)
        })
        .map_err(err)?
        .into_iter()
        .map(|b| (b.subharmonic, b.points))
        .collect()
    });
    let rows: Vec<BranchRow> = branches
        .iter()
        .enumerate()
        .flat_map(|(i, (k, points))| points.iter().map(move |q| BranchRow::new(i, *k, q)))
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

/// Two-parameter curves of folds or period doublings of a `Params` or a `Model` from the special
/// points of a one-parameter branch (`hdgear continue2`): the rows of its `--out` as a dict of
/// columns.
#[pyfunction]
#[pyo3(signature = (params, range1, range2, start, subharmonic, switch))]
pub(crate) fn continuation2<'py>(
    py: Python<'py>,
    params: &Bound<'py, PyAny>,
    range1: &str,
    range2: &str,
    start: &str,
    subharmonic: u32,
    switch: bool,
) -> PyResult<Bound<'py, PyDict>> {
    use hdgear::periodic::{
        ContinuationOptions, CurveKind, CurveRow, curves_at_gpds, curves_from_branch,
    };
    let (kind, nth) = CurveKind::parse_start(start).map_err(err)?;
    let opts = ContinuationOptions::default();
    let rows: Vec<CurveRow> = hdgear::on_subject!(&subject_of(params)?, |p| {
        let ranges = ranges_of(p, [range1, range2])?;
        let curves = py
            .detach(|| {
                let mut curves = curves_from_branch(p, ranges, kind, nth, subharmonic, &opts)?;
                if switch {
                    let more = curves_at_gpds(p, ranges, &curves, &opts)?;
                    curves.extend(more);
                }
                Ok::<_, hdgear::Error>(curves)
            })
            .map_err(err)?;
        curves
            .iter()
            .enumerate()
            .flat_map(|(i, c)| CurveRow::of(i, c))
            .collect()
    });
    record_columns(py, &rows)
}

/// The two ranges `NAME=FROM:TO[:log]`, each naming a parameter of `p`.
fn ranges_of<S: Periodic>(p: &S, texts: [&str; 2]) -> PyResult<[Range<S::Param>; 2]> {
    Ok([
        Range::parse_for(texts[0], p).map_err(err)?,
        Range::parse_for(texts[1], p).map_err(err)?,
    ])
}

/// The boundaries of a parameter plane of a `Params` (every kind) or a `Model` (the kinds it
/// defines) as curves (`hdgear boundary`): the rows of its `--out` as a dict of columns.
#[pyfunction]
#[pyo3(signature = (params, range1, range2, kinds, step, detection))]
pub(crate) fn boundary<'py>(
    py: Python<'py>,
    params: &Bound<'py, PyAny>,
    range1: &str,
    range2: &str,
    kinds: Vec<String>,
    step: f64,
    detection: Detection,
) -> PyResult<Bound<'py, PyDict>> {
    use hdgear::burst::{BoundaryKind, PlaneOptions, PlaneRow, PlaneSystem, plane_boundaries};
    use hdgear::periodic::Box2;
    let kinds: Vec<BoundaryKind> = kinds
        .iter()
        .map(|k| k.parse())
        .collect::<Result<_, _>>()
        .map_err(err)?;
    let opts = PlaneOptions::with_step(step);
    let burst = detection.0;
    let rows: Vec<PlaneRow> = hdgear::on_subject!(&subject_of(params)?, |p| {
        let ranges = ranges_of(p, [range1, range2])?;
        // no kinds named: every kind this system defines
        let kinds: Vec<BoundaryKind> = if kinds.is_empty() {
            BoundaryKind::ALL
                .into_iter()
                .filter(|&k| p.defines(k).is_ok())
                .collect()
        } else {
            kinds.clone()
        };
        let plane = ranges.map(|r| r.param);
        let curves = py
            .detach(|| plane_boundaries(p, plane, &Box2::of(ranges), &kinds, &opts, &burst))
            .map_err(err)?;
        curves
            .iter()
            .enumerate()
            .flat_map(|(i, c)| PlaneRow::of(i, c))
            .collect()
    });
    record_columns(py, &rows)
}
