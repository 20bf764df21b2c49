//! A term as one declaration: its torque (and its state's rate) written once, as a function
//! over any [`Num`], from which every machine's need is derived ([`Declared`] implements
//! [`Term`] for it).
//!
//! heyoka's design is the anchor: a model is an expression, and its derivatives and Taylor
//! decomposition follow from it. Here the expression is a generic Rust function, and each use
//! instantiates it with its own numbers:
//!
//! * `f64`: the value T(x, x', z);
//! * [`Dual`]: the value with three directional derivatives, so the Jacobian (∂T/∂x, ∂T/∂x',
//!   ∂T/∂z) and each parameter derivative ∂T/∂p are exact, not differenced;
//! * [`Row`] on `f64` or on [`Lanes`]: row k of T's Taylor coefficients along a solution whose
//!   rows 0..=k are known. Each operation the function performs is one elementary step of the
//!   Taylor decomposition: its rows are kept in the term's [`Scratch`] from order to order (the
//!   n-th operation in row n), a product's row is a Cauchy sum, a sum's row a sum. The function
//!   is straight-line code, so each call makes the same operations in the same order and the
//!   compiler, which sees the whole function, inlines it into the stepper (a monomorphised term).
//!
//! The vocabulary is the ring operations (+, −, ×, by numbers too) over x, x', z, the
//! parameters and the piece's signs s_v = sgn x' and s_z = sgn z ([`Vars`]). A law written in
//! it is a polynomial in x, x' and z on each piece of its law, so its Taylor series converge
//! for every step and the state's own rows show their size: a declared term never limits
//! steps. |x'| is s_v·x'; a law that reads s_v switches at x' = 0 and says so
//! ([`Law::SWITCHES_AT_REST`]), one that reads s_z at z = 0. Laws with a transcendental
//! function (tanh, exp) or sticking are written as [`Term`]s, with their own step limits.
//!
//! **Why one file.** The declaration, the three kinds of number it is evaluated over and the
//! [`Term`] derived from them are one mechanism: a number's operations and the derivation that
//! reads them change together.

use super::jet::{Jet, Lanes};
use super::relation::Relation;
use super::term::piece_sign;
use super::term::{LANE_PARAMS, LaneRows, MAX_ROWS, ParamInfo, Scratch, Side, StateInfo, Term};
#[cfg(doc)]
use crate::integrate::taylor::square_coefficient;
use crate::integrate::taylor::{cauchy_by, square_by};
use std::cell::Cell;
use std::marker::PhantomData;
use std::ops::{Add, Mul, Neg, Sub};

/// The numbers a law is written over: the ring operations, with plain numbers on the right.
pub trait Num:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Mul<f64, Output = Self>
{
}

impl Num for f64 {}

/// What a law reads: the twist x, its rate v = x', the term's state z (0 without one) and the
/// signs of the piece of its law, s_v = sgn x' and s_z = sgn z (each ±1 on a piece, fixed
/// across the switch while the integration runs on that piece).
#[derive(Clone, Copy, Debug)]
pub struct Vars<N> {
    /// The twist x.
    pub x: N,
    /// Its rate x'.
    pub v: N,
    /// The term's internal state z.
    pub z: N,
    /// sgn x' on the piece.
    pub sv: N,
    /// sgn z on the piece.
    pub sz: N,
}

/// A term's law, declared once: its parameters, its torque T and its state's rate r as
/// functions over any [`Num`], and what they read. [`Declared`] derives the [`Term`].
///
/// ```
/// use hdgear::model::law::{Declared, Law, Num, Vars};
/// use hdgear::model::terms::{Domain, ParamInfo, Term};
///
/// // a hardening spring k·x³, declared
/// #[derive(Clone, Copy, Debug, PartialEq)]
/// struct Hardening;
/// impl Law for Hardening {
///     const KIND: &'static str = "hardening";
///     const ABOUT: &'static str = "hardening spring k·x³";
///     const PARAMS: &'static [ParamInfo] = &[ParamInfo {
///         name: "k", symbol: "k", latex: "k", meaning: "cubic stiffness",
///         domain: Domain::NonNegative, default: 1.0, si: "k3·L²/(C·T)",
///     }];
///     const TEXT: &'static str = " + k·x³";
///     const LATEX: &'static str = r" + k x^3";
///     #[inline(always)]
///     fn torque<N: Num>(s: &Vars<N>, p: &[N]) -> N {
///         p[0] * s.x * s.x * s.x
///     }
/// }
/// let t = Declared::<Hardening>::from_values(&[2.0]);
/// assert_eq!(t.torque(0.5, 0.0, 0.0), 0.25);
/// assert_eq!(t.gradient(0.5, 0.0, 0.0), [1.5, 0.0, 0.0]); // derived: 3k·x²
/// assert_eq!(t.param_derivative(0, 0.5, 0.0, 0.0), 0.125); // derived: x³
/// ```
pub trait Law: Copy + std::fmt::Debug + PartialEq + 'static {
    /// The term's kind: its table name in scenario files.
    const KIND: &'static str;
    /// What the term models, in a line.
    const ABOUT: &'static str;
    /// Its parameters, in the order `p` holds them (at most [`MAX_PARAMS`]).
    const PARAMS: &'static [ParamInfo];
    /// The term in the equation's text (`x'` the velocity), with a leading sign.
    const TEXT: &'static str;
    /// The term in LaTeX, with a leading sign.
    const LATEX: &'static str;
    /// Whether the law reads s_v (it is not analytic across x' = 0).
    const SWITCHES_AT_REST: bool = false;
    /// Whether the law reads s_z (it is not analytic across z = 0).
    const SWITCHES_AT_ZERO_STATE: bool = false;
    /// Its internal state, if it has one (then [`Law::rate`] is its equation).
    const STATE: Option<StateInfo> = None;
    /// Its state's equation as text (`z' = …`), for a law with a state.
    const RATE_TEXT: Option<&'static str> = None;
    /// Its state's equation in LaTeX, for a law with a state.
    const RATE_LATEX: Option<&'static str> = None;
    /// Rules between its parameters beyond their domains.
    const RELATIONS: &'static [Relation] = &[];
    /// T(x, x', z) on the piece `s`, with the parameters `p`. Mark it `#[inline(always)]`: a
    /// Taylor pass is straight-line code only when the law is inlined into it (the bench
    /// `law_rows` measured a spring's scalar rows 3.5× slower with the law left out of line,
    /// and as fast as hand-written rows with it inlined).
    fn torque<N: Num>(s: &Vars<N>, p: &[N]) -> N;
    /// z' = r(x, x', z) on the piece `s` (a law with a state; 0, the default, is never read
    /// for a law without one). `#[inline(always)]` as [`Law::torque`].
    fn rate<N: Num>(s: &Vars<N>, _p: &[N]) -> N {
        s.x * 0.0
    }
}

/// The most parameters a declared law has: its lanes carry them with the piece's two signs in
/// [`LANE_PARAMS`] numbers.
pub const MAX_PARAMS: usize = LANE_PARAMS - 2;

/// A number with its derivatives along three directions (forward-mode differentiation): what
/// [`Declared`] evaluates a law over to get its Jacobian and parameter derivatives exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dual {
    /// The value.
    pub value: f64,
    /// Its derivatives along the three seeded directions.
    pub d: [f64; 3],
}

impl Dual {
    /// A number that does not vary.
    pub fn constant(value: f64) -> Dual {
        Dual { value, d: [0.0; 3] }
    }
    /// A number varying along direction `i` at unit rate.
    pub fn seed(value: f64, i: usize) -> Dual {
        let mut d = [0.0; 3];
        d[i] = 1.0;
        Dual { value, d }
    }
}

impl Add for Dual {
    type Output = Dual;
    fn add(self, o: Dual) -> Dual {
        Dual {
            value: self.value + o.value,
            d: [0, 1, 2].map(|i| self.d[i] + o.d[i]),
        }
    }
}
impl Sub for Dual {
    type Output = Dual;
    fn sub(self, o: Dual) -> Dual {
        self + -o
    }
}
impl Neg for Dual {
    type Output = Dual;
    fn neg(self) -> Dual {
        Dual {
            value: -self.value,
            d: self.d.map(|d| -d),
        }
    }
}
impl Mul for Dual {
    type Output = Dual;
    // the product rule: (ab)' = a'b + ab'
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn mul(self, o: Dual) -> Dual {
        Dual {
            value: self.value * o.value,
            d: [0, 1, 2].map(|i| self.d[i] * o.value + self.value * o.d[i]),
        }
    }
}
impl Add<f64> for Dual {
    type Output = Dual;
    fn add(self, c: f64) -> Dual {
        Dual {
            value: self.value + c,
            ..self
        }
    }
}
impl Mul<f64> for Dual {
    type Output = Dual;
    fn mul(self, c: f64) -> Dual {
        Dual {
            value: self.value * c,
            d: self.d.map(|d| d * c),
        }
    }
}
impl Num for Dual {}

/// Where a [`Row`]'s coefficients are: a constant (row 0 only), one of the series x, x', z, or
/// the rows of an intermediate kept in the term's scratch.
#[derive(Clone, Copy, Debug)]
enum Source<J> {
    Constant(J),
    Series(usize),
    Kept(usize),
}

/// The Taylor pass of one order k over a law: the series of x, x' and z (rows 0..=k), the
/// term's scratch rows as cells, and the next scratch row an operation takes. The torque's
/// operations take rows from the first up, the rate's from the last down.
pub struct Tape<'a, J> {
    k: usize,
    series: [&'a [J]; 3],
    rows: &'a [Cell<J>],
    next: Cell<usize>,
    down: bool,
}

impl<'a, J: Jet> Tape<'a, J> {
    /// The pass of order `k` over the series `x`, `v`, `z` keeping its rows in `rows`.
    #[inline(always)]
    fn new(k: usize, [x, v, z]: [&'a [J]; 3], rows: &'a mut [[J; MAX_ROWS]], down: bool) -> Self {
        let rows = Cell::from_mut(rows.as_flattened_mut()).as_slice_of_cells();
        let next = if down { rows.len() / MAX_ROWS } else { 0 };
        Tape {
            k,
            series: [x, v, z],
            rows,
            next: Cell::new(next),
            down,
        }
    }

    /// The law's inputs on this pass, with the piece's signs `sv`, `sz`.
    #[inline(always)]
    fn vars<'t>(&'t self, [sv, sz]: [J; 2]) -> Vars<Row<'t, 'a, J>> {
        let series = |i| Row {
            tape: self,
            source: Source::Series(i),
        };
        Vars {
            x: series(0),
            v: series(1),
            z: series(2),
            sv: self.constant(sv),
            sz: self.constant(sz),
        }
    }

    /// A constant on this pass.
    #[inline(always)]
    fn constant<'t>(&'t self, c: J) -> Row<'t, 'a, J> {
        Row {
            tape: self,
            source: Source::Constant(c),
        }
    }

    /// Keeps `value` as row k of the next intermediate.
    #[inline(always)]
    fn keep<'t>(&'t self, value: J) -> Row<'t, 'a, J> {
        let slot = if self.down {
            let s = self.next.get() - 1;
            self.next.set(s);
            s
        } else {
            let s = self.next.get();
            self.next.set(s + 1);
            s
        };
        self.rows[slot * MAX_ROWS + self.k].set(value);
        Row {
            tape: self,
            source: Source::Kept(slot),
        }
    }
}

/// A law's intermediate on a Taylor pass ([`Tape`]): its operations compute their row k.
#[derive(Clone, Copy)]
pub struct Row<'t, 'a, J> {
    tape: &'t Tape<'a, J>,
    source: Source<J>,
}

/// An intermediate's rows 0..=k, read in place: a series' or kept rows.
enum View<'x, J> {
    Plain(&'x [J]),
    Kept(&'x [Cell<J>]),
}

impl<J: Jet> Row<'_, '_, J> {
    /// Row j (≤ k) of this intermediate.
    #[inline(always)]
    fn at(&self, j: usize) -> J {
        match self.source {
            Source::Constant(c) => {
                if j == 0 {
                    c
                } else {
                    J::splat(0.0)
                }
            }
            Source::Series(i) => self.tape.series[i][j],
            Source::Kept(s) => self.tape.rows[s * MAX_ROWS + j].get(),
        }
    }

    /// Rows 0..=k of a series or a kept intermediate (not of a constant).
    #[inline(always)]
    fn view(&self, k: usize) -> View<'_, J> {
        match self.source {
            Source::Series(i) => View::Plain(&self.tape.series[i][..=k]),
            Source::Kept(s) => View::Kept(&self.tape.rows[s * MAX_ROWS..][..=k]),
            Source::Constant(_) => unreachable!("a constant's product is not a Cauchy sum"),
        }
    }

    /// Row k of the product of two intermediates that are not constants: the Cauchy sum
    /// Σ_{j=0..=k} a_j b_{k−j}, or for a square its symmetric half (as [`square_coefficient`]).
    #[inline(always)]
    fn cauchy_row(&self, o: &Self, k: usize) -> J {
        let same = match (self.source, o.source) {
            (Source::Series(i), Source::Series(j)) | (Source::Kept(i), Source::Kept(j)) => i == j,
            _ => false,
        };
        match (self.view(k), o.view(k)) {
            (View::Plain(a), View::Plain(_)) if same => square_by(|j| a[j], k),
            (View::Kept(a), View::Kept(_)) if same => square_by(|j| a[j].get(), k),
            (View::Plain(a), View::Plain(b)) => cauchy_by(|j| a[j], |j| b[j], k),
            (View::Plain(a), View::Kept(b)) => cauchy_by(|j| a[j], |j| b[j].get(), k),
            (View::Kept(a), View::Plain(b)) => cauchy_by(|j| a[j].get(), |j| b[j], k),
            (View::Kept(a), View::Kept(b)) => cauchy_by(|j| a[j].get(), |j| b[j].get(), k),
        }
    }
}

impl<'t, 'a, J: Jet> Add for Row<'t, 'a, J> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        match (self.source, o.source) {
            (Source::Constant(a), Source::Constant(b)) => self.tape.constant(a + b),
            _ => self.tape.keep(self.at(self.tape.k) + o.at(self.tape.k)),
        }
    }
}
impl<'t, 'a, J: Jet> Sub for Row<'t, 'a, J> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        match (self.source, o.source) {
            (Source::Constant(a), Source::Constant(b)) => self.tape.constant(a - b),
            _ => self.tape.keep(self.at(self.tape.k) - o.at(self.tape.k)),
        }
    }
}
impl<'t, 'a, J: Jet> Neg for Row<'t, 'a, J> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        match self.source {
            Source::Constant(a) => self.tape.constant(-a),
            _ => self.tape.keep(-self.at(self.tape.k)),
        }
    }
}
impl<'t, 'a, J: Jet> Mul for Row<'t, 'a, J> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        let k = self.tape.k;
        match (self.source, o.source) {
            (Source::Constant(a), Source::Constant(b)) => self.tape.constant(a * b),
            (Source::Constant(a), _) => self.tape.keep(a * o.at(k)),
            (_, Source::Constant(b)) => self.tape.keep(self.at(k) * b),
            _ => self.tape.keep(self.cauchy_row(&o, k)),
        }
    }
}
impl<'t, 'a, J: Jet> Add<f64> for Row<'t, 'a, J> {
    type Output = Self;
    #[inline(always)]
    fn add(self, c: f64) -> Self {
        self + self.tape.constant(J::splat(c))
    }
}
impl<'t, 'a, J: Jet> Mul<f64> for Row<'t, 'a, J> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, c: f64) -> Self {
        self * self.tape.constant(J::splat(c))
    }
}
impl<J: Jet> Num for Row<'_, '_, J> {}

/// The term a [`Law`] declares: its parameter values and the piece it is on. Every [`Term`]
/// item is derived from the law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Declared<L> {
    values: [f64; MAX_PARAMS],
    side: Side,
    law: PhantomData<L>,
}

impl<L: Law> Declared<L> {
    /// The parameters as numbers of kind `N` (`wrap` of each value).
    #[inline(always)]
    fn params<N>(&self, wrap: impl Fn(usize, f64) -> N) -> [N; MAX_PARAMS] {
        std::array::from_fn(|i| wrap(i, self.values[i]))
    }

    /// The inputs at (x, v, z) as numbers of kind `N`, the signs from the piece or the state.
    #[inline(always)]
    fn vars<N>(&self, [x, v, z]: [f64; 3], wrap: impl Fn(usize, f64) -> N) -> Vars<N> {
        Vars {
            x: wrap(0, x),
            v: wrap(1, v),
            z: wrap(2, z),
            sv: wrap(3, piece_sign(self.side.v, v)),
            sz: wrap(4, piece_sign(self.side.z, z)),
        }
    }

    /// The Jacobian of `f` (the torque or the rate) at (x, v, z).
    fn gradient_of(&self, f: fn(&Vars<Dual>, &[Dual]) -> Dual, at: [f64; 3]) -> [f64; 3] {
        let s = self.vars(at, |i, u| {
            if i < 3 {
                Dual::seed(u, i)
            } else {
                Dual::constant(u)
            }
        });
        f(&s, &self.params(|_, u| Dual::constant(u))).d
    }

    /// ∂f/∂p_i at (x, v, z).
    fn param_derivative_of(
        &self,
        f: fn(&Vars<Dual>, &[Dual]) -> Dual,
        i: usize,
        at: [f64; 3],
    ) -> f64 {
        let s = self.vars(at, |_, u| Dual::constant(u));
        let p = self.params(|j, u| {
            if j == i {
                Dual::seed(u, 0)
            } else {
                Dual::constant(u)
            }
        });
        f(&s, &p).d[0]
    }

    /// Row k of the torque (or with `rate` of the state's rate) on the series `xvz`, the rate's
    /// rows kept from the scratch's last row down, the torque's from its first up.
    #[inline(always)]
    fn row_of<J: Jet>(
        rate: bool,
        values: &[J],
        signs: [J; 2],
        k: usize,
        xvz: [&[J]; 3],
        rows: &mut [[J; MAX_ROWS]],
    ) -> J {
        let tape = Tape::new(k, xvz, rows, rate);
        let p: [Row<'_, '_, J>; MAX_PARAMS] = std::array::from_fn(|i| tape.constant(values[i]));
        let (s, p) = (tape.vars(signs), &p[..L::PARAMS.len()]);
        if rate {
            L::rate(&s, p)
        } else {
            L::torque(&s, p)
        }
        .at(k)
    }

    /// The piece's signs on lanes: each fixed sign, else the sign of the series' row 0.
    #[inline(always)]
    fn lane_signs(values: &[Lanes], v: &[Lanes], z: &[Lanes]) -> [Lanes; 2] {
        [
            values[MAX_PARAMS].zip(v[0], piece_sign),
            values[MAX_PARAMS + 1].zip(z[0], piece_sign),
        ]
    }
}

impl<L: Law> Term for Declared<L> {
    const KIND: &'static str = L::KIND;
    const ABOUT: &'static str = L::ABOUT;
    const PARAMS: &'static [ParamInfo] = L::PARAMS;
    const RELATIONS: &'static [Relation] = L::RELATIONS;
    const STATE: Option<StateInfo> = L::STATE;
    const SWITCHES_AT_REST: bool = L::SWITCHES_AT_REST;
    const SWITCHES_AT_ZERO_STATE: bool = L::SWITCHES_AT_ZERO_STATE;
    const ON_LANES: bool = true;

    fn from_values(values: &[f64]) -> Self {
        let mut v = [0.0; MAX_PARAMS];
        v[..values.len()].copy_from_slice(values);
        Declared {
            values: v,
            side: Side::default(),
            law: PhantomData,
        }
    }
    fn values(&self) -> &[f64] {
        &self.values[..L::PARAMS.len()]
    }
    #[inline]
    fn torque(&self, x: f64, v: f64, z: f64) -> f64 {
        L::torque(
            &self.vars([x, v, z], |_, u| u),
            &self.values[..L::PARAMS.len()],
        )
    }
    fn gradient(&self, x: f64, v: f64, z: f64) -> [f64; 3] {
        self.gradient_of(L::torque, [x, v, z])
    }
    fn param_derivative(&self, i: usize, x: f64, v: f64, z: f64) -> f64 {
        self.param_derivative_of(L::torque, i, [x, v, z])
    }
    #[inline(always)]
    fn taylor(&self, k: usize, x: &[f64], v: &[f64], z: &[f64], rows: &mut Scratch) -> f64 {
        let signs = [piece_sign(self.side.v, v[0]), piece_sign(self.side.z, z[0])];
        Self::row_of(false, &self.values, signs, k, [x, v, z], &mut rows.0)
    }
    #[inline(always)]
    fn taylor_lanes(
        values: &[Lanes],
        k: usize,
        x: &[Lanes],
        v: &[Lanes],
        z: &[Lanes],
        rows: &mut LaneRows,
    ) -> Option<Lanes> {
        let signs = Self::lane_signs(values, v, z);
        Some(Self::row_of(false, values, signs, k, [x, v, z], rows))
    }
    #[inline(always)]
    fn rate_taylor_lanes(
        values: &[Lanes],
        k: usize,
        x: &[Lanes],
        v: &[Lanes],
        z: &[Lanes],
        rows: &mut LaneRows,
    ) -> Lanes {
        if L::STATE.is_none() {
            return Lanes::splat(0.0);
        }
        let signs = Self::lane_signs(values, v, z);
        Self::row_of(true, values, signs, k, [x, v, z], rows)
    }
    fn lane_values(&self) -> [f64; LANE_PARAMS] {
        let mut out = [0.0; LANE_PARAMS];
        out[..MAX_PARAMS].copy_from_slice(&self.values);
        out[MAX_PARAMS] = self.side.v;
        out[MAX_PARAMS + 1] = self.side.z;
        out
    }
    fn rate(&self, x: f64, v: f64, z: f64) -> f64 {
        if L::STATE.is_none() {
            return 0.0;
        }
        L::rate(
            &self.vars([x, v, z], |_, u| u),
            &self.values[..L::PARAMS.len()],
        )
    }
    fn rate_gradient(&self, x: f64, v: f64, z: f64) -> [f64; 3] {
        if L::STATE.is_none() {
            return [0.0; 3];
        }
        self.gradient_of(L::rate, [x, v, z])
    }
    fn rate_param_derivative(&self, i: usize, x: f64, v: f64, z: f64) -> f64 {
        if L::STATE.is_none() {
            return 0.0;
        }
        self.param_derivative_of(L::rate, i, [x, v, z])
    }
    #[inline(always)]
    fn rate_taylor(&self, k: usize, x: &[f64], v: &[f64], z: &[f64], rows: &mut Scratch) -> f64 {
        if L::STATE.is_none() {
            return 0.0;
        }
        let signs = [piece_sign(self.side.v, v[0]), piece_sign(self.side.z, z[0])];
        Self::row_of(true, &self.values, signs, k, [x, v, z], &mut rows.0)
    }
    fn text(&self) -> String {
        L::TEXT.into()
    }
    fn latex(&self) -> String {
        L::LATEX.into()
    }
    fn rate_text(&self) -> Option<String> {
        L::RATE_TEXT.map(String::from)
    }
    fn rate_latex(&self) -> Option<String> {
        L::RATE_LATEX.map(String::from)
    }
    fn directed(self, side: Side) -> Self {
        Declared { side, ..self }
    }
}
