//! Many switching models integrated at once ([`integrate_switching_models`]): each lane a
//! [`Switching`] integration, the Taylor steps of its slipping pieces taken on vector lanes.
//!
//! A slipping piece fixes every sign (sgn x', sgn z), so it is an analytic model whose
//! switching terms read their signs as numbers ([`crate::model::terms::Term::lane_values`]):
//! the pieces of models of one structure share one structure too, and their passes run as one
//! on [`crate::batch::Lanes`] ([`super::lanes::run_vector`]) while each lane keeps its own
//! piece. After each lane's step its switching integration cuts the step at a located switch
//! and enters the next piece or the rest, as it does alone; its steps at rest (held, or
//! drifting with internal states that move on) and every step of models that do not share a
//! structure are the scalar integration's own.

use super::Model;
use super::lanes::{OnLanes, batchable, outcome, run_vector, same_structure};
use crate::error::Result;
use crate::integrate::lanes::{LANES, LaneResult, check_inputs};
use crate::integrate::{Method, Options, Stepper, Taylor};
use crate::model::switching::{Pieces, Switching, SwitchingDense};
use crate::simd::{Simd, dispatched};

/// Integrates each of `models`, whose laws switch ([`Model::switches`]: sgn x', |z|), from its
/// start `starts[i]` at τ = 0 over its span `spans[i] = (from, t_end)`, [`LANES`] at a time,
/// each as [`Switching`] integrates it alone by Taylor's method (sticking included), and calls
/// `observe(i, step)` with every step of model i that ends after `from`, in order. N is the
/// models' state dimension ([`Model::dim`], the same for all).
///
/// Where the models of a chunk share one structure of terms that each have a copy on vector
/// lanes (the study's terms, the friction laws, Coulomb friction and Bouc–Wen hysteresis), the
/// slipping pieces' Taylor passes run on the lanes, their step rule and limits to ~1e-9 as in
/// [`super::integrate_models`]: each lane's steps and switches are its scalar integration's to
/// about that, its states to the tolerance. Otherwise each lane is integrated on its own.
///
/// Fails as a whole on bad input: counts that differ, a model whose dimension is not N or
/// whose law does not switch (that is [`super::integrate_models`]'s), a parameter outside its
/// domain, a delayed feedback, unusable options. A model that blows up, chatters or runs out of
/// steps gets its own error, and its neighbours' results are the same as without it.
///
/// ```
/// use hdgear::integrate::Options;
/// use hdgear::model::{Model, integrate_switching_models, terms::AnyTerm};
/// use hdgear::Params;
/// // the study's model with Bouc–Wen hysteresis of three stiffnesses
/// let p = Params { delta: 1.0, omega: 0.5, ..Params::default() };
/// let models: Vec<Model> = [0.1, 0.5, 1.0]
///     .iter()
///     .map(|&kh| {
///         Model::study(&p)
///             .with_term(AnyTerm::new("boucwen", &[kh, 0.0, 1.0, 0.5, 0.5, 1.0]).unwrap())
///             .unwrap()
///     })
///     .collect();
/// let ends = integrate_switching_models::<3>(&models, &[[0.0; 3]; 3], &[(0.0, 20.0); 3], Options::default(), |_, _| {})
///     .unwrap();
/// assert!(ends.iter().all(|e| e.is_ok()));
/// ```
pub fn integrate_switching_models<const N: usize>(
    models: &[Model],
    starts: &[[f64; N]],
    spans: &[(f64, f64)],
    tol: Options,
    mut observe: impl FnMut(usize, &SwitchingDense<N>),
) -> Result<Vec<Result<LaneResult<N>>>> {
    check_inputs(models, starts.len(), spans, &tol, |m| {
        batchable::<N>(m, true)
    })?;
    let tol = Options {
        method: Method::Taylor,
        ..tol
    };
    let pieces: Vec<Pieces> = models.iter().filter_map(Pieces::new).collect();
    let mut out = Vec::with_capacity(models.len());
    for (c, chunk) in pieces.chunks(LANES).enumerate() {
        let first = c * LANES;
        let mut lanes: Vec<SwitchLane<'_, N>> = Vec::with_capacity(chunk.len());
        for (l, p) in chunk.iter().enumerate() {
            let i = first + l;
            lanes.push(SwitchLane {
                sw: Switching::new(p, 0.0, starts[i], tol)?,
                span: spans[i],
                end: None,
            });
        }
        let mut show = |l: usize, step: &SwitchingDense<N>| observe(first + l, step);
        if same_structure(chunk.iter().flat_map(Pieces::slipping_pieces)) {
            switching_on(Simd::detect(), &mut lanes, &tol, &mut show);
        } else {
            for (l, lane) in lanes.iter_mut().enumerate() {
                while lane.next_on_lanes(l, &mut show).is_some() {
                    lane.step_alone(l, &mut show);
                }
            }
        }
        out.extend(lanes.into_iter().map(|lane| outcome(lane.end)));
    }
    Ok(out)
}

dispatched! {
    /// [`run_vector`] on switching lanes with the arithmetic of the vector unit `simd` names.
    fn switching_on['p, const N: usize](lanes: &mut [SwitchLane<'p, N>], tol: &Options, show: &mut dyn FnMut(usize, &SwitchingDense<N>)) -> () = run_vector::<FMA, N, _>(lanes, tol, show)
}

/// One lane: its switching integration, its span and, once it has stopped, its outcome.
struct SwitchLane<'p, const N: usize> {
    sw: Switching<'p, N>,
    span: (f64, f64),
    end: Option<Result<LaneResult<N>>>,
}

impl<'p, const N: usize> SwitchLane<'p, N> {
    /// Steps the lane on its own while it is at rest, until its next step is a slipping
    /// piece's Taylor step: then that stepper's weights ([`Taylor::begin`]); `None` once the
    /// lane has its outcome.
    fn next_on_lanes(
        &mut self,
        l: usize,
        show: &mut dyn FnMut(usize, &SwitchingDense<N>),
    ) -> Option<[f64; N]> {
        loop {
            if self.end.is_some() {
                return None;
            }
            if self.sw.t() >= self.span.1 {
                self.end = Some(Ok(LaneResult {
                    y: *self.sw.y(),
                    steps: self.sw.stats().steps,
                }));
                return None;
            }
            if let Some(e) = self.sw.spent() {
                self.end = Some(Err(e.into()));
                return None;
            }
            if let Some(taylor) = self.sw.on_piece() {
                match taylor.begin(self.span.1) {
                    Ok(Some(scale)) => return Some(scale),
                    Ok(None) => {}
                    Err(e) => {
                        self.end = Some(Err(e));
                        return None;
                    }
                }
            }
            self.step_alone(l, show);
        }
    }

    /// One step of the lane's switching integration on its own.
    fn step_alone(&mut self, l: usize, show: &mut dyn FnMut(usize, &SwitchingDense<N>)) {
        let done = self.sw.step(self.span.1);
        self.after(l, done, show);
    }

    /// The outcome of a step: shown when it ends past the span's start, kept when it failed.
    fn after(
        &mut self,
        l: usize,
        done: Result<()>,
        show: &mut dyn FnMut(usize, &SwitchingDense<N>),
    ) {
        match done {
            Ok(()) if self.sw.t() > self.span.0 => show(l, &self.sw.dense()),
            Ok(()) => {}
            Err(e) => self.end = Some(Err(e)),
        }
    }
}

impl<'p, const N: usize> OnLanes<'p, N> for SwitchLane<'p, N> {
    type Dense = SwitchingDense<N>;
    #[inline(always)]
    fn begin(&mut self, l: usize, show: &mut dyn FnMut(usize, &Self::Dense)) -> Option<[f64; N]> {
        self.next_on_lanes(l, show)
    }
    /// The current piece (the model the lane was built on while at rest).
    #[inline(always)]
    fn model(&self) -> &'p Model {
        self.sw.piece()
    }
    #[inline(always)]
    fn stepper(&mut self) -> Option<&mut Taylor<'p, Model, N>> {
        self.sw.on_piece()
    }
    #[inline(always)]
    fn finish<const FMA: bool>(
        &mut self,
        l: usize,
        h: f64,
        show: &mut dyn FnMut(usize, &Self::Dense),
    ) {
        let span_end = self.span.1;
        let Some(taylor) = self.sw.on_piece() else {
            return;
        };
        let done = taylor
            .finish::<FMA>(span_end, h)
            .and_then(|()| self.sw.after_inner_step());
        self.after(l, done, show);
    }
}
