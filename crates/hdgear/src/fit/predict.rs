//! What a law predicts for each kind of data, with its derivatives in the free parameters
//! (forward sensitivities, from the terms' own parameter derivatives: no finite differences).
//!
//! - **Friction sweep.** At a constant sliding speed v each term gives its steady torque
//!   T(0, v, z*), its internal state at the rest point z* of its rate, r(0, v, z*) = 0 (LuGre's
//!   bristles: z* = g(v)·sgn v / σ₀). By the implicit function theorem
//!   dT/dp = ∂T/∂p − ∂T/∂z · (∂r/∂p)/(∂r/∂z).
//! - **Quasi-static loop.** The twist is applied slowly along the measured path. Each term's
//!   state follows the twist at dz/dx = s·r(x, s, z) on the side s = sgn x' (a rate-independent
//!   law's rate is proportional to |x'|: Dahl, Bouc–Wen, LuGre without a Stribeck drop), and the
//!   torque is the creep torque T(x, 0⁺·s, z) of the terms on that side, as on the model's
//!   quasi-static branches ([`crate::model::branches`]). The sensitivities S = dz/dp follow
//!   dS/dx = s·(∂r/∂z·S + ∂r/∂p), integrated with the states by the same RK4 steps, so they are
//!   the exact derivatives of the computed path.

use super::data::{Data, DataKind};
use super::law::{FitLaw, LawParam};
use super::lm::Residuals;
use crate::error::{Error, Result};
use crate::model::term::Side;
use crate::model::terms::AnyTerm;

/// RK4 steps per range of the measured twist along a loop, at least (more where a state relaxes
/// fast): the states' error, of order h⁴, is then below 1e-11 of their range for the laws here
/// (the tests check the Dahl loop against its closed form).
const STEPS_PER_RANGE: f64 = 4000.0;

/// The most RK4 steps between two measured twists: a law whose state relaxes over 1e-5
/// of such a step is refused at those values (a fit's trial step there is rejected): its state
/// follows its rest curve within the data's resolution, which a law without the state describes.
const MAX_SUBSTEPS: f64 = 1e4;

/// The weighted residuals (model − data)/sd of a law with parameters `free` on `data`.
pub(crate) struct Problem<'a> {
    pub(crate) law: &'a FitLaw,
    pub(crate) free: &'a [LawParam],
    pub(crate) data: &'a Data,
    /// Passes of the measured path run before the one compared (a loop's preconditioning).
    pub(crate) repeat: usize,
}

impl Problem<'_> {
    /// Refuses a law the kind of data cannot determine, naming the term.
    pub(crate) fn check(&self) -> Result<()> {
        for t in self.law.terms() {
            let refuse = |reason: &str| Error::InvalidInput {
                what: "fitted term",
                text: t.kind().into(),
                reason: reason.into(),
            };
            if t.is_load() || t.delay().is_some() {
                return Err(refuse(
                    "a load whatever the motion or a delay has no steady or quasi-static value",
                ));
            }
            if self.data.kind == DataKind::Loop
                && t.state().is_some()
                && !rate_independent(t, &self.data.x)
            {
                return Err(refuse(
                    "its state's rate is not proportional to the twist rate (it depends on speed): \
                     a quasi-static loop cannot determine it; fit it to a friction sweep",
                ));
            }
        }
        Ok(())
    }

    /// The law's predictions at every point, and their derivatives (row-major, points × free).
    pub(crate) fn predict(&self, law: &FitLaw, out: &mut [f64], jac: &mut [f64]) -> Result<()> {
        jac.fill(0.0);
        let k = self.free.len();
        match self.data.kind {
            DataKind::Friction => {
                for (i, (v, o)) in self.data.x.iter().zip(out.iter_mut()).enumerate() {
                    *o = steady(law, self.free, *v, &mut jac[i * k..(i + 1) * k])?;
                }
                Ok(())
            }
            DataKind::Loop => quasi_static(law, self.free, &self.data.x, self.repeat, out, jac),
        }
    }

    /// Row i's standard deviation (1 where the data give none): what its residual is divided by.
    pub(crate) fn weight(&self, i: usize) -> f64 {
        self.data.sd.as_ref().map_or(1.0, |s| s[i])
    }
}

impl Residuals for Problem<'_> {
    fn residual_count(&self) -> usize {
        self.data.len()
    }
    fn dim(&self) -> usize {
        self.free.len()
    }
    fn eval(&self, p: &[f64], r: &mut [f64], jac: &mut [f64]) -> Result<()> {
        let law = self.law.with(self.free, p)?;
        self.predict(&law, r, jac)?;
        if let Some(i) = (0..r.len()).find(|&i| !r[i].is_finite()) {
            return Err(Error::InvalidInput {
                what: "fitted law",
                text: law.to_toml().replace('\n', " "),
                reason: format!("its torque at point {} is not finite", i + 1),
            });
        }
        let k = self.free.len();
        for (i, ri) in r.iter_mut().enumerate() {
            let w = self.weight(i);
            *ri = (*ri - self.data.torque[i]) / w;
            jac[i * k..(i + 1) * k].iter_mut().for_each(|d| *d /= w);
        }
        Ok(())
    }
}

/// The law's steady torque at sliding speed v, its derivatives added into `row`.
fn steady(law: &FitLaw, free: &[LawParam], v: f64, row: &mut [f64]) -> Result<f64> {
    let mut torque = 0.0;
    for (ti, t) in law.terms().iter().enumerate() {
        let own = || free.iter().enumerate().filter(move |(_, q)| q.term == ti);
        let Some(_) = t.state() else {
            torque += t.torque(0.0, v, 0.0);
            for (k, q) in own() {
                row[k] += t.param_derivative(q.index, 0.0, v, 0.0);
            }
            continue;
        };
        let z = steady_state(t, v)?;
        let rz = t.rate_gradient(0.0, v, z)[2];
        let tz = t.gradient(0.0, v, z)[2];
        torque += t.torque(0.0, v, z);
        for (k, q) in own() {
            let dz = -t.rate_param_derivative(q.index, 0.0, v, z) / rz;
            row[k] += t.param_derivative(q.index, 0.0, v, z) + tz * dz;
        }
    }
    Ok(torque)
}

/// The state z* with r(0, v, z*) = 0 that a term settles to at constant speed v, by Newton's
/// method from its rest state (one step for a rate affine in z: LuGre, Dahl and Bouc–Wen with
/// exponent 1); refused where the rest point is not a simple root (∂r/∂z = 0 there).
fn steady_state(t: &AnyTerm, v: f64) -> Result<f64> {
    let refuse = || Error::InvalidInput {
        what: "fitted term",
        text: t.kind().into(),
        reason: format!(
            "its state has no simple steady value at speed {v} (a hysteresis exponent above 1?): \
             fit it to a loop instead"
        ),
    };
    let mut z = t.state_at_rest(0.0);
    for _ in 0..100 {
        let rz = t.rate_gradient(0.0, v, z)[2];
        if rz.is_nan() || rz >= 0.0 {
            return Err(refuse());
        }
        let dz = -t.rate(0.0, v, z) / rz;
        z += dz;
        if dz.abs() <= 4.0 * f64::EPSILON * z.abs() {
            return Ok(z);
        }
    }
    Err(refuse())
}

/// Whether a term's state follows the twist the same at any slow rate: its rate at unit speed
/// on each side, s·r(x, s, z), equals the quasi-static slope dz/dx = ∂r/∂x'(x, 0⁺·s, z) of the
/// term on that side (as [`crate::model::branches`] takes it), at probes across the measured
/// twists. Then r is proportional to |x'| from 0 to unit speed (Dahl, Bouc–Wen, LuGre without a
/// Stribeck drop), and the slope's parameter derivatives are the rate's at unit speed. A law whose
/// rate depends on the speed (LuGre with a drop) is refused: a quasi-static loop sees only its
/// limit at rest.
fn rate_independent(t: &AnyTerm, x: &[f64]) -> bool {
    let (lo, hi) = span(x);
    let zs = [
        t.state_at_rest(lo),
        0.37 * (hi - lo) + 1e-3,
        -0.61 * (hi - lo) - 1e-3,
    ];
    [lo, 0.5 * (lo + hi), hi].iter().all(|&xp| {
        zs.iter().all(|&z| {
            [1.0, -1.0].iter().all(|&s| {
                let unit = s * t.rate(xp, s, z);
                let slope = t.directed(Side { v: s, z: 0.0 }).rate_gradient(xp, 0.0, z)[1];
                (unit - slope).abs() <= 1e-12 * (unit.abs() + slope.abs()) + f64::MIN_POSITIVE
            })
        })
    })
}

/// The smallest and largest of the measured twists.
fn span(x: &[f64]) -> (f64, f64) {
    x.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        })
}

/// A stateful term's index among the states, and where its sensitivities start.
struct Stateful {
    term: usize,
    at: usize,
}

/// The law along the measured twist path `x` (see the module's text), run `repeat` times before
/// the pass compared.
fn quasi_static(
    law: &FitLaw,
    free: &[LawParam],
    x: &[f64],
    repeat: usize,
    out: &mut [f64],
    jac: &mut [f64],
) -> Result<()> {
    let terms = law.terms();
    let k = free.len();
    let stateful: Vec<Stateful> = terms
        .iter()
        .enumerate()
        .filter(|(_, t)| t.state().is_some())
        .enumerate()
        .map(|(j, (term, _))| Stateful {
            term,
            at: j * (1 + k),
        })
        .collect();
    // y = for each state: z, then dz/dp_0 … dz/dp_{k−1}
    let mut y = vec![0.0; stateful.len() * (1 + k)];
    for s in &stateful {
        y[s.at] = terms[s.term].state_at_rest(x[0]);
    }
    let (lo, hi) = span(x);
    let h_max = (hi - lo).max(f64::MIN_POSITIVE) / STEPS_PER_RANGE;
    let sides = arrival_sides(x);
    let field = |s: f64, xv: f64, y: &[f64], dy: &mut [f64]| {
        for st in &stateful {
            let t = &terms[st.term];
            let z = y[st.at];
            let rz = t.rate_gradient(xv, s, z)[2];
            dy[st.at] = s * t.rate(xv, s, z);
            for (kk, q) in free.iter().enumerate() {
                let own = if q.term == st.term {
                    t.rate_param_derivative(q.index, xv, s, z)
                } else {
                    0.0
                };
                dy[st.at + 1 + kk] = s * (rz * y[st.at + 1 + kk] + own);
            }
        }
    };
    for pass in 0..=repeat {
        for i in 0..x.len() {
            if i > 0 || pass > 0 {
                let from = if i == 0 { x[x.len() - 1] } else { x[i - 1] };
                let along = if x[i] < from { -1.0 } else { 1.0 };
                // steps within RK4's accuracy where a state relaxes fast (h·|∂r/∂z| ≤ 0.1)
                let stiff = stateful.iter().fold(0.0_f64, |m, st| {
                    m.max(terms[st.term].rate_gradient(from, along, y[st.at])[2].abs())
                });
                let h = h_max.min(0.1 / stiff);
                if (x[i] - from).abs() > MAX_SUBSTEPS * h {
                    return Err(Error::InvalidInput {
                        what: "fitted law",
                        text: law.to_toml().replace('\n', " "),
                        reason: format!(
                            "a state relaxes over a twist of {:.1e}, too fast to follow along the \
                             measured steps",
                            1.0 / stiff
                        ),
                    });
                }
                rk4(&field, along, from, x[i], h, &mut y);
            }
            if pass < repeat {
                continue;
            }
            let torque = creep(
                terms,
                free,
                &stateful,
                x[i],
                sides[i],
                &y,
                &mut jac[i * k..(i + 1) * k],
            );
            out[i] = torque;
        }
    }
    Ok(())
}

/// sgn x' on arrival at each point of a twist path (the first point: the way the path leaves
/// it; a repeated twist keeps the side before it).
fn arrival_sides(x: &[f64]) -> Vec<f64> {
    let mut sides = vec![1.0; x.len()];
    for i in 0..x.len() {
        let d = if i == 0 {
            x.get(1).map_or(0.0, |x1| x1 - x[0])
        } else {
            x[i] - x[i - 1]
        };
        sides[i] = if d > 0.0 {
            1.0
        } else if d < 0.0 {
            -1.0
        } else if i > 0 {
            sides[i - 1]
        } else {
            1.0
        };
    }
    sides
}

/// The creep torque of the terms on side `s` at twist `x` with the states and sensitivities `y`,
/// its derivatives in the free parameters added into `row`.
fn creep(
    terms: &[AnyTerm],
    free: &[LawParam],
    stateful: &[Stateful],
    x: f64,
    s: f64,
    y: &[f64],
    row: &mut [f64],
) -> f64 {
    let side = Side { v: s, z: 0.0 };
    let mut torque = 0.0;
    for (ti, t) in terms.iter().enumerate() {
        let t = t.directed(side);
        let st = stateful.iter().find(|st| st.term == ti);
        let z = st.map_or(0.0, |st| y[st.at]);
        torque += t.torque(x, 0.0, z);
        let tz = t.gradient(x, 0.0, z)[2];
        for (kk, q) in free.iter().enumerate() {
            if q.term == ti {
                row[kk] += t.param_derivative(q.index, x, 0.0, z);
            }
            if let Some(st) = st {
                row[kk] += tz * y[st.at + 1 + kk];
            }
        }
    }
    torque
}

/// RK4 ([`crate::integrate::rk4_step`]) from twist `a` to `b` in equal steps of at most
/// `h_max`, on side `s`.
fn rk4(
    f: &impl Fn(f64, f64, &[f64], &mut [f64]),
    s: f64,
    a: f64,
    b: f64,
    h_max: f64,
    y: &mut [f64],
) {
    if y.is_empty() || a == b {
        return;
    }
    let n = ((b - a).abs() / h_max).ceil().max(1.0) as usize;
    let h = (b - a) / n as f64;
    let mut scratch = vec![0.0; 5 * y.len()];
    let mut field = |x: f64, y: &[f64], dy: &mut [f64]| {
        f(s, x, y, dy);
        true
    };
    for step in 0..n {
        crate::integrate::rk4_step(&mut field, a + h * step as f64, h, y, &mut scratch);
    }
}
