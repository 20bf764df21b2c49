//! The self-contained HTML report that reproduces the study (`hdgear report`).
//!
//! Computed once, then rendered: [`Report::compute`] runs every computation (each study response
//! integrated once, through a [`Study`]), [`html::render`] turns the [`Report`] into
//! `index.html` (everything inline: SVG figures, CSS; no JavaScript, no network), and
//! [`Report::write`] puts it, the figures as SVG and PNG and the data behind every table and
//! figure as CSV/JSON into a directory. Table cells carry their exact values in `data-value`
//! attributes so tests (and scripts) can check them against `hdgear table --json`.
//!
//! A model of the user's own (`hdgear report --config FILE`, `--card CARD`) gets its own,
//! shorter document: [`model::ModelReport`].

pub mod control;
mod files;
pub mod html;
mod markup;
pub mod memory;
pub mod model;
pub mod periodic;
pub mod plane;
pub mod robust;

use crate::burst::{Boundaries, BurstOptions};
use crate::error::Result;
use crate::fast::{A_RANGE, CurvePoint, curve};
use crate::figures::FigureKind;
use crate::output::plot::Figure;
use crate::params::Params;
use crate::physical::PhysicalParams;
use crate::physical::catalogue::{CatalogueDrive, CubicFit};
use crate::physical::design::{DesignCheck, design_check};
use crate::physical::simulate::{ReductionCheck, check_reduction};
use crate::study::{Case, GridRun, Study};
use crate::table::{STUDY_GAMMAS, Tables, tables_in};
use files::Files;
use serde::Serialize;
use std::path::Path;

/// What the report runs.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ReportOptions {
    /// The study's point (γ varies where the study varies it).
    pub base: Params,
    /// Burst detection and tolerances.
    pub burst: BurstOptions,
    /// Points of the γ sweep.
    pub sweep_points: usize,
    /// Grid of the (γ, δ) map.
    pub map_size: (usize, usize),
    /// Tolerance (rtol = atol) of the γ sweep and the map, which only need verdicts and counts.
    pub grid_tol: f64,
    /// Worker threads (0: one per core): the grids' in [`Report::compute`], every stage's in
    /// [`build`].
    pub threads: usize,
    /// Overwrite files in the output directory that hdgear did not write (see [`MANIFEST`]).
    pub force: bool,
}

/// The file in the output directory that lists what hdgear wrote there; only those files are
/// overwritten without [`ReportOptions::force`].
pub const MANIFEST: &str = ".hdgear-report";

impl Default for ReportOptions {
    fn default() -> Self {
        ReportOptions {
            base: Params::default(),
            burst: BurstOptions::default(),
            sweep_points: 160,
            map_size: (60, 36),
            // the default (with Taylor a looser tolerance takes more steps: see
            // `burst::CLASSIFICATION_TOL`)
            grid_tol: crate::integrate::Options::default().rtol,
            threads: 0,
            force: false,
        }
    }
}

/// What was written.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ReportSummary {
    /// Files written, relative to the output directory.
    pub files: Vec<String>,
    /// The tables shown.
    pub tables: Tables,
}

/// The report's figures, in order: the kind, the γ it is drawn at (`None`: the study's point),
/// and its file stem.
pub const FIGURES: [(FigureKind, Option<f64>, &str); 9] = [
    (FigureKind::XdotGamma, None, "xdot-gamma"),
    (FigureKind::XEquilibrium, Some(1.0), "x-equilibrium"),
    (
        FigureKind::TransformedPhase,
        Some(0.1),
        "transformed-phase-g0.1",
    ),
    (
        FigureKind::TransformedPhase,
        Some(0.01),
        "transformed-phase-g0.01",
    ),
    (FigureKind::PhasePlane, Some(1.0), "phase-plane"),
    (FigureKind::Slope, None, "slope"),
    (FigureKind::Sweep, None, "sweep"),
    (FigureKind::Map, None, "map"),
    (FigureKind::Boundary, None, "boundary"),
];

/// Figures of the periodic section, built from its computations (see
/// [`periodic::PeriodicEvidence::figures`]), in order: the figure kind they are an instance of
/// (None: the drive's response in SI units, which only `hdgear physical --frequency-response
/// --plot` draws, and the (ω, δ) plane, which `hdgear continue2 --plot` and `hdgear boundary
/// --plot` draw in parts) and the file stem.
pub const PERIODIC_FIGURES: [(Option<FigureKind>, &str); 5] = [
    (Some(FigureKind::FrequencyResponse), "frequency-response"),
    (Some(FigureKind::OrbitDiagram), "orbit-diagram-g10"),
    (Some(FigureKind::LyapunovMap), "lyapunov-map-g10"),
    (None, "physical-frequency-response"),
    (None, "plane-omega-delta"),
];

/// The drive of the physical section.
pub const PHYSICAL_DRIVE: &str = "CSF-20-50";

/// The dimensionless span [`check_reduction`] compares the two-inertia model and its reduction
/// over, and the tolerance of both simulations.
pub const REDUCTION_CHECK: (f64, f64) = (300.0, 1e-12);

/// The stages of [`Report::compute`] and [`Report::write`], in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Stage {
    /// The study's responses (once each) and both tables.
    Tables,
    /// The γ sweep.
    Sweep,
    /// The (γ, δ) map.
    Map,
    /// The physical drive and the bursting boundaries, and beside them the periodic response:
    /// orbits, continuation, orbit diagram, Lyapunov map (independent computations, run
    /// together).
    PhysicalAndPeriodic,
    /// Building the figures from what was computed.
    Figures,
    /// Rendering and writing the files.
    Writing,
}

impl Stage {
    /// Every stage, in order.
    pub const ALL: [Stage; 6] = [
        Stage::Tables,
        Stage::Sweep,
        Stage::Map,
        Stage::PhysicalAndPeriodic,
        Stage::Figures,
        Stage::Writing,
    ];

    /// What the stage does with `opts`, in words.
    pub fn describe(self, opts: &ReportOptions) -> String {
        match self {
            Stage::Tables => "the study's responses (each integrated once) and both tables".into(),
            Stage::Sweep => format!("γ sweep ({} simulations)", opts.sweep_points),
            Stage::Map => format!(
                "(γ, δ) map ({} simulations)",
                opts.map_size.0 * opts.map_size.1
            ),
            Stage::PhysicalAndPeriodic => format!(
                "physical drive ({PHYSICAL_DRIVE}): reduction, two-inertia check, design check; \
                 bursting boundaries; and together with them periodic orbits, frequency \
                 response, period-doubling bubble, orbit diagram, Lyapunov map, the drive's \
                 frequency response; burst control at γ = 1 and 0.1 and on the bursting drive; \
                 the drive under manufacturing spread"
            ),
            Stage::Figures => format!(
                "{} figures",
                FIGURES.len() + PERIODIC_FIGURES.len() + 1 + robust::ROBUST_FIGURES.len()
            ),
            Stage::Writing => "writing SVG, PNG, data and index.html".into(),
        }
    }
}

/// Told when each [`Stage`] starts (progress lines in the binary).
pub trait Observer {
    /// `stage` starts.
    fn stage(&mut self, stage: Stage);
}

impl<F: FnMut(Stage)> Observer for F {
    fn stage(&mut self, stage: Stage) {
        self(stage);
    }
}

/// The physical section's numbers.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PhysicalEvidence {
    /// The catalogue data of [`PHYSICAL_DRIVE`].
    pub catalogue: CatalogueDrive,
    /// The drive built from them.
    pub drive: PhysicalParams,
    /// Its stiffness fit.
    pub fit: CubicFit,
    /// Its design check (which includes the reduction).
    pub check: DesignCheck,
    /// The same drive judged with the catalogue's own piecewise-linear curve in place of the fit
    /// ([`crate::physical::curve_law`]).
    pub catalogue_law: crate::physical::curve_law::CatalogueLaw,
    /// The same with the curve's knees rounded over
    /// [`crate::physical::curve_law::ILLUSTRATED_ROUNDING`] of θ(T₁).
    pub rounded_law: crate::physical::curve_law::CatalogueLaw,
    /// The same drive made to burst (softer k1, larger disturbance).
    pub variant: PhysicalParams,
    /// The variant's design check.
    pub variant_check: DesignCheck,
    /// The two-inertia model against the reduced model.
    pub reduction_check: ReductionCheck,
}

/// `drive` made to burst: softer k1, larger disturbance.
fn bursting_variant(drive: &PhysicalParams) -> PhysicalParams {
    PhysicalParams {
        k1: 2000.0,
        t_am: 112.0,
        ..*drive
    }
}

impl PhysicalEvidence {
    /// [`PHYSICAL_DRIVE`] and its bursting variant (softer k1, larger disturbance).
    pub fn drives() -> Result<(PhysicalParams, PhysicalParams)> {
        let (drive, _) = crate::physical::catalogue::preset(PHYSICAL_DRIVE, None)?;
        Ok((drive, bursting_variant(&drive)))
    }

    /// The physical section for [`PHYSICAL_DRIVE`].
    pub fn compute(opts: &BurstOptions) -> Result<PhysicalEvidence> {
        let (drive, fit) = crate::physical::catalogue::preset(PHYSICAL_DRIVE, None)?;
        let variant = bursting_variant(&drive);
        let (span, tol) = REDUCTION_CHECK;
        let card = crate::physical::card::builtin_card(PHYSICAL_DRIVE)?;
        let law = |rounding| crate::physical::curve_law::check(card, &drive, rounding, opts);
        Ok(PhysicalEvidence {
            catalogue: CatalogueDrive::by_name(PHYSICAL_DRIVE)?,
            drive,
            fit,
            check: design_check(&drive, opts)?,
            catalogue_law: law(0.0)?,
            rounded_law: law(crate::physical::curve_law::ILLUSTRATED_ROUNDING)?,
            variant,
            variant_check: design_check(&variant, opts)?,
            reduction_check: check_reduction(&drive, span, 1.0, tol)?,
        })
    }
}

/// Everything the report shows, computed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Report {
    /// hdgear's version.
    pub version: &'static str,
    /// What was run.
    pub options: ReportOptions,
    /// Both tables.
    pub tables: Tables,
    /// The study's four γ, in [`STUDY_GAMMAS`] order.
    pub cases: Vec<Case>,
    /// The equilibrium curve of each case (1001 points).
    #[serde(skip)]
    pub curves: Vec<Vec<CurvePoint>>,
    /// The γ sweep.
    pub sweep: GridRun,
    /// The (γ, δ) map.
    pub map: GridRun,
    /// The physical section.
    pub physical: PhysicalEvidence,
    /// Bursting boundaries through the study's point and through γ = 1.
    pub boundaries: [Boundaries; 2],
    /// The periodic section.
    pub periodic: periodic::PeriodicEvidence,
    /// The burst-control section.
    pub control: control::ControlEvidence,
    /// The section on design under manufacturing spread.
    pub robust: robust::RobustEvidence,
    /// The section on friction and hysteresis.
    pub memory: memory::MemoryEvidence,
    /// The figures, in [`FIGURES`] order, then the periodic section's, then the control
    /// section's ([`control::CONTROL_FIGURE`]), then the spread section's
    /// ([`robust::ROBUST_FIGURES`]), then the memory section's ([`memory::MEMORY_FIGURE`]).
    #[serde(skip)]
    pub figures: Vec<Figure>,
}

impl Report {
    /// Runs every computation of the report, telling `observer` as each stage starts.
    pub fn compute(opts: &ReportOptions, observer: &mut impl Observer) -> Result<Report> {
        let base = opts.base;
        base.validate()?;
        let mut grid_opts = opts.burst;
        grid_opts.tol.rtol = opts.grid_tol;
        grid_opts.tol.atol = opts.grid_tol;
        let mut study = Study::new(
            opts.burst,
            grid_opts,
            opts.threads,
            opts.sweep_points,
            opts.map_size,
        );
        let at = |gamma: f64| Params { gamma, ..base };

        observer.stage(Stage::Tables);
        let mut points: Vec<Params> = STUDY_GAMMAS.iter().map(|g| at(g.0)).collect();
        points.extend(FIGURES.iter().filter_map(|f| f.1.map(at)));
        study.cases(&points)?;
        let tables = tables_in(&mut study, &base)?;
        let cases: Vec<Case> = study
            .cases(&points[..STUDY_GAMMAS.len()])?
            .into_iter()
            .cloned()
            .collect();
        let curves = cases
            .iter()
            .map(|c| curve(&c.params, A_RANGE, 1001))
            .collect::<Result<Vec<_>>>()?;

        observer.stage(Stage::Sweep);
        let sweep = study.sweep(&base)?.clone();
        observer.stage(Stage::Map);
        let map = study.map(&base)?.clone();

        observer.stage(Stage::PhysicalAndPeriodic);
        let (physical, bounds, periodic, control, robust) = side_sections(opts, &mut study)?;
        let memory = memory::MemoryEvidence::compute(&base, &opts.burst)?;
        observer.stage(Stage::Figures);
        let mut figures = study_figures(&base, &mut study)?;
        figures.extend(periodic.figures(&base));
        figures.push(control.figure());
        figures.extend(robust.figures());
        figures.push(memory.figure());
        Ok(Report {
            version: env!("CARGO_PKG_VERSION"),
            options: *opts,
            tables,
            cases,
            curves,
            sweep,
            map,
            physical,
            boundaries: [bounds[0], bounds[1]],
            periodic,
            control,
            robust,
            memory,
            figures,
        })
    }

    /// Writes the report into `dir` (created if missing; files hdgear did not write there are
    /// refused unless `force`): data, figures as SVG and PNG, and `index.html`.
    pub fn write(&self, dir: &Path, force: bool) -> Result<ReportSummary> {
        self.write_into(Files::open(dir, force)?)
    }

    fn write_into(&self, mut out: Files) -> Result<ReportSummary> {
        out.json("data/tables.json", &self.tables)?;
        out.bytes(
            "data/tables.csv",
            crate::table::render::csv(&self.tables)
                .map_err(|source| crate::Error::Io {
                    path: out.path("data/tables.csv"),
                    source,
                })?
                .as_bytes(),
        )?;
        for (case, curve) in self.cases.iter().zip(&self.curves) {
            let tag = format!("g{}", case.params.gamma);
            out.json(&format!("data/analysis-{tag}.json"), case)?;
            out.csv(&format!("data/curve-{tag}.csv"), curve)?;
        }
        out.csv("data/sweep-gamma.csv", &self.sweep.rows)?;
        out.csv("data/map-gamma-delta.csv", &self.map.rows)?;
        let pe = &self.periodic;
        let rows = |branches: &[&crate::periodic::OrbitBranch<crate::params::Param>]| {
            branches
                .iter()
                .enumerate()
                .flat_map(|(i, b)| {
                    b.points
                        .iter()
                        .map(move |q| crate::periodic::BranchRow::new(i, b.subharmonic, q))
                })
                .collect::<Vec<_>>()
        };
        out.csv("data/frequency-response.csv", &rows(&[&pe.response]))?;
        let mut bubble = vec![&pe.bubble];
        bubble.extend(pe.doubled.as_ref());
        out.csv("data/period-doubling-bubble.csv", &rows(&bubble))?;
        out.csv("data/lyapunov-map.csv", &pe.lyapunov)?;
        out.json("data/periodic.json", pe)?;
        out.json("data/control.json", &self.control)?;
        out.json("data/robust.json", &self.robust)?;
        out.json("data/memory.json", &self.memory)?;
        let svgs = out.figures(&self.figures)?;
        out.bytes("index.html", html::render(self, &svgs).as_bytes())?;
        Ok(ReportSummary {
            files: out.written,
            tables: self.tables.clone(),
        })
    }
}

/// The sections computed side by side (independent of one another): the physical drive, the
/// boundaries, the periodic response, burst control and the drive under spread.
fn side_sections(
    opts: &ReportOptions,
    study: &mut Study,
) -> Result<(
    PhysicalEvidence,
    Vec<Boundaries>,
    periodic::PeriodicEvidence,
    control::ControlEvidence,
    robust::RobustEvidence,
)> {
    let base = opts.base;
    let at = |gamma: f64| Params { gamma, ..base };
    let (drive, variant) = PhysicalEvidence::drives()?;
    let gammas: Vec<f64> = STUDY_GAMMAS.iter().map(|g| g.0).collect();
    let (((physical, bounds), periodic), control) = rayon::join(
        || {
            rayon::join(
                || {
                    rayon::join(
                        || PhysicalEvidence::compute(&opts.burst),
                        || study.boundaries(&[base, at(1.0)]),
                    )
                },
                || {
                    periodic::PeriodicEvidence::compute(
                        &base,
                        &gammas,
                        &opts.burst,
                        (&drive, &variant),
                        opts.threads,
                    )
                },
            )
        },
        || {
            rayon::join(
                || control::ControlEvidence::compute(&base, &variant, &opts.burst),
                || robust::RobustEvidence::compute(&drive, &opts.burst),
            )
        },
    );
    let (control, robust) = control;
    Ok((physical?, bounds?, periodic?, control?, robust?))
}

/// The study's figures, in [`FIGURES`] order, each at its γ (the base set's without one).
fn study_figures(base: &Params, study: &mut Study) -> Result<Vec<Figure>> {
    FIGURES
        .iter()
        .map(|&(kind, gamma, name)| {
            let p = gamma.map_or(*base, |gamma| Params { gamma, ..*base });
            let mut f = kind.build(&p, study)?;
            f.name = name.to_string();
            Ok(f)
        })
        .collect()
}

/// Builds the report into `dir`: checks the directory, computes ([`Report::compute`]) and writes
/// ([`Report::write`]).
///
/// With [`ReportOptions::threads`] > 0 every stage runs on that many threads (the grids, the
/// sections computed side by side, the figures drawn side by side), so `threads: 1` keeps the
/// report on one core.
pub fn build(
    dir: &Path,
    opts: &ReportOptions,
    observer: &mut (impl Observer + Send),
) -> Result<ReportSummary> {
    // refuse a directory with foreign files before computing anything
    let out = Files::open(dir, opts.force)?;
    let run = move || {
        let report = Report::compute(opts, observer)?;
        observer.stage(Stage::Writing);
        report.write_into(out)
    };
    if opts.threads == 0 {
        return run();
    }
    crate::sweep::pool(opts.threads)?.install(run)
}
