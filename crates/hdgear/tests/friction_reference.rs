//! The burst verdict on models with friction or hysteresis against an independent reference:
//! `tests/data/friction_cases.json`, made by `friction_cases.py` (scipy DOP853 at 1e-12, an own
//! stick/slip loop for sticking friction, the signatures written from the guide's definitions),
//! on cases drawn at random from ranges fixed before any was run.

use hdgear::burst::{BurstOptions, classify, response_model};
use hdgear::model::Model;
use hdgear::model::terms::AnyTerm;

/// Every case: the model, its term's kind and the reference block.
fn cases() -> Vec<(String, Model, serde_json::Value)> {
    crate::common::reference_cases("friction_cases.json")
        .into_iter()
        .map(|(id, p, c)| {
            let values: Vec<f64> = c["values"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| x.as_f64().unwrap())
                .collect();
            let term = AnyTerm::new(c["term"].as_str().unwrap(), &values).unwrap();
            let m = Model::study(&p).with_term(term).unwrap();
            (id, m, c["reference"].clone())
        })
        .collect()
}

/// The verdict (and with it the signature: stick-slip, overshoot, ringing, fold-jump or none)
/// agrees with the reference on at least 95 % of the cases, and the burst and slip-burst counts
/// per period on every case whose verdict agrees. The peak |x'| is never below the reference's
/// (beyond the integrations' error) and above it by less than 1e-3 relative: the reference takes
/// the largest of its samples 0.02 apart.
#[test]
fn verdicts_agree_with_the_independent_reference() {
    let all = cases();
    assert!(all.len() >= 30, "{} cases", all.len());
    let opts = BurstOptions::default();
    let mut agree = 0;
    let mut worst_peak: f64 = 0.0;
    let mut kinds = std::collections::BTreeMap::<String, usize>::new();
    for (id, m, reference) in &all {
        let r = response_model(m, &opts).unwrap();
        let p = m.equivalent_params().unwrap();
        let c = classify(&p, &r);
        let want = reference["verdict"].as_str().unwrap();
        *kinds.entry(want.to_string()).or_default() += 1;
        // null where the fast motion never stops (a group longer than half a slow period)
        let count = reference["bursts_per_period"].as_f64();
        println!(
            "{id}: hdgear {} ({:?} per period), reference {want} ({count:?} per period)",
            c.verdict.name(),
            r.rates.bursts_per_period
        );
        if c.verdict.name() == want {
            agree += 1;
            assert_eq!(r.rates.bursts_per_period, count, "{id}");
            let slips = r.sticking.map_or(0.0, |k| k.slip_bursts_per_period);
            assert_eq!(
                slips,
                reference["slip_bursts_per_period"].as_f64().unwrap(),
                "{id}"
            );
        }
        // the reference's peak is the largest of samples 0.02 apart, so below the true one by
        // up to (0.01)²/2 of the curvature of |x'| there
        let peak = reference["peak_abs_xdot"].as_f64().unwrap();
        let diff = (r.rates.peak_abs_xdot - peak) / peak;
        assert!((-1e-8..1e-3).contains(&diff), "{id}: peak {diff:e}");
        worst_peak = worst_peak.max(diff.abs());
        println!(
            "   peak |x'| {:.6}, relative difference {diff:.1e}",
            r.rates.peak_abs_xdot
        );
    }
    println!(
        "{agree} of {} agree; reference verdicts {kinds:?}",
        all.len()
    );
    assert!(
        agree as f64 >= 0.95 * all.len() as f64,
        "{agree} of {}",
        all.len()
    );
}
