//! The worst case over the tolerance box and the margin: how far every parameter may move at
//! once before the verdict changes.
//!
//! The box's edges are each tolerance's [`Distribution::range`](super::Distribution::range).
//! From the nominal point a ray runs through each of the 2^k corners; on each ray the point at
//! scale s is nominal + s·(corner − nominal) (s = 1: the corner, s = 2: twice as far). Each ray
//! is judged at [`SCALES`] and its first change of verdict bracketed, then bisected
//! [`HALVINGS`] times in s. The verdict is discontinuous, so the rays are how it is refined:
//! the bracket ends carry the continuous measures of the responses just inside and outside.
//!
//! * The **worst corner**: the ray that changes soonest when the nominal set is burst-free
//!   (closest to bursting), the one that changes last when it bursts (furthest into bursting);
//!   rays without a change are ordered by the largest leading lobe, then the peak |x'|, at the
//!   corner.
//! * The **margin**: the least inside end over the rays, the scale of the box within which no
//!   corner changes the verdict.
//!
//! That the box at the margin holds no change inside is an assumption (a verdict monotone along
//! each parameter changes first at a corner); it is checked, not taken: [`INTERIOR`] points of a
//! Sobol sequence inside the box at the margin are judged, and those that differ counted.

use super::{Failure, Outcome, Sample, Space, evaluate};
use crate::burst::BurstOptions;
use crate::error::{Error, Result};
use serde::Serialize;

/// The scales each ray is judged at before bisection: the box in eighths, then beyond it up to
/// four times its size (where every parameter stays in its domain).
pub const SCALES: [f64; 12] = [
    0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1.0, 1.5, 2.0, 3.0, 4.0,
];

/// Halvings of each bracket in s (the bracket ends 1/8 · 2⁻¹² ≈ 3e-5 apart inside the box).
pub const HALVINGS: usize = 12;

/// Points judged inside the box at the margin to check it.
pub const INTERIOR: usize = 256;

/// Most toleranced parameters the corner enumeration takes (2^12 = 4096 rays).
pub const MAX_CORNER_DIMS: usize = 12;

/// One corner of the tolerance box and its ray.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Corner {
    /// −1 (low edge) or +1 (high edge) for each tolerance.
    pub signs: Vec<i8>,
    /// The parameters' values at the corner.
    pub values: Vec<f64>,
    /// The verdict at the corner (s = 1), or why there is none.
    pub outcome: std::result::Result<Outcome, Failure>,
    /// The bracket in s of the ray's first change of verdict: its end with the nominal verdict,
    /// its end with the other, and their outcomes. None: no change up to `reach`.
    pub crossing: Option<VerdictChange>,
    /// How far along the ray the verdict was searched (the last scale in the domain).
    pub reach: f64,
}

/// A bracketed change of verdict along a ray.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct VerdictChange {
    /// The end with the nominal verdict.
    pub inside: f64,
    /// The end with the other verdict.
    pub outside: f64,
    /// The outcome at `inside`.
    pub inside_outcome: Outcome,
    /// The outcome at `outside`.
    pub outside_outcome: Outcome,
}

/// The worst case and margin of a space.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WorstCase {
    /// The verdict at the nominal set.
    pub nominal: Outcome,
    /// Every corner with its ray.
    pub corners: Vec<Corner>,
    /// The worst corner's index into `corners`.
    pub worst: usize,
    /// The scale of the box within which no ray changes the verdict: the least inside end of the
    /// rays' brackets (None: no ray changes within its reach).
    pub margin: Option<f64>,
    /// The least reach of the rays (the margin is at least this when None).
    pub reach: f64,
    /// Each tolerance's edges of the box at the margin (or the reach), in % of its nominal
    /// value: (low, high).
    pub margin_percent: Vec<(f64, f64)>,
    /// Points judged inside the box at the margin (of 256; those without a verdict
    /// are not counted).
    pub interior_checked: usize,
    /// Of them, those whose verdict differs from the nominal one (0 when the corner rule held).
    pub interior_differing: usize,
}

fn point(nominal: &[f64], corner: &[f64], s: f64) -> Vec<f64> {
    nominal
        .iter()
        .zip(corner)
        .map(|(&n, &c)| n + s * (c - n))
        .collect()
}

/// Finds the worst corner and the margin of `space` (see the module docs).
pub fn worst_case(space: &Space, opts: &BurstOptions) -> Result<WorstCase> {
    let k = space.dims();
    if k > MAX_CORNER_DIMS {
        return Err(Error::InvalidInput {
            what: "worst case",
            text: format!("{k} tolerances"),
            reason: format!("the corner enumeration takes at most {MAX_CORNER_DIMS}"),
        });
    }
    opts.validate()?;
    let nom = space.nominal_values();
    let nominal = match evaluate(space, std::slice::from_ref(&nom), opts)
        .remove(0)
        .outcome
    {
        Ok(o) => o,
        Err(Failure::OutsideDomain(m) | Failure::Solver(m)) => {
            return Err(Error::InvalidInput {
                what: "nominal set",
                text: m,
                reason: "it has no verdict".into(),
            });
        }
    };
    let ranges: Vec<(f64, f64)> = space
        .tolerances
        .iter()
        .map(|t| t.distribution.range())
        .collect();
    let corners = corners(&ranges);
    // every ray at every scale, in one parallel batch
    let grid: Vec<Vec<f64>> = corners
        .iter()
        .flat_map(|(_, c)| SCALES.iter().map(|&s| point(&nom, c, s)))
        .collect();
    let judged = evaluate(space, &grid, opts);
    let mut rays: Vec<Corner> = corners
        .into_iter()
        .zip(judged.chunks(SCALES.len()))
        .map(|((signs, values), on_ray)| scan_ray(signs, values, on_ray, &nominal))
        .collect();
    bisect_rays(space, opts, &nom, &mut rays, &nominal);
    let better = |a: &Corner, b: &Corner| worse_than(a, b, nominal.bursting);
    let worst = (0..rays.len())
        .reduce(|w, i| if better(&rays[i], &rays[w]) { i } else { w })
        .unwrap_or(0);
    let margin = rays
        .iter()
        .filter_map(|r| r.crossing.as_ref().map(|c| c.inside))
        .reduce(f64::min);
    let reach = rays.iter().map(|r| r.reach).fold(f64::INFINITY, f64::min);
    let m = margin.unwrap_or(reach);
    let margin_percent = nom
        .iter()
        .zip(&ranges)
        .map(|(&n, &(lo, hi))| {
            (
                100.0 * m * (lo - n) / n.abs(),
                100.0 * m * (hi - n) / n.abs(),
            )
        })
        .collect();
    let inside = interior(space, opts, &nom, &ranges, m);
    let judged: Vec<&Outcome> = inside
        .iter()
        .filter_map(|s| s.outcome.as_ref().ok())
        .collect();
    let differing = judged
        .iter()
        .filter(|o| o.bursting != nominal.bursting)
        .count();
    Ok(WorstCase {
        nominal,
        corners: rays,
        worst,
        margin,
        reach,
        margin_percent,
        interior_checked: judged.len(),
        interior_differing: differing,
    })
}

/// The 2^k corners of the box with edges `ranges`: each one's signs (−1 low, +1 high) and values.
fn corners(ranges: &[(f64, f64)]) -> Vec<(Vec<i8>, Vec<f64>)> {
    (0..1usize << ranges.len())
        .map(|c| {
            let signs: Vec<i8> = (0..ranges.len())
                .map(|i| if c >> i & 1 == 1 { 1 } else { -1 })
                .collect();
            let values = signs
                .iter()
                .zip(ranges)
                .map(|(&s, &(lo, hi))| if s > 0 { hi } else { lo })
                .collect();
            (signs, values)
        })
        .collect()
}

/// A ray from its judged scales: its corner's outcome, its first change bracketed, its reach.
fn scan_ray(signs: Vec<i8>, values: Vec<f64>, on_ray: &[Sample], nominal: &Outcome) -> Corner {
    let at_corner = SCALES
        .iter()
        .position(|&s| s == 1.0)
        .expect("the box is a scale");
    let mut ray = Corner {
        signs,
        values,
        outcome: on_ray[at_corner].outcome.clone(),
        crossing: None,
        reach: 0.0,
    };
    let mut last: (f64, Outcome) = (0.0, *nominal);
    for (&s, sample) in SCALES.iter().zip(on_ray) {
        let Ok(o) = sample.outcome else { break };
        ray.reach = s;
        if o.bursting != nominal.bursting {
            ray.crossing = Some(VerdictChange {
                inside: last.0,
                outside: s,
                inside_outcome: last.1,
                outside_outcome: o,
            });
            break;
        }
        last = (s, o);
    }
    ray
}

/// Bisects every ray's bracket [`HALVINGS`] times, all rays' midpoints judged together.
fn bisect_rays(space: &Space, opts: &BurstOptions, nom: &[f64], rays: &mut [Corner], n: &Outcome) {
    for _ in 0..HALVINGS {
        let open: Vec<usize> = (0..rays.len())
            .filter(|&i| rays[i].crossing.is_some())
            .collect();
        let mids: Vec<Vec<f64>> = open
            .iter()
            .map(|&i| {
                let c = rays[i].crossing.as_ref().expect("filtered");
                point(nom, &rays[i].values, 0.5 * (c.inside + c.outside))
            })
            .collect();
        for (&i, sample) in open.iter().zip(evaluate(space, &mids, opts)) {
            let c = rays[i].crossing.as_mut().expect("filtered");
            let mid = 0.5 * (c.inside + c.outside);
            match sample.outcome {
                Ok(o) if o.bursting == n.bursting => (c.inside, c.inside_outcome) = (mid, o),
                Ok(o) => (c.outside, c.outside_outcome) = (mid, o),
                // a failure inside a bracket of two verdicts: the bracket stays as it is
                Err(_) => {}
            }
        }
    }
}

/// Whether ray `a` is worse than `b` (see the module docs).
fn worse_than(a: &Corner, b: &Corner, nominal_bursting: bool) -> bool {
    let at = |r: &Corner| r.crossing.as_ref().map_or(f64::INFINITY, |c| c.inside);
    let (sa, sb) = (at(a), at(b));
    if sa != sb {
        return if nominal_bursting { sa > sb } else { sa < sb };
    }
    let measure = |r: &Corner| match &r.outcome {
        Ok(o) => (o.measures[2], o.measures[1]),
        Err(_) => (f64::NEG_INFINITY, f64::NEG_INFINITY),
    };
    let (ma, mb) = (measure(a), measure(b));
    ma.0 > mb.0 || (ma.0 == mb.0 && ma.1 > mb.1)
}

/// [`INTERIOR`] Sobol points inside the box at scale `m`, judged.
fn interior(
    space: &Space,
    opts: &BurstOptions,
    nom: &[f64],
    ranges: &[(f64, f64)],
    m: f64,
) -> Vec<Sample> {
    if m <= 0.0 {
        return Vec::new();
    }
    let Ok(points) = super::Points::new(super::Sampler::Sobol, 0x5EED, nom.len()) else {
        return Vec::new();
    };
    let values: Vec<Vec<f64>> = (0..INTERIOR as u64)
        .map(|i| {
            let mut u = vec![0.0; nom.len()];
            points.point(i, &mut u);
            u.iter()
                .zip(nom.iter().zip(ranges))
                .map(|(&u, (&n, &(lo, hi)))| n + m * (lo + u * (hi - lo) - n))
                .collect()
        })
        .collect();
    evaluate(space, &values, opts)
}
