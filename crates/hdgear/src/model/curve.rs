//! The equilibrium curve of a model assembled from terms ([`ModelCurve`]), for the burst verdict
//! where the model's static torque is not a study cubic (a catalogue's piecewise-linear
//! stiffness, a cubic with a stiffer end stop, a stiffness the load's phase schedules):
//! g(x) = μ + δa solved by a root finder, every fact the verdict reads derived from g, g', the
//! fast subsystem's stiffness and the damping at rest c as the study's closed forms derive them
//! from the cubic. What g is comes from a [`Statics`]: the model's [`Model::static_torque`]
//! ([`StaticTorque`]), or the closed loop of a scheduled stiffness
//! ([`super::scheduled_curve::ScheduledTorque`]).

use super::Model;
use crate::error::{Error, Result};
use crate::fast::{A_RANGE, Along, Follower, SlowestRelaxation, StaticCurve, relaxation_rate_with};

/// Samples of g' across the traversed x-range that locate the folds (sign changes of g'): a
/// fold pair closer than a sample apart (a decreasing piece narrower than 1/4096 of the range)
/// is not seen.
const FOLD_SAMPLES: usize = 4096;

/// What a [`ModelCurve`]'s equilibria are: the curve g with g(x*) = μ + δa at the equilibria x*
/// at load a, and the fast subsystem's stiffness there.
pub trait Statics: Clone + Copy + std::fmt::Debug {
    /// The model (its forcing, its damping at rest, its check).
    fn model(&self) -> &Model;
    /// The curve g(x) = μ + δa(x), a(x) the load at which x is an equilibrium.
    fn g(&self, x: f64) -> f64;
    /// Its slope g'(x) = δ/(dx*/da).
    fn g_prime(&self, x: f64) -> f64;
    /// The fast subsystem's stiffness at the equilibrium x (the linearisation's −∂x''/∂x), which
    /// sets its stability and relaxation: g' itself where the static torque does not move with
    /// the load.
    fn stiffness(&self, x: f64) -> f64 {
        self.g_prime(x)
    }
    /// Every equilibrium at load a, increasing.
    fn equilibria(&self, a: f64) -> Result<Vec<f64>>;
    /// The stable equilibria at load a in closed form, where the law has one (else `None`: the
    /// curve finds them on its branches by Brent's method).
    fn stable_roots(&self, _a: f64) -> Option<Vec<f64>> {
        None
    }
}

/// A model's static torque g(x) ([`Model::static_torque`]), the same at every load.
#[derive(Clone, Copy, Debug)]
pub struct StaticTorque(pub Model);

impl Statics for StaticTorque {
    fn model(&self) -> &Model {
        &self.0
    }
    fn g(&self, x: f64) -> f64 {
        self.0.static_torque(x)
    }
    fn g_prime(&self, x: f64) -> f64 {
        self.0.static_stiffness(x)
    }
    fn equilibria(&self, a: f64) -> Result<Vec<f64>> {
        let [mu, delta, _] = self.0.forcing();
        self.0.equilibria_at(mu + delta * a)
    }
}

/// The equilibrium curve of a [`Model`]: its static torque g, its slope g' and its damping at
/// rest c ([`super::Facts::damping_at_rest`]), over the x-range [x_lo, x_hi] that a ∈ [−1, 1]
/// traverses (the lowest equilibrium at a = −1 to the highest at a = 1; g lies below μ − δ to the
/// left of it and above μ + δ to the right, so nothing beyond it is an equilibrium in range).
/// At most one pair of folds (one hysteresis band) is followed.
///
/// ```
/// use hdgear::fast::StaticCurve;
/// use hdgear::model::{Model, ModelCurve, terms::AnyTerm};
/// // a three-segment catalogue law, slopes 0.05, 0.5 and 5, kinks at |x| = 0.3 and 0.8
/// let law = AnyTerm::new("piecewise", &[0.05, 0.5, 5.0, 0.3, 0.5, 0.0, 0.0]).unwrap();
/// let c = ModelCurve::new(&Model::damped(0.0, 1.0, 0.01).with_term(law).unwrap()).unwrap();
/// assert_eq!(c.fold_band(), None); // monotone: one branch
/// assert!((c.min_traversed_gprime() - 0.05).abs() < 1e-12); // the soft middle
/// assert_eq!(c.focus_gprime(), 0.25); // unit damping: c²/4
/// ```
#[derive(Clone, Copy, Debug)]
pub struct ModelCurve<S: Statics = StaticTorque> {
    law: S,
    /// c, the damping at rest.
    damping: f64,
    /// [x_lo, x_hi], the traversed x-range.
    range: (f64, f64),
    /// The fold abscissae x− < x+ (g' < 0 between them), if any.
    band: Option<(f64, f64)>,
}

impl ModelCurve {
    /// The curve of `m`'s static torque; refused (naming the model) for a scheduled stiffness
    /// (whose curve is [`ModelCurve::scheduled`]'s), damping at rest c ≤ 0 (no relaxation: no
    /// equilibrium is followed), a static torque that does not confine x, or more than one pair
    /// of folds in the traversed range.
    pub fn new(m: &Model) -> Result<ModelCurve> {
        if m.is_scheduled() {
            return Err(refusal(
                m,
                "a scheduled stiffness moves the equilibria with the load's phase a: its curve is the closed loop's (ModelCurve::scheduled)",
            ));
        }
        ModelCurve::of(StaticTorque(*m))
    }
}

/// The error refusing model `m` (a curve, a verdict), for `reason`.
pub(crate) fn refusal(m: &Model, reason: impl Into<String>) -> Error {
    Error::InvalidInput {
        what: "model",
        text: m.equation(),
        reason: reason.into(),
    }
}

impl<S: Statics> ModelCurve<S> {
    /// The curve `law` makes; refused as [`ModelCurve::new`] says.
    pub fn of(law: S) -> Result<ModelCurve<S>> {
        let m = law.model();
        m.check()?;
        let damping = m.facts().damping_at_rest;
        if damping.is_nan() || damping <= 0.0 {
            return Err(refusal(
                m,
                format!(
                    "its damping at rest c = {damping} is not positive: the fast subsystem does not relax onto an equilibrium curve"
                ),
            ));
        }
        let lo = law.equilibria(A_RANGE.0)?;
        let hi = law.equilibria(A_RANGE.1)?;
        let (x_lo, x_hi) = (lo[0], hi[hi.len() - 1]);
        let gp = |x: f64| law.stiffness(x);
        // the folds: sign changes of the stiffness across the range, each narrowed to f64's
        // resolution
        let x = |i: usize| x_lo + (x_hi - x_lo) * i as f64 / FOLD_SAMPLES as f64;
        let mut folds = Vec::new();
        let (mut a, mut rising) = (x(0), gp(x(0)) > 0.0);
        for i in 1..=FOLD_SAMPLES {
            let b = x(i);
            let rising_b = gp(b) > 0.0;
            if rising != rising_b {
                let same = |t: f64| (gp(t) > 0.0) == rising;
                let (l, r) = crate::roots::bisect(a, b, 200, crate::roots::at_resolution, same);
                folds.push(0.5 * (l + r));
            }
            (a, rising) = (b, rising_b);
        }
        let band = match folds.as_slice() {
            [] => None,
            &[xm, xp] => Some((xm, xp)),
            _ => {
                return Err(refusal(
                    m,
                    format!(
                        "its equilibrium curve has {} folds over a ∈ [−1, 1]; the verdict follows one hysteresis band (two folds) at most",
                        folds.len()
                    ),
                ));
            }
        };
        Ok(ModelCurve {
            law,
            damping,
            range: (x_lo, x_hi),
            band,
        })
    }

    /// The increasing branches (g' > 0 inside), as x-intervals: the range, or the two pieces
    /// outside the band; each with whether it is outermost on the left and on the right (where
    /// [`ModelCurve::root_on`] may look beyond it).
    fn branches(&self) -> impl Iterator<Item = ((f64, f64), (bool, bool))> + use<S> {
        let (l, r) = self.range;
        let pieces = match self.band {
            None => [Some(((l, r), (true, true))), None],
            Some((xm, xp)) => [
                Some(((l, xm), (true, false))),
                Some(((xp, r), (false, true))),
            ],
        };
        pieces.into_iter().flatten()
    }

    /// The root of g = `level` on the increasing branch [l, r], if the level is within g's values
    /// there. The outer ends move outwards until they bracket the level: g is below μ − δ left
    /// of the range and above μ + δ right of it, up to the rounding of the range's ends.
    fn root_on(&self, (mut l, mut r): (f64, f64), level: f64, outer: (bool, bool)) -> Option<f64> {
        let f = |x: f64| self.g(x) - level;
        let width = (self.range.1 - self.range.0).max(f64::MIN_POSITIVE);
        let (mut fl, mut fr) = (f(l), f(r));
        let mut step = width;
        while outer.0 && fl > 0.0 && step.is_finite() {
            l -= step;
            fl = f(l);
            step *= 2.0;
        }
        let mut step = width;
        while outer.1 && fr < 0.0 && step.is_finite() {
            r += step;
            fr = f(r);
            step *= 2.0;
        }
        if fl > 0.0 || fr < 0.0 {
            return None;
        }
        let tol = bracket_tolerance(l, r);
        Some(crate::roots::brent(f, l, fl, r, fr, tol))
    }

    /// [`ModelCurve::root_on`] bracketed from `hint` (a root found on the branch a little
    /// earlier; NaN: none): the far end of the bracket is twice Newton's step from it towards
    /// the level, the step doubled until the bracket holds the root (g increases on the branch),
    /// and the whole branch searched as [`ModelCurve::root_on`] does when the bracket would
    /// reach the branch's end. The same root to the same tolerance, in a few evaluations of g
    /// where the whole branch takes many (its kinks slow the interpolation).
    fn root_near(
        &self,
        (l, r): (f64, f64),
        level: f64,
        outer: (bool, bool),
        hint: f64,
    ) -> Option<f64> {
        if !(hint > l && hint < r) {
            return self.root_on((l, r), level, outer);
        }
        let f = |x: f64| self.g(x) - level;
        let f_hint = f(hint);
        if f_hint == 0.0 {
            return Some(hint);
        }
        let tol = bracket_tolerance(l, r);
        let newton = (f_hint / self.law.g_prime(hint)).abs();
        // towards the level: up where g is below it
        let direction = if f_hint < 0.0 { 1.0 } else { -1.0 };
        let (mut near, mut f_near) = (hint, f_hint);
        let mut step = if newton.is_finite() {
            newton.max(tol)
        } else {
            r - l
        };
        loop {
            let far = near + direction * 2.0 * step;
            if far <= l || far >= r {
                return self.root_on((l, r), level, outer);
            }
            let f_far = f(far);
            if (f_far > 0.0) != (f_near > 0.0) || f_far == 0.0 {
                return Some(crate::roots::brent(f, near, f_near, far, f_far, tol));
            }
            (near, f_near, step) = (far, f_far, 2.0 * step);
        }
    }

    /// The stable equilibria at a, increasing (one per branch whose values reach μ + δa, unless
    /// it is the branch's end at a fold, where g' = 0: a fold point is not stable).
    fn stable_roots(&self, a: f64) -> Vec<f64> {
        if let Some(roots) = self.law.stable_roots(a) {
            return roots;
        }
        self.branch_roots(a, &mut [f64::NAN; 2])
            .into_iter()
            .flatten()
            .collect()
    }

    /// [`ModelCurve::stable_roots`] branch by branch, without the law's own closed form: each
    /// branch's root searched next to its entry of `hints` ([`ModelCurve::root_near`]; NaN:
    /// none), which becomes the root found there (NaN: none); `None` where the branch has no
    /// stable root.
    fn branch_roots(&self, a: f64, hints: &mut [f64; 2]) -> [Option<f64>; 2] {
        let level = self.forcing(a);
        let mut roots = [None; 2];
        for (((iv, outer), hint), root) in self.branches().zip(hints).zip(&mut roots) {
            let found = self.root_near(iv, level, outer, *hint);
            *hint = found.unwrap_or(f64::NAN);
            *root = found.filter(|&x| self.law.stiffness(x) > 0.0);
        }
        roots
    }

    /// The x-intervals of the stable branches that a ∈ [−1, 1] traverses, increasing.
    fn traversed(&self) -> Vec<(f64, f64)> {
        let (a0, a1) = A_RANGE;
        let (lo, hi) = (self.forcing(a0), self.forcing(a1));
        self.branches()
            .filter_map(|((l, r), outer)| {
                let start = if self.g(l) < lo {
                    self.root_on((l, r), lo, outer)?
                } else {
                    l
                };
                let end = if self.g(r) > hi {
                    self.root_on((l, r), hi, outer)?
                } else {
                    r
                };
                (start <= end).then_some((start, end))
            })
            .collect()
    }

    /// The branch the response settles on (as the cubic's [`crate::fast::settled_branch`]):
    /// its x-intervals, and whether the state must jump (both folds in range).
    fn settled(&self) -> (Vec<(f64, f64)>, bool) {
        let all = self.traversed();
        let Some((xm, xp)) = self.band else {
            return (all, false);
        };
        let keep = |f: &dyn Fn(f64) -> bool| -> Vec<(f64, f64)> {
            all.iter()
                .copied()
                .filter(|&(l, r)| f(0.5 * (l + r)))
                .collect()
        };
        let (am, ap) = (self.a_at(xm), self.a_at(xp));
        if am > A_RANGE.1 {
            (keep(&|x| x < xm), false)
        } else if ap < A_RANGE.0 {
            (keep(&|x| x > xp), false)
        } else {
            (all, true)
        }
    }

    /// The least stiffness over the intervals and where (512 samples and a golden-section
    /// refinement on each: a segment of the law narrower than 1/512 of an interval can be missed).
    fn least_gprime(&self, intervals: &[(f64, f64)]) -> (f64, f64) {
        intervals
            .iter()
            .map(|&(l, r)| {
                let (x, neg) = crate::fast::max_on(|x| -self.law.stiffness(x), l, r);
                (-neg, x)
            })
            .fold(
                (f64::INFINITY, f64::NAN),
                |m, c| if c.0 < m.0 { c } else { m },
            )
    }
}

/// Brent's tolerance on a bracket [l, r]: a few rounding errors of its larger end.
fn bracket_tolerance(l: f64, r: f64) -> f64 {
    4.0 * f64::EPSILON * l.abs().max(r.abs())
}

/// The stable equilibrium of a [`ModelCurve`] nearest a state: the root on each increasing
/// branch by Brent's method, bracketed next to the root last found on that branch
/// (`ModelCurve::root_near`): a response's samples come in time order, so between two of them
/// the equilibrium moves little.
#[derive(Clone, Copy, Debug)]
pub struct ModelFollower<S: Statics = StaticTorque> {
    curve: ModelCurve<S>,
    /// The root last found on each branch ([`ModelCurve::branches`]'s order; NaN: none).
    last: [f64; 2],
}

impl<S: Statics> Follower for ModelFollower<S> {
    fn at(&mut self, a: f64, x: f64) -> f64 {
        let c = &self.curve;
        let nearest = |best: Option<f64>, r: f64| match best {
            Some(b) if (b - x).abs() <= (r - x).abs() => Some(b),
            _ => Some(r),
        };
        if let Some(roots) = c.law.stable_roots(a) {
            return roots.into_iter().fold(None, nearest).unwrap_or(x);
        }
        c.branch_roots(a, &mut self.last)
            .into_iter()
            .flatten()
            .fold(None, nearest)
            .unwrap_or(x)
    }
}

impl<S: Statics> StaticCurve for ModelCurve<S> {
    type Follower = ModelFollower<S>;
    fn omega(&self) -> f64 {
        self.law.model().forcing()[2]
    }
    fn delta(&self) -> f64 {
        self.law.model().forcing()[1]
    }
    fn forcing(&self, a: f64) -> f64 {
        let [mu, delta, _] = self.law.model().forcing();
        mu + delta * a
    }
    fn g(&self, x: f64) -> f64 {
        self.law.g(x)
    }
    fn g_prime(&self, x: f64) -> f64 {
        self.law.g_prime(x)
    }
    fn stiffness(&self, x: f64) -> f64 {
        self.law.stiffness(x)
    }
    fn a_at(&self, x: f64) -> f64 {
        let [mu, delta, _] = self.law.model().forcing();
        (self.g(x) - mu) / delta
    }
    fn check(&self) -> Result<()> {
        self.law.model().check()
    }
    /// By the law's root finder; none where it fails (a torque that does not confine x at
    /// this load, which [`ModelCurve::of`] has refused over a ∈ [−1, 1]).
    fn roots(&self, a: f64) -> Vec<f64> {
        self.law.equilibria(a).unwrap_or_default()
    }
    fn fold_band(&self) -> Option<(f64, f64)> {
        self.band
    }
    fn follower(&self, _x0: f64) -> ModelFollower<S> {
        ModelFollower {
            curve: *self,
            last: [f64::NAN; 2],
        }
    }
    fn start(&self) -> f64 {
        self.stable_roots(0.0)
            .first()
            .copied()
            .unwrap_or(self.range.0)
    }
    fn x_extent(&self) -> f64 {
        (self.range.1 - self.range.0).max(f64::MIN_POSITIVE)
    }
    fn min_traversed_gprime(&self) -> f64 {
        // a fold in range: the curve's slope passes 0 on the traversed path
        let fold_in_range = self.band.is_some_and(|(xm, xp)| {
            [xm, xp]
                .iter()
                .any(|&x| (A_RANGE.0..=A_RANGE.1).contains(&self.a_at(x)))
        });
        if fold_in_range {
            return 0.0;
        }
        self.least_gprime(&self.traversed()).0.max(0.0)
    }
    fn damping(&self) -> f64 {
        self.damping
    }
    fn max_equilibrium_speed(&self) -> f64 {
        let (intervals, must_jump) = self.settled();
        crate::fast::max_speed_on(self, &intervals, must_jump)
    }
    fn max_first_order_lag(&self) -> f64 {
        let (intervals, must_jump) = self.settled();
        crate::fast::max_first_order_lag_on(self, &intervals, must_jump)
    }
    fn slowest_relaxation(&self) -> SlowestRelaxation {
        let (intervals, must_jump) = self.settled();
        if self.delta() > 0.0 && !must_jump && !intervals.is_empty() {
            let (gp, x) = self.least_gprime(&intervals);
            return SlowestRelaxation {
                rate: relaxation_rate_with(gp, self.damping),
                a: self.a_at(x),
                x,
                along: Along::SettledBranch,
            };
        }
        self.turning_point_relaxation()
    }
    fn turning_point_relaxation(&self) -> SlowestRelaxation {
        let mut best = SlowestRelaxation {
            rate: f64::INFINITY,
            a: f64::NAN,
            x: f64::NAN,
            along: Along::TurningPoints,
        };
        for a in [A_RANGE.0, A_RANGE.1] {
            for x in self.stable_roots(a) {
                let rate = relaxation_rate_with(self.law.stiffness(x), self.damping);
                if rate < best.rate {
                    best = SlowestRelaxation {
                        rate,
                        a,
                        x,
                        along: Along::TurningPoints,
                    };
                }
            }
        }
        best
    }
}
