//! Delayed feedback ũ = K·(x(τ − τ_d) − x(τ)) as a term ([`Delay`]): it carries the delayed
//! twist x_d = x(τ − τ_d) as its state, which no equation of the state gives; the run supplies
//! it from its own history ([`super::delayed::Delayed`], the method of steps).
use super::term::{Domain, ParamInfo, Scratch, StateInfo, Term};
use serde::Serialize;

/// Delayed feedback ũ = K·(x(τ − τ_d) − x(τ)) on the twist: the term K·(x − x_d), x_d the twist
/// τ_d ago. Zero on every equilibrium (x_d = x at rest), so the equilibrium curve is the open
/// loop's. Integrated only by the method of steps ([`super::delayed::Delayed`]): the state x_d has no rate of
/// its own ([`Term::rate`] is NaN, so a machine that integrated it without its history would
/// fail at once rather than run a wrong model).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Delay(pub [f64; 2]);

impl Term for Delay {
    const KIND: &'static str = "delay";
    const ABOUT: &'static str =
        "delayed feedback: ũ = K·(x(τ − τ_d) − x(τ)), by the method of steps (DOP853)";
    const STATE: Option<StateInfo> = Some(StateInfo {
        name: "xd",
        meaning: "the delayed twist x(τ − τ_d), read from the run's history",
    });
    const PARAMS: &'static [ParamInfo] = &[
        ParamInfo {
            name: "kdelay",
            symbol: "K",
            latex: "K",
            meaning: "gain of the delayed feedback",
            domain: Domain::NonNegative,
            default: 0.0,
            si: "K·J_eq²/(N²·J_i·C²) (K in N m/rad of twist)",
        },
        ParamInfo {
            name: "taud",
            symbol: "τ_d",
            latex: r"\tau_d",
            meaning: "delay of the feedback",
            domain: Domain::Positive,
            default: 1.0,
            si: "t_d·C/J_eq",
        },
    ];
    fn from_values(v: &[f64]) -> Self {
        Delay([v[0], v[1]])
    }
    fn values(&self) -> &[f64] {
        &self.0
    }
    fn torque(&self, x: f64, _v: f64, xd: f64) -> f64 {
        self.0[0] * (x - xd)
    }
    fn gradient(&self, _x: f64, _v: f64, _xd: f64) -> [f64; 3] {
        [self.0[0], 0.0, -self.0[0]]
    }
    /// ∂/∂K = x − x_d; ∂/∂τ_d is the history's K·x'(τ − τ_d), which the state does not hold:
    /// NaN.
    fn param_derivative(&self, i: usize, x: f64, _v: f64, xd: f64) -> f64 {
        if i == 0 { x - xd } else { f64::NAN }
    }
    #[inline(always)]
    fn taylor(&self, k: usize, x: &[f64], _v: &[f64], xd: &[f64], _rows: &mut Scratch) -> f64 {
        self.0[0] * (x[k] - xd[k])
    }
    /// x_d' = x'(τ − τ_d): the history's, not the state's (NaN here; [`super::delayed::Delayed`] supplies it).
    fn rate(&self, _x: f64, _v: f64, _xd: f64) -> f64 {
        f64::NAN
    }
    fn rate_taylor(&self, _k: usize, _x: &[f64], _v: &[f64], _z: &[f64], _r: &mut Scratch) -> f64 {
        f64::NAN
    }
    fn text(&self) -> String {
        " + K·(x − x_d)".into()
    }
    fn latex(&self) -> String {
        r" + K (x - x_d)".into()
    }
    fn rate_text(&self) -> Option<String> {
        Some("x_d(τ) = x(τ − τ_d)".into())
    }
    fn rate_latex(&self) -> Option<String> {
        Some(r"x_d(\tau) = x(\tau - \tau_d)".into())
    }
    fn state_at_rest(&self, x: f64) -> f64 {
        x
    }
    fn delay(&self) -> Option<[f64; 2]> {
        Some(self.0)
    }
}
