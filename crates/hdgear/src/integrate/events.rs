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
/// would be pointless). `fa`, `fb` are f(a), f(b).
///
/// Brent's method (R. P. Brent, *Algorithms for Minimization without Derivatives*, 1973, ch. 4:
/// `zeroin`): inverse quadratic interpolation or the secant through the best points, bisection
/// when they do not shrink the bracket fast enough, and a step of at least half the tolerance, so
/// that once the estimate is within the tolerance the next step crosses the root and closes the
/// bracket. On the burst scan's events (extrema of x', zeros of e and e', jumps; 929k roots in a
/// 100 × 100 (γ, δ) map) it takes 4.9 evaluations of f per root against 6.7 for the Illinois
/// variant of regula falsi used before, whose bracket closes only after its stale end is moved
/// (and which stopped at its cap of 100 evaluations 1e-4 away from the ninefold root of
/// (t − 0.123)⁹, where this one takes 120).
///
/// ```
/// let r = hdgear::integrate::events::refine_root(|t| t * t - 2.0, 1.0, -1.0, 2.0, 2.0);
/// assert!((r - 2f64.sqrt()).abs() < 1e-12);
/// ```
pub fn refine_root(mut f: impl FnMut(f64) -> f64, a: f64, fa: f64, b: f64, fb: f64) -> f64 {
    if fb == 0.0 {
        return b;
    }
    if fa == 0.0 {
        return a;
    }
    let tol = 1e-13 * a.abs().max(1.0);
    // half the tolerance: the bracket's half-width to reach, and the shortest step
    let tol1 = 0.5 * tol;
    // b: the best estimate; c: the end of the bracket across the root from b; a: b's previous
    // value (for the interpolation); d, e: the last two steps
    let (mut a, mut fa, mut b, mut fb) = (a, fa, b, fb);
    let (mut c, mut fc) = (a, fa);
    let (mut d, mut e) = (b - a, b - a);
    // (simple roots take 1–8 evaluations; a triple root 128, whose bracket shrinks slowly)
    for _ in 0..200 {
        if (fb > 0.0) == (fc > 0.0) {
            (c, fc) = (a, fa);
            (d, e) = (b - a, b - a);
        }
        if fc.abs() < fb.abs() {
            (a, fa) = (b, fb);
            (b, fb) = (c, fc);
            (c, fc) = (a, fa);
        }
        let xm = 0.5 * (c - b);
        if xm.abs() <= tol1 || fb == 0.0 {
            return b;
        }
        if e.abs() >= tol1 && fa.abs() > fb.abs() {
            let s = fb / fa;
            let (mut p, mut q) = if a == c {
                (2.0 * xm * s, 1.0 - s)
            } else {
                let (q0, r) = (fa / fc, fb / fc);
                (
                    s * (2.0 * xm * q0 * (q0 - r) - (b - a) * (r - 1.0)),
                    (q0 - 1.0) * (r - 1.0) * (s - 1.0),
                )
            };
            if p > 0.0 {
                q = -q;
            } else {
                p = -p;
            }
            if 2.0 * p < (3.0 * xm * q - (tol1 * q).abs()).min((e * q).abs()) {
                (e, d) = (d, p / q);
            } else {
                (d, e) = (xm, xm);
            }
        } else {
            (d, e) = (xm, xm);
        }
        (a, fa) = (b, fb);
        b += if d.abs() > tol1 { d } else { tol1.copysign(xm) };
        fb = f(b);
    }
    b
}
