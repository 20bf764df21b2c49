//! Figures of the periodic response: frequency response, orbit diagram, Lyapunov map, and the
//! drive's frequency response in SI units.

use super::maps::cell_edges;
use crate::error::Result;
use crate::output::plot::{Figure, Map, Panel, Series, Style};
use crate::params::{Param, Params};
use crate::study::Study;
use crate::sweep::Axis;

/// Splits a branch into runs of equal stability, as (stable, points (λ, y)) with the boundary
/// point in both neighbours so the curve stays connected.
fn stability_runs<P>(
    b: &crate::periodic::OrbitBranch<P>,
    xy: &impl Fn(usize, &crate::periodic::OrbitPoint) -> (f64, f64),
) -> Vec<(bool, Vec<(f64, f64)>)> {
    let mut runs: Vec<(bool, Vec<(f64, f64)>)> = Vec::new();
    for (i, q) in b.points.iter().enumerate() {
        let pt = xy(i, q);
        match runs.last_mut() {
            Some((s, pts)) if *s == q.stable || q.special.is_some() => pts.push(pt),
            Some((_, pts)) => {
                let last = *pts.last().expect("runs are never empty");
                runs.push((q.stable, vec![last, pt]));
            }
            None => runs.push((q.stable, vec![pt])),
        }
    }
    runs
}

/// One panel of a frequency-response figure: the points `xy(i, point i)` of the branch, with
/// the axis labels.
fn response_panel<P>(
    b: &crate::periodic::OrbitBranch<P>,
    (title, x_label): (&str, &str),
    xy: impl Fn(usize, &crate::periodic::OrbitPoint) -> (f64, f64),
) -> Panel {
    use crate::periodic::Special;
    let mut series = Vec::new();
    let (mut stable_named, mut unstable_named) = (false, false);
    for (stable, points) in stability_runs(b, &xy) {
        let named = if stable {
            &mut stable_named
        } else {
            &mut unstable_named
        };
        let label = match (*named, stable) {
            (true, _) => String::new(),
            (false, true) => "stable".into(),
            (false, false) => "unstable".into(),
        };
        *named = true;
        series.push(Series {
            label,
            points,
            color: usize::from(!stable),
            style: if stable { Style::Line } else { Style::Thin },
        });
    }
    let markers = b
        .points
        .iter()
        .enumerate()
        .filter(|(_, q)| q.special.is_some())
        .map(|(i, q)| {
            let label = match q.special {
                Some(Special::Fold) => "fold",
                Some(Special::PeriodDoubling) => "period doubling",
                _ => "branch point",
            };
            let (x, y) = xy(i, q);
            (x, y, label.to_string())
        })
        .collect();
    Panel {
        title: title.into(),
        x_label: x_label.into(),
        y_label: title.into(),
        x_log: true,
        series,
        markers,
        ..Panel::default()
    }
}

/// The frequency-response curve: peak-to-peak x and max |x'| against ω (log), stable branches
/// thick, unstable thin, folds and period doublings marked.
pub fn frequency_response_figure<S: crate::periodic::Periodic>(
    p: &S,
    b: &crate::periodic::OrbitBranch<S::Param>,
) -> Figure {
    use crate::periodic::Special;
    let folds: Vec<String> = b
        .specials()
        .filter(|q| q.special == Some(Special::Fold))
        .map(|q| format!("{:.4}", q.param))
        .collect();
    let pds = b
        .specials()
        .filter(|q| q.special == Some(Special::PeriodDoubling))
        .count();
    Figure {
        name: "frequency-response".into(),
        caption: format!(
            "Frequency response of the periodic response (period 2π/ω) at {}, by \
             pseudo-arclength continuation in ln ω with Floquet multipliers from the variational \
             equations. Thick: stable; thin: unstable. {} {}",
            p.caption(),
            if folds.is_empty() {
                "No fold: the response is single-valued, a slow sweep of ω does not jump."
                    .to_string()
            } else {
                format!(
                    "Folds at ω = {}: the hardening stiffness bends the resonance peak to the \
                     right, and a slow sweep of ω jumps at the folds (up at the upper fold, down \
                     at the lower), with hysteresis between them.",
                    folds.join(", ")
                )
            },
            if pds > 0 {
                format!(
                    "{pds} period doubling(s): between them the period-1 response is unstable and \
                     the response has twice the forcing period."
                )
            } else {
                String::new()
            }
        ),
        size: (1000, 800),
        panels: vec![
            response_panel(b, ("peak-to-peak x", "ω"), |_, q| {
                (q.param, q.amplitude.peak_to_peak)
            }),
            response_panel(b, ("max |x'|", "ω"), |_, q| {
                (q.param, q.amplitude.max_abs_xdot)
            }),
        ],
        map: None,
    }
}

/// The stroboscopic orbit diagram: x at phase 0 of every recorded period against the parameter,
/// up-sweep and down-sweep in two colours (where they differ, the response is hysteretic).
pub fn orbit_diagram_figure<S: crate::periodic::Periodic>(
    p: &S,
    param: S::Param,
    points: &[crate::periodic::DiagramPoint],
) -> Figure {
    use crate::periodic::SweepDirection;
    let series = [SweepDirection::Up, SweepDirection::Down]
        .into_iter()
        .enumerate()
        .map(|(i, s)| Series {
            label: format!("sweep {}", s.name()),
            points: points
                .iter()
                .filter(|q| q.sweep == s)
                .flat_map(|q| q.section.iter().map(move |y| (q.param, y[0])))
                .collect(),
            color: i,
            style: Style::Points,
        })
        .collect();
    let positive = points.iter().all(|q| q.param > 0.0);
    let (lo, hi) = points.iter().fold((f64::INFINITY, 0.0f64), |(l, h), q| {
        (l.min(q.param), h.max(q.param))
    });
    let lyap: Vec<(f64, f64)> = points
        .iter()
        .filter(|q| q.sweep == SweepDirection::Up)
        .filter_map(|q| q.lyapunov.map(|l| (q.param, l)))
        .collect();
    let x_log = positive && hi > 10.0 * lo;
    let mut panels = vec![Panel {
        title: format!("stroboscopic section against {param}"),
        x_label: param.to_string(),
        y_label: "x at phase 0".into(),
        x_log,
        series,
        ..Panel::default()
    }];
    if !lyap.is_empty() {
        panels.push(Panel {
            title: "largest Lyapunov exponent (up-sweep)".into(),
            x_label: param.to_string(),
            y_label: "λ_max".into(),
            x_log,
            series: vec![Series {
                label: String::new(),
                points: lyap,
                color: 2,
                style: Style::Line,
            }],
            ..Panel::default()
        });
    }
    Figure {
        name: "orbit-diagram".into(),
        caption: format!(
            "Orbit diagram against {param} (the other parameters: {}, ω = {}): x at phase 0 of \
             each recorded forcing period after the transient, \
             each value started from the previous value's state. One dot per value: a period-1 \
             response; two: period 2 (after a period doubling); a cloud: no periodic response \
             within the record. Where the up- and down-sweeps differ, two stable responses \
             coexist and the sweep direction decides (hysteresis between folds).",
            p.caption(),
            p.omega()
        ),
        size: (1000, if panels.len() > 1 { 800 } else { 600 }),
        panels,
        map: None,
    }
}

/// Bins of the Lyapunov map, as (upper bound, name), the last unbounded. −1/2 is the exponent of
/// every orbit whose multipliers are a complex pair (|m| = e^{−T/2}, from the fast Jacobian's trace −1), the
/// most strongly attracting a response of this damping can be; near 0 a multiplier is near the
/// unit circle (a fold or a period doubling close by); above 0, sensitive dependence.
pub const LYAPUNOV_BINS: [(f64, &str); 5] = [
    (-0.45, "λ ≈ −1/2: complex multipliers"),
    (-0.1, "−0.45 < λ ≤ −0.1"),
    (-0.01, "−0.1 < λ ≤ −0.01: near a bifurcation"),
    (0.01, "|λ| ≤ 0.01: at a bifurcation, or not periodic"),
    (f64::INFINITY, "λ > 0.01: chaotic"),
];

/// The Lyapunov exponent over a grid: a curve for one axis, a map in [`LYAPUNOV_BINS`] for two.
pub fn lyapunov_figure<S: crate::sweep::Sweep>(
    grid: &crate::sweep::Grid<S>,
    rows: &[crate::periodic::LyapunovRow<S::Point>],
) -> Figure {
    let caption = format!(
        "Largest Lyapunov exponent (Benettin, variational equations) of the response reached \
         from the default start, over {} point(s) (the other parameters: {}, ω = {}). For a \
         periodic response it equals the largest Floquet exponent; −1/2 wherever the \
         multipliers are a complex pair; near 0 at folds and period doublings.",
        rows.len(),
        grid.base.caption(),
        grid.base.omega(),
    );
    let ax = &grid.axes[0];
    if grid.axes.len() == 1 {
        return lyapunov_curve(ax, rows, caption);
    }
    let ay = &grid.axes[1];
    let cells = rows
        .iter()
        .filter(|r| r.lyapunov.is_finite())
        .map(|r| {
            let (i, j) = (r.index % ax.count, r.index / ax.count);
            let (x0, x1) = cell_edges(ax, i);
            let (y0, y1) = cell_edges(ay, j);
            let k = LYAPUNOV_BINS
                .iter()
                .position(|(hi, _)| r.lyapunov <= *hi)
                .unwrap_or(LYAPUNOV_BINS.len() - 1);
            (x0, x1, y0, y1, k)
        })
        .collect();
    let (xr, yr) = (
        (cell_edges(ax, 0).0, cell_edges(ax, ax.count - 1).1),
        (cell_edges(ay, 0).0, cell_edges(ay, ay.count - 1).1),
    );
    Figure {
        name: "lyapunov".into(),
        caption,
        size: (1000, 700),
        panels: Vec::new(),
        map: Some(Map {
            frame: Panel {
                title: format!(
                    "largest Lyapunov exponent over ({}, {})",
                    ax.param, ay.param
                ),
                x_label: ax.param.to_string(),
                y_label: ay.param.to_string(),
                x_log: ax.log,
                y_log: ay.log,
                x_range: Some(xr),
                y_range: Some(yr),
                legend_left: true,
                ..Panel::default()
            },
            cells,
            categories: LYAPUNOV_BINS.iter().map(|b| b.1.to_string()).collect(),
        }),
    }
}

/// A drive's frequency-response curve in SI units: peak-to-peak twist \[mrad\] and the largest
/// elastic torque \[N m\] against the disturbance frequency \[Hz\].
pub fn physical_response_figure(r: &crate::periodic::PhysicalResponse) -> Figure {
    let d = &r.drive;
    let folds: Vec<String> = r
        .points
        .iter()
        .filter(|q| q.special == Some(crate::periodic::Special::Fold))
        .map(|q| format!("{:.1} Hz", q.frequency_hz))
        .collect();
    let peak = r
        .points
        .iter()
        .max_by(|a, b| a.twist_peak_to_peak.total_cmp(&b.twist_peak_to_peak));
    Figure {
        name: "physical-frequency-response".into(),
        caption: format!(
            "Frequency response of the drive (J_i = {} kg m², J_o = {} kg m², N = {}, k1 = {} N m/rad, \
             k2 = {} N m/rad³, φ = {} rad, C = {} N m s/rad, T_m = {} N m, T_am = {} N m) against \
             the disturbance frequency, from the reduced model's continuation converted to SI \
             (θ = L x, Ω = ω/T). {} {}",
            d.j_in,
            d.j_out,
            d.ratio,
            d.k1,
            d.k2,
            d.backlash,
            d.c_eq,
            d.t_m,
            d.t_am,
            peak.map_or(String::new(), |q| format!(
                "The largest response, {:.3} mrad peak to peak, is at {:.1} Hz.",
                1e3 * q.twist_peak_to_peak,
                q.frequency_hz
            )),
            if folds.is_empty() {
                "No fold: at this disturbance amplitude the response is single-valued and a \
                 frequency sweep does not jump."
                    .to_string()
            } else {
                format!(
                    "Folds (jumps of a frequency sweep) at {}.",
                    folds.join(", ")
                )
            }
        ),
        size: (1000, 800),
        panels: vec![
            // the SI values of point i are r.points[i] (one per branch point)
            response_panel(
                &r.branch,
                ("peak-to-peak twist [mrad]", "f [Hz]"),
                |i, _| {
                    let q = &r.points[i];
                    (q.frequency_hz, 1e3 * q.twist_peak_to_peak)
                },
            ),
            response_panel(
                &r.branch,
                ("largest elastic torque [N m]", "f [Hz]"),
                |i, _| (r.points[i].frequency_hz, r.points[i].torque_range[1]),
            ),
        ],
        map: None,
    }
}

/// The Lyapunov exponent against the one axis of a sweep.
fn lyapunov_curve<P: std::fmt::Display, V>(
    ax: &crate::sweep::Axis<P>,
    rows: &[crate::periodic::LyapunovRow<V>],
    caption: String,
) -> Figure {
    // the one axis: a row's index is its place on it
    let points = rows
        .iter()
        .filter(|r| r.lyapunov.is_finite())
        .map(|r| (ax.value(r.index), r.lyapunov))
        .collect();
    Figure {
        name: "lyapunov".into(),
        caption,
        size: (1000, 500),
        panels: vec![Panel {
            title: format!("largest Lyapunov exponent against {}", ax.param),
            x_label: ax.param.to_string(),
            y_label: "λ_max".into(),
            x_log: ax.log,
            series: vec![Series {
                label: String::new(),
                points,
                color: 2,
                style: Style::Line,
            }],
            ..Panel::default()
        }],
        map: None,
    }
}

/// [`frequency_response_figure`] over the default ω range of `p`.
pub fn frequency_response_kind(p: &Params, _study: &mut Study) -> Result<Figure> {
    let b = crate::periodic::frequency_response(
        p,
        None,
        &crate::periodic::ContinuationOptions::default(),
    )?;
    Ok(frequency_response_figure(p, &b))
}

/// [`orbit_diagram_figure`] over ω ∈ [ω_s/2, 1.5 ω_s] (ω_s: the stiffest static frequency, see
/// [`crate::periodic::default_frequency_range`]), the resonance and its bend, 161 values.
pub fn orbit_diagram_kind(p: &Params, _study: &mut Study) -> Result<Figure> {
    // the default range is [ω_s/20, 3 ω_s]
    let ws = crate::periodic::default_frequency_range(p).1 / 3.0;
    let values: Vec<f64> = (0..=160)
        .map(|i| 0.5 * ws + ws * f64::from(i) / 160.0)
        .collect();
    let opts = crate::periodic::DiagramOptions {
        lyapunov: Some(200),
        ..crate::periodic::DiagramOptions::default()
    };
    let mut points = Vec::new();
    crate::periodic::orbit_diagram(p, Param::Omega, &values, &opts, |q| points.push(q))?;
    Ok(orbit_diagram_figure(p, Param::Omega, &points))
}

/// [`lyapunov_figure`] over ω ∈ [ω_s/4, 2ω_s] × δ ∈ [δ/8, 8δ] (log, 32 × 20).
pub fn lyapunov_map_kind(p: &Params, study: &mut Study) -> Result<Figure> {
    let ws = crate::periodic::default_frequency_range(p).1 / 3.0;
    let d = if p.delta > 0.0 { p.delta } else { 1.0 };
    let grid = crate::sweep::Grid::new(
        *p,
        vec![
            Axis {
                param: Param::Omega,
                start: ws / 4.0,
                end: 2.0 * ws,
                count: 32,
                log: true,
            },
            Axis {
                param: Param::Delta,
                start: d / 8.0,
                end: 8.0 * d,
                count: 20,
                log: true,
            },
        ],
    )?;
    let opts = crate::periodic::DiagramOptions {
        discard: 100,
        lyapunov: Some(100),
        ..crate::periodic::DiagramOptions::default()
    };
    let rows = crate::sweep::lyapunov_map(&grid, &opts, study.threads)?;
    Ok(lyapunov_figure(&grid, &rows))
}

/// The curves of a parameter plane: folds and period doublings of the periodic response
/// (two-parameter continuation) and boundaries of the fast-slow picture (the bursting boundary
/// predicted and simulated, the fold set of the fast subsystem, the fast-slow edge), each kind
/// in its own colour, the codimension-two points marked.
pub fn plane_figure<P, A>(
    curves: &[crate::periodic::Curve2<P>],
    boundaries: &[crate::burst::PlaneCurve<A>],
    names: [&str; 2],
    logs: [bool; 2],
) -> Figure {
    use crate::burst::BoundaryKind;
    use crate::periodic::CurveKind;
    let mut seen = [false; 2 + BoundaryKind::ALL.len()];
    let mut series = |color: usize, label: String, points: Vec<(f64, f64)>| {
        let first = !std::mem::replace(&mut seen[color], true);
        Series {
            label: if first { label } else { String::new() },
            points,
            color,
            style: Style::Line,
        }
    };
    let mut all: Vec<Series> = curves
        .iter()
        .map(|c| {
            let color = usize::from(c.kind == CurveKind::PeriodDoubling);
            let points = c.points.iter().map(|q| (q.params[0], q.params[1]));
            series(color, format!("{} curve", c.kind.name()), points.collect())
        })
        .collect();
    all.extend(boundaries.iter().map(|b| {
        let color = 2 + BoundaryKind::ALL
            .iter()
            .position(|&k| k == b.kind)
            .unwrap_or(0);
        let points = b.points.iter().map(|q| (q.params[0], q.params[1]));
        series(
            color,
            format!("{} ({} inside)", b.kind.name(), b.kind.inside()),
            points.collect(),
        )
    }));
    let markers = curves
        .iter()
        .flat_map(|c| c.points.iter())
        .filter_map(|q| {
            q.special
                .map(|s| (q.params[0], q.params[1], s.name().to_string()))
        })
        .collect();
    Figure {
        name: "curves".into(),
        caption: format!(
            "Curves of the ({}, {}) plane. Folds of cycles and period doublings of the periodic \
             response, each followed by two-parameter continuation: between the two branches of \
             a fold curve the response is hysteretic (two stable orbits, a jump at each fold); \
             at a cusp the two folds meet and the hysteresis vanishes; inside a period-doubling \
             curve the period-1 orbit is unstable and a period-2 orbit takes over. Boundaries \
             of the fast-slow picture, each the edge of the region where its verdict holds \
             (named in the legend), followed by the predictor–corrector of \
             hdgear::burst::plane_boundaries.",
            names[0], names[1]
        ),
        size: (1000, 700),
        panels: vec![Panel {
            title: format!("Curves in ({}, {})", names[0], names[1]),
            x_label: names[0].into(),
            y_label: names[1].into(),
            x_log: logs[0],
            y_log: logs[1],
            series: all,
            markers,
            ..Panel::default()
        }],
        map: None,
    }
}
