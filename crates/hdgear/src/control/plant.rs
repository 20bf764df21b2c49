//! The plant a law is added to ([`Plant`]): the study's set, with its closed forms, or any model
//! assembled from terms (friction, hysteresis, a card's curve), with the facts its equilibrium
//! curve gives. Every search of [`super`] is generic over it.

use crate::burst::BurstOptions;
use crate::error::{Error, Result};
use crate::model::Model;
use crate::model::schedule::Scheduled;
use crate::params::{Param, Params};
use serde::Serialize;

/// What the control searches read of the plant beyond its model.
pub trait Plant: Clone + Send + Sync + Serialize {
    /// The open loop as a model: the law's term is added to it.
    fn open_loop(&self) -> Model;
    /// The x-extent X of the open loop's equilibrium curve over a ∈ [−1, 1] (the unit of the
    /// shifts a law causes).
    fn curve_extent(&self) -> Result<f64>;
    /// Whether the state must jump at the folds of the branch it settles on.
    fn must_jump(&self) -> Result<bool>;
    /// Whether `closed` (the open loop with a law) has the open loop's equilibrium curve.
    fn curve_unchanged_by(&self, closed: &Model) -> bool;
    /// The scheduled stiffness built for the plant with least slope `gmin` and ramp `ramp`.
    fn schedule(&self, gmin: f64, ramp: f64) -> Result<Scheduled>;
    /// The plant as a refusal names it.
    fn point(&self) -> String;
    /// The plant as a table's heading names it: its parameters.
    fn title(&self) -> String;
    /// The plant with parameter `q` scaled by `factor` (a model error), checked; a model
    /// without `q` (no study stiffness) is returned as it is.
    fn scaled(&self, q: Param, factor: f64) -> Result<Self>;
    /// The plant under the load δ/`s` (what feed-forward leaves of it).
    fn load_over(&self, s: f64) -> Result<Self>;
    /// Whether the open loop bursts.
    fn bursts(&self, opts: &BurstOptions) -> Result<bool>;
    /// The least and largest stiffness of the equilibrium the open loop's state follows
    /// ([`crate::fast::StaticCurve::stiffness_range`]).
    fn stiffness_range(&self) -> Result<(f64, f64)>;
}

impl Plant for Params {
    fn open_loop(&self) -> Model {
        Model::study(self)
    }
    fn curve_extent(&self) -> Result<f64> {
        Ok(crate::burst::curve_extent(self))
    }
    fn must_jump(&self) -> Result<bool> {
        Ok(crate::fast::settled_branch(self).must_jump)
    }
    fn curve_unchanged_by(&self, closed: &Model) -> bool {
        closed.equivalent_params() == Some(*self)
    }
    fn schedule(&self, gmin: f64, ramp: f64) -> Result<Scheduled> {
        Ok(Scheduled::for_plant(self, gmin, ramp))
    }
    fn point(&self) -> String {
        format!("γ = {}, δ = {}, ω = {}", self.gamma, self.delta, self.omega)
    }
    fn title(&self) -> String {
        format!(
            "α = {}, γ = {}, ε = {}, μ = {}, δ = {}, ω = {}",
            self.alpha, self.gamma, self.eps, self.mu, self.delta, self.omega
        )
    }
    fn scaled(&self, q: Param, factor: f64) -> Result<Params> {
        Ok(self.with(q, self.value(q) * factor))
    }
    fn load_over(&self, s: f64) -> Result<Params> {
        Ok(Params {
            delta: self.delta / s,
            ..*self
        })
    }
    fn bursts(&self, opts: &BurstOptions) -> Result<bool> {
        let r = crate::burst::response(self, opts)?;
        Ok(crate::burst::classify(self, &r).bursting)
    }
    fn stiffness_range(&self) -> Result<(f64, f64)> {
        Ok(crate::fast::StaticCurve::stiffness_range(self))
    }
}

/// Static torques are compared at these twists (the spread of [`Model::equivalent_params`]'s).
const SAMPLES: [f64; 6] = [-2.7, -0.61, 0.0, 0.37, 1.3, 3.1];

impl Plant for Model {
    fn open_loop(&self) -> Model {
        *self
    }
    fn curve_extent(&self) -> Result<f64> {
        Ok(crate::burst::model_curve_facts(self)?.0)
    }
    fn must_jump(&self) -> Result<bool> {
        Ok(crate::burst::model_curve_facts(self)?.1)
    }
    fn curve_unchanged_by(&self, closed: &Model) -> bool {
        !closed.is_scheduled()
            && SAMPLES
                .iter()
                .all(|&x| closed.static_torque(x) == self.static_torque(x))
    }
    /// Built on the study cubic the model's static torque equals
    /// ([`Model::equivalent_params`]); refused for any other.
    fn schedule(&self, gmin: f64, ramp: f64) -> Result<Scheduled> {
        match self.equivalent_params() {
            Some(p) => Ok(Scheduled::for_plant(&p, gmin, ramp)),
            None => Err(Error::InvalidInput {
                what: "control law",
                text: <Scheduled as crate::model::terms::Term>::KIND.to_string(),
                reason: format!(
                    "the scheduled stiffness is built on a study cubic, and the static torque \
                     of {} is none",
                    self.equation()
                ),
            }),
        }
    }
    fn point(&self) -> String {
        let [_, delta, omega] = self.forcing();
        format!("δ = {delta}, ω = {omega} (model {})", self.equation())
    }
    fn title(&self) -> String {
        let values: Vec<String> = self
            .param_values()
            .iter()
            .map(|q| format!("{} = {}", q.info.symbol, q.value))
            .collect();
        format!("{}: {}", self.equation(), values.join(", "))
    }
    fn scaled(&self, q: Param, factor: f64) -> Result<Model> {
        match self.param(q.name()) {
            Ok(m) => self.with(m, self.get(m) * factor),
            Err(_) => Ok(*self),
        }
    }
    fn load_over(&self, s: f64) -> Result<Model> {
        let delta = self.param(Param::Delta.name())?;
        self.with(delta, self.get(delta) / s)
    }
    fn stiffness_range(&self) -> Result<(f64, f64)> {
        crate::burst::model_stiffness_range(self)
    }
    fn bursts(&self, opts: &BurstOptions) -> Result<bool> {
        let r = crate::burst::response_model(self, opts)?;
        Ok(crate::burst::classify_model(self, &r)?.bursting)
    }
}
