//! The survey behind the cusp's normal form (`hdgear::fast::passage`): random parameter sets whose
//! settled branch passes the inflection through a node part, with the predicted and the
//! simulated ω boundaries, one JSON line each (`pred`, `sim`; `gap` = γ − 1/(3α), `ai` the
//! inflection's load). Nothing is fitted to it: the threshold is solved from the normal form.
//! Usage: `cargo run --release --example cusp_survey N SEED [GAP_MIN GAP_MAX [A_MAX]]`
//! (defaults 10 1 0.002 0.05 0.7), or `… thresholds` for s_c at six g'_min with the swing floor
//! a decade either way and the passage's edge at 4 and 16 times g' = 4 (ratios to the default).

#[path = "../tests/common/cusp_sets.rs"]
mod cusp_sets;

use hdgear::burst::{BurstOptions, boundaries};
use hdgear::fast::predict;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("thresholds") {
        for g in [0.0, 0.0125, 0.05, 0.1, 0.2, 0.2475] {
            let t = std::time::Instant::now();
            let base = hdgear::fast::ramp_threshold_at(g, 1e-5, 4.0).unwrap();
            let dt = t.elapsed().as_secs_f64();
            let v: Vec<String> = [(1e-4, 4.0), (1e-6, 4.0), (1e-5, 16.0), (1e-5, 64.0)]
                .iter()
                .map(|&(f, e)| {
                    format!(
                        "{:.4}",
                        hdgear::fast::ramp_threshold_at(g, f, e).unwrap() / base
                    )
                })
                .collect();
            println!(
                "{g} {base:.5e} table {:.5e} {dt:.3}s {}",
                hdgear::fast::ramp_threshold(g).unwrap(),
                v.join(" ")
            );
        }
        return;
    }
    let arg = |i: usize, default: f64| args.get(i).and_then(|s| s.parse().ok()).unwrap_or(default);
    let (n, seed) = (arg(0, 10.0) as usize, arg(1, 1.0) as u64);
    for p in cusp_sets::near_cusp_sets(n, seed, (arg(2, 0.002), arg(3, 0.05)), arg(4, 0.7)) {
        let (ai, gap) = (p.a_at(p.critical_gamma()), p.gamma - p.critical_gamma());
        let pr = predict(&p);
        let b = match boundaries(&p, &BurstOptions::default()) {
            Ok(b) => b,
            Err(e) => {
                eprintln!("{e}");
                continue;
            }
        };
        println!(
            "{{\"alpha\":{},\"gamma\":{},\"eps\":{},\"mu\":{},\"delta\":{},\"ai\":{},\"gap\":{},\"pred\":{},\"sim\":{},\"kmax\":{},\"at_x\":{},\"node\":{}}}",
            p.alpha,
            p.gamma,
            p.eps,
            p.mu,
            p.delta,
            ai,
            gap,
            b.predicted_omega,
            b.simulated_omega.map_or("null".into(), |w| w.to_string()),
            pr.forcing_rate,
            pr.at_x,
            pr.node_min_gprime.map_or("null".into(), |w| w.to_string())
        );
    }
}
