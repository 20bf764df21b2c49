//! The largest Lyapunov exponent by Benettin's method, one orbit at a time or sixteen in a batch.

use super::*;

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
    advance(&sys, &mut z, (0.0, discard), tol)?;
    let sum = advance(&sys, &mut z, (discard, discard + span), tol)?;
    Ok(sum / span)
}

/// Integrates the state and tangent `z` from τ = t0 to t1 (phase ωτ), renormalising the tangent
/// every [`PIECE`] time units; returns the sum of the logarithms of the growth factors. A
/// switching oscillator carries the tangent by its flow's monodromy, saltations included
/// ([`Oscillator::switching_flow`]); where a rest zeroes it the sum is −∞.
fn advance<O: Oscillator>(
    sys: &Phase<'_, O>,
    z: &mut [f64; 8],
    (t0, t1): (f64, f64),
    tol: Options,
) -> Result<f64> {
    let omega = sys.o.omega();
    // a switching oscillator's flow keeps its monodromy normalised over the whole span
    if let Some(f) = sys
        .o
        .switching_flow(None, t0 * omega, [z[0], z[1]], (t1 - t0) * omega, tol)
    {
        let f = f?;
        let m = f.m;
        let u = [
            m[0][0] * z[2] + m[0][1] * z[3],
            m[1][0] * z[2] + m[1][1] * z[3],
        ];
        let n = u[0].hypot(u[1]);
        if n == 0.0 {
            return Ok(f64::NEG_INFINITY);
        }
        [z[0], z[1], z[2], z[3]] = [f.y[0], f.y[1], u[0] / n, u[1] / n];
        return Ok(n.ln() + f.log_scale);
    }
    let (mut t, mut sum) = (t0, 0.0);
    while t < t1 {
        let b = (t + PIECE).min(t1);
        let mut s = stepper(sys, t * omega, *z, method_for::<O>(tol))?;
        while s.t() < b * omega {
            s.step(b * omega)?;
        }
        *z = *s.y();
        let n = z[2].hypot(z[3]);
        sum += n.ln();
        z[2] /= n;
        z[3] /= n;
        t = b;
    }
    Ok(sum)
}

/// A Lyapunov exponent averaged until it converged, with its uncertainty.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LyapunovEstimate {
    /// The largest exponent (per unit τ): the mean growth rate over `span`.
    pub exponent: f64,
    /// Its standard error, from the spread of the rates of the blocks the span is made of (batch
    /// means: blocks of whole forcing periods, at least [`LYAPUNOV_BLOCK`] time units each).
    pub standard_error: f64,
    /// The time units averaged over (after the alignment, two blocks).
    pub span: f64,
    /// Whether the standard error reached the requested relative accuracy before the limit of
    /// [`LYAPUNOV_MAX_SPAN`] time units.
    pub converged: bool,
}

/// The shortest block of a [`lyapunov_converged`] estimate, in time units: twenty times the
/// slowest decay time 1/r = 2 of the fast subsystem's unit damping, so that one block aligns the
/// tangent vector to e⁻²⁰ of its start whatever the forcing period.
pub const LYAPUNOV_BLOCK: f64 = 40.0;

/// The longest span a [`lyapunov_converged`] estimate averages over, in time units.
pub const LYAPUNOV_MAX_SPAN: f64 = 1e5;

/// The largest Lyapunov exponent by Benettin's method (as [`lyapunov`]), averaged until its
/// standard error is at most `rel_tol`·|λ| (or `rel_tol`·10⁻³ near λ = 0), with at least eight
/// blocks, or until [`LYAPUNOV_MAX_SPAN`]. Blocks are whole forcing periods of at least
/// [`LYAPUNOV_BLOCK`] time units; the first two align the tangent vector and are not counted.
///
/// ```
/// use hdgear::{Params, periodic::lyapunov_converged, integrate::Options};
/// // a periodic response on a focus: both exponents −1/2 (Liouville: they sum to −1)
/// let p = Params { gamma: 10.0, omega: 6.0, delta: 8.0, ..Params::default() };
/// let e = lyapunov_converged(&p, [0.0, 0.0], 1e-3, Options::default()).unwrap();
/// assert!(e.converged && (e.exponent + 0.5).abs() < 3.0 * e.standard_error.max(1e-6));
/// ```
pub fn lyapunov_converged<O: Oscillator>(
    o: &O,
    y0: [f64; 2],
    rel_tol: f64,
    tol: Options,
) -> Result<LyapunovEstimate> {
    o.check()?;
    if !(rel_tol > 0.0 && rel_tol < 1.0) {
        return Err(Error::InvalidOption {
            name: "rel_tol",
            value: rel_tol,
            reason: "must be in (0, 1)",
        });
    }
    let omega = o.omega();
    let period = std::f64::consts::TAU / omega;
    let block = period * (LYAPUNOV_BLOCK / period).ceil();
    crate::integrate::check_budget(LYAPUNOV_MAX_SPAN + 2.0 * block, &tol)?;
    let sys = Phase {
        o,
        param: None,
        inv_omega: 1.0 / omega,
    };
    let mut z = [y0[0], y0[1], 1.0, 1.0, 0.0, 0.0, 0.0, 0.0];
    advance(&sys, &mut z, (0.0, 2.0 * block), tol)?;
    let mut rates: Vec<f64> = Vec::new();
    let mut t = 2.0 * block;
    loop {
        rates.push(advance(&sys, &mut z, (t, t + block), tol)? / block);
        t += block;
        let n = rates.len() as f64;
        let mean = rates.iter().sum::<f64>() / n;
        let var = rates.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
        let standard_error = (var / n).sqrt();
        let converged = rates.len() >= 8 && standard_error <= rel_tol * mean.abs().max(1e-3);
        let span = n * block;
        if converged || span >= LYAPUNOV_MAX_SPAN {
            return Ok(LyapunovEstimate {
                exponent: mean,
                standard_error,
                span,
                converged,
            });
        }
    }
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
