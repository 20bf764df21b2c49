//! What first-order averaging makes of a model's fast periodic torque ([`Averaging`]): a
//! dither's in the control table, a kinematic error's in `hdgear model`.

use crate::model::Model;
use crate::params::Params;
use serde::Serialize;

/// What first-order averaging makes of a fast periodic torque of amplitude D at Ω_d (a dither
/// ũ = D·sin Ω_dτ, a kinematic error's base excitation: [`Model::dither`]).
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
    /// The averaging of `model`'s fast periodic torque: `None` without one (or where the model
    /// has no equivalent study set, [`Model::equivalent_params`]). The ripple is read from the
    /// stiffening, against the same model without the torque.
    pub fn of(model: &Model) -> Option<Averaging> {
        let [_, wd] = model.dither()?;
        let params = model.equivalent_params()?;
        let open = model.without_fast_torque().equivalent_params()?;
        let gmax = crate::fast::x_intervals(&params, (-1.0, 1.0))
            .iter()
            .flat_map(|&(l, r)| [params.g_prime(l), params.g_prime(r)])
            .fold(0.0_f64, f64::max);
        Some(Averaging {
            ripple: ((params.gamma - open.gamma) / (1.5 * open.alpha))
                .max(0.0)
                .sqrt(),
            params,
            frequency_ratio: wd / gmax.sqrt(),
        })
    }
}
