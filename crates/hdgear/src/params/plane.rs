//! A plane of two parameters: each parameter's coordinate ([`Scale`]: λ or ln λ) and the box
//! a curve is followed in ([`Box2`]), shared by two-parameter continuation
//! ([`crate::periodic`]) and the boundaries of the fast-slow picture ([`crate::burst`]).

use crate::error::{Error, Result};
use serde::Serialize;

/// How the parameter enters the arclength: as itself, or as its logarithm (for ranges over
/// decades of a positive parameter, such as ω).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Scale {
    /// u = λ.
    Linear,
    /// u = ln λ (λ > 0).
    Log,
}

impl Scale {
    /// The coordinate u of λ.
    pub fn to_u(self, lambda: f64) -> f64 {
        match self {
            Scale::Linear => lambda,
            Scale::Log => lambda.ln(),
        }
    }
    /// λ at the coordinate u.
    pub fn to_lambda(self, u: f64) -> f64 {
        match self {
            Scale::Linear => u,
            Scale::Log => u.exp(),
        }
    }
    /// dλ/du.
    pub fn dlambda(self, u: f64) -> f64 {
        match self {
            Scale::Linear => 1.0,
            Scale::Log => u.exp(),
        }
    }
}

/// The box a curve is followed in: each parameter's range and coordinate.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Box2 {
    /// (low, high) of λ₁ and of λ₂.
    pub ranges: [(f64, f64); 2],
    /// λ or ln λ for each.
    pub scales: [Scale; 2],
}

impl Box2 {
    /// Checks the ranges (finite, low < high, positive on a log scale, within the magnitude
    /// limit every parameter has: [`crate::params::MAGNITUDE_LIMIT`]).
    pub fn validate(&self) -> Result<()> {
        for (i, (&(lo, hi), s)) in self.ranges.iter().zip(self.scales).enumerate() {
            let name = if i == 0 { "range1" } else { "range2" };
            crate::params::check_magnitude(name, lo)?;
            crate::params::check_magnitude(name, hi)?;
            let ok =
                lo.is_finite() && hi.is_finite() && lo < hi && (s == Scale::Linear || lo > 0.0);
            if !ok {
                return Err(Error::InvalidOption {
                    name,
                    value: if lo.is_finite() { hi } else { lo },
                    reason: "needs finite low < high (> 0 on a log scale)",
                });
            }
        }
        Ok(())
    }
}
