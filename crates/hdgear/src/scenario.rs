//! Scenario files: one TOML file that can describe both a dimensionless parameter set
//! (`[params]`) and a physical drive (`[physical]`). It sits above [`crate::params`] and
//! [`crate::physical`], which know nothing of files.

use crate::error::{Error, Result};
use crate::params::ParamOverrides;
use crate::physical::PhysicalOverrides;
use crate::physical::model::{BEARING_KINDS, Bearings};
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
    /// Friction at the bearings of the two-inertia drive (the `[bearings.output.LAW]` and
    /// `[bearings.input.LAW]` tables, SI values: [`Scenario::bearings`]).
    #[serde(default)]
    pub bearings: Option<BearingTables>,
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
        s.bearings(path)?;
        Ok(s)
    }

    /// The bearings' friction laws the `[bearings]` table gives (none without it): at most one
    /// law per side, each a table named by its kind with every parameter in SI units
    /// ([`Bearings::law`]), e.g.
    ///
    /// ```toml
    /// [bearings.output.stribeck]
    /// fc = 0.8      # N m
    /// fs = 1.2      # N m
    /// vst = 0.05    # rad/s
    /// cv = 0.01     # N m s/rad
    /// vr = 1e-3     # rad/s
    /// ```
    pub fn bearings(&self, path: &Path) -> Result<Bearings> {
        let Some(tables) = &self.bearings else {
            return Ok(Bearings::default());
        };
        let err = |message: String| Error::Config {
            path: path.to_path_buf(),
            message,
        };
        let side = |name: &str, laws: &Option<BTreeMap<String, BTreeMap<String, f64>>>| {
            let Some(laws) = laws else { return Ok(None) };
            let mut laws = laws.iter();
            match (laws.next(), laws.next()) {
                (Some((kind, values)), None) => {
                    let named = values.iter().map(|(k, &v)| (k.as_str(), v));
                    Bearings::law(name, kind, named)
                        .map(Some)
                        .map_err(|e| err(format!("[bearings.{name}.{kind}] {e}")))
                }
                _ => Err(err(format!(
                    "[bearings.{name}] holds one law's table (one of {})",
                    BEARING_KINDS.join(", ")
                ))),
            }
        };
        Bearings::new(
            side("output", &tables.output)?,
            side("input", &tables.input)?,
        )
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

/// The `[bearings]` table of a scenario file: per side, one law's table by its kind.
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BearingTables {
    /// The output bearing's law (on θo').
    #[serde(default)]
    pub output: Option<BTreeMap<String, BTreeMap<String, f64>>>,
    /// The wave generator's law (on θi').
    #[serde(default)]
    pub input: Option<BTreeMap<String, BTreeMap<String, f64>>>,
}

pub use crate::model::tables::{TermTable, TermTableError, extra_kinds, term_values};

impl Scenario {
    /// The extra terms' tables as (kind, values), each checked: a known kind, a table, and known
    /// keys with numbers (errors name the table and the key).
    pub fn term_tables(&self, path: &Path) -> Result<Vec<TermTable>> {
        let err = |message: String| Error::Config {
            path: path.to_path_buf(),
            message,
        };
        let mut out = Vec::new();
        for (name, value) in &self.terms {
            let table = value.as_table();
            let mut named = Vec::new();
            for (key, v) in table.into_iter().flatten() {
                let number = v.as_float().or_else(|| v.as_integer().map(|n| n as f64));
                named.push((key.as_str(), number));
            }
            let read = term_values(name, named.iter().map(|&(k, v)| (k, v.unwrap_or(f64::NAN))));
            match read {
                Err(TermTableError::UnknownKind { known, .. }) => {
                    let known: Vec<&str> =
                        ["params", "physical"].into_iter().chain(known).collect();
                    return Err(err(format!(
                        "unknown table [{name}] (known: {})",
                        known.join(", ")
                    )));
                }
                Err(e) => return Err(err(e.to_string())),
                Ok(_) if table.is_none() => {
                    return Err(err(format!("[{name}] must be a table of numbers")));
                }
                Ok(kv) => match named.iter().find(|(_, v)| v.is_none()) {
                    Some((key, _)) => return Err(err(format!("[{name}] {key} must be a number"))),
                    None => out.push(kv),
                },
            }
        }
        Ok(out)
    }

    /// Whether the file has tables of extra terms (which only the commands that run an
    /// assembled model read).
    pub fn has_terms(&self) -> bool {
        !self.terms.is_empty()
    }

    /// The model these tables give on top of the study's with `p`: each term's table, its
    /// missing keys at their defaults, checked against the parameters' domains. A `[spring]`
    /// table is the model's stiffness: it replaces the study's αx³ − x² + γ(x − ε), which leaves
    /// the unit inertia and damping under μ + δ sin ωτ ([`crate::model::Model::damped`]; a linear
    /// oscillator with Coulomb friction, say), and `[params]` may then not set α, γ or ε.
    pub fn model(&self, p: &crate::Params, path: &Path) -> Result<crate::model::Model> {
        use crate::model::{Model, spring::Spring, terms::Term};
        let tables = self.term_tables(path)?;
        let base = if tables.iter().any(|(kind, _)| *kind == Spring::KIND) {
            use crate::params::Param;
            let given = self.params.as_ref().and_then(|o| {
                [Param::Alpha, Param::Gamma, Param::Eps]
                    .into_iter()
                    .find_map(|q| Some((q.name(), o.get(q)?)))
            });
            if let Some((name, v)) = given {
                return Err(Error::Config {
                    path: path.to_path_buf(),
                    message: format!(
                        "[params] {name} = {v} does not apply: the [spring] table is the model's \
                         stiffness, in place of the study's αx³ − x² + γ(x − ε)"
                    ),
                });
            }
            Model::damped(p.mu, p.delta, p.omega)
        } else {
            Model::study(p)
        };
        tables.into_iter().try_fold(base, |m, (kind, values)| {
            m.with_term(crate::model::terms::AnyTerm::new(kind, &values)?)
        })
    }
}

/// The largest scenario file read (a scenario is a few lines; this only stops `/dev/zero`).
pub const SCENARIO_MAX_BYTES: u64 = 1 << 20;
