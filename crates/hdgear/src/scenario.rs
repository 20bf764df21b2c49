//! Scenario files: one TOML file that can describe both a dimensionless parameter set
//! (`[params]`) and a physical drive (`[physical]`). It sits above [`crate::params`] and
//! [`crate::physical`], which know nothing of files.

use crate::error::{Error, Result};
use crate::params::ParamOverrides;
use crate::physical::PhysicalOverrides;
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

/// A scenario file. Tables: `[params]` (dimensionless), `[physical]` (a drive in SI units; read
/// by the physical-model commands) and one table per extra term of the model, named by the
/// term's kind (`[friction]`, `[stribeck]`: [`crate::model::terms::AnyTerm::KINDS`]; read by
/// [`Scenario::model`]). Unknown tables or keys are errors that name them.
#[derive(Clone, Debug, Default, Deserialize)]
pub struct Scenario {
    /// Dimensionless parameters (the `[params]` table), if the file has one.
    #[serde(default)]
    pub params: Option<ParamOverrides>,
    /// Physical drive parameters in SI units (the `[physical]` table), if the file has one.
    #[serde(default)]
    pub physical: Option<PhysicalOverrides>,
    /// Every other table: a term of the model each (checked by [`Scenario::parse`]).
    #[serde(flatten)]
    pub terms: BTreeMap<String, toml::Value>,
}

impl Scenario {
    /// Parses a scenario from TOML text; `path` is used in error messages.
    pub fn parse(text: &str, path: &Path) -> Result<Scenario> {
        let s: Scenario = toml::from_str(text).map_err(|e| Error::Config {
            path: path.to_path_buf(),
            message: e.message().to_string()
                + &e.span()
                    .map(|s| {
                        let line = text[..s.start].matches('\n').count() + 1;
                        format!(" (line {line})")
                    })
                    .unwrap_or_default(),
        })?;
        s.term_tables(path)?;
        Ok(s)
    }

    /// Reads and parses a scenario file (at most [`SCENARIO_MAX_BYTES`]).
    pub fn load(path: &Path) -> Result<Scenario> {
        use std::io::Read;
        let err = |message: String| Error::Config {
            path: path.to_path_buf(),
            message,
        };
        let file = crate::output::open_input(path).map_err(|e| err(e.to_string()))?;
        let mut bytes = Vec::new();
        file.take(SCENARIO_MAX_BYTES + 1)
            .read_to_end(&mut bytes)
            .map_err(|e| err(e.to_string()))?;
        if bytes.len() as u64 > SCENARIO_MAX_BYTES {
            return Err(err(format!(
                "larger than {SCENARIO_MAX_BYTES} bytes: not a scenario file"
            )));
        }
        let text = String::from_utf8(bytes).map_err(|_| err("not UTF-8 text".into()))?;
        Scenario::parse(&text, path)
    }
}

/// A term's table from a scenario file: its kind and its parameter values (the keys it sets,
/// its defaults for the others).
type TermTable = (&'static str, Vec<f64>);

impl Scenario {
    /// The extra terms' tables as (kind, values), each checked: a known kind, a table, and known
    /// keys with numbers (errors name the table and the key).
    fn term_tables(&self, path: &Path) -> Result<Vec<TermTable>> {
        use crate::model::{Model, terms::AnyTerm};
        let err = |message: String| Error::Config {
            path: path.to_path_buf(),
            message,
        };
        let mut out = Vec::new();
        for (name, value) in &self.terms {
            // the study's own terms (damping, stiffness) take their values from [params]
            let found = AnyTerm::KINDS
                .iter()
                .find(|k| k.0 == name && Model::is_extra_kind(k.0));
            let Some(&(kind, _, params)) = found else {
                let known: Vec<&str> = ["params", "physical"]
                    .into_iter()
                    .chain(
                        AnyTerm::KINDS
                            .iter()
                            .map(|k| k.0)
                            .filter(|k| Model::is_extra_kind(k)),
                    )
                    .collect();
                return Err(err(format!(
                    "unknown table [{name}] (known: {})",
                    known.join(", ")
                )));
            };
            let table = value
                .as_table()
                .ok_or_else(|| err(format!("[{name}] must be a table of numbers")))?;
            let mut values: Vec<f64> = params.iter().map(|q| q.default).collect();
            for (key, v) in table {
                let Some(i) = params.iter().position(|p| p.name == key) else {
                    let known: Vec<&str> = params.iter().map(|p| p.name).collect();
                    return Err(err(format!(
                        "unknown key {key} in [{name}] (known: {})",
                        known.join(", ")
                    )));
                };
                values[i] = v
                    .as_float()
                    .or_else(|| v.as_integer().map(|n| n as f64))
                    .ok_or_else(|| err(format!("[{name}] {key} must be a number")))?;
            }
            out.push((kind, values));
        }
        Ok(out)
    }

    /// Whether the file has tables of extra terms (which only the commands that run an
    /// assembled model read).
    pub fn has_terms(&self) -> bool {
        !self.terms.is_empty()
    }

    /// The model these tables give on top of the study's with `p`: each term's table, its
    /// missing keys at their defaults, checked against the parameters' domains.
    pub fn model(&self, p: &crate::Params, path: &Path) -> Result<crate::model::Model> {
        self.term_tables(path)?
            .into_iter()
            .try_fold(crate::model::Model::study(p), |m, (kind, values)| {
                m.with_term(crate::model::terms::AnyTerm::new(kind, &values)?)
            })
    }
}

/// The largest scenario file read (a scenario is a few lines; this only stops `/dev/zero`).
pub const SCENARIO_MAX_BYTES: u64 = 1 << 20;
