//! The model report as HTML: one function per section, each reading the computed
//! [`ModelReport`], a section not computed showing its reason.

// HTML blocks end with a newline of their own, for a readable source.
#![allow(clippy::write_with_newline)]

use super::{DriveEvidence, ModelReport, OrbitEvidence, ResponseEvidence, Section};
use crate::fast::CurveAnalysis;
use crate::model::{Description, ModelParam};
use crate::periodic::{OrbitBranch, Special};
use crate::report::html::{figure, margin_rows, page_start};
use crate::report::markup::{cell, esc, num};
use std::fmt::Write as _;

/// `index.html` of the model report, with the figures' SVG texts `svgs` inline.
pub(super) fn render(r: &ModelReport, svgs: &[String]) -> String {
    let mut h = String::new();
    page_start(
        &mut h,
        &format!("hdgear report: {}", r.origin),
        &format!("Report on {}", r.origin),
        &[
            ("model", "Model"),
            ("fast", "Fast subsystem"),
            ("response", "Response"),
            ("orbit", "Periodic orbit"),
            ("frequency", "Frequency response"),
            ("drive", "Drive"),
            ("figures", "Figures"),
            ("elsewhere", "Not in this report"),
        ],
    );
    model_section(&mut h, &r.model);
    fast_section(&mut h, &r.curve);
    response_section(&mut h, &r.response);
    orbit_section(&mut h, &r.orbit);
    frequency_section(&mut h, &r.frequency);
    drive_section(&mut h, r.drive.as_ref());
    h.push_str("<section id=\"figures\"><h2>Figures</h2>\n");
    for (f, svg) in r.figures.iter().zip(svgs) {
        figure(&mut h, f, svg);
    }
    h.push_str("</section>\n<section id=\"elsewhere\"><h2>Not in this report</h2><table><tr><th>the study's section</th><th>why, and where</th></tr>\n");
    for e in &r.elsewhere {
        let _ = write!(
            h,
            "<tr><td>{}</td><td>{}</td></tr>\n",
            esc(e.section),
            esc(&e.reason)
        );
    }
    let _ = write!(
        h,
        "</table></section>\n<p>hdgear {}; burst tolerance rtol = {:e}, atol = {:e}.</p></body></html>\n",
        r.version, r.options.burst.tol.rtol, r.options.burst.tol.atol
    );
    h
}

/// The opening of section `id` titled `title`; for a section not computed, its reason and the
/// closing tag (and `None`).
fn open<'a, T>(h: &mut String, id: &str, title: &str, s: &'a Section<T>) -> Option<&'a T> {
    let _ = write!(h, "<section id=\"{id}\"><h2>{title}</h2>");
    match s {
        Section::Shown(v) => Some(v),
        Section::NotApplicable(why) => {
            let _ = write!(
                h,
                "<p class=\"na\" data-not-applicable=\"{id}\">Not computed for this model: {}</p></section>\n",
                esc(why)
            );
            None
        }
    }
}

fn model_section(h: &mut String, d: &Description) {
    let _ = write!(
        h,
        "<section id=\"model\"><h2>Model and parameters</h2><span class=\"eq\">{}</span>\
         <p>States: {}. Terms: {}.</p><table><tr><th>term</th><th>name</th><th>symbol</th>\
         <th>value</th><th>meaning</th></tr>\n",
        esc(&d.equation),
        d.states.join(", "),
        d.terms
            .iter()
            .map(|t| t.kind())
            .collect::<Vec<_>>()
            .join(", ")
    );
    for p in &d.parameters {
        let _ = write!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td>{}<td>{}</td></tr>\n",
            p.term,
            p.info.name,
            esc(p.info.symbol),
            cell(&format!("{}.{}", p.term, p.info.name), p.value),
            esc(p.info.meaning)
        );
    }
    let f = &d.facts;
    let _ = write!(
        h,
        "</table><p>Derived from the terms for the fast subsystem: damping at rest c = {}{}, an \
         equilibrium is a focus above g' = c²/4 = {}, a focus's ringing decays in 2/c = {} \
         (ω·2/c = {}); a Hopf bifurcation of the fast subsystem is {}.</p></section>\n",
        num(f.damping_at_rest),
        if f.damping_uniform {
            ""
        } else {
            " (its least over x)"
        },
        num(f.focus_node_threshold),
        num(f.decay_time),
        num(f.omega_decay),
        if f.hopf_possible {
            "possible"
        } else {
            "impossible"
        }
    );
}

fn fast_section(h: &mut String, s: &Section<CurveAnalysis>) {
    let Some(c) = open(h, "fast", "The fast subsystem", s) else {
        return;
    };
    let _ = write!(
        h,
        "<p>The forcing frozen at a ∈ [{}, {}]: {}–{} equilibria per a; {}. The slowest \
         relaxation on the path the state follows is {} ({}, at a = {}); the settled \
         equilibrium moves at most at |dx*/dτ| = {}.</p>",
        c.a_range[0],
        c.a_range[1],
        c.min_count,
        c.max_count,
        if c.folds.is_empty() {
            "no fold (the static torque rises monotonically)".to_string()
        } else {
            format!(
                "folds at {}",
                c.folds
                    .iter()
                    .map(|f| format!("(a, x) = ({}, {})", num(f.a), num(f.x)))
                    .collect::<Vec<_>>()
                    .join(" and ")
            )
        },
        num(c.slowest_relaxation.rate),
        c.slowest_relaxation.along.name(),
        num(c.slowest_relaxation.a),
        num(c.max_equilibrium_speed)
    );
    h.push_str("</section>\n");
}

fn response_section(h: &mut String, s: &Section<ResponseEvidence>) {
    let Some(e) = open(h, "response", "Response and verdict", s) else {
        return;
    };
    let (r, c) = (&e.response, &e.classification);
    let _ = write!(
        h,
        "<p>From the default start (the lowest stable equilibrium at a = 0, at rest), measured \
         over τ ∈ [{}, {}]: <b class=\"{}\" data-verdict=\"{}\">{}</b>, mode {}, mechanism {}{}.\
         </p><table><tr><th>bursts per slow period</th><th>spikes per burst</th><th>peak |x'|</th>\
         <th>quiescent fraction</th></tr><tr>{}{}{}{}</tr></table>",
        num(r.window_start),
        num(r.window_end),
        if c.bursting { "bad" } else { "good" },
        c.verdict.name(),
        c.verdict.name(),
        c.mode.name(),
        c.mechanism.name(),
        if c.fast_slow_domain {
            ""
        } else {
            "; outside the fast-slow domain (ω is not slow against the fast subsystem)"
        },
        cell(
            "bursts_per_period",
            r.rates.bursts_per_period.unwrap_or(f64::NAN)
        ),
        cell("spikes_per_burst", r.rates.spikes_per_burst),
        cell("peak_abs_xdot", r.rates.peak_abs_xdot),
        cell("quiescent_fraction", r.rates.quiescent_fraction)
    );
    match &r.sticking {
        Some(st) if st.stuck_fraction >= 1.0 => h.push_str(
            "<p>It rests the whole window: the friction's sticking band holds the load \
             throughout.</p>",
        ),
        Some(st) => {
            let _ = write!(
                h,
                "<p>It sticks: rests per slow period {}, the mean rest {} long, at rest {} % of \
                 the window.</p>",
                num(st.sticks_per_period),
                num(st.mean_stick),
                num(100.0 * st.stuck_fraction)
            );
        }
        None => {}
    }
    h.push_str("</section>\n");
}

fn orbit_section(h: &mut String, s: &Section<OrbitEvidence>) {
    let Some(e) = open(h, "orbit", "The periodic orbit", s) else {
        return;
    };
    let o = &e.orbit;
    let m = |k: usize| {
        let q = o.multipliers[k];
        if q.log_abs == f64::NEG_INFINITY {
            "= 0 (a rest forgets the speed)".to_string()
        } else {
            format!("with ln|m| = {} (arg {})", num(q.log_abs), num(q.arg))
        }
    };
    let _ = write!(
        h,
        "<p>Period 2π/ω = {}, found by shooting from (x, x') = ({}, {}) (Newton residual {:.1e}). \
         Floquet multipliers m₁ {} and m₂ {}: <b>{}</b>. x from {} to {}, max |x'| {}{}. The verdict on \
         the orbit itself: {}.</p></section>\n",
        num(o.period),
        num(o.start[0]),
        num(o.start[1]),
        o.residual,
        m(0),
        m(1),
        o.stability().name(),
        num(o.x_range[0]),
        num(o.x_range[1]),
        num(o.max_abs_xdot),
        o.rests.map_or(String::new(), |r| format!(
            "; {} rest(s) per period, at rest {} % of it",
            r.rests,
            num(100.0 * r.time_stuck / o.period)
        )),
        e.verdict.verdict.name()
    );
}

fn frequency_section(h: &mut String, s: &Section<OrbitBranch<ModelParam>>) {
    let Some(b) = open(h, "frequency", "The frequency response", s) else {
        return;
    };
    let specials: Vec<String> = b
        .specials()
        .map(|q| {
            format!(
                "{} at ω = {}",
                q.special.map_or("", Special::name),
                num(q.param)
            )
        })
        .collect();
    let peak = b.points.iter().max_by(|x, y| {
        x.amplitude
            .peak_to_peak
            .total_cmp(&y.amplitude.peak_to_peak)
    });
    let _ = write!(
        h,
        "<p>By continuation in ln ω over [{}, {}], {} points{}. {}.</p></section>\n",
        num(b.points.first().map_or(f64::NAN, |q| q.param)),
        num(b.points.last().map_or(f64::NAN, |q| q.param)),
        b.points.len(),
        peak.map_or(String::new(), |q| format!(
            "; the largest response, peak-to-peak x {}, at ω = {}",
            num(q.amplitude.peak_to_peak),
            num(q.param)
        )),
        if specials.is_empty() {
            "No fold and no period doubling: the response is single-valued".to_string()
        } else {
            specials.join(", ")
        }
    );
}

fn drive_section(h: &mut String, d: Option<&DriveEvidence>) {
    h.push_str("<section id=\"drive\"><h2>The drive</h2>");
    let Some(d) = d else {
        h.push_str(
            "<p class=\"na\" data-not-applicable=\"drive\">Not computed for this model: a \
             dimensionless model has no SI units (`hdgear report --card CARD` reports on a \
             catalogue drive).</p></section>\n",
        );
        return;
    };
    let c = &d.check;
    let _ = write!(
        h,
        "<p>Card {}: k1 = {} N m/rad, k2 = {} N m/rad³, J_in = {} kg m², J_out = {} kg m², \
         T_m = {} N m, T_am = {} N m at {} Hz. Assumed: {}.</p><p>Its design check on the reduced \
         model without friction (the study's equation at the drive's α, γ, ε, μ, δ, ω; the \
         sections above carry the card's friction when it has one): the drive {} ({}). The single \
         changes that cross the bursting boundary:</p><table><tr><th>parameter</th>\
         <th>current</th><th>boundary</th><th>change</th><th>inside</th><th>outside</th></tr>\n",
        esc(&d.card),
        num(d.drive.k1),
        num(d.drive.k2),
        num(d.drive.j_in),
        num(d.drive.j_out),
        num(d.drive.t_m),
        num(d.drive.t_am),
        num(d.drive.omega / std::f64::consts::TAU),
        esc(&d.assumptions.join("; ")),
        if c.judgement.bursting {
            "bursts"
        } else {
            "does not burst"
        },
        c.mode.map_or("not simulated", |m| m.name())
    );
    h.push_str(&margin_rows(c));
    h.push_str("</table></section>\n");
}
