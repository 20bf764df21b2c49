//! The study's cubic g(x) = αx³ − x² + γ(x − ε) as a [`StaticCurve`]: every answer from its
//! closed forms (the roots by bracketed Newton, the folds, the settled branch), so the burst scan
//! keeps its fast path on the study's model.

use super::equilibria::{EqType, EquilibriumTracker, eigenvalues, equilibria, fold_abscissae};
use super::static_curve::{Follower, SlowestRelaxation, StaticCurve};
use super::{A_RANGE, x_extent};
use crate::error::Result;
use crate::params::Params;

impl Follower for EquilibriumTracker {
    #[inline]
    fn at(&mut self, a: f64, x: f64) -> f64 {
        EquilibriumTracker::at(self, a, x)
    }
}

/// The study's cubic: every answer from its closed forms.
impl StaticCurve for Params {
    type Follower = EquilibriumTracker;
    #[inline(always)]
    fn omega(&self) -> f64 {
        self.omega
    }
    #[inline(always)]
    fn delta(&self) -> f64 {
        self.delta
    }
    #[inline(always)]
    fn forcing(&self, a: f64) -> f64 {
        Params::forcing(self, a)
    }
    #[inline(always)]
    fn g(&self, x: f64) -> f64 {
        Params::g(self, x)
    }
    #[inline(always)]
    fn g_prime(&self, x: f64) -> f64 {
        Params::g_prime(self, x)
    }
    #[inline(always)]
    fn a_at(&self, x: f64) -> f64 {
        Params::a_at(self, x)
    }
    fn check(&self) -> Result<()> {
        self.validate().map(|_| ())
    }
    fn roots(&self, a: f64) -> Vec<f64> {
        equilibria(self, a).roots.iter().map(|r| r.x).collect()
    }
    fn eigenvalues(&self, x: f64) -> [(f64, f64); 2] {
        eigenvalues(Params::g_prime(self, x))
    }
    fn kind(&self, x: f64) -> EqType {
        EqType::from_g_prime(Params::g_prime(self, x))
    }
    fn fold_band(&self) -> Option<(f64, f64)> {
        fold_abscissae(self)
    }
    fn follower(&self, x0: f64) -> EquilibriumTracker {
        EquilibriumTracker::new(self, x0)
    }
    fn start(&self) -> f64 {
        super::stable_equilibrium(self, 0.0)
    }
    fn x_extent(&self) -> f64 {
        x_extent(self, A_RANGE)
    }
    fn min_traversed_gprime(&self) -> f64 {
        super::min_gprime(self, &super::x_intervals(self, A_RANGE))
    }
    /// Unit damping: the study's x' (so a focus above g' = c²/4 = 1/4, a decay time of 2).
    fn damping(&self) -> f64 {
        1.0
    }
    fn max_equilibrium_speed(&self) -> f64 {
        super::max_equilibrium_speed(self)
    }
    fn max_first_order_lag(&self) -> f64 {
        super::max_first_order_lag(self)
    }
    fn slowest_relaxation(&self) -> SlowestRelaxation {
        super::slowest_relaxation(self)
    }
    fn turning_point_relaxation(&self) -> SlowestRelaxation {
        super::turning_point_relaxation(self)
    }
    fn slow_period(&self) -> f64 {
        Params::slow_period(self)
    }
}
