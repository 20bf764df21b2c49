//! The tolerance cloud: where a spread drive's samples fall in the reduced (γ, δ) plane, each
//! coloured by its verdict, against the boundary predicted from the equilibrium curve.

use crate::fast::predict;
use crate::output::plot::{Figure, Panel, Series, Style};
use crate::params::Params;

/// Most samples drawn (the first ones: Sobol points from index 0 spread over the whole box).
pub const CLOUD_POINTS: usize = 4096;

/// Points of the predicted boundary drawn across the cloud's γ range.
const BOUNDARY_POINTS: usize = 60;

/// δ where the prediction at `p` with γ = `gamma` changes, bisected in ln δ over
/// [`lo`, `hi`] (None without a change there).
fn predicted_delta(p: &Params, gamma: f64, lo: f64, hi: f64) -> Option<f64> {
    let bursts = |delta: f64| predict(&Params { gamma, delta, ..*p }).bursting;
    let (mut a, mut b) = (lo.ln(), hi.ln());
    let at_a = bursts(lo);
    if at_a == bursts(hi) {
        return None;
    }
    for _ in 0..40 {
        let m = 0.5 * (a + b);
        if bursts(m.exp()) == at_a {
            a = m
        } else {
            b = m
        }
    }
    Some((0.5 * (a + b)).exp())
}

/// The cloud of `samples` (reduced γ, δ, bursting) around the nominal reduced set `nominal`,
/// with the boundary predicted at the nominal's other parameters.
pub fn cloud_figure(nominal: &Params, samples: &[(f64, f64, bool)]) -> Figure {
    let shown = &samples[..samples.len().min(CLOUD_POINTS)];
    let pick = |b: bool| -> Vec<(f64, f64)> {
        shown
            .iter()
            .filter(|s| s.2 == b)
            .map(|s| (s.0, s.1))
            .collect()
    };
    let range = |f: fn(&(f64, f64, bool)) -> f64, v: f64| {
        shown
            .iter()
            .map(f)
            .fold((v, v), |(lo, hi), x| (lo.min(x), hi.max(x)))
    };
    let (g0, g1) = range(|s| s.0, nominal.gamma);
    let (d0, d1) = range(|s| s.1, nominal.delta);
    let (g0, g1) = (g0 / 1.1, g1 * 1.1);
    let boundary: Vec<(f64, f64)> = (0..BOUNDARY_POINTS)
        .filter_map(|i| {
            let g = g0 * (g1 / g0).powf(i as f64 / (BOUNDARY_POINTS - 1) as f64);
            predicted_delta(nominal, g, d0 / 4.0, d1 * 4.0).map(|d| (g, d))
        })
        .collect();
    let n = shown.len();
    let bursting = pick(true).len();
    let panel = Panel {
        title: format!("{n} samples in the reduced (γ, δ) plane: {bursting} bursting"),
        x_label: "γ (reduced)".into(),
        y_label: "δ (reduced)".into(),
        x_log: true,
        y_log: true,
        x_range: Some((g0, g1)),
        y_range: Some((d0 / 1.1, d1 * 1.1)),
        series: vec![
            Series {
                label: "burst-free sample".into(),
                points: pick(false),
                color: 0,
                style: Style::Points,
            },
            Series {
                label: "bursting sample".into(),
                points: pick(true),
                color: 1,
                style: Style::Points,
            },
            Series {
                label: "predicted boundary at the nominal α, ε, μ, ω".into(),
                points: boundary,
                color: 2,
                style: Style::Line,
            },
        ],
        markers: vec![(nominal.gamma, nominal.delta, "nominal".into())],
        ..Panel::default()
    };
    Figure {
        name: "tolerance-cloud".into(),
        caption: format!(
            "The tolerance cloud: the first {n} samples of the spread drive, each reduced to the \
             dimensionless model and placed at its (γ, δ), coloured by its simulated verdict. The \
             line is the boundary predicted from the equilibrium curve at the nominal set's α, \
             ε, μ and ω; the samples' own α, ε, μ and ω spread too, so a sample can lie on the \
             'wrong' side of it. What the line shows is the direction: towards small γ (a soft \
             or lightly damped drive) and large δ (a large disturbance) the drive bursts."
        ),
        size: (1000, 700),
        panels: vec![panel],
        map: None,
    }
}
