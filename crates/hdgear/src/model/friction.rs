//! Friction on the twist's rate x': smooth Coulomb friction (tanh), the Stribeck law with a
//! regularised sign, and Coulomb–Stribeck friction with sticking, whose sign switches at x' = 0
//! ([`super::switching`]). The Stribeck curve they share with LuGre is defined here.

use super::jet::{
    Jet, Lanes, cauchy, exp_coefficient, exp_step_limit, square_coefficient, tanh_coefficient,
    tanh_step_limit,
};
use super::relation::Relation;
use super::term::{
    Domain, LANE_PARAMS, LaneRows, MAX_ROWS, ParamInfo, Scratch, Side, Term, piece_sign,
};
use crate::integrate::taylor::SCRATCH_ROWS;
use serde::Serialize;

/// The Stribeck curve g(v) = f_c + (f_s − f_c)·e^{−(v/v_st)²} the friction laws share
/// ([`Stribeck`], [`Coulomb`], [`LuGre`]): its value, slope, parameter derivatives and Taylor
/// rows, defined once.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Level<J = f64> {
    pub(crate) fc: J,
    pub(crate) fs: J,
    pub(crate) vst: J,
}

impl<J: Jet> Level<J> {
    /// Row k of g from v's rows 0..=k, keeping q = −(v/v_st)² and e^q in `q` and `e`.
    #[inline(always)]
    pub(crate) fn row(self, v: &[J], q: &mut [J], e: &mut [J], k: usize) -> J {
        let Level { fc, fs, vst } = self;
        q[k] = square_coefficient(v, k) * (J::splat(-1.0) / (vst * vst));
        e[k] = exp_coefficient(q, e, k);
        (fs - fc) * e[k] + if k == 0 { fc } else { J::splat(0.0) }
    }
}

impl Level {
    /// (g, ∂g/∂v, e = e^{−(v/v_st)²}).
    pub(crate) fn at(self, v: f64) -> (f64, f64, f64) {
        let Level { fc, fs, vst } = self;
        let e = (-(v / vst).powi(2)).exp();
        (
            fc + (fs - fc) * e,
            (fs - fc) * e * (-2.0 * v / (vst * vst)),
            e,
        )
    }

    /// (∂g/∂f_c, ∂g/∂f_s, ∂g/∂v_st) at v.
    pub(crate) fn param_derivatives(self, v: f64) -> [f64; 3] {
        let Level { fc, fs, vst } = self;
        let (.., e) = self.at(v);
        [1.0 - e, e, (fs - fc) * e * 2.0 * v * v / (vst * vst * vst)]
    }
}

/// Smooth Coulomb friction f_c·tanh(x'/v_s): a regularised sign with velocity scale v_s.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Friction(pub [f64; 2]);

impl Term for Friction {
    const KIND: &'static str = "friction";
    const ABOUT: &'static str = "smooth Coulomb friction f_c·tanh(x'/v_s)";
    const ON_LANES: bool = true;
    const PARAMS: &'static [ParamInfo] = &[
        ParamInfo {
            name: "fc",
            symbol: "f_c",
            latex: "f_c",
            meaning: "Coulomb friction torque",
            domain: Domain::NonNegative,
            default: 0.05,
            si: "T_c·k2·φ·J_eq²/C⁴ (a torque on μ's scale)",
        },
        ParamInfo {
            name: "vs",
            symbol: "v_s",
            latex: "v_s",
            meaning: "velocity scale of the regularisation",
            domain: Domain::Positive,
            default: 0.01,
            si: "θ'·k2·φ·J_eq²/C³ (a velocity on x's scale)",
        },
    ];
    fn from_values(v: &[f64]) -> Self {
        Friction([v[0], v[1]])
    }
    fn values(&self) -> &[f64] {
        &self.0
    }
    fn torque(&self, _x: f64, v: f64, _z: f64) -> f64 {
        let [fc, vs] = self.0;
        fc * (v / vs).tanh()
    }
    fn gradient(&self, _x: f64, v: f64, _z: f64) -> [f64; 3] {
        let [fc, vs] = self.0;
        let t = (v / vs).tanh();
        [0.0, fc * (1.0 - t * t) / vs, 0.0]
    }
    fn param_derivative(&self, i: usize, _x: f64, v: f64, _z: f64) -> f64 {
        let [fc, vs] = self.0;
        let t = (v / vs).tanh();
        [t, -fc * (1.0 - t * t) * v / (vs * vs)][i]
    }
    /// u = v/v_s (row 0), tanh u (row 1) and its square (row 2), on any `Jet` (one recurrence for
    /// [`Term::taylor`] and [`Term::taylor_lanes`]).
    #[inline(always)]
    fn taylor(&self, k: usize, _x: &[f64], v: &[f64], _z: &[f64], rows: &mut Scratch) -> f64 {
        friction_row(self.0, k, v, &mut rows.0)
    }
    #[inline(always)]
    fn taylor_lanes(
        values: &[Lanes],
        k: usize,
        _x: &[Lanes],
        v: &[Lanes],
        _z: &[Lanes],
        rows: &mut LaneRows,
    ) -> Option<Lanes> {
        Some(friction_row([values[0], values[1]], k, v, rows))
    }
    const LIMITS_STEPS: bool = true;
    /// tanh(x'/v_s) far from x' = 0 ([`tanh_step_limit`]).
    fn step_limit(&self, rows: &Scratch, order: usize, h: f64, negligible: f64) -> f64 {
        friction_limit(self.0[0], &rows.0, order, h, negligible)
    }
    #[inline(always)]
    fn step_limit_lanes(
        values: &[Lanes],
        rows: &LaneRows,
        order: usize,
        h: Lanes,
        negligible: Lanes,
    ) -> Lanes {
        friction_limit(values[0], rows, order, h, negligible)
    }
    fn text(&self) -> String {
        " + f_c·tanh(x'/v_s)".into()
    }
    fn latex(&self) -> String {
        r" + f_c \tanh(\dot x / v_s)".into()
    }
}

/// Static friction is at least the sliding level it drops to: the Stribeck law's (f_c + (f_s −
/// f_c)·e^{−(x'/v_st)²}) is then its largest at rest, and the sticking band ±f_s holds every
/// slip that the sliding level would stop. f_s < f_c would make friction rise with speed out of
/// rest, a law no friction test of a drive shows. `fc` and `fs` are the first two parameters of
/// each friction law that has both.
pub const STATIC_AT_LEAST_SLIDING: Relation = Relation::AtLeast {
    upper: 1,
    lower: 0,
    reason: "the static (breakaway) friction must be at least the Coulomb (sliding) level",
};

/// The Coulomb (sliding) friction level shared by the Stribeck, switched-Coulomb and LuGre friction laws.
pub(super) const FRICTION_FC: ParamInfo = ParamInfo {
    name: "fc",
    symbol: "f_c",
    latex: "f_c",
    meaning: "Coulomb (sliding) friction torque",
    domain: Domain::NonNegative,
    default: 0.05,
    si: "T·k2·φ·J_eq²/C⁴ (a torque on μ's scale)",
};

/// The static (breakaway) friction level shared by the Stribeck, switched-Coulomb and LuGre friction laws.
pub(super) const FRICTION_FS: ParamInfo = ParamInfo {
    name: "fs",
    symbol: "f_s",
    latex: "f_s",
    meaning: "static (breakaway) friction torque",
    domain: Domain::NonNegative,
    default: 0.08,
    si: "T·k2·φ·J_eq²/C⁴ (a torque on μ's scale)",
};

/// The Stribeck velocity shared by the Stribeck, switched-Coulomb and LuGre friction laws.
pub(super) const STRIBECK_VELOCITY: ParamInfo = ParamInfo {
    name: "vst",
    symbol: "v_st",
    latex: r"v_{st}",
    meaning: "Stribeck velocity",
    domain: Domain::Positive,
    default: 0.1,
    si: "θ'·k2·φ·J_eq²/C³ (a velocity on x's scale)",
};

/// The viscous friction coefficient shared by the Stribeck and switched-Coulomb friction laws
/// (LuGre names its own, σ₂).
const VISCOUS: ParamInfo = ParamInfo {
    name: "cv",
    symbol: "c_v",
    latex: "c_v",
    meaning: "viscous friction coefficient (added to the unit damping)",
    domain: Domain::NonNegative,
    default: 0.0,
    si: "c_v/C (over the damping C)",
};

/// Coulomb–Stribeck–viscous friction (f_c + (f_s − f_c)·e^{−(x'/v_s)²})·tanh(x'/v_r) + c_v·x',
/// regularised at the velocity scale v_r.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Stribeck(pub [f64; 5]);

impl Stribeck {
    fn level(&self) -> Level {
        let [fc, fs, vst, ..] = self.0;
        Level { fc, fs, vst }
    }
}

impl Term for Stribeck {
    const KIND: &'static str = "stribeck";
    const RELATIONS: &'static [Relation] = &[STATIC_AT_LEAST_SLIDING];
    const ABOUT: &'static str = "Coulomb–Stribeck–viscous friction, regularised by tanh(x'/v_r)";
    const ON_LANES: bool = true;
    const PARAMS: &'static [ParamInfo] = &[
        FRICTION_FC,
        FRICTION_FS,
        STRIBECK_VELOCITY,
        VISCOUS,
        ParamInfo {
            name: "vr",
            symbol: "v_r",
            latex: "v_r",
            meaning: "velocity scale of the regularisation",
            domain: Domain::Positive,
            default: 0.01,
            si: "θ'·k2·φ·J_eq²/C³ (a velocity on x's scale)",
        },
    ];
    fn from_values(v: &[f64]) -> Self {
        Stribeck([v[0], v[1], v[2], v[3], v[4]])
    }
    fn values(&self) -> &[f64] {
        &self.0
    }
    fn torque(&self, _x: f64, v: f64, _z: f64) -> f64 {
        let [.., cv, vr] = self.0;
        self.level().at(v).0 * (v / vr).tanh() + cv * v
    }
    fn gradient(&self, _x: f64, v: f64, _z: f64) -> [f64; 3] {
        let [.., cv, vr] = self.0;
        let t = (v / vr).tanh();
        let (level, dlevel, _) = self.level().at(v);
        [0.0, dlevel * t + level * (1.0 - t * t) / vr + cv, 0.0]
    }
    fn param_derivative(&self, i: usize, _x: f64, v: f64, _z: f64) -> f64 {
        let vr = self.0[4];
        let t = (v / vr).tanh();
        match i {
            0..=2 => self.level().param_derivatives(v)[i] * t,
            3 => v,
            _ => -self.level().at(v).0 * (1.0 - t * t) * v / (vr * vr),
        }
    }
    /// q = −(v/v_st)² (row 0), e^q (row 1), u = v/v_r (row 2), tanh u (row 3) and its square
    /// (row 4); T_k = Σ_j (f_c[j = 0] + (f_s − f_c)e_j)·tanh_{k−j} + c_v v_k, on any `Jet` (one
    /// recurrence for [`Term::taylor`] and [`Term::taylor_lanes`]).
    #[inline(always)]
    fn taylor(&self, k: usize, _x: &[f64], v: &[f64], _z: &[f64], rows: &mut Scratch) -> f64 {
        stribeck_row(self.0, k, v, &mut rows.0)
    }
    #[inline(always)]
    fn taylor_lanes(
        values: &[Lanes],
        k: usize,
        _x: &[Lanes],
        v: &[Lanes],
        _z: &[Lanes],
        rows: &mut LaneRows,
    ) -> Option<Lanes> {
        let p = [values[0], values[1], values[2], values[3], values[4]];
        Some(stribeck_row(p, k, v, rows))
    }
    const LIMITS_STEPS: bool = true;
    /// The Stribeck factor e^q ([`exp_step_limit`]) and tanh(x'/v_r) far from x' = 0
    /// ([`tanh_step_limit`]).
    fn step_limit(&self, rows: &Scratch, order: usize, h: f64, negligible: f64) -> f64 {
        let [fc, fs, ..] = self.0;
        stribeck_limit([fc, fs], &rows.0, order, h, negligible)
    }
    #[inline(always)]
    fn step_limit_lanes(
        values: &[Lanes],
        rows: &LaneRows,
        order: usize,
        h: Lanes,
        negligible: Lanes,
    ) -> Lanes {
        stribeck_limit([values[0], values[1]], rows, order, h, negligible)
    }
    fn text(&self) -> String {
        " + (f_c + (f_s − f_c)·exp(−(x'/v_st)²))·tanh(x'/v_r) + c_v·x'".into()
    }
    fn latex(&self) -> String {
        r" + \left(f_c + (f_s - f_c) e^{-(\dot x / v_{st})^2}\right) \tanh(\dot x / v_r) + c_v \dot x"
            .into()
    }
}

/// [`Friction`]'s row k on any [`Jet`]: u = v/v_s (row 0), tanh u (row 1) and its square
/// (row 2).
#[inline(always)]
fn friction_row<J: Jet>(
    [fc, vs]: [J; 2],
    k: usize,
    v: &[J],
    rows: &mut [[J; MAX_ROWS]; SCRATCH_ROWS],
) -> J {
    let [u, t, sq, ..] = rows;
    u[k] = v[k] * (J::splat(1.0) / vs);
    t[k] = tanh_coefficient(u, sq, k);
    sq[k] = square_coefficient(t, k);
    fc * t[k]
}

/// [`Friction`]'s step limit on any [`Jet`], from its rows ([`friction_row`]): tanh(x'/v_s) far
/// from x' = 0 ([`tanh_step_limit`]).
#[inline(always)]
fn friction_limit<J: Jet>(
    fc: J,
    rows: &[[J; MAX_ROWS]; SCRATCH_ROWS],
    order: usize,
    h: J,
    negligible: J,
) -> J {
    let [u, _, sq, ..] = rows;
    tanh_step_limit(u, sq, order, h, fc, negligible)
}

/// [`Stribeck`]'s step limit on any [`Jet`], from its rows ([`stribeck_row`]): the Stribeck
/// factor e^q ([`exp_step_limit`]), then tanh(x'/v_r) far from x' = 0 ([`tanh_step_limit`]).
#[inline(always)]
fn stribeck_limit<J: Jet>(
    [fc, fs]: [J; 2],
    rows: &[[J; MAX_ROWS]; SCRATCH_ROWS],
    order: usize,
    h: J,
    negligible: J,
) -> J {
    let [q, e, u, _, sq, ..] = rows;
    let h = exp_step_limit(q, e, order, h, (fs - fc).abs(), negligible);
    tanh_step_limit(u, sq, order, h, fc.max(fs), negligible)
}

/// [`Stribeck`]'s row k on any [`Jet`]: q = −(v/v_st)² (row 0), e^q (row 1), u = v/v_r
/// (row 2), tanh u (row 3) and its square (row 4); T_k = Σ_j (f_c[j = 0] + (f_s − f_c)e_j)·
/// tanh_{k−j} + c_v v_k.
#[inline(always)]
fn stribeck_row<J: Jet>(
    [fc, fs, vst, cv, vr]: [J; 5],
    k: usize,
    v: &[J],
    rows: &mut [[J; MAX_ROWS]; SCRATCH_ROWS],
) -> J {
    let [q, e, u, t, sq, ..] = rows;
    Level { fc, fs, vst }.row(v, q, e, k);
    u[k] = v[k] * (J::splat(1.0) / vr);
    t[k] = tanh_coefficient(u, sq, k);
    sq[k] = square_coefficient(t, k);
    fc * t[k] + (fs - fc) * cauchy(e, t, k) + cv * v[k]
}

/// Coulomb–Stribeck–viscous friction with sticking, not regularised:
/// (f_c + (f_s − f_c)·e^{−(x'/v_st)²})·sgn x' + c_v·x'. At x' = 0 it is the static band: the
/// motion sticks while the rest of the torque stays within ±f_s ([`super::Model::breakaway`]);
/// a [`super::switching::Switching`] integration steps it piece by piece, each piece with sgn x'
/// fixed ([`Term::directed`]), so its Taylor rows are analytic on the piece.
// serialised as its values alone: the piece is integration state, not a parameter
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(transparent)]
pub struct Coulomb {
    values: [f64; 4],
    /// sgn x' on the current piece (0: read it from x').
    #[serde(skip)]
    side: f64,
}

impl Coulomb {
    /// sgn x' on this piece: the side it is directed to, else the sign of `v` (0 at rest).
    fn sign(&self, v: f64) -> f64 {
        piece_sign(self.side, v)
    }

    fn level(&self) -> Level {
        let [fc, fs, vst, _] = self.values;
        Level { fc, fs, vst }
    }
}

impl Term for Coulomb {
    const KIND: &'static str = "coulomb";
    const RELATIONS: &'static [Relation] = &[STATIC_AT_LEAST_SLIDING];
    const SWITCHES_AT_REST: bool = true;
    const ABOUT: &'static str =
        "Coulomb–Stribeck–viscous friction with sticking (sgn x', integrated piece by piece)";
    const PARAMS: &'static [ParamInfo] = &[
        FRICTION_FC,
        ParamInfo {
            meaning: "static (breakaway) friction torque: the sticking band",
            ..FRICTION_FS
        },
        STRIBECK_VELOCITY,
        VISCOUS,
    ];
    fn from_values(v: &[f64]) -> Self {
        Coulomb {
            values: [v[0], v[1], v[2], v[3]],
            side: 0.0,
        }
    }
    fn values(&self) -> &[f64] {
        &self.values
    }
    fn torque(&self, _x: f64, v: f64, _z: f64) -> f64 {
        self.level().at(v).0 * self.sign(v) + self.values[3] * v
    }
    /// On the piece (the switch's Dirac at x' = 0 is the events' business, not the gradient's).
    fn gradient(&self, _x: f64, v: f64, _z: f64) -> [f64; 3] {
        let (_, dlevel, _) = self.level().at(v);
        [0.0, dlevel * self.sign(v) + self.values[3], 0.0]
    }
    fn param_derivative(&self, i: usize, _x: f64, v: f64, _z: f64) -> f64 {
        match i {
            0..=2 => self.level().param_derivatives(v)[i] * self.sign(v),
            _ => v,
        }
    }
    /// q = −(v/v_st)² (row 0) and e^q (row 1); T_k = s·(f_c[k = 0] + (f_s − f_c)e_k) + c_v v_k
    /// with s the piece's constant sgn x', on any `Jet` (one recurrence for [`Term::taylor`] and
    /// [`Term::taylor_lanes`]).
    #[inline(always)]
    fn taylor(&self, k: usize, _x: &[f64], v: &[f64], _z: &[f64], rows: &mut Scratch) -> f64 {
        let [fc, fs, vst, cv] = self.values;
        coulomb_row([fc, fs, vst, cv, self.sign(v[0])], k, v, &mut rows.0)
    }
    const ON_LANES: bool = true;
    /// On a piece: the values and the piece's sgn x'.
    fn lane_values(&self) -> [f64; LANE_PARAMS] {
        let [fc, fs, vst, cv] = self.values;
        [fc, fs, vst, cv, self.side, 0.0]
    }
    #[inline(always)]
    fn taylor_lanes(
        values: &[Lanes],
        k: usize,
        _x: &[Lanes],
        v: &[Lanes],
        _z: &[Lanes],
        rows: &mut LaneRows,
    ) -> Option<Lanes> {
        let p = [values[0], values[1], values[2], values[3], values[4]];
        Some(coulomb_row(p, k, v, rows))
    }
    const LIMITS_STEPS: bool = true;
    /// The Stribeck factor e^q ([`exp_step_limit`]).
    fn step_limit(&self, rows: &Scratch, order: usize, h: f64, negligible: f64) -> f64 {
        let [fc, fs, ..] = self.values;
        coulomb_limit([fc, fs], &rows.0, order, h, negligible)
    }
    #[inline(always)]
    fn step_limit_lanes(
        values: &[Lanes],
        rows: &LaneRows,
        order: usize,
        h: Lanes,
        negligible: Lanes,
    ) -> Lanes {
        coulomb_limit([values[0], values[1]], rows, order, h, negligible)
    }
    fn text(&self) -> String {
        " + (f_c + (f_s − f_c)·exp(−(x'/v_st)²))·sgn x' + c_v·x'".into()
    }
    fn latex(&self) -> String {
        r" + \left(f_c + (f_s - f_c) e^{-(\dot x / v_{st})^2}\right) \operatorname{sgn} \dot x + c_v \dot x"
            .into()
    }
    fn breakaway(&self) -> Option<f64> {
        Some(self.values[1])
    }
    fn directed(self, side: Side) -> Self {
        Coulomb {
            side: side.v,
            ..self
        }
    }
}

/// [`Coulomb`]'s row k on any [`Jet`], with s its piece's sgn x': q = −(v/v_st)² (row 0), e^q
/// (row 1); T_k = s·(f_c[k = 0] + (f_s − f_c)e_k) + c_v v_k.
#[inline(always)]
fn coulomb_row<J: Jet>(
    [fc, fs, vst, cv, s]: [J; 5],
    k: usize,
    v: &[J],
    rows: &mut [[J; MAX_ROWS]; SCRATCH_ROWS],
) -> J {
    let [q, e, ..] = rows;
    let level = Level { fc, fs, vst }.row(v, q, e, k);
    s * level + cv * v[k]
}

/// [`Coulomb`]'s step limit on any [`Jet`], from its rows ([`coulomb_row`]): the Stribeck factor
/// e^q ([`exp_step_limit`]).
#[inline(always)]
fn coulomb_limit<J: Jet>(
    [fc, fs]: [J; 2],
    rows: &[[J; MAX_ROWS]; SCRATCH_ROWS],
    order: usize,
    h: J,
    negligible: J,
) -> J {
    let [q, e, ..] = rows;
    exp_step_limit(q, e, order, h, (fs - fc).abs(), negligible)
}
