//! What every batch shares (the study's [`crate::batch`] and the assembled models'
//! [`crate::model::integrate_models`]): the number of lanes, a lane's outcome and the checks of
//! the input.

use super::approx;
use crate::error::Result;
use crate::integrate::Options;

/// Trajectories per batch.
pub const LANES: usize = 16;

/// The outcome of one lane: of the study's model (N = 2), or of a [`crate::model::Model`] with
/// N state components ([`crate::model::integrate_models`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneResult<const N: usize = 2> {
    /// Final state ([x, x'] and the model's internal states).
    pub y: [f64; N],
    /// Steps taken by this lane.
    pub steps: u64,
}

/// The checks every batch entry point makes: usable options, one start and one span per
/// point, valid parameters (`valid`), a step budget that can reach each span's end.
pub(crate) fn check_inputs<P>(
    points: &[P],
    starts: usize,
    spans: &[(f64, f64)],
    tol: &Options,
    valid: impl Fn(&P) -> Result<()>,
) -> Result<()> {
    tol.validate()?;
    if starts != points.len() || spans.len() != points.len() {
        return Err(crate::Error::InvalidInput {
            what: "batch",
            text: format!(
                "{starts} starts and {} spans for {} parameter sets",
                spans.len(),
                points.len()
            ),
            reason: "one start and one span per parameter set".into(),
        });
    }
    for (p, &(_, t_end)) in points.iter().zip(spans) {
        valid(p)?;
        crate::integrate::check_budget(t_end, tol)?;
    }
    Ok(())
}

/// A number a Taylor recurrence runs on: one `f64`, or [`Lanes`] of them, each lane the same
/// arithmetic in the same order as one `f64` (so a recurrence written once over `J: Jet` gives
/// every lane the scalar result to the bit). The step limits are written over it too
/// ([`crate::model::jet::exp_step_limit`]): their comparisons give a [`Jet::Mask`], their
/// branches are [`Jet::select`]s; their logarithms and exponentials ([`Jet::ln`]) are the
/// library's on one `f64` and short polynomials to ~1e-9 on [`Lanes`], so there each lane's limit
/// is its scalar limit to ~1e-9.
pub trait Jet:
    Copy
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Div<Output = Self>
    + std::ops::Neg<Output = Self>
{
    /// Which lanes a comparison holds on: `bool` for one `f64`, [`LaneMask`] for [`Lanes`].
    type Mask: Copy + std::ops::BitAnd<Output = Self::Mask>;
    /// `v` on every lane.
    fn splat(v: f64) -> Self;
    /// `f` on every lane (the library's transcendental functions: row 0 of exp, tanh, …).
    fn map(self, f: impl Fn(f64) -> f64) -> Self;
    /// `f` of each lane of `self` and of `other`.
    fn zip(self, other: Self, f: impl Fn(f64, f64) -> f64) -> Self;
    /// self > other on each lane (false where either is NaN).
    fn gt(self, other: Self) -> Self::Mask;
    /// `a` on the lanes where `mask` holds, `b` on the others.
    fn select(mask: Self::Mask, a: Self, b: Self) -> Self;
    /// Whether `mask` holds on some lane.
    fn any(mask: Self::Mask) -> bool;
    /// |self| on each lane.
    #[inline(always)]
    fn abs(self) -> Self {
        self.map(f64::abs)
    }
    /// [`f64::max`] on each lane.
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        self.zip(other, f64::max)
    }
    /// [`f64::min`] on each lane.
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        self.zip(other, f64::min)
    }
    /// ln on each lane: the library's on one `f64`; on [`Lanes`], to ~1e-9 by the short
    /// polynomials (the exponent from the bits, series of atanh and exp), which vectorise.
    fn ln(self) -> Self;
    /// ln(1 + ·) on each lane, as [`Jet::ln`] (~1e-9 relative on [`Lanes`]).
    fn ln_1p(self) -> Self;
    /// exp on each lane, as [`Jet::ln`] (~1e-9 relative on [`Lanes`]).
    fn exp(self) -> Self;
}

impl Jet for f64 {
    type Mask = bool;
    #[inline(always)]
    fn splat(v: f64) -> Self {
        v
    }
    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        f(self)
    }
    #[inline(always)]
    fn zip(self, other: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        f(self, other)
    }
    #[inline(always)]
    fn gt(self, other: Self) -> bool {
        self > other
    }
    #[inline(always)]
    fn select(mask: bool, a: Self, b: Self) -> Self {
        if mask { a } else { b }
    }
    #[inline(always)]
    fn any(mask: bool) -> bool {
        mask
    }
    #[inline(always)]
    fn ln(self) -> Self {
        f64::ln(self)
    }
    #[inline(always)]
    fn ln_1p(self) -> Self {
        f64::ln_1p(self)
    }
    #[inline(always)]
    fn exp(self) -> Self {
        f64::exp(self)
    }
}

/// [`LANES`] numbers, one per lane, worked on together (the vector unit's registers).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(align(64))]
pub struct Lanes(pub [f64; LANES]);

/// Which of [`LANES`] lanes a comparison holds on ([`Jet::Mask`] of [`Lanes`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LaneMask(pub [bool; LANES]);

impl std::ops::BitAnd for LaneMask {
    type Output = LaneMask;
    #[inline(always)]
    fn bitand(mut self, rhs: LaneMask) -> LaneMask {
        for (a, b) in self.0.iter_mut().zip(rhs.0) {
            *a &= b;
        }
        self
    }
}

// loops over the lanes, not `array::map`: its closure may be compiled apart from the caller's
// vector unit
impl Jet for Lanes {
    type Mask = LaneMask;
    #[inline(always)]
    fn splat(v: f64) -> Self {
        Lanes([v; LANES])
    }
    #[inline(always)]
    fn map(mut self, f: impl Fn(f64) -> f64) -> Self {
        for v in &mut self.0 {
            *v = f(*v);
        }
        self
    }
    #[inline(always)]
    fn zip(mut self, other: Self, f: impl Fn(f64, f64) -> f64) -> Self {
        for (v, o) in self.0.iter_mut().zip(other.0) {
            *v = f(*v, o);
        }
        self
    }
    #[inline(always)]
    fn gt(self, other: Self) -> LaneMask {
        let mut m = [false; LANES];
        for ((m, a), b) in m.iter_mut().zip(self.0).zip(other.0) {
            *m = a > b;
        }
        LaneMask(m)
    }
    #[inline(always)]
    fn select(mask: LaneMask, mut a: Self, b: Self) -> Self {
        for ((a, b), m) in a.0.iter_mut().zip(b.0).zip(mask.0) {
            if !m {
                *a = b;
            }
        }
        a
    }
    #[inline(always)]
    fn any(mask: LaneMask) -> bool {
        mask.0.iter().any(|&m| m)
    }
    #[inline(always)]
    fn ln(self) -> Self {
        self.map(approx::ln::<false>)
    }
    #[inline(always)]
    fn ln_1p(self) -> Self {
        self.map(approx::ln_1p::<false>)
    }
    #[inline(always)]
    fn exp(self) -> Self {
        self.map(approx::exp::<false>)
    }
}

/// The lane-wise operators of [`Lanes`].
macro_rules! lane_ops {
    ($($op:ident $method:ident),*) => {$(
        impl std::ops::$op for Lanes {
            type Output = Lanes;
            #[inline(always)]
            fn $method(self, rhs: Lanes) -> Lanes {
                let mut out = self;
                for (o, r) in out.0.iter_mut().zip(rhs.0) {
                    *o = std::ops::$op::$method(*o, r);
                }
                out
            }
        }
    )*};
}
lane_ops!(Add add, Sub sub, Mul mul, Div div);

impl std::ops::Neg for Lanes {
    type Output = Lanes;
    #[inline(always)]
    fn neg(self) -> Lanes {
        Lanes(self.0.map(|v| -v))
    }
}
