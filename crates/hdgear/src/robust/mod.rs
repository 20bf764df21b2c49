//! The design check under manufacturing spread: how likely a drive whose parameters spread is to
//! burst ([`probability`]), its worst case and margin ([`worst_case`]), and which tolerance
//! matters ([`sensitivity`]).
//!
//! A [`Space`] is a nominal parameter set (the study's dimensionless one, a drive in SI units, or
//! an assembled [`Model`] with any of its terms' parameters) with a [`Tolerance`] on some of its
//! parameters. Every sample is judged as the design check judges a drive
//! ([`crate::physical::design::judge`]): reduced, simulated on the sixteen-lane batches and
//! classified by its signatures, or predicted from the equilibrium curve when its reduced ω is
//! too small to simulate (each sample says which). A model's samples are simulated one by one
//! and classified against the model's own equilibrium curve. Sample i of a run is a function
//! of the seed and i alone ([`sequence`]), so a run is reproducible to the byte on any thread
//! count and in any shard split.
//!
//! **Why one file.** The nominal drive, its tolerance space, the Monte Carlo options and the
//! probability with its interval are the vocabulary the samplers, the worst case and the Sobol
//! indices (their own files) all use.

use crate::burst::BurstOptions;
use crate::error::{Error, Result};
use crate::model::{Model, ModelParam};
use crate::params::{Param, Params};
use crate::physical::design::Basis;
use crate::physical::{DriveParam, PhysicalParams};
use serde::{Deserialize, Serialize};

pub mod importance;
mod load;
mod samples;
pub mod sequence;
pub mod sobol;
pub use sobol::{MAX_DESIGN_RUNS, Sensitivity, sensitivity};
mod worst;

pub use crate::distribution::{
    Distribution, normal_cdf, normal_quantile, samples_for_width, wilson,
};
pub use importance::{DesignPoint, Importance, design_point, importance};
pub use load::{LoadPoint, load_curve, load_factors, load_target};
pub use samples::{Failure, Measure, ModelSampleRow, Outcome, Sample, SampleRow, evaluate};
pub use sequence::{Points, Sampler};
pub use worst::{Corner, WorstCase, worst_case};

/// The parameter set the tolerances spread around.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", content = "values", rename_all = "kebab-case")]
#[expect(
    clippy::large_enum_variant,
    reason = "one nominal per space, copied once per sample beside a whole simulation; a model \
              stays a stack value (Copy) as everywhere else"
)]
pub enum Nominal {
    /// A dimensionless set.
    Study(Params),
    /// A drive in SI units (each sample reduced).
    Drive(PhysicalParams),
    /// An assembled model (a scenario's terms): any of its parameters spreads.
    Model(Model),
}

/// A parameter that spreads: one of the nominal set's own.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(untagged)]
pub enum Target {
    /// A dimensionless parameter.
    Study(Param),
    /// A drive parameter.
    Drive(DriveParam),
    /// A parameter of a model's forcing or terms.
    Model(ModelParam),
}

impl Target {
    /// The name users write (`gamma`, `k1`, …).
    pub fn name(self) -> &'static str {
        match self {
            Target::Study(p) => p.name(),
            Target::Drive(p) => p.name(),
            Target::Model(p) => p.name(),
        }
    }
}

impl Nominal {
    /// The parameter called `name` in this kind of set.
    pub fn target(&self, name: &str) -> Result<Target> {
        Ok(match self {
            Nominal::Study(_) => Target::Study(name.parse()?),
            Nominal::Drive(_) => Target::Drive(name.parse()?),
            Nominal::Model(m) => Target::Model(m.param(name)?),
        })
    }

    /// The value of a parameter of this kind of set.
    pub fn value(&self, t: Target) -> f64 {
        match (self, t) {
            (Nominal::Study(p), Target::Study(q)) => p.value(q),
            (Nominal::Drive(d), Target::Drive(q)) => d.value(q),
            (Nominal::Model(m), Target::Model(q)) => m.get(q),
            _ => f64::NAN,
        }
    }

    /// The set with one parameter changed (a model's value checked against its domain; a
    /// study set or a drive is checked by [`Nominal::check`]).
    pub fn with(self, t: Target, v: f64) -> Result<Nominal> {
        Ok(match (self, t) {
            (Nominal::Study(p), Target::Study(q)) => Nominal::Study(p.with(q, v)),
            (Nominal::Drive(d), Target::Drive(q)) => Nominal::Drive(d.with(q, v)),
            (Nominal::Model(m), Target::Model(q)) => Nominal::Model(m.with(q, v)?),
            (n, _) => n,
        })
    }

    /// The dimensionless set it stands for (a drive reduced), checked; a model with terms has
    /// none (it is judged on its own equilibrium curve).
    pub fn reduced(&self) -> Result<Params> {
        match self {
            Nominal::Study(p) => {
                p.validate()?;
                Ok(*p)
            }
            Nominal::Drive(d) => Ok(d.reduce()?.params),
            Nominal::Model(m) => Err(Error::InvalidInput {
                what: "model",
                text: m.equation(),
                reason: "a model with terms has no reduced study set".into(),
            }),
        }
    }

    /// Checks that the set is inside the model's domain.
    pub fn check(&self) -> Result<()> {
        match self {
            Nominal::Model(m) => m.check(),
            n => n.reduced().map(drop),
        }
    }
}

/// One parameter's spread, with where it comes from.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Tolerance {
    /// The parameter.
    pub target: Target,
    /// Its distribution.
    pub distribution: Distribution,
    /// Its source (`assumption: …` for a default, `user` for one given).
    pub source: String,
}

/// Default spreads of a drive's parameters when the user gives none, each an assumption: the
/// catalogues give single typical values and state no scatter (REAL-DRIVES.md C4), so these are
/// orders of magnitude an engineer would start from, to be replaced by measured ones.
pub const DRIVE_DEFAULTS: [(DriveParam, f64, &str); 6] = [
    (
        DriveParam::K1,
        0.15,
        "assumption: catalogue stiffness is a typical value, ±15 %",
    ),
    (
        DriveParam::K2,
        0.15,
        "assumption: catalogue stiffness is a typical value, ±15 %",
    ),
    (
        DriveParam::CEq,
        0.30,
        "assumption: hysteresis loss (damping) ±30 %",
    ),
    (DriveParam::Backlash, 0.25, "assumption: lost motion ±25 %"),
    (DriveParam::JOut, 0.10, "assumption: load inertia ±10 %"),
    (
        DriveParam::TAm,
        0.20,
        "assumption: disturbance amplitude ±20 %",
    ),
];

/// The least probability outside the range a spread's reach is checked over, for a spread
/// without bounds (normal, log-normal): no run draws enough samples (10⁶ is already a large
/// one) for one in 10⁶ beyond it to matter, while a spread that reaches a zero or negative
/// stiffness within it is a modelling error, not a tail.
const REACH_TAIL: f64 = 1e-6;

/// Checks that a tolerance keeps its parameter where the model exists: the set with the
/// parameter at each end of the spread (a band's own ends; the [`REACH_TAIL`] quantiles of an
/// unbounded one) is valid. A ±100 % band on a stiffness, or a band out to 1e300, is refused,
/// naming the value it reaches and why that value is refused.
fn check_reach(nominal: &Nominal, t: &Tolerance) -> Result<()> {
    let ends = match t.distribution {
        Distribution::Uniform { lo, hi } | Distribution::TruncatedNormal { lo, hi, .. } => [lo, hi],
        d => [d.quantile(REACH_TAIL), d.quantile(1.0 - REACH_TAIL)],
    };
    for v in ends {
        if let Err(e) = nominal.with(t.target, v).and_then(|n| n.check()) {
            return Err(Error::InvalidInput {
                what: "tolerance",
                text: t.target.name().into(),
                reason: format!(
                    "its spread reaches {v:e}, where {e}; narrow it (a lognormal: spread stays \
                     above 0)"
                ),
            });
        }
    }
    Ok(())
}

/// A nominal set with its tolerances.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Space {
    /// The nominal set.
    pub nominal: Nominal,
    /// The spreads, one per parameter.
    pub tolerances: Vec<Tolerance>,
}

impl Space {
    /// A checked space: a valid nominal set, at least one tolerance, each of its own kind of
    /// parameter, none twice, each distribution valid.
    pub fn new(nominal: Nominal, tolerances: Vec<Tolerance>) -> Result<Space> {
        nominal.check()?;
        if tolerances.is_empty() {
            return Err(Error::InvalidInput {
                what: "tolerances",
                text: String::new(),
                reason: "give at least one (NAME=±X%)".into(),
            });
        }
        for (i, t) in tolerances.iter().enumerate() {
            if nominal.value(t.target).is_nan() {
                return Err(Error::InvalidInput {
                    what: "tolerance",
                    text: t.target.name().into(),
                    reason: "not a parameter of the nominal set".into(),
                });
            }
            if tolerances[..i].iter().any(|u| u.target == t.target) {
                return Err(Error::InvalidInput {
                    what: "tolerance",
                    text: t.target.name().into(),
                    reason: "given twice".into(),
                });
            }
            t.distribution.validate()?;
            check_reach(&nominal, t)?;
        }
        Ok(Space {
            nominal,
            tolerances,
        })
    }

    /// A tolerance as users write it, `NAME=SPEC` ([`Distribution::parse`] reads SPEC around the
    /// nominal value).
    pub fn parse_tolerance(nominal: &Nominal, text: &str) -> Result<Tolerance> {
        let (name, spec) = text.split_once('=').ok_or_else(|| Error::InvalidInput {
            what: "tolerance",
            text: text.to_string(),
            reason: "expected NAME=SPEC (k1=±20%, gamma=normal:0.1)".into(),
        })?;
        let target = nominal.target(name.trim())?;
        Ok(Tolerance {
            target,
            distribution: Distribution::parse(spec, nominal.value(target))?,
            source: "user".into(),
        })
    }

    /// A drive's default tolerances ([`DRIVE_DEFAULTS`]).
    pub fn drive_defaults(d: &PhysicalParams) -> Vec<Tolerance> {
        DRIVE_DEFAULTS
            .iter()
            .map(|&(p, band, source)| {
                let v = d.value(p);
                Tolerance {
                    target: Target::Drive(p),
                    distribution: Distribution::Uniform {
                        lo: v - band * v.abs(),
                        hi: v + band * v.abs(),
                    },
                    source: source.into(),
                }
            })
            .collect()
    }

    /// A drive's tolerances from its card: the card's bands (with the card's source) where it
    /// has them, [`DRIVE_DEFAULTS`] for the other parameters.
    pub fn card_tolerances(
        d: &PhysicalParams,
        card: &crate::physical::card::Card,
        sources: &std::collections::BTreeMap<String, crate::physical::card::Source>,
    ) -> Result<Vec<Tolerance>> {
        let nominal = Nominal::Drive(*d);
        let mut out = Space::drive_defaults(d);
        let Some(t) = &card.tolerance else {
            return Ok(out);
        };
        let source = sources.get(&t.source).map_or(t.source.clone(), |s| {
            format!("card {}: {}", card.name, s.cite)
        });
        for (name, spec) in &t.bands {
            let mut tol = Space::parse_tolerance(&nominal, &format!("{name}={spec}"))?;
            tol.source.clone_from(&source);
            match out.iter_mut().find(|u| u.target == tol.target) {
                Some(u) => *u = tol,
                None => out.push(tol),
            }
        }
        Ok(out)
    }

    /// Number of toleranced parameters.
    pub fn dims(&self) -> usize {
        self.tolerances.len()
    }

    /// The parameter values at a point of the unit cube (each coordinate a quantile).
    pub fn values(&self, unit: &[f64]) -> Vec<f64> {
        self.tolerances
            .iter()
            .zip(unit)
            .map(|(t, &u)| t.distribution.quantile(u))
            .collect()
    }

    /// The nominal set with the toleranced parameters at `values` (a model's changed all at
    /// once, so a rule between two of them is judged on the pair: [`Model::with_all`]).
    pub fn at(&self, values: &[f64]) -> Result<Nominal> {
        if let Nominal::Model(m) = &self.nominal {
            return self.model_at(m, values).map(Nominal::Model);
        }
        self.tolerances
            .iter()
            .zip(values)
            .try_fold(self.nominal, |n, (t, &v)| n.with(t.target, v))
    }

    /// [`Space::at`] of a model space whose nominal model is `m`.
    fn model_at(&self, m: &Model, values: &[f64]) -> Result<Model> {
        let changes: Vec<(ModelParam, f64)> = self
            .tolerances
            .iter()
            .zip(values)
            .filter_map(|(t, &v)| match t.target {
                Target::Model(q) => Some((q, v)),
                _ => None,
            })
            .collect();
        m.with_all(&changes)
    }

    /// The nominal values of the toleranced parameters.
    pub fn nominal_values(&self) -> Vec<f64> {
        self.tolerances
            .iter()
            .map(|t| self.nominal.value(t.target))
            .collect()
    }
}

/// How a probability is estimated.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct McOptions {
    /// Samples (indices `first .. first + samples` of the sequence).
    pub samples: u64,
    /// The first index (a shard's start).
    pub first: u64,
    /// Sobol or random points.
    pub sampler: Sampler,
    /// The seed.
    pub seed: u64,
    /// Two-sided confidence of the interval (default 0.95).
    pub level: f64,
    /// The interval width asked for: the samples it needs are reported.
    pub width: f64,
}

impl Default for McOptions {
    fn default() -> Self {
        McOptions {
            samples: 4096,
            first: 0,
            sampler: Sampler::Sobol,
            seed: 1,
            level: 0.95,
            width: 0.02,
        }
    }
}

impl McOptions {
    /// The index after the run's last sample, checked against the points' `capacity`; the
    /// error names the option that asked for the samples (`samples`, `importance`) and the
    /// index its run would end at (a shard's block ends inside the whole run's).
    pub fn end(&self, points: &Points, option: &'static str) -> Result<u64> {
        let end = self.first.checked_add(self.samples);
        end.filter(|&e| e <= points.capacity())
            .ok_or(Error::InvalidOption {
                name: option,
                value: self.first as f64 + self.samples as f64,
                reason: "the sampler's sequence has fewer points (the Sobol sequence has 2³²)",
            })
    }

    /// Checks the options.
    pub fn validate(&self) -> Result<()> {
        let bad = crate::error::bad_option;
        if self.samples == 0 {
            return bad("samples", 0.0, "must be at least 1");
        }
        if !(self.level > 0.0 && self.level < 1.0) {
            return bad("level", self.level, "must lie in (0, 1)");
        }
        if !(self.width > 0.0 && self.width < 1.0) {
            return bad("width", self.width, "must lie in (0, 1)");
        }
        Ok(())
    }
}

/// P(burst) over a run's samples.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Probability {
    /// Samples drawn.
    pub samples: u64,
    /// Samples with a verdict.
    pub judged: u64,
    /// Of them bursting.
    pub bursting: u64,
    /// Of the verdicts, how many were predicted (reduced ω too small to simulate).
    pub predicted: u64,
    /// Samples outside the model's domain (excluded).
    pub outside_domain: u64,
    /// Samples whose integration failed (excluded).
    pub failed: u64,
    /// bursting / judged.
    #[serde(deserialize_with = "crate::output::nan_if_null")]
    pub p: f64,
    /// Wilson interval at `level`.
    pub interval: (f64, f64),
    /// Its confidence.
    pub level: f64,
    /// Samples an interval `width` wide needs at this p.
    pub needed_for_width: u64,
    /// The width asked for.
    pub width: f64,
}

impl Probability {
    /// No samples counted yet, at this confidence `level` and interval `width`.
    fn none(level: f64, width: f64) -> Probability {
        Probability {
            samples: 0,
            judged: 0,
            bursting: 0,
            predicted: 0,
            outside_domain: 0,
            failed: 0,
            p: f64::NAN,
            interval: (0.0, 1.0),
            level,
            needed_for_width: 0,
            width,
        }
    }

    /// Counts a run's samples.
    pub fn of(samples: &[Sample], mc: &McOptions) -> Probability {
        let mut p = Probability::none(mc.level, mc.width);
        p.add(samples);
        p.finish()
    }

    /// The probability over the samples of several shards of one run (their counts added).
    pub fn merge(parts: &[Probability]) -> Result<Probability> {
        let first = parts.first().ok_or_else(|| no_parts("probability"))?;
        let mut total = Probability::none(first.level, first.width);
        for p in parts {
            if (p.level, p.width) != (first.level, first.width) {
                return Err(Error::InvalidInput {
                    what: "shards",
                    text: format!("level {} width {}", p.level, p.width),
                    reason: "the shards were run with different levels or widths".into(),
                });
            }
            total.samples += p.samples;
            total.judged += p.judged;
            total.bursting += p.bursting;
            total.predicted += p.predicted;
            total.outside_domain += p.outside_domain;
            total.failed += p.failed;
        }
        Ok(total.finish())
    }

    fn add(&mut self, samples: &[Sample]) {
        for s in samples {
            self.samples += 1;
            match &s.outcome {
                Ok(o) => {
                    self.judged += 1;
                    self.bursting += u64::from(o.bursting);
                    self.predicted += u64::from(o.basis == Basis::Prediction);
                }
                Err(Failure::OutsideDomain(_)) => self.outside_domain += 1,
                Err(Failure::Solver(_)) => self.failed += 1,
            }
        }
    }

    fn finish(mut self) -> Probability {
        self.p = self.bursting as f64 / self.judged as f64;
        self.interval = wilson(self.bursting, self.judged, self.level);
        let p = if self.judged > 0 { self.p } else { 0.5 };
        self.needed_for_width = samples_for_width(p, self.width, self.level);
        self
    }
}

fn no_parts(what: &'static str) -> Error {
    Error::InvalidInput {
        what,
        text: String::new(),
        reason: "nothing to merge".into(),
    }
}

/// Samples per streamed chunk: the memory a run holds whatever its size.
pub const CHUNK: u64 = 4096;

/// Estimates P(burst) from `mc.samples` samples of `space`, judged in chunks of [`CHUNK`];
/// `each` sees every chunk's samples in order (to write them out) and may stop the run with an
/// error.
///
/// ```
/// use hdgear::{Params, burst::BurstOptions};
/// use hdgear::robust::{McOptions, Nominal, Space, probability};
/// let nominal = Nominal::Study(Params { gamma: 30.0, ..Params::default() });
/// let t = Space::parse_tolerance(&nominal, "gamma=±10%").unwrap();
/// let space = Space::new(nominal, vec![t]).unwrap();
/// let mc = McOptions { samples: 32, ..McOptions::default() };
/// let p = probability(&space, &BurstOptions::default(), &mc, |_| Ok(())).unwrap();
/// assert_eq!((p.samples, p.bursting), (32, 0)); // γ = 27 … 33 lies far from the boundary
/// ```
pub fn probability(
    space: &Space,
    opts: &BurstOptions,
    mc: &McOptions,
    mut each: impl FnMut(&[Sample]) -> Result<()>,
) -> Result<Probability> {
    mc.validate()?;
    opts.validate()?;
    let points = Points::new(mc.sampler, mc.seed, space.dims())?;
    let end = mc.end(&points, "samples")?;
    let mut total = Probability::of(&[], mc);
    let mut start = mc.first;
    while start < end {
        let stop = (start + CHUNK).min(end);
        let values: Vec<Vec<f64>> = (start..stop)
            .map(|i| {
                let mut u = vec![0.0; space.dims()];
                points.point(i, &mut u);
                space.values(&u)
            })
            .collect();
        let mut samples = evaluate(space, &values, opts);
        for s in &mut samples {
            s.index += start;
        }
        total.add(&samples);
        each(&samples)?;
        start = stop;
    }
    Ok(total.finish())
}

/// Everything the design check under spread reports: the one page of a design review.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RobustAnalysis {
    /// The space.
    pub space: Space,
    /// P(burst).
    pub probability: Probability,
    /// The sampling options.
    pub sampling: McOptions,
    /// Worst case and margin (None when not asked for).
    pub worst: Option<WorstCase>,
    /// P(burst) by importance sampling (None when not asked for).
    pub importance: Option<Importance>,
    /// Sobol indices (None when not asked for).
    pub sensitivity: Option<Sensitivity>,
    /// The catalogue's resonance rule (drives only).
    pub resonance: Option<Resonance>,
    /// P(burst) against the load amplitude (None when not asked for).
    pub load_curve: Option<Vec<LoadPoint>>,
    /// The shard (K, N) this is part K of (None: a whole run).
    pub shard: Option<(u64, u64)>,
}

/// What [`analyse`] computes beside P(burst).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AnalysisOptions {
    /// The sampling of P(burst).
    pub mc: McOptions,
    /// The worst case and margin.
    pub worst: bool,
    /// Sobol indices from a Saltelli design of this many rows.
    pub sobol: Option<usize>,
    /// P(burst) also by importance sampling, from the samples of these indices (a shard's
    /// block, or `0..n`).
    pub importance: Option<std::ops::Range<u64>>,
    /// P(burst) at [`load_factors`] times the load amplitude, from this many samples each.
    pub load_curve: Option<u64>,
    /// The shard (K, N) the run is, recorded for merging.
    pub shard: Option<(u64, u64)>,
}

/// P(burst), then the worst case, P(burst) by importance sampling and the Sobol indices when
/// asked for; `each` sees the
/// samples of P(burst) chunk by chunk ([`probability`]).
pub fn analyse(
    space: &Space,
    opts: &BurstOptions,
    a: &AnalysisOptions,
    each: impl FnMut(&[Sample]) -> Result<()>,
) -> Result<RobustAnalysis> {
    // what cannot be run is refused before the sampling, not after it: a design that cannot be
    // held, importance samples beyond the sequence
    if let Some(n) = a.sobol {
        sobol::check_design(n, space.dims())?;
    }
    let importance_mc = a.importance.clone().map(|r| McOptions {
        samples: r.end.saturating_sub(r.start),
        first: r.start,
        ..a.mc
    });
    if let Some(mc) = &importance_mc {
        space.check_importance()?;
        mc.end(
            &Points::new(mc.sampler, mc.seed, space.dims() + 1)?,
            "importance",
        )?;
    }
    let probability = probability(space, opts, &a.mc, each)?;
    let worst = a.worst.then(|| worst_case(space, opts)).transpose()?;
    let importance = importance_mc
        .map(|mc| importance(space, opts, &mc))
        .transpose()?;
    let load_curve = a
        .load_curve
        .map(|n| {
            let mc = McOptions {
                samples: n,
                first: 0,
                ..a.mc
            };
            load_curve(space, opts, &mc)
        })
        .transpose()?;
    let sensitivity = a
        .sobol
        .map(|n| sobol::sensitivity(space, opts, n, a.mc.sampler, a.mc.seed))
        .transpose()?;
    Ok(RobustAnalysis {
        space: space.clone(),
        probability,
        sampling: a.mc,
        worst,
        importance,
        sensitivity,
        resonance: resonance(space),
        load_curve,
        shard: a.shard,
    })
}

/// The catalogue's selection rule for the torsional mode: f_n = √(k1/J_o)/(2π) at least the
/// application's minimum (Harmonic Drive's selection procedure).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Resonance {
    /// f_n at the nominal values \[Hz\].
    pub nominal_hz: f64,
    /// The lowest f_n over the tolerance box (k1 at its low edge, J_o at its high edge) \[Hz\].
    pub lowest_hz: f64,
    /// The application's own requirement (a card's `application.resonance_required`) \[Hz\].
    pub required_hz: Option<f64>,
}

/// The applications of the selection rule and their minimum f_n \[Hz\].
pub const APPLICATIONS: [(&str, f64); 4] = [
    ("slow-turntable", 4.0),
    ("robot-base", 8.0),
    ("hand-axis", 15.0),
    ("milling-head", 20.0),
];

/// The selection rule's frequencies for a drive space (None for a study set).
pub fn resonance(space: &Space) -> Option<Resonance> {
    let Nominal::Drive(d) = space.nominal else {
        return None;
    };
    let f = |k1: f64, j: f64| (k1 / j).sqrt() / (2.0 * std::f64::consts::PI);
    let edge = |p: DriveParam, low: bool| {
        space
            .tolerances
            .iter()
            .find(|t| t.target == Target::Drive(p))
            .map_or(d.value(p), |t| {
                let (lo, hi) = t.distribution.range();
                if low { lo } else { hi }
            })
    };
    Some(Resonance {
        nominal_hz: f(d.k1, d.j_out),
        lowest_hz: f(edge(DriveParam::K1, true), edge(DriveParam::JOut, false)),
        required_hz: None,
    })
}
