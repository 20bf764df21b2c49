//! The figures of one model's report (`hdgear report --config FILE`): its response over one slow
//! period, the response over its equilibrium curve, its periodic orbit.

use super::decimate;
use crate::burst::{Classification, Response};
use crate::fast::{A_RANGE, StaticCurve};
use crate::output::num;
use crate::output::plot::{Figure, Panel, Series, Style};
use crate::periodic::{PeriodicOrbit, Stability};
use crate::simulate::StateSample;

/// x(τ) and x'(τ) over the sampled slow period, bursts shaded.
pub fn response_figure(samples: &[StateSample], response: &Response, c: &Classification) -> Figure {
    let (t0, t1) = (
        samples.first().map_or(0.0, |s| s.t),
        samples.last().map_or(0.0, |s| s.t),
    );
    let shaded: Vec<(f64, f64, usize)> = response
        .bursts
        .iter()
        .filter(|b| b.onset < t1)
        .map(|b| (b.onset.max(t0), b.end.min(t1), 1))
        .collect();
    let label = if shaded.is_empty() { "" } else { "burst" };
    let panel = |y: &str, f: fn(&StateSample) -> f64| {
        let points: Vec<(f64, f64)> = samples.iter().map(|s| (s.t, f(s))).collect();
        let tol = 1e-3 * super::span_of(&points);
        Panel {
            title: format!("{y}(τ), one slow period"),
            x_label: "τ".into(),
            y_label: y.into(),
            x_range: Some((t0, t1)),
            series: vec![Series {
                label: String::new(),
                points: decimate(&points, tol),
                color: 0,
                style: Style::Line,
            }],
            shaded: shaded.clone(),
            shaded_label: label.into(),
            ..Panel::default()
        }
    };
    Figure {
        name: "response".into(),
        caption: format!(
            "The response from the default start over one slow period after the transient \
             (the window the verdict reads): {} (mode {}, mechanism {}), {} burst(s) per slow \
             period, peak |x'| = {}. Shaded: detected bursts.",
            c.verdict.name(),
            c.mode.name(),
            c.mechanism.name(),
            response
                .rates
                .bursts_per_period
                .map_or("no count (the fast motion never stops)".into(), num),
            num(response.rates.peak_abs_xdot)
        ),
        size: (1000, 800),
        panels: vec![panel("x", |s| s.x), panel("x'", |s| s.xdot)],
        map: None,
    }
}

/// The response in the (a, x) plane, a = sin ωτ, over the fast subsystem's equilibrium curve
/// a(x) = (g(x) − μ)/δ, its folds marked.
pub fn fast_slow_figure<C: StaticCurve>(c: &C, samples: &[StateSample], omega: f64) -> Figure {
    let ends = (c.roots(A_RANGE.0), c.roots(A_RANGE.1));
    let (lo, hi) = match (ends.0.first(), ends.1.last()) {
        (Some(&lo), Some(&hi)) if hi > lo => (lo, hi),
        _ => (-1.0, 1.0),
    };
    let n = 1000;
    let curve: Vec<(f64, f64)> = (0..=n)
        .map(|i| {
            let x = lo + (hi - lo) * f64::from(i) / f64::from(n);
            (c.a_at(x), x)
        })
        .collect();
    let path: Vec<(f64, f64)> = samples.iter().map(|s| ((omega * s.t).sin(), s.x)).collect();
    let markers = c
        .fold_band()
        .map(|(xm, xp)| {
            [xm, xp]
                .iter()
                .map(|&x| (c.a_at(x), x, "fold".to_string()))
                .collect()
        })
        .unwrap_or_default();
    let tol = 1e-4 * super::span_of(&path);
    Figure {
        name: "fast-slow".into(),
        caption: "The response in the plane of the slow variable a = sin ωτ and x, over the \
                  fast subsystem's equilibrium curve (the forcing frozen at a; for a term that \
                  sticks, the sliding centre line, not every rest point). Where the response \
                  leaves the curve, the fast motion takes over: a jump at a fold, an overshoot \
                  of a steep part, ringing about a focus, or a slip from a rest."
            .into(),
        size: (1000, 700),
        panels: vec![Panel {
            title: "x against a over the equilibrium curve".into(),
            x_label: "a".into(),
            y_label: "x".into(),
            series: vec![
                Series {
                    label: "equilibria x*(a)".into(),
                    points: curve,
                    color: 1,
                    style: Style::Thin,
                },
                Series {
                    label: "response".into(),
                    points: decimate(&path, tol),
                    color: 0,
                    style: Style::Line,
                },
            ],
            markers,
            ..Panel::default()
        }],
        map: None,
    }
}

/// The period-1 orbit in the phase plane and x(τ) over its period.
pub fn orbit_figure<S>(orbit: &PeriodicOrbit<S>, verdict: &Classification) -> Figure {
    let s = &orbit.samples;
    let plane: Vec<(f64, f64)> = s.iter().map(|q| (q[1], q[2])).collect();
    let x: Vec<(f64, f64)> = s.iter().map(|q| (q[0], q[1])).collect();
    let line = |points: Vec<(f64, f64)>| Series {
        label: String::new(),
        points: decimate(&points, 1e-3 * super::span_of(&points)),
        color: 0,
        style: Style::Line,
    };
    Figure {
        name: "orbit".into(),
        caption: format!(
            "The periodic orbit of period 2π/ω = {} found by shooting: in the phase plane and \
             x over one period. {}; the verdict on the orbit itself: {}.",
            num(orbit.period),
            match orbit.stability() {
                Stability::Stable => "Stable (both Floquet multipliers inside the unit circle)",
                Stability::Unstable =>
                    "Unstable (a Floquet multiplier on or outside the unit circle): the response \
                     need not settle on it",
                Stability::RestsAllPeriod =>
                    "At rest all period: the friction's sticking band holds the load throughout",
            },
            verdict.verdict.name()
        ),
        size: (1000, 500),
        panels: vec![
            Panel {
                title: "phase plane".into(),
                x_label: "x".into(),
                y_label: "x'".into(),
                series: vec![line(plane)],
                ..Panel::default()
            },
            Panel {
                title: "x over one period".into(),
                x_label: "τ".into(),
                y_label: "x".into(),
                series: vec![line(x)],
                ..Panel::default()
            },
        ],
        map: None,
    }
}
