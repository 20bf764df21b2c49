//! Bursts in a response: detection, per-burst and per-response metrics, and the classification
//! of the oscillation mode and its mechanism.
//!
//! # Detection rule
//!
//! The *quasi-static velocity* is the speed the state would have if it sat on the stable
//! equilibrium x*(a) as a = sin(ωτ) moves: v_qs(τ) = ω·(dx*/da)·cos(ωτ) = ω·δ/g'(x*)·cos(ωτ),
//! with x* the stable equilibrium nearest to the state (the only one without folds). The
//! *deviation* is d(τ) = x'(τ) − v_qs(τ): zero for a state that follows the curve adiabatically,
//! large where the equilibrium escapes or the state rings.
//!
//! A burst starts when |d| exceeds θ_on = [`BurstOptions::on_threshold`]·ω·X (X: the x-extent of
//! the equilibrium curve over a ∈ [−1, 1], so ω·X is the natural speed of the slow drift), and
//! ends at the last time |d| was above θ_off = θ_on/2 once |d| has stayed below θ_off for
//! [`BurstOptions::quiet_gap`] time units. The gap (10 time units, five relaxation times 1/r = 2
//! of a focus) keeps a burst's decaying ringing, whose |d| dips to zero twice per oscillation, in
//! one burst. |d| is evaluated at every accepted integration step (steps are 0.05–0.25 time
//! units here, well below the ringing half-period), so onset and end are accurate to one step.
//!
//! Why θ_on = 0.5·ω·X: measured over three slow periods at the study's point, max |d| is
//! 3e-7 (γ = 30) and 4e-5 (γ = 10) — the smooth slow drift and its extrema — against 0.087
//! (γ = 1) and 1.8 (γ = 0.1); ω·X ≈ 0.019, so the threshold 0.0095 is 240 times above the
//! adiabatic γ = 10 response and 9 times below the weakest burst of the study.
//!
//! # Metrics
//!
//! Bursts are counted in a window of whole slow periods that starts at the first turning point
//! of a (a = ±1, where the equilibrium stands still and nothing bursts) after the discarded
//! transient, so the count does not depend on where the window cuts a burst.
//!
//! * per burst: onset and end, a at onset, duration, peak |x'|, and *spikes*: the extrema of x'
//!   inside the burst whose |x'| is at least [`BurstOptions::spike_fraction`] (20 %) of the
//!   burst's peak |x'| — the pulse and the ringing swings that stand out of it (with the
//!   dimensionless damping 1, each ringing swing is about a third of the previous one, so 20 %
//!   keeps the pulse and its first one or two echoes and drops the decayed tail). Extrema are
//!   located exactly (zeros of x'' on the dense output, refined by bisection).
//! * per response: bursts per slow period, mean spikes per burst, burst amplitude (mean peak
//!   |x'| over bursts), peak |x'| over the window, quiescent duration (mean time between the end
//!   of one burst and the onset of the next) and quiescent fraction (of the window), and the
//!   largest tracking error max|x − x*(a)| (at step ends).

use crate::error::{Error, Result};
use crate::fast::{self, stable_equilibrium};
use crate::integrate::{Dop853, Options, System};
use crate::model::Dimensionless;
use crate::params::Params;
use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, PI};

/// Options of burst detection; `Default` is the documented rule.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct BurstOptions {
    /// Slow periods discarded as transient before the window (default 1).
    pub discard_periods: f64,
    /// Whole slow periods analysed (default 2, so 3 periods are simulated plus the shift to the
    /// window's turning point).
    pub periods: u32,
    /// θ_on in units of ω·X (default 0.5).
    pub on_threshold: f64,
    /// Quiet time that closes a burst (default 10 time units).
    pub quiet_gap: f64,
    /// Fraction of the burst's peak |x'| a ringing extremum of x' must reach to count as a
    /// spike (default 0.2).
    pub spike_fraction: f64,
    /// Integrator tolerances.
    pub tol: Options,
}

impl Default for BurstOptions {
    fn default() -> Self {
        BurstOptions {
            discard_periods: 1.0,
            periods: 2,
            on_threshold: 0.5,
            quiet_gap: 10.0,
            spike_fraction: 0.2,
            tol: Options::default(),
        }
    }
}

impl BurstOptions {
    /// Checks the options.
    pub fn validate(&self) -> Result<()> {
        let bad = |name, value, reason| {
            Err(Error::InvalidOption {
                name,
                value,
                reason,
            })
        };
        if !(self.discard_periods.is_finite() && self.discard_periods >= 0.0) {
            return bad("discard", self.discard_periods, "must be finite and ≥ 0");
        }
        if self.periods == 0 {
            return bad("periods", 0.0, "must be ≥ 1");
        }
        if !(self.on_threshold.is_finite() && self.on_threshold > 0.0) {
            return bad("on_threshold", self.on_threshold, "must be finite and > 0");
        }
        if !(self.quiet_gap.is_finite() && self.quiet_gap > 0.0) {
            return bad("quiet_gap", self.quiet_gap, "must be finite and > 0");
        }
        if !(self.spike_fraction.is_finite()
            && self.spike_fraction > 0.0
            && self.spike_fraction < 1.0)
        {
            return bad("spike_fraction", self.spike_fraction, "must be in (0, 1)");
        }
        self.tol.validate()
    }
}

/// One burst.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Burst {
    /// Time at which |d| first exceeded θ_on.
    pub onset: f64,
    /// Last time |d| was above θ_off.
    pub end: f64,
    /// Slow variable at onset.
    pub a_onset: f64,
    /// end − onset.
    pub duration: f64,
    /// Largest |x'| in the burst.
    pub peak_abs_xdot: f64,
    /// Largest |x' − v_qs| in the burst.
    pub peak_deviation: f64,
    /// Extrema of x' with |x'| ≥ spike_fraction · peak_abs_xdot.
    pub spikes: u32,
    /// False when the simulation ended before the burst did.
    pub complete: bool,
}

/// The measured response.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Response {
    /// Start of the analysis window.
    pub window_start: f64,
    /// End of the analysis window.
    pub window_end: f64,
    /// Bursts with onset in the window, per slow period.
    pub bursts_per_period: f64,
    /// Mean spikes per burst (complete bursts in the window; 0 without bursts).
    pub spikes_per_burst: f64,
    /// Mean peak |x'| over the bursts (0 without bursts).
    pub burst_amplitude: f64,
    /// Largest |x'| in the window.
    pub peak_abs_xdot: f64,
    /// Largest |x' − v_qs| in the window.
    pub peak_deviation: f64,
    /// Mean time from the end of one burst to the onset of the next (the window length per
    /// period without bursts).
    pub quiescent_duration: f64,
    /// Fraction of the window outside bursts.
    pub quiescent_fraction: f64,
    /// max |x − x*(a)| over the window (x*: nearest stable equilibrium), at step ends.
    pub max_tracking_error: f64,
    /// θ_on used.
    pub on_threshold: f64,
    /// The bursts with onset in the window.
    pub bursts: Vec<Burst>,
}

/// The oscillation mode (study's table).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mode {
    /// The state follows the equilibrium closely; x' is the smooth slow wave.
    Normal,
    /// No bursts, but the state lags the equilibrium visibly.
    Transitional,
    /// Bursts twice per slow period.
    FastSlow,
    /// Strong bursts.
    PronouncedBursting,
}

/// The mechanism behind the bursts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Mechanism {
    /// No bursts.
    None,
    /// Bursts while the fast subsystem has one stable equilibrium for every traversed a.
    SharpQuantitativeChange,
    /// Folds lie inside the traversed range of a.
    FoldHysteresis,
}

impl Mode {
    /// The kebab-case name.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Normal => "normal",
            Mode::Transitional => "transitional",
            Mode::FastSlow => "fast-slow",
            Mode::PronouncedBursting => "pronounced-bursting",
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
        }
    }
}

/// Classification thresholds (see [`classify`]). Both act on one measured number, the largest
/// tracking error max|x − x*| as a fraction of the curve's x-extent X: how far the state falls
/// behind the equilibrium it should follow.
///
/// Measured at the study's point (three slow periods, default detection): max|x − x*|/X =
/// 7.8e-5 (γ = 50), 1.4e-4 (γ = 30), 2.5e-4 (γ = 20), 9.1e-4 (γ = 10), 3.4e-3 (γ = 5),
/// 9.7e-3 (γ = 3) without bursts; 0.022 (γ = 2), 0.066 (γ = 1), 0.108 (γ = 0.5), 0.129 (γ = 0.3),
/// 0.151 (γ = 0.1), 0.156 (γ = 0.05) with bursts. It grows monotonically as γ falls.
pub mod thresholds {
    /// Without bursts: `transitional` above 3e-4·X, else `normal`. Between γ = 30 (1.4e-4, a
    /// factor 2.2 below) and γ = 10 (9.1e-4, a factor 3 above), the study's normal and
    /// transitional cases: the lag becomes a visible fraction of the slow motion.
    pub const TRANSITIONAL_LAG: f64 = 3e-4;
    /// With bursts: `pronounced-bursting` above 0.1·X, else `fast-slow`: the state is left behind
    /// by more than a tenth of the whole curve. Between γ = 1 (0.066, a factor 1.5 below) and
    /// γ = 0.1 (0.151, a factor 1.5 above), the study's fast-slow and pronounced cases.
    pub const PRONOUNCED_LAG: f64 = 0.1;
}

/// Mode and mechanism.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Classification {
    /// The oscillation mode.
    pub mode: Mode,
    /// The mechanism.
    pub mechanism: Mechanism,
}

/// The stable equilibrium nearest to x at slow variable a. `multi` is the a-interval where the
/// fast subsystem has three equilibria (between the fold values), if any: outside it the
/// equilibrium is unique and a Newton iteration warm-started from the previous one (`hint`)
/// finds it; inside it all roots are computed and the nearest stable one is taken.
fn nearest_stable(p: &Params, a: f64, x: f64, multi: Option<(f64, f64)>, hint: f64) -> f64 {
    let unique = multi.is_none_or(|(lo, hi)| a < lo || a > hi);
    if unique {
        let rhs = p.forcing(a);
        let mut y = hint;
        for _ in 0..8 {
            let step = (p.g(y) - rhs) / p.g_prime(y);
            y -= step;
            if step.abs() <= 1e-13 * (1.0 + y.abs()) && p.g_prime(y) > 0.0 {
                return y;
            }
        }
    }
    fast::nearest_stable_equilibrium(p, a, x).unwrap_or(x)
}

/// The x-extent X of the equilibrium curve over a ∈ [−1, 1].
pub fn curve_extent(p: &Params) -> f64 {
    let iv = fast::x_intervals(p, (-1.0, 1.0));
    match (iv.first(), iv.last()) {
        (Some(l), Some(r)) => (r.1 - l.0).max(f64::MIN_POSITIVE),
        _ => f64::MIN_POSITIVE,
    }
}

struct Open {
    onset: f64,
    a_onset: f64,
    last_active: f64,
    peak_v: f64,
    peak_d: f64,
    extrema: Vec<f64>, // |x'| at the extrema of x'
}

/// Simulates from the default start (the stable equilibrium at a = 0) and measures the response.
///
/// ```
/// use hdgear::{Params, burst::{response, BurstOptions}};
/// let r = response(&Params::default(), &BurstOptions::default()).unwrap(); // γ = 0.1
/// assert_eq!(r.bursts_per_period, 2.0);
/// ```
pub fn response(p: &Params, opts: &BurstOptions) -> Result<Response> {
    p.validate()?;
    opts.validate()?;
    let period = p.slow_period();
    // window: first turning point of a (phase π/2 + kπ) at or after the discarded transient
    let t_discard = opts.discard_periods * period;
    let phase = p.omega * t_discard;
    let k = ((phase - FRAC_PI_2) / PI).ceil().max(0.0);
    let t_w0 = (FRAC_PI_2 + k * PI) / p.omega;
    let t_w1 = t_w0 + f64::from(opts.periods) * period;
    let multi = match fast::folds(p, (-1.0, 1.0)).as_slice() {
        [f1, f2] => Some((f1.a.min(f2.a), f1.a.max(f2.a))),
        _ => None,
    };
    let x_extent = curve_extent(p);
    let theta_on = opts.on_threshold * p.omega * x_extent;
    let theta_off = 0.5 * theta_on;

    let sys = Dimensionless::new(*p);
    let x0 = stable_equilibrium(p, 0.0);
    let mut solver = Dop853::new(&sys, 0.0, [x0, 0.0], opts.tol)?;
    let mut xs_hint = x0;
    let mut bursts: Vec<Burst> = Vec::new();
    let mut open: Option<Open> = None;
    let (mut peak_v, mut peak_d, mut max_track) = (0.0f64, 0.0f64, 0.0f64);
    let deviation = |t: f64, y: &[f64; 2], xs: f64| {
        let v_qs = p.omega * p.delta / p.g_prime(xs) * (p.omega * t).cos();
        y[1] - v_qs
    };
    let mut prev_acc = solver.dy()[1];
    // Burst detection starts one quiet gap before the window so a burst that began just
    // before the window start is seen whole (and not counted: its onset is outside).
    let t_detect = (t_w0 - 2.0 * opts.quiet_gap).max(0.0);
    while solver.t() < t_w1 {
        solver.step(t_w1)?;
        let t = solver.t();
        let y = *solver.y();
        let acc = solver.dy()[1];
        if t < t_detect {
            prev_acc = acc;
            continue;
        }
        let a = (p.omega * t).sin();
        let xs = nearest_stable(p, a, y[0], multi, xs_hint);
        xs_hint = xs;
        let d = deviation(t, &y, xs);
        let in_window = t >= t_w0;
        if in_window {
            peak_v = peak_v.max(y[1].abs());
            peak_d = peak_d.max(d.abs());
            max_track = max_track.max((y[0] - xs).abs());
        }
        // extrema of x' inside this step (sign change of x''), located on the dense output
        if (acc > 0.0) != (prev_acc > 0.0) {
            let dense = solver.dense();
            let (mut lo, mut hi) = (dense.t_start(), dense.t_end());
            let f = |tt: f64| sys.rhs(tt, &dense.eval(tt))[1];
            let flo = f(lo);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if (f(mid) > 0.0) == (flo > 0.0) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let te = 0.5 * (lo + hi);
            let ye = dense.eval(te);
            let xe = nearest_stable(p, (p.omega * te).sin(), ye[0], multi, xs);
            let de = deviation(te, &ye, xe).abs();
            if te >= t_w0 {
                peak_v = peak_v.max(ye[1].abs());
            }
            if let Some(o) = open.as_mut() {
                o.extrema.push(ye[1].abs());
                o.peak_v = o.peak_v.max(ye[1].abs());
                o.peak_d = o.peak_d.max(de);
            }
        }
        prev_acc = acc;
        match open.as_mut() {
            None => {
                if d.abs() > theta_on {
                    open = Some(Open {
                        onset: t,
                        a_onset: a,
                        last_active: t,
                        peak_v: y[1].abs(),
                        peak_d: d.abs(),
                        extrema: Vec::new(),
                    });
                }
            }
            Some(o) => {
                o.peak_v = o.peak_v.max(y[1].abs());
                o.peak_d = o.peak_d.max(d.abs());
                if d.abs() > theta_off {
                    o.last_active = t;
                } else if t - o.last_active > opts.quiet_gap {
                    bursts.push(close(open.take().expect("open"), true, opts));
                }
            }
        }
    }
    if let Some(o) = open.take() {
        bursts.push(close(o, false, opts));
    }
    bursts.retain(|b| b.onset >= t_w0 && b.onset < t_w1);

    let n_periods = f64::from(opts.periods);
    let window = t_w1 - t_w0;
    let complete: Vec<&Burst> = bursts.iter().filter(|b| b.complete).collect();
    let mean = |f: &dyn Fn(&Burst) -> f64, v: &[&Burst]| {
        if v.is_empty() {
            0.0
        } else {
            v.iter().map(|b| f(b)).sum::<f64>() / v.len() as f64
        }
    };
    let busy: f64 = bursts
        .iter()
        .map(|b| b.end.min(t_w1) - b.onset)
        .sum::<f64>();
    let quiescent_duration = if bursts.is_empty() {
        period
    } else {
        (window - busy) / bursts.len() as f64
    };
    Ok(Response {
        window_start: t_w0,
        window_end: t_w1,
        bursts_per_period: bursts.len() as f64 / n_periods,
        spikes_per_burst: mean(&|b| f64::from(b.spikes), &complete),
        burst_amplitude: mean(&|b| b.peak_abs_xdot, &complete),
        peak_abs_xdot: peak_v,
        peak_deviation: peak_d,
        quiescent_duration,
        quiescent_fraction: 1.0 - busy / window,
        max_tracking_error: max_track,
        on_threshold: theta_on,
        bursts,
    })
}

fn close(o: Open, complete: bool, opts: &BurstOptions) -> Burst {
    let cut = opts.spike_fraction * o.peak_v;
    Burst {
        onset: o.onset,
        end: o.last_active,
        a_onset: o.a_onset,
        duration: o.last_active - o.onset,
        peak_abs_xdot: o.peak_v,
        peak_deviation: o.peak_d,
        spikes: o.extrema.iter().filter(|&&d| d >= cut).count() as u32,
        complete,
    }
}

/// Mode and mechanism from a measured response and the fast-subsystem folds.
///
/// * mechanism: `none` without bursts; `fold-hysteresis` when a fold of the fast subsystem lies
///   in the traversed range a ∈ [−1, 1]; otherwise `sharp-quantitative-change` (one stable
///   equilibrium for every traversed a, yet bursts).
/// * mode without bursts: `transitional` when max|x − x*| > [`thresholds::TRANSITIONAL_LAG`]·X,
///   else `normal`. With bursts: `pronounced-bursting` when max|x − x*| >
///   [`thresholds::PRONOUNCED_LAG`]·X, else `fast-slow`.
pub fn classify(p: &Params, r: &Response) -> Classification {
    let x_extent = curve_extent(p);
    let folds_in_range = fast::folds(p, (-1.0, 1.0)).iter().any(|f| f.in_range);
    if r.bursts.is_empty() {
        let mode = if r.max_tracking_error > thresholds::TRANSITIONAL_LAG * x_extent {
            Mode::Transitional
        } else {
            Mode::Normal
        };
        return Classification {
            mode,
            mechanism: Mechanism::None,
        };
    }
    let mode = if r.max_tracking_error > thresholds::PRONOUNCED_LAG * x_extent {
        Mode::PronouncedBursting
    } else {
        Mode::FastSlow
    };
    Classification {
        mode,
        mechanism: if folds_in_range {
            Mechanism::FoldHysteresis
        } else {
            Mechanism::SharpQuantitativeChange
        },
    }
}
