//! The wave generator's own excitation as a term: the kinematic (transmission) error of the
//! gear mesh, periodic in the wave generator's angle.

use super::jet::sin_cos_coefficients;
use super::term::{Domain, ParamInfo, Scratch, StateInfo, Term};
use serde::Serialize;

/// Kinematic error e(θ_wg) = A·sin(kθ_wg + ψ) at a constant wave-generator speed θ_wg' = Ω_in
/// (Tuttle & Seering 1996; k = 2, twice per revolution, is the dominant harmonic of a harmonic
/// drive). The output lags the ideal ratio by e, so the total twist is x + e with x the elastic
/// twist, which the model's state holds: the stiffness and every other term act on x, the
/// inertia and the unit damping on the total, and moving their share of e to the left-hand side
/// gives the base excitation T = e'' + e' = A·(kΩ_in·cos φ − (kΩ_in)²·sin φ), φ = kθ_wg + ψ.
/// A torque whatever the motion at the frequency kΩ_in: far above the fast mode it leaves a
/// ripple of about A on x, which averages into the cubic as a dither's does
/// ([`Term::dither`], [`super::control::dither_ripple`]); where kΩ_in meets the fast mode's
/// frequency √g' it resonates (the critical input speeds).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct KinematicError(pub [f64; 4]);

impl KinematicError {
    /// kΩ_in, the excitation's angular frequency.
    fn frequency(&self) -> f64 {
        self.0[1] * self.0[2]
    }

    /// The torque's two parts at phase φ: (cos φ's factor kΩ_in·A, sin φ's −(kΩ_in)²·A).
    fn factors(&self) -> (f64, f64) {
        let w = self.frequency();
        (self.0[0] * w, -self.0[0] * w * w)
    }

    /// (sin φ, cos φ) at the wave generator's angle θ, φ = kθ + ψ.
    fn sin_cos(&self, theta: f64) -> (f64, f64) {
        libm::sincos(self.0[1] * theta + self.0[3])
    }

    /// ∂T/∂φ at angle θ.
    fn phase_derivative(&self, theta: f64) -> f64 {
        let (c, s) = self.factors();
        let (sin, cos) = self.sin_cos(theta);
        s * cos - c * sin
    }
}

impl Term for KinematicError {
    const KIND: &'static str = "kinematic";
    const ABOUT: &'static str = "kinematic error of the mesh: the base excitation of e = A·sin(kθ_wg + ψ) at the \
         wave-generator speed θ_wg' = Ω_in";
    const STATE: Option<StateInfo> = Some(StateInfo {
        name: "thwg",
        meaning: "wave-generator angle Ω_in·τ",
    });
    const PARAMS: &'static [ParamInfo] = &[
        ParamInfo {
            name: "ke",
            symbol: "A",
            latex: "A",
            meaning: "amplitude of the kinematic error",
            domain: Domain::NonNegative,
            default: 0.0,
            si: "e/L (e in rad at the output; L the model's length scale)",
        },
        ParamInfo {
            name: "kharm",
            symbol: "k",
            latex: "k",
            meaning: "harmonic of the error per wave-generator revolution",
            domain: Domain::Exponent,
            default: 2.0,
            si: "cycles per revolution of the wave generator",
        },
        ParamInfo {
            name: "win",
            symbol: "Ω_in",
            latex: r"\Omega_{in}",
            meaning: "angular speed of the wave generator",
            domain: Domain::Positive,
            default: 10.0,
            si: "Ω_in·J_eq/C (Ω_in in rad/s)",
        },
        ParamInfo {
            name: "psike",
            symbol: "ψ",
            latex: r"\psi",
            meaning: "phase of the kinematic error",
            domain: Domain::Any,
            default: 0.0,
            si: "rad",
        },
    ];
    const LOAD: bool = true;
    const PHASE_RATE: Option<usize> = Some(2);
    fn from_values(v: &[f64]) -> Self {
        KinematicError([v[0], v[1], v[2], v[3]])
    }
    fn values(&self) -> &[f64] {
        &self.0
    }
    fn torque(&self, _x: f64, _v: f64, theta: f64) -> f64 {
        let (c, s) = self.factors();
        let (sin, cos) = self.sin_cos(theta);
        c * cos + s * sin
    }
    fn gradient(&self, _x: f64, _v: f64, theta: f64) -> [f64; 3] {
        [0.0, 0.0, self.0[1] * self.phase_derivative(theta)]
    }
    fn param_derivative(&self, i: usize, _x: f64, _v: f64, theta: f64) -> f64 {
        let [a, k, w, _] = self.0;
        let (sin, cos) = self.sin_cos(theta);
        let f = k * w;
        match i {
            0 => f * cos - f * f * sin,
            // through the frequency kΩ_in and, for k, the phase kθ
            1 => a * w * (cos - 2.0 * f * sin) + theta * self.phase_derivative(theta),
            2 => a * k * (cos - 2.0 * f * sin),
            _ => self.phase_derivative(theta),
        }
    }
    /// φ = kθ + ψ (row 2), sin φ (row 0) and cos φ (row 1) by their recurrences.
    #[inline(always)]
    fn taylor(&self, k: usize, _x: &[f64], _v: &[f64], theta: &[f64], rows: &mut Scratch) -> f64 {
        let [s, c, phi, ..] = &mut rows.0;
        phi[k] = self.0[1] * theta[k] + if k == 0 { self.0[3] } else { 0.0 };
        (s[k], c[k]) = sin_cos_coefficients(phi, s, c, k);
        let (fc, fs) = self.factors();
        fc * c[k] + fs * s[k]
    }
    fn text(&self) -> String {
        " + A·kΩ_in·cos(kθ_wg + ψ) − A·(kΩ_in)²·sin(kθ_wg + ψ)".into()
    }
    fn latex(&self) -> String {
        r" + A k\Omega_{in} \cos(k\theta_{wg} + \psi) - A (k\Omega_{in})^2 \sin(k\theta_{wg} + \psi)"
            .into()
    }
    fn rate_text(&self) -> Option<String> {
        Some("θ_wg' = Ω_in".into())
    }
    fn rate_latex(&self) -> Option<String> {
        Some(r"\dot\theta_{wg} = \Omega_{in}".into())
    }
    /// −e' = −A·kΩ_in·cos ψ at the wave generator's angle at rest, θ_wg = 0: the elastic twist
    /// moves against the error, so that the output, on the total twist x + e, starts at rest. A
    /// start at x' = 0 would start the output at e' instead, a transient of about A·kΩ_in in x'.
    fn twist_rate_at_rest(&self) -> f64 {
        -self.factors().0 * self.sin_cos(self.state_at_rest(0.0)).1
    }
    /// The torque's amplitude A·kΩ_in·√(1 + (kΩ_in)²) at kΩ_in, for the verdict's averaging
    /// (at A = 0 the model is the one without the error: [`super::Model::dither`]).
    fn dither(&self) -> Option<[f64; 2]> {
        let w = self.frequency();
        Some([self.0[0] * w * (1.0 + w * w).sqrt(), w])
    }
}
