//! `hdgear analyze`: the fast subsystem, the prediction, the measured response.

use crate::args::parse_range;
use crate::sink::{note, warn, warn_range};
use anyhow::Result;
use hdgear::model::Model;
use hdgear::model::Subject;
use hdgear::params::Warning;

use crate::args::BurstArgs;
use crate::sources::ParamArgs;
use clap::Args;

/// Arguments of `hdgear analyze`.
#[derive(Args, Debug)]
pub struct AnalyzeArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    /// Range of the slow variable a, as A0:A1.
    #[arg(long, default_value = "-1:1", allow_hyphen_values = true)]
    pub a_range: String,
    /// Print one JSON document instead of the readable summary.
    #[arg(long)]
    pub json: bool,
    /// Skip the simulated response and its classification (fast-subsystem analysis only).
    #[arg(long)]
    pub no_response: bool,
    /// Also locate the simulated bursting boundaries in gamma and omega through this point, where
    /// the simulated verdict switches, from the predicted ones (under a second at the study's
    /// point; longer at small omega, which is slow to simulate).
    #[arg(long)]
    pub simulated_boundaries: bool,
    #[command(flatten)]
    pub burst: BurstArgs,
}

pub fn run(a: AnalyzeArgs) -> Result<()> {
    let (system, warnings) = a.params.resolve_system()?;
    match system {
        Subject::Study(p) => run_study(p, warnings, a),
        Subject::Model(m) => run_model(&m, warnings, &a),
    }
}

/// A model with terms: its equilibrium curve's analysis at its own damping at rest, and the
/// measured response against that curve.
fn run_model(m: &Model, warnings: Vec<Warning>, a: &AnalyzeArgs) -> Result<()> {
    let range = parse_range(&a.a_range)?;
    let opts = a.burst.options()?;
    if a.simulated_boundaries {
        anyhow::bail!(
            "--simulated-boundaries searches the study's gamma and omega for the switch of the \
             verdict: for a model with terms ({}) it is not computed",
            term_kinds(m)
        );
    }
    let remarks = warnings.iter().map(ToString::to_string).collect();
    let response = (!a.no_response).then_some(&opts);
    let doc = hdgear::study::analyze_model(m, range, response, remarks)?;
    warn_range(range);
    if let Some(r) = &doc.response {
        crate::sink::tolerance_note(r, &opts.tol);
    }
    if a.json {
        crate::sink::outln!("{}", serde_json::to_string_pretty(&doc)?);
        return Ok(());
    }
    warn(&warnings);
    if let Some(kind) = m.terms().find(|t| t.switches_at_rest()).map(|t| t.kind()) {
        note(&format!(
            "the {kind} term sticks: at rest x stays wherever the load is within its breakaway \
             of the static torque, so the curve below is the sliding centre line, not every rest \
             point"
        ));
    }
    crate::sink::outln!("model {}", m.equation());
    crate::sink::out!("{}", crate::summary::curve_analysis_text(&doc.analysis));
    if let (Some(r), Some(c)) = (&doc.response, &doc.classification) {
        crate::sink::out!("{}", crate::summary::response_text(r, c));
    }
    Ok(())
}

/// The kinds of a model's terms beyond the study's damping and stiffness, comma-separated.
fn term_kinds(m: &Model) -> String {
    m.terms()
        .map(|t| t.kind())
        .filter(|k| Model::is_extra_kind(k))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The study's model: the cubic's closed forms, the prediction and the measured response.
fn run_study(p: hdgear::Params, warnings: Vec<Warning>, a: AnalyzeArgs) -> Result<()> {
    let range = parse_range(&a.a_range)?;
    let opts = a.burst.options()?;
    let an = hdgear::fast::analyze(&p, range)?;
    warn_range(range);
    let measured = if a.no_response {
        None
    } else {
        let r = hdgear::burst::response(&p, &opts)?;
        let c = hdgear::burst::classify(&p, &r);
        crate::sink::tolerance_note(&r, &opts.tol);
        if !c.fast_slow_domain {
            let e = hdgear::burst::fast_slow_edge(&p);
            let s = e.slowest;
            let why = match e.limit {
                // within both conditions: only the measured motion put it outside
                _ if p.omega <= e.omega_max => {
                    "the fast motion never stops between passages".into()
                }
                hdgear::burst::DomainLimit::Ordering => format!(
                    "omega >= r = {:.4e}, the slowest relaxation rate on the traversed path ({}), \
                     at a = {:.6}: the time scales exchange roles there",
                    s.rate,
                    s.along.name(),
                    s.a
                ),
                hdgear::burst::DomainLimit::Settling => format!(
                    "omega > r/10, r = {:.3} the relaxation rate at a = ±1, where the state settles",
                    e.turning_point_rate
                ),
            };
            note(&format!(
                "omega = {:?} is not slow against the fast subsystem ({why}{}): the fast-slow \
                 picture does not apply, mode not-fast-slow",
                p.omega,
                if r.continuous_fast_motion && p.omega > e.omega_max {
                    ", and the fast motion never stops"
                } else {
                    ""
                }
            ));
        }
        Some((r, c))
    };
    let bounds = if a.simulated_boundaries {
        Some(hdgear::burst::boundaries(&p, &opts)?)
    } else {
        None
    };
    if a.json {
        let (response, classification) = measured.unzip();
        let doc = hdgear::study::PointAnalysis {
            analysis: an,
            response,
            classification,
            boundaries: bounds,
            warnings: warnings.iter().map(ToString::to_string).collect(),
        };
        crate::sink::outln!("{}", serde_json::to_string_pretty(&doc)?);
    } else {
        warn(&warnings);
        crate::sink::out!("{}", crate::summary::analysis_text(&an));
        if let Some((r, c)) = &measured {
            crate::sink::out!("{}", crate::summary::response_text(r, c));
        }
        if let Some(b) = &bounds {
            let g = |v: Option<f64>| v.map_or("none".to_string(), |v| format!("{v:.4}"));
            let w = |v: Option<f64>| v.map_or("none".to_string(), |v| format!("{v:.4e}"));
            crate::sink::outln!(
                "bursting boundary in gamma: predicted {}, simulated {}; in omega: predicted {}, simulated {}",
                g(b.predicted_gamma),
                g(b.simulated_gamma),
                w(Some(b.predicted_omega)),
                w(b.simulated_omega)
            );
        }
    }
    Ok(())
}
