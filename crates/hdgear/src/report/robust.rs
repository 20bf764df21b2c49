//! The report's section on design under manufacturing spread: the report's drive made soft
//! ([`ROBUST_DRIVE`]) with the default tolerance bands: P(burst) with its interval, the worst
//! corner and margin, which tolerance matters, P(burst) against the load, the resonance rule.

use super::markup::{cell, esc, num};
use crate::burst::BurstOptions;
use crate::error::Result;
use crate::output::plot::Figure;
use crate::physical::PhysicalParams;
use crate::robust::{AnalysisOptions, McOptions, Measure, Nominal, RobustAnalysis, Space, analyse};
use serde::Serialize;
use std::fmt::Write as _;

/// The drive of the section: the report's catalogue drive with k1 = 2000 N m/rad and a
/// disturbance T_am = 22 N m, burst-free at its nominal values and near its boundary.
pub const ROBUST_DRIVE: (f64, f64) = (2000.0, 22.0);

/// Samples of P(burst), rows of the Saltelli design, samples at each load of the load curve.
pub const ROBUST_SAMPLES: (u64, usize, u64) = (1024, 512, 256);

/// The section's figures' file stems, in order.
pub const ROBUST_FIGURES: [&str; 2] = ["sobol-bars", "load-curve"];

/// The section's numbers.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RobustEvidence {
    /// The analysis of [`ROBUST_DRIVE`] under the default bands.
    pub analysis: RobustAnalysis,
}

impl RobustEvidence {
    /// The drive `drive` with [`ROBUST_DRIVE`]'s k1 and T_am, analysed.
    pub fn compute(drive: &PhysicalParams, opts: &BurstOptions) -> Result<RobustEvidence> {
        let d = PhysicalParams {
            k1: ROBUST_DRIVE.0,
            t_am: ROBUST_DRIVE.1,
            ..*drive
        };
        let space = Space::new(Nominal::Drive(d), Space::drive_defaults(&d))?;
        let (samples, rows, load) = ROBUST_SAMPLES;
        let a = AnalysisOptions {
            mc: McOptions {
                samples,
                ..McOptions::default()
            },
            worst: true,
            sobol: Some(rows),
            importance: None,
            load_curve: Some(load),
            shard: None,
        };
        Ok(RobustEvidence {
            analysis: analyse(&space, opts, &a, |_| Ok(()))?,
        })
    }

    /// The Sobol bars and the load curve, named as [`ROBUST_FIGURES`].
    pub fn figures(&self) -> Vec<Figure> {
        let a = &self.analysis;
        let bars = a
            .sensitivity
            .as_ref()
            .and_then(crate::figures::sobol_figure);
        let load = a
            .load_curve
            .as_ref()
            .map(|l| crate::figures::load_figure(l, "T_am [N m]"));
        bars.into_iter()
            .chain(load)
            .zip(ROBUST_FIGURES)
            .map(|(mut f, name)| {
                f.name = name.into();
                f
            })
            .collect()
    }
}

/// The section's HTML.
pub(super) fn html(h: &mut String, ev: &RobustEvidence) {
    let a = &ev.analysis;
    let p = &a.probability;
    let _ = writeln!(
        h,
        "<section id=\"robust\"><h2>Design under manufacturing spread</h2><p>The drive of the \
         physical section with a soft k1 = {} N m/rad and a disturbance T_am = {} N m, burst-free \
         at its nominal values. Its parameters spread by the default bands, each an assumption \
         (the catalogues state no scatter):</p><table><tr><th>parameter</th><th>spread</th>\
         <th>source</th></tr>",
        ROBUST_DRIVE.0, ROBUST_DRIVE.1
    );
    for t in &a.space.tolerances {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td></tr>",
            t.target.name(),
            esc(&t.distribution.to_string()),
            esc(&t.source)
        );
    }
    let _ = writeln!(
        h,
        "</table><table id=\"robust-probability\"><tr><th>samples</th><th>bursting</th>\
         <th>P(burst)</th><th>{:.0} % Wilson interval</th></tr><tr><td>{}</td><td>{}</td>{}\
         <td>[{}, {}]</td></tr></table>",
        100.0 * p.level,
        p.samples,
        p.bursting,
        cell("p", p.p),
        num(p.interval.0),
        num(p.interval.1)
    );
    if let Some(w) = &a.worst {
        worst_html(h, a, w);
    }
    if let Some(s) = &a.sensitivity {
        sobol_html(h, s);
    }
    if let Some(r) = &a.resonance {
        resonance_html(h, r);
    }
    h.push_str("</section>\n");
}

fn worst_html(h: &mut String, a: &RobustAnalysis, w: &crate::robust::WorstCase) {
    let names: Vec<&str> = a.space.tolerances.iter().map(|t| t.target.name()).collect();
    let corner: Vec<String> = names
        .iter()
        .zip(&w.corners[w.worst].signs)
        .map(|(n, &s)| format!("{n} {}", if s > 0 { "high" } else { "low" }))
        .collect();
    let bands: Vec<String> = names
        .iter()
        .zip(&w.margin_percent)
        .map(|(n, (lo, hi))| format!("{n} {lo:+.2} % … {hi:+.2} %"))
        .collect();
    let _ = writeln!(
        h,
        "<p>Worst corner of the {} (closest to bursting): {}. Margin: burst-free with every \
         parameter within {} (the box scaled by <span data-key=\"margin\">{}</span>; {} \
         points inside it checked, {} with another verdict).</p>",
        w.corners.len(),
        corner.join(", "),
        bands.join(", "),
        w.margin.map_or("–".into(), num),
        w.interior_checked,
        w.interior_differing
    );
}

fn sobol_html(h: &mut String, s: &crate::robust::Sensitivity) {
    if let Some((_, Some(ix))) = s.measures.iter().find(|m| m.0 == Measure::Burst) {
        let _ = write!(
            h,
            "<table id=\"robust-sobol\"><tr><th>Sobol index of the verdict (N = {})</th>",
            s.n
        );
        for n in &s.parameters {
            let _ = write!(h, "<th>{n}</th>");
        }
        for (what, v) in [("first-order", &ix.first), ("total", &ix.total)] {
            let _ = write!(h, "</tr><tr><td>{what}</td>");
            for (n, e) in s.parameters.iter().zip(v) {
                h.push_str(&cell(&format!("{what}-{n}"), e.value));
            }
        }
        let (first, total): (f64, f64) = (
            ix.first.iter().map(|e| e.value).sum(),
            ix.total.iter().map(|e| e.value).sum(),
        );
        // the totals count each interaction once per parameter in it: a sum of totals well above
        // the sum of first-order indices (which is at most 1) means interactions carry much of
        // the variance
        let how = if total > 1.5 * first {
            "the totals sum to well above the first-order indices: the verdict depends on how the \
             parameters combine"
        } else {
            "the totals are close to the first-order indices: each parameter acts mostly alone"
        };
        let _ = writeln!(
            h,
            "</tr></table><p>Σ first-order = {}, Σ total = {}: {how} (figure \
             <a href=\"#fig-sobol-bars\">sobol-bars</a>). P(burst) against the load amplitude, \
             the other bands unchanged: figure <a href=\"#fig-load-curve\">load-curve</a>.</p>",
            num(first),
            num(total)
        );
    }
}

fn resonance_html(h: &mut String, r: &crate::robust::Resonance) {
    let rule: Vec<String> = crate::robust::APPLICATIONS
        .iter()
        .map(|&(name, hz)| {
            let ok = if r.lowest_hz >= hz { "passes" } else { "fails" };
            format!("{ok} {name} (≥ {hz} Hz)")
        })
        .collect();
    let _ = writeln!(
        h,
        "<p>The catalogue's selection rule, beside the verdict: f<sub>n</sub> = \
         √(k1/J<sub>o</sub>)/2π = {} Hz nominal, {} Hz at the band's soft, heavy edge; it \
         {}. The rule and the burst verdict answer different questions.</p>",
        num(r.nominal_hz),
        num(r.lowest_hz),
        rule.join(", ")
    );
}
