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
//! Models that share one structure of terms that each have a copy on vector lanes
//! ([`on_vector_lanes`]: the study's terms, the friction laws, Bouc–Wen hysteresis) run one pass
//! for all sixteen on [`Lanes`] ([`run_vector`], internal states included), each term's
//! recurrence written once over [`Jet`] numbers so that every lane computes what its scalar pass
//! does, in the same order. Their step rule and the terms'
//! step limits run on the lanes too, their logarithms and exponentials by short polynomials to
//! ~1e-9 ([`crate::integrate::approx`], as the study's batch does): their steps are the scalar
//! stepper's to about that, so their states agree with it to the tolerance, not to the bit.
//! Otherwise the lanes need not share a structure: each runs its own model's terms, interleaved.
//! Models that switch ([`Model::switches`]: sgn x', |z|) are stepped piece by piece by
//! [`crate::model::switching`], and have their own batch ([`super::switching_lanes`], on the same
//! [`run_vector`]); a delayed feedback needs its run's history. This batch refuses both.

use super::{MAX_TERMS, Model};
use crate::error::{Error, Result};
use crate::integrate::lanes::{Jet, LANES, LaneResult, Lanes, check_inputs};
use crate::integrate::taylor::{cap, forcing_series, step_from_norms, weighted_norm};
use crate::integrate::{Options, Stepper, Taylor, TaylorDense};
use crate::model::switching::Pieces;
use crate::model::terms::{LANE_PARAMS, LaneRows, MAX_ROWS};
use crate::simd::{Level, Simd, dispatched};

/// Integrates each of `models` from its start `starts[i]` at τ = 0 over its span
/// `spans[i] = (from, t_end)` by Taylor's method, [`LANES`] at a time, and calls
/// `observe(i, step)` with every step of model i that ends after `from`, in order. N is the
/// models' state dimension ([`Model::dim`], the same for all). Each lane takes the steps the
/// scalar stepper takes ([`crate::integrate::Method::Taylor`]): to the bit, or on vector lanes
/// ([`on_vector_lanes`]) to the ~1e-9 of their step rule.
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
    check_inputs(models, starts.len(), spans, &tol, |m| {
        batchable::<N>(m, false)
    })?;
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
        // passes on vector lanes take the widest vector unit; interleaved scalar passes the
        // scalar stepper's (`Taylor::step`)
        let vector = same_structure(lanes.iter().map(|lane| lane.model));
        let simd = if vector {
            Simd::detect()
        } else {
            Simd::detect().at_most(Level::Avx2)
        };
        run_on(simd, &mut lanes, vector, &tol, &mut show);
        out.extend(lanes.into_iter().map(|lane| outcome(lane.end)));
    }
    Ok(out)
}

/// Whether model `m` can run with N state components in the batch of smooth models
/// ([`integrate_models`], `switching` false) or of switching ones
/// ([`super::integrate_switching_models`]).
pub(super) fn batchable<const N: usize>(m: &Model, switching: bool) -> Result<()> {
    m.check()?;
    let refuse = |reason: &str| {
        Err(Error::InvalidInput {
            what: "model",
            text: m.equation(),
            reason: reason.into(),
        })
    };
    if m.dim() != N {
        let reason = format!(
            "it has {} state components; the batch was asked for {N}",
            m.dim()
        );
        return refuse(&reason);
    }
    match (m.switches(), switching) {
        (true, false) => {
            return refuse(
                "its law switches (sgn x', |z|): integrate it with integrate_switching_models",
            );
        }
        (false, true) => {
            return refuse("its law does not switch: integrate it with integrate_models");
        }
        _ => {}
    }
    if m.delay().is_some() {
        return refuse("a delayed feedback needs its run's history");
    }
    Ok(())
}

/// A lane's outcome once its run has returned (each runs until it has one).
pub(super) fn outcome<const N: usize>(end: Option<Result<LaneResult<N>>>) -> Result<LaneResult<N>> {
    end.unwrap_or_else(|| {
        Err(Error::InvalidInput {
            what: "batch",
            text: "a lane".into(),
            reason: "it stopped before its end".into(),
        })
    })
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
    fn run_on['m, const N: usize](lanes: &mut [Lane<'m, N>], vector: bool, tol: &Options, show: &mut dyn FnMut(usize, &TaylorDense<N>)) -> () = run::<FMA, N>(lanes, vector, tol, show)
}

/// Steps every lane to its end: each round, one step of every lane still running. Models that
/// share one structure of terms on vector lanes (`vector`, from [`on_vector_lanes`]'s test) run
/// their passes as one on [`Lanes`] ([`run_vector`]); others run their passes interleaved
/// order by order.
#[inline(always)]
fn run<const FMA: bool, const N: usize>(
    lanes: &mut [Lane<'_, N>],
    vector: bool,
    tol: &Options,
    show: &mut dyn FnMut(usize, &TaylorDense<N>),
) {
    if vector {
        return run_vector::<FMA, N, _>(lanes, tol, show);
    }
    let mut scales = [[0.0; N]; LANES];
    let mut passes: [Option<super::system::Pass>; LANES] = [const { None }; LANES];
    loop {
        // which lanes step this round, with the weights of their step rule
        let mut running = 0;
        for (l, lane) in lanes.iter_mut().enumerate() {
            passes[l] = lane.start().map(|scale| {
                scales[l] = scale;
                running += 1;
                let (t, y, p, ..) = lane.stepper.rows_mut();
                lane.model.pass(t, y, p)
            });
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
            lane.step::<FMA>(l, n, &scales[l], show);
        }
    }
}

/// Whether [`integrate_models`] runs the passes of `models` on vector lanes, all sixteen of a
/// chunk at once: when they share one structure (the same kinds of term in the same slots, all
/// held or none) of terms that each have a copy on lanes
/// ([`crate::model::terms::AnyTerm::on_lanes`]: the study's terms, the friction laws, Bouc–Wen
/// hysteresis). Other batches run their lanes' passes interleaved, each on its own model, and
/// take the scalar stepper's steps to the bit; on vector lanes the step rule and the terms'
/// limits are computed to ~1e-9 ([`integrate_models`]). For models that switch, whether
/// [`super::integrate_switching_models`] runs their slipping pieces' passes on vector lanes.
///
/// ```
/// use hdgear::model::{Model, on_vector_lanes, terms::AnyTerm};
/// use hdgear::Params;
/// let friction = |fc: f64| {
///     Model::study(&Params::default())
///         .with_term(AnyTerm::new("friction", &[fc, 0.01]).unwrap())
///         .unwrap()
/// };
/// assert!(on_vector_lanes(&[friction(0.1), friction(0.3)]));
/// // a model without the friction term has another structure
/// assert!(!on_vector_lanes(&[friction(0.1), Model::study(&Params::default())]));
/// ```
pub fn on_vector_lanes(models: &[Model]) -> bool {
    if models.iter().all(|m| !m.switches()) {
        return same_structure(models.iter());
    }
    // switching models: their slipping pieces, as `integrate_switching_models` runs them
    let pieces: Vec<Pieces> = models.iter().filter_map(Pieces::new).collect();
    pieces.len() == models.len() && same_structure(pieces.iter().flat_map(Pieces::slipping_pieces))
}

/// Whether the models `models` yields share one structure of terms on vector lanes (the same
/// kinds in the same slots, each with a copy on lanes and the same [`AnyTerm::lane_shape`]; all
/// held or none): [`on_vector_lanes`], and for switching models of their pieces.
///
/// [`AnyTerm::lane_shape`]: crate::model::terms::AnyTerm::lane_shape
pub(super) fn same_structure<'m>(mut models: impl Iterator<Item = &'m Model>) -> bool {
    let mut first = None;
    models.all(|m| {
        let first: &Model = first.get_or_insert(m);
        m.held == first.held
            && m.terms.iter().zip(&first.terms).all(|pair| match pair {
                (None, None) => true,
                (Some(a), Some(b)) => {
                    a.kind() == b.kind() && a.on_lanes() && a.lane_shape() == b.lane_shape()
                }
                _ => false,
            })
    })
}

/// A lane of a batch whose passes run on vector lanes ([`run_vector`]): a model's Taylor
/// stepper ([`Lane`]), or a switching integration's on its current piece
/// ([`super::switching_lanes`]).
pub(super) trait OnLanes<'m, const N: usize> {
    /// What a step shows.
    type Dense;
    /// The start of the lane's next step on the lanes: the weights of its step rule, or `None`
    /// when it has stopped (its outcome then kept). `show` (as lane `l`) takes whatever steps
    /// the lane takes on its own before that.
    fn begin(&mut self, l: usize, show: &mut dyn FnMut(usize, &Self::Dense)) -> Option<[f64; N]>;
    /// The model whose pass the step takes (after [`OnLanes::begin`]).
    fn model(&self) -> &'m Model;
    /// The stepper whose rows the pass fills (there is one after [`OnLanes::begin`] gave
    /// weights).
    fn stepper(&mut self) -> Option<&mut Taylor<'m, Model, N>>;
    /// The lane's step of `h` on the rows in its stepper, shown as lane `l`'s.
    fn finish<const FMA: bool>(
        &mut self,
        l: usize,
        h: f64,
        show: &mut dyn FnMut(usize, &Self::Dense),
    );
}

/// Steps every lane to its end, one step of every running lane per round, for lanes whose
/// models share a structure of terms on vector lanes ([`same_structure`]) and options `tol`:
/// each round one pass of every lane at once on [`Lanes`] (each term's
/// [`crate::model::terms::AnyTerm::taylor_lanes`], the lanes' [`Term::lane_values`] side by side),
/// which gives each lane the rows of its scalar pass to the bit; then the step rule and the
/// terms' step limits on all lanes at once (to ~1e-9), and each lane's step.
///
/// [`Term::lane_values`]: crate::model::terms::Term::lane_values
#[inline(always)]
pub(super) fn run_vector<'m, const FMA: bool, const N: usize, L: OnLanes<'m, N>>(
    lanes: &mut [L],
    tol: &Options,
    show: &mut dyn FnMut(usize, &L::Dense),
) {
    use crate::integrate::taylor::SCRATCH_ROWS;
    let zero = Lanes([0.0; LANES]);
    // the structure (kinds, slots, states), the same on every lane
    let model = lanes[0].model();
    let (order, shift) = crate::integrate::taylor::rule(tol);
    let pass = model.pass::<N>(0.0, &[0.0; N], order);
    let n = pass.n;
    // each lane's terms' numbers, refreshed where a lane's model changes (a switching lane's
    // piece); a lane past the models' count repeats lane 0's
    let mut params = [[zero; LANE_PARAMS]; MAX_TERMS];
    let mut current: [*const Model; LANES] = [std::ptr::null(); LANES];
    for (l, now) in current.iter_mut().enumerate() {
        let m = lanes.get(l).unwrap_or(&lanes[0]).model();
        set_lane(&mut params, l, m);
        *now = m;
    }
    let mut rows: Box<[LaneRows; MAX_TERMS]> =
        Box::new([[[zero; MAX_ROWS]; SCRATCH_ROWS]; MAX_TERMS]);
    let moving = Lanes::splat(if model.held { 0.0 } else { 1.0 });
    // the slots of the terms that limit steps
    let limiting: Vec<usize> = (0..MAX_TERMS)
        .filter(|&i| model.terms[i].is_some_and(|t| t.limits_steps()))
        .collect();
    let mut scales = [[0.0; N]; LANES];
    let mut running = [false; LANES];
    let [mu, delta, omega] = by_lane(lanes, |m| m.forcing());
    loop {
        // the state's row 0 and sin, cos ωt of every lane that steps this round
        let (mut f, mut s) = ([zero; MAX_ROWS], [[zero; MAX_ROWS]; N]);
        let (mut sin, mut cos) = (zero, zero);
        let mut any = false;
        for (l, lane) in lanes.iter_mut().enumerate() {
            running[l] = false;
            let Some(scale) = lane.begin(l, show) else {
                continue;
            };
            let m = lane.model();
            let Some(stepper) = lane.stepper() else {
                continue;
            };
            (scales[l], running[l], any) = (scale, true, true);
            if !std::ptr::eq(current[l], m) {
                set_lane(&mut params, l, m);
                current[l] = m;
            }
            let (t, y, ..) = stepper.rows_mut();
            (sin.0[l], cos.0[l]) = libm::sincos(omega.0[l] * t);
            for (si, &yi) in s.iter_mut().zip(y) {
                si[0].0[l] = yi;
            }
        }
        if !any {
            return;
        }
        // the forcing's rows, each lane's as its model's (`Model::forcing_rows`)
        forcing_series(delta, omega, (sin, cos), n, &mut f);
        f[0] = f[0] + mu;
        // the pass on the lanes, as `Model::pass_row` runs it on one
        let live = &pass.live[..pass.m];
        pass_on_lanes(model, live, &params, &mut rows, (&f, &mut s), moving, n);
        // each lane's rows back to its stepper; the step rule and the terms' limits on all lanes
        for (l, lane) in lanes.iter_mut().enumerate() {
            let Some(stepper) = lane.stepper().filter(|_| running[l]) else {
                continue;
            };
            let (.., c, _) = stepper.rows_mut();
            for (k, ck) in c.iter_mut().enumerate().take(n + 1) {
                for (i, v) in ck.iter_mut().enumerate() {
                    *v = s[i][k].0[l];
                }
            }
        }
        let h = rule_on_lanes::<FMA, N>((order, shift, tol.h_max), &s, &scales);
        let h = model.limit_step_lanes(&params, &rows, &limiting, n, h, tol.atol);
        for (l, lane) in lanes.iter_mut().enumerate() {
            if running[l] {
                lane.finish::<FMA>(l, h.0[l], show);
            }
        }
    }
}

/// One Taylor pass of a model's structure on the lanes to order `n`, as [`Model::pass_row`]
/// runs it on one: the present terms `live` (slot, state index) of `model`, their numbers
/// `params` and own rows `rows` by slot, the forcing's rows `f` and the state's rows `s` (row 0
/// given, rows 1..=n filled); `moving` is 0 on a held model.
#[inline(always)]
fn pass_on_lanes<const N: usize>(
    model: &Model,
    live: &[(usize, Option<usize>)],
    params: &[[Lanes; LANE_PARAMS]; MAX_TERMS],
    rows: &mut [LaneRows; MAX_TERMS],
    (f, s): (&[Lanes; MAX_ROWS], &mut [[Lanes; MAX_ROWS]; N]),
    moving: Lanes,
    n: usize,
) {
    use crate::integrate::taylor::INV;
    const NONE: [Lanes; MAX_ROWS] = [Lanes([0.0; LANES]); MAX_ROWS];
    for k in 0..=n {
        let mut acc = f[k];
        let mut rates = [Lanes([0.0; LANES]); N];
        for &(i, at) in live {
            let Some(term) = &model.terms[i] else {
                continue;
            };
            let (p, r) = (&params[i], &mut rows[i]);
            let z = at.map_or(&NONE, |j| &s[j]);
            if let Some(j) = at {
                rates[j] = term.rate_taylor_lanes(p, k, &s[0], &s[1], z, r);
            }
            if let Some(t) = term.taylor_lanes(p, k, &s[0], &s[1], z, r) {
                acc = acc - t;
            }
        }
        if k == n {
            break;
        }
        s[0][k + 1] = moving * s[1][k] * Lanes::splat(INV[k]);
        s[1][k + 1] = moving * acc * Lanes::splat(INV[k]);
        for i in 2..N {
            s[i][k + 1] = rates[i] * Lanes::splat(INV[k]);
        }
    }
}

/// The step rule ([`crate::integrate::Taylor::rule`], with its order, shift and cap `parts`) on
/// every lane at once, from the state's rows `s` and each lane's weights `scales`; its
/// logarithms and exponential by the short polynomials of [`crate::integrate::approx`], which
/// vectorise (the scalar rule takes the library's).
#[inline(always)]
fn rule_on_lanes<const FMA: bool, const N: usize>(
    (p, shift, h_max): (usize, f64, Option<f64>),
    s: &[[Lanes; MAX_ROWS]; N],
    scales: &[[f64; N]; LANES],
) -> Lanes {
    let mut h = Lanes([0.0; LANES]);
    for (l, (hl, scale)) in h.0.iter_mut().zip(scales).enumerate() {
        let norm = |k: usize| weighted_norm(|i| s[i][k].0[l], scale);
        let rule = step_from_norms::<FMA, true>(p, shift, norm(p - 1), norm(p));
        *hl = cap(rule, h_max);
    }
    h
}

/// `value` of each lane's model side by side on the lanes: value j of lane l at `[j].0[l]`; a
/// lane past the models' count repeats lane 0's.
fn by_lane<'m, const N: usize, const J: usize, L: OnLanes<'m, N>>(
    lanes: &[L],
    value: impl Fn(&Model) -> [f64; J],
) -> [Lanes; J] {
    let mut out = [Lanes([0.0; LANES]); J];
    for l in 0..LANES {
        for (o, v) in out
            .iter_mut()
            .zip(value(lanes.get(l).unwrap_or(&lanes[0]).model()))
        {
            o.0[l] = v;
        }
    }
    out
}

/// Lane l's column of the terms' numbers by slot (`params[i][j].0[l]`, value j of the term in
/// slot i: its [`crate::model::terms::Term::lane_values`]) from its model `m`.
fn set_lane(params: &mut [[Lanes; LANE_PARAMS]; MAX_TERMS], l: usize, m: &Model) {
    for (slot, term) in params.iter_mut().zip(&m.terms) {
        let values = term.map_or([0.0; LANE_PARAMS], |t| t.lane_values());
        for (p, v) in slot.iter_mut().zip(values) {
            p.0[l] = v;
        }
    }
}

impl<const N: usize> Lane<'_, N> {
    /// The start of the lane's step ([`Taylor::begin`]): the weights of its step rule, or `None`
    /// when it has stopped (its outcome then kept).
    #[inline(always)]
    fn start(&mut self) -> Option<[f64; N]> {
        if self.end.is_some() {
            return None;
        }
        match self.stepper.begin(self.span.1) {
            Ok(Some(scale)) => return Some(scale),
            Ok(None) => {
                self.end = Some(Ok(LaneResult {
                    y: *self.stepper.y(),
                    steps: self.stepper.stats().steps,
                }))
            }
            Err(e) => self.end = Some(Err(e)),
        }
        None
    }

    /// The lane's step on the rows of its pass to order `n` (in its stepper), as the scalar
    /// stepper takes it: the rule with the weights `scale`, the terms' limits, then
    /// [`Lane::finish`].
    #[inline(always)]
    fn step<const FMA: bool>(
        &mut self,
        l: usize,
        n: usize,
        scale: &[f64; N],
        show: &mut dyn FnMut(usize, &TaylorDense<N>),
    ) {
        let mut h = self.stepper.rule::<FMA>(scale);
        if self.model.limits_steps() {
            let atol = self.stepper.options().atol;
            h = self.model.limit_step(self.stepper.work(), n, h, atol);
        }
        self.end_step::<FMA>(l, h, show);
    }

    /// The lane's step of `h` on the coefficients in its stepper, with its checks; a step that
    /// ends past the span's start is shown as lane `l`'s.
    #[inline(always)]
    fn end_step<const FMA: bool>(
        &mut self,
        l: usize,
        h: f64,
        show: &mut dyn FnMut(usize, &TaylorDense<N>),
    ) {
        match self.stepper.finish::<FMA>(self.span.1, h) {
            Ok(()) if self.stepper.t() > self.span.0 => show(l, &self.stepper.dense()),
            Ok(()) => {}
            Err(e) => self.end = Some(Err(e)),
        }
    }
}

impl<'m, const N: usize> OnLanes<'m, N> for Lane<'m, N> {
    type Dense = TaylorDense<N>;
    #[inline(always)]
    fn begin(&mut self, _: usize, _: &mut dyn FnMut(usize, &Self::Dense)) -> Option<[f64; N]> {
        self.start()
    }
    #[inline(always)]
    fn model(&self) -> &'m Model {
        self.model
    }
    #[inline(always)]
    fn stepper(&mut self) -> Option<&mut Taylor<'m, Model, N>> {
        Some(&mut self.stepper)
    }
    #[inline(always)]
    fn finish<const FMA: bool>(
        &mut self,
        l: usize,
        h: f64,
        show: &mut dyn FnMut(usize, &Self::Dense),
    ) {
        self.end_step::<FMA>(l, h, show);
    }
}
