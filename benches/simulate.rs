//! Three slow periods of the study's model at rtol = atol = 1e-10, γ ∈ {30, 0.1}.
//!
//! * `plain`: the bare integration to τ = 3·2π/ω (what SPEC §5's "stack-only DOP853" row measures;
//!   this integrator is itself a stack-only DOP853 loop, so it is its own yardstick).
//! * `sampled`: `hdgear simulate`'s work: dense output at dt = 0.05 plus the exact max |x'|.
//!
//! Steps and right-hand-side evaluations are printed once per case.

use criterion::{Criterion, criterion_group, criterion_main};
use hdgear::Params;
use hdgear::integrate::{Dop853, Options};
use hdgear::model::Dimensionless;
use hdgear::simulate::{SimOptions, simulate};
use std::hint::black_box;

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

criterion_group!(benches, bench);
criterion_main!(benches);
