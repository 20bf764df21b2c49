//! The periodic response itself: the orbit of period k·T (T = 2π/ω) found by shooting, its
//! monodromy matrix from the variational equations, its Floquet multipliers, and the largest
//! Lyapunov exponent by Benettin's method; continuation of the orbit in a parameter with its
//! folds and period doublings ([`continue_orbit`]), frequency-response curves
//! ([`frequency_response`], also a drive's in SI units), the stroboscopic orbit diagram and
//! Lyapunov maps ([`orbit_diagram`], [`lyapunov_point`]). Every model goes through one small
//! trait, [`Oscillator`], in the forcing phase s = ωτ.
//!
//! **Variational equations.** Along a solution (x, x'), a perturbation Φ obeys Φ' = J Φ with
//! J = [[0, 1], [−g'(x), −1]], g'(x) = 3αx² − 2x + γ (for the study's model). They are integrated
//! with the state and the parameter sensitivity w = ∂(x, x')/∂λ (an 8-dimensional system) by
//! Taylor's method ([`Oscillator::phase_taylor`]; DOP853 for an oscillator without Taylor
//! coefficients); the monodromy M = Φ(kT) is never formed directly, because
//! its entries shrink like e^{−τ/2} (e^{−314} over one slow period of the study): the span is cut
//! into pieces of at most [`PIECE`] time units, Φ restarts at I on each, and the product is kept
//! normalised with its logarithmic scale apart. The determinant is accumulated as Σ ln det of the
//! pieces (no cancellation even when one multiplier is e^{500} times the other), so the second
//! multiplier is det / the first — and Liouville's formula, det M = exp(∫ tr J) = e^{−kT}, is a
//! check of the integration, not an identity of the code.
//!
//! **Shooting.** Newton on P(y) = φ_{kT}(y) − y with P'(y) = M − I, from the state after
//! [`SETTLE_TIME`] from the default start; converged when |P(y)| ≤ [`NEWTON_TOL`]·(1+|y|).
//!
//! ```
//! use hdgear::{Params, periodic::{PeriodicOptions, shoot}};
//! let orbit = shoot(&Params::default(), 1, &PeriodicOptions::default()).unwrap();
//! assert!(orbit.stable && orbit.residual < 1e-10);
//! // Liouville: ln|m1| + ln|m2| = −kT
//! let sum = orbit.log_abs_multipliers[0] + orbit.log_abs_multipliers[1];
//! assert!((sum + orbit.period).abs() < 1e-8 * orbit.period);
//! ```

use crate::error::{Error, Result};
use crate::integrate::{Method, Options, Stepper, System, stepper};
use crate::params::Params;
use serde::Serialize;

mod branch;
mod continuation;
mod diagram;
mod floquet;
mod from_branch;
mod gpd;
mod lyapunov;
mod normal_form;
mod orbit_length;
mod oscillator;
mod response;
mod saltation;
mod shooting;
mod two_parameter;
pub use crate::params::{Box2, Scale};
pub use branch::*;
pub use continuation::*;
pub use diagram::*;
pub use floquet::*;
pub use from_branch::{curves_at_gpds, curves_from_branch};
pub use gpd::switch_at_gpd;
pub use lyapunov::*;
pub use normal_form::{Criticality, FLIP_FD_STEP, FLIP_NEAR, flip_coefficient};
pub use orbit_length::{MAX_ORBIT_STEPS, check_orbit_length};
pub use oscillator::Oscillator;
pub use response::*;
pub use shooting::*;
pub use two_parameter::*;

/// Longest piece (dimensionless time) over which Φ is integrated from I: 10 decay times of the
/// fast subsystem (1/2 each), so Φ's entries stay within e^{±10}·(growth of the node direction).
pub const PIECE: f64 = 5.0;

/// Time (τ) simulated from the start before shooting, rounded up to whole forcing periods (at
/// least one): the study's transient decays like e^{−τ/2}, so after 60 time units it is e^{−30},
/// and Newton starts next to the orbit. (One period of the study's ω = 0.01 is 628.)
pub const SETTLE_TIME: f64 = 60.0;

/// Newton's stopping tolerance on the residual |φ(y) − y|, relative to 1 + |y|.
pub const NEWTON_TOL: f64 = 1e-11;

/// Options of the periodic-orbit computations.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PeriodicOptions {
    /// Integrator tolerances and method (Taylor by default, DOP853 for an oscillator without
    /// Taylor coefficients); by default 1e-12 at order 20, whose longer steps pay for the
    /// variational equations' extra work per step ([`Options::order`]).
    pub tol: Options,
    /// Newton iterations at most.
    pub max_newton: usize,
    /// Output spacing of the orbit's samples.
    pub dt: f64,
}

impl Default for PeriodicOptions {
    fn default() -> Self {
        PeriodicOptions {
            tol: Options {
                rtol: 1e-12,
                atol: 1e-12,
                order: Some(crate::integrate::taylor::MAX_ORDER),
                ..Options::default()
            },
            max_newton: 20,
            dt: 0.05,
        }
    }
}

/// The oscillator in phase time s = ωτ with its variational equations and the derivative with
/// respect to one parameter: [x, x', Φ11, Φ21, Φ12, Φ22, w1, w2], Φ by columns, w = ∂(x, x')/∂λ.
struct Phase<'a, O: Oscillator> {
    o: &'a O,
    param: Option<O::Param>,
    inv_omega: f64,
}

impl<O: Oscillator> System<8> for Phase<'_, O> {
    #[inline]
    fn rhs(&self, s: f64, y: &[f64; 8]) -> [f64; 8] {
        let (x, v, k) = (y[0], y[1], self.inv_omega);
        let a = self.o.accel(s, x, v);
        let [ax, av] = self.o.accel_gradient(s, x, v);
        let (d1, d2) = match self.param {
            None => (0.0, 0.0),
            Some(p) if O::is_frequency(p) => (-v * k * k, -a * k * k),
            Some(p) => (0.0, self.o.accel_derivative(p, s, x, v) * k),
        };
        [
            v * k,
            a * k,
            y[3] * k,
            (ax * y[2] + av * y[3]) * k,
            y[5] * k,
            (ax * y[4] + av * y[5]) * k,
            y[7] * k + d1,
            (ax * y[6] + av * y[7]) * k + d2,
        ]
    }
    fn taylor(&self, s: f64, y: &[f64; 8], order: usize, c: &mut [[f64; 8]]) -> bool {
        self.o.phase_taylor(self.param, s, y, order, c)
    }
}

/// `tol` with Taylor's method replaced by DOP853 where the oscillator gives no Taylor
/// coefficients ([`Oscillator::TAYLOR`]).
pub(crate) fn method_for<O: Oscillator>(tol: Options) -> Options {
    if tol.method == Method::Taylor && !O::TAYLOR {
        Options {
            method: Method::Dop853,
            ..tol
        }
    } else {
        tol
    }
}
