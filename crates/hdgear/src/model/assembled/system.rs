//! The model as a first-order system ([`System`]): its right-hand side, Jacobian and Taylor
//! coefficients, each from the terms' own definitions.

use super::{MAX_STATES, MAX_TERMS, Model};
use crate::integrate::lanes::{Jet, Lanes};
use crate::integrate::{System, Workspace};
use crate::model::terms::{LANE_PARAMS, LaneRows};
use crate::model::terms::{MAX_ROWS, Scratch};

/// Component `at` of the state `y`, 0 where there is none.
#[inline(always)]
pub(super) fn state(y: &[f64], at: Option<usize>) -> f64 {
    at.and_then(|i| y.get(i).copied()).unwrap_or(0.0)
}

/// The model as a first-order system in (x, v = x', z…), N = [`Model::dim`] (the caller
/// chooses N by it), every method derived from the terms.
impl<const N: usize> System<N> for Model {
    #[inline]
    fn rhs(&self, t: f64, y: &[f64; N]) -> [f64; N] {
        debug_assert_eq!(N, self.dim());
        let mut f = [0.0; N];
        if !self.held {
            f[0] = y[1];
            f[1] = self.accel_at(self.forcing[2] * t, y);
        }
        for (term, at) in self.slots() {
            if let Some(i) = at {
                f[i] = term.rate(y[0], y[1], y[i]);
            }
        }
        f
    }
    fn jacobian(&self, _t: f64, y: &[f64; N]) -> Option<[[f64; N]; N]> {
        let mut j = [[0.0; N]; N];
        j[0][1] = 1.0;
        for (term, at) in self.slots() {
            let z = state(y, at);
            let [tx, tv, tz] = term.gradient(y[0], y[1], z);
            j[1][0] -= tx;
            j[1][1] -= tv;
            if let Some(i) = at {
                j[1][i] -= tz;
                let [rx, rv, rz] = term.rate_gradient(y[0], y[1], z);
                (j[i][0], j[i][1], j[i][i]) = (rx, rv, rz);
            }
        }
        if self.held {
            (j[0], j[1]) = ([0.0; N], [0.0; N]);
        }
        Some(j)
    }
    /// x_{k+1} = v_k/(k+1), v_{k+1} = (μ[k=0] + δ s_k − Σ_i T_{i,k})/(k+1),
    /// z_{k+1} = r_k/(k+1), each term's T_k and r_k by its own recurrences
    /// ([`crate::model::terms::Term::taylor`]), s_k sin ωt's in closed form.
    fn taylor(&self, t: f64, y: &[f64; N], order: usize, c: &mut [[f64; N]]) -> bool {
        self.taylor_in(t, y, order, c, &mut [Scratch::default(); MAX_TERMS])
    }
    fn taylor_in(
        &self,
        t: f64,
        y: &[f64; N],
        order: usize,
        c: &mut [[f64; N]],
        work: &mut Workspace,
    ) -> bool {
        self.taylor_rows(t, y, order, c, work);
        true
    }
    fn taylor_limits_steps(&self) -> bool {
        self.limits_steps()
    }
    /// `step` on the state's rows, shortened by the terms' own limits
    /// ([`crate::model::terms::Term::step_limit`]) on the terms' rows of the same pass. A term's
    /// truncation δ over a step of length h moves x' by at most δ·h: held to atol per time unit
    /// (atol itself on steps up to a time unit, the fast subsystem's scale), that is the
    /// absolute error the state's own rule aims at, so a smaller δ is negligible.
    // the trait's one pass (`System::taylor_step`)
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn taylor_step<F: FnOnce(&[[f64; N]]) -> f64>(
        &self,
        t: f64,
        y: &[f64; N],
        order: usize,
        c: &mut [[f64; N]],
        atol: f64,
        rows: &mut Workspace,
        step: F,
    ) -> Option<f64> {
        let n = self.taylor_rows(t, y, order, c, rows);
        Some(self.limit_step(rows, n, step(c), atol))
    }
}

impl Model {
    /// Rows 0..=order (capped at the integrator's) of the Taylor coefficients through (t, y)
    /// into `c`, the terms' own rows into `rows`; returns the order reached.
    #[inline(always)]
    fn taylor_rows<const N: usize>(
        &self,
        t: f64,
        y: &[f64; N],
        order: usize,
        c: &mut [[f64; N]],
        rows: &mut [Scratch; MAX_TERMS],
    ) -> usize {
        let mut pass = self.pass(t, y, order.min(c.len() - 1));
        for k in 0..=pass.n {
            self.pass_row::<N>(&mut pass, k, rows);
        }
        pass.finish(c)
    }

    /// The start of a Taylor pass through (t, y) to `order` (capped at the integrator's): the
    /// forcing's rows, the state's row 0 and the present terms with their states' slots. A pass
    /// runs order by order ([`Model::pass_row`]), so several passes may run interleaved
    /// ([`super::lanes`]).
    #[inline(always)]
    pub(super) fn pass<const N: usize>(&self, t: f64, y: &[f64; N], order: usize) -> Pass {
        let n = order.min(crate::integrate::taylor::MAX_ORDER);
        let mut f = [0.0; MAX_ROWS];
        self.forcing_rows(t, n, &mut f);
        // rows of x, v and the internal states (a state's absent rows stay 0)
        let mut s = [[0.0; MAX_ROWS]; 2 + MAX_STATES];
        for (row, &y) in s.iter_mut().zip(y) {
            row[0] = y;
        }
        // the present terms, each with its slot (its rows in `rows`) and its state's index
        let mut live = [(0, None); MAX_TERMS];
        let mut m = 0;
        for (i, (term, at)) in self.terms.iter().zip(self.state_slots()).enumerate() {
            if term.is_some() {
                live[m] = (i, at);
                m += 1;
            }
        }
        Pass { n, f, s, live, m }
    }

    /// The forcing's rows 0..=n through t into `f`: μ[k = 0] + δ·(sin ωt)_k.
    #[inline(always)]
    pub(super) fn forcing_rows(&self, t: f64, n: usize, f: &mut [f64; MAX_ROWS]) {
        let [mu, delta, omega] = self.forcing;
        crate::integrate::taylor::forcing_coefficients(delta, omega, t, n, f);
        f[0] += mu;
    }

    /// Row k of the acceleration and of the states' rates, the terms' rows kept in `rows`, and
    /// from them the state's row k + 1 (below the pass's order; at its order, the terms' rows
    /// only: the step limits read them).
    #[inline(always)]
    pub(super) fn pass_row<const N: usize>(
        &self,
        pass: &mut Pass,
        k: usize,
        rows: &mut [Scratch; MAX_TERMS],
    ) {
        use crate::integrate::taylor::INV;
        // the zero rows a stateless term reads as its z
        const NONE: [f64; MAX_ROWS] = [0.0; MAX_ROWS];
        let s = &mut pass.s;
        let mut acc = pass.f[k];
        let mut rates = [0.0; 2 + MAX_STATES];
        for &(i, at) in &pass.live[..pass.m] {
            let Some(term) = &self.terms[i] else { continue };
            let (x, v) = (&s[0], &s[1]);
            let z = at.map_or(&NONE, |j| &s[j]);
            if let Some(j) = at {
                rates[j] = term.rate_taylor(k, x, v, z, &mut rows[i]);
            }
            acc -= term.taylor(k, x, v, z, &mut rows[i]);
        }
        if k == pass.n {
            return;
        }
        // held: x and v keep their rows 1.. at 0
        let moving = if self.held { 0.0 } else { 1.0 };
        s[0][k + 1] = moving * s[1][k] * INV[k];
        s[1][k + 1] = moving * acc * INV[k];
        for i in 2..N {
            s[i][k + 1] = rates[i] * INV[k];
        }
    }

    /// Whether a term may shorten the step rule's step ([`Model::limit_step`]).
    #[inline(always)]
    pub(super) fn limits_steps(&self) -> bool {
        self.terms().any(|t| t.limits_steps())
    }

    /// The longest step, at most `h` (the step rule's on the state's rows), on which every
    /// term's own series is accurate ([`crate::model::terms::Term::step_limit`]), from the
    /// terms' rows of a pass to order `n` (the rule [`System::taylor_step`] states).
    #[inline(always)]
    pub(super) fn limit_step(&self, rows: &Workspace, n: usize, h: f64, atol: f64) -> f64 {
        self.limit_step_by(rows, n, h, negligible(atol, h))
    }

    /// [`Model::limit_step`] with the change of a term that counts as negligible given: what a
    /// system built on the model's terms in other units derives from its own tolerance (the
    /// two-inertia drive's twist, [`crate::physical::model::Physical`]).
    #[inline(always)]
    pub(crate) fn limit_step_by(&self, rows: &[Scratch], n: usize, h: f64, negligible: f64) -> f64 {
        self.terms
            .iter()
            .zip(rows.iter())
            .fold(h, |h, (term, r)| match term {
                Some(term) => term.step_limit(r, n, h, negligible),
                _ => h,
            })
    }

    /// Row k of the terms' torque Σ T(x, v) along x's and v's rows 0..=k, each term's own rows
    /// in `rows` by slot (called for k = 0, 1, 2, … in turn): for a model whose terms have no
    /// state of their own, whose torque a larger system uses (the two-inertia drive's twist).
    #[inline(always)]
    pub(crate) fn torque_row(&self, k: usize, x: &[f64], v: &[f64], rows: &mut [Scratch]) -> f64 {
        const NONE: [f64; MAX_ROWS] = [0.0; MAX_ROWS];
        let mut sum = 0.0;
        for (term, r) in self.terms.iter().zip(rows.iter_mut()) {
            if let Some(term) = term {
                sum += term.taylor(k, x, v, &NONE, r);
            }
        }
        sum
    }
}

impl Model {
    /// [`Model::limit_step`] on every lane at once: the terms in the slots `limiting`, with the
    /// lanes' parameters `params` and rows `rows` by slot ([`Term::step_limit_lanes`], each lane
    /// its scalar limit to ~1e-9).
    ///
    /// [`Term::step_limit_lanes`]: crate::model::terms::Term::step_limit_lanes
    #[inline(always)]
    pub(super) fn limit_step_lanes(
        &self,
        params: &[[Lanes; LANE_PARAMS]; MAX_TERMS],
        rows: &[LaneRows; MAX_TERMS],
        limiting: &[usize],
        n: usize,
        h: Lanes,
        atol: f64,
    ) -> Lanes {
        let negligible = negligible(atol, h);
        // a loop, not a fold: an iterator adaptor left outlined would compile the limits for
        // the baseline instruction set, not the caller's vector unit
        let mut h = h;
        for &i in limiting {
            if let Some(term) = &self.terms[i] {
                h = term.step_limit_lanes(&params[i], &rows[i], n, h, negligible);
            }
        }
        h
    }
}

/// The change of a term over a step of `h` that counts as negligible: `atol` per time unit, the
/// state rule's own target (over a step longer than 1, divided by its length).
#[inline(always)]
pub(super) fn negligible<J: Jet>(atol: f64, h: J) -> J {
    J::splat(atol) / h.max(J::splat(1.0))
}

/// One Taylor pass of a [`Model`] in progress ([`Model::pass`]): the rows of the forcing and of
/// the state, filled order by order.
pub(super) struct Pass {
    /// The pass's order.
    pub(super) n: usize,
    /// The forcing's rows μ[k = 0] + δ·(sin ωt)_k.
    f: [f64; MAX_ROWS],
    /// The rows of x, v and the internal states.
    s: [[f64; MAX_ROWS]; 2 + MAX_STATES],
    /// The present terms: their slots and their states' indices.
    pub(super) live: [(usize, Option<usize>); MAX_TERMS],
    /// How many of `live` are present.
    pub(super) m: usize,
}

impl Pass {
    /// The state's rows 0..=n into `c`; returns n.
    #[inline(always)]
    pub(super) fn finish<const N: usize>(&self, c: &mut [[f64; N]]) -> usize {
        for (k, ck) in c.iter_mut().enumerate().take(self.n + 1) {
            for (i, v) in ck.iter_mut().enumerate() {
                *v = self.s[i][k];
            }
        }
        self.n
    }
}
