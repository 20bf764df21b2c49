//! Model parameters: the dimensionless set ([`Params`]), named presets, and TOML scenario files.
//!
//! Sources are applied in order, later overriding earlier: a named preset, a scenario file's
//! `[params]` table, then single values (the command line's flags). [`ParamOverrides`] is the
//! partial set both the file and the flags produce.

mod plane;
pub use plane::{Box2, Scale};

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use std::fmt;

/// The dimensionless parameters of
/// x'' + x' + α x³ − x² + γ (x − ε) = μ + δ sin(ω τ).
///
/// The default is the study's point with γ = 0.1 (pronounced bursting).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, crate::output::Record)]
pub struct Params {
    /// α > 0: cubic stiffness (what confines the motion).
    pub alpha: f64,
    /// γ: linear stiffness. Any finite value.
    pub gamma: f64,
    /// ε: backlash offset of the linear term. Any finite value.
    pub eps: f64,
    /// μ: mean load. Any finite value.
    pub mu: f64,
    /// δ ≥ 0: amplitude of the slow torque disturbance.
    pub delta: f64,
    /// ω > 0: frequency of the slow disturbance.
    pub omega: f64,
}

impl Default for Params {
    fn default() -> Self {
        Params {
            alpha: 16.0,
            gamma: 0.1,
            eps: 0.71,
            mu: 0.07,
            delta: 15.0,
            omega: 0.01,
        }
    }
}

/// One of the six dimensionless parameters: the one source of their names (serde, Display and
/// FromStr all use [`Param::name`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Param {
    /// α, cubic stiffness.
    Alpha,
    /// γ, linear stiffness.
    Gamma,
    /// ε, backlash offset.
    Eps,
    /// μ, mean load.
    Mu,
    /// δ, amplitude of the slow disturbance.
    Delta,
    /// ω, frequency of the slow disturbance.
    Omega,
}

impl Param {
    /// All six, in the order used by tables and sweeps.
    pub const ALL: [Param; 6] = [
        Param::Alpha,
        Param::Gamma,
        Param::Eps,
        Param::Mu,
        Param::Delta,
        Param::Omega,
    ];

    /// The six names in [`Param::ALL`]'s order: the columns of every table row that carries a
    /// parameter set (the fields of [`Params`], held to these by a test).
    pub const NAMES: [&'static str; 6] = {
        let mut names = [""; 6];
        let mut i = 0;
        while i < names.len() {
            names[i] = Param::ALL[i].name();
            i += 1;
        }
        names
    };

    /// The name users write (`alpha`, `gamma`, `eps`, `mu`, `delta`, `omega`).
    pub const fn name(self) -> &'static str {
        match self {
            Param::Alpha => "alpha",
            Param::Gamma => "gamma",
            Param::Eps => "eps",
            Param::Mu => "mu",
            Param::Delta => "delta",
            Param::Omega => "omega",
        }
    }
}

impl fmt::Display for Param {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name())
    }
}

impl std::str::FromStr for Param {
    type Err = Error;
    fn from_str(name: &str) -> Result<Param> {
        crate::error::by_name(&Param::ALL, Param::name, "parameter name", name)
    }
}

/// Named parameter sets: the study's point and its four γ cases.
pub const PRESETS: [(&str, f64); 5] = [
    ("paper", 0.1),
    ("paper-g30", 30.0),
    ("paper-g10", 10.0),
    ("paper-g1", 1.0),
    ("paper-g0.1", 0.1),
];

/// A non-fatal remark about a parameter set.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Warning {
    /// α·ε ≠ 1: no physical drive reduces to this set (α·ε = C²/(k2φ²J)·k2φ²J/C² = 1; guide: corrections to the study).
    AlphaEpsNotOne {
        /// The product α·ε.
        alpha_eps: f64,
    },
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::AlphaEpsNotOne { alpha_eps } => write!(
                f,
                "alpha*eps = {alpha_eps:.4} is not 1: no physical drive gives this set; studied \
                 as a dimensionless model (guide: corrections to the study)"
            ),
        }
    }
}

impl Params {
    /// The named preset (see [`PRESETS`]).
    ///
    /// ```
    /// let p = hdgear::Params::preset("paper-g30").unwrap();
    /// assert_eq!(p.gamma, 30.0);
    /// assert!(hdgear::Params::preset("nope").is_err());
    /// ```
    pub fn preset(name: &str) -> Result<Params> {
        PRESETS
            .iter()
            .find(|(n, _)| n.eq_ignore_ascii_case(name))
            .map(|&(_, gamma)| Params {
                gamma,
                ..Params::default()
            })
            .ok_or_else(|| Error::UnknownPreset {
                name: name.to_string(),
                known: PRESETS.map(|(n, _)| n).join(", "),
            })
    }

    /// The value of a parameter.
    pub fn value(&self, param: Param) -> f64 {
        match param {
            Param::Alpha => self.alpha,
            Param::Gamma => self.gamma,
            Param::Eps => self.eps,
            Param::Mu => self.mu,
            Param::Delta => self.delta,
            Param::Omega => self.omega,
        }
    }

    /// The same set with one parameter changed.
    pub fn with(mut self, param: Param, value: f64) -> Params {
        *match param {
            Param::Alpha => &mut self.alpha,
            Param::Gamma => &mut self.gamma,
            Param::Eps => &mut self.eps,
            Param::Mu => &mut self.mu,
            Param::Delta => &mut self.delta,
            Param::Omega => &mut self.omega,
        } = value;
        self
    }

    /// Checks the domain (all finite, α > 0, ω > 0, δ ≥ 0, every magnitude within
    /// [`MAGNITUDE_LIMIT`]) and returns the warnings of a valid set.
    pub fn validate(&self) -> Result<Vec<Warning>> {
        for param in Param::ALL {
            let (name, v) = (param.name(), self.value(param));
            if !v.is_finite() {
                return Err(invalid(name, v, "must be finite"));
            }
            check_magnitude(name, v)?;
        }
        if self.alpha <= 0.0 {
            return Err(invalid(
                Param::Alpha.name(),
                self.alpha,
                "must be > 0 (the cubic stiffness confines the motion)",
            ));
        }
        if self.omega <= 0.0 {
            return Err(invalid(Param::Omega.name(), self.omega, "must be > 0"));
        }
        if self.delta < 0.0 {
            return Err(invalid(
                Param::Delta.name(),
                self.delta,
                "must be ≥ 0 (its sign is the phase of the disturbance)",
            ));
        }
        let mut w = Vec::new();
        let ae = self.alpha * self.eps;
        if (ae - 1.0).abs() > 1e-9 {
            w.push(Warning::AlphaEpsNotOne { alpha_eps: ae });
        }
        Ok(w)
    }

    /// g(x) = α x³ − x² + γ (x − ε): the restoring force of the fast subsystem.
    #[inline(always)]
    pub fn g(&self, x: f64) -> f64 {
        ((self.alpha * x - 1.0) * x + self.gamma) * x - self.gamma * self.eps
    }

    /// g'(x) = 3α x² − 2x + γ.
    #[inline(always)]
    pub fn g_prime(&self, x: f64) -> f64 {
        (3.0 * self.alpha * x - 2.0) * x + self.gamma
    }

    /// The slow variable at which x is an equilibrium: a(x) = (g(x) − μ)/δ (the equilibrium curve
    /// is a graph over x; δ > 0).
    #[inline(always)]
    pub fn a_at(&self, x: f64) -> f64 {
        (self.g(x) - self.mu) / self.delta
    }

    /// The forcing μ + δ a for slow variable a.
    #[inline(always)]
    pub fn forcing(&self, a: f64) -> f64 {
        self.mu + self.delta * a
    }

    /// The slow period 2π/ω.
    pub fn slow_period(&self) -> f64 {
        std::f64::consts::TAU / self.omega
    }

    /// The critical γ = 1/(3α): folds exist below it, the cusp is at it.
    pub fn critical_gamma(&self) -> f64 {
        1.0 / (3.0 * self.alpha)
    }
}

/// Every parameter, dimensionless or physical, has |value| ≤ 1e100 and, unless it is 0, ≥ 1e-100:
/// beyond that the cubic terms (x³, k2·θ³, φ²) and the reduction's products overflow or
/// underflow, and the error would name a derived value instead of the user's.
pub const MAGNITUDE_LIMIT: f64 = 1e100;

/// Checks one value against [`MAGNITUDE_LIMIT`] (an infinite one is refused as not finite, which
/// says more than its magnitude).
pub(crate) fn check_magnitude(name: &str, v: f64) -> Result<()> {
    if v.is_infinite() {
        return Err(invalid(name, v, "must be finite"));
    }
    if v.abs() > MAGNITUDE_LIMIT {
        return Err(invalid(
            name,
            v,
            "magnitude above 1e100: the model's cubic terms would overflow",
        ));
    }
    if beyond_magnitude(v) {
        return Err(invalid(
            name,
            v,
            "nonzero magnitude below 1e-100: the model's scales would overflow (use 0 or a larger value)",
        ));
    }
    Ok(())
}

/// Whether a value lies beyond [`MAGNITUDE_LIMIT`] either way (0 is within).
pub(crate) fn beyond_magnitude(v: f64) -> bool {
    v.abs() > MAGNITUDE_LIMIT || (v != 0.0 && v.abs() < 1.0 / MAGNITUDE_LIMIT)
}

pub(crate) fn invalid(name: &str, value: f64, reason: &'static str) -> Error {
    Error::InvalidParameter {
        name: name.to_string(),
        value,
        reason,
    }
}

/// A partial parameter set: the `[params]` table of a scenario file, or command-line flags.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParamOverrides {
    /// α
    pub alpha: Option<f64>,
    /// γ
    pub gamma: Option<f64>,
    /// ε
    pub eps: Option<f64>,
    /// μ
    pub mu: Option<f64>,
    /// δ
    pub delta: Option<f64>,
    /// ω
    pub omega: Option<f64>,
}

impl ParamOverrides {
    /// Sets parameter `q`'s value.
    ///
    /// ```
    /// use hdgear::params::{Param, ParamOverrides, Params};
    /// for q in Param::ALL {
    ///     let mut o = ParamOverrides::default();
    ///     o.set(q, 0.5);
    ///     assert_eq!(o.get(q), Some(0.5));
    ///     let mut p = Params::default();
    ///     o.apply(&mut p);
    ///     assert_eq!(p, Params::default().with(q, 0.5));
    /// }
    /// ```
    pub fn set(&mut self, q: Param, value: f64) {
        *self.fields()[q as usize] = Some(value);
    }

    /// Parameter `q`'s value, if present.
    pub fn get(&self, q: Param) -> Option<f64> {
        let mut copy = *self;
        *copy.fields()[q as usize]
    }

    /// The six values, in the order of [`Param`]'s variants.
    fn fields(&mut self) -> [&mut Option<f64>; 6] {
        let ParamOverrides {
            alpha,
            gamma,
            eps,
            mu,
            delta,
            omega,
        } = self;
        [alpha, gamma, eps, mu, delta, omega]
    }

    /// Applies the values that are present to `p`.
    pub fn apply(&self, p: &mut Params) {
        for q in Param::ALL {
            if let Some(v) = self.get(q) {
                *p = p.with(q, v);
            }
        }
    }
}

/// Resolves the parameter set from its sources: preset, then the overrides of a scenario file
/// (its `[params]` table, see [`crate::scenario`]), then flag overrides,
/// and validates it. Returns the set and its warnings.
///
/// ```
/// use hdgear::params::{resolve, ParamOverrides};
/// let flags = ParamOverrides { gamma: Some(1.0), ..Default::default() };
/// let (p, warnings) = resolve("paper", None, &flags).unwrap();
/// assert_eq!(p.gamma, 1.0);
/// assert_eq!(warnings.len(), 1); // the study's α·ε = 11.36 ≠ 1
/// ```
pub fn resolve(
    preset: &str,
    file: Option<&ParamOverrides>,
    flags: &ParamOverrides,
) -> Result<(Params, Vec<Warning>)> {
    let mut p = Params::preset(preset)?;
    if let Some(o) = file {
        o.apply(&mut p);
    }
    flags.apply(&mut p);
    let w = p.validate()?;
    Ok((p, w))
}
