//! A fitted card: a base card with the sections a fit determined replaced, their source the fit
//! itself (data file, checksum, residual, intervals), and the fitted stiffness's standard errors
//! as its tolerance bands for `robust`.

use super::Fit;
use crate::error::{Error, Result};
use crate::physical::card::{Card, CardFile, FORMAT, Friction, Source, SourceKind, Tolerances};
use std::collections::BTreeMap;

/// The key of a fit's entry in a card file's `[sources]`.
fn source_key(fit: &Fit) -> String {
    format!("fit-{}-{}", fit.kind.name(), fit.source.crc32)
}

/// The fit as a citation: what was fitted to what, how well, and each estimate's interval.
pub fn citation(fit: &Fit) -> String {
    let intervals: Vec<String> = fit
        .estimates
        .iter()
        .map(|e| match e.interval() {
            Some([lo, hi]) => format!("{} = {:.6e} [{:.4e}, {:.4e}]", e.name, e.value, lo, hi),
            None => format!("{} = {:.6e} (undetermined)", e.name, e.value),
        })
        .collect();
    format!(
        "hdgear fit of the {} data {} (CRC-32 {}, {} points): residual noise {:.3e} N m on {} \
         degrees of freedom; 95 % intervals: {}",
        fit.kind.name(),
        fit.source.path,
        fit.source.crc32,
        fit.x.len(),
        fit.noise,
        fit.dof,
        intervals.join("; ")
    )
}

/// `base` with what `fit` determined: a friction law (`coulomb`, `stribeck` or `lugre`: its
/// levels, Stribeck speed and viscous coefficient, at the output) replaces the friction section;
/// a `piecewise` curve (no offset, sharp kinks) replaces the stiffness section, and its
/// stiffnesses' standard errors become the tolerance bands `k1`, `k2` (normal). The result is
/// validated as any card file is.
pub fn fitted_card(base: &Card, sources: &BTreeMap<String, Source>, fit: &Fit) -> Result<CardFile> {
    let key = source_key(fit);
    let mut card = base.clone();
    let mut sources = sources.clone();
    sources.insert(
        key.clone(),
        Source {
            kind: SourceKind::Fit,
            cite: citation(fit),
        },
    );
    let mut changed = false;
    let refuse = |reason: &str| Error::InvalidInput {
        what: "fitted card",
        text: base.name.clone(),
        reason: reason.into(),
    };
    for t in fit.law.terms() {
        let v = t.values();
        match t.kind() {
            "coulomb" | "stribeck" => {
                card.friction = Some(friction(&key, [v[0], v[1], v[2], v[3]]));
                changed = true;
            }
            "lugre" => {
                card.friction = Some(friction(&key, [v[0], v[1], v[2], v[5]]));
                changed = true;
            }
            "piecewise" => {
                curve(&mut card, &key, v, fit).map_err(&refuse)?;
                changed = true;
            }
            _ => {}
        }
    }
    if !changed {
        return Err(refuse(
            "the fitted law has no term a card holds (coulomb, stribeck or lugre friction; a piecewise curve)",
        ));
    }
    // the sources the card cites, and no others
    let mut cited: Vec<String> = card
        .sections()
        .iter()
        .map(|s| s.source().to_string())
        .collect();
    cited.extend(card.tolerance.as_ref().map(|t| t.source.clone()));
    sources.retain(|k, _| cited.contains(k));
    let file = CardFile {
        format: FORMAT,
        sources,
        card: vec![card],
    };
    // what a reader of the file will check
    CardFile::parse(&file.to_toml())
}

fn friction(key: &str, [fc, fs, vst, cv]: [f64; 4]) -> Friction {
    Friction {
        source: key.into(),
        note: Some("fitted by hdgear fit, at the output".into()),
        coulomb: Some(fc),
        breakaway: Some(fs),
        stribeck_speed: Some(vst),
        viscous: Some(cv),
        ..Friction::default()
    }
}

/// A fitted `piecewise` curve into the card's stiffness section, its stiffnesses' standard
/// errors into the tolerance bands `k1`, `k2`; refused (the reason) with an offset or rounding.
fn curve(
    card: &mut Card,
    key: &str,
    v: &[f64],
    fit: &Fit,
) -> std::result::Result<(), &'static str> {
    let [k1, k2, k3, x1, w2, x0, xr] = [v[0], v[1], v[2], v[3], v[4], v[5], v[6]];
    if x0 != 0.0 || xr != 0.0 {
        return Err("a card's curve has no offset (x0) or rounding (xr): hold them at 0");
    }
    card.stiffness.source = key.into();
    card.stiffness.note = Some("fitted by hdgear fit (t1 = k1·x1, t2 = t1 + k2·w2)".into());
    card.stiffness.t1 = Some(k1 * x1);
    card.stiffness.t2 = Some(k1 * x1 + k2 * w2);
    card.stiffness.k1 = Some(k1);
    card.stiffness.k2 = Some(k2);
    card.stiffness.k3 = Some(k3);
    let bands: BTreeMap<String, String> = fit
        .estimates
        .iter()
        .filter_map(|e| {
            let name = e.name.strip_prefix("piecewise.")?;
            let se = e.std_error?;
            ["k1", "k2"]
                .contains(&name)
                .then(|| (name.to_string(), format!("normal:{se:e}")))
        })
        .collect();
    if !bands.is_empty() {
        card.tolerance = Some(Tolerances {
            source: key.into(),
            bands,
        });
    }
    Ok(())
}
