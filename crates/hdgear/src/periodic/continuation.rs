//! Pseudo-arclength continuation of periodic orbits, with folds of cycles, period doublings and
//! branch switching onto the doubled branch.
//!
//! **Unknowns** z = (x₀, x₀', u): the orbit's start at phase 0 and the parameter coordinate u = λ
//! (or ln λ with [`Scale::Log`]). **Equations**: P(z) = φ_{2πk}(x₀, x₀'; λ) − (x₀, x₀') = 0, and
//! the arclength condition t·(z − z_pred) = 0 with t the unit tangent at the last point. The
//! Jacobian [M − I | ∂φ/∂u] comes from the variational equations (M) and the parameter
//! sensitivity integrated with them (∂φ/∂u), never from finite differences; the tangent is the
//! cross product of its two rows (a 2 × 3 matrix has a one-dimensional kernel at regular points
//! and at folds alike).
//!
//! **Step control**: the step grows by 1.5 after a corrector that converged in ≤ 2 iterations,
//! shrinks by 0.7 after ≥ 5, halves after a failure or a tangent turn over
//! [`ContinuationOptions::max_turn`], down to [`ContinuationOptions::min_step`].
//!
//! **Special points.** The multipliers of the forced model can leave the unit circle only as real
//! numbers: their product is det M = e^{−kT} < 1 (Liouville, trace −1), so a complex pair has
//! |m| = e^{−kT/2} < 1 and no torus (Neimark–Sacker) bifurcation exists. Two test functions,
//! ψ₊ = det(M − I) (zero at a fold of cycles, or at a branch point if the parameter does not turn
//! back) and ψ₋ = det(M + I) (zero at a period doubling), are symmetric functions of the
//! multipliers and so continuous along the branch, even when a multiplier crosses ±1 and then
//! collides with the other within one step (seen at a fold of a drive's response: a functional of
//! the largest real multiplier alone missed it). A sign change between two points is located by
//! the Illinois method on the arclength, correcting onto the branch at every trial, to
//! |ψ| ≤ 1e-10. A pair of crossings closer than one step (a bubble narrower than the step) is not
//! seen; [`ContinuationOptions::max_step`] bounds how narrow.
//!
//! **Branch switching** at a period doubling: the doubled branch (period 2k) leaves the point
//! perpendicular to the parameter axis along the eigenvector v of M for −1 (for the 2k-map the
//! point is a symmetric pitchfork), so the first doubled point is corrected from (x* + h·v, u*)
//! with the hyperplane v·(x − x* − h·v) = 0, and then followed like any branch.
//!
//! ```
//! use hdgear::{Params, params::Param, periodic::{ContinuationOptions, continue_orbit}};
//! // the study's point followed in μ from 0.07 to 0.2
//! let p = Params::default();
//! let b = continue_orbit(&p, Param::Mu, 1, None, 0.2, &ContinuationOptions::default()).unwrap();
//! assert!((b.points.last().unwrap().param - 0.2).abs() < 1e-12);
//! assert!(b.points.iter().all(|q| q.stable));
//! ```
//!
//! **Why one file.** The predictor, the corrector, the step control and the location of special
//! points share the tracer's private state; the branch types, the two-parameter curves and the
//! switching at special points live apart.

use super::branch::*;
use super::{Amplitude, Oscillator, Scale, Solved, amplitude, flow};
use crate::error::{Error, Result, SolverError};
use std::f64::consts::{PI, TAU};

/// A corrected point: z, the flow from it, the corrector's iterations.
struct Point {
    z: [f64; 3],
    flow: super::Flow,
    iterations: usize,
}

/// Everything fixed along one continuation.
struct Tracer<'a, O: Oscillator> {
    o: &'a O,
    param: O::Param,
    k: u32,
    opts: &'a ContinuationOptions,
    /// The range in u, low and high.
    bounds: [f64; 2],
    /// |range| in u.
    range: f64,
    /// The range in λ, low and high (exactly as given).
    lambda_bounds: [f64; 2],
    /// The state's scale S: the unknowns are (x₀/S, x₀'/S, u), so that the arclength weighs the
    /// state and the parameter alike whatever the response's size (set from the first orbit:
    /// its largest |x|, |x'| or peak-to-peak x, at least 1).
    scale: f64,
    /// Points where the branch ends if it passes through them: (z, the point, why).
    terminals: Vec<([f64; 3], OrbitPoint, End)>,
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// Solves a 3 × 3 system by Gaussian elimination with partial pivoting.
fn solve3(mut a: [[f64; 3]; 3], mut b: [f64; 3]) -> Option<[f64; 3]> {
    for c in 0..3 {
        let p = (c..3).max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))?;
        if a[p][c] == 0.0 || !a[p][c].is_finite() {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..3 {
            let f = a[r][c] / a[c][c];
            let pivot = a[c];
            for (x, y) in a[r][c..].iter_mut().zip(&pivot[c..]) {
                *x -= f * y;
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = [0.0; 3];
    for r in (0..3).rev() {
        let s: f64 = (r + 1..3).map(|j| a[r][j] * x[j]).sum();
        x[r] = (b[r] - s) / a[r][r];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

impl<O: Oscillator> Tracer<'_, O> {
    fn at(&self, u: f64) -> Result<O> {
        self.o.with(self.param, self.opts.scale.to_lambda(u))
    }

    fn flow_at(&self, z: [f64; 3]) -> Result<super::Flow> {
        let o = self.at(z[2])?;
        let mut f = flow(
            &o,
            Some(self.param),
            0.0,
            self.state(z),
            TAU * f64::from(self.k),
            self.opts.periodic.tol,
        )?;
        // ∂(φ/S)/∂u
        let d = self.opts.scale.dlambda(z[2]) / self.scale;
        f.w = [f.w[0] * d, f.w[1] * d];
        Ok(f)
    }

    /// The state (x₀, x₀') of the unknowns z.
    fn state(&self, z: [f64; 3]) -> [f64; 2] {
        [self.scale * z[0], self.scale * z[1]]
    }

    /// The unknowns of state y at parameter coordinate u.
    fn unknowns(&self, y: [f64; 2], u: f64) -> [f64; 3] {
        [y[0] / self.scale, y[1] / self.scale, u]
    }

    /// Newton on P(z) = 0, n·z = c from z. `Ok(None)` when it does not converge (the caller
    /// shrinks the step); errors of the integration itself propagate.
    fn correct(&self, mut z: [f64; 3], n: [f64; 3], c: f64) -> Result<Option<Point>> {
        for iterations in 0..=self.opts.max_corrector {
            if self.at(z[2]).is_err() {
                return Ok(None);
            }
            let f = match self.flow_at(z) {
                Ok(f) => f,
                Err(Error::Solver(
                    SolverError::StepSizeTooSmall { .. } | SolverError::BlowUp { .. },
                )) => {
                    return Ok(None);
                }
                Err(e) => return Err(e),
            };
            let y = self.state(z);
            let r = [f.y[0] - y[0], f.y[1] - y[1]];
            let g = dot(n, z) - c;
            if super::converged(r, y) && g.abs() <= 1e-12 * (1.0 + norm(z)) {
                return Ok(Some(Point {
                    z,
                    flow: f,
                    iterations,
                }));
            }
            if iterations == self.opts.max_corrector {
                break;
            }
            let Some(a) = f.m_minus_i() else {
                return Ok(None);
            };
            let j = [
                [a[0][0], a[0][1], f.w[0]],
                [a[1][0], a[1][1], f.w[1]],
                [n[0], n[1], n[2]],
            ];
            // the scaled residual (φ − y)/S has the Jacobian [M − I | ∂(φ/S)/∂u] in (y/S, u)
            let Some(d) = solve3(j, [-r[0] / self.scale, -r[1] / self.scale, -g]) else {
                return Ok(None);
            };
            z = [z[0] + d[0], z[1] + d[1], z[2] + d[2]];
            if !z.iter().all(|v| v.is_finite()) {
                return Ok(None);
            }
        }
        Ok(None)
    }

    /// The unit tangent at a point: the kernel of [M − I | ∂φ/∂u], oriented along `along`.
    fn tangent(&self, p: &Point, along: [f64; 3]) -> Option<[f64; 3]> {
        let a = p.flow.m_minus_i()?;
        let (r0, r1) = (
            [a[0][0], a[0][1], p.flow.w[0]],
            [a[1][0], a[1][1], p.flow.w[1]],
        );
        let t = [
            r0[1] * r1[2] - r0[2] * r1[1],
            r0[2] * r1[0] - r0[0] * r1[2],
            r0[0] * r1[1] - r0[1] * r1[0],
        ];
        let n = norm(t);
        if !(n > 0.0 && n.is_finite()) {
            return None;
        }
        let s = if dot(t, along) < 0.0 { -1.0 } else { 1.0 };
        Some(t.map(|v| s * v / n))
    }

    fn branch_point(&self, p: &Point, special: Option<Special>) -> Result<OrbitPoint> {
        let multipliers = super::multipliers(&p.flow);
        let o = self.at(p.z[2])?;
        let critical_direction = special.map(|s| critical_direction(&p.flow, s));
        let tol = self.opts.periodic.tol;
        // at a doubling of this branch's orbit (a multiplier −1; the doubled branch's own first
        // point, the same doubling seen over twice the period, has +1)
        let flip_coefficient = match special {
            Some(Special::PeriodDoubling) if multipliers.iter().any(|m| m.arg == PI) => {
                Some(super::flip_coefficient(&o, self.state(p.z), self.k, tol)?)
            }
            _ => None,
        };
        Ok(OrbitPoint {
            param: self.opts.scale.to_lambda(p.z[2]),
            start: self.state(p.z),
            multipliers,
            stable: multipliers.iter().all(|m| m.log_abs < 0.0),
            amplitude: amplitude(&o, self.state(p.z), self.k, self.opts.periodic.tol)?,
            special,
            critical_direction,
            flip_coefficient,
        })
    }

    /// Follows the branch from `p` with tangent `t` until the range ends.
    fn trace(
        &self,
        mut p: Point,
        mut t: [f64; 3],
        mut points: Vec<OrbitPoint>,
    ) -> Result<OrbitBranch<O::Param>> {
        let (min, max) = (
            self.opts.min_step * self.range,
            self.opts.max_step * self.range,
        );
        let mut ds = self.opts.initial_step * self.range;
        let mut psi = test_functions(&p.flow);
        let mut first_terminal: Option<([f64; 3], OrbitPoint, End)> = None;
        loop {
            if points.len() >= self.opts.max_points {
                return Ok(self.finish(points, End::MaxPoints));
            }
            let zp = [p.z[0] + ds * t[0], p.z[1] + ds * t[1], p.z[2] + ds * t[2]];
            let next = self.correct(zp, t, dot(t, zp))?;
            let accepted = next.and_then(|q| self.tangent(&q, t).map(|tq| (q, tq)));
            // a corrector that lands far from the predictor (on the hyperplane, but on another
            // branch) or a sharp turn of the tangent: the step was too long
            let Some((q, tq)) = accepted.filter(|(q, tq)| {
                let turn = dot(t, *tq).clamp(-1.0, 1.0).acos();
                (turn <= self.opts.max_turn && norm(sub(q.z, zp)) <= ds) || ds <= min
            }) else {
                ds *= 0.5;
                if ds < min {
                    let param = self.opts.scale.to_lambda(p.z[2]);
                    return Ok(self.finish(points, End::StepTooSmall { param }));
                }
                continue;
            };
            let psi_q = test_functions(&q.flow);
            points.extend(self.specials_between(&p, t, &q, tq, psi, psi_q)?);
            if let Some((_, point, end)) = self.terminal_hit(first_terminal.as_ref(), &p, &q) {
                points.push(*point);
                return Ok(self.finish(points, *end));
            }
            if first_terminal.is_none() && points.len() >= 3 {
                // the start becomes a terminal once the branch is more than two steps from it
                let b = points[0];
                let z0 = self.unknowns(b.start, self.opts.scale.to_u(b.param));
                if norm(sub(q.z, z0)) > 2.0 * norm(sub(q.z, p.z)) {
                    let closing = OrbitPoint {
                        special: None,
                        flip_coefficient: None,
                        ..b
                    };
                    first_terminal = Some((z0, closing, End::Closed));
                }
            }
            if !self.inside(q.z[2]) {
                points.extend(self.edge_point(&p, &q)?);
                return Ok(self.finish(points, End::Reached));
            }
            points.push(self.branch_point(&q, None)?);
            self.opts.traced();
            ds = if q.iterations <= 2 {
                (ds * 1.5).min(max)
            } else if q.iterations >= 5 {
                (ds * 0.7).max(min)
            } else {
                ds
            };
            psi = psi_q;
            p = q;
            t = tq;
        }
    }

    /// The special points between p and q (tangents t, tq; test functions psi, psi_q), located
    /// and in arclength order.
    fn specials_between(
        &self,
        p: &Point,
        t: [f64; 3],
        q: &Point,
        tq: [f64; 3],
        psi: [f64; 2],
        psi_q: [f64; 2],
    ) -> Result<Vec<OrbitPoint>> {
        let mut found = Vec::new();
        for (i, kind) in [(0, Special::BranchPoint), (1, Special::PeriodDoubling)] {
            let (a, b) = (psi[i], psi_q[i]);
            if (a > 0.0) != (b > 0.0) {
                // a multiplier through +1 where the parameter turns back is a fold
                let kind = if i == 0 && t[2] * tq[2] < 0.0 {
                    Special::Fold
                } else {
                    kind
                };
                let located = self.locate(p, t, dot(t, q.z) - dot(t, p.z), i, a, b)?;
                if let Some((sigma, s)) = located.filter(|(_, s)| {
                    // a root of the test function, not a jump across 0: a grazing rest of a
                    // model whose friction sticks makes the flow map non-differentiable, and
                    // the multipliers jump there (the locator's bracket shrinks onto the jump
                    // with the value staying at the jump's size, while at a root it falls to
                    // the corrector's 1e-10)
                    test_functions(&s.flow)[i].abs() <= (JUMP * a.abs().max(b.abs())).max(1e-10)
                }) {
                    found.push((sigma, s, kind));
                }
            }
        }
        found.sort_by(|a, b| a.0.total_cmp(&b.0));
        found
            .into_iter()
            .filter(|(_, s, _)| self.inside(s.z[2]))
            .map(|(_, s, kind)| self.branch_point(&s, Some(kind)))
            .collect()
    }

    /// The terminal (or `extra`) the chord from p to q passes through, if any: within a quarter
    /// of the chord's length of it, beyond p.
    fn terminal_hit<'t>(
        &'t self,
        extra: Option<&'t ([f64; 3], OrbitPoint, End)>,
        p: &Point,
        q: &Point,
    ) -> Option<&'t ([f64; 3], OrbitPoint, End)> {
        let chord = sub(q.z, p.z);
        self.terminals.iter().chain(extra).find(|(z, _, _)| {
            let rel = sub(*z, p.z);
            let w = (dot(rel, chord) / dot(chord, chord)).clamp(0.0, 1.0);
            let off = sub(rel, chord.map(|c| w * c));
            w > 0.0 && norm(off) <= 0.25 * norm(chord)
        })
    }

    /// The point on the end of the range between p (inside) and q (outside), corrected with the
    /// parameter fixed at the end, which it carries exactly.
    fn edge_point(&self, p: &Point, q: &Point) -> Result<Option<OrbitPoint>> {
        let high = q.z[2] > self.bounds[1];
        let edge = self.bounds[usize::from(high)];
        let w = (edge - p.z[2]) / (q.z[2] - p.z[2]);
        let guess = [
            p.z[0] + w * (q.z[0] - p.z[0]),
            p.z[1] + w * (q.z[1] - p.z[1]),
            edge,
        ];
        match self.correct(guess, [0.0, 0.0, 1.0], edge)? {
            Some(e) => {
                let mut b = self.branch_point(&e, None)?;
                b.param = self.lambda_bounds[usize::from(high)];
                Ok(Some(b))
            }
            None => Ok(None),
        }
    }

    fn inside(&self, u: f64) -> bool {
        let slack = 1e-12 * (1.0 + u.abs());
        u >= self.bounds[0] - slack && u <= self.bounds[1] + slack
    }

    fn finish(&self, points: Vec<OrbitPoint>, end: End) -> OrbitBranch<O::Param> {
        OrbitBranch {
            param: self.param,
            subharmonic: self.k,
            points,
            end,
        }
    }

    /// The zero of test function `i` between p (σ = 0, value a) and σ_b (value b), by the
    /// Illinois method on σ with a corrector at every trial.
    fn locate(
        &self,
        p: &Point,
        t: [f64; 3],
        sigma_b: f64,
        i: usize,
        a: f64,
        b: f64,
    ) -> Result<Option<(f64, Point)>> {
        let tol = 1e-12 * (1.0 + norm(p.z));
        let done = |f: f64, width: f64| f.abs() <= 1e-10 || width <= tol;
        crate::roots::illinois((0.0, a), (sigma_b, b), 60, done, |sigma| {
            let zp = [
                p.z[0] + sigma * t[0],
                p.z[1] + sigma * t[1],
                p.z[2] + sigma * t[2],
            ];
            let q = self.correct(zp, t, dot(t, p.z) + sigma)?;
            Ok(q.map(|q| (test_functions(&q.flow)[i], q)))
        })
    }
}

/// The largest test-function value, relative to its values at the step's ends, at which a
/// located sign change is a root (or at most the locator's own 1e-10): a root is located to
/// 1e-10 in value or to a bracket 1e-12 of the step wide, where a differentiable test function
/// is within about 1e-12 of its change over the step, nine decades below this; a jump across 0
/// keeps a value of the ends' order, three decades above it.
const JUMP: f64 = 1e-3;

/// ψ₊ = det(M − I) = (m1 − 1)(m2 − 1) and ψ₋ = det(M + I) = (m1 + 1)(m2 + 1): symmetric in the
/// multipliers, so continuous along the branch even where a multiplier crosses ±1 and collides
/// with the other within one step; a complex pair contributes |m ∓ 1|² > 0, so a sign change
/// means a real multiplier through ±1. From det M (accumulated) and tr M (normalised), with the
/// scale capped so that e^{700} still fits.
pub(super) fn test_functions(f: &super::Flow) -> [f64; 2] {
    let det = f.det_sign * f.log_det.min(700.0).exp();
    let tr = (f.m[0][0] + f.m[1][1]) * f.log_scale.min(700.0).exp();
    [det - tr + 1.0, det + tr + 1.0]
}

/// The unit eigenvector of M for its multiplier nearest +1 (fold, branch point) or −1.
fn critical_direction(f: &super::Flow, s: Special) -> [f64; 2] {
    let target = if s == Special::PeriodDoubling {
        -1.0
    } else {
        1.0
    };
    // in the normalised m the critical eigenvalue is ±e^{−log_scale}
    let e = target * (-f.log_scale).exp();
    let m = f.m;
    let (v1, v2) = ([m[0][1], e - m[0][0]], [e - m[1][1], m[1][0]]);
    let v = if v1[0].hypot(v1[1]) >= v2[0].hypot(v2[1]) {
        v1
    } else {
        v2
    };
    let n = v[0].hypot(v[1]);
    if n > 0.0 {
        [v[0] / n, v[1] / n]
    } else {
        [1.0, 0.0]
    }
}

/// Follows the periodic orbit of period k·2π/ω of `o` in `param` from its current value to
/// `to`. The first orbit is found by Newton from `guess` (or, when None, from the state after
/// settling from rest for [`super::SETTLE_TIME`]).
pub fn continue_orbit<O: Oscillator>(
    o: &O,
    param: O::Param,
    k: u32,
    guess: Option<[f64; 2]>,
    to: f64,
    opts: &ContinuationOptions,
) -> Result<OrbitBranch<O::Param>> {
    opts.validate()?;
    o.check()?;
    let from = o.get(param);
    let mut tracer = tracer(o, param, k, [from, to], opts)?;
    let Solved { y, .. } = match guess {
        Some(y) => super::newton(o, k, y, &opts.periodic)?,
        None => super::settle_and_solve(o, k, [0.0, 0.0], &opts.periodic)?,
    };
    let extent = amplitude(o, y, k, opts.periodic.tol)?;
    if o.pieces().is_some() && extent.peak_to_peak == 0.0 && extent.max_abs_xdot == 0.0 {
        return Err(Error::InvalidInput {
            what: "periodic orbit",
            text: format!("a rest at x = {}", y[0]),
            reason: "the friction holds the drive at rest all period: every x of its sticking \
                     band is such an orbit, none isolated, so no branch follows from it (a \
                     smaller breakaway or a larger load makes it slip)"
                .into(),
        });
    }
    tracer.scale = state_scale(y, &extent);
    let u = opts.scale.to_u(from);
    let z = tracer.unknowns(y, u);
    let first = tracer
        .correct(z, [0.0, 0.0, 1.0], u)?
        .ok_or(Error::NoConvergence {
            what: "first point of the branch",
            iterations: opts.max_corrector,
            residual: f64::NAN,
        })?;
    let dir = if opts.scale.to_u(to) >= u { 1.0 } else { -1.0 };
    let t = tracer
        .tangent(&first, [0.0, 0.0, dir])
        .ok_or(Error::NoConvergence {
            what: "tangent at the first point (it is a fold)",
            iterations: 0,
            residual: f64::NAN,
        })?;
    let mut start = tracer.branch_point(&first, None)?;
    start.param = from;
    tracer.trace(first, t, vec![start])
}

/// The state scale of a branch from its first orbit (see [`Tracer::scale`]).
fn state_scale(y: [f64; 2], a: &Amplitude) -> f64 {
    [
        y[0].abs(),
        y[1].abs(),
        a.peak_to_peak,
        a.max_abs_xdot,
        a.x_min.abs(),
        a.x_max.abs(),
    ]
    .into_iter()
    .fold(1.0, f64::max)
}

fn tracer<'a, O: Oscillator>(
    o: &'a O,
    param: O::Param,
    k: u32,
    [from, to]: [f64; 2],
    opts: &'a ContinuationOptions,
) -> Result<Tracer<'a, O>> {
    if k == 0 {
        return Err(Error::InvalidOption {
            name: "subharmonic",
            value: 0.0,
            reason: "must be ≥ 1",
        });
    }
    o.with(param, from)?;
    o.with(param, to)?;
    if opts.scale == Scale::Log && !(from > 0.0 && to > 0.0) {
        return Err(Error::InvalidOption {
            name: "to",
            value: if from > 0.0 { to } else { from },
            reason: "a logarithmic continuation needs a positive parameter at both ends",
        });
    }
    let (a, b) = (opts.scale.to_u(from), opts.scale.to_u(to));
    let range = (b - a).abs();
    if !(range > 0.0 && range.is_finite()) {
        return Err(Error::InvalidOption {
            name: "to",
            value: to,
            reason: "must differ from the parameter's current value",
        });
    }
    // the longest forcing period in the range decides the integration budget
    let slowest = if O::is_frequency(param) {
        from.min(to)
    } else {
        o.omega()
    };
    crate::integrate::check_budget(TAU * f64::from(k) / slowest, &opts.periodic.tol)?;
    Ok(Tracer {
        o,
        param,
        k,
        opts,
        bounds: [a.min(b), a.max(b)],
        range,
        scale: 1.0,
        lambda_bounds: [from.min(to), from.max(to)],
        terminals: Vec::new(),
    })
}

/// Starts the doubled branch (period 2k·2π/ω) at a period-doubling point of a branch of period
/// k and follows it, on whichever side of the point it lies, until it leaves `range` (the
/// parameter's [low, high], which must contain the point), closes, or reaches one of the `others`
/// period doublings of the parent branch (a bubble: it ends there, [`End::Rejoined`]). The first
/// point of the result is the period-doubling point itself (seen as a 2k-orbit).
pub fn switch_at_period_doubling<O: Oscillator>(
    o: &O,
    param: O::Param,
    k: u32,
    at: &OrbitPoint,
    others: &[OrbitPoint],
    range: [f64; 2],
    opts: &ContinuationOptions,
) -> Result<OrbitBranch<O::Param>> {
    opts.validate()?;
    let Some(v) = at
        .critical_direction
        .filter(|_| at.special == Some(Special::PeriodDoubling))
    else {
        return Err(Error::InvalidOption {
            name: "at",
            value: at.param,
            reason: "is not a located period-doubling point",
        });
    };
    let mut tracer = tracer(o, param, 2 * k, range, opts)?;
    tracer.scale = state_scale(at.start, &at.amplitude);
    for q in others
        .iter()
        .filter(|q| q.special == Some(Special::PeriodDoubling) && q != &at)
    {
        let z = tracer.unknowns(q.start, opts.scale.to_u(q.param));
        if let Some(c) = tracer.correct(z, [0.0, 0.0, 1.0], z[2])? {
            let end = End::Rejoined { param: q.param };
            tracer.terminals.push((
                z,
                tracer.branch_point(&c, Some(Special::PeriodDoubling))?,
                end,
            ));
        }
    }
    if !tracer.inside(opts.scale.to_u(at.param)) {
        return Err(Error::InvalidOption {
            name: "range",
            value: at.param,
            reason: "must contain the period-doubling point",
        });
    }
    let u = opts.scale.to_u(at.param);
    let star = tracer.unknowns(at.start, u);
    let origin = tracer.correct(star, [0.0, 0.0, 1.0], u)?;
    let mut points = Vec::new();
    if let Some(origin) = &origin {
        let mut b = tracer.branch_point(origin, Some(Special::PeriodDoubling))?;
        b.critical_direction = Some(v);
        points.push(b);
    }
    let n = [v[0], v[1], 0.0];
    let tol = opts.periodic.tol;
    for h in SWITCH_LADDER.map(|f| f * opts.initial_step * tracer.range) {
        let zp = [star[0] + h * v[0], star[1] + h * v[1], u];
        let Some(first) = tracer.correct(zp, n, dot(n, zp))? else {
            continue;
        };
        // landed on the period-k branch again?
        let oz = tracer.at(first.z[2])?;
        let y = tracer.state(first.z);
        if super::minimal_subharmonic(&oz, y, 2 * k, tol)? < 2 * k {
            continue;
        }
        let Some(t) = tracer.tangent(&first, n) else {
            continue;
        };
        points.push(tracer.branch_point(&first, None)?);
        return tracer.trace(first, t, points);
    }
    Err(Error::NoConvergence {
        what: "the doubled branch at a period doubling",
        iterations: opts.max_corrector,
        residual: f64::NAN,
    })
}

/// The first offsets tried off a branch point onto the new branch, in units of the first step:
/// the first step itself, then shorter and longer ones (a corrector that fails from one may
/// converge from the next).
pub(super) const SWITCH_LADDER: [f64; 4] = [1.0, 0.3, 3.0, 0.1];

/// The branch of period k·2π/ω from the parameter's current value to `to`
/// ([`continue_orbit`]), then with `switch` the doubled branch born at each of its period
/// doublings ([`switch_at_period_doubling`], within the range between the two values). A doubled
/// branch that ends at a later period doubling (a bubble) is not traced again from there.
pub fn continue_with_doubled<O: Oscillator>(
    o: &O,
    param: O::Param,
    k: u32,
    to: f64,
    switch: bool,
    opts: &ContinuationOptions,
) -> Result<Vec<OrbitBranch<O::Param>>> {
    let from = o.get(param);
    let mut branches = vec![continue_orbit(o, param, k, None, to, opts)?];
    if !switch {
        return Ok(branches);
    }
    let pds: Vec<OrbitPoint> = branches[0]
        .specials()
        .filter(|q| q.special == Some(Special::PeriodDoubling))
        .copied()
        .collect();
    for pd in &pds {
        let seen = branches[1..].iter().any(|b| {
            b.points
                .last()
                .is_some_and(|q| (q.param - pd.param).abs() <= 1e-6 * (1.0 + pd.param.abs()))
        });
        if !seen {
            let range = [from.min(to), from.max(to)];
            branches.push(switch_at_period_doubling(
                o, param, k, pd, &pds, range, opts,
            )?);
        }
    }
    Ok(branches)
}
