//! Timing helpers the examples that time hdgear share (`#[path]`-included by each).

use hdgear::Params;
use hdgear::batch::LANES;
use hdgear::integrate::{Options, Stats, Stepper};
use hdgear::model::{Model, integrate_models, integrate_switching_models};
use std::time::Instant;

/// The friction case: a slow sine the friction holds at times (stick-slip), as in the tests.
pub const PARAMS: Params = Params {
    alpha: 16.0,
    gamma: 0.1,
    eps: 0.71,
    mu: 0.07,
    delta: 1.0,
    omega: 0.5,
};

/// The best time per run over 5 batches of `reps` runs (the least-disturbed estimate on a shared
/// machine) from the stepper `start` makes to `t_end`, with the last run's final state and work.
pub fn time<const N: usize, S: Stepper<N>>(
    reps: u32,
    t_end: f64,
    start: impl Fn() -> S,
) -> (f64, Vec<f64>, Stats) {
    let run = || {
        let mut s = start();
        while s.t() < t_end {
            s.step(t_end).expect("the run completes");
        }
        (*s.y(), s.stats())
    };
    let mut last = run();
    let best = best_per_run(reps, || last = std::hint::black_box(run()));
    (best, last.0.to_vec(), last.1)
}

/// The best time per trajectory over 5 batches of `reps` runs of [`LANES`] copies of `m` on the
/// lanes of [`integrate_models`] (of [`integrate_switching_models`] where `m` switches), from
/// rest to `t_end`.
pub fn batch_time<const N: usize>(reps: u32, t_end: f64, m: &Model, o: Options) -> f64 {
    let models = [*m; LANES];
    let spans = [(t_end, t_end); LANES];
    let starts = [[0.0; N]; LANES];
    let run = || {
        let ends = if m.switches() {
            integrate_switching_models::<N>(&models, &starts, &spans, o, |_, _| {})
        } else {
            integrate_models::<N>(&models, &starts, &spans, o, |_, _| {})
        };
        ends.expect("valid input")
    };
    best_per_run(reps, || {
        std::hint::black_box(run());
    }) / LANES as f64
}

/// The best time per call of `once` over 5 batches of `reps` calls (the least-disturbed
/// estimate on a shared machine).
pub fn best_per_run(reps: u32, mut once: impl FnMut()) -> f64 {
    let mut best = f64::INFINITY;
    for _ in 0..5 {
        let t0 = Instant::now();
        for _ in 0..reps {
            once();
        }
        best = best.min(t0.elapsed().as_secs_f64() / f64::from(reps));
    }
    best
}
