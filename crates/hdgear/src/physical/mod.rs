//! The physical two-inertia drive in SI units, and its reduction to the dimensionless model
//! (guide: the model and its parameters). The reduction lives here and nowhere else.
//!
//! ```text
//! J_o θo'' + C (θo' − θi'/N) + K(θ) f(θ)      =  T_m + T_am sin(Ω t)
//! J_i θi'' − C (θo' − θi'/N)/N − K(θ) f(θ)/N  = −T_m/N
//! θ = θo − θi/N,  K(θ) = k1 + k2 θ²,  f(θ) = θ − φ
//! ```
//!
//! Eliminating the rigid-body mode: θ'' + (C/J) θ' + K(θ)(θ − φ)/J = T_m/J + (T_am/J_o) sin Ωt,
//! J = J_eq = N² J_i J_o / (N² J_i + J_o). With t = T τ, T = J/C, and θ = L x, L = C²/(J k2 φ):
//!
//! ```text
//! α = C²/(k2 φ² J)   γ = k1 J/C²   ε = k2 φ² J/C²   μ = k2 φ J² T_m/C⁴
//! δ = k2 φ J³ T_am/(J_o C⁴)   ω = Ω J/C
//! ```
//!
//! (δ with C⁴, not the C² the study prints; α·ε = 1 identically.)

pub mod card;
pub mod catalogue;
pub mod check;
pub mod cosim;
pub mod curve_law;
pub mod design;
pub mod fmu;
pub mod friction;
pub mod model;
pub mod simulate;

use crate::error::{Error, Result};
use crate::params::{Params, check_magnitude, invalid};
use serde::{Deserialize, Serialize};

/// A harmonic drive in SI units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhysicalParams {
    /// J_i: input-side inertia (motor + wave generator) \[kg m²\], > 0.
    pub j_in: f64,
    /// J_o: output-side inertia (flexspline + load) \[kg m²\], > 0.
    pub j_out: f64,
    /// N: reduction ratio \[-\], > 0.
    pub ratio: f64,
    /// k1: linear torsional stiffness \[N m/rad\], ≥ 0.
    pub k1: f64,
    /// k2: cubic torsional stiffness \[N m/rad³\], ≥ 0.
    pub k2: f64,
    /// φ: backlash \[rad\], ≥ 0.
    pub backlash: f64,
    /// C: equivalent damping \[N m s/rad\], > 0.
    pub c_eq: f64,
    /// T_m: mean torque \[N m\], finite.
    pub t_m: f64,
    /// T_am: amplitude of the slow output torque disturbance \[N m\], ≥ 0.
    pub t_am: f64,
    /// Ω: frequency of the disturbance \[rad/s\], > 0.
    pub omega: f64,
}

/// One of the ten parameters of a drive: the one source of their names (TOML keys; CLI flags
/// with `-` for `_`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DriveParam {
    /// J_i \[kg m²\].
    JIn,
    /// J_o \[kg m²\].
    JOut,
    /// N.
    Ratio,
    /// k1 \[N m/rad\].
    K1,
    /// k2 \[N m/rad³\].
    K2,
    /// φ \[rad\].
    Backlash,
    /// C \[N m s/rad\].
    CEq,
    /// T_m \[N m\].
    TM,
    /// T_am \[N m\].
    TAm,
    /// Ω \[rad/s\].
    Omega,
}

impl DriveParam {
    /// All ten, in the order of the TOML table.
    pub const ALL: [DriveParam; 10] = [
        DriveParam::JIn,
        DriveParam::JOut,
        DriveParam::Ratio,
        DriveParam::K1,
        DriveParam::K2,
        DriveParam::Backlash,
        DriveParam::CEq,
        DriveParam::TM,
        DriveParam::TAm,
        DriveParam::Omega,
    ];

    /// The name users write (`j_in`, …, `omega`).
    pub fn name(self) -> &'static str {
        match self {
            DriveParam::JIn => "j_in",
            DriveParam::JOut => "j_out",
            DriveParam::Ratio => "ratio",
            DriveParam::K1 => "k1",
            DriveParam::K2 => "k2",
            DriveParam::Backlash => "backlash",
            DriveParam::CEq => "c_eq",
            DriveParam::TM => "t_m",
            DriveParam::TAm => "t_am",
            DriveParam::Omega => "omega",
        }
    }
}

impl DriveParam {
    /// Its unit as FMI and Modelica write it (`None`: a pure number).
    pub fn unit(self) -> Option<&'static str> {
        match self {
            DriveParam::JIn | DriveParam::JOut => Some("kg.m2"),
            DriveParam::Ratio => None,
            DriveParam::K1 => Some("N.m/rad"),
            DriveParam::K2 => Some("N.m/rad3"),
            DriveParam::Backlash => Some("rad"),
            DriveParam::CEq => Some("N.m.s/rad"),
            DriveParam::TM | DriveParam::TAm => Some("N.m"),
            DriveParam::Omega => Some("rad/s"),
        }
    }

    /// What it is, in a line.
    pub fn meaning(self) -> &'static str {
        match self {
            DriveParam::JIn => "input-side inertia (motor and wave generator)",
            DriveParam::JOut => "output-side inertia (flexspline and load)",
            DriveParam::Ratio => "reduction ratio",
            DriveParam::K1 => "linear torsional stiffness",
            DriveParam::K2 => "cubic torsional stiffness",
            DriveParam::Backlash => "backlash",
            DriveParam::CEq => "equivalent damping across the compliance",
            DriveParam::TM => "mean torque on the output (held by the input)",
            DriveParam::TAm => "amplitude of the output torque disturbance T_am sin(omega t)",
            DriveParam::Omega => "frequency of the output torque disturbance",
        }
    }
}

impl std::fmt::Display for DriveParam {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

impl std::str::FromStr for DriveParam {
    type Err = Error;
    fn from_str(name: &str) -> Result<DriveParam> {
        crate::error::by_name(
            &DriveParam::ALL,
            DriveParam::name,
            "drive parameter name",
            name,
        )
    }
}

impl PhysicalParams {
    /// The value of a parameter.
    pub fn value(&self, param: DriveParam) -> f64 {
        match param {
            DriveParam::JIn => self.j_in,
            DriveParam::JOut => self.j_out,
            DriveParam::Ratio => self.ratio,
            DriveParam::K1 => self.k1,
            DriveParam::K2 => self.k2,
            DriveParam::Backlash => self.backlash,
            DriveParam::CEq => self.c_eq,
            DriveParam::TM => self.t_m,
            DriveParam::TAm => self.t_am,
            DriveParam::Omega => self.omega,
        }
    }

    /// The same drive with one parameter changed.
    pub fn with(mut self, param: DriveParam, v: f64) -> PhysicalParams {
        *match param {
            DriveParam::JIn => &mut self.j_in,
            DriveParam::JOut => &mut self.j_out,
            DriveParam::Ratio => &mut self.ratio,
            DriveParam::K1 => &mut self.k1,
            DriveParam::K2 => &mut self.k2,
            DriveParam::Backlash => &mut self.backlash,
            DriveParam::CEq => &mut self.c_eq,
            DriveParam::TM => &mut self.t_m,
            DriveParam::TAm => &mut self.t_am,
            DriveParam::Omega => &mut self.omega,
        } = v;
        self
    }

    /// Checks the domain: all finite; inertias, ratio, damping and Ω > 0; k1, k2, backlash and
    /// T_am ≥ 0.
    pub fn validate(&self) -> Result<()> {
        for param in DriveParam::ALL {
            let (name, v) = (param.name(), self.value(param));
            if !v.is_finite() {
                return Err(invalid(name, v, "must be finite"));
            }
            check_magnitude(name, v)?;
        }
        use DriveParam::{Backlash, CEq, JIn, JOut, K1, K2, Omega, Ratio, TAm};
        let positive =
            [JIn, JOut, Ratio, CEq, Omega].map(|q| (q, self.value(q) > 0.0, "must be > 0"));
        let non_negative =
            [K1, K2, Backlash, TAm].map(|q| (q, self.value(q) >= 0.0, "must be ≥ 0"));
        let broken = positive
            .iter()
            .chain(&non_negative)
            .find(|(_, holds, _)| !holds);
        if let Some(&(param, _, reason)) = broken {
            return Err(invalid(param.name(), self.value(param), reason));
        }
        Ok(())
    }

    /// J_eq = N² J_i J_o / (N² J_i + J_o) \[kg m²\].
    pub fn j_eq(&self) -> f64 {
        let n2ji = self.ratio * self.ratio * self.j_in;
        n2ji * self.j_out / (n2ji + self.j_out)
    }

    /// ζ = C/(2√(k1 J)), the damping ratio of the torsional mode with inertia `j` on the
    /// compliance (a [`Reduction::j_eq`]: J_eq with a free input, J_o with a held one).
    pub fn zeta_on(&self, j: f64) -> f64 {
        self.c_eq / (2.0 * (self.k1 * j).sqrt())
    }

    /// The spring's law T(θ) = (k1 + k2θ²)(θ − φ) \[N m\] of the twist θ \[rad\], as the term
    /// ([`Spring`](crate::model::terms::Spring)) in SI units: what the two-inertia model
    /// ([`model::Physical`]) takes in its own units and the periodic response's torque range
    /// evaluates.
    ///
    /// ```
    /// use hdgear::model::terms::Term;
    /// use hdgear::physical::PhysicalParams;
    /// let d = PhysicalParams { j_in: 1e-4, j_out: 1.0, ratio: 50.0, k1: 2e3, k2: 1e9,
    ///     backlash: 1e-3, c_eq: 5.0, t_m: 1.0, t_am: 0.5, omega: 1.0 };
    /// assert_eq!(d.spring().torque(1e-3, 0.0, 0.0), 0.0);
    /// ```
    pub fn spring(&self) -> crate::model::terms::Spring {
        <crate::model::terms::Spring as crate::model::terms::Term>::from_values(&[
            self.k1,
            self.k2,
            self.backlash,
        ])
    }

    /// The reduction to dimensionless form; an error when φ = 0 or k2 = 0 (L undefined).
    ///
    /// ```
    /// use hdgear::physical::PhysicalParams;
    /// let d = PhysicalParams { j_in: 1e-4, j_out: 1.0, ratio: 50.0, k1: 2e3, k2: 1e9,
    ///     backlash: 1e-3, c_eq: 5.0, t_m: 1.0, t_am: 0.5, omega: 1.0 };
    /// let r = d.reduce().unwrap();
    /// assert!((r.params.alpha * r.params.eps - 1.0).abs() < 1e-12);
    /// ```
    pub fn reduce(&self) -> Result<Reduction> {
        self.reduce_on(self.j_eq())
    }

    /// The reduction with the wave generator held (θi fixed: a position-controlled motor, or
    /// the gear's own starting torque holding the load): the twist is then the output inertia
    /// on the compliance alone, J_o θ'' + C θ' + T_s(θ) = T_m + T_am sin Ωt, so J_eq becomes J_o
    /// and the disturbance reaches the twist whole (δ = T_am over the torque unit, against
    /// J_eq/J_o of it with a free input). An error where [`PhysicalParams::reduce`] gives one.
    ///
    /// ```
    /// use hdgear::physical::PhysicalParams;
    /// let d = PhysicalParams { j_in: 1e-4, j_out: 1.0, ratio: 50.0, k1: 2e3, k2: 1e9,
    ///     backlash: 1e-3, c_eq: 5.0, t_m: 1.0, t_am: 0.5, omega: 1.0 };
    /// let (free, held) = (d.reduce().unwrap(), d.reduce_held().unwrap());
    /// assert_eq!(held.j_eq, d.j_out);
    /// // the same drive with a wave generator a billion times heavier: its input barely moves
    /// let heavy = PhysicalParams { j_in: 1e9 * d.j_in, ..d }.reduce().unwrap();
    /// assert!((heavy.params.gamma / held.params.gamma - 1.0).abs() < 1e-6);
    /// assert!(held.params.gamma > free.params.gamma);
    /// ```
    pub fn reduce_held(&self) -> Result<Reduction> {
        self.reduce_on(self.j_out)
    }

    /// [`PhysicalParams::reduce`] with `j` as the twist's inertia: J_eq with a free input,
    /// J_o with a held one.
    fn reduce_on(&self, j: f64) -> Result<Reduction> {
        self.validate()?;
        if self.backlash == 0.0 {
            return Err(Error::NoReduction {
                reason: "backlash = 0: the length scale L = C²/(J k2 φ) is undefined, so no \
                         dimensionless model corresponds to a zero-backlash drive; simulate the \
                         physical model instead (the two-inertia simulation)"
                    .into(),
            });
        }
        if self.k2 == 0.0 {
            return Err(Error::NoReduction {
                reason: "k2 = 0: the length scale L = C²/(J k2 φ) is undefined (a linear \
                         stiffness has no cubic term to scale by); simulate the physical model \
                         instead (the two-inertia simulation)"
                    .into(),
            });
        }
        let c = self.c_eq;
        let (k1, k2, phi) = (self.k1, self.k2, self.backlash);
        let c2 = c * c;
        let c4 = c2 * c2;
        let params = Params {
            alpha: c2 / (k2 * phi * phi * j),
            gamma: k1 * j / c2,
            eps: k2 * phi * phi * j / c2,
            mu: k2 * phi * j * j * self.t_m / c4,
            delta: k2 * phi * j * j * j * self.t_am / (self.j_out * c4),
            omega: self.omega * j / c,
        };
        if let Err(Error::InvalidParameter { name, value, .. }) = params.validate() {
            return Err(Error::NoReduction {
                reason: format!(
                    "this drive reduces to {name} = {value:?}, outside the dimensionless model's \
                     range (finite, |value| within 1e-100 … 1e100): its SI values are too far \
                     apart; simulate the physical model instead (the two-inertia simulation)"
                ),
            });
        }
        Ok(Reduction {
            params,
            j_eq: j,
            time_scale: j / c,
            length_scale: c2 / (j * k2 * phi),
        })
    }

    /// The way back: the drive with the given J_i, J_o, N, C and φ whose reduction is `p`.
    /// Requires α·ε = 1 (otherwise no drive reduces to `p`) and δ ≥ 0.
    pub fn from_dimensionless(
        p: &Params,
        j_in: f64,
        j_out: f64,
        ratio: f64,
        c_eq: f64,
        backlash: f64,
    ) -> Result<PhysicalParams> {
        p.validate()?;
        if (p.alpha * p.eps - 1.0).abs() > 1e-9 {
            return Err(Error::NoReduction {
                reason: format!(
                    "alpha*eps = {} differs from 1: no physical drive reduces to this set",
                    p.alpha * p.eps
                ),
            });
        }
        let mut d = PhysicalParams {
            j_in,
            j_out,
            ratio,
            k1: 0.0,
            k2: 1.0,
            backlash,
            c_eq,
            t_m: 0.0,
            t_am: 0.0,
            omega: 1.0,
        };
        d.validate()?;
        if backlash == 0.0 {
            return Err(invalid("backlash", 0.0, "must be > 0 for a reduction"));
        }
        let j = d.j_eq();
        let c = c_eq;
        let (c2, phi) = (c * c, backlash);
        d.k2 = c2 / (p.alpha * phi * phi * j);
        d.k1 = p.gamma * c2 / j;
        d.t_m = p.mu * c2 * c2 / (d.k2 * phi * j * j);
        d.t_am = p.delta * j_out * c2 * c2 / (d.k2 * phi * j * j * j);
        d.omega = p.omega * c / j;
        d.validate()?;
        Ok(d)
    }
}

/// The dimensionless parameters of a drive with the scales that map them back.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Reduction {
    /// α, γ, ε, μ, δ, ω.
    pub params: Params,
    /// J_eq \[kg m²\].
    pub j_eq: f64,
    /// T = J_eq/C \[s\]: t = T τ.
    pub time_scale: f64,
    /// L = C²/(J_eq k2 φ) \[rad\]: θ = L x.
    pub length_scale: f64,
}

impl Reduction {
    /// Physical time \[s\] of dimensionless time τ.
    pub fn time(&self, tau: f64) -> f64 {
        self.time_scale * tau
    }
    /// Dimensionless time of physical time t \[s\].
    pub fn tau(&self, t: f64) -> f64 {
        t / self.time_scale
    }
    /// Relative torsion θ \[rad\] of dimensionless x.
    pub fn theta(&self, x: f64) -> f64 {
        self.length_scale * x
    }
    /// Torsion rate θ' \[rad/s\] of dimensionless x' (= dx/dτ).
    pub fn theta_dot(&self, xdot: f64) -> f64 {
        self.length_scale * xdot / self.time_scale
    }
    /// Torque \[N m\] per unit of the dimensionless model's torques (μ, δ, a friction level):
    /// J_eq·L/T² = C⁴/(k2 φ J_eq²), so that μ = T_m/unit.
    pub fn torque_unit(&self) -> f64 {
        self.j_eq * self.length_scale / (self.time_scale * self.time_scale)
    }
}

/// A partial physical set (the `[physical]` table of a scenario file, or CLI flags).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PhysicalOverrides {
    /// J_i \[kg m²\]
    pub j_in: Option<f64>,
    /// J_o \[kg m²\]
    pub j_out: Option<f64>,
    /// N
    pub ratio: Option<f64>,
    /// k1 \[N m/rad\]
    pub k1: Option<f64>,
    /// k2 \[N m/rad³\]
    pub k2: Option<f64>,
    /// φ \[rad\]
    pub backlash: Option<f64>,
    /// C \[N m s/rad\]
    pub c_eq: Option<f64>,
    /// T_m \[N m\]
    pub t_m: Option<f64>,
    /// T_am \[N m\]
    pub t_am: Option<f64>,
    /// Ω \[rad/s\]
    pub omega: Option<f64>,
}

impl PhysicalOverrides {
    /// Applies the values present.
    pub fn apply(&self, d: &mut PhysicalParams) {
        let pairs = [
            (DriveParam::JIn, self.j_in),
            (DriveParam::JOut, self.j_out),
            (DriveParam::Ratio, self.ratio),
            (DriveParam::K1, self.k1),
            (DriveParam::K2, self.k2),
            (DriveParam::Backlash, self.backlash),
            (DriveParam::CEq, self.c_eq),
            (DriveParam::TM, self.t_m),
            (DriveParam::TAm, self.t_am),
            (DriveParam::Omega, self.omega),
        ];
        for (param, v) in pairs {
            if let Some(v) = v {
                *d = d.with(param, v);
            }
        }
    }
}
