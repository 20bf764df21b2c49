//! The study's own two terms, declared ([`super::law`]): the unit damping x' and the cubic
//! stiffness αx³ − x² + γ(x − ε), the model every study command starts from.

use super::law::{Declared, Law, Num, Vars};
use super::term::{Domain, ParamInfo};
use crate::params::Param;

/// Unit linear damping x' (the dimensionless time scale makes its coefficient 1).
///
/// ```
/// use hdgear::model::terms::{Damping, Term};
/// assert_eq!(Damping::default().torque(0.3, -2.0, 0.0), -2.0);
/// ```
pub type Damping = Declared<DampingLaw>;

/// [`Damping`]'s law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DampingLaw;

impl Law for DampingLaw {
    const KIND: &'static str = "damping";
    const ABOUT: &'static str = "unit linear damping x' (the time scale makes it 1)";
    const PARAMS: &'static [ParamInfo] = &[];
    const TEXT: &'static str = " + x'";
    const LATEX: &'static str = r" + \dot x";
    #[inline(always)]
    fn torque<N: Num>(s: &Vars<N>, _p: &[N]) -> N {
        s.v
    }
}

/// The study's stiffness g(x) = αx³ − x² + γ(x − ε): the flexspline's cubic hardening, the
/// quadratic of the tooth contact and the linear stiffness with its backlash offset.
///
/// ```
/// use hdgear::model::terms::{Stiffness, Term};
/// let g = Stiffness::from_values(&[16.0, 0.1, 0.71]);
/// assert!((g.torque(0.5, 0.0, 0.0) - (2.0 - 0.25 + 0.1 * (0.5 - 0.71))).abs() < 1e-15);
/// assert_eq!(g.array(), [16.0, 0.1, 0.71]);
/// ```
pub type Stiffness = Declared<StiffnessLaw>;

/// [`Stiffness`]'s law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StiffnessLaw;

impl Law for StiffnessLaw {
    const KIND: &'static str = "stiffness";
    const ABOUT: &'static str = "cubic stiffness with backlash offset, αx³ − x² + γ(x − ε)";
    const PARAMS: &'static [ParamInfo] = &[
        ParamInfo {
            name: Param::Alpha.name(),
            symbol: "α",
            latex: r"\alpha",
            meaning: "cubic stiffness (what confines the motion)",
            domain: Domain::Positive,
            default: 16.0,
            si: "C²/(k2·φ²·J_eq)",
        },
        ParamInfo {
            name: Param::Gamma.name(),
            symbol: "γ",
            latex: r"\gamma",
            meaning: "linear stiffness",
            domain: Domain::Any,
            default: 0.1,
            si: "k1·J_eq/C²",
        },
        ParamInfo {
            name: Param::Eps.name(),
            symbol: "ε",
            latex: r"\varepsilon",
            meaning: "backlash offset of the linear term",
            domain: Domain::Any,
            default: 0.71,
            si: "k2·φ²·J_eq/C²",
        },
    ];
    const TEXT: &'static str = " + αx³ − x² + γ(x − ε)";
    const LATEX: &'static str = r" + \alpha x^3 - x^2 + \gamma (x - \varepsilon)";
    /// Written as α·x²·x − x² + (γx − γε), the cube by one square and one product.
    #[inline(always)]
    fn torque<N: Num>(s: &Vars<N>, p: &[N]) -> N {
        let x2 = s.x * s.x;
        p[0] * (x2 * s.x) - x2 + (p[1] * s.x - p[1] * p[2])
    }
}
