//! The drive's spring in its physical form as a term: the two-inertia model's twist law
//! ([`crate::physical::model::Physical`]) and, in any model, a hardening stiffness with a
//! backlash offset that the study's reduced form cannot hold (no backlash, or no cubic).
//! Declared once ([`super::law`]).

use super::law::{Declared, Law, Num, Vars};
use super::term::{Domain, ParamInfo};

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
/// let s = Spring::from_values(&[2e3, 1e9, 1e-3]);
/// assert_eq!(s.torque(1e-3, 0.0, 0.0), 0.0);
/// assert!((s.torque(2e-3, 0.0, 0.0) - (2e3 + 1e9 * 4e-6) * 1e-3).abs() < 1e-12);
/// assert!(AnyTerm::new("spring", &[2e3, -1.0, 0.0]).is_err()); // k_c ≥ 0: hardening
/// ```
pub type Spring = Declared<SpringLaw>;

/// [`Spring`]'s law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpringLaw;

impl Law for SpringLaw {
    const KIND: &'static str = "spring";
    const ABOUT: &'static str = "hardening spring with backlash offset (k_l + k_c·x²)(x − φ): the \
         two-inertia drive's twist law";
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
    const TEXT: &'static str = " + (k_l + k_c·x²)(x − φ)";
    const LATEX: &'static str = r" + (k_l + k_c x^2)(x - \varphi)";
    #[inline(always)]
    fn torque<N: Num>(s: &Vars<N>, p: &[N]) -> N {
        (p[0] + p[1] * (s.x * s.x)) * (s.x - p[2])
    }
}
