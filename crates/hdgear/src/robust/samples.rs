//! The samples of a run: each one's verdict and measures ([`Outcome`]) or why it has none
//! ([`Failure`]), how a batch of them is judged ([`evaluate`]), and their rows in the samples
//! file ([`SampleRow`] for a study set or a drive, [`ModelSampleRow`] for a model).

use super::{Nominal, Space};
use crate::burst::{BurstOptions, Verdict};
use crate::error::Result;
use crate::model::Model;
use crate::params::{Param, Params};
use crate::physical::design::{Basis, judge_reduced};
use rayon::prelude::*;
use serde::Serialize;

/// A continuous measure of a response (or the burst indicator): what sensitivity is computed of.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Measure {
    /// 1 when bursting, else 0 (its mean is P(burst)).
    Burst,
    /// Largest |x'| in the window.
    PeakAbsXdot,
    /// Largest leading lobe, in units of X.
    MaxOvershoot,
    /// Largest ringing swing of x', in units of ω·X.
    MaxRingingSwing,
    /// peak |x'| / the equilibrium's largest speed.
    SpeedRatio,
}

impl Measure {
    /// All, in the order of the columns.
    pub const ALL: [Measure; 5] = [
        Measure::Burst,
        Measure::PeakAbsXdot,
        Measure::MaxOvershoot,
        Measure::MaxRingingSwing,
        Measure::SpeedRatio,
    ];

    /// Its column name.
    pub fn name(self) -> &'static str {
        match self {
            Measure::Burst => "burst",
            Measure::PeakAbsXdot => "peak_abs_xdot",
            Measure::MaxOvershoot => "max_overshoot",
            Measure::MaxRingingSwing => "max_ringing_swing",
            Measure::SpeedRatio => "speed_ratio",
        }
    }
}

/// The verdict on one sample, with its measures.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Outcome {
    /// Bursting or not.
    pub bursting: bool,
    /// The strongest signature (null when predicted).
    pub verdict: Option<Verdict>,
    /// Simulated or predicted.
    pub basis: Basis,
    /// Whether the sample is in the fast-slow domain.
    pub fast_slow_domain: bool,
    /// Each of [`Measure::ALL`] (NaN when predicted, but the burst indicator).
    pub measures: [f64; 5],
}

impl Outcome {
    /// The verdict's name, as the design check labels it (`ringing`, `no-bursts (predicted)`, …).
    pub fn label(&self) -> &'static str {
        crate::physical::design::Judgement {
            bursting: self.bursting,
            verdict: self.verdict,
            fast_slow_domain: self.fast_slow_domain,
            basis: self.basis,
        }
        .label()
    }
}

/// Why a sample has no verdict.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", content = "message", rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Failure {
    /// Its parameter values are outside the model's domain (a negative stiffness, …).
    OutsideDomain(String),
    /// Its integration failed.
    Solver(String),
}

/// One judged sample.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sample {
    /// Its index in the run's sequence.
    pub index: u64,
    /// The toleranced parameters' values.
    pub values: Vec<f64>,
    /// The dimensionless set it reduces to (None outside the domain).
    pub reduced: Option<Params>,
    /// The verdict, or why there is none.
    pub outcome: std::result::Result<Outcome, Failure>,
}

/// Judges the sets `values` (each the toleranced parameters' values) in parallel, in order.
pub fn evaluate(space: &Space, values: &[Vec<f64>], opts: &BurstOptions) -> Vec<Sample> {
    /// Sets per parallel task: four sixteen-lane batches.
    const TASK: usize = 4 * crate::batch::LANES;
    if let Nominal::Model(m) = &space.nominal {
        return evaluate_models(space, m, values, opts);
    }
    let reduced: Vec<Result<Params>> = values
        .iter()
        .map(|v| space.at(v).and_then(|n| n.reduced()))
        .collect();
    let judged: Vec<std::result::Result<Outcome, Failure>> = reduced
        .par_chunks(TASK)
        .flat_map_iter(|chunk| {
            let ok: Vec<Params> = chunk
                .iter()
                .filter_map(|r| r.as_ref().ok())
                .copied()
                .collect();
            let mut j = judge_reduced(&ok, opts).into_iter();
            chunk
                .iter()
                .map(|r| match r {
                    Err(e) => Err(Failure::OutsideDomain(e.to_string())),
                    Ok(_) => match j.next().expect("one verdict per valid set") {
                        Ok(judged) => Ok(outcome(judged)),
                        Err(e) => Err(Failure::Solver(e.to_string())),
                    },
                })
                .collect::<Vec<_>>()
        })
        .collect();
    values
        .iter()
        .zip(judged)
        .zip(reduced)
        .enumerate()
        .map(|(i, ((v, outcome), r))| Sample {
            index: i as u64,
            values: v.clone(),
            reduced: r.ok(),
            outcome,
        })
        .collect()
}

/// [`evaluate`] on a model's space: each sample simulated on its own (a model's terms are not
/// on the batches' lanes alike) and classified against its own equilibrium curve
/// ([`crate::physical::design::judge_model`], the drive check's verdict on a model).
fn evaluate_models(
    space: &Space,
    nominal: &Model,
    values: &[Vec<f64>],
    opts: &BurstOptions,
) -> Vec<Sample> {
    values
        .par_iter()
        .enumerate()
        .map(|(i, v)| {
            let outcome = match space.model_at(nominal, v) {
                Ok(m) => match crate::physical::design::judge_model(&m, opts) {
                    Ok(Some((o, resp))) => Ok(outcome((o.judgement, None, Some(resp)))),
                    Ok(None) => Err(Failure::Solver(format!(
                        "ω = {} is below the least simulated ({}), or the response needs more \
                         steps than a search allows; a model has no curve-only prediction",
                        m.forcing()[2],
                        crate::physical::design::MIN_SIMULATED_OMEGA
                    ))),
                    Err(e) => Err(Failure::Solver(e.to_string())),
                },
                Err(e) => Err(Failure::OutsideDomain(e.to_string())),
            };
            Sample {
                index: i as u64,
                values: v.clone(),
                reduced: None,
                outcome,
            }
        })
        .collect()
}

/// A sample as a row of the samples file: its index, the dimensionless set it reduces to, its
/// verdict and measures (NaN where there are none), and why it has no verdict (empty otherwise).
#[derive(Clone, Debug, PartialEq, Serialize, crate::output::Record)]
pub struct SampleRow {
    /// Index in the run's sequence.
    pub index: u64,
    /// α of the reduced set.
    pub alpha: f64,
    /// γ.
    pub gamma: f64,
    /// ε.
    pub eps: f64,
    /// μ.
    pub mu: f64,
    /// δ.
    pub delta: f64,
    /// ω.
    pub omega: f64,
    /// `fold-jump`, `overshoot`, `ringing`, `no-bursts`, or `bursting (predicted)` / `no-bursts
    /// (predicted)`; empty without a verdict.
    pub verdict: String,
    /// Each of [`Measure::ALL`].
    pub burst: f64,
    /// Largest |x'|.
    pub peak_abs_xdot: f64,
    /// Largest leading lobe / X.
    pub max_overshoot: f64,
    /// Largest ringing swing / (ω X).
    pub max_ringing_swing: f64,
    /// peak |x'| over the equilibrium's largest speed.
    pub speed_ratio: f64,
    /// Why there is no verdict.
    pub error: String,
}

/// A sample's columns after its parameters: the verdict's label, the measures (NaN without a
/// verdict) and why there is none (empty otherwise).
fn verdict_columns(s: &Sample) -> (String, [f64; 5], String) {
    match &s.outcome {
        Ok(o) => (o.label().to_string(), o.measures, String::new()),
        Err(Failure::OutsideDomain(e) | Failure::Solver(e)) => {
            (String::new(), [f64::NAN; 5], e.clone())
        }
    }
}

impl From<&Sample> for SampleRow {
    fn from(s: &Sample) -> SampleRow {
        let p = s
            .reduced
            .map_or([f64::NAN; 6], |p| Param::ALL.map(|q| p.value(q)));
        let (verdict, m, error) = verdict_columns(s);
        SampleRow {
            index: s.index,
            alpha: p[0],
            gamma: p[1],
            eps: p[2],
            mu: p[3],
            delta: p[4],
            omega: p[5],
            verdict,
            burst: m[0],
            peak_abs_xdot: m[1],
            max_overshoot: m[2],
            max_ringing_swing: m[3],
            speed_ratio: m[4],
            error,
        }
    }
}

/// A model's sample as a row of the samples file: its index, the toleranced parameters' values
/// under their names (a model has no reduced study set), then a [`SampleRow`]'s verdict columns.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelSampleRow {
    /// Index in the run's sequence.
    pub index: u64,
    /// (name, value) of each toleranced parameter, in the space's order.
    pub values: Vec<(&'static str, f64)>,
    /// The verdict's label (empty without one).
    pub verdict: String,
    /// Each of [`Measure::ALL`] (NaN without a verdict).
    pub measures: [f64; 5],
    /// Why there is no verdict.
    pub error: String,
}

impl ModelSampleRow {
    /// The row of sample `s` of `space`.
    pub fn of(space: &Space, s: &Sample) -> ModelSampleRow {
        let (verdict, measures, error) = verdict_columns(s);
        ModelSampleRow {
            index: s.index,
            values: space
                .tolerances
                .iter()
                .map(|t| t.target.name())
                .zip(s.values.iter().copied())
                .collect(),
            verdict,
            measures,
            error,
        }
    }

    /// The columns of `space`'s rows, in the order a row writes them.
    pub fn columns(space: &Space) -> Vec<&'static str> {
        std::iter::once("index")
            .chain(space.tolerances.iter().map(|t| t.target.name()))
            .chain(std::iter::once("verdict"))
            .chain(Measure::ALL.iter().map(|m| m.name()))
            .chain(std::iter::once("error"))
            .collect()
    }
}

impl Serialize for ModelSampleRow {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        use serde::ser::SerializeStruct;
        let mut out = s.serialize_struct("ModelSampleRow", self.values.len() + 8)?;
        out.serialize_field("index", &self.index)?;
        for (name, value) in &self.values {
            out.serialize_field(name, value)?;
        }
        out.serialize_field("verdict", &self.verdict)?;
        for (m, value) in Measure::ALL.iter().zip(&self.measures) {
            out.serialize_field(m.name(), value)?;
        }
        out.serialize_field("error", &self.error)?;
        out.end()
    }
}

fn outcome((j, _, r): crate::physical::design::Judged) -> Outcome {
    let m = r.map_or([f64::NAN; 4], |r| {
        [
            r.rates.peak_abs_xdot,
            r.signatures.max_overshoot,
            r.signatures.max_ringing_swing,
            r.measures.speed_ratio,
        ]
    });
    Outcome {
        bursting: j.bursting,
        verdict: j.verdict,
        basis: j.basis,
        fast_slow_domain: j.fast_slow_domain,
        measures: [f64::from(u8::from(j.bursting)), m[0], m[1], m[2], m[3]],
    }
}
