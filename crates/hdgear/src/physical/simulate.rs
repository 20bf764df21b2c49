//! Simulating the two-inertia drive in SI units.

use crate::error::Result;
use crate::integrate::{Options, Stats};
use serde::Serialize;

/// A sample of the physical simulation: the CSV columns `t,theta_in,theta_out,theta,theta_dot`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, crate::output::Record)]
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
    /// Friction at the bearings.
    pub bearings: super::model::Bearings,
    /// Friction across the compliance, in SI units.
    pub twist_friction: Option<crate::model::terms::AnyTerm>,
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
    out: impl FnMut(&PhysicalSample),
) -> Result<PhysicalSummary> {
    simulate_drive(&super::model::Physical::new(*d), t_end, dt, tol, out)
}

/// [`simulate_physical`] of a drive with friction at its bearings
/// ([`super::model::Bearings`]).
///
/// ```
/// use hdgear::integrate::Options;
/// use hdgear::model::terms::AnyTerm;
/// use hdgear::physical::{PhysicalParams, model::{Bearings, Physical}, simulate::simulate_drive};
/// let d = PhysicalParams { j_in: 1e-4, j_out: 1.0, ratio: 50.0, k1: 2e3, k2: 1e9,
///     backlash: 1e-3, c_eq: 5.0, t_m: 1.0, t_am: 0.5, omega: 1.0 };
/// let output = AnyTerm::new("stribeck", &[0.8, 1.2, 0.05, 0.01, 1e-3]).unwrap();
/// let sys = Physical::with_bearings(d, Bearings::new(Some(output), None).unwrap());
/// let s = simulate_drive(&sys, 0.05, 0.05, Options::default(), |_| {}).unwrap();
/// assert!(s.final_state.theta.is_finite());
/// ```
pub fn simulate_drive(
    sys: &super::model::Physical,
    t_end: f64,
    dt: f64,
    tol: Options,
    mut out: impl FnMut(&PhysicalSample),
) -> Result<PhysicalSummary> {
    let d = sys.drive();
    d.validate()?;
    if let Ok(r) = d.reduce() {
        crate::integrate::check_budget(t_end / r.time_scale, &tol)?;
    }
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
        crate::integrate::sample(sys, 0.0, z0, t_end, dt, tol, |t, z| out(&sample(t, z)))?;
    let s = sys.from_internal(&z);
    Ok(PhysicalSummary {
        t_end,
        final_state: sample(t_end, &z),
        final_rates: [s[1], s[3]],
        stats,
        angle_scale: scale,
        bearings: sys.bearings(),
        twist_friction: sys.twist_friction(),
    })
}

/// How closely the two-inertia model and its reduction agree: both simulated from rest over
/// `tau_end` dimensionless time units, sampled every `dt` of them, compared as θ(t) = L·x(t/T).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ReductionCheck {
    /// Dimensionless span simulated.
    pub tau_end: f64,
    /// Tolerance (rtol = atol) of both simulations.
    pub tol: f64,
    /// Largest |θ − L·x| over the largest |L·x|.
    pub theta: f64,
    /// Largest |θ' − (L/T)·x'| over the largest |(L/T)·x'|.
    pub theta_dot: f64,
    /// Largest mismatch of the sample times, t/T − τ.
    pub time: f64,
}

/// Simulates `d` and its reduced model side by side (see [`ReductionCheck`]); fails when the
/// drive has no reduction.
pub fn check_reduction(
    d: &super::PhysicalParams,
    tau_end: f64,
    dt: f64,
    tol: f64,
) -> Result<ReductionCheck> {
    let r = d.reduce()?;
    let opts = Options {
        rtol: tol,
        atol: tol,
        ..Options::default()
    };
    let mut phys = Vec::new();
    simulate_physical(d, r.time(tau_end), r.time(dt), opts, |s| {
        phys.push((s.t, s.theta, s.theta_dot));
    })?;
    let mut red = Vec::new();
    crate::simulate::simulate(
        &r.params,
        &crate::simulate::SimOptions {
            t_end: tau_end,
            dt,
            start: crate::simulate::Start::Rest,
            tol: opts,
        },
        |t, y| red.push((t, r.theta(y[0]), r.theta_dot(y[1]))),
    )?;
    let peak = |f: fn(&(f64, f64, f64)) -> f64| red.iter().map(f).fold(0.0, f64::max);
    let (scale, rate_scale) = (peak(|q| q.1.abs()), peak(|q| q.2.abs()));
    let mut out = ReductionCheck {
        tau_end,
        tol,
        theta: 0.0,
        theta_dot: 0.0,
        time: if phys.len() == red.len() {
            0.0
        } else {
            f64::INFINITY
        },
    };
    for (p, q) in phys.iter().zip(&red) {
        out.time = out.time.max((r.tau(p.0) - q.0).abs());
        out.theta = out.theta.max((p.1 - q.1).abs() / scale);
        out.theta_dot = out.theta_dot.max((p.2 - q.2).abs() / rate_scale);
    }
    Ok(out)
}

/// What produced a physical trajectory: the `meta` of its JSON output.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PhysicalSetup {
    /// The drive.
    pub drive: super::PhysicalParams,
    /// Friction at its bearings.
    pub bearings: super::model::Bearings,
    /// Friction across the compliance, in SI units.
    pub twist_friction: Option<crate::model::terms::AnyTerm>,
    /// Duration \[s\].
    pub t_end: f64,
    /// Sample spacing \[s\].
    pub dt: f64,
}

/// The final state of a physical run by name.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FinalState {
    /// θ \[rad\].
    pub theta: f64,
    /// θ' \[rad/s\].
    pub theta_dot: f64,
    /// θi \[rad\].
    pub theta_in: f64,
    /// θo \[rad\].
    pub theta_out: f64,
    /// θi' \[rad/s\].
    pub theta_in_dot: f64,
    /// θo' \[rad/s\].
    pub theta_out_dot: f64,
}

/// What `hdgear physical --simulate --summary` prints.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SimulationSummary {
    /// Final time \[s\].
    pub t_end: f64,
    /// Final state.
    #[serde(rename = "final")]
    pub final_state: FinalState,
    /// Integrator work.
    pub stats: Stats,
    /// The angle scale Θ \[rad\] of the absolute tolerance.
    pub angle_scale: f64,
    /// Friction at the bearings (none: the drive as the study has it).
    pub bearings: super::model::Bearings,
    /// Friction across the compliance, in SI units (none: the drive as the study has it).
    pub twist_friction: Option<crate::model::terms::AnyTerm>,
}

impl PhysicalSummary {
    /// The printed summary.
    pub fn report(&self) -> SimulationSummary {
        let f = self.final_state;
        SimulationSummary {
            t_end: self.t_end,
            final_state: FinalState {
                theta: f.theta,
                theta_dot: f.theta_dot,
                theta_in: f.theta_in,
                theta_out: f.theta_out,
                theta_in_dot: self.final_rates[0],
                theta_out_dot: self.final_rates[1],
            },
            stats: self.stats,
            angle_scale: self.angle_scale,
            bearings: self.bearings,
            twist_friction: self.twist_friction,
        }
    }
}
