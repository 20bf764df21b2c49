//! The closed loop of a study plant and a scheduled stiffness ([`super::schedule::Scheduled`])
//! as an equilibrium curve ([`ScheduledTorque`]): the load at which each twist is an equilibrium,
//! found by Brent's method, and the fast subsystem's stiffness there.

use super::Model;
use super::curve::{ModelCurve, Statics, refusal};
use super::schedule::Scheduled;
use super::terms::AnyTerm;
use crate::error::Result;
use crate::params::Params;

impl ModelCurve<ScheduledTorque> {
    /// The curve of `m`'s closed loop with its scheduled stiffness
    /// ([`ScheduledTorque`]); refused as [`ModelCurve::new`] and
    /// [`ScheduledTorque::new`] say.
    pub fn scheduled(m: &Model) -> Result<ModelCurve<ScheduledTorque>> {
        ModelCurve::of(ScheduledTorque::new(m)?)
    }
}

/// Samples across the closed loop's traversed x-range on which [`ScheduledTorque::new`] checks
/// that each x is an equilibrium at one load only.
const SINGLE_LOAD_SAMPLES: usize = 1024;

/// The closed loop of a study plant and a [`Scheduled`] stiffness as a curve
/// ([`super::ModelCurve::scheduled`]). With the load frozen at a, the plant's
/// g(x) = αx³ − x² + γ(x − ε) plus k(a)·(x − x̂_c) is the study's cubic with γ + k(a) and
/// γε + k(a)·x̂_c: its equilibria at a in closed form. The curve's g is μ + δ·a(x), a(x) the
/// load at which x is an equilibrium, the root of
///
/// F(x, a) = g(x) + k(a)·(x − x̂_c) − μ − δa = 0,
///
/// so that dx*/da = (δ − k'(a)·(x − x̂_c))/(g'(x) + k(a)) = δ/g'_curve. The fast subsystem's
/// stiffness at x is g'(x) + k(a(x)). Since 0 ≤ k ≤ K ([`Scheduled::max_gain`]), the root lies
/// between a₀ + min(0, K·s)/δ and a₀ + max(0, K·s)/δ, a₀ = (g(x) − μ)/δ the open loop's load,
/// s = x − x̂_c: F changes sign there, and Brent's method finds it. On the closed loop's branch x and the reference lie on
/// the same side of x̂_c, so ∂F/∂a = k'·s − δ < 0 there and a(x) is single-valued; where a plant
/// unlike the schedule's model makes it fold back, the curve is refused.
///
/// ```
/// use hdgear::Params;
/// use hdgear::fast::StaticCurve;
/// use hdgear::model::{Model, ModelCurve, schedule::Scheduled, terms::AnyTerm};
/// let p = Params::default(); // γ = 0.1: a soft middle, slope 0.079 at its softest
/// let law = AnyTerm::Scheduled(Scheduled::for_plant(&p, 0.3, 0.0));
/// let c = ModelCurve::scheduled(&Model::study(&p).with_term(law).unwrap()).unwrap();
/// assert_eq!(c.fold_band(), None);
/// assert!((c.min_traversed_gprime() - 0.3).abs() < 1e-9); // the schedule's target
/// ```
#[derive(Clone, Copy, Debug)]
pub struct ScheduledTorque {
    model: Model,
    /// The plant: the model without the schedule, as a study set.
    plant: Params,
    law: Scheduled,
}

impl ScheduledTorque {
    /// The closed loop `m`; refused (naming the model) when it has no scheduled stiffness, when
    /// its plant is not a study cubic (up to terms of affine static torque,
    /// [`Model::equivalent_params`]), when the schedule's phase does not run at the load's ω (its
    /// gain is then no function of the load a), or when some x in the traversed range is an
    /// equilibrium at two loads.
    pub fn new(m: &Model) -> Result<ScheduledTorque> {
        let refuse = |reason: &str| refusal(m, reason);
        let law = m
            .terms()
            .find_map(|t| match t {
                AnyTerm::Scheduled(s) => Some(*s),
                _ => None,
            })
            .ok_or_else(|| refuse("it has no scheduled stiffness"))?;
        let plant = m.without_schedule().equivalent_params().ok_or_else(|| {
            refuse("a scheduled stiffness's closed loop is known for a plant whose static torque is a study cubic")
        })?;
        let omega = m.forcing()[2];
        if law.0[6] != omega {
            return Err(refusal(
                m,
                format!(
                    "the schedule's phase runs at ω̂ = {} and the load at ω = {omega}: its gain is no function of the load a, so there is no equilibrium curve",
                    law.0[6]
                ),
            ));
        }
        if plant.delta == 0.0 {
            return Err(refuse(
                "with δ = 0 the load does not move: a curve over a needs δ ≠ 0",
            ));
        }
        let c = ScheduledTorque {
            model: *m,
            plant,
            law,
        };
        let (lo, hi) = (
            c.equilibria(-1.0)?[0],
            *c.equilibria(1.0)?.last().unwrap_or(&0.0),
        );
        let single = (0..=SINGLE_LOAD_SAMPLES).all(|i| {
            let x = lo + (hi - lo) * i as f64 / SINGLE_LOAD_SAMPLES as f64;
            c.load_at(x).2 > 0.0
        });
        if !single {
            return Err(refuse(
                "the schedule makes some twist an equilibrium at two loads (its plant model is too far from the plant): the curve folds back in a",
            ));
        }
        Ok(c)
    }

    /// The closed loop with the load frozen at a, as a study set whose equilibria at a are its
    /// own: γ + k(a), and γε + k(a)·x̂_c moved into μ.
    pub fn frozen(&self, a: f64) -> Params {
        let p = &self.plant;
        let k = self.law.gain(a);
        Params {
            gamma: p.gamma + k,
            eps: 0.0,
            mu: p.mu + p.gamma * p.eps + k * self.law.0[2],
            ..*p
        }
    }

    /// The frozen closed loop's equilibria at load a, increasing (only the stable ones with
    /// `stable`).
    fn roots_at(&self, a: f64, stable: bool) -> Vec<f64> {
        let e = crate::fast::equilibria(&self.frozen(a), a);
        e.roots
            .iter()
            .filter(|r| !stable || r.kind.is_stable())
            .map(|r| r.x)
            .collect()
    }

    /// The load a(x) at which x is an equilibrium, k(a) there and −∂F/∂a = δ − k'(a)·(x − x̂_c),
    /// F(x, a) = g(x) + k(a)·(x − x̂_c) − μ − δa. F falls with a (the single-load check of
    /// [`ScheduledTorque::new`]) and its root lies where 0 ≤ k ≤ k_max puts it. It is solved for
    /// the reference's offset s₀ rather than for a: a(s₀) ([`Scheduled::load_of`]) and k(s₀)
    /// are polynomials, where k(a) takes a cube root per evaluation.
    fn load_at(&self, x: f64) -> (f64, f64, f64) {
        let (p, law) = (&self.plant, &self.law);
        let s = x - law.0[2];
        let torque = p.g(x) - p.mu;
        if law.0[5] == 0.0 {
            // the load does not move the reference: k is one constant and F linear in a
            let k = law.gain(0.0);
            return ((torque + k * s) / p.delta, k, p.delta);
        }
        let open = torque / p.delta;
        let d = law.max_gain() * s / p.delta;
        let (l, r) = (open + d.min(0.0), open + d.max(0.0));
        // (a, s₀(a))
        let (a, s0) = if l == r {
            (l, law.reference(l))
        } else {
            let f = |s0: f64| torque - p.delta * law.load_of(s0) + law.gain_slope_at(s0)[0] * s;
            let (sl, sr) = (law.reference(l), law.reference(r));
            let (fl, fr) = (f(sl), f(sr));
            if (fl > 0.0) == (fr > 0.0) && fl != 0.0 && fr != 0.0 {
                // a root on an end of [l, r] (the gain off, or at its largest) that the
                // rounding of s₀ at the ends moved outside: that end
                if fl.abs() <= fr.abs() {
                    (l, sl)
                } else {
                    (r, sr)
                }
            } else {
                let tol = 4.0 * f64::EPSILON * sl.abs().max(sr.abs()).max(1.0);
                let s0 = crate::roots::brent(f, sl, fl, sr, fr, tol);
                (law.load_of(s0), s0)
            }
        };
        let [k, dk] = law.gain_slope_at(s0);
        (a, k, p.delta - dk * s)
    }
}

impl Statics for ScheduledTorque {
    fn model(&self) -> &Model {
        &self.model
    }
    fn g(&self, x: f64) -> f64 {
        self.plant.forcing(self.load_at(x).0)
    }
    fn g_prime(&self, x: f64) -> f64 {
        let (_, k, da) = self.load_at(x);
        self.plant.delta * (self.plant.g_prime(x) + k) / da
    }
    fn stiffness(&self, x: f64) -> f64 {
        self.plant.g_prime(x) + self.load_at(x).1
    }
    fn equilibria(&self, a: f64) -> Result<Vec<f64>> {
        Ok(self.roots_at(a, false))
    }
    fn stable_roots(&self, a: f64) -> Option<Vec<f64>> {
        Some(self.roots_at(a, true))
    }
}

/// A model's equilibrium curve at its own damping at rest, of either kind: its static
/// torque's ([`ModelCurve::new`]) or, with a scheduled stiffness, the closed loop's
/// ([`ModelCurve::scheduled`]).
pub enum AnyCurve {
    /// The static torque's.
    Torque(ModelCurve),
    /// The closed loop's of a scheduled stiffness.
    Scheduled(ModelCurve<ScheduledTorque>),
}

impl AnyCurve {
    /// The curve of `m`, of the kind its terms call for; refused as the two constructors say.
    pub fn of(m: &Model) -> Result<AnyCurve> {
        Ok(if m.is_scheduled() {
            AnyCurve::Scheduled(ModelCurve::scheduled(m)?)
        } else {
            AnyCurve::Torque(ModelCurve::new(m)?)
        })
    }
}
