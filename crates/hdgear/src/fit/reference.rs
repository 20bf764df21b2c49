//! Published friction laws of real harmonic-drive joints, shipped as examples and as a check on
//! the fit: the ergoCub humanoid's identified Stribeck–Coulomb–viscous laws
//! (`laws/ergocub-friction.toml`, with its citation).

use super::FitLaw;
use crate::model::terms::AnyTerm;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The file of the ergoCub joints' friction laws, with its citation in its comments.
pub const ERGOCUB_TOML: &str = include_str!("../../laws/ergocub-friction.toml");

/// One joint's published friction law.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct JointFriction {
    /// The joint (`l_knee`, `r_ankle_roll`, …).
    pub joint: String,
    /// Its harmonic drive's ratio.
    pub ratio: f64,
    /// The law as hdgear's `coulomb` term (F_c, F_s, v_s, F_v), joint side, SI.
    pub law: FitLaw,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Table {
    ratio: f64,
    fc: f64,
    fs: f64,
    vst: f64,
    cv: f64,
}

/// The ergoCub joints' laws (Sorrentino et al., Humanoids 2024), in the file's order of names.
pub fn ergocub() -> Vec<JointFriction> {
    let tables: BTreeMap<String, Table> =
        toml::from_str(ERGOCUB_TOML).expect("the shipped laws parse");
    tables
        .into_iter()
        .map(|(joint, t)| JointFriction {
            joint,
            ratio: t.ratio,
            law: FitLaw::new(vec![
                AnyTerm::new("coulomb", &[t.fc, t.fs, t.vst, t.cv]).expect("a valid law"),
            ])
            .expect("one term"),
        })
        .collect()
}
