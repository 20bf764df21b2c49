//! Simulating the two-inertia drive in SI units.

use crate::error::Result;
use crate::integrate::{Options, Stats};
use serde::Serialize;

/// A sample of the physical simulation: the CSV columns `t,theta_in,theta_out,theta,theta_dot`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PhysicalSample {
    /// Time \[s\].
    pub t: f64,
    /// θi \[rad\].
    pub theta_in: f64,
    /// θo \[rad\].
    pub theta_out: f64,
    /// θ = θo − θi/N \[rad\].
    pub theta: f64,
    /// θ' \[rad/s\].
    pub theta_dot: f64,
}
crate::record!(PhysicalSample: "t", "theta_in", "theta_out", "theta", "theta_dot");

/// The outcome of a physical simulation besides its samples.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PhysicalSummary {
    /// Final time \[s\].
    pub t_end: f64,
    /// Final state.
    pub final_state: PhysicalSample,
    /// Final input and output rates \[rad/s\].
    pub final_rates: [f64; 2],
    /// Integrator work.
    pub stats: Stats,
    /// The angle scale Θ \[rad\] the absolute tolerance was multiplied by.
    pub angle_scale: f64,
}

/// The angle scale Θ \[rad\] of a drive: the length scale L where the reduction exists, else the
/// static twist under |T_m| + T_am (or 1 rad when nothing loads the drive). Absolute tolerances
/// of the physical simulation are in units of Θ.
pub fn angle_scale(d: &super::PhysicalParams) -> f64 {
    if let Ok(r) = d.reduce() {
        return r.length_scale;
    }
    let load = d.t_m.abs() + d.t_am;
    if load > 0.0 && (d.k1 > 0.0 || d.k2 > 0.0) {
        super::catalogue::cubic_twist(d.k1, d.k2, load).max(d.backlash)
    } else if d.backlash > 0.0 {
        d.backlash
    } else {
        1.0
    }
}

/// Simulates the two-inertia drive from rest (all angles and rates zero) to `t_end` seconds,
/// calling `out` every `dt` seconds (dense output). `tol.atol` is taken in units of
/// [`angle_scale`].
pub fn simulate_physical(
    d: &super::PhysicalParams,
    t_end: f64,
    dt: f64,
    tol: Options,
    mut out: impl FnMut(&PhysicalSample),
) -> Result<PhysicalSummary> {
    d.validate()?;
    if let Ok(r) = d.reduce() {
        crate::integrate::check_budget(t_end / r.time_scale, &tol)?;
    }
    let sys = super::model::Physical::new(*d);
    let scale = angle_scale(d);
    let tol = Options {
        atol: tol.atol * scale,
        ..tol
    };
    let z0 = [0.0; 4];
    let sample = |t: f64, z: &[f64; 4]| {
        let s = sys.from_internal(z);
        PhysicalSample {
            t,
            theta_in: s[0],
            theta_out: s[2],
            theta: s[4],
            theta_dot: s[5],
        }
    };
    let (z, stats) =
        crate::integrate::sample(&sys, 0.0, z0, t_end, dt, tol, |t, z| out(&sample(t, z)))?;
    let s = sys.from_internal(&z);
    Ok(PhysicalSummary {
        t_end,
        final_state: sample(t_end, &z),
        final_rates: [s[1], s[3]],
        stats,
        angle_scale: scale,
    })
}
