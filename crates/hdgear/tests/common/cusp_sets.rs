//! Random parameter sets whose settled branch passes the inflection x_i = 1/(3α) through a node
//! part: used by `tests/burst.rs` and by `examples/cusp_survey.rs` (which includes this file).

use hdgear::Params;

/// `n` sets drawn from `seed`: α log-uniform in [1, 30], γ − 1/(3α) log-uniform in `gap`,
/// ε uniform in [0.2, 1], δ log-uniform in [0.3, 30], and μ placing the inflection at the load
/// a_i uniform in [−`a_max`, `a_max`] (ω = 0.01).
pub fn near_cusp_sets(n: usize, mut seed: u64, gap: (f64, f64), a_max: f64) -> Vec<Params> {
    let mut u = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let log_u = |u: f64, (lo, hi): (f64, f64)| (lo.ln() + u * (hi / lo).ln()).exp();
    (0..n)
        .map(|_| {
            let alpha = log_u(u(), (1.0, 30.0));
            let gamma = 1.0 / (3.0 * alpha) + log_u(u(), gap);
            let eps = 0.2 + 0.8 * u();
            let delta = log_u(u(), (0.3, 30.0));
            let ai = a_max * (2.0 * u() - 1.0);
            let mut p = Params {
                alpha,
                gamma,
                eps,
                mu: 0.0,
                delta,
                omega: 0.01,
            };
            p.mu = p.g(p.critical_gamma()) - delta * ai;
            p
        })
        .collect()
}
