//! One FMU instance: FMI 2.0's co-simulation state machine, the variables by value reference,
//! and the drive being stepped.

use super::{FmuDrive, Role, Slot, Variable};
use crate::integrate::Options;
use crate::physical::cosim::CoSimulation;
use serde::Serialize;

/// Where an instance is in FMI 2.0's co-simulation state machine.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Phase {
    /// After `fmi2Instantiate` (and `fmi2Reset`): parameters may be set.
    Instantiated,
    /// Between `fmi2EnterInitializationMode` and `fmi2ExitInitializationMode`.
    Initialisation,
    /// Stepping: `fmi2DoStep`, inputs set, outputs read.
    Stepping,
    /// After `fmi2Terminate`: outputs read, nothing else but reset.
    Terminated,
    /// After an error: only reset (and freeing).
    Failed,
}

/// Why an FMU call was refused: what the exported library logs before it returns `fmi2Error`.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FmuError {
    /// No variable has this value reference.
    #[error("no variable has value reference {0}")]
    UnknownReference(u32),
    /// The call is not allowed where the instance is.
    #[error("{call} is not allowed in phase {phase:?}")]
    WrongPhase {
        /// The FMI function.
        call: &'static str,
        /// Where the instance is.
        phase: Phase,
    },
    /// The variable may not be set now (an output; a parameter after initialisation).
    #[error("{name} cannot be set in phase {phase:?}")]
    NotSettable {
        /// The variable.
        name: String,
        /// Where the instance is.
        phase: Phase,
    },
    /// A value out of its domain, or a failed step: hdgear's own error.
    #[error(transparent)]
    Model(#[from] crate::error::Error),
    /// The host's communication point is not where the drive is.
    #[error("communication point {given} is not the drive's time {at}")]
    CommunicationPoint {
        /// The host's point.
        given: f64,
        /// The drive's time.
        at: f64,
    },
}

/// One FMU instance: its values, its phase and, once initialised, the drive being stepped.
/// `Clone`, so that a host's saved FMU state is a copy of it.
///
/// ```
/// use hdgear::physical::{PhysicalParams, model::Physical};
/// use hdgear::physical::fmu::{FmuDrive, Instance};
/// let d = PhysicalParams { j_in: 1e-4, j_out: 1.0, ratio: 50.0, k1: 2e3, k2: 1e9,
///     backlash: 1e-3, c_eq: 5.0, t_m: 0.0, t_am: 0.0, omega: 1.0 };
/// let spec = FmuDrive::new("demo", &Physical::new(d), 1e-10).unwrap();
/// let vr = |name: &str| spec.variables().iter().position(|v| v.name == name).unwrap() as u32;
/// let mut fmu = Instance::new(spec.clone());
/// fmu.setup(None, 0.0).unwrap();
/// fmu.enter_initialisation().unwrap();
/// fmu.exit_initialisation().unwrap();
/// fmu.set_real(vr("tau_load"), 1.0).unwrap();
/// fmu.do_step(0.0, 0.01).unwrap();
/// assert!(fmu.get_real(vr("w_out")).unwrap() > 0.0);
/// assert!(fmu.set_real(vr("k1"), 1.0).is_err()); // a parameter, after initialisation
/// ```
#[derive(Clone, Debug)]
pub struct Instance {
    /// The values as set by the host.
    spec: FmuDrive,
    /// The values the instance was made with, the description's start values (for reset).
    start: FmuDrive,
    variables: Vec<Variable>,
    inputs: [f64; 2],
    t0: f64,
    tolerance: f64,
    phase: Phase,
    run: Option<CoSimulation>,
}

impl Instance {
    /// An instance of the drive, instantiated.
    pub fn new(spec: FmuDrive) -> Instance {
        Instance {
            variables: spec.variables(),
            tolerance: spec.tolerance,
            start: spec.clone(),
            spec,
            inputs: [0.0; 2],
            t0: 0.0,
            phase: Phase::Instantiated,
            run: None,
        }
    }

    /// Where the instance is.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// The time the drive has reached, once initialised.
    pub fn time(&self) -> Option<f64> {
        self.run.as_ref().map(CoSimulation::time)
    }

    fn expect(&mut self, call: &'static str, allowed: &[Phase]) -> Result<(), FmuError> {
        if allowed.contains(&self.phase) {
            Ok(())
        } else {
            Err(FmuError::WrongPhase {
                call,
                phase: self.phase,
            })
        }
    }

    /// Marks the instance failed when `r` is an error (FMI: after `fmi2Error` only reset).
    fn failing<T>(&mut self, r: Result<T, FmuError>) -> Result<T, FmuError> {
        if r.is_err() {
            self.phase = Phase::Failed;
        }
        r
    }

    /// `fmi2SetupExperiment`: the tolerance, if the host gives one, and the start time.
    pub fn setup(&mut self, tolerance: Option<f64>, start: f64) -> Result<(), FmuError> {
        self.expect("fmi2SetupExperiment", &[Phase::Instantiated])?;
        for (name, value) in [
            ("tolerance", tolerance.unwrap_or(1e-10)),
            ("startTime", start),
        ] {
            if !value.is_finite() || (name == "tolerance" && value <= 0.0) {
                return Err(crate::error::Error::InvalidOption {
                    name,
                    value,
                    reason: "must be finite (a tolerance > 0)",
                }
                .into());
            }
        }
        if let Some(tol) = tolerance {
            self.tolerance = tol;
        }
        self.t0 = start;
        Ok(())
    }

    /// `fmi2EnterInitializationMode`.
    pub fn enter_initialisation(&mut self) -> Result<(), FmuError> {
        self.expect("fmi2EnterInitializationMode", &[Phase::Instantiated])?;
        self.phase = Phase::Initialisation;
        Ok(())
    }

    /// `fmi2ExitInitializationMode`: the drive from its parameters, at rest at the start time.
    /// Fails, naming the value, on a parameter out of its domain.
    pub fn exit_initialisation(&mut self) -> Result<(), FmuError> {
        self.expect("fmi2ExitInitializationMode", &[Phase::Initialisation])?;
        let run = self.start();
        self.run = Some(self.failing(run)?);
        self.phase = Phase::Stepping;
        Ok(())
    }

    fn start(&self) -> Result<CoSimulation, FmuError> {
        let opts = Options {
            rtol: self.tolerance,
            atol: self.tolerance,
            ..Options::default()
        };
        Ok(CoSimulation::new(self.spec.physical()?, self.t0, opts)?)
    }

    /// `fmi2DoStep` from `current` over `h` seconds, the inputs held.
    pub fn do_step(&mut self, current: f64, h: f64) -> Result<(), FmuError> {
        self.expect("fmi2DoStep", &[Phase::Stepping])?;
        let [motor, load] = self.inputs;
        let r = match self.run.as_mut() {
            Some(run) => {
                let at = run.time();
                if (current - at).abs() > 1e-9 * at.abs().max(1.0) {
                    Err(FmuError::CommunicationPoint { given: current, at })
                } else {
                    run.advance(current + h, motor, load)
                        .map_err(FmuError::from)
                }
            }
            None => Err(FmuError::WrongPhase {
                call: "fmi2DoStep",
                phase: self.phase,
            }),
        };
        self.failing(r)
    }

    /// `fmi2Terminate`.
    pub fn terminate(&mut self) -> Result<(), FmuError> {
        self.expect("fmi2Terminate", &[Phase::Stepping])?;
        self.phase = Phase::Terminated;
        Ok(())
    }

    /// `fmi2Reset`: back to instantiated, with the FMU's own start values.
    pub fn reset(&mut self) {
        *self = Instance::new(self.start.clone());
    }

    fn variable(&self, vr: u32) -> Result<&Variable, FmuError> {
        self.variables
            .get(vr as usize)
            .ok_or(FmuError::UnknownReference(vr))
    }

    /// `fmi2SetReal` of one variable: a parameter before the end of initialisation, an input
    /// before initialisation or while stepping. A non-finite value is refused.
    pub fn set_real(&mut self, vr: u32, value: f64) -> Result<(), FmuError> {
        let v = self.variable(vr)?.clone();
        let settable = match v.role {
            Role::Parameter(_) => matches!(self.phase, Phase::Instantiated | Phase::Initialisation),
            Role::Input => matches!(
                self.phase,
                Phase::Instantiated | Phase::Initialisation | Phase::Stepping
            ),
            Role::Output => false,
        };
        if !settable {
            return Err(FmuError::NotSettable {
                name: v.name,
                phase: self.phase,
            });
        }
        if !value.is_finite() {
            return Err(crate::error::Error::InvalidParameter {
                name: v.name,
                value,
                reason: "must be finite",
            }
            .into());
        }
        match v.slot {
            Slot::Drive(p) => self.spec.drive = self.spec.drive.with(p, value),
            Slot::Law(side, i) => {
                if let Some(law) = self.spec.law_mut(side) {
                    law.values[i] = value;
                }
            }
            Slot::Input(i) => self.inputs[i] = value,
            Slot::Output(_) => {}
        }
        Ok(())
    }

    /// `fmi2GetReal` of one variable. An output before initialisation ends is the drive at
    /// rest with the parameters as set.
    pub fn get_real(&self, vr: u32) -> Result<f64, FmuError> {
        let v = self.variable(vr)?;
        Ok(match v.slot {
            Slot::Drive(p) => self.spec.drive.value(p),
            Slot::Law(side, i) => self.spec.law(side).map_or(f64::NAN, |l| l.values[i]),
            Slot::Input(i) => self.inputs[i],
            Slot::Output(o) => match &self.run {
                Some(run) => o.of(&run.outputs()),
                None => o.of(&self.start()?.outputs()),
            },
        })
    }
}
