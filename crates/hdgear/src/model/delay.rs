//! Delayed feedback ũ = K·(x(τ − τ_d) − x(τ)): a delay-differential equation. Its term ([`Delay`])
//! carries the delayed twist x_d = x(τ − τ_d) as its state, which no equation of the state gives:
//! the run supplies it from its own history ([`Delayed`], the method of steps). Each step is at
//! most τ_d long, so every time a step's stages read, τ − τ_d, lies in steps already taken (or
//! before the run, where the drive rests at its start). The history is the steps' own dense
//! output, kept exactly over the last τ_d. The steps are DOP853's: a Taylor step would need the
//! history's Taylor coefficients at τ − τ_d, which a DOP853 or Taylor step's dense output of
//! another step does not carry.

use super::Model;
use super::terms::{Domain, ParamInfo, Scratch, StateInfo, Term};
use crate::error::{Error, Result};
use crate::integrate::{AnyDense, DenseOutput, Method, Options, System};
use serde::Serialize;
use std::cell::RefCell;
use std::collections::VecDeque;

/// Delayed feedback ũ = K·(x(τ − τ_d) − x(τ)) on the twist: the term K·(x − x_d), x_d the twist
/// τ_d ago. Zero on every equilibrium (x_d = x at rest), so the equilibrium curve is the open
/// loop's. Integrated only by the method of steps ([`Delayed`]): the state x_d has no rate of
/// its own ([`Term::rate`] is NaN, so a machine that integrated it without its history would
/// fail at once rather than run a wrong model).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Delay(pub [f64; 2]);

impl Term for Delay {
    const KIND: &'static str = "delay";
    const ABOUT: &'static str =
        "delayed feedback: ũ = K·(x(τ − τ_d) − x(τ)), by the method of steps (DOP853)";
    const STATE: Option<StateInfo> = Some(StateInfo {
        name: "xd",
        meaning: "the delayed twist x(τ − τ_d), read from the run's history",
    });
    const PARAMS: &'static [ParamInfo] = &[
        ParamInfo {
            name: "kdelay",
            symbol: "K",
            latex: "K",
            meaning: "gain of the delayed feedback",
            domain: Domain::NonNegative,
            default: 0.0,
            si: "K·J_eq²/(N²·J_i·C²) (K in N m/rad of twist)",
        },
        ParamInfo {
            name: "taud",
            symbol: "τ_d",
            latex: r"\tau_d",
            meaning: "delay of the feedback",
            domain: Domain::Positive,
            default: 1.0,
            si: "t_d·C/J_eq",
        },
    ];
    fn from_values(v: &[f64]) -> Self {
        Delay([v[0], v[1]])
    }
    fn values(&self) -> &[f64] {
        &self.0
    }
    fn torque(&self, x: f64, _v: f64, xd: f64) -> f64 {
        self.0[0] * (x - xd)
    }
    fn gradient(&self, _x: f64, _v: f64, _xd: f64) -> [f64; 3] {
        [self.0[0], 0.0, -self.0[0]]
    }
    /// ∂/∂K = x − x_d; ∂/∂τ_d is the history's K·x'(τ − τ_d), which the state does not hold:
    /// NaN.
    fn param_derivative(&self, i: usize, x: f64, _v: f64, xd: f64) -> f64 {
        if i == 0 { x - xd } else { f64::NAN }
    }
    #[inline(always)]
    fn taylor(&self, k: usize, x: &[f64], _v: &[f64], xd: &[f64], _rows: &mut Scratch) -> f64 {
        self.0[0] * (x[k] - xd[k])
    }
    /// x_d' = x'(τ − τ_d): the history's, not the state's (NaN here; [`Delayed`] supplies it).
    fn rate(&self, _x: f64, _v: f64, _xd: f64) -> f64 {
        f64::NAN
    }
    fn rate_taylor(&self, _k: usize, _x: &[f64], _v: &[f64], _z: &[f64], _r: &mut Scratch) -> f64 {
        f64::NAN
    }
    fn text(&self) -> String {
        " + K·(x − x_d)".into()
    }
    fn latex(&self) -> String {
        r" + K (x - x_d)".into()
    }
    fn rate_text(&self) -> Option<String> {
        Some("x_d(τ) = x(τ − τ_d)".into())
    }
    fn rate_latex(&self) -> Option<String> {
        Some(r"x_d(\tau) = x(\tau - \tau_d)".into())
    }
    fn state_at_rest(&self, x: f64) -> f64 {
        x
    }
    fn delay(&self) -> Option<[f64; 2]> {
        Some(self.0)
    }
}

/// A model with a delayed term as a [`System`] of the method of steps: its right-hand side with
/// x_d read from the run's history at τ − τ_d (and x_d' = x'(τ − τ_d), so the state's x_d
/// follows it). Before the run the drive rests at the start's twist. Push every accepted step
/// ([`Delayed::push`]) before the next is taken.
pub struct Delayed<'m, const N: usize> {
    model: &'m Model,
    /// The state index of x_d.
    slot: usize,
    tau: f64,
    /// The twist before the run.
    x0: f64,
    /// The steps ending within τ_d of the latest, in order.
    history: RefCell<VecDeque<AnyDense<N>>>,
}

impl<'m, const N: usize> Delayed<'m, N> {
    /// The method of steps for `model` started at `y0` (`None` without a delayed term).
    pub fn new(model: &'m Model, y0: &[f64; N]) -> Option<Delayed<'m, N>> {
        let [_, tau] = model.delay()?;
        let slot = model.delay_slot()?;
        Some(Delayed {
            model,
            slot,
            tau,
            x0: y0[0],
            history: RefCell::new(VecDeque::new()),
        })
    }

    /// The integration options for a run to `t_end` with tolerances `tol`: DOP853 with steps of
    /// at most τ_d. A delay as long as the run or longer is refused (the feedback would read
    /// nothing but the rest before it), and so are a delay so short that the run would need more
    /// steps than `tol.max_steps` and a model that also switches.
    pub fn options(&self, tol: Options, t_end: f64) -> Result<Options> {
        if self.model.switches() {
            return Err(Error::InvalidInput {
                what: "model",
                text: self.model.equation(),
                reason: "a delayed feedback with a term that switches (sticking friction) is not \
                         integrated: the method of steps here runs on one smooth piece"
                    .into(),
            });
        }
        if self.tau >= t_end {
            return Err(Error::InvalidParameter {
                name: "taud".into(),
                value: self.tau,
                reason: "must be shorter than the run (its feedback would read only the rest before it)",
            });
        }
        if t_end / self.tau > tol.max_steps as f64 {
            return Err(Error::InvalidParameter {
                name: "taud".into(),
                value: self.tau,
                reason: "is too short for the run: its steps are at most τ_d long, and the run would need more than the step budget",
            });
        }
        Ok(Options {
            method: Method::Dop853,
            h_max: Some(tol.h_max.map_or(self.tau, |h| h.min(self.tau))),
            ..tol
        })
    }

    /// Adds an accepted step to the history and forgets the steps no later time will read.
    pub fn push(&self, d: AnyDense<N>) {
        let mut h = self.history.borrow_mut();
        let horizon = d.t_end() - self.tau;
        h.push_back(d);
        while h.len() > 1 && h[1].t_start() <= horizon {
            h.pop_front();
        }
    }

    /// (x, x') at time s ≤ the latest step's end: the history's, or rest before the run.
    fn past(&self, s: f64) -> [f64; 2] {
        let h = self.history.borrow();
        if s <= 0.0 || h.is_empty() {
            return [self.x0, 0.0];
        }
        let i = h.partition_point(|d| d.t_end() < s).min(h.len() - 1);
        let y = h[i].eval(s);
        [y[0], y[1]]
    }
}

impl<const N: usize> System<N> for Delayed<'_, N> {
    fn rhs(&self, t: f64, y: &[f64; N]) -> [f64; N] {
        let [xd, vd] = self.past(t - self.tau);
        let mut z = *y;
        z[self.slot] = xd;
        let mut f = self.model.rhs(t, &z);
        f[self.slot] = vd;
        f
    }
}
