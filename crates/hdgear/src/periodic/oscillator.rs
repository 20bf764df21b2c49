//! The one seam the periodic machinery needs: a forced second-order oscillator
//! x'' = a(s, x, x') whose forcing depends on time only through its phase s = ωτ, with the
//! derivatives shooting, monodromy and continuation use. [`Params`] (the study's model) is one;
//! any forced oscillator can be another (the tests use a lightly damped Duffing oscillator).

use crate::error::Result;
use crate::params::{Param, Params};
use std::fmt;

/// A forced oscillator x'' = a(s, x, x'), s = ωτ the forcing phase (period 2π in s), with
/// parameters that continuation can vary.
///
/// Working in the phase s instead of τ fixes the period at 2π·k whatever ω is, so ω is a
/// parameter like the others: in s the system reads dx/ds = x'/ω, dx'/ds = a/ω, and its
/// derivative with respect to ω at fixed s is −(x', a)/ω² (the forcing frequency enters only
/// through the time scale; implementations must keep `a` free of ω other than through `s`).
pub trait Oscillator: Copy + Send + Sync {
    /// The name of one parameter.
    type Param: Copy + PartialEq + fmt::Debug + fmt::Display + Send + Sync;
    /// The forcing frequency ω.
    fn omega(&self) -> f64;
    /// x'' at phase s, position x and velocity v = dx/dτ.
    fn accel(&self, phase: f64, x: f64, v: f64) -> f64;
    /// (∂a/∂x, ∂a/∂v).
    fn accel_gradient(&self, phase: f64, x: f64, v: f64) -> [f64; 2];
    /// ∂a/∂λ at fixed phase, x, v (0 for the frequency, see above).
    fn accel_derivative(&self, param: Self::Param, phase: f64, x: f64, v: f64) -> f64;
    /// The value of a parameter.
    fn get(&self, param: Self::Param) -> f64;
    /// The oscillator with one parameter changed, checked (an error names the value).
    fn with(&self, param: Self::Param, value: f64) -> Result<Self>;
    /// Whether `param` is the forcing frequency ω.
    fn is_frequency(param: Self::Param) -> bool;
    /// Checks every parameter (an error names the value).
    fn check(&self) -> Result<()>;
}

impl Oscillator for Params {
    type Param = Param;
    fn omega(&self) -> f64 {
        self.omega
    }
    #[inline(always)]
    fn accel(&self, phase: f64, x: f64, v: f64) -> f64 {
        self.forcing(libm::sin(phase)) - v - self.g(x)
    }
    #[inline(always)]
    fn accel_gradient(&self, _phase: f64, x: f64, _v: f64) -> [f64; 2] {
        [-self.g_prime(x), -1.0]
    }
    /// −x³ (α), −(x − ε) (γ), γ (ε), 1 (μ), sin s (δ), 0 (ω).
    fn accel_derivative(&self, param: Param, phase: f64, x: f64, _v: f64) -> f64 {
        match param {
            Param::Alpha => -x * x * x,
            Param::Gamma => -(x - self.eps),
            Param::Eps => self.gamma,
            Param::Mu => 1.0,
            Param::Delta => libm::sin(phase),
            Param::Omega => 0.0,
        }
    }
    fn get(&self, param: Param) -> f64 {
        self.value(param)
    }
    fn with(&self, param: Param, value: f64) -> Result<Params> {
        let q = Params::with(*self, param, value);
        q.validate()?;
        Ok(q)
    }
    fn is_frequency(param: Param) -> bool {
        param == Param::Omega
    }
    fn check(&self) -> Result<()> {
        self.validate().map(|_| ())
    }
}
