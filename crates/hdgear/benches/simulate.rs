//! Three slow periods of the study's model at rtol = atol = 1e-10, γ ∈ {30, 0.1}.
//!
//! * `plain`: the bare integration to τ = 3·2π/ω (what SPEC §5's "stack-only DOP853" row measures;
//!   this integrator is itself a stack-only DOP853 loop, so it is its own yardstick).
//! * `sampled`: `hdgear simulate`'s work: dense output at dt = 0.05 plus the exact max |x'|.
//!
//! * `differential-equations/dop853`: the same problem with the `differential-equations` 0.7
//!   crate's DOP853 (final state only), the best-kept crate SPEC §5 lists: the reason hdgear
//!   has its own integrator is measured here.
//!
//! Steps and right-hand-side evaluations are printed once per case.

use criterion::{Criterion, criterion_group, criterion_main};
use hdgear::Params;
use hdgear::integrate::{Dop853, Options};
use hdgear::model::Dimensionless;
use hdgear::simulate::{SimOptions, simulate};
use std::hint::black_box;

/// The same model for the `differential-equations` crate (with the same `libm` sine as ours, so
/// the integrators are compared, not the sines).
struct DeModel(Params);

impl differential_equations::prelude::ODE<f64, [f64; 2]> for DeModel {
    fn diff(&self, t: f64, y: &[f64; 2], dydt: &mut [f64; 2]) {
        let p = &self.0;
        dydt[0] = y[1];
        dydt[1] = p.forcing(libm::sin(p.omega * t)) - y[1] - p.g(y[0]);
    }
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("simulate_3_periods");
    for gamma in [30.0, 0.1] {
        let p = Params {
            gamma,
            ..Params::default()
        };
        let sys = Dimensionless::new(p);
        let x0 = hdgear::fast::stable_equilibrium(&p, 0.0);
        let t_end = 3.0 * p.slow_period();
        let run = || {
            let mut s = Dop853::new(&sys, 0.0, [x0, 0.0], Options::default()).unwrap();
            s.integrate_to(t_end).unwrap();
            s
        };
        let st = run().stats();
        eprintln!(
            "gamma {gamma}: plain: steps {} rejected {} rhs_evals {}",
            st.steps, st.rejected, st.rhs_evals
        );
        let opts = SimOptions::default();
        let s2 = simulate(&p, &opts, |_, _| {}).unwrap().stats;
        eprintln!(
            "gamma {gamma}: sampled (dt 0.05): steps {} rhs_evals {}",
            s2.steps, s2.rhs_evals
        );
        let de = DeModel(p);
        let de_run = || {
            use differential_equations::prelude::*;
            IVP::ode(&de, 0.0, t_end, [x0, 0.0])
                .method(ExplicitRungeKutta::dop853().rtol(1e-10).atol(1e-10))
                .t_eval([t_end])
                .solve()
                .unwrap()
        };
        let sol = de_run();
        let (ours, theirs) = (run().y()[0], sol.y.last().unwrap()[0]);
        eprintln!(
            "gamma {gamma}: differential-equations dop853: steps {} (rejected {}) rhs_evals {}; \
             final x differs from ours by {:.1e}",
            sol.steps.accepted,
            sol.steps.rejected,
            sol.evals.function,
            (ours - theirs).abs()
        );
        g.bench_function(
            format!("differential-equations-dop853/gamma={gamma}"),
            |b| b.iter(|| black_box(de_run().y.len())),
        );
        g.bench_function(format!("plain/gamma={gamma}"), |b| {
            b.iter(|| black_box(run().y()[0]))
        });
        g.bench_function(format!("sampled/gamma={gamma}"), |b| {
            b.iter(|| {
                let mut acc = 0.0;
                simulate(&p, &opts, |_, y| acc += y[0]).unwrap();
                black_box(acc)
            })
        });
    }
    g.finish();
}

// No criterion plots: its plotters backend would need a font this binary does not register.
criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = bench
}
criterion_main!(benches);
