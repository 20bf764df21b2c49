//! The simulated bursting boundary in γ and in ω through a given point, started from the predicted
//! boundary ([`crate::fast::predict`]) so that only a few simulations are needed.
//!
//! # The search
//!
//! The switch of the simulated verdict ([`super::classify`]) is bracketed and then narrowed in
//! log scale to [`BOUNDARY_REL_TOL`], several parameter values at a time when the batch
//! integrator can run them ([`super::responses`] with Taylor's method: [`crate::batch::LANES`]
//! values in lock-step cost about as much as two or three one by one), one at a time otherwise:
//!
//! 1. **first round**: the prediction alone (one at a time), or [`crate::batch::LANES`] values
//!    spaced by a factor e^[`FIRST_ROUND_STEP`] around it, 0.62–1.52 times the prediction (the
//!    prediction's error is 3–20 % at the report's three boundaries and within a factor 1.35 along
//!    the study's line, 1.9 at its end; see [`crate::fast::FORCING_RATE_THRESHOLD`]);
//! 2. **bracket**: when every value of the round has the same verdict, doubling or halving from
//!    the last one toward the switch, one value at a time (each step depends on the last);
//! 3. **narrowing**: the bracket is cut into equal parts in log scale at the round's values
//!    (one: bisection; sixteen: seventeen parts) and the part where the verdict first switches,
//!    seen from the side below the switch, is kept, until it is narrower than
//!    [`BOUNDARY_REL_TOL`]; its geometric midpoint is the boundary.
//!
//! The rounds only decide where the simulations are made: every bracket ends as two simulated
//! values with different verdicts at most [`BOUNDARY_REL_TOL`] apart, whatever the round's size.
//! The batch rounds each verdict its own way (it carries sin ωτ as state and uses fused
//! multiply-adds), so a value within a fraction of a per cent of the switch may get the other
//! verdict than one by one; both searches find a switch of the simulated verdict to the same
//! tolerance.

use super::{BurstOptions, classify, response, responses};
use crate::error::Result;
use crate::fast::{predict, predicted_gamma_boundary};
use crate::integrate::Method;
use crate::params::Params;
use crate::roots::{first_switch, multisect_log};
use serde::Serialize;

/// The smallest ω the ω search simulates (3 slow periods = 1.9·10⁶ time units, the longest
/// run a boundary search may ask for).
pub const OMEGA_SEARCH_MIN: f64 = 1e-5;

/// Relative width of the final bracket of a simulated boundary.
pub const BOUNDARY_REL_TOL: f64 = 0.01;

/// Log spacing of the first round's values around the prediction when they run as a batch.
pub const FIRST_ROUND_STEP: f64 = 0.06;

/// Predicted and simulated bursting boundaries through one parameter point.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Boundaries {
    /// Predicted γ boundary (bursting below it), other parameters fixed.
    pub predicted_gamma: Option<f64>,
    /// Simulated γ boundary, to [`BOUNDARY_REL_TOL`].
    pub simulated_gamma: Option<f64>,
    /// Predicted ω boundary (bursting above it; 0 with a fold in range).
    pub predicted_omega: f64,
    /// Simulated ω boundary, to [`BOUNDARY_REL_TOL`] (`None` when the verdict does not change
    /// between [`OMEGA_SEARCH_MIN`] and the edge of the fast-slow domain).
    pub simulated_omega: Option<f64>,
}

/// The simulated verdicts (bursting or not) at the parameter sets `at(x)` for `xs`.
fn bursting(xs: &[f64], at: impl Fn(f64) -> Params, opts: &BurstOptions) -> Result<Vec<bool>> {
    let points: Vec<Params> = xs.iter().map(|&x| at(x)).collect();
    simulated_bursting(&points, opts)
}

/// The simulated verdicts (bursting or not) at `points`: as one batch when there are several and
/// the method is Taylor's, one by one otherwise.
pub(super) fn simulated_bursting(points: &[Params], opts: &BurstOptions) -> Result<Vec<bool>> {
    if let [p] = points[..] {
        // a batch of one lane costs as much as sixteen
        return Ok(vec![classify(&p, &response(&p, opts)?).bursting]);
    }
    responses(points, opts)
        .into_iter()
        .zip(points)
        .map(|(r, p)| Ok(classify(p, &r?).bursting))
        .collect()
}

/// Finds where `holds` switches (true below the switch when `below` is true, above it
/// otherwise) within [lo, hi], starting from `start`, with rounds of `lanes` values in increasing
/// order, the first spaced by a factor e^`first_step` (see the module docs).
fn search(
    start: f64,
    (lo, hi): (f64, f64),
    below: bool,
    (lanes, first_step): (usize, f64),
    mut holds: impl FnMut(&[f64]) -> Result<Vec<bool>>,
) -> Result<Option<f64>> {
    // whether each value is on the lower side of the switch
    let mut lower = |xs: &[f64]| -> Result<Vec<bool>> {
        Ok(holds(xs)?.into_iter().map(|h| h == below).collect())
    };
    let start = start.clamp(lo, hi);
    // the first round: the prediction, or LANES values around it (those inside [lo, hi])
    let half = (lanes / 2) as f64;
    let xs: Vec<f64> = (0..lanes)
        .map(|j| start * (first_step * (j as f64 - half)).exp())
        .filter(|x| (lo..=hi).contains(x))
        .collect();
    let sides = lower(&xs)?;
    // invariant from here: (a, b) with a < b, a on the lower side, b on the upper one
    let (a, b) = match first_switch(&xs, &sides) {
        Some(pair) => pair,
        None => {
            // no switch in the round: double up from its top or halve down from its bottom
            let up = sides[sides.len() - 1];
            let mut x = if up { xs[xs.len() - 1] } else { xs[0] };
            loop {
                let next = if up { x * 2.0 } else { x / 2.0 };
                if !(lo..=hi).contains(&next) {
                    return Ok(None);
                }
                if lower(&[next])?[0] != up {
                    break if up { (x, next) } else { (next, x) };
                }
                x = next;
            }
        }
    };
    multisect_log((a, b), lanes, BOUNDARY_REL_TOL, lower).map(Some)
}

/// Predicted and simulated boundaries through `p` (simulations: a handful of rounds for γ and
/// for ω; a round at ω below 1e-4 is long: its slow periods span millions of time units).
pub fn boundaries(p: &Params, opts: &BurstOptions) -> Result<Boundaries> {
    let lanes = match opts.tol.method {
        Method::Taylor => (crate::batch::LANES, FIRST_ROUND_STEP),
        Method::Dop853 => (1, FIRST_ROUND_STEP),
    };
    boundaries_with(p, opts, lanes)
}

/// [`boundaries`] with rounds of `lanes` values, the first spaced by e^`first_step`.
fn boundaries_with(p: &Params, opts: &BurstOptions, lanes: (usize, f64)) -> Result<Boundaries> {
    let predicted_gamma = predicted_gamma_boundary(p);
    let pr = predict(p);
    let gc = p.critical_gamma();
    let simulated_gamma = search(
        predicted_gamma.unwrap_or(p.gamma),
        (gc * (1.0 + 1e-9), 1e6 * (gc + 1.0)),
        true,
        lanes,
        |gs| bursting(gs, |gamma| Params { gamma, ..*p }, opts),
    )?;
    let omega_max = super::fast_slow_omega_max(p);
    let simulated_omega = if pr.fold_in_range {
        None
    } else {
        search(
            pr.omega_boundary,
            (OMEGA_SEARCH_MIN, omega_max),
            false,
            lanes,
            |ws| bursting(ws, |omega| Params { omega, ..*p }, opts),
        )?
    };
    Ok(Boundaries {
        predicted_gamma,
        simulated_gamma,
        predicted_omega: pr.omega_boundary,
        simulated_omega,
    })
}

#[cfg(test)]
mod tests {
    use super::{BOUNDARY_REL_TOL, search};

    /// A switch at 3.7, true below it (or above it): found to the tolerance from starts on
    /// both sides, near and far (the first round misses it, then the bracket walks), one value a
    /// round and sixteen, and `None` when the switch is outside the range. Each round's values
    /// come in increasing order, and the sixteen-value search needs fewer rounds.
    #[test]
    fn the_search_finds_a_switch_to_the_tolerance() {
        let switch = 3.7;
        for below in [true, false] {
            for start in [0.01, 1.0, 3.0, 3.7, 4.5, 1e3] {
                let mut rounds = [0; 2];
                for (i, lanes) in [(1, 0.06), (16, 0.06)].into_iter().enumerate() {
                    let holds = |xs: &[f64]| {
                        assert!(xs.windows(2).all(|w| w[0] < w[1]), "{xs:?}");
                        assert!(xs.len() == 1 || xs.len() == lanes.0, "{xs:?}");
                        rounds[i] += 1;
                        Ok(xs.iter().map(|&x| (x < switch) == below).collect())
                    };
                    let found = search(start, (1e-3, 1e4), below, lanes, holds)
                        .unwrap()
                        .unwrap();
                    assert!(
                        (found / switch).ln().abs() <= 0.5 * BOUNDARY_REL_TOL,
                        "{below} {start} {lanes:?}: {found}"
                    );
                    let outside = |xs: &[f64]| Ok(xs.iter().map(|_| below).collect());
                    assert_eq!(
                        search(start, (1e-3, 1e4), below, lanes, outside).unwrap(),
                        None
                    );
                }
                assert!(rounds[1] < rounds[0], "{below} {start}: rounds {rounds:?}");
            }
        }
    }

    /// The first round's spacing only decides where the simulations are made: a tenth and ten
    /// times [`super::FIRST_ROUND_STEP`] (a first round of ±0.5 % that misses the switch and
    /// walks, one of a factor 100 either way) find the same boundaries at γ = 1 to the brackets'
    /// widths, and so does one value a round.
    #[test]
    fn the_first_round_spacing_does_not_change_the_boundaries() {
        use super::{FIRST_ROUND_STEP, boundaries_with};
        let p = crate::Params {
            gamma: 1.0,
            ..crate::Params::default()
        };
        let o = crate::burst::BurstOptions::default();
        let at = |lanes| boundaries_with(&p, &o, lanes).unwrap();
        let base = at((16, FIRST_ROUND_STEP));
        for lanes in [
            (16, 0.1 * FIRST_ROUND_STEP),
            (16, 10.0 * FIRST_ROUND_STEP),
            (1, 0.0),
        ] {
            let b = at(lanes);
            for (x, y) in [
                (base.simulated_gamma, b.simulated_gamma),
                (base.simulated_omega, b.simulated_omega),
            ] {
                let (x, y) = (x.unwrap(), y.unwrap());
                assert!(
                    (x / y).ln().abs() <= 2.0 * BOUNDARY_REL_TOL,
                    "{lanes:?}: {x} vs {y}"
                );
            }
        }
    }
}
