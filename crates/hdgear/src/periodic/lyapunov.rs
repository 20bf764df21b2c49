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
