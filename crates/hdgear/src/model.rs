//! Right-hand sides of the models.
//!
//! The dimensionless model in first-order form, with state (x, v = x'):
//!
//! x' = v,  v' = μ + δ sin(ω τ) − v − g(x),  g(x) = α x³ − x² + γ (x − ε).

use crate::integrate::System;
use crate::params::Params;

/// The dimensionless harmonic drive model (SPEC §2) as a [`System`] with state [x, x'].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Dimensionless {
    /// The parameters.
    pub p: Params,
}

impl Dimensionless {
    /// Wraps a parameter set.
    pub fn new(p: Params) -> Self {
        Dimensionless { p }
    }
}

// `libm::sin` (the Rust port of musl's, correctly rounded to within 1 ulp) instead of `f64::sin`:
// the right-hand side is dominated by the sine, and libm's inlines to about 60 % of the glibc
// call's time here (measured: 0.66 ms vs 1.13 ms per 127k calls).
impl System<2> for Dimensionless {
    #[inline(always)]
    fn rhs(&self, t: f64, y: &[f64; 2]) -> [f64; 2] {
        let p = &self.p;
        [y[1], p.forcing(libm::sin(p.omega * t)) - y[1] - p.g(y[0])]
    }
    /// ∂f/∂y = [[0, 1], [−g'(x), −1]] (trace −1 everywhere: SPEC §3).
    fn jacobian(&self, _t: f64, y: &[f64; 2]) -> Option<[[f64; 2]; 2]> {
        Some([[0.0, 1.0], [-self.p.g_prime(y[0]), -1.0]])
    }
    /// x_{k+1} = v_k/(k+1), v_{k+1} = (μ[k=0] + δ s_k − v_k − α(x³)_k + (x²)_k − γ x_k
    /// + γε[k=0])/(k+1), with (x²)_k, (x³)_k Cauchy sums and s_k the coefficients of sin ωt.
    fn taylor(&self, t: f64, y: &[f64; 2], order: usize, c: &mut [[f64; 2]]) -> bool {
        use crate::integrate::taylor::{INV, MAX_ORDER, cauchy, sine_coefficients};
        let p = &self.p;
        let n = order.min(MAX_ORDER).min(c.len() - 1);
        let (mut x, mut x2, mut s) = (
            [0.0; MAX_ORDER + 1],
            [0.0; MAX_ORDER + 1],
            [0.0; MAX_ORDER + 1],
        );
        sine_coefficients(p.omega, t, n, &mut s);
        c[0] = *y;
        x[0] = y[0];
        for k in 0..n {
            // (x²)_k by symmetry: twice the products below the middle, plus the middle square
            let half = k.div_ceil(2);
            let below: f64 = x[..half]
                .iter()
                .zip(x[k + 1 - half..=k].iter().rev())
                .map(|(a, b)| a * b)
                .sum();
            x2[k] = 2.0 * below + if k % 2 == 0 { x[k / 2] * x[k / 2] } else { 0.0 };
            let x3 = cauchy(&x2, &x, k);
            let [xk, vk] = c[k];
            let constant = if k == 0 { p.mu + p.gamma * p.eps } else { 0.0 };
            let acc = constant + p.delta * s[k] - vk - p.alpha * x3 + x2[k] - p.gamma * xk;
            c[k + 1] = [vk * INV[k], acc * INV[k]];
            x[k + 1] = c[k + 1][0];
        }
        true
    }
}
