//! A card's fitted friction law in its drive's reduced model, the verdict with it, and what
//! change of the friction or of the load would change that verdict.
//!
//! The law is the card's Coulomb–Stribeck–viscous fit with sticking,
//! (F_c + (F_s − F_c)·e^{−(θ'/v_s)²})·sgn θ' + c_v·θ', applied across the compliance, on the
//! twist rate θ' ([`ASSUMPTION`]). In the reduced model it is the `coulomb` term
//! ([`crate::model::terms::Coulomb`]) with its torques over [`super::Reduction::torque_unit`],
//! its speed over L/T and c_v over C; the drive sticks while the rest of the torque stays within
//! ±F_s. The response is integrated piece by piece and judged as every model with sticking
//! friction is ([`crate::burst::response_model`]): a slip that is the window's largest burst
//! makes the verdict stick-slip.
//!
//! ```
//! use hdgear::physical::card;
//! let mut c = card::builtin_card("CSG-20-50").unwrap().clone();
//! c.friction = Some(card::Friction { source: "hd-torsional-csg".into(), coulomb: Some(1.0),
//!     breakaway: Some(1.5), stribeck_speed: Some(0.01), ..Default::default() });
//! let law = c.friction_law().unwrap().unwrap();
//! assert_eq!((law.coulomb, law.breakaway, law.viscous), (1.0, 1.5, 0.0));
//! ```

use super::PhysicalParams;
use super::card::Card;
pub use super::card::FrictionLaw;
use super::design::{DriveVerdict, Margin, judge_model, search_margin};
use crate::burst::{BurstOptions, StickSlip};
use crate::error::Result;
use crate::model::Model;
use crate::model::friction::Coulomb;
use crate::model::mesh_loss::MeshLoss;
use crate::model::terms::{AnyTerm, Term};
use rayon::prelude::*;
use serde::Serialize;

/// Where the card's friction is taken to act, stated in every output that uses it.
pub const ASSUMPTION: &str = "the card's friction acts across the compliance, on the twist rate \
    θ' (the reduction to one equation holds for such friction only; friction on the input or \
    output rotation alone moves the rigid-body mode too, which this verdict does not model)";

/// [`MESH_PRESLIDING`]'s literal, written once: the constant and [`MESH_ASSUMPTION`]'s text
/// both take it from here.
macro_rules! mesh_presliding {
    () => {
        5e-5
    };
}

/// How a card's efficiency is taken, stated in every output that uses it.
pub const MESH_ASSUMPTION: &str = concat!(
    "the card's efficiency η is a torque-proportional mesh loss μ_m = 1/η − 1 on the twist (the \
     loss μ_m·|T_s| opposes the twist rate), its sign turning over ",
    mesh_presliding!(),
    " rad of twist after a reversal (the harmonic-drive twin's presliding length)"
);

/// θ_m: the twist over which the mesh loss's sign turns after a reversal \[rad\] (the
/// harmonic-drive twin's Dahl presliding length, REAL-DRIVES.md), an assumption
/// ([`MESH_ASSUMPTION`]).
pub const MESH_PRESLIDING: f64 = mesh_presliding!();

/// The law in the reduced model's units: the `coulomb` term's f_c, f_s, v_st and c_v.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ReducedFriction {
    /// f_c = F_c/unit torque.
    pub fc: f64,
    /// f_s = F_s/unit torque.
    pub fs: f64,
    /// v_st = v_s·T/L.
    pub vst: f64,
    /// c_v = c_v/C.
    pub cv: f64,
    /// The mesh loss's μ_m (a ratio: the same in every unit) and θ_m = [`MESH_PRESLIDING`]/L,
    /// if the card gives an efficiency.
    pub mesh: Option<[f64; 2]>,
}

/// What a designer can change in the friction check, each as a factor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FrictionKnob {
    /// The Stribeck drop F_s − F_c (F_c kept): what releases a slip.
    Drop,
    /// F_c, with the drop kept.
    Coulomb,
    /// c_v.
    Viscous,
    /// v_s.
    StribeckSpeed,
    /// The mesh loss μ_m.
    MeshLoss,
    /// The slow load's amplitude T_am.
    TAm,
}

impl FrictionKnob {
    /// Every knob, in the order reported.
    pub const ALL: [FrictionKnob; 6] = [
        FrictionKnob::Drop,
        FrictionKnob::Coulomb,
        FrictionKnob::Viscous,
        FrictionKnob::StribeckSpeed,
        FrictionKnob::MeshLoss,
        FrictionKnob::TAm,
    ];

    /// Its name in the output.
    pub fn name(self) -> &'static str {
        match self {
            FrictionKnob::Drop => "drop",
            FrictionKnob::Coulomb => "coulomb",
            FrictionKnob::Viscous => "viscous",
            FrictionKnob::StribeckSpeed => "stribeck_speed",
            FrictionKnob::MeshLoss => "mesh_loss",
            FrictionKnob::TAm => "t_am",
        }
    }
}

impl std::fmt::Display for FrictionKnob {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

impl FrictionLaw {
    /// The law in the units of `r`.
    pub fn reduced(&self, d: &PhysicalParams, r: &super::Reduction) -> ReducedFriction {
        let unit = r.torque_unit();
        ReducedFriction {
            fc: self.coulomb / unit,
            fs: self.breakaway / unit,
            vst: self.stribeck_speed / r.theta_dot(1.0),
            cv: self.viscous / d.c_eq,
            mesh: self
                .mesh_loss
                .map(|mu| [mu, MESH_PRESLIDING / r.length_scale]),
        }
    }

    /// The law with `knob` ×`f` (T_am is the drive's, not the law's: unchanged here).
    pub fn scaled(&self, knob: FrictionKnob, f: f64) -> FrictionLaw {
        let drop = self.breakaway - self.coulomb;
        let mut l = *self;
        match knob {
            FrictionKnob::Drop => l.breakaway = self.coulomb + f * drop,
            FrictionKnob::Coulomb => {
                l.coulomb *= f;
                l.breakaway = l.coulomb + drop;
            }
            FrictionKnob::Viscous => l.viscous *= f,
            FrictionKnob::StribeckSpeed => l.stribeck_speed *= f,
            FrictionKnob::MeshLoss => l.mesh_loss = self.mesh_loss.map(|mu| mu * f),
            FrictionKnob::TAm => {}
        }
        l
    }

    /// The knob's current value (SI).
    pub fn value(&self, knob: FrictionKnob, d: &PhysicalParams) -> f64 {
        match knob {
            FrictionKnob::Drop => self.breakaway - self.coulomb,
            FrictionKnob::Coulomb => self.coulomb,
            FrictionKnob::Viscous => self.viscous,
            FrictionKnob::StribeckSpeed => self.stribeck_speed,
            FrictionKnob::MeshLoss => self.mesh_loss.unwrap_or(0.0),
            FrictionKnob::TAm => d.t_am,
        }
    }
}

/// The reduced model of drive `d` with friction `law`: the study's equation, the `coulomb` term
/// and, for a card with an efficiency, the `meshloss` term.
pub fn drive_model(d: &PhysicalParams, law: &FrictionLaw) -> Result<Model> {
    reduced_model(d, law, &d.reduce()?)
}

/// The reduced model of drive `d` built from `card`: with the card's fitted friction
/// ([`drive_model`]) when it has a `[friction]` table, else the study's equation at `d`'s
/// reduced parameters.
pub fn card_model(card: &Card, d: &PhysicalParams) -> Result<Model> {
    match card.friction_law()? {
        Some(law) => drive_model(d, &law),
        None => Ok(Model::study(&d.reduce()?.params)),
    }
}

/// [`drive_model`] with `d`'s reduction `r` at hand.
fn reduced_model(d: &PhysicalParams, law: &FrictionLaw, r: &super::Reduction) -> Result<Model> {
    let f = law.reduced(d, r);
    let coulomb = AnyTerm::new(Coulomb::KIND, &[f.fc, f.fs, f.vst, f.cv])?;
    let m = Model::study(&r.params).with_term(coulomb)?;
    match f.mesh {
        Some(mesh) => m.with_term(AnyTerm::new(MeshLoss::KIND, &mesh)?),
        None => Ok(m),
    }
}

/// The verdict on a drive with friction.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FrictionOutcome {
    /// The verdict, mode and mechanism (its fields at the top level).
    #[serde(flatten)]
    pub outcome: DriveVerdict,
    /// The rests and slips of the response.
    pub sticking: Option<StickSlip>,
    /// The largest slip's peak twist rate \[rad/s\] (0 without rests).
    pub slip_peak_rate: f64,
}

/// The verdict on `d` with `law`, `None` when it cannot be simulated: the reduced ω below
/// [`super::design::MIN_SIMULATED_OMEGA`] (no equilibrium-curve prediction covers friction), or
/// more steps than a search allows.
pub fn judge(
    d: &PhysicalParams,
    law: &FrictionLaw,
    opts: &BurstOptions,
) -> Result<Option<FrictionOutcome>> {
    let r = d.reduce()?;
    let m = reduced_model(d, law, &r)?;
    Ok(
        judge_model(&m, opts)?.map(|(outcome, resp)| FrictionOutcome {
            outcome,
            sticking: resp.sticking,
            slip_peak_rate: resp
                .sticking
                .map_or(0.0, |s| r.theta_dot(s.slip_peak_speed)),
        }),
    )
}

/// The friction check of a card's drive.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FrictionCheck {
    /// The card's law.
    pub law: FrictionLaw,
    /// The source key of the card's friction section.
    pub source: String,
    /// The law in the reduced model.
    pub reduced: ReducedFriction,
    /// Where the friction is taken to act ([`ASSUMPTION`]).
    pub assumption: &'static str,
    /// δ/f_s = T_am·(J_eq/J_o)/F_s: the slow load's swing that twists the drive (the rest,
    /// T_am·(1 − J_eq/J_o), swings the rigid-body mode) over the sticking band. At most 1, the
    /// band holds the swing from rest and the drive never slips. `None` without a band (F_s = 0).
    pub load_over_breakaway: Option<f64>,
    /// The verdict with the friction (`None` when it could not be simulated).
    pub outcome: Option<FrictionOutcome>,
    /// For each knob, the single change that changes the verdict (none without an outcome; the
    /// mesh loss's only for a card with an efficiency).
    pub margins: Vec<Margin<FrictionKnob>>,
}

/// Checks drive `d` (built from `card`) with the card's friction law; `None` when the card has
/// no fitted law. The knobs' searches run side by side.
pub fn check(
    card: &Card,
    d: &PhysicalParams,
    opts: &BurstOptions,
) -> Result<Option<FrictionCheck>> {
    let Some(law) = card.friction_law()? else {
        return Ok(None);
    };
    let r = d.reduce()?;
    let outcome = judge(d, &law, opts)?;
    let margins = match outcome {
        None => Vec::new(),
        // the mesh loss's knob only where the card gives an efficiency
        Some(now) => FrictionKnob::ALL
            .par_iter()
            .filter(|&&knob| knob != FrictionKnob::MeshLoss || law.mesh_loss.is_some())
            .map(|&knob| {
                search_margin(knob, law.value(knob, d), now.outcome.judgement, |f| {
                    let (dd, l) = match knob {
                        FrictionKnob::TAm => (
                            PhysicalParams {
                                t_am: d.t_am * f,
                                ..*d
                            },
                            law,
                        ),
                        _ => (*d, law.scaled(knob, f)),
                    };
                    Ok(judge(&dd, &l, opts)?.map(|o| o.outcome.judgement))
                })
            })
            .collect::<Vec<_>>()
            .into_iter()
            .collect::<Result<_>>()?,
    };
    let reduced = law.reduced(d, &r);
    Ok(Some(FrictionCheck {
        law,
        source: card
            .friction
            .as_ref()
            .map_or(String::new(), |f| f.source.clone()),
        reduced,
        assumption: ASSUMPTION,
        load_over_breakaway: (reduced.fs > 0.0).then(|| r.params.delta / reduced.fs),
        outcome,
        margins,
    }))
}
