//! The one seam the periodic machinery needs: a forced second-order oscillator
//! x'' = a(s, x, x') whose forcing depends on time only through its phase s = ωτ, with the
//! derivatives shooting, monodromy and continuation use. [`Params`] (the study's model) is one;
//! any forced oscillator can be another (the tests use a lightly damped Duffing oscillator).

use super::Flow;
use crate::error::Result;
use crate::integrate::Options;
use crate::model::switching::Pieces;
use crate::model::{Model, ModelParam};
use crate::params::{Param, Params};
use std::fmt;

/// A forced oscillator x'' = a(s, x, x'), s = ωτ the forcing phase (period 2π in s), with
/// parameters that continuation can vary.
///
/// Working in the phase s instead of τ fixes the period at 2π·k whatever ω is, so ω is a
/// parameter like the others: in s the system reads dx/ds = x'/ω, dx'/ds = a/ω, and its
/// derivative with respect to ω at fixed s is −(x', a)/ω² (the forcing frequency enters only
/// through the time scale; implementations must keep `a` free of ω other than through `s`).
pub trait Oscillator: Copy + Send + Sync {
    /// The name of one parameter.
    type Param: Copy + PartialEq + fmt::Debug + fmt::Display + Send + Sync;
    /// The forcing frequency ω.
    fn omega(&self) -> f64;
    /// x'' at phase s, position x and velocity v = dx/dτ.
    fn accel(&self, phase: f64, x: f64, v: f64) -> f64;
    /// (∂a/∂x, ∂a/∂v).
    fn accel_gradient(&self, phase: f64, x: f64, v: f64) -> [f64; 2];
    /// ∂a/∂λ at fixed phase, x, v (0 for the frequency, see above).
    fn accel_derivative(&self, param: Self::Param, phase: f64, x: f64, v: f64) -> f64;
    /// The value of a parameter.
    fn get(&self, param: Self::Param) -> f64;
    /// The oscillator with one parameter changed, checked (an error names the value).
    fn with(&self, param: Self::Param, value: f64) -> Result<Self>;
    /// Whether `param` is the forcing frequency ω.
    fn is_frequency(param: Self::Param) -> bool;
    /// Checks every parameter (an error names the value).
    fn check(&self) -> Result<()>;
    /// Whether [`Oscillator::phase_taylor`] gives Taylor coefficients (then the periodic
    /// machinery integrates with Taylor's method, else with DOP853).
    const TAYLOR: bool = false;
    /// The normalised Taylor coefficients c\[0..=order\] in the phase of the solution through
    /// `y` at phase `s`, for Taylor's method: with N = 2 of (x, x'); with N = 8 of
    /// (x, x', Φ by columns, w) as the periodic machinery integrates them (Φ' = J Φ/ω,
    /// w' = J w/ω + ∂f/∂λ for `param`). Returns false, the default, when not provided.
    fn phase_taylor<const N: usize>(
        &self,
        _param: Option<Self::Param>,
        _s: f64,
        _y: &[f64; N],
        _order: usize,
        _c: &mut [[f64; N]],
    ) -> bool {
        false
    }
    /// The pieces of the motion of an oscillator whose vector field switches (friction that
    /// sticks, [`Pieces`]): its state is then integrated switch by switch. `None`, the default,
    /// for a smooth oscillator.
    fn pieces(&self) -> Option<Pieces> {
        None
    }
    /// [`Oscillator::pieces`]' flow with its monodromy Φ and parameter sensitivity w, carried
    /// across each switch by its saltation matrix (the guide's periodic page). `None`, the default,
    /// for a smooth oscillator, whose variational equations are integrated with the state.
    fn switching_flow(
        &self,
        _param: Option<Self::Param>,
        _s0: f64,
        _y0: [f64; 2],
        _span: f64,
        _tol: Options,
    ) -> Option<Result<Flow>> {
        None
    }
    /// Benettin's largest Lyapunov exponent ([`super::lyapunov`]) of each `(oscillator, start,
    /// (discard, span))`, several at once: one by one by default; [`Params`] with Taylor's method
    /// runs them through the batch integrator ([`super::lyapunov_many`]).
    fn lyapunov_each(
        items: &[(Self, [f64; 2], (f64, f64))],
        tol: Options,
    ) -> Result<Vec<Result<f64>>> {
        Ok(lyapunov_one_by_one(items, tol))
    }
}

/// [`Oscillator::lyapunov_each`] one item after the other ([`super::lyapunov`]).
fn lyapunov_one_by_one<O: Oscillator>(
    items: &[(O, [f64; 2], (f64, f64))],
    tol: Options,
) -> Vec<Result<f64>> {
    items
        .iter()
        .map(|(o, y, (discard, span))| super::lyapunov(o, *y, *discard, *span, tol))
        .collect()
}

impl Oscillator for Params {
    type Param = Param;
    fn omega(&self) -> f64 {
        self.omega
    }
    #[inline(always)]
    fn accel(&self, phase: f64, x: f64, v: f64) -> f64 {
        self.forcing(libm::sin(phase)) - v - self.g(x)
    }
    #[inline(always)]
    fn accel_gradient(&self, _phase: f64, x: f64, _v: f64) -> [f64; 2] {
        [-self.g_prime(x), -1.0]
    }
    /// −x³ (α), −(x − ε) (γ), γ (ε), 1 (μ), sin s (δ), 0 (ω).
    fn accel_derivative(&self, param: Param, phase: f64, x: f64, _v: f64) -> f64 {
        match param {
            Param::Alpha => -x * x * x,
            Param::Gamma => -(x - self.eps),
            Param::Eps => self.gamma,
            Param::Mu => 1.0,
            Param::Delta => libm::sin(phase),
            Param::Omega => 0.0,
        }
    }
    fn get(&self, param: Param) -> f64 {
        self.value(param)
    }
    fn with(&self, param: Param, value: f64) -> Result<Params> {
        let q = Params::with(*self, param, value);
        q.validate()?;
        Ok(q)
    }
    fn is_frequency(param: Param) -> bool {
        param == Param::Omega
    }
    fn check(&self) -> Result<()> {
        self.validate().map(|_| ())
    }
    const TAYLOR: bool = true;
    fn lyapunov_each(
        items: &[(Self, [f64; 2], (f64, f64))],
        tol: Options,
    ) -> Result<Vec<Result<f64>>> {
        if tol.method != crate::integrate::Method::Taylor {
            return Ok(lyapunov_one_by_one(items, tol));
        }
        let points: Vec<Params> = items.iter().map(|i| i.0).collect();
        let starts: Vec<[f64; 2]> = items.iter().map(|i| i.1).collect();
        let spans: Vec<(f64, f64)> = items.iter().map(|i| i.2).collect();
        super::lyapunov_many(&points, &starts, &spans, tol)
    }
    /// In the phase, with k = 1/ω: x' = k v, v' = k a, a = μ + δ sin s − v − g(x); the
    /// variations p' = k q, q' = k (−g'(x) p − q) for each column (p, q) of Φ and for w, plus
    /// ∂f/∂λ in w: (−k² v, −k² a) for ω, (0, k ∂a/∂λ) otherwise. Coefficients of x², x³ and
    /// g'(x)·p by Cauchy sums, of sin s in closed form.
    fn phase_taylor<const N: usize>(
        &self,
        param: Option<Param>,
        s: f64,
        y: &[f64; N],
        order: usize,
        c: &mut [[f64; N]],
    ) -> bool {
        use crate::integrate::taylor::{INV, MAX_ORDER, sine_coefficients, square_coefficient};
        let p = self;
        let n = order.min(MAX_ORDER).min(c.len() - 1);
        let k = 1.0 / p.omega;
        if N == 2 {
            // the model's own recurrence in τ = s/ω: the k-th coefficient in s is ω^−k times it
            let mut tau = [[0.0; 2]; MAX_ORDER + 1];
            let model = crate::model::Dimensionless::new(*p);
            crate::integrate::System::taylor(&model, s * k, &[y[0], y[1]], n, &mut tau);
            let mut scale = 1.0;
            for (cj, tj) in c.iter_mut().zip(tau).take(n + 1) {
                cj[0] = tj[0] * scale;
                cj[1] = tj[1] * scale;
                scale *= k;
            }
            return true;
        }
        if N != 8 {
            return false;
        }
        // series of x, x², x³, sin s, a, g'(x), and the columns of each variable (for Cauchy sums)
        let mut col = [[0.0; MAX_ORDER + 1]; 8];
        let (mut x2, mut x3, mut sine, mut acc, mut gp) = (
            [0.0; MAX_ORDER + 1],
            [0.0; MAX_ORDER + 1],
            [0.0; MAX_ORDER + 1],
            [0.0; MAX_ORDER + 1],
            [0.0; MAX_ORDER + 1],
        );
        sine_coefficients(1.0, s, n, &mut sine);
        c[0] = *y;
        for (i, v) in y.iter().enumerate() {
            col[i][0] = *v;
        }
        let first = |j: usize| if j == 0 { 1.0 } else { 0.0 };
        for j in 0..n {
            let x = &col[0];
            x2[j] = square_coefficient(x, j);
            gp[j] = 3.0 * p.alpha * x2[j] - 2.0 * x[j] + first(j) * p.gamma;
            // x³'s sum and the three columns' g'·p sums in one pass, four independent chains
            // (as four loops one after the other, each sum's additions waited on each other:
            // 57 % of a frequency response's time was this function)
            let mut sums = [0.0; 4];
            for i in 0..=j {
                sums[0] += x2[i] * x[j - i];
                sums[1] += gp[i] * col[2][j - i];
                sums[2] += gp[i] * col[4][j - i];
                sums[3] += gp[i] * col[6][j - i];
            }
            x3[j] = sums[0];
            acc[j] = first(j) * (p.mu + p.gamma * p.eps) + p.delta * sine[j]
                - col[1][j]
                - (p.alpha * x3[j] - x2[j] + p.gamma * x[j]);
            let mut next = [0.0; 8];
            next[0] = k * col[1][j];
            next[1] = k * acc[j];
            if N == 8 {
                // Φ's two columns and w: p' = k q, q' = k (−g' p − q)
                for (m, (pi, qi)) in [(2, 3), (4, 5), (6, 7)].into_iter().enumerate() {
                    next[pi] = k * col[qi][j];
                    next[qi] = k * (-sums[m + 1] - col[qi][j]);
                }
                let (d1, d2) = match param {
                    None => (0.0, 0.0),
                    Some(Param::Omega) => (-k * k * col[1][j], -k * k * acc[j]),
                    Some(q) => {
                        let da = match q {
                            Param::Alpha => -x3[j],
                            Param::Gamma => -(col[0][j] - first(j) * p.eps),
                            Param::Eps => first(j) * p.gamma,
                            Param::Mu => first(j),
                            Param::Delta => sine[j],
                            Param::Omega => 0.0,
                        };
                        (0.0, k * da)
                    }
                };
                next[6] += d1;
                next[7] += d2;
            }
            for i in 0..N {
                col[i][j + 1] = next[i] * INV[j];
                c[j + 1][i] = col[i][j + 1];
            }
        }
        true
    }
}

/// A model assembled from terms, through the same seam: every derivative from its terms. A
/// model with internal states (memory) is refused by [`Oscillator::check`]: its orbits live in
/// more than the plane (x, x') this seam shoots in.
impl Oscillator for Model {
    type Param = ModelParam;
    fn omega(&self) -> f64 {
        self.forcing()[2]
    }
    fn accel(&self, phase: f64, x: f64, v: f64) -> f64 {
        Model::accel(self, phase, x, v)
    }
    fn accel_gradient(&self, _phase: f64, x: f64, v: f64) -> [f64; 2] {
        Model::accel_gradient(self, x, v)
    }
    fn accel_derivative(&self, param: ModelParam, phase: f64, x: f64, v: f64) -> f64 {
        Model::accel_derivative(self, param, phase, x, v)
    }
    fn get(&self, param: ModelParam) -> f64 {
        Model::get(self, param)
    }
    fn with(&self, param: ModelParam, value: f64) -> Result<Model> {
        Model::with(self, param, value)
    }
    fn is_frequency(param: ModelParam) -> bool {
        param.is_frequency()
    }
    fn pieces(&self) -> Option<Pieces> {
        Pieces::new(self)
    }
    fn switching_flow(
        &self,
        param: Option<ModelParam>,
        s0: f64,
        y0: [f64; 2],
        span: f64,
        tol: Options,
    ) -> Option<Result<Flow>> {
        let pieces = Pieces::new(self)?;
        Some(super::saltation::flow(&pieces, param, s0, y0, span, tol))
    }
    fn check(&self) -> Result<()> {
        if self.dim() > 2 {
            let own: Vec<String> = self
                .terms()
                .filter_map(|t| {
                    t.state()
                        .map(|s| format!("its {} term's {}", t.kind(), s.name))
                })
                .collect();
            return Err(crate::error::Error::InvalidInput {
                what: "model",
                text: self.equation(),
                reason: format!(
                    "no periodic orbit is computed for a state beyond (x, x'): {} makes the \
                     orbit live outside the plane the shooting works in",
                    own.join(" and ")
                ),
            });
        }
        Model::check(self)
    }
}
