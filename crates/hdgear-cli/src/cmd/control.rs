//! `hdgear control`: feedback laws against the bursts, each tuned to its least gain (or assessed
//! at a given gain), side by side with what they cost.

use crate::cli::{BurstArgs, ParamArgs};
use crate::sink::{out, outln, warn};
use anyhow::Result;
use clap::Args;
use hdgear::control::{Comparison, compare};

/// Arguments of `hdgear control`.
#[derive(Args, Debug)]
pub struct ControlArgs {
    /// The laws: vstiffness (ũ = −k_p x), vdamping (ũ = −k_d x'), washout (ũ = −k_w (x − ξ),
    /// ξ' = ω_w (x − ξ)); all three without any.
    #[arg(value_name = "LAW")]
    pub laws: Vec<String>,
    /// Assess each law at this gain instead of tuning it to its least gain that removes the
    /// bursts.
    #[arg(long, allow_negative_numbers = true)]
    pub gain: Option<f64>,
    /// The washout filter's corner frequency ω_w (the term's default without it).
    #[arg(long, allow_negative_numbers = true)]
    pub ww: Option<f64>,
    /// Relative width of a tuned gain's final bracket.
    #[arg(long, default_value_t = 1e-3)]
    pub rel_tol: f64,
    /// JSON instead of text.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub params: ParamArgs,
    #[command(flatten)]
    pub burst: BurstArgs,
}

/// Runs `hdgear control`.
pub fn run(a: ControlArgs) -> Result<()> {
    let (p, warnings) = a.params.resolve()?;
    let opts = a.burst.options()?;
    warn(&warnings);
    let laws: Vec<&str> = a.laws.iter().map(String::as_str).collect();
    let doc = compare(&p, &laws, a.gain, a.ww, &opts, a.rel_tol)?;
    if a.json {
        outln!("{}", serde_json::to_string_pretty(&doc)?);
    } else {
        out!("{}", text(&doc));
    }
    Ok(())
}

/// The side-by-side table.
fn text(doc: &Comparison) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let p = &doc.params;
    let _ = writeln!(
        s,
        "control at α = {}, γ = {}, ε = {}, μ = {}, δ = {}, ω = {}",
        p.alpha, p.gamma, p.eps, p.mu, p.delta, p.omega
    );
    let first = doc
        .tunings
        .first()
        .map(|t| &t.tuned)
        .or(doc.assessments.first());
    if let Some(a) = first {
        let _ = writeln!(
            s,
            "open loop: {}, peak |x'| {:.4}",
            a.open_verdict.name(),
            a.open_peak_xdot
        );
    }
    if !doc.tunings.is_empty() {
        let _ = writeln!(
            s,
            "each law at its least gain that removes the bursts (the gain below it still bursts):"
        );
    }
    let _ = writeln!(
        s,
        "{:<11} {:>10} {:>10} {:<10} {:>7} {:>8} {:>9} {:>9} {:>10} {:>7} {:>7}",
        "law", "gain", "below", "verdict", "peak", "energy", "effort", "rms", "mean", "a=±1", "max"
    );
    let _ = writeln!(
        s,
        "{:<11} {:>10} {:>10} {:<10} {:>7} {:>8} {:>9} {:>9} {:>10} {:>7} {:>7}",
        "", "", "", "", "/open", "dB", "peak |ũ|", "ũ", "ũ", "shift", "shift"
    );
    let rows = doc
        .tunings
        .iter()
        .map(|t| (&t.tuned, Some(t.below.gain)))
        .chain(doc.assessments.iter().map(|a| (a, None)));
    for (a, below) in rows {
        let _ = writeln!(
            s,
            "{:<11} {:>10.5} {:>10} {:<10} {:>7.3} {:>8.1} {:>9.4} {:>9.4} {:>10.2e} {:>6.2}% {:>6.2}%",
            a.term.kind(),
            a.gain,
            below.map_or("-".into(), |b| format!("{b:.5}")),
            a.verdict.name(),
            a.peak_ratio(),
            a.fast_energy_db,
            a.effort_peak,
            a.effort_rms,
            a.effort_mean,
            100.0 * a.static_shift,
            100.0 * a.max_shift
        );
    }
    if let Some(f) = &doc.feedforward {
        let _ = writeln!(
            s,
            "feed-forward of the load, ũ = −κδ sin(ωτ + Δφ): no bursts while |1 − κ e^(iΔφ)| ≤ {:.4} \
             (amplitude error ≤ {:.1} % at the exact phase, phase error ≤ {:.1}° at the exact \
             amplitude), peak |ũ| = δ = {}",
            f.residual_limit,
            100.0 * f.max_amplitude_error,
            f.max_phase_error.to_degrees(),
            f.effort_peak
        );
    }
    s.push_str(
        "peak: closed-loop peak |x'| over the open loop's; energy: the fast mode's about the moving \
         equilibrium, closed over open; ũ: the control torque on μ's scale (a non-zero mean drives \
         the rigid-body mode); shift: the change of x over the curve's extent X at the load's \
         extremes and anywhere\n",
    );
    s
}
