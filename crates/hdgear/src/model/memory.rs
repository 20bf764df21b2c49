//! Terms with an internal state (memory): LuGre friction, whose bristle deflection s carries the
//! presliding and the friction's lag, and Bouc–Wen hysteresis of the flexspline, whose state z
//! carries the loop. Each is one [`Term`] with [`Term::STATE`]; the model gives it a state of its
//! own beside x and x' ([`super::Model::dim`]).
//!
//! Both laws hold |x'| (and Bouc–Wen |z|): on a piece where the signs are fixed ([`Side`]) they are
//! analytic, and a switching integration ([`super::switching`]) cuts steps where a sign changes.
//! Both states' rates vanish at x' = 0, so a state is held while the motion rests.

use super::friction::{
    FRICTION_FC, FRICTION_FS, Level, STATIC_AT_LEAST_SLIDING, STRIBECK_VELOCITY,
};
use super::jet::{Jet, Lanes};
use super::jet::{cauchy, exp_step_limit, quotient_coefficient, whole_power_rows};
use super::relation::Relation;
use super::term::{
    Domain, LANE_PARAMS, LaneRows, MAX_ROWS, ParamInfo, Scratch, Side, StateInfo, Term, piece_sign,
};
use crate::integrate::taylor::SCRATCH_ROWS;
use serde::Serialize;

/// LuGre friction on x': F = σ₀s + σ₁s' + σ₂x' with the bristle state
/// s' = x' − σ₀|x'|·s/g(x') and g(v) = f_c + (f_s − f_c)·e^{−(v/v_st)²} (Canudas de Wit et al.
/// 1995). At a constant sliding speed s settles at sgn(v)·g(v)/σ₀ and F at sgn(v)·g(v) + σ₂v; at
/// rest a small displacement meets the presliding stiffness σ₀.
// serialised as its values alone: the piece is integration state, not a parameter
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(transparent)]
pub struct LuGre {
    values: [f64; 6],
    /// sgn x' on the current piece (0: read from x').
    #[serde(skip)]
    side: f64,
}

impl LuGre {
    /// g(v) and its slope ([`Level`]).
    fn level(&self, v: f64) -> (f64, f64, f64) {
        let [fc, fs, vst, ..] = self.values;
        Level { fc, fs, vst }.at(v)
    }
}

impl Term for LuGre {
    const KIND: &'static str = "lugre";
    const RELATIONS: &'static [Relation] = &[STATIC_AT_LEAST_SLIDING];
    const ABOUT: &'static str = "LuGre friction σ₀s + σ₁s' + σ₂x' with a bristle state s";
    const STATE: Option<StateInfo> = Some(StateInfo {
        name: "s",
        meaning: "LuGre bristle deflection",
    });
    const SWITCHES_AT_REST: bool = true;
    const PARAMS: &'static [ParamInfo] = &[
        ParamInfo {
            domain: Domain::Positive,
            ..FRICTION_FC
        },
        ParamInfo {
            domain: Domain::Positive,
            ..FRICTION_FS
        },
        STRIBECK_VELOCITY,
        ParamInfo {
            name: "sigma0",
            symbol: "σ₀",
            latex: r"\sigma_0",
            meaning: "bristle (presliding) stiffness",
            domain: Domain::Positive,
            default: 100.0,
            si: "σ₀·J_eq/C² (a stiffness on γ's scale)",
        },
        ParamInfo {
            name: "sigma1",
            symbol: "σ₁",
            latex: r"\sigma_1",
            meaning: "bristle damping",
            domain: Domain::NonNegative,
            default: 10.0,
            si: "σ₁/C (over the damping C)",
        },
        ParamInfo {
            name: "sigma2",
            symbol: "σ₂",
            latex: r"\sigma_2",
            meaning: "viscous friction (added to the unit damping)",
            domain: Domain::NonNegative,
            default: 0.0,
            si: "σ₂/C (over the damping C)",
        },
    ];
    fn from_values(v: &[f64]) -> Self {
        LuGre {
            values: [v[0], v[1], v[2], v[3], v[4], v[5]],
            side: 0.0,
        }
    }
    fn values(&self) -> &[f64] {
        &self.values
    }
    fn rate(&self, _x: f64, v: f64, s: f64) -> f64 {
        let sigma0 = self.values[3];
        let (g, ..) = self.level(v);
        v - sigma0 * piece_sign(self.side, v) * v * s / g
    }
    fn rate_gradient(&self, _x: f64, v: f64, s: f64) -> [f64; 3] {
        let sigma0 = self.values[3];
        let (g, dg, _) = self.level(v);
        let sv = piece_sign(self.side, v);
        // r = v − σ₀·sv·v·s/g: ∂r/∂v = 1 − σ₀·sv·s·(g − v·g')/g²
        [
            0.0,
            1.0 - sigma0 * sv * s * (g - v * dg) / (g * g),
            -sigma0 * sv * v / g,
        ]
    }
    fn rate_param_derivative(&self, i: usize, _x: f64, v: f64, s: f64) -> f64 {
        let [fc, fs, vst, sigma0, ..] = self.values;
        let level = Level { fc, fs, vst };
        let (g, ..) = level.at(v);
        let abs_v = piece_sign(self.side, v) * v;
        // ∂r/∂g = σ₀|v|s/g², then ∂g/∂p
        let by_g = sigma0 * abs_v * s / (g * g);
        match i {
            0..=2 => by_g * level.param_derivatives(v)[i],
            3 => -abs_v * s / g,
            _ => 0.0,
        }
    }
    fn torque(&self, x: f64, v: f64, s: f64) -> f64 {
        let [.., sigma0, sigma1, sigma2] = self.values;
        sigma0 * s + sigma1 * self.rate(x, v, s) + sigma2 * v
    }
    fn gradient(&self, x: f64, v: f64, s: f64) -> [f64; 3] {
        let [.., sigma0, sigma1, sigma2] = self.values;
        let [_, rv, rs] = self.rate_gradient(x, v, s);
        [0.0, sigma1 * rv + sigma2, sigma0 + sigma1 * rs]
    }
    fn param_derivative(&self, i: usize, x: f64, v: f64, s: f64) -> f64 {
        let sigma1 = self.values[4];
        let own = match i {
            3 => s,
            4 => self.rate(x, v, s),
            5 => v,
            _ => 0.0,
        };
        own + sigma1 * self.rate_param_derivative(i, x, v, s)
    }
    /// q = −(v/v_st)² (row 0), e^q (row 1), g (row 2), w = s/g (row 3) and
    /// r = v − σ₀·sv·(v·w) (row 4), sv the piece's constant sgn x', on any `Jet` (one
    /// recurrence for [`Term::rate_taylor`] and [`Term::rate_taylor_lanes`]).
    #[inline(always)]
    fn rate_taylor(&self, k: usize, _x: &[f64], v: &[f64], s: &[f64], rows: &mut Scratch) -> f64 {
        let [fc, fs, vst, sigma0, ..] = self.values;
        let directed = sigma0 * piece_sign(self.side, v[0]);
        lugre_rate_row([fc, fs, vst, directed], k, v, s, &mut rows.0)
    }
    #[inline(always)]
    fn taylor(&self, k: usize, _x: &[f64], v: &[f64], s: &[f64], rows: &mut Scratch) -> f64 {
        let [.., sigma0, sigma1, sigma2] = self.values;
        lugre_row([sigma0, sigma1, sigma2], k, v, s, &rows.0)
    }
    const ON_LANES: bool = true;
    /// On a piece: f_c, f_s, v_st, σ₀·sv (sv the piece's sgn x'), σ₁ and σ₂; σ₀ = |σ₀·sv|. Only
    /// a piece's sign is constant: a model whose terms read their signs from the state runs on
    /// lanes only as pieces ([`super::integrate_switching_models`]).
    fn lane_values(&self) -> [f64; LANE_PARAMS] {
        let [fc, fs, vst, sigma0, sigma1, sigma2] = self.values;
        [fc, fs, vst, sigma0 * self.side, sigma1, sigma2]
    }
    #[inline(always)]
    fn taylor_lanes(
        values: &[Lanes],
        k: usize,
        _x: &[Lanes],
        v: &[Lanes],
        s: &[Lanes],
        rows: &mut LaneRows,
    ) -> Option<Lanes> {
        let sigma0 = values[3].abs();
        Some(lugre_row([sigma0, values[4], values[5]], k, v, s, rows))
    }
    #[inline(always)]
    fn rate_taylor_lanes(
        values: &[Lanes],
        k: usize,
        _x: &[Lanes],
        v: &[Lanes],
        s: &[Lanes],
        rows: &mut LaneRows,
    ) -> Lanes {
        let p = [values[0], values[1], values[2], values[3]];
        lugre_rate_row(p, k, v, s, rows)
    }
    const LIMITS_STEPS: bool = true;
    /// The Stribeck factor e^q ([`exp_step_limit`]), weighed by what it moves: σ₀|v·w|·|f_s −
    /// f_c|/g in the rate, times (1 + σ₁) in the torque.
    fn step_limit(&self, rows: &Scratch, order: usize, h: f64, negligible: f64) -> f64 {
        let [fc, fs, _, sigma0, sigma1, _] = self.values;
        lugre_limit([fc, fs, sigma0, sigma1], &rows.0, order, h, negligible)
    }
    #[inline(always)]
    fn step_limit_lanes(
        values: &[Lanes],
        rows: &LaneRows,
        order: usize,
        h: Lanes,
        negligible: Lanes,
    ) -> Lanes {
        let p = [values[0], values[1], values[3].abs(), values[4]];
        lugre_limit(p, rows, order, h, negligible)
    }
    fn text(&self) -> String {
        " + σ₀·s + σ₁·s' + σ₂·x'".into()
    }
    fn latex(&self) -> String {
        r" + \sigma_0 s + \sigma_1 \dot s + \sigma_2 \dot x".into()
    }
    fn rate_text(&self) -> Option<String> {
        Some("s' = x' − σ₀·|x'|·s/(f_c + (f_s − f_c)·exp(−(x'/v_st)²))".into())
    }
    fn rate_latex(&self) -> Option<String> {
        Some(
            r"\dot s = \dot x - \sigma_0 |\dot x| s / \left(f_c + (f_s - f_c) e^{-(\dot x / v_{st})^2}\right)"
                .into(),
        )
    }
    fn directed(self, side: Side) -> Self {
        LuGre {
            side: side.v,
            ..self
        }
    }
}

/// [`LuGre`]'s rate row k on any [`Jet`], on a piece where σ₀·sgn x' is `directed`:
/// q = −(v/v_st)² (row 0), e^q (row 1), g (row 2), w = s/g (row 3) and r = v − directed·(v·w)
/// (row 4).
#[inline(always)]
fn lugre_rate_row<J: Jet>(
    [fc, fs, vst, directed]: [J; 4],
    k: usize,
    v: &[J],
    s: &[J],
    rows: &mut [[J; MAX_ROWS]; SCRATCH_ROWS],
) -> J {
    let [q, e, g, w, r, ..] = rows;
    g[k] = Level { fc, fs, vst }.row(v, q, e, k);
    w[k] = quotient_coefficient(s, g, w, k);
    r[k] = v[k] - directed * cauchy(v, w, k);
    r[k]
}

/// [`LuGre`]'s torque row k on any [`Jet`]: σ₀·s_k + σ₁·r_k + σ₂·v_k, r's rows from
/// [`lugre_rate_row`].
#[inline(always)]
fn lugre_row<J: Jet>(
    [sigma0, sigma1, sigma2]: [J; 3],
    k: usize,
    v: &[J],
    s: &[J],
    rows: &[[J; MAX_ROWS]; SCRATCH_ROWS],
) -> J {
    sigma0 * s[k] + sigma1 * rows[4][k] + sigma2 * v[k]
}

/// [`LuGre`]'s step limit on any [`Jet`], from its rows ([`lugre_rate_row`]): the Stribeck
/// factor e^q ([`exp_step_limit`]), weighed by σ₀|w|·|f_s − f_c|/g·(1 + σ₁).
#[inline(always)]
fn lugre_limit<J: Jet>(
    [fc, fs, sigma0, sigma1]: [J; 4],
    rows: &[[J; MAX_ROWS]; SCRATCH_ROWS],
    order: usize,
    h: J,
    negligible: J,
) -> J {
    let [q, e, g, w, ..] = rows;
    let amplitude = (J::splat(1.0) + sigma1) * sigma0 * w[0].abs() * (fs - fc).abs() / g[0];
    exp_step_limit(q, e, order, h, amplitude, negligible)
}

/// Bouc–Wen hysteresis of the flexspline on the twist x: T = k_h·(ρ·x + (1 − ρ)·z) with
/// z' = A·x' − β·|x'|·|z|ⁿ⁻¹·z − γ_h·x'·|z|ⁿ (Wen 1976). Rate-independent: z depends on the
/// path of x, not on its speed; its loops' area is the energy the term dissipates per cycle. The
/// exponent n is a whole number (1 to 4), so that on a piece of fixed signs the law is a
/// polynomial.
// serialised as its values alone: the piece is integration state, not a parameter
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(transparent)]
pub struct BoucWen {
    values: [f64; 6],
    #[serde(skip)]
    side: Side,
}

impl BoucWen {
    /// (sv, sz, n): the piece's signs and the exponent.
    fn signs(&self, v: f64, z: f64) -> (f64, f64, i32) {
        (
            piece_sign(self.side.v, v),
            piece_sign(self.side.z, z),
            self.values[5] as i32,
        )
    }

    /// c with β·|v|·|z|ⁿ⁻¹·z + γ_h·v·|z|ⁿ = c·v·zⁿ on the piece.
    fn coefficient(&self, sv: f64, sz: f64, n: i32) -> f64 {
        let [_, _, _, beta, gamma, _] = self.values;
        beta * sv * sz.powi(n - 1) + gamma * sz.powi(n)
    }
}

impl Term for BoucWen {
    const KIND: &'static str = "boucwen";
    /// The loading branch of z against the twist x is dz/dx = A + c·zⁿ with c = −(β + γ_h)
    /// (z, x' > 0). With c > 0 and n ≥ 2 it reaches infinity within a finite twist (∫dz/(A +
    /// c·zⁿ) converges), so the state blows up under a moderate load; with n = 1 it is
    /// (A/c)(e^{c·Δx} − 1), finite for every finite twist (Noël & Schoukens' benchmark has
    /// c > 0 and n = 1). β < 0 is refused by its domain: unloading then grows |z| again.
    const RELATIONS: &'static [Relation] = &[Relation::NonNegativeSumFrom {
        first: 3,
        second: 4,
        when: 5,
        from: 2.0,
        reason: "betah + gammah must be ≥ 0 for an exponent nh ≥ 2, or the hysteretic state z \
                 blows up within a finite twist",
    }];
    const ABOUT: &'static str = "Bouc–Wen hysteresis k_h·(ρx + (1 − ρ)z) with a hysteretic state z";
    const STATE: Option<StateInfo> = Some(StateInfo {
        name: "z",
        meaning: "Bouc–Wen hysteretic twist",
    });
    const SWITCHES_AT_REST: bool = true;
    const SWITCHES_AT_ZERO_STATE: bool = true;
    const PARAMS: &'static [ParamInfo] = &[
        ParamInfo {
            name: "kh",
            symbol: "k_h",
            latex: "k_h",
            meaning: "stiffness of the hysteretic element",
            domain: Domain::NonNegative,
            default: 0.5,
            si: "k·J_eq/C² (a stiffness on γ's scale)",
        },
        ParamInfo {
            name: "rho",
            symbol: "ρ",
            latex: r"\rho",
            meaning: "elastic share of the element",
            domain: Domain::Fraction,
            default: 0.0,
            si: "ρ (a ratio)",
        },
        ParamInfo {
            name: "ah",
            symbol: "A",
            latex: "A",
            meaning: "initial slope of z against x",
            domain: Domain::Positive,
            default: 1.0,
            si: "A (a ratio)",
        },
        ParamInfo {
            name: "betah",
            symbol: "β",
            latex: r"\beta",
            meaning: "loop shape (with γ_h); β < 0 lets unloading grow z without bound",
            domain: Domain::NonNegative,
            default: 0.5,
            si: "β·x_scaleⁿ",
        },
        ParamInfo {
            name: "gammah",
            symbol: "γ_h",
            latex: r"\gamma_h",
            meaning: "loop shape (with β)",
            domain: Domain::Any,
            default: 0.5,
            si: "γ_h·x_scaleⁿ",
        },
        ParamInfo {
            name: "nh",
            symbol: "n",
            latex: "n",
            meaning: "sharpness of the transition to the plastic branch",
            domain: Domain::Exponent,
            default: 1.0,
            si: "n",
        },
    ];
    fn from_values(v: &[f64]) -> Self {
        BoucWen {
            values: [v[0], v[1], v[2], v[3], v[4], v[5]],
            side: Side::default(),
        }
    }
    fn values(&self) -> &[f64] {
        &self.values
    }
    fn rate(&self, _x: f64, v: f64, z: f64) -> f64 {
        let a = self.values[2];
        let (sv, sz, n) = self.signs(v, z);
        a * v - self.coefficient(sv, sz, n) * v * z.powi(n)
    }
    fn rate_gradient(&self, _x: f64, v: f64, z: f64) -> [f64; 3] {
        let a = self.values[2];
        let (sv, sz, n) = self.signs(v, z);
        let c = self.coefficient(sv, sz, n);
        [
            0.0,
            a - c * z.powi(n),
            -c * v * f64::from(n) * z.powi(n - 1),
        ]
    }
    fn rate_param_derivative(&self, i: usize, _x: f64, v: f64, z: f64) -> f64 {
        let [_, _, _, beta, gamma, _] = self.values;
        let (sv, sz, n) = self.signs(v, z);
        let abs_z = sz * z;
        match i {
            2 => v,
            3 => -sv * sz.powi(n - 1) * v * z.powi(n),
            4 => -sz.powi(n) * v * z.powi(n),
            5 if abs_z > 0.0 => {
                -(beta * sv * sz.powi(n - 1) + gamma * sz.powi(n)) * v * z.powi(n) * abs_z.ln()
            }
            _ => 0.0,
        }
    }
    fn torque(&self, x: f64, _v: f64, z: f64) -> f64 {
        let [kh, rho, ..] = self.values;
        kh * (rho * x + (1.0 - rho) * z)
    }
    fn gradient(&self, _x: f64, _v: f64, _z: f64) -> [f64; 3] {
        let [kh, rho, ..] = self.values;
        [kh * rho, 0.0, kh * (1.0 - rho)]
    }
    fn param_derivative(&self, i: usize, x: f64, _v: f64, z: f64) -> f64 {
        let [kh, rho, ..] = self.values;
        match i {
            0 => rho * x + (1.0 - rho) * z,
            1 => kh * (x - z),
            _ => 0.0,
        }
    }
    /// zⁿ by repeated products (rows 0..n − 2 hold z², z³, z⁴), then
    /// r = A·v − c·(v·zⁿ) with the piece's constant c, on any `Jet` (one recurrence for
    /// [`Term::rate_taylor`] and [`Term::rate_taylor_lanes`]).
    #[inline(always)]
    fn rate_taylor(&self, k: usize, _x: &[f64], v: &[f64], z: &[f64], rows: &mut Scratch) -> f64 {
        let a = self.values[2];
        let (sv, sz, n) = self.signs(v[0], z[0]);
        let c = self.coefficient(sv, sz, n);
        bouc_wen_rate_row(a, c, n as usize, k, v, z, &mut rows.0)
    }
    #[inline(always)]
    fn taylor(&self, k: usize, x: &[f64], _v: &[f64], z: &[f64], _rows: &mut Scratch) -> f64 {
        let [kh, rho, ..] = self.values;
        bouc_wen_row(kh, rho, k, x, z)
    }
    const ON_LANES: bool = true;
    /// On a piece: k_h, ρ, A, the piece's constant c = β·s_v·s_zⁿ⁻¹ + γ_h·s_zⁿ (s_v, s_z its
    /// signs of x' and z) and n. Only a piece's c is constant: a model whose terms read their
    /// signs from the state runs on lanes only as pieces ([`super::integrate_switching_models`]).
    fn lane_values(&self) -> [f64; LANE_PARAMS] {
        let [kh, rho, a, .., n] = self.values;
        let (sv, sz, n_whole) = (self.side.v, self.side.z, n as i32);
        [kh, rho, a, self.coefficient(sv, sz, n_whole), n, 0.0]
    }
    /// The exponent n, whose products the recurrence unrolls.
    fn lane_shape(&self) -> usize {
        self.values[5] as usize
    }
    #[inline(always)]
    fn taylor_lanes(
        values: &[Lanes],
        k: usize,
        x: &[Lanes],
        _v: &[Lanes],
        z: &[Lanes],
        _rows: &mut LaneRows,
    ) -> Option<Lanes> {
        Some(bouc_wen_row(values[0], values[1], k, x, z))
    }
    #[inline(always)]
    fn rate_taylor_lanes(
        values: &[Lanes],
        k: usize,
        _x: &[Lanes],
        v: &[Lanes],
        z: &[Lanes],
        rows: &mut LaneRows,
    ) -> Lanes {
        // n is the same on every lane (`lane_shape`)
        let n = values[4].0[0] as usize;
        bouc_wen_rate_row(values[2], values[3], n, k, v, z, rows)
    }
    fn text(&self) -> String {
        " + k_h·(ρ·x + (1 − ρ)·z)".into()
    }
    fn latex(&self) -> String {
        r" + k_h \left(\rho x + (1 - \rho) z\right)".into()
    }
    fn rate_text(&self) -> Option<String> {
        Some("z' = A·x' − β·|x'|·|z|ⁿ⁻¹·z − γ_h·x'·|z|ⁿ".into())
    }
    fn rate_latex(&self) -> Option<String> {
        Some(r"\dot z = A \dot x - \beta |\dot x| |z|^{n-1} z - \gamma_h \dot x |z|^n".into())
    }
    fn directed(self, side: Side) -> Self {
        BoucWen { side, ..self }
    }
}

/// [`BoucWen`]'s torque row k on any [`Jet`]: k_h·(ρ·x_k + (1 − ρ)·z_k).
#[inline(always)]
fn bouc_wen_row<J: Jet>(kh: J, rho: J, k: usize, x: &[J], z: &[J]) -> J {
    kh * (rho * x[k] + (J::splat(1.0) - rho) * z[k])
}

/// [`BoucWen`]'s rate row k on any [`Jet`], on a piece whose constant is c: zⁿ by repeated
/// products (rows 0..n − 2 of `rows` hold z², z³, z⁴), then r_k = A·v_k − c·(v·zⁿ)_k.
#[inline(always)]
fn bouc_wen_rate_row<J: Jet>(
    a: J,
    c: J,
    n: usize,
    k: usize,
    v: &[J],
    z: &[J],
    rows: &mut [[J; MAX_ROWS]; SCRATCH_ROWS],
) -> J {
    let zn = whole_power_rows(z, n, rows, k);
    a * v[k] - c * cauchy(v, zn, k)
}
