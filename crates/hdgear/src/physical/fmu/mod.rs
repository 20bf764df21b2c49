//! A drive as an FMI 2.0 co-simulation FMU: what it holds ([`FmuDrive`]), its variables (from
//! the drive's parameter table, [`super::DriveParam`], and its laws' tables), its
//! `modelDescription.xml` ([`description`]), the instance the exported library runs
//! ([`Instance`]: FMI's state machine and its variables by value reference), and the archive
//! with its reference result ([`archive`]). The C ABI around it is the `hdgear-fmu` crate's;
//! everything it reads is here, so the description and the binary cannot disagree.

pub mod archive;
pub mod description;
pub mod instance;

pub use archive::{ReferenceRow, Resources, resource_folder};
pub use instance::{FmuError, Instance, Phase};

use super::cosim::DriveOutputs;
use super::model::{Bearings, Physical, law_quantities};
use super::{DriveParam, PhysicalParams};
use crate::model::terms::AnyTerm;
use serde::{Deserialize, Serialize};

/// The file stem of the FMU's shared library and its `modelIdentifier`.
pub const MODEL_IDENTIFIER: &str = "hdgear_fmu";

/// A law of the drive (a bearing's, or the friction across the compliance) by kind and values
/// in SI units, as the FMU's resources hold it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LawValues {
    /// One of [`super::model::BEARING_KINDS`].
    pub kind: String,
    /// Its values, in the order of its parameter table.
    pub values: Vec<f64>,
}

impl LawValues {
    /// The law of a term.
    pub fn of(term: &AnyTerm) -> LawValues {
        LawValues {
            kind: term.kind().to_string(),
            values: term.values().to_vec(),
        }
    }

    fn term(&self) -> crate::error::Result<AnyTerm> {
        AnyTerm::new(&self.kind, &self.values)
    }
}

/// Where a law acts: the FMU's variables of its parameters are named `<side>.<parameter>`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum LawSite {
    /// Friction at the output bearing, on θo'.
    OutputBearing,
    /// Friction at the wave generator, on θi'.
    InputBearing,
    /// Friction across the compliance, on θ'.
    Twist,
}

impl LawSite {
    const ALL: [LawSite; 3] = [
        LawSite::OutputBearing,
        LawSite::InputBearing,
        LawSite::Twist,
    ];

    /// The prefix of its variables' names.
    pub fn name(self) -> &'static str {
        match self {
            LawSite::OutputBearing => "output_bearing",
            LawSite::InputBearing => "input_bearing",
            LawSite::Twist => "twist_friction",
        }
    }
}

/// What an FMU of a drive holds: the drive, its laws and the integrator's tolerance. Written to
/// the FMU's `resources/drive.json` with its GUID; the exported library reads it at
/// `fmi2Instantiate`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FmuDrive {
    /// The model's name (the card's).
    pub name: String,
    /// The drive.
    pub drive: PhysicalParams,
    /// Friction at the output bearing.
    pub output_bearing: Option<LawValues>,
    /// Friction at the wave generator.
    pub input_bearing: Option<LawValues>,
    /// Friction across the compliance.
    pub twist_friction: Option<LawValues>,
    /// Relative and absolute tolerance of hdgear's stepper (the absolute one in units of the
    /// drive's angle scale), unless the host's `fmi2SetupExperiment` gives one.
    pub tolerance: f64,
}

/// An FMU's variable: one row of `modelDescription.xml`; its value reference is its index in
/// [`FmuDrive::variables`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Variable {
    /// Its name.
    pub name: String,
    /// What it is.
    pub description: String,
    /// Its unit (`None`: a pure number).
    pub unit: Option<&'static str>,
    /// Parameter, input or output, with its start value where it has one.
    pub role: Role,
    /// Where its value lives.
    pub slot: Slot,
}

/// A variable's causality, with its start value.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum Role {
    /// Fixed before initialisation, with its start value.
    Parameter(f64),
    /// Set by the host before each step, held over it (start 0).
    Input,
    /// Computed.
    Output,
}

/// Where a variable's value lives.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum Slot {
    /// A parameter of the drive.
    Drive(DriveParam),
    /// Parameter `1` of the law on side `0`.
    Law(LawSite, usize),
    /// Input 0 (motor torque) or 1 (load torque).
    Input(usize),
    /// An output.
    Output(Output),
}

/// The FMU's outputs ([`DriveOutputs`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Output {
    /// θi.
    PhiIn,
    /// θi'.
    WIn,
    /// θo.
    PhiOut,
    /// θo'.
    WOut,
    /// θ.
    Twist,
    /// θ'.
    TwistRate,
    /// The transmitted torque.
    TauGear,
}

impl Output {
    const ALL: [Output; 7] = [
        Output::PhiIn,
        Output::WIn,
        Output::PhiOut,
        Output::WOut,
        Output::Twist,
        Output::TwistRate,
        Output::TauGear,
    ];

    /// (name, unit, description).
    fn about(self) -> (&'static str, &'static str, &'static str) {
        match self {
            Output::PhiIn => ("phi_in", "rad", "input (wave generator) angle"),
            Output::WIn => ("w_in", "rad/s", "input speed"),
            Output::PhiOut => ("phi_out", "rad", "output angle"),
            Output::WOut => ("w_out", "rad/s", "output speed"),
            Output::Twist => (
                "twist",
                "rad",
                "twist across the compliance, phi_out - phi_in/N",
            ),
            Output::TwistRate => ("twist_rate", "rad/s", "rate of the twist"),
            Output::TauGear => (
                "tau_gear",
                "N.m",
                "torque transmitted across the compliance",
            ),
        }
    }

    fn of(self, o: &DriveOutputs) -> f64 {
        match self {
            Output::PhiIn => o.phi_in,
            Output::WIn => o.w_in,
            Output::PhiOut => o.phi_out,
            Output::WOut => o.w_out,
            Output::Twist => o.twist,
            Output::TwistRate => o.twist_rate,
            Output::TauGear => o.tau_gear,
        }
    }
}

/// The inputs: (name, description).
const INPUTS: [(&str, &str); 2] = [
    (
        "tau_motor",
        "torque on the input inertia, in the sense of phi_in (added to -t_m/N)",
    ),
    (
        "tau_load",
        "torque on the output inertia, in the sense of phi_out (added to t_m + t_am sin(omega t))",
    ),
];

/// The units the variables use, with their SI base-unit exponents (kg, m, s, rad).
const UNITS: [(&str, [i32; 4]); 7] = [
    ("kg.m2", [1, 2, 0, 0]),
    ("N.m/rad", [1, 2, -2, -1]),
    ("N.m/rad3", [1, 2, -2, -3]),
    ("rad", [0, 0, 0, 1]),
    ("N.m.s/rad", [1, 2, -1, -1]),
    ("N.m", [1, 2, -2, 0]),
    ("rad/s", [0, 0, -1, 1]),
];

impl FmuDrive {
    /// The drive with its laws; fails, naming the term, on a law the two-inertia model does
    /// not take, and on a drive out of its domain.
    pub fn new(name: &str, sys: &Physical, tolerance: f64) -> crate::error::Result<FmuDrive> {
        let b = sys.bearings();
        let spec = FmuDrive {
            name: name.to_string(),
            drive: *sys.drive(),
            output_bearing: b.output.as_ref().map(LawValues::of),
            input_bearing: b.input.as_ref().map(LawValues::of),
            twist_friction: sys.twist_friction().as_ref().map(LawValues::of),
            tolerance,
        };
        spec.physical()?;
        Ok(spec)
    }

    fn law(&self, side: LawSite) -> Option<&LawValues> {
        match side {
            LawSite::OutputBearing => self.output_bearing.as_ref(),
            LawSite::InputBearing => self.input_bearing.as_ref(),
            LawSite::Twist => self.twist_friction.as_ref(),
        }
    }

    fn law_mut(&mut self, side: LawSite) -> Option<&mut LawValues> {
        match side {
            LawSite::OutputBearing => self.output_bearing.as_mut(),
            LawSite::InputBearing => self.input_bearing.as_mut(),
            LawSite::Twist => self.twist_friction.as_mut(),
        }
    }

    /// The two-inertia model these values make (checked: the drive's domain, each law's).
    pub fn physical(&self) -> crate::error::Result<Physical> {
        self.drive.validate()?;
        let term = |law: Option<&LawValues>| law.map(LawValues::term).transpose();
        let bearings = Bearings::new(
            term(self.output_bearing.as_ref())?,
            term(self.input_bearing.as_ref())?,
        )?;
        let sys = Physical::with_bearings(self.drive, bearings);
        match term(self.twist_friction.as_ref())? {
            Some(law) => sys.with_twist_friction(law),
            None => Ok(sys),
        }
    }

    /// Every variable, in value-reference order: the drive's parameters, each law's, the two
    /// inputs, the outputs.
    pub fn variables(&self) -> Vec<Variable> {
        let mut v: Vec<Variable> = DriveParam::ALL
            .iter()
            .map(|&p| Variable {
                name: p.name().to_string(),
                description: p.meaning().to_string(),
                unit: p.unit(),
                role: Role::Parameter(self.drive.value(p)),
                slot: Slot::Drive(p),
            })
            .collect();
        for side in LawSite::ALL {
            let Some(law) = self.law(side) else { continue };
            let infos = AnyTerm::params_of(&law.kind).unwrap_or_default();
            let units = law_quantities(&law.kind).unwrap_or_default();
            for (i, (info, value)) in infos.iter().zip(&law.values).enumerate() {
                v.push(Variable {
                    name: format!("{}.{}", side.name(), info.name),
                    description: format!("{} ({} law), {}", side.name(), law.kind, info.meaning),
                    unit: units.get(i).map(|q| q.unit()),
                    role: Role::Parameter(*value),
                    slot: Slot::Law(side, i),
                });
            }
        }
        for (i, (name, description)) in INPUTS.iter().enumerate() {
            v.push(Variable {
                name: name.to_string(),
                description: description.to_string(),
                unit: Some("N.m"),
                role: Role::Input,
                slot: Slot::Input(i),
            });
        }
        for o in Output::ALL {
            let (name, unit, description) = o.about();
            v.push(Variable {
                name: name.to_string(),
                description: description.to_string(),
                unit: Some(unit),
                role: Role::Output,
                slot: Slot::Output(o),
            });
        }
        v
    }
}
