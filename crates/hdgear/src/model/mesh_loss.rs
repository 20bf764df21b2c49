//! The torque-proportional mesh loss of a strain-wave gear on the twist: T_m = μ_m·|T_s(x)|·σ,
//! the loss a fraction μ_m of the torque the mesh transmits, its sign a Dahl-type state σ that
//! turns towards sgn x' over the twist θ_m after each reversal,
//! σ' = x'·(1 − sgn(x')·σ)/θ_m (REAL-DRIVES.md, "torque-proportional mesh loss": the
//! inclined-plane view, MuJoCo issue 3528's loss for strain-wave gears, the harmonic-drive twin's
//! tooth-flank channel).
//!
//! T_s is the model's elastic law, the term it reads: the study's cubic stiffness or the
//! catalogue's piecewise curve ([`Elastic`]). The model hands the term a copy of that law when it
//! is assembled and whenever one of the law's parameters changes ([`super::Model::with_term`],
//! [`super::Model::with`]), so the law is still defined once, by its own term. A hysteresis term's
//! torque (Bouc–Wen's or Dahl's share) is not part of T_s here: the loss is proportional to the
//! elastic curve's torque, an assumption `hdgear model` states with the term.
//!
//! In full slip σ = ±1 and the loss is ±μ_m·|T_s|: the quasi-static branches are
//! (1 + μ_m)·T_s(x) = load while the twist grows and (1 − μ_m)·T_s(x) = load while it shrinks
//! (for T_s > 0), which [`super::branches`] derives from the term's rate at rest. The law is not
//! analytic where x' = 0 (sgn x') or T_s = 0 (|T_s|): a switching integration cuts the steps at
//! x' = 0 ([`super::switching`]), and a Taylor step ends where T_s changes sign. T_s depends on
//! the twist alone, so it changes sign at fixed twists, the law's roots (the cubic's real roots,
//! the curve's centre x₀), found once when the model links the law: a step ends where the twist's
//! own polynomial reaches one ([`super::jet::first_exit`]), as a catalogue curve's steps end on
//! its kinks. (Locating T_s = 0 on T_s's polynomial instead would let the next step start a
//! truncation error of T_s on the old side, where that polynomial turns back at once.)
//!
//! ```
//! use hdgear::Params;
//! use hdgear::model::{Model, terms::AnyTerm};
//! let p = Params::default();
//! let loss = AnyTerm::new("meshloss", &[0.25, 0.01]).unwrap();
//! let m = Model::study(&p).with_term(loss).unwrap();
//! // in full forward slip (σ = 1) the loss is a quarter of the elastic torque
//! let x = 0.8;
//! let elastic = p.g(x);
//! let y = [x, 0.1, 1.0];
//! let total = m.torque_at(&y);
//! assert!((total - (0.1 + elastic + 0.25 * elastic.abs())).abs() < 1e-14);
//! ```

use super::jet::{cauchy, exit_from};
use super::piecewise::{Piecewise, on_kink};
use super::study_terms::Stiffness;
use super::term::{Domain, ParamInfo, Scratch, Side, StateInfo, Term, piece_sign};
use serde::Serialize;

/// The rows of [`Scratch`] the loss keeps for itself (rows below are the elastic law's): T_s's,
/// x's (for [`Term::step_limit`]), and the step's piece: sgn T_s on it (at 0) and the interval of
/// twist between roots of T_s the step starts in (at 1 and 2).
const TS: usize = 5;
const XS: usize = 6;
const PIECE: usize = 7;

/// The elastic law a mesh loss reads its transmitted torque T_s from: one of the model's terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Elastic {
    /// The study's cubic stiffness.
    Stiffness(Stiffness),
    /// The catalogue's piecewise-linear curve.
    Piecewise(Piecewise),
}

impl Elastic {
    /// T_s(x).
    fn torque(&self, x: f64) -> f64 {
        match self {
            Elastic::Stiffness(s) => s.torque(x, 0.0, 0.0),
            Elastic::Piecewise(p) => p.torque(x, 0.0, 0.0),
        }
    }

    /// dT_s/dx.
    fn slope(&self, x: f64) -> f64 {
        match self {
            Elastic::Stiffness(s) => s.gradient(x, 0.0, 0.0)[0],
            Elastic::Piecewise(p) => p.gradient(x, 0.0, 0.0)[0],
        }
    }

    /// Row k of T_s along the step (the law's own rows in `rows` 0 to 4).
    #[inline(always)]
    fn taylor(&self, k: usize, x: &[f64], v: &[f64], z: &[f64], rows: &mut Scratch) -> f64 {
        match self {
            Elastic::Stiffness(s) => s.taylor(k, x, v, z, rows),
            Elastic::Piecewise(p) => p.taylor(k, x, v, z, rows),
        }
    }

    /// The twists where T_s = 0, in increasing order (up to three: the cubic's real roots, the
    /// curve's centre x₀), and how many there are.
    fn roots(&self) -> ([f64; 3], usize) {
        match self {
            Elastic::Stiffness(s) => {
                let [alpha, gamma, eps] = s.array();
                let p = crate::Params {
                    alpha,
                    gamma,
                    eps,
                    mu: 0.0,
                    delta: 0.0,
                    omega: 1.0,
                };
                let e = crate::fast::equilibria(&p, 0.0);
                let mut r = [0.0; 3];
                for (r, q) in r.iter_mut().zip(&e.roots) {
                    *r = q.x;
                }
                (r, e.roots.len().min(3))
            }
            Elastic::Piecewise(p) => ([p.0[5], 0.0, 0.0], 1),
        }
    }

    /// The law's own step limit (a catalogue curve's kinks).
    fn step_limit(&self, rows: &Scratch, order: usize, h: f64, negligible: f64) -> f64 {
        match self {
            Elastic::Stiffness(s) => s.step_limit(rows, order, h, negligible),
            Elastic::Piecewise(p) => p.step_limit(rows, order, h, negligible),
        }
    }
}

/// Torque-proportional mesh loss μ_m·|T_s(x)|·σ with σ' = x'·(1 − sgn(x')·σ)/θ_m (see the
/// [module](self)). Its values are [μ_m, θ_m]; the elastic law T_s comes from the model.
// serialised as its values alone: the law is the model's and the piece integration state
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(transparent)]
pub struct MeshLoss {
    values: [f64; 2],
    /// The transmitted torque's law, the model's ([`MeshLoss::reading`]); `None` before the
    /// model links it (the loss is then 0).
    #[serde(skip)]
    law: Option<Elastic>,
    /// The law's roots ([`Elastic::roots`]; entries past their count are 0), found when the
    /// law is linked.
    #[serde(skip)]
    roots: ([f64; 3], usize),
    /// sgn x' on the current piece (0: read from x').
    #[serde(skip)]
    side: f64,
}

impl MeshLoss {
    /// The loss reading its transmitted torque from `law`.
    pub fn reading(self, law: Option<Elastic>) -> Self {
        MeshLoss {
            law,
            roots: law.map_or(([0.0; 3], 0), |l| l.roots()),
            ..self
        }
    }

    /// [sgn T_s, lo, hi] on the interval [lo, hi] between the law's roots that a step from x₀
    /// moving in `direction` lies in (a start within a few rounding errors of a root lies beyond
    /// it in the direction of motion).
    fn piece(&self, law: &Elastic, x0: f64, direction: f64) -> [f64; 3] {
        let (roots, n) = self.roots;
        let roots = &roots[..n];
        let passed = |r: f64| {
            if (x0 - r).abs() <= on_kink(r) {
                direction > 0.0 || (direction == 0.0 && x0 > r)
            } else {
                x0 > r
            }
        };
        let i = roots.iter().take_while(|&&r| passed(r)).count();
        let lo = if i == 0 {
            f64::NEG_INFINITY
        } else {
            roots[i - 1]
        };
        let hi = roots.get(i).copied().unwrap_or(f64::INFINITY);
        let inside = match (lo.is_finite(), hi.is_finite()) {
            (true, true) => 0.5 * (lo + hi),
            (true, false) => lo + 1.0,
            (false, true) => hi - 1.0,
            (false, false) => x0,
        };
        [piece_sign(0.0, law.torque(inside)), lo, hi]
    }

    /// The law it reads.
    pub fn law(&self) -> Option<Elastic> {
        self.law
    }

    /// T_s(x), 0 without a law.
    fn transmitted(&self, x: f64) -> f64 {
        self.law.map_or(0.0, |l| l.torque(x))
    }
}

impl Term for MeshLoss {
    const KIND: &'static str = "meshloss";
    const ABOUT: &'static str = "torque-proportional mesh loss μ_m·|T_s|·σ, σ' = x'·(1 − sgn(x')·σ)/θ_m (T_s: the model's elastic law)";
    const STATE: Option<StateInfo> = Some(StateInfo {
        name: "sm",
        meaning: "the mesh loss's sign σ (−1 … 1)",
    });
    const SWITCHES_AT_REST: bool = true;
    const PARAMS: &'static [ParamInfo] = &[
        ParamInfo {
            name: "mum",
            symbol: "μ_m",
            latex: r"\mu_m",
            meaning: "loss per unit of transmitted torque (1/η − 1 at the efficiency η)",
            domain: Domain::NonNegative,
            default: 0.2,
            si: "1/η − 1 (a ratio)",
        },
        ParamInfo {
            name: "thetam",
            symbol: "θ_m",
            latex: r"\theta_m",
            meaning: "twist over which the loss's sign turns after a reversal",
            domain: Domain::Positive,
            default: 0.01,
            si: "θ_m/L (θ_m in rad of twist; L the model's length scale)",
        },
    ];
    fn from_values(v: &[f64]) -> Self {
        MeshLoss {
            values: [v[0], v[1]],
            law: None,
            roots: ([0.0; 3], 0),
            side: 0.0,
        }
    }
    fn values(&self) -> &[f64] {
        &self.values
    }
    fn torque(&self, x: f64, _v: f64, s: f64) -> f64 {
        self.values[0] * self.transmitted(x).abs() * s
    }
    fn gradient(&self, x: f64, _v: f64, s: f64) -> [f64; 3] {
        let mu = self.values[0];
        let ts = self.transmitted(x);
        let slope = self.law.map_or(0.0, |l| l.slope(x));
        [mu * piece_sign(0.0, ts) * slope * s, 0.0, mu * ts.abs()]
    }
    fn param_derivative(&self, i: usize, x: f64, _v: f64, s: f64) -> f64 {
        match i {
            0 => self.transmitted(x).abs() * s,
            _ => 0.0,
        }
    }
    fn rate(&self, _x: f64, v: f64, s: f64) -> f64 {
        v * (1.0 - piece_sign(self.side, v) * s) / self.values[1]
    }
    fn rate_gradient(&self, _x: f64, v: f64, s: f64) -> [f64; 3] {
        let (theta, sv) = (self.values[1], piece_sign(self.side, v));
        [0.0, (1.0 - sv * s) / theta, -sv * v / theta]
    }
    fn rate_param_derivative(&self, i: usize, x: f64, v: f64, s: f64) -> f64 {
        match i {
            1 => -self.rate(x, v, s) / self.values[1],
            _ => 0.0,
        }
    }
    /// r_k = (v_k − sgn(x')·(v·σ)_k)/θ_m on the piece.
    #[inline(always)]
    fn rate_taylor(&self, k: usize, _x: &[f64], v: &[f64], s: &[f64], _rows: &mut Scratch) -> f64 {
        let sv = piece_sign(self.side, v[0]);
        (v[k] - sv * cauchy(v, s, k)) * (1.0 / self.values[1])
    }
    /// T_s's rows from the law (its own rows in `rows` 0 to 4, T_s's in row 5), then
    /// μ_m·sgn(T_s)·(T_s·σ)_k, the sign fixed on the step by the interval between the law's roots
    /// it starts in (chosen at row 1 by x', or at rest by x''; a start within a few rounding
    /// errors of a root lies beyond it in the direction of motion).
    #[inline(always)]
    fn taylor(&self, k: usize, x: &[f64], v: &[f64], s: &[f64], rows: &mut Scratch) -> f64 {
        let Some(law) = self.law else { return 0.0 };
        let ts = law.taylor(k, x, v, s, rows);
        rows.0[TS][k] = ts;
        rows.0[XS][k] = x[k];
        let mu = self.values[0];
        if k == 0 {
            return mu * ts.abs() * s[0];
        }
        if k == 1 {
            let direction = if x[1] != 0.0 { x[1] } else { v[1] };
            let piece = self.piece(&law, x[0], direction);
            rows.0[PIECE][..3].copy_from_slice(&piece);
        }
        mu * rows.0[PIECE][0] * cauchy(&rows.0[TS], s, k)
    }
    const LIMITS_STEPS: bool = true;
    /// The law's own limit, then the step ends where the twist leaves the interval between the
    /// law's roots it started in, located on x's polynomial ([`exit_from`]; widened by a few
    /// rounding errors, as the start's piece reads a root). A loss of μ_m = 0 never limits.
    fn step_limit(&self, rows: &Scratch, order: usize, h: f64, negligible: f64) -> f64 {
        let Some(law) = self.law else { return h };
        let h = law.step_limit(rows, order, h, negligible);
        if order == 0 || self.values[0] == 0.0 {
            return h;
        }
        let [_, lo, hi] = [rows.0[PIECE][0], rows.0[PIECE][1], rows.0[PIECE][2]];
        let (lo, hi) = (lo - on_kink(lo), hi + on_kink(hi));
        let xs = &rows.0[XS];
        exit_from(xs, order, h, (lo, hi))
    }
    fn text(&self) -> String {
        " + μ_m·|T_s(x)|·σ".into()
    }
    fn latex(&self) -> String {
        r" + \mu_m \lvert T_s(x) \rvert \sigma".into()
    }
    fn rate_text(&self) -> Option<String> {
        Some("σ' = x'·(1 − sgn(x')·σ)/θ_m, T_s the elastic law's torque".into())
    }
    fn rate_latex(&self) -> Option<String> {
        Some(
            r"\dot\sigma = \dot x \left(1 - \operatorname{sgn}(\dot x)\,\sigma\right)/\theta_m"
                .into(),
        )
    }
    fn directed(self, side: Side) -> Self {
        MeshLoss {
            side: side.v,
            ..self
        }
    }
}
