//! Many models integrated by Taylor's method at once ([`integrate_models`]), [`LANES`] in
//! lock-step and their passes interleaved order by order.
//!
//! One Taylor pass is one chain: each row waits for the rows it is made of, so a single
//! trajectory leaves most of the CPU's execution units idle. The passes of sixteen trajectories
//! are sixteen independent chains: computing row k of every lane before row k + 1 of any gives
//! the CPU independent work to overlap. Each lane is a scalar [`Taylor`] stepper and runs the
//! model's own pass ([`Model::pass`], [`Model::pass_row`]), step rule and checks
//! ([`Taylor::begin`], [`Taylor::finish`]): a lane's steps are those of the scalar stepper, to
//! the bit.
//!
//! The lanes need not share a structure: each runs its own model's terms. Models that switch
//! ([`Model::switches`]: sgn x', |z|) are stepped piece by piece by [`crate::model::switching`],
//! and a delayed feedback needs its run's history; the batch refuses both.

use super::Model;
use crate::error::{Error, Result};
use crate::integrate::lanes::{LANES, LaneResult, check_inputs};
use crate::integrate::{Options, Stepper, Taylor, TaylorDense};
use crate::simd::{Level, Simd, dispatched};

/// Integrates each of `models` from its start `starts[i]` at τ = 0 over its span
/// `spans[i] = (from, t_end)` by Taylor's method, [`LANES`] at a time, and calls
/// `observe(i, step)` with every step of model i that ends after `from`, in order. N is the
/// models' state dimension ([`Model::dim`], the same for all). Each lane takes the steps the
/// scalar stepper takes ([`crate::integrate::Method::Taylor`]), to the bit.
///
/// Fails as a whole on bad input: counts that differ, a model whose dimension is not N, a
/// parameter outside its domain, a model that switches or has a delayed feedback, unusable
/// options. A model that blows up or runs out of steps gets its own error, and its neighbours'
/// results are the same as without it.
///
/// ```
/// use hdgear::integrate::{DenseOutput, Options};
/// use hdgear::model::{Model, integrate_models, terms::AnyTerm};
/// use hdgear::Params;
/// // the study's model with smooth friction of three levels
/// let models: Vec<Model> = [0.0, 0.1, 1.0]
///     .iter()
///     .map(|&fc| {
///         Model::study(&Params::default())
///             .with_term(AnyTerm::new("friction", &[fc, 0.01]).unwrap())
///             .unwrap()
///     })
///     .collect();
/// let spans = [(0.0, 50.0); 3];
/// let mut peak = [0.0f64; 3];
/// let ends = integrate_models::<2>(&models, &[[0.0; 2]; 3], &spans, Options::default(), |i, step| {
///     peak[i] = peak[i].max(step.eval(step.t_end())[1].abs());
/// })
/// .unwrap();
/// assert!(ends.iter().all(|e| e.is_ok()));
/// ```
pub fn integrate_models<const N: usize>(
    models: &[Model],
    starts: &[[f64; N]],
    spans: &[(f64, f64)],
    tol: Options,
    mut observe: impl FnMut(usize, &TaylorDense<N>),
) -> Result<Vec<Result<LaneResult<N>>>> {
    check_inputs(models, starts.len(), spans, &tol, batchable::<N>)?;
    let mut out = Vec::with_capacity(models.len());
    for (c, chunk) in models.chunks(LANES).enumerate() {
        let first = c * LANES;
        let mut lanes: Vec<Lane<'_, N>> = Vec::with_capacity(chunk.len());
        for (l, model) in chunk.iter().enumerate() {
            let i = first + l;
            lanes.push(Lane {
                model,
                stepper: Taylor::new(model, 0.0, starts[i], tol)?,
                span: spans[i],
                end: None,
            });
        }
        let mut show = |l: usize, step: &TaylorDense<N>| observe(first + l, step);
        // the step's own arithmetic as the scalar stepper's (`Taylor::step`)
        run_on(Simd::detect().at_most(Level::Avx2), &mut lanes, &mut show);
        out.extend(lanes.into_iter().map(|lane| {
            // (`run` returns once every lane has its outcome)
            lane.end.unwrap_or_else(|| {
                Err(Error::InvalidInput {
                    what: "batch",
                    text: "a lane".into(),
                    reason: "it stopped before its end".into(),
                })
            })
        }));
    }
    Ok(out)
}

/// Whether model `m` can run in the batch with N state components.
fn batchable<const N: usize>(m: &Model) -> Result<()> {
    m.check()?;
    let refuse = |reason: String| {
        Err(Error::InvalidInput {
            what: "model",
            text: m.equation(),
            reason,
        })
    };
    if m.dim() != N {
        return refuse(format!(
            "it has {} state components; the batch was asked for {N}",
            m.dim()
        ));
    }
    if m.switches() {
        return refuse("its law switches (sgn x', |z|): it is stepped piece by piece".into());
    }
    if m.delay().is_some() {
        return refuse("a delayed feedback needs its run's history".into());
    }
    Ok(())
}

/// One lane: its model, its stepper, its span and, once it has stopped, its outcome.
struct Lane<'m, const N: usize> {
    model: &'m Model,
    stepper: Taylor<'m, Model, N>,
    span: (f64, f64),
    end: Option<Result<LaneResult<N>>>,
}

dispatched! {
    /// [`run`] with the arithmetic of the vector unit `simd` names.
    fn run_on['m, const N: usize](lanes: &mut [Lane<'m, N>], show: &mut dyn FnMut(usize, &TaylorDense<N>)) -> () = run::<FMA, N>(lanes, show)
}

/// Steps every lane to its end: each round, one step of every lane still running, their
/// passes interleaved order by order.
#[inline(always)]
fn run<const FMA: bool, const N: usize>(
    lanes: &mut [Lane<'_, N>],
    show: &mut dyn FnMut(usize, &TaylorDense<N>),
) {
    let mut scales = [[0.0; N]; LANES];
    let mut passes: [Option<super::system::Pass>; LANES] = [const { None }; LANES];
    loop {
        // which lanes step this round, with the weights of their step rule
        let mut running = 0;
        for (l, lane) in lanes.iter_mut().enumerate() {
            passes[l] = None;
            if lane.end.is_some() {
                continue;
            }
            match lane.stepper.begin(lane.span.1) {
                Ok(Some(scale)) => {
                    scales[l] = scale;
                    let (t, y, p, ..) = lane.stepper.rows_mut();
                    passes[l] = Some(lane.model.pass(t, y, p));
                    running += 1;
                }
                Ok(None) => {
                    lane.end = Some(Ok(LaneResult {
                        y: *lane.stepper.y(),
                        steps: lane.stepper.stats().steps,
                    }))
                }
                Err(e) => lane.end = Some(Err(e)),
            }
        }
        if running == 0 {
            return;
        }
        // the passes, order by order: row k of every lane before row k + 1 of any
        let top = passes.iter().flatten().map(|p| p.n).max().unwrap_or(0);
        for k in 0..=top {
            for (lane, pass) in lanes.iter_mut().zip(passes.iter_mut()) {
                if let Some(pass) = pass.as_mut().filter(|p| k <= p.n) {
                    let (.., work) = lane.stepper.rows_mut();
                    lane.model.pass_row::<N>(pass, k, work);
                }
            }
        }
        // each lane's step on its rows, as the scalar stepper takes it
        for (l, (lane, pass)) in lanes.iter_mut().zip(&passes).enumerate() {
            let Some(pass) = pass else { continue };
            let (.., c, _) = lane.stepper.rows_mut();
            let n = pass.finish(c);
            let mut h = lane.stepper.rule::<FMA>(&scales[l]);
            if lane.model.limits_steps() {
                let atol = lane.stepper.options().atol;
                h = lane.model.limit_step(lane.stepper.work(), n, h, atol);
            }
            match lane.stepper.finish::<FMA>(lane.span.1, h) {
                Ok(()) if lane.stepper.t() > lane.span.0 => show(l, &lane.stepper.dense()),
                Ok(()) => {}
                Err(e) => lane.end = Some(Err(e)),
            }
        }
    }
}
