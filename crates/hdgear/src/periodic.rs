//! The periodic response itself: the orbit of period k·T (T = 2π/ω) found by shooting, its
//! monodromy matrix from the variational equations, its Floquet multipliers, and the largest
//! Lyapunov exponent by Benettin's method.
//!
//! **Variational equations.** Along a solution (x, x'), a perturbation Φ obeys Φ' = J Φ with
//! J = [[0, 1], [−g'(x), −1]], g'(x) = 3αx² − 2x + γ. They are integrated with the state
//! (a 6-dimensional system) by DOP853; the monodromy M = Φ(kT) is never formed directly, because
//! its entries shrink like e^{−τ/2} (e^{−314} over one slow period of the study): the span is cut
//! into pieces of at most [`PIECE`] time units, Φ restarts at I on each, and the product is kept
//! normalised with its logarithmic scale apart. The determinant is accumulated as Σ ln det of the
//! pieces (no cancellation even when one multiplier is e^{500} times the other), so the second
//! multiplier is det / the first — and Liouville's formula, det M = exp(∫ tr J) = e^{−kT}, is a
//! check of the integration, not an identity of the code.
//!
//! **Shooting.** Newton on P(y) = φ_{kT}(y) − y with P'(y) = M − I, from the state after
//! [`SETTLE_PERIODS`] periods of the default start; converged when |P(y)| ≤ [`NEWTON_TOL`]·(1+|y|).
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
use crate::model::Dimensionless;
use crate::params::Params;
use serde::Serialize;

/// Longest piece (dimensionless time) over which Φ is integrated from I: 10 decay times of the
/// fast subsystem (1/2 each), so Φ's entries stay within e^{±10}·(growth of the node direction).
pub const PIECE: f64 = 5.0;

/// Slow periods simulated from the default start before shooting: the transient decays like
/// e^{−τ/2}, so after one period of the study (τ = 628) it is e^{−314} — gone.
pub const SETTLE_PERIODS: f64 = 1.0;

/// Newton's stopping tolerance on the residual |φ(y) − y|, relative to 1 + |y|.
pub const NEWTON_TOL: f64 = 1e-11;

/// Options of the periodic-orbit computations.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PeriodicOptions {
    /// Integrator tolerances (DOP853 is used for the 6-dimensional variational system).
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
                method: Method::Dop853,
                ..Options::default()
            },
            max_newton: 20,
            dt: 0.05,
        }
    }
}

/// The model with its variational equations: [x, x', Φ11, Φ21, Φ12, Φ22] (Φ by columns).
struct Variational {
    model: Dimensionless,
    p: Params,
}

impl System<6> for Variational {
    fn rhs(&self, t: f64, y: &[f64; 6]) -> [f64; 6] {
        let f = self.model.rhs(t, &[y[0], y[1]]);
        let x = y[0];
        let gp = 3.0 * self.p.alpha * x * x - 2.0 * x + self.p.gamma;
        [f[0], f[1], y[3], -gp * y[2] - y[3], y[5], -gp * y[4] - y[5]]
    }
}

/// The flow over a span with its monodromy: Φ = `m`·e^{`log_scale`}, ln|det Φ| = `log_det`.
#[derive(Clone, Copy, Debug)]
struct Flow {
    y: [f64; 2],
    m: [[f64; 2]; 2],
    log_scale: f64,
    log_det: f64,
    det_sign: f64,
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

/// Integrates state and Φ from (t0, y0) over `span`, piece by piece; `on_step` sees each
/// accepted step's end (t, x, x').
fn flow(p: &Params, t0: f64, y0: [f64; 2], span: f64, tol: Options) -> Result<Flow> {
    let sys = Variational {
        model: Dimensionless::new(*p),
        p: *p,
    };
    let pieces = (span / PIECE).ceil().max(1.0) as usize;
    let mut out = Flow {
        y: y0,
        m: [[1.0, 0.0], [0.0, 1.0]],
        log_scale: 0.0,
        log_det: 0.0,
        det_sign: 1.0,
    };
    for k in 0..pieces {
        let (a, b) = (
            t0 + span * k as f64 / pieces as f64,
            t0 + span * (k + 1) as f64 / pieces as f64,
        );
        let start = [out.y[0], out.y[1], 1.0, 0.0, 0.0, 1.0];
        let mut s = stepper(&sys, a, start, tol)?;
        while s.t() < b {
            s.step(b)?;
        }
        let z = *s.y();
        let piece = [[z[2], z[4]], [z[3], z[5]]];
        let det = piece[0][0] * piece[1][1] - piece[0][1] * piece[1][0];
        out.log_det += det.abs().ln();
        out.det_sign *= det.signum();
        out.y = [z[0], z[1]];
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
    /// max |x'| over the orbit (at the samples).
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
    crate::integrate::check_budget(period * (SETTLE_PERIODS + 2.0), &opts.tol)?;
    let y0 = crate::simulate::initial_state(p, crate::simulate::Start::Equilibrium);
    // settle over whole forcing periods, so the phase stays τ ≡ 0
    let mut y = flow(p, 0.0, y0, SETTLE_PERIODS.ceil() * t_forcing, opts.tol)?.y;
    let mut iterations = 0;
    let mut f = flow(p, 0.0, y, period, opts.tol)?;
    loop {
        let r = [f.y[0] - y[0], f.y[1] - y[1]];
        let residual = r[0].hypot(r[1]);
        if residual <= NEWTON_TOL * (1.0 + y[0].hypot(y[1])) {
            return orbit(p, k, period, y, residual, iterations, &f, opts);
        }
        if iterations == opts.max_newton {
            return Err(Error::NoConvergence {
                what: "periodic orbit (Newton on the stroboscopic map)",
                iterations,
                residual,
            });
        }
        // (M − I) Δ = −r with M = m·e^{log_scale}
        let s = f.log_scale.exp();
        let a = [
            [f.m[0][0] * s - 1.0, f.m[0][1] * s],
            [f.m[1][0] * s, f.m[1][1] * s - 1.0],
        ];
        let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
        if det == 0.0 || !det.is_finite() {
            return Err(Error::NoConvergence {
                what: "periodic orbit (a multiplier is 1: a fold of cycles)",
                iterations,
                residual,
            });
        }
        y = [
            y[0] + (-r[0] * a[1][1] + r[1] * a[0][1]) / det,
            y[1] + (-r[1] * a[0][0] + r[0] * a[1][0]) / det,
        ];
        iterations += 1;
        f = flow(p, 0.0, y, period, opts.tol)?;
    }
}

/// Assembles the orbit: multipliers, samples, amplitudes.
#[allow(clippy::too_many_arguments)]
fn orbit(
    p: &Params,
    k: u32,
    period: f64,
    y: [f64; 2],
    residual: f64,
    newton_iterations: usize,
    f: &Flow,
    opts: &PeriodicOptions,
) -> Result<PeriodicOrbit> {
    let multipliers = multipliers(f);
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
    let (lo, hi) = samples
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), s| {
            (l.min(s[1]), h.max(s[1]))
        });
    let max_abs_xdot = samples.iter().fold(0.0f64, |m, s| m.max(s[2].abs()));
    let t_forcing = period / f64::from(k);
    let mut minimal_subharmonic = k;
    for j in (1..k).filter(|j| k.is_multiple_of(*j)) {
        let z = flow(p, 0.0, y, f64::from(j) * t_forcing, opts.tol)?.y;
        if (z[0] - y[0]).hypot(z[1] - y[1]) <= 1e-8 * (1.0 + y[0].hypot(y[1])) {
            minimal_subharmonic = j;
            break;
        }
    }
    Ok(PeriodicOrbit {
        params: *p,
        subharmonic: k,
        period,
        start: y,
        residual,
        newton_iterations,
        multipliers,
        log_abs_multipliers: log_abs,
        floquet_exponents: log_abs.map(|l| l / period),
        stable: log_abs.iter().all(|&l| l < 0.0),
        minimal_subharmonic,
        max_abs_xdot,
        x_range: [lo, hi],
        peak_to_peak: hi - lo,
        samples,
    })
}

/// The largest Lyapunov exponent by Benettin's method: one tangent vector integrated with the
/// state from (0, y0), renormalised every [`PIECE`] time units; the first `discard` time units
/// align the vector and are not counted; the average growth rate over the next `span`.
pub fn lyapunov(p: &Params, y0: [f64; 2], discard: f64, span: f64, tol: Options) -> Result<f64> {
    p.validate()?;
    crate::integrate::check_budget(discard + span, &tol)?;
    let sys = Variational {
        model: Dimensionless::new(*p),
        p: *p,
    };
    let mut z = [y0[0], y0[1], 1.0, 1.0, 0.0, 0.0];
    let (mut t, mut sum) = (0.0, 0.0);
    let end = discard + span;
    while t < end {
        let b = (t + PIECE).min(end);
        let mut s = stepper(&sys, t, z, tol)?;
        while s.t() < b {
            s.step(b)?;
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
