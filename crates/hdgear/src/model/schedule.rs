//! Scheduled stiffness, the study's "feedback on a": a stiffness gain k(a) that the slow load's
//! phase schedules, ũ = −k(a)·(x − x_c), strong where the traversal crosses the soft middle of
//! the curve and zero elsewhere.
//!
//! About the point x_c = 1/(3α) where the cubic is softest, g(x_c + s) = g_c + g'_c·s + αs³
//! with g'_c = γ − 1/(3α) (its least slope). The closed loop's equilibria at a solve
//! αs³ + (g'_c + k(a))·s = b₀ + δa, b₀ = μ − g_c, with the slope g'_c + k(a) + 3αs². To keep
//! that slope at least g'_min everywhere, the schedule takes the stiffened reference curve
//! αs₀³ + g'_min·s₀ = b₀ + δa (monotone, one real root, Cardano's formula) and sets
//!
//! k(a) = max(0, D − 3α·s₀(a)²), D = g'_min − g'_c,
//!
//! the least gain that gives the reference point s₀(a) the slope g'_min. The closed loop's
//! followed equilibrium then lies at |s| ≥ |s₀| on s₀'s side: at s₀ the residual is
//! (k − D)·s₀, of the sign opposite to s₀ whenever k ≤ D, so the root lies beyond s₀, and its
//! slope is g'_c + k + 3αs² ≥ g'_c + k + 3αs₀² ≥ g'_min. (With D ≤ 0 the plant is steep
//! enough: k ≡ 0 and every slope is at least g'_c ≥ g'_min.) With no fold on the closed loop's
//! path the fast-slow passage has no jump.
//!
//! The schedule is the controller's: its parameters are the plant model it was built from (α, x_c,
//! g'_c, b₀, δ, ω), which a model error leaves behind.

use super::jet::sin_cos_coefficients;
use super::terms::{Domain, ParamInfo, Scratch, Term};
use crate::params::Params;
use serde::Serialize;

/// Scheduled stiffness ũ = −k(a)·(x − x_c), a = sin θ, θ' = ω (the load's phase), k(a) =
/// max(0, g'_min − g'_c − 3α·s₀(a)²) with s₀ the root of αs₀³ + g'_min·s₀ = b₀ + δa (see the
/// [module](self)). Parameters: g'_min (the gain a tuner searches), then the plant model α,
/// x_c, g'_c, b₀, δ, ω. Their defaults are the schedule for the study's default set with
/// g'_min = 0.3.
///
/// ```
/// use hdgear::Params;
/// use hdgear::model::schedule::Scheduled;
/// let p = Params::default(); // least slope γ − 1/(3α) ≈ 0.079
/// let law = Scheduled::for_plant(&p, 0.3);
/// // largest at the softest point, zero where the curve is stiff enough on its own
/// let x_c = 1.0 / (3.0 * p.alpha);
/// let at_xc = p.a_at(x_c);
/// assert!((law.gain(at_xc) - (0.3 - p.g_prime(x_c))).abs() < 1e-12);
/// assert_eq!(law.gain(1.0), 0.0);
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Scheduled(pub [f64; 7]);

/// Where the schedule keeps its rows in [`Scratch`]: sin θ, cos θ, s₀, s₀², and the piece (at 0:
/// 1 where the gain is on, 0 where it is off) with θ₀ (at 1).
const SIN: usize = 0;
const COS: usize = 1;
const S: usize = 2;
const S2: usize = 3;
const PIECE: usize = 4;
/// The piece of a step that starts on the gain's kink, until its row 1 shows which way it goes.
const UNDECIDED: f64 = 2.0;

impl Scheduled {
    /// The schedule for the study plant `p` with the target least slope `gmin`.
    pub fn for_plant(p: &Params, gmin: f64) -> Scheduled {
        let xc = 1.0 / (3.0 * p.alpha);
        Scheduled([
            gmin,
            p.alpha,
            xc,
            p.g_prime(xc),
            p.mu - p.g(xc),
            p.delta,
            p.omega,
        ])
    }

    /// The stiffened reference's offset s₀(a) from x_c: the real root of
    /// αs³ + g'_min·s = b₀ + δa (g'_min > 0), by Cardano's formula s = u − p/(3u),
    /// u = sgn(r)·∛(|r| + √(r² + (p/3)³)), p = g'_min/α, r = (b₀ + δa)/(2α), then one Newton
    /// step, which restores the digits the subtraction loses near r = 0.
    pub fn reference(&self, a: f64) -> f64 {
        let [m, alpha, _, _, b0, delta, _] = self.0;
        let (p, r) = (m / alpha, 0.5 * (b0 + delta * a) / alpha);
        let root = (r * r + (p / 3.0).powi(3)).sqrt();
        let u = (r.abs() + root)
            .cbrt()
            .copysign(if r == 0.0 { 1.0 } else { r });
        let s = u - p / (3.0 * u);
        s - (alpha * s * s * s + m * s - 2.0 * alpha * r) / (3.0 * alpha * s * s + m)
    }

    /// The gain k(a) = max(0, D − 3α·s₀(a)²).
    pub fn gain(&self, a: f64) -> f64 {
        self.unclamped(self.reference(a)).max(0.0)
    }

    /// D − 3α·s²: the gain at the reference point s before it is clamped at 0.
    fn unclamped(&self, s: f64) -> f64 {
        self.deficit() - 3.0 * self.0[1] * s * s
    }

    /// D = g'_min − g'_c: the gain at the softest point (≤ 0: no gain anywhere).
    pub fn deficit(&self) -> f64 {
        self.0[0] - self.0[3]
    }

    /// The load levels a₋ < a₊ between which the gain is on (s₀ = ∓√(D/(3α))); `None` when it is
    /// never on (D ≤ 0) or the load does not move the reference (δ̂ = 0).
    pub fn levels(&self) -> Option<[f64; 2]> {
        let [m, alpha, _, _, b0, delta, _] = self.0;
        let d = self.deficit();
        if d <= 0.0 || delta == 0.0 {
            return None;
        }
        let edge = (d / (3.0 * alpha)).sqrt();
        Some([-edge, edge].map(|s| (alpha * s * s * s + m * s - b0) / delta))
    }

    /// ∂s₀/∂(b₀ + δa) = 1/(3αs₀² + g'_min).
    fn reference_slope(&self, s: f64) -> f64 {
        1.0 / (3.0 * self.0[1] * s * s + self.0[0])
    }
}

impl Term for Scheduled {
    const KIND: &'static str = "scheduled";
    const ABOUT: &'static str = "scheduled stiffness: ũ = −k(a)·(x − x_c), a = sin θ, θ' = ω, \
         k(a) the least gain giving the stiffened reference the slope g'_min";
    const STATE: Option<super::terms::StateInfo> = Some(super::terms::StateInfo {
        name: "thsch",
        meaning: "the load's phase ωτ, which schedules the gain",
    });
    const PARAMS: &'static [ParamInfo] = &[
        ParamInfo {
            name: "gmin",
            symbol: "g'_min",
            latex: "g'_{min}",
            meaning: "least slope the schedule keeps on the closed loop's equilibrium curve",
            domain: Domain::Positive,
            default: 0.3,
            si: "a stiffness on γ's scale (K·J_eq/C²)",
        },
        ParamInfo {
            name: "salpha",
            symbol: "α̂",
            latex: r"\hat\alpha",
            meaning: "the schedule's plant model: the cubic's coefficient α",
            domain: Domain::Positive,
            default: 16.0,
            si: "as α",
        },
        ParamInfo {
            name: "sxc",
            symbol: "x̂_c",
            latex: r"\hat x_c",
            meaning: "the schedule's plant model: the softest twist 1/(3α)",
            domain: Domain::Any,
            default: 1.0 / 48.0,
            si: "as x",
        },
        ParamInfo {
            name: "sgc",
            symbol: "ĝ'_c",
            latex: r"\hat g'_c",
            meaning: "the schedule's plant model: the least slope γ − 1/(3α)",
            domain: Domain::Any,
            default: 0.1 - 1.0 / 48.0,
            si: "as γ",
        },
        ParamInfo {
            name: "sb0",
            symbol: "b̂₀",
            latex: r"\hat b_0",
            meaning: "the schedule's plant model: μ − g(x_c)",
            domain: Domain::Any,
            default: 0.13920601851851852,
            si: "as μ",
        },
        ParamInfo {
            name: "sdelta",
            symbol: "δ̂",
            latex: r"\hat\delta",
            meaning: "the schedule's plant model: the load amplitude δ",
            domain: Domain::NonNegative,
            default: 15.0,
            si: "as δ",
        },
        ParamInfo {
            name: "somega",
            symbol: "ω̂",
            latex: r"\hat\omega",
            meaning: "the load's angular frequency, the phase's rate",
            domain: Domain::Positive,
            default: 0.01,
            si: "as ω",
        },
    ];
    const PHASE_RATE: Option<usize> = Some(6);
    const SCHEDULED: bool = true;
    fn from_values(v: &[f64]) -> Self {
        Scheduled([v[0], v[1], v[2], v[3], v[4], v[5], v[6]])
    }
    fn values(&self) -> &[f64] {
        &self.0
    }
    fn torque(&self, x: f64, _v: f64, theta: f64) -> f64 {
        self.gain(libm::sin(theta)) * (x - self.0[2])
    }
    fn gradient(&self, x: f64, _v: f64, theta: f64) -> [f64; 3] {
        let (sin, cos) = libm::sincos(theta);
        let s = self.reference(sin);
        let k = self.unclamped(s).max(0.0);
        // dk/dθ = −6α·s₀·ds₀/dθ on the active piece, ds₀/dθ = δ·cos θ/(3αs₀² + g'_min)
        let dk = if k > 0.0 {
            -6.0 * self.0[1] * s * self.0[5] * cos * self.reference_slope(s)
        } else {
            0.0
        };
        [k, 0.0, dk * (x - self.0[2])]
    }
    fn param_derivative(&self, i: usize, x: f64, _v: f64, theta: f64) -> f64 {
        let sin = libm::sin(theta);
        let s = self.reference(sin);
        let k = self.unclamped(s).max(0.0);
        let u = x - self.0[2];
        if i == 2 {
            return -k;
        }
        if k <= 0.0 || i == 6 {
            return 0.0;
        }
        let [_, alpha, ..] = self.0;
        let ds = self.reference_slope(s);
        // k = g'_min − g'_c − 3αs₀²; s₀ moves with g'_min, α, b₀ and δ through
        // αs₀³ + g'_min·s₀ = b₀ + δa
        let dk_ds = -6.0 * alpha * s;
        let dk = match i {
            0 => 1.0 + dk_ds * (-s * ds),
            1 => -3.0 * s * s + dk_ds * (-s * s * s * ds),
            3 => -1.0,
            4 => dk_ds * ds,
            _ => dk_ds * sin * ds,
        };
        dk * u
    }
    /// sin θ and cos θ by their recurrences, s₀'s rows from αs₀³ + g'_min·s₀ = b₀ + δ sin θ
    /// (row k: (3αs₀² + g'_min)·s_k = δ·sin_k − α·(s₀·P_k + Q_k), P_k and Q_k the parts of
    /// (s₀²)_k and (s₀³)_k without s_k), then k = D − 3α·s₀² on the piece the step starts on
    /// (0 on the other), times x − x_c.
    fn taylor(&self, k: usize, x: &[f64], _v: &[f64], theta: &[f64], rows: &mut Scratch) -> f64 {
        let [m, alpha, xc, ..] = self.0;
        let delta = self.0[5];
        let r = &mut rows.0;
        let (sk, ck) = sin_cos_coefficients(theta, &r[SIN], &r[COS], k);
        (r[SIN][k], r[COS][k]) = (sk, ck);
        if k == 0 {
            let s = self.reference(sk);
            (r[S][0], r[S2][0]) = (s, s * s);
            r[PIECE][1] = theta[0];
            let value = self.unclamped(s);
            // on a kink to rounding (a step ends on one, [`Term::step_limit`]): decided at row 1,
            // by the way the motion goes
            let on_kink = self.levels().is_some_and(|levels| {
                let resolution = 64.0 * f64::EPSILON + 4.0 * f64::EPSILON * theta[0].abs();
                levels.iter().any(|&a| (sk - a).abs() <= resolution)
            });
            r[PIECE][0] = if on_kink {
                UNDECIDED
            } else {
                f64::from(u8::from(value > 0.0))
            };
            return value.max(0.0) * (x[0] - xc);
        }
        let s0 = r[S][0];
        let p: f64 = (1..k).map(|i| r[S][i] * r[S][k - i]).sum();
        let q: f64 = (1..k).map(|i| r[S2][i] * r[S][k - i]).sum();
        let sk = (delta * r[SIN][k] - alpha * (s0 * p + q)) / (3.0 * alpha * s0 * s0 + m);
        r[S][k] = sk;
        r[S2][k] = 2.0 * s0 * sk + p;
        if r[PIECE][0] == UNDECIDED {
            // D − 3αs₀² rises (the gain switches on) where s₀·s₀' < 0
            r[PIECE][0] = f64::from(u8::from(-s0 * sk > 0.0));
        }
        if r[PIECE][0] == 0.0 {
            return 0.0;
        }
        let gain = |i: usize| {
            let base = if i == 0 { self.deficit() } else { 0.0 };
            base - 3.0 * alpha * r[S2][i]
        };
        (0..=k)
            .map(|i| gain(i) * if k - i == 0 { x[0] - xc } else { x[k - i] })
            .sum()
    }
    const LIMITS_STEPS: bool = true;
    /// The step ends where the gain switches on or off: where sin θ, θ = θ₀ + ω̂τ exactly, next
    /// reaches a level a₋ or a₊ ([`Scheduled::levels`]), in closed form (the next step starts on
    /// the kink, its piece decided by the way it goes).
    fn step_limit(&self, rows: &Scratch, order: usize, h: f64, _negligible: f64) -> f64 {
        let Some(levels) = self.levels() else {
            return h;
        };
        if order == 0 {
            return h;
        }
        let theta0 = rows.0[PIECE][1];
        let after = theta0 + 64.0 * f64::EPSILON * theta0.abs().max(1.0);
        let next = levels
            .iter()
            .filter(|a| a.abs() <= 1.0)
            .flat_map(|&a| {
                let base = a.asin();
                [base, std::f64::consts::PI - base]
            })
            .map(|angle| {
                // the first angle + 2πn past θ₀
                let turns = ((after - angle) / std::f64::consts::TAU).floor() + 1.0;
                angle + turns * std::f64::consts::TAU
            })
            .fold(f64::INFINITY, f64::min);
        h.min((next - theta0) / self.0[6])
    }
    fn text(&self) -> String {
        " + k(a)·(x − x̂_c)".into()
    }
    fn latex(&self) -> String {
        r" + k(a)\,(x - \hat x_c)".into()
    }
    fn rate_text(&self) -> Option<String> {
        Some("θ' = ω̂, a = sin θ".into())
    }
    fn rate_latex(&self) -> Option<String> {
        Some(r"\dot\theta = \hat\omega,\ a = \sin\theta".into())
    }
}
