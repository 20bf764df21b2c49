//! The two-inertia model: does a small input inertia (J_i N² ≪ J_o) make it stiff?
//!
//! The same reduced point (α 16, ε 1/16, γ 1, μ 0.07, δ 15, ω 0.01) is mapped back to drives with
//! N²J_i/J_o from 0.25 down to 2.5e-7 and simulated by DOP853 over 300 dimensionless time
//! units, next to the dimensionless model. Steps and right-hand-side evaluations are printed;
//! the times are measured. If the small inertia made the system stiff, the explicit method's
//! step count would grow as N²J_i/J_o falls (its steps limited by stability, not accuracy).

use criterion::{Criterion, criterion_group, criterion_main};
use hdgear::Params;
use hdgear::integrate::Options;
use hdgear::physical::PhysicalParams;
use hdgear::physical::simulate::simulate_physical;
use hdgear::simulate::{SimOptions, Start, simulate};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let p = Params {
        alpha: 16.0,
        gamma: 1.0,
        eps: 1.0 / 16.0,
        ..Params::default()
    };
    let tau_end = 300.0;
    let mut g = c.benchmark_group("physical_300_tau");
    let s = simulate(
        &p,
        &SimOptions {
            t_end: tau_end,
            dt: tau_end,
            start: Start::Rest,
            ..SimOptions::default()
        },
        |_, _| {},
    )
    .unwrap();
    eprintln!("dimensionless: {:?}", s.stats);
    for j_in in [1e-4, 1e-6, 1e-8, 1e-10] {
        let d = PhysicalParams::from_dimensionless(&p, j_in, 1.0, 50.0, 5.0, 1e-3).unwrap();
        let r = d.reduce().unwrap();
        let t_end = r.time(tau_end);
        let run = || simulate_physical(&d, t_end, t_end, Options::default(), |_| {}).unwrap();
        let ratio = 2500.0 * j_in;
        eprintln!("N^2 J_i / J_o = {ratio:e}: {:?}", run().stats);
        g.bench_function(format!("ratio={ratio:e}"), |b| b.iter(|| black_box(run())));
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
