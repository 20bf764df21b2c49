//! Equilibria of the fast subsystem at a frozen slow variable a: the real roots of the cubic
//! F(x, a) = α x³ − x² + γ (x − ε) − μ − δ a, with their linear stability.
//!
//! Method: F is monotone between its critical points (the folds x± where g'(x) = 0, when they
//! exist), so each real root lies in a known interval with a sign change: (−∞, x−], [x−, x+],
//! [x+, ∞), or all of ℝ without folds. The infinite ends are cut at the Cauchy bound
//! 1 + max|coefficient/α|. Each root is then found by Newton's method safeguarded by bisection in
//! its bracket, which converges to the correctly rounded neighbourhood of the root whatever the
//! conditioning, and stays accurate next to a double root (where the closed-form Cardano formula
//! loses half the digits). A fold value within rounding of zero (|F(x±)| ≤ 8·ε_mach·Σ|terms|) is
//! reported as a double root.

use crate::params::Params;
use serde::Serialize;

/// Linear type of an equilibrium (x, 0) of x'' + x' + g(x) = μ + δ a.
///
/// The Jacobian is [[0, 1], [−g'(x), −1]]: trace −1, determinant g'(x), eigenvalues
/// (−1 ± √(1 − 4 g'))/2.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum EqType {
    /// 0 < g' ≤ 1/4: two real negative eigenvalues.
    StableNode,
    /// g' > 1/4: complex eigenvalues with real part −1/2.
    StableFocus,
    /// g' < 0: one positive, one negative eigenvalue.
    Saddle,
    /// g' = 0 (a fold point): a zero eigenvalue.
    Degenerate,
}

impl EqType {
    /// The type for a given g'(x).
    pub fn from_g_prime(gp: f64) -> EqType {
        // the study's damping at rest c = 1: a focus above c²/4
        EqType::with_damping(gp, 1.0)
    }

    /// The type for stiffness k and damping c > 0 (Jacobian [[0, 1], [−k, −c]]): a focus above
    /// k = c²/4; [`EqType::from_g_prime`] is c = 1.
    pub fn with_damping(k: f64, c: f64) -> EqType {
        if k > 0.25 * c * c {
            EqType::StableFocus
        } else if k > 0.0 {
            EqType::StableNode
        } else if k < 0.0 {
            EqType::Saddle
        } else {
            EqType::Degenerate
        }
    }

    /// Name used in CSV/JSON output.
    pub fn name(self) -> &'static str {
        match self {
            EqType::StableNode => "stable-node",
            EqType::StableFocus => "stable-focus",
            EqType::Saddle => "saddle",
            EqType::Degenerate => "degenerate",
        }
    }

    /// True for the asymptotically stable types.
    pub fn is_stable(self) -> bool {
        matches!(self, EqType::StableNode | EqType::StableFocus)
    }
}

/// The two eigenvalues λ = re ± i·im of the Jacobian for a given g'(x), larger real part first.
pub fn eigenvalues(gp: f64) -> [(f64, f64); 2] {
    let disc = 1.0 - 4.0 * gp;
    if disc >= 0.0 {
        let s = disc.sqrt();
        [(-0.5 + 0.5 * s, 0.0), (-0.5 - 0.5 * s, 0.0)]
    } else {
        let w = 0.5 * (-disc).sqrt();
        [(-0.5, w), (-0.5, -w)]
    }
}

/// The eigenvalues λ = re ± i·im of [[0, 1], [−k, −c]] (λ² + cλ + k = 0), larger real part
/// first: [`eigenvalues`] at any damping c.
pub fn eigenvalues_with(k: f64, c: f64) -> [(f64, f64); 2] {
    let disc = c * c - 4.0 * k;
    if disc >= 0.0 {
        let s = disc.sqrt();
        [(0.5 * (-c + s), 0.0), (0.5 * (-c - s), 0.0)]
    } else {
        let w = 0.5 * (-disc).sqrt();
        [(-0.5 * c, w), (-0.5 * c, -w)]
    }
}

/// One equilibrium (x, 0) of the fast subsystem.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Equilibrium {
    /// Position x.
    pub x: f64,
    /// g'(x) = 3αx² − 2x + γ (the Jacobian's determinant).
    pub g_prime: f64,
    /// Eigenvalues as (re, im) pairs.
    pub eigenvalues: [(f64, f64); 2],
    /// Linear type.
    pub kind: EqType,
    /// 1 for a simple root, 2 for a double root (a fold), 3 at the cusp.
    pub multiplicity: u8,
}

impl Equilibrium {
    fn at(p: &Params, x: f64, multiplicity: u8) -> Equilibrium {
        let gp = if multiplicity > 1 { 0.0 } else { p.g_prime(x) };
        Equilibrium {
            x,
            g_prime: gp,
            eigenvalues: eigenvalues(gp),
            kind: EqType::from_g_prime(gp),
            multiplicity,
        }
    }
}

/// All equilibria at one value of the slow variable.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Equilibria {
    /// The slow variable a.
    pub a: f64,
    /// Distinct real roots in increasing x.
    pub roots: Vec<Equilibrium>,
    /// Discriminant Δ = 18abcd − 4b³d + b²c² − 4ac³ − 27a²d² of the cubic ax³ + bx² + cx + d
    /// with a = α, b = −1, c = γ, d = −(γε + μ + δa). Sign convention (the usual one): Δ > 0 three
    /// distinct real roots, Δ = 0 a multiple root, Δ < 0 one real root. (The study states the
    /// opposite sign for "one root"; it uses another convention.)
    pub discriminant: f64,
}

impl Equilibria {
    /// Number of distinct real equilibria (1, 2 or 3).
    pub fn count(&self) -> usize {
        self.roots.len()
    }
}

/// The fold abscissae x− < x+ where g'(x) = 0, if 1 − 3αγ > 0 (γ < 1/(3α)).
///
/// x± = (1 ± s)/(3α) with s = √(1 − 3αγ); x− is computed as γ/(1 + s) to avoid cancellation.
pub fn fold_abscissae(p: &Params) -> Option<(f64, f64)> {
    let d = 1.0 - 3.0 * p.alpha * p.gamma;
    if d <= 0.0 {
        return None;
    }
    let s = d.sqrt();
    let xp = (1.0 + s) / (3.0 * p.alpha);
    let xm = p.gamma / (1.0 + s);
    Some((xm, xp))
}

/// F(x, a) and the sum of the magnitudes of its terms (the rounding scale of F).
fn f_and_scale(p: &Params, x: f64, rhs: f64) -> (f64, f64) {
    let f = p.g(x) - rhs;
    let scale = (p.alpha * x * x * x).abs()
        + x * x
        + (p.gamma * x).abs()
        + (p.gamma * p.eps).abs()
        + rhs.abs();
    (f, scale)
}

/// The root of the monotone F(x) = g(x) − `rhs` on [lo, hi] with F(lo), F(hi) of opposite signs
/// (or zero), to the last bit.
fn bracketed_root(p: &Params, rhs: f64, lo: f64, hi: f64) -> f64 {
    crate::roots::newton_bracketed(|x| p.g(x) - rhs, |x| p.g_prime(x), lo, hi)
}

/// All real equilibria at slow variable `a`, with their stability.
///
/// ```
/// let p = hdgear::Params::default();
/// let e = hdgear::fast::equilibria(&p, 0.0);
/// assert_eq!(e.count(), 1);
/// assert!(e.roots[0].kind.is_stable());
/// ```
pub fn equilibria(p: &Params, a: f64) -> Equilibria {
    let rhs = p.forcing(a) + p.gamma * p.eps; // α x³ − x² + γ x = rhs
    let (ca, cb, cc, cd) = (p.alpha, -1.0, p.gamma, -rhs);
    let discriminant = 18.0 * ca * cb * cc * cd - 4.0 * cb.powi(3) * cd + cb * cb * cc * cc
        - 4.0 * ca * cc.powi(3)
        - 27.0 * ca * ca * cd * cd;
    let bound = 1.0 + (1.0 / ca).max((cc / ca).abs()).max((cd / ca).abs());
    let rhs_f = p.forcing(a);
    let mut roots = Vec::with_capacity(3);
    match fold_abscissae(p) {
        None => {
            let x = bracketed_root(p, rhs_f, -bound, bound);
            // At the cusp (γ = 1/(3α) exactly) a triple root is possible.
            let mult = if p.g_prime(x) == 0.0 { 3 } else { 1 };
            roots.push(Equilibrium::at(p, x, mult));
        }
        Some((xm, xp)) => {
            let (fm, sm) = f_and_scale(p, xm, rhs_f);
            let (fp, sp) = f_and_scale(p, xp, rhs_f);
            let zero_m = fm.abs() <= 8.0 * f64::EPSILON * sm;
            let zero_p = fp.abs() <= 8.0 * f64::EPSILON * sp;
            if zero_m {
                roots.push(Equilibrium::at(p, xm, 2));
            } else if fm > 0.0 {
                roots.push(Equilibrium::at(p, bracketed_root(p, rhs_f, -bound, xm), 1));
            }
            if !zero_m && !zero_p && fm > 0.0 && fp < 0.0 {
                roots.push(Equilibrium::at(p, bracketed_root(p, rhs_f, xm, xp), 1));
            }
            if zero_p {
                roots.push(Equilibrium::at(p, xp, 2));
            } else if fp < 0.0 {
                roots.push(Equilibrium::at(p, bracketed_root(p, rhs_f, xp, bound), 1));
            }
        }
    }
    Equilibria {
        a,
        roots,
        discriminant,
    }
}

/// The stable equilibrium the default initial condition starts on at slow variable `a`: the only
/// one without folds; in the hysteresis regime (two stable branches) the lower one.
pub fn stable_equilibrium(p: &Params, a: f64) -> f64 {
    let e = equilibria(p, a);
    e.roots
        .iter()
        .find(|r| r.kind.is_stable())
        .or(e.roots.first())
        .map(|r| r.x)
        .expect("a real cubic has at least one real root")
}

/// The stable equilibrium at slow variable `a` nearest to the state `x` (the one a trajectory at
/// x is attracted to or tracking), or `None` when no equilibrium there is stable.
pub fn nearest_stable_equilibrium(p: &Params, a: f64, x: f64) -> Option<f64> {
    equilibria(p, a)
        .roots
        .iter()
        .filter(|r| r.kind.is_stable())
        .map(|r| r.x)
        .min_by(|u, v| (u - x).abs().total_cmp(&(v - x).abs()))
}

/// One Newton step of the tracker on g(y) = `rhs` from the iterate `y` (computed without
/// branches, so that it vectorises over the lanes of a batch).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Newton {
    /// g'(y) > 0: the iterate is on a stable branch (else nothing below means anything).
    pub on_branch: bool,
    /// The next iterate.
    pub y: f64,
    /// The next iterate is the root to rounding.
    pub done: bool,
    /// dx*/da = δ/g' there.
    pub slope: f64,
    /// d²x*/da² = −g''·(dx*/da)²/g' there.
    pub curvature: f64,
}

/// The tracker's Newton step (one function for one scan and for the lanes of many): everything
/// but the step itself from the iterate y (one division, computed while g(y) is), since calls
/// follow each other through the tracker's state and the length of this chain is what a scan
/// pays per sample. Newton's error after the step is |g''|/(2g')·dy² to leading order: done when
/// that is at the rounding level of y (no second evaluation to test the residual). `scale` is
/// 1/α, the x-scale of the cubic's features (its inflection is at 1/(3α)): computed once per
/// parameter set by the caller (a division per call was a quarter of the batched sampling's).
#[inline(always)]
pub(crate) fn newton(p: &Params, scale: f64, y: f64, rhs: f64) -> Newton {
    let gp = p.g_prime(y);
    let inv_gp = 1.0 / gp;
    let half_g2 = 3.0 * p.alpha * y - 1.0;
    let tolerance = 4.0 * f64::EPSILON * (y.abs() + scale) * gp;
    let dy = (p.g(y) - rhs) * inv_gp;
    let slope = p.delta * inv_gp;
    Newton {
        // (false for NaN)
        on_branch: gp > 0.0,
        y: y - dy,
        done: half_g2.abs() * dy * dy <= tolerance,
        slope,
        curvature: -2.0 * half_g2 * slope * slope * inv_gp,
    }
}

/// The equilibrium a state follows: the nearest stable one at the current a (the only one without
/// folds), by Newton warm-started from the last one, with the exact cubic solve as fallback.
#[derive(Clone, Debug)]
pub struct EquilibriumTracker {
    p: Params,
    /// 1/α ([`newton`]'s scale).
    scale: f64,
    /// The a-interval with three equilibria (between the fold values), if any.
    multi: Option<(f64, f64)>,
    /// The last equilibrium returned, the a it was for, and dx*/da and d²x*/da² there (0:
    /// unknown).
    hint: f64,
    last_a: f64,
    slope: f64,
    curvature: f64,
}

impl EquilibriumTracker {
    /// A tracker for `p` starting from the equilibrium guess `x0`.
    pub fn new(p: &Params, x0: f64) -> EquilibriumTracker {
        let multi = match folds(p, (f64::NEG_INFINITY, f64::INFINITY)).as_slice() {
            [f1, f2] => Some((f1.a.min(f2.a), f1.a.max(f2.a))),
            _ => None,
        };
        EquilibriumTracker {
            p: *p,
            scale: 1.0 / p.alpha,
            multi,
            hint: x0,
            last_a: 0.0,
            slope: 0.0,
            curvature: 0.0,
        }
    }

    /// The a-interval with three equilibria (between the fold values), if any.
    pub(crate) fn multi(&self) -> Option<(f64, f64)> {
        self.multi
    }

    /// The warm start: the last equilibrium, its a, dx*/da and d²x*/da² there.
    pub(crate) fn state(&self) -> [f64; 4] {
        [self.hint, self.last_a, self.slope, self.curvature]
    }

    /// Sets the warm start [`EquilibriumTracker::state`] gives (as followed elsewhere).
    pub(crate) fn set_state(&mut self, [hint, last_a, slope, curvature]: [f64; 4]) {
        (self.hint, self.last_a, self.slope, self.curvature) = (hint, last_a, slope, curvature);
    }

    /// x*(a) for a state at x.
    pub fn at(&mut self, a: f64, x: f64) -> f64 {
        let p = &self.p;
        let unique = self.multi.is_none_or(|(lo, hi)| a < lo || a > hi);
        if unique {
            let rhs = p.forcing(a);
            // predicted along the branch's Taylor polynomial from the last point, with
            // dx*/da = δ/g' and d²x*/da² = −g''·(dx*/da)²/g' (differentiate g(x*) = μ + δa
            // twice): Newton's first step then lands at the rounding level for the small moves
            // of a scan (with the tangent alone it took two)
            let da = a - self.last_a;
            let mut y = self.hint + da * (self.slope + 0.5 * self.curvature * da);
            for _ in 0..8 {
                let n = newton(p, self.scale, y, rhs);
                if !n.on_branch {
                    break; // not on a stable branch: the exact solve below decides
                }
                y = n.y;
                if n.done {
                    (self.hint, self.last_a, self.slope, self.curvature) =
                        (y, a, n.slope, n.curvature);
                    return y;
                }
            }
        }
        let y = super::nearest_stable_equilibrium(p, a, x).unwrap_or(x);
        (self.hint, self.last_a, self.slope, self.curvature) = (y, a, 0.0, 0.0);
        y
    }
}

/// A fold (saddle-node) point of the fast subsystem: g'(x) = 0 on the equilibrium curve.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Fold {
    /// a at the fold.
    pub a: f64,
    /// x at the fold.
    pub x: f64,
    /// True when a lies in the analysed a-range (so the slow variable traverses it).
    pub in_range: bool,
}

/// The fold points of the fast subsystem (closed form), each flagged in or out of `a_range`.
pub fn folds(p: &Params, a_range: (f64, f64)) -> Vec<Fold> {
    match fold_abscissae(p) {
        None => Vec::new(),
        Some((xm, xp)) if p.delta > 0.0 => [xm, xp]
            .iter()
            .map(|&x| {
                let a = p.a_at(x);
                Fold {
                    a,
                    x,
                    in_range: a >= a_range.0 && a <= a_range.1,
                }
            })
            .collect(),
        Some(_) => Vec::new(),
    }
}
