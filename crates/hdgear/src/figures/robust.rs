//! The figures of the design check under spread: the tolerance cloud (where a spread drive's
//! samples fall in the reduced (γ, δ) plane, each coloured by its verdict, against the boundary
//! predicted from the equilibrium curve), the Sobol bars (which tolerance matters) and
//! P(burst) against the load amplitude.

use crate::fast::predict;
use crate::output::plot::{Figure, Map, Panel, Series, Style};
use crate::params::Params;
use crate::robust::{LoadPoint, Measure, Sensitivity};

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

/// The Sobol bars of the burst indicator (of the peak |x'| when the verdict does not vary):
/// one bar per tolerance, its height the total index with its bootstrap interval, a black tick
/// at the first-order index. None when no measure varies.
pub fn sobol_figure(sens: &Sensitivity) -> Option<Figure> {
    let (measure, ix) = [Measure::Burst, Measure::PeakAbsXdot]
        .into_iter()
        .find_map(|m| {
            let (_, ix) = sens.measures.iter().find(|(n, _)| *n == m)?;
            ix.as_ref().filter(|ix| ix.variance > 0.0).map(|ix| (m, ix))
        })?;
    let k = sens.parameters.len();
    let top = ix
        .total
        .iter()
        .map(|t| t.hi)
        .fold(1.0f64, f64::max)
        .min(1.5);
    let mut series = Vec::new();
    for i in 0..k {
        let x = i as f64;
        series.push(Series {
            label: if i == 0 {
                "first-order index".into()
            } else {
                String::new()
            },
            points: vec![(x - 0.3, ix.first[i].value), (x + 0.3, ix.first[i].value)],
            color: 6,
            style: Style::Line,
        });
        series.push(Series {
            label: if i == 0 {
                "95 % bootstrap interval of the total".into()
            } else {
                String::new()
            },
            points: vec![(x, ix.total[i].lo), (x, ix.total[i].hi)],
            color: 6,
            style: Style::Thin,
        });
    }
    let frame = Panel {
        title: format!(
            "Which tolerance matters for {} (N = {}, {} runs)",
            measure.name(),
            sens.n,
            sens.n * (k + 2)
        ),
        x_label: "tolerance (colour: legend)".into(),
        y_label: "total Sobol index (bar)".into(),
        x_range: Some((-0.6, k as f64 - 0.4)),
        y_range: Some((0.0, top)),
        series,
        ..Panel::default()
    };
    let cells = (0..k)
        .map(|i| {
            let x = i as f64;
            (x - 0.35, x + 0.35, 0.0, ix.total[i].value.max(0.0), i)
        })
        .collect();
    Some(Figure {
        name: "sobol-bars".into(),
        caption: format!(
            "Which tolerance matters: for each toleranced parameter the share of the variance of \
             {} it causes, alone and with every other (the total Sobol index, the bar, with its \
             bootstrap interval) and alone (the first-order index, the black tick). A bar near \
             zero: that tolerance can be relaxed. A total well above the first-order index: it \
             matters through its interaction with others.",
            measure.name()
        ),
        size: (1000, 600),
        panels: Vec::new(),
        map: Some(Map {
            frame,
            cells,
            categories: sens.parameters.iter().map(|p| p.to_string()).collect(),
        }),
    })
}

/// P(burst) against the load amplitude, with the Wilson intervals; `load` names the amplitude
/// (`T_am [N m]`, `δ`).
pub fn load_figure(points: &[LoadPoint], load: &str) -> Figure {
    let mut series = vec![Series {
        label: "P(burst)".into(),
        points: points.iter().map(|p| (p.load, p.probability.p)).collect(),
        color: 1,
        style: Style::Line,
    }];
    for (i, p) in points.iter().enumerate() {
        let (lo, hi) = p.probability.interval;
        series.push(Series {
            label: if i == 0 {
                format!("{:.0} % Wilson interval", 100.0 * p.probability.level)
            } else {
                String::new()
            },
            points: vec![(p.load, lo), (p.load, hi)],
            color: 0,
            style: Style::Thin,
        });
    }
    let nominal = points.iter().find(|p| p.factor == 1.0).map(|p| p.load);
    let samples = points.first().map_or(0, |p| p.probability.samples);
    Figure {
        name: "load-curve".into(),
        caption: format!(
            "P(burst) of the spread drive against its load amplitude {load}, the other \
             tolerances unchanged (the load's own band scales with it), {samples} samples at each \
             load, the same points at every load. Where the curve leaves zero is the load the \
             design can take with its manufacturing spread."
        ),
        size: (1000, 600),
        panels: vec![Panel {
            title: format!("P(burst) against the load amplitude {load}"),
            x_label: load.into(),
            y_label: "P(burst)".into(),
            y_range: Some((0.0, 1.0)),
            series,
            vlines: nominal
                .map(|x| vec![(x, "nominal load".into())])
                .unwrap_or_default(),
            legend_left: true,
            ..Panel::default()
        }],
        map: None,
    }
}
