//! The passage near the cusp: where the traversed curve turns from focus to node and back about
//! the inflection, the prediction reduces to one problem with two numbers.
//!
//! About the inflection x_i = 1/(3α) the cubic is exactly g(x) = g(x_i) + g'_min·(x − x_i) +
//! α(x − x_i)³ (g'' = 0 there), with g'_min = γ − 1/(3α). With y = √(3α)·(x − x_i) and the load
//! linearised about the time τ = 0 the equilibrium passes x_i, a ≈ a_i + ω·√(1 − a_i²)·τ,
//! x'' + x' + g(x) = μ + δa becomes
//!
//! y'' + y' + g'_min·y + y³/3 = s·τ,   s = √(3α)·δ·ω·√(1 − a_i²),
//!
//! the same for every α, ε, μ, δ and ω. Whether its passage rings, that is whether y' has more
//! than the one extremum of its pulse, depends only on the ramp rate s against a threshold
//! s_c(g'_min) that [`ramp_threshold`] computes by integrating this normal form. The only
//! approximation is the linearised sine over the passage. Far from the cusp the same question is
//! answered by the forcing rate κ of [`super::predict`] on the focus part; near it, where a node
//! part lies between the two focus parts, the state lags through the node and enters the focus
//! part with a lag it then rings about, which κ does not see.

use crate::error::Result;
use crate::integrate::events::{Detector, Direction};
use crate::integrate::{Dop853, Options, System};
use serde::Serialize;
use std::sync::OnceLock;

/// The passage is integrated between the points where g' = 16 · (the node–focus edge 1/4) = 4:
/// there the focus rings at √(g' − 1/4) ≈ 1.9, eight times faster than near the edge where the
/// passage excites it, and the equilibrium's lag is 1/g'² = 1/16 of the edge's. Starting and
/// ending further out, at g' = 16 or 64, gives the same thresholds (`tests/burst.rs`).
pub const PASSAGE_GPRIME: f64 = 4.0;

/// A swing of y' smaller than this fraction of the pulse is not counted (the integration's
/// error is far below it). Near the cusp the extra extrema of ringing appear in pairs whose swing
/// grows quickly from zero at the threshold, so a decade either way moves the threshold by less
/// than 2 % for g'_min ≤ 0.2 (`tests/burst.rs`). Close to 1/4, where the node part vanishes,
/// ringing sets in gradually and the floor matters more (a floor ten times higher finds none at
/// g'_min = 0.2475); there the κ criterion, which the prediction also applies, decides.
pub const SWING_FRACTION: f64 = 1e-5;

/// Relative tolerance of [`ramp_threshold`] (the bisection in ln s stops at this width).
pub const THRESHOLD_REL_TOL: f64 = 1e-4;

/// The normal form's right-hand side, state [y, y'].
struct NormalForm {
    gprime_min: f64,
    ramp: f64,
}

impl System<2> for NormalForm {
    fn rhs(&self, t: f64, y: &[f64; 2]) -> [f64; 2] {
        [y[1], self.accel(t, y)]
    }
}

impl NormalForm {
    fn static_torque(&self, y: f64) -> f64 {
        self.gprime_min * y + y * y * y / 3.0
    }

    fn accel(&self, t: f64, y: &[f64; 2]) -> f64 {
        self.ramp * t - y[1] - self.static_torque(y[0])
    }
}

/// Whether the passage of the normal form with g'_min = `gprime_min` ≥ 0 at ramp rate `ramp` > 0
/// rings: y' has three or more extrema between the run's ends once swings below `swing_fraction`
/// of the pulse are pruned (the burst scan's rule, [`SWING_FRACTION`] by default). The state
/// starts on the equilibrium y* with g'(y*) = `edge` ([`PASSAGE_GPRIME`] by default), with its
/// first-order lag y*'/g' and speed y*', and the run ends where the equilibrium is as far on the
/// other side.
pub fn passage_rings(gprime_min: f64, ramp: f64, swing_fraction: f64, edge: f64) -> Result<bool> {
    let nf = NormalForm { gprime_min, ramp };
    let y_edge = (edge - gprime_min).max(0.0).sqrt();
    let t_end = nf.static_torque(y_edge) / ramp;
    let speed = ramp / edge;
    let y0 = [-y_edge - speed / edge, speed];
    let mut solver = Dop853::new(&nf, -t_end, y0, Options::default())?;
    let mut extrema = Detector::new(|t, y: &[f64; 2]| nf.accel(t, y), Direction::Either);
    let mut values = vec![y0[1]];
    while solver.t() < t_end {
        solver.step(t_end)?;
        let dense = solver.dense();
        extrema.scan(&dense, |c| values.push(c.y[1]));
    }
    values.push(solver.y()[1]);
    Ok(interior_extrema(&values, swing_fraction) >= 3)
}

/// How many extrema of y' are left between the run's two ends once swings below
/// `swing_fraction` of the pulse are pruned. `values` holds y' at the start, at each extremum and
/// at the end. A swing below the floor removes the extremum it would create with its partner;
/// the ends are never removed, so the flat tails, where y'' is the difference of two nearly
/// equal torques and its sign is rounding, leave nothing behind.
fn interior_extrema(values: &[f64], swing_fraction: f64) -> usize {
    let floor = swing_fraction * values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let (Some(&first), Some(&last)) = (values.first(), values.last()) else {
        return 0;
    };
    let mut kept = vec![first];
    for &v in &values[1..values.len() - 1] {
        let small = kept.last().is_some_and(|&k| (v - k).abs() < floor);
        match (small, kept.len()) {
            (false, _) => kept.push(v),
            (true, 1) => {} // next to the start: the swing is the tail's
            (true, _) => {
                kept.pop();
            }
        }
    }
    if kept.len() > 1 && kept.last().is_some_and(|&k| (last - k).abs() < floor) {
        kept.pop();
    }
    kept.len() - 1
}

/// The least ramp rate s at which the passage rings ([`passage_rings`] with the defaults), by
/// bisection in ln s to [`THRESHOLD_REL_TOL`] between 1e-4 (no passage rings: the pulse is
/// 10⁴ times slower than the fast mode) and 10 (every passage rings).
pub fn ramp_threshold_at(gprime_min: f64, swing_fraction: f64, edge: f64) -> Result<f64> {
    let (lo, hi) = crate::roots::try_bisect(
        1e-4f64.ln(),
        10f64.ln(),
        usize::MAX,
        |l, h| h - l <= THRESHOLD_REL_TOL,
        |m| {
            Ok::<bool, crate::error::Error>(!passage_rings(
                gprime_min,
                m.exp(),
                swing_fraction,
                edge,
            )?)
        },
    )?;
    Ok((0.5 * (lo + hi)).exp())
}

/// Spacing in g'_min of the table [`ramp_threshold`] interpolates (ln s_c is smooth in g'_min:
/// linear interpolation over this spacing is within the threshold's own tolerance, checked
/// against direct solves between the nodes in `tests/burst.rs`).
pub const TABLE_STEP: f64 = NODE_FOCUS / INTERVALS as f64;

/// The normal form's focus threshold c²/4 at its unit damping (c = 1, the study's): the table
/// covers the node part below it.
const NODE_FOCUS: f64 = 0.25;

/// Intervals of the table over 0 ≤ g'_min ≤ 1/4.
const INTERVALS: usize = 50;

/// Nodes of the table: g'_min = 0, [`TABLE_STEP`], …, 1/4.
const NODES: usize = INTERVALS + 1;

/// ln s_c at node `j`, solved the first time it is asked for (each solve takes a few
/// milliseconds; a prediction needs two nodes).
fn node(j: usize) -> Option<f64> {
    static TABLE: [OnceLock<Option<f64>>; NODES] = [const { OnceLock::new() }; NODES];
    *TABLE[j].get_or_init(|| {
        ramp_threshold_at(j as f64 * TABLE_STEP, SWING_FRACTION, PASSAGE_GPRIME)
            .map(f64::ln)
            .ok()
    })
}

/// s_c(g'_min): the least ramp rate at which the passage near the cusp rings, for
/// 0 ≤ g'_min ≤ 1/4 (`None` outside, or if the normal form could not be solved). Interpolated
/// linearly in ln s_c between the nodes of a table spaced [`TABLE_STEP`] apart, each solved
/// once per process when first needed.
///
/// ```
/// let s0 = hdgear::fast::ramp_threshold(0.0).unwrap();
/// let s1 = hdgear::fast::ramp_threshold(0.2).unwrap();
/// assert!(s0 > 1e-3 && s1 > s0); // a stiffer node part needs a faster ramp
/// ```
pub fn ramp_threshold(gprime_min: f64) -> Option<f64> {
    if !(0.0..=NODE_FOCUS).contains(&gprime_min) {
        return None;
    }
    let u = gprime_min / TABLE_STEP;
    let j = (u.floor() as usize).min(NODES - 2);
    let f = u - j as f64;
    Some(((1.0 - f) * node(j)? + f * node(j + 1)?).exp())
}

/// The passage near the cusp a prediction judged (see the module docs).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CuspPassage {
    /// g'_min = γ − 1/(3α), the stiffness at the inflection (0 ≤ g'_min < 1/4: a node there).
    pub gprime_min: f64,
    /// a_i, the load at which the equilibrium passes the inflection.
    pub at_a: f64,
    /// The ramp rate s = √(3α)·δ·ω·√(1 − a_i²).
    pub ramp_rate: f64,
    /// s_c(g'_min): ringing is predicted for s above it.
    pub threshold: f64,
}

impl CuspPassage {
    /// Whether the passage is predicted to ring.
    pub fn rings(&self) -> bool {
        self.ramp_rate > self.threshold
    }
}
