//! The quasi-static branches x±(a) of a model with friction or hysteresis: what replaces the
//! equilibrium curve when the fast subsystem has memory.
//!
//! With a frozen, a model with sticking friction rests anywhere in a band of twists, and one with
//! a hysteretic state has a line of equilibria, one per state: the equilibria are no longer a
//! curve. A slow load moves the drive along a *branch* instead: creeping with x' → 0⁺ while the
//! load rises (loading) and x' → 0⁻ while it falls (unloading). On a branch the creep torque
//! T_s(x, z) = Σ T(x, 0·s, z) (the sign of x' fixed at s on every switching term) equals the load
//! μ + δa, and each memory state follows the twist at dz/dx = ∂z'/∂x' at x' = 0 on that side (its
//! rate vanishes at rest and is linear in x' there). So
//!
//! dx/da = δ / K_t,  K_t = ∂T_s/∂x + Σ ∂T_s/∂z · dz/dx,
//!
//! K_t the branch's tangent stiffness. Where K_t approaches 0⁺ the branch is steep (a spiking
//! area, the study's mechanism); where it reaches 0 the branch ends in a fold (a jump). At a
//! reversal of the load the motion rests until the creep torque of the other side meets the load:
//! with sticking friction that takes the load across the band (the rest at a turning point), with
//! hysteresis alone it is immediate.

use super::{MAX_STATES, Model};
use crate::error::{Error, Result};
use serde::Serialize;

/// Steps per unit of a in the branches' RK4 integration (the branch is as smooth as the terms;
/// its error, of order h⁴, is checked in the tests against closed forms).
const STEPS_PER_UNIT: f64 = 4000.0;
/// The most cycles of the load the branches are followed through: the loop of a hysteretic state
/// settles geometrically, and the cycles stop once x at a = 1 changes by less than
/// [`CLOSED`]·max(1, |x|) over one (the closure reached is reported).
const MAX_CYCLES: usize = 200;
/// The relative change of the loop's state per cycle at which it counts as closed: a few ulps of
/// the RK4 branches' own balance error.
const CLOSED: f64 = 1e-12;

/// A point of a branch.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LoopPoint {
    /// The slow variable.
    pub a: f64,
    /// The twist.
    pub x: f64,
    /// The internal states, in state order (0 past the model's).
    pub z: [f64; MAX_STATES],
    /// The tangent stiffness K_t there.
    pub stiffness: f64,
}

/// One quasi-static branch, followed from where the motion leaves rest after the reversal.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LoopBranch {
    /// sgn x' along it: +1 loading (a rising), −1 unloading.
    pub side: f64,
    /// a at the reversal before it (the load's turning point).
    pub reversal: f64,
    /// a where the motion leaves rest; `None` when the load's range never takes the creep
    /// torque across the band (the drive stays at rest).
    pub breakaway: Option<f64>,
    /// Its points, from the breakaway to the end of the load's range or the fold.
    pub points: Vec<LoopPoint>,
    /// a where K_t reaches 0: the branch ends in a fold (a jump), if it does.
    pub fold: Option<f64>,
    /// The smallest tangent stiffness on the branch, with its a (the steepest point).
    pub min_stiffness: Option<(f64, f64)>,
}

impl LoopBranch {
    /// Where the branch predicts bursts to start: its steepest point (the smallest tangent
    /// stiffness: a spiking area where it nears 0⁺) and its breakaway (the slip after the rest
    /// that follows a reversal), in a.
    pub fn predicted_onsets(&self) -> Vec<f64> {
        self.min_stiffness
            .map(|(a, _)| a)
            .into_iter()
            .chain(self.breakaway)
            .collect()
    }

    /// The prediction ([`LoopBranch::predicted_onsets`]) nearest to `a`, if there is one.
    pub fn nearest_prediction(&self, a: f64) -> Option<f64> {
        self.predicted_onsets()
            .into_iter()
            .min_by(|u, v| (u - a).abs().total_cmp(&(v - a).abs()))
    }
}

/// The loading and unloading branches of a model's steady loop under a ∈ [−1, 1].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Branches {
    /// Loading (a from −1 to 1).
    pub loading: LoopBranch,
    /// Unloading (a from 1 to −1).
    pub unloading: LoopBranch,
    /// The change of x at a = 1 over the last cycle: how closed the loop is.
    pub closure: f64,
}

impl Branches {
    /// The branch a response under the load μ + δ sin ωτ follows at time τ: the loading one
    /// while the load rises, else the unloading one. A burst starts on the branch at its pulse,
    /// `branches.at(burst.t_peak, omega)`.
    pub fn at(&self, tau: f64, omega: f64) -> &LoopBranch {
        if (omega * tau).cos() > 0.0 {
            &self.loading
        } else {
            &self.unloading
        }
    }
}

impl Model {
    /// The creep torque T_s(x, z), the tangent stiffness K_t and dz/dx on side `s` at (x, z).
    fn creep(&self, s: f64, x: f64, z: &[f64; MAX_STATES]) -> (f64, f64, [f64; MAX_STATES]) {
        let piece = self.directed(s, [0.0; MAX_STATES]);
        let (mut torque, mut stiffness) = (0.0, 0.0);
        let mut dz = [0.0; MAX_STATES];
        for (t, at) in piece.slots() {
            let zt = at.map_or(0.0, |i| z[i - 2]);
            torque += t.torque(x, 0.0, zt);
            let [tx, _, tz] = t.gradient(x, 0.0, zt);
            stiffness += tx;
            if let Some(i) = at {
                dz[i - 2] = t.rate_gradient(x, 0.0, zt)[1];
                stiffness += tz * dz[i - 2];
            }
        }
        (torque, stiffness, dz)
    }

    /// The quasi-static branches of the model's steady loop ([`Branches`]): from rest at a = 0
    /// (the virgin state), up to a = 1, then down to −1 and up to 1 until the loop closes (at
    /// most 200 times), the last down and up reported. Refused for a model with a load that
    /// acts whatever the motion, a delay or a state that moves at rest: they have no
    /// quasi-static branch.
    ///
    /// ```
    /// use hdgear::{Params, model::{Model, terms::AnyTerm}};
    /// let p = Params { gamma: 2.0, ..Params::default() };
    /// let m = Model::study(&p).with_term(AnyTerm::new("coulomb", &[0.5, 0.5, 0.1, 0.0]).unwrap()).unwrap();
    /// let b = m.branches().unwrap();
    /// // after the load's top the drive rests until the load has fallen by 2 f_s
    /// let fall = 1.0 - b.unloading.breakaway.unwrap();
    /// assert!((fall * p.delta - 1.0).abs() < 1e-9);
    /// ```
    pub fn branches(&self) -> Result<Branches> {
        self.check()?;
        let refuse = |reason: &str| Error::InvalidInput {
            what: "model",
            text: self.equation(),
            reason: reason.into(),
        };
        // a state that moves at a held twist (probed away from 0, where every rate may vanish)
        let moving = self.moves_at_rest(&[0.3, 0.0, 0.2, 0.2][..self.dim()]);
        if moving || self.terms().any(|t| t.is_load() || t.delay().is_some()) {
            return Err(refuse(
                "its quasi-static branches need every torque to follow the motion and every state to rest with it (no load term, delay or moving state)",
            ));
        }
        let x0 = self.stable_equilibrium(0.0)?;
        let mut state = (x0, self.rest_states(x0));
        let mut up = self.sweep(1.0, 0.0, 1.0, state);
        let mut down = up.clone();
        let mut closure = f64::NAN;
        for _ in 0..MAX_CYCLES {
            let (a, top) = end_of(&up, state);
            down = self.sweep(-1.0, a, -1.0, top);
            let (a, bottom) = end_of(&down, top);
            up = self.sweep(1.0, a, 1.0, bottom);
            state = end_of(&up, bottom).1;
            closure = (state.0 - top.0).abs();
            if closure <= CLOSED * state.0.abs().max(1.0) {
                break;
            }
        }
        Ok(Branches {
            loading: up,
            unloading: down,
            closure,
        })
    }

    /// The branch on side `s` from the state `(x, z)` the reversal at `from` left, to `to`.
    fn sweep(&self, s: f64, from: f64, to: f64, (x, z): (f64, [f64; MAX_STATES])) -> LoopBranch {
        let [mu, delta, _] = self.forcing();
        let (torque, ..) = self.creep(s, x, &z);
        // the rest lasts until the load meets this side's creep torque
        let start = ((torque - mu) / delta - from) * s;
        let mut branch = LoopBranch {
            side: s,
            reversal: from,
            breakaway: None,
            points: Vec::new(),
            fold: None,
            min_stiffness: None,
        };
        let span = (to - from) * s;
        if start > span {
            return branch;
        }
        let a0 = from + s * start.max(0.0);
        branch.breakaway = Some(a0);
        let n = ((to - a0).abs() * STEPS_PER_UNIT).ceil().max(1.0) as usize;
        let h = (to - a0) / n as f64;
        // y = (x, z): dy/da = (δ/K_t)·(1, dz/dx), undefined at a fold (K_t ≤ 0)
        let mut field = |_: f64, y: &[f64], dy: &mut [f64]| {
            let z = std::array::from_fn(|j| y[1 + j]);
            let (_, k, dz) = self.creep(s, y[0], &z);
            for (j, d) in dy.iter_mut().enumerate() {
                *d = delta / k * if j == 0 { 1.0 } else { dz[j - 1] };
            }
            k > 0.0
        };
        let mut scratch = [0.0; 5 * (1 + MAX_STATES)];
        let mut y = [0.0; 1 + MAX_STATES];
        y[0] = x;
        y[1..].copy_from_slice(&z);
        let push = |a: f64, y: &[f64; 1 + MAX_STATES], b: &mut LoopBranch| {
            let z = std::array::from_fn(|j| y[1 + j]);
            let k = self.creep(s, y[0], &z).1;
            b.points.push(LoopPoint {
                a,
                x: y[0],
                z,
                stiffness: k,
            });
        };
        push(a0, &y, &mut branch);
        for i in 0..n {
            let a = a0 + h * i as f64;
            if !crate::integrate::rk4_step(&mut field, a, h, &mut y, &mut scratch) {
                branch.fold = Some(a);
                break;
            }
            push(a + h, &y, &mut branch);
        }
        branch.min_stiffness = steepest(&branch.points, delta);
        branch
    }
}

/// The smallest tangent stiffness on a branch, with its a: the smallest of the points, refined
/// by the parabola in x through it and its two neighbours (exact where K_t is quadratic in x, as
/// the study's g'(x) is; near a steep point the points lie far apart in x, since dx/da = δ/K_t).
/// a at the vertex is where the segment's cubic Hermite x(a) (slopes δ/K_t) reaches it.
fn steepest(points: &[LoopPoint], delta: f64) -> Option<(f64, f64)> {
    let i =
        (0..points.len()).min_by(|&i, &j| points[i].stiffness.total_cmp(&points[j].stiffness))?;
    let sample = Some((points[i].a, points[i].stiffness));
    if i == 0 || i + 1 == points.len() {
        return sample;
    }
    let [p, q, r] = [&points[i - 1], &points[i], &points[i + 1]];
    let (d1, d2) = (
        (q.stiffness - p.stiffness) / (q.x - p.x),
        (r.stiffness - q.stiffness) / (r.x - q.x),
    );
    let curvature = (d2 - d1) / (r.x - p.x);
    if !(curvature > 0.0 && curvature.is_finite()) {
        return sample;
    }
    // K(x) = K_q + d1 (x − x_q) + c (x − x_q)(x − x_p): its vertex
    let xv = 0.5 * (q.x + p.x) - d1 / (2.0 * curvature);
    let (lo, hi) = if (xv - q.x) * (p.x - q.x) > 0.0 {
        (p, q)
    } else {
        (q, r)
    };
    if !((lo.x.min(hi.x)..=lo.x.max(hi.x)).contains(&xv)) {
        return sample;
    }
    let k = q.stiffness + d1 * (xv - q.x) + curvature * (xv - q.x) * (xv - p.x);
    // a where x = xv on the segment: x(a) as the cubic Hermite of its ends, whose slopes
    // dx/da = δ/K_t are the field's (fourth order in the step, as the points are)
    let (h, slope) = (hi.a - lo.a, |b: &LoopPoint| delta / b.stiffness);
    let x_at = |t: f64| {
        let (t2, t3) = (t * t, t * t * t);
        (2.0 * t3 - 3.0 * t2 + 1.0) * lo.x
            + (t3 - 2.0 * t2 + t) * h * slope(lo)
            + (-2.0 * t3 + 3.0 * t2) * hi.x
            + (t3 - t2) * h * slope(hi)
    };
    let rising = hi.x > lo.x;
    let (t0, t1) = crate::roots::bisect(0.0, 1.0, 60, crate::roots::at_resolution, |t| {
        (x_at(t) < xv) == rising
    });
    let a = lo.a + h * 0.5 * (t0 + t1);
    Some((a, k.min(q.stiffness)))
}

/// Where a sweep left the drive at the end of the load's range: its last point (at a fold, where
/// the quasi-static picture ends in a jump it does not follow, the fold's), or the state it
/// rested in throughout.
fn end_of(b: &LoopBranch, state: (f64, [f64; MAX_STATES])) -> (f64, (f64, [f64; MAX_STATES])) {
    let end = b.side;
    match b.points.last() {
        Some(p) => (end, (p.x, p.z)),
        None => (end, state),
    }
}
