//! Quadratic damping, declared ([`super::law`]): the example of a term in one short file.

use super::law::{Declared, Law, Num, Vars};
use super::term::{Domain, ParamInfo};

/// Quadratic damping c_q·x'·|x'|: a drag growing with the square of the speed (churning of the
/// lubricant in an oil-bath gear), odd in x' like a damping.
///
/// ```
/// use hdgear::model::terms::{AnyTerm, Term};
/// let t = AnyTerm::new("drag", &[0.5]).unwrap();
/// assert_eq!(t.torque(0.0, -2.0, 0.0), -2.0);
/// assert_eq!(t.gradient(0.0, -2.0, 0.0), [0.0, 2.0, 0.0]); // 2·c_q·|x'|, derived
/// ```
pub type Drag = Declared<DragLaw>;

/// [`Drag`]'s law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DragLaw;

impl Law for DragLaw {
    const KIND: &'static str = "drag";
    const ABOUT: &'static str = "quadratic damping c_q·x'·|x'| (drag of the lubricant)";
    const PARAMS: &'static [ParamInfo] = &[ParamInfo {
        name: "cq",
        symbol: "c_q",
        latex: "c_q",
        meaning: "quadratic damping coefficient",
        domain: Domain::NonNegative,
        default: 0.1,
        si: "c_q·C²/(k2·φ·J_eq²) (c_q in N m s²/rad²)",
    }];
    const SWITCHES_AT_REST: bool = true;
    const TEXT: &'static str = " + c_q·x'·|x'|";
    const LATEX: &'static str = r" + c_q \dot x |\dot x|";
    #[inline(always)]
    fn torque<N: Num>(s: &Vars<N>, p: &[N]) -> N {
        p[0] * s.sv * (s.v * s.v)
    }
}
