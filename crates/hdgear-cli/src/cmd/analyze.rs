//! `hdgear analyze`: the fast subsystem, the prediction, the measured response.

use crate::cli::{AnalyzeArgs, parse_range};
use crate::sink::{note, warn, warn_range};
use anyhow::Result;

pub fn run(a: AnalyzeArgs) -> Result<()> {
    let (p, warnings) = a.params.resolve()?;
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
