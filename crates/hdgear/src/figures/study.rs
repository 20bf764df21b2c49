//! The study's own figures: x'(τ) for the four γ, x(τ) over the equilibrium, the transformed
//! phase portrait, the phase plane and the slope |dx/da|.

use super::decimate;
use crate::error::Result;
use crate::fast::{self, curve};
use crate::output::plot::{Figure, Panel, Series, Style};
use crate::params::Params;
use crate::study::{Case, Study};
use crate::table::STUDY_GAMMAS;

fn burst_spans(w: &Case, t1: f64) -> Vec<(f64, f64, usize)> {
    w.response
        .bursts
        .iter()
        .filter(|b| b.onset < t1)
        .map(|b| (b.onset, b.end.min(t1), 1))
        .collect()
}

/// The legend label of shaded bursts (none when there are none).
fn burst_label(w: &Case) -> String {
    if w.response.bursts.is_empty() {
        String::new()
    } else {
        "burst".into()
    }
}

/// x'(t) over one slow period for the study's four γ, bursts shaded.
pub fn xdot_gamma(base: &Params, study: &mut Study) -> Result<Figure> {
    let mut panels = Vec::new();
    let points = STUDY_GAMMAS.map(|(gamma, _)| Params { gamma, ..*base });
    for w in study.cases(&points)? {
        let (gamma, c) = (w.params.gamma, &w.classification);
        let t1 = w.sample_end();
        let pts: Vec<(f64, f64)> = w.samples.iter().map(|s| (s.0, s.2)).collect();
        let tol = 1e-3 * super::span_of(&pts);
        panels.push(Panel {
            title: format!(
                "γ = {gamma}: {} (max |x'| = {:.4})",
                c.mode.name(),
                w.response.rates.peak_abs_xdot
            ),
            x_label: "τ".into(),
            y_label: "x'".into(),
            x_range: Some((w.response.window_start, t1)),
            series: vec![Series {
                label: String::new(),
                points: decimate(&pts, tol),
                color: 0,
                style: Style::Line,
            }],
            shaded: burst_spans(w, t1),
            shaded_label: burst_label(w),
            ..Panel::default()
        });
    }
    Ok(Figure {
        name: "xdot-gamma".into(),
        caption: "x'(τ) over one slow period 2π/ω after the transient, for γ = 30, 10, 1 and 0.1 \
                  (each panel its own scale). For γ = 30 and 10 x' is the smooth slow wave of a \
                  state that follows its equilibrium; for γ = 1 and 0.1 it is flat except for two \
                  bursts per period (shaded: detected bursts), each a fast pulse followed by \
                  ringing that decays within about ten time units."
            .into(),
        size: (1000, 1000),
        panels,
        map: None,
    })
}

/// x*(a(τ)) along the stable branch nearest the state, at the samples of `w`.
fn tracked_equilibrium(p: &Params, w: &Case) -> Vec<(f64, f64)> {
    w.samples
        .iter()
        .map(|s| {
            let a = (p.omega * s.0).sin();
            (
                s.0,
                fast::nearest_stable_equilibrium(p, a, s.1).unwrap_or(f64::NAN),
            )
        })
        .collect()
}

/// x(τ) with the equilibrium x*(a(τ)) over it, one slow period.
pub fn x_equilibrium(p: &Params, study: &mut Study) -> Result<Figure> {
    let w = study.case(p)?;
    let t1 = w.sample_end();
    let x: Vec<(f64, f64)> = w.samples.iter().map(|s| (s.0, s.1)).collect();
    let tol = 1e-3 * super::span_of(&x);
    let xs = tracked_equilibrium(p, w);
    let mut panels = vec![Panel {
        title: format!("x and x*(a), γ = {}, one slow period", p.gamma),
        x_label: "τ".into(),
        y_label: "x".into(),
        x_range: Some((w.response.window_start, t1)),
        series: vec![
            Series {
                label: "x*(a(τ))".into(),
                points: decimate(&xs, tol),
                color: 1,
                style: Style::Line,
            },
            Series {
                label: "x(τ)".into(),
                points: decimate(&x, tol),
                color: 0,
                style: Style::Thin,
            },
        ],
        shaded: burst_spans(w, t1),
        shaded_label: burst_label(w),
        ..Panel::default()
    }];
    let (z0, z1) = zoom_range(w, &xs);
    let zoom = |v: &[(f64, f64)]| {
        v.iter()
            .copied()
            .filter(|q| q.0 >= z0 && q.0 <= z1)
            .collect::<Vec<_>>()
    };
    panels.push(Panel {
        title: format!("zoom: τ from {z0:.0} to {z1:.0}"),
        x_label: "τ".into(),
        y_label: "x".into(),
        x_range: Some((z0, z1)),
        series: vec![
            Series {
                label: "x*(a(τ))".into(),
                points: zoom(&xs),
                color: 1,
                style: Style::Line,
            },
            Series {
                label: "x(τ)".into(),
                points: zoom(&x),
                color: 0,
                style: Style::Line,
            },
        ],
        shaded: burst_spans(w, t1)
            .into_iter()
            .filter(|b| b.1 > z0 && b.0 < z1)
            .collect(),
        shaded_label: burst_label(w),
        ..Panel::default()
    });
    Ok(Figure {
        name: "x-equilibrium".into(),
        caption: format!(
            "x(τ) and the stable equilibrium x*(a(τ)) of the fast subsystem over one slow period \
             (top) and around one burst (bottom), γ = {}. In the quiescent areas the state lies on \
             its equilibrium; where the equilibrium curve is steep x* runs across almost at once, \
             the state lags behind (max |x − x*| = {:.4}) and catches up with damped ringing \
             (shaded: the detected burst).",
            p.gamma, w.response.rates.max_tracking_error
        ),
        size: (1000, 800),
        panels,
        map: None,
    })
}

/// Around the first burst (or the steepest passage of x* when there is none).
fn zoom_range(w: &Case, xs: &[(f64, f64)]) -> (f64, f64) {
    match w.response.bursts.first() {
        Some(b) => (b.onset - 15.0, b.end + 15.0),
        None => {
            let i = xs
                .windows(2)
                .enumerate()
                .max_by(|a, b| {
                    (a.1[1].1 - a.1[0].1)
                        .abs()
                        .total_cmp(&(b.1[1].1 - b.1[0].1).abs())
                })
                .map_or(0, |(i, _)| i);
            (xs[i].0 - 40.0, xs[i].0 + 40.0)
        }
    }
}

/// The caption of the transformed phase portrait.
fn transformed_phase_caption(gamma: f64, areas: &[fast::Interval], has_folds: bool) -> String {
    format!(
        "The transformed phase portrait: the trajectory (a(τ), x(τ)) over one slow period on \
         the equilibrium curve of the fast subsystem, γ = {} (top: the whole range; bottom: \
         a zoom around a ≈ 0). Shaded: the spiking area{} predicted by the fast subsystem \
         ({}). {}",
        gamma,
        if areas.len() == 1 { "" } else { "s" },
        if areas.is_empty() {
            "none".to_string()
        } else {
            areas
                .iter()
                .map(|s| format!("a ∈ [{:.4}, {:.4}]", s.a_min, s.a_max))
                .collect::<Vec<_>>()
                .join(", ")
        },
        if !has_folds {
            "The curve has no fold: one stable equilibrium for every a. The trajectory \
             follows it in the quiescent areas and leaves it only where the curve is steep, \
             overshooting and ringing back onto it."
        } else {
            "Folds (crosses) lie in the traversed range: between them the curve has three \
             branches (the middle one saddles), and the trajectory jumps between the stable \
             branches (hysteresis)."
        }
    )
}

/// The trajectory of `w` in the (a, x) plane and the equilibrium curve (stable points, and
/// saddles where there are any).
fn phase_series(p: &Params, w: &Case) -> Result<Vec<Series>> {
    let c = curve(p, crate::fast::A_RANGE, 2000)?;
    let traj: Vec<(f64, f64)> = w
        .samples
        .iter()
        .map(|s| ((p.omega * s.0).sin(), s.1))
        .collect();
    let stable: Vec<(f64, f64)> = c
        .iter()
        .filter(|q| q.kind.is_stable())
        .map(|q| (q.a, q.x))
        .collect();
    let saddle: Vec<(f64, f64)> = c
        .iter()
        .filter(|q| !q.kind.is_stable())
        .map(|q| (q.a, q.x))
        .collect();
    let mut series = vec![Series {
        label: "trajectory".into(),
        points: decimate(&traj, 1e-4),
        color: 0,
        style: Style::Thin,
    }];
    series.push(Series {
        label: "stable equilibria".into(),
        points: stable,
        color: 1,
        style: Style::Points,
    });
    if !saddle.is_empty() {
        series.push(Series {
            label: "saddles".into(),
            points: saddle,
            color: 3,
            style: Style::Points,
        });
    }
    Ok(series)
}

/// The trajectory in the (a, x) plane over the equilibrium curve; spiking areas shaded, folds
/// marked.
pub fn transformed_phase(p: &Params, study: &mut Study) -> Result<Figure> {
    let w = study.case(p)?;
    let an = &w.analysis;
    let series = phase_series(p, w)?;
    let folds: Vec<(f64, f64, String)> = an
        .equilibria
        .folds
        .iter()
        .filter(|f| f.in_range)
        .map(|f| (f.a, f.x, "fold".into()))
        .collect();
    let areas = &an.equilibria.spiking_areas;
    let full = Panel {
        title: format!("trajectory in the (a, x) plane, γ = {}", p.gamma),
        x_label: "a = sin(ωτ)".into(),
        y_label: "x".into(),
        x_range: Some((-1.02, 1.02)),
        series: series.clone(),
        shaded: areas.iter().map(|s| (s.a_min, s.a_max, 4)).collect(),
        shaded_label: if areas.is_empty() {
            String::new()
        } else {
            "spiking area".into()
        },
        markers: folds.clone(),
        ..Panel::default()
    };
    // zoom on the spiking areas (or the steepest point): where the trajectory leaves the curve
    let (lo, hi) = match (areas.first(), areas.last()) {
        (Some(f), Some(l)) => (f.a_min, l.a_max),
        _ => (an.equilibria.max_slope.a, an.equilibria.max_slope.a),
    };
    let half = (3.0 * (hi - lo)).max(0.06);
    let (z0, z1) = (
        (0.5 * (lo + hi) - half).max(-1.0),
        (0.5 * (lo + hi) + half).min(1.0),
    );
    let zoomed: Vec<Series> = series
        .iter()
        .map(|s| Series {
            points: s
                .points
                .iter()
                .copied()
                .filter(|q| q.0 >= z0 && q.0 <= z1)
                .collect(),
            ..s.clone()
        })
        .collect();
    let zoom = Panel {
        title: format!("zoom: a from {z0:.3} to {z1:.3}"),
        x_range: Some((z0, z1)),
        series: zoomed,
        ..full.clone()
    };
    Ok(Figure {
        name: "transformed-phase".into(),
        caption: transformed_phase_caption(p.gamma, areas, !folds.is_empty()),
        size: (1000, 1000),
        panels: vec![full, zoom],
        map: None,
    })
}

/// The phase plane (x, x') over one slow period.
pub fn phase_plane(p: &Params, study: &mut Study) -> Result<Figure> {
    let w = study.case(p)?;
    let pts: Vec<(f64, f64)> = w.samples.iter().map(|s| (s.1, s.2)).collect();
    Ok(Figure {
        name: "phase-plane".into(),
        caption: format!(
            "The phase plane (x, x') over one slow period, γ = {}. Slow drift along x' ≈ 0; each \
             burst is a loop away from it that spirals back (the fast subsystem's equilibria are \
             stable foci or nodes).",
            p.gamma
        ),
        size: (800, 600),
        panels: vec![Panel {
            title: format!("phase plane, γ = {}", p.gamma),
            x_label: "x".into(),
            y_label: "x'".into(),
            series: vec![Series {
                label: String::new(),
                points: decimate(&pts, 1e-4 * super::span_of(&pts)),
                color: 0,
                style: Style::Line,
            }],
            ..Panel::default()
        }],
        map: None,
    })
}

/// |dx/da| against a (log scale) for the four γ of the study.
pub fn slope(base: &Params, _study: &mut Study) -> Result<Figure> {
    let mut series = Vec::new();
    for (i, (gamma, _)) in STUDY_GAMMAS.iter().enumerate() {
        let p = Params {
            gamma: *gamma,
            ..*base
        };
        let c = curve(&p, crate::fast::A_RANGE, 2000)?;
        series.push(Series {
            label: format!("γ = {gamma}"),
            points: c.iter().map(|q| (q.a, q.slope.abs())).collect(),
            color: i,
            style: Style::Line,
        });
    }
    Ok(Figure {
        name: "slope".into(),
        caption: "The slope |dx/da| = δ/|g'(x)| of the equilibrium curve against a, log scale. \
                  As γ falls toward 1/(3α) the peak near a ≈ 0 grows from 0.47 (γ = 30, whose \
                  steepest point lies outside the range) through 1.5 and 15.3 to 189.5 (γ = 0.1): \
                  a sharp quantitative change, with no fold (the slope stays finite)."
            .into(),
        size: (1000, 550),
        panels: vec![Panel {
            title: "slope of the equilibrium curve".into(),
            x_label: "a".into(),
            y_label: "|dx/da|".into(),
            y_log: true,
            x_range: Some(crate::fast::A_RANGE),
            series,
            ..Panel::default()
        }],
        map: None,
    })
}
