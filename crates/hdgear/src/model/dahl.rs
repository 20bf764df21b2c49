//! Dahl's hysteresis of the flexspline on the twist: a torque T_h that follows the twist along
//! dT_h/dx = σ·(1 − sgn(x')·T_h/T_c)ⁿ (Dahl 1968; the law of the harmonic-drive twin's
//! `hysteresis_dahl`, REAL-DRIVES.md). From a reversal T_h climbs towards ±T_c with the slope σ at
//! T_h = 0; the exponent n shapes the knee (n = 1 an exponential approach, larger n a rounder,
//! slower one). Rate-independent, like Bouc–Wen ([`super::memory::BoucWen`]): T_h depends on the
//! path of x, not on its speed.

use super::jet::{Jet, Lanes, cauchy, whole_power_rows};
use super::term::{
    Domain, LANE_PARAMS, LaneRows, MAX_ROWS, ParamInfo, Scratch, Side, StateInfo, Term, piece_sign,
};
use crate::integrate::taylor::SCRATCH_ROWS;
use serde::Serialize;

/// Dahl hysteresis: the torque T_h, the term's state, with T_h' = σ·x'·(1 − sgn(x')·T_h/T_c)ⁿ.
/// The exponent n is a whole number (1 to 4), so that on a piece of fixed sgn x' the law is a
/// polynomial in T_h. |T_h| stays below T_c from the virgin state, so the base
/// b = 1 − sgn(x')·T_h/T_c stays positive and only x' = 0 switches it.
///
/// With n = 1 it is LuGre with f_s = f_c and σ₁ = σ₂ = 0 ([`super::memory::LuGre`]), and Bouc–Wen
/// with A = σ, β = σ/T_c, γ_h = 0, k_h = 1, ρ = 0: the tests hold the three to one another.
// serialised as its values alone: the piece is integration state, not a parameter
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(transparent)]
pub struct Dahl {
    values: [f64; 3],
    /// sgn x' on the current piece (0: read from x').
    #[serde(skip)]
    side: f64,
}

impl Dahl {
    /// (sgn x' on the piece, the base b, the exponent n) at (v, T_h).
    fn base(&self, v: f64, th: f64) -> (f64, f64, i32) {
        let [_, tc, n] = self.values;
        let sv = piece_sign(self.side, v);
        (sv, 1.0 - sv * th / tc, n as i32)
    }
}

impl Term for Dahl {
    const KIND: &'static str = "dahl";
    const ABOUT: &'static str = "Dahl hysteresis T_h with T_h' = σ·x'·(1 − sgn(x')·T_h/T_c)ⁿ";
    const STATE: Option<StateInfo> = Some(StateInfo {
        name: "th",
        meaning: "Dahl hysteresis torque",
    });
    const SWITCHES_AT_REST: bool = true;
    const PARAMS: &'static [ParamInfo] = &[
        ParamInfo {
            name: "sigmad",
            symbol: "σ",
            latex: r"\sigma",
            meaning: "slope dT_h/dx at T_h = 0 (the presliding stiffness)",
            domain: Domain::Positive,
            default: 10.0,
            si: "k·J_eq/C² (a stiffness on γ's scale)",
        },
        ParamInfo {
            name: "tcd",
            symbol: "T_c",
            latex: "T_c",
            meaning: "torque the hysteresis saturates at",
            domain: Domain::Positive,
            default: 0.1,
            si: "T·k2·φ·J_eq²/C⁴ (a torque on μ's scale)",
        },
        ParamInfo {
            name: "nd",
            symbol: "n",
            latex: "n",
            meaning: "shape of the knee (1: exponential)",
            domain: Domain::Exponent,
            default: 1.0,
            si: "n",
        },
    ];
    fn from_values(v: &[f64]) -> Self {
        Dahl {
            values: [v[0], v[1], v[2]],
            side: 0.0,
        }
    }
    fn values(&self) -> &[f64] {
        &self.values
    }
    fn rate(&self, _x: f64, v: f64, th: f64) -> f64 {
        let (_, b, n) = self.base(v, th);
        self.values[0] * v * b.powi(n)
    }
    fn rate_gradient(&self, _x: f64, v: f64, th: f64) -> [f64; 3] {
        let [sigma, tc, _] = self.values;
        let (sv, b, n) = self.base(v, th);
        [
            0.0,
            sigma * b.powi(n),
            -sigma * v * f64::from(n) * b.powi(n - 1) * sv / tc,
        ]
    }
    fn rate_param_derivative(&self, i: usize, _x: f64, v: f64, th: f64) -> f64 {
        let [sigma, tc, _] = self.values;
        let (sv, b, n) = self.base(v, th);
        match i {
            0 => v * b.powi(n),
            1 => sigma * v * f64::from(n) * b.powi(n - 1) * sv * th / (tc * tc),
            2 if b > 0.0 => sigma * v * b.powi(n) * b.ln(),
            _ => 0.0,
        }
    }
    fn torque(&self, _x: f64, _v: f64, th: f64) -> f64 {
        th
    }
    fn gradient(&self, _x: f64, _v: f64, _th: f64) -> [f64; 3] {
        [0.0, 0.0, 1.0]
    }
    fn param_derivative(&self, _i: usize, _x: f64, _v: f64, _th: f64) -> f64 {
        0.0
    }
    /// The base b = 1 − sv·T_h/T_c's row, its powers by repeated products, then r = σ·(v·bⁿ)
    /// on the piece's sgn x' (one recurrence over `Jet` for this and the lanes).
    #[inline(always)]
    fn rate_taylor(&self, k: usize, _x: &[f64], v: &[f64], th: &[f64], rows: &mut Scratch) -> f64 {
        let [sigma, tc, _] = self.values;
        let (sv, _, n) = self.base(v[0], th[0]);
        dahl_rate_row([sigma, tc, sv], n as usize, k, v, th, &mut rows.0)
    }
    #[inline(always)]
    fn taylor(&self, k: usize, _x: &[f64], _v: &[f64], th: &[f64], _rows: &mut Scratch) -> f64 {
        th[k]
    }
    const ON_LANES: bool = true;
    /// On a piece: σ, T_c, n and the piece's sgn x'. Only a piece's sign is constant: a model
    /// whose terms read their signs from the state runs on lanes only as pieces
    /// ([`super::integrate_switching_models`]).
    fn lane_values(&self) -> [f64; LANE_PARAMS] {
        let [sigma, tc, n] = self.values;
        [sigma, tc, n, self.side, 0.0, 0.0]
    }
    /// The exponent n, whose products the recurrence unrolls.
    fn lane_shape(&self) -> usize {
        self.values[2] as usize
    }
    #[inline(always)]
    fn taylor_lanes(
        _values: &[Lanes],
        k: usize,
        _x: &[Lanes],
        _v: &[Lanes],
        th: &[Lanes],
        _rows: &mut LaneRows,
    ) -> Option<Lanes> {
        Some(th[k])
    }
    #[inline(always)]
    fn rate_taylor_lanes(
        values: &[Lanes],
        k: usize,
        _x: &[Lanes],
        v: &[Lanes],
        th: &[Lanes],
        rows: &mut LaneRows,
    ) -> Lanes {
        // n is the same on every lane (`lane_shape`)
        let n = values[2].0[0] as usize;
        dahl_rate_row([values[0], values[1], values[3]], n, k, v, th, rows)
    }
    fn text(&self) -> String {
        " + T_h".into()
    }
    fn latex(&self) -> String {
        " + T_h".into()
    }
    fn rate_text(&self) -> Option<String> {
        Some("T_h' = σ·x'·(1 − sgn(x')·T_h/T_c)ⁿ".into())
    }
    fn rate_latex(&self) -> Option<String> {
        Some(
            r"\dot T_h = \sigma \dot x \left(1 - \operatorname{sgn}(\dot x)\, T_h/T_c\right)^n"
                .into(),
        )
    }
    fn directed(self, side: Side) -> Self {
        Dahl {
            side: side.v,
            ..self
        }
    }
}

/// [`Dahl`]'s rate row k on any [`Jet`], on a piece of sgn x' = sv: the base
/// b = 1 − sv·T_h/T_c (row 0 of `rows`), its powers b², b³, b⁴ by repeated products (rows 1 to
/// n − 1), then r = σ·(v·bⁿ).
#[inline(always)]
fn dahl_rate_row<J: Jet>(
    [sigma, tc, sv]: [J; 3],
    n: usize,
    k: usize,
    v: &[J],
    th: &[J],
    rows: &mut [[J; MAX_ROWS]; SCRATCH_ROWS],
) -> J {
    let (base, powers) = rows.split_at_mut(1);
    let one = J::splat(if k == 0 { 1.0 } else { 0.0 });
    base[0][k] = one - sv * th[k] * (J::splat(1.0) / tc);
    sigma * cauchy(v, whole_power_rows(&base[0], n, powers, k), k)
}
