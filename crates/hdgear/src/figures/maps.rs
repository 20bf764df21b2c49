//! Figures over parameter planes: the γ sweep, the (γ, δ) map and the bursting boundary in
//! (ω, γ).

use crate::burst::Mode;
use crate::error::Result;
use crate::fast::{self};
use crate::output::plot::{Figure, Map, Panel, Series, Style};
use crate::params::Params;
use crate::study::{GridRun, Study};
use crate::sweep::Axis;
use rayon::prelude::*;

/// Peak |x'| and spikes per burst against γ.
pub fn sweep_figure(base: &Params, study: &mut Study) -> Result<Figure> {
    let rows = &study.sweep(base)?.rows;
    let gc = base.critical_gamma();
    let peak: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (r.params.gamma, r.rates.peak_abs_xdot))
        .collect();
    let spikes: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (r.params.gamma, r.rates.spikes_per_burst))
        .collect();
    let bursting = rows
        .iter()
        .filter(|r| r.rates.bursts_per_period.is_some_and(|b| b > 0.0))
        .map(|r| r.params.gamma)
        .fold(0.0, f64::max);
    let vline = vec![(gc, format!("1/(3α) = {gc:.4}"))];
    Ok(Figure {
        name: "sweep".into(),
        caption: format!(
            "A sweep of γ from 0.01 to 30 (log-spaced, {} points; the other parameters as in the \
             study). Top: the largest |x'| after the transient; bottom: spikes per burst. Bursts \
             appear below γ ≈ {:.2}, far above the fold threshold 1/(3α) = {:.4} (grey line): \
             the bursting sets in through the steepening of the curve, not through a bifurcation.",
            rows.len(),
            bursting,
            gc
        ),
        size: (1000, 800),
        panels: vec![
            Panel {
                title: "peak |x'| against γ".into(),
                x_label: "γ".into(),
                y_label: "max |x'|".into(),
                x_log: true,
                y_log: true,
                series: vec![Series {
                    label: "peak |x'|".into(),
                    points: peak,
                    color: 0,
                    style: Style::Line,
                }],
                vlines: vline.clone(),
                ..Panel::default()
            },
            Panel {
                title: "spikes per burst against γ".into(),
                x_label: "γ".into(),
                y_label: "spikes per burst".into(),
                x_log: true,
                series: vec![Series {
                    label: "spikes per burst".into(),
                    points: spikes,
                    color: 1,
                    style: Style::Points,
                }],
                vlines: vline,
                ..Panel::default()
            },
        ],
        map: None,
    })
}

/// The smallest δ at which the folds of the fast subsystem lie inside a ∈ [−1, 1]:
/// max |g(x±) − μ| (γ < 1/(3α)).
pub fn fold_delta(p: &Params) -> Option<f64> {
    fast::fold_abscissae(p).map(|(xm, xp)| (p.g(xm) - p.mu).abs().max((p.g(xp) - p.mu).abs()))
}

/// The edges of grid cell `i` on `ax`: halfway between grid values (geometric for log axes).
pub(super) fn cell_edges<P>(ax: &Axis<P>, i: usize) -> (f64, f64) {
    let v = ax.value(i);
    let prev = if i > 0 { ax.value(i - 1) } else { v };
    let next = if i + 1 < ax.count { ax.value(i + 1) } else { v };
    if ax.log {
        let lo = if i > 0 {
            (prev * v).sqrt()
        } else {
            v * (v / next).sqrt()
        };
        let hi = if i + 1 < ax.count {
            (v * next).sqrt()
        } else {
            v * (v / prev).sqrt()
        };
        (lo, hi)
    } else {
        let lo = if i > 0 {
            0.5 * (prev + v)
        } else {
            v - 0.5 * (next - v)
        };
        let hi = if i + 1 < ax.count {
            0.5 * (v + next)
        } else {
            v + 0.5 * (v - prev)
        };
        (lo, hi)
    }
}

/// The boundary of the region where folds lie in a ∈ [−1, 1]: δ ≥ δ_fold(γ) for γ from `g_min`
/// to 1/(3α), closed on the right by γ = 1/(3α) up to `d_max`.
fn fold_boundary(base: &Params, g_min: f64, d_max: f64) -> Vec<(f64, f64)> {
    let gc = base.critical_gamma();
    let cusp = Params { gamma: gc, ..*base };
    let mut fold: Vec<(f64, f64)> = (0..199)
        .map(|k| g_min * (gc / g_min).powf(k as f64 / 199.0))
        .filter_map(|g| fold_delta(&Params { gamma: g, ..*base }).map(|d| (g, d)))
        .collect();
    fold.push((gc, (cusp.g(gc) - cusp.mu).abs()));
    fold.push((gc, d_max));
    fold
}

/// The (γ, δ) boundary predicted from the equilibrium curve alone: for each γ in `xr` the δ in
/// `yr` above which bursting is predicted.
fn predicted_delta_boundary(base: &Params, xr: (f64, f64), yr: (f64, f64)) -> Vec<(f64, f64)> {
    let gc = base.critical_gamma();
    // one bisection of predictions per γ, the γs side by side (the figure stage is otherwise
    // on one core)
    (0..160)
        .into_par_iter()
        .map(|k| xr.0 * (xr.1 / xr.0).powf(f64::from(k) / 159.0))
        .filter(|&g| g > gc)
        .filter_map(|g| {
            let quiet = |d: f64| {
                !fast::predict(&Params {
                    gamma: g,
                    delta: d,
                    ..*base
                })
                .bursting
            };
            crate::roots::bisect_log(yr.0, yr.1, quiet).map(|d| (g, d))
        })
        .collect()
}

/// The (γ, δ) plane coloured by mode, with the fold curve and the cusp over it.
pub fn map_figure(base: &Params, study: &mut Study) -> Result<Figure> {
    let GridRun { grid, rows } = study.map(base)?;
    let modes = [
        Mode::Normal,
        Mode::Transitional,
        Mode::FastSlow,
        Mode::PronouncedBursting,
        Mode::Relaxation,
        Mode::NotFastSlow,
    ];
    let (ga, da) = (&grid.axes[0], &grid.axes[1]);
    let edges = cell_edges;
    let mut cells = Vec::new();
    for r in rows {
        let (i, j) = (r.index % ga.count, r.index / ga.count);
        let (x0, x1) = edges(ga, i);
        let (y0, y1) = edges(da, j);
        if let Some(k) = modes.iter().position(|&m| Some(m) == r.mode) {
            cells.push((x0, x1, y0, y1, k));
        }
    }
    let gc = base.critical_gamma();
    let cusp = Params { gamma: gc, ..*base };
    let cusp_delta = (cusp.g(gc) - cusp.mu).abs();
    let (xr, yr) = (
        (edges(ga, 0).0, edges(ga, ga.count - 1).1),
        (edges(da, 0).0, edges(da, da.count - 1).1),
    );
    let fold = fold_boundary(base, ga.start, yr.1);
    let predicted = predicted_delta_boundary(base, xr, yr);
    Ok(Figure {
        name: "map".into(),
        caption: format!(
            "Oscillation mode over the (γ, δ) plane ({} × {} simulations, both axes logarithmic; \
             the other parameters as in the study). Black: the fold boundary — inside it (left \
             of γ = 1/(3α) = {:.4} and above the fold curve) the folds of the fast subsystem lie \
             in the traversed range a ∈ [−1, 1] and the bursting is fold-hysteresis; the cross \
             marks the cusp. Everything that bursts outside it bursts with no bifurcation at all \
             (sharp-quantitative-change): by far the larger part of the bursting region. Dots: the \
             boundary predicted from the equilibrium curve alone (bursting above them), to compare \
             with the simulated modes.",
            ga.count, da.count, gc
        ),
        size: (1000, 700),
        panels: Vec::new(),
        map: Some(Map {
            frame: Panel {
                title: "mode over (γ, δ)".into(),
                x_label: "γ".into(),
                y_label: "δ".into(),
                x_log: true,
                y_log: true,
                legend_left: true,
                x_range: Some(xr),
                y_range: Some(yr),
                series: vec![
                    Series {
                        label: "fold boundary".into(),
                        points: fold,
                        color: 6,
                        style: Style::Line,
                    },
                    Series {
                        label: "predicted bursting boundary".into(),
                        points: predicted,
                        color: 6,
                        style: Style::Points,
                    },
                ],
                markers: if cusp_delta <= yr.1 {
                    vec![(gc, cusp_delta.max(yr.0), "cusp".into())]
                } else {
                    Vec::new()
                },
                ..Panel::default()
            },
            cells,
            categories: modes.iter().map(|m| m.name().to_string()).collect(),
        }),
    })
}

/// The predicted bursting boundary (ω at which κ reaches the threshold) and the edge of the
/// fast-slow domain, for 200 γ log-spaced from just above the cusp to 30, as (ω, γ).
type Curve = Vec<(f64, f64)>;

fn boundary_curves(base: &Params) -> (Curve, Curve) {
    let gc = base.critical_gamma();
    let (g0, g1) = (gc * 1.001, 30.0_f64);
    let gammas: Vec<f64> = (0..200)
        .map(|i| g0 * (g1 / g0).powf(f64::from(i) / 199.0))
        .collect();
    let at = |g: f64| Params { gamma: g, ..*base };
    let predicted: Vec<(f64, f64)> = gammas
        .par_iter()
        .map(|&g| (fast::predict(&at(g)).omega_boundary, g))
        .filter(|q| q.0.is_finite() && q.0 > 0.0)
        .collect();
    let domain: Vec<(f64, f64)> = gammas
        .iter()
        .map(|&g| (crate::burst::fast_slow_omega_max(&at(g)), g))
        .collect();
    (predicted, domain)
}

/// The bursting boundary in the (ω, γ) plane: predicted from the equilibrium curve alone
/// (κ = [`crate::fast::FORCING_RATE_THRESHOLD`]) for γ from just above the cusp to 30, the edge
/// of the fast-slow domain (ω = r/10), and the boundaries located by simulation through `base` (in
/// γ and in ω) and through γ = 1 (in ω).
pub fn boundary_figure(base: &Params, study: &mut Study) -> Result<Figure> {
    let gc = base.critical_gamma();
    let at = |g: f64| Params { gamma: g, ..*base };
    let (predicted, domain) = boundary_curves(base);
    let b = study.boundaries(&[*base, at(1.0)])?;
    let simulated: Vec<(f64, f64)> = [
        b[0].simulated_gamma.map(|g| (base.omega, g)),
        b[0].simulated_omega.map(|w| (w, base.gamma)),
        b[1].simulated_omega.map(|w| (w, 1.0)),
    ]
    .into_iter()
    .flatten()
    .collect();
    // the largest factor between a simulated boundary and its prediction
    let ratio = |p: Option<f64>, s: Option<f64>| match (p, s) {
        (Some(p), Some(s)) if p > 0.0 && s > 0.0 => (p / s).max(s / p),
        _ => 1.0,
    };
    let factor = ratio(b[0].predicted_gamma, b[0].simulated_gamma)
        .max(ratio(Some(b[0].predicted_omega), b[0].simulated_omega))
        .max(ratio(Some(b[1].predicted_omega), b[1].simulated_omega));
    let x_min = predicted.iter().map(|q| q.0).fold(base.omega, f64::min) / 2.0;
    let x_max = domain.iter().map(|q| q.0).fold(base.omega, f64::max) * 2.0;
    let series = vec![
        Series {
            label: "predicted boundary (κ = threshold)".into(),
            points: predicted,
            color: 0,
            style: Style::Line,
        },
        Series {
            label: "fast-slow domain edge ω = r/10".into(),
            points: domain,
            color: 2,
            style: Style::Thin,
        },
        Series {
            label: "fold threshold γ = 1/(3α)".into(),
            points: vec![(x_min, gc), (x_max, gc)],
            color: 3,
            style: Style::Thin,
        },
        Series {
            label: "located by simulation".into(),
            points: simulated,
            color: 1,
            style: Style::Points,
        },
    ];
    Ok(Figure {
        name: "boundary".into(),
        caption: format!(
            "The bursting boundary in the (ω, γ) plane (the other parameters as at the study's \
             point). Bursting lies to the right of and below the predicted curve: faster forcing \
             or a steeper equilibrium curve. The dots are where the simulated verdict switches, to {} % \
             (γ at ω = {}, ω at γ = {} and at γ = 1); they lie within a factor \
             {factor:.2} of the prediction, which uses the equilibrium curve alone. As ω → 0 the boundary runs \
             down to the fold threshold 1/(3α) = {gc:.4}: without folds every burst vanishes \
             (Fenichel). Right of the domain edge the forcing is too fast for a fast-slow reading.",
            100.0 * crate::burst::BOUNDARY_REL_TOL,
            base.omega,
            base.gamma
        ),
        size: (1000, 700),
        panels: vec![Panel {
            title: "bursting boundary".into(),
            x_label: "ω".into(),
            y_label: "γ".into(),
            x_log: true,
            y_log: true,
            x_range: Some((x_min, x_max)),
            series,
            markers: vec![(base.omega, base.gamma, "study's point".into())],
            legend_left: true,
            ..Panel::default()
        }],
        map: None,
    })
}
