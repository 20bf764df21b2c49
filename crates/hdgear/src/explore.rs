//! What the live explorer (`hdgear serve`) shows for one parameter set ([`View`], computed in
//! one pass) or one model with terms ([`ModelView`]): the fast-subsystem analysis, the response
//! and its verdict, the equilibrium curve, and the trajectory over one slow period thinned for
//! the screen.
//!
//! The trajectory is sampled every [`crate::study::SAMPLE_DT`] (up to 10⁵ samples at small ω)
//! and thinned to at most 2·[`TRACE_BUCKETS`] points by keeping, in each of [`TRACE_BUCKETS`]
//! equal time buckets, the samples where x' is smallest and largest: a burst a few samples wide
//! keeps its peak (a plain every-k-th thinning would drop it), and no screen is wider than the
//! buckets.
//!
//! ```
//! use hdgear::{Params, explore::View};
//! let v = View::compute(&Params::default(), Vec::new(), &View::options()).unwrap();
//! assert!(v.classification.bursting);
//! assert!(v.trace.t.len() <= 2 * hdgear::explore::TRACE_BUCKETS + 2);
//! ```

use crate::burst::{BurstOptions, Classification, Response};
use crate::error::Result;
use crate::fast::{A_RANGE, Analysis, CurveAnalysis, CurveBranch, StaticCurve};
use crate::model::{AnyCurve, Model};
use crate::params::{Params, Warning};
use crate::study::Case;
use serde::Serialize;

/// Time buckets of the thinned trajectory.
pub const TRACE_BUCKETS: usize = 1200;

/// Points of the equilibrium curve.
pub const CURVE_POINTS: usize = 801;

/// The explorer's step budget: a parameter set whose run would need more integration steps
/// (estimated before any work, at the most optimistic step) is refused. 4·10⁶ steps is about a
/// second of integration here; the study's points take 10⁴.
pub const STEP_BUDGET: u64 = 4_000_000;

/// The equilibrium curve over a ∈ [−1, 1], as columns.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Curve {
    /// Slow variable.
    pub a: Vec<f64>,
    /// Equilibrium position.
    pub x: Vec<f64>,
    /// dx/da.
    pub slope: Vec<f64>,
    /// Stable (node or focus) or a saddle.
    pub stable: Vec<bool>,
    /// Branch (single, lower, middle, upper).
    pub branch: Vec<CurveBranch>,
}

/// The trajectory over the first analysed slow period, thinned, as columns.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Trace {
    /// Time τ.
    pub t: Vec<f64>,
    /// a = sin ωτ.
    pub a: Vec<f64>,
    /// x.
    pub x: Vec<f64>,
    /// x'.
    pub xdot: Vec<f64>,
}

/// Everything one view of the explorer shows.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct View {
    /// The parameters.
    pub params: Params,
    /// Their warnings (α·ε ≠ 1, …), as sentences.
    pub warnings: Vec<String>,
    /// The fast subsystem: folds, cusp, steepest point, spiking areas, the prediction and the
    /// predicted boundaries in γ and ω.
    pub analysis: Analysis,
    /// The verdict: bursting, mode, mechanism, fast-slow domain.
    pub classification: Classification,
    /// The measured response: signatures, rates, the bursts.
    pub response: Response,
    /// The equilibrium curve.
    pub curve: Curve,
    /// The trajectory over one slow period.
    pub trace: Trace,
}

impl View {
    /// The explorer's detection options: the defaults within [`STEP_BUDGET`].
    pub fn options() -> BurstOptions {
        let mut o = BurstOptions::default();
        o.tol.max_steps = STEP_BUDGET;
        o
    }

    /// Computes the view of `p` (with its `warnings`) under `opts`.
    pub fn compute(p: &Params, warnings: Vec<Warning>, opts: &BurstOptions) -> Result<View> {
        let case = Case::compute(p, opts)?;
        Ok(View {
            params: *p,
            warnings: warnings.iter().map(ToString::to_string).collect(),
            analysis: case.analysis,
            classification: case.classification,
            response: case.response,
            curve: Curve::of(p)?,
            trace: Trace::of(&case.samples, p.omega),
        })
    }
}

impl Curve {
    /// The equilibrium curve `c` at [`CURVE_POINTS`] points over a ∈ [−1, 1].
    fn of(c: &impl StaticCurve) -> Result<Curve> {
        let mut curve = Curve::default();
        for c in crate::fast::curve(c, A_RANGE, CURVE_POINTS)? {
            curve.a.push(c.a);
            curve.x.push(c.x);
            curve.slope.push(c.slope);
            curve.stable.push(c.kind.is_stable());
            curve.branch.push(c.branch);
        }
        Ok(curve)
    }
}

impl Trace {
    /// The samples (τ, x, x') thinned ([`thin`]), with a = sin ωτ.
    fn of(samples: &[(f64, f64, f64)], omega: f64) -> Trace {
        let mut trace = Trace::default();
        for i in thin(samples, TRACE_BUCKETS) {
            let (t, x, v) = samples[i];
            trace.t.push(t);
            trace.a.push((omega * t).sin());
            trace.x.push(x);
            trace.xdot.push(v);
        }
        trace
    }
}

/// Samples (τ, x, x') of a run.
type Samples = Vec<(f64, f64, f64)>;

/// Everything one view of a model with terms shows: as [`View`], with the analysis of the
/// model's own equilibrium curve ([`CurveAnalysis`]: folds, damping at rest, relaxation) in place
/// of the study's closed forms, and the model itself (serialised as its description: equation,
/// terms, parameters).
///
/// ```
/// use hdgear::{Params, explore::{ModelView, View}, model::{Model, terms::AnyTerm}};
/// let m = Model::study(&Params::default())
///     .with_term(AnyTerm::new("friction", &[0.1, 0.05]).unwrap())
///     .unwrap();
/// let v = ModelView::compute(&m, Vec::new(), &View::options()).unwrap();
/// assert!((v.analysis.damping_at_rest - 3.0).abs() < 1e-12); // 1 + f_c/v_s
/// assert_eq!(v.curve.a.len(), hdgear::explore::CURVE_POINTS);
/// assert!(v.trace.t.len() > 100);
/// ```
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelView {
    /// The model.
    pub model: Model,
    /// Remarks on its study set (α·ε ≠ 1, …), as sentences.
    pub warnings: Vec<String>,
    /// Its equilibrium curve's analysis.
    pub analysis: CurveAnalysis,
    /// The verdict.
    pub classification: Classification,
    /// The measured response.
    pub response: Response,
    /// The equilibrium curve.
    pub curve: Curve,
    /// The trajectory over the first analysed slow period.
    pub trace: Trace,
}

impl ModelView {
    /// Computes the view of `m` (with its study set's `warnings`) under `opts`. The verdict is
    /// [`crate::burst::response_model`]'s; the trace is a second run of the same model from the
    /// same start with the same tolerances, sampled every [`crate::study::SAMPLE_DT`] over the
    /// first slow period the verdict analyses.
    pub fn compute(m: &Model, warnings: Vec<String>, opts: &BurstOptions) -> Result<ModelView> {
        let (analysis, curve, samples) = match AnyCurve::of(m)? {
            AnyCurve::Torque(c) => Self::parts(m, &c, opts)?,
            AnyCurve::Scheduled(c) => Self::parts(m, &c, opts)?,
        };
        let response = crate::burst::response_model(m, opts)?;
        Ok(ModelView {
            model: *m,
            warnings,
            analysis,
            classification: crate::burst::classify_model(m, &response)?,
            response,
            curve,
            trace: Trace::of(&samples, m.forcing()[2]),
        })
    }

    /// The analysis and samples of `c`, and the samples of `m`'s run over the first slow period
    /// the verdict analyses.
    fn parts<C: StaticCurve>(
        m: &Model,
        c: &C,
        opts: &BurstOptions,
    ) -> Result<(CurveAnalysis, Curve, Samples)> {
        use crate::simulate::{SimOptions, Start, simulate_model};
        let analysis = crate::fast::curve_analysis(c, A_RANGE)?;
        let (t0, _) = crate::burst::window(c, opts);
        let t1 = t0 + c.slow_period();
        crate::integrate::check_budget(t1, &opts.tol)?;
        let sim = SimOptions {
            t_end: t1,
            dt: crate::study::SAMPLE_DT,
            start: Start::Given {
                x0: c.start(),
                v0: m.rest_rate(),
            },
            tol: opts.tol,
        };
        let mut samples = Vec::new();
        simulate_model(m, &sim, |t, y| {
            if t >= t0 {
                samples.push((t, y[0], y[1]));
            }
        })?;
        Ok((analysis, Curve::of(c)?, samples))
    }
}

/// Indices (increasing) of the samples kept: the first and the last, and in each of `buckets`
/// equal time buckets those of the smallest and the largest x'.
pub fn thin(samples: &[(f64, f64, f64)], buckets: usize) -> Vec<usize> {
    let n = samples.len();
    if n <= 2 * buckets + 2 {
        return (0..n).collect();
    }
    let (t0, t1) = (samples[0].0, samples[n - 1].0);
    let width = (t1 - t0) / buckets as f64;
    let mut keep = vec![0];
    let mut i = 0;
    for b in 0..buckets {
        let end = t0 + (b + 1) as f64 * width;
        let (mut lo, mut hi) = (usize::MAX, usize::MAX);
        while i < n && (samples[i].0 < end || b == buckets - 1) {
            if lo == usize::MAX || samples[i].2 < samples[lo].2 {
                lo = i;
            }
            if hi == usize::MAX || samples[i].2 > samples[hi].2 {
                hi = i;
            }
            i += 1;
        }
        if lo != usize::MAX {
            keep.extend([lo.min(hi), lo.max(hi)]);
        }
    }
    keep.push(n - 1);
    keep.dedup();
    keep
}
