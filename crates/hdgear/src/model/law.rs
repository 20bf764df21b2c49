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
//! The vocabulary is the field operations (+, −, ×, ÷, by numbers too), tanh and exp, over x,
//! x', z, the parameters and the piece's signs s_v = sgn x' and s_z = sgn z ([`Vars`]). |x'| is
//! s_v·x'; a law that reads s_v switches at x' = 0 and says so ([`Law::SWITCHES_AT_REST`]), one
//! that reads s_z at z = 0. A law of the rational operations alone has Taylor series whose size
//! the state's own rows show, and never limits steps. A tanh or an exp can be tiny where a step
//! starts and grow within it, which the state's rows do not show: each carries the scale of the
//! torque it multiplies, and a second pass over the same operations, after the rows, applies
//! its step rule ([`tanh_step_limit`], [`exp_step_limit`]) to the rows its first pass kept.
//! Laws with sticking are written as [`Term`]s, and so, still, are the friction laws: declared,
//! they give the hand-written rows and step limits to the bit (the tests hold them so), but
//! dispatched among a model's terms their passes cost more per step than the hand-written ones.
//!
//! **Why one file.** The declaration, the three kinds of number it is evaluated over and the
//! [`Term`] derived from them are one mechanism: a number's operations and the derivation that
//! reads them change together.

use super::jet::{
    Jet, Lanes, exp_coefficient_by, exp_step_limit, quotient_coefficient_by, tanh_coefficient_by,
    tanh_step_limit,
};
use super::relation::Relation;
use super::term::piece_sign;
use super::term::{LANE_PARAMS, LaneRows, MAX_ROWS, ParamInfo, Scratch, Side, StateInfo, Term};
#[cfg(doc)]
use crate::integrate::taylor::square_coefficient;
use crate::integrate::taylor::{cauchy_by, square_by};
use std::cell::Cell;
use std::marker::PhantomData;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// The numbers a law is written over: the field operations, with plain numbers on the right,
/// and the two transcendental functions friction laws need.
pub trait Num:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Add<f64, Output = Self>
    + Mul<f64, Output = Self>
{
    /// tanh of this number. `scale`, made of the parameters, is the largest torque the factor
    /// multiplies: each step is kept where tanh's series has converged or its change times
    /// `scale` is negligible ([`tanh_step_limit`]). A law that calls it sets
    /// [`Law::LIMITS_STEPS`].
    fn tanh(self, scale: Self) -> Self;
    /// e to the power of this number, `scale` as for [`Num::tanh`] ([`exp_step_limit`]).
    fn exp(self, scale: Self) -> Self;
}

impl Num for f64 {
    #[inline(always)]
    fn tanh(self, _scale: f64) -> f64 {
        f64::tanh(self)
    }
    #[inline(always)]
    fn exp(self, _scale: f64) -> f64 {
        f64::exp(self)
    }
}

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
    /// Whether the law calls [`Num::tanh`] or [`Num::exp`], whose step rules then apply (a law
    /// that calls them without it is refused by an assertion on its first Taylor row).
    const LIMITS_STEPS: bool = false;
    /// Its state at rest at twist `x` with the parameters `p` (as [`Term::state_at_rest`]; 0,
    /// the default, for a virgin memory state).
    fn state_at_rest(_x: f64, _p: &[f64]) -> f64 {
        0.0
    }
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
impl Div for Dual {
    type Output = Dual;
    // the quotient rule: (a/b)' = (a' − (a/b)·b')/b
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, o: Dual) -> Dual {
        let q = self.value / o.value;
        Dual {
            value: q,
            d: [0, 1, 2].map(|i| (self.d[i] - q * o.d[i]) / o.value),
        }
    }
}
impl Num for Dual {
    fn tanh(self, _scale: Dual) -> Dual {
        let t = self.value.tanh();
        Dual {
            value: t,
            d: self.d.map(|d| d * (1.0 - t * t)),
        }
    }
    fn exp(self, _scale: Dual) -> Dual {
        let e = self.value.exp();
        Dual {
            value: e,
            d: self.d.map(|d| d * e),
        }
    }
}

/// Rows a pass can read in place: one of the series x, x', z, or an intermediate kept in the
/// term's scratch.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Base {
    Series(usize),
    Kept(usize),
}

/// What a [`Row`] is: a constant (row 0 only), rows read in place, or an intermediate of which
/// only row k is known. An intermediate is kept (its row k stored in a scratch row) only where an
/// operation reads its earlier rows (a product, a divisor, a tanh's or exp's argument): the same
/// operation kept its earlier rows on the earlier passes.
#[derive(Clone, Copy, Debug)]
enum Source<J> {
    Constant(J),
    Plain(Base),
    Value(J),
}

/// The term's scratch rows as a pass sees them: written on a pass of the rows, read on a pass of
/// the step rules.
#[derive(Clone, Copy)]
enum Store<'a, J> {
    Write(&'a [Cell<J>]),
    Read(&'a [J]),
}

/// A pass of the step rules over the rows a step computed (rows 0..=`order`): each tanh or exp
/// shortens `h` by its rule.
struct Limit<J> {
    order: usize,
    negligible: J,
    h: Cell<J>,
}

/// A pass over a law: of one order k (each operation computes its row k, from the series of x,
/// x' and z and the rows its operations kept in the term's scratch), or of the step rules
/// (`limit`: the same operations replayed, taking the same scratch rows, over the rows a step
/// computed). The torque's operations take scratch rows from the first up, the rate's from the
/// last down.
pub struct Tape<'a, J> {
    k: usize,
    series: [&'a [J]; 3],
    rows: Store<'a, J>,
    next: Cell<usize>,
    down: bool,
    limit: Option<Limit<J>>,
    limits_steps: bool,
}

impl<'a, J: Jet> Tape<'a, J> {
    /// The law's inputs on this pass, with the piece's signs `sv`, `sz`.
    #[inline(always)]
    fn vars<'t>(&'t self, [sv, sz]: [J; 2]) -> Vars<Row<'t, 'a, J>> {
        let series = |i| self.row(Source::Plain(Base::Series(i)));
        Vars {
            x: series(0),
            v: series(1),
            z: series(2),
            sv: self.constant(sv),
            sz: self.constant(sz),
        }
    }

    /// The intermediate at `source` on this pass.
    #[inline(always)]
    fn row<'t>(&'t self, source: Source<J>) -> Row<'t, 'a, J> {
        Row { tape: self, source }
    }

    /// A constant on this pass.
    #[inline(always)]
    fn constant<'t>(&'t self, c: J) -> Row<'t, 'a, J> {
        self.row(Source::Constant(c))
    }

    /// An intermediate of which row k is `value`.
    #[inline(always)]
    fn value<'t>(&'t self, value: J) -> Row<'t, 'a, J> {
        self.row(Source::Value(value))
    }

    /// Takes the next scratch row.
    #[inline(always)]
    fn reserve(&self) -> usize {
        let slot = if self.down {
            self.next.get() - 1
        } else {
            self.next.get()
        };
        self.next.set(if self.down { slot } else { slot + 1 });
        slot
    }

    /// Stores row k of the scratch row `slot` (on a pass of the rows).
    #[inline(always)]
    fn write(&self, slot: usize, value: impl FnOnce() -> J) {
        if let (Store::Write(rows), None) = (self.rows, &self.limit) {
            rows[slot * MAX_ROWS + self.k].set(value());
        }
    }

    /// Keeps `value` as row k of the next scratch row.
    #[inline(always)]
    fn keep(&self, value: impl FnOnce() -> J) -> Base {
        let slot = self.reserve();
        self.write(slot, value);
        Base::Kept(slot)
    }

    /// Row j (≤ k) of the scratch row `slot`.
    #[inline(always)]
    fn kept(&self, slot: usize, j: usize) -> J {
        match self.rows {
            Store::Write(rows) => rows[slot * MAX_ROWS + j].get(),
            Store::Read(rows) => rows[slot * MAX_ROWS + j],
        }
    }

    /// Row j (≤ k) of the rows at `b` (on a pass of the step rules, which has no series, a
    /// series reads as 0: no rule reads one).
    #[inline(always)]
    fn base_at(&self, b: Base, j: usize) -> J {
        match b {
            Base::Series(_) if self.limit.is_some() => J::splat(0.0),
            Base::Series(i) => self.series[i][j],
            Base::Kept(s) => self.kept(s, j),
        }
    }

    /// Rows 0..=`order` of the scratch row `slot` on a pass of the step rules (what a rule
    /// reads).
    #[inline(always)]
    fn read(&self, slot: usize, order: usize) -> &'a [J] {
        match self.rows {
            Store::Read(rows) => &rows[slot * MAX_ROWS..][..=order],
            Store::Write(_) => unreachable!("a pass of the rows applies no step rule"),
        }
    }

    /// Row k of the product of the rows at `a` and `b`: the Cauchy sum Σ_{j=0..=k} a_j b_{k−j},
    /// or for a square its symmetric half (as [`square_coefficient`]).
    #[inline(always)]
    fn cauchy_row(&self, a: Base, b: Base) -> J {
        let k = self.k;
        let at = |b: Base| move |j: usize| self.base_at(b, j);
        match (a, b) {
            (Base::Series(i), Base::Series(j)) if i == j => square_by(|j| self.series[i][j], k),
            (Base::Series(i), Base::Series(j)) => {
                let (a, b) = (&self.series[i][..=k], &self.series[j][..=k]);
                cauchy_by(|j| a[j], |j| b[j], k)
            }
            (Base::Kept(_), Base::Kept(_)) if a == b => square_by(at(a), k),
            _ => cauchy_by(at(a), at(b), k),
        }
    }

    /// The amplitude a step rule reads from `scale` (made of the parameters: a constant).
    #[inline(always)]
    fn amplitude(&self, scale: Source<J>) -> J {
        match scale {
            Source::Constant(a) => a.abs(),
            _ => unreachable!("a step rule's scale is made of the parameters"),
        }
    }
}

/// A law's intermediate on a pass ([`Tape`]): its operations compute their row k.
#[derive(Clone, Copy)]
pub struct Row<'t, 'a, J> {
    tape: &'t Tape<'a, J>,
    source: Source<J>,
}

impl<J: Jet> Row<'_, '_, J> {
    /// Row k of this intermediate.
    #[inline(always)]
    fn now(&self) -> J {
        let k = self.tape.k;
        match self.source {
            Source::Constant(c) => {
                if k == 0 {
                    c
                } else {
                    J::splat(0.0)
                }
            }
            Source::Plain(b) => self.tape.base_at(b, k),
            Source::Value(v) => v,
        }
    }

    /// The rows of this intermediate, which is not a constant, in place: row k of one that is
    /// only a value is kept.
    #[inline(always)]
    fn base(&self) -> Base {
        match self.source {
            Source::Plain(b) => b,
            Source::Value(v) => self.tape.keep(|| v),
            Source::Constant(_) => unreachable!("a constant's product is a scaling"),
        }
    }

    /// The rows of this intermediate in the scratch (a series' row k is copied there): what a
    /// step rule reads.
    #[inline(always)]
    fn scratch(&self) -> usize {
        match self.source {
            Source::Plain(Base::Kept(s)) => s,
            _ => {
                let v = self.now();
                match self.tape.keep(|| v) {
                    Base::Kept(s) => s,
                    Base::Series(_) => unreachable!("keep returns a scratch row"),
                }
            }
        }
    }

    /// `f` of this intermediate's and `o`'s row k.
    #[inline(always)]
    fn combine(self, o: Self, f: impl Fn(J, J) -> J) -> Self {
        match (self.source, o.source) {
            (Source::Constant(a), Source::Constant(b)) => self.tape.constant(f(a, b)),
            _ => self.tape.value(f(self.now(), o.now())),
        }
    }
}

impl<'t, 'a, J: Jet> Add for Row<'t, 'a, J> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        self.combine(o, |a, b| a + b)
    }
}
impl<'t, 'a, J: Jet> Sub for Row<'t, 'a, J> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        self.combine(o, |a, b| a - b)
    }
}
impl<'t, 'a, J: Jet> Neg for Row<'t, 'a, J> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        match self.source {
            Source::Constant(a) => self.tape.constant(-a),
            _ => self.tape.value(-self.now()),
        }
    }
}
impl<'t, 'a, J: Jet> Mul for Row<'t, 'a, J> {
    type Output = Self;
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        let tape = self.tape;
        // a constant scales every row
        match (self.source, o.source) {
            (Source::Constant(a), Source::Constant(b)) => tape.constant(a * b),
            (Source::Constant(c), _) => tape.value(c * o.now()),
            (_, Source::Constant(c)) => tape.value(self.now() * c),
            _ => {
                let (a, b) = (self.base(), o.base());
                if tape.limit.is_some() {
                    return tape.value(J::splat(0.0));
                }
                tape.value(tape.cauchy_row(a, b))
            }
        }
    }
}
impl<'t, 'a, J: Jet> Div for Row<'t, 'a, J> {
    type Output = Self;
    /// By a constant, a scaling by its reciprocal; by an intermediate d, the quotient's row k from
    /// d's rows and its own (kept): q_k = (n_k − Σ_{j=1..k} d_j q_{k−j})/d₀.
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        let tape = self.tape;
        match o.source {
            Source::Constant(c) => self * tape.constant(J::splat(1.0) / c),
            _ => {
                let (n, d) = (self.now(), o.base());
                let q = tape.reserve();
                tape.write(q, || {
                    quotient_coefficient_by(n, |j| tape.base_at(d, j), |j| tape.kept(q, j), tape.k)
                });
                tape.row(Source::Plain(Base::Kept(q)))
            }
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
impl<J: Jet> Num for Row<'_, '_, J> {
    /// tanh u by its recurrence from u's rows (kept) and tanh²'s (kept beside tanh's); on a pass of
    /// the step rules, [`tanh_step_limit`] on those rows.
    #[inline(always)]
    fn tanh(self, scale: Self) -> Self {
        let tape = self.tape;
        if let Source::Constant(c) = self.source {
            return tape.constant(c.map(f64::tanh));
        }
        assert!(
            tape.limits_steps,
            "a law that calls tanh sets Law::LIMITS_STEPS"
        );
        let u = self.scratch();
        let (t, sq) = (tape.reserve(), tape.reserve());
        if let Some(l) = &tape.limit {
            let o = l.order;
            let (u, sq) = (tape.read(u, o), tape.read(sq, o));
            let a = tape.amplitude(scale.source);
            l.h.set(tanh_step_limit(u, sq, o, l.h.get(), a, l.negligible));
        } else {
            let k = tape.k;
            tape.write(t, || {
                tanh_coefficient_by(|j| tape.kept(u, j), |j| tape.kept(sq, j), k)
            });
            tape.write(sq, || square_by(|j| tape.kept(t, j), k));
        }
        tape.row(Source::Plain(Base::Kept(t)))
    }
    /// e^u by its recurrence from u's rows (kept) and its own (kept); on a pass of the step rules,
    /// [`exp_step_limit`] on those rows.
    #[inline(always)]
    fn exp(self, scale: Self) -> Self {
        let tape = self.tape;
        if let Source::Constant(c) = self.source {
            return tape.constant(c.map(f64::exp));
        }
        assert!(
            tape.limits_steps,
            "a law that calls exp sets Law::LIMITS_STEPS"
        );
        let u = self.scratch();
        let e = tape.reserve();
        if let Some(l) = &tape.limit {
            let o = l.order;
            let (u, e) = (tape.read(u, o), tape.read(e, o));
            let a = tape.amplitude(scale.source);
            l.h.set(exp_step_limit(u, e, o, l.h.get(), a, l.negligible));
        } else {
            let k = tape.k;
            tape.write(e, || {
                exp_coefficient_by(|j| tape.kept(u, j), |j| tape.kept(e, j), k)
            });
        }
        tape.row(Source::Plain(Base::Kept(e)))
    }
}

/// The term a [`Law`] declares: its parameter values and the piece it is on. Every [`Term`]
/// item is derived from the law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Declared<L> {
    values: [f64; MAX_PARAMS],
    side: Side,
    law: PhantomData<L>,
}

/// The law with its parameters' defaults.
impl<L: Law> Default for Declared<L> {
    fn default() -> Self {
        Declared {
            values: std::array::from_fn(|i| L::PARAMS.get(i).map_or(0.0, |p| p.default)),
            side: Side::default(),
            law: PhantomData,
        }
    }
}

impl<L: Law> Declared<L> {
    /// Its `N` parameter values as an array (`N` the law's count of parameters).
    pub fn array<const N: usize>(&self) -> [f64; N] {
        debug_assert_eq!(
            N,
            L::PARAMS.len(),
            "{} has {} parameters",
            L::KIND,
            L::PARAMS.len()
        );
        std::array::from_fn(|i| self.values[i])
    }

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
        let first = if rate { rows.len() } else { 0 };
        let tape = Tape {
            k,
            series: xvz,
            rows: Store::Write(Cell::from_mut(rows.as_flattened_mut()).as_slice_of_cells()),
            next: Cell::new(first),
            down: rate,
            limit: None,
            limits_steps: L::LIMITS_STEPS,
        };
        Self::replay(&tape, values, signs, rate).now()
    }

    /// The torque (or with `rate` the state's rate) over `tape`'s numbers.
    #[inline(always)]
    fn replay<'t, 'a, J: Jet>(
        tape: &'t Tape<'a, J>,
        values: &[J],
        signs: [J; 2],
        rate: bool,
    ) -> Row<'t, 'a, J> {
        let p: [Row<'_, '_, J>; MAX_PARAMS] = std::array::from_fn(|i| tape.constant(values[i]));
        let (s, p) = (tape.vars(signs), &p[..L::PARAMS.len()]);
        if rate {
            L::rate(&s, p)
        } else {
            L::torque(&s, p)
        }
    }

    /// The longest step, at most `h`, that the step rules of the law's tanh and exp allow over
    /// the rows 0..=`order` a step computed in `rows` (the torque's and the state's rate's).
    #[inline(always)]
    fn limit_of<J: Jet>(
        values: &[J],
        rows: &[[J; MAX_ROWS]],
        order: usize,
        h: J,
        negligible: J,
    ) -> J {
        let mut h = h;
        for rate in [false, true] {
            if rate && L::STATE.is_none() {
                break;
            }
            let tape = Tape {
                k: order,
                series: [&[]; 3],
                rows: Store::Read(rows.as_flattened()),
                next: Cell::new(if rate { rows.len() } else { 0 }),
                down: rate,
                limit: Some(Limit {
                    order,
                    negligible,
                    h: Cell::new(h),
                }),
                limits_steps: L::LIMITS_STEPS,
            };
            // the signs pick no scratch rows
            Self::replay(&tape, values, [J::splat(1.0); 2], rate);
            h = tape.limit.map_or(h, |l| l.h.get());
        }
        h
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
    const LIMITS_STEPS: bool = L::LIMITS_STEPS;
    fn step_limit(&self, rows: &Scratch, order: usize, h: f64, negligible: f64) -> f64 {
        Self::limit_of(&self.values, &rows.0, order, h, negligible)
    }
    #[inline(always)]
    fn step_limit_lanes(
        values: &[Lanes],
        rows: &LaneRows,
        order: usize,
        h: Lanes,
        negligible: Lanes,
    ) -> Lanes {
        Self::limit_of(values, rows, order, h, negligible)
    }

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
    fn state_at_rest(&self, x: f64) -> f64 {
        L::state_at_rest(x, self.values())
    }
}
