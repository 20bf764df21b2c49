//! Every dispatch level this CPU has (AVX-512, AVX2, portable) runs the same inputs through
//! every vectorised path: the scalar Taylor step and its recurrence, the 16-lane batch (with and
//! without a tangent), the batched burst scan and the dense scan of the curve-only prediction.
//! The two FMA levels must agree bit for bit (the same operations at another register width).
//! The portable level has no fused multiply-add, so it rounds differently, and a different
//! rounding can move a step-size choice and so the whole step sequence: it must agree to the
//! integration's own accuracy (1e-8 relative over the runs here, at a tolerance of 1e-10), take
//! the same number of steps within one per hundred, and give the same verdicts and counts.

use hdgear::Params;
use hdgear::batch::{integrate_batch, integrate_batch_tangent};
use hdgear::burst::{BurstOptions, classify, responses};
use hdgear::fast::predict;
use hdgear::integrate::Options;
use hdgear::simd::{Level, Simd};
use hdgear::simulate::{SimOptions, simulate};

/// Everything the vectorised paths give for a fixed set of inputs, as numbers and words.
#[derive(Debug, PartialEq)]
struct Outputs {
    numbers: Vec<f64>,
    steps: Vec<u64>,
    words: Vec<String>,
}

fn points() -> Vec<Params> {
    [0.1, 0.5, 1.0, 2.0, 5.0, 30.0]
        .iter()
        .flat_map(|&gamma| {
            [8.0, 15.0].map(|delta| Params {
                gamma,
                delta,
                ..Params::default()
            })
        })
        .collect()
}

fn outputs() -> Outputs {
    let mut numbers = Vec::new();
    let mut steps = Vec::new();
    let mut words = Vec::new();
    let ps = points();
    // the scalar Taylor stepper (its step and the model's recurrence are dispatched)
    let opts = SimOptions {
        t_end: 400.0,
        ..SimOptions::default()
    };
    let run = simulate(&ps[0], &opts, |_, y| numbers.extend(y)).unwrap();
    numbers.push(run.max_abs_xdot);
    steps.push(run.stats.steps);
    // the batch, plain and with a tangent
    let starts = vec![[0.0, 0.0]; ps.len()];
    for r in integrate_batch(&ps, &starts, 300.0, Options::default()).unwrap() {
        numbers.extend(r.y);
        steps.push(r.steps);
    }
    let with_tangent = vec![[0.0, 0.0, 1.0, 0.0]; ps.len()];
    let spans = vec![(0.0, 300.0); ps.len()];
    for r in integrate_batch_tangent(&ps, &with_tangent, &spans, Options::default()).unwrap() {
        let r = r.unwrap();
        numbers.extend(r.y);
        numbers.extend(r.tangent);
        numbers.push(r.ln_growth);
        steps.push(r.steps);
    }
    // the batched burst scan and the classification
    for (p, r) in ps.iter().zip(responses(&ps, &BurstOptions::default())) {
        let r = r.unwrap();
        let c = classify(p, &r);
        words.push(format!(
            "{:?} {:?} {:?}",
            c.verdict, c.mode, r.rates.bursts_per_period
        ));
        numbers.push(r.rates.peak_abs_xdot);
        numbers.push(r.measures.speed_ratio);
    }
    // the curve-only prediction's dense scan
    for p in &ps {
        let pr = predict(p);
        words.push(pr.bursting.to_string());
        numbers.push(pr.forcing_rate);
    }
    Outputs {
        numbers,
        steps,
        words,
    }
}

#[test]
fn every_dispatch_level_gives_the_same_results() {
    let levels = Simd::available();
    let all: Vec<(Level, Outputs)> = levels
        .iter()
        .map(|s| (s.level(), s.capped(outputs)))
        .collect();
    let widest = &all.last().unwrap().1;
    for (level, out) in all.iter().rev() {
        assert_eq!(out.words, widest.words, "{level:?}");
        assert_eq!(out.numbers.len(), widest.numbers.len(), "{level:?}");
        if level.fma() {
            // bit for bit: compare the representations, so that NaN = NaN and 0 ≠ −0
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert!(
                bits(&out.numbers) == bits(&widest.numbers) && out.steps == widest.steps,
                "{level:?} differs from {:?}",
                all.last().unwrap().0
            );
        } else {
            for (i, (a, b)) in out.numbers.iter().zip(&widest.numbers).enumerate() {
                assert!(
                    (a - b).abs() <= 1e-8 * (1.0 + b.abs()),
                    "{level:?}: number {i} is {a}, the FMA levels' {b}"
                );
            }
            for (a, b) in out.steps.iter().zip(&widest.steps) {
                assert!(
                    a.abs_diff(*b) * 100 <= *b,
                    "{level:?}: {a} steps against {b}"
                );
            }
        }
    }
    // this machine's levels, so the test log says what was compared
    eprintln!(
        "dispatch levels compared: {:?}",
        all.iter().map(|a| a.0).collect::<Vec<_>>()
    );
}
