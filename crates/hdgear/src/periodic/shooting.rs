//! The periodic orbit by shooting: Newton on the stroboscopic map, its amplitudes, whether it
//! bursts, and its least period.

use super::*;

/// A periodic orbit of the forced model.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PeriodicOrbit {
    /// The parameters.
    pub params: Params,
    /// k: the orbit's period is k·2π/ω.
    pub subharmonic: u32,
    /// Its period k·2π/ω.
    pub period: f64,
    /// (x, x') at τ = 0 (the phase where a = sin ωτ = 0, rising).
    pub start: [f64; 2],
    /// |φ(y) − y| at the solution.
    pub residual: f64,
    /// Newton iterations taken.
    pub newton_iterations: usize,
    /// The two Floquet multipliers, the larger first.
    pub multipliers: [Multiplier; 2],
    /// ln|m1|, ln|m2|.
    pub log_abs_multipliers: [f64; 2],
    /// Floquet exponents ln|m|/period.
    pub floquet_exponents: [f64; 2],
    /// Both multipliers inside the unit circle.
    pub stable: bool,
    /// The smallest j dividing k with φ_{j·2π/ω}(start) = start (to 1e-8): 1 when the orbit
    /// asked for as a subharmonic is the period-1 orbit.
    pub minimal_subharmonic: u32,
    /// max |x'| over the orbit (located on the dense output, see [`Amplitude`]).
    pub max_abs_xdot: f64,
    /// Smallest and largest x.
    pub x_range: [f64; 2],
    /// Peak-to-peak amplitude of x.
    pub peak_to_peak: f64,
    /// (τ, x, x') every `dt` over one period.
    #[serde(skip)]
    pub samples: Vec<[f64; 3]>,
}

/// A converged shooting solution: the start at phase 0 and the flow over k periods from it.
pub(crate) struct Solved {
    pub(crate) y: [f64; 2],
    pub(crate) flow: Flow,
    pub(crate) iterations: usize,
    pub(crate) residual: f64,
}

/// Whether |r| is within Newton's tolerance at y.
pub(crate) fn converged(r: [f64; 2], y: [f64; 2]) -> bool {
    r[0].hypot(r[1]) <= NEWTON_TOL * (1.0 + y[0].hypot(y[1]))
}

/// Newton on P(y) = φ_{2πk}(y) − y (phase time) from `y`.
pub(crate) fn newton<O: Oscillator>(
    o: &O,
    k: u32,
    mut y: [f64; 2],
    opts: &PeriodicOptions,
) -> Result<Solved> {
    let span = std::f64::consts::TAU * f64::from(k);
    let mut iterations = 0;
    loop {
        let f = flow(o, None, 0.0, y, span, opts.tol)?;
        let r = [f.y[0] - y[0], f.y[1] - y[1]];
        let residual = r[0].hypot(r[1]);
        if converged(r, y) {
            return Ok(Solved {
                y,
                flow: f,
                iterations,
                residual,
            });
        }
        if iterations == opts.max_newton || !residual.is_finite() {
            return Err(Error::NoConvergence {
                what: "periodic orbit (Newton on the stroboscopic map)",
                iterations,
                residual,
            });
        }
        let singular = || Error::NoConvergence {
            what: "periodic orbit (a multiplier is 1: a fold of cycles)",
            iterations,
            residual,
        };
        // (M − I) Δ = −r
        let a = f.m_minus_i().ok_or_else(singular)?;
        let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
        if det == 0.0 || !det.is_finite() {
            return Err(singular());
        }
        y = [
            y[0] + (-r[0] * a[1][1] + r[1] * a[0][1]) / det,
            y[1] + (-r[1] * a[0][0] + r[0] * a[1][0]) / det,
        ];
        iterations += 1;
    }
}

/// Extent of a periodic response: extremes of x (at the zeros of x') and the largest |x'| (at a
/// zero of x'' or an end), each located on the integrator's dense output to 1e-12 in phase.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Amplitude {
    /// Smallest x.
    pub x_min: f64,
    /// Largest x.
    pub x_max: f64,
    /// x_max − x_min.
    pub peak_to_peak: f64,
    /// Largest |x'|.
    pub max_abs_xdot: f64,
}

/// The oscillator alone in phase time (for the amplitudes).
pub(crate) struct Plain<'a, O: Oscillator>(pub(crate) &'a O, pub(crate) f64);

impl<O: Oscillator> System<2> for Plain<'_, O> {
    #[inline]
    fn rhs(&self, s: f64, y: &[f64; 2]) -> [f64; 2] {
        [y[1] * self.1, self.0.accel(s, y[0], y[1]) * self.1]
    }
    fn taylor(&self, s: f64, y: &[f64; 2], order: usize, c: &mut [[f64; 2]]) -> bool {
        self.0.phase_taylor(None, s, y, order, c)
    }
}

/// Sub-intervals of each step searched for sign changes of x' and x''.
const EXTREMUM_PROBES: usize = 6;

/// The [`Amplitude`] of the response through `y0` at phase 0 over `k` forcing periods.
pub fn amplitude<O: Oscillator>(o: &O, y0: [f64; 2], k: u32, tol: Options) -> Result<Amplitude> {
    use crate::integrate::DenseOutput;
    let sys = Plain(o, 1.0 / o.omega());
    let end = std::f64::consts::TAU * f64::from(k);
    let mut s = stepper(&sys, 0.0, y0, method_for::<O>(tol))?;
    let (mut lo, mut hi, mut vmax) = (y0[0], y0[0], y0[1].abs());
    let acc = |t: f64, y: [f64; 2]| o.accel(t, y[0], y[1]);
    while s.t() < end {
        s.step(end)?;
        let d = s.dense();
        let (t0, t1) = (d.t_start(), d.t_end());
        let mut prev_t = t0;
        let mut prev = d.eval(t0);
        for j in 1..=EXTREMUM_PROBES {
            let t = t0 + (t1 - t0) * j as f64 / EXTREMUM_PROBES as f64;
            let y = d.eval(t);
            lo = lo.min(y[0]);
            hi = hi.max(y[0]);
            vmax = vmax.max(y[1].abs());
            if (prev[1] > 0.0) != (y[1] > 0.0) {
                let z = d.eval(bisect(prev_t, t, |u| d.eval(u)[1]));
                lo = lo.min(z[0]);
                hi = hi.max(z[0]);
            }
            if (acc(prev_t, prev) > 0.0) != (acc(t, y) > 0.0) {
                let z = d.eval(bisect(prev_t, t, |u| acc(u, d.eval(u))));
                vmax = vmax.max(z[1].abs());
            }
            prev_t = t;
            prev = y;
        }
    }
    Ok(Amplitude {
        x_min: lo,
        x_max: hi,
        peak_to_peak: hi - lo,
        max_abs_xdot: vmax,
    })
}

/// A sign change of `f` on [a, b], by bisection to the resolution of f64.
fn bisect(a: f64, b: f64, f: impl Fn(f64) -> f64) -> f64 {
    let fa = f(a) > 0.0;
    let (a, b) = crate::roots::bisect(a, b, 60, crate::roots::at_resolution, |m| {
        (f(m) > 0.0) == fa
    });
    0.5 * (a + b)
}

/// Finds the periodic orbit of period k·2π/ω by shooting from the settled default start.
pub fn shoot(p: &Params, k: u32, opts: &PeriodicOptions) -> Result<PeriodicOrbit> {
    p.validate()?;
    if k == 0 {
        return Err(Error::InvalidOption {
            name: "subharmonic",
            value: 0.0,
            reason: "must be ≥ 1",
        });
    }
    let t_forcing = p.slow_period();
    let period = f64::from(k) * t_forcing;
    crate::integrate::check_budget(t_forcing * settle_periods(p) + 2.0 * period, &opts.tol)?;
    let y0 = crate::simulate::initial_state(p, crate::simulate::Start::Equilibrium);
    let solved = settle_and_solve(p, k, y0, opts)?;
    orbit(p, k, period, &solved, opts)
}

/// Whole forcing periods covering [`SETTLE_TIME`] (at least one).
fn settle_periods<O: Oscillator>(o: &O) -> f64 {
    (SETTLE_TIME * o.omega() / std::f64::consts::TAU)
        .ceil()
        .max(1.0)
}

/// Settles from `y0` for [`SETTLE_TIME`] (whole periods, so the phase stays 0) and shoots;
/// if Newton does not converge from there (a weakly damped oscillator, a slow transient), settles
/// ten times longer and shoots once more.
pub(crate) fn settle_and_solve<O: Oscillator>(
    o: &O,
    k: u32,
    y0: [f64; 2],
    opts: &PeriodicOptions,
) -> Result<Solved> {
    let span = std::f64::consts::TAU * settle_periods(o);
    let y = flow(o, None, 0.0, y0, span, opts.tol)?.y;
    match newton(o, k, y, opts) {
        Err(Error::NoConvergence { .. }) => {
            crate::integrate::check_budget(10.0 * span / o.omega(), &opts.tol)?;
            let y = flow(o, None, 0.0, y, 10.0 * span, opts.tol)?.y;
            newton(o, k, y, opts)
        }
        other => other,
    }
}

/// Assembles the orbit: multipliers, samples, amplitudes.
fn orbit(
    p: &Params,
    k: u32,
    period: f64,
    solved: &Solved,
    opts: &PeriodicOptions,
) -> Result<PeriodicOrbit> {
    let y = solved.y;
    let multipliers = multipliers(&solved.flow);
    let log_abs = [multipliers[0].log_abs, multipliers[1].log_abs];
    let sim = crate::simulate::SimOptions {
        t_end: period,
        dt: opts.dt,
        start: crate::simulate::Start::Given { x0: y[0], v0: y[1] },
        tol: Options {
            method: Method::Taylor,
            ..opts.tol
        },
    };
    let mut samples = Vec::new();
    crate::simulate::simulate(p, &sim, |t, s| samples.push([t, s[0], s[1]]))?;
    let amp = amplitude(p, y, k, opts.tol)?;
    Ok(PeriodicOrbit {
        params: *p,
        subharmonic: k,
        period,
        start: y,
        residual: solved.residual,
        newton_iterations: solved.iterations,
        multipliers,
        log_abs_multipliers: log_abs,
        floquet_exponents: log_abs.map(|l| l / period),
        stable: log_abs.iter().all(|&l| l < 0.0),
        minimal_subharmonic: minimal_subharmonic(p, y, k, opts.tol)?,
        max_abs_xdot: amp.max_abs_xdot,
        x_range: [amp.x_min, amp.x_max],
        peak_to_peak: amp.peak_to_peak,
        samples,
    })
}

/// The burst verdict on the periodic orbit itself: the response from the orbit's start at τ = 0
/// measured with `opts` but no transient discarded (the orbit has none), over
/// max(`opts.periods`, k) slow periods.
///
/// ```
/// use hdgear::{Params, burst::{BurstOptions, Verdict}, periodic::{PeriodicOptions, burst_verdict, shoot}};
/// let p = Params::default(); // γ = 0.1: overshoot bursts
/// let orbit = shoot(&p, 1, &PeriodicOptions::default()).unwrap();
/// let c = burst_verdict(&orbit, &BurstOptions::default()).unwrap();
/// assert_eq!(c.verdict, Verdict::Overshoot);
/// ```
pub fn burst_verdict(
    orbit: &PeriodicOrbit,
    opts: &crate::burst::BurstOptions,
) -> Result<crate::burst::Classification> {
    let opts = crate::burst::BurstOptions {
        discard_periods: 0.0,
        periods: opts.periods.max(orbit.subharmonic),
        ..*opts
    };
    let r = crate::burst::response_from(&orbit.params, &opts, orbit.start)?;
    Ok(crate::burst::classify(&orbit.params, &r))
}

/// The smallest j dividing k with φ_{2πj}(y) = y to 1e-8 (relative to 1 + |y|).
pub(crate) fn minimal_subharmonic<O: Oscillator>(
    o: &O,
    y: [f64; 2],
    k: u32,
    tol: Options,
) -> Result<u32> {
    for j in (1..k).filter(|j| k.is_multiple_of(*j)) {
        let z = flow(o, None, 0.0, y, std::f64::consts::TAU * f64::from(j), tol)?.y;
        if (z[0] - y[0]).hypot(z[1] - y[1]) <= 1e-8 * (1.0 + y[0].hypot(y[1])) {
            return Ok(j);
        }
    }
    Ok(k)
}
