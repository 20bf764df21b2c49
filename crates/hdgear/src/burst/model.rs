//! The burst verdict on a model assembled from terms ([`Model`]): the same scan and
//! classification as the study's model, of a model whose equilibria are a study parameter set's
//! ([`Model::equivalent_params`]): its further terms (friction, control laws) act on the motion
//! and enter x'' as an extra torque, measured against that set's equilibrium curve.

use super::scan::{History, ScanStep};
use super::{BurstOptions, Plan, Response};
use crate::error::{Error, Result};
use crate::integrate::{AnyDense, DenseOutput, Stepper, stepper};
use crate::model::{MAX_STATES, Model};

/// A step of the model's N-component dense output read as x, x' and the torque of its terms
/// beyond the equivalent parameter set's cubic and unit damping.
#[derive(Clone, Copy, Debug)]
struct Projected<'m, const N: usize> {
    inner: AnyDense<N>,
    model: &'m Model,
    params: &'m crate::Params,
}

impl<const N: usize> Projected<'_, N> {
    fn extra_at(&self, y: &[f64; N]) -> f64 {
        // the model's torque less the study's x' + g(x)
        self.model.torque_at(y) - y[1] - self.params.g(y[0])
    }
}

impl<const N: usize> DenseOutput<2> for Projected<'_, N> {
    fn t_start(&self) -> f64 {
        self.inner.t_start()
    }
    fn t_end(&self) -> f64 {
        self.inner.t_end()
    }
    fn eval(&self, t: f64) -> [f64; 2] {
        let y = self.inner.eval(t);
        [y[0], y[1]]
    }
    fn end_state(&self) -> [f64; 2] {
        let y = self.inner.end_state();
        [y[0], y[1]]
    }
    fn abs_bound(&self, i: usize) -> Option<f64> {
        self.inner.abs_bound(i)
    }
    fn abs_floor(&self, i: usize) -> Option<f64> {
        self.inner.abs_floor(i)
    }
}

impl<const N: usize> ScanStep for Projected<'_, N> {
    fn state_at(&self, t: f64) -> ([f64; 2], f64) {
        let y = self.inner.eval(t);
        ([y[0], y[1]], self.extra_at(&y))
    }
    fn end(&self) -> ([f64; 2], f64) {
        let y = self.inner.end_state();
        ([y[0], y[1]], self.extra_at(&y))
    }
}

/// Simulates the model from its lowest stable equilibrium at a = 0 (at rest, its internal
/// states at rest there: [`Model::rest_states`]) and measures the response as [`super::response`]
/// does the study's: the signatures against the equilibrium curve of
/// [`Model::equivalent_params`], x'' the model's own.
///
/// Refused for a model whose static torque is not a study cubic (its equilibria are not a
/// parameter set's) and for one integrated piece by piece (sticking friction): its verdict would
/// need the scan to follow the pieces.
///
/// ```
/// use hdgear::{Params, burst::{BurstOptions, Verdict, classify, response_model}};
/// use hdgear::{control::law_term, model::Model};
/// let p = Params::default(); // γ = 0.1: bursting
/// let opts = BurstOptions::default();
/// let open = response_model(&Model::study(&p), &opts).unwrap();
/// assert_eq!(classify(&p, &open).verdict, Verdict::Overshoot);
/// // with virtual damping k_d = 3 the overshoot and ringing are gone
/// let m = Model::study(&p).with_term(law_term("vdamping", 3.0, &[]).unwrap()).unwrap();
/// let closed = response_model(&m, &opts).unwrap();
/// assert_eq!(classify(&p, &closed).verdict, Verdict::NoBursts);
/// ```
pub fn response_model(m: &Model, opts: &BurstOptions) -> Result<Response> {
    m.check()?;
    let refuse = |reason: &str| Error::InvalidInput {
        what: "model",
        text: m.equation(),
        reason: reason.into(),
    };
    if m.switches() {
        return Err(refuse(
            "the burst verdict needs a smooth model (a term with sticking is integrated piece by piece)",
        ));
    }
    let p = m.equivalent_params().ok_or_else(|| {
        refuse("its static torque is not a study cubic αx³ − x² + γ(x − ε), so its equilibria are no parameter set's")
    })?;
    let x0 = crate::fast::stable_equilibrium(&p, 0.0);
    let z: [f64; MAX_STATES] = m.rest_states(x0);
    match m.dim() {
        2 => run::<2>(m, &p, opts, [x0, 0.0]),
        3 => run::<3>(m, &p, opts, [x0, 0.0, z[0]]),
        _ => run::<4>(m, &p, opts, [x0, 0.0, z[0], z[1]]),
    }
}

fn run<const N: usize>(
    m: &Model,
    p: &crate::Params,
    opts: &BurstOptions,
    y0: [f64; N],
) -> Result<Response> {
    let plan = Plan::new(p, opts)?;
    let mut solver = stepper(m, 0.0, y0, opts.tol)?;
    let mut scanner = plan.scanner(p, opts, y0[0]);
    let mut history = History::new(plan.history_span());
    while solver.t() < plan.scan.1 {
        solver.step(plan.scan.1)?;
        if solver.t() > plan.scan.0 {
            history.push(Projected {
                inner: solver.dense(),
                model: m,
                params: p,
            });
            if let Some(d) = history.latest() {
                scanner.push(d, &history);
            }
        }
    }
    Ok(plan.assemble(p, opts, scanner.finish(&history)))
}
