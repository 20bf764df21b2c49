//! The periodic response itself: the orbit of period k·T (T = 2π/ω) found by shooting, its
//! monodromy matrix from the variational equations, its Floquet multipliers, and the largest
//! Lyapunov exponent by Benettin's method; continuation of the orbit in a parameter with its
//! folds and period doublings ([`continue_orbit`]), frequency-response curves
//! ([`frequency_response`], also a drive's in SI units), the stroboscopic orbit diagram and
//! Lyapunov maps ([`orbit_diagram`], [`lyapunov_point`]). Every model goes through one small
//! trait, [`Oscillator`], in the forcing phase s = ωτ.
//!
//! **Variational equations.** Along a solution (x, x'), a perturbation Φ obeys Φ' = J Φ with
//! J = [[0, 1], [−g'(x), −1]], g'(x) = 3αx² − 2x + γ (for the study's model). They are integrated
//! with the state and the parameter sensitivity w = ∂(x, x')/∂λ (an 8-dimensional system) by
//! Taylor's method ([`Oscillator::phase_taylor`]; DOP853 for an oscillator without Taylor
//! coefficients); the monodromy M = Φ(kT) is never formed directly, because
//! its entries shrink like e^{−τ/2} (e^{−314} over one slow period of the study): the span is cut
//! into pieces of at most [`PIECE`] time units, Φ restarts at I on each, and the product is kept
//! normalised with its logarithmic scale apart. The determinant is accumulated as Σ ln det of the
//! pieces (no cancellation even when one multiplier is e^{500} times the other), so the second
//! multiplier is det / the first — and Liouville's formula, det M = exp(∫ tr J) = e^{−kT}, is a
//! check of the integration, not an identity of the code.
//!
//! **Shooting.** Newton on P(y) = φ_{kT}(y) − y with P'(y) = M − I, from the state after
//! [`SETTLE_TIME`] from the default start; converged when |P(y)| ≤ [`NEWTON_TOL`]·(1+|y|).
//!
//! ```
//! use hdgear::{Params, periodic::{PeriodicOptions, shoot}};
//! let orbit = shoot(&Params::default(), 1, &PeriodicOptions::default()).unwrap();
//! assert!(orbit.stable && orbit.residual < 1e-10);
//! // Liouville: ln|m1| + ln|m2| = −kT
//! let sum = orbit.log_abs_multipliers[0] + orbit.log_abs_multipliers[1];
//! assert!((sum + orbit.period).abs() < 1e-8 * orbit.period);
//! ```

use crate::error::{Error, Result};
use crate::integrate::{Method, Options, Stepper, System, stepper};
use crate::params::Params;
use serde::Serialize;

mod continuation;
mod diagram;
mod oscillator;
mod response;
pub use continuation::*;
pub use diagram::*;
pub use oscillator::Oscillator;
pub use response::*;

/// Longest piece (dimensionless time) over which Φ is integrated from I: 10 decay times of the
/// fast subsystem (1/2 each), so Φ's entries stay within e^{±10}·(growth of the node direction).
pub const PIECE: f64 = 5.0;

/// Time (τ) simulated from the start before shooting, rounded up to whole forcing periods (at
/// least one): the study's transient decays like e^{−τ/2}, so after 60 time units it is e^{−30},
/// and Newton starts next to the orbit. (One period of the study's ω = 0.01 is 628.)
pub const SETTLE_TIME: f64 = 60.0;

/// Newton's stopping tolerance on the residual |φ(y) − y|, relative to 1 + |y|.
pub const NEWTON_TOL: f64 = 1e-11;

/// Options of the periodic-orbit computations.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PeriodicOptions {
    /// Integrator tolerances and method (Taylor by default, DOP853 for an oscillator without
    /// Taylor coefficients); by default 1e-12 at order 20, whose longer steps pay for the
    /// variational equations' extra work per step ([`Options::order`]).
    pub tol: Options,
    /// Newton iterations at most.
    pub max_newton: usize,
    /// Output spacing of the orbit's samples.
    pub dt: f64,
}

impl Default for PeriodicOptions {
    fn default() -> Self {
        PeriodicOptions {
            tol: Options {
                rtol: 1e-12,
                atol: 1e-12,
                order: Some(crate::integrate::taylor::MAX_ORDER),
                ..Options::default()
            },
            max_newton: 20,
            dt: 0.05,
        }
    }
}

/// The oscillator in phase time s = ωτ with its variational equations and the derivative with
/// respect to one parameter: [x, x', Φ11, Φ21, Φ12, Φ22, w1, w2], Φ by columns, w = ∂(x, x')/∂λ.
struct Phase<'a, O: Oscillator> {
    o: &'a O,
    param: Option<O::Param>,
    inv_omega: f64,
}

impl<O: Oscillator> System<8> for Phase<'_, O> {
    #[inline]
    fn rhs(&self, s: f64, y: &[f64; 8]) -> [f64; 8] {
        let (x, v, k) = (y[0], y[1], self.inv_omega);
        let a = self.o.accel(s, x, v);
        let [ax, av] = self.o.accel_gradient(s, x, v);
        let (d1, d2) = match self.param {
            None => (0.0, 0.0),
            Some(p) if O::is_frequency(p) => (-v * k * k, -a * k * k),
            Some(p) => (0.0, self.o.accel_derivative(p, s, x, v) * k),
        };
        [
            v * k,
            a * k,
            y[3] * k,
            (ax * y[2] + av * y[3]) * k,
            y[5] * k,
            (ax * y[4] + av * y[5]) * k,
            y[7] * k + d1,
            (ax * y[6] + av * y[7]) * k + d2,
        ]
    }
    fn taylor(&self, s: f64, y: &[f64; 8], order: usize, c: &mut [[f64; 8]]) -> bool {
        self.o.phase_taylor(self.param, s, y, order, c)
    }
}

/// `tol` with Taylor's method replaced by DOP853 where the oscillator gives no Taylor
/// coefficients ([`Oscillator::TAYLOR`]).
pub(crate) fn method_for<O: Oscillator>(tol: Options) -> Options {
    if tol.method == Method::Taylor && !O::TAYLOR {
        Options {
            method: Method::Dop853,
            ..tol
        }
    } else {
        tol
    }
}

/// The flow over a span with its monodromy: Φ = `m`·e^{`log_scale`}, ln|det Φ| = `log_det`, and
/// w = ∂y/∂λ for the parameter asked for (0 otherwise).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Flow {
    pub(crate) y: [f64; 2],
    pub(crate) m: [[f64; 2]; 2],
    pub(crate) log_scale: f64,
    pub(crate) log_det: f64,
    pub(crate) det_sign: f64,
    pub(crate) w: [f64; 2],
}

impl Flow {
    /// M − I, or None when M's scale overflows.
    pub(crate) fn m_minus_i(&self) -> Option<[[f64; 2]; 2]> {
        let s = self.log_scale.exp();
        let a = [
            [self.m[0][0] * s - 1.0, self.m[0][1] * s],
            [self.m[1][0] * s, self.m[1][1] * s - 1.0],
        ];
        a.iter().flatten().all(|v| v.is_finite()).then_some(a)
    }
}

fn mul(a: [[f64; 2]; 2], b: [[f64; 2]; 2]) -> [[f64; 2]; 2] {
    [
        [
            a[0][0] * b[0][0] + a[0][1] * b[1][0],
            a[0][0] * b[0][1] + a[0][1] * b[1][1],
        ],
        [
            a[1][0] * b[0][0] + a[1][1] * b[1][0],
            a[1][0] * b[0][1] + a[1][1] * b[1][1],
        ],
    ]
}

/// Integrates state, Φ and w from phase `s0` and state `y0` over `span` (in phase), piece by
/// piece (each piece at most [`PIECE`] units of τ).
pub(crate) fn flow<O: Oscillator>(
    o: &O,
    param: Option<O::Param>,
    s0: f64,
    y0: [f64; 2],
    span: f64,
    tol: Options,
) -> Result<Flow> {
    let omega = o.omega();
    let sys = Phase {
        o,
        param,
        inv_omega: 1.0 / omega,
    };
    let pieces = (span / (PIECE * omega)).ceil().max(1.0) as usize;
    let mut out = Flow {
        y: y0,
        m: [[1.0, 0.0], [0.0, 1.0]],
        log_scale: 0.0,
        log_det: 0.0,
        det_sign: 1.0,
        w: [0.0; 2],
    };
    // the error control acts on x, x' and the variations alike; atol is meant in τ-units of
    // x' and stays as given
    for k in 0..pieces {
        let (a, b) = (
            s0 + span * k as f64 / pieces as f64,
            s0 + span * (k + 1) as f64 / pieces as f64,
        );
        let start = [out.y[0], out.y[1], 1.0, 0.0, 0.0, 1.0, 0.0, 0.0];
        let mut s = stepper(&sys, a, start, method_for::<O>(tol))?;
        while s.t() < b {
            s.step(b)?;
        }
        let z = *s.y();
        let piece = [[z[2], z[4]], [z[3], z[5]]];
        let det = piece[0][0] * piece[1][1] - piece[0][1] * piece[1][0];
        out.log_det += det.abs().ln();
        out.det_sign *= det.signum();
        out.y = [z[0], z[1]];
        // w_total = Φ_piece w_total + w_piece
        out.w = [
            piece[0][0] * out.w[0] + piece[0][1] * out.w[1] + z[6],
            piece[1][0] * out.w[0] + piece[1][1] * out.w[1] + z[7],
        ];
        out.m = mul(piece, out.m);
        let norm = out.m.iter().flatten().fold(0.0f64, |n, v| n.max(v.abs()));
        if norm > 0.0 && norm.is_finite() {
            out.m.iter_mut().flatten().for_each(|v| *v /= norm);
            out.log_scale += norm.ln();
        }
    }
    Ok(out)
}

/// A Floquet multiplier, possibly complex.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Multiplier {
    /// ln |m| (the multiplier itself may underflow: e^{−314} at the study's point).
    pub log_abs: f64,
    /// arg m (0 or π for a real multiplier).
    pub arg: f64,
}

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

/// Multipliers from the normalised monodromy and the accumulated determinant.
fn multipliers(f: &Flow) -> [Multiplier; 2] {
    let m = f.m;
    let tr = m[0][0] + m[1][1];
    let det_scaled = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let disc = tr * tr - 4.0 * det_scaled;
    // ln|det M| from the pieces, not from the (possibly rank-deficient) normalised product
    let log_det = f.log_det;
    if disc < 0.0 {
        // a complex pair: |m|² = det M
        let arg = (-disc).sqrt().atan2(tr).abs();
        let half = 0.5 * log_det;
        return [
            Multiplier { log_abs: half, arg },
            Multiplier {
                log_abs: half,
                arg: -arg,
            },
        ];
    }
    // the larger real root, stably: tr/2 + sign(tr)·√disc/2
    let big = 0.5 * (tr + tr.signum() * disc.sqrt());
    let log1 = big.abs().ln() + f.log_scale;
    let sign2 = f.det_sign * big.signum();
    [
        Multiplier {
            log_abs: log1,
            arg: if big < 0.0 { std::f64::consts::PI } else { 0.0 },
        },
        Multiplier {
            log_abs: log_det - log1,
            arg: if sign2 < 0.0 {
                std::f64::consts::PI
            } else {
                0.0
            },
        },
    ]
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
struct Plain<'a, O: Oscillator>(&'a O, f64);

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
fn bisect(mut a: f64, mut b: f64, f: impl Fn(f64) -> f64) -> f64 {
    let fa = f(a) > 0.0;
    for _ in 0..60 {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        if (f(m) > 0.0) == fa {
            a = m;
        } else {
            b = m;
        }
    }
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

/// The largest Lyapunov exponent (per unit τ) by Benettin's method: one tangent vector
/// integrated with the state from phase 0 and `y0`, renormalised every [`PIECE`] time units and
/// at `discard`; the first `discard` time units align the vector and are not counted; the
/// average growth rate over the next `span`. [`lyapunov_many`] computes the same for many
/// parameter sets of the dimensionless model at once.
pub fn lyapunov<O: Oscillator>(
    o: &O,
    y0: [f64; 2],
    discard: f64,
    span: f64,
    tol: Options,
) -> Result<f64> {
    o.check()?;
    crate::integrate::check_budget(discard + span, &tol)?;
    let omega = o.omega();
    let sys = Phase {
        o,
        param: None,
        inv_omega: 1.0 / omega,
    };
    let mut z = [y0[0], y0[1], 1.0, 1.0, 0.0, 0.0, 0.0, 0.0];
    let (mut t, mut sum) = (0.0, 0.0);
    let end = discard + span;
    while t < end {
        // pieces end at `discard`, so the growth counted is exactly that over the span
        let b = (t + PIECE).min(if t < discard { discard } else { end });
        let mut s = stepper(&sys, t * omega, z, method_for::<O>(tol))?;
        while s.t() < b * omega {
            s.step(b * omega)?;
        }
        z = *s.y();
        let n = z[2].hypot(z[3]);
        if t >= discard {
            sum += n.ln();
        }
        z[2] /= n;
        z[3] /= n;
        t = b;
    }
    Ok(sum / span)
}

/// [`lyapunov`] for many parameter sets of the dimensionless model at once, [`LANES`] at a time
/// through the batch integrator ([`crate::batch::integrate_batch_tangent`]): point i starts from
/// `starts[i]` at phase 0 with the tangent (1, 1), aligns it over `spans[i].0` and returns the
/// average growth rate over the next `spans[i].1` (or the error that stopped that point). The
/// same exponent as [`lyapunov`] with Taylor's method up to the integration's error (the batch
/// chooses its steps from the state alone, and carries sin ωt as state). Fails as a whole only on
/// bad input.
///
/// [`LANES`]: crate::batch::LANES
///
/// ```
/// use hdgear::{Params, periodic::lyapunov_many, integrate::Options};
/// let p = Params { gamma: 10.0, omega: 6.0, delta: 8.0, ..Params::default() };
/// let period = std::f64::consts::TAU / p.omega;
/// let l = lyapunov_many(&[p], &[[0.0, 0.0]], &[(100.0 * period, 100.0 * period)], Options::default())
///     .unwrap();
/// // a periodic response of a focus type: both exponents −1/2 (Liouville: they sum to −1)
/// assert!((l[0].as_ref().unwrap() + 0.5).abs() < 0.01);
/// ```
pub fn lyapunov_many(
    points: &[Params],
    starts: &[[f64; 2]],
    spans: &[(f64, f64)],
    tol: Options,
) -> Result<Vec<Result<f64>>> {
    use crate::batch::integrate_batch_tangent;
    if spans.len() != points.len() {
        return Err(Error::InvalidInput {
            what: "Lyapunov spans",
            text: format!("{} spans for {} parameter sets", spans.len(), points.len()),
            reason: "one (discard, span) pair per parameter set".into(),
        });
    }
    if let Some(&(discard, span)) = spans.iter().find(|s| !(s.0 >= 0.0 && s.1 > 0.0)) {
        return Err(Error::InvalidOption {
            name: "span",
            value: if discard >= 0.0 { span } else { discard },
            reason: "the alignment must be ≥ 0 and the span > 0",
        });
    }
    let starts_4: Vec<[f64; 4]> = starts.iter().map(|y| [y[0], y[1], 1.0, 1.0]).collect();
    let align: Vec<(f64, f64)> = spans.iter().map(|&(d, _)| (0.0, d)).collect();
    let aligned = integrate_batch_tangent(points, &starts_4, &align, tol)?;
    // a point that failed to align goes on from its start (its error is kept below)
    let next: Vec<[f64; 4]> = aligned
        .iter()
        .zip(&starts_4)
        .map(|(r, s)| match r {
            Ok(r) => [r.y[0], r.y[1], r.tangent[0], r.tangent[1]],
            Err(_) => *s,
        })
        .collect();
    let measure: Vec<(f64, f64)> = spans.iter().map(|&(d, s)| (d, d + s)).collect();
    let measured = integrate_batch_tangent(points, &next, &measure, tol)?;
    Ok(aligned
        .into_iter()
        .zip(measured)
        .zip(spans)
        .map(|((a, m), &(_, span))| {
            a?;
            Ok(m?.ln_growth / span)
        })
        .collect())
}
