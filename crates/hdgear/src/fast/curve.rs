//! The equilibrium curve {(a, x): F(x, a) = 0} over an a-range, sampled by x.
//!
//! The curve is a graph over x: a(x) = (g(x) − μ)/δ (guide: the fast subsystem). Every point is therefore computed
//! *exactly* from its x, and steep parts (where x changes fast with a) are resolved for free. The
//! x values are spread uniformly in arc length of the curve drawn in the box a-range × x-extent
//! (both normalised to 1), so flat and steep parts get points alike.

use super::StaticCurve;
use super::equilibria::EqType;
use crate::error::{Error, Result};
use serde::Serialize;

/// Which branch of the equilibrium curve a point lies on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CurveBranch {
    /// No folds (γ ≥ 1/(3α)): the curve is one monotone branch.
    Single,
    /// x < x− (the lower fold abscissa): stable.
    Lower,
    /// x− < x < x+: saddles.
    Middle,
    /// x > x+: stable.
    Upper,
}

impl CurveBranch {
    /// The branch of abscissa x.
    pub fn of<C: StaticCurve>(p: &C, x: f64) -> CurveBranch {
        match p.fold_band() {
            None => CurveBranch::Single,
            Some((xm, xp)) => {
                if x < xm {
                    CurveBranch::Lower
                } else if x > xp {
                    CurveBranch::Upper
                } else {
                    CurveBranch::Middle
                }
            }
        }
    }
}

/// One point of the equilibrium curve: the columns of `hdgear equilibria`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, crate::output::Record)]
pub struct CurvePoint {
    /// Slow variable.
    pub a: f64,
    /// Equilibrium position.
    pub x: f64,
    /// dx/da = δ / g'(x) (±inf at a fold).
    pub slope: f64,
    /// g'(x) = 3αx² − 2x + γ.
    pub gprime: f64,
    /// Real part of the first eigenvalue (the larger).
    pub re1: f64,
    /// Imaginary part of the first eigenvalue.
    pub im1: f64,
    /// Real part of the second eigenvalue.
    pub re2: f64,
    /// Imaginary part of the second eigenvalue.
    pub im2: f64,
    /// Linear type.
    #[serde(rename = "type")]
    pub kind: EqType,
    /// Branch.
    pub branch: CurveBranch,
}

impl CurvePoint {
    /// The curve point with abscissa x (a computed from x; requires δ > 0).
    pub fn at_x<C: StaticCurve>(p: &C, x: f64) -> CurvePoint {
        let a = p.a_at(x);
        Self::at(p, a, x)
    }

    fn at<C: StaticCurve>(p: &C, a: f64, x: f64) -> CurvePoint {
        let gp = p.g_prime(x);
        let [(re1, im1), (re2, im2)] = p.eigenvalues(x);
        CurvePoint {
            a,
            x,
            slope: if p.delta() == 0.0 {
                0.0
            } else {
                p.delta() / gp
            },
            gprime: gp,
            re1,
            im1,
            re2,
            im2,
            kind: p.kind(x),
            branch: CurveBranch::of(p, x),
        }
    }
}

/// The widest a-range analysed: a = sin ωτ only covers [−1, 1], and a range up to ±1e6 shows
/// the curve beyond it; further out the cubic's roots overflow.
pub const A_RANGE_LIMIT: f64 = 1e6;

/// Checks an a-range: finite, a_min < a_max, within ±[`A_RANGE_LIMIT`], and wider than
/// rounding (1e-12 relative).
pub fn check_a_range(a_range: (f64, f64)) -> Result<()> {
    let (a0, a1) = a_range;
    let bad = |reason: &str| {
        Err(Error::InvalidInput {
            what: "a-range",
            text: format!("{a0:?}:{a1:?}"),
            reason: reason.into(),
        })
    };
    if !(a0.is_finite() && a1.is_finite() && a0 < a1) {
        return bad("needs finite A0 < A1");
    }
    if a0 < -A_RANGE_LIMIT || a1 > A_RANGE_LIMIT {
        return bad("must lie within [-1e6, 1e6] (a = sin(omega t) covers [-1, 1])");
    }
    if a1 - a0 < 1e-12 * a0.abs().max(a1.abs()).max(1.0) {
        return bad("narrower than 1e-12 (relative): below the rounding level of a");
    }
    Ok(())
}

/// The x-intervals on which a(x) ∈ [a0, a1], in increasing x (δ > 0).
pub fn x_intervals<C: StaticCurve>(p: &C, a_range: (f64, f64)) -> Vec<(f64, f64)> {
    let (a0, a1) = a_range;
    let mut ends: Vec<f64> = p.roots(a0).into_iter().chain(p.roots(a1)).collect();
    ends.sort_by(f64::total_cmp);
    ends.dedup();
    let a_of = |x: f64| p.a_at(x);
    ends.windows(2)
        .filter(|w| {
            let am = a_of(0.5 * (w[0] + w[1]));
            am >= a0 && am <= a1
        })
        .map(|w| (w[0], w[1]))
        .collect()
}

/// The most points a curve may have (10⁷: far beyond any figure's resolution; the points take
/// 0.5 GB).
pub const MAX_CURVE_POINTS: usize = 10_000_000;

/// Samples the curve over `a_range` with `points` points (≥ 2), uniformly in normalised arc
/// length. With δ = 0 the equilibria do not depend on a: the curve is horizontal lines, sampled
/// uniformly in a.
///
/// ```
/// let p = hdgear::Params { gamma: 1.0, ..Default::default() };
/// let c = hdgear::fast::curve(&p, hdgear::fast::A_RANGE, 1000).unwrap();
/// assert_eq!(c.len(), 1000);
/// assert!(c.iter().all(|q| q.kind.is_stable()));
/// ```
pub fn curve<C: StaticCurve>(p: &C, a_range: (f64, f64), points: usize) -> Result<Vec<CurvePoint>> {
    p.check()?;
    check_a_range(a_range)?;
    if !(2..=MAX_CURVE_POINTS).contains(&points) {
        return Err(Error::InvalidOption {
            name: "points",
            value: points as f64,
            reason: "must be ≥ 2 and at most 1e7",
        });
    }
    let (a0, a1) = a_range;
    if p.delta() == 0.0 {
        return Ok(flat_curve(p, a_range, points));
    }
    let intervals = x_intervals(p, a_range);
    if intervals.is_empty() {
        return Err(Error::InvalidInput {
            what: "a-range",
            text: format!("{a0:?}:{a1:?}"),
            reason: "too narrow: the equilibria at its two ends coincide to rounding".into(),
        });
    }
    let polylines = arc_polylines(p, a_range, &intervals, points);
    let counts = split_points(&polylines, points);
    let mut out = Vec::with_capacity(points);
    for (line, n) in polylines.iter().zip(counts) {
        sample_polyline(p, a_range, line, n, &mut out);
    }
    Ok(out)
}

/// With δ = 0 the equilibria do not depend on a: horizontal lines, sampled uniformly in a.
fn flat_curve<C: StaticCurve>(p: &C, (a0, a1): (f64, f64), points: usize) -> Vec<CurvePoint> {
    let roots = p.roots(a0);
    let per = points.div_ceil(roots.len());
    let mut out = Vec::with_capacity(points);
    for r in &roots {
        for k in 0..per {
            let a = a0 + (a1 - a0) * k as f64 / (per - 1).max(1) as f64;
            out.push(CurvePoint::at(p, a, *r));
        }
    }
    out.truncate(points);
    out
}

/// A polyline along the curve: (x, cumulative normalised arc length).
type Polyline = (Vec<f64>, Vec<f64>);

/// A fine polyline per x-interval, 4 sub-samples per output point.
fn arc_polylines<C: StaticCurve>(
    p: &C,
    a_range: (f64, f64),
    intervals: &[(f64, f64)],
    points: usize,
) -> Vec<Polyline> {
    let (sa, sx) = (a_range.1 - a_range.0, super::x_extent(p, a_range));
    let a_of = |x: f64| p.a_at(x);
    let fine = (4 * points).max(64);
    let total_x: f64 = intervals.iter().map(|i| i.1 - i.0).sum();
    let mut polylines = Vec::new();
    for &(xl, xr) in intervals {
        let m = ((fine as f64 * (xr - xl) / total_x).ceil() as usize).max(8);
        let mut xs = Vec::with_capacity(m + 1);
        let mut ss = Vec::with_capacity(m + 1);
        let (mut s, mut prev) = (0.0, (a_of(xl), xl));
        for j in 0..=m {
            let x = if j == m {
                xr
            } else {
                xl + (xr - xl) * j as f64 / m as f64
            };
            let q = (a_of(x), x);
            s += (((q.0 - prev.0) / sa).powi(2) + ((q.1 - prev.1) / sx).powi(2)).sqrt();
            xs.push(x);
            ss.push(s);
            prev = q;
        }
        polylines.push((xs, ss));
    }
    polylines
}

fn arc_length(line: &Polyline) -> f64 {
    line.1.last().copied().unwrap_or(0.0)
}

/// Output points per polyline ∝ its arc length, at least 2 each, `points` in all.
fn split_points(polylines: &[Polyline], points: usize) -> Vec<usize> {
    let total: f64 = polylines.iter().map(arc_length).sum();
    let mut counts: Vec<usize> = polylines
        .iter()
        .map(|l| ((points as f64 * arc_length(l) / total).round() as usize).max(2))
        .collect();
    let largest = |c: &[usize]| (0..c.len()).max_by_key(|&i| c[i]).unwrap_or(0);
    while counts.iter().sum::<usize>() > points {
        let i = largest(&counts);
        counts[i] -= 1;
    }
    while counts.iter().sum::<usize>() < points {
        let i = largest(&counts);
        counts[i] += 1;
    }
    counts
}

/// `n` points spread uniformly in arc length along one polyline.
fn sample_polyline<C: StaticCurve>(
    p: &C,
    (a0, a1): (f64, f64),
    (xs, ss): &Polyline,
    n: usize,
    out: &mut Vec<CurvePoint>,
) {
    let len = ss.last().copied().unwrap_or(0.0);
    let (first, last) = (xs[0], xs[xs.len() - 1]);
    let mut j = 0;
    for k in 0..n {
        let target = len * k as f64 / (n - 1) as f64;
        while j + 1 < ss.len() - 1 && ss[j + 1] < target {
            j += 1;
        }
        let x = if k == 0 {
            first
        } else if k == n - 1 {
            last
        } else {
            let (s0, s1) = (ss[j], ss[j + 1]);
            let w = if s1 > s0 {
                (target - s0) / (s1 - s0)
            } else {
                0.0
            };
            xs[j] + w.clamp(0.0, 1.0) * (xs[j + 1] - xs[j])
        };
        let mut pt = CurvePoint::at_x(p, x);
        // Interval ends are the exact roots at a0 or a1, and a(x) stays within [a0, a1]
        // inside an interval: remove the rounding noise of evaluating a(x).
        if k == 0 || k == n - 1 {
            pt.a = if (pt.a - a0).abs() < (pt.a - a1).abs() {
                a0
            } else {
                a1
            };
        } else {
            pt.a = pt.a.clamp(a0, a1);
        }
        out.push(pt);
    }
}
