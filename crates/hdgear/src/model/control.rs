//! Feedback laws as terms: a motor-side control torque u enters the reduced model as
//! x'' + … = μ + δ sin ωτ + ũ, ũ = u·T²/(L·N²·J_i) (T = J_eq/C and L the model's time and length
//! scales), so a law ũ = −F(x, x', ξ) is the term +F on the left-hand side, with its gains as
//! parameters and a filter's state as the term's own state. [`crate::control`] measures what
//! each law does.

use super::jet::sin_cos_coefficients;
use super::law::{Declared, Law, Num, Vars};
use super::term::{Domain, ParamInfo, Scratch, StateInfo, Term};
use serde::Serialize;

/// The SI reading of a stiffness gain (a torque per unit twist at the motor).
const STIFFNESS_GAIN_SI: &str = "K·J_eq²/(N²·J_i·C²) (K in N m/rad of twist)";

/// Virtual stiffness ũ = −k_p·x: feedback on the twist. Exactly the open-loop model with
/// γ → γ + k_p and ε → γε/(γ + k_p) (the term is linear in x and folds into the stiffness).
pub type VirtualStiffness = Declared<VirtualStiffnessLaw>;

/// [`VirtualStiffness`]'s law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VirtualStiffnessLaw;

impl Law for VirtualStiffnessLaw {
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
    const TEXT: &'static str = " + k_p·x";
    const LATEX: &'static str = " + k_p x";
    #[inline(always)]
    fn torque<N: Num>(s: &Vars<N>, p: &[N]) -> N {
        p[0] * s.x
    }
}

/// Virtual damping ũ = −k_d·x': feedback on the twist rate (adds to the unit damping).
pub type VirtualDamping = Declared<VirtualDampingLaw>;

/// [`VirtualDamping`]'s law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VirtualDampingLaw;

impl Law for VirtualDampingLaw {
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
    const TEXT: &'static str = " + k_d·x'";
    const LATEX: &'static str = r" + k_d \dot x";
    #[inline(always)]
    fn torque<N: Num>(s: &Vars<N>, p: &[N]) -> N {
        p[0] * s.v
    }
}

/// Washout feedback ũ = −k_w·(x − ξ), ξ' = ω_w·(x − ξ): a high-pass filter of the twist, zero on
/// every equilibrium (ξ = x at rest), so the equilibrium curve is the open loop's and only
/// departures faster than ω_w are opposed, with the stiffness k_w.
pub type Washout = Declared<WashoutLaw>;

/// [`Washout`]'s law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WashoutLaw;

impl Law for WashoutLaw {
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
    const TEXT: &'static str = " + k_w·(x − ξ)";
    const LATEX: &'static str = r" + k_w (x - \xi)";
    const RATE_TEXT: Option<&'static str> = Some("ξ' = ω_w·(x − ξ)");
    const RATE_LATEX: Option<&'static str> = Some(r"\dot\xi = \omega_w (x - \xi)");
    #[inline(always)]
    fn torque<N: Num>(s: &Vars<N>, p: &[N]) -> N {
        p[0] * (s.x - s.z)
    }
    #[inline(always)]
    fn rate<N: Num>(s: &Vars<N>, p: &[N]) -> N {
        p[1] * (s.x - s.z)
    }
    /// ξ = x: the filter has followed the twist to rest.
    fn state_at_rest(x: f64, _p: &[f64]) -> f64 {
        x
    }
}

/// Dither ũ = D·sin θ, θ' = Ω_d: a fast periodic torque whatever the motion (θ, its phase, is the
/// term's state, so the model stays autonomous apart from the slow load). At Ω_d ≫ 1 the twist
/// carries a ripple A·sin θ about a slower motion X, and averaged over the ripple the cubic
/// stiffens: ⟨g(X + A sin θ)⟩ = g(X) + 1.5αA²·X − A²/2 ([`dither_ripple`]). The burst verdict
/// of a dithered model is taken on its motion averaged over the dither period
/// ([`crate::burst::response_model`]), against the averaged model's equilibria
/// ([`super::Model::equivalent_params`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Dither(pub [f64; 2]);

impl Term for Dither {
    const KIND: &'static str = "dither";
    const ABOUT: &'static str = "dither: a fast control torque ũ = D·sin θ with the phase θ' = Ω_d";
    const STATE: Option<StateInfo> = Some(StateInfo {
        name: "theta",
        meaning: "dither phase Ω_d·τ",
    });
    const PARAMS: &'static [ParamInfo] = &[
        ParamInfo {
            name: "dd",
            symbol: "D",
            latex: "D",
            meaning: "amplitude of the dither torque",
            domain: Domain::NonNegative,
            default: 0.0,
            si: "u_d·T²/(L·N²·J_i) (u_d in N m at the motor)",
        },
        ParamInfo {
            name: "wd",
            symbol: "Ω_d",
            latex: r"\Omega_d",
            meaning: "angular frequency of the dither",
            domain: Domain::Positive,
            default: 10.0,
            si: "Ω_d·J_eq/C",
        },
    ];
    const LOAD: bool = true;
    const PHASE_RATE: Option<usize> = Some(1);
    fn from_values(v: &[f64]) -> Self {
        Dither([v[0], v[1]])
    }
    fn values(&self) -> &[f64] {
        &self.0
    }
    fn torque(&self, _x: f64, _v: f64, theta: f64) -> f64 {
        -self.0[0] * libm::sin(theta)
    }
    fn gradient(&self, _x: f64, _v: f64, theta: f64) -> [f64; 3] {
        [0.0, 0.0, -self.0[0] * libm::cos(theta)]
    }
    fn param_derivative(&self, i: usize, _x: f64, _v: f64, theta: f64) -> f64 {
        if i == 0 { -libm::sin(theta) } else { 0.0 }
    }
    /// sin θ (row 0) and cos θ (row 1) by their recurrences.
    #[inline(always)]
    fn taylor(&self, k: usize, _x: &[f64], _v: &[f64], theta: &[f64], rows: &mut Scratch) -> f64 {
        let [s, c, ..] = &mut rows.0;
        (s[k], c[k]) = sin_cos_coefficients(theta, s, c, k);
        -self.0[0] * s[k]
    }
    fn text(&self) -> String {
        " − D·sin θ".into()
    }
    fn latex(&self) -> String {
        r" - D \sin\theta".into()
    }
    fn rate_text(&self) -> Option<String> {
        Some("θ' = Ω_d".into())
    }
    fn rate_latex(&self) -> Option<String> {
        Some(r"\dot\theta = \Omega_d".into())
    }
    fn dither(&self) -> Option<[f64; 2]> {
        Some(self.0)
    }
}

/// The ripple amplitude A a dither of amplitude `amplitude` and angular frequency `omega_d`
/// leaves on the twist where the bursts form, the inflection of the averaged cubic: the linear
/// response of x'' + c·x' + k·x at Ω_d, A = D/√((k − Ω_d²)² + (cΩ_d)²), with c the damping at
/// rest and k the averaged slope there, k = `gprime_min` + 1.5αA² (`gprime_min` = γ − 1/(3α),
/// the open loop's); solved for A by fixed-point iteration (a contraction where Ω_d² exceeds
/// k, which first-order averaging needs anyway).
///
/// ```
/// use hdgear::model::control::dither_ripple;
/// // far above every stiffness: A → D/(Ω_d·√(Ω_d² + c²))
/// let a = dither_ripple(16.0, 0.0, 1.0, 1e3, 1.0);
/// assert!((a - 1.0 / (1e3 * (1e6_f64 + 1.0).sqrt())).abs() < 1e-15);
/// ```
pub fn dither_ripple(alpha: f64, gprime_min: f64, amplitude: f64, omega_d: f64, c: f64) -> f64 {
    let w2 = omega_d * omega_d;
    let response = |a: f64| {
        let k = gprime_min + 1.5 * alpha * a * a;
        amplitude / ((k - w2).powi(2) + (c * omega_d).powi(2)).sqrt()
    };
    let mut a = response(0.0);
    for _ in 0..200 {
        let next = response(a);
        if (next - a).abs() <= 1e-15 * next {
            return next;
        }
        a = next;
    }
    a
}
