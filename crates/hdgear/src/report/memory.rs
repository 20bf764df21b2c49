//! The report's section on memory in the drive: friction and hysteresis on the twist, the
//! quasi-static loading and unloading branches x±(a) that replace the equilibrium curve
//! ([`crate::model::Model::branches`]), and where the simulated bursts start against what the
//! branches predict ([`crate::model::branches::LoopBranch::predicted_onsets`]).

use super::control::TRACE_DT;
use super::markup::{cell, esc, num};
use crate::burst::{BurstOptions, Classification, StickSlip, classify, response_model, window};
use crate::error::Result;
use crate::figures::decimate;
use crate::model::Model;
use crate::model::branches::{Branches, LoopBranch};
use crate::model::terms::AnyTerm;
use crate::output::plot::{Figure, Panel, Series, Style};
use crate::params::Params;
use serde::Serialize;
use std::fmt::Write as _;

/// The section's figure's file stem.
pub const MEMORY_FIGURE: &str = "memory-branches";

/// The section's cases, each on the report's base set at its own γ: γ, the term's kind and its
/// values (in the order of its parameters), and what it shows.
pub const MEMORY_CASES: [(f64, &str, &[f64], &str); 3] = [
    (
        1.0,
        "coulomb",
        &[0.5, 0.5, 0.1, 0.0],
        "Coulomb friction with sticking at the study's γ = 1",
    ),
    (
        0.5,
        "boucwen",
        &[1.0, 0.0, 1.0, 0.5, 0.5, 2.0],
        "Bouc–Wen hysteresis of the flexspline",
    ),
    (
        30.0,
        "coulomb",
        &[0.5, 2.0, 0.001, 0.0],
        "a Stribeck drop at a stiff point, where the study's model alone has no bursts",
    ),
];

/// Points in the (a, x) plane.
pub type PlanePoints = Vec<(f64, f64)>;

/// Where a simulated burst starts, against the predictions of the branch it starts on.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Onset {
    /// a at the burst's onset.
    pub a: f64,
    /// Whether the load was rising (the loading branch's), judged at the burst's pulse.
    pub loading: bool,
    /// The nearest prediction on that branch (`None` when it has none).
    pub predicted: Option<f64>,
}

/// What a branch predicts, without its points.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BranchSummary {
    /// a where the motion leaves rest after the reversal.
    pub breakaway: Option<f64>,
    /// The steepest point: a and the tangent stiffness K_t there.
    pub steepest: Option<(f64, f64)>,
    /// a of a fold, where the branch ends in a jump.
    pub fold: Option<f64>,
    /// The branch's points (in the figure, thinned).
    pub points: usize,
}

impl BranchSummary {
    fn of(b: &LoopBranch) -> BranchSummary {
        BranchSummary {
            breakaway: b.breakaway,
            steepest: b.min_stiffness,
            fold: b.fold,
            points: b.points.len(),
        }
    }
}

/// One case of the section.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MemoryCase {
    /// What it shows.
    pub what: &'static str,
    /// The study's parameters of the case.
    pub params: Params,
    /// The term added to the study's model.
    pub term: AnyTerm,
    /// The model's equation and its states' equations.
    pub equation: String,
    /// Verdict, mode and mechanism of the simulated response.
    pub classification: Classification,
    /// Its rests and slips (`None` without a sticking term).
    pub sticking: Option<StickSlip>,
    /// The loading branch (a rising).
    pub loading: BranchSummary,
    /// The unloading branch.
    pub unloading: BranchSummary,
    /// The change of x at a = 1 over the loop's last cycle: how closed it is.
    pub closure: f64,
    /// Each burst's onset in the window, with its branch's nearest prediction.
    pub onsets: Vec<Onset>,
    /// The branches, with their points.
    #[serde(skip)]
    pub branches: Branches,
    /// The response over the window in the (a, x) plane, and the onsets' (a, x).
    #[serde(skip)]
    pub path: (PlanePoints, PlanePoints),
}

impl MemoryCase {
    /// The case of γ `gamma` with term `kind` = `values` on `base`.
    fn compute(
        base: &Params,
        (gamma, kind, values, what): (f64, &str, &[f64], &'static str),
        opts: &BurstOptions,
    ) -> Result<MemoryCase> {
        let params = Params { gamma, ..*base };
        let term = AnyTerm::new(kind, values)?;
        let m = Model::study(&params).with_term(term)?;
        let branches = m.branches()?;
        let response = response_model(&m, opts)?;
        let classification = classify(&params, &response);
        let onsets: Vec<Onset> = response
            .bursts
            .iter()
            .map(|b| {
                let branch = branches.at(b.t_peak, params.omega);
                Onset {
                    a: b.a_onset,
                    loading: branch.side > 0.0,
                    predicted: branch.nearest_prediction(b.a_onset),
                }
            })
            .collect();
        let times: Vec<f64> = response.bursts.iter().map(|b| b.onset).collect();
        let path = trajectory(&m, &params, opts, &times)?;
        Ok(MemoryCase {
            what,
            params,
            term,
            equation: m.equation(),
            classification,
            sticking: response.sticking,
            loading: BranchSummary::of(&branches.loading),
            unloading: BranchSummary::of(&branches.unloading),
            closure: branches.closure,
            onsets,
            branches,
            path,
        })
    }

    /// The largest distance in a of an onset from its branch's nearest prediction; `None` where
    /// slips dominate (stick-slip), whose bursts recur in a staircase between the branches and
    /// are not predicted one by one, or where no burst has a prediction.
    pub fn worst_onset_error(&self) -> Option<f64> {
        if self.sticking.is_some_and(|s| s.slip_dominates) {
            return None;
        }
        self.onsets
            .iter()
            .filter_map(|o| o.predicted.map(|p| (o.a - p).abs()))
            .reduce(f64::max)
    }

    /// The term as `kind (name = value, …)`.
    pub fn term_text(&self) -> String {
        let values: Vec<String> = self
            .term
            .params()
            .iter()
            .zip(self.term.values())
            .map(|(p, v)| format!("{} = {v}", p.name))
            .collect();
        format!("{} ({})", self.term.kind(), values.join(", "))
    }
}

/// The response of `m` over the burst window in the (a, x) plane, and (a, x) at each of the
/// times `onsets` (interpolated between the samples).
fn trajectory(
    m: &Model,
    p: &Params,
    opts: &BurstOptions,
    onsets: &[f64],
) -> Result<(PlanePoints, PlanePoints)> {
    let (w0, w1) = window(p, opts);
    let samples = super::control::samples(m, (w0 - TRACE_DT, w1), opts, 0)?;
    let a = |t: f64| (p.omega * t).sin();
    let at = |t: f64| {
        let i = samples
            .partition_point(|s| s.0 <= t)
            .clamp(1, samples.len() - 1);
        let ((t0, x0), (t1, x1)) = (samples[i - 1], samples[i]);
        (a(t), x0 + (x1 - x0) * (t - t0) / (t1 - t0))
    };
    let marks = if samples.len() < 2 {
        Vec::new()
    } else {
        onsets.iter().map(|&t| at(t)).collect()
    };
    Ok((samples.iter().map(|&(t, x)| (a(t), x)).collect(), marks))
}

/// The section's numbers.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MemoryEvidence {
    /// The cases of [`MEMORY_CASES`], in order.
    pub cases: Vec<MemoryCase>,
}

impl MemoryEvidence {
    /// Every case of [`MEMORY_CASES`] on `base`.
    pub fn compute(base: &Params, opts: &BurstOptions) -> Result<MemoryEvidence> {
        let cases = MEMORY_CASES
            .iter()
            .map(|&c| MemoryCase::compute(base, c, opts))
            .collect::<Result<_>>()?;
        Ok(MemoryEvidence { cases })
    }

    /// A panel per case: both branches, the response over them, the predictions and onsets.
    pub fn figure(&self) -> Figure {
        let panels = self.cases.iter().map(panel).collect();
        Figure {
            name: MEMORY_FIGURE.into(),
            caption: "With friction or hysteresis on the twist the equilibria are no longer a \
                      curve: a slow load moves the drive up the loading branch x₊(a) and down \
                      the unloading branch x₋(a), resting between them after each reversal. \
                      Thin: the simulated response over the window; crosses: what the branches \
                      predict (each branch's steepest point and its breakaway); circles: where \
                      the simulated bursts start. At the stiff point the drive sticks and slips \
                      in a staircase between the branches."
                .into(),
            size: (1000, 1400),
            panels,
            map: None,
        }
    }
}

/// The point of `b` nearest to `a` in a, as (a, x).
fn on_branch(b: &LoopBranch, a: f64) -> Option<(f64, f64)> {
    b.points
        .iter()
        .min_by(|p, q| (p.a - a).abs().total_cmp(&(q.a - a).abs()))
        .map(|p| (a, p.x))
}

/// One case's panel.
fn panel(c: &MemoryCase) -> Panel {
    let x_span = c.path.0.iter().map(|q| q.1.abs()).fold(1e-12, f64::max);
    let branch = |b: &LoopBranch, label: &str, color| Series {
        label: label.into(),
        points: decimate(
            &b.points.iter().map(|p| (p.a, p.x)).collect::<Vec<_>>(),
            1e-4 * x_span,
        ),
        color,
        style: Style::Line,
    };
    let mut markers: Vec<(f64, f64, String)> = [&c.branches.loading, &c.branches.unloading]
        .into_iter()
        .flat_map(|b| {
            b.predicted_onsets()
                .into_iter()
                .filter_map(|a| on_branch(b, a))
        })
        .map(|(a, x)| (a, x, "predicted".into()))
        .collect();
    markers.extend(c.path.1.iter().map(|&(a, x)| (a, x, "burst onset".into())));
    Panel {
        title: format!(
            "γ = {}, {}: {}",
            c.params.gamma,
            c.term_text(),
            c.classification.verdict.name()
        ),
        x_label: "a = sin(ωτ)".into(),
        y_label: "x".into(),
        x_range: Some((-1.02, 1.02)),
        series: vec![
            branch(&c.branches.loading, "loading x₊(a)", 0),
            branch(&c.branches.unloading, "unloading x₋(a)", 1),
            Series {
                label: "response".into(),
                points: decimate(&c.path.0, 1e-4 * x_span),
                color: 2,
                style: Style::Thin,
            },
        ],
        markers,
        legend_left: true,
        ..Panel::default()
    }
}

/// The section in `index.html`.
pub fn html(h: &mut String, e: &MemoryEvidence) {
    let _ = writeln!(
        h,
        "<section id=\"memory\"><h2>Friction and hysteresis: branches instead of a curve</h2>\
         <p>The study leaves out what real drives carry: friction and the hysteresis of the \
         flexspline. With either on the twist the fast subsystem's equilibria form a band, and a \
         slow load moves the drive along a loading branch x₊(a) and an unloading branch x₋(a) \
         (the quasi-static solution with x' → 0±, each followed from its breakaway after the \
         reversal). A branch predicts bursts where its tangent stiffness K<sub>t</sub> is least \
         (its steepest point, the study's mechanism on the branch) and where it leaves rest (the \
         breakaway, a slip). Each case below is the study's model with one term, simulated over \
         the same window as the study's verdicts (figure <a href=\"#fig-{MEMORY_FIGURE}\">\
         {MEMORY_FIGURE}</a>; data in <code>data/memory.json</code>).</p>\
         <table><tr><th>case</th><th>γ</th><th>term</th><th>verdict</th><th>mode</th>\
         <th>rests per period</th><th>largest slip |x'|</th><th>loading: steepest a (K<sub>t</sub>), \
         breakaway</th><th>unloading: steepest a (K<sub>t</sub>), breakaway</th><th>bursts</th>\
         <th>worst |onset − prediction| in a</th></tr>"
    );
    let branch = |b: &BranchSummary| {
        let steep = b
            .steepest
            .map_or("-".into(), |(a, k)| format!("{} ({})", num(a), num(k)));
        format!("{steep}, {}", b.breakaway.map_or("-".into(), num))
    };
    for (i, c) in e.cases.iter().enumerate() {
        let (rests, slip) = c.sticking.map_or(("-".into(), "-".into()), |s| {
            (num(s.sticks_per_period), num(s.slip_peak_speed))
        });
        let _ = writeln!(
            h,
            "<tr data-case=\"{i}\"><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>\
             <td>{rests}</td><td>{slip}</td><td>{}</td><td>{}</td><td>{}</td>{}</tr>",
            esc(c.what),
            num(c.params.gamma),
            esc(&c.term_text()),
            c.classification.verdict.name(),
            c.classification.mode.name(),
            branch(&c.loading),
            branch(&c.unloading),
            c.onsets.len(),
            cell("onset-error", c.worst_onset_error().unwrap_or(f64::NAN)),
        );
    }
    h.push_str(
        "</table><p>The last column is each case's largest distance in a between a burst's onset \
         and the nearest prediction on the branch it starts on (loading while the load rises, \
         judged at the burst's pulse); the distance shrinks as the load slows (the library's \
         tests: seven models at ω = 0.01 and 0.005). With Coulomb friction \
         f<sub>c</sub> = f<sub>s</sub> the branches are the study's curve shifted by \
         ∓f<sub>s</sub>. With the Stribeck drop at the stiff point no branch is steep and the \
         bursts are slips (stick-slip, a fourth signature beside jump, overshoot and ringing): \
         past the breakaway the drive sticks and slips in a staircase between the branches, a \
         slip each time the load has crossed the band again, so the branches bound the slips \
         but do not predict their onsets one by one (–).</p></section>\n",
    );
}
