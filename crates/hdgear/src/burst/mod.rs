//! Bursts in a response, judged by their physical signatures, with continuous measures of degree
//! and the classification into the study's modes.
//!
//! # What can show the fast mode
//!
//! The fast subsystem x'' + x' + g(x) = μ + δa has trace −1 at every equilibrium: no Hopf
//! bifurcation and no limit cycle exists (guide: the fast subsystem). So a passage of the slow variable a = sin ωτ
//! can show the fast mode in only three ways, and each is measured as an event located on the
//! dense output (a root of a smooth function of the interpolant, never a step end):
//!
//! * **jump**: x crosses the whole unstable band [x−, x+] between the fold abscissae (only with
//!   folds) — a crossing of the far edge of the band after the state was beyond the near one;
//! * **overshoot**: the state gets *ahead* of the equilibrium x*(a) it follows. Adiabatic tracking
//!   on a stable branch always lags (dx*/da = δ/g' > 0), so e = x − x* has the sign opposite to
//!   da/dτ ∝ cos ωτ. A *leading lobe* is an interval where e·cos ωτ > 0 bounded by zeros of e on
//!   both sides; its size is max|e| (at a zero of e', located). Lobes that begin or end at a turning
//!   point of a (cos ωτ = 0) are not overshoot: there the direction of the drive reverses while
//!   the state still lags, so the sign test is void. An overshoot is a leading lobe of at least
//!   [`BurstOptions::overshoot_floor`]·X (X: the curve's x-extent over a ∈ [−1, 1]);
//! * **ringing**: the fast mode oscillates about the moving equilibrium, so x' has extra extrema.
//!   Extrema of x' are zeros of x'' (located); swings smaller than
//!   [`BurstOptions::swing_floor`]·ω·X are pruned with the extremum they would create (ω·X is the
//!   scale of the slow drift's own speed). Ringing is three or more extrema in one group, not
//!   counting the equilibrium's own speed extrema beyond its first (a passage of the cubic has
//!   one hump of dx*/dτ; a curve with several, such as a scheduled stiffness's, would otherwise
//!   ring by quasi-static motion alone).
//!
//! Events closer than the *group gap* G = min(10·τ_r, T/8) form one group (τ_r = 2 is the decay
//! time of every oscillatory fast motion: its eigenvalues have real part −1/2 for any g' > 1/4;
//! ringing extrema further apart than 10·τ_r have decayed by e⁻¹⁰ in between; T/8 keeps the two
//! passages of a slow period apart). A group with a signature is a **burst**. Its *pulse* is its
//! largest |x'|; a burst counts in the window when its pulse does; its onset is the last time
//! before the pulse at which |x'| was below half the pulse. A group longer than T/2 means the
//! fast motion never stops: the response is then reported as `continuous_fast_motion` and has no
//! bursts-per-period (`null`), and it is outside the fast-slow domain.
//!
//! # Why these floors (and why the verdicts do not depend on them)
//!
//! Both floors only remove what no plot could show and what the integration cannot resolve: at
//! rtol = 1e-10 the state carries errors near 1e-10, and an adiabatic response has no leading
//! lobe and no extra extremum at all. `tests/burst.rs` reruns the reference cases with each floor
//! and the gap multiplied and divided by 10 and checks that no verdict changes.
//!
//! # Window
//!
//! Bursts are counted in a window of whole slow periods starting at the first turning point of a
//! (a = ±1) after the discarded transient; the scan starts a margin earlier and ends a margin later
//! (min(T/4, 5G)) so that bursts at the window's edges are seen whole.
//!
//! **Why one file.** The options, the burst and its signatures, the measures and the response are
//! the vocabulary every part of the verdict (scan, lanes, classification, boundaries: their own
//! files) shares.

mod boundary;
mod bursts;
mod classify;
mod lanes;
mod model;
mod plane;
mod scan;

pub use boundary::{BOUNDARY_REL_TOL, Boundaries, OMEGA_SEARCH_MIN, boundaries};
use bursts::assemble;
pub use bursts::{NOISE_FACTOR, ToleranceLimit, overshoot_floor, swing_floor, tolerance_limit};
pub use classify::{
    Classification, DomainEdge, DomainLimit, Mechanism, Mode, Verdict, classify, fast_slow_domain,
    fast_slow_edge, fast_slow_omega_max, turning_point_rate,
};
pub use model::{
    PointVerdict, classify_model, model_curve_facts, model_stiffness_range, response_model,
    response_model_from, response_model_on, verdict_model,
};
pub use plane::{
    BoundaryKind, CURVE_TOL, EDGE_SAMPLES, MAX_TURN, PlaneCurve, PlaneEnd, PlaneOptions,
    PlanePoint, PlaneRow, PlaneSystem, ROUND, plane_boundaries,
};

use scan::{History, Pivot, Scan, Scanner};

use crate::error::{Error, Result};
use crate::fast::StaticCurve;
use crate::fast::{self, stable_equilibrium};
use crate::integrate::{DenseOutput, Options, Stepper, stepper};
use crate::model::Dimensionless;
use crate::params::Params;
use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, PI};

/// A tolerance (rtol = atol) for runs that only need verdicts, modes and counts (sweeps, maps):
/// `tests/burst.rs` shows that none of them changes from 1e-6 to 1e-12 over the 20 reference
/// cases and a 200-point γ sweep; 1e-8 keeps two decades of margin. It saves work with
/// `--method dop853` (1.8 times fewer steps than 1e-10) but not with Taylor's method, whose
/// order falls with the tolerance faster than its step grows (at the study's point 2628 steps at
/// 1e-8 against 2277 at 1e-10). So sweeps, maps and the report's grids run at the default 1e-10
/// with Taylor.
pub const CLASSIFICATION_TOL: f64 = 1e-8;

/// The time-scale separation the fast-slow picture needs where the state settles: ω at most the
/// slowest relaxation rate at the turning points divided by this (a decade, the usual meaning of "ω ≪ r"; see
/// [`fast_slow_domain`]).
pub const TIME_SCALE_SEPARATION: f64 = 10.0;

/// Options of burst detection; `Default` is the documented rule.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BurstOptions {
    /// Slow periods discarded as transient before the window (default 1).
    pub discard_periods: f64,
    /// Whole slow periods analysed (default 2).
    pub periods: u32,
    /// Smallest swing of x' that counts, in units of ω·X (default 1e-3).
    pub swing_floor: f64,
    /// Smallest leading lobe of x − x* that counts as overshoot, in units of X (default 1e-4).
    pub overshoot_floor: f64,
    /// Group gap in decay times τ_r = 2 (default 10; the gap is also capped at T/8).
    pub gap_decay_times: f64,
    /// Fraction of a burst's largest swing of x' a swing must reach to count as a spike
    /// (default 0.2: each ringing swing is about a third of the one before, so the pulse and its
    /// first one or two echoes count, the decayed tail does not).
    pub spike_fraction: f64,
    /// Integrator tolerances.
    pub tol: Options,
}

impl Default for BurstOptions {
    fn default() -> Self {
        BurstOptions {
            discard_periods: 1.0,
            periods: 2,
            swing_floor: 1e-3,
            overshoot_floor: 1e-4,
            gap_decay_times: 10.0,
            spike_fraction: 0.2,
            tol: Options::default(),
        }
    }
}

impl BurstOptions {
    /// Checks the options.
    pub fn validate(&self) -> Result<()> {
        let bad = crate::error::bad_option;
        if !(self.discard_periods.is_finite() && self.discard_periods >= 0.0) {
            return bad("discard", self.discard_periods, "must be finite and ≥ 0");
        }
        if self.periods == 0 {
            return bad("periods", 0.0, "must be ≥ 1");
        }
        for (name, v) in [
            ("swing_floor", self.swing_floor),
            ("overshoot_floor", self.overshoot_floor),
            ("gap_decay_times", self.gap_decay_times),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return bad(name, v, "must be finite and > 0");
            }
        }
        if !(self.spike_fraction.is_finite()
            && self.spike_fraction > 0.0
            && self.spike_fraction < 1.0)
        {
            return bad("spike_fraction", self.spike_fraction, "must be in (0, 1)");
        }
        self.tol.validate()
    }

    /// The group gap G = min(gap_decay_times·τ_r, T/8) for slow period `period` and a fast
    /// subsystem of decay time τ_r = `decay_time` (2/c at damping c: [`StaticCurve::decay_time`]).
    pub fn group_gap_for(&self, period: f64, decay_time: f64) -> f64 {
        (self.gap_decay_times * decay_time).min(period / 8.0)
    }
}

/// One burst: a group of events with at least one signature.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, crate::output::Record)]
pub struct Burst {
    /// Last time before the pulse at which |x'| was below half the pulse.
    pub onset: f64,
    /// Time of the group's last event.
    pub end: f64,
    /// Slow variable at onset.
    pub a_onset: f64,
    /// end − onset.
    pub duration: f64,
    /// Time of the pulse (largest |x'|).
    pub t_peak: f64,
    /// Slow variable at the pulse.
    pub a_peak: f64,
    /// |x'| at the pulse.
    pub peak_abs_xdot: f64,
    /// Swings of x' inside the burst of at least spike_fraction of its largest swing: the pulse's
    /// fall and the echoes that stand out of it (≥ 1; unlike the count of all extrema it does not
    /// depend on the swing floor).
    pub spikes: u32,
    /// Extrema of x' in the burst after pruning, less the equilibrium's own speed extrema beyond
    /// its first (ringing when ≥ 3).
    pub extrema: u32,
    /// Largest swing of x' between consecutive extrema after the pulse, in units of ω·X.
    pub ringing_swing: f64,
    /// Largest leading lobe of x − x*, in units of X (0 without overshoot).
    pub overshoot: f64,
    /// Leading lobes of at least the overshoot floor.
    pub overshoot_lobes: u32,
    /// Crossings of the unstable band.
    pub jumps: u32,
    /// False when the simulation ended before the burst did.
    pub complete: bool,
}

impl Burst {
    /// The burst's strongest signature.
    pub fn verdict(&self) -> Verdict {
        if self.jumps > 0 {
            Verdict::FoldJump
        } else if self.overshoot_lobes > 0 {
            Verdict::Overshoot
        } else if self.extrema >= 3 {
            Verdict::Ringing
        } else {
            Verdict::NoBursts
        }
    }
}

/// Which signatures a response shows, with their rates and sizes.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Signatures {
    /// A jump across the unstable band was measured.
    pub jump: bool,
    /// A leading lobe of at least the floor was measured.
    pub overshoot: bool,
    /// A group of three or more extrema of x' was measured.
    pub ringing: bool,
    /// Jumps in the window per slow period.
    pub jumps_per_period: f64,
    /// Bursts with ringing per slow period.
    pub ringing_bursts_per_period: f64,
    /// Largest leading lobe in the window, in units of X (0: the state never gets ahead).
    pub max_overshoot: f64,
    /// Largest ringing swing of x' in the window's bursts, in units of ω·X.
    pub max_ringing_swing: f64,
}

/// Continuous measures of how far a response is from adiabatic tracking.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Measures {
    /// peak |x'| / max|dx*/dτ|, the largest speed of the equilibrium as a = sin ωτ sweeps the
    /// curve (ω·δ·√(1 − a²)/g'): 1 for quasi-static tracking, below 1 when the state cannot keep up
    /// with the equilibrium, above 1 when it overshoots (0 with a fold in range, where the
    /// equilibrium's speed is unbounded).
    pub speed_ratio: f64,
    /// max|x − x*| / max|e₁|, e₁ = −c·(dx*/dτ)/g'(x*) the first-order adiabatic lag (c the
    /// damping), its maximum taken over the branch the response settles on: → 1 as ω → 0 on a
    /// normally hyperbolic branch (Fenichel); far from 1 when the state leaves the curve (0 with
    /// a fold in range, where e₁ is unbounded).
    pub lag_ratio: f64,
    /// max|x − x*| / X.
    pub relative_lag: f64,
}

/// A response's burst statistics over its window: what a sweep row reports of it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, crate::output::Record)]
pub struct Rates {
    /// Bursts whose pulse lies in the window, per slow period; `None` when the fast motion never
    /// stops ([`Response::continuous_fast_motion`]) or the point failed.
    pub bursts_per_period: Option<f64>,
    /// Mean spikes per burst (0 without bursts).
    pub spikes_per_burst: f64,
    /// Mean pulse |x'| over the bursts (0 without bursts).
    pub burst_amplitude: f64,
    /// Largest |x'| in the window.
    pub peak_abs_xdot: f64,
    /// Mean time from the end of one burst to the onset of the next (the slow period without
    /// bursts).
    pub quiescent_duration: f64,
    /// Fraction of the window outside bursts.
    pub quiescent_fraction: f64,
    /// max |x − x*(a)| over the window (x*: the stable equilibrium followed), located.
    pub max_tracking_error: f64,
}

impl Rates {
    /// The statistics of a point that could not be computed: every value NaN (none for the
    /// bursts per period).
    pub fn unknown() -> Rates {
        Rates {
            bursts_per_period: None,
            spikes_per_burst: f64::NAN,
            burst_amplitude: f64::NAN,
            peak_abs_xdot: f64::NAN,
            quiescent_duration: f64::NAN,
            quiescent_fraction: f64::NAN,
            max_tracking_error: f64::NAN,
        }
    }
}

/// The measured response.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Response {
    /// Start of the analysis window.
    pub window_start: f64,
    /// End of the analysis window.
    pub window_end: f64,
    /// The burst statistics (their fields at the top level of the JSON).
    #[serde(flatten)]
    pub rates: Rates,
    /// A burst lasts longer than half a slow period: the fast motion never settles.
    pub continuous_fast_motion: bool,
    /// Set when the tolerance, not the physics, decided what counts as motion (absent from the
    /// JSON otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance_limited: Option<ToleranceLimit>,
    /// The signatures.
    pub signatures: Signatures,
    /// The continuous measures.
    pub measures: Measures,
    /// X, the curve's x-extent over a ∈ [−1, 1].
    pub x_extent: f64,
    /// The group gap G used.
    pub group_gap: f64,
    /// The bursts whose pulse lies in the window.
    pub bursts: Vec<Burst>,
    /// How the motion stuck and slipped, for a model with sticking friction (absent from the
    /// JSON otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sticking: Option<StickSlip>,
}

/// How a model with sticking friction rested and slipped over the window ([`Response::sticking`]).
/// A rest counts when its breakaway lies in the window; a *slip burst* is a burst whose pulse is
/// the first extremum of x' after a breakaway: the motion the breakaway released, before any
/// other. (A breakaway always releases some: at rest x' = 0, while the equilibrium the slip
/// follows moves on; whether that is a burst is the scan's usual floors' decision.)
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StickSlip {
    /// Rests per slow period.
    pub sticks_per_period: f64,
    /// Their mean duration (0 without rests).
    pub mean_stick: f64,
    /// The longest rest.
    pub max_stick: f64,
    /// Fraction of the window spent at rest.
    pub stuck_fraction: f64,
    /// Largest |x'| at the first extremum after a breakaway (0 without rests).
    pub slip_peak_speed: f64,
    /// Slip bursts per slow period.
    pub slip_bursts_per_period: f64,
    /// Whether the window's largest burst (by its pulse |x'|) is a slip burst: then stick-slip
    /// is the response's mechanism ([`classify`]).
    pub slip_dominates: bool,
}

impl StickSlip {
    /// The stick-slip signature: a slip burst in the window.
    pub fn stick_slip(&self) -> bool {
        self.slip_bursts_per_period > 0.0
    }
}

/// The x-extent X of the equilibrium curve over a ∈ [−1, 1].
pub fn curve_extent(p: &impl StaticCurve) -> f64 {
    p.x_extent()
}

/// The smallest g' over the stable part of the curve traversed by a ∈ [−1, 1] (0 with a fold
/// in range): its slowest, steepest point.
pub fn min_traversed_gprime(p: &impl StaticCurve) -> f64 {
    p.min_traversed_gprime()
}

/// The window [t_w0, t_w1): whole slow periods from the first turning point of a after the
/// discarded transient.
pub fn window(p: &impl StaticCurve, opts: &BurstOptions) -> (f64, f64) {
    let t_discard = opts.discard_periods * p.slow_period();
    let k = ((p.omega() * t_discard - FRAC_PI_2) / PI).ceil().max(0.0);
    let t_w0 = (FRAC_PI_2 + k * PI) / p.omega();
    (t_w0, t_w0 + f64::from(opts.periods) * p.slow_period())
}

/// Simulates from the default start (the lowest stable equilibrium at a = 0, at rest) and
/// measures the response.
///
/// ```
/// use hdgear::{Params, burst::{response, BurstOptions}};
/// let r = response(&Params::default(), &BurstOptions::default()).unwrap(); // γ = 0.1
/// assert_eq!(r.rates.bursts_per_period, Some(2.0));
/// assert!(r.signatures.overshoot);
/// ```
pub fn response(p: &Params, opts: &BurstOptions) -> Result<Response> {
    response_observed(p, opts, None)
}

/// Shown each step's dense output by [`response_observed`].
pub type StepObserver<'a> = &'a mut dyn FnMut(&dyn DenseOutput<2>);

/// [`response`], showing every step's dense output to `on_step` as it is taken (from τ = 0 to
/// past the window's end), so that samples of the same pass can be kept without integrating
/// again. Without an observer the dense output is formed only for the steps the scan needs.
pub fn response_observed(
    p: &Params,
    opts: &BurstOptions,
    on_step: Option<StepObserver<'_>>,
) -> Result<Response> {
    let x0 = stable_equilibrium(p, 0.0);
    measure(p, opts, [x0, 0.0], x0, on_step)
}

/// The response from the state `start` at τ = 0 instead of the default start: with a point of
/// the periodic orbit (at phase 0) and `opts.discard_periods` = 0 it is the verdict on the
/// periodic response itself, with no transient to discard (see
/// [`crate::periodic::burst_verdict`]).
pub fn response_from(p: &Params, opts: &BurstOptions, start: [f64; 2]) -> Result<Response> {
    p.validate()?;
    if !start.iter().all(|v| v.is_finite()) {
        return Err(crate::Error::InvalidOption {
            name: "start",
            value: start[0] + start[1],
            reason: "must be finite",
        });
    }
    // the equilibrium the tracker starts from: the stable one at a(0) = 0 nearest the start
    let x_eq = crate::fast::equilibria(p, 0.0)
        .roots
        .iter()
        .filter(|r| r.kind.is_stable())
        .map(|r| r.x)
        .min_by(|a, b| (a - start[0]).abs().total_cmp(&(b - start[0]).abs()))
        .unwrap_or(start[0]);
    measure(p, opts, start, x_eq, None)
}

/// Simulates from `start` at τ = 0 and scans the response, the equilibrium tracker starting on
/// the branch through `x_eq` at a = 0.
fn measure(
    p: &Params,
    opts: &BurstOptions,
    start: [f64; 2],
    x_eq: f64,
    mut on_step: Option<StepObserver<'_>>,
) -> Result<Response> {
    let plan = Plan::new(p, opts)?;
    let sys = Dimensionless::new(*p);
    let mut solver = stepper(&sys, 0.0, start, opts.tol)?;
    let mut scanner = plan.scanner(p, opts, x_eq);
    let mut history = History::new(plan.history_span());
    while solver.t() < plan.scan.1 {
        solver.step(plan.scan.1)?;
        let scanned = solver.t() > plan.scan.0;
        if scanned || on_step.is_some() {
            let dense = solver.dense();
            if let Some(f) = on_step.as_mut() {
                f(&dense);
            }
            if scanned {
                history.push(dense);
                if let Some(d) = history.latest() {
                    scanner.push(d, &history);
                }
            }
        }
    }
    Ok(plan.assemble(p, opts, scanner.finish(&history)))
}

/// The responses of many parameter sets from the default start, by the batch integrator
/// ([`crate::batch`]: sixteen points in lock-step, each step of all sixteen scanned as it comes,
/// what every step needs computed over the lanes at once). The same verdicts and measures as
/// [`response`] with [`crate::integrate::Method::Taylor`], up to the batch's own rounding (it carries sin ωt as state and uses fused multiply-adds where
/// the CPU has them). Options with `Method::Dop853` run [`response`] point by point. One result per
/// point, in order; a point that fails (bad parameters, a run too long, a blow-up) has its own
/// error and leaves the others' results as they would be without it.
///
/// ```
/// use hdgear::{Params, burst::{BurstOptions, response, responses}};
/// let points = [0.1, 3.0, 30.0].map(|gamma| Params { gamma, ..Params::default() });
/// let opts = BurstOptions::default();
/// let batch = responses(&points, &opts);
/// for (p, r) in points.iter().zip(&batch) {
///     let one = response(p, &opts).unwrap();
///     assert_eq!(r.as_ref().unwrap().rates.bursts_per_period, one.rates.bursts_per_period);
/// }
/// ```
pub fn responses(points: &[Params], opts: &BurstOptions) -> Vec<Result<Response>> {
    // None: not measured yet (then measured on its own below)
    let mut out: Vec<Option<Result<Response>>> = Vec::with_capacity(points.len());
    if opts.tol.method == crate::integrate::Method::Taylor {
        // the points that can run (the others keep their own error), with plans and scanners
        let mut ok = Vec::new();
        for (i, p) in points.iter().enumerate() {
            match Plan::new(p, opts) {
                Ok(plan) => {
                    ok.push((i, plan, stable_equilibrium(p, 0.0)));
                    out.push(None);
                }
                Err(e) => out.push(Some(Err(e))),
            }
        }
        let params: Vec<Params> = ok.iter().map(|o| points[o.0]).collect();
        let starts: Vec<[f64; 2]> = ok.iter().map(|o| [o.2, 0.0]).collect();
        let spans: Vec<(f64, f64)> = ok.iter().map(|o| o.1.scan).collect();
        // one scan of sixteen lanes per chunk of the batch
        let mut scans: Vec<lanes::LaneScan> = ok
            .chunks(crate::batch::LANES)
            .map(|chunk| {
                let lanes = chunk.iter().map(|(i, plan, x0)| {
                    let p = points[*i];
                    let scanner = plan.scanner(&p, opts, *x0);
                    (scanner, p, plan.scan.1, plan.history_span())
                });
                lanes::LaneScan::new(lanes.collect())
            })
            .collect();
        let run =
            crate::batch::integrate_batch_steps(&params, &starts, &spans, opts.tol, |c, step| {
                scans[c].push(step)
            });
        // (an error here is bad input for the batch as a whole: each point then on its own)
        if let Ok(lanes) = run {
            let scanned = scans.into_iter().flat_map(lanes::LaneScan::finish);
            for (((i, plan, _), lane), scan) in ok.into_iter().zip(lanes).zip(scanned) {
                let result = lane.and_then(|_| {
                    // a lane that ends without error has been scanned to its end
                    scan.ok_or(Error::InvalidInput {
                        what: "batch",
                        text: format!("point {i}"),
                        reason: "its scan did not reach the end of its span".into(),
                    })
                });
                out[i] = Some(result.map(|scan| plan.assemble(&points[i], opts, scan)));
            }
        }
    }
    out.resize_with(points.len(), || None);
    out.into_iter()
        .zip(points)
        .map(|(r, p)| r.unwrap_or_else(|| response(p, opts)))
        .collect()
}

/// Where a response is integrated and scanned, from the options and the slow period.
struct Plan {
    /// The window [t_w0, t_w1).
    window: (f64, f64),
    /// The scanned span [t_s0, t_s1]: the window and a margin on both sides.
    scan: (f64, f64),
    gap: f64,
    x_extent: f64,
}

impl Plan {
    fn new(p: &impl StaticCurve, opts: &BurstOptions) -> Result<Plan> {
        p.check()?;
        opts.validate()?;
        let period = p.slow_period();
        let gap = opts.group_gap_for(period, p.decay_time());
        let (t_w0, t_w1) = window(p, opts);
        let margin = (period / 4.0).min(5.0 * gap);
        let scan = ((t_w0 - margin).max(0.0), t_w1 + margin);
        crate::integrate::check_budget(scan.1, &opts.tol)?;
        Ok(Plan {
            window: (t_w0, t_w1),
            scan,
            gap,
            x_extent: curve_extent(p),
        })
    }

    fn scanner<C: StaticCurve>(&self, p: &C, opts: &BurstOptions, x_eq: f64) -> Scanner<C> {
        Scanner::new(
            p,
            x_eq,
            swing_floor(p, opts, self.x_extent),
            0.01 * overshoot_floor(opts, self.x_extent),
            self.window,
        )
    }

    /// How far back a pulse's onset is looked for.
    fn history_span(&self) -> f64 {
        4.0 * self.gap
    }

    fn assemble(&self, p: &impl StaticCurve, opts: &BurstOptions, scan: Scan) -> Response {
        assemble(
            p,
            opts,
            scan,
            self.window,
            self.scan.1,
            self.gap,
            self.x_extent,
        )
    }
}

/// What produced a list of bursts: the `meta` of `hdgear bursts`' JSON output.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BurstsSetup {
    /// The parameters.
    pub params: Params,
    /// Detection options.
    pub options: BurstOptions,
    /// The response's classification.
    pub classification: Classification,
    /// Bursts per slow period (`None`: continuous fast motion).
    pub bursts_per_period: Option<f64>,
    /// The analysed window [start, end).
    pub window: (f64, f64),
    /// The rests and slips, for a model with sticking friction (absent from the JSON otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sticking: Option<StickSlip>,
}

impl BurstsSetup {
    /// The setup of response `r` at `params` measured with `options`.
    pub fn new(params: &Params, options: &BurstOptions, r: &Response) -> BurstsSetup {
        BurstsSetup::classified(params, options, r, classify(params, r))
    }

    /// The setup of response `r` of a model assembled from terms, classified against its own
    /// curve ([`classify_model`]); `params` are the study parameters it was built from.
    pub fn classified(
        params: &Params,
        options: &BurstOptions,
        r: &Response,
        classification: Classification,
    ) -> BurstsSetup {
        BurstsSetup {
            params: *params,
            options: *options,
            classification,
            bursts_per_period: r.rates.bursts_per_period,
            window: (r.window_start, r.window_end),
            sticking: r.sticking,
        }
    }
}
