//! Rules between two parameters of one term beyond each one's own domain ([`Relation`]): the
//! static friction at least its sliding level, a Bouc–Wen loop whose state stays bounded.

use crate::error::{Error, Result};
use serde::Serialize;

/// A rule between two parameters of one term, beyond each one's own [`Domain`](super::terms::Domain): declared with
/// the term ([`Term::RELATIONS`](super::terms::Term::RELATIONS)) and checked wherever a term is built ([`AnyTerm::new`](super::terms::AnyTerm::new)), so a
/// scenario table, a bearing law, a sweep point and a card's friction all meet the same rule.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Relation {
    /// Parameter `upper` ≥ parameter `lower` (indices into [`Term::PARAMS`](super::terms::Term::PARAMS)), for the reason
    /// given.
    AtLeast {
        /// The parameter bounded below.
        upper: usize,
        /// The parameter that bounds it.
        lower: usize,
        /// The rule in words and why it holds.
        reason: &'static str,
    },
    /// Parameter `first` + parameter `second` ≥ 0 wherever parameter `when` ≥ `from`, for the
    /// reason given.
    NonNegativeSumFrom {
        /// The parameter named in the error.
        first: usize,
        /// The other.
        second: usize,
        /// The parameter that decides whether the rule applies.
        when: usize,
        /// The value of `when` from which it applies.
        from: f64,
        /// The rule in words and why it holds.
        reason: &'static str,
    },
}

impl Relation {
    /// The two parameters it relates (the one an error names first) and the rule in words.
    fn parts(self) -> (usize, usize, &'static str) {
        match self {
            Relation::AtLeast {
                upper,
                lower,
                reason,
            } => (upper, lower, reason),
            Relation::NonNegativeSumFrom {
                first,
                second,
                reason,
                ..
            } => (first, second, reason),
        }
    }

    /// The rule in words, and why it holds.
    pub fn reason(self) -> &'static str {
        self.parts().2
    }

    /// Whether `values` (in the term's parameter order) keep the rule.
    pub fn holds(self, values: &[f64]) -> bool {
        let (a, b, _) = self.parts();
        match self {
            Relation::AtLeast { .. } => values[a] >= values[b],
            Relation::NonNegativeSumFrom { when, from, .. } => {
                values[when] < from || values[a] + values[b] >= 0.0
            }
        }
    }

    /// Checks `values` (in the term's parameter order) against the rule; the error names both
    /// parameters (`name_of` the i-th's name) with their values.
    pub fn check(self, name_of: impl Fn(usize) -> &'static str, values: &[f64]) -> Result<()> {
        if self.holds(values) {
            return Ok(());
        }
        let (name, other, reason) = self.parts();
        Err(Error::RelationBroken {
            name: name_of(name).to_string(),
            value: values[name],
            other: name_of(other).to_string(),
            other_value: values[other],
            reason,
        })
    }
}
