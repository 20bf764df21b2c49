//! A drive model assembled from terms ([`Model`]): x'' + Σ T_i(x, x') = μ + δ sin ωτ, unit
//! inertia. Its right-hand side, Jacobian, Taylor coefficients, parameter derivatives and the
//! facts of its fast subsystem are derived from the terms' own definitions
//! ([`super::terms::Term`]); nothing here restates a term.
//!
//! **Why one file.** These are the inherent methods of one type, `Model` (building, parameters,
//! evaluation, the derived facts); its system, lane and study parts already live in `assembled/`.

use super::terms::{AnyTerm, Damping, Domain, MeshLoss, ParamInfo, Side, Stiffness, Term};
use crate::error::{Error, Result};
use crate::params::{Param, Params};
use serde::Serialize;
use std::fmt;

/// The most terms one model holds: one set of a Taylor stepper's rows each
/// ([`crate::integrate::Workspace`]).
pub const MAX_TERMS: usize = crate::integrate::taylor::WORKSPACE_SETS;

/// The most internal states (of its terms) one model holds beside x and x': its state has at
/// most 2 + MAX_STATES components.
pub const MAX_STATES: usize = 2;

/// The forcing's parameters: μ, δ, ω of μ + δ sin ωτ.
pub const FORCING: [ParamInfo; 3] = [
    ParamInfo {
        name: Param::Mu.name(),
        symbol: "μ",
        latex: r"\mu",
        meaning: "mean load",
        domain: Domain::Any,
        default: 0.07,
        si: "k2·φ·J_eq²·T_m/C⁴",
    },
    ParamInfo {
        name: Param::Delta.name(),
        symbol: "δ",
        latex: r"\delta",
        meaning: "amplitude of the slow disturbance",
        domain: Domain::NonNegative,
        default: 15.0,
        si: "k2·φ·J_eq³·T_am/(J_o·C⁴)",
    },
    ParamInfo {
        name: Param::Omega.name(),
        symbol: "ω",
        latex: r"\omega",
        meaning: "frequency of the slow disturbance",
        domain: Domain::Positive,
        default: 0.01,
        si: "Ω·J_eq/C",
    },
];

/// A drive model: unit inertia, a list of terms (torques on the left-hand side) and the forcing
/// μ + δ sin ωτ on the right. `Copy` and stack-only, like [`Params`].
///
/// ```
/// use hdgear::model::{Model, terms::AnyTerm};
/// use hdgear::Params;
/// let m = Model::study(&Params::default())
///     .with_term(AnyTerm::new("friction", &[0.05, 0.01]).unwrap())
///     .unwrap();
/// assert_eq!(m.equation(), "x'' + x' + αx³ − x² + γ(x − ε) + f_c·tanh(x'/v_s) = μ + δ sin ωτ");
/// // the friction's slope at rest adds to the unit damping: the focus/node threshold moves
/// let facts = m.facts();
/// assert!((facts.damping_at_rest - 6.0).abs() < 1e-12);
/// assert!((facts.focus_node_threshold - 9.0).abs() < 1e-12);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Model {
    /// μ, δ, ω.
    forcing: [f64; 3],
    terms: [Option<AnyTerm>; MAX_TERMS],
    /// The motion held at rest (x' = x'' = 0), only the internal states moving
    /// ([`Model::held`]).
    held: bool,
}

/// One parameter of a [`Model`]: the forcing's (`term` = None) or term `term`'s `index`-th.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ModelParam {
    term: Option<u8>,
    index: u8,
    name: &'static str,
}

impl ModelParam {
    /// The name users write.
    pub fn name(self) -> &'static str {
        self.name
    }

    /// Whether it is the forcing frequency ω (which enters only through the phase ωτ).
    pub fn is_frequency(self) -> bool {
        self.term.is_none() && self.index == 2
    }
}

impl fmt::Display for ModelParam {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(self.name)
    }
}

/// A parameter of a model with its value, as `hdgear model` lists it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ParamValue {
    /// The term it belongs to (`forcing` for μ, δ, ω).
    pub term: &'static str,
    /// Its definition.
    #[serde(flatten)]
    pub info: ParamInfo,
    /// Its value in this model.
    pub value: f64,
}

/// What follows from a model's terms for its fast subsystem x'' + Σ T(x, x') = a (the forcing
/// frozen at a): its equilibria have x' = 0 and Jacobian [[0, 1], [−g'(x), −c(x)]] with
/// g'(x) = Σ ∂T/∂x and c(x) = Σ ∂T/∂x' at x' = 0.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Facts {
    /// c, the damping at rest (−trace of the fast Jacobian at an equilibrium); the smallest over
    /// the sampled x where it varies.
    pub damping_at_rest: f64,
    /// Whether c is the same at every sampled x (to 1e-12 relative): then the values below hold
    /// at every equilibrium.
    pub damping_uniform: bool,
    /// Whether a Hopf bifurcation of the fast subsystem is possible: where c ≤ 0 the trace of
    /// its Jacobian can cross zero; with a delayed feedback its characteristic equation
    /// λ² + cλ + g' + K(1 − e^{−λτ_d}) = 0 has roots that cross the imaginary axis as τ_d or K
    /// grows, whatever c.
    pub hopf_possible: bool,
    /// The slope g' above which an equilibrium is a focus (complex eigenvalues): c²/4.
    pub focus_node_threshold: f64,
    /// 2/c: the e-folding time of an oscillation about a focus (its amplitude decays as
    /// e^{−cτ/2}).
    pub decay_time: f64,
    /// ω times the decay time: how far the forcing's phase moves while a focus's ringing decays
    /// (the fast-slow picture needs it small).
    pub omega_decay: f64,
}

/// A model described for people and programs: what `hdgear model` prints.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Description {
    /// The equation as text.
    pub equation: String,
    /// The equation in LaTeX.
    pub latex: String,
    /// The states, in the order the integrators hold them: x, x', then the terms' own.
    pub states: Vec<&'static str>,
    /// The terms, in order, each with its kind and parameter values.
    pub terms: Vec<AnyTerm>,
    /// Every parameter with its definition and value.
    pub parameters: Vec<ParamValue>,
    /// The facts of the fast subsystem derived from the terms.
    pub facts: Facts,
}

/// The definition of one of the study's six parameters (name, symbol, meaning, domain,
/// default), read from the term or forcing that owns it: what flags, sliders and tables show.
///
/// ```
/// use hdgear::model::study_param;
/// use hdgear::params::Param;
/// assert_eq!(study_param(Param::Delta).symbol, "δ");
/// assert_eq!(study_param(Param::Alpha).default, 16.0);
/// ```
pub fn study_param(q: crate::params::Param) -> ParamInfo {
    *FORCING
        .iter()
        .chain(Stiffness::PARAMS)
        .find(|i| i.name == q.name())
        .expect("the study's stiffness and forcing define every parameter of Param")
}

impl Model {
    /// The model's [`Description`].
    pub fn describe(&self) -> Description {
        Description {
            equation: self.equation(),
            latex: self.latex(),
            states: self.states(),
            terms: self.terms().copied().collect(),
            parameters: self.param_values(),
            facts: self.facts(),
        }
    }

    /// The study's model x'' + x' + αx³ − x² + γ(x − ε) = μ + δ sin ωτ with `p`'s values.
    pub fn study(p: &Params) -> Model {
        let mut m = Model::damped(p.mu, p.delta, p.omega);
        m.terms[1] = Some(AnyTerm::Stiffness(Stiffness::from_values(&[
            p.alpha, p.gamma, p.eps,
        ])));
        m
    }

    /// A unit inertia and damping under the load μ + δ sin ωτ, with no stiffness of its own: the
    /// terms added give it all ([`Model::with_term`]). For drives whose stiffness is not the
    /// study's cubic (a catalogue's piecewise-linear curve) and for systems that are not a drive,
    /// such as an identification benchmark; [`Model::equivalent_params`] is `None`, and the burst
    /// verdict measures against the model's own equilibrium curve ([`super::ModelCurve`]).
    pub fn damped(mu: f64, delta: f64, omega: f64) -> Model {
        let mut terms = [None; MAX_TERMS];
        terms[0] = Some(AnyTerm::Damping(Damping::default()));
        Model {
            forcing: [mu, delta, omega],
            terms,
            held: false,
        }
    }

    /// The model with one more term; refused when a term of its kind is already there, when a
    /// parameter name would be taken twice, or when the model is full ([`MAX_TERMS`]).
    pub fn with_term(mut self, term: AnyTerm) -> Result<Model> {
        let refuse = |reason: String| Error::InvalidInput {
            what: "model term",
            text: term.kind().to_string(),
            reason,
        };
        for p in term.params() {
            if let Ok(q) = self.param(p.name) {
                return Err(refuse(format!(
                    "its parameter {} is taken by the model's {}",
                    p.name,
                    self.owner(q)
                )));
            }
        }
        if self.terms().any(|t| t.kind() == term.kind()) {
            return Err(refuse("the model has one already".into()));
        }
        if let (Some(_), Some(other)) = (term.dither(), self.terms().find(|t| t.dither().is_some()))
        {
            // the verdict averages the motion over one fast period; two need two time scales
            return Err(refuse(format!(
                "the model's {} is a fast periodic torque already (one is averaged, not two)",
                other.kind()
            )));
        }
        if term.state().is_some() && self.dim() - 2 == MAX_STATES {
            return Err(refuse(format!(
                "a model holds at most {MAX_STATES} terms with a state of their own"
            )));
        }
        let slot = self.terms.iter_mut().find(|t| t.is_none());
        *slot.ok_or_else(|| refuse(format!("a model holds at most {MAX_TERMS} terms")))? =
            Some(term);
        self.linked()
    }

    /// The model with each term that reads the elastic law (a mesh loss,
    /// [`crate::model::mesh_loss::MeshLoss`]) given the model's: refused when there is none to
    /// read, or two (the study's stiffness and a piecewise curve).
    fn linked(mut self) -> Result<Model> {
        let (law, second) = {
            let mut laws = self.terms().filter_map(AnyTerm::elastic);
            (laws.next(), laws.next())
        };
        for term in self.terms.iter_mut().flatten() {
            if let AnyTerm::MeshLoss(loss) = term {
                if law.is_none() || second.is_some() {
                    return Err(Error::InvalidInput {
                        what: "model term",
                        text: MeshLoss::KIND.to_string(),
                        reason: format!(
                            "it reads the transmitted torque of one elastic law (stiffness or \
                             piecewise), and the model has {}",
                            if law.is_none() { "none" } else { "two" }
                        ),
                    });
                }
                *loss = loss.reading(law);
            }
        }
        Ok(self)
    }

    /// The model's terms, in order.
    pub fn terms(&self) -> impl Iterator<Item = &AnyTerm> {
        self.terms.iter().flatten()
    }

    /// For each term slot, the index of its internal state in the model's state (2, 3, …) if
    /// it has one: the one place the states are laid out.
    fn state_slots(&self) -> [Option<usize>; MAX_TERMS] {
        let mut at = [None; MAX_TERMS];
        let mut next = 2;
        for (a, term) in at.iter_mut().zip(&self.terms) {
            if term.is_some_and(|t| t.state().is_some()) {
                *a = Some(next);
                next += 1;
            }
        }
        at
    }

    /// The terms, each with the index of its internal state ([`Model::state_slots`]).
    pub(super) fn slots(&self) -> impl Iterator<Item = (&AnyTerm, Option<usize>)> {
        self.terms
            .iter()
            .zip(self.state_slots())
            .filter_map(|(t, at)| t.as_ref().map(|t| (t, at)))
    }

    /// The dimension of the model's state: x, x' and one per term with a state of its own.
    pub fn dim(&self) -> usize {
        2 + self.terms().filter(|t| t.state().is_some()).count()
    }

    /// The names of the state's components, in order.
    pub fn states(&self) -> Vec<&'static str> {
        let own = self.terms().filter_map(|t| t.state().map(|s| s.name));
        ["x", "x'"].into_iter().chain(own).collect()
    }

    /// μ, δ, ω.
    pub fn forcing(&self) -> [f64; 3] {
        self.forcing
    }

    /// The parameter called `name`: `NAME` or `TERM.NAME` (`fc` or `friction.fc`, `delta` or
    /// `forcing.delta`; a model's names are unique, [`Model::with_term`]). An error names the
    /// text and lists the model's.
    ///
    /// ```
    /// use hdgear::model::{Model, terms::AnyTerm};
    /// let m = Model::study(&hdgear::Params::default())
    ///     .with_term(AnyTerm::new("friction", &[0.1, 0.05]).unwrap())
    ///     .unwrap();
    /// assert_eq!(m.param("friction.fc").unwrap(), m.param("fc").unwrap());
    /// assert_eq!(m.get(m.param("forcing.delta").unwrap()), 15.0);
    /// assert!(m.param("friction.alpha").is_err());
    /// ```
    pub fn param(&self, name: &str) -> Result<ModelParam> {
        let name = name.trim();
        let qualified = |q: &ModelParam| format!("{}.{}", self.owner(*q), q.name);
        let found: Vec<ModelParam> = match name.split_once('.') {
            Some(_) => self.params().filter(|q| qualified(q) == name).collect(),
            None => self.params().filter(|q| q.name == name).collect(),
        };
        match found[..] {
            [q] => Ok(q),
            _ => Err(Error::InvalidInput {
                what: "parameter name",
                text: name.to_string(),
                reason: format!(
                    "no such parameter; this model's are {} (each also as TERM.NAME)",
                    self.params().map(|q| q.name).collect::<Vec<_>>().join(", ")
                ),
            }),
        }
    }

    /// Every parameter, the forcing's first.
    pub fn params(&self) -> impl Iterator<Item = ModelParam> + '_ {
        let forcing = FORCING.iter().enumerate().map(|(i, p)| ModelParam {
            term: None,
            index: i as u8,
            name: p.name,
        });
        let terms = self.terms.iter().enumerate().flat_map(|(t, term)| {
            term.iter().flat_map(move |term| {
                term.params()
                    .iter()
                    .enumerate()
                    .map(move |(i, p)| ModelParam {
                        term: Some(t as u8),
                        index: i as u8,
                        name: p.name,
                    })
            })
        });
        forcing.chain(terms)
    }

    /// Every parameter with its definition and value.
    pub fn param_values(&self) -> Vec<ParamValue> {
        self.params()
            .map(|q| ParamValue {
                term: self.owner(q),
                info: self.info(q),
                value: self.get(q),
            })
            .collect()
    }

    fn owner(&self, q: ModelParam) -> &'static str {
        q.term.map_or("forcing", |t| self.term(t).kind())
    }

    fn term(&self, t: u8) -> &AnyTerm {
        self.terms[t as usize]
            .as_ref()
            .expect("a ModelParam names a present term")
    }

    fn info(&self, q: ModelParam) -> ParamInfo {
        match q.term {
            None => FORCING[q.index as usize],
            Some(t) => self.term(t).params()[q.index as usize],
        }
    }

    /// A parameter's value.
    pub fn get(&self, q: ModelParam) -> f64 {
        match q.term {
            None => self.forcing[q.index as usize],
            Some(t) => self.term(t).values()[q.index as usize],
        }
    }

    /// The model with one parameter changed, checked against its domain.
    pub fn with(&self, q: ModelParam, value: f64) -> Result<Model> {
        self.with_all(&[(q, value)])
    }

    /// The model with several parameters changed at once, each checked against its domain and
    /// each changed term's rules judged on its new values together: f_s ≥ f_c holds or fails for
    /// the pair a user asks for, never for a half-changed model between them.
    ///
    /// ```
    /// use hdgear::model::{Model, terms::AnyTerm};
    /// let coulomb = AnyTerm::new("coulomb", &[0.05, 0.1, 0.1, 0.0]).unwrap(); // fc, fs, …
    /// let m = Model::damped(0.0, 0.5, 1.0).with_term(coulomb).unwrap();
    /// let (fc, fs) = (m.param("fc").unwrap(), m.param("fs").unwrap());
    /// // one at a time, raising f_c first breaks f_s ≥ f_c on the way
    /// assert!(m.with(fc, 0.2).is_err());
    /// let both = m.with_all(&[(fc, 0.2), (fs, 0.3)]).unwrap();
    /// assert_eq!((both.get(fc), both.get(fs)), (0.2, 0.3));
    /// ```
    pub fn with_all(&self, changes: &[(ModelParam, f64)]) -> Result<Model> {
        let mut m = *self;
        let mut changed: [Option<Vec<f64>>; MAX_TERMS] = std::array::from_fn(|_| None);
        for &(q, value) in changes {
            self.info(q).domain.check(q.name, value)?;
            match q.term {
                None => m.forcing[q.index as usize] = value,
                Some(t) => {
                    changed[t as usize].get_or_insert_with(|| self.term(t).values().to_vec())
                        [q.index as usize] = value;
                }
            }
        }
        for (t, values) in changed.iter().enumerate() {
            if let Some(values) = values {
                m.terms[t] = Some(AnyTerm::new(self.term(t as u8).kind(), values)?);
            }
        }
        m.linked()
    }

    /// Checks every parameter against its domain.
    pub fn check(&self) -> Result<()> {
        self.params()
            .try_for_each(|q| self.info(q).domain.check(q.name, self.get(q)))?;
        self.terms().try_for_each(|t| {
            t.relations()
                .iter()
                .try_for_each(|r| r.check(|i| t.params()[i].name, t.values()))
        })
    }

    /// x'' = μ + δ sin(phase) − Σ T(x, v) with the terms' internal states at 0 (the model's
    /// own for a model without them).
    #[inline]
    pub fn accel(&self, phase: f64, x: f64, v: f64) -> f64 {
        self.accel_at(phase, &[x, v])
    }

    /// x'' = μ + δ sin(phase) − Σ T(x, v, z) at the state `y` = [x, v, z…] (a state `y` does not
    /// hold is 0).
    #[inline]
    pub fn accel_at(&self, phase: f64, y: &[f64]) -> f64 {
        let [mu, delta, _] = self.forcing;
        mu + delta * libm::sin(phase) - self.torque_at(y)
    }

    /// Σ T(x, v, z), the terms' torque at the state `y` = [x, v, z…] (a state `y` does not hold
    /// is 0).
    #[inline]
    pub fn torque_at(&self, y: &[f64]) -> f64 {
        self.slots()
            .map(|(t, at)| t.torque(y[0], y[1], state(y, at)))
            .sum()
    }

    /// (∂x''/∂x, ∂x''/∂v) = −Σ ∇T, the internal states at 0.
    #[inline]
    pub fn accel_gradient(&self, x: f64, v: f64) -> [f64; 2] {
        self.terms().fold([0.0, 0.0], |[a, b], t| {
            let [gx, gv, _] = t.gradient(x, v, 0.0);
            [a - gx, b - gv]
        })
    }

    /// ∂x''/∂λ at fixed phase, x, v, the internal states at 0 (0 for ω, which enters only
    /// through the phase).
    pub fn accel_derivative(&self, q: ModelParam, phase: f64, x: f64, v: f64) -> f64 {
        match (q.term, q.index) {
            (None, 0) => 1.0,
            (None, 1) => libm::sin(phase),
            (None, _) => 0.0,
            (Some(t), i) => -self.term(t).param_derivative(i as usize, x, v, 0.0),
        }
    }

    /// Whether a term's torque at rest depends on the load's phase ([`AnyTerm::is_scheduled`]): the
    /// equilibria move with a ([`Model::static_torque`] is at a = 0; no equivalent study set).
    pub fn is_scheduled(&self) -> bool {
        self.terms().any(|t| t.is_scheduled())
    }

    /// The static torque g(x) = Σ T(x, 0, z_rest(x)): the fast subsystem's equilibria solve
    /// g(x) = a, each internal state at rest ([`AnyTerm::state_at_rest`]: 0, the virgin state, for
    /// a model with memory; x for a washout filter). A load whatever the motion
    /// ([`AnyTerm::is_load`]: a dither, a kinematic error, a multisine) has no static part (its
    /// mean is 0) and is left out.
    pub fn static_torque(&self, x: f64) -> f64 {
        self.terms()
            .filter(|t| !t.is_load())
            .map(|t| t.torque(x, 0.0, t.state_at_rest(x)))
            .sum()
    }

    /// The study's parameter set whose stiffness g(x) = αx³ − x² + γ(x − ε) is this model's
    /// static torque ([`Model::static_torque`]) and whose forcing is the model's: what the fast
    /// subsystem's analysis of this model's equilibria is. The study's stiffness term gives α, γ
    /// and ε; the other terms' static torque must be affine in x, a₁x + a₀ (to 1e-12 of its size
    /// at six points, and at 33 across the x-range of the set's equilibria over a ∈ [−1, 1], ends
    /// included), and folds in: γ' = γ + a₁, ε' = (γε − a₀)/γ'. With no static torque of
    /// their own (friction, damping, a washout) the set is the stiffness term's exactly; with
    /// virtual stiffness k_p it is γ + k_p, γε/(γ + k_p). `None` otherwise (a static torque not
    /// affine in x, γ' = 0 with a₀ ≠ γε, or a scheduled stiffness).
    ///
    /// With a dither ([`Model::dither`]) it is the averaged model's: the ripple A it leaves
    /// ([`super::control::dither_ripple`], at the model's damping at rest) adds 1.5αA² to a₁ and
    /// −A²/2 to a₀.
    pub fn equivalent_params(&self) -> Option<Params> {
        let [alpha, gamma, eps] = self.terms().find_map(|t| match t {
            AnyTerm::Stiffness(s) if !self.is_scheduled() => Some(s.array()),
            _ => None,
        })?;
        let study = Stiffness::from_values(&[alpha, gamma, eps]);
        let rest = |x: f64| self.static_torque(x) - study.torque(x, 0.0, 0.0);
        let (a0, a1) = (rest(0.0), rest(1.0) - rest(0.0));
        let affine_at = |x: f64| {
            let size = a1.abs() * x.abs() + a0.abs() + study.torque(x, 0.0, 0.0).abs();
            (rest(x) - (a1 * x + a0)).abs() <= 1e-12 * size.max(1.0)
        };
        if ![-2.7, -0.61, 0.37, 1.3, 3.1, 0.0_f64]
            .into_iter()
            .all(affine_at)
        {
            return None;
        }
        let (a0, a1) = match self.dither() {
            Some([d, wd]) => {
                let gprime_min = gamma + a1 - 1.0 / (3.0 * alpha);
                let c = self.facts().damping_at_rest;
                let r = super::control::dither_ripple(alpha, gprime_min, d, wd, c);
                (a0 - 0.5 * r * r, a1 + 1.5 * alpha * r * r)
            }
            None => (a0, a1),
        };
        let (gamma, eps) = if a0 == 0.0 && a1 == 0.0 {
            (gamma, eps)
        } else if gamma + a1 != 0.0 {
            (gamma + a1, (gamma * eps - a0) / (gamma + a1))
        } else if gamma * eps == a0 {
            (0.0, 0.0)
        } else {
            return None;
        };
        let p = self.set_with([alpha, gamma, eps]);
        // the set's equilibria are the model's only if the rest is affine wherever they lie too:
        // from the lowest at a = −1 to the highest at a = 1, which a kink beyond the six points
        // above (a piecewise stiffness's) would otherwise change unseen
        let end = |a: f64, last: bool| {
            let r = crate::fast::equilibria(&p, a).roots;
            if last { r.last() } else { r.first() }.map(|e| e.x)
        };
        if let (Some(lo), Some(hi)) = (end(-1.0, false), end(1.0, true)) {
            const SAMPLES: usize = 32;
            let x = |i: usize| lo + (hi - lo) * i as f64 / SAMPLES as f64;
            if !(0..=SAMPLES).map(x).all(affine_at) {
                return None;
            }
        }
        Some(p)
    }

    /// x' of the drive at rest: the sum of the terms' [`AnyTerm::twist_rate_at_rest`] (0 but for
    /// a kinematic error, which moves the elastic twist against itself).
    pub fn rest_rate(&self) -> f64 {
        self.terms().map(|t| t.twist_rate_at_rest()).sum()
    }

    /// The fastest rate of the model at rest (x = 0, x' = 0, each state at rest) and the kind of
    /// the term it comes from: over every term, the largest of its damping |∂T/∂x'|, the rate
    /// √|∂T/∂x| of its stiffness, its state's own rate |∂r/∂z| and coupling √|∂T/∂z·∂r/∂x'|,
    /// and a load's angular frequency; and the forcing's ω. Each is a rate the motion or a load
    /// moves at, so a step of any method spans a few radians of it at the most
    /// ([`crate::integrate::check_rate_budget`]). It leaves out what the motion meets away from
    /// rest (a hardening stiffness), so it errs low: a refusal by it is certain.
    ///
    /// ```
    /// use hdgear::model::{Model, terms::AnyTerm};
    /// let m = Model::study(&hdgear::Params::default());
    /// let (rate, _) = m.fastest_rate();
    /// assert!((rate - 1.0).abs() < 1e-12); // the unit damping (√γ = 0.32 at γ = 0.1)
    /// let fast = m.with_term(AnyTerm::new("vdamping", &[1e6]).unwrap()).unwrap();
    /// assert_eq!(fast.fastest_rate(), (1e6, "vdamping"));
    /// ```
    pub fn fastest_rate(&self) -> (f64, &'static str) {
        let z = self.rest_states(0.0);
        let mut best = (self.forcing[2], "forcing");
        for (t, at) in self.slots() {
            let zi = at.map_or(0.0, |i| z[i - 2]);
            let [tx, tv, tz] = t.gradient(0.0, 0.0, zi);
            let [_, rv, rz] = t.rate_gradient(0.0, 0.0, zi);
            let rate = [
                tv.abs(),
                tx.abs().sqrt(),
                rz.abs(),
                (tz * rv).abs().sqrt(),
                t.load_frequency(),
            ]
            .into_iter()
            .fold(0.0, f64::max);
            if rate > best.0 {
                best = (rate, t.kind());
            }
        }
        best
    }

    /// The internal states at rest at twist x, in state order ([`AnyTerm::state_at_rest`]).
    pub fn rest_states(&self, x: f64) -> [f64; MAX_STATES] {
        let mut z = [0.0; MAX_STATES];
        for (t, at) in self.slots() {
            if let Some(i) = at {
                z[i - 2] = t.state_at_rest(x);
            }
        }
        z
    }

    /// The static band of the model's sticking terms (the sum of their [`AnyTerm::breakaway`]):
    /// x' stays 0 while |x''| at x' = 0 without them is within it. `None` when no term sticks.
    pub fn breakaway(&self) -> Option<f64> {
        self.terms()
            .filter_map(|t| t.breakaway())
            .reduce(|a, b| a + b)
    }

    /// Whether a term's law is not analytic across x' = 0 or across its state's 0: then the
    /// model is integrated piece by piece ([`super::switching`]).
    pub fn switches(&self) -> bool {
        self.terms()
            .any(|t| t.switches_at_rest() || t.switches_at_zero_state())
    }

    /// The state indices (2, 3, …) of the internal states whose law is not analytic across 0.
    pub fn switching_states(&self) -> impl Iterator<Item = usize> + '_ {
        self.slots()
            .filter(|(t, _)| t.switches_at_zero_state())
            .filter_map(|(_, at)| at)
    }

    /// The model on one piece of its switches: `v` = +1 or −1 fixes sgn x' in every switching
    /// term, `z[j]` sgn of internal state j (0: read from the state), which makes it analytic on
    /// the piece.
    pub fn directed(&self, v: f64, z: [f64; MAX_STATES]) -> Model {
        let mut m = *self;
        for (t, at) in m.terms.iter_mut().zip(self.state_slots()) {
            if let Some(t) = t {
                *t = t.directed(Side {
                    v,
                    z: at.map_or(0.0, |i| z[i - 2]),
                });
            }
        }
        m
    }

    /// The model's fast periodic torque [D, Ω_d] (a dither, a kinematic error: [`AnyTerm::dither`];
    /// a model holds one), if its amplitude D > 0: at amplitude 0 the model is the one without it.
    pub fn dither(&self) -> Option<[f64; 2]> {
        self.terms()
            .find_map(|t| t.dither())
            .filter(|[d, _]| *d > 0.0)
    }

    /// The highest angular frequency of the model's loads that act whatever the motion
    /// ([`AnyTerm::load_frequency`]), 0 without one.
    pub fn load_frequency(&self) -> f64 {
        self.terms().map(|t| t.load_frequency()).fold(0.0, f64::max)
    }

    /// The model with the motion held at rest: x' = x'' = 0, and each internal state moving by
    /// its own equation z' = r(x, 0, z) at the held x. What a sticking term's static band holds
    /// ([`super::switching`]): a memory term's state rests with the motion (its rate vanishes at
    /// x' = 0), but a wave generator keeps turning and a washout's filter keeps relaxing.
    pub fn held(&self) -> Model {
        Model {
            held: true,
            ..*self
        }
    }

    /// Whether an internal state moves while the motion is held at the state `y` (x' taken as
    /// 0): a rate r(x, 0, z) ≠ 0. The rates do not depend on time, so where none moves at the
    /// start of a rest, none moves during it.
    pub fn moves_at_rest(&self, y: &[f64]) -> bool {
        self.slots()
            .any(|(t, at)| at.is_some_and(|i| t.rate(y[0], 0.0, y[i]) != 0.0))
    }

    /// The model without its fast periodic torque ([`Model::dither`]): what that torque's
    /// averaging is measured against.
    pub fn without_fast_torque(&self) -> Model {
        self.without(|t| t.dither().is_some())
    }

    /// The model without its scheduled stiffness ([`Model::is_scheduled`]): the plant it
    /// controls.
    pub fn without_schedule(&self) -> Model {
        self.without(AnyTerm::is_scheduled)
    }

    /// The model without the terms `drop` picks.
    fn without(&self, drop: impl Fn(&AnyTerm) -> bool) -> Model {
        let mut m = *self;
        for slot in &mut m.terms {
            if slot.as_ref().is_some_and(&drop) {
                *slot = None;
            }
        }
        m
    }

    /// The model's delayed feedback [K, τ_d], if a term is one ([`AnyTerm::delay`]).
    pub fn delay(&self) -> Option<[f64; 2]> {
        self.terms().find_map(|t| t.delay())
    }

    /// The state index of the delayed twist, for a model with a delayed feedback.
    pub(crate) fn delay_slot(&self) -> Option<usize> {
        self.slots().find_map(|(t, at)| t.delay().and(at))
    }

    /// Whether the model has terms beyond the study's (damping and stiffness).
    pub fn has_extra_terms(&self) -> bool {
        self.terms().any(|t| Model::is_extra_kind(t.kind()))
    }

    /// Whether a term of `kind` is not one of the study's own (whose values come from
    /// [`Params`]): the kinds a scenario file gives a table of their own.
    pub fn is_extra_kind(kind: &str) -> bool {
        Model::study(&Params::default())
            .terms()
            .all(|t| t.kind() != kind)
    }

    /// The slope g'(x) of the static torque ([`Model::static_torque`]): each term's ∂T/∂x plus
    /// ∂T/∂z times the slope of its state at rest (0 for a memory term's virgin state, 1 for a
    /// washout's or a delay's, which rest at x: every term's rest state is affine in x).
    pub fn static_stiffness(&self, x: f64) -> f64 {
        self.terms()
            .filter(|t| !t.is_load())
            .map(|t| {
                let z = t.state_at_rest(x);
                let [gx, _, gz] = t.gradient(x, 0.0, z);
                let dz = t.state_at_rest(1.0) - t.state_at_rest(0.0);
                if dz == 0.0 { gx } else { gx + gz * dz }
            })
            .sum()
    }

    /// Every root of g(x) = `level` (g = [`Model::static_torque`]), increasing: the fast
    /// subsystem's equilibria at that torque. Found without the cubic's closed forms, so for any
    /// terms: the range [−R, R] doubled until g brackets the level there (the confining stiffness
    /// makes it), 4096 samples across it, each sign change refined by Brent's method to the
    /// resolution of f64 (two roots closer than a sample apart are not told apart).
    pub fn equilibria_at(&self, level: f64) -> Result<Vec<f64>> {
        let f = |x: f64| self.static_torque(x) - level;
        let mut r = 1.0_f64;
        while !(f(-r) < 0.0 && f(r) > 0.0) {
            r *= 2.0;
            if r > 1e150 {
                return Err(Error::InvalidInput {
                    what: "model",
                    text: self.equation(),
                    reason: format!(
                        "its static torque does not confine x: no equilibrium at the torque {level}"
                    ),
                });
            }
        }
        const SAMPLES: usize = 4096;
        let x = |i: usize| -r + 2.0 * r * i as f64 / SAMPLES as f64;
        let mut lo = (x(0), f(x(0)));
        let mut roots = Vec::new();
        for i in 1..=SAMPLES {
            let hi = (x(i), f(x(i)));
            if lo.1 == 0.0 {
                roots.push(lo.0);
            } else if lo.1 * hi.1 < 0.0 {
                let tol = 4.0 * f64::EPSILON * lo.0.abs().max(hi.0.abs());
                roots.push(crate::roots::brent(f, lo.0, lo.1, hi.0, hi.1, tol));
            }
            lo = hi;
        }
        Ok(roots)
    }

    /// The lowest stable equilibrium of the fast subsystem at slow variable a: the lowest root of
    /// g(x) = μ + δa ([`Model::equilibria_at`]) with g'(x) > 0 and damping c(x) > 0.
    pub fn stable_equilibrium(&self, a: f64) -> Result<f64> {
        let [mu, delta, _] = self.forcing;
        let roots = self.equilibria_at(mu + delta * a)?;
        let stable = |x: f64| {
            let [ax, av] = self.accel_gradient(x, 0.0);
            -ax > 0.0 && -av > 0.0
        };
        Ok(roots
            .iter()
            .copied()
            .find(|&x| stable(x))
            .or(roots.first().copied())
            .expect("g − level changes sign on [−R, R]"))
    }

    /// The fast subsystem's facts ([`Facts`]), from the terms' gradients at rest.
    pub fn facts(&self) -> Facts {
        // c(x) over x ∈ [−10, 10] (every equilibrium of the study's sets lies in |x| < 2; a term
        // whose damping at rest varies with x shows it here)
        let cs: Vec<f64> = (0..=40)
            .map(|i| -self.accel_gradient(-10.0 + 0.5 * i as f64, 0.0)[1])
            .collect();
        let (lo, hi) = cs
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &c| {
                (l.min(c), h.max(c))
            });
        let c = lo;
        let decay_time = 2.0 / c;
        Facts {
            damping_at_rest: c,
            damping_uniform: hi - lo <= 1e-12 * hi.abs().max(1.0),
            hopf_possible: c <= 0.0 || self.delay().is_some_and(|[k, _]| k > 0.0),
            focus_node_threshold: c * c / 4.0,
            decay_time,
            omega_decay: self.forcing[2] * decay_time,
        }
    }

    /// The equation as text: x'' + terms = μ + δ sin ωτ, then each internal state's equation.
    pub fn equation(&self) -> String {
        let lhs: String = self.terms().map(|t| t.text()).collect();
        let rates: String = self
            .terms()
            .filter_map(|t| t.rate_text())
            .map(|r| format!("; {r}"))
            .collect();
        format!("x''{lhs} = μ + δ sin ωτ{rates}")
    }

    /// The equation in LaTeX, then each internal state's equation.
    pub fn latex(&self) -> String {
        let lhs: String = self.terms().map(|t| t.latex()).collect();
        let rates: String = self
            .terms()
            .filter_map(|t| t.rate_latex())
            .map(|r| format!(", \\quad {r}"))
            .collect();
        format!(r"\ddot x{lhs} = \mu + \delta \sin \omega\tau{rates}")
    }
}

mod lanes;
mod study;
mod switching_lanes;
mod system;
pub use lanes::{integrate_models, on_vector_lanes};
pub use study::Subject;
pub use switching_lanes::integrate_switching_models;
use system::state;
