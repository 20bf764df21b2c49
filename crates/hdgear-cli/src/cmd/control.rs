//! `hdgear control`: feedback laws against the bursts, each tuned to its least gain (or assessed
//! at a given gain), side by side with what they cost.

use crate::args::BurstArgs;
use crate::sink::{out, outln, warn};
use crate::sources::ParamArgs;
use anyhow::{Context, Result};
use clap::Args;
use hdgear::control::{
    Comparison, ControlOptions, DriveControl, Plant, Ratings, compare, compare_drive,
};

/// Arguments of `hdgear control`.
#[derive(Args, Debug)]
pub struct ControlArgs {
    /// The laws: vstiffness (ũ = −k_p x), vdamping (ũ = −k_d x'), washout (ũ = −k_w (x − ξ),
    /// ξ' = ω_w (x − ξ)), dither (ũ = D sin Ω_d τ, the gain D; its verdict is of the motion
    /// averaged over the dither's period), delay (ũ = K (x(τ − τ_d) − x(τ)), the gain K),
    /// scheduled (ũ = −k(a) (x − x_c), built for the given parameter set, the gain the least
    /// slope g'_min it keeps); every law but dither and delay without any.
    #[arg(value_name = "LAW")]
    pub laws: Vec<String>,
    /// Assess each law at this gain instead of tuning it to its least gain that removes the
    /// bursts.
    #[arg(long, allow_negative_numbers = true)]
    pub gain: Option<f64>,
    /// The washout filter's corner frequency ω_w (the term's default without it).
    #[arg(long, allow_negative_numbers = true)]
    pub ww: Option<f64>,
    /// The dither's angular frequency Ω_d (the term's default without it).
    #[arg(long, allow_negative_numbers = true)]
    pub wd: Option<f64>,
    /// The delayed feedback's delay τ_d (the term's default without it).
    #[arg(long, allow_negative_numbers = true)]
    pub taud: Option<f64>,
    /// Relative width of a tuned gain's final bracket.
    #[arg(long, default_value_t = 1e-3)]
    pub rel_tol: f64,
    /// Relative model error each tuned law must stand: the least gain that keeps every plant
    /// with α, γ, ε, μ, δ within ±SPREAD burst-free (0.2: ±20 %; 0: not checked).
    #[arg(long, default_value_t = 0.2, allow_negative_numbers = true)]
    pub spread: f64,
    /// A drive instead of a parameter set: its card (built-in name, FILE.toml or FILE.toml#NAME)
    /// with the documented assumptions for the rest (hdgear physical --control changes them);
    /// the efforts in N m against its torque ratings.
    #[arg(long, value_name = "CARD", conflicts_with_all = crate::sources::NOT_WITH_CARD)]
    pub card: Option<String>,
    /// JSON instead of text.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub params: ParamArgs,
    #[command(flatten)]
    pub burst: BurstArgs,
}

impl ControlArgs {
    /// The checked options of the comparison.
    fn options(&self) -> ControlOptions {
        ControlOptions {
            gain: self.gain,
            ww: self.ww,
            wd: self.wd,
            taud: self.taud,
            rel_tol: self.rel_tol,
            spread: (self.spread != 0.0).then_some(self.spread),
        }
    }
}

/// Runs `hdgear control`.
pub fn run(a: ControlArgs) -> Result<()> {
    let opts = a.burst.options()?;
    let laws: Vec<&str> = a.laws.iter().map(String::as_str).collect();
    if let Some(card) = &a.card {
        let loaded = crate::cmd::card::load(card).context("--card")?;
        let built =
            hdgear::physical::catalogue::assemble(&loaded.card, None, None).context("--card")?;
        let doc = drive_control(&built.drive, &loaded, &laws, &a.options(), &opts)?;
        return print(&doc, a.json, drive_text);
    }
    let (system, warnings) = a.params.resolve_system()?;
    warn(&warnings);
    hdgear::on_subject!(&system, |p| {
        let doc = compare(p, &laws, &a.options(), &opts)?;
        print(&doc, a.json, text)
    })
}

/// The laws compared on the drive `d` (built from `card`), against the card's ratings.
pub fn drive_control(
    d: &hdgear::physical::PhysicalParams,
    card: &crate::cmd::card::Loaded,
    laws: &[&str],
    c: &ControlOptions,
    opts: &hdgear::burst::BurstOptions,
) -> Result<DriveControl> {
    let origin = match &card.card.torque {
        Some(t) => format!("card {} (source: {})", card.card.name, t.source),
        None => format!("card {} has no [torque] ratings", card.card.name),
    };
    let ratings = Ratings::of(card.card.torque.as_ref(), origin);
    compare_drive(d, ratings, laws, c, opts).context("cannot compare the laws on the drive")
}

/// `doc` as JSON or as `text` says.
pub fn print<T: serde::Serialize>(doc: &T, json: bool, text: fn(&T) -> String) -> Result<()> {
    if json {
        outln!("{}", serde_json::to_string_pretty(doc)?);
    } else {
        out!("{}", text(doc));
    }
    Ok(())
}

/// The drive's comparison: the reduced model's table, then each law's torque in N m.
pub fn drive_text(doc: &DriveControl) -> String {
    use std::fmt::Write;
    let mut s = crate::summary::drive_line(&doc.drive);
    s.push_str(&format!(
        "control torque at the output per unit ũ: L·N²·J_in/T² = {:.4e} N m (at the motor: /N)\n",
        doc.torque_scale
    ));
    s.push_str(&text(&doc.comparison));
    let r = &doc.ratings;
    let rating = |v: Option<f64>| v.map_or("-".to_string(), |t| format!("{t} N m"));
    let _ = writeln!(
        s,
        "on the drive (ratings at the output: rated {}, repeated peak {}; {}):",
        rating(r.rated),
        rating(r.repeated_peak),
        r.origin
    );
    let _ = writeln!(
        s,
        "{:<11} {:>10} {:>11} {:>11} {:>12} {:>9} {:>9} {:>12}  flag",
        "law", "gain", "peak |u|/N", "rms u/N", "peak |u|", "/rep.pk", "/rated", "drift"
    );
    let _ = writeln!(
        s,
        "{:<11} {:>10} {:>11} {:>11} {:>12} {:>9} {:>9} {:>12}",
        "", "", "motor N m", "motor N m", "output N m", "", "", "rad/s/period"
    );
    let pct = |f: Option<f64>| f.map_or("-".to_string(), |f| format!("{:.1}%", 100.0 * f));
    for e in &doc.efforts {
        let check = e.check();
        let flag = match check {
            hdgear::control::RatingCheck::AboveRepeatedPeak => check.text().to_uppercase(),
            _ => check.text().to_string(),
        };
        let _ = writeln!(
            s,
            "{:<11} {:>10.5} {:>11.4e} {:>11.4e} {:>12.4e} {:>9} {:>9} {:>12.3e}  {flag}",
            e.law,
            e.gain,
            e.motor_peak,
            e.motor_rms,
            e.output_peak,
            pct(e.of_repeated_peak),
            pct(e.of_rated),
            e.rigid_drift
        );
    }
    s.push_str(
        "u: the control torque referred to the output, set against the ratings; u/N: what the \
         motor delivers; drift: the output speed the mean of u gives the rigid-body mode per slow \
         period\n",
    );
    s
}

/// The side-by-side table.
pub fn text<P: Plant>(doc: &Comparison<P>) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(s, "control at {}", doc.params.title());
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
        "{:<11} {:>10} {:>10} {:<10} {:>7} {:>8} {:>9} {:>9} {:>10} {:>7} {:>7} {:>8}",
        "law",
        "gain",
        "below",
        "verdict",
        "peak",
        "energy",
        "effort",
        "rms",
        "mean",
        "a=±1",
        "max",
        "robust"
    );
    let _ = writeln!(
        s,
        "{:<11} {:>10} {:>10} {:<10} {:>7} {:>8} {:>9} {:>9} {:>10} {:>7} {:>7} {:>8}",
        "", "", "", "", "/open", "dB", "peak |ũ|", "ũ", "ũ", "shift", "shift", "gain ×"
    );
    let below = doc.tunings.iter().map(|t| Some(t.below.gain));
    let robust = doc.robustness.iter().map(|r| Some(r.ratio));
    let rows = doc
        .rows()
        .zip(below.chain(std::iter::repeat(None)))
        .zip(robust.chain(std::iter::repeat(None)));
    for ((a, below), robust) in rows {
        let _ = writeln!(
            s,
            "{:<11} {:>10.5} {:>10} {:<10} {:>7.3} {:>8.1} {:>9.4} {:>9.4} {:>10.2e} {:>6.2}% {:>6.2}% {:>8}",
            a.term.kind(),
            a.gain,
            below.map_or("-".into(), |b| format!("{b:.5}")),
            if a.unstable {
                "unstable"
            } else {
                a.verdict.name()
            },
            a.peak_ratio(),
            a.fast_energy_db,
            a.effort_peak,
            a.effort_rms,
            a.effort_mean,
            100.0 * a.static_shift,
            100.0 * a.max_shift,
            robust.map_or("-".into(), |r| format!("{r:.3}"))
        );
    }
    notes(&mut s, doc);
    s
}

/// The table's closing lines: feed-forward's tolerance, the model error checked, the key.
fn notes<P>(s: &mut String, doc: &Comparison<P>) {
    use std::fmt::Write;
    for a in doc.rows() {
        if let Some(v) = &a.averaging {
            let _ = writeln!(
                *s,
                "{} at {:.5}: averaged model γ = {:.5}, ε = {:.5} (ripple A = {:.4} on the twist); Ω_d/√(max g') = {:.2} (averaging needs it well above 1)",
                a.term.kind(),
                a.gain,
                v.params.gamma,
                v.params.eps,
                v.ripple,
                v.frequency_ratio,
            );
        }
    }
    if let Some(f) = &doc.feedforward {
        let _ = writeln!(
            *s,
            "feed-forward of the load, ũ = −κδ sin(ωτ + Δφ): no bursts while |1 − κ e^(iΔφ)| ≤ {:.4} \
             (amplitude error ≤ {:.1} % at the exact phase, phase error ≤ {:.1}° at the exact \
             amplitude), peak |ũ| = δ = {}",
            f.residual_limit,
            100.0 * f.max_amplitude_error,
            f.max_phase_error.to_degrees(),
            f.effort_peak
        );
    }
    if let Some(r) = doc.robustness.first() {
        let _ = writeln!(
            *s,
            "robust: every plant with α, γ, ε, μ, δ within ±{} % ({} plants: the box's corners and \
             the nominal set) burst-free",
            100.0 * r.spread,
            r.plants
        );
    }
    s.push_str(
        "peak: closed-loop peak |x'| over the open loop's; energy: the fast mode's, the mean \
         kinetic energy x'²/2, closed over open; ũ: the control torque on μ's scale (a non-zero mean drives \
         the rigid-body mode); shift: the change of x over the curve's extent X at the load's \
         extremes and anywhere; robust gain ×: the gain that keeps every plant within the model \
         error burst-free, over the least gain\n",
    );
}
