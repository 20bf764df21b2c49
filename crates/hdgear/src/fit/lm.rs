//! Levenberg–Marquardt with box bounds, our own: the fits have a handful of parameters, need
//! bounds (a Stribeck speed stays > 0), a column mask (the profile likelihood holds one parameter
//! fixed) and JᵀJ at the minimum for the covariance; the maintained crates offer either no
//! bounds or a dense-algebra dependency the rest of hdgear does not need. The damping follows
//! Nielsen's rule (Madsen, Nielsen & Tingleff, *Methods for non-linear least squares problems*,
//! 2004, §3.2) with Marquardt's scaling by diag JᵀJ, and a step is projected onto the bounds.

use super::linalg::{cholesky_solve, normal_equations};
use crate::error::Result;
use serde::Serialize;

/// The most iterations of one minimisation: the fits here converge in tens from a start in the
/// bounds; a run that needs more is reported as not converged.
const MAX_ITERATIONS: usize = 400;
/// A step smaller than this fraction of every parameter's scale (its size, or 1e-9 of its
/// bounds' width near 0) ends the iteration: the model then changes by less than its own
/// rounding, far below any noise.
const STEP_TOLERANCE: f64 = 1e-12;
/// An accepted step that lowers the sum of squares by less than this fraction ends it too.
const REDUCTION_TOLERANCE: f64 = 1e-15;

/// A least-squares problem: residuals r(p) (model − data, weighted) and their Jacobian.
pub trait Residuals {
    /// The number of residuals.
    fn residual_count(&self) -> usize;
    /// The number of parameters.
    fn dim(&self) -> usize;
    /// r(p) into `r` and ∂r/∂p into `jac` (row-major, `len` × `dim`); an error where p is
    /// outside the law's domain (a relation between its parameters broken).
    fn eval(&self, p: &[f64], r: &mut [f64], jac: &mut [f64]) -> Result<()>;
}

/// Why a minimisation stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Stop {
    /// The step became negligible.
    Step,
    /// The sum of squares stopped falling.
    Reduction,
    /// The residuals vanished (noise-free data, exact model).
    Exact,
    /// The iteration limit was reached first: not converged.
    Iterations,
}

impl Stop {
    /// Its name, as the JSON writes it.
    pub fn name(self) -> &'static str {
        match self {
            Stop::Step => "step",
            Stop::Reduction => "reduction",
            Stop::Exact => "exact",
            Stop::Iterations => "iterations",
        }
    }
}

/// Where a minimisation ended.
#[derive(Clone, Debug)]
pub(crate) struct Minimum {
    pub(crate) p: Vec<f64>,
    pub(crate) ssr: f64,
    pub(crate) r: Vec<f64>,
    pub(crate) jac: Vec<f64>,
    pub(crate) iterations: usize,
    pub(crate) stop: Stop,
}

/// The columns of J the mask keeps, as a dense m × k matrix.
fn masked(jac: &[f64], n: usize, active: &[usize]) -> Vec<f64> {
    jac.chunks_exact(n)
        .flat_map(|row| active.iter().map(move |&j| row[j]))
        .collect()
}

/// A point with its residuals, Jacobian and sum of squares.
struct Point {
    p: Vec<f64>,
    r: Vec<f64>,
    jac: Vec<f64>,
    ssr: f64,
}

impl Point {
    fn at(problem: &impl Residuals, p: Vec<f64>) -> Result<Point> {
        let (m, n) = (problem.residual_count(), problem.dim());
        let (mut r, mut jac) = (vec![0.0; m], vec![0.0; m * n]);
        problem.eval(&p, &mut r, &mut jac)?;
        let ssr = r.iter().map(|x| x * x).sum();
        Ok(Point { p, r, jac, ssr })
    }

    fn end(self, iterations: usize, stop: Stop) -> Minimum {
        Minimum {
            p: self.p,
            ssr: self.ssr,
            r: self.r,
            jac: self.jac,
            iterations,
            stop,
        }
    }
}

/// The damped Gauss–Newton step h of the active parameters, (A + λ·D)h = −g with D = diag A
/// (floored where a column of J vanishes, so that the matrix stays definite and that
/// parameter's step is 0), and A, g = JᵀJ, Jᵀr; `None` where it cannot be solved.
fn damped_step(a: &[f64], g: &[f64], k: usize, lambda: f64) -> Option<Vec<f64>> {
    let floor = 1e-12 * (0..k).map(|i| a[i * k + i]).fold(0.0, f64::max);
    let mut system = a.to_vec();
    for i in 0..k {
        system[i * k + i] += lambda * a[i * k + i].max(floor);
    }
    let minus_g: Vec<f64> = g.iter().map(|x| -x).collect();
    cholesky_solve(&system, k, &minus_g)
}

/// Minimises ½‖r(p)‖² from `p0` within [lo, hi], varying only the parameters in `active`.
pub(crate) fn minimise(
    problem: &impl Residuals,
    p0: &[f64],
    bounds: &[(f64, f64)],
    active: &[usize],
) -> Result<Minimum> {
    let n = problem.dim();
    let mut at = Point::at(problem, p0.to_vec())?;
    let k = active.len();
    let scale: Vec<f64> = active
        .iter()
        .map(|&j| at.p[j].abs().max(1e-9 * (bounds[j].1 - bounds[j].0)))
        .collect();
    let (mut lambda, mut nu) = (1e-3, 2.0);
    for iteration in 0..MAX_ITERATIONS {
        if at.ssr == 0.0 || k == 0 {
            return Ok(at.end(iteration, Stop::Exact));
        }
        let (a, g) = normal_equations(&masked(&at.jac, n, active), &at.r, k);
        let Some(step) = damped_step(&a, &g, k, lambda) else {
            lambda *= nu;
            nu *= 2.0;
            continue;
        };
        let mut trial = at.p.clone();
        for (i, &j) in active.iter().enumerate() {
            trial[j] = (at.p[j] + step[i]).clamp(bounds[j].0, bounds[j].1);
        }
        let taken: Vec<f64> = active.iter().map(|&j| trial[j] - at.p[j]).collect();
        let negligible = |(i, &j): (usize, &usize)| {
            taken[i].abs() <= STEP_TOLERANCE * at.p[j].abs().max(scale[i])
        };
        if active.iter().enumerate().all(negligible) {
            return Ok(at.end(iteration, Stop::Step));
        }
        let Ok(next) = Point::at(problem, trial) else {
            lambda *= nu;
            nu *= 2.0;
            continue;
        };
        // the fall the linear model predicts for the step taken: −2·hᵀg − hᵀAh
        let predicted: f64 = (0..k)
            .map(|i| {
                let ah: f64 = (0..k).map(|j| a[i * k + j] * taken[j]).sum();
                -2.0 * taken[i] * g[i] - taken[i] * ah
            })
            .sum();
        let rho = (at.ssr - next.ssr) / predicted;
        if next.ssr < at.ssr && rho > 0.0 {
            let fall = at.ssr - next.ssr;
            at = next;
            lambda *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
            nu = 2.0;
            if fall <= REDUCTION_TOLERANCE * at.ssr {
                return Ok(at.end(iteration + 1, Stop::Reduction));
            }
        } else {
            lambda *= nu;
            nu *= 2.0;
        }
    }
    Ok(at.end(MAX_ITERATIONS, Stop::Iterations))
}
