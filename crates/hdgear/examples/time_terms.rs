//! Times a model assembled from terms: the study's model with regularised Coulomb–Stribeck–viscous
//! friction ((f_c + (f_s − f_c)e^{−(x'/v_st)²})·tanh(x'/v_r) + c_v·x'), integrated from rest to
//! `t_end` with nothing sampled, Taylor's method through [`hdgear::model::Model`]'s derived
//! recurrences. With `--hysteresis` the model also carries Bouc–Wen hysteresis on the twist
//! ([`HYSTERESIS`]), whose |x'| and |z| are exact: the run goes piece by piece, each step cut at
//! x' = 0 and z = 0 ([`hdgear::model::switching::Switching`]).
//! The same run is timed again on [`LANES`] lanes, as `batch_seconds_per_run`, per trajectory:
//! of [`integrate_models`] for the smooth model (one pass on vector lanes for all sixteen, each
//! lane taking the scalar stepper's steps), of [`integrate_switching_models`] with hysteresis or
//! sticking (each lane a switching integration, its slipping pieces' passes on vector lanes).
//! Prints one JSON line per (v_r, tolerance):
//! `{"vr":..,"rtol":..,"seconds_per_run":..,"batch_seconds_per_run":..,"steps":..,"y":[x, x', (z)]}`.
//! With `--sticking` the friction is not regularised: Coulomb–Stribeck–viscous friction with
//! sgn x' and sticking (the `coulomb` term, v_r unused), stepped piece by piece, each step cut at
//! x' = 0 and each rest held until the applied torque leaves the static band ±f_s.
//! With `--lugre` the friction is LuGre's ([`LUGRE`]: the same f_c, f_s, v_st, σ₂ = c_v, and a
//! bristle state, v_r unused), its |x'| exact, stepped piece by piece.
//! Used by `bench/compare_heyoka_terms.py`, which runs heyoka on the same equation.
//! Usage: `cargo run --release --example time_terms REPS T_END VR[,VR…] TOL… [--hysteresis]
//! [--sticking | --lugre]`.

use hdgear::integrate::{Options, stepper};
use hdgear::model::Model;
use hdgear::model::switching::{Pieces, Switching};
use hdgear::model::terms::AnyTerm;

#[path = "common/timing.rs"]
mod timing;
use timing::{PARAMS, batch_time, time};

/// f_c, f_s, v_st, c_v.
const FRICTION: [f64; 4] = [0.3, 0.4, 0.1, 0.05];
/// LuGre's f_c, f_s, v_st (as [`FRICTION`]), σ₀, σ₁ and σ₂ (= c_v).
const LUGRE: [f64; 6] = [0.3, 0.4, 0.1, 100.0, 10.0, 0.05];
/// Bouc–Wen's k_h, ρ, A, β, γ_h, n: ż = A·x' − β|x'|z − γ_h·x'|z|, torque k_h·z.
const HYSTERESIS: [f64; 6] = [0.5, 0.0, 1.0, 0.5, 0.5, 1.0];

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let hysteresis = args.iter().any(|a| a == "--hysteresis");
    let sticking = args.iter().any(|a| a == "--sticking");
    let lugre = args.iter().any(|a| a == "--lugre");
    args.retain(|a| a != "--hysteresis" && a != "--sticking" && a != "--lugre");
    // a state beside x and x': the hysteresis's or LuGre's
    let stateful = hysteresis || lugre;
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
        let friction = if lugre {
            AnyTerm::new("lugre", &LUGRE)
        } else if sticking {
            AnyTerm::new("coulomb", &FRICTION)
        } else {
            AnyTerm::new("stribeck", &[fc, fs, vst, cv, vr])
        };
        let mut m = Model::study(&PARAMS)
            .with_term(friction.expect("valid term"))
            .expect("a free slot");
        if hysteresis {
            m = m
                .with_term(AnyTerm::new("boucwen", &HYSTERESIS).expect("valid term"))
                .expect("a free slot");
        }
        let pieces = Pieces::new(&m);
        for &tol in &tols {
            let o = Options {
                rtol: tol,
                atol: tol,
                ..Options::default()
            };
            let batch = match (&pieces, stateful) {
                (None, _) => batch_time::<2>(reps, t_end, &m, o),
                (Some(_), true) => batch_time::<3>(reps, t_end, &m, o),
                (Some(_), false) => batch_time::<2>(reps, t_end, &m, o),
            };
            let (best, y, st) = match &pieces {
                None => time(reps, t_end, || {
                    stepper(&m, 0.0, [0.0; 2], o).expect("valid options")
                }),
                Some(p) if stateful => time(reps, t_end, || {
                    Switching::<3>::new(p, 0.0, [0.0; 3], o).expect("valid options")
                }),
                Some(p) => time(reps, t_end, || {
                    Switching::<2>::new(p, 0.0, [0.0; 2], o).expect("valid options")
                }),
            };
            println!(
                "{{\"vr\":{vr:e},\"rtol\":{tol:e},\"seconds_per_run\":{best},\"batch_seconds_per_run\":{},\"steps\":{},\"y\":[{}]}}",
                batch,
                st.steps,
                y.iter()
                    .map(|v| format!("{v:.17e}"))
                    .collect::<Vec<_>>()
                    .join(",")
            );
        }
    }
}
