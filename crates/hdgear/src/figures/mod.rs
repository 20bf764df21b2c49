//! The figures of the study (and beyond), as data ([`Figure`]) built from computations.
//! Rendering is [`crate::output::plot`]'s job.

use crate::burst::BurstOptions;
use crate::error::Result;
use crate::output::plot::Figure;
use crate::params::{Param, Params};
use crate::study::Study;

mod decimate;
mod maps;
mod model;
mod periodic;
mod robust;
mod study;

pub use decimate::decimate;
pub use maps::{boundary_figure, fold_delta, map_figure, sweep_figure};
pub use model::{fast_slow_figure, orbit_figure, response_figure};
pub use periodic::{
    LYAPUNOV_BINS, frequency_response_figure, frequency_response_kind, lyapunov_figure,
    lyapunov_map_kind, orbit_diagram_figure, orbit_diagram_kind, physical_response_figure,
    plane_figure,
};
pub use robust::{CLOUD_POINTS, cloud_figure, load_figure, sobol_figure};
pub use study::{phase_plane, slope, transformed_phase, x_equilibrium, xdot_gamma};

/// The spread of the points' ordinates (at least 1e-12): the scale a figure's decimation
/// tolerance is a fraction of.
pub(crate) fn span_of(points: &[(f64, f64)]) -> f64 {
    let (lo, hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), q| {
            (l.min(q.1), h.max(q.1))
        });
    (hi - lo).max(1e-12)
}

/// The figure kinds (`hdgear plot KIND`, the report's figures). Adding a figure is a variant
/// here, a line in [`KINDS`] and its function.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum FigureKind {
    /// x'(τ) over one slow period for the study's four γ.
    XdotGamma,
    /// x(τ) with the equilibrium over it.
    XEquilibrium,
    /// The trajectory over the equilibrium curve in the (a, x) plane.
    TransformedPhase,
    /// (x, x').
    PhasePlane,
    /// |dx/da| against a.
    Slope,
    /// Peak |x'| and spikes against γ.
    Sweep,
    /// The (γ, δ) plane coloured by mode.
    Map,
    /// The bursting boundary in the (ω, γ) plane, predicted and simulated.
    Boundary,
    /// The frequency-response curve with stable and unstable branches, folds and doublings.
    FrequencyResponse,
    /// The stroboscopic orbit diagram against ω, swept up and down, with Benettin's exponent.
    OrbitDiagram,
    /// The largest Lyapunov exponent over (ω, δ).
    LyapunovMap,
}

/// How a figure kind is named, what it varies and how it is built.
pub struct KindEntry {
    /// The kind.
    pub kind: FigureKind,
    /// The name users write (and the serde name).
    pub name: &'static str,
    /// The parameters the figure varies itself (so a value given for them would be ignored).
    pub varies: &'static [Param],
    /// Builds the figure at a parameter point from (and into) the shared computations.
    pub build: fn(&Params, &mut Study) -> Result<Figure>,
}

/// The one list of figure kinds, in the order listed to users.
pub const KINDS: [KindEntry; 11] = [
    KindEntry {
        kind: FigureKind::XdotGamma,
        name: "xdot-gamma",
        varies: &[Param::Gamma],
        build: xdot_gamma,
    },
    KindEntry {
        kind: FigureKind::XEquilibrium,
        name: "x-equilibrium",
        varies: &[],
        build: x_equilibrium,
    },
    KindEntry {
        kind: FigureKind::TransformedPhase,
        name: "transformed-phase",
        varies: &[],
        build: transformed_phase,
    },
    KindEntry {
        kind: FigureKind::PhasePlane,
        name: "phase-plane",
        varies: &[],
        build: phase_plane,
    },
    KindEntry {
        kind: FigureKind::Slope,
        name: "slope",
        varies: &[Param::Gamma],
        build: slope,
    },
    KindEntry {
        kind: FigureKind::Sweep,
        name: "sweep",
        varies: &[Param::Gamma],
        build: sweep_figure,
    },
    KindEntry {
        kind: FigureKind::Map,
        name: "map",
        varies: &[Param::Gamma, Param::Delta],
        build: map_figure,
    },
    KindEntry {
        kind: FigureKind::Boundary,
        name: "boundary",
        varies: &[Param::Gamma, Param::Omega],
        build: boundary_figure,
    },
    KindEntry {
        kind: FigureKind::FrequencyResponse,
        name: "frequency-response",
        varies: &[Param::Omega],
        build: frequency_response_kind,
    },
    KindEntry {
        kind: FigureKind::OrbitDiagram,
        name: "orbit-diagram",
        varies: &[Param::Omega],
        build: orbit_diagram_kind,
    },
    KindEntry {
        kind: FigureKind::LyapunovMap,
        name: "lyapunov-map",
        varies: &[Param::Omega, Param::Delta],
        build: lyapunov_map_kind,
    },
];

impl FigureKind {
    /// Every kind, in the order listed to users.
    pub const ALL: [FigureKind; KINDS.len()] = {
        let mut all = [FigureKind::XdotGamma; KINDS.len()];
        let mut i = 0;
        while i < KINDS.len() {
            all[i] = KINDS[i].kind;
            i += 1;
        }
        all
    };

    fn entry(self) -> &'static KindEntry {
        // every kind has its line in KINDS (a test checks the order)
        &KINDS[self as usize]
    }

    /// The name users write.
    pub fn name(self) -> &'static str {
        self.entry().name
    }

    /// The parameters the figure varies itself (so a value given for them would be ignored).
    pub fn varies(self) -> &'static [Param] {
        self.entry().varies
    }

    /// Builds the figure at `p` (the base point of figures that vary parameters), reusing and
    /// filling `study`.
    pub fn build(self, p: &Params, study: &mut Study) -> Result<Figure> {
        (self.entry().build)(p, study)
    }
}

impl std::fmt::Display for FigureKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

impl std::str::FromStr for FigureKind {
    type Err = crate::Error;
    fn from_str(name: &str) -> Result<FigureKind> {
        crate::error::by_name(&FigureKind::ALL, FigureKind::name, "figure kind", name)
    }
}

/// Builds one figure by kind for `hdgear plot` (sweep sizes: 120 γ values; map 40 × 24).
pub fn by_kind(
    kind: FigureKind,
    p: &Params,
    opts: &BurstOptions,
    threads: usize,
) -> Result<Figure> {
    let mut study = Study::new(*opts, *opts, threads, 120, (40, 24));
    kind.build(p, &mut study)
}
