//! The flow over a span with its monodromy kept normalised in pieces, and the Floquet multipliers
//! from it.

use super::*;

/// The flow over a span with its monodromy: Φ = `m`·e^{`log_scale`}, ln|det Φ| = `log_det`, and
/// w = ∂y/∂λ for the parameter asked for (0 otherwise). What the shooting, the Floquet
/// multipliers and continuation read; built inside the crate only.
#[derive(Clone, Copy, Debug)]
pub struct Flow {
    pub(crate) y: [f64; 2],
    pub(crate) m: [[f64; 2]; 2],
    pub(crate) log_scale: f64,
    pub(crate) log_det: f64,
    pub(crate) det_sign: f64,
    pub(crate) w: [f64; 2],
}

impl Flow {
    /// The flow over an empty span at `y`: Φ = I, w = 0.
    pub(crate) fn start(y: [f64; 2]) -> Flow {
        Flow {
            y,
            m: [[1.0, 0.0], [0.0, 1.0]],
            log_scale: 0.0,
            log_det: 0.0,
            det_sign: 1.0,
            w: [0.0; 2],
        }
    }

    /// A linear piece: Φ = `a` (its determinant accumulated as ln|det a|, −∞ for a singular
    /// one), w = `w`, ending at `y`.
    pub(crate) fn linear(a: [[f64; 2]; 2], w: [f64; 2], y: [f64; 2]) -> Flow {
        let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
        Flow {
            y,
            m: a,
            log_scale: 0.0,
            log_det: det.abs().ln(),
            det_sign: det.signum(),
            w,
        }
    }

    /// This flow followed by `next`: Φ = Φ_next·Φ (kept normalised, its scale apart),
    /// w = Φ_next·w + w_next, the end at `next`'s.
    pub(crate) fn then(&mut self, next: &Flow) {
        let s = next.log_scale.exp();
        let n = next.m;
        self.w = [
            (n[0][0] * self.w[0] + n[0][1] * self.w[1]) * s + next.w[0],
            (n[1][0] * self.w[0] + n[1][1] * self.w[1]) * s + next.w[1],
        ];
        self.m = mul(n, self.m);
        self.log_scale += next.log_scale;
        self.log_det += next.log_det;
        self.det_sign *= next.det_sign;
        self.y = next.y;
        let norm = self.m.iter().flatten().fold(0.0f64, |n, v| n.max(v.abs()));
        if norm > 0.0 && norm.is_finite() {
            self.m.iter_mut().flatten().for_each(|v| *v /= norm);
            self.log_scale += norm.ln();
        }
    }

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

/// Integrates state, Φ and w from phase `s0` and state `y0` over `span` (in phase): piece by
/// piece for a smooth oscillator ([`smooth_flow`]), switch by switch with the saltation matrices
/// for one whose friction sticks ([`Oscillator::switching_flow`]).
pub(crate) fn flow<O: Oscillator>(
    o: &O,
    param: Option<O::Param>,
    s0: f64,
    y0: [f64; 2],
    span: f64,
    tol: Options,
) -> Result<Flow> {
    match o.switching_flow(param, s0, y0, span, tol) {
        Some(f) => f,
        None => smooth_flow(o, param, y0, (s0, span), tol),
    }
}

/// [`flow`] of a smooth oscillator from `y0` over the phases (s0, s0 + span): the variational
/// equations integrated with the state, piece by piece (each piece at most [`PIECE`] units of τ).
pub(crate) fn smooth_flow<O: Oscillator>(
    o: &O,
    param: Option<O::Param>,
    y0: [f64; 2],
    (s0, span): (f64, f64),
    tol: Options,
) -> Result<Flow> {
    let omega = o.omega();
    let sys = Phase {
        o,
        param,
        inv_omega: 1.0 / omega,
    };
    let pieces = (span / (PIECE * omega)).ceil().max(1.0) as usize;
    let mut out = Flow::start(y0);
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
        out.then(&Flow::linear(piece, [z[6], z[7]], [z[0], z[1]]));
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

/// Multipliers from the normalised monodromy and the accumulated determinant.
pub(crate) fn multipliers(f: &Flow) -> [Multiplier; 2] {
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
