//! The fast subsystem x'' + x' + g(x) = μ + δ a with the slow variable a = sin(ω τ) frozen.
//!
//! Exact facts used throughout (guide: the fast subsystem): the Jacobian at an equilibrium is
//! [[0, 1], [−g'(x), −1]], so the trace is −1 for every parameter and every equilibrium: the fast
//! subsystem can never undergo a Hopf bifurcation. Equilibria are stable iff g'(x) > 0; the only
//! bifurcations are folds where g'(x) = 0, which exist iff γ < 1/(3α); γ = 1/(3α) is a cusp.

/// The range of the slow variable a = sin ωτ: what every response traverses.
pub const A_RANGE: (f64, f64) = (-1.0, 1.0);

/// The x-extent X of the equilibrium curve over `a_range` (the unit of x-distances in burst
/// detection and classification); the smallest positive number when the curve is a point.
pub fn x_extent<C: StaticCurve>(p: &C, a_range: (f64, f64)) -> f64 {
    let iv = x_intervals(p, a_range);
    match (iv.first(), iv.last()) {
        (Some(l), Some(r)) => (r.1 - l.0).max(f64::MIN_POSITIVE),
        _ => f64::MIN_POSITIVE,
    }
}

mod analysis;
mod cubic;
mod curve;
mod domain;
pub use domain::{slowest_relaxation, turning_point_relaxation};
mod equilibria;
pub(crate) use equilibria::newton;
pub mod passage;
pub use passage::{
    CuspPassage, PASSAGE_GPRIME, SWING_FRACTION, TABLE_STEP, THRESHOLD_REL_TOL, passage_rings,
    ramp_threshold, ramp_threshold_at,
};
mod predict;
mod static_curve;
pub use static_curve::{Along, Follower, SlowestRelaxation, StaticCurve, relaxation_rate_with};

pub use analysis::{
    Analysis, CurveAnalysis, Cusp, EquilibriaSummary, FoldRow, Interval, NO_HOPF_REASON, Point,
    Regime, Slope, analyze, curve_analysis, cusp, fold_curves, max_slope,
};
pub use curve::{
    A_RANGE_LIMIT, CurveBranch, CurvePoint, MAX_CURVE_POINTS, check_a_range, curve, x_intervals,
};
pub use equilibria::{
    EqType, Equilibria, Equilibrium, EquilibriumTracker, Fold, eigenvalues, equilibria,
    fold_abscissae, folds, nearest_stable_equilibrium, stable_equilibrium,
};
pub use predict::{
    FORCING_RATE_THRESHOLD, Prediction, SettledBranch, focus_pieces, forcing_rate,
    max_equilibrium_speed, max_first_order_lag, predict, predicted_gamma_boundary, settled_branch,
};
pub(crate) use predict::{max_first_order_lag_on, max_on, max_speed_on, min_gprime};

/// What produced an equilibrium curve: the `meta` of `hdgear equilibria`'s JSON output.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct CurveSetup<P = crate::params::Params> {
    /// The parameters (the study's set, or a model's description).
    pub params: P,
    /// The range of a sampled.
    pub a_range: (f64, f64),
}

/// What produced the fold curves: the `meta` of `hdgear bifurcation`'s JSON output.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct FoldCurvesSetup {
    /// The parameters (γ is varied).
    pub params: crate::params::Params,
    /// Where the fold curves meet.
    pub cusp: Cusp,
}
