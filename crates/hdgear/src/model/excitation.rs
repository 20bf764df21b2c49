//! Broadband excitation as a term: a multisine load, the input of system-identification
//! benchmarks.

use super::term::{Domain, MAX_ROWS, ParamInfo, Scratch, StateInfo, Term};
use serde::Serialize;

/// A multisine load u(τ) = a·Σ_{k=k₁}^{k₂} cos(kθ + φ_k) on the phase θ' = Ω₀, with Schroeder's
/// phases φ_k = −π·j(j + 1)/K (j = k − k₁, K = k₂ − k₁ + 1 lines), which keep its crest factor
/// low (Schroeder 1970; Pintelon & Schoukens, *System Identification*, 2012, ch. 2). It is the
/// input of identification benchmarks such as Noël & Schoukens' Bouc–Wen system. As a term its
/// torque is T = −u (terms sit on the left-hand side). Its lines have equal amplitudes, so its
/// RMS is a·√(K/2); it has no lines when k₂ < k₁. It acts whatever the motion, with mean 0, so it
/// has no static part ([`Term::LOAD`]).
///
/// ```
/// use hdgear::model::{Model, terms::AnyTerm};
/// use hdgear::Params;
/// let p = Params { delta: 0.0, ..Params::default() };
/// let m = Model::study(&p).with_term(AnyTerm::new("multisine", &[0.5, 2.0, 1.0, 8.0]).unwrap()).unwrap();
/// // the load leaves the fast subsystem's equilibria where they were
/// let x0 = Model::study(&p).stable_equilibrium(0.0).unwrap();
/// assert_eq!(m.stable_equilibrium(0.0).unwrap(), x0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Multisine(pub [f64; 4]);

impl Multisine {
    /// The lines k₁ … k₂ with their phases φ_k.
    fn lines(&self) -> impl Iterator<Item = (f64, f64)> {
        let [_, _, k1, k2] = self.0;
        let count = (k2 - k1 + 1.0).max(0.0);
        (0..count as u32).map(move |j| {
            let j = f64::from(j);
            (k1 + j, -std::f64::consts::PI * j * (j + 1.0) / count)
        })
    }

    /// Σ_k weight(k)·part(sin, cos) over the lines at phase θ (of kθ + φ_k): the torque and its
    /// phase derivative.
    fn sum(&self, theta: f64, weight: impl Fn(f64) -> f64, part: impl Fn(f64, f64) -> f64) -> f64 {
        self.lines()
            .map(|(k, phi)| {
                let (s, c) = libm::sincos(k * theta + phi);
                weight(k) * part(s, c)
            })
            .sum()
    }
}

impl Term for Multisine {
    const KIND: &'static str = "multisine";
    const ABOUT: &'static str =
        "multisine load a·Σ cos(kθ + φ_k), k = k₁ … k₂, Schroeder phases, θ' = Ω₀";
    const STATE: Option<StateInfo> = Some(StateInfo {
        name: "thms",
        meaning: "the multisine's phase Ω₀·τ",
    });
    const PARAMS: &'static [ParamInfo] = &[
        ParamInfo {
            name: "msa",
            symbol: "a",
            latex: "a",
            meaning: "amplitude of each line of the multisine",
            domain: Domain::NonNegative,
            default: 0.0,
            si: "a torque on μ's scale",
        },
        ParamInfo {
            name: "msw",
            symbol: "Ω₀",
            latex: r"\Omega_0",
            meaning: "the multisine's base frequency (its period 2π/Ω₀)",
            domain: Domain::Positive,
            default: 1.0,
            si: "Ω₀·J_eq/C (Ω₀ in rad/s)",
        },
        ParamInfo {
            name: "msk1",
            symbol: "k₁",
            latex: "k_1",
            meaning: "the multisine's first line (a multiple of Ω₀)",
            domain: Domain::Line,
            default: 1.0,
            si: "a whole number",
        },
        ParamInfo {
            name: "msk2",
            symbol: "k₂",
            latex: "k_2",
            meaning: "the multisine's last line (none when below k₁)",
            domain: Domain::Line,
            default: 10.0,
            si: "a whole number",
        },
    ];
    const LOAD: bool = true;
    const PHASE_RATE: Option<usize> = Some(1);
    fn from_values(v: &[f64]) -> Self {
        Multisine([v[0], v[1], v[2], v[3]])
    }
    fn values(&self) -> &[f64] {
        &self.0
    }
    fn torque(&self, _x: f64, _v: f64, theta: f64) -> f64 {
        -self.0[0] * self.sum(theta, |_| 1.0, |_, c| c)
    }
    fn gradient(&self, _x: f64, _v: f64, theta: f64) -> [f64; 3] {
        [0.0, 0.0, self.0[0] * self.sum(theta, |k| k, |s, _| s)]
    }
    /// ∂T/∂a; the frequency enters through the phase state only, and the lines are whole
    /// numbers (0 for both).
    fn param_derivative(&self, i: usize, _x: f64, _v: f64, theta: f64) -> f64 {
        if i == 0 {
            -self.sum(theta, |_| 1.0, |_, c| c)
        } else {
            0.0
        }
    }
    /// The phase moves at the constant rate Ω₀, so each line's rows are in closed form:
    /// row j of cos(kθ + φ) is (kΩ₀)^j/j!·cos(kθ₀ + φ + jπ/2). All rows are summed at k = 0
    /// (one sine and cosine per line) into `rows` and read out after.
    #[inline(always)]
    fn taylor(&self, k: usize, _x: &[f64], _v: &[f64], theta: &[f64], rows: &mut Scratch) -> f64 {
        let out = &mut rows.0[0];
        if k == 0 {
            let [a, w, ..] = self.0;
            *out = [0.0; MAX_ROWS];
            for (line, phi) in self.lines() {
                let (s, c) = libm::sincos(line * theta[0] + phi);
                // cos(ψ + jπ/2) cycles through c, −s, −c, s
                let cycle = [c, -s, -c, s];
                let mut scale = -a;
                for (j, row) in out.iter_mut().enumerate() {
                    *row += scale * cycle[j % 4];
                    scale *= line * w / (j + 1) as f64;
                }
            }
        }
        out[k]
    }
    /// Its last line's, k₂·Ω₀ (0 without lines).
    fn load_frequency(&self) -> f64 {
        self.lines().last().map_or(0.0, |(k, _)| k * self.0[1])
    }
    fn text(&self) -> String {
        " − a·Σ_{k=k₁..k₂} cos(kθ_ms + φ_k)".into()
    }
    fn latex(&self) -> String {
        r" - a \sum_{k=k_1}^{k_2} \cos(k\theta_{ms} + \varphi_k)".into()
    }
    fn rate_text(&self) -> Option<String> {
        Some("θ_ms' = Ω₀, φ_k = −π(k − k₁)(k − k₁ + 1)/(k₂ − k₁ + 1)".into())
    }
    fn rate_latex(&self) -> Option<String> {
        Some(r"\dot\theta_{ms} = \Omega_0".into())
    }
}
