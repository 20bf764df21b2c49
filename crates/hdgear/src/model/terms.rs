//! Every term a drive model is assembled from, in one list ([`AnyTerm`]): each a torque
//! T(x, x', z) on the left-hand side of x'' + Σ T = μ + δ sin ωτ (z the term's own internal
//! state, where it has one: [`super::memory`]). What a term is, is [`Term`]
//! ([`super::term`]).

pub use super::control::{Dither, VirtualDamping, VirtualStiffness, Washout};
pub use super::dahl::Dahl;
pub use super::delay::Delay;
pub use super::drag::Drag;
pub use super::excitation::Multisine;
pub use super::friction::STATIC_AT_LEAST_SLIDING;
pub use super::friction::{Coulomb, Friction, Stribeck};
use super::jet::Lanes;
pub use super::memory::{BoucWen, LuGre};
pub use super::mesh::KinematicError;
pub use super::mesh_loss::{Elastic, MeshLoss};
pub use super::piecewise::Piecewise;
pub use super::relation::Relation;
pub use super::schedule::Scheduled;
pub use super::spring::Spring;
pub use super::study_terms::{Damping, Stiffness};
pub use super::term::{
    Domain, LANE_PARAMS, LaneRows, MAX_LINE, MAX_ROWS, ParamInfo, Scratch, Side, StateInfo, Term,
    piece_sign,
};
use crate::error::{Error, Result};
use serde::Serialize;

/// Declares [`AnyTerm`] over the term types and forwards [`Term`]'s methods to them: the one
/// list of terms hdgear has (a new term is one line here).
macro_rules! any_term {
    ($($variant:ident),* $(,)?) => {
        /// Any of hdgear's terms: what a [`super::Model`] holds (stack-only, `Copy`). Serialised
        /// as `{"kind": KIND, "values": [...]}`, the kind its [`Term::KIND`].
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub enum AnyTerm {
            $(
                #[doc = concat!("[`", stringify!($variant), "`].")]
                $variant($variant),
            )*
        }

        impl Serialize for AnyTerm {
            fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
                use serde::ser::SerializeStruct;
                let mut st = s.serialize_struct("AnyTerm", 2)?;
                st.serialize_field("kind", self.kind())?;
                st.serialize_field("values", self.values())?;
                st.end()
            }
        }

        impl AnyTerm {
            /// The kinds of term, each with its line and parameters.
            pub const KINDS: &'static [(&'static str, &'static str, &'static [ParamInfo])] =
                &[$(($variant::KIND, $variant::ABOUT, $variant::PARAMS)),*];

            /// The parameters of the term of kind `kind` (None for no such kind).
            pub fn params_of(kind: &str) -> Option<&'static [ParamInfo]> {
                AnyTerm::KINDS.iter().find(|k| k.0 == kind).map(|k| k.2)
            }

            /// The term of kind `kind` with these values (checked: their count and domains).
            pub fn new(kind: &str, values: &[f64]) -> Result<AnyTerm> {
                $(
                    if kind == $variant::KIND {
                        check_values($variant::PARAMS, $variant::RELATIONS, values)?;
                        return Ok(AnyTerm::$variant($variant::from_values(values)));
                    }
                )*
                Err(unknown_kind(kind))
            }

            /// The term's kind.
            pub fn kind(&self) -> &'static str {
                match self { $(AnyTerm::$variant(_) => $variant::KIND,)* }
            }
            /// Its parameters.
            pub fn params(&self) -> &'static [ParamInfo] {
                match self { $(AnyTerm::$variant(_) => $variant::PARAMS,)* }
            }
            /// The rules between its parameters ([`Term::RELATIONS`]).
            pub fn relations(&self) -> &'static [Relation] {
                match self { $(AnyTerm::$variant(_) => $variant::RELATIONS,)* }
            }
            /// Its parameter values.
            pub fn values(&self) -> &[f64] {
                match self { $(AnyTerm::$variant(t) => t.values(),)* }
            }
            /// Its internal state, if it has one.
            pub fn state(&self) -> Option<StateInfo> {
                match self { $(AnyTerm::$variant(_) => $variant::STATE,)* }
            }
            /// Whether its law is not analytic across x' = 0 ([`Term::SWITCHES_AT_REST`]).
            pub fn switches_at_rest(&self) -> bool {
                match self { $(AnyTerm::$variant(_) => $variant::SWITCHES_AT_REST,)* }
            }
            /// Whether it is a load of mean 0 whatever the motion ([`Term::LOAD`]).
            pub fn is_load(&self) -> bool {
                match self { $(AnyTerm::$variant(_) => $variant::LOAD,)* }
            }
            /// Whether its torque at rest depends on the load's phase ([`Term::SCHEDULED`]).
            pub fn is_scheduled(&self) -> bool {
                match self { $(AnyTerm::$variant(_) => $variant::SCHEDULED,)* }
            }
            /// Whether its law is not analytic across z = 0
            /// ([`Term::SWITCHES_AT_ZERO_STATE`]).
            pub fn switches_at_zero_state(&self) -> bool {
                match self { $(AnyTerm::$variant(_) => $variant::SWITCHES_AT_ZERO_STATE,)* }
            }
            /// T(x, v, z).
            #[inline]
            pub fn torque(&self, x: f64, v: f64, z: f64) -> f64 {
                match self { $(AnyTerm::$variant(t) => t.torque(x, v, z),)* }
            }
            /// (∂T/∂x, ∂T/∂v, ∂T/∂z).
            #[inline]
            pub fn gradient(&self, x: f64, v: f64, z: f64) -> [f64; 3] {
                match self { $(AnyTerm::$variant(t) => t.gradient(x, v, z),)* }
            }
            /// ∂T/∂p for its parameter `i`.
            pub fn param_derivative(&self, i: usize, x: f64, v: f64, z: f64) -> f64 {
                match self { $(AnyTerm::$variant(t) => t.param_derivative(i, x, v, z),)* }
            }
            /// Row k of T's Taylor coefficients ([`Term::taylor`]).
            #[inline(always)]
            pub fn taylor(&self, k: usize, x: &[f64], v: &[f64], z: &[f64], rows: &mut Scratch) -> f64 {
                match self { $(AnyTerm::$variant(t) => t.taylor(k, x, v, z, rows),)* }
            }
            /// Whether its kind runs on vector lanes ([`Term::ON_LANES`]).
            pub fn on_lanes(&self) -> bool {
                match self { $(AnyTerm::$variant(_) => $variant::ON_LANES,)* }
            }
            /// [`Term::taylor_lanes`] of its kind, with the lanes' parameters `values`.
            #[inline(always)]
            pub fn taylor_lanes(&self, values: &[Lanes], k: usize, x: &[Lanes], v: &[Lanes], z: &[Lanes], rows: &mut LaneRows) -> Option<Lanes> {
                match self { $(AnyTerm::$variant(_) => $variant::taylor_lanes(values, k, x, v, z, rows),)* }
            }
            /// [`Term::rate_taylor_lanes`] of its kind, with the lanes' parameters `values`.
            #[inline(always)]
            pub fn rate_taylor_lanes(&self, values: &[Lanes], k: usize, x: &[Lanes], v: &[Lanes], z: &[Lanes], rows: &mut LaneRows) -> Lanes {
                match self { $(AnyTerm::$variant(_) => $variant::rate_taylor_lanes(values, k, x, v, z, rows),)* }
            }
            /// The numbers its copy on lanes reads ([`Term::lane_values`]).
            pub fn lane_values(&self) -> [f64; LANE_PARAMS] {
                match self { $(AnyTerm::$variant(t) => t.lane_values(),)* }
            }
            /// What its copy on lanes takes as the same on every lane ([`Term::lane_shape`]).
            pub fn lane_shape(&self) -> usize {
                match self { $(AnyTerm::$variant(t) => t.lane_shape(),)* }
            }
            /// z' of its internal state ([`Term::rate`]).
            #[inline]
            pub fn rate(&self, x: f64, v: f64, z: f64) -> f64 {
                match self { $(AnyTerm::$variant(t) => t.rate(x, v, z),)* }
            }
            /// (∂r/∂x, ∂r/∂v, ∂r/∂z) ([`Term::rate_gradient`]).
            #[inline]
            pub fn rate_gradient(&self, x: f64, v: f64, z: f64) -> [f64; 3] {
                match self { $(AnyTerm::$variant(t) => t.rate_gradient(x, v, z),)* }
            }
            /// ∂r/∂p for its parameter `i`.
            pub fn rate_param_derivative(&self, i: usize, x: f64, v: f64, z: f64) -> f64 {
                match self { $(AnyTerm::$variant(t) => t.rate_param_derivative(i, x, v, z),)* }
            }
            /// Row k of r's Taylor coefficients ([`Term::rate_taylor`]).
            #[inline(always)]
            pub fn rate_taylor(&self, k: usize, x: &[f64], v: &[f64], z: &[f64], rows: &mut Scratch) -> f64 {
                match self { $(AnyTerm::$variant(t) => t.rate_taylor(k, x, v, z, rows),)* }
            }
            /// Its state's equation as text ([`Term::rate_text`]).
            pub fn rate_text(&self) -> Option<String> {
                match self { $(AnyTerm::$variant(t) => t.rate_text(),)* }
            }
            /// Its state's equation in LaTeX ([`Term::rate_latex`]).
            pub fn rate_latex(&self) -> Option<String> {
                match self { $(AnyTerm::$variant(t) => t.rate_latex(),)* }
            }
            /// The term's text.
            pub fn text(&self) -> String {
                match self { $(AnyTerm::$variant(t) => t.text(),)* }
            }
            /// The term's LaTeX.
            pub fn latex(&self) -> String {
                match self { $(AnyTerm::$variant(t) => t.latex(),)* }
            }
            /// Whether it may shorten a Taylor step ([`Term::LIMITS_STEPS`]).
            pub fn limits_steps(&self) -> bool {
                match self { $(AnyTerm::$variant(_) => $variant::LIMITS_STEPS,)* }
            }
            /// The longest step its own series allow ([`Term::step_limit`]).
            pub fn step_limit(&self, rows: &Scratch, order: usize, h: f64, negligible: f64) -> f64 {
                match self { $(AnyTerm::$variant(t) => t.step_limit(rows, order, h, negligible),)* }
            }
            /// [`Term::step_limit_lanes`] of its kind, with the lanes' parameters `values`.
            #[inline(always)]
            pub fn step_limit_lanes(&self, values: &[Lanes], rows: &LaneRows, order: usize, h: Lanes, negligible: Lanes) -> Lanes {
                match self { $(AnyTerm::$variant(_) => $variant::step_limit_lanes(values, rows, order, h, negligible),)* }
            }
            /// Its static band if it sticks at x' = 0 ([`Term::breakaway`]).
            pub fn breakaway(&self) -> Option<f64> {
                match self { $(AnyTerm::$variant(t) => t.breakaway(),)* }
            }
            /// Its dither [D, Ω_d], if it is one ([`Term::dither`]).
            pub fn dither(&self) -> Option<[f64; 2]> {
                match self { $(AnyTerm::$variant(t) => t.dither(),)* }
            }
            /// Its delay [K, τ_d], if it is a delayed feedback ([`Term::delay`]).
            pub fn delay(&self) -> Option<[f64; 2]> {
                match self { $(AnyTerm::$variant(t) => t.delay(),)* }
            }
            /// Its highest load frequency ([`Term::load_frequency`]).
            pub fn load_frequency(&self) -> f64 {
                match self { $(AnyTerm::$variant(t) => t.load_frequency(),)* }
            }
            /// x' at rest ([`Term::twist_rate_at_rest`]).
            pub fn twist_rate_at_rest(&self) -> f64 {
                match self { $(AnyTerm::$variant(t) => t.twist_rate_at_rest(),)* }
            }
            /// Its internal state at rest at twist x ([`Term::state_at_rest`]).
            pub fn state_at_rest(&self, x: f64) -> f64 {
                match self { $(AnyTerm::$variant(t) => t.state_at_rest(x),)* }
            }
            /// The term on one side of its switch ([`Term::directed`]).
            pub fn directed(self, side: Side) -> AnyTerm {
                match self { $(AnyTerm::$variant(t) => AnyTerm::$variant(t.directed(side)),)* }
            }
        }
    };
}

any_term!(
    Damping,
    Stiffness,
    Friction,
    Stribeck,
    Coulomb,
    LuGre,
    BoucWen,
    Dahl,
    VirtualStiffness,
    VirtualDamping,
    Washout,
    Dither,
    Delay,
    KinematicError,
    MeshLoss,
    Multisine,
    Piecewise,
    Scheduled,
    Spring,
    Drag,
);

impl AnyTerm {
    /// The elastic law this term is, if it is one (what a mesh loss scales).
    pub fn elastic(&self) -> Option<Elastic> {
        match self {
            AnyTerm::Stiffness(s) => Some(Elastic::Stiffness(*s)),
            AnyTerm::Piecewise(p) => Some(Elastic::Piecewise(*p)),
            _ => None,
        }
    }
}

/// Checks a term's values against its parameter list: each within the magnitude limit every
/// parameter has ([`crate::params::MAGNITUDE_LIMIT`]), then its own domain, then the rules
/// between them.
fn check_values(params: &[ParamInfo], relations: &[Relation], values: &[f64]) -> Result<()> {
    if params.len() != values.len() {
        return Err(Error::InvalidInput {
            what: "term values",
            text: format!("{values:?}"),
            reason: format!("{} values expected", params.len()),
        });
    }
    params.iter().zip(values).try_for_each(|(p, &v)| {
        crate::params::check_magnitude(p.name, v)?;
        p.domain.check(p.name, v)
    })?;
    relations
        .iter()
        .try_for_each(|r| r.check(|i| params[i].name, values))
}

fn unknown_kind(kind: &str) -> Error {
    let known: Vec<&str> = AnyTerm::KINDS.iter().map(|k| k.0).collect();
    Error::InvalidInput {
        what: "term kind",
        text: kind.to_string(),
        reason: format!("known: {}", known.join(", ")),
    }
}
