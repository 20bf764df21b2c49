//! Burst control, quantified: a feedback law is a term of the model ([`crate::model::control`]);
//! [`assess`] measures what it does against the open loop, [`tune`] finds the least gain that
//! removes the bursts, [`robustness`] how much more it needs under a model error, and
//! [`drive`] reads it all back in N m on a physical drive.
//!
//! Each law's gain is its term's first parameter; the others (the washout's ω_w) are fixed by
//! the caller. The verdict is the burst scan's on the closed loop ([`response_model`]), whose
//! equilibria are a study parameter set's; the measures come from a second pass sampled every
//! [`SAMPLE_DT`] over the same window.
//!
//! **Why one file.** Assessing a law and tuning its gain share the open-loop run, the sampled
//! measures and the quadrature over the window; the gain search, stability and robustness already
//! live in their own files.

use crate::burst::{BurstOptions, Verdict, classify_model, response_model};
use crate::error::{Error, Result};
use crate::model::Model;
use crate::model::control::{Dither, VirtualDamping, VirtualStiffness, Washout};
use crate::model::delay::Delay;
use crate::model::schedule::{RAMP_DEFAULT, Scheduled};
use crate::model::terms::{AnyTerm, Term};
use crate::params::Params;
use crate::simulate::{ModelStep, SimOptions, Start, simulate_model_steps};
use serde::Serialize;

mod averaging;
pub mod drive;
mod plant;
mod robustness;
mod search;
mod stability;
pub use averaging::Averaging;
pub use drive::{DriveControl, DriveEffort, RatingCheck, Ratings, compare_drive};
pub use plant::Plant;
pub use robustness::{MODEL_ERROR_PARAMS, Robustness, model_error_plants, robustness};
pub use search::{GAIN_MAX, GAIN_MIN, GAIN_START, MIN_REL_TOL};
use search::{check_gain, check_rel_tol, crossing};
pub use stability::{DelayLimit, crossing_gain, delay_limit};

/// The control laws, by their terms' kinds: the one list `hdgear control` and [`tune`] offer.
pub const LAWS: [&str; 6] = [
    VirtualStiffness::KIND,
    VirtualDamping::KIND,
    Washout::KIND,
    Dither::KIND,
    Delay::KIND,
    Scheduled::KIND,
];

/// The laws [`compare`] runs when given none: every law of [`LAWS`] but the dither, whose
/// verdicts each integrate the ripple (steps a fraction of its period, some 10–100 times the
/// others' work), and the delayed feedback, whose gain depends on a delay the caller chooses;
/// both run on request.
pub const DEFAULT_LAWS: [&str; 4] = [
    VirtualStiffness::KIND,
    VirtualDamping::KIND,
    Washout::KIND,
    Scheduled::KIND,
];

/// Spacing of the samples the measures are taken from (the fast mode's period at the study's
/// sets is ≥ 2π/√(g'max) ≈ 1: 20 samples or more per oscillation; the peaks of x' are the
/// scan's own, located exactly).
pub const SAMPLE_DT: f64 = 0.05;

/// A law with its parameter values: the term of kind `law` (one of [`LAWS`]) with gain `gain`
/// (its first parameter) and its other parameters `rest`, checked against its domains.
pub fn law_term(law: &str, gain: f64, rest: &[f64]) -> Result<AnyTerm> {
    if !LAWS.contains(&law) {
        return Err(Error::InvalidInput {
            what: "control law",
            text: law.to_string(),
            reason: format!("known: {}", LAWS.join(", ")),
        });
    }
    let values: Vec<f64> = std::iter::once(gain).chain(rest.iter().copied()).collect();
    AnyTerm::new(law, &values)
}

/// What a law at one gain does, against the open loop over the same window. For the dither the
/// verdict and peak |x'| are of the motion averaged over its period (the scan's), the energy,
/// efforts and shifts of the motion itself, ripple included (what the drive feels).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Assessment {
    /// The law's term with its values.
    pub term: AnyTerm,
    /// The gain (the term's first parameter).
    pub gain: f64,
    /// The closed loop's verdict.
    pub verdict: Verdict,
    /// The open loop's verdict.
    pub open_verdict: Verdict,
    /// The law makes the loop oscillate by itself: the closed loop's fast motion never settles
    /// (one burst group longer than half a slow period,
    /// [`crate::burst::Response::continuous_fast_motion`]) where the open loop's does. An
    /// unstable loop never counts as removing the bursts, whatever its verdict.
    pub unstable: bool,
    /// Largest |x'| in the window, closed loop.
    pub peak_xdot: f64,
    /// Largest |x'| in the window, open loop.
    pub open_peak_xdot: f64,
    /// Energy of the fast mode, closed over open in dB: the kinetic energy x'²/2 of the twist
    /// averaged over the window. About the moving equilibrium it differs from it by the
    /// quasi-static motion's own share, (δω/g'(x*))²/2, which every law keeping the curve shares
    /// and which is of order ω² away from the steep part. Two other readings were measured and
    /// refused: (x' − ẋ*)² grows without bound at a fold (ẋ* = δω cos ωτ/g'(x*)) and on the
    /// steep part is the curve's speed, which the motion cannot follow, rather than the motion;
    /// the energy of the fast subsystem frozen at the instant's load, x'²/2 + V(x) − V(x*),
    /// counts the lag a law adds as energy, which is [`Assessment::max_shift`]'s business.
    pub fast_energy_db: f64,
    /// Largest |ũ| in the window (the control torque on μ's scale).
    pub effort_peak: f64,
    /// RMS of ũ over the window.
    pub effort_rms: f64,
    /// Mean of ũ over the window: what the control torque does to the rigid-body mode (a
    /// non-zero mean accelerates it; its speed drifts by the mean's integral).
    pub effort_mean: f64,
    /// Invasiveness: the largest change of x at the load's extremes a = ±1 (the turning points
    /// in the window, where the state sits quasi-statically on the curve), over the open loop's
    /// curve extent X.
    pub static_shift: f64,
    /// For a dither: what first-order averaging makes of it (`None` for the other laws).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub averaging: Option<Averaging>,
    /// The largest change of x anywhere in the window, over X: with the load's extremes' shift,
    /// the lag a law adds while the load moves (a washout acts as a damper k_w/ω_w below its
    /// corner, and the state lags the curve by that much more).
    pub max_shift: f64,
}

impl Assessment {
    /// Whether the closed loop shows no burst signature.
    pub fn removes_bursts(&self) -> bool {
        self.verdict == Verdict::NoBursts && !self.unstable
    }

    /// Closed-loop peak |x'| over the open loop's.
    pub fn peak_ratio(&self) -> f64 {
        self.peak_xdot / self.open_peak_xdot
    }
}

/// The closed loop: the plant `p`'s model with the law's term.
pub fn closed_loop<P: Plant>(p: &P, term: AnyTerm) -> Result<Model> {
    p.open_loop().with_term(term)
}

/// Measures the law `term` on the study model with `p` (see [`Assessment`]).
///
/// ```
/// use hdgear::{Params, burst::{BurstOptions, Verdict}, control::{assess, law_term}};
/// let p = Params::default(); // γ = 0.1: bursts
/// let washout = law_term("washout", 10.0, &[0.03]).unwrap();
/// let a = assess(&p, washout, &BurstOptions::default()).unwrap();
/// assert_eq!(a.open_verdict, Verdict::Overshoot);
/// assert!(a.removes_bursts() && a.peak_ratio() < 0.2);
/// ```
pub fn assess<P: Plant>(p: &P, term: AnyTerm, opts: &BurstOptions) -> Result<Assessment> {
    assess_sampled(p, term, opts, SAMPLE_DT)
}

/// [`assess`] with the measures' samples spaced about `sample_dt` apart instead of
/// [`SAMPLE_DT`].
fn assess_sampled<P: Plant>(
    p: &P,
    term: AnyTerm,
    opts: &BurstOptions,
    sample_dt: f64,
) -> Result<Assessment> {
    assess_against(p, term, opts, &OpenLoop::sampled(p, opts, sample_dt)?)
}

/// The open loop's measures, which every assessment on the same set compares against, and the
/// samples' spacing (the closed loop's are taken on the same grid).
struct OpenLoop(Run, f64);

impl OpenLoop {
    fn of<P: Plant>(p: &P, opts: &BurstOptions) -> Result<OpenLoop> {
        OpenLoop::sampled(p, opts, SAMPLE_DT)
    }

    fn sampled<P: Plant>(p: &P, opts: &BurstOptions, sample_dt: f64) -> Result<OpenLoop> {
        let open = p.open_loop();
        Ok(OpenLoop(Run::of(&open, &open, opts, sample_dt)?, sample_dt))
    }
}

/// [`assess`] against the open loop's measures `open` (of the same `p` and `opts`).
fn assess_against<P: Plant>(
    p: &P,
    term: AnyTerm,
    opts: &BurstOptions,
    open: &OpenLoop,
) -> Result<Assessment> {
    let closed = closed_loop(p, term)?;
    let o = &open.0;
    let c = Run::of(&closed, &p.open_loop(), opts, open.1)?;
    let x_extent = p.curve_extent()?;
    let largest = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    let shift = largest(&o.turning_x, &c.turning_x);
    let max_shift = largest(&o.xs, &c.xs);
    Ok(Assessment {
        term,
        gain: term.values()[0],
        verdict: c.verdict,
        open_verdict: o.verdict,
        unstable: c.continuous && !o.continuous,
        peak_xdot: c.peak_xdot,
        open_peak_xdot: o.peak_xdot,
        fast_energy_db: 10.0 * (c.fast_energy / o.fast_energy).log10(),
        effort_peak: c.effort[0],
        effort_rms: c.effort[1],
        effort_mean: c.effort[2],
        static_shift: shift / x_extent,
        averaging: Averaging::of(&closed),
        max_shift: max_shift / x_extent,
    })
}

/// The accuracy of each step's window integrals, relative to the size of the terms they are
/// computed from: a piece is halved until the two halves' sum agrees with the whole to this (at
/// most 30 times). It sits three decades above the rounding of those terms (the difference of
/// two torques cancels), and far below the differences the control table reports.
pub const ADAPTIVE_TOL: f64 = 1e-10;

/// 5-point Gauss–Legendre nodes on [−1, 1] and their weights: exact for polynomials of degree 9.
/// The window's integrals are taken on every step of the integrator and refined by halving
/// ([`ADAPTIVE_TOL`]): a step's dense output is a polynomial of higher degree than the rule
/// integrates exactly, and the integrands are its squares.
const GAUSS5: [(f64, f64); 5] = [
    (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
    (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.0, 0.568_888_888_888_888_9),
    (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.906_179_845_938_664, 0.236_926_885_056_189_1),
];

/// The 5-point Gauss–Legendre integrals of `f`'s components over [a, b].
fn gauss5(f: &mut impl FnMut(f64) -> [f64; 6], a: f64, b: f64) -> [f64; 6] {
    let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
    let mut sum = [0.0; 6];
    for (node, weight) in GAUSS5 {
        for (s, v) in sum.iter_mut().zip(f(mid + half * node)) {
            *s += weight * half * v;
        }
    }
    sum
}

/// ∫ f over [a, b] given its one-piece value `whole`. `f` gives three integrands and, after
/// them, a non-negative scale of each: the size of the terms it is computed from, whose
/// rounding its value carries. A piece is halved until the halves agree with the whole to
/// [`ADAPTIVE_TOL`] times the scale's integral (so rounding, some 1e-13 of the scale, cannot
/// keep it halving), at most `depth` times; a non-finite value stops it.
fn adaptive(
    f: &mut impl FnMut(f64) -> [f64; 6],
    a: f64,
    b: f64,
    whole: [f64; 6],
    depth: u32,
) -> [f64; 6] {
    let mid = 0.5 * (a + b);
    let (left, right) = (gauss5(f, a, mid), gauss5(f, mid, b));
    let halves: [f64; 6] = std::array::from_fn(|i| left[i] + right[i]);
    let agree = (0..3).all(|i| {
        let err = (halves[i] - whole[i]).abs();
        !err.is_finite() || err <= ADAPTIVE_TOL * halves[i + 3]
    });
    if agree || depth == 0 {
        return halves;
    }
    let l = adaptive(f, a, mid, left, depth - 1);
    let r = adaptive(f, mid, b, right, depth - 1);
    std::array::from_fn(|i| l[i] + r[i])
}

/// One loop's verdict and measures.
struct Run {
    verdict: Verdict,
    /// The fast motion never settles ([`crate::burst::Response::continuous_fast_motion`]).
    continuous: bool,
    peak_xdot: f64,
    fast_energy: f64,
    /// Peak |ũ|, RMS and mean of ũ.
    effort: [f64; 3],
    /// x at the turning points of a in the window, in order.
    turning_x: Vec<f64>,
    /// x at every sample in the window.
    xs: Vec<f64>,
}

impl Run {
    /// The loop `m` (the open loop `open` with a law's term, or `open` itself).
    fn of(m: &Model, open: &Model, opts: &BurstOptions, sample_dt: f64) -> Result<Run> {
        let r = response_model(m, opts)?;
        let verdict = classify_model(m, &r)?.verdict;
        let continuous = r.continuous_fast_motion;
        let (w0, w1) = (r.window_start, r.window_end);
        // a grid on which every turning point of a, τ = (2k + 1)·π/(2ω), is a sample
        let quarter = std::f64::consts::FRAC_PI_2 / m.forcing()[2];
        let per_quarter = (quarter / sample_dt).ceil();
        let dt = quarter / per_quarter;
        // ũ = −(the law's torque): the loop's terms' torque less the open loop's, with the size
        // of the two torques it is the difference of (the integrals' tolerance scale)
        let control = |y: &[f64]| {
            let (t_open, t_loop) = (open.torque_at(y), m.torque_at(y));
            (t_open - t_loop, t_open.abs() + t_loop.abs())
        };
        // the window's integrals of the kinetic energy, ũ² and ũ along every step
        let mut integrals = [0.0; 3];
        let mut y = [0.0; crate::model::MAX_STATES + 2];
        let mut peak = 0.0_f64;
        let (mut turning_x, mut window_x) = (Vec::new(), Vec::new());
        let sim = SimOptions {
            t_end: w1,
            dt,
            start: Start::Equilibrium,
            tol: opts.tol,
        };
        // peak |ũ| and the twist on the output grid
        let samples = |t: f64, y: &[f64]| {
            if t < w0 - 0.5 * dt {
                return;
            }
            peak = peak.max(control(y).0.abs());
            window_x.push(y[0]);
            if (t / dt).round() as i64 % (2 * per_quarter as i64) == per_quarter as i64 {
                turning_x.push(y[0]);
            }
        };
        let steps = |step: &dyn ModelStep| {
            let (t0, t1) = step.span();
            let (a, b) = (t0.max(w0), t1.min(w1));
            if a >= b {
                return;
            }
            let mut f = |t: f64| {
                step.state(t, &mut y);
                let (u, scale) = control(&y[..m.dim()]);
                let e = 0.5 * y[1] * y[1];
                [e, u * u, u, e, scale * scale, scale]
            };
            let whole = gauss5(&mut f, a, b);
            for (sum, v) in integrals.iter_mut().zip(adaptive(&mut f, a, b, whole, 30)) {
                *sum += v;
            }
        };
        simulate_model_steps(m, &sim, samples, steps)?;
        let means = integrals.map(|v| v / (w1 - w0));
        Ok(Run {
            verdict,
            continuous,
            peak_xdot: r.rates.peak_abs_xdot,
            fast_energy: means[0],
            effort: [peak, means[1].sqrt(), means[2]],
            turning_x,
            xs: window_x,
        })
    }
}

/// The least gain of a law that removes the bursts: the final bracket's two ends, each assessed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Tuning {
    /// The law's kind.
    pub law: &'static str,
    /// The largest gain found bursting (0: the open loop, when even the smallest gain tried
    /// removes them).
    pub below: Assessment,
    /// The least gain found without bursts: the tuned law.
    pub tuned: Assessment,
    /// The bracket's relative width, tuned/below − 1.
    pub relative_width: f64,
}

/// The refusal of a search for the least control at a point whose open loop does not burst.
fn no_control_needed<P: Plant>(p: &P, law: &str) -> Error {
    Error::InvalidInput {
        what: "control law",
        text: law.to_string(),
        reason: format!(
            "the open loop does not burst at {}: no control is needed",
            p.point()
        ),
    }
}

/// Whether `p`'s closed loop with law `law` at `gain` (other parameters `rest`) bursts, or never
/// settles (a loop the law makes oscillate by itself, [`Assessment::unstable`], does not remove
/// the bursts): the verdict every search here bisects.
fn bursts_at<P: Plant>(
    p: &P,
    law: &str,
    gain: f64,
    rest: &[f64],
    opts: &BurstOptions,
) -> Result<bool> {
    let m = closed_loop(p, law_term(law, gain, rest)?)?;
    let r = response_model(&m, opts)?;
    Ok(classify_model(&m, &r)?.bursting || r.continuous_fast_motion)
}

/// The least gain of law `law` (other parameters `rest`) that removes the bursts of `p`: gains
/// doubled from [`GAIN_START`] until the verdict is no-bursts (or halved while half still removes them), then the bracket bisected
/// geometrically to `rel_tol`; both ends assessed. An error when the open loop does not burst (no
/// control is needed) or no gain up to [`GAIN_MAX`] removes the bursts.
pub fn tune<P: Plant>(
    p: &P,
    law: &str,
    rest: &[f64],
    opts: &BurstOptions,
    rel_tol: f64,
) -> Result<Tuning> {
    check_rel_tol(rel_tol)?;
    static_jumps_refused(p, law, rest)?;
    tune_against(p, law, rest, opts, rel_tol, &OpenLoop::of(p, opts)?)
}

/// Refuses a search for the least gain of a law that cannot remove the bursts at any gain. With
/// both folds in the traversed range the state must jump at each fold, at every ω and whatever
/// the dynamics; a law with no static torque (its closed loop has the open loop's equilibria
/// exactly) leaves the folds where they are, and the search would only simulate ever stiffer
/// loops up to [`GAIN_MAX`]. Checked before any simulation.
fn static_jumps_refused<P: Plant>(p: &P, law: &str, rest: &[f64]) -> Result<()> {
    let closed = closed_loop(p, law_term(law, 1.0, rest)?)?;
    if p.must_jump()? && p.curve_unchanged_by(&closed) {
        return Err(Error::InvalidInput {
            what: "control law",
            text: law.to_string(),
            reason: format!(
                "both folds lie in the traversed range at {}, so the state must jump at \
                 each (fold hysteresis); {law} leaves the equilibrium curve unchanged, so no \
                 gain removes the jumps: a law that stiffens the curve (vstiffness) can",
                p.point()
            ),
        });
    }
    Ok(())
}

/// [`tune`] with the open loop's measures given (computed once for several laws).
fn tune_against<P: Plant>(
    p: &P,
    law: &str,
    rest: &[f64],
    opts: &BurstOptions,
    rel_tol: f64,
    open: &OpenLoop,
) -> Result<Tuning> {
    let bursts = |gain: f64| bursts_at(p, law, gain, rest, opts);
    // the open loop's own verdict (a zero gain is not the open loop for every law: a schedule
    // with g'_min = 0 still stiffens a folding plant)
    let o = &open.0;
    if o.verdict == Verdict::NoBursts && !o.continuous {
        return Err(no_control_needed(p, law));
    }
    // a delay's loop turns unstable at a gain its characteristic roots give: the search stays
    // below it, where each run settles, and says so when no such gain removes the bursts
    let limit = stability::law_limit(p, law, rest)?;
    let max = limit.map_or(GAIN_MAX, |l| l.gain.min(GAIN_MAX));
    let (lo, hi) =
        crossing(bursts, GAIN_START, GAIN_MIN, max, rel_tol)?.ok_or_else(|| Error::NoGain {
            law: known_law(law),
            reason: match limit {
                Some(l) if l.gain < GAIN_MAX => unstable_above(&l),
                _ => format!("none up to {GAIN_MAX} does"),
            },
        })?;
    Ok(Tuning {
        law: known_law(law),
        below: assess_against(p, law_term(law, lo, rest)?, opts, open)?,
        tuned: assess_against(p, law_term(law, hi, rest)?, opts, open)?,
        relative_width: if lo > 0.0 {
            hi / lo - 1.0
        } else {
            f64::INFINITY
        },
    })
}

/// `law` as the entry of [`LAWS`] it names (checked where its term was built).
fn known_law(law: &str) -> &'static str {
    LAWS.into_iter().find(|l| *l == law).unwrap_or("the law")
}

/// Why no gain of a delayed feedback removes the bursts: the loop is unstable above `l.gain`.
fn unstable_above(l: &DelayLimit) -> String {
    format!(
        "with τ_d = {} the closed loop is unstable from K = {:.4} (a root of λ² + λ + k + K − K·e^(−λτ_d) reaches λ = ±{:.4}i at \
         the equilibrium of stiffness k = {:.4}), and every smaller gain still bursts; a shorter \
         delay allows more gain",
        l.taud, l.gain, l.frequency, l.stiffness
    )
}

/// The parameters of `law` after its gain on the plant `p`: its term's defaults, with `c.ww` for
/// a washout's corner frequency, `c.wd` for a dither's frequency and `c.taud` for a delayed
/// feedback's delay where given; for a scheduled stiffness, the plant model `p` itself
/// ([`Scheduled::for_plant`], with the default ramp), which a model error then leaves behind.
pub fn law_rest<P: Plant>(law: &str, p: &P, c: &ControlOptions) -> Result<Vec<f64>> {
    if law == Scheduled::KIND {
        return Ok(p.schedule(0.0, RAMP_DEFAULT)?.0[1..].to_vec());
    }
    Ok(AnyTerm::params_of(law)
        .unwrap_or_default()
        .iter()
        .skip(1)
        .map(|p| match (p.name, c.ww, c.wd, c.taud) {
            ("ww", Some(w), ..) | ("wd", _, Some(w), _) | ("taud", .., Some(w)) => w,
            _ => p.default,
        })
        .collect())
}

/// What [`compare`] runs: tune each law, or assess each at one gain.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ControlOptions {
    /// Assess each law at this gain instead of tuning it.
    pub gain: Option<f64>,
    /// The washout's corner frequency ω_w (its term's default without it).
    pub ww: Option<f64>,
    /// The dither's angular frequency Ω_d (its term's default without it).
    pub wd: Option<f64>,
    /// The delayed feedback's delay τ_d (its term's default without it).
    pub taud: Option<f64>,
    /// The relative width a tuned gain's final bracket stops at, in (0, 1).
    pub rel_tol: f64,
    /// With it (in (0, 1)), each tuned law's [`robustness`] to this relative model error; 0 or
    /// `None`: not checked.
    pub spread: Option<f64>,
}

impl Default for ControlOptions {
    /// Tuned to 1e-3, no robustness.
    fn default() -> Self {
        ControlOptions {
            gain: None,
            ww: None,
            wd: None,
            taud: None,
            rel_tol: 1e-3,
            spread: None,
        }
    }
}

/// Several laws side by side on one parameter set: each tuned ([`tune`]) or each assessed at one
/// gain ([`assess`]); what `hdgear control --json` writes and Python's `hdgear.control` returns.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Comparison<P = Params> {
    /// The plant: the study's set, or a model's description.
    pub params: P,
    /// The laws tuned (empty when assessed at a gain).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub tunings: Vec<Tuning>,
    /// Each tuned law's robustness, in [`Comparison::tunings`]' order (empty without a spread).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub robustness: Vec<Robustness<P>>,
    /// The laws assessed at the given gain (empty when tuned).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub assessments: Vec<Assessment>,
    /// Feed-forward of the load and the tolerance it needs, when every law is tuned.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub feedforward: Option<FeedForward>,
}

impl<P> Comparison<P> {
    /// Each law's row: at its least gain when tuned, else at the given gain.
    pub fn rows(&self) -> impl Iterator<Item = &Assessment> {
        self.tunings
            .iter()
            .map(|t| &t.tuned)
            .chain(&self.assessments)
    }
}

/// The laws `laws` ([`DEFAULT_LAWS`] when empty) on `p` as `c` says: tuned to `c.rel_tol` (with every
/// law tuned, feed-forward's tolerance too, [`feedforward`]; with `c.spread`, each law's
/// [`robustness`]), or assessed at `c.gain`. Every law and value is checked before anything
/// runs; `c.ww` without the washout among the laws, `c.wd` without the dither or `c.taud`
/// without the delayed feedback is refused.
pub fn compare<P: Plant>(
    p: &P,
    laws: &[&str],
    c: &ControlOptions,
    opts: &BurstOptions,
) -> Result<Comparison<P>> {
    let all = laws.is_empty();
    let laws: Vec<&str> = if all {
        DEFAULT_LAWS.to_vec()
    } else {
        laws.to_vec()
    };
    if let Some(gain) = c.gain {
        for law in &laws {
            check_gain(law, gain)?;
        }
    }
    let terms = laws
        .iter()
        .map(|l| law_term(l, c.gain.unwrap_or(GAIN_START), &law_rest(l, p, c)?))
        .collect::<Result<Vec<_>>>()?;
    for (name, value, law, what) in [
        ("ww", c.ww, Washout::KIND, "a corner frequency"),
        ("wd", c.wd, Dither::KIND, "a dither frequency"),
        ("taud", c.taud, Delay::KIND, "a delay"),
    ] {
        if let Some(w) = value
            && !laws.contains(&law)
        {
            return Err(Error::InvalidInput {
                what: name,
                text: w.to_string(),
                reason: format!("only the {law} law has {what}"),
            });
        }
    }
    check_rel_tol(c.rel_tol)?;
    if let Some(s) = c.spread
        && !(0.0..1.0).contains(&s)
    {
        return Err(Error::InvalidOption {
            name: "spread",
            value: s,
            reason: "must lie in [0, 1) (0: no robustness check)",
        });
    }
    let mut out = Comparison {
        params: p.clone(),
        tunings: Vec::new(),
        robustness: Vec::new(),
        assessments: Vec::new(),
        feedforward: None,
    };
    if c.gain.is_none() {
        for law in &laws {
            static_jumps_refused(p, law, &law_rest(law, p, c)?)?;
        }
    }
    let open = OpenLoop::of(p, opts)?;
    match c.gain {
        Some(_) => {
            for term in terms {
                out.assessments.push(assess_against(p, term, opts, &open)?);
            }
        }
        None => {
            for law in &laws {
                let t = tune_against(p, law, &law_rest(law, p, c)?, opts, c.rel_tol, &open)?;
                if let Some(s) = c.spread.filter(|&s| s > 0.0) {
                    out.robustness.push(robustness(p, &t, s, opts, c.rel_tol)?);
                }
                out.tunings.push(t);
            }
            if all {
                out.feedforward = Some(feedforward(p, opts, c.rel_tol)?);
            }
        }
    }
    Ok(out)
}

/// What feed-forward of the slow load, ũ = −κδ·sin(ωτ + Δφ), leaves: the residual forcing is
/// δ·sin ωτ − κδ·sin(ωτ + Δφ) = δ_r·sin(ωτ + ψ) with δ_r = δ·|1 − κe^{iΔφ}| (exactly the open
/// loop with δ → δ_r, shifted in phase, which only the discarded transient sees), so the bursts
/// are gone where δ_r stays below the δ-boundary, and the tolerance on the load's estimate is the
/// disc |1 − κe^{iΔφ}| ≤ ρ = δ_boundary/δ.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FeedForward {
    /// ρ: the largest residual δ_r/δ without bursts (the least of the final bracket's
    /// non-bursting end).
    pub residual_limit: f64,
    /// The smallest residual found bursting (the bracket's other end).
    pub residual_bursting: f64,
    /// With the exact phase, the largest amplitude error |1 − κ|: ρ.
    pub max_amplitude_error: f64,
    /// With the exact amplitude (κ = 1), the largest phase error 2·asin(ρ/2) in rad (π when
    /// ρ ≥ 2: any phase).
    pub max_phase_error: f64,
    /// Peak |ũ| at κ = 1, Δφ = 0: δ.
    pub effort_peak: f64,
}

/// The residual δ_r/δ = |1 − κe^{iΔφ}| = √(1 − 2κ·cos Δφ + κ²) of feed-forward with amplitude
/// ratio κ and phase error Δφ (rad).
pub fn feedforward_residual(kappa: f64, phase_error: f64) -> f64 {
    (1.0 - 2.0 * kappa * phase_error.cos() + kappa * kappa)
        .max(0.0)
        .sqrt()
}

/// How well the load must be known for feed-forward to remove the bursts of `p` ([`FeedForward`]):
/// the δ-boundary found by bisection of the verdict in δ_r/δ, to `rel_tol`.
pub fn feedforward<P: Plant>(p: &P, opts: &BurstOptions, rel_tol: f64) -> Result<FeedForward> {
    check_rel_tol(rel_tol)?;
    // s = δ/δ_r, the suppression: bursting at s = 1 (the open loop) unless nothing is needed
    let bursts = |s: f64| -> Result<bool> { p.load_over(s)?.bursts(opts) };
    if !bursts(1.0)? {
        return Err(no_control_needed(p, "feed-forward"));
    }
    let (lo, hi) = crossing(bursts, 1.0, 1.0, 1e12, rel_tol)?.ok_or(Error::InvalidInput {
        what: "control law",
        text: "feed-forward".into(),
        reason: "the bursts remain down to δ_r = 1e-12·δ".into(),
    })?;
    let rho = 1.0 / hi;
    Ok(FeedForward {
        residual_limit: rho,
        residual_bursting: 1.0 / lo,
        max_amplitude_error: rho,
        max_phase_error: if rho >= 2.0 {
            std::f64::consts::PI
        } else {
            2.0 * (0.5 * rho).asin()
        },
        effort_peak: p.open_loop().forcing()[1],
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::burst::window;

    /// [`SAMPLE_DT`] a decade either way, for three laws that remove the bursts. What the grid
    /// cannot change does not: the verdicts (the burst scan's), the static shift (the turning
    /// points are grid points at every spacing), and the window's integrals (the fast energy, the
    /// effort's RMS and mean), which are taken along the integrator's steps, not on the grid:
    /// equal to rounding (1e-9 relative; the energy to 1e-6 dB, the mean to 1e-9 of the peak).
    /// Only the peak, a maximum over samples, moves: low by at most 1 − cos(π·dt/T) for the
    /// fastest oscillation T ≥ 1.
    #[test]
    fn the_sample_spacing_does_not_change_the_measures_over_a_decade() {
        for (gamma, law, gain, rest) in [
            (0.1, "washout", 10.0, &[0.03][..]),
            (1.0, "vdamping", 2.0, &[]),
            (0.1, "vstiffness", 3.0, &[]),
        ] {
            let p = Params {
                gamma,
                ..Params::default()
            };
            let opts = BurstOptions::default();
            let at = |dt: f64| {
                let t = law_term(law, gain, rest).unwrap();
                assess_sampled(&p, t, &opts, dt).unwrap()
            };
            let a = at(SAMPLE_DT);
            assert_eq!(a.verdict, Verdict::NoBursts, "{law}");
            for dt in [SAMPLE_DT / 10.0, SAMPLE_DT * 10.0] {
                let b = at(dt);
                let rel = |x: f64, y: f64| (x / y - 1.0).abs();
                let what = format!("{law} at γ = {gamma}, dt = {dt}");
                assert_eq!(b.verdict, a.verdict, "{what}");
                assert!(rel(b.static_shift, a.static_shift) < 1e-12, "{what}");
                assert!(rel(b.effort_rms, a.effort_rms) < 1e-9, "{what}");
                assert!(
                    (b.effort_mean - a.effort_mean).abs() < 1e-9 * a.effort_peak,
                    "{what}"
                );
                let sampled = 1.0 - (std::f64::consts::PI * dt.max(SAMPLE_DT)).cos();
                assert!(rel(b.effort_peak, a.effort_peak) <= sampled, "{what}");
                assert!(
                    (b.fast_energy_db - a.fast_energy_db).abs() < 1e-6,
                    "{what}: {} {}",
                    b.fast_energy_db,
                    a.fast_energy_db
                );
            }
        }
    }

    /// The window's fast energy, the mean of x'²/2 over whole slow periods, against an
    /// independent quadrature written here: the solution sampled every 1e-3 on the model's
    /// output grid and the trapezoidal rule (its error O(dt²)). At the study's γ = 0.1
    /// (bursting on the steep part of the curve) and at γ = 0.01, below the cusp, where the
    /// motion jumps at folds: the measure is finite there too. Measured 4.1e-14 and 1.5e-14
    /// apart; asserted 1e-9.
    #[test]
    fn the_fast_energy_is_the_integral_of_the_solution() {
        for gamma in [0.1, 0.01] {
            let p = Params {
                gamma,
                ..Params::default()
            };
            let opts = BurstOptions::default();
            let m = Model::study(&p);
            let run = Run::of(&m, &m, &opts, SAMPLE_DT).unwrap();
            let (w0, w1) = window(&p, &opts);
            let dt = (w1 - w0) / ((w1 - w0) / 1e-3).ceil();
            let (mut sum, mut n, mut ends) = (0.0, 0usize, 0.0);
            let sim = SimOptions {
                t_end: w1,
                dt,
                start: Start::Equilibrium,
                tol: opts.tol,
            };
            simulate_model_steps(
                &m,
                &sim,
                |t, y| {
                    if t < w0 - 0.5 * dt {
                        return;
                    }
                    let v = 0.5 * y[1] * y[1];
                    if n == 0 || (t - w1).abs() < 0.5 * dt {
                        ends += 0.5 * v;
                    }
                    sum += v;
                    n += 1;
                },
                |_| {},
            )
            .unwrap();
            let trapezoid = (sum - ends) * dt / (w1 - w0);
            let rel = (run.fast_energy / trapezoid - 1.0).abs();
            assert!(
                run.fast_energy.is_finite() && rel < 1e-9,
                "γ = {gamma}: {} against {trapezoid}: {rel:e}",
                run.fast_energy
            );
        }
    }
}
