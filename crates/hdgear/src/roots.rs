//! One-dimensional root finding, shared by every part of hdgear that solves for a scalar.
//!
//! | finder | for | used by |
//! |---|---|---|
//! | [`brent`] | a continuous f with a sign change on a bracket | events on the dense output, the burst scan's extrema and jumps |
//! | [`newton_bracketed`] | a monotone f with its derivative, bracketed | the equilibria of the fast subsystem |
//! | [`illinois`] | a continuous f whose trials may fail or carry a result, bracketed | special points on a branch and on a two-parameter curve (a corrector at every trial) |
//! | [`bisect`], [`try_bisect`] | where a predicate (or a sign) switches | spiking-area edges, extremum times of a periodic orbit, catalogue twists, the design margin |
//! | [`bisect_log`] | a predicate's switch on a positive axis, in log scale | the predicted γ boundary, the map's predicted boundary |
//! | [`multisect`] | a predicate's switch, several values per round (a batch) | the boundary curves in a parameter plane |
//! | [`multisect_log`] | the same in log scale | the simulated bursting boundaries |
//!
//! Each finder keeps its bracket and returns a point inside it; none of them extrapolates.

use std::convert::Infallible;

/// A root of a scalar function f on [a, b] with f(a)·f(b) ≤ 0, to a bracket of width `tol`.
/// `fa`, `fb` are f(a), f(b).
///
/// Brent's method (R. P. Brent, *Algorithms for Minimization without Derivatives*, 1973, ch. 4:
/// `zeroin`): inverse quadratic interpolation or the secant through the best points, bisection
/// when they do not shrink the bracket fast enough, and a step of at least half the tolerance, so
/// that once the estimate is within the tolerance the next step crosses the root and closes the
/// bracket. Simple roots take 1–8 evaluations; a root of high multiplicity up to the cap of 200
/// (its bracket shrinks slowly), after which the best estimate is returned.
///
/// ```
/// let r = hdgear::roots::brent(|t| t * t - 2.0, 1.0, -1.0, 2.0, 2.0, 1e-13);
/// assert!((r - 2f64.sqrt()).abs() < 1e-12);
/// ```
pub fn brent(mut f: impl FnMut(f64) -> f64, a: f64, fa: f64, b: f64, fb: f64, tol: f64) -> f64 {
    if fb == 0.0 {
        return b;
    }
    if fa == 0.0 {
        return a;
    }
    // half the tolerance: the bracket's half-width to reach, and the shortest step
    let tol1 = 0.5 * tol;
    // b: the best estimate; c: the end of the bracket across the root from b; a: b's previous
    // value (for the interpolation); d, e: the last two steps
    let (mut a, mut fa, mut b, mut fb) = (a, fa, b, fb);
    let (mut c, mut fc) = (a, fa);
    let (mut d, mut e) = (b - a, b - a);
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

/// The root of a monotone f on [lo, hi] (f(lo), f(hi) of opposite signs or zero) to the last bit:
/// Newton's step with derivative `df` where it stays inside the shrinking bracket, bisection where
/// it does not, and one polishing Newton step once the iterate stops moving.
///
/// ```
/// let r = hdgear::roots::newton_bracketed(|x| x * x * x - 2.0, |x| 3.0 * x * x, 0.0, 2.0);
/// assert!((r - 2f64.cbrt()).abs() <= 2.0 * f64::EPSILON);
/// ```
pub fn newton_bracketed(
    f: impl Fn(f64) -> f64,
    df: impl Fn(f64) -> f64,
    mut lo: f64,
    mut hi: f64,
) -> f64 {
    let (flo, fhi) = (f(lo), f(hi));
    if flo == 0.0 {
        return lo;
    }
    if fhi == 0.0 {
        return hi;
    }
    let increasing = fhi > flo;
    let mut x = 0.5 * (lo + hi);
    for _ in 0..300 {
        let fx = f(x);
        if fx == 0.0 {
            return x;
        }
        // shrink the bracket
        if (fx < 0.0) == increasing {
            lo = x;
        } else {
            hi = x;
        }
        let d = df(x);
        let newton = x - fx / d;
        let next = if d != 0.0 && newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if next == x || (hi - lo) <= 2.0 * f64::EPSILON * x.abs().max(f64::MIN_POSITIVE) {
            return next;
        }
        if (next - x).abs() <= f64::EPSILON * x.abs() {
            // one more Newton step polishes to the last bit
            let fx2 = f(next);
            let d2 = df(next);
            return if d2 != 0.0 { next - fx2 / d2 } else { next };
        }
        x = next;
    }
    x
}

/// The Illinois variant of regula falsi (the secant through the bracket's ends, the value kept
/// at the end that stays twice in a row halved) for a root of f on [a, b] with f(a) = `fa`,
/// f(b) = `fb` of opposite signs, where each trial may fail (`Err`), give up (`Ok(None)`) or
/// return f's value with a result (a corrected point). Stops when `done(value, bracket width)`
/// or after `max` trials; returns the last trial's (x, result), `None` when the first gives up.
///
/// ```
/// let r = hdgear::roots::illinois::<_, ()>((0.0, -2.0), (2.0, 2.0), 60, |v, w| v.abs() < 1e-14 || w < 1e-14, |x| {
///     Ok(Some((x * x - 2.0, x)))
/// })
/// .unwrap()
/// .unwrap();
/// assert!((r.1 - 2f64.sqrt()).abs() < 1e-13);
/// ```
pub fn illinois<T, E>(
    (a, fa): (f64, f64),
    (b, fb): (f64, f64),
    max: usize,
    done: impl Fn(f64, f64) -> bool,
    mut f: impl FnMut(f64) -> Result<Option<(f64, T)>, E>,
) -> Result<Option<(f64, T)>, E> {
    let (mut lo, mut hi, mut flo, mut fhi) = (a, b, fa, fb);
    // which end moved last: -1 the low one, 1 the high one
    let mut side = 0;
    let mut best = None;
    for _ in 0..max {
        let x = (lo * fhi - hi * flo) / (fhi - flo);
        let Some((v, result)) = f(x)? else {
            return Ok(best);
        };
        best = Some((x, result));
        if done(v, (hi - lo).abs()) {
            return Ok(best);
        }
        if (v > 0.0) == (flo > 0.0) {
            (lo, flo) = (x, v);
            if side == -1 {
                fhi *= 0.5;
            }
            side = -1;
        } else {
            (hi, fhi) = (x, v);
            if side == 1 {
                flo *= 0.5;
            }
            side = 1;
        }
    }
    Ok(best)
}

/// Bisection of the switch of a fallible predicate between `a` and `b` (in either order): halves
/// the bracket at most `rounds` times, keeping `a` on the side where `same_as_a` holds, and stops
/// early once `done(a, b)`. Returns the final bracket (a, b).
pub fn try_bisect<E>(
    mut a: f64,
    mut b: f64,
    rounds: usize,
    mut done: impl FnMut(f64, f64) -> bool,
    mut same_as_a: impl FnMut(f64) -> Result<bool, E>,
) -> Result<(f64, f64), E> {
    for _ in 0..rounds {
        if done(a, b) {
            break;
        }
        let m = 0.5 * (a + b);
        if same_as_a(m)? {
            a = m;
        } else {
            b = m;
        }
    }
    Ok((a, b))
}

/// [`try_bisect`] for a predicate that cannot fail.
///
/// ```
/// // where x² crosses 2, to the resolution of f64
/// let (a, b) = hdgear::roots::bisect(1.0, 2.0, 100, hdgear::roots::at_resolution, |x| x * x < 2.0);
/// assert!(a < 2f64.sqrt() && 2f64.sqrt() <= b && b - a <= 2.0 * f64::EPSILON);
/// ```
pub fn bisect(
    a: f64,
    b: f64,
    rounds: usize,
    done: impl FnMut(f64, f64) -> bool,
    mut same_as_a: impl FnMut(f64) -> bool,
) -> (f64, f64) {
    let found = try_bisect::<Infallible>(a, b, rounds, done, |m| Ok(same_as_a(m)));
    match found {
        Ok(bracket) => bracket,
    }
}

/// A stopping rule for [`bisect`]: the bracket's midpoint is no longer strictly inside it (the
/// resolution of f64 is reached).
pub fn at_resolution(a: f64, b: f64) -> bool {
    let m = 0.5 * (a + b);
    m <= a.min(b) || m >= a.max(b)
}

/// A stopping rule for [`bisect`] that never stops early (all rounds are made).
pub fn all_rounds(_: f64, _: f64) -> bool {
    false
}

/// Bisection in log scale for the switch of a predicate that holds at `lo` and not at `hi`
/// (`None` otherwise), to a relative 1e-6.
///
/// ```
/// let s = hdgear::roots::bisect_log(1e-3, 1e3, |x| x < 7.0).unwrap();
/// assert!((s / 7.0 - 1.0).abs() < 1e-6);
/// ```
pub fn bisect_log(lo: f64, hi: f64, holds: impl Fn(f64) -> bool) -> Option<f64> {
    if !holds(lo) || holds(hi) {
        return None;
    }
    let (l, h) = bisect(
        lo.ln(),
        hi.ln(),
        usize::MAX,
        |l, h| h - l <= 1e-6,
        |m| holds(m.exp()),
    );
    Some((0.5 * (l + h)).exp())
}

/// The first pair of neighbours in `xs` (increasing) whose flags go from `lower` (true) to not
/// lower (false).
pub fn first_switch(xs: &[f64], lower: &[bool]) -> Option<(f64, f64)> {
    (1..xs.len())
        .find(|&k| lower[k - 1] && !lower[k])
        .map(|k| (xs[k - 1], xs[k]))
}

/// Narrows a bracket (a, b), a < b, with `lower(a)` and not `lower(b)`, until `done(a, b)` or
/// the resolution of f64: each round cuts it into `n` + 1 equal parts at `n` values evaluated
/// together (`lower` gets them in increasing order) and keeps the part where the flag first
/// switches. Returns the final bracket.
///
/// ```
/// let (a, b) = hdgear::roots::multisect::<()>((0.0, 4.0), 3, |a, b| b - a <= 1e-9, |xs| {
///     Ok(xs.iter().map(|&x| x < 1.5).collect())
/// })
/// .unwrap();
/// assert!(a < 1.5 && 1.5 <= b && b - a <= 1e-9);
/// ```
pub fn multisect<E>(
    (mut a, mut b): (f64, f64),
    n: usize,
    mut done: impl FnMut(f64, f64) -> bool,
    mut lower: impl FnMut(&[f64]) -> Result<Vec<bool>, E>,
) -> Result<(f64, f64), E> {
    while !done(a, b) && !at_resolution(a, b) {
        // the bracket's ends and the round's values between them
        let parts = n as f64 + 1.0;
        let mut xs = vec![a];
        xs.extend((1..=n).map(|j| a + (b - a) * j as f64 / parts));
        xs.push(b);
        let mut sides = vec![true];
        sides.extend(lower(&xs[1..=n])?);
        sides.push(false);
        // (there is one: the ends are on either side)
        let Some(part) = first_switch(&xs, &sides) else {
            break;
        };
        (a, b) = part;
    }
    Ok((a, b))
}

/// [`multisect`] in log scale on a positive axis, until ln b − ln a ≤ `rel_tol`. Returns the
/// final bracket's geometric midpoint.
pub fn multisect_log<E>(
    (a, b): (f64, f64),
    n: usize,
    rel_tol: f64,
    mut lower: impl FnMut(&[f64]) -> Result<Vec<bool>, E>,
) -> Result<f64, E> {
    let (la, lb) = multisect(
        (a.ln(), b.ln()),
        n,
        |la, lb| lb - la <= rel_tol,
        |ls| lower(&ls.iter().map(|l| l.exp()).collect::<Vec<_>>()),
    )?;
    Ok((0.5 * (la + lb)).exp())
}
