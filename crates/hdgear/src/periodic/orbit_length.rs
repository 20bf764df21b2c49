//! The longest orbit a two-parameter trace may shoot ([`check_orbit_length`]): a box reaching
//! down to a tiny ω holds orbits so long that tracing it would take hours, refused at once.

use super::{Box2, Oscillator};
use crate::error::{Error, Result};

/// The most integration steps one shooting of an orbit may take in a two-parameter trace, at
/// [`crate::integrate::OPTIMISTIC_STEP`]. Each point of a curve is a Newton solve of a few
/// shootings, each with the variational equations, and a curve has tens to hundreds of points:
/// the work grows in proportion to the longest period. This bound keeps a box at the scale of
/// an interactive run; ten times it is a long wait, a hundred times hours.
pub const MAX_ORBIT_STEPS: f64 = 2e6;

/// Refuses, before any work, a box whose longest orbit (period k·2π/ω at the least ω in it: the
/// box's when ω is one of `params`, else `o`'s) needs more than [`MAX_ORBIT_STEPS`] steps.
pub fn check_orbit_length<O: Oscillator>(
    o: &O,
    params: [O::Param; 2],
    k: u32,
    box2: &Box2,
) -> Result<()> {
    let omega = (0..2)
        .filter(|&i| O::is_frequency(params[i]))
        .map(|i| box2.ranges[i].0)
        .fold(o.omega(), f64::min);
    let period = f64::from(k) * std::f64::consts::TAU / omega;
    let steps = period / crate::integrate::OPTIMISTIC_STEP;
    if steps > MAX_ORBIT_STEPS {
        return Err(Error::InvalidInput {
            what: "parameter box",
            text: format!("ω down to {omega:e}"),
            reason: format!(
                "its longest orbit lasts {period:.3e} time units, about {steps:.1e} steps per \
                 shooting, over the {MAX_ORBIT_STEPS:e} a trace of hundreds of shootings affords; \
                 raise the least ω to {:.3e} or more",
                f64::from(k) * std::f64::consts::TAU
                    / (MAX_ORBIT_STEPS * crate::integrate::OPTIMISTIC_STEP)
            ),
        });
    }
    Ok(())
}
