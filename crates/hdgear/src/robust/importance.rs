//! Importance sampling of a small P(burst): samples drawn near the predicted boundary and
//! weighted back, so that a probability of 10⁻⁵ is estimated from thousands of samples, not
//! millions.
//!
//! The toleranced parameters are written in standard-normal coordinates z (each value is its
//! distribution's quantile of Φ(z): [`Distribution::from_standard`](super::Distribution)).
//! The **design point** z\* is the point nearest the origin where bursting is *predicted* from
//! the equilibrium curve ([`crate::fast::predict`], microseconds a set): on rays along the
//! axes, through the corners and along [`DIRECTIONS`] quasi-random directions, the first
//! predicted change is bracketed on radii [`RADIUS_STEP`] apart up to [`MAX_RADIUS`] and
//! bisected. Samples are then drawn from the defensive mixture
//! q = (1 − λ)·φ(z) + λ·φ(z − z\*) with λ = [`SHARE`], judged by the full simulated verdict,
//! and weighted by w = φ(z)/q(z) = 1/((1 − λ) + λ·exp(z·z\* − |z\*|²/2)).
//!
//! The estimate Σ w·1\[burst\]/n is unbiased for *any* z\*: the prediction only decides how
//! efficient it is, never its value. The weights are at most 1/(1 − λ) = 2, so an estimate can
//! be at worst twice as noisy as plain sampling where the prediction is wrong, and the bound
//! P ≤ P_q/(1 − λ) (P_q the proposal's own burst fraction) gives an upper limit that needs no
//! normal approximation. The variance reduction reported is p(1 − p)/s², plain sampling's
//! variance per sample at the estimated p over the weighted indicator's sample variance s².

use super::{CHUNK, Failure, McOptions, Space, evaluate};
use crate::burst::BurstOptions;
use crate::distribution::{normal_quantile, wilson};
use crate::error::{Error, Result};
use crate::fast::predict;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// λ, the share of samples drawn around the design point: half, which bounds every weight by 2
/// (a defensive mixture, Hesterberg 1995) while putting half the samples where bursting is.
pub const SHARE: f64 = 0.5;

/// The farthest design point searched for, in standard deviations: Φ(−8) ≈ 6·10⁻¹⁶, beyond
/// any probability a design review weighs.
pub const MAX_RADIUS: f64 = 8.0;

/// Radii on each ray are judged this far apart before the first change is bisected: half a
/// standard deviation. A predicted-bursting region thinner than that along every ray can be
/// stepped over; that moves the design point, so it costs efficiency, never correctness.
pub const RADIUS_STEP: f64 = 0.5;

/// Halvings of a ray's bracket (0.5·2⁻²⁰ ≈ 5·10⁻⁷ standard deviations).
pub const HALVINGS: usize = 20;

/// Quasi-random ray directions beside the 2k axes and (up to 2¹⁰) corners.
pub const DIRECTIONS: usize = 256;

/// Most tolerances whose corners are searched (2¹⁰ rays).
const MAX_CORNER_DIMS: usize = 10;

/// The nearest predicted-bursting point in standard-normal coordinates.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DesignPoint {
    /// Its standard-normal coordinates z\*.
    pub z: Vec<f64>,
    /// The toleranced parameters' values there.
    pub values: Vec<f64>,
    /// β = |z\*|.
    pub beta: f64,
    /// Φ(−β): the first-order (FORM) estimate of the predicted P(burst), for comparison.
    pub first_order_p: f64,
    /// Rays searched.
    pub rays: usize,
}

/// P(burst) by importance sampling.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Importance {
    /// The design point the samples were drawn around (None: bursting is predicted at the
    /// nominal set, or nowhere within [`MAX_RADIUS`]; the samples are then plain ones).
    pub design: Option<DesignPoint>,
    /// Why there is no design point.
    pub note: Option<String>,
    /// λ, the share drawn around it.
    pub share: f64,
    /// The first sample's index in the sequence (a shard's start).
    pub first: u64,
    /// Samples drawn.
    pub samples: u64,
    /// Of them with a verdict.
    pub judged: u64,
    /// Of them bursting (under the proposal, unweighted).
    pub bursting: u64,
    /// Samples outside the model's domain or whose integration failed (excluded).
    pub excluded: u64,
    /// Σ w·1\[burst\] over the judged samples.
    pub sum: f64,
    /// Σ (w·1\[burst\])².
    pub sum_sq: f64,
    /// The estimate Σ w·1\[burst\]/judged.
    #[serde(deserialize_with = "crate::output::nan_if_null")]
    pub p: f64,
    /// Its standard error s/√n.
    #[serde(deserialize_with = "crate::output::nan_if_null")]
    pub std_error: f64,
    /// p ± z·s/√n at `level` (a normal approximation: see `upper_bound` when `bursting` < 10).
    pub interval: (f64, f64),
    /// The upper limit P ≤ P_q/(1 − λ) at `level` with P_q's Wilson upper end: valid without
    /// the normal approximation.
    pub upper_bound: f64,
    /// The confidence of both.
    pub level: f64,
    /// Plain sampling's variance per sample at p over this estimate's (NaN without bursting).
    #[serde(deserialize_with = "crate::output::nan_if_null")]
    pub variance_reduction: f64,
    /// Plain samples that would give the same standard error (judged × variance reduction).
    #[serde(deserialize_with = "crate::output::nan_if_null")]
    pub equivalent_plain_samples: f64,
}

impl Importance {
    /// No sample yet: the counts and sums zero, the estimate undefined until [`Importance::finish`].
    fn empty(
        design: Option<DesignPoint>,
        note: Option<String>,
        share: f64,
        first: u64,
        level: f64,
    ) -> Importance {
        Importance {
            design,
            note,
            share,
            first,
            samples: 0,
            judged: 0,
            bursting: 0,
            excluded: 0,
            sum: 0.0,
            sum_sq: 0.0,
            p: f64::NAN,
            std_error: f64::NAN,
            interval: (0.0, 1.0),
            upper_bound: 1.0,
            level,
            variance_reduction: f64::NAN,
            equivalent_plain_samples: f64::NAN,
        }
    }

    /// The estimate, interval and variance reduction from the sums (shards add their sums).
    pub fn finish(mut self) -> Importance {
        let n = self.judged as f64;
        self.p = self.sum / n;
        let var = ((self.sum_sq - n * self.p * self.p) / (n - 1.0)).max(0.0);
        self.std_error = (var / n).sqrt();
        let z = normal_quantile(0.5 + 0.5 * self.level);
        self.interval = (
            (self.p - z * self.std_error).max(0.0),
            (self.p + z * self.std_error).min(1.0),
        );
        let one_sided = 2.0 * self.level - 1.0;
        self.upper_bound =
            (wilson(self.bursting, self.judged, one_sided).1 / (1.0 - self.share)).min(1.0);
        self.variance_reduction = if var > 0.0 {
            self.p * (1.0 - self.p) / var
        } else {
            f64::NAN
        };
        self.equivalent_plain_samples = n * self.variance_reduction;
        self
    }

    /// The estimate over several shards of one run: their counts and sums added, once their
    /// design points and options are checked equal and their blocks of samples found to join
    /// (in any order) into one from the first shard's start.
    pub fn merge(parts: &[Importance]) -> Result<Importance> {
        let mut sorted: Vec<&Importance> = parts.iter().collect();
        sorted.sort_by_key(|p| p.first);
        let first = *sorted
            .first()
            .ok_or_else(|| super::no_parts("importance"))?;
        let mut total = Importance::empty(
            first.design.clone(),
            first.note.clone(),
            first.share,
            first.first,
            first.level,
        );
        for p in sorted {
            let bad = |reason: &str| Error::InvalidInput {
                what: "shards",
                text: format!("importance samples from index {}", p.first),
                reason: reason.into(),
            };
            if (&p.design, p.share, p.level) != (&first.design, first.share, first.level) {
                return Err(bad("another design point or level than the first shard's"));
            }
            if p.first != total.first + total.samples {
                return Err(bad(
                    "the blocks of samples do not join (a shard missing or twice)",
                ));
            }
            total.samples += p.samples;
            total.judged += p.judged;
            total.bursting += p.bursting;
            total.excluded += p.excluded;
            total.sum += p.sum;
            total.sum_sq += p.sum_sq;
        }
        Ok(total.finish())
    }
}

impl Space {
    /// The toleranced parameters' values at standard-normal coordinates z.
    pub fn values_standard(&self, z: &[f64]) -> Vec<f64> {
        self.tolerances
            .iter()
            .zip(z)
            .map(|(t, &z)| t.distribution.from_standard(z))
            .collect()
    }

    fn predicted_bursting(&self, z: &[f64]) -> bool {
        self.at(&self.values_standard(z))
            .and_then(|n| n.reduced())
            .is_ok_and(|p| predict(&p).bursting)
    }

    /// Refuses importance sampling where there is no design point to draw near: a model with
    /// terms has no curve-only prediction of its boundary (the rays would find none and every
    /// sample would be a plain one).
    pub fn check_importance(&self) -> Result<()> {
        match &self.nominal {
            super::Nominal::Model(m) => Err(crate::Error::InvalidInput {
                what: "option",
                text: "importance".into(),
                reason: format!(
                    "{} has no curve-only prediction of its bursting boundary to sample near \
                     (the study's cubic and drives have one); use plain samples",
                    m.equation()
                ),
            }),
            _ => Ok(()),
        }
    }
}

/// The ray directions: ±axes, the corners (k ≤ 10), [`DIRECTIONS`] quasi-random ones.
fn directions(k: usize, seed: u64) -> Result<Vec<Vec<f64>>> {
    let mut out = Vec::new();
    for i in 0..k {
        for s in [-1.0, 1.0] {
            let mut d = vec![0.0; k];
            d[i] = s;
            out.push(d);
        }
    }
    if k > 1 && k <= MAX_CORNER_DIMS {
        let norm = 1.0 / (k as f64).sqrt();
        for c in 0..1usize << k {
            out.push(
                (0..k)
                    .map(|i| if c >> i & 1 == 1 { norm } else { -norm })
                    .collect(),
            );
        }
    }
    let points = super::Points::new(super::Sampler::Sobol, seed, k)?;
    let mut u = vec![0.0; k];
    for i in 0..DIRECTIONS as u64 {
        points.point(i, &mut u);
        let d: Vec<f64> = u.iter().map(|&u| normal_quantile(u)).collect();
        let n = d.iter().map(|x| x * x).sum::<f64>().sqrt();
        if n > 0.0 {
            out.push(d.iter().map(|x| x / n).collect());
        }
    }
    Ok(out)
}

/// The first radius along `d` where bursting is predicted, bisected (None within the reach).
fn ray_crossing(space: &Space, d: &[f64]) -> Option<f64> {
    let at = |r: f64| space.predicted_bursting(&d.iter().map(|x| r * x).collect::<Vec<_>>());
    let steps = (MAX_RADIUS / RADIUS_STEP).round() as usize;
    let j = (1..=steps).find(|&j| at(j as f64 * RADIUS_STEP))?;
    let (_, hi) = crate::roots::bisect(
        (j - 1) as f64 * RADIUS_STEP,
        j as f64 * RADIUS_STEP,
        HALVINGS,
        |_, _| false,
        |r| !at(r),
    );
    Some(hi)
}

/// The design point of `space` (see the module docs), or why there is none.
pub fn design_point(space: &Space, seed: u64) -> Result<std::result::Result<DesignPoint, String>> {
    let k = space.dims();
    if space.predicted_bursting(&vec![0.0; k]) {
        return Ok(Err(
            "bursting is predicted at the nominal set: P is not small, plain samples".into(),
        ));
    }
    let dirs = directions(k, seed)?;
    let best = dirs
        .par_iter()
        .filter_map(|d| ray_crossing(space, d).map(|r| (r, d)))
        .min_by(|a, b| a.0.total_cmp(&b.0));
    let Some((beta, d)) = best else {
        return Ok(Err(format!(
            "no bursting is predicted within {MAX_RADIUS} standard deviations: plain samples"
        )));
    };
    let z: Vec<f64> = d.iter().map(|x| beta * x).collect();
    Ok(Ok(DesignPoint {
        values: space.values_standard(&z),
        z,
        beta,
        first_order_p: crate::distribution::normal_cdf(-beta),
        rays: dirs.len(),
    }))
}

/// Estimates P(burst) over `space` by importance sampling around the design point (module
/// docs), from `mc.samples` samples of the sequence (index `first` on, coordinate k choosing
/// the mixture's component), judged in chunks of [`CHUNK`].
pub fn importance(space: &Space, opts: &BurstOptions, mc: &McOptions) -> Result<Importance> {
    mc.validate()?;
    opts.validate()?;
    space.check_importance()?;
    let k = space.dims();
    let (design, note) = match design_point(space, mc.seed)? {
        Ok(d) => (Some(d), None),
        Err(why) => (None, Some(why)),
    };
    let share = if design.is_some() { SHARE } else { 0.0 };
    let centre = design.as_ref().map_or(vec![0.0; k], |d| d.z.clone());
    let beta2: f64 = centre.iter().map(|x| x * x).sum();
    let points = super::Points::new(mc.sampler, mc.seed, k + 1)?;
    let end = mc.end(&points, "importance")?;
    let mut total = Importance::empty(design, note, share, mc.first, mc.level);
    let mut start = mc.first;
    let mut u = vec![0.0; k + 1];
    while start < end {
        let stop = (start + CHUNK).min(end);
        let (values, weights): (Vec<Vec<f64>>, Vec<f64>) = (start..stop)
            .map(|i| {
                points.point(i, &mut u);
                let shifted = u[k] < share;
                let z: Vec<f64> = u[..k]
                    .iter()
                    .zip(&centre)
                    .map(|(&u, &c)| normal_quantile(u) + if shifted { c } else { 0.0 })
                    .collect();
                let dot: f64 = z.iter().zip(&centre).map(|(a, b)| a * b).sum();
                let w = 1.0 / ((1.0 - share) + share * (dot - 0.5 * beta2).exp());
                (space.values_standard(&z), w)
            })
            .unzip();
        for (s, w) in evaluate(space, &values, opts).iter().zip(weights) {
            total.samples += 1;
            match &s.outcome {
                Ok(o) => {
                    total.judged += 1;
                    if o.bursting {
                        total.bursting += 1;
                        total.sum += w;
                        total.sum_sq += w * w;
                    }
                }
                Err(Failure::OutsideDomain(_) | Failure::Solver(_)) => total.excluded += 1,
            }
        }
        start = stop;
    }
    Ok(total.finish())
}
