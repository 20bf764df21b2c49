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
//! the least gain that gives the reference point s₀(a) the slope g'_min. Any gain k ≥ that
//! keeps the closed loop's followed equilibrium at least that steep. The root lies on s₀'s side
//! of x_c (the residual at s = 0 is −(b₀ + δa), of the sign opposite to s₀). Where k ≤ D the
//! residual at s₀ is (k − D)·s₀, also of the sign opposite to s₀, so the root lies beyond s₀
//! and its slope is g'_c + k + 3αs² ≥ g'_c + k + 3αs₀² ≥ g'_min; where k > D the slope is at least
//! g'_c + k > g'_min. (With D ≤ 0 the plant is steep enough: k ≡ 0 and every slope is at least
//! g'_c ≥ g'_min.) With no fold on the closed loop's path the fast-slow passage has no jump.
//!
//! The least gain switches on and off with a kink: dk/da jumps there, and so does the speed
//! dx*/dτ of the equilibrium the state follows, by the share −k'·(x − x_c)/(g' + k) of it. A
//! jump in the equilibrium's speed kicks the fast mode as a step in velocity would, and the
//! closed loop rings after each switch. Measured at the study's γ = 0.1: with g'_min = 3 (every
//! slope ≥ 3, past the open loop's boundary γ ≈ 2.2) the kinked schedule still overshoots, each
//! burst starting where the gain switches on. So the gain is the least one passed through a
//! ramp that is C¹: with κ = D − 3α·s₀² (the least gain before the clamp) and a width
//! w = ρ·D,
//!
//! k = 0 for κ ≤ −w, (κ + w)²/(4w) for |κ| < w, κ for κ ≥ w,
//!
//! which is at least max(0, κ) (so the slope promise holds) and whose slope in κ runs from 0 to 1
//! without a jump. ρ = 0 is the least gain itself.
//!
//! The schedule is the controller's: its parameters are the plant model it was built from (α, x_c,
//! g'_c, b₀, δ, ω), which a model error leaves behind, and its ramp ρ.

use super::jet::sin_cos_coefficients;
use super::term::{Domain, ParamInfo, Scratch, Term};
use crate::params::Params;
use serde::Serialize;

/// Scheduled stiffness ũ = −k(a)·(x − x_c), a = sin θ, θ' = ω (the load's phase), k(a) the
/// least gain max(0, g'_min − g'_c − 3α·s₀(a)²) through a C¹ ramp of width ρ·D, s₀ the root of
/// αs₀³ + g'_min·s₀ = b₀ + δa (see the [module](self)). Parameters: g'_min (the gain a tuner
/// searches), the plant model α, x_c, g'_c, b₀, δ, ω, and the ramp ρ. Their defaults are the
/// schedule for the study's default set with g'_min = 0.3.
///
/// ```
/// use hdgear::Params;
/// use hdgear::model::schedule::Scheduled;
/// let p = Params::default(); // least slope γ − 1/(3α) ≈ 0.079
/// let law = Scheduled::for_plant(&p, 0.3, 0.0); // the least gain, no ramp
/// // largest at the softest point, zero where the curve is stiff enough on its own
/// let x_c = 1.0 / (3.0 * p.alpha);
/// let at_xc = p.a_at(x_c);
/// assert!((law.gain(at_xc) - (0.3 - p.g_prime(x_c))).abs() < 1e-12);
/// assert_eq!(law.gain(1.0), 0.0);
/// // the ramp never gives less
/// let ramped = Scheduled::for_plant(&p, 0.3, 0.5);
/// assert!((-1.0..=1.0).contains(&0.2) && ramped.gain(0.2) >= law.gain(0.2));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Scheduled(pub [f64; 8]);

/// Where the schedule keeps its rows in [`Scratch`]: sin θ, cos θ, s₀, s₀², and the piece (at 0:
/// [`OFF`], [`RAMP`] or [`ON`]) with θ₀ (at 1).
const SIN: usize = 0;
const COS: usize = 1;
const S: usize = 2;
const S2: usize = 3;
const PIECE: usize = 4;
/// The gain's pieces in κ: off (κ ≤ −w), the ramp (|κ| < w), on (κ ≥ w: k = κ).
const OFF: f64 = 0.0;
const RAMP: f64 = 1.0;
const ON: f64 = 2.0;
/// The piece of a step that starts on a kink, until its row 1 shows which way it goes.
const UNDECIDED: f64 = 3.0;

/// The ramp's default width ρ, in units of the deficit D: at the study's γ = 0.01, 0.1 and 1
/// with g'_min = 3, the closed loop still rings with ρ = 1 and no longer with ρ = 3 (with ρ = 0
/// it overshoots, each burst starting where the gain switches on).
pub const RAMP_DEFAULT: f64 = 3.0;

impl Scheduled {
    /// The schedule for the study plant `p` with the target least slope `gmin` and the ramp
    /// `ramp` (ρ).
    pub fn for_plant(p: &Params, gmin: f64, ramp: f64) -> Scheduled {
        let xc = 1.0 / (3.0 * p.alpha);
        Scheduled([
            gmin,
            p.alpha,
            xc,
            p.g_prime(xc),
            p.mu - p.g(xc),
            p.delta,
            p.omega,
            ramp,
        ])
    }

    /// The stiffened reference's offset s₀(a) from x_c: the real root of
    /// αs³ + g'_min·s = b₀ + δa (g'_min > 0), by Cardano's formula s = u − p/(3u),
    /// u = sgn(r)·∛(|r| + √(r² + (p/3)³)), p = g'_min/α, r = (b₀ + δa)/(2α), then one Newton
    /// step, which restores the digits the subtraction loses near r = 0.
    pub fn reference(&self, a: f64) -> f64 {
        let [m, alpha, _, _, b0, delta, ..] = self.0;
        let (p, r) = (m / alpha, 0.5 * (b0 + delta * a) / alpha);
        let root = (r * r + (p / 3.0).powi(3)).sqrt();
        let u = (r.abs() + root)
            .cbrt()
            .copysign(if r == 0.0 { 1.0 } else { r });
        let s = u - p / (3.0 * u);
        s - (alpha * s * s * s + m * s - 2.0 * alpha * r) / (3.0 * alpha * s * s + m)
    }

    /// The gain k(a): κ = D − 3α·s₀(a)² through the ramp.
    pub fn gain(&self, a: f64) -> f64 {
        self.ramp(self.unclamped(self.reference(a)))[0]
    }

    /// The gain k(a) and its slope dk/da = (dk/dκ)·dκ/da, dκ/da = −6α·s₀·δ/(3αs₀² + g'_min).
    pub fn gain_slope(&self, a: f64) -> [f64; 2] {
        self.gain_slope_at(self.reference(a))
    }

    /// [`Scheduled::gain_slope`] where the reference's offset is s₀ = `s`.
    pub(super) fn gain_slope_at(&self, s: f64) -> [f64; 2] {
        let [k, dk] = self.ramp(self.unclamped(s));
        [k, dk * self.kappa_slope(s)]
    }

    /// The load a at which the reference's offset is s₀ = `s` (the inverse of
    /// [`Scheduled::reference`], for δ̂ ≠ 0): (αs₀³ + g'_min·s₀ − b₀)/δ̂.
    pub(super) fn load_of(&self, s: f64) -> f64 {
        let [m, alpha, _, _, b0, delta, ..] = self.0;
        (alpha * s * s * s + m * s - b0) / delta
    }

    /// The largest gain, at κ = D (s₀ = 0).
    pub fn max_gain(&self) -> f64 {
        self.ramp(self.deficit())[0]
    }

    /// The ramp's width w = ρ·D (0 where D ≤ 0: the gain is off everywhere).
    pub fn width(&self) -> f64 {
        self.0[7] * self.deficit().max(0.0)
    }

    /// The piece of the ramp κ lies on.
    fn piece(&self, kappa: f64) -> f64 {
        let w = self.width();
        if kappa <= -w {
            OFF
        } else if kappa < w {
            RAMP
        } else {
            ON
        }
    }

    /// The gain at κ and its slope dk/dκ.
    fn ramp(&self, kappa: f64) -> [f64; 2] {
        let w = self.width();
        match self.piece(kappa) {
            OFF => [0.0, 0.0],
            RAMP => {
                let q = kappa + w;
                [q * q / (4.0 * w), q / (2.0 * w)]
            }
            _ => [kappa, 1.0],
        }
    }

    /// dκ/da = −6α·s₀·ds₀/da, ds₀/da = δ/(3αs₀² + g'_min).
    fn kappa_slope(&self, s: f64) -> f64 {
        -6.0 * self.0[1] * s * self.0[5] * self.reference_slope(s)
    }

    /// D − 3α·s²: the gain at the reference point s before it is clamped at 0.
    fn unclamped(&self, s: f64) -> f64 {
        self.deficit() - 3.0 * self.0[1] * s * s
    }

    /// D = g'_min − g'_c: the gain at the softest point (≤ 0: no gain anywhere).
    pub fn deficit(&self) -> f64 {
        self.0[0] - self.0[3]
    }

    /// The load levels where the gain changes piece, increasing: where κ = −w (s₀ =
    /// ±√((D + w)/(3α)), the gain's edges) and, for w < D, where κ = w (s₀ = ±√((D − w)/(3α))).
    /// Empty when the gain is never on (D ≤ 0) or the load does not move the reference (δ̂ = 0).
    pub fn levels(&self) -> Vec<f64> {
        let (levels, n) = self.level_array();
        levels[..n].to_vec()
    }

    /// [`Scheduled::levels`] without an allocation (the Taylor step reads them): the first `n`.
    fn level_array(&self) -> ([f64; 4], usize) {
        let mut levels = [0.0; 4];
        let [_, alpha, _, _, _, delta, ..] = self.0;
        let (d, w) = (self.deficit(), self.width());
        if d <= 0.0 || delta == 0.0 {
            return (levels, 0);
        }
        let edges = [d + w, d - w]
            .into_iter()
            .filter(|&e| e > 0.0)
            .take(1 + usize::from(w > 0.0));
        let mut n = 0;
        for e in edges {
            let s = (e / (3.0 * alpha)).sqrt();
            for s in [-s, s] {
                levels[n] = self.load_of(s);
                n += 1;
            }
        }
        levels[..n].sort_by(f64::total_cmp);
        (levels, n)
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
    const STATE: Option<super::term::StateInfo> = Some(super::term::StateInfo {
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
        ParamInfo {
            name: "sramp",
            symbol: "ρ",
            latex: r"\rho",
            meaning: "the gain's C¹ ramp, in units of the deficit D (0: the least gain, which kinks)",
            domain: Domain::NonNegative,
            default: RAMP_DEFAULT,
            si: "a ratio",
        },
    ];
    const PHASE_RATE: Option<usize> = Some(6);
    const SCHEDULED: bool = true;
    fn from_values(v: &[f64]) -> Self {
        Scheduled([v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7]])
    }
    fn values(&self) -> &[f64] {
        &self.0
    }
    fn torque(&self, x: f64, _v: f64, theta: f64) -> f64 {
        self.gain(libm::sin(theta)) * (x - self.0[2])
    }
    fn gradient(&self, x: f64, _v: f64, theta: f64) -> [f64; 3] {
        let (sin, cos) = libm::sincos(theta);
        let [k, dk] = self.gain_slope(sin);
        [k, 0.0, dk * cos * (x - self.0[2])]
    }
    fn param_derivative(&self, i: usize, x: f64, _v: f64, theta: f64) -> f64 {
        let sin = libm::sin(theta);
        let s = self.reference(sin);
        let kappa = self.unclamped(s);
        let piece = self.piece(kappa);
        let [k, dk_dkappa] = self.ramp(kappa);
        if i == 2 {
            return -k;
        }
        if piece == OFF || i == 6 {
            return 0.0;
        }
        let [_, alpha, ..] = self.0;
        let ds = self.reference_slope(s);
        // κ = g'_min − g'_c − 3αs₀²; s₀ moves with g'_min, α, b₀ and δ through
        // αs₀³ + g'_min·s₀ = b₀ + δa
        let dkappa_ds = -6.0 * alpha * s;
        let dkappa = match i {
            0 => 1.0 + dkappa_ds * (-s * ds),
            1 => -3.0 * s * s + dkappa_ds * (-s * s * s * ds),
            3 => -1.0,
            4 => dkappa_ds * ds,
            5 => dkappa_ds * sin * ds,
            _ => 0.0,
        };
        // the ramp's width w = ρ·D moves with g'_min, g'_c and ρ
        let rho = self.0[7];
        let dw = match i {
            0 => rho,
            3 => -rho,
            7 => self.deficit(),
            _ => 0.0,
        };
        let dk_dw = if piece == RAMP {
            dk_dkappa - k / self.width()
        } else {
            0.0
        };
        (dk_dkappa * dkappa + dk_dw * dw) * (x - self.0[2])
    }
    /// sin θ and cos θ by their recurrences, s₀'s rows from αs₀³ + g'_min·s₀ = b₀ + δ sin θ
    /// (row k: (3αs₀² + g'_min)·s_k = δ·sin_k − α·(s₀·P_k + Q_k), P_k and Q_k the parts of
    /// (s₀²)_k and (s₀³)_k without s_k), κ's rows D − 3α·(s₀²)_k, the gain's on the piece the
    /// step starts on (0 off, κ's on, (κ + w)²/(4w)'s by Cauchy products on the ramp), times
    /// x − x_c.
    #[inline(always)]
    fn taylor(&self, k: usize, x: &[f64], _v: &[f64], theta: &[f64], rows: &mut Scratch) -> f64 {
        let [m, alpha, xc, ..] = self.0;
        let delta = self.0[5];
        let w = self.width();
        let r = &mut rows.0;
        let (sk, ck) = sin_cos_coefficients(theta, &r[SIN], &r[COS], k);
        (r[SIN][k], r[COS][k]) = (sk, ck);
        if k == 0 {
            let s = self.reference(sk);
            (r[S][0], r[S2][0]) = (s, s * s);
            r[PIECE][1] = theta[0];
            let kappa = self.unclamped(s);
            // on a kink to rounding (a step ends on one, [`Term::step_limit`]): decided at row 1,
            // by the way the motion goes; the gain is continuous there, so its row 0 is either
            // piece's
            let resolution = 64.0 * f64::EPSILON + 4.0 * f64::EPSILON * theta[0].abs();
            let (levels, n) = self.level_array();
            let on_kink = levels[..n].iter().any(|&a| (sk - a).abs() <= resolution);
            r[PIECE][0] = if on_kink {
                UNDECIDED
            } else {
                self.piece(kappa)
            };
            return self.ramp(kappa)[0] * (x[0] - xc);
        }
        let s0 = r[S][0];
        let p: f64 = (1..k).map(|i| r[S][i] * r[S][k - i]).sum();
        let q: f64 = (1..k).map(|i| r[S2][i] * r[S][k - i]).sum();
        let sk = (delta * r[SIN][k] - alpha * (s0 * p + q)) / (3.0 * alpha * s0 * s0 + m);
        r[S][k] = sk;
        r[S2][k] = 2.0 * s0 * sk + p;
        let kappa = |i: usize| {
            let base = if i == 0 { self.deficit() } else { 0.0 };
            base - 3.0 * alpha * r[S2][i]
        };
        let mut piece = r[PIECE][0];
        if piece == UNDECIDED {
            // κ rises where s₀·s₀' < 0; at the lower kink (κ = −w) rising enters the ramp (on,
            // for w = 0), at the upper (κ = w) falling does
            let rising = -s0 * sk > 0.0;
            let k0 = kappa(0);
            let lower = (k0 + w).abs() <= (k0 - w).abs();
            piece = match (lower, rising) {
                (true, false) => OFF,
                (false, true) => ON,
                (true, true) if w == 0.0 => ON,
                _ => RAMP,
            };
        }
        let gain = |i: usize| match piece {
            OFF => 0.0,
            ON => kappa(i),
            _ => {
                let q = |j: usize| kappa(j) + if j == 0 { w } else { 0.0 };
                (0..=i).map(|j| q(j) * q(i - j)).sum::<f64>() / (4.0 * w)
            }
        };
        let row = (0..=k)
            .map(|i| gain(i) * if k - i == 0 { x[0] - xc } else { x[k - i] })
            .sum();
        r[PIECE][0] = piece;
        row
    }
    const LIMITS_STEPS: bool = true;
    /// The step ends where the gain changes piece: where sin θ, θ = θ₀ + ω̂τ exactly, next
    /// reaches a level of [`Scheduled::levels`], in closed form (the next step starts on the
    /// kink, its piece decided by the way it goes).
    fn step_limit(&self, rows: &Scratch, order: usize, h: f64, _negligible: f64) -> f64 {
        let (levels, n) = self.level_array();
        let levels = &levels[..n];
        if order == 0 || levels.is_empty() {
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
