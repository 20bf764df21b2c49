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
        let p = self.study_set()?;
        (*self == Model::study(&p)).then_some(p)
    }

    /// The remarks on the study's set this model carries ([`Model::study_set`]: α·ε ≠ 1, …);
    /// none without the study's stiffness.
    pub fn study_warnings(&self) -> crate::error::Result<Vec<crate::params::Warning>> {
        self.study_set().map_or(Ok(Vec::new()), |p| p.validate())
    }

    /// The study's six values this model carries, whatever else it holds: its cubic
    /// stiffness's α, γ, ε and its forcing's μ, δ, ω; `None` without the study's stiffness.
    pub fn study_set(&self) -> Option<Params> {
        let [alpha, gamma, eps] = self.terms().find_map(|t| match t {
            AnyTerm::Stiffness(s) => Some(s.array()),
            _ => None,
        })?;
        Some(self.set_with([alpha, gamma, eps]))
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

/// What a computation runs on: the study's set when the assembled model is the study's own
/// (its closed forms and its batch integrator: the same numbers as before models were
/// assembled), else the model with its terms. The library's generic seams
/// ([`crate::periodic::Periodic`], [`crate::sweep::Sweep`], [`crate::burst::PlaneSystem`]) take
/// either; [`crate::on_subject!`] runs one body on whichever a `Subject` holds.
///
/// ```
/// use hdgear::{Params, model::{Model, Subject, terms::AnyTerm}};
/// let p = Params::default();
/// assert_eq!(Model::study(&p).subject(), Subject::Study(p));
/// let f = Model::study(&p).with_term(AnyTerm::new("friction", &[0.1, 0.05]).unwrap()).unwrap();
/// assert_eq!(f.subject(), Subject::Model(f));
/// let omega = hdgear::on_subject!(&f.subject(), |s| hdgear::periodic::Oscillator::omega(s));
/// assert_eq!(omega, p.omega);
/// ```
// one value per run, borrowed as the type the library's seams take: not boxed
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Subject {
    /// The study's model.
    Study(Params),
    /// A model with terms beyond the study's, or without the study's own.
    Model(Model),
}

impl Model {
    /// This model as a [`Subject`]: [`Subject::Study`] where it is the study's model
    /// ([`Model::study_params`]).
    pub fn subject(self) -> Subject {
        match self.study_params() {
            Some(p) => Subject::Study(p),
            None => Subject::Model(self),
        }
    }
}

impl Subject {
    /// The stable equilibrium the default start takes at slow variable `a`: the cubic's in
    /// closed form for the study's set ([`crate::fast::stable_equilibrium`]), the model's own
    /// else ([`Model::stable_equilibrium`]).
    pub fn stable_equilibrium(&self, a: f64) -> crate::error::Result<f64> {
        match self {
            Subject::Study(p) => Ok(crate::fast::stable_equilibrium(p, a)),
            Subject::Model(m) => m.stable_equilibrium(a),
        }
    }

    /// The assembled model (the study's, built from the set, for [`Subject::Study`]).
    pub fn model(&self) -> Model {
        match self {
            Subject::Study(p) => Model::study(p),
            Subject::Model(m) => *m,
        }
    }
}

/// Runs `$body` with `$s` bound to the [`Subject`]'s parameter set or model, whichever it holds:
/// the two are different types behind the library's generic seams, so the body is compiled for
/// each.
#[macro_export]
macro_rules! on_subject {
    ($system:expr, |$s:ident| $body:expr) => {
        match $system {
            $crate::model::Subject::Study($s) => $body,
            $crate::model::Subject::Model($s) => $body,
        }
    };
}
