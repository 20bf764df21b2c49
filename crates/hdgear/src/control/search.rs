//! The search for the least gain (or spread) where the bursts stop: a bracket from a start,
//! doubled or halved, then bisected geometrically, and the checks of its options.

use crate::error::{Error, Result};
use crate::model::terms::AnyTerm;

/// The first gain tried: 1/64, below the study's least gains (of order 1). The bracket the
/// search ends on does not depend on it: gains double upward from it while the closed loop
/// bursts, or halve downward while half the gain still removes the bursts.
pub const GAIN_START: f64 = 1.0 / 64.0;
/// The largest gain tried (2^16): a law that has not removed the bursts by then is reported as
/// unable to.
pub const GAIN_MAX: f64 = 65536.0;
/// The smallest gain tried (2^-40): bursts removed by less are at the verdict's own threshold.
pub const GAIN_MIN: f64 = 1.0 / 1_099_511_627_776.0;

/// A bracket's relative width (`rel_tol`) or a relative model error (`spread`) must lie in
/// (0, 1).
pub(super) fn check_fraction(name: &'static str, value: f64) -> Result<()> {
    if value > 0.0 && value < 1.0 {
        Ok(())
    } else {
        Err(Error::InvalidOption {
            name,
            value,
            reason: "must lie in (0, 1)",
        })
    }
}

/// `gain` against the domain of `law`'s gain (its first parameter), refused as the option the
/// caller gave it by ([`super::ControlOptions::gain`]) rather than as the term's parameter.
pub(super) fn check_gain(law: &str, gain: f64) -> Result<()> {
    match AnyTerm::params_of(law).and_then(|ps| ps.first()) {
        Some(first) => first.domain.check(first.name, gain).map_err(|e| match e {
            Error::InvalidParameter { reason, .. } => Error::InvalidOption {
                name: "gain",
                value: gain,
                reason,
            },
            other => other,
        }),
        // an unknown law is refused by name where its term is built
        None => Ok(()),
    }
}

/// The narrowest relative bracket two f64 gains can form, with room for the geometric midpoint
/// between them: four units in the last place (2⁻⁵⁰ ≈ 8.9e-16).
pub const MIN_REL_TOL: f64 = 4.0 * f64::EPSILON;

/// A bracket's relative width must lie in [[`MIN_REL_TOL`], 1): a narrower one cannot be
/// reached in f64, and the bisection would never end.
pub(super) fn check_rel_tol(value: f64) -> Result<()> {
    check_fraction("rel_tol", value)?;
    if value < MIN_REL_TOL {
        return Err(Error::InvalidOption {
            name: "rel_tol",
            value,
            reason: "below 8.9e-16 (four units in the last place): no two f64 gains bracket \
                     that narrowly",
        });
    }
    Ok(())
}

/// Where `bursts` (true for small values of a suppressing variable, false for large ones) turns
/// false: from `start`, doubled while it bursts (up to `max`, tried last: `None` if it bursts)
/// or halved while half of it does not (down to `min`: the lower end 0 below), then the bracket
/// bisected geometrically to `rel_tol` (at least [`MIN_REL_TOL`], checked by every caller: wider
/// than three units in the last place, the midpoint is strictly inside). Returns (largest value
/// found bursting, least found not).
pub(super) fn crossing(
    mut bursts: impl FnMut(f64) -> Result<bool>,
    start: f64,
    min: f64,
    max: f64,
    rel_tol: f64,
) -> Result<Option<(f64, f64)>> {
    let mut lo = 0.0;
    let mut hi = start;
    if !bursts(hi)? {
        while hi > min && !bursts(0.5 * hi)? {
            hi *= 0.5;
        }
        lo = if hi > min { 0.5 * hi } else { 0.0 };
    }
    while bursts(hi)? {
        lo = hi;
        if hi >= max {
            return Ok(None);
        }
        hi = (2.0 * hi).min(max);
    }
    while lo > 0.0 && hi / lo - 1.0 > rel_tol {
        let mid = (lo * hi).sqrt();
        if bursts(mid)? {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(Some((lo, hi)))
}
