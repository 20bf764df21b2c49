//! `hdgear model`: the assembled model, its parameters and the facts derived from its terms.

use crate::cli::ModelArgs;
use crate::sink::{outln, warn};
use anyhow::Result;

pub fn run(a: ModelArgs) -> Result<()> {
    let (_, model, warnings) = a.params.resolve_model()?;
    warn(&warnings);
    let d = model.describe();
    if a.json {
        outln!("{}", serde_json::to_string_pretty(&d)?);
        return Ok(());
    }
    outln!("equation  {}", d.equation);
    outln!("LaTeX     {}", d.latex);
    outln!("states    {}", d.states.join(", "));
    outln!(
        "terms     {}",
        d.terms
            .iter()
            .map(|t| t.kind())
            .collect::<Vec<_>>()
            .join(", ")
    );
    outln!();
    outln!(
        "{:<10} {:<6} {:<5} {:>12} {:>10} {:<7} meaning",
        "term",
        "name",
        "sym",
        "value",
        "default",
        "domain"
    );
    for p in &d.parameters {
        outln!(
            "{:<10} {:<6} {:<5} {:>12} {:>10} {:<7} {}",
            p.term,
            p.info.name,
            p.info.symbol,
            format!("{}", p.value),
            format!("{}", p.info.default),
            p.info.domain.text(),
            p.info.meaning
        );
    }
    let f = d.facts;
    outln!();
    outln!("fast subsystem (forcing frozen at a), derived from the terms:");
    outln!(
        "  damping at rest c = {}{}",
        f.damping_at_rest,
        if f.damping_uniform {
            ""
        } else {
            " (the smallest: it varies with x)"
        }
    );
    outln!(
        "  Hopf bifurcation {}",
        if f.hopf_possible && f.damping_at_rest > 0.0 {
            "possible (a delayed feedback: its roots cross the imaginary axis as K·τ_d grows)"
        } else if f.hopf_possible {
            "possible (c ≤ 0 somewhere)"
        } else {
            "impossible (c > 0: the trace −c of the Jacobian never crosses 0)"
        }
    );
    outln!(
        "  focus above g' = c²/4 = {}, node below",
        f.focus_node_threshold
    );
    outln!(
        "  decay time 2/c = {} (ω·2/c = {:.3e})",
        f.decay_time,
        f.omega_decay
    );
    Ok(())
}
