//! A 1000-point γ sweep (0.1 to 30, log-spaced; the default response: 1 slow period discarded,
//! 2 analysed, rtol = atol = 1e-10) on 1 and 2 threads. Bar (burst issue): under 1.5 s on the
//! 2-core machine; a numba-compiled Dormand–Prince 5(4) needs ~2.9 s on one core.

use criterion::{Criterion, criterion_group, criterion_main};
use hdgear::Params;
use hdgear::burst::BurstOptions;
use hdgear::sweep::{Axis, Grid, run};
use std::collections::HashSet;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let grid = Grid::new(
        Params::default(),
        vec![Axis::parse("gamma=0.1:30:1000:log").unwrap()],
    )
    .unwrap();
    let opts = BurstOptions::default();
    let mut g = c.benchmark_group("sweep_1000_gamma");
    g.sample_size(10);
    for threads in [1, 2] {
        g.bench_function(format!("threads={threads}"), |b| {
            b.iter(|| {
                let mut n = 0usize;
                run(&grid, &opts, &HashSet::new(), threads, |r| {
                    n += 1;
                    black_box(r);
                })
                .unwrap();
                assert_eq!(n, 1000);
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
