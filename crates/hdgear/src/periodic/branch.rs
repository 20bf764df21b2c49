//! What a continuation gives: its options, its points with their special points, the branch and
//! how it ended, and the rows of its output file.

use super::*;
use std::f64::consts::PI;

/// Options of the continuation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ContinuationOptions {
    /// Integrator tolerances and Newton's iteration limit.
    pub periodic: PeriodicOptions,
    /// Linear or logarithmic parameter coordinate.
    pub scale: Scale,
    /// First step, as a fraction of the range |u(end) − u(start)|.
    pub initial_step: f64,
    /// Largest step, same unit: 1/40 of the range keeps ≥ 40 points on a straight branch.
    pub max_step: f64,
    /// Smallest step, same unit; below it the continuation stops ([`End::StepTooSmall`]).
    pub min_step: f64,
    /// Largest angle (radians) between successive tangents: a sharper turn means the predictor
    /// may have jumped to another branch, so the step is halved.
    pub max_turn: f64,
    /// Corrector iterations at most.
    pub max_corrector: usize,
    /// Points at most.
    pub max_points: usize,
    /// A count the tracers add each point they accept to, for a caller's progress display (a
    /// long two-parameter trace takes minutes). Not serialised. Default `None`.
    #[serde(skip)]
    pub progress: Option<Counter>,
}

/// A count of the points continuations have traced ([`ContinuationOptions::progress`]): a
/// `static` the caller reads while the trace runs ([`crate::integrate::Shared`]).
///
/// ```
/// use std::sync::atomic::{AtomicU64, Ordering};
/// use hdgear::{Params, integrate::Shared, periodic::{ContinuationOptions, continue_orbit}};
/// static TRACED: AtomicU64 = AtomicU64::new(0);
/// let opts = ContinuationOptions { progress: Some(Shared(&TRACED)), ..Default::default() };
/// let p = Params { gamma: 30.0, ..Params::default() };
/// let b = continue_orbit(&p, hdgear::params::Param::Omega, 1, None, 0.02, &opts).unwrap();
/// assert!(TRACED.load(Ordering::Relaxed) as usize >= b.points.len() - 2);
/// ```
pub type Counter = crate::integrate::Shared<std::sync::atomic::AtomicU64>;

impl ContinuationOptions {
    /// Counts one more accepted point ([`ContinuationOptions::progress`]).
    pub(crate) fn traced(&self) {
        if let Some(c) = self.progress {
            c.0.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        }
    }
}

impl Default for ContinuationOptions {
    fn default() -> Self {
        ContinuationOptions {
            periodic: PeriodicOptions::default(),
            scale: Scale::Linear,
            initial_step: 0.005,
            max_step: 0.025,
            min_step: 1e-9,
            max_turn: 0.3,
            max_corrector: 8,
            max_points: 5000,
            progress: None,
        }
    }
}

impl ContinuationOptions {
    /// Checks the step sizes, angle and limits.
    pub fn validate(&self) -> Result<()> {
        let bad = |name, value: f64, reason| {
            Err(Error::InvalidOption {
                name,
                value,
                reason,
            })
        };
        if !(self.min_step > 0.0 && self.min_step <= self.initial_step) {
            return bad("min_step", self.min_step, "must be > 0 and ≤ initial_step");
        }
        if !(self.initial_step <= self.max_step && self.max_step <= 1.0) {
            return bad("max_step", self.max_step, "must be ≥ initial_step and ≤ 1");
        }
        if !(self.max_turn > 0.0 && self.max_turn < PI) {
            return bad("max_turn", self.max_turn, "must be in (0, π)");
        }
        if self.max_corrector == 0 || self.max_points < 2 {
            return bad("max_points", self.max_points as f64, "must be ≥ 2");
        }
        self.periodic.tol.validate()
    }
}

/// A special point of a branch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Special {
    /// A multiplier through +1 where the parameter turns back: a fold (saddle-node) of cycles,
    /// the jump of a frequency-response curve.
    Fold,
    /// A multiplier through −1: a period doubling; the doubled branch starts here.
    PeriodDoubling,
    /// A multiplier through +1 where the parameter does not turn: a branch point.
    BranchPoint,
}

impl Special {
    /// The name written in tables.
    pub fn name(self) -> &'static str {
        match self {
            Special::Fold => "fold",
            Special::PeriodDoubling => "period-doubling",
            Special::BranchPoint => "branch-point",
        }
    }
}

/// One point of a branch.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct OrbitPoint {
    /// The parameter λ.
    pub param: f64,
    /// (x, x') at phase 0.
    pub start: [f64; 2],
    /// The multipliers, the larger first.
    pub multipliers: [Multiplier; 2],
    /// Both inside the unit circle.
    pub stable: bool,
    /// Extremes of the response.
    pub amplitude: Amplitude,
    /// Set at a located special point.
    pub special: Option<Special>,
    /// At a special point, the eigenvector of M for the critical multiplier (unit length).
    #[serde(skip)]
    pub critical_direction: Option<[f64; 2]>,
    /// At a period doubling, its normal-form coefficient ([`super::flip_coefficient`]): > 0
    /// supercritical (the doubled orbit is born stable), < 0 subcritical.
    pub flip_coefficient: Option<f64>,
}

impl OrbitPoint {
    /// At a period doubling, which way it goes (from [`OrbitPoint::flip_coefficient`]).
    pub fn criticality(&self) -> Option<super::Criticality> {
        self.flip_coefficient.and_then(super::Criticality::of)
    }
}

/// Why a branch ended.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case", tag = "reason")]
pub enum End {
    /// It reached the end of the range (the last point is on it exactly) or left the range at
    /// its start.
    Reached,
    /// [`ContinuationOptions::max_points`] points.
    MaxPoints,
    /// The corrector failed even at the smallest step, near this parameter.
    StepTooSmall {
        /// λ at the last point.
        param: f64,
    },
    /// The branch came back to its first point: a closed loop (an isola), traced once.
    Closed,
    /// A branch born at a branch point reached another point of that kind on its parent (the
    /// last point is that point): a doubled branch another period doubling of the branch it was
    /// born on (a period-doubling bubble), a fold curve of doubled orbits another generalised
    /// period doubling ([`switch_at_gpd`](super::switch_at_gpd)).
    Rejoined {
        /// λ (λ₁ on a curve) at that point.
        param: f64,
    },
    /// The curve was switched onto at its first point, a branch point of another curve (a fold
    /// curve of doubled orbits at its generalised period doubling).
    Switched,
}

/// A branch of periodic orbits.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct OrbitBranch<P> {
    /// The parameter followed.
    pub param: P,
    /// k: the orbits have period k·2π/ω.
    pub subharmonic: u32,
    /// The points in order along the branch, special points in their place.
    pub points: Vec<OrbitPoint>,
    /// Why it ended.
    pub end: End,
}

impl<P> OrbitBranch<P> {
    /// The special points.
    pub fn specials(&self) -> impl Iterator<Item = &OrbitPoint> {
        self.points.iter().filter(|p| p.special.is_some())
    }
}

/// One row of a branch table (`hdgear continue --out`): the branch's index (0 the branch asked
/// for, 1, 2, … the doubled branches), its subharmonic, and the point.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, crate::output::Record)]
pub struct BranchRow {
    /// Index of the branch.
    pub branch: usize,
    /// k of the branch (period k·2π/ω).
    pub subharmonic: u32,
    /// The parameter's value.
    pub param: f64,
    /// x at phase 0.
    pub x0: f64,
    /// x' at phase 0.
    pub xdot0: f64,
    /// Smallest x.
    pub x_min: f64,
    /// Largest x.
    pub x_max: f64,
    /// x_max − x_min.
    pub peak_to_peak: f64,
    /// Largest |x'|.
    pub max_abs_xdot: f64,
    /// ln |m1| (the larger multiplier).
    pub ln_abs_m1: f64,
    /// arg m1.
    pub arg_m1: f64,
    /// ln |m2|.
    pub ln_abs_m2: f64,
    /// arg m2.
    pub arg_m2: f64,
    /// Both multipliers inside the unit circle.
    pub stable: bool,
    /// fold, period-doubling, branch-point or empty.
    pub special: &'static str,
    /// At a period doubling, its normal-form coefficient (> 0 supercritical); empty elsewhere.
    pub flip_coefficient: Option<f64>,
}

impl BranchRow {
    /// The row of point `q` of branch number `branch` with subharmonic `k`.
    pub fn new(branch: usize, k: u32, q: &OrbitPoint) -> BranchRow {
        BranchRow {
            branch,
            subharmonic: k,
            param: q.param,
            x0: q.start[0],
            xdot0: q.start[1],
            x_min: q.amplitude.x_min,
            x_max: q.amplitude.x_max,
            peak_to_peak: q.amplitude.peak_to_peak,
            max_abs_xdot: q.amplitude.max_abs_xdot,
            ln_abs_m1: q.multipliers[0].log_abs,
            arg_m1: q.multipliers[0].arg,
            ln_abs_m2: q.multipliers[1].log_abs,
            arg_m2: q.multipliers[1].arg,
            stable: q.stable,
            special: q.special.map_or("", Special::name),
            flip_coefficient: q.flip_coefficient,
        }
    }
}
