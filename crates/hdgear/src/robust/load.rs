//! P(burst) against the load amplitude: the same space at a quarter to twice its nominal load.

use super::{McOptions, Nominal, Probability, Space, Target, Tolerance, probability};
use crate::burst::BurstOptions;
use crate::error::Result;
use crate::params::Param;
use crate::physical::DriveParam;
use serde::Serialize;

/// The factors on the load amplitude of [`load_curve`]: 2^(j/4) for j = −8 … 4, a quarter to
/// twice the nominal load in steps of 19 %, the nominal (j = 0) among them.
pub fn load_factors() -> impl Iterator<Item = f64> {
    (-8..=4).map(|j| 2f64.powf(f64::from(j) / 4.0))
}

/// P(burst) at one load amplitude.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LoadPoint {
    /// The factor on the nominal load.
    pub factor: f64,
    /// The load amplitude (T_am in N m for a drive, δ for a study set).
    pub load: f64,
    /// P(burst) there.
    pub probability: Probability,
}

/// The load amplitude of a set: a drive's T_am, a study set's or a model's δ.
pub fn load_target(nominal: &Nominal) -> Target {
    match nominal {
        Nominal::Drive(_) => Target::Drive(DriveParam::TAm),
        Nominal::Study(_) => Target::Study(Param::Delta),
        Nominal::Model(m) => Target::Model(
            m.param(Param::Delta.name())
                .expect("every model has the forcing's delta"),
        ),
    }
}

/// P(burst) against the load amplitude: the space with its nominal load (and the load's
/// tolerance, which scales with it) at each of [`load_factors`], `mc.samples` samples each
/// (the same points at every load).
pub fn load_curve(space: &Space, opts: &BurstOptions, mc: &McOptions) -> Result<Vec<LoadPoint>> {
    let target = load_target(&space.nominal);
    let nominal = space.nominal.value(target);
    load_factors()
        .map(|c| {
            let tolerances = space
                .tolerances
                .iter()
                .map(|t| Tolerance {
                    distribution: if t.target == target {
                        t.distribution.scaled(c)
                    } else {
                        t.distribution
                    },
                    ..t.clone()
                })
                .collect();
            let scaled = Space::new(space.nominal.with(target, c * nominal)?, tolerances)?;
            Ok(LoadPoint {
                factor: c,
                load: c * nominal,
                probability: probability(&scaled, opts, mc, |_| Ok(()))?,
            })
        })
        .collect()
}
