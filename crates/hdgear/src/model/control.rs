//! Feedback laws as terms: a motor-side control torque u enters the reduced model as
//! x'' + … = μ + δ sin ωτ + ũ, ũ = u·T²/(L·N²·J_i) (T = J_eq/C and L the model's time and length
//! scales), so a law ũ = −F(x, x', ξ) is the term +F on the left-hand side, with its gains as
//! parameters and a filter's state as the term's own state. [`crate::control`] measures what
//! each law does.

use super::terms::{Domain, ParamInfo, Scratch, StateInfo, Term};
use serde::Serialize;

/// The SI reading of a stiffness gain (a torque per unit twist at the motor).
const STIFFNESS_GAIN_SI: &str = "K·J_eq²/(N²·J_i·C²) (K in N m/rad of twist)";

/// Virtual stiffness ũ = −k_p·x: feedback on the twist. Exactly the open-loop model with
/// γ → γ + k_p and ε → γε/(γ + k_p) (the term is linear in x and folds into the stiffness).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct VirtualStiffness(pub [f64; 1]);

impl Term for VirtualStiffness {
    const KIND: &'static str = "vstiffness";
    const ABOUT: &'static str = "virtual stiffness: control torque ũ = −k_p·x on the twist";
    const PARAMS: &'static [ParamInfo] = &[ParamInfo {
        name: "kp",
        symbol: "k_p",
        latex: "k_p",
        meaning: "stiffness gain of the twist feedback",
        domain: Domain::NonNegative,
        default: 0.0,
        si: STIFFNESS_GAIN_SI,
    }];
    fn from_values(v: &[f64]) -> Self {
        VirtualStiffness([v[0]])
    }
    fn values(&self) -> &[f64] {
        &self.0
    }
    fn torque(&self, x: f64, _v: f64, _z: f64) -> f64 {
        self.0[0] * x
    }
    fn gradient(&self, _x: f64, _v: f64, _z: f64) -> [f64; 3] {
        [self.0[0], 0.0, 0.0]
    }
    fn param_derivative(&self, _i: usize, x: f64, _v: f64, _z: f64) -> f64 {
        x
    }
    fn taylor(&self, k: usize, x: &[f64], _v: &[f64], _z: &[f64], _rows: &mut Scratch) -> f64 {
        self.0[0] * x[k]
    }
    fn text(&self) -> String {
        " + k_p·x".into()
    }
    fn latex(&self) -> String {
        " + k_p x".into()
    }
}

/// Virtual damping ũ = −k_d·x': feedback on the twist rate (adds to the unit damping).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct VirtualDamping(pub [f64; 1]);

impl Term for VirtualDamping {
    const KIND: &'static str = "vdamping";
    const ABOUT: &'static str = "virtual damping: control torque ũ = −k_d·x' on the twist rate";
    const PARAMS: &'static [ParamInfo] = &[ParamInfo {
        name: "kd",
        symbol: "k_d",
        latex: "k_d",
        meaning: "damping gain of the twist-rate feedback",
        domain: Domain::NonNegative,
        default: 0.0,
        si: "K_d·J_eq/(N²·J_i·C) (K_d in N m s/rad of twist)",
    }];
    fn from_values(v: &[f64]) -> Self {
        VirtualDamping([v[0]])
    }
    fn values(&self) -> &[f64] {
        &self.0
    }
    fn torque(&self, _x: f64, v: f64, _z: f64) -> f64 {
        self.0[0] * v
    }
    fn gradient(&self, _x: f64, _v: f64, _z: f64) -> [f64; 3] {
        [0.0, self.0[0], 0.0]
    }
    fn param_derivative(&self, _i: usize, _x: f64, v: f64, _z: f64) -> f64 {
        v
    }
    fn taylor(&self, k: usize, _x: &[f64], v: &[f64], _z: &[f64], _rows: &mut Scratch) -> f64 {
        self.0[0] * v[k]
    }
    fn text(&self) -> String {
        " + k_d·x'".into()
    }
    fn latex(&self) -> String {
        r" + k_d \dot x".into()
    }
}

/// Washout feedback ũ = −k_w·(x − ξ), ξ' = ω_w·(x − ξ): a high-pass filter of the twist, zero on
/// every equilibrium (ξ = x at rest), so the equilibrium curve is the open loop's and only
/// departures faster than ω_w are opposed, with the stiffness k_w.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Washout(pub [f64; 2]);

impl Term for Washout {
    const KIND: &'static str = "washout";
    const ABOUT: &'static str =
        "washout feedback: ũ = −k_w·(x − ξ) with the filter state ξ' = ω_w·(x − ξ)";
    const STATE: Option<StateInfo> = Some(StateInfo {
        name: "xi",
        meaning: "washout filter state (the twist low-passed at ω_w)",
    });
    const PARAMS: &'static [ParamInfo] = &[
        ParamInfo {
            name: "kw",
            symbol: "k_w",
            latex: "k_w",
            meaning: "stiffness gain of the washout feedback",
            domain: Domain::NonNegative,
            default: 0.0,
            si: STIFFNESS_GAIN_SI,
        },
        ParamInfo {
            name: "ww",
            symbol: "ω_w",
            latex: r"\omega_w",
            meaning: "washout filter's corner frequency",
            domain: Domain::Positive,
            default: 0.1,
            si: "Ω_w·J_eq/C",
        },
    ];
    fn from_values(v: &[f64]) -> Self {
        Washout([v[0], v[1]])
    }
    fn values(&self) -> &[f64] {
        &self.0
    }
    fn torque(&self, x: f64, _v: f64, xi: f64) -> f64 {
        self.0[0] * (x - xi)
    }
    fn gradient(&self, _x: f64, _v: f64, _xi: f64) -> [f64; 3] {
        [self.0[0], 0.0, -self.0[0]]
    }
    fn param_derivative(&self, i: usize, x: f64, _v: f64, xi: f64) -> f64 {
        if i == 0 { x - xi } else { 0.0 }
    }
    fn taylor(&self, k: usize, x: &[f64], _v: &[f64], xi: &[f64], _rows: &mut Scratch) -> f64 {
        self.0[0] * (x[k] - xi[k])
    }
    fn rate(&self, x: f64, _v: f64, xi: f64) -> f64 {
        self.0[1] * (x - xi)
    }
    fn rate_gradient(&self, _x: f64, _v: f64, _xi: f64) -> [f64; 3] {
        [self.0[1], 0.0, -self.0[1]]
    }
    fn rate_param_derivative(&self, i: usize, x: f64, _v: f64, xi: f64) -> f64 {
        if i == 1 { x - xi } else { 0.0 }
    }
    fn rate_taylor(&self, k: usize, x: &[f64], _v: &[f64], xi: &[f64], _r: &mut Scratch) -> f64 {
        self.0[1] * (x[k] - xi[k])
    }
    fn text(&self) -> String {
        " + k_w·(x − ξ)".into()
    }
    fn latex(&self) -> String {
        r" + k_w (x - \xi)".into()
    }
    fn rate_text(&self) -> Option<String> {
        Some("ξ' = ω_w·(x − ξ)".into())
    }
    fn rate_latex(&self) -> Option<String> {
        Some(r"\dot\xi = \omega_w (x - \xi)".into())
    }
    fn state_at_rest(&self, x: f64) -> f64 {
        x
    }
}
