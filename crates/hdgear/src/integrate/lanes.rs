//! What every batch shares (the study's [`crate::batch`] and the assembled models'
//! [`crate::model::integrate_models`]): the number of lanes, a lane's outcome and the checks of
//! the input.

use crate::error::Result;
use crate::integrate::Options;

/// Trajectories per batch.
pub const LANES: usize = 16;

/// The outcome of one lane: of the study's model (N = 2), or of a [`crate::model::Model`] with
/// N state components ([`crate::model::integrate_models`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneResult<const N: usize = 2> {
    /// Final state ([x, x'] and the model's internal states).
    pub y: [f64; N],
    /// Steps taken by this lane.
    pub steps: u64,
}

/// The checks every batch entry point makes: usable options, one start and one span per
/// point, valid parameters (`valid`), a step budget that can reach each span's end.
pub(crate) fn check_inputs<P>(
    points: &[P],
    starts: usize,
    spans: &[(f64, f64)],
    tol: &Options,
    valid: impl Fn(&P) -> Result<()>,
) -> Result<()> {
    tol.validate()?;
    if starts != points.len() || spans.len() != points.len() {
        return Err(crate::Error::InvalidInput {
            what: "batch",
            text: format!(
                "{starts} starts and {} spans for {} parameter sets",
                spans.len(),
                points.len()
            ),
            reason: "one start and one span per parameter set".into(),
        });
    }
    for (p, &(_, t_end)) in points.iter().zip(spans) {
        valid(p)?;
        crate::integrate::check_budget(t_end, tol)?;
    }
    Ok(())
}
