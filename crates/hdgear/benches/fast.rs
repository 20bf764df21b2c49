//! The fast-subsystem analysis without simulation: `analyze` (folds, cusp, slopes, spiking areas)
//! and a 10,000-point equilibrium curve, at the study's point (γ = 0.1) and in the fold regime
//! (γ = 0.01). Bar (analysis issue): the curve under 10 ms; AUTO-07p takes 18–37 ms per branch.

use criterion::{Criterion, criterion_group, criterion_main};
use hdgear::Params;
use hdgear::fast::{analyze, curve};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("fast");
    for gamma in [0.1, 0.01] {
        let p = Params {
            gamma,
            ..Params::default()
        };
        g.bench_function(format!("analyze/gamma={gamma}"), |b| {
            b.iter(|| black_box(analyze(black_box(&p), (-1.0, 1.0)).unwrap()))
        });
        g.bench_function(format!("curve_10000/gamma={gamma}"), |b| {
            b.iter(|| black_box(curve(black_box(&p), (-1.0, 1.0), 10_000).unwrap()))
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
