//! The two-inertia drive advanced one communication step at a time by a host (an FMU's
//! `fmi2DoStep`, a MuJoCo coupling): the torques the host applies are held over each step, and
//! hdgear's own stepper runs to the step's end with every law of the drive (the state carries
//! over from step to step).

use super::model::Physical;
use crate::error::{Error, Result};
use crate::integrate::{Options, Stats};
use serde::Serialize;

/// What a host reads of the drive after a step.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct DriveOutputs {
    /// θi, the input (wave generator) angle \[rad\].
    pub phi_in: f64,
    /// θi' \[rad/s\].
    pub w_in: f64,
    /// θo, the output angle \[rad\].
    pub phi_out: f64,
    /// θo' \[rad/s\].
    pub w_out: f64,
    /// θ = θo − θi/N, the twist \[rad\].
    pub twist: f64,
    /// θ' \[rad/s\].
    pub twist_rate: f64,
    /// The torque across the compliance \[N m\] ([`Physical::twist_torque`]): what the drive
    /// transmits to its output.
    pub tau_gear: f64,
}

/// A drive being co-simulated: its laws, the time and the state reached. `Copy`, so that a
/// host saves and restores it by value (FMI's get and set FMU state).
///
/// ```
/// use hdgear::integrate::Options;
/// use hdgear::physical::{PhysicalParams, model::Physical, cosim::CoSimulation};
/// let d = PhysicalParams { j_in: 1e-4, j_out: 1.0, ratio: 50.0, k1: 2e3, k2: 1e9,
///     backlash: 1e-3, c_eq: 5.0, t_m: 0.0, t_am: 0.0, omega: 1.0 };
/// let mut drive = CoSimulation::new(Physical::new(d), 0.0, Options::default()).unwrap();
/// // 1 N m on the output up to t = 0.01, then nothing up to t = 0.02 (seconds)
/// drive.advance(0.01, 0.0, 1.0).unwrap();
/// drive.advance(0.02, 0.0, 0.0).unwrap();
/// assert!(drive.outputs().w_out > 0.0);
/// assert!(drive.advance(0.01, 0.0, 0.0).is_err()); // backwards
/// ```
#[derive(Clone, Copy, Debug)]
pub struct CoSimulation {
    sys: Physical,
    t: f64,
    z: [f64; 4],
    tol: Options,
    stats: Stats,
}

impl CoSimulation {
    /// The drive at rest at time `t0` \[s\], integrated with `tol` (its absolute tolerance in
    /// units of the drive's angle scale, as `hdgear physical --simulate` takes it,
    /// [`super::simulate::angle_scale`]). Fails on a drive out of its domain.
    pub fn new(sys: Physical, t0: f64, tol: Options) -> Result<CoSimulation> {
        let d = sys.drive();
        d.validate()?;
        if !t0.is_finite() {
            return Err(Error::InvalidOption {
                name: "start time",
                value: t0,
                reason: "must be finite",
            });
        }
        let tol = Options {
            atol: tol.atol * super::simulate::angle_scale(d),
            ..tol
        };
        Ok(CoSimulation {
            sys,
            t: t0,
            z: [0.0; 4],
            tol,
            stats: Stats::default(),
        })
    }

    /// Advances to `t_end` \[s\] with `motor` and `load` \[N m\] applied throughout
    /// ([`Physical::with_inputs`]). The steps end at `t_end` exactly; the state is kept. On an
    /// error (a backward or non-finite end, a non-finite torque, a failed integration) the drive
    /// is left where it was.
    pub fn advance(&mut self, t_end: f64, motor: f64, load: f64) -> Result<()> {
        if !(t_end.is_finite() && t_end > self.t) {
            return Err(Error::InvalidOption {
                name: "communication point",
                value: t_end,
                reason: "must be finite and after the drive's time",
            });
        }
        for (name, value) in [("tau_motor", motor), ("tau_load", load)] {
            if !value.is_finite() {
                return Err(Error::InvalidOption {
                    name,
                    value,
                    reason: "must be finite",
                });
            }
        }
        let sys = self.sys.with_inputs(motor, load);
        let span = t_end - self.t;
        let (z, stats) =
            crate::integrate::sample(&sys, self.t, self.z, t_end, span, self.tol, |_, _| {})?;
        (self.t, self.z) = (t_end, z);
        self.stats.steps += stats.steps;
        self.stats.rejected += stats.rejected;
        self.stats.rhs_evals += stats.rhs_evals;
        Ok(())
    }

    /// The time reached \[s\].
    pub fn time(&self) -> f64 {
        self.t
    }

    /// The drive's laws.
    pub fn system(&self) -> &Physical {
        &self.sys
    }

    /// The integrator's work so far, over every step.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// Angles, rates and the transmitted torque at the time reached.
    pub fn outputs(&self) -> DriveOutputs {
        let [phi_in, w_in, phi_out, w_out, twist, twist_rate] = self.sys.from_internal(&self.z);
        DriveOutputs {
            phi_in,
            w_in,
            phi_out,
            w_out,
            twist,
            twist_rate,
            tau_gear: self.sys.twist_torque(twist, twist_rate),
        }
    }
}
