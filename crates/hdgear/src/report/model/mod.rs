//! The report of one assembled model (`hdgear report --config FILE` or `--card CARD`): the model
//! and its parameters, its fast subsystem, its response and verdict, its periodic orbit, its
//! frequency response and, for a card, the drive's design check; every section the model does not
//! have says why, in the words of the library's refusal, and the study's own sections name the
//! command that computes them for this model.
//!
//! Each section is the same computation the command of its name runs (`analyze`, `bursts`,
//! `periodic`, `frequency-response`, `physical`), on the same [`Model`].

mod html;

use super::files::Files;
use crate::burst::{BurstOptions, Classification, Response};
use crate::error::Result;
use crate::fast::{A_RANGE, CurveAnalysis};
use crate::model::terms::AnyTerm;
use crate::model::{AnyCurve, Description, Model, ModelParam};
use crate::output::plot::Figure;
use crate::periodic::{
    BranchRow, ContinuationOptions, OrbitBranch, PeriodicOptions, PeriodicOrbit,
};
use crate::physical::PhysicalParams;
use crate::physical::design::{DesignCheck, design_check};
use crate::simulate::{SimOptions, Start, StateSample};
use serde::Serialize;
use std::path::Path;

/// What the model report runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct ModelReportOptions {
    /// Burst detection and tolerances (the response, the orbit's verdict, the design check).
    pub burst: BurstOptions,
    /// Worker threads (0: one per core).
    pub threads: usize,
    /// Overwrite files in the output directory that hdgear did not write.
    pub force: bool,
}

/// A section of the model report: computed, or the reason the model does not have it (the
/// library's one-line refusal, which names the term).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Section<T> {
    /// Computed.
    Shown(T),
    /// Not computed, and why.
    NotApplicable(String),
}

impl<T> Section<T> {
    /// The section from a computation: its value, or its error's message as the reason.
    fn of(r: Result<T>) -> Section<T> {
        match r {
            Ok(v) => Section::Shown(v),
            Err(e) => Section::NotApplicable(e.to_string()),
        }
    }

    /// The value, if computed.
    pub fn shown(&self) -> Option<&T> {
        match self {
            Section::Shown(v) => Some(v),
            Section::NotApplicable(_) => None,
        }
    }
}

/// The response from the default start, measured and judged as `hdgear bursts` does.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ResponseEvidence {
    /// The measured response.
    pub response: Response,
    /// Its verdict, mode and mechanism.
    pub classification: Classification,
    /// (τ, x, x') every [`crate::study::SAMPLE_DT`] over the first analysed slow period, from
    /// the same start and tolerance.
    #[serde(skip)]
    pub samples: Vec<StateSample>,
}

/// The period-1 orbit, as `hdgear periodic` computes it, with the verdict on the orbit itself.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OrbitEvidence {
    /// The orbit, its multipliers and its samples.
    pub orbit: PeriodicOrbit<Model>,
    /// The burst verdict on the orbit from its own start.
    pub verdict: Classification,
}

/// A card's drive: what `hdgear physical --card` checks, in SI units.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DriveEvidence {
    /// The card's name.
    pub card: String,
    /// The drive built from the card and the documented assumptions.
    pub drive: PhysicalParams,
    /// The assumptions standing in for what the card leaves out.
    pub assumptions: Vec<&'static str>,
    /// Its design check (the reduced model without friction: the study's equation).
    pub check: DesignCheck,
}

/// A section of the study's report this report does not compute, and the command that does.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Elsewhere {
    /// The study report's section.
    pub section: &'static str,
    /// Why it is not here, and where to get it for this model.
    pub reason: String,
}

/// Everything the model report shows, computed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelReport {
    /// hdgear's version.
    pub version: &'static str,
    /// Where the model came from (a scenario file, a card), in words.
    pub origin: String,
    /// What was run.
    pub options: ModelReportOptions,
    /// The model: equation, states, terms, parameters, facts of the fast subsystem.
    pub model: Description,
    /// The fast subsystem's equilibrium curve over a ∈ [−1, 1] (`hdgear analyze`).
    pub curve: Section<CurveAnalysis>,
    /// The response and its verdict (`hdgear bursts`).
    pub response: Section<ResponseEvidence>,
    /// The period-1 orbit (`hdgear periodic`).
    pub orbit: Section<OrbitEvidence>,
    /// The frequency response (`hdgear frequency-response`).
    pub frequency: Section<OrbitBranch<ModelParam>>,
    /// The card's drive, for a model built from a card.
    pub drive: Option<DriveEvidence>,
    /// The study report's sections not computed here.
    pub elsewhere: Vec<Elsewhere>,
    /// The figures: the response, the response over the equilibrium curve, the orbit, the
    /// frequency response (those whose section was computed).
    #[serde(skip)]
    pub figures: Vec<Figure>,
}

/// A card's drive to report on beside its model: the card's name, the drive, the assumptions.
pub type CardDrive<'a> = (&'a str, &'a PhysicalParams, &'a [&'static str]);

impl ModelReport {
    /// Runs every section on `m` (described as `origin`), the independent ones side by side;
    /// with `drive` also the card's design check.
    pub fn compute(
        m: &Model,
        origin: &str,
        drive: Option<CardDrive<'_>>,
        opts: &ModelReportOptions,
    ) -> Result<ModelReport> {
        m.check()?;
        let burst = &opts.burst;
        let ((curve, response), ((orbit, frequency), drive)) = rayon::join(
            || {
                rayon::join(
                    || Section::of(curve_of(m)),
                    || Section::of(response_of(m, burst)),
                )
            },
            || {
                rayon::join(
                    || {
                        rayon::join(
                            || Section::of(orbit_of(m, burst)),
                            || {
                                Section::of(crate::periodic::frequency_response(
                                    m,
                                    None,
                                    &ContinuationOptions::default(),
                                ))
                            },
                        )
                    },
                    || drive.map(|d| drive_of(d, burst)).transpose(),
                )
            },
        );
        let drive = drive?;
        let mut report = ModelReport {
            version: env!("CARGO_PKG_VERSION"),
            origin: origin.to_string(),
            options: *opts,
            model: m.describe(),
            curve,
            response,
            orbit,
            frequency,
            elsewhere: elsewhere(drive.is_some(), m),
            drive,
            figures: Vec::new(),
        };
        report.figures = report.build_figures(m)?;
        Ok(report)
    }

    /// The figures of the computed sections.
    fn build_figures(&self, m: &Model) -> Result<Vec<Figure>> {
        let mut figures = Vec::new();
        if let Some(r) = self.response.shown() {
            figures.push(crate::figures::response_figure(
                &r.samples,
                &r.response,
                &r.classification,
            ));
            if let Ok(c) = AnyCurve::of(m) {
                let omega = m.forcing()[2];
                figures.push(match c {
                    AnyCurve::Torque(c) => crate::figures::fast_slow_figure(&c, &r.samples, omega),
                    AnyCurve::Scheduled(c) => {
                        crate::figures::fast_slow_figure(&c, &r.samples, omega)
                    }
                });
            }
        }
        if let Some(o) = self.orbit.shown() {
            figures.push(crate::figures::orbit_figure(&o.orbit, &o.verdict));
        }
        if let Some(b) = self.frequency.shown() {
            figures.push(crate::figures::frequency_response_figure(m, b));
        }
        Ok(figures)
    }

    /// Writes the report into `dir` (files hdgear did not write there are refused unless
    /// `force`): the data behind each section, the figures as SVG and PNG, and `index.html`.
    pub fn write(&self, dir: &Path, force: bool) -> Result<Vec<String>> {
        self.write_into(Files::open(dir, force)?)
    }

    fn write_into(&self, mut out: Files) -> Result<Vec<String>> {
        out.json("data/model-report.json", self)?;
        if let Some(r) = self.response.shown() {
            out.csv("data/response.csv", &r.samples)?;
        }
        if let Some(o) = self.orbit.shown() {
            let rows: Vec<StateSample> = o.orbit.samples.iter().map(|&s| s.into()).collect();
            out.csv("data/orbit.csv", &rows)?;
        }
        if let Some(b) = self.frequency.shown() {
            let rows: Vec<BranchRow> = b.points.iter().map(|q| BranchRow::new(0, 1, q)).collect();
            out.csv("data/frequency-response.csv", &rows)?;
        }
        let svgs = out.figures(&self.figures)?;
        out.bytes("index.html", html::render(self, &svgs).as_bytes())?;
        Ok(out.written)
    }
}

/// The equilibrium curve's analysis, as `hdgear analyze` gives it.
fn curve_of(m: &Model) -> Result<CurveAnalysis> {
    Ok(crate::study::analyze_model(m, A_RANGE, None, Vec::new())?.analysis)
}

/// The response from the default start, with one slow period's samples from the same start.
fn response_of(m: &Model, opts: &BurstOptions) -> Result<ResponseEvidence> {
    let response = crate::burst::response_model(m, opts)?;
    let classification = crate::burst::classify_model(m, &response)?;
    let t0 = response.window_start;
    let sim = SimOptions {
        t_end: t0 + std::f64::consts::TAU / m.forcing()[2],
        dt: crate::study::SAMPLE_DT,
        start: Start::Equilibrium,
        tol: opts.tol,
    };
    let mut samples = Vec::new();
    crate::simulate::simulate_model(m, &sim, |t, y| {
        if t >= t0 {
            samples.push(StateSample {
                t,
                x: y[0],
                xdot: y[1],
            });
        }
    })?;
    Ok(ResponseEvidence {
        response,
        classification,
        samples,
    })
}

/// The period-1 orbit from the default start and its verdict.
fn orbit_of(m: &Model, opts: &BurstOptions) -> Result<OrbitEvidence> {
    let orbit = crate::periodic::shoot(m, 1, &PeriodicOptions::default())?;
    let verdict = crate::periodic::burst_verdict(&orbit, opts)?;
    Ok(OrbitEvidence { orbit, verdict })
}

/// The card's drive and its design check.
fn drive_of((card, d, assumptions): CardDrive<'_>, opts: &BurstOptions) -> Result<DriveEvidence> {
    Ok(DriveEvidence {
        card: card.to_string(),
        drive: *d,
        assumptions: assumptions.to_vec(),
        check: design_check(d, opts)?,
    })
}

/// The study report's sections this report leaves out, each with the command that computes it
/// for this model (built from a card when `card`, else from a scenario file).
fn elsewhere(card: bool, m: &Model) -> Vec<Elsewhere> {
    let source = if card { "--card CARD" } else { "--config FILE" };
    // an example name: the first parameter of a term beyond the study's, qualified as the
    // sweeps take it, else the load's amplitude
    let name = m
        .terms()
        .map(|t| t.kind())
        .filter(|&k| Model::is_extra_kind(k))
        .find_map(|k| Some(format!("{k}.{}", AnyTerm::params_of(k)?.first()?.name)))
        .unwrap_or_else(|| crate::params::Param::Delta.name().to_string());
    let mut v = vec![
        Elsewhere {
            section: "Tables 1 and 2",
            reason: "the study's modes at its four γ and its claims about α, γ, δ, ω are \
                     statements about the study's cubic at the study's point; `hdgear table` \
                     measures them"
                .into(),
        },
        Elsewhere {
            section: "Sweeps and maps",
            reason: format!(
                "a map needs the axes that matter for this model; `hdgear sweep {source} --param \
                 {name}=LO:HI:N` varies any of its parameters by name"
            ),
        },
        Elsewhere {
            section: "Bursting boundaries",
            reason: format!(
                "`hdgear boundary {source} --param {name}=LO:HI --param ...` traces them in \
                 any two of its parameters"
            ),
        },
        Elsewhere {
            section: "Burst control",
            reason: format!(
                "`hdgear control {source}` adds each law to this model, its terms included, and \
                 tunes it there"
            ),
        },
        Elsewhere {
            section: "Design under manufacturing spread",
            reason: format!(
                "`hdgear robust {source} --tolerance {name}=±20%` spreads any of its parameters"
            ),
        },
    ];
    if !card {
        v.push(Elsewhere {
            section: "A physical drive",
            reason: "a dimensionless model has no SI units; `hdgear report --card CARD` reports \
                     on a catalogue drive with its design check"
                .into(),
        });
    }
    v
}

/// Builds the model report of `m` into `dir`: checks the directory, computes
/// ([`ModelReport::compute`]) and writes ([`ModelReport::write`]); returns the files written,
/// relative to `dir`.
pub fn build(
    dir: &Path,
    m: &Model,
    origin: &str,
    drive: Option<CardDrive<'_>>,
    opts: &ModelReportOptions,
) -> Result<Vec<String>> {
    // refuse a directory with foreign files before computing anything
    let out = Files::open(dir, opts.force)?;
    let run = move || ModelReport::compute(m, origin, drive, opts)?.write_into(out);
    if opts.threads == 0 {
        return run();
    }
    crate::sweep::pool(opts.threads)?.install(run)
}
