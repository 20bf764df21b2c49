//! The verdict, the mode and the mechanism of a measured response, and the fast-slow domain.

use super::*;

/// The strongest signature of a response (order: fold-jump > stick-slip > overshoot > ringing >
/// no-bursts).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Verdict {
    /// The state follows the equilibrium adiabatically.
    NoBursts,
    /// The fast mode rings about the moving equilibrium; the state never gets ahead.
    Ringing,
    /// The state gets ahead of the equilibrium it follows.
    Overshoot,
    /// The motion sticks, and the largest burst is a slip after a breakaway (a model with
    /// sticking friction: [`StickSlip`]).
    StickSlip,
    /// The state jumps across the unstable band between two folds.
    FoldJump,
}

/// The oscillation mode: the study's four words, defined from the signatures (each keeps its
/// meaning as ω changes), plus the two cases the study's words do not cover.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Mode {
    /// No signature: the state follows the equilibrium (x' is the smooth slow wave).
    Normal,
    /// Ringing only: the fast mode is excited, but the state never gets ahead.
    Transitional,
    /// Overshoot on a branch whose slowest point is a focus (g' > 1/4): a pulse and ringing.
    FastSlow,
    /// Overshoot where the slowest point of the traversed branch is a node (g' ≤ 1/4): the
    /// state creeps behind the equilibrium, then snaps ahead of it.
    PronouncedBursting,
    /// Jumps between two stable branches across the folds: a relaxation (hysteresis) loop, the only
    /// bursting that survives ω → 0.
    Relaxation,
    /// Outside the fast-slow domain: the forcing is not slow against the fast subsystem.
    NotFastSlow,
    /// The motion rests in the friction band, breaks away and slips in a burst.
    StickSlip,
}

/// The mechanism behind the bursts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Mechanism {
    /// No signature.
    None,
    /// Overshoot or ringing on a single stable branch: no bifurcation, a steep curve.
    SharpQuantitativeChange,
    /// A measured jump across the folds.
    FoldHysteresis,
    /// Static friction holds the motion while the load builds up, and releases it in a slip.
    StickSlip,
}

impl Mode {
    /// The kebab-case name.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Normal => "normal",
            Mode::Transitional => "transitional",
            Mode::FastSlow => "fast-slow",
            Mode::PronouncedBursting => "pronounced-bursting",
            Mode::Relaxation => "relaxation",
            Mode::NotFastSlow => "not-fast-slow",
            Mode::StickSlip => "stick-slip",
        }
    }
}

impl Mechanism {
    /// The kebab-case name.
    pub fn name(self) -> &'static str {
        match self {
            Mechanism::None => "none",
            Mechanism::SharpQuantitativeChange => "sharp-quantitative-change",
            Mechanism::FoldHysteresis => "fold-hysteresis",
            Mechanism::StickSlip => "stick-slip",
        }
    }
}

impl Verdict {
    /// The kebab-case name.
    pub fn name(self) -> &'static str {
        match self {
            Verdict::NoBursts => "no-bursts",
            Verdict::Ringing => "ringing",
            Verdict::Overshoot => "overshoot",
            Verdict::StickSlip => "stick-slip",
            Verdict::FoldJump => "fold-jump",
        }
    }
}

macro_rules! display_by_name {
    ($($t:ty),*) => {$(
        impl std::fmt::Display for $t {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.pad(self.name())
            }
        }
    )*};
}
display_by_name!(Verdict, Mode, Mechanism);

/// Verdict, mode and mechanism.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Classification {
    /// Any signature present.
    pub bursting: bool,
    /// The strongest signature.
    pub verdict: Verdict,
    /// The oscillation mode.
    pub mode: Mode,
    /// The mechanism.
    pub mechanism: Mechanism,
    /// Whether the fast-slow picture applies (see [`fast_slow_domain`]).
    pub fast_slow_domain: bool,
}

/// Whether the forcing is slow against the fast subsystem, so that the fast-slow picture (a
/// frozen, the state settling between passages) applies. Two conditions, and, measured, the fast
/// motion stops between passages (no continuous fast motion):
///
/// * **settling**: where the state rests, at the turning points a = ±1 where the equilibrium
///   stands still, ω ≤ r_q/10: a decade of time-scale separation (the usual meaning of
///   "ω ≪ r"), r_q the slowest relaxation rate there ([`turning_point_rate`]; 1/2 on a focus, so
///   ω ≤ 0.05 for the study's stiff branches);
/// * **ordering**: at every point of the path the state follows, ω < r, r the slowest
///   relaxation rate met there ([`fast::slowest_relaxation`]). Where ω ≥ r the "fast"
///   subsystem relaxes more slowly than the forcing turns: the two time scales have exchanged
///   roles, and no fast-slow decomposition holds. This is the crossing point itself, not a
///   chosen margin: a node part is where bursts start (the state creeps behind the equilibrium,
///   then snaps ahead), so asking for a decade there would exclude the bursting the picture is
///   meant to explain (the study's γ = 0.1 example passes a node with ω/r = 0.12).
pub fn fast_slow_domain(p: &impl StaticCurve, r: &Response) -> bool {
    !r.continuous_fast_motion && p.omega() <= fast_slow_omega_max(p)
}

/// The largest ω of the fast-slow domain: the smaller of r_q/[`TIME_SCALE_SEPARATION`] and the
/// slowest relaxation rate on the path (see [`fast_slow_domain`]).
pub fn fast_slow_omega_max(p: &impl StaticCurve) -> f64 {
    fast_slow_edge(p).omega_max
}

/// Which of the fast-slow domain's two conditions ([`fast_slow_domain`]) sets its edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum DomainLimit {
    /// Settling at the turning points: ω ≤ r_q/[`TIME_SCALE_SEPARATION`].
    Settling,
    /// Ordering on the path: ω < r, r the slowest relaxation rate met.
    Ordering,
}

/// The edge of the fast-slow domain in ω, its two conditions' rates and which one sets it: what
/// a report of "outside the domain" names, derived here once.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct DomainEdge {
    /// The largest ω of the domain ([`fast_slow_omega_max`]).
    pub omega_max: f64,
    /// r_q, the slowest relaxation rate at the turning points a = ±1.
    pub turning_point_rate: f64,
    /// The slowest relaxation met on the traversed path, and where.
    pub slowest: fast::SlowestRelaxation,
    /// The condition that sets `omega_max`.
    pub limit: DomainLimit,
}

/// The edge of the fast-slow domain of `p` ([`DomainEdge`]).
///
/// ```
/// use hdgear::{Params, burst::{DomainLimit, fast_slow_edge}};
/// // the study's γ = 30: stiff everywhere, the turning points' decade sets the edge
/// let e = fast_slow_edge(&Params { gamma: 30.0, ..Params::default() });
/// assert_eq!(e.limit, DomainLimit::Settling);
/// assert_eq!(e.omega_max, e.turning_point_rate / 10.0);
/// ```
pub fn fast_slow_edge(p: &impl StaticCurve) -> DomainEdge {
    let slowest = p.slowest_relaxation();
    // taken at the turning points already when the path is not followed (both folds in range)
    let turning = if slowest.along == fast::Along::TurningPoints {
        slowest
    } else {
        p.turning_point_relaxation()
    };
    let settling = turning.rate / TIME_SCALE_SEPARATION;
    let limit = if slowest.rate < settling {
        DomainLimit::Ordering
    } else {
        DomainLimit::Settling
    };
    DomainEdge {
        omega_max: settling.min(slowest.rate),
        turning_point_rate: turning.rate,
        slowest,
        limit,
    }
}

/// The slowest relaxation rate of the fast subsystem at the stable equilibria at the turning
/// points a = ±1 (the smaller of the two).
pub fn turning_point_rate(p: &impl StaticCurve) -> f64 {
    p.turning_point_relaxation().rate
}

/// Verdict, mode and mechanism of a measured response.
///
/// * verdict: the strongest signature (fold-jump > stick-slip > overshoot > ringing > no-bursts);
///   bursting when any is present;
/// * mechanism: `fold-hysteresis` when a jump is measured, `stick-slip` when the largest burst
///   is a slip from a breakaway ([`StickSlip::slip_dominates`]), `sharp-quantitative-change` for
///   overshoot or ringing on a single branch, `none` otherwise;
/// * mode: `not-fast-slow` outside [`fast_slow_domain`]; else `relaxation` (jump), `stick-slip`,
///   `pronounced-bursting` (overshoot, slowest traversed point a node: g' ≤ 1/4), `fast-slow`
///   (overshoot, a focus there), `transitional` (ringing only), `normal` (nothing).
pub fn classify(p: &impl StaticCurve, r: &Response) -> Classification {
    let s = &r.signatures;
    let verdict = if s.jump {
        Verdict::FoldJump
    } else if r.sticking.is_some_and(|k| k.slip_dominates) {
        Verdict::StickSlip
    } else if s.overshoot {
        Verdict::Overshoot
    } else if s.ringing {
        Verdict::Ringing
    } else {
        Verdict::NoBursts
    };
    let domain = fast_slow_domain(p, r);
    let mode = if !domain {
        Mode::NotFastSlow
    } else {
        match verdict {
            Verdict::FoldJump => Mode::Relaxation,
            Verdict::StickSlip => Mode::StickSlip,
            Verdict::Overshoot if min_traversed_gprime(p) <= p.focus_gprime() => {
                Mode::PronouncedBursting
            }
            Verdict::Overshoot => Mode::FastSlow,
            Verdict::Ringing => Mode::Transitional,
            Verdict::NoBursts => Mode::Normal,
        }
    };
    Classification {
        bursting: verdict != Verdict::NoBursts,
        verdict,
        mode,
        mechanism: match verdict {
            Verdict::FoldJump => Mechanism::FoldHysteresis,
            Verdict::StickSlip => Mechanism::StickSlip,
            Verdict::Overshoot | Verdict::Ringing => Mechanism::SharpQuantitativeChange,
            Verdict::NoBursts => Mechanism::None,
        },
        fast_slow_domain: domain,
    }
}
