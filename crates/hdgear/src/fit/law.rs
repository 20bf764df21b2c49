//! The law a fit adjusts: the model's own terms ([`AnyTerm`]), in the data's units, with the
//! parameters to free named as the terms name them.

use crate::error::{Error, Result};
use crate::model::tables::TermTable;
use crate::model::terms::AnyTerm;
use serde::Serialize;

/// The terms whose sum is fitted to the data, each with its values in the data's (SI) units, as
/// a drive's bearing laws are given ([`crate::scenario::Scenario::bearings`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FitLaw {
    terms: Vec<AnyTerm>,
}

/// A parameter of a [`FitLaw`]: term `term`'s `index`-th, with its qualified name `kind.name`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct LawParam {
    /// `kind.name`, e.g. `coulomb.fs`.
    pub name: String,
    /// The term's position in the law.
    pub term: usize,
    /// The parameter's position in the term's table.
    pub index: usize,
}

impl FitLaw {
    /// The law of these terms: at least one, each kind once.
    pub fn new(terms: Vec<AnyTerm>) -> Result<FitLaw> {
        let refuse = |text: String, reason: &str| Error::InvalidInput {
            what: "fitted law",
            text,
            reason: reason.into(),
        };
        if terms.is_empty() {
            return Err(refuse("(no terms)".into(), "give at least one term to fit"));
        }
        for (i, t) in terms.iter().enumerate() {
            if terms[..i].iter().any(|u| u.kind() == t.kind()) {
                return Err(refuse(t.kind().into(), "each kind of term may appear once"));
            }
        }
        Ok(FitLaw { terms })
    }

    /// The law of a scenario file's term tables ([`crate::scenario::Scenario::term_tables`]).
    pub fn from_tables(tables: &[TermTable]) -> Result<FitLaw> {
        FitLaw::new(
            tables
                .iter()
                .map(|(kind, values)| AnyTerm::new(kind, values))
                .collect::<Result<_>>()?,
        )
    }

    /// Its terms.
    pub fn terms(&self) -> &[AnyTerm] {
        &self.terms
    }

    /// The parameter `name`: `kind.name`, or the bare name where one term has it.
    pub fn param(&self, name: &str) -> Result<LawParam> {
        let (kind, bare) = match name.split_once('.') {
            Some((k, b)) => (Some(k), b),
            None => (None, name),
        };
        let mut found = self.terms.iter().enumerate().filter_map(|(term, t)| {
            let index = t.params().iter().position(|p| p.name == bare)?;
            (kind.is_none_or(|k| k == t.kind())).then(|| LawParam {
                name: format!("{}.{}", t.kind(), bare),
                term,
                index,
            })
        });
        match (found.next(), found.next()) {
            (Some(q), None) => Ok(q),
            (Some(_), Some(_)) => Err(Error::InvalidInput {
                what: "fitted parameter",
                text: name.into(),
                reason: "two terms have it: write it as kind.name".into(),
            }),
            (None, _) => Err(Error::InvalidInput {
                what: "fitted parameter",
                text: name.into(),
                reason: format!(
                    "the law has no such parameter (it has {})",
                    self.names().join(", ")
                ),
            }),
        }
    }

    /// Every parameter's qualified name, in order.
    pub fn names(&self) -> Vec<String> {
        self.terms
            .iter()
            .flat_map(|t| {
                t.params()
                    .iter()
                    .map(|p| format!("{}.{}", t.kind(), p.name))
            })
            .collect()
    }

    /// The value of `q`.
    pub fn get(&self, q: &LawParam) -> f64 {
        self.terms[q.term].values()[q.index]
    }

    /// The law with the parameters `qs` set to `values`, each term checked whole (domains and
    /// relations such as f_s ≥ f_c).
    pub fn with(&self, qs: &[LawParam], values: &[f64]) -> Result<FitLaw> {
        let mut tables: Vec<Vec<f64>> = self.terms.iter().map(|t| t.values().to_vec()).collect();
        for (q, &v) in qs.iter().zip(values) {
            tables[q.term][q.index] = v;
        }
        let terms = self
            .terms
            .iter()
            .zip(&tables)
            .map(|(t, values)| AnyTerm::new(t.kind(), values))
            .collect::<Result<_>>()?;
        Ok(FitLaw { terms })
    }

    /// The law as a scenario file's term tables (`[coulomb]` with `fc = …`), values written to
    /// round-trip.
    pub fn to_toml(&self) -> String {
        let mut out = String::new();
        for t in &self.terms {
            out += &format!("[{}]\n", t.kind());
            for (p, v) in t.params().iter().zip(t.values()) {
                out += &format!("{} = {:?}\n", p.name, v);
            }
        }
        out
    }
}
