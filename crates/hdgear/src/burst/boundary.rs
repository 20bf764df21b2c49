//! The simulated bursting boundary in γ and in ω through a given point, by bisection on the
//! simulated verdict ([`super::classify`]), started from the predicted boundary
//! ([`crate::fast::predict`]) so that only a few simulations are needed.

use super::{BurstOptions, classify, response};
use crate::error::Result;
use crate::fast::{predict, predicted_gamma_boundary};
use crate::params::Params;
use serde::Serialize;

/// The smallest ω the ω search simulates (3 slow periods = 1.9·10⁶ time units, about 3 s).
pub const OMEGA_SEARCH_MIN: f64 = 1e-5;

/// Relative width of the final bracket of a simulated boundary.
pub const BOUNDARY_REL_TOL: f64 = 0.01;

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

fn bursting(p: &Params, opts: &BurstOptions) -> Result<bool> {
    Ok(classify(p, &response(p, opts)?).bursting)
}

/// Brackets the switch of `holds` (true below the switch when `below` is true, above it
/// otherwise) by doubling or halving from `start` within [lo, hi], then bisects in log scale.
fn search(
    start: f64,
    (lo, hi): (f64, f64),
    below: bool,
    mut holds: impl FnMut(f64) -> Result<bool>,
) -> Result<Option<f64>> {
    let mut x = start.clamp(lo, hi);
    let hx = holds(x)?;
    // move away from the side x is on until the verdict changes
    let up = hx == below; // bursting below the switch and bursting here: the switch is above
    let (a, b);
    loop {
        let next = if up { x * 2.0 } else { x / 2.0 };
        if !(lo..=hi).contains(&next) {
            return Ok(None);
        }
        if holds(next)? != hx {
            if up {
                (a, b) = (x, next);
            } else {
                (a, b) = (next, x);
            }
            break;
        }
        x = next;
    }
    // invariant: holds(a) == below, holds(b) != below
    let (mut la, mut lb) = (a.ln(), b.ln());
    while lb - la > BOUNDARY_REL_TOL {
        let m = 0.5 * (la + lb);
        if holds(m.exp())? == below {
            la = m;
        } else {
            lb = m;
        }
    }
    Ok(Some((0.5 * (la + lb)).exp()))
}

/// Predicted and simulated boundaries through `p` (simulations: a handful for γ, more for ω;
/// each ω step below 1e-4 takes a few hundred milliseconds).
pub fn boundaries(p: &Params, opts: &BurstOptions) -> Result<Boundaries> {
    let predicted_gamma = predicted_gamma_boundary(p);
    let pr = predict(p);
    let gc = p.critical_gamma();
    let simulated_gamma = search(
        predicted_gamma.unwrap_or(p.gamma),
        (gc * (1.0 + 1e-9), 1e6 * (gc + 1.0)),
        true,
        |g| bursting(&Params { gamma: g, ..*p }, opts),
    )?;
    let omega_max = super::turning_point_rate(p) / super::TIME_SCALE_SEPARATION;
    let simulated_omega = if pr.fold_in_range {
        None
    } else {
        search(
            pr.omega_boundary,
            (OMEGA_SEARCH_MIN, omega_max),
            false,
            |w| bursting(&Params { omega: w, ..*p }, opts),
        )?
    };
    Ok(Boundaries {
        predicted_gamma,
        simulated_gamma,
        predicted_omega: pr.omega_boundary,
        simulated_omega,
    })
}
