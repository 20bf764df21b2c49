//! What each term kind costs per Taylor step: the study's model with one term of each kind added
//! (its parameters' defaults), integrated from rest over `T_END` with nothing sampled, timed per
//! step on one trajectory and per lane-step on [`LANES`] lanes, beside the floor: the study's
//! hand-scheduled recurrence ([`Dimensionless`]) and the study's model assembled from its two
//! declared terms ([`Model::study`]).
//!
//! Every row runs the way hdgear's commands run that model: a model that switches (|x'|, |z|,
//! sticking) piece by piece ([`Switching`], [`integrate_switching_models`]), any other by one
//! Taylor stepper ([`integrate_models`] on the lanes). A delayed feedback needs the run's history
//! and is integrated by its own method steps: it has no row.
//!
//! Prints a Markdown table (`bench/term_costs.py` runs it for `bench/RESULTS.md`).
//! Usage: `cargo run --profile dist --example term_costs [REPS [KIND]]` (default 20 repetitions,
//! every kind).

use hdgear::integrate::{Options, Stats, System, stepper};
use hdgear::model::switching::{Pieces, Switching};
use hdgear::model::terms::AnyTerm;
use hdgear::model::{Dimensionless, Model};

#[path = "common/timing.rs"]
mod timing;
use timing::{PARAMS, batch_time, time};

/// The span of each run.
const T_END: f64 = 60.0;
/// The tolerance of each run (rtol = atol).
const TOL: f64 = 1e-10;

fn main() {
    let mut args = std::env::args().skip(1);
    let reps: u32 = args.next().and_then(|s| s.parse().ok()).unwrap_or(20);
    let only: Option<String> = args.next();
    let o = Options {
        rtol: TOL,
        atol: TOL,
        ..Options::default()
    };
    println!("| model | steps | ns per step | ns per lane-step (16 lanes) |");
    println!("|---|---|---|---|");
    let floor = Dimensionless::new(PARAMS);
    let (t, _, st) = time(reps, T_END, || {
        stepper(&floor, 0.0, [0.0; 2], o).expect("valid options")
    });
    row(
        "the study's hand-scheduled recurrence (the floor)",
        t,
        st,
        None,
    );
    let study = Model::study(&PARAMS);
    let mut models = vec![(
        "the study's model of declared terms (damping, stiffness)".to_string(),
        study,
    )];
    for (kind, _, params) in AnyTerm::KINDS {
        let defaults: Vec<f64> = params.iter().map(|p| p.default).collect();
        let term = AnyTerm::new(kind, &defaults).expect("a kind's defaults are valid");
        if study.terms().any(|t| t.kind() == *kind) || term.delay().is_some() {
            continue;
        }
        let m = study.with_term(term).expect("a free slot");
        models.push((format!("the study's model + `{kind}`"), m));
    }
    for (label, m) in models {
        if only.as_ref().is_some_and(|k| !label.contains(k.as_str())) {
            continue;
        }
        let (t, st) = match m.dim() {
            2 => one::<2>(reps, &m, o),
            3 => one::<3>(reps, &m, o),
            n => panic!("{label}: {n} states"),
        };
        let lanes = match m.dim() {
            2 => lanes::<2>(reps, &m, o, st.steps),
            _ => lanes::<3>(reps, &m, o, st.steps),
        };
        row(&label, t, st, Some(lanes));
    }
}

/// One Markdown row: the work and the time per step.
fn row(label: &str, seconds: f64, st: Stats, lane_step: Option<(f64, bool)>) {
    let per_step = seconds / st.steps as f64 * 1e9;
    let lanes = lane_step.map_or("–".into(), |(t, vector)| {
        format!(
            "{:.0}{}",
            t * 1e9,
            if vector { "" } else { " (interleaved)" }
        )
    });
    println!("| {label} | {} | {per_step:.0} | {lanes} |", st.steps);
}

/// The best time per run of `m` from rest, by the stepper its commands take, with its work.
fn one<const N: usize>(reps: u32, m: &Model, o: Options) -> (f64, Stats)
where
    Model: System<N>,
{
    let (best, _, st) = match Pieces::new(m) {
        Some(p) => time(reps, T_END, || {
            Switching::<N>::new(&p, 0.0, [0.0; N], o).expect("valid options")
        }),
        None => time(reps, T_END, || {
            stepper(m, 0.0, [0.0; N], o).expect("valid options")
        }),
    };
    (best, st)
}

/// The best time per lane-step of 16 copies of `m` on the lanes, taking `steps` steps
/// each (a lane takes its scalar run's steps), and whether its passes ran on vector lanes (else
/// the lanes' scalar passes interleaved: a term with no copy on lanes).
fn lanes<const N: usize>(reps: u32, m: &Model, o: Options, steps: u64) -> (f64, bool) {
    let vector = m.terms().all(|t| t.on_lanes());
    (batch_time::<N>(reps, T_END, m, o) / steps as f64, vector)
}
