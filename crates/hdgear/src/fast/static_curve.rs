//! The seam between the burst scan and the equilibrium curve it measures against: what the scan
//! and its verdict read of a fast subsystem x'' + c·x' + g(x) = μ + δa with a = sin ωτ frozen.
//! The study's cubic ([`Params`]) answers from its closed forms; a model assembled from terms
//! (`model::ModelCurve`) from a root finder on its static torque. The scan is generic over it, so
//! the cubic keeps its fast path and any other stiffness law gets the same verdict.

use crate::error::Result;
use serde::Serialize;

/// Follows the stable equilibrium a state tracks while a moves.
pub trait Follower: Clone + std::fmt::Debug {
    /// x*(a) for a state at x: the stable equilibrium at a that the state follows.
    fn at(&mut self, a: f64, x: f64) -> f64;
}

/// The equilibrium curve g(x) = μ + δa of a fast subsystem x'' + c·x' + g(x) = μ + δa, and the
/// facts of it the burst verdict reads ([`crate::burst`]).
pub trait StaticCurve: Clone + std::fmt::Debug {
    /// What follows the equilibrium a state tracks.
    type Follower: Follower;
    /// The slow forcing's angular frequency ω.
    fn omega(&self) -> f64;
    /// The slow forcing's amplitude δ.
    fn delta(&self) -> f64;
    /// The forcing μ + δa at slow variable a.
    fn forcing(&self, a: f64) -> f64;
    /// The static torque g(x).
    fn g(&self, x: f64) -> f64;
    /// Its slope g'(x): the equilibrium moves at dx*/da = δ/g'.
    fn g_prime(&self, x: f64) -> f64;
    /// The fast subsystem's stiffness at the equilibrium x, which sets its stability and its
    /// relaxation: g'(x) unless the static torque moves with the load (a scheduled stiffness,
    /// whose equilibria move with a both through the load and through the gain).
    fn stiffness(&self, x: f64) -> f64 {
        self.g_prime(x)
    }
    /// The slow variable at which x is an equilibrium: a(x) = (g(x) − μ)/δ.
    fn a_at(&self, x: f64) -> f64;
    /// Every equilibrium at slow variable a, increasing.
    fn roots(&self, a: f64) -> Vec<f64>;
    /// The eigenvalues (re, im) of the fast Jacobian [[0, 1], [−k, −c]] at the equilibrium x
    /// (k its [`StaticCurve::stiffness`], c the [`StaticCurve::damping`]), larger real part
    /// first.
    fn eigenvalues(&self, x: f64) -> [(f64, f64); 2] {
        super::equilibria::eigenvalues_with(self.stiffness(x), self.damping())
    }
    /// The linear type of the equilibrium x.
    fn kind(&self, x: f64) -> super::EqType {
        super::EqType::with_damping(self.stiffness(x), self.damping())
    }
    /// Whether the curve's parameters are valid.
    fn check(&self) -> Result<()>;
    /// The fold abscissae x− < x+ bounding the unstable band (g' < 0 between them), if any.
    fn fold_band(&self) -> Option<(f64, f64)>;
    /// A follower starting from the equilibrium guess `x0`.
    fn follower(&self, x0: f64) -> Self::Follower;
    /// The default start: the lowest stable equilibrium at a = 0.
    fn start(&self) -> f64;
    /// The x-extent X of the curve over a ∈ [−1, 1] (the unit of x-distances in detection).
    fn x_extent(&self) -> f64;
    /// The smallest g' over the curve traversed by a ∈ [−1, 1] (0 with a fold in range).
    fn min_traversed_gprime(&self) -> f64;
    /// The damping at rest c: −trace of the fast Jacobian [[0, 1], [−g', −c]].
    fn damping(&self) -> f64;
    /// The slope above which a stable equilibrium is a focus (complex eigenvalues): c²/4.
    fn focus_gprime(&self) -> f64 {
        let c = self.damping();
        c * c / 4.0
    }
    /// The e-folding time 2/c of a ringing about a focus (its amplitude decays as e^{−cτ/2}).
    fn decay_time(&self) -> f64 {
        2.0 / self.damping()
    }
    /// The largest speed |dx*/dτ| of the equilibrium on the branch the response settles on
    /// (infinite when the state must jump).
    fn max_equilibrium_speed(&self) -> f64;
    /// The largest first-order adiabatic lag |e₁| = c·|dx*/dτ|/k on the branch the response
    /// settles on, k the fast stiffness ([`StaticCurve::stiffness`]; infinite when the state must
    /// jump).
    fn max_first_order_lag(&self) -> f64;
    /// The slowest relaxation met on the path the state follows ([`super::slowest_relaxation`]).
    fn slowest_relaxation(&self) -> SlowestRelaxation;
    /// The slowest relaxation at the stable equilibria at a = ±1.
    fn turning_point_relaxation(&self) -> SlowestRelaxation;
    /// The least and largest fast stiffness ([`StaticCurve::stiffness`]) of the equilibrium the
    /// state follows over one slow period from the default start (a = sin θ at 1024 phases θ):
    /// the linear stiffness a feedback law meets on the way.
    fn stiffness_range(&self) -> (f64, f64) {
        const PHASES: u32 = 1024;
        let mut x = self.start();
        let mut follower = self.follower(x);
        (0..=PHASES).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), j| {
            let a = (std::f64::consts::TAU * f64::from(j) / f64::from(PHASES)).sin();
            x = follower.at(a, x);
            let k = self.stiffness(x);
            (lo.min(k), hi.max(k))
        })
    }
    /// The slow period 2π/ω.
    fn slow_period(&self) -> f64 {
        std::f64::consts::TAU / self.omega()
    }
    /// The extrema (τ, dx*/dτ, is_max) of the followed equilibrium's speed
    /// dx*/dτ = ω·cos ωτ·δ/g'(x*) over [t0, t1] (a = sin ωτ), sampled at least every quarter of
    /// the decay time (its humps are slow: each lasts a fraction of the slow period); none when
    /// the state must jump (the speed is unbounded at the fold).
    fn speed_extrema(&self, t0: f64, t1: f64) -> Vec<(f64, f64, bool)> {
        if t1.partial_cmp(&t0) != Some(std::cmp::Ordering::Greater)
            || !self.max_equilibrium_speed().is_finite()
        {
            return Vec::new();
        }
        let n = ((t1 - t0) / (0.25 * self.decay_time()))
            .ceil()
            .clamp(64.0, 4096.0) as usize;
        let mut x = self.start();
        let mut follower = self.follower(x);
        let mut speed = |t: f64| {
            let (a, c) = (self.omega() * t).sin_cos();
            x = follower.at(a, x);
            self.omega() * c * self.delta() / self.g_prime(x)
        };
        let h = (t1 - t0) / n as f64;
        let mut out = Vec::new();
        let (mut before, mut now) = (speed(t0), speed(t0 + h));
        for i in 2..=n {
            let t = t0 + h * i as f64;
            let next = speed(t);
            if (now - before) * (next - now) < 0.0 {
                out.push((t - h, now, next < now));
            }
            (before, now) = (now, next);
        }
        out
    }
}

/// The slowest relaxation rate min |Re λ| of λ² + cλ + g' = 0 for g' > 0 (0 otherwise): c/2 on
/// a focus (g' ≥ c²/4), (c/2)·(1 − √(1 − 4g'/c²)) on a node.
pub fn relaxation_rate_with(gp: f64, c: f64) -> f64 {
    if gp <= 0.0 {
        return 0.0;
    }
    let disc = 1.0 - 4.0 * gp / (c * c);
    if disc >= 0.0 {
        0.5 * c * (1.0 - disc.sqrt())
    } else {
        0.5 * c
    }
}

/// Where the slowest relaxation was taken.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Along {
    /// Over the whole stable branch the response settles on (it spans a ∈ [−1, 1]).
    SettledBranch,
    /// At the turning points a = ±1 (both folds in range, or δ = 0: see the module docs).
    TurningPoints,
}

impl Along {
    /// The name used in text output.
    pub fn name(self) -> &'static str {
        match self {
            Along::SettledBranch => "settled-branch",
            Along::TurningPoints => "turning-points",
        }
    }
}

/// The slowest relaxation rate of the fast subsystem met on the traversed path, and where.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SlowestRelaxation {
    /// min |Re λ| of the fast subsystem there ([`super::relaxation_rate_with`] at the curve's damping).
    pub rate: f64,
    /// The slow variable a where it is met.
    pub a: f64,
    /// The equilibrium x there.
    pub x: f64,
    /// Over what it was taken.
    pub along: Along,
}
