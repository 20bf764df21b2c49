//! A tuned law's robustness to model error: the least gain that keeps every plant within a
//! relative error of the nominal one burst-free ([`robustness`]).

use super::search::{GAIN_MAX, check_fraction, check_rel_tol, crossing};
use super::{Plant, Tuning, bursts_at};
use crate::burst::BurstOptions;
use crate::error::{Error, Result};
use crate::params::{Param, Params};
use serde::Serialize;

/// The parameters a model error moves in [`robustness`]: the plant's stiffness law (α, γ, ε) and
/// the load it carries (μ, δ); ω, the load's frequency, is taken as known.
pub const MODEL_ERROR_PARAMS: [Param; 5] = [
    Param::Alpha,
    Param::Gamma,
    Param::Eps,
    Param::Mu,
    Param::Delta,
];

/// How much gain a law needs to keep the bursts away from every plant within a relative model
/// error: each of [`MODEL_ERROR_PARAMS`] scaled by 1 − spread or 1 + spread, all 2⁵ corners of
/// that box (where a verdict monotone in each parameter has its worst case) with the nominal set.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Robustness<P = Params> {
    /// The relative model error (0.2: ±20 %).
    pub spread: f64,
    /// The plants checked: the box's corners and the nominal set.
    pub plants: usize,
    /// The least gain without bursts on every plant (the final bracket's upper end).
    pub gain: f64,
    /// That gain over the nominal plant's least gain: the margin a design at the nominal least
    /// gain lacks (1: none needed).
    pub ratio: f64,
    /// A plant that still bursts at the bracket's lower end: the worst case found.
    pub worst: P,
}

/// The plants within ±`spread` of `p` ([`Robustness`]): the nominal set first, then the box's
/// corners.
pub fn model_error_plants<P: Plant>(p: &P, spread: f64) -> Result<Vec<P>> {
    let n = MODEL_ERROR_PARAMS.len();
    std::iter::once(Ok(p.clone()))
        .chain((0..1usize << n).map(|corner| {
            MODEL_ERROR_PARAMS
                .iter()
                .enumerate()
                .try_fold(p.clone(), |q, (i, &param)| {
                    let sign = if corner >> i & 1 == 1 { 1.0 } else { -1.0 };
                    q.scaled(param, 1.0 + sign * spread)
                })
        }))
        .collect()
}

/// The least gain of `tuned`'s law (its other parameters kept) without bursts on every plant
/// within ±`spread` of `p` ([`Robustness`]), bisected to `rel_tol` from the nominal least gain
/// upward (the plants checked in parallel, in order, up to the first that bursts).
pub fn robustness<P: Plant>(
    p: &P,
    tuned: &Tuning,
    spread: f64,
    opts: &BurstOptions,
    rel_tol: f64,
) -> Result<Robustness<P>> {
    use rayon::prelude::*;
    check_rel_tol(rel_tol)?;
    check_fraction("spread", spread)?;
    let plants = model_error_plants(p, spread)?;
    let rest = &tuned.tuned.term.values()[1..];
    let law = tuned.law;
    // the first plant (in the list's order) that bursts at `gain`, if any, or the first error:
    // the plants after it are not judged, which a gain that fails leaves most of
    let bursting = |gain: f64| -> Result<Option<P>> {
        plants
            .par_iter()
            .find_map_first(|q| match bursts_at(q, law, gain, rest, opts) {
                Ok(false) => None,
                Ok(true) => Some(Ok(q.clone())),
                Err(e) => Some(Err(e)),
            })
            .transpose()
    };
    // The bracket is bisected on one plant alone, the worst known (at first, the first that
    // bursts at the nominal least gain), and every plant is judged only at that bisection's
    // upper end. Where all hold there, the bracket is the answer: its lower end bursts the
    // worst plant, its upper end no plant. Where another bursts there, it is the worst, and
    // its own bracket is sought from that gain up. With each plant's verdict monotone in the
    // gain (as the bisection assumes) the bracket holds the same least gain as one bisected on
    // every plant at each step, to the same `rel_tol`, at about one run per step instead of one
    // per plant.
    let start = tuned.tuned.gain;
    let unable = || Error::NoGain {
        law,
        reason: format!(
            "none up to {GAIN_MAX} (nor below a delay's stability limit) keeps every plant within \
             ±{} % burst-free",
            100.0 * spread
        ),
    };
    let mut from = start;
    let mut worst = bursting(start)?;
    let mut hi = start;
    while let Some(q) = &worst {
        let max = super::stability::law_limit(q, law, rest)?.map_or(GAIN_MAX, |l| l.gain);
        (_, hi) = crossing(
            |g| bursts_at(q, law, g, rest, opts),
            from,
            from,
            max,
            rel_tol,
        )?
        .ok_or_else(unable)?;
        match bursting(hi)? {
            Some(next) => {
                from = hi;
                worst = Some(next);
            }
            None => break,
        }
    }
    Ok(Robustness {
        spread,
        plants: plants.len(),
        gain: hi,
        ratio: hi / start,
        worst: worst.unwrap_or_else(|| p.clone()),
    })
}
