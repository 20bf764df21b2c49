//! The report's "Beyond the study: the periodic response" section: the periodic orbits of the
//! study's four γ with their multipliers and their own burst verdicts, the frequency-response
//! curve at the study's point, a period-doubling bubble with its doubled branch, a Lyapunov map,
//! and a physical drive's frequency response in SI units.

use crate::burst::{BurstOptions, Classification};
use crate::error::Result;
use crate::output::plot::Figure;
use crate::params::{Param, Params};
use crate::periodic::{
    ContinuationOptions, DiagramOptions, DiagramPoint, LyapunovRow, OrbitBranch, PeriodicOptions,
    PhysicalResponse, Scale, burst_verdict, continue_with_doubled, frequency_response,
    orbit_diagram, physical_frequency_response, shoot,
};
use crate::physical::PhysicalParams;
use crate::sweep::{Axis, Grid};
use serde::Serialize;

/// γ of the period-doubling example: at the study's other parameters the period-1 response
/// doubles near ω ≈ 8.14 and undoubles near 9.56 (found with `hdgear orbit-diagram`).
pub const BUBBLE_GAMMA: f64 = 10.0;

/// The ω range the bubble's branch and orbit diagram cover (both folds and both doublings).
pub const BUBBLE_OMEGA: (f64, f64) = (5.0, 10.5);

/// The periodic orbit of one of the study's γ.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StudyOrbit {
    /// γ.
    pub gamma: f64,
    /// Newton's residual.
    pub residual: f64,
    /// ln|m1|, ln|m2|.
    pub log_abs_multipliers: [f64; 2],
    /// Whether the multipliers are a complex pair.
    pub complex: bool,
    /// Both inside the unit circle.
    pub stable: bool,
    /// Peak-to-peak x.
    pub peak_to_peak: f64,
    /// max |x'|.
    pub max_abs_xdot: f64,
    /// The burst verdict on the orbit itself.
    pub on_orbit: Classification,
}

/// Everything the section shows.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PeriodicEvidence {
    /// The study's four γ.
    pub orbits: Vec<StudyOrbit>,
    /// The frequency response at the study's point.
    pub response: OrbitBranch<Param>,
    /// The branch through the period-doubling bubble (γ = [`BUBBLE_GAMMA`]).
    pub bubble: OrbitBranch<Param>,
    /// Its doubled branch.
    pub doubled: Option<OrbitBranch<Param>>,
    /// The orbit diagram over [`BUBBLE_OMEGA`].
    #[serde(skip)]
    pub diagram: Vec<DiagramPoint>,
    /// The Lyapunov map's grid and rows.
    pub lyapunov_grid: Grid,
    /// Its rows.
    #[serde(skip)]
    pub lyapunov: Vec<LyapunovRow>,
    /// The catalogue drive's frequency response.
    pub drive: PhysicalResponse,
    /// The bursting variant's.
    pub variant: PhysicalResponse,
    /// The (ω, δ) plane at the study's γ.
    pub plane: super::plane::PlaneEvidence,
}

impl PeriodicEvidence {
    /// Computes the section at the study's point `base` for the drive and its variant.
    pub fn compute(
        base: &Params,
        gammas: &[f64],
        burst: &BurstOptions,
        drives: (&PhysicalParams, &PhysicalParams),
        threads: usize,
    ) -> Result<PeriodicEvidence> {
        let copts = ContinuationOptions::default();
        // two independent halves on the two cores: the dimensionless computations, the drives
        let (dimensionless, physical) = rayon::join(
            || dimensionless_part(base, gammas, burst),
            || -> Result<_> {
                Ok((
                    physical_frequency_response(drives.0, None, &copts)?,
                    physical_frequency_response(drives.1, None, &copts)?,
                    super::plane::PlaneEvidence::compute(base, burst)?,
                ))
            },
        );
        let (orbits, response, bubble, doubled, diagram) = dimensionless?;
        let (drive, variant, plane) = physical?;
        let at = Params {
            gamma: BUBBLE_GAMMA,
            ..*base
        };
        let lyapunov_grid = Grid::new(
            at,
            vec![
                Axis::parse("omega=2:14:32:log")?,
                Axis::parse("delta=2:80:20:log")?,
            ],
        )?;
        let lopts = DiagramOptions {
            discard: 100,
            lyapunov: Some(100),
            ..DiagramOptions::default()
        };
        let lyapunov = crate::sweep::lyapunov_map(&lyapunov_grid, &lopts, threads)?;
        Ok(PeriodicEvidence {
            orbits,
            response,
            bubble,
            doubled,
            diagram,
            lyapunov_grid,
            lyapunov,
            drive,
            variant,
            plane,
        })
    }

    /// The section's figures: the frequency response at the study's point, the bubble's orbit
    /// diagram, the Lyapunov map, the variant drive's response in SI units and the (ω, δ) plane.
    pub fn figures(&self, base: &Params) -> Vec<Figure> {
        let at = Params {
            gamma: BUBBLE_GAMMA,
            ..*base
        };
        let mut figures = vec![
            crate::figures::frequency_response_figure(base, &self.response),
            crate::figures::orbit_diagram_figure(&at, Param::Omega, &self.diagram),
            crate::figures::lyapunov_figure(&self.lyapunov_grid, &self.lyapunov),
            crate::figures::physical_response_figure(&self.variant),
            self.plane.figure(),
        ];
        for (f, (_, name)) in figures.iter_mut().zip(super::PERIODIC_FIGURES) {
            f.name = name.to_string();
        }
        figures
    }
}

fn study_orbit(p: &Params, burst: &BurstOptions) -> Result<StudyOrbit> {
    let o = shoot(p, 1, &PeriodicOptions::default())?;
    Ok(StudyOrbit {
        gamma: p.gamma,
        residual: o.residual,
        log_abs_multipliers: o.log_abs_multipliers,
        complex: o.multipliers[0].arg != 0.0 && o.multipliers[0].arg.abs() != std::f64::consts::PI,
        stable: o.stable,
        peak_to_peak: o.peak_to_peak,
        max_abs_xdot: o.max_abs_xdot,
        on_orbit: burst_verdict(&o, burst)?,
    })
}

/// What [`dimensionless_part`] computes.
type Dimensionless = (
    Vec<StudyOrbit>,
    OrbitBranch<Param>,
    OrbitBranch<Param>,
    Option<OrbitBranch<Param>>,
    Vec<DiagramPoint>,
);

/// The study's orbits, the frequency response, the bubble with its doubled branch and its orbit
/// diagram.
fn dimensionless_part(
    base: &Params,
    gammas: &[f64],
    burst: &BurstOptions,
) -> Result<Dimensionless> {
    let copts = ContinuationOptions::default();
    let orbits = gammas
        .iter()
        .map(|&g| study_orbit(&Params { gamma: g, ..*base }, burst))
        .collect::<Result<Vec<_>>>()?;
    let response = frequency_response(base, None, &copts)?;
    let at = Params {
        gamma: BUBBLE_GAMMA,
        omega: BUBBLE_OMEGA.0,
        ..*base
    };
    let log = ContinuationOptions {
        scale: Scale::Log,
        ..copts
    };
    // the branch and the doubled branch from its first period doubling (which ends at the
    // second, so no other is traced)
    let mut branches =
        continue_with_doubled(&at, Param::Omega, 1, BUBBLE_OMEGA.1, true, &log)?.into_iter();
    let bubble = branches.next().ok_or(crate::Error::NoConvergence {
        what: "the period-doubling bubble's branch",
        iterations: 0,
        residual: f64::NAN,
    })?;
    let doubled = branches.next();
    // 0.05 apart over the bubble's range; 100 periods settle (the previous value's state is
    // close) and 100 more give Benettin's exponent to a few 1e-3
    let values: Vec<f64> = (0..=110)
        .map(|i| BUBBLE_OMEGA.0 + 0.05 * f64::from(i))
        .collect();
    let mut diagram = Vec::new();
    let dopts = DiagramOptions {
        discard: 100,
        lyapunov: Some(100),
        ..DiagramOptions::default()
    };
    orbit_diagram(&at, Param::Omega, &values, &dopts, |q| diagram.push(q))?;
    Ok((orbits, response, bubble, doubled, diagram))
}
