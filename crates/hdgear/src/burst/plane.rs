//! Boundaries in a plane of two parameters, as curves: the predicted bursting boundary
//! ([`crate::fast::predict`]), the simulated one ([`super::classify`]), the fold set of the fast
//! subsystem (where a fold, and where both folds, enter the traversed range a ∈ [−1, 1]) and the
//! edge of the fast-slow domain ([`super::fast_slow_omega_max`]). Each is the edge of the region
//! where a verdict holds ([`BoundaryKind`]), and one tracer follows them all.
//!
//! # The tracer
//!
//! Each parameter is taken as itself or as its logarithm ([`Scale`]) and scaled so that the box is
//! the unit square (coordinates v). A curve is followed from a point P on it with a heading θ and a
//! step h:
//!
//! 1. **predictor–corrector on a half circle**: the half circle of radius h around P ahead of the
//!    heading, from θ − π/2 to θ + π/2, is searched for the switch of the verdict — first at
//!    [`PlaneOptions::round`] angles evaluated together (both ends among them: they must lie on
//!    either side of the curve, the region on the same side as at the previous step; the first
//!    switch from the outside end is taken), then narrowed ([`crate::roots::multisect`]) until the
//!    bracket's two ends differ by at most the kind's tolerance in each parameter (relative:
//!    [`BOUNDARY_REL_TOL`] for the simulated boundary, [`CURVE_TOL`] for the others). Its midpoint
//!    is the next point and its direction from P the next heading. The heading is the tangent
//!    predictor (the secant of the last step); the circle is the corrector, and unlike a correction
//!    along the normal it also finds the curve after a corner.
//! 2. **step control**: a step that turns the heading by more than [`PlaneOptions::max_turn`], or
//!    whose half circle's ends are not on either side, is retried at h/2; after a turn below a
//!    third of it h grows by 3/2, up to [`PlaneOptions::step_max`]. At the least step (the larger
//!    of [`PlaneOptions::step_min`] and four brackets' widths: a step shorter than its bracket
//!    would be noise) a turn is accepted — a corner, such as where the fold curve meets the cusp
//!    line γ = 1/(3α) — and ends on one side end the curve ([`PlaneEnd::StepTooSmall`]).
//! 3. **ends**: points of the half circle outside the box are taken on its edge (each coordinate
//!    clamped to [0, 1], which keeps the path continuous), so the switch the search finds there is
//!    where the curve leaves the box, on its edge exactly ([`PlaneEnd::Edge`]); or after
//!    [`PlaneOptions::max_points`] points.
//!
//! **Starts**: the switches of the verdict along the box's four edges,
//! [`PlaneOptions::edge_samples`] values each, narrowed to the tolerance. A curve is followed from
//! one end; the start at its other end is then dropped. The simulated boundary is started from the
//! predicted boundary's starts: on the same edge, a window of `lanes` values around the predicted
//! switch, widened until it holds a switch. Curves that close inside the box without touching its
//! edges are not found.
//!
//! **Why one file.** One tracer follows every kind of boundary: the kinds, the tracer (start
//! search, steps, exits through the box's edges) and its rows are read together, and the tracer's
//! helpers are private to it.

use super::{BOUNDARY_REL_TOL, BurstOptions, boundary::simulated_bursting, fast_slow_omega_max};
use crate::error::{Error, Result};
use crate::fast::predict;
use crate::integrate::Method;
use crate::model::{Model, ModelParam};
use crate::params::{Box2, Param, Params, Scale};
use crate::roots::{first_switch, multisect};
use rayon::prelude::*;
use serde::Serialize;
use std::f64::consts::{FRAC_PI_2, PI};

/// Relative tolerance of the points of the boundaries computed without simulation (the predicted
/// boundary, the fold set, the fast-slow edge): their verdicts are exact functions of the
/// parameters, so the bracket is narrowed far below any feature of the curves.
pub const CURVE_TOL: f64 = 1e-9;

/// The largest turn of the heading in one step, in radians: a longer step would cut across a
/// bend whose radius is under h/0.3 ≈ 3 steps.
pub const MAX_TURN: f64 = 0.3;

/// Angles of the first round on each half circle (one batch of the simulated verdict): a
/// feature crossing the half circle over more than π·h/15 ≈ 0.21 h (0.0042 of the box at the
/// default [`PlaneOptions::step_max`]) holds one of them, so the step is cut until it is
/// followed instead of stepped over.
pub const ROUND: usize = crate::batch::LANES;

/// Values per edge of the box in the search for starts of the boundaries computed without
/// simulation (two curves leaving an edge less than 1/64 of it apart may be seen as none).
pub const EDGE_SAMPLES: usize = 64;

/// A boundary in the plane: the edge of the region where a verdict holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum BoundaryKind {
    /// Bursting predicted from the equilibrium curve ([`crate::fast::predict`]).
    Predicted,
    /// Bursting simulated ([`super::classify`] of [`super::response`]).
    Simulated,
    /// At least one fold of the fast subsystem in a ∈ [−1, 1].
    AFoldInRange,
    /// Both folds in a ∈ [−1, 1]: the state must jump every half period (fold hysteresis).
    BothFoldsInRange,
    /// The fast-slow domain: ω ≤ [`super::fast_slow_omega_max`].
    FastSlowEdge,
}

impl BoundaryKind {
    /// All of them, in the order of the output.
    pub const ALL: [BoundaryKind; 5] = [
        BoundaryKind::Predicted,
        BoundaryKind::Simulated,
        BoundaryKind::AFoldInRange,
        BoundaryKind::BothFoldsInRange,
        BoundaryKind::FastSlowEdge,
    ];

    /// The name users write and the output carries.
    pub fn name(self) -> &'static str {
        match self {
            BoundaryKind::Predicted => "predicted",
            BoundaryKind::Simulated => "simulated",
            BoundaryKind::AFoldInRange => "a-fold-in-range",
            BoundaryKind::BothFoldsInRange => "both-folds-in-range",
            BoundaryKind::FastSlowEdge => "fast-slow-edge",
        }
    }

    /// What holds on the region's side of the curve.
    pub fn inside(self) -> &'static str {
        match self {
            BoundaryKind::Predicted => "bursting predicted",
            BoundaryKind::Simulated => "bursting simulated",
            BoundaryKind::AFoldInRange => "a fold of the fast subsystem in a ∈ [−1, 1]",
            BoundaryKind::BothFoldsInRange => "both folds in a ∈ [−1, 1] (fold hysteresis)",
            BoundaryKind::FastSlowEdge => {
                "fast-slow (ω at most a tenth of the turning points' relaxation rate, below the path's)"
            }
        }
    }

    /// The relative tolerance of its points.
    pub fn tolerance(self) -> f64 {
        match self {
            BoundaryKind::Simulated => BOUNDARY_REL_TOL,
            _ => CURVE_TOL,
        }
    }

    /// The verdicts at `points` (the simulated ones as a batch).
    pub fn holds(self, points: &[Params], opts: &BurstOptions) -> Result<Vec<bool>> {
        let cheap: fn(&Params) -> bool = match self {
            BoundaryKind::Simulated => return simulated_bursting(points, opts),
            BoundaryKind::Predicted => |p| predict(p).bursting,
            BoundaryKind::AFoldInRange => |p| predict(p).folds_in_range >= 1,
            BoundaryKind::BothFoldsInRange => |p| predict(p).fold_in_range,
            BoundaryKind::FastSlowEdge => |p| p.omega <= fast_slow_omega_max(p),
        };
        Ok(points.iter().map(cheap).collect())
    }
}

/// A system whose boundaries in a plane of two of its parameters the tracer follows: the
/// study's parameter set (every [`BoundaryKind`]) or an assembled [`Model`] (the simulated
/// boundary; the others are closed forms of the study's cubic).
pub trait PlaneSystem: Copy + Send + Sync {
    /// A parameter of the plane.
    type Axis: Copy + PartialEq + Serialize + std::fmt::Display + Send + Sync;
    /// The system with each (parameter, value) of `changes` set at once: a model's values
    /// checked and a term's rule judged on the new values together ([`Model::with_all`]); a
    /// parameter set's unchecked (checked by [`PlaneSystem::check`]).
    fn set(&self, changes: &[(Self::Axis, f64)]) -> Result<Self>;
    /// Checks that the system is inside its domain.
    fn check(&self) -> Result<()>;
    /// Refuses a boundary that is not defined for this system, naming it and why.
    fn defines(&self, kind: BoundaryKind) -> Result<()>;
    /// Whether `kind`'s verdict holds at each of `sets`.
    fn holds(kind: BoundaryKind, sets: &[Self], opts: &BurstOptions) -> Result<Vec<bool>>;
    /// Values of the simulated verdict narrowed together: a batch's lanes, or 1 where each
    /// value runs alone.
    fn simulated_lanes(opts: &BurstOptions) -> usize;
    /// Whether the simulated boundary starts near the predicted one's starts (else from a scan
    /// of the box's edges).
    const PREDICTS: bool;
}

impl PlaneSystem for Params {
    type Axis = Param;
    fn set(&self, changes: &[(Param, f64)]) -> Result<Params> {
        Ok(changes.iter().fold(*self, |p, &(q, v)| p.with(q, v)))
    }
    fn check(&self) -> Result<()> {
        self.validate().map(drop)
    }
    fn defines(&self, _kind: BoundaryKind) -> Result<()> {
        Ok(())
    }
    fn holds(kind: BoundaryKind, sets: &[Params], opts: &BurstOptions) -> Result<Vec<bool>> {
        kind.holds(sets, opts)
    }
    fn simulated_lanes(opts: &BurstOptions) -> usize {
        match opts.tol.method {
            Method::Taylor => crate::batch::LANES,
            _ => 1,
        }
    }
    const PREDICTS: bool = true;
}

impl PlaneSystem for Model {
    type Axis = ModelParam;
    fn set(&self, changes: &[(ModelParam, f64)]) -> Result<Model> {
        self.with_all(changes)
    }
    fn check(&self) -> Result<()> {
        Model::check(self)
    }
    fn defines(&self, kind: BoundaryKind) -> Result<()> {
        match kind {
            BoundaryKind::Simulated => Ok(()),
            _ => Err(Error::InvalidInput {
                what: "boundary kind",
                text: kind.name().into(),
                reason: "a closed form of the study's cubic, not defined for a model with terms \
                         (its simulated boundary is)"
                    .into(),
            }),
        }
    }
    /// Each set simulated on its own (in parallel) and classified against its own equilibrium
    /// curve ([`super::verdict_model`]).
    fn holds(kind: BoundaryKind, sets: &[Model], opts: &BurstOptions) -> Result<Vec<bool>> {
        match sets.first() {
            Some(m) => m.defines(kind)?,
            None => return Ok(Vec::new()),
        }
        sets.par_iter()
            .map(|m| super::verdict_model(m, opts).map(|(c, _, _)| c.bursting))
            .collect()
    }
    fn simulated_lanes(_opts: &BurstOptions) -> usize {
        1
    }
    const PREDICTS: bool = false;
}

impl std::str::FromStr for BoundaryKind {
    type Err = Error;
    fn from_str(s: &str) -> Result<BoundaryKind> {
        BoundaryKind::ALL
            .into_iter()
            .find(|k| k.name() == s.trim())
            .ok_or_else(|| Error::InvalidInput {
                what: "boundary kind",
                text: s.to_string(),
                reason: format!(
                    "expected one of {}",
                    BoundaryKind::ALL.map(BoundaryKind::name).join(", ")
                ),
            })
    }
}

/// Step options of the tracer (in units of the box: each axis is 1 wide in its scale).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PlaneOptions {
    /// Largest step (default 0.02: at least 50 points across the box).
    pub step_max: f64,
    /// Least step (default 1e-4; never below four brackets' widths).
    pub step_min: f64,
    /// Most points per curve (default 2000).
    pub max_points: usize,
    /// Largest turn of the heading in one step, in radians (default [`MAX_TURN`]).
    pub max_turn: f64,
    /// Angles of the first round on each half circle (default [`ROUND`]).
    pub round: usize,
    /// Values per edge of the box in the search for starts (default [`EDGE_SAMPLES`]).
    pub edge_samples: usize,
}

impl Default for PlaneOptions {
    fn default() -> Self {
        PlaneOptions {
            step_max: 0.02,
            step_min: 1e-4,
            max_points: 2000,
            max_turn: MAX_TURN,
            round: ROUND,
            edge_samples: EDGE_SAMPLES,
        }
    }
}

impl PlaneOptions {
    /// The defaults with the largest step `step` (the least step no larger than it).
    pub fn with_step(step: f64) -> PlaneOptions {
        let d = PlaneOptions::default();
        PlaneOptions {
            step_max: step,
            step_min: d.step_min.min(step),
            ..d
        }
    }

    /// Checks 0 < step_min ≤ step_max ≤ 0.25, max_points ≥ 2, 0 < max_turn ≤ π, round ≥ 3 and
    /// edge_samples ≥ 2.
    pub fn validate(&self) -> Result<()> {
        let bad = |name, value, reason| {
            Err(Error::InvalidOption {
                name,
                value,
                reason,
            })
        };
        if !(self.step_max > 0.0 && self.step_max <= 0.25) {
            return bad("step_max", self.step_max, "must be in (0, 0.25]");
        }
        if !(self.step_min > 0.0 && self.step_min <= self.step_max) {
            return bad("step_min", self.step_min, "must be in (0, step_max]");
        }
        if self.max_points < 2 {
            return bad("max_points", self.max_points as f64, "must be at least 2");
        }
        if !(self.max_turn > 0.0 && self.max_turn <= PI) {
            return bad("max_turn", self.max_turn, "must be in (0, π]");
        }
        if self.round < 3 {
            return bad("round", self.round as f64, "must be at least 3");
        }
        if self.edge_samples < 2 {
            return bad(
                "edge_samples",
                self.edge_samples as f64,
                "must be at least 2",
            );
        }
        Ok(())
    }
}

/// A point of a boundary curve.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PlanePoint {
    /// (λ₁, λ₂): the midpoint of the bracket.
    pub params: [f64; 2],
    /// The bracket's end outside the region (where the verdict does not hold).
    pub outside: [f64; 2],
    /// Its end inside.
    pub inside: [f64; 2],
}

/// Why a curve ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum PlaneEnd {
    /// It left the box: the last point is on its edge.
    Edge,
    /// [`PlaneOptions::max_points`] points.
    MaxPoints,
    /// At the least step the half circle's ends were on one side (a feature narrower than the
    /// least step, or the verdict's noise).
    StepTooSmall,
}

/// A boundary curve, followed from one end on the box's edge.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PlaneCurve<A = Param> {
    /// Which boundary.
    pub kind: BoundaryKind,
    /// The two parameters.
    pub params: [A; 2],
    /// The points in order, the first on the box's edge.
    pub points: Vec<PlanePoint>,
    /// Why it ended.
    pub end: PlaneEnd,
    /// Verdicts evaluated (simulations for the simulated boundary).
    pub evaluations: usize,
}

/// A point of a boundary curve as a row of its output file.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, crate::output::Record)]
pub struct PlaneRow {
    /// Index of the curve.
    pub curve: usize,
    /// Its kind ([`BoundaryKind::name`]).
    pub kind: &'static str,
    /// λ₁.
    pub param1: f64,
    /// λ₂.
    pub param2: f64,
    /// λ₁ at the bracket's end outside the region.
    pub outside1: f64,
    /// λ₂ there.
    pub outside2: f64,
    /// λ₁ at its end inside.
    pub inside1: f64,
    /// λ₂ there.
    pub inside2: f64,
}

impl PlaneRow {
    /// The rows of curve number `i`.
    pub fn of<A>(i: usize, c: &PlaneCurve<A>) -> impl Iterator<Item = PlaneRow> + '_ {
        c.points.iter().map(move |q| PlaneRow {
            curve: i,
            kind: c.kind.name(),
            param1: q.params[0],
            param2: q.params[1],
            outside1: q.outside[0],
            outside2: q.outside[1],
            inside1: q.inside[0],
            inside2: q.inside[1],
        })
    }
}

/// Where a curve starts: its point on an edge, the inward heading.
#[derive(Clone, Copy, Debug)]
struct Start {
    point: PlanePoint,
    v: [f64; 2],
    heading: f64,
}

/// The plane: the base set, the two parameters, the box in u, and one boundary's verdict.
struct Plane<'a, S: PlaneSystem> {
    base: S,
    params: [S::Axis; 2],
    scales: [Scale; 2],
    ranges: [(f64, f64); 2],
    /// u at the box's low edge, and its width, per parameter.
    low: [f64; 2],
    width: [f64; 2],
    /// The boundary's kind (its label), its verdict and relative tolerance.
    kind: BoundaryKind,
    verdict: &'a dyn Fn(&[S]) -> Result<Vec<bool>>,
    tol: f64,
    /// Values a round (evaluated together).
    lanes: usize,
    evaluations: usize,
}

impl<'a, S: PlaneSystem> Plane<'a, S> {
    /// The plane of `params` over `box2` for a boundary of `kind` with `verdict`, evaluated
    /// `lanes` values a round.
    fn new(
        base: &S,
        params: [S::Axis; 2],
        box2: &Box2,
        kind: BoundaryKind,
        verdict: &'a dyn Fn(&[S]) -> Result<Vec<bool>>,
        lanes: usize,
    ) -> Plane<'a, S> {
        let u = |i: usize| {
            let (s, (lo, hi)) = (box2.scales[i], box2.ranges[i]);
            (s.to_u(lo), s.to_u(hi) - s.to_u(lo))
        };
        let [(l0, w0), (l1, w1)] = [u(0), u(1)];
        Plane {
            base: *base,
            params,
            scales: box2.scales,
            ranges: box2.ranges,
            low: [l0, l1],
            width: [w0, w1],
            kind,
            verdict,
            tol: kind.tolerance(),
            lanes,
            evaluations: 0,
        }
    }

    /// (λ₁, λ₂) at v, each coordinate clamped to the box (its edges exactly).
    fn lambda(&self, v: [f64; 2]) -> [f64; 2] {
        [0, 1].map(|i| match v[i] {
            c if c <= 0.0 => self.ranges[i].0,
            c if c >= 1.0 => self.ranges[i].1,
            c => self.scales[i].to_lambda(self.low[i] + c * self.width[i]),
        })
    }

    fn set(&self, v: [f64; 2]) -> Result<S> {
        let l = self.lambda(v);
        self.base
            .set(&[(self.params[0], l[0]), (self.params[1], l[1])])
    }

    fn holds(&mut self, vs: &[[f64; 2]]) -> Result<Vec<bool>> {
        self.evaluations += vs.len();
        let sets: Vec<S> = vs.iter().map(|&v| self.set(v)).collect::<Result<_>>()?;
        (self.verdict)(&sets)
    }

    /// Whether a and b differ by at most `factor` tolerances in each parameter (relative).
    fn close(&self, a: [f64; 2], b: [f64; 2], factor: f64) -> bool {
        let (la, lb) = (self.lambda(a), self.lambda(b));
        let tol = factor * self.tol;
        (0..2).all(|i| (la[i] - lb[i]).abs() <= tol * la[i].abs().max(lb[i].abs()))
    }

    /// The least step: four brackets' widths in v, or `step_min`.
    fn least_step(&self, opts: &PlaneOptions) -> f64 {
        let bracket = (0..2)
            .map(|i| {
                let tol = self.tol;
                match self.scales[i] {
                    Scale::Log => tol / self.width[i],
                    Scale::Linear => {
                        let hi = self.low[i] + self.width[i];
                        tol * self.low[i].abs().max(hi.abs()) / self.width[i]
                    }
                }
            })
            .fold(0.0, f64::max);
        opts.step_min.max(4.0 * bracket).min(opts.step_max)
    }

    /// The switch on the path s ↦ `path(s)` between `s_out` (outside) and `s_in` (inside),
    /// narrowed to the tolerance: (outside end, inside end).
    fn narrow(
        &mut self,
        path: &impl Fn(f64) -> [f64; 2],
        (s_out, s_in): (f64, f64),
    ) -> Result<(f64, f64)> {
        let s = |t: f64| s_out + t * (s_in - s_out);
        let lanes = self.lanes;
        let (a, b) = {
            let close = |a: f64, b: f64| self.close(path(s(a)), path(s(b)), 1.0);
            let (mut evaluations, plane) = (0, &*self);
            let bracket = multisect((0.0, 1.0), lanes, close, |ts| {
                evaluations += ts.len();
                let sets: Vec<S> = ts
                    .iter()
                    .map(|&t| plane.set(path(s(t))))
                    .collect::<Result<_>>()?;
                Ok::<_, Error>((plane.verdict)(&sets)?.iter().map(|h| !h).collect())
            })?;
            self.evaluations += evaluations;
            bracket
        };
        Ok((s(a), s(b)))
    }

    fn point(&self, path: &impl Fn(f64) -> [f64; 2], (s_out, s_in): (f64, f64)) -> PlanePoint {
        PlanePoint {
            params: self.lambda(path(0.5 * (s_out + s_in))),
            outside: self.lambda(path(s_out)),
            inside: self.lambda(path(s_in)),
        }
    }

    /// The switches along edge `e` (0: v₂ = 0, 1: v₁ = 1, 2: v₂ = 1, 3: v₁ = 0) at `n` + 1
    /// values from s = `lo` to `hi`, narrowed: the starts there.
    fn edge_starts(&mut self, e: usize, (lo, hi): (f64, f64), n: usize) -> Result<Vec<Start>> {
        let path = move |s: f64| match e {
            0 => [s, 0.0],
            1 => [1.0, s],
            2 => [s, 1.0],
            _ => [0.0, s],
        };
        let heading = [FRAC_PI_2, PI, -FRAC_PI_2, 0.0][e];
        let ss: Vec<f64> = (0..=n)
            .map(|j| lo + (hi - lo) * j as f64 / n as f64)
            .collect();
        let vs: Vec<[f64; 2]> = ss.iter().map(|&s| path(s)).collect();
        let inside = self.holds(&vs)?;
        let mut starts = Vec::new();
        for j in 1..ss.len() {
            if inside[j] != inside[j - 1] {
                let pair = if inside[j] {
                    (ss[j - 1], ss[j])
                } else {
                    (ss[j], ss[j - 1])
                };
                let bracket = self.narrow(&path, pair)?;
                let mid = 0.5 * (bracket.0 + bracket.1);
                starts.push(Start {
                    point: self.point(&path, bracket),
                    v: path(mid),
                    heading,
                });
            }
        }
        Ok(starts)
    }

    /// The starts on all four edges.
    fn starts(&mut self, opts: &PlaneOptions) -> Result<Vec<Start>> {
        let mut all = Vec::new();
        for e in 0..4 {
            all.extend(self.edge_starts(e, (0.0, 1.0), opts.edge_samples)?);
        }
        Ok(all)
    }

    /// A start near `near` (a start of another boundary) on the same edge: the switch nearest it
    /// in a window of `lanes` values around it, widened until it holds one.
    fn start_near(&mut self, near: &Start) -> Result<Option<Start>> {
        let e = edge_of(near.heading);
        let at = if e.is_multiple_of(2) {
            near.v[0]
        } else {
            near.v[1]
        };
        let n = self.lanes.max(2) - 1;
        let mut w = 0.05;
        loop {
            let window = ((at - w).max(0.0), (at + w).min(1.0));
            let found = self.edge_starts(e, window, n)?;
            let nearest = found.into_iter().min_by(|a, b| {
                let d = |s: &Start| (s.v[0] - near.v[0]).hypot(s.v[1] - near.v[1]);
                d(a).total_cmp(&d(b))
            });
            if nearest.is_some() || window == (0.0, 1.0) {
                return Ok(nearest);
            }
            w *= 2.0;
        }
    }

    /// Follows the curve from `start` (see the module docs).
    fn follow(&mut self, start: &Start, opts: &PlaneOptions) -> Result<PlaneCurve<S::Axis>> {
        let least = self.least_step(opts);
        let evaluations = self.evaluations;
        let mut points = vec![start.point];
        let (mut v, mut heading, mut h) = (start.v, start.heading, opts.step_max);
        // +1 when the region is on the left of the heading, −1 on the right (unknown at first)
        let mut side: Option<f64> = None;
        let end = loop {
            if points.len() >= opts.max_points {
                break PlaneEnd::MaxPoints;
            }
            let circle = move |phi: f64| [v[0] + h * phi.cos(), v[1] + h * phi.sin()];
            // the round: from the right end (θ − π/2) to the left end (θ + π/2)
            let m = opts.round;
            let phis: Vec<f64> = (0..m)
                .map(|k| heading - FRAC_PI_2 + PI * k as f64 / (m - 1) as f64)
                .collect();
            let vs: Vec<[f64; 2]> = phis.iter().map(|&phi| circle(phi)).collect();
            let inside = self.holds(&vs)?;
            let (right, left) = (inside[0], inside[m - 1]);
            let sides_ok = right != left && side.is_none_or(|s| left == (s > 0.0));
            if !sides_ok {
                if h <= least {
                    break PlaneEnd::StepTooSmall;
                }
                h = (0.5 * h).max(least);
                continue;
            }
            // from the outside end to the inside end; the first switch
            let order: Vec<usize> = if left {
                (0..m).collect()
            } else {
                (0..m).rev().collect()
            };
            let ks: Vec<f64> = (0..m).map(|k| k as f64).collect();
            let outside: Vec<bool> = order.iter().map(|&k| !inside[k]).collect();
            let Some((a, b)) = first_switch(&ks, &outside) else {
                unreachable!("the ends are on either side")
            };
            let (ka, kb) = (order[a as usize], order[b as usize]);
            let path = |phi: f64| circle(phi);
            let bracket = self.narrow(&path, (phis[ka], phis[kb]))?;
            let phi = 0.5 * (bracket.0 + bracket.1);
            let turn = (phi - heading + PI).rem_euclid(2.0 * PI) - PI;
            if side.is_some() && turn.abs() > opts.max_turn && h > least {
                h = (0.5 * h).max(least);
                continue;
            }
            let q = circle(phi);
            points.push(self.point(&path, bracket));
            side = Some(if left { 1.0 } else { -1.0 });
            let outside_box = q.iter().any(|&c| !(-1e-12..=1.0 + 1e-12).contains(&c));
            if outside_box {
                break PlaneEnd::Edge;
            }
            (v, heading) = (q, phi);
            if turn.abs() < opts.max_turn / 3.0 {
                h = (1.5 * h).min(opts.step_max);
            }
        };
        Ok(PlaneCurve {
            kind: self.kind,
            params: self.params,
            points,
            end,
            evaluations: self.evaluations - evaluations,
        })
    }

    /// Every curve from `starts`, each once.
    fn follow_all(
        &mut self,
        mut starts: Vec<Start>,
        opts: &PlaneOptions,
    ) -> Result<Vec<PlaneCurve<S::Axis>>> {
        let mut curves = Vec::new();
        while !starts.is_empty() {
            let start = starts.remove(0);
            let curve = self.follow(&start, opts)?;
            if curve.end == PlaneEnd::Edge {
                let last = curve.points[curve.points.len() - 1].params;
                let v_last = self.v_of(last);
                starts.retain(|s| !self.close(s.v, v_last, 4.0));
            }
            curves.push(curve);
        }
        Ok(curves)
    }

    /// v at (λ₁, λ₂).
    fn v_of(&self, l: [f64; 2]) -> [f64; 2] {
        [0, 1].map(|i| (self.scales[i].to_u(l[i]) - self.low[i]) / self.width[i])
    }
}

/// The edge a start with this inward heading is on.
fn edge_of(heading: f64) -> usize {
    [FRAC_PI_2, PI, -FRAC_PI_2, 0.0]
        .iter()
        .position(|&h| h == heading)
        .unwrap_or(0)
}

/// The boundaries `kinds` in the plane of `params` over `box2`, the other parameters as in
/// `base`: every curve that meets the box's edge, each followed once (see the module docs).
/// The simulated boundary is started from the predicted one's starts, and its verdicts run as
/// batches with Taylor's method.
///
/// ```
/// use hdgear::burst::{BoundaryKind, BurstOptions, PlaneOptions, plane_boundaries};
/// use hdgear::params::{Param, Params};
/// use hdgear::periodic::{Box2, Scale};
/// // the predicted bursting boundary in (omega, gamma) at the study's other parameters
/// let box2 = Box2 { ranges: [(1e-4, 0.05), (0.3, 3.0)], scales: [Scale::Log; 2] };
/// let curves = plane_boundaries(
///     &Params::default(), [Param::Omega, Param::Gamma], &box2, &[BoundaryKind::Predicted],
///     &PlaneOptions::default(), &BurstOptions::default(),
/// ).unwrap();
/// assert_eq!(curves.len(), 1);
/// // on it, the forcing rate is at its threshold: the closed-form omega boundary
/// for q in &curves[0].points {
///     let p = Params { omega: q.params[0], gamma: q.params[1], ..Params::default() };
///     let w = hdgear::fast::predict(&p).omega_boundary;
///     assert!((q.params[0] / w - 1.0).abs() < 1e-6);
/// }
/// ```
pub fn plane_boundaries<S: PlaneSystem>(
    base: &S,
    params: [S::Axis; 2],
    box2: &Box2,
    kinds: &[BoundaryKind],
    opts: &PlaneOptions,
    burst: &BurstOptions,
) -> Result<Vec<PlaneCurve<S::Axis>>> {
    if params[0] == params[1] {
        return Err(Error::InvalidInput {
            what: "parameter plane",
            text: params[0].to_string(),
            reason: "the two parameters must differ".into(),
        });
    }
    box2.validate()?;
    opts.validate()?;
    for &kind in kinds {
        base.defines(kind)?;
    }
    // every set of the box is valid when its corners are (each parameter's domain is an
    // interval; a model's rules between parameters are checked at each point as well)
    for (a, b) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
        let [(l0, h0), (l1, h1)] = box2.ranges;
        let corner = [(params[0], [l0, h0][a]), (params[1], [l1, h1][b])];
        base.set(&corner)?.check()?;
    }
    let verdicts = BoundaryKind::ALL.map(|kind| move |sets: &[S]| S::holds(kind, sets, burst));
    let plane = |kind: BoundaryKind| {
        let lanes = match kind {
            BoundaryKind::Simulated => S::simulated_lanes(burst),
            _ => 1,
        };
        let i = BoundaryKind::ALL
            .iter()
            .position(|&k| k == kind)
            .unwrap_or(0);
        Plane::new(base, params, box2, kind, &verdicts[i], lanes)
    };
    let mut curves = Vec::new();
    for &kind in kinds {
        let mut pl = plane(kind);
        let starts = if kind == BoundaryKind::Simulated && S::PREDICTS {
            let predicted = plane(BoundaryKind::Predicted).starts(opts)?;
            let mut starts = Vec::new();
            for s in &predicted {
                starts.extend(pl.start_near(s)?);
            }
            starts
        } else {
            pl.starts(opts)?
        };
        curves.extend(pl.follow_all(starts, opts)?);
    }
    Ok(curves)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The curves of a synthetic region in the unit square (the box (ω, γ) ∈ [1, 2]², linear, so
    /// that v = λ − 1), followed as the predicted boundary is: from the edge scans, one at a time.
    fn trace(region: impl Fn(f64, f64) -> bool) -> Vec<PlaneCurve> {
        let verdict = |sets: &[Params]| -> Result<Vec<bool>> {
            Ok(sets
                .iter()
                .map(|p| region(p.omega - 1.0, p.gamma - 1.0))
                .collect())
        };
        let box2 = Box2 {
            ranges: [(1.0, 2.0); 2],
            scales: [Scale::Linear; 2],
        };
        let mut plane = Plane::new(
            &Params::default(),
            [Param::Omega, Param::Gamma],
            &box2,
            BoundaryKind::Predicted,
            &verdict,
            1,
        );
        let starts = plane.starts(&PlaneOptions::default()).unwrap();
        plane.follow_all(starts, &PlaneOptions::default()).unwrap()
    }

    /// The points' v.
    fn vs(c: &PlaneCurve) -> Vec<[f64; 2]> {
        c.points
            .iter()
            .map(|q| [q.params[0] - 1.0, q.params[1] - 1.0])
            .collect()
    }

    /// A circle's arc across the box: one curve from edge to edge, every point on the circle to
    /// the tolerance (relative to λ ∈ [1, 2]: 2e-9 in v), its steps at most `step_max`, both
    /// ends on the edges; followed once although it has a start at each end.
    #[test]
    fn a_circle_is_followed_once_to_the_tolerance() {
        let (cx, cy, r) = (0.1, -0.2, 0.8);
        let curves = trace(|x, y| (x - cx).hypot(y - cy) < r);
        assert_eq!(curves.len(), 1);
        let c = &curves[0];
        assert_eq!(c.end, PlaneEnd::Edge);
        let v = vs(c);
        for q in &v {
            let d = (q[0] - cx).hypot(q[1] - cy) - r;
            assert!(d.abs() < 4e-9, "{q:?}: {d}");
        }
        for w in v.windows(2) {
            let step = (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
            assert!(step <= PlaneOptions::default().step_max * (1.0 + 1e-9));
        }
        let on_edge = |q: &[f64; 2]| q.iter().any(|&c| c == 0.0 || c == 1.0);
        assert!(on_edge(&v[0]) && on_edge(&v[v.len() - 1]));
        // an arc of length r·(angle between the ends) took at least that over step_max points
        let angle = |q: &[f64; 2]| (q[1] - cy).atan2(q[0] - cx);
        let length = r * (angle(&v[v.len() - 1]) - angle(&v[0])).abs();
        assert!(v.len() as f64 >= length / PlaneOptions::default().step_max);
    }

    /// A corner (the region x < 0.6 and y < 0.7, like the fold set closed by the cusp line): the
    /// curve turns there and passes within a least step of it.
    #[test]
    fn a_corner_is_turned() {
        let curves = trace(|x, y| x < 0.6 && y < 0.7);
        assert_eq!(curves.len(), 1);
        let v = vs(&curves[0]);
        let nearest = v
            .iter()
            .map(|q| (q[0] - 0.6).hypot(q[1] - 0.7))
            .fold(f64::INFINITY, f64::min);
        assert!(nearest < 1e-3, "{nearest}");
        for q in &v {
            let off = (q[0] - 0.6).abs().min((q[1] - 0.7).abs());
            assert!(off < 4e-9, "{q:?}");
        }
    }

    /// A tongue of width w rising from the line y = 0.5 to y = 0.9 is followed up to its tip
    /// and back down when w is above the round's resolution (π·step_max/15 = 0.0042), wherever
    /// it stands against the steps (twenty places). Measured below it: w = 0.004 is followed at
    /// 19 of the 20 places, 0.002 at 8, 0.0005 at 3, 0.0002 at none.
    #[test]
    fn a_narrow_tongue_is_followed_not_stepped_over() {
        for w in [0.005, 0.01, 0.05] {
            for k in 0..20 {
                let at = 0.3 + 0.4 * f64::from(k) / 19.0;
                let curves = trace(|x, y| y < 0.5 || ((x - at).abs() < 0.5 * w && y < 0.9));
                assert_eq!(curves.len(), 1, "{w}");
                let v = vs(&curves[0]);
                let top = v.iter().map(|q| q[1]).fold(0.0, f64::max);
                assert!((top - 0.9).abs() < 1e-8, "{w} at {at}: top {top}");
            }
        }
    }
}
