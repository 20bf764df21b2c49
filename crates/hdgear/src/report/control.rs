//! The report's burst-control section: the laws tuned at the study's bursting points, x'(τ)
//! open against closed through the first burst, and the report's bursting drive with each law's
//! torque in N m.

use crate::burst::{BurstOptions, response};
use crate::control::{Comparison, ControlOptions, DriveControl, Ratings, compare, compare_drive};
use crate::error::Result;
use crate::figures::decimate;
use crate::model::Model;
use crate::output::plot::{Figure, Panel, Series, Style};
use crate::params::Params;
use crate::physical::PhysicalParams;
use crate::simulate::{SimOptions, Start, simulate_model};
use serde::Serialize;

/// The study's bursting points the laws are tuned at.
pub const CONTROL_GAMMAS: [f64; 2] = [1.0, 0.1];

/// The figure's file stem.
pub const CONTROL_FIGURE: &str = "control-xdot";

/// The card whose catalogue ratings stand in for the report drive's (the CSF cards carry none):
/// the same size, ratio and torsional-stiffness table.
pub const RATINGS_CARD: &str = "SHG-20-50";

/// The model error each tuned law's robustness is checked against (±20 %).
pub const SPREAD: f64 = 0.2;

/// A labelled trace: the loop's name and its points (τ, x').
pub type LabelledTrace = (String, Vec<(f64, f64)>);

/// The section's numbers.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ControlEvidence {
    /// The laws compared at each of [`CONTROL_GAMMAS`].
    pub study: Vec<Comparison>,
    /// The laws on the report's bursting drive, in N m.
    pub drive: DriveControl,
    /// x'(τ) through the first burst: per γ, the open loop then each law at its least gain.
    #[serde(skip)]
    pub traces: Vec<Vec<LabelledTrace>>,
}

impl ControlEvidence {
    /// The laws tuned at [`CONTROL_GAMMAS`] (with `base`'s other parameters) and on `variant`.
    pub fn compute(
        base: &Params,
        variant: &PhysicalParams,
        opts: &BurstOptions,
    ) -> Result<ControlEvidence> {
        let c = ControlOptions {
            spread: Some(SPREAD),
            ..ControlOptions::default()
        };
        use rayon::prelude::*;
        let stand_in = crate::physical::card::builtin_card(RATINGS_CARD)?;
        let ratings = Ratings::of(
            stand_in.torque.as_ref(),
            format!(
                "{RATINGS_CARD}'s catalogue ratings stand in: the same size, ratio and \
                 stiffness table; the CSF rating table was not read, and CSF, the standard \
                 version, is rated lower than the high-torque CSG whose row {RATINGS_CARD}'s \
                 equals"
            ),
        );
        // the γ cases and the drive are independent: side by side
        let (study, drive) = rayon::join(
            || {
                CONTROL_GAMMAS
                    .par_iter()
                    .map(|&gamma| compare(&Params { gamma, ..*base }, &[], &c, opts))
                    .collect::<Result<Vec<_>>>()
            },
            || compare_drive(variant, ratings, &[], &c, opts),
        );
        let (study, drive) = (study?, drive?);
        let traces = study
            .par_iter()
            .map(|cmp| traces(cmp, opts))
            .collect::<Result<Vec<_>>>()?;
        Ok(ControlEvidence {
            study,
            drive,
            traces,
        })
    }

    /// x'(τ) open against closed, a panel per γ.
    pub fn figure(&self) -> Figure {
        let panels = self
            .study
            .iter()
            .zip(&self.traces)
            .map(|(cmp, series)| {
                let span = series
                    .iter()
                    .flat_map(|s| s.1.iter().map(|q| q.1.abs()))
                    .fold(1e-12, f64::max);
                Panel {
                    title: format!(
                        "γ = {}: the first burst, open loop and each law at its least gain",
                        cmp.params.gamma
                    ),
                    x_label: "τ".into(),
                    y_label: "x'".into(),
                    series: series
                        .iter()
                        .enumerate()
                        .map(|(i, (label, pts))| Series {
                            label: label.clone(),
                            points: decimate(pts, 1e-3 * span),
                            color: i,
                            style: if i == 0 { Style::Thin } else { Style::Line },
                        })
                        .collect(),
                    ..Panel::default()
                }
            })
            .collect();
        Figure {
            name: CONTROL_FIGURE.into(),
            caption: "x'(τ) through the open loop's first burst at γ = 1 and 0.1: the open loop \
                      (thin: the pulse, then ringing) against virtual stiffness, virtual damping, \
                      washout and scheduled stiffness, each at its least gain that removes the \
                      bursts. Virtual stiffness flattens the curve: its pulse comes earlier. \
                      Virtual damping keeps the pulse's time and ends the ringing. The washout \
                      keeps the curve and lags it: its pulse comes latest, with small ripples \
                      after it. The scheduled stiffness stiffens the curve's soft middle only: \
                      the passage spreads into two shallow humps, the lowest peak of the four."
                .into(),
            size: (1000, 800),
            panels,
            map: None,
        }
    }
}

/// Spacing of the traces' samples (as the control measures').
pub(super) const TRACE_DT: f64 = crate::control::SAMPLE_DT;

/// Time shown before the open loop's first burst's onset and after it.
const TRACE_SPAN: (f64, f64) = (20.0, 60.0);

/// x'(τ) around the open loop's first burst in the window: the open loop, then each tuned law.
fn traces(cmp: &Comparison, opts: &BurstOptions) -> Result<Vec<LabelledTrace>> {
    let p = &cmp.params;
    let open = response(p, opts)?;
    let onset = open.bursts.first().map_or(open.window_start, |b| b.onset);
    let (t0, t1) = (onset - TRACE_SPAN.0, onset + TRACE_SPAN.1);
    let mut loops = vec![("open loop".to_string(), Model::study(p))];
    for t in &cmp.tunings {
        loops.push((
            format!("{} {:.3}", t.law, t.tuned.gain),
            crate::control::closed_loop(p, t.tuned.term)?,
        ));
    }
    loops
        .into_iter()
        .map(|(label, m)| Ok((label, samples(&m, (t0, t1), opts, 1)?)))
        .collect()
}

/// (τ, y\[i\]) of `m` run from its equilibrium, every [`TRACE_DT`] from t0 to t1.
pub(super) fn samples(
    m: &Model,
    (t0, t1): (f64, f64),
    opts: &BurstOptions,
    i: usize,
) -> Result<Vec<(f64, f64)>> {
    let sim = SimOptions {
        t_end: t1,
        dt: TRACE_DT,
        start: Start::Equilibrium,
        tol: opts.tol,
    };
    let mut pts = Vec::new();
    simulate_model(m, &sim, |t, y| {
        if t >= t0 {
            pts.push((t, y[i]));
        }
    })?;
    Ok(pts)
}
