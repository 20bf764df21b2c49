//! The drive's spring in its physical form as a term: the two-inertia model's twist law
//! ([`crate::physical::model::Physical`]) and, in any model, a hardening stiffness with a
//! backlash offset that the study's reduced form cannot hold (no backlash, or no cubic).

use super::jet::{Jet, Lanes};
use super::term::{Domain, LaneRows, ParamInfo, Scratch, Term, cubic_row, cubic_taylor};
use serde::Serialize;

/// The hardening spring T(x) = (k_l + k_c·x²)(x − φ): the flexspline's linear and cubic
/// stiffness acting on the twist beyond the backlash offset φ. In SI units (x = θ in rad, k_l in
/// N m/rad, k_c in N m/rad³) it is the two-inertia drive's twist torque
/// ([`crate::physical::PhysicalParams::spring`]); where the drive reduces to the study's form
/// (φ > 0, k_c > 0) it is the study's stiffness αx³ − x² + γ(x − ε) in the reduction's units, with
/// α·ε = 1 ([`super::terms::Stiffness`], whose ε may differ from 1/α).
///
/// ```
/// use hdgear::model::terms::{AnyTerm, Term};
/// use hdgear::model::spring::Spring;
/// let s = Spring([2e3, 1e9, 1e-3]);
/// assert_eq!(s.torque(1e-3, 0.0, 0.0), 0.0);
/// assert!((s.torque(2e-3, 0.0, 0.0) - (2e3 + 1e9 * 4e-6) * 1e-3).abs() < 1e-12);
/// assert!(AnyTerm::new("spring", &[2e3, -1.0, 0.0]).is_err()); // k_c ≥ 0: hardening
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Spring(pub [f64; 3]);

impl Term for Spring {
    const KIND: &'static str = "spring";
    const ABOUT: &'static str = "hardening spring with backlash offset (k_l + k_c·x²)(x − φ): the \
         two-inertia drive's twist law";
    const ON_LANES: bool = true;
    const PARAMS: &'static [ParamInfo] = &[
        ParamInfo {
            name: "klin",
            symbol: "k_l",
            latex: "k_l",
            meaning: "linear stiffness of the spring",
            domain: Domain::Any,
            default: 0.0,
            si: "k1·L/unit torque (k1 in N m/rad)",
        },
        ParamInfo {
            name: "kcub",
            symbol: "k_c",
            latex: "k_c",
            meaning: "cubic (hardening) stiffness of the spring",
            domain: Domain::NonNegative,
            default: 0.0,
            si: "k2·L³/unit torque (k2 in N m/rad³)",
        },
        ParamInfo {
            name: "phi",
            symbol: "φ",
            latex: r"\varphi",
            meaning: "backlash offset of the spring",
            domain: Domain::Any,
            default: 0.0,
            si: "φ/L (φ in rad)",
        },
    ];
    fn from_values(v: &[f64]) -> Self {
        Spring([v[0], v[1], v[2]])
    }
    fn values(&self) -> &[f64] {
        &self.0
    }
    fn torque(&self, x: f64, _v: f64, _z: f64) -> f64 {
        let [kl, kc, phi] = self.0;
        (kl + kc * x * x) * (x - phi)
    }
    fn gradient(&self, x: f64, _v: f64, _z: f64) -> [f64; 3] {
        let [kl, kc, phi] = self.0;
        [kl + kc * x * (3.0 * x - 2.0 * phi), 0.0, 0.0]
    }
    fn param_derivative(&self, i: usize, x: f64, _v: f64, _z: f64) -> f64 {
        let [kl, kc, phi] = self.0;
        [x - phi, x * x * (x - phi), -(kl + kc * x * x)][i]
    }
    cubic_taylor!(|[kl, kc, phi]| [kc, -(kc * phi), kl, -(kl * phi)]);
    fn text(&self) -> String {
        " + (k_l + k_c·x²)(x − φ)".into()
    }
    fn latex(&self) -> String {
        r" + (k_l + k_c x^2)(x - \varphi)".into()
    }
}
