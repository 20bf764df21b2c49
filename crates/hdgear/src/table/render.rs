//! Markdown and CSV renderings of the study's tables.

use super::Tables;
use crate::params::Param;
use std::fmt::Write;

fn g(v: f64) -> String {
    if v.is_infinite() {
        "inf".into()
    } else if v.is_nan() {
        "-".into()
    } else {
        format!("{v:.4}")
    }
}

/// Both tables as Markdown.
pub fn markdown(t: &Tables) -> String {
    let mut s = String::new();
    let b = &t.base;
    let _ = writeln!(
        s,
        "Study point: alpha = {}, eps = {}, mu = {}, delta = {}, omega = {} (gamma varies).\n",
        b.alpha, b.eps, b.mu, b.delta, b.omega
    );
    s.push_str("| gamma | equilibrium curve | largest dx/da | dx/da at a = 0 | bursts per period | spikes per burst | peak abs(x') | signature | mode (measured) | mechanism | study's mode |\n");
    s.push_str("|---|---|---|---|---|---|---|---|---|---|---|\n");
    for r in &t.gamma_table {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {}{} |",
            r.gamma,
            r.shape,
            g(r.max_slope),
            g(r.slope_at_a0),
            r.bursts_per_period,
            g(r.spikes_per_burst),
            g(r.peak_abs_xdot),
            r.verdict,
            r.mode,
            r.mechanism,
            r.study_mode,
            if r.agrees {
                ""
            } else {
                " (measurement disagrees)"
            }
        );
    }
    s.push_str("\n| parameter | low | high | burst amplitude low/high | spikes per burst low/high | quiescent duration low/high | spiking-area centre low/high | study's claim | verdict |\n");
    s.push_str("|---|---|---|---|---|---|---|---|---|\n");
    for r in &t.effects_table {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} / {} | {} / {} | {} / {} | {} / {} | {} | {} |",
            r.parameter,
            r.low,
            r.high,
            g(r.amplitude[0]),
            g(r.amplitude[1]),
            g(r.spikes[0]),
            g(r.spikes[1]),
            g(r.quiescent_duration[0]),
            g(r.quiescent_duration[1]),
            g(r.spiking_center[0]),
            g(r.spiking_center[1]),
            r.claim,
            if r.verdict == super::ClaimVerdict::Contradicts {
                format!("**contradicts**: {}", r.measured)
            } else {
                r.verdict.to_string()
            }
        );
    }
    s.push('\n');
    for r in &t.effects_table {
        let _ = writeln!(s, "- {}", r.measured);
    }
    s
}

/// Both tables as CSV: the γ table, a blank line, then the effects table (each with its header).
pub fn csv(t: &Tables) -> std::io::Result<String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        Param::Gamma.name(),
        "shape",
        "max_slope",
        "slope_at_a0",
        "bursts_per_period",
        "spikes_per_burst",
        "peak_abs_xdot",
        "verdict",
        "mode",
        "mechanism",
        "study_mode",
        "agrees",
    ])?;
    for r in &t.gamma_table {
        w.write_record([
            r.gamma.to_string(),
            r.shape.into(),
            r.max_slope.to_string(),
            r.slope_at_a0.to_string(),
            r.bursts_per_period.to_string(),
            r.spikes_per_burst.to_string(),
            r.peak_abs_xdot.to_string(),
            r.verdict.to_string(),
            r.mode.to_string(),
            r.mechanism.to_string(),
            r.study_mode.to_string(),
            r.agrees.to_string(),
        ])?;
    }
    let mut out =
        String::from_utf8(w.into_inner().map_err(|e| e.into_error())?).expect("csv writes UTF-8");
    out.push('\n');
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "parameter",
        "low",
        "high",
        "amplitude_low",
        "amplitude_high",
        "spikes_low",
        "spikes_high",
        "quiescent_low",
        "quiescent_high",
        "spiking_center_low",
        "spiking_center_high",
        "claim",
        "verdict",
        "measured",
    ])?;
    for r in &t.effects_table {
        w.write_record([
            r.parameter.to_string(),
            r.low.to_string(),
            r.high.to_string(),
            r.amplitude[0].to_string(),
            r.amplitude[1].to_string(),
            r.spikes[0].to_string(),
            r.spikes[1].to_string(),
            r.quiescent_duration[0].to_string(),
            r.quiescent_duration[1].to_string(),
            r.spiking_center[0].to_string(),
            r.spiking_center[1].to_string(),
            r.claim.into(),
            r.verdict.to_string(),
            r.measured.clone(),
        ])?;
    }
    out.push_str(&String::from_utf8(w.into_inner().map_err(|e| e.into_error())?).expect("UTF-8"));
    Ok(out)
}
