//! The study's own two terms: the unit damping x' and the cubic stiffness
//! αx³ − x² + γ(x − ε), the model every study command starts from.

use super::jet::{Jet, Lanes};
use super::term::{Domain, LaneRows, ParamInfo, Scratch, Term, cubic_row, cubic_taylor};
use crate::params::Param;
use serde::Serialize;

/// Unit linear damping x' (the dimensionless time scale makes its coefficient 1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Damping([f64; 0]);

impl Term for Damping {
    const KIND: &'static str = "damping";
    const ABOUT: &'static str = "unit linear damping x' (the time scale makes it 1)";
    const ON_LANES: bool = true;
    const PARAMS: &'static [ParamInfo] = &[];
    fn from_values(_: &[f64]) -> Self {
        Damping([])
    }
    fn values(&self) -> &[f64] {
        &self.0
    }
    fn torque(&self, _x: f64, v: f64, _z: f64) -> f64 {
        v
    }
    fn gradient(&self, _x: f64, _v: f64, _z: f64) -> [f64; 3] {
        [0.0, 1.0, 0.0]
    }
    fn param_derivative(&self, _i: usize, _x: f64, _v: f64, _z: f64) -> f64 {
        0.0
    }
    #[inline(always)]
    fn taylor(&self, k: usize, _x: &[f64], v: &[f64], _z: &[f64], _rows: &mut Scratch) -> f64 {
        v[k]
    }
    #[inline(always)]
    fn taylor_lanes(
        _: &[Lanes],
        k: usize,
        _x: &[Lanes],
        v: &[Lanes],
        _z: &[Lanes],
        _: &mut LaneRows,
    ) -> Option<Lanes> {
        Some(v[k])
    }
    fn text(&self) -> String {
        " + x'".into()
    }
    fn latex(&self) -> String {
        r" + \dot x".into()
    }
}

/// The study's stiffness g(x) = αx³ − x² + γ(x − ε): the flexspline's cubic hardening, the
/// quadratic of the tooth contact and the linear stiffness with its backlash offset.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Stiffness(pub [f64; 3]);

impl Term for Stiffness {
    const KIND: &'static str = "stiffness";
    const ABOUT: &'static str = "cubic stiffness with backlash offset, αx³ − x² + γ(x − ε)";
    const ON_LANES: bool = true;
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
    fn from_values(v: &[f64]) -> Self {
        Stiffness([v[0], v[1], v[2]])
    }
    fn values(&self) -> &[f64] {
        &self.0
    }
    fn torque(&self, x: f64, _v: f64, _z: f64) -> f64 {
        let [alpha, gamma, eps] = self.0;
        (alpha * x - 1.0) * x * x + gamma * (x - eps)
    }
    fn gradient(&self, x: f64, _v: f64, _z: f64) -> [f64; 3] {
        let [alpha, gamma, _] = self.0;
        [(3.0 * alpha * x - 2.0) * x + gamma, 0.0, 0.0]
    }
    fn param_derivative(&self, i: usize, x: f64, _v: f64, _z: f64) -> f64 {
        let [_, gamma, eps] = self.0;
        [x * x * x, x - eps, -gamma][i]
    }
    cubic_taylor!(|[alpha, gamma, eps]| [alpha, J::splat(-1.0), gamma, -(gamma * eps)]);
    fn text(&self) -> String {
        " + αx³ − x² + γ(x − ε)".into()
    }
    fn latex(&self) -> String {
        r" + \alpha x^3 - x^2 + \gamma (x - \varepsilon)".into()
    }
}
