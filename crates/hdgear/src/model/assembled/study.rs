//! How a [`Model`] meets the study's set: whether it is the study's model itself, and how it
//! serialises (as its description, its parameters by the names users write).

use super::{Model, ModelParam};
use crate::model::terms::AnyTerm;
use crate::params::Params;
use serde::Serialize;

impl Model {
    /// The study's set when this model is the study's model itself ([`Model::study`]: unit
    /// damping, the cubic stiffness, nothing else), so that every computation on it may take the
    /// study's closed forms and fast paths with the same dynamics; `None` for any other model
    /// (unlike [`Model::equivalent_params`], which only matches the static torque).
    ///
    /// ```
    /// use hdgear::{Params, model::{Model, terms::AnyTerm}};
    /// let p = Params::default();
    /// assert_eq!(Model::study(&p).study_params(), Some(p));
    /// let f = Model::study(&p).with_term(AnyTerm::new("friction", &[0.1, 0.05]).unwrap()).unwrap();
    /// assert_eq!(f.study_params(), None);
    /// assert_eq!(f.equivalent_params(), Some(p)); // friction has no static torque
    /// ```
    pub fn study_params(&self) -> Option<Params> {
        let [alpha, gamma, eps] = self.terms().find_map(|t| match t {
            AnyTerm::Stiffness(s) => Some(s.0),
            _ => None,
        })?;
        let p = self.set_with([alpha, gamma, eps]);
        (*self == Model::study(&p)).then_some(p)
    }

    /// The study's set with the stiffness `[α, γ, ε]` under this model's forcing.
    pub(super) fn set_with(&self, [alpha, gamma, eps]: [f64; 3]) -> Params {
        let [mu, delta, omega] = self.forcing;
        Params {
            alpha,
            gamma,
            eps,
            mu,
            delta,
            omega,
        }
    }
}

/// A parameter serialises as the name users write.
impl Serialize for ModelParam {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.name)
    }
}

/// A model serialises as its [`super::Description`] (equation, terms, parameters, facts).
impl Serialize for Model {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        self.describe().serialize(s)
    }
}
