//! Zero-crossing events located on the dense output.
//!
//! A [`Detector`] watches a scalar function g(t, y) step by step. Each step is split into
//! [`Detector::subdivisions`] equal parts (default 4) so that two crossings inside one step are not
//! missed as long as they are separated by more than a quarter step; every sign change is then
//! refined on the step's interpolant by Brent's method ([`refine_root`]) until the bracket is
//! shorter than 1e-13·max(1, |t|) (the interpolant itself is accurate to the integration tolerance,
//! so refining further would be pointless).

use super::DenseOutput;

/// Which sign changes count.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// g goes from negative to positive.
    Rising,
    /// g goes from positive to negative.
    Falling,
    /// Either way.
    Either,
}

/// One located crossing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing<const N: usize> {
    /// Time of the crossing.
    pub t: f64,
    /// State at the crossing (from the dense output).
    pub y: [f64; N],
    /// True when g rises through zero.
    pub rising: bool,
}

/// Watches g(t, y) for sign changes across successive steps.
pub struct Detector<G, const N: usize> {
    g: G,
    direction: Direction,
    /// How many equal parts each step is split into before refining (≥ 1).
    pub subdivisions: usize,
    last: Option<(f64, f64)>,
}

impl<G: FnMut(f64, &[f64; N]) -> f64, const N: usize> Detector<G, N> {
    /// A detector of the crossings of `g` in the given direction.
    pub fn new(g: G, direction: Direction) -> Self {
        Detector {
            g,
            direction,
            subdivisions: 4,
            last: None,
        }
    }

    /// Scans one step's dense output and calls `found` for each crossing, in time order.
    pub fn scan(&mut self, dense: &impl DenseOutput<N>, mut found: impl FnMut(Crossing<N>)) {
        let (t0, t1) = (dense.t_start(), dense.t_end());
        let (mut ta, mut ga) = match self.last {
            Some((t, g)) if t == t0 => (t, g),
            _ => (t0, (self.g)(t0, &dense.eval(t0))),
        };
        let m = self.subdivisions.max(1);
        for j in 1..=m {
            let tb = if j == m {
                t1
            } else {
                t0 + (t1 - t0) * j as f64 / m as f64
            };
            let gb = (self.g)(tb, &dense.eval(tb));
            let rising = ga < 0.0 && gb >= 0.0;
            let falling = ga > 0.0 && gb <= 0.0;
            let wanted = match self.direction {
                Direction::Rising => rising,
                Direction::Falling => falling,
                Direction::Either => rising || falling,
            };
            if wanted {
                let g = &mut self.g;
                let t = refine_root(|t| g(t, &dense.eval(t)), ta, ga, tb, gb);
                found(Crossing {
                    t,
                    y: dense.eval(t),
                    rising,
                });
            }
            ta = tb;
            ga = gb;
        }
        self.last = Some((t1, ga));
    }
}

/// A root of a scalar function f on [a, b] with f(a)·f(b) ≤ 0, to a bracket of 1e-13·max(1, |a|)
/// (the interpolants it is used on are accurate to the integration tolerance, so refining further
/// would be pointless), by [`crate::roots::brent`]. `fa`, `fb` are f(a), f(b). On the burst
/// scan's events (extrema of x', zeros of e and e', jumps) Brent's method takes about 5
/// evaluations per root, fewer than the Illinois variant of regula falsi, whose bracket closes
/// only after its stale end is moved.
///
/// ```
/// let r = hdgear::integrate::events::refine_root(|t| t * t - 2.0, 1.0, -1.0, 2.0, 2.0);
/// assert!((r - 2f64.sqrt()).abs() < 1e-12);
/// ```
pub fn refine_root(f: impl FnMut(f64) -> f64, a: f64, fa: f64, b: f64, fb: f64) -> f64 {
    crate::roots::brent(f, a, fa, b, fb, 1e-13 * a.abs().max(1.0))
}
