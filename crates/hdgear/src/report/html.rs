//! The report as HTML: one function per section, each reading the computed [`Report`]. The
//! methods text takes its numbers from the options and constants it describes.
//!
//! **Why one file.** One function per section of one document, in the document's order, sharing the
//! page's markup helpers: reading this file top to bottom is reading the report.

// HTML blocks end with a newline of their own, for a readable source.
#![allow(clippy::write_with_newline)]

use super::markup::{cell, esc, num};
use super::periodic::{BUBBLE_GAMMA, BUBBLE_OMEGA};
use super::{PHYSICAL_DRIVE, Report};
use crate::burst::{BOUNDARY_REL_TOL, TIME_SCALE_SEPARATION};
use crate::fast::{FORCING_RATE_THRESHOLD, NO_HOPF_REASON, StaticCurve};
use crate::params::{Param, Params};
use std::fmt::Write as _;

/// `index.html` of `r`, with the figures' SVG texts `svgs` (in [`super::FIGURES`] order) inline.
pub fn render(r: &Report, svgs: &[String]) -> String {
    let mut h = String::new();
    head(&mut h);
    summary(&mut h, r);
    model(&mut h, r);
    corrections(&mut h, r);
    h.push_str("<section id=\"tables\"><h2>The study's tables, measured</h2>");
    gamma_table(&mut h, r);
    effects_table(&mut h, r);
    h.push_str("</section>\n");
    figures(&mut h, r, svgs);
    mechanism(&mut h, r);
    boundaries(&mut h, r);
    physical(&mut h, r);
    periodic(&mut h, r);
    control(&mut h, r);
    super::robust::html(&mut h, &r.robust);
    super::memory::html(&mut h, &r.memory);
    methods(&mut h, r);
    h
}

/// The six dimensionless parameters as table cells, in the order α, γ, ε, μ, δ, ω.
fn param_cells(p: &Params) -> String {
    crate::params::Param::ALL
        .iter()
        .map(|&n| cell(n.name(), p.value(n)))
        .collect()
}

/// The rows of a design check's margin table.
pub(super) fn margin_rows(c: &crate::physical::design::DesignCheck) -> String {
    c.margins
        .iter()
        .map(|m| {
            let side = |s: &Option<crate::physical::design::BracketEnd>| {
                s.map_or("–".into(), |s| s.to_string())
            };
            format!(
                "<tr><td>{}</td>{}<td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n",
                m.parameter,
                cell("current", m.current),
                m.boundary_value.map_or_else(
                    || {
                        m.refused
                            .clone()
                            .unwrap_or_else(|| "none within ×1/64…×64".into())
                    },
                    num
                ),
                m.change_percent
                    .map_or("–".into(), |c| format!("{c:+.1} % ({})", m.effect)),
                side(&m.inside),
                side(&m.outside)
            )
        })
        .collect()
}

const CSS: &str = "body{font-family:'DejaVu Sans',Verdana,sans-serif;max-width:1060px;margin:2em auto;padding:0 1em;color:#222;line-height:1.5}
h1{font-size:1.7em}h2{border-bottom:2px solid #0072b2;padding-bottom:.2em;margin-top:2em}
table{border-collapse:collapse;margin:1em 0;font-size:.92em}th,td{border:1px solid #bbb;padding:.3em .6em;text-align:left;vertical-align:top}
th{background:#eef4f9}td[data-value]{text-align:right;font-variant-numeric:tabular-nums}
figure{margin:1.5em 0;border:1px solid #ddd;padding:.5em}figure svg{width:100%;height:auto}figcaption{font-size:.95em;color:#333;margin-top:.4em}
.eq{font-family:'DejaVu Sans Mono',monospace;background:#f6f6f6;padding:.5em 1em;display:block;white-space:pre-wrap}
.bad{color:#b00020;font-weight:bold}.good{color:#007a3d;font-weight:bold}code{background:#f3f3f3;padding:0 .2em}
nav a{margin-right:1em}";

/// The study report's page start.
fn head(h: &mut String) {
    page_start(
        h,
        "hdgear report: fast-slow oscillations of a harmonic drive",
        "Fast-slow oscillations of a harmonic drive gear: the study reproduced",
        &[
            ("model", "Model"),
            ("corrections", "Corrections"),
            ("tables", "Tables"),
            ("figures", "Figures"),
            ("mechanism", "Mechanism"),
            ("physical", "Physical drive"),
            ("periodic", "Periodic response"),
            ("methods", "Methods"),
        ],
    );
}

/// The page's start: doctype, `title`, the style sheet, the heading `h1` and a navigation bar
/// of (anchor, label) links. Shared by the study's report and a model's.
pub(super) fn page_start(h: &mut String, title: &str, h1: &str, nav: &[(&str, &str)]) {
    let links: String = nav
        .iter()
        .map(|(id, label)| format!("<a href=\"#{id}\">{label}</a>"))
        .collect();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{}</title>\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><style>{CSS}</style></head><body>\n\
         <h1>{}</h1>\n<nav>{links}</nav>\n",
        esc(title),
        esc(h1)
    );
}

/// The summary: what was measured, and whether the study holds.
fn summary(h: &mut String, r: &Report) {
    let (base, t) = (&r.options.base, &r.tables);
    let gc = base.critical_gamma();
    let agree_all = t.gamma_table.iter().all(|r| r.agrees);
    let contradicted: Vec<&str> = t
        .effects_table
        .iter()
        .filter(|r| r.verdict != crate::table::ClaimVerdict::Agrees)
        .map(|r| r.parameter)
        .collect();
    let _ = write!(
        h,
        "<section id=\"summary\"><h2>Summary</h2><p>The dimensionless harmonic drive model of Han, Huang, Ding &amp; Bi (2022) \
         was simulated and its fast subsystem analysed by hdgear {}. Bursting is judged by the three signatures the fast \
         mode can show (a jump across the folds, an overshoot of the equilibrium, ringing about it), and the modes are \
         defined from them so that they keep their meaning as ω changes. Measured: {}. The study's modes are reproduced {}. \
         None of the four γ values has a fold \
         (they all exceed 1/(3α) = {:.4}) and no Hopf bifurcation can occur at all, yet γ = 1 and 0.1 burst twice per slow \
         period: the bursts come from a sharp quantitative change — a nearly vertical part of the equilibrium curve — \
         not from a bifurcation, and they vanish as ω → 0, as Fenichel's theorem requires. Of the study's parameter claims, {}.</p></section>\n",
        env!("CARGO_PKG_VERSION"),
        t.gamma_table
            .iter()
            .map(|r| format!("γ = {} {} ({})", r.gamma, r.mode, r.verdict))
            .collect::<Vec<_>>()
            .join(", "),
        if agree_all {
            "<span class=\"good\">exactly</span>".to_string()
        } else {
            format!(
                "<span class=\"bad\">except where marked</span>: at ω = {} a response with no signature at all \
                 follows its equilibrium with the first-order adiabatic lag, which shrinks with ω, so the study's \
                 \"transitional\" for such a response (γ = 10) is not a distinct response mode",
                base.omega
            )
        },
        gc,
        if contradicted.is_empty() {
            "all hold as measured".to_string()
        } else {
            format!(
                "the one on {} is <span class=\"bad\">contradicted</span> by the measurements; the others hold",
                contradicted.join(", ")
            )
        }
    );
}

/// The model and the study's point.
fn model(h: &mut String, r: &Report) {
    let base = &r.options.base;
    let gc = base.critical_gamma();
    let _ = write!(
        h,
        "<section id=\"model\"><h2>Model and parameters</h2>\
         <span class=\"eq\">x'' + x' + α x³ − x² + γ (x − ε) = μ + δ sin(ω τ)\n\
         fast subsystem (a = sin ωτ frozen):  x'' + x' + g(x) = μ + δ a,   g(x) = α x³ − x² + γ (x − ε)</span>\
         <table><tr><th>parameter</th><th>α</th><th>γ</th><th>ε</th><th>μ</th><th>δ</th><th>ω</th></tr>\
         <tr><td>study's point</td>{}</tr></table>\
         <p>γ varies over 30, 10, 1, 0.1 where the study varies it; everything else is fixed unless a table or figure says \
         otherwise. The critical value 1/(3α) = {:.6} is where the fast subsystem acquires folds (a cusp).</p></section>\n",
        param_cells(base),
        gc
    );
}

/// The corrections to the study, with the reduction check's number.
fn corrections(h: &mut String, r: &Report) {
    let (base, ph) = (&r.options.base, &r.physical);
    let _ = write!(
        h,
        "<section id=\"corrections\"><h2>Corrections to the study</h2><ul>\
         <li>The disturbance amplitude is δ = k2 φ J³ T_am/(J_o C<sup>4</sup>): the study prints C², which is not dimensionless. \
         Checked by simulation: the two-inertia model of a {PHYSICAL_DRIVE} drive and its reduced model agree, θ(t) = L·x(t/T), to \
         {:.1e} relative over 300 time units.</li>\
         <li>α·ε = 1 identically for every physical drive. The study's set has α·ε = {:.2}, so no drive reduces to it; it is \
         studied here as a dimensionless model (hdgear warns about such sets).</li>\
         <li>A zero-backlash drive (φ = 0) has no reduction: the length scale L = C²/(J k2 φ) is undefined. hdgear says so and \
         simulates the physical model instead.</li>\
         <li>With the usual sign convention the discriminant of the cubic is <i>negative</i> where there is one equilibrium; the \
         study's \"Δ &gt; 0\" uses the opposite convention.</li></ul></section>\n",
        ph.reduction_check.theta,
        base.alpha * base.eps
    );
}

/// The γ table.
fn gamma_table(h: &mut String, r: &Report) {
    let t = &r.tables;
    // γ table
    let _ = write!(
        h,
        "<h3>Equilibrium curve and oscillation mode against γ</h3>\
         <table id=\"gamma-table\"><tr><th>γ</th><th>equilibrium curve</th><th>largest |dx/da|</th><th>dx/da at a = 0</th>\
         <th>bursts per period</th><th>spikes per burst</th><th>peak |x'|</th><th>mode (measured)</th><th>mechanism</th><th>study</th></tr>\n"
    );
    for r in &t.gamma_table {
        let _ = writeln!(
            h,
            "<tr data-gamma=\"{}\">{}<td>{}</td>{}{}{}{}{}<td data-key=\"mode\">{}</td><td>{}</td><td>{}{}</td></tr>",
            r.gamma,
            cell(Param::Gamma.name(), r.gamma),
            esc(r.shape),
            cell("max_slope", r.max_slope),
            cell("slope_at_a0", r.slope_at_a0),
            cell("bursts_per_period", r.bursts_per_period),
            cell("spikes_per_burst", r.spikes_per_burst),
            cell("peak_abs_xdot", r.peak_abs_xdot),
            r.mode,
            r.mechanism,
            r.study_mode,
            if r.agrees {
                " <span class=\"good\">✓</span>"
            } else {
                " <span class=\"bad\">✗ (measurement disagrees)</span>"
            }
        );
    }
    h.push_str("</table><p>Curve words come from the largest slope in decades (&lt; 1 smooth and gradual, 1–10 moderately steep, \
                10–100 very steep with a sharp turn, ≥ 100 extremely steep, near-vertical).</p>\n");
}

/// The parameter-effects table.
fn effects_table(h: &mut String, r: &Report) {
    let t = &r.tables;
    let _ = write!(
        h,
        "<h3>Parameter effects (each parameter halved and doubled around the study's point)</h3>\
         <table id=\"effects-table\"><tr><th rowspan=\"2\">parameter</th><th rowspan=\"2\">low</th><th rowspan=\"2\">high</th>\
         <th colspan=\"2\">burst amplitude</th><th colspan=\"2\">spikes per burst</th><th colspan=\"2\">quiescent duration</th>\
         <th colspan=\"2\">spiking-area centre (a)</th><th rowspan=\"2\">study's claim</th><th rowspan=\"2\">verdict</th></tr>\
         <tr><th>low</th><th>high</th><th>low</th><th>high</th><th>low</th><th>high</th><th>low</th><th>high</th></tr>\n"
    );
    for r in &t.effects_table {
        let _ = writeln!(
            h,
            "<tr data-parameter=\"{}\"><td>{}</td>{}{}{}{}{}{}{}{}{}{}<td>{}</td><td>{}</td></tr>",
            r.parameter,
            r.parameter,
            cell("low", r.low),
            cell("high", r.high),
            cell("amplitude_low", r.amplitude[0]),
            cell("amplitude_high", r.amplitude[1]),
            cell("spikes_low", r.spikes[0]),
            cell("spikes_high", r.spikes[1]),
            cell("quiescent_low", r.quiescent_duration[0]),
            cell("quiescent_high", r.quiescent_duration[1]),
            cell("center_low", r.spiking_center[0]),
            cell("center_high", r.spiking_center[1]),
            esc(r.claim),
            if r.verdict == crate::table::ClaimVerdict::Agrees {
                "<span class=\"good\">agrees</span>"
            } else {
                "<span class=\"bad\">contradicts</span> (see below)"
            }
        );
    }
    h.push_str("</table><ul>");
    for r in &t.effects_table {
        let _ = write!(h, "<li>{}</li>", esc(&r.measured));
    }
    h.push_str("</ul>\n");
}

/// The figures, inline, with captions and links to the files.
fn figures(h: &mut String, r: &Report, svgs: &[String]) {
    h.push_str("<section id=\"figures\"><h2>Figures</h2>\n");
    for (f, svg) in r.figures.iter().zip(svgs) {
        figure(h, f, svg);
    }
    h.push_str("</section>\n");
}

/// One figure inline: its SVG text `svg` (the XML declaration dropped), its caption and links
/// to its files.
pub(super) fn figure(h: &mut String, f: &crate::output::plot::Figure, svg: &str) {
    let name = &f.name;
    let svg = svg.trim_start_matches(|c| c != '<');
    let svg = svg
        .strip_prefix("<?xml version=\"1.0\" encoding=\"UTF-8\"?>")
        .unwrap_or(svg);
    let _ = write!(
        h,
        "<figure id=\"fig-{name}\" data-figure=\"{name}\">{svg}<figcaption><b>Figure: {name}.</b> {} \
         (<a href=\"figures/{name}.svg\">SVG</a>, <a href=\"figures/{name}.png\">PNG</a>)</figcaption></figure>\n",
        esc(&f.caption)
    );
}

/// The mechanism: the fast subsystem's evidence for each γ, and the γ sweep.
fn mechanism(h: &mut String, r: &Report) {
    let base = &r.options.base;
    let gc = base.critical_gamma();
    let sweep = &r.sweep.rows;
    // mechanism
    let _ = write!(
        h,
        "<section id=\"mechanism\"><h2>The mechanism, with the computed evidence</h2>\
         <p>No Hopf bifurcation is possible: {}. Folds need γ &lt; 1/(3α) = {:.6}; none of the study's γ values is below it. \
         For each γ the fast subsystem and the measured response give:</p>\
         <table id=\"evidence\"><tr><th>γ</th><th>equilibria per a</th><th>folds</th><th>stable everywhere</th><th>spiking area(s), a</th>\
         <th>max κ (threshold {})</th><th>burst pulses, a</th><th>bursts per period</th><th>signature / mode / mechanism</th></tr>\n",
        esc(NO_HOPF_REASON),
        gc,
        FORCING_RATE_THRESHOLD
    );
    for case in &r.cases {
        let (p, e, r, c) = (
            &case.params,
            &case.analysis.equilibria,
            &case.response,
            &case.classification,
        );
        let areas = if e.spiking_areas.is_empty() {
            "none".to_string()
        } else {
            e.spiking_areas
                .iter()
                .map(|s| format!("[{:.4}, {:.4}]", s.a_min, s.a_max))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let onsets = if r.bursts.is_empty() {
            "–".to_string()
        } else {
            r.bursts
                .iter()
                .map(|b| format!("{:.4}", b.a_peak))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}–{}</td><td>{}</td><td>{}</td><td>{}</td>{}<td>{}</td>{}<td>{} / {} / {}</td></tr>",
            p.gamma,
            e.min_count,
            e.max_count,
            e.folds.len(),
            e.stable_everywhere,
            areas,
            cell("forcing_rate", e.prediction.forcing_rate),
            onsets,
            cell(
                "bursts_per_period",
                r.rates.bursts_per_period.unwrap_or(f64::NAN)
            ),
            c.verdict.name(),
            c.mode.name(),
            c.mechanism.name()
        );
    }
    let first_burst = sweep
        .iter()
        .filter(|r| r.rates.bursts_per_period.is_some_and(|b| b > 0.0))
        .map(|r| r.params.gamma)
        .fold(0.0, f64::max);
    let predicted = crate::fast::predicted_gamma_boundary(base);
    let _ = write!(
        h,
        "</table><p>For γ = 1 and 0.1 the fast subsystem has one stable equilibrium for every a, so nothing bifurcates, yet \
         the state overshoots the equilibrium it follows and rings: the pulses lie just after a ≈ 0, where the curve is \
         steepest. The γ sweep shows bursting (first ringing) from γ ≈ {:.2} down, a factor {:.0} above the fold threshold; \
         the prediction from the equilibrium curve alone (κ &gt; {}) puts the boundary at γ = {}. Below 1/(3α) the folds add \
         jumps (figure transformed-phase-g0.01): the only bursting that survives ω → 0.</p>\n",
        first_burst,
        first_burst / gc,
        FORCING_RATE_THRESHOLD,
        predicted.map_or("–".into(), |g| format!("{g:.3}"))
    );
}

/// The bursting boundaries, predicted and simulated.
fn boundaries(h: &mut String, r: &Report) {
    let (base, bounds) = (&r.options.base, &r.boundaries);
    let opt = |v: Option<f64>| v.map_or("–".to_string(), num);
    let _ = write!(
        h,
        "<p>The bursting boundary, predicted from the equilibrium curve alone and located where the simulated verdict switches \
         (to {} %):</p><table id=\"boundaries\"><tr><th>boundary</th><th>predicted</th><th>simulated</th></tr>\
         <tr><td>γ at ω = {} (bursting below)</td><td>{}</td><td>{}</td></tr>\
         <tr><td>ω at γ = {} (bursting above)</td><td>{}</td><td>{}</td></tr>\
         <tr><td>ω at γ = 1 (bursting above)</td><td>{}</td><td>{}</td></tr></table>\
         <p>As ω → 0 every bursting without folds disappears (Fenichel: the slow manifold is normally hyperbolic), \
         at the ω boundaries above; with folds in range the jumps persist at every ω.</p></section>\n",
        100.0 * BOUNDARY_REL_TOL,
        base.omega,
        opt(bounds[0].predicted_gamma),
        opt(bounds[0].simulated_gamma),
        base.gamma,
        num(bounds[0].predicted_omega),
        opt(bounds[0].simulated_omega),
        num(bounds[1].predicted_omega),
        opt(bounds[1].simulated_omega),
    );
}

/// The verdict on the physical drive with the catalogue's own curve, as a paragraph: with its
/// corners, then with its knees rounded (`rounded`, on a drive whose reduced load has `delta`
/// and `omega`).
fn catalogue_law(
    law: &crate::physical::curve_law::CatalogueLaw,
    rounded: &crate::physical::curve_law::CatalogueLaw,
    delta: f64,
    omega: f64,
) -> String {
    let verdict =
        |law: &crate::physical::curve_law::CatalogueLaw| match (&law.outcome, &law.signatures) {
            (Some(o), Some(sig)) if o.judgement.bursting => format!(
                "bursts ({}, largest overshoot {:.1e} of the slow swing X, ringing swing {:.3} ωX)",
                o.judgement.label(),
                sig.max_overshoot,
                sig.max_ringing_swing
            ),
            (Some(o), _) => format!("does not burst ({})", o.judgement.label()),
            (None, _) => "could not be simulated".into(),
        };
    format!(
        "<p>With the catalogue's own curve, the three straight segments in place of the fit \
         (assumed: {}), the same drive {}; {}. With its knees rounded over {} of θ(T1) (an \
         illustration of a measured curve, not a catalogue value), which the slow load passes in \
         {:.2} torsional periods, it {}.</p>",
        esc(law.assumption),
        esc(&verdict(law)),
        esc(crate::physical::curve_law::KNEES),
        rounded.rounding,
        rounded.passage_periods(delta, omega),
        esc(&verdict(rounded))
    )
}

/// The physical drive: reduction, design check, and a variant that bursts.
fn physical(h: &mut String, r: &Report) {
    let ph = &r.physical;
    // physical
    let d = &ph.drive;
    let rp = &ph.check.reduced.params;
    let _ = write!(
        h,
        "<section id=\"physical\"><h2>A physical drive: {PHYSICAL_DRIVE}</h2>\
         <p>Catalogue stiffness (T1 = {} N m, T2 = {} N m, K1 = {:e}, K2 = {:e} N m/rad) fitted by T = k1θ + k2θ³: \
         k1 = {}, k2 = {} (twist error {:.1} % at T1, {:.1} % at T2). Assumed: {}.</p>\
         <table><tr><th>J_eq [kg m²]</th><th>T = J/C [s]</th><th>L [rad]</th><th>α</th><th>γ</th><th>ε</th><th>μ</th><th>δ</th><th>ω</th><th>α·ε</th></tr>\
         <tr>{}{}{}{}{}</tr></table>\
         <p>Design check: the drive {} ({}); the steepest point of its equilibrium curve lies at a = {:.3}, {} The single changes that cross the \
         bursting boundary, each with the verdict simulated just inside and just outside it:</p><table><tr><th>parameter</th>\
         <th>current</th><th>boundary</th><th>change</th><th>inside</th><th>outside</th></tr>\n",
        ph.catalogue.t1,
        ph.catalogue.t2,
        ph.catalogue.k1,
        ph.catalogue.k2,
        num(d.k1),
        num(d.k2),
        100.0 * ph.fit.twist_error_t1,
        100.0 * ph.fit.twist_error_t2,
        esc(&crate::physical::catalogue::assumption_texts().join("; ")),
        cell("j_eq", ph.check.reduced.j_eq),
        cell("time_scale", ph.check.reduced.time_scale),
        cell("length_scale", ph.check.reduced.length_scale),
        param_cells(rp),
        cell("alpha_eps", rp.alpha * rp.eps),
        if ph.check.judgement.bursting {
            "bursts"
        } else {
            "does not burst"
        },
        ph.check.mode.map_or("not simulated", |m| m.name()),
        ph.check.steepest_point_a,
        if ph.check.distance_in_a > 0.0 {
            "outside the range [−1, 1] the slow variable covers: the drive works far from the steep part."
        } else {
            "inside the range the slow variable covers."
        }
    );
    h.push_str(&margin_rows(&ph.check));
    let (vd, vc) = (&ph.variant, &ph.variant_check);
    let _ = write!(
        h,
        "</table>{}<p>The same drive made softer and more disturbed (k1 = {} N m/rad, T_am = {} N m; \
         reduced γ = {:.3}, δ = {:.2}) {} ({}, {}); the single changes that end the bursts:</p>\
         <table><tr><th>parameter</th><th>current</th><th>boundary</th><th>change</th><th>inside</th><th>outside</th></tr>\n",
        catalogue_law(&ph.catalogue_law, &ph.rounded_law, rp.delta, rp.omega),
        num(vd.k1),
        num(vd.t_am),
        vc.reduced.params.gamma,
        vc.reduced.params.delta,
        if vc.judgement.bursting {
            "bursts"
        } else {
            "does not burst"
        },
        vc.mode.map_or("not simulated", |m| m.name()),
        vc.mechanism.map_or("-", |m| m.name())
    );
    h.push_str(&margin_rows(vc));
    h.push_str("</table></section>\n");
}

/// The burst-control section: each law at its least gain at γ = 1 and 0.1, then on the
/// bursting drive in N m.
fn control(h: &mut String, r: &Report) {
    let ce = &r.control;
    h.push_str(
        "<section id=\"control\"><h2>Burst control</h2><p>Four feedback laws, each a term of \
         the model, tuned to the least gain that removes the bursts (the gain below it still \
         bursts): virtual stiffness ũ = −k<sub>p</sub>x, virtual damping ũ = −k<sub>d</sub>x', \
         washout ũ = −k<sub>w</sub>(x − ξ), ξ' = ω<sub>w</sub>(x − ξ) with ω<sub>w</sub> = 0.1, \
         and the scheduled stiffness ũ = −k(a)(x − x<sub>c</sub>), a = sin ωτ, whose gain is \
         g'<sub>min</sub>, the least slope it gives the closed loop's equilibrium curve. \
         Peak: closed-loop peak |x'| over the open loop's; energy: the fast mode's, the mean \
         kinetic energy x'²/2, closed over open; shift: the change of x over the curve's extent at \
         the load's extremes and anywhere; robust: the gain that keeps every plant with α, γ, ε, \
         μ, δ within ±20 % burst-free, over the least gain (figure <a href=\"#fig-control-xdot\">\
         control-xdot</a>).</p>\n",
    );
    for cmp in &ce.study {
        let _ = write!(
            h,
            "<h3>γ = {}</h3><table><tr><th>law</th><th>least gain</th><th>below</th>\
             <th>verdict</th><th>peak</th><th>energy [dB]</th><th>peak |ũ|</th><th>RMS ũ</th>\
             <th>shift a = ±1</th><th>max shift</th><th>robust gain ×</th></tr>\n",
            cmp.params.gamma
        );
        for (t, rb) in cmp.tunings.iter().zip(&cmp.robustness) {
            let a = &t.tuned;
            let _ = writeln!(
                h,
                "<tr data-law=\"{}\"><td>{}</td>{}<td>{}</td><td>{}</td><td>{:.3}</td><td>{:.1}</td>\
                 <td>{:.4}</td><td>{:.4}</td><td>{:.2} %</td><td>{:.2} %</td>{}</tr>",
                t.law,
                t.law,
                cell("gain", a.gain),
                num(t.below.gain),
                a.verdict.name(),
                a.peak_ratio(),
                a.fast_energy_db,
                a.effort_peak,
                a.effort_rms,
                100.0 * a.static_shift,
                100.0 * a.max_shift,
                cell("robust", rb.ratio)
            );
        }
        h.push_str("</table>\n");
        if let Some(f) = &cmp.feedforward {
            let _ = writeln!(
                h,
                "<p>Feed-forward of the load, ũ = −κδ sin(ωτ + Δφ), leaves the open loop with \
                 δ<sub>r</sub> = δ|1 − κe<sup>iΔφ</sup>|: no bursts while that stays below \
                 {:.4}·δ, an amplitude error of {:.1} % at the exact phase or a phase error of \
                 {:.1}° at the exact amplitude.</p>",
                f.residual_limit,
                100.0 * f.max_amplitude_error,
                f.max_phase_error.to_degrees()
            );
        }
    }
    control_drive(h, &ce.drive);
}

/// The control section's drive table: each law's torque in N m against the ratings.
fn control_drive(h: &mut String, dc: &crate::control::DriveControl) {
    let rp = &dc.reduction.params;
    let _ = write!(
        h,
        "<h3>On the bursting drive, in N m</h3><p>The physical section's bursting variant of \
         {PHYSICAL_DRIVE} (reduced γ = {:.3}, δ = {:.2}). A control torque u referred to the \
         output enters the twist as u/(N²J<sub>i</sub>), so u = ũ·L·N²J<sub>i</sub>/T² = {} N m \
         per unit ũ; the motor delivers u/N. Ratings: {}. Drift: the output speed the mean of u \
         gives the rigid-body mode per slow period.</p><table><tr><th>law</th><th>gain</th>\
         <th>peak |u| [N m]</th><th>peak |u|/N at the motor [N m]</th><th>of the repeated peak \
         torque</th><th>of the rated torque</th><th>drift [rad/s]</th><th></th></tr>\n",
        rp.gamma,
        rp.delta,
        num(dc.torque_scale),
        esc(&dc.ratings.origin)
    );
    let pct = |f: Option<f64>| f.map_or("-".to_string(), |f| format!("{:.1} %", 100.0 * f));
    for e in &dc.efforts {
        let check = e.check();
        let flag = match check {
            crate::control::RatingCheck::AboveRepeatedPeak => format!("<b>{}</b>", check.text()),
            _ => check.text().to_string(),
        };
        let _ = writeln!(
            h,
            "<tr data-law=\"{}\"><td>{}</td><td>{}</td>{}<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{flag}</td></tr>",
            e.law,
            e.law,
            num(e.gain),
            cell("output_peak", e.output_peak),
            num(e.motor_peak),
            pct(e.of_repeated_peak),
            pct(e.of_rated),
            num(e.rigid_drift)
        );
    }
    h.push_str("</table></section>\n");
}

/// Special points of a branch of one kind, as "8.4135, 7.8608".
fn special_list(
    b: &crate::periodic::OrbitBranch<crate::params::Param>,
    kind: crate::periodic::Special,
) -> String {
    let v: Vec<String> = b
        .specials()
        .filter(|q| q.special == Some(kind))
        .map(|q| format!("{:.6}", q.param))
        .collect();
    if v.is_empty() {
        "none".into()
    } else {
        v.join(", ")
    }
}

/// Beyond the study: the periodic response.
fn periodic(h: &mut String, r: &Report) {
    use crate::periodic::Special;
    let pe = &r.periodic;
    let base = &r.options.base;
    let _ = write!(
        h,
        "<section id=\"periodic\"><h2>Beyond the study: the periodic response</h2>\
         <p>Everything above integrates long enough for the transient to die. The periodic response can \
         also be computed directly: Newton on the stroboscopic map (shooting), with the monodromy matrix \
         from the variational equations, its Floquet multipliers, and pseudo-arclength continuation in a \
         parameter with folds (a multiplier through +1) and period doublings (through −1) located on the \
         branch. Since the trace of the Jacobian is −1 everywhere, the product of the multipliers is \
         e<sup>−T</sup> (Liouville): a complex pair has modulus e<sup>−T/2</sup> &lt; 1, so the only ways to \
         lose stability are folds and period doublings — there is no torus bifurcation.</p>\
         <table><tr><th>γ</th><th>ln|m1|</th><th>ln|m2|</th><th>multipliers</th><th>peak-to-peak x</th>\
         <th>max |x'|</th><th>verdict on the orbit</th><th>verdict after the transient</th></tr>\n"
    );
    for (o, c) in pe.orbits.iter().zip(&r.cases) {
        let _ = writeln!(
            h,
            "<tr>{}{}{}<td>{}</td>{}{}<td>{}</td><td>{}</td></tr>",
            cell(Param::Gamma.name(), o.gamma),
            cell("ln_m1", o.log_abs_multipliers[0]),
            cell("ln_m2", o.log_abs_multipliers[1]),
            if o.complex {
                "complex pair (a focus)"
            } else {
                "real"
            },
            cell("peak_to_peak", o.peak_to_peak),
            cell("max_abs_xdot", o.max_abs_xdot),
            o.on_orbit.verdict.name(),
            c.classification.verdict.name()
        );
    }
    let b = &pe.response;
    let stable = b.points.iter().filter(|q| q.stable).count();
    let _ = write!(
        h,
        "</table><p>At the study's ω = {} the orbit is the quasi-static response: its multipliers are \
         e<sup>−T/2</sup> = e<sup>−{:.2}</sup>, and the burst verdict measured on the orbit itself, with no \
         transient to discard, {} (a test checks the same over the twenty reference cases).</p>\
         <p><b>Frequency response at the study's point</b> (γ = {}, δ = {}; figure \
         <a href=\"#fig-{}\">frequency-response</a>): {} points from ω = {:.4} to {:.4}, {} of them \
         stable. Folds at ω = {}; period doublings: {}. {}</p>",
        base.omega,
        std::f64::consts::PI / base.omega,
        if pe
            .orbits
            .iter()
            .zip(&r.cases)
            .all(|(o, c)| o.on_orbit == c.classification)
        {
            "is the verdict of the long simulation for every γ"
        } else {
            "differs from the long simulation's for some γ (see the table)"
        },
        base.gamma,
        base.delta,
        super::PERIODIC_FIGURES[0].1,
        b.points.len(),
        b.points.first().map_or(f64::NAN, |q| q.param),
        b.points.last().map_or(f64::NAN, |q| q.param),
        stable,
        special_list(b, Special::Fold),
        special_list(b, Special::PeriodDoubling),
        if b.specials().any(|q| q.special == Some(Special::Fold)) {
            "Between two folds two stable responses coexist and a slow sweep of ω jumps at the folds \
             (the hardening cubic bends the resonance to the right; such jumps were checked against \
             brute-force up- and down-sweeps to within the sweep step, test)."
        } else {
            "Without a fold the response is single-valued: a slow sweep of ω does not jump."
        },
    );
    bubble(h, pe);
    drive_response(h, pe);
}

/// The period-doubling bubble and the Lyapunov map.
fn bubble(h: &mut String, pe: &super::periodic::PeriodicEvidence) {
    use crate::periodic::Special;
    let doubled = pe.doubled.as_ref().map_or(String::from("none found"), |d| {
        format!(
            "{} points of period 2·2π/ω, {}",
            d.points.len(),
            match d.end {
                crate::periodic::End::Rejoined { param } => {
                    format!("rejoining the period-1 branch at the second doubling, ω = {param:.6}")
                }
                _ => "ending at the range's end".into(),
            }
        )
    });
    let max_l = pe
        .lyapunov
        .iter()
        .map(|r| r.lyapunov)
        .filter(|l| l.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    let near_zero = pe.lyapunov.iter().filter(|r| r.lyapunov > -0.01).count();
    let _ = write!(
        h,
        "<p><b>A period-doubling bubble</b> (γ = {}; figure <a href=\"#fig-{}\">orbit diagram</a>): \
         continued in ω from {} to {}, the period-1 response has folds at ω = {} and doubles at ω = {}; \
         the doubled branch: {}. The orbit diagram (each ω started from the previous state, swept up and \
         down) shows the same jumps and the period-2 window; Benettin's exponent goes to 0 at each \
         bifurcation and is −1/2 wherever the multipliers are complex.</p>\
         <p><b>Lyapunov map</b> over (ω, δ) at γ = {} ({} points; figure <a href=\"#fig-{}\">\
         lyapunov map</a>): the largest exponent is {:.4}; {} points are within 0.01 of 0 (at a bifurcation). \
         {} The tongues where the exponent rises toward 0 are the resonances where folds and doublings \
         occur.</p>",
        BUBBLE_GAMMA,
        super::PERIODIC_FIGURES[1].1,
        BUBBLE_OMEGA.0,
        BUBBLE_OMEGA.1,
        special_list(&pe.bubble, Special::Fold),
        special_list(&pe.bubble, Special::PeriodDoubling),
        doubled,
        BUBBLE_GAMMA,
        pe.lyapunov.len(),
        super::PERIODIC_FIGURES[2].1,
        max_l,
        near_zero,
        if max_l > 0.01 {
            "Positive exponents were found: sensitive dependence, no periodic response there."
        } else {
            "No positive exponent was found in this range: with this damping the responses are \
             periodic."
        },
    );
}

/// The drive's frequency response in SI units, which closes the section.
fn drive_response(h: &mut String, pe: &super::periodic::PeriodicEvidence) {
    use crate::periodic::Special;
    let peak = |x: &crate::periodic::PhysicalResponse| {
        x.points
            .iter()
            .max_by(|a, b| a.twist_peak_to_peak.total_cmp(&b.twist_peak_to_peak))
            .copied()
    };
    let folds_hz = |x: &crate::periodic::PhysicalResponse| {
        let v: Vec<String> = x
            .points
            .iter()
            .filter(|q| q.special == Some(Special::Fold))
            .map(|q| format!("{:.1} Hz", q.frequency_hz))
            .collect();
        if v.is_empty() {
            "none, a frequency sweep does not jump".to_string()
        } else {
            v.join(", ")
        }
    };
    if let (Some(a), Some(v)) = (peak(&pe.drive), peak(&pe.variant)) {
        let _ = write!(
            h,
            "<p><b>The physical drive's frequency response</b> ({PHYSICAL_DRIVE}, in SI units: θ = L·x, \
             f = ω/(2πT)): at its catalogue disturbance the largest response is {:.3} mrad peak to peak at \
             {:.1} Hz (elastic torque up to {:.2} N m); folds: {}. The softer, harder-driven variant above \
             (figure <a href=\"#fig-{}\">physical frequency response</a>): its largest response is {:.2} \
             mrad at {:.1} Hz with an elastic torque of {:.0} N m; folds: {} (where there are folds, a small \
             change of speed near them makes the twist jump). These curves were checked against the two-inertia simulation in SI \
             units (test: twist extremes to 1e-5 of the amplitude).</p>\n",
            1e3 * a.twist_peak_to_peak,
            a.frequency_hz,
            a.torque_range[1],
            folds_hz(&pe.drive),
            super::PERIODIC_FIGURES[3].1,
            1e3 * v.twist_peak_to_peak,
            v.frequency_hz,
            v.torque_range[1],
            folds_hz(&pe.variant),
        );
    }
    plane(h, &pe.plane);
    h.push_str("</section>\n");
}

/// The (ω, δ) plane's paragraph.
fn plane(h: &mut String, e: &super::plane::PlaneEvidence) {
    use crate::burst::BoundaryKind;
    let cusps: Vec<String> = e
        .cusps()
        .iter()
        .map(|c| format!("(ω, δ) = ({:.4}, {:.4})", c[0], c[1]))
        .collect();
    let delta = crate::params::Params::default().delta;
    let at = |kind| {
        e.omega_at(kind, delta)
            .map_or_else(|| "none".to_string(), |w| format!("{w:.3e}"))
    };
    let _ = write!(
        h,
        "<p><b>The (ω, δ) plane</b> at the study's γ and other parameters (figure <a \
         href=\"#fig-{}\">(ω, δ) plane</a>): {} fold curve(s) of the frequency response followed by \
         two-parameter continuation, with their cusps at {} (below a cusp's δ that resonance has no \
         hysteresis); {} period-doubling curve(s). Far below the resonance, the bursting boundary \
         as curves (the predictor–corrector of <code>hdgear boundary</code>): at the study's δ = \
         {delta} it lies at ω = {} (predicted) and {} (simulated, to 1 %); the fast-slow picture \
         holds below ω = {}. Each curve was checked in the tests against independent \
         one-parameter computations (folds at ten δ to 1e-8; the simulated boundary against ten \
         bisections within their 1 % brackets).</p>\n",
        super::PERIODIC_FIGURES[4].1,
        e.folds.len(),
        if cusps.is_empty() {
            "none".to_string()
        } else {
            cusps.join(" and ")
        },
        e.doublings.len(),
        at(BoundaryKind::Predicted),
        at(BoundaryKind::Simulated),
        at(BoundaryKind::FastSlowEdge),
    );
}

/// How each number was computed, from the options and constants themselves.
fn methods(h: &mut String, r: &Report) {
    let opts = &r.options;
    // the study's fast subsystem's facts, from its damping at rest (c = 1)
    let (focus, decay) = (opts.base.focus_gprime(), opts.base.decay_time());
    // methods
    let _ = write!(
        h,
        "<section id=\"methods\"><h2>How each number was computed</h2><ul>\
         <li><b>Simulation</b>: {}, rtol = {:e}, \
         atol = {:e}, from the stable equilibrium at a(0) = 0; checked against independent scipy trajectories to 1e-9.</li>\
         <li><b>Equilibria, folds, cusp, slopes</b>: closed forms on the cubic g(x) = μ + δa (roots bracketed between the fold \
         abscissae and polished by Newton); the curve is sampled by x, so steep parts are exact.</li>\
         <li><b>Prediction and spiking areas</b>: κ = |g''|·ω·δ·√(1 − a²)/g'², the rate at which the equilibrium's speed \
         changes, on the part of the curve where the fast subsystem is a focus (g' &gt; {focus}, where it can ring); bursting is \
         predicted where κ &gt; {} or a fold lies in a ∈ [−1, 1].</li>\
         <li><b>Bursts</b> are judged by the three signatures the fast mode can show (trace −1: no Hopf, no cycles), each \
         located on the dense output: a <i>jump</i> across the band between the folds; an <i>overshoot</i>, a lobe of \
         x − x* on the leading side (adiabatic tracking always lags) of at least {:e}·X; <i>ringing</i>, three or more extrema \
         of x' in one group, swings below {:e}·ω·X pruned. Events closer than min({}·τ_r, T/8) (τ_r = {decay}, the decay time of \
         the fast oscillation) group into one burst, counted where its pulse (largest |x'|) lies; {} slow period(s) discarded, \
         {} analysed from the next turning point of a. Spikes: swings of x' of at least {} of the burst's largest.</li>\
         <li><b>Modes</b> from the signatures: normal (none), transitional (ringing only), fast-slow (overshoot where the \
         slowest traversed point is a focus), pronounced bursting (overshoot where it is a node, g' ≤ {focus}), relaxation \
         (jumps); not fast-slow when ω &gt; r/{TIME_SCALE_SEPARATION} (r: the relaxation rate at a = ±1) or ω ≥ the slowest relaxation rate on the path the state follows or the fast motion never stops. \
         Mechanism: fold-hysteresis when a jump is measured, sharp-quantitative-change for overshoot or ringing.</li>\
         <li><b>Sweep and map</b>: {} and {} × {} independent simulations in parallel at rtol = atol = {:e}, the \
         loosest tolerance with a margin at which no verdict, mode or burst count changes (tested from 1e-6 to 1e-12 on \
         the reference cases and a 200-point γ sweep); data in <code>data/</code>.</li>\
         <li><b>Physical drive</b>: two-inertia equations integrated in (θ, θ', θo, θo'); reduction J_eq, T = J/C, L = C²/(J k2 φ).</li>\
         </ul><p>Data beside this page: <code>data/tables.json</code>, <code>data/tables.csv</code>, <code>data/analysis-g*.json</code>, \
         <code>data/curve-g*.csv</code>, <code>data/sweep-gamma.csv</code>, <code>data/map-gamma-delta.csv</code>; every figure as SVG and PNG in \
         <code>figures/</code>. Produced by <code>hdgear report</code>.</p></section>\n</body></html>\n",
        crate::integrate::Method::default().describe(),
        opts.burst.tol.rtol,
        opts.burst.tol.atol,
        FORCING_RATE_THRESHOLD,
        opts.burst.overshoot_floor,
        opts.burst.swing_floor,
        opts.burst.gap_decay_times,
        opts.burst.discard_periods,
        opts.burst.periods,
        opts.burst.spike_fraction,
        opts.sweep_points,
        opts.map_size.0,
        opts.map_size.1,
        opts.grid_tol
    );
}
