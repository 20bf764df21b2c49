//! The design check under spread on a model assembled from terms: any of its parameters spreads,
//! by name, and each sample's verdict is the one `hdgear bursts` gives on that sample's model
//! built afresh from its scenario text.

use hdgear::burst::{BurstOptions, verdict_model};
use hdgear::model::Model;
use hdgear::robust::{McOptions, ModelSampleRow, Nominal, Sample, Space, probability};
use hdgear::scenario::Scenario;
use std::path::Path;

/// The model a user's scenario file with that text gives (as `hdgear bursts --config` reads it).
fn model_of(text: &str) -> Model {
    let path = Path::new("sample.toml");
    let s = Scenario::parse(text, path).unwrap();
    let (p, _) = hdgear::params::resolve("paper", s.params.as_ref(), &Default::default()).unwrap();
    s.model(&p, path).unwrap()
}

/// A sticking Coulomb drive on the study's curve at γ = 2, δ = 1.5, with `fs` as given.
fn coulomb(fs: f64) -> String {
    format!("[params]\ngamma = 2.0\ndelta = 1.5\n\n[coulomb]\nfc = 0.05\nfs = {fs:?}\n")
}

/// A drive with regularised friction `fc` on the study's curve at γ = `gamma`.
fn friction(gamma: f64, fc: f64) -> String {
    format!("[params]\ngamma = {gamma:?}\n\n[friction]\nfc = {fc:?}\n")
}

/// All samples of a run of `n` Sobol samples of `space`.
fn samples(space: &Space, n: u64) -> (hdgear::robust::Probability, Vec<Sample>) {
    let mc = McOptions {
        samples: n,
        ..McOptions::default()
    };
    let mut all = Vec::new();
    let p = probability(space, &BurstOptions::default(), &mc, |s| {
        all.extend_from_slice(s);
        Ok(())
    })
    .unwrap();
    (p, all)
}

/// A drive whose friction level and linear stiffness spread: every sample's verdict (its
/// bursting, its label) is that of the model built from the sample's own scenario text, and
/// P(burst) counts them. Both verdicts occur (the spread straddles the boundary), so a sample
/// whose values reached the wrong parameter would show.
#[test]
fn each_sample_of_a_friction_space_is_its_own_scenarios_verdict() {
    let nominal = Nominal::Model(model_of(&friction(2.0, 0.1)));
    let tolerances = ["friction.fc=0.02..0.5", "gamma=±40%"]
        .iter()
        .map(|t| Space::parse_tolerance(&nominal, t).unwrap())
        .collect();
    let space = Space::new(nominal, tolerances).unwrap();
    let (p, all) = samples(&space, 24);
    assert_eq!((p.samples, p.judged), (24, 24));
    let mut seen = [false; 2];
    for s in &all {
        let (fc, gamma) = (s.values[0], s.values[1]);
        let m = model_of(&friction(gamma, fc));
        let (c, _, _) = verdict_model(&m, &BurstOptions::default()).unwrap();
        let o = s.outcome.as_ref().unwrap();
        assert_eq!(
            o.bursting, c.bursting,
            "sample {}: fc {fc}, γ {gamma}",
            s.index
        );
        assert_eq!(o.label(), c.verdict.name());
        assert!(s.reduced.is_none());
        seen[usize::from(o.bursting)] = true;
    }
    assert_eq!(
        seen,
        [true, true],
        "the spread should straddle the boundary"
    );
    let bursting = all
        .iter()
        .filter(|s| s.outcome.as_ref().unwrap().bursting)
        .count();
    assert_eq!(p.bursting, bursting as u64);
    // the samples file's row: the toleranced values under their own names
    let row = ModelSampleRow::of(&space, &all[0]);
    let columns = ModelSampleRow::columns(&space);
    assert_eq!(&columns[..4], ["index", "fc", "gamma", "verdict"]);
    let mut csv = csv::WriterBuilder::new()
        .has_headers(false)
        .from_writer(Vec::new());
    csv.serialize(&row).unwrap();
    let line = String::from_utf8(csv.into_inner().unwrap()).unwrap();
    assert_eq!(line.split(',').count(), columns.len(), "{line}");
    assert!(line.starts_with(&format!("0,{},{},", all[0].values[0], all[0].values[1])));
}

/// The study's model written as a model (no extra terms) spreads as the study's parameter set
/// does: each sample bursts exactly when the study path's sample (batch lanes) does.
#[test]
fn the_studys_model_spreads_as_the_study_set_does() {
    let p = hdgear::Params {
        gamma: 2.2,
        ..Default::default()
    };
    let runs: Vec<Vec<bool>> = [Nominal::Study(p), Nominal::Model(Model::study(&p))]
        .into_iter()
        .map(|nominal| {
            let t = Space::parse_tolerance(&nominal, "gamma=±40%").unwrap();
            let (_, all) = samples(&Space::new(nominal, vec![t]).unwrap(), 16);
            all.iter()
                .map(|s| s.outcome.as_ref().unwrap().bursting)
                .collect()
        })
        .collect();
    assert_eq!(runs[0], runs[1]);
    assert!(runs[0].contains(&true) && runs[0].contains(&false));
}

/// A spread that takes the static friction below the sliding one is refused before any sample
/// runs, naming the value it reaches; two parameters of one rule that spread together are judged
/// as a pair in each sample, and a valid pair's verdict is its scenario's (stick-slip).
#[test]
fn a_spread_that_breaks_a_terms_rule_is_refused() {
    let nominal = Nominal::Model(model_of(&coulomb(0.1)));
    let t = Space::parse_tolerance(&nominal, "coulomb.fs=±60%").unwrap();
    let e = Space::new(nominal, vec![t]).unwrap_err().to_string();
    assert!(e.contains("fs") && e.contains("reaches 4"), "{e}");
    // f_c and f_s spread together: each sample is valid or refused as the pair it is
    let both = ["coulomb.fc=0.04..0.06", "coulomb.fs=0.055..0.2"]
        .iter()
        .map(|t| Space::parse_tolerance(&nominal, t).unwrap())
        .collect();
    let space = Space::new(nominal, both).unwrap();
    let (p, all) = samples(&space, 16);
    for s in &all {
        assert_eq!(s.outcome.is_ok(), s.values[1] >= s.values[0], "{s:?}");
    }
    let valid = all.iter().find(|s| s.outcome.is_ok()).unwrap();
    let text =
        coulomb(valid.values[1]).replace("fc = 0.05", &format!("fc = {:?}", valid.values[0]));
    let (c, _, _) = verdict_model(&model_of(&text), &BurstOptions::default()).unwrap();
    assert_eq!(valid.outcome.as_ref().unwrap().label(), c.verdict.name());
    let broken = all.iter().filter(|s| s.values[1] < s.values[0]).count();
    assert_eq!(p.outside_domain, broken as u64);
}
