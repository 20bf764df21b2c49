//! hdgear's benchmarks in one binary (`cargo bench`; `cargo bench -- simulate` for one group):
//!
//! * `simulate_3_periods`: three slow periods at rtol = atol = 1e-10, γ ∈ {30, 0.1}: each method
//!   (`taylor`, `dop853`) on the plain integration, DOP853 as a bare loop (`plain`), with the
//!   sampled output of `hdgear simulate` (`sampled`), and the `differential-equations` crate's
//!   DOP853 on the same problem.
//! * `fast`: the fast-subsystem analysis without simulation.
//! * `sweep_1000_gamma`: a 1000-point γ sweep with burst analysis on 1 and 2 threads.
//! * `physical_300_tau`: the two-inertia model as the input inertia shrinks (stiffness check).
//! * `study_path`: the study's hand-scheduled fast path ([`Dimensionless`], the study's batch)
//!   against the generic path of the model assembled from terms ([`Model::study`]) on the same
//!   work: what keeps the fast path (issue 94 keeps one only where it is ≥ 1.2× faster).
//! * `law_rows`: the spring's Taylor rows 0..=20 written by hand (here) against the library's
//!   [`Spring`], declared once ([`hdgear::model::law`]), on one number and on sixteen lanes:
//!   what a declaration costs per step.
//!
//! Against other tools in the same run: `bench/compare_heyoka.py`, `bench/compare_scipy.py`.

use criterion::{Criterion, criterion_group, criterion_main};
use hdgear::Params;
use hdgear::burst::BurstOptions;
use hdgear::fast::{analyze, curve};
use hdgear::integrate::{Dop853, Method, Options};
use hdgear::model::Dimensionless;
use hdgear::model::spring::Spring;
use hdgear::model::terms::Term;
use hdgear::physical::PhysicalParams;
use hdgear::physical::simulate::simulate_physical;
use hdgear::simulate::{SimOptions, Start, integrate_periods, simulate};
use hdgear::sweep::{Axis, Grid, run};
use std::hint::black_box;

// Three slow periods of the study's model at rtol = atol = 1e-10, γ ∈ {30, 0.1}.
//
// * `plain`: the bare integration to τ = 3·2π/ω (a stack-only DOP853's bare cost;
//   this integrator is itself a stack-only DOP853 loop, so it is its own yardstick).
// * `sampled`: `hdgear simulate`'s work: dense output at dt = 0.05 plus the exact max |x'|.
//
// * `differential-equations/dop853`: the same problem with the `differential-equations` 0.7
//   crate's DOP853 (final state only), the best-kept DOP853 crate: the reason hdgear
//   has its own integrator is measured here.
//
// Steps and right-hand-side evaluations are printed once per case.

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

fn simulate_group(c: &mut Criterion) {
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
        for method in Method::ALL {
            let o = Options {
                method,
                ..Options::default()
            };
            g.bench_function(format!("{method}/gamma={gamma}"), |b| {
                b.iter(|| black_box(integrate_periods(&p, 3.0, o).unwrap()))
            });
        }
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

// The fast-subsystem analysis without simulation: `analyze` (folds, cusp, slopes, spiking areas)
// and a 10,000-point equilibrium curve, at the study's point (γ = 0.1) and in the fold regime
// (γ = 0.01). Bar (analysis issue): the curve under 10 ms; AUTO-07p takes 18–37 ms per branch.

fn fast_group(c: &mut Criterion) {
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

// A 1000-point γ sweep (0.1 to 30, log-spaced; the default response: 1 slow period discarded,
// 2 analysed, rtol = atol = 1e-10) on 1 and 2 threads. Bar (burst issue): under 1.5 s on the
// 2-core machine; a numba-compiled Dormand–Prince 5(4) needs ~2.9 s on one core.

fn sweep_group(c: &mut Criterion) {
    let grid = Grid::new(
        Params::default(),
        vec![Axis::parse("gamma=0.1:30:1000:log").unwrap()],
    )
    .unwrap();
    let opts = BurstOptions::default();
    let all: Vec<usize> = (0..grid.len()).collect();
    let mut g = c.benchmark_group("sweep_1000_gamma");
    g.sample_size(10);
    for threads in [1, 2] {
        g.bench_function(format!("threads={threads}"), |b| {
            b.iter(|| {
                let mut n = 0usize;
                run(&grid, &opts, &all, threads, |r| {
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

// The two-inertia model: does a small input inertia (J_i N² ≪ J_o) make it stiff?
//
// The same reduced point (α 16, ε 1/16, γ 1, μ 0.07, δ 15, ω 0.01) is mapped back to drives with
// N²J_i/J_o from 0.25 down to 2.5e-7 and simulated by DOP853 over 300 dimensionless time
// units, next to the dimensionless model. Steps and right-hand-side evaluations are printed;
// the times are measured. If the small inertia made the system stiff, the explicit method's
// step count would grow as N²J_i/J_o falls (its steps limited by stability, not accuracy).

fn physical_group(c: &mut Criterion) {
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

// The study's fast path against the generic path on the same work: three slow periods of the
// default start at rtol = atol = 1e-10 by Taylor's method, γ ∈ {30, 0.1}, one trajectory
// (`Dimensionless` against `Model::study`) and sixteen on the vector lanes (`integrate_batch`
// against `integrate_models`, γ log-spaced 0.1–30). The two are held together by
// `tests/model.rs` (right-hand side to rounding, Taylor rows to 1e-14). And the periodic orbit
// by shooting at the study's point, the study's variational recurrence against the model's. Steps are printed: equal
// steps mean the time is the cost per step.

/// Taylor's method on `sys` from (x0, 0) to `t_end`: the final x and the steps taken.
fn taylor_run<S: hdgear::integrate::System<2>>(
    sys: &S,
    x0: f64,
    t_end: f64,
    opts: Options,
) -> (f64, u64) {
    use hdgear::integrate::{Stepper, Taylor};
    let mut s = Taylor::new(sys, 0.0, [x0, 0.0], opts).unwrap();
    while s.t() < t_end {
        s.step(t_end).unwrap();
    }
    (s.y()[0], s.stats().steps)
}

fn study_path_group(c: &mut Criterion) {
    use hdgear::batch::integrate_batch;
    use hdgear::model::{Model, integrate_models};
    let mut g = c.benchmark_group("study_path");
    let opts = Options::default();
    for gamma in [30.0, 0.1] {
        let p = Params {
            gamma,
            ..Params::default()
        };
        let x0 = hdgear::fast::stable_equilibrium(&p, 0.0);
        let t_end = 3.0 * p.slow_period();
        let (fast, generic) = (Dimensionless::new(p), Model::study(&p));
        let (a, b) = (
            taylor_run(&fast, x0, t_end, opts),
            taylor_run(&generic, x0, t_end, opts),
        );
        eprintln!(
            "gamma {gamma}: steps specialised {}, generic {}; final x differs by {:.1e}",
            a.1,
            b.1,
            (a.0 - b.0).abs()
        );
        g.bench_function(format!("scalar-specialised/gamma={gamma}"), |b| {
            b.iter(|| black_box(taylor_run(&fast, x0, t_end, opts)))
        });
        g.bench_function(format!("scalar-generic/gamma={gamma}"), |b| {
            b.iter(|| black_box(taylor_run(&generic, x0, t_end, opts)))
        });
    }
    // the periodic orbit by shooting (Newton with the variational equations) at the study's
    // point: the study's own variational recurrence against the model's
    let p = Params::default();
    let po = hdgear::periodic::PeriodicOptions::default();
    g.bench_function("shoot-specialised", |b| {
        b.iter(|| black_box(hdgear::periodic::shoot(&p, 1, &po).unwrap().start))
    });
    let m = Model::study(&p);
    g.bench_function("shoot-generic", |b| {
        b.iter(|| black_box(hdgear::periodic::shoot(&m, 1, &po).unwrap().start))
    });
    let points: Vec<Params> = (0..16)
        .map(|i| Params {
            gamma: 0.1 * 300f64.powf(f64::from(i) / 15.0),
            ..Params::default()
        })
        .collect();
    let models: Vec<Model> = points.iter().map(Model::study).collect();
    let starts: Vec<[f64; 2]> = points
        .iter()
        .map(|p| [hdgear::fast::stable_equilibrium(p, 0.0), 0.0])
        .collect();
    let t_end = 3.0 * points[0].slow_period();
    let spans = vec![(t_end, t_end); 16];
    g.bench_function("batch16-specialised", |b| {
        b.iter(|| black_box(integrate_batch(&points, &starts, t_end, opts).unwrap()))
    });
    g.bench_function("batch16-generic", |b| {
        b.iter(|| {
            black_box(integrate_models::<2>(&models, &starts, &spans, opts, |_, _| {}).unwrap())
        })
    });
    g.finish();
}

/// The spring (k_l + k_c·x²)(x − φ)'s Taylor row k written by hand, as the library's [`Spring`]
/// was before it was declared: (x²)_k by the symmetric half sum kept in `sq`, (x³)_k a Cauchy
/// sum, then c₃x³ + c₂x² + c₁x + c₀ with c = [k_c, −k_c·φ, k_l, −k_l·φ].
#[inline(always)]
fn hand_spring_row<J: hdgear::model::jet::Jet>(
    [kl, kc, phi]: [J; 3],
    k: usize,
    x: &[J],
    sq: &mut [J],
) -> J {
    use hdgear::model::jet::{cauchy, square_coefficient};
    sq[k] = square_coefficient(x, k);
    let cube = cauchy(sq, x, k);
    let linear = kl * x[k] + if k == 0 { -(kl * phi) } else { J::splat(0.0) };
    kc * cube + -(kc * phi) * sq[k] + linear
}

fn law_rows_group(c: &mut Criterion) {
    use hdgear::integrate::taylor::{SCRATCH_ROWS, Scratch};
    use hdgear::model::jet::{Jet, Lanes};
    use hdgear::model::terms::{LaneRows, MAX_ROWS};
    let mut g = c.benchmark_group("law_rows");
    let values = [2.0, 0.7, 0.1];
    let declared = Spring::from_values(&values);
    let x: [f64; MAX_ROWS] =
        std::array::from_fn(|k| 0.5f64.powi(k as i32) * (1.0 + 0.1 * k as f64));
    let zero = [0.0; MAX_ROWS];
    let order = 20;
    let rows_of = |t: &dyn Fn(usize, &mut Scratch) -> f64| {
        let mut rows = Scratch([[0.0; MAX_ROWS]; SCRATCH_ROWS]);
        (0..=order).map(|k| t(k, &mut rows)).sum::<f64>()
    };
    let (a, b) = (
        rows_of(&|k, r| hand_spring_row(values, k, &x, &mut r.0[0])),
        rows_of(&|k, r| declared.taylor(k, &x, &zero, &zero, r)),
    );
    eprintln!(
        "law_rows: hand {a}, declared {b}, differ by {:.1e}",
        (a - b).abs()
    );
    g.bench_function("scalar-hand", |bch| {
        bch.iter(|| {
            black_box(rows_of(&|k, r| {
                hand_spring_row(values, k, black_box(&x), &mut r.0[0])
            }))
        })
    });
    g.bench_function("scalar-declared", |bch| {
        bch.iter(|| {
            black_box(rows_of(&|k, r| {
                declared.taylor(k, black_box(&x), &zero, &zero, r)
            }))
        })
    });
    let lx: [Lanes; MAX_ROWS] = x.map(Lanes::splat);
    let lz = [Lanes::splat(0.0); MAX_ROWS];
    let lane_rows = |f: &dyn Fn(usize, &mut LaneRows) -> Lanes| {
        let mut rows: LaneRows = [[Lanes::splat(0.0); MAX_ROWS]; SCRATCH_ROWS];
        (0..=order).map(|k| f(k, &mut rows).0[0]).sum::<f64>()
    };
    let hv = values.map(Lanes::splat);
    let dv = declared.lane_values().map(Lanes::splat);
    g.bench_function("lanes-hand", |bch| {
        bch.iter(|| {
            black_box(lane_rows(&|k, r| {
                hand_spring_row(hv, k, black_box(&lx), &mut r[0])
            }))
        })
    });
    g.bench_function("lanes-declared", |bch| {
        bch.iter(|| {
            black_box(lane_rows(&|k, r| {
                Spring::taylor_lanes(&dv, k, black_box(&lx), &lz, &lz, r).unwrap()
            }))
        })
    });
    g.finish();
}

// No criterion plots: its plotters backend would need a font this binary does not register.
criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = simulate_group, fast_group, sweep_group, physical_group, study_path_group, law_rows_group
}
criterion_main!(benches);
