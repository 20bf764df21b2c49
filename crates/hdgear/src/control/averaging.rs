//! What first-order averaging makes of a dither ([`Averaging`]), for the control table.

use crate::model::Model;
use crate::params::Params;
use serde::Serialize;

/// What first-order averaging makes of a dither ũ = D·sin Ω_dτ on the study's model.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Averaging {
    /// The ripple amplitude A on the twist ([`crate::model::control::dither_ripple`]).
    pub ripple: f64,
    /// The averaged model: γ + 1.5αA², with the −A²/2 load folded into ε.
    pub params: Params,
    /// Ω_d over the fast mode's largest angular frequency on the averaged curve, √(max g'):
    /// averaging needs it well above 1 (the dither faster than every motion it is averaged
    /// against; the guide's control page shows where it holds).
    pub frequency_ratio: f64,
}

impl Averaging {
    /// The dithered closed loop `closed` of the study model with `p`: `None` without a dither.
    pub(crate) fn of(p: &Params, closed: &Model) -> Option<Averaging> {
        let [_, wd] = closed.dither()?;
        let params = closed.equivalent_params()?;
        let gmax = crate::fast::x_intervals(&params, (-1.0, 1.0))
            .iter()
            .flat_map(|&(l, r)| [params.g_prime(l), params.g_prime(r)])
            .fold(0.0_f64, f64::max);
        Some(Averaging {
            ripple: ((params.gamma - p.gamma) / (1.5 * p.alpha)).max(0.0).sqrt(),
            params,
            frequency_ratio: wd / gmax.sqrt(),
        })
    }
}
