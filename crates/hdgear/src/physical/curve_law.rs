//! The verdict on a card's drive with the catalogue's own stiffness law, the three straight
//! segments K₁, K₂, K₃, in place of the cubic fit ([`super::catalogue::fit`]).
//!
//! The drive is the one [`super::check::check_card`] builds, reduced with its cubic fit's scales
//! (so μ, δ and ω are the fitted model's, and the two verdicts differ by the law alone). The law
//! is the `piecewise` term ([`crate::model::piecewise::Piecewise`]) with slopes K_i·J_eq/C²,
//! knees θ(T₁)/L and (θ(T₂) − θ(T₁))/L, and the fit's backlash offset φ/L = ε ([`ASSUMPTION`]);
//! its kinks end the Taylor steps. The law converted back to N m reproduces the catalogue's
//! knees ([`CatalogueLaw::knee_residual`]).
//!
//! ```
//! use hdgear::physical::{card, catalogue, curve_law};
//! let c = card::builtin_card("CSF-20-50").unwrap();
//! let d = catalogue::assemble(c, None, None).unwrap().drive;
//! let law = curve_law::check(c, &d, 0.0, &hdgear::burst::BurstOptions::default()).unwrap();
//! assert!(law.knee_residual < 1e-12); // T1 and T2 come back from the reduced law
//! // the assumed mean load T1 sits on the first knee: crossing its corner, the drive rings
//! assert!(law.outcome.unwrap().judgement.bursting);
//! assert!(law.signatures.unwrap().max_overshoot < 1e-3); // by a small fraction of the swing
//! ```

use super::card::Card;
use super::design::{DriveVerdict, judge_model};
use super::{PhysicalParams, Reduction};
use crate::burst::{BurstOptions, Signatures};
use crate::error::Result;
use crate::model::Model;
use crate::model::terms::AnyTerm;
use serde::Serialize;

/// How the catalogue's curve enters the model, stated in every output that uses it.
pub const ASSUMPTION: &str = "the catalogue's piecewise-linear curve P takes the place of the \
    cubic fit's (k1 + k2θ²)(θ − φ) as P(θ − φ): the fit's backlash offset, the catalogue's slopes \
    and knees (K2 beyond T2 where the card gives no K3)";

/// The card's drive with its catalogue law: the reduced law, how well it returns the knees, and
/// the verdict.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CatalogueLaw {
    /// The `piecewise` term's values in the drive's reduced units:
    /// [K₁, K₂, K₃]·J_eq/C², θ(T₁)/L, (θ(T₂) − θ(T₁))/L, φ/L and the knee rounding x_r (0: the
    /// catalogue's corners).
    pub reduced: [f64; 7],
    /// The knee rounding asked for, as a fraction of θ(T₁) ([`term`]).
    pub rounding: f64,
    /// max over T₁ and T₂ of |P_reduced(θ(T)/L + φ/L)·unit − T|/T: the reduced law at the
    /// catalogue's twists, back in N m, against the catalogue's torques (a rounding moves the
    /// law off the knees by about ½(K₂ − K₁)·x_r there).
    pub knee_residual: f64,
    /// How the law enters the model ([`ASSUMPTION`]).
    pub assumption: &'static str,
    /// The verdict (`None` when it could not be simulated: the reduced ω below
    /// [`super::design::MIN_SIMULATED_OMEGA`], or more steps than a search allows).
    pub outcome: Option<DriveVerdict>,
    /// How large what the verdict saw is (with the outcome): the largest overshoot in units of
    /// the slow swing X, the largest ringing swing of x' in units of ω·X, the bursts per period.
    pub signatures: Option<Signatures>,
}

impl CatalogueLaw {
    /// The torsional periods the slow load takes to pass the knee rounding, on a drive whose
    /// reduced load is `delta`·sin(`omega`·τ): it crosses the first knee at a twist rate of about
    /// δω/k₁ (quasi-static, on slope k₁), so it passes x_r in x_r·k₁/(δω), against the torsional
    /// period 2π/√k₁. A passage well below one period rings as the corner does; several periods
    /// ring no more than the smooth fit.
    pub fn passage_periods(&self, delta: f64, omega: f64) -> f64 {
        let (k1, xr) = (self.reduced[0], self.reduced[6]);
        xr * k1 / (delta * omega) / (std::f64::consts::TAU / k1.sqrt())
    }
}

/// A knee rounding the report shows beside the catalogue's corners, as a fraction of θ(T₁): an
/// illustration of a measured curve, whose knees turn over some twist (no catalogue gives how
/// much), not a value of the card.
pub const ILLUSTRATED_ROUNDING: f64 = 0.01;

/// What the knees do to the verdict, stated beside a bursting one: a corner of the curve is
/// the sharpest form of the study's sharp-quantitative-change mechanism.
pub const KNEES: &str = "the catalogue's knees are corners: the load crossing one changes the \
    slope at once, the sharpest form of the study's sharp-quantitative-change mechanism; a \
    measured curve is rounded there, and where the load takes longer than a torsional period to \
    pass the rounding the knee rings far less (the smooth cubic fit's verdict is that limit)";

/// The largest knee rounding [`term`] takes: the first knee's own twist θ(T₁). A wider rounding
/// reaches back to the origin and is no longer the catalogue's curve.
pub const MAX_ROUNDING: f64 = 1.0;

/// Checks a knee rounding (a fraction of θ(T₁), 0 to [`MAX_ROUNDING`]).
pub fn check_rounding(rounding: f64) -> Result<()> {
    if (0.0..=MAX_ROUNDING).contains(&rounding) {
        Ok(())
    } else {
        Err(crate::Error::InvalidOption {
            name: "knee_rounding",
            value: rounding,
            reason: "must be 0 (the catalogue's corners) to 1 (a fraction of the first knee's twist)",
        })
    }
}

/// The `piecewise` term of `card`'s curve in the units of `r` (the reduction of `d`), its knees
/// rounded over `rounding`·θ(T₁) of twist (0: the catalogue's corners; the hyperbolic rounding
/// of [`crate::model::piecewise::Piecewise`], whose x_r this sets).
pub fn term(card: &Card, d: &PhysicalParams, r: &Reduction, rounding: f64) -> Result<AnyTerm> {
    check_rounding(rounding)?;
    let c = card.curve();
    let slope = |k: f64| k * r.j_eq / (d.c_eq * d.c_eq);
    let (th1, th2) = (c.twist(c.t1), c.twist(c.t2));
    let l = r.length_scale;
    AnyTerm::new(
        "piecewise",
        &[
            slope(c.k1),
            slope(c.k2),
            slope(c.k3.unwrap_or(c.k2)),
            th1 / l,
            (th2 - th1) / l,
            d.backlash / l,
            rounding * th1 / l,
        ],
    )
}

/// The reduced model of `d` (built from `card`) with the catalogue's law for its stiffness:
/// unit inertia and damping, the reduced load μ + δ sin ωτ, and [`term`] with `rounding`.
pub fn model(card: &Card, d: &PhysicalParams, rounding: f64) -> Result<Model> {
    Ok(on(card, d, &d.reduce()?, rounding)?.1)
}

/// [`term`] and [`model`] with `d`'s reduction `r` at hand.
fn on(card: &Card, d: &PhysicalParams, r: &Reduction, rounding: f64) -> Result<(AnyTerm, Model)> {
    let law = term(card, d, r, rounding)?;
    let p = r.params;
    Ok((law, Model::damped(p.mu, p.delta, p.omega).with_term(law)?))
}

/// Checks drive `d` (built from `card`) with the catalogue's law, its knees rounded by
/// `rounding` ([`term`]).
pub fn check(
    card: &Card,
    d: &PhysicalParams,
    rounding: f64,
    opts: &BurstOptions,
) -> Result<CatalogueLaw> {
    let r = d.reduce()?;
    let (law, m) = on(card, d, &r, rounding)?;
    let c = card.curve();
    let unit = r.torque_unit();
    let back = |t: f64| {
        let x = (c.twist(t) + d.backlash) / r.length_scale;
        (law.torque(x, 0.0, 0.0) * unit - t).abs() / t
    };
    let judged = judge_model(&m, opts)?;
    Ok(CatalogueLaw {
        reduced: law
            .values()
            .try_into()
            .expect("the piecewise term has seven values"),
        rounding,
        knee_residual: back(c.t1).max(back(c.t2)),
        assumption: ASSUMPTION,
        outcome: judged.as_ref().map(|(o, _)| *o),
        signatures: judged.map(|(_, resp)| resp.signatures),
    })
}
