//! Exact features of the fast subsystem over a range of the slow variable: equilibrium counts,
//! folds, the cusp, the steepest point and largest slope, the impossibility of Hopf
//! bifurcations, and the spiking and quiescent areas.
//!
//! Everything except the spiking areas is a closed form. The spiking areas use the forcing-rate
//! criterion of the prediction (`super::predict`, κ > `FORCING_RATE_THRESHOLD` on the focus part
//! of the curve); their boundaries are located by bisection on the exact curve a(x) to 1e-12 in x.

use super::curve::{check_a_range, x_intervals};
use super::equilibria::{Fold, fold_abscissae, folds};
use super::predict::{
    FORCING_RATE_THRESHOLD, Prediction, focus_pieces, forcing_rate, predict,
    predicted_gamma_boundary,
};
use crate::error::{Error, Result};
use crate::params::{Param, Params};
use serde::Serialize;

/// A point (a, x) of the (a, x) plane.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Point {
    /// Slow variable.
    pub a: f64,
    /// Position.
    pub x: f64,
}

/// The cusp point of the (a, γ) bifurcation set: γ = 1/(3α), x = 1/(3α), where both folds meet.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Cusp {
    /// γ at the cusp, 1/(3α).
    pub gamma: f64,
    /// a at the cusp (with the other parameters as given).
    pub a: f64,
    /// x at the cusp, 1/(3α).
    pub x: f64,
}

/// A slope value with where it is attained.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Slope {
    /// |dx/da|; +inf at a fold (written as `null` in JSON).
    pub value: f64,
    /// a where it is attained.
    pub a: f64,
    /// x where it is attained.
    pub x: f64,
}

/// An interval [a_min, a_max] of the slow variable.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Interval {
    /// Lower end.
    pub a_min: f64,
    /// Upper end.
    pub a_max: f64,
}

/// The fast subsystem's regime, from γ against 1/(3α).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Regime {
    /// γ > 1/(3α): one equilibrium for every a, a monotone curve.
    Monotone,
    /// γ = 1/(3α): the cusp.
    Cusp,
    /// γ < 1/(3α): two folds, three equilibria between them.
    FoldHysteresis,
}

impl Regime {
    /// The kebab-case name.
    pub fn name(self) -> &'static str {
        match self {
            Regime::Monotone => "monotone",
            Regime::Cusp => "cusp",
            Regime::FoldHysteresis => "fold-hysteresis",
        }
    }
}

/// Why no Hopf bifurcation can occur, as derived.
pub const NO_HOPF_REASON: &str = "the Jacobian [[0, 1], [-g'(x), -1]] has trace -1 at every \
equilibrium for every parameter value; a Hopf bifurcation needs a pair of purely imaginary \
eigenvalues, i.e. trace 0, so none can occur";

/// Summary of the equilibria over the a-range.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct EquilibriaSummary {
    /// Fewest distinct equilibria at any a in the range.
    pub min_count: usize,
    /// Most distinct equilibria at any a in the range.
    pub max_count: usize,
    /// Every equilibrium at every a in the range is asymptotically stable.
    pub stable_everywhere: bool,
    /// Largest |dx/da| over the range (on any branch), and where.
    pub max_slope: Slope,
    /// dx/da at a = 0 of the stable equilibrium the default start uses (null if 0 is out of range).
    pub slope_at_a0: Option<f64>,
    /// All fold points of the fast subsystem (empty for γ ≥ 1/(3α)).
    pub folds: Vec<Fold>,
    /// Always false: see `hopf_reason`.
    pub hopf_possible: bool,
    /// The derivation.
    pub hopf_reason: &'static str,
    /// The spiking areas (a-intervals), merged and sorted: where the prediction's forcing rate κ
    /// exceeds its threshold on the focus part of the traversed curve, and each fold in range
    /// (a zero-width interval at the fold's a, where the jump starts).
    pub spiking_areas: Vec<Interval>,
    /// The rest of the range.
    pub quiescent_areas: Vec<Interval>,
    /// The prediction from the curve alone (over a ∈ [−1, 1], the range a = sin ωτ traverses).
    pub prediction: Prediction,
    /// The predicted γ boundary with the other parameters fixed: bursting predicted below it
    /// (`None` when no switch exists between the cusp and 10⁶).
    pub predicted_gamma_boundary: Option<f64>,
    /// The slowest relaxation on the path the state follows over a ∈ [−1, 1], and where: the
    /// fast-slow domain needs ω below its rate (`burst::fast_slow_domain`).
    pub slowest_relaxation: super::SlowestRelaxation,
}

/// The analysis of the fast subsystem: the document `hdgear analyze --json` prints.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Analysis {
    /// The parameters.
    pub params: Params,
    /// The analysed range of the slow variable.
    pub a_range: [f64; 2],
    /// 1/(3α): folds exist iff γ is below it.
    pub critical_gamma: f64,
    /// γ − 1/(3α).
    pub gamma_margin: f64,
    /// `monotone` (γ > 1/(3α)), `cusp` (equal) or `fold-hysteresis` (below).
    pub regime: Regime,
    /// The cusp point.
    pub cusp: Cusp,
    /// The steepest point of the whole curve when it is monotone: x = 1/(3α), slope
    /// δ/(γ − 1/(3α)) (null in the fold regime, where the slope is infinite at the folds).
    pub steepest_point: Option<Slope>,
    /// Equilibria over the range.
    pub equilibria: EquilibriaSummary,
}

fn a_of(p: &Params, x: f64) -> f64 {
    p.a_at(x)
}

/// The cusp with the other parameters of `p`.
pub fn cusp(p: &Params) -> Cusp {
    let gc = p.critical_gamma();
    let q = Params { gamma: gc, ..*p };
    let x = gc; // 1/(3α)
    Cusp {
        gamma: gc,
        a: if p.delta > 0.0 { a_of(&q, x) } else { f64::NAN },
        x,
    }
}

/// Bisection for the boundary where `inside(x)` changes between xa (inside = ia) and xb, to a
/// relative 1e-12 (absolute 1e-15 near x = 0).
fn boundary(xa: f64, xb: f64, inside: impl Fn(f64) -> bool) -> f64 {
    let ia = inside(xa);
    let close = |a: f64, b: f64| (b - a).abs() <= 1e-12 * (0.5 * (a + b)).abs().max(1e-3);
    let (xa, xb) = crate::roots::bisect(xa, xb, 200, close, |m| inside(m) == ia);
    0.5 * (xa + xb)
}

/// Merges overlapping intervals (sorted by a_min).
fn merge(mut v: Vec<Interval>) -> Vec<Interval> {
    v.sort_by(|a, b| a.a_min.total_cmp(&b.a_min));
    let mut out: Vec<Interval> = Vec::new();
    for i in v {
        match out.last_mut() {
            Some(last) if i.a_min <= last.a_max => last.a_max = last.a_max.max(i.a_max),
            _ => out.push(i),
        }
    }
    out
}

/// The fewest and most equilibria for one a over the range: 3 strictly between the fold values
/// of a, 2 at them, else 1.
fn counts(fold_list: &[Fold], (a0, a1): (f64, f64)) -> (usize, usize) {
    match fold_list {
        [f1, f2] => {
            let (lo, hi) = (f2.a.min(f1.a), f2.a.max(f1.a));
            let max_c = if a0 < hi && a1 > lo {
                3
            } else if a0 <= hi && a1 >= lo {
                2
            } else {
                1
            };
            let min_c = if a0 < lo || a1 > hi {
                1
            } else if a0 > lo && a1 < hi {
                3
            } else {
                2
            };
            (min_c, max_c)
        }
        _ => (1, 1),
    }
}

/// The largest |dx/da| on the curve traversed by a ∈ `a_range`: at x = 1/(3α) if on it, at the
/// folds (+inf), or at the ends. What a sweep row reports of the curve, without the rest of
/// [`analyze`] (whose γ-boundary bisection costs more than the row's simulation).
///
/// ```
/// use hdgear::{Params, fast::max_slope};
/// let p = Params::default(); // γ = 0.1 > 1/(3α): no folds, steepest at x = 1/(3α)
/// let s = max_slope(&p, (-1.0, 1.0));
/// assert!((s.value - p.delta / (p.gamma - p.critical_gamma())).abs() < 1e-9 * s.value);
/// ```
pub fn max_slope(p: &Params, a_range: (f64, f64)) -> Slope {
    slope_with_folds(p, a_range, &folds(p, a_range))
}

/// [`max_slope`] with the folds already found.
fn slope_with_folds(p: &Params, a_range: (f64, f64), fold_list: &[Fold]) -> Slope {
    let (a0, a1) = a_range;
    let intervals = x_intervals(p, a_range);
    let on_curve = |x: f64| intervals.iter().any(|&(l, r)| x >= l && x <= r);
    let mut candidates: Vec<f64> = intervals.iter().flat_map(|&(l, r)| [l, r]).collect();
    let x0 = 1.0 / (3.0 * p.alpha);
    if on_curve(x0) {
        candidates.push(x0);
    }
    for f in fold_list.iter().filter(|f| f.in_range) {
        candidates.push(f.x);
    }
    let slope_at = |x: f64| {
        let gp = p.g_prime(x);
        if gp == 0.0 || fold_list.iter().any(|f| f.x == x) {
            f64::INFINITY
        } else {
            (p.delta / gp).abs()
        }
    };
    let best = candidates
        .iter()
        .copied()
        .max_by(|a, b| slope_at(*a).total_cmp(&slope_at(*b)))
        .unwrap_or(x0);
    Slope {
        value: slope_at(best),
        a: a_of(p, best).clamp(a0, a1),
        x: best,
    }
}

/// The pieces of the focus parts of the curve (as x-intervals) where κ > κ_c.
fn rate_pieces(p: &Params) -> Vec<(f64, f64)> {
    let inside = |x: f64| forcing_rate(p, x) > FORCING_RATE_THRESHOLD;
    let mut areas = Vec::new();
    const SAMPLES: usize = 4000;
    for (pl, pr) in focus_pieces(p) {
        let mut start: Option<f64> = None;
        let mut prev_x = pl;
        for j in 0..=SAMPLES {
            let x = pl + (pr - pl) * j as f64 / SAMPLES as f64;
            let now = inside(x);
            match (start, now) {
                (None, true) => {
                    start = Some(if j == 0 {
                        x
                    } else {
                        boundary(prev_x, x, inside)
                    })
                }
                (Some(s), false) => {
                    areas.push((s, boundary(prev_x, x, inside)));
                    start = None;
                }
                _ => {}
            }
            prev_x = x;
        }
        if let Some(s) = start {
            areas.push((s, pr));
        }
    }
    areas
}

/// Spiking areas: the focus parts of the traversed curve where κ > κ_c, and the folds.
fn spiking_areas(p: &Params, a_range: (f64, f64), fold_list: &[Fold]) -> Vec<Interval> {
    let (a0, a1) = a_range;
    let mut areas = rate_pieces(p);
    // κ vanishes at the inflection x = 1/(3α) (g'' = 0), and the node part around it cannot ring:
    // areas on either side of the inflection on one stable branch are one steep region
    areas.sort_by(|l, r| l.0.total_cmp(&r.0));
    let xc = p.critical_gamma();
    let mut joined: Vec<(f64, f64)> = Vec::new();
    for (l, r) in areas {
        match joined.last_mut() {
            Some(last)
                if last.1 <= xc
                    && l >= xc
                    && fold_abscissae(p).is_none_or(|(xm, xp)| xp < last.1 || xm > l) =>
            {
                last.1 = r;
            }
            _ => joined.push((l, r)),
        }
    }
    let mut areas = joined;
    for f in fold_list.iter().filter(|f| f.in_range) {
        areas.push((f.x, f.x));
    }
    merge(
        areas
            .into_iter()
            .map(|(xl, xr)| {
                let (al, ar) = (a_of(p, xl), a_of(p, xr));
                Interval {
                    a_min: al.min(ar).clamp(a0, a1),
                    a_max: al.max(ar).clamp(a0, a1),
                }
            })
            .collect(),
    )
}

/// The parts of `a_range` outside `spiking` (sorted, disjoint).
fn complement(spiking: &[Interval], (a0, a1): (f64, f64)) -> Vec<Interval> {
    let mut quiescent_areas = Vec::new();
    let mut cursor = a0;
    for s in spiking {
        if s.a_min > cursor {
            quiescent_areas.push(Interval {
                a_min: cursor,
                a_max: s.a_min,
            });
        }
        cursor = cursor.max(s.a_max);
    }
    if cursor < a1 {
        quiescent_areas.push(Interval {
            a_min: cursor,
            a_max: a1,
        });
    }
    quiescent_areas
}

/// Analyses the fast subsystem over `a_range` (δ must be > 0: with δ = 0 the slow variable does
/// not move the equilibria at all).
///
/// ```
/// let p = hdgear::Params { gamma: 1.0, ..Default::default() };
/// let an = hdgear::fast::analyze(&p, hdgear::fast::A_RANGE).unwrap();
/// assert!(!an.equilibria.hopf_possible);
/// assert!(an.equilibria.folds.is_empty());
/// assert_eq!(an.equilibria.spiking_areas.len(), 1);
/// ```
pub fn analyze(p: &Params, a_range: (f64, f64)) -> Result<Analysis> {
    p.validate()?;
    check_a_range(a_range)?;
    if p.delta == 0.0 {
        return Err(Error::InvalidParameter {
            name: Param::Delta.name().into(),
            value: 0.0,
            reason: "must be > 0 for the fast-slow analysis (with δ = 0 the slow variable does \
                     not move the equilibria)",
        });
    }
    let (a0, a1) = a_range;
    let gc = p.critical_gamma();
    let fold_list = folds(p, a_range);
    let regime = if p.gamma > gc {
        Regime::Monotone
    } else if p.gamma == gc {
        Regime::Cusp
    } else {
        Regime::FoldHysteresis
    };
    let (min_count, max_count) = counts(&fold_list, a_range);
    let cusp_pt = cusp(p);
    let cusp_in_range = regime == Regime::Cusp && cusp_pt.a >= a0 && cusp_pt.a <= a1;
    let stable_everywhere = max_count == 1 && !cusp_in_range;

    let max_slope = slope_with_folds(p, a_range, &fold_list);
    let x0 = 1.0 / (3.0 * p.alpha);
    let steepest_point = (p.gamma > gc).then(|| Slope {
        value: p.delta / (p.gamma - gc),
        a: a_of(p, x0),
        x: x0,
    });
    let slope_at_a0 = (a0 <= 0.0 && a1 >= 0.0).then(|| {
        let x = super::equilibria::stable_equilibrium(p, 0.0);
        p.delta / p.g_prime(x)
    });

    let prediction = predict(p);
    let spiking_areas = spiking_areas(p, a_range, &fold_list);
    let quiescent_areas = complement(&spiking_areas, a_range);

    Ok(Analysis {
        params: *p,
        a_range: [a0, a1],
        critical_gamma: gc,
        gamma_margin: p.gamma - gc,
        regime,
        cusp: cusp_pt,
        steepest_point,
        equilibria: EquilibriaSummary {
            min_count,
            max_count,
            stable_everywhere,
            max_slope,
            slope_at_a0,
            folds: fold_list,
            hopf_possible: false,
            hopf_reason: NO_HOPF_REASON,
            spiking_areas,
            quiescent_areas,
            prediction,
            predicted_gamma_boundary: predicted_gamma_boundary(p),
            slowest_relaxation: super::slowest_relaxation(p),
        },
    })
}

/// One row of the two-parameter bifurcation set: the two folds at one γ < 1/(3α).
/// `lower` is the fold at the smaller x (x−, where g has its local maximum: the larger a).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, crate::output::Record)]
pub struct FoldRow {
    /// γ.
    pub gamma: f64,
    /// a at the fold x−.
    pub a_lower: f64,
    /// x− = γ/(1 + √(1 − 3αγ)).
    pub x_lower: f64,
    /// a at the fold x+.
    pub a_upper: f64,
    /// x+ = (1 + √(1 − 3αγ))/(3α).
    pub x_upper: f64,
}

/// The fold curves in the (a, γ) plane for γ from `gamma_min` up to the cusp 1/(3α) (the last
/// row, where both folds meet), `points` rows equally spaced in γ. Closed forms throughout.
pub fn fold_curves(p: &Params, gamma_min: f64, points: usize) -> Result<Vec<FoldRow>> {
    p.validate()?;
    let gc = p.critical_gamma();
    if !(gamma_min.is_finite() && gamma_min < gc) {
        return Err(Error::InvalidOption {
            name: "gamma-min",
            value: gamma_min,
            reason: "must be finite and below the critical gamma 1/(3*alpha), where folds exist",
        });
    }
    crate::params::check_magnitude("gamma-min", gamma_min)?;
    if p.delta == 0.0 {
        return Err(Error::InvalidParameter {
            name: Param::Delta.name().into(),
            value: 0.0,
            reason: "must be > 0: with δ = 0 the folds have no a-coordinate",
        });
    }
    if points < 2 {
        return Err(Error::InvalidOption {
            name: "points",
            value: points as f64,
            reason: "must be ≥ 2",
        });
    }
    (0..points)
        .map(|k| {
            let gamma = if k == points - 1 {
                gc
            } else {
                gamma_min + (gc - gamma_min) * k as f64 / (points - 1) as f64
            };
            let q = Params { gamma, ..*p };
            let (xm, xp) = fold_abscissae(&q).unwrap_or((gc, gc));
            FoldRow {
                gamma,
                a_lower: a_of(&q, xm),
                x_lower: xm,
                a_upper: a_of(&q, xp),
                x_upper: xp,
            }
        })
        .map(|r| {
            if [r.a_lower, r.x_lower, r.a_upper, r.x_upper]
                .iter()
                .all(|v| v.is_finite())
            {
                Ok(r)
            } else {
                Err(Error::InvalidOption {
                    name: "gamma-min",
                    value: gamma_min,
                    reason: "too far below the cusp: the fold points overflow there",
                })
            }
        })
        .collect()
}

/// The fast subsystem's analysis of any equilibrium curve ([`super::StaticCurve`]): what
/// `hdgear analyze` shows for a model assembled from terms, derived from its static torque g and
/// its damping at rest c alone (the study's [`Analysis`] adds the cubic's closed forms: its
/// cusp, critical γ and predicted boundary).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CurveAnalysis {
    /// The analysed range of the slow variable.
    pub a_range: [f64; 2],
    /// c, the damping at rest: the fast Jacobian [[0, 1], [−g', −c]] has trace −c.
    pub damping_at_rest: f64,
    /// g' above which a stable equilibrium is a focus (it rings): c²/4.
    pub focus_gprime: f64,
    /// The folds of the curve (g' = 0), in increasing x.
    pub folds: Vec<Fold>,
    /// Fewest distinct equilibria at any sampled a in the range (257 values across it, and the
    /// middle of the fold band).
    pub min_count: usize,
    /// Most distinct equilibria at any sampled a.
    pub max_count: usize,
    /// The slowest relaxation on the path the state follows over a ∈ [−1, 1].
    pub slowest_relaxation: super::SlowestRelaxation,
    /// The largest speed |dx*/dτ| of the equilibrium the response settles on (infinite when it
    /// must jump at a fold).
    pub max_equilibrium_speed: f64,
    /// The largest first-order adiabatic lag c·|dx*/dτ|/g' on that branch.
    pub max_first_order_lag: f64,
}

/// Analyses the equilibrium curve `c` over `a_range` ([`CurveAnalysis`]).
///
/// ```
/// use hdgear::{Params, fast::{A_RANGE, curve_analysis}, model::{Model, ModelCurve, terms::AnyTerm}};
/// // smooth friction f_c·tanh(x'/v_s) adds f_c/v_s = 2 to the damping at rest; the curve is the
/// // study's (friction has no static torque), so the two folds of γ = 0.01 stay where they were
/// let p = Params { gamma: 0.01, ..Params::default() };
/// let m = Model::study(&p).with_term(AnyTerm::new("friction", &[0.1, 0.05]).unwrap()).unwrap();
/// let an = curve_analysis(&ModelCurve::new(&m).unwrap(), A_RANGE).unwrap();
/// assert!((an.damping_at_rest - 3.0).abs() < 1e-12);
/// assert_eq!((an.folds.len(), an.max_count), (2, 3));
/// let x_lower = hdgear::fast::fold_abscissae(&p).unwrap().0;
/// assert!((an.folds[0].x - x_lower).abs() < 1e-9);
/// ```
pub fn curve_analysis<C: super::StaticCurve>(c: &C, a_range: (f64, f64)) -> Result<CurveAnalysis> {
    c.check()?;
    check_a_range(a_range)?;
    let (a0, a1) = a_range;
    let folds: Vec<Fold> = c
        .fold_band()
        .map(|(xm, xp)| vec![xm, xp])
        .unwrap_or_default()
        .into_iter()
        .map(|x| {
            let a = c.a_at(x);
            Fold {
                a,
                x,
                in_range: (a0..=a1).contains(&a),
            }
        })
        .collect();
    // between the folds' a (where all three roots live, however narrow the band: a grid of a
    // can miss it) and on a grid; at a fold itself the double root is a tangency
    const SAMPLES: usize = 256;
    let inside = match folds[..] {
        [f, g] => Some(0.5 * (f.a + g.a)).filter(|a| (a0..=a1).contains(a)),
        _ => None,
    };
    let counts: Vec<usize> = (0..=SAMPLES)
        .map(|i| a0 + (a1 - a0) * i as f64 / SAMPLES as f64)
        .chain(inside)
        .map(|a| c.roots(a).len())
        .collect();
    Ok(CurveAnalysis {
        a_range: [a0, a1],
        damping_at_rest: c.damping(),
        focus_gprime: c.focus_gprime(),
        folds,
        min_count: counts.iter().copied().min().unwrap_or(0),
        max_count: counts.iter().copied().max().unwrap_or(0),
        slowest_relaxation: c.slowest_relaxation(),
        max_equilibrium_speed: c.max_equilibrium_speed(),
        max_first_order_lag: c.max_first_order_lag(),
    })
}
