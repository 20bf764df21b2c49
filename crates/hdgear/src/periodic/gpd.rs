//! Branch switching at a generalised period doubling (GPD): the curve of folds of the doubled
//! orbits that is born there ([`switch_at_gpd`]).
//!
//! At a GPD of the curve of period doublings of the k-orbits, the stroboscopic map on its centre
//! manifold is η ↦ −(1 + β₁)η + cη³ + eη⁵, with c = 0 at the point (β₁ the distance from the
//! period-doubling curve, c the normal-form coefficient along it). Its doubled orbits ±η solve
//! β₁ = cη² + eη⁴, and two of them meet in a fold where c = −2eη², at β₁ = −c²/(4e): a curve of
//! folds of the doubled orbits (period 2k·2π/ω) leaves the GPD on the subcritical side (c < 0 for
//! e > 0), with η² ∝ c and its distance from the period-doubling curve ∝ c².
//!
//! Seen over 2k periods, every orbit of the period-doubling curve has the multiplier (−1)² = +1
//! too, so the fold system of period 2k (the one [`continue_curve`](super::continue_curve)
//! solves) holds both curves, and the GPD is a branch point of it. There the new curve's tangent
//! is the flip direction q (M q = −q) in the state, with no parameter part (β₁ ∝ η⁴, c ∝ η²).
//! The switch moves the orbit by h·q, holds its projection on q fixed while the corrector puts
//! it on the fold system of period 2k, and refuses a point that is a k-orbit again (that is the
//! period-doubling curve itself). The curve is then followed away from the GPD until it leaves
//! the box or reaches another GPD of the same period-doubling curve ([`End::Rejoined`]).

use super::continuation::SWITCH_LADDER;
use super::floquet::{flow, multipliers};
use super::normal_form::flip_direction;
use super::shooting::minimal_subharmonic;
use super::two_parameter::{axpy, dot, tracer};
use super::{Box2, Codim2, ContinuationOptions, Curve2, CurveKind, CurvePoint2, End, Oscillator};
use crate::error::{Error, Result};
use std::f64::consts::TAU;

/// The fold curve of the doubled orbits (period 2k·2π/ω) born at `gpd`, a generalised period
/// doubling of `pd` (a period-doubling curve of period k·2π/ω from
/// [`continue_curve`](super::continue_curve), with the same `o` and `box2`). Its first point is
/// the GPD seen over 2k periods (its ends: [`End::Switched`], then why the curve ended; a curve
/// that reaches another GPD of `pd` ends there).
///
/// ```
/// use hdgear::Params;
/// use hdgear::periodic::{Box2, Codim2, ContinuationOptions, CurveKind, Range, curves_from_branch,
///     switch_at_gpd};
/// // γ = 10: the period doublings of the bubble in (ω, μ), then the folds of their doubled orbits
/// let p = Params { gamma: 10.0, ..Params::default() };
/// let ranges = [Range::parse("omega=7:10:log").unwrap(), Range::parse("mu=-5:5").unwrap()];
/// let opts = ContinuationOptions::default();
/// let pd = curves_from_branch(&p, ranges, CurveKind::PeriodDoubling, Some(1), 1, &opts).unwrap();
/// let gpd = pd[0].points.iter().find(|q| q.special == Some(Codim2::GeneralisedPeriodDoubling));
/// let lpc = switch_at_gpd(&p, &pd[0], gpd.unwrap(), &Box2::of(ranges), &opts).unwrap();
/// assert_eq!(lpc.subharmonic, 2);
/// ```
pub fn switch_at_gpd<O: Oscillator>(
    o: &O,
    pd: &Curve2<O::Param>,
    gpd: &CurvePoint2,
    box2: &Box2,
    opts: &ContinuationOptions,
) -> Result<Curve2<O::Param>> {
    opts.validate()?;
    box2.validate()?;
    let is_gpd = |q: &CurvePoint2| q.special == Some(Codim2::GeneralisedPeriodDoubling);
    if pd.kind != CurveKind::PeriodDoubling || !is_gpd(gpd) {
        return Err(Error::InvalidInput {
            what: "start",
            text: format!("{:?}", gpd.params),
            reason: "is not a generalised period doubling of a period-doubling curve".into(),
        });
    }
    let (k, params, tol) = (pd.subharmonic, pd.params, opts.periodic.tol);
    let mut tr = tracer(o, params, CurveKind::Fold, 2 * k, gpd.start, box2, opts);
    let scale = tr.scale;
    let unknowns = |q: &CurvePoint2| {
        let u = [0, 1].map(|i| box2.scales[i].to_u(q.params[i]));
        [q.start[0] / scale, q.start[1] / scale, u[0], u[1]]
    };
    let star = unknowns(gpd);
    let origin = doubled(o, pd, gpd, tol)?;
    for other in pd.points.iter().filter(|q| is_gpd(q)) {
        let z = unknowns(other);
        if axpy(z, -1.0, star).iter().any(|d| d.abs() > 1e-9) {
            tr.terminals.push((z, doubled(o, pd, other, tol)?));
        }
    }
    let q = flip_direction(&tr.at(star)?, gpd.start, k, tol)?;
    let n = [q[0], q[1], 0.0, 0.0];
    for h in SWITCH_LADDER.map(|f| f * opts.initial_step * tr.size) {
        for sign in [1.0, -1.0] {
            let zp = axpy(star, sign * h, n);
            let Some(first) = tr.correct(zp, n, dot(n, zp))? else {
                continue;
            };
            // landed on the period-doubling curve (a k-orbit) again?
            if minimal_subharmonic(&tr.at(first.z)?, tr.state(first.z), 2 * k, tol)? < 2 * k {
                continue;
            }
            let Some(t) = tr.tangent(&first, n.map(|v| sign * v)) else {
                continue;
            };
            let head = [origin, tr.curve_point(&first, None)?];
            let (rest, end) = tr.trace(first, t)?;
            return Ok(Curve2 {
                kind: CurveKind::Fold,
                params,
                subharmonic: 2 * k,
                points: head.into_iter().chain(rest).collect(),
                ends: [End::Switched, end],
            });
        }
    }
    Err(Error::NoConvergence {
        what: "the fold curve of the doubled orbits at a generalised period doubling",
        iterations: opts.max_corrector,
        residual: f64::NAN,
    })
}

/// A point of the period-doubling curve `pd` seen as an orbit of twice its period (multipliers
/// squared: one is +1), as it stands on a fold curve of the doubled orbits.
fn doubled<O: Oscillator>(
    o: &O,
    pd: &Curve2<O::Param>,
    q: &CurvePoint2,
    tol: crate::integrate::Options,
) -> Result<CurvePoint2> {
    let o = o
        .with(pd.params[0], q.params[0])?
        .with(pd.params[1], q.params[1])?;
    let k = 2 * pd.subharmonic;
    let f = flow(&o, None, 0.0, q.start, TAU * f64::from(k), tol)?;
    Ok(CurvePoint2 {
        multipliers: multipliers(&f),
        amplitude: super::amplitude(&o, q.start, k, tol)?,
        flip_coefficient: None,
        ..*q
    })
}
