//! The design check: how far a physical drive is from the bursting regime, and which single
//! change of k1, k2, C, T_am or backlash moves it across, by how much.
//!
//! "Bursting" is decided as everywhere else: the drive is reduced to dimensionless form and its
//! response simulated and measured ([`crate::burst::response`]); it bursts when bursts are
//! detected. When the reduced ω is below 1e-4 (a slow period beyond 63,000 time units, too long
//! to simulate routinely) the fast-subsystem spiking criterion decides instead
//! ([`crate::fast::SPIKING_THRESHOLD`]), and the report says so.
//!
//! For each parameter the factor f that first flips the verdict is searched on f = 2^k,
//! k = ±1 … ±6 (a change within ×1/64 … ×64; the side nearer to 1 wins), then refined by 12
//! bisections in log f (to 0.02 %). A scaled drive whose simulation needs more than
//! [`SEARCH_MAX_STEPS`] steps is judged by the criterion.

use crate::burst::{BurstOptions, classify, response};
use crate::error::Result;
use crate::fast::{SPIKING_THRESHOLD, analyze};
use crate::params::physical::{PhysicalParams, Reduction};
use serde::Serialize;

/// Parameters a designer can change, in the order reported (the mean load t_m too: it sets
/// where on the equilibrium curve the drive operates).
pub const DESIGN_PARAMETERS: [&str; 6] = ["k1", "k2", "c_eq", "t_am", "backlash", "t_m"];

/// How one parameter moves the drive across the bursting boundary.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Margin {
    /// Parameter name.
    pub parameter: &'static str,
    /// Its current value (SI).
    pub current: f64,
    /// Multiplicative factor that crosses the boundary (null if none within 1/64…64).
    pub factor: Option<f64>,
    /// The value at the boundary (SI).
    pub boundary_value: Option<f64>,
    /// (factor − 1)·100.
    pub change_percent: Option<f64>,
    /// `enters bursting` or `leaves bursting`.
    pub effect: &'static str,
}

/// The design check of a drive.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DesignCheck {
    /// The reduction.
    pub reduced: Reduction,
    /// γ − 1/(3α) at the reduced point.
    pub gamma_margin: f64,
    /// a at the steepest point of the equilibrium curve, x = 1/(3α) (the slow variable covers
    /// [−1, 1]; the further outside, the further the drive is from the steep part).
    pub steepest_point_a: f64,
    /// max(0, |steepest_point_a| − 1): how far the slow variable would have to go beyond its
    /// range to reach the steep part (0 when it is reached).
    pub distance_in_a: f64,
    /// Largest spiking ratio R of the fast subsystem and its threshold.
    pub spiking_ratio: f64,
    /// The threshold on R.
    pub spiking_threshold: f64,
    /// Whether the drive bursts now.
    pub bursting: bool,
    /// `simulation` or `fast-subsystem criterion` (see the module docs).
    pub basis: &'static str,
    /// Predicted mode (null when not simulated).
    pub mode: Option<&'static str>,
    /// Predicted mechanism (null when not simulated).
    pub mechanism: Option<&'static str>,
    /// One entry per changeable parameter.
    pub margins: Vec<Margin>,
}

/// Below this reduced ω the criterion replaces simulation.
pub const MIN_SIMULATED_OMEGA: f64 = 1e-4;

/// Step budget of one simulated verdict in the search (a scaled drive can need very small
/// steps, e.g. C/64 makes the reduced γ 4096 times larger); past it the criterion decides.
pub const SEARCH_MAX_STEPS: u64 = 2_000_000;

fn bursts(d: &PhysicalParams, opts: &BurstOptions) -> Result<bool> {
    let r = d.reduce()?;
    if r.params.omega >= MIN_SIMULATED_OMEGA {
        let mut o = *opts;
        o.tol.max_steps = SEARCH_MAX_STEPS;
        match response(&r.params, &o) {
            Ok(resp) => return Ok(resp.bursts_per_period > 0.0),
            Err(crate::Error::TooManySteps { .. }) => {}
            Err(e) => return Err(e),
        }
    }
    let an = analyze(&r.params, (-1.0, 1.0))?;
    Ok(an.equilibria.spiking_criterion.max_ratio > SPIKING_THRESHOLD)
}

fn scaled(d: &PhysicalParams, name: &str, f: f64) -> PhysicalParams {
    let mut e = *d;
    let v = d.get(name).expect("known name");
    e.set(name, v * f).expect("known name");
    e
}

/// Runs the design check.
pub fn design_check(d: &PhysicalParams, opts: &BurstOptions) -> Result<DesignCheck> {
    let r = d.reduce()?;
    let p = r.params;
    let an = analyze(&p, (-1.0, 1.0))?;
    let simulated = p.omega >= MIN_SIMULATED_OMEGA;
    let (bursting, mode, mechanism) = if simulated {
        let resp = response(&p, opts)?;
        let c = classify(&p, &resp);
        (
            resp.bursts_per_period > 0.0,
            Some(c.mode.name()),
            Some(c.mechanism.name()),
        )
    } else {
        (
            an.equilibria.spiking_criterion.max_ratio > SPIKING_THRESHOLD,
            None,
            None,
        )
    };
    let mut margins = Vec::new();
    for name in DESIGN_PARAMETERS {
        let current = d.get(name).expect("known");
        let mut found: Option<(f64, f64)> = None; // bracket (inside, outside) in log2 f
        if current != 0.0 {
            'search: for k in 1..=6 {
                for sign in [-1.0, 1.0] {
                    let lf = sign * k as f64;
                    if bursts(&scaled(d, name, lf.exp2()), opts)? != bursting {
                        found = Some((lf - sign, lf));
                        break 'search;
                    }
                }
            }
        }
        let factor = match found {
            None => None,
            Some((mut a, mut b)) => {
                for _ in 0..12 {
                    let m = 0.5 * (a + b);
                    if bursts(&scaled(d, name, m.exp2()), opts)? != bursting {
                        b = m;
                    } else {
                        a = m;
                    }
                }
                Some((0.5 * (a + b)).exp2())
            }
        };
        margins.push(Margin {
            parameter: name,
            current,
            factor,
            boundary_value: factor.map(|f| f * current),
            change_percent: factor.map(|f| 100.0 * (f - 1.0)),
            effect: if bursting {
                "leaves bursting"
            } else {
                "enters bursting"
            },
        });
    }
    let x0 = 1.0 / (3.0 * p.alpha);
    let steepest_point_a = (p.g(x0) - p.mu) / p.delta;
    Ok(DesignCheck {
        reduced: r,
        steepest_point_a,
        distance_in_a: (steepest_point_a.abs() - 1.0).max(0.0),
        gamma_margin: p.gamma - p.critical_gamma(),
        spiking_ratio: an.equilibria.spiking_criterion.max_ratio,
        spiking_threshold: SPIKING_THRESHOLD,
        bursting,
        basis: if simulated {
            "simulation"
        } else {
            "fast-subsystem criterion"
        },
        mode,
        mechanism,
        margins,
    })
}
