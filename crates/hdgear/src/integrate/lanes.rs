//! What every batch shares (the study's [`crate::batch`] and the assembled models'
//! [`crate::model::integrate_models`]): the number of lanes, a lane's outcome and the checks of
//! the input.

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
/// every lane the scalar result to the bit).
pub trait Jet:
    Copy
    + std::ops::Add<Output = Self>
    + std::ops::Sub<Output = Self>
    + std::ops::Mul<Output = Self>
    + std::ops::Div<Output = Self>
    + std::ops::Neg<Output = Self>
{
    /// `v` on every lane.
    fn splat(v: f64) -> Self;
    /// `f` on every lane (the library's transcendental functions: row 0 of exp, tanh, …).
    fn map(self, f: impl Fn(f64) -> f64) -> Self;
}

impl Jet for f64 {
    #[inline(always)]
    fn splat(v: f64) -> Self {
        v
    }
    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        f(self)
    }
}

/// [`LANES`] numbers, one per lane, worked on together (the vector unit's registers).
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(align(64))]
pub struct Lanes(pub [f64; LANES]);

impl Jet for Lanes {
    #[inline(always)]
    fn splat(v: f64) -> Self {
        Lanes([v; LANES])
    }
    #[inline(always)]
    fn map(self, f: impl Fn(f64) -> f64) -> Self {
        Lanes(self.0.map(f))
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
