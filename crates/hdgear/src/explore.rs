//! What the live explorer (`hdgear serve`) shows for one parameter set, computed in one pass:
//! the fast-subsystem analysis, the response and its verdict, the equilibrium curve, and the
//! trajectory over one slow period thinned for the screen.
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
use crate::fast::{A_RANGE, Analysis, CurveBranch};
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
        let mut curve = Curve::default();
        for c in crate::fast::curve(p, A_RANGE, CURVE_POINTS)? {
            curve.a.push(c.a);
            curve.x.push(c.x);
            curve.slope.push(c.slope);
            curve.stable.push(c.kind.is_stable());
            curve.branch.push(c.branch);
        }
        let mut trace = Trace::default();
        for i in thin(&case.samples, TRACE_BUCKETS) {
            let (t, x, v) = case.samples[i];
            trace.t.push(t);
            trace.a.push((p.omega * t).sin());
            trace.x.push(x);
            trace.xdot.push(v);
        }
        Ok(View {
            params: *p,
            warnings: warnings.iter().map(ToString::to_string).collect(),
            analysis: case.analysis,
            classification: case.classification,
            response: case.response,
            curve,
            trace,
        })
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
