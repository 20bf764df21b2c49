//! The fit's figure: the data with the fitted law, and the residuals below.

use super::{DataKind, Fit};
use crate::output::plot::{Figure, Panel, Series, Style};

/// Measured and fitted torque against speed or twist (a loop's points joined in path order), and
/// the weighted residuals: structure in them (a trend, a kink at a reversal) is what the law
/// leaves out.
pub fn figure(fit: &Fit, name: &str) -> Figure {
    let x_label = match fit.kind {
        DataKind::Friction => "speed [rad/s]",
        DataKind::Loop => "twist [rad]",
    };
    let mut order: Vec<usize> = (0..fit.x.len()).collect();
    if fit.kind == DataKind::Friction {
        order.sort_by(|&i, &j| fit.x[i].total_cmp(&fit.x[j]));
    }
    let pts = |y: &[f64]| order.iter().map(|&i| (fit.x[i], y[i])).collect::<Vec<_>>();
    let data = Panel {
        title: format!(
            "{} fit: {} parameters, noise {:.3e}",
            fit.kind.name(),
            fit.estimates.len(),
            fit.noise
        ),
        x_label: x_label.into(),
        y_label: "torque [N m]".into(),
        series: vec![
            Series {
                label: "measured".into(),
                points: pts(&fit.measured),
                color: 0,
                style: Style::Points,
            },
            Series {
                label: "fitted".into(),
                points: pts(&fit.predicted),
                color: 1,
                style: Style::Line,
            },
        ],
        legend_left: true,
        ..Panel::default()
    };
    let residuals = Panel {
        title: "residuals (fitted − measured, weighted)".into(),
        x_label: x_label.into(),
        y_label: "residual".into(),
        series: vec![Series {
            label: String::new(),
            points: pts(&fit.residuals),
            color: 0,
            style: Style::Points,
        }],
        ..Panel::default()
    };
    Figure {
        name: name.into(),
        caption: "The measured torque with the fitted law, and the residuals: they should scatter \
                  without structure around 0."
            .into(),
        size: (900, 900),
        panels: vec![data, residuals],
        map: None,
    }
}
