//! `hdgear model`: the assembled model, its parameters and the facts derived from its terms.

use crate::sink::{outln, warn};
use anyhow::Result;
use hdgear::control::Averaging;
use hdgear::model::Description;
use hdgear::model::branches::Branches;
use serde::Serialize;

use crate::sources::ParamArgs;
use clap::Args;

/// Arguments of `hdgear model`.
#[derive(Args, Debug)]
pub struct ModelArgs {
    #[command(flatten)]
    pub params: ParamArgs,
    /// Also give the quasi-static loading and unloading branches x±(a) of the steady loop under
    /// a ∈ [−1, 1]: breakaways, steepest points (spiking areas), folds; with --json every point.
    #[arg(long)]
    pub branches: bool,
    /// Print JSON (for programs) instead of text.
    #[arg(long)]
    pub json: bool,
}

/// What `model --json` prints: the description and, for a model with a fast periodic torque,
/// what averaging makes of it.
#[derive(Serialize)]
struct Doc {
    #[serde(flatten)]
    description: Description,
    #[serde(skip_serializing_if = "Option::is_none")]
    averaged: Option<Averaging>,
    #[serde(skip_serializing_if = "Option::is_none")]
    branches: Option<Branches>,
}

pub fn run(a: ModelArgs) -> Result<()> {
    let (_, model, warnings) = a.params.resolve_model()?;
    warn(&warnings);
    let d = model.describe();
    let averaged = Averaging::of(&model);
    let branches = a.branches.then(|| model.branches()).transpose()?;
    if a.json {
        let doc = Doc {
            description: d,
            averaged,
            branches,
        };
        outln!("{}", serde_json::to_string_pretty(&doc)?);
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
    print_facts(&d.facts)?;
    if let (Some(av), Some(fast)) = (averaged, model.dither()) {
        print_averaging(&av, fast)?;
    }
    if let Some(b) = &branches {
        print_branches(b)?;
    }
    Ok(())
}

/// The summary of the quasi-static branches.
fn print_branches(b: &Branches) -> Result<()> {
    outln!();
    outln!(
        "quasi-static branches under a from -1 to 1 and back (the steady loop, closed to {:.1e}):",
        b.closure
    );
    for (name, br) in [("loading", &b.loading), ("unloading", &b.unloading)] {
        outln!(
            "  {name:<9} {}; steepest at {}; {}; {} points",
            br.breakaway.map_or(
                "never leaves rest (the band holds the whole load)".into(),
                |a| format!("leaves rest at a = {a:.6}")
            ),
            br.min_stiffness
                .map_or("-".into(), |(a, k)| format!("a = {a:.6} (K_t = {k:.6})")),
            br.fold.map_or("no fold".into(), |a| format!(
                "a fold (a jump) at a = {a:.6}"
            )),
            br.points.len()
        );
    }
    Ok(())
}

/// The facts of the fast subsystem derived from the terms.
fn print_facts(f: &hdgear::model::Facts) -> Result<()> {
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

/// What averaging makes of a fast periodic torque [D, Ω].
fn print_averaging(av: &Averaging, [d, wd]: [f64; 2]) -> Result<()> {
    outln!(
        "fast periodic torque {d} at Ω = {wd} (Ω/√max g' = {:.3} on the averaged curve; \
         averaging needs it well above 1):",
        av.frequency_ratio
    );
    outln!(
        "  ripple ≈ {:.4e} on x; averaged stiffness γ = {}, ε = {}",
        av.ripple,
        av.params.gamma,
        av.params.eps
    );
    Ok(())
}
