//! Times a model assembled from terms: the study's model with regularised Coulomb–Stribeck–viscous
//! friction ((f_c + (f_s − f_c)e^{−(x'/v_st)²})·tanh(x'/v_r) + c_v·x'), integrated from rest to
//! `t_end` with nothing sampled, Taylor's method through [`hdgear::model::Model`]'s derived
//! recurrences. Prints one JSON line per (v_r, tolerance):
//! `{"vr":..,"rtol":..,"seconds_per_run":..,"steps":..,"x":..,"xdot":..}`.
//! Used by `bench/compare_heyoka_terms.py`, which runs heyoka on the same equation.
//! Usage: `cargo run --release --example time_terms REPS T_END VR[,VR…] TOL…`.

use hdgear::Params;
use hdgear::integrate::{Options, Stepper, stepper};
use hdgear::model::Model;
use hdgear::model::terms::AnyTerm;
use std::time::Instant;

/// The friction case: a slow sine the friction holds at times (stick-slip), as in the tests.
const PARAMS: Params = Params {
    alpha: 16.0,
    gamma: 0.1,
    eps: 0.71,
    mu: 0.07,
    delta: 1.0,
    omega: 0.5,
};
/// f_c, f_s, v_st, c_v.
const FRICTION: [f64; 4] = [0.3, 0.4, 0.1, 0.05];

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let reps: u32 = args.first().and_then(|s| s.parse().ok()).unwrap_or(50);
    let t_end: f64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(60.0);
    let vrs: Vec<f64> = args
        .get(2)
        .map(|s| s.split(',').filter_map(|v| v.parse().ok()).collect())
        .unwrap_or_else(|| vec![1e-2]);
    let mut tols: Vec<f64> = args.iter().skip(3).filter_map(|s| s.parse().ok()).collect();
    if tols.is_empty() {
        tols.push(1e-10);
    }
    for &vr in &vrs {
        let [fc, fs, vst, cv] = FRICTION;
        let m = Model::study(&PARAMS)
            .with_term(AnyTerm::new("stribeck", &[fc, fs, vst, cv, vr]).expect("valid term"))
            .expect("a free slot");
        for &tol in &tols {
            let o = Options {
                rtol: tol,
                atol: tol,
                ..Options::default()
            };
            let run = || {
                let mut s = stepper(&m, 0.0, [0.0, 0.0], o).expect("valid options");
                while s.t() < t_end {
                    s.step(t_end).expect("the run completes");
                }
                (*s.y(), s.stats())
            };
            let mut last = None;
            let mut best = f64::INFINITY;
            // best of 5 batches: the least-disturbed estimate on a shared machine
            for _ in 0..5 {
                let t0 = Instant::now();
                for _ in 0..reps {
                    last = Some(std::hint::black_box(run()));
                }
                best = best.min(t0.elapsed().as_secs_f64() / f64::from(reps));
            }
            let Some((y, st)) = last else { return };
            println!(
                "{{\"vr\":{vr:e},\"rtol\":{tol:e},\"seconds_per_run\":{best},\"steps\":{},\"x\":{:.17e},\"xdot\":{:.17e}}}",
                st.steps, y[0], y[1]
            );
        }
    }
}
