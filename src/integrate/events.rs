//! Zero-crossing events located on the dense output.
//!
//! A [`Detector`] watches a scalar function g(t, y) step by step. Each step is split into
//! [`Detector::subdivisions`] equal parts (default 4) so that two crossings inside one step are not
//! missed as long as they are separated by more than a quarter step; every sign change is then
//! refined on the 7th-order interpolant by the Illinois variant of regula falsi until the bracket is
//! shorter than 1e-13·max(1, |t|) (the interpolant itself is accurate to the integration tolerance,
//! so refining further would be pointless).

use super::Dense;

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
    pub fn scan(&mut self, dense: &Dense<N>, mut found: impl FnMut(Crossing<N>)) {
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
                let t = self.refine(dense, ta, ga, tb, gb);
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

    /// Illinois regula falsi on [a, b] with g(a)·g(b) ≤ 0.
    fn refine(
        &mut self,
        dense: &Dense<N>,
        mut a: f64,
        mut ga: f64,
        mut b: f64,
        mut gb: f64,
    ) -> f64 {
        if gb == 0.0 {
            return b;
        }
        let tol = 1e-13 * a.abs().max(1.0);
        let mut side = 0i8;
        for _ in 0..100 {
            if (b - a).abs() <= tol {
                break;
            }
            let c = (a * gb - b * ga) / (gb - ga);
            let c = if c.is_finite() && c > a && c < b {
                c
            } else {
                0.5 * (a + b)
            };
            let gc = (self.g)(c, &dense.eval(c));
            if gc == 0.0 {
                return c;
            }
            if (gc < 0.0) == (ga < 0.0) {
                a = c;
                ga = gc;
                if side == -1 {
                    gb *= 0.5;
                }
                side = -1;
            } else {
                b = c;
                gb = gc;
                if side == 1 {
                    ga *= 0.5;
                }
                side = 1;
            }
        }
        if ga.abs() < gb.abs() { a } else { b }
    }
}
