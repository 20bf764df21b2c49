//! The method of steps for a model with a delayed term ([`super::delay::Delay`]): a
//! delay-differential equation. Each step is at most τ_d long, so every time a step's stages
//! read, τ − τ_d, lies in steps already taken (or before the run, where the drive rests at its
//! start). The history is the steps' own dense output, kept exactly over the last τ_d. The steps
//! are DOP853's: a Taylor step would need the history's Taylor coefficients at τ − τ_d, which a
//! DOP853 or Taylor step's dense output of another step does not carry.

use super::Model;
use crate::error::{Error, Result};
use crate::integrate::{AnyDense, DenseOutput, Method, Options, System};
use std::cell::RefCell;
use std::collections::VecDeque;

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
