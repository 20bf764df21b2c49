//! The term tables of a scenario file (`[coulomb]`, `[lugre]`, …): which kinds may have one (the
//! terms beyond the study's own) and a table's values from its named keys. What scenario files,
//! drive models and Python's `terms` read.

use super::Model;
use super::terms::AnyTerm;

/// A term's table from a scenario file: its kind and its parameter values (the keys it sets,
/// its defaults for the others).
pub type TermTable = (&'static str, Vec<f64>);

/// Why a term's named values cannot be read ([`term_values`]).
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TermTableError {
    /// No extra term has this kind.
    #[error("unknown term {name} (known: {})", known.join(", "))]
    UnknownKind {
        /// The kind given.
        name: String,
        /// The extra terms' kinds.
        known: Vec<&'static str>,
    },
    /// The term has no parameter of this name.
    #[error("unknown key {key} in [{name}] (known: {})", known.join(", "))]
    UnknownKey {
        /// The term's kind.
        name: String,
        /// The key given.
        key: String,
        /// The term's parameters.
        known: Vec<&'static str>,
    },
}

/// The kinds of the terms a model may add to the study's own (whose values come from
/// [`crate::Params`]).
pub fn extra_kinds() -> impl Iterator<Item = &'static str> {
    AnyTerm::KINDS
        .iter()
        .map(|k| k.0)
        .filter(|k| Model::is_extra_kind(k))
}

/// An extra term's kind and its parameter values from named values, the names it does not set
/// at their defaults: what a scenario file's table and Python's `terms` give. The values are
/// not checked here ([`AnyTerm::new`] checks their domains).
///
/// ```
/// use hdgear::model::tables::{term_values, TermTableError};
/// let (kind, values) = term_values("coulomb", [("fs", 0.6)]).unwrap();
/// assert_eq!((kind, values[1]), ("coulomb", 0.6));
/// assert!(matches!(term_values("coulomb", [("f_s", 0.6)]), Err(TermTableError::UnknownKey { .. })));
/// ```
pub fn term_values<'a>(
    name: &str,
    named: impl IntoIterator<Item = (&'a str, f64)>,
) -> std::result::Result<TermTable, TermTableError> {
    let found = AnyTerm::KINDS
        .iter()
        .find(|k| k.0 == name && Model::is_extra_kind(k.0));
    let Some(&(kind, _, params)) = found else {
        return Err(TermTableError::UnknownKind {
            name: name.to_string(),
            known: extra_kinds().collect(),
        });
    };
    let mut values: Vec<f64> = params.iter().map(|q| q.default).collect();
    for (key, v) in named {
        let Some(i) = params.iter().position(|p| p.name == key) else {
            return Err(TermTableError::UnknownKey {
                name: name.to_string(),
                key: key.to_string(),
                known: params.iter().map(|p| p.name).collect(),
            });
        };
        values[i] = v;
    }
    Ok((kind, values))
}
