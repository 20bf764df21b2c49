//! Two-parameter continuation: the curve of folds of cycles (or of period doublings) as two
//! parameters change together, with its codimension-two points.
//!
//! **Unknowns** z = (x₀/S, x₀'/S, u₁, u₂): the orbit's start at phase 0 (scaled by S, as in
//! [`continue_orbit`](super::continue_orbit)) and both parameter coordinates (λ or ln λ).
//! **Equations**: the periodicity P(z) = (φ_{2πk}(x₀, x₀'; λ₁, λ₂) − (x₀, x₀'))/S = 0, the test
//! function ψ(z) = 0 (ψ₊ = det(M − I) for folds, ψ₋ = det(M + I) for period doublings, the
//! functions the one-parameter continuation locates its special points with), and the arclength
//! condition t·(z − z_pred) = 0: four equations, a curve in four unknowns. On the curve one
//! multiplier is exactly +1 (−1), since ψ = (m₁ ∓ 1)(m₂ ∓ 1) and the other multiplier is far
//! from ±1 (m₁m₂ = e^{−kT}).
//!
//! The Jacobian's first two rows [M − I | ∂φ/∂u₁ | ∂φ/∂u₂] come from the variational equations
//! (one integration per parameter), the row of ψ from forward differences of ψ over
//! [`GRADIENT_STEP`] in each unknown (ψ depends on M, whose derivatives would need the
//! second-order variational equations): a quasi-Newton corrector, which converges to the same
//! zero (the residuals are exact) a little more slowly. Converged when |P| ≤ 1e-11·(1 + |x₀|) as
//! in shooting and |ψ| ≤ [`PSI_TOL`].
//!
//! **Codimension-two points**, located by the Illinois method on the arclength with a corrector
//! at every trial:
//! * a **cusp** (of a fold curve): the curve's projection on the parameter plane stops and turns
//!   back. Its parameter-plane velocity (t₃, t₄) keeps its direction (normal to the fold line)
//!   and changes sign, so (t₃, t₄)·(t₃, t₄)_before is the test function. There the two folds of a
//!   one-parameter branch meet and its hysteresis vanishes.
//! * a **generalised period doubling** (of a period-doubling curve): the doubling's normal-form
//!   coefficient ([`super::flip_coefficient`]) passes through zero, and the doubling turns from
//!   supercritical to subcritical.
//!
//! No other codimension-two point of cycles can occur in a forced oscillator of one degree of
//! freedom, so none is looked for. By Liouville's formula det M = exp(∫ ∂a/∂v dτ) > 0, while a
//! fold–flip (multipliers +1 and −1) needs m₁m₂ = −1. The 1:1 and 1:2 resonances (a double +1 or
//! −1) and a Neimark–Sacker pair on the unit circle need det M = 1, which damping along the orbit
//! rules out (the study's model has ∂a/∂v = −1: det M = e^{−kT}).
//!
//! Step control is that of [`continue_orbit`](super::continue_orbit), in units of the parameter
//! box's diagonal in u: a step grows by 1.5 after a corrector of at most three iterations, halves
//! after a failure, a tangent turn over `max_turn` or a corrector that lands farther from the
//! predictor than the step; the curve ends where it leaves the box (on its edge exactly), closes
//! on itself, or the step falls below `min_step`.
//!
//! **Why one file.** The curve's unknowns, its corrector, the location of its codimension-two
//! points and its rows share the tracer's private state and the 4-vector helpers; split, they would
//! have to be made visible to each other.

use super::branch::{ContinuationOptions, End};
use super::continuation::test_functions;
use super::{Amplitude, Flow, Multiplier, Oscillator, amplitude, flow, multipliers};
use super::{Box2, Scale};
use crate::error::{Error, Result, SolverError};
use serde::Serialize;
use std::f64::consts::TAU;

/// Forward-difference step of ψ's gradient in the (scaled) unknowns: √ε·10 ≈ 1.5e-7 balances
/// the truncation error (∝ h) against the integration's noise in ψ (≈ 1e-13/h).
pub const GRADIENT_STEP: f64 = 1.5e-7;

/// |ψ| at a converged point: with |m₂ ∓ 1| of order one it puts the critical multiplier within
/// about 1e-11 of ±1, inside the 1e-9 the curve is checked to.
pub const PSI_TOL: f64 = 1e-11;

/// Which curve.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum CurveKind {
    /// Folds of cycles: a multiplier at +1.
    Fold,
    /// Period doublings: a multiplier at −1.
    PeriodDoubling,
}

impl CurveKind {
    /// The name users write.
    pub fn name(self) -> &'static str {
        match self {
            CurveKind::Fold => "fold",
            CurveKind::PeriodDoubling => "period-doubling",
        }
    }

    /// Parses a start, `fold[:N]` or `period-doubling[:N]` (`pd` for short): the curves through
    /// every such point of a one-parameter branch, or through its Nth (from 1) only.
    ///
    /// ```
    /// use hdgear::periodic::CurveKind;
    /// assert_eq!(CurveKind::parse_start("pd:2").unwrap(), (CurveKind::PeriodDoubling, Some(2)));
    /// assert!(CurveKind::parse_start("hopf").is_err());
    /// ```
    pub fn parse_start(text: &str) -> Result<(CurveKind, Option<usize>)> {
        let bad = |reason: &str| Error::InvalidInput {
            what: "start",
            text: text.to_string(),
            reason: reason.to_string(),
        };
        let (kind, n) = match text.split_once(':') {
            Some((k, n)) => (k, Some(n)),
            None => (text, None),
        };
        let kind = match kind.trim() {
            "fold" => CurveKind::Fold,
            "period-doubling" | "pd" => CurveKind::PeriodDoubling,
            _ => return Err(bad("expected fold or period-doubling, with :N for the Nth")),
        };
        let n = match n.map(|n| n.trim().parse::<usize>()) {
            None => None,
            Some(Ok(n)) if n >= 1 => Some(n),
            Some(_) => return Err(bad("N must be a whole number from 1")),
        };
        Ok((kind, n))
    }

    /// The index of its test function in [`test_functions`] (ψ₊ then ψ₋).
    fn index(self) -> usize {
        match self {
            CurveKind::Fold => 0,
            CurveKind::PeriodDoubling => 1,
        }
    }
}

/// A special point on a curve: a codimension-two point, or where the curve turns back in its
/// second parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Codim2 {
    /// Two folds meet: the hysteresis is born here.
    Cusp,
    /// The period doubling's normal-form coefficient ([`super::flip_coefficient`]) changes sign:
    /// the doubling turns from supercritical to subcritical.
    GeneralisedPeriodDoubling,
    /// Not a bifurcation: λ₂ is least or largest along the curve, where it turns back in the
    /// second parameter (a resonance bubble's least δ: below it the one-parameter branch in λ₁
    /// has no fold or doubling of this curve).
    TurningPoint,
}

impl Codim2 {
    /// The name written in tables.
    pub fn name(self) -> &'static str {
        match self {
            Codim2::Cusp => "cusp",
            Codim2::GeneralisedPeriodDoubling => "generalised-period-doubling",
            Codim2::TurningPoint => "turning-point",
        }
    }
}

/// One point of a two-parameter curve.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CurvePoint2 {
    /// (λ₁, λ₂).
    pub params: [f64; 2],
    /// (x, x') at phase 0.
    pub start: [f64; 2],
    /// The multipliers, the larger first.
    pub multipliers: [Multiplier; 2],
    /// Extremes of the response.
    pub amplitude: Amplitude,
    /// Set at a located codimension-two point.
    pub special: Option<Codim2>,
    /// On a period-doubling curve, the doubling's normal-form coefficient
    /// ([`super::flip_coefficient`]): > 0 supercritical, < 0 subcritical.
    pub flip_coefficient: Option<f64>,
}

/// A curve of folds or period doublings in two parameters.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Curve2<P> {
    /// Folds or period doublings.
    pub kind: CurveKind,
    /// The two parameters.
    pub params: [P; 2],
    /// k: the orbits have period k·2π/ω.
    pub subharmonic: u32,
    /// The points in order along the curve, codimension-two points in their place.
    pub points: Vec<CurvePoint2>,
    /// Why each end ended: the start of `points`, then its end.
    pub ends: [End; 2],
}

/// A corrected point.
#[derive(Clone, Copy)]
pub(super) struct Point {
    pub(super) z: [f64; 4],
    flow: Flow,
    /// ∂(φ/S)/∂u₂ (the flow carries ∂(φ/S)/∂u₁).
    w2: [f64; 2],
    grad: [f64; 4],
    iterations: usize,
}

pub(super) struct Tracer<'a, O: Oscillator> {
    o: &'a O,
    params: [O::Param; 2],
    kind: CurveKind,
    k: u32,
    opts: &'a ContinuationOptions,
    scales: [Scale; 2],
    /// The box in u: (low, high) per parameter.
    bounds: [[f64; 2]; 2],
    /// Its diagonal in u: the unit of the steps.
    pub(super) size: f64,
    /// The state's scale S.
    pub(super) scale: f64,
    /// Points where a curve born at a switch ends ([`End::Rejoined`]): in unknowns, and as
    /// written.
    pub(super) terminals: Vec<([f64; 4], CurvePoint2)>,
}

pub(super) fn dot(a: [f64; 4], b: [f64; 4]) -> f64 {
    a.iter().zip(&b).map(|(x, y)| x * y).sum()
}

fn norm(a: [f64; 4]) -> f64 {
    dot(a, a).sqrt()
}

pub(super) fn axpy(a: [f64; 4], s: f64, b: [f64; 4]) -> [f64; 4] {
    std::array::from_fn(|i| a[i] + s * b[i])
}

/// Solves an n × n system by Gaussian elimination with partial pivoting.
fn solve<const N: usize>(mut a: [[f64; N]; N], mut b: [f64; N]) -> Option<[f64; N]> {
    for c in 0..N {
        let p = (c..N).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c] == 0.0 || !a[p][c].is_finite() {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..N {
            let f = a[r][c] / a[c][c];
            let pivot = a[c];
            for (x, y) in a[r][c..].iter_mut().zip(&pivot[c..]) {
                *x -= f * y;
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = [0.0; N];
    for r in (0..N).rev() {
        let s: f64 = (r + 1..N).map(|j| a[r][j] * x[j]).sum();
        x[r] = (b[r] - s) / a[r][r];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

fn det3(m: [[f64; 3]; 3]) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// The kernel of a 3 × 4 matrix of rank 3: its signed 3 × 3 minors.
fn kernel(rows: [[f64; 4]; 3]) -> [f64; 4] {
    std::array::from_fn(|j| {
        let minor = rows.map(|r| {
            let mut c = [0.0; 3];
            let mut n = 0;
            for (i, v) in r.iter().enumerate() {
                if i != j {
                    c[n] = *v;
                    n += 1;
                }
            }
            c
        });
        if j % 2 == 0 {
            det3(minor)
        } else {
            -det3(minor)
        }
    })
}

impl<O: Oscillator> Tracer<'_, O> {
    fn lambda(&self, z: [f64; 4]) -> [f64; 2] {
        [
            self.scales[0].to_lambda(z[2]),
            self.scales[1].to_lambda(z[3]),
        ]
    }

    pub(super) fn at(&self, z: [f64; 4]) -> Result<O> {
        let l = self.lambda(z);
        self.o
            .with(self.params[0], l[0])?
            .with(self.params[1], l[1])
    }

    pub(super) fn state(&self, z: [f64; 4]) -> [f64; 2] {
        [self.scale * z[0], self.scale * z[1]]
    }

    fn span(&self) -> f64 {
        TAU * f64::from(self.k)
    }

    fn psi(&self, f: &Flow) -> f64 {
        test_functions(f)[self.kind.index()]
    }

    /// Newton on (P, ψ, n·z − c) = 0 from z; `Ok(None)` when it does not converge.
    pub(super) fn correct(&self, mut z: [f64; 4], n: [f64; 4], c: f64) -> Result<Option<Point>> {
        let tol = self.opts.periodic.tol;
        let soft = |e: Error| match e {
            Error::Solver(SolverError::StepSizeTooSmall { .. } | SolverError::BlowUp { .. }) => {
                Ok(None)
            }
            Error::InvalidParameter { .. } | Error::InvalidOption { .. } => Ok(None),
            e => Err(e),
        };
        for iterations in 0..=self.opts.max_corrector {
            let o = match self.at(z) {
                Ok(o) => o,
                Err(e) => return soft(e),
            };
            let y = self.state(z);
            let flows = flow(&o, Some(self.params[0]), 0.0, y, self.span(), tol).and_then(|f1| {
                let f2 = flow(&o, Some(self.params[1]), 0.0, y, self.span(), tol)?;
                Ok((f1, f2))
            });
            let (mut f1, f2) = match flows {
                Ok(f) => f,
                Err(e) => return soft(e),
            };
            let d1 = self.scales[0].dlambda(z[2]) / self.scale;
            let d2 = self.scales[1].dlambda(z[3]) / self.scale;
            f1.w = [f1.w[0] * d1, f1.w[1] * d1];
            let w2 = [f2.w[0] * d2, f2.w[1] * d2];
            let r = [f1.y[0] - y[0], f1.y[1] - y[1]];
            let g = self.psi(&f1);
            let a = dot(n, z) - c;
            let mut grad = [0.0; 4];
            for (j, gj) in grad.iter_mut().enumerate() {
                let mut zj = z;
                zj[j] += GRADIENT_STEP;
                let fj = self
                    .at(zj)
                    .and_then(|oj| flow(&oj, None, 0.0, self.state(zj), self.span(), tol));
                match fj {
                    Ok(fj) => *gj = (self.psi(&fj) - g) / GRADIENT_STEP,
                    Err(e) => return soft(e),
                }
            }
            let point = Point {
                z,
                flow: f1,
                w2,
                grad,
                iterations,
            };
            if super::converged(r, y) && g.abs() <= PSI_TOL && a.abs() <= 1e-12 * (1.0 + norm(z)) {
                return Ok(Some(point));
            }
            if iterations == self.opts.max_corrector {
                break;
            }
            let Some(rows) = self.rows(&point) else {
                return Ok(None);
            };
            let j = [rows[0], rows[1], rows[2], n];
            let rhs = [-r[0] / self.scale, -r[1] / self.scale, -g, -a];
            let Some(d) = solve(j, rhs) else {
                return Ok(None);
            };
            z = axpy(z, 1.0, d);
            if !z.iter().all(|v| v.is_finite()) || self.far_outside(z) {
                return Ok(None);
            }
        }
        Ok(None)
    }

    /// Whether a Newton iterate's parameters lie more than the box's own width outside it in
    /// either parameter. The trace keeps only points inside the box and one step (at most
    /// [`ContinuationOptions::max_step`] of the diagonal) beyond it, so such an iterate is
    /// diverging; following it would shoot at parameters the user never asked for (ln ω ten
    /// units below a box of width 1.25: periods of 10⁶ time units, seconds per flow), and the
    /// trace halves its step instead.
    fn far_outside(&self, z: [f64; 4]) -> bool {
        self.bounds.iter().enumerate().any(|(i, &[lo, hi])| {
            let w = hi - lo;
            !(z[2 + i] >= lo - w && z[2 + i] <= hi + w)
        })
    }

    /// The Jacobian's rows of P and ψ at a point.
    fn rows(&self, p: &Point) -> Option<[[f64; 4]; 3]> {
        let a = p.flow.m_minus_i()?;
        Some([
            [a[0][0], a[0][1], p.flow.w[0], p.w2[0]],
            [a[1][0], a[1][1], p.flow.w[1], p.w2[1]],
            p.grad,
        ])
    }

    /// The unit tangent at a point, oriented along `along`.
    pub(super) fn tangent(&self, p: &Point, along: [f64; 4]) -> Option<[f64; 4]> {
        let t = kernel(self.rows(p)?);
        let n = norm(t);
        if !(n > 0.0 && n.is_finite()) {
            return None;
        }
        let s = if dot(t, along) < 0.0 { -1.0 } else { 1.0 };
        Some(t.map(|v| s * v / n))
    }

    pub(super) fn inside(&self, z: [f64; 4]) -> bool {
        (0..2).all(|i| {
            let u = z[2 + i];
            let slack = 1e-12 * (1.0 + u.abs());
            u >= self.bounds[i][0] - slack && u <= self.bounds[i][1] + slack
        })
    }

    /// Whether a point of the curve lies in the box.
    fn holds(&self, q: &CurvePoint2) -> bool {
        self.inside([
            0.0,
            0.0,
            self.scales[0].to_u(q.params[0]),
            self.scales[1].to_u(q.params[1]),
        ])
    }

    pub(super) fn curve_point(&self, p: &Point, special: Option<Codim2>) -> Result<CurvePoint2> {
        self.curve_point_with(p, special, self.flip(p))
    }

    /// [`Tracer::curve_point`] with the normal-form coefficient at `p` already computed.
    fn curve_point_with(
        &self,
        p: &Point,
        special: Option<Codim2>,
        flip_coefficient: Option<f64>,
    ) -> Result<CurvePoint2> {
        let o = self.at(p.z)?;
        Ok(CurvePoint2 {
            params: self.lambda(p.z),
            start: self.state(p.z),
            multipliers: multipliers(&p.flow),
            amplitude: amplitude(&o, self.state(p.z), self.k, self.opts.periodic.tol)?,
            special,
            flip_coefficient,
        })
    }

    /// On a period-doubling curve, the normal-form coefficient at `p` (None elsewhere, and where
    /// it cannot be computed).
    fn flip(&self, p: &Point) -> Option<f64> {
        if self.kind != CurveKind::PeriodDoubling {
            return None;
        }
        let o = self.at(p.z).ok()?;
        super::flip_coefficient(&o, self.state(p.z), self.k, self.opts.periodic.tol).ok()
    }

    /// The zero of `f` (a function of a corrected point and its tangent) between p (σ = 0,
    /// value fa) and σ_b (value fb), by the Illinois method with a corrector at every trial.
    fn locate(
        &self,
        p: &Point,
        t: [f64; 4],
        sigma_b: f64,
        (fa, fb): (f64, f64),
        f: impl Fn(&Point, [f64; 4]) -> Option<f64>,
    ) -> Result<Option<Point>> {
        let done = |v: f64, width: f64| v == 0.0 || width <= 1e-10;
        let found = crate::roots::illinois((0.0, fa), (sigma_b, fb), 80, done, |sigma| {
            let zp = axpy(p.z, sigma, t);
            let Some(q) = self.correct(zp, t, dot(t, p.z) + sigma)? else {
                return Ok::<_, Error>(None);
            };
            let value = self.tangent(&q, t).and_then(|tq| f(&q, tq));
            Ok(value.map(|v| (v, q)))
        })?;
        Ok(found.map(|(_, q)| q))
    }

    /// The codimension-two points between p and q (tangents t, tq), located, in order.
    /// `flips` are the normal-form coefficients at p and q ([`Tracer::flip`]).
    fn specials_between(
        &self,
        p: &Point,
        t: [f64; 4],
        q: &Point,
        tq: [f64; 4],
        flips: (Option<f64>, Option<f64>),
    ) -> Result<Vec<CurvePoint2>> {
        let sigma_b = dot(t, q.z) - dot(t, p.z);
        let mut found: Vec<(f64, CurvePoint2)> = Vec::new();
        // cusp: the parameter-plane velocity reverses
        let tp = [t[2], t[3]];
        let cusp = |_: &Point, tq: [f64; 4]| Some(tq[2] * tp[0] + tq[3] * tp[1]);
        let (a, b) = (tp[0] * tp[0] + tp[1] * tp[1], tq[2] * tp[0] + tq[3] * tp[1]);
        if self.kind == CurveKind::Fold
            && b < 0.0
            && let Some(s) = self.locate(p, t, sigma_b, (a, b), cusp)?
        {
            found.push((dot(t, s.z), self.curve_point(&s, Some(Codim2::Cusp))?));
        }
        // turning point in λ₂: the tangent's λ₂ part changes sign while the parameter velocity
        // goes on (not reversed, as at a cusp); u₂ is monotone in λ₂, so its extremum is λ₂'s
        if found.is_empty()
            && t[3] * tq[3] < 0.0
            && b > 0.0
            && let Some(s) = self.locate(p, t, sigma_b, (t[3], tq[3]), |_, tq| Some(tq[3]))?
        {
            let point = self.curve_point(&s, Some(Codim2::TurningPoint))?;
            found.push((dot(t, s.z), point));
        }
        // generalised period doubling: the normal-form coefficient changes sign through zero (a
        // change of sign where |c| does not fall below both ends' values is not a zero of c)
        if let (Some(a), Some(b)) = flips
            && (a > 0.0) != (b > 0.0)
        {
            let f = |s: &Point, _: [f64; 4]| self.flip(s);
            if let Some(s) = self.locate(p, t, sigma_b, (a, b), f)?
                && self
                    .flip(&s)
                    .is_some_and(|c| c.abs() <= a.abs().min(b.abs()))
            {
                let point = self.curve_point(&s, Some(Codim2::GeneralisedPeriodDoubling))?;
                found.push((dot(t, s.z), point));
            }
        }
        found.sort_by(|x, y| x.0.total_cmp(&y.0));
        Ok(found.into_iter().map(|f| f.1).collect())
    }

    /// The point on the box's edge between p (inside) and q (outside), corrected with the
    /// parameter that left fixed at its bound.
    fn edge_point(&self, p: &Point, q: &Point) -> Result<Option<CurvePoint2>> {
        let (mut best, mut edge) = (1.0f64, None);
        for i in 0..2 {
            for (b, &bound) in self.bounds[i].iter().enumerate() {
                let (a, c) = (p.z[2 + i], q.z[2 + i]);
                let crosses = if b == 0 { c < bound } else { c > bound };
                if crosses && a != c {
                    let w = (bound - a) / (c - a);
                    if w < best {
                        (best, edge) = (w, Some((i, bound)));
                    }
                }
            }
        }
        let Some((i, bound)) = edge else {
            return Ok(None);
        };
        let guess = axpy(p.z, best, axpy(q.z, -1.0, p.z));
        let mut n = [0.0; 4];
        n[2 + i] = 1.0;
        match self.correct(guess, n, bound)? {
            Some(e) => Ok(Some(self.curve_point(&e, None)?)),
            None => Ok(None),
        }
    }

    /// Follows the curve from p along t until it leaves the box, closes or stalls.
    pub(super) fn trace(&self, mut p: Point, mut t: [f64; 4]) -> Result<(Vec<CurvePoint2>, End)> {
        let (min, max) = (
            self.opts.min_step * self.size,
            self.opts.max_step * self.size,
        );
        let (z0, t0) = (p.z, t);
        let mut ds = self.opts.initial_step * self.size;
        let mut points = Vec::new();
        let mut left = false;
        // the normal-form coefficient at p, computed once per point
        let mut flip_p = self.flip(&p);
        loop {
            if points.len() >= self.opts.max_points {
                return Ok((points, End::MaxPoints));
            }
            let zp = axpy(p.z, ds, t);
            let next = self.correct(zp, t, dot(t, zp))?;
            let accepted = next.and_then(|q| self.tangent(&q, t).map(|tq| (q, tq)));
            let Some((q, tq)) = accepted.filter(|(q, tq)| {
                let turn = (dot(t, *tq) / (norm(t) * norm(*tq)))
                    .clamp(-1.0, 1.0)
                    .acos();
                // the cusp turns the parameter part back but not the whole tangent
                (turn <= self.opts.max_turn && norm(axpy(q.z, -1.0, zp)) <= ds) || ds <= min
            }) else {
                ds *= 0.5;
                if ds < min {
                    let param = self.lambda(p.z)[0];
                    return Ok((points, End::StepTooSmall { param }));
                }
                continue;
            };
            let flip_q = self.flip(&q);
            let specials = self.specials_between(&p, t, &q, tq, (flip_p, flip_q))?;
            points.extend(specials.into_iter().filter(|s| self.holds(s)));
            if !self.inside(q.z) {
                points.extend(self.edge_point(&p, &q)?);
                return Ok((points, End::Reached));
            }
            // another point of the kind this curve was born at, within a step
            if let Some((_, end)) = self
                .terminals
                .iter()
                .find(|(z, _)| norm(axpy(q.z, -1.0, *z)) <= ds)
            {
                points.push(*end);
                return Ok((
                    points,
                    End::Rejoined {
                        param: end.params[0],
                    },
                ));
            }
            let from_start = norm(axpy(q.z, -1.0, z0));
            // back at the start, and heading the way it first went: another branch can pass
            // within a step of the start when steps are long (a box much larger than the curve)
            if left && from_start <= ds && dot(tq, t0) > self.opts.max_turn.cos() {
                return Ok((points, End::Closed));
            }
            left |= from_start > 3.0 * ds;
            points.push(self.curve_point_with(&q, None, flip_q)?);
            self.opts.traced();
            ds = if q.iterations <= 3 {
                (ds * 1.5).min(max)
            } else {
                (ds * 0.7).max(min)
            };
            p = q;
            t = tq;
            flip_p = flip_q;
        }
    }
}

/// Follows the curve of `kind` in `params` through the orbit of period k·2π/ω of `o` that starts
/// near `start` at phase 0, a point of that kind (a fold or a period doubling located by
/// [`continue_orbit`](super::continue_orbit) in `params[0]`), in both directions within `box2`.
/// The start is first corrected onto the curve with `params[1]` fixed; a start that is not a
/// point of that kind is refused with the reason.
///
/// ```
/// use hdgear::{Params, params::Param};
/// use hdgear::periodic::{Box2, ContinuationOptions, CurveKind, Scale, Special, continue_curve,
///     frequency_response};
/// // the study's point with γ = 30: the frequency response's two folds near ω ≈ 8
/// let p = Params { gamma: 30.0, ..Params::default() };
/// let r = frequency_response(&p, Some((4.0, 12.0)), &ContinuationOptions::default()).unwrap();
/// let fold = r.specials().find(|q| q.special == Some(Special::Fold)).unwrap();
/// let box2 = Box2 { ranges: [(4.0, 12.0), (10.0, 20.0)], scales: [Scale::Log, Scale::Log] };
/// let o = Params { omega: fold.param, ..p };
/// let c = continue_curve(&o, [Param::Omega, Param::Delta], CurveKind::Fold, 1, fold.start,
///     &box2, &ContinuationOptions::default()).unwrap();
/// // one multiplier is +1 all along
/// assert!(c.points.iter().all(|q| q.multipliers[0].log_abs.abs() < 1e-9));
/// ```
pub fn continue_curve<O: Oscillator>(
    o: &O,
    params: [O::Param; 2],
    kind: CurveKind,
    k: u32,
    start: [f64; 2],
    box2: &Box2,
    opts: &ContinuationOptions,
) -> Result<Curve2<O::Param>> {
    opts.validate()?;
    box2.validate()?;
    super::check_orbit_length(o, params, k, box2)?;
    if params[0] == params[1] {
        return Err(Error::InvalidInput {
            what: "parameters",
            text: format!("{}", params[0]),
            reason: "two different parameters are needed".into(),
        });
    }
    let tr = tracer(o, params, kind, k, start, box2, opts);
    let u = [0, 1].map(|i| box2.scales[i].to_u(o.get(params[i])));
    let z0 = [start[0] / tr.scale, start[1] / tr.scale, u[0], u[1]];
    let bad_start = |reason: String| Error::InvalidInput {
        what: "start",
        text: format!(
            "{} = {}, {} = {}",
            params[0],
            o.get(params[0]),
            params[1],
            o.get(params[1])
        ),
        reason,
    };
    if !tr.inside(z0) {
        return Err(bad_start("outside the box".into()));
    }
    let Some(p) = tr.correct(z0, [0.0, 0.0, 0.0, 1.0], u[1])? else {
        return Err(bad_start(format!(
            "no {} of the period-{k} orbit near it (the corrector did not converge)",
            kind.name()
        )));
    };
    let Some(t) = tr.tangent(&p, [0.0, 0.0, 1.0, 1.0]) else {
        return Err(bad_start(
            "the curve has no tangent there (a singular point)".into(),
        ));
    };
    let first = tr.curve_point(&p, None)?;
    let (mut back, end0) = tr.trace(p, t.map(|v| -v))?;
    let (forward, end1) = if end0 == End::Closed {
        (Vec::new(), End::Closed)
    } else {
        tr.trace(p, t)?
    };
    back.reverse();
    back.push(first);
    back.extend(forward);
    Ok(Curve2 {
        kind,
        params,
        subharmonic: k,
        points: back,
        ends: [end0, end1],
    })
}

/// The point of the curve of `kind` with `params[fixed]` = `value`, corrected from `near` (a
/// point of the curve close to it, e.g. of a [`Curve2`] from [`continue_curve`] with the same
/// `o`, `params`, `k` and `box2`): where the curve crosses a line of the parameter plane, or a
/// restart from any point of an output file.
#[allow(clippy::too_many_arguments)]
pub fn point_on_curve<O: Oscillator>(
    o: &O,
    params: [O::Param; 2],
    kind: CurveKind,
    k: u32,
    near: &CurvePoint2,
    (fixed, value): (usize, f64),
    box2: &Box2,
    opts: &ContinuationOptions,
) -> Result<CurvePoint2> {
    opts.validate()?;
    box2.validate()?;
    let tr = tracer(o, params, kind, k, near.start, box2, opts);
    let z = [
        near.start[0] / tr.scale,
        near.start[1] / tr.scale,
        box2.scales[0].to_u(near.params[0]),
        box2.scales[1].to_u(near.params[1]),
    ];
    let mut n = [0.0; 4];
    n[2 + fixed.min(1)] = 1.0;
    let u = box2.scales[fixed.min(1)].to_u(value);
    match tr.correct(z, n, u)? {
        Some(p) => tr.curve_point(&p, None),
        None => Err(Error::InvalidInput {
            what: "point on curve",
            text: format!("{} = {value}", params[fixed.min(1)]),
            reason: format!("the corrector did not converge from {:?}", near.params),
        }),
    }
}

pub(super) fn tracer<'a, O: Oscillator>(
    o: &'a O,
    params: [O::Param; 2],
    kind: CurveKind,
    k: u32,
    start: [f64; 2],
    box2: &Box2,
    opts: &'a ContinuationOptions,
) -> Tracer<'a, O> {
    let bounds = [0, 1].map(|i| {
        let (lo, hi) = box2.ranges[i];
        [box2.scales[i].to_u(lo), box2.scales[i].to_u(hi)]
    });
    let size =
        ((bounds[0][1] - bounds[0][0]).powi(2) + (bounds[1][1] - bounds[1][0]).powi(2)).sqrt();
    let scale = start[0].abs().max(start[1].abs()).max(1.0);
    Tracer {
        o,
        params,
        kind,
        k,
        opts,
        scales: box2.scales,
        bounds,
        size,
        scale,
        terminals: Vec::new(),
    }
}

/// A point of a two-parameter curve as a row of its output file.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, crate::output::Record)]
pub struct CurveRow {
    /// Index of the curve.
    pub curve: usize,
    /// fold or period-doubling.
    pub kind: &'static str,
    /// k (period k·2π/ω).
    pub subharmonic: u32,
    /// λ₁.
    pub param1: f64,
    /// λ₂.
    pub param2: f64,
    /// x at phase 0.
    pub x0: f64,
    /// x' at phase 0.
    pub xdot0: f64,
    /// x_max − x_min.
    pub peak_to_peak: f64,
    /// Largest |x'|.
    pub max_abs_xdot: f64,
    /// ln |m1| (the larger multiplier).
    pub ln_abs_m1: f64,
    /// arg m1.
    pub arg_m1: f64,
    /// ln |m2|.
    pub ln_abs_m2: f64,
    /// arg m2.
    pub arg_m2: f64,
    /// cusp, generalised-period-doubling or empty.
    pub special: &'static str,
    /// The period doubling's normal-form coefficient (period-doubling curves; empty on folds).
    pub flip_coefficient: Option<f64>,
}

impl CurveRow {
    /// The rows of curve number `i`.
    pub fn of<P>(i: usize, c: &Curve2<P>) -> impl Iterator<Item = CurveRow> + '_ {
        c.points.iter().map(move |q| CurveRow {
            curve: i,
            kind: c.kind.name(),
            subharmonic: c.subharmonic,
            param1: q.params[0],
            param2: q.params[1],
            x0: q.start[0],
            xdot0: q.start[1],
            peak_to_peak: q.amplitude.peak_to_peak,
            max_abs_xdot: q.amplitude.max_abs_xdot,
            ln_abs_m1: q.multipliers[0].log_abs,
            arg_m1: q.multipliers[0].arg,
            ln_abs_m2: q.multipliers[1].log_abs,
            arg_m2: q.multipliers[1].arg,
            special: q.special.map_or("", Codim2::name),
            flip_coefficient: q.flip_coefficient,
        })
    }
}

impl<P: Copy + PartialEq + std::fmt::Debug + std::fmt::Display + Send + Sync> Curve2<P> {
    /// Where the curve crosses the line λ_fixed = `value` of the parameter plane, each crossing
    /// corrected onto it ([`point_on_curve`]) from the curve's point before it; `o` is any set
    /// of the curve's other parameters, `box2` and `opts` those it was followed with.
    pub fn crossings<O: Oscillator<Param = P>>(
        &self,
        o: &O,
        (fixed, value): (usize, f64),
        box2: &Box2,
        opts: &ContinuationOptions,
    ) -> Result<Vec<CurvePoint2>> {
        let j = fixed.min(1);
        let off = |q: &CurvePoint2| q.params[j] - value;
        // in order along the curve: every point on the line (a curve's ends on the box's edge
        // among them, its first point too), and the nearer point of each pair the line passes
        // between
        let pts = &self.points;
        (0..pts.len())
            .filter_map(|i| {
                if off(&pts[i]) == 0.0 {
                    return Some(&pts[i]);
                }
                let next = pts.get(i + 1).filter(|q| off(&pts[i]) * off(q) < 0.0)?;
                Some(if off(&pts[i]).abs() < off(next).abs() {
                    &pts[i]
                } else {
                    next
                })
            })
            .map(|near| {
                point_on_curve(
                    o,
                    self.params,
                    self.kind,
                    self.subharmonic,
                    near,
                    (j, value),
                    box2,
                    opts,
                )
            })
            .collect()
    }
}
