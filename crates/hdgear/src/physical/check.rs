//! The check of a drive card: what its catalogue numbers imply before any simulation (the curve
//! and its cubic fit, the damping from the hysteresis loss, the torsional natural frequency and
//! the critical input speed, the distance from the folds) and the verdict on the drive built
//! from it.
//!
//! ```
//! use hdgear::physical::{card, check};
//! let c = card::builtin_card("CSG-20-50").unwrap();
//! let r = check::check_card(c, &card::builtin().sources, check::DampingChoice::HysteresisLoss,
//!     0.0, &hdgear::burst::BurstOptions::default()).unwrap();
//! assert!(r.folds.three_alpha_gamma > 1.0); // no folds with a catalogue law
//! assert_eq!(r.catalogue_law.rounding, 0.0); // the catalogue's own corners
//! ```

use super::card::{Card, Source, SourceKind};
use super::catalogue::{CubicFit, assemble, fit};
use super::design::{
    CatalogueOrigin, DriveSummary, DriveVerdict, Judgement, outcome_of, summarize,
};
use crate::burst::BurstOptions;
use crate::error::Result;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;

/// Where the drive's damping comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum DampingChoice {
    /// From the card's hysteresis loss (ζ_eq of a ±rated-torque cycle), when it has one;
    /// otherwise as [`DampingChoice::Assumed`].
    HysteresisLoss,
    /// The application's ζ, or the assumed 10 %.
    Assumed,
}

impl DampingChoice {
    /// Every choice, in the order of the command-line's values.
    pub const ALL: [DampingChoice; 2] = [DampingChoice::HysteresisLoss, DampingChoice::Assumed];

    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            DampingChoice::HysteresisLoss => "loss",
            DampingChoice::Assumed => "assumed",
        }
    }

    /// The choice called `text`.
    pub fn parse(text: &str) -> Result<DampingChoice> {
        crate::error::by_name(&Self::ALL, Self::name, "damping", text)
    }
}

/// The card's piecewise-linear curve at its knees and at the rated torque.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CurveFacts {
    /// Twist at T1 \[rad\] (T1/K1).
    pub twist_t1: f64,
    /// Twist at T2 \[rad\].
    pub twist_t2: f64,
    /// Twist at the rated torque \[rad\], when the card rates it.
    pub twist_rated: Option<f64>,
    /// The largest torque the curve is used to \[N m\].
    pub t_max: f64,
    /// |T(θ(T1)) − T1| / T1 and the same at T2: the curve's inverse reproduces its knees.
    pub knee_residual: f64,
}

/// The damping ratio the hysteresis loss implies.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LossDamping {
    /// The loss \[rad\].
    pub loss: f64,
    /// The kind of its source (an assumption on the built-in cards).
    pub source: SourceKind,
    /// The torque amplitude of the cycle \[N m\]: the rated torque, or T2 without a rating.
    pub amplitude: f64,
    /// ζ_eq = E_d/(4π E_s) of the cycle.
    pub zeta: f64,
}

/// The damping the drive was given, and the alternative.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DampingFacts {
    /// ζ from the hysteresis loss, when the card has a loss.
    pub from_loss: Option<LossDamping>,
    /// The damping used: the loss's where it was asked for and the card has a loss, else the
    /// assumed (the application's ζ or 10 %).
    pub choice: DampingChoice,
    /// ζ the drive was given.
    pub zeta: f64,
    /// γ = k1 J/C² = 1/(4ζ²) with that ζ.
    pub gamma: f64,
}

/// Frequencies of the linear torsional mode.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Frequencies {
    /// f_n = √(K1/J_eq)/2π \[Hz\] with the catalogue K1.
    pub natural_hz: f64,
    /// The application's required f_n \[Hz\], when given.
    pub required_hz: Option<f64>,
    /// The input speed \[rpm\] whose twice-per-revolution kinematic error meets f_n: 30·f_n.
    pub critical_input_rpm: f64,
    /// The card's maximum input speed \[rpm\], when given.
    pub max_input_rpm: Option<f64>,
}

/// How far the fitted law is from having folds (the study's bursting needs them or a steep
/// curve): with K(θ) = k1 + k2θ², 3αγ = 3k1/(k2 φ²), folds exist iff 3αγ < 1, i.e. φ > √(3k1/k2).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Folds {
    /// 3αγ of the drive.
    pub three_alpha_gamma: f64,
    /// The drive's backlash φ \[rad\].
    pub backlash: f64,
    /// The backlash at which folds appear \[rad\].
    pub fold_backlash: f64,
}

/// What the held verdicts assume ([`HeldInput`], the held columns of [`load_map`]), stated in
/// every output that shows them.
pub const HELD_ASSUMPTION: &str = "the cubic fit's drive under a position-controlled motor: J_o \
    alone on the compliance, the whole disturbance on the twist";

/// The drive with its wave generator held ([`super::PhysicalParams::reduce_held`]: a
/// position-controlled motor, or the gear's own starting torque holding the load) beside the
/// free input of [`CardCheck::summary`] (a torque-driven motor): the twist is then J_o on the
/// compliance, and the slow disturbance reaches it whole.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct HeldInput {
    /// What the verdict assumes ([`HELD_ASSUMPTION`]).
    pub assumption: &'static str,
    /// The held reduction's dimensionless set.
    pub reduced: crate::Params,
    /// ζ = C/(2√(k1 J_o)) of the held torsional mode (γ = 1/(4ζ²)).
    pub zeta: f64,
    /// The verdict with the input held.
    pub outcome: DriveVerdict,
    /// N·T_st: the card's starting torque at the input as a torque at the output \[N m\], when
    /// the card gives one.
    pub starting_at_output: Option<f64>,
    /// Whether that torque holds the input against the slow disturbance (N·T_st ≥ T_am: a held
    /// input passes the disturbance whole to the friction, quasi-statically; a burst's own
    /// torque peaks may still make it slip): then this verdict, not the free input's, is the
    /// drive's under a torque-driven motor too. `None` without a starting torque.
    pub held_by_friction: Option<bool>,
}

/// The verdict on `d` with its wave generator held, and whether `card`'s starting torque holds
/// it ([`HeldInput`]).
pub fn held_input(
    card: &Card,
    d: &super::PhysicalParams,
    opts: &BurstOptions,
) -> Result<HeldInput> {
    let r = d.reduce_held()?;
    let starting_at_output = card
        .friction
        .as_ref()
        .and_then(|f| f.starting)
        .map(|t| d.ratio * t);
    Ok(HeldInput {
        assumption: HELD_ASSUMPTION,
        reduced: r.params,
        zeta: d.zeta_on(r.j_eq),
        outcome: outcome_of(&r.params, opts)?,
        starting_at_output,
        held_by_friction: starting_at_output.map(|t| t >= d.t_am),
    })
}

/// Everything `hdgear card check` reports on a card.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CardCheck {
    /// The card's name.
    pub name: String,
    /// The quantities the card has no value for.
    pub missing: Vec<String>,
    /// The sources of the card's sections, by section.
    pub sources: BTreeMap<&'static str, Source>,
    /// The piecewise curve.
    pub curve: CurveFacts,
    /// The cubic fit used for the drive (up to T2).
    pub fit: CubicFit,
    /// The cubic fit up to the rated torque, when the card rates one within its curve.
    pub fit_to_rated: Option<CubicFit>,
    /// The damping.
    pub damping: DampingFacts,
    /// The torsional mode's frequencies.
    pub frequencies: Frequencies,
    /// Distance from the folds.
    pub folds: Folds,
    /// The drive built from the card and the verdict on it.
    pub summary: DriveSummary,
    /// The verdict with the catalogue's own piecewise-linear law in place of the cubic fit.
    pub catalogue_law: super::curve_law::CatalogueLaw,
    /// The verdict with the wave generator held.
    pub held_input: HeldInput,
    /// The verdict with the card's fitted friction law, when it has one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction: Option<super::friction::FrictionCheck>,
}

/// The damping ratio the card's hysteresis loss implies for a ±rated-torque cycle (±T2 without
/// a rating), when it has a loss.
pub fn loss_damping(card: &Card, sources: &BTreeMap<String, Source>) -> Option<LossDamping> {
    let c = card.curve();
    let h = card.hysteresis.as_ref()?;
    let loss = h.loss?;
    let amplitude = card.rated_on_curve().unwrap_or(c.t2);
    Some(LossDamping {
        loss,
        source: sources
            .get(&h.source)
            .map_or(SourceKind::Assumption, |s| s.kind),
        amplitude,
        zeta: c.equivalent_damping(loss, amplitude),
    })
}

/// The ζ a drive gets under `choice`: the loss's when chosen and known, else none (the
/// application's or the assumed 10 %, see [`assemble`]).
fn chosen_zeta(choice: DampingChoice, from_loss: &Option<LossDamping>) -> Option<f64> {
    match (choice, from_loss) {
        (DampingChoice::HysteresisLoss, Some(l)) => Some(l.zeta),
        _ => None,
    }
}

/// Checks `card` (whose file has `sources`) and judges the drive built from it with `damping`,
/// the catalogue curve's knees rounded by `knee_rounding` ([`super::curve_law::term`]).
pub fn check_card(
    card: &Card,
    sources: &BTreeMap<String, Source>,
    damping: DampingChoice,
    knee_rounding: f64,
    opts: &BurstOptions,
) -> Result<CardCheck> {
    card.validate(sources)?;
    super::curve_law::check_rounding(knee_rounding)?;
    let c = card.curve();
    let rated = card.rated_on_curve();
    let knee = |t: f64| (c.torque(c.twist(t)) - t).abs() / t;
    let curve = CurveFacts {
        twist_t1: c.twist(c.t1),
        twist_t2: c.twist(c.t2),
        twist_rated: rated.map(|t| c.twist(t)),
        t_max: c.t_max,
        knee_residual: knee(c.t1).max(knee(c.t2)),
    };
    let from_loss = loss_damping(card, sources);
    let zeta = chosen_zeta(damping, &from_loss);
    // the loss asked for on a card without one falls back to the assumed damping: say so
    let used = match zeta {
        Some(_) => damping,
        None => DampingChoice::Assumed,
    };
    let a = assemble(card, None, zeta)?;
    let d = a.drive;
    let j_eq = d.j_eq();
    let app = card.application.as_ref();
    let natural_hz = (c.k1 / j_eq).sqrt() / std::f64::consts::TAU;
    let origin = CatalogueOrigin {
        name: card.name.clone(),
        fit: a.fit,
        assumptions: a.assumptions,
    };
    let summary = summarize(&d, origin, opts)?;
    let catalogue_law = super::curve_law::check(card, &d, knee_rounding, opts)?;
    let friction = super::friction::check(card, &d, opts)?;
    let held_input = held_input(card, &d, opts)?;
    Ok(CardCheck {
        name: card.name.clone(),
        missing: card.missing(),
        sources: card.cited(sources),
        curve,
        fit: a.fit,
        fit_to_rated: rated.map(|t| fit(&c, t)).transpose()?,
        damping: DampingFacts {
            from_loss,
            choice: used,
            zeta: a.zeta,
            gamma: 1.0 / (4.0 * a.zeta * a.zeta),
        },
        frequencies: Frequencies {
            natural_hz,
            required_hz: app.and_then(|a| a.resonance_required),
            critical_input_rpm: 30.0 * natural_hz,
            max_input_rpm: card.speed.as_ref().and_then(|s| s.max_input_rpm),
        },
        folds: Folds {
            three_alpha_gamma: summary.three_alpha_gamma,
            backlash: d.backlash,
            fold_backlash: (3.0 * d.k1 / d.k2).sqrt(),
        },
        summary,
        catalogue_law,
        held_input,
        friction,
    })
}

/// The grid of a card's load map: slow output-torque amplitudes (up to the rated torque) and
/// frequencies, log-spaced.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MapGrid {
    /// Amplitudes: `amplitudes` points from `t_am_max`/`amplitudes` to `t_am_max` \[N m\].
    pub t_am_max: f64,
    /// Number of amplitudes (≥ 1).
    pub amplitudes: usize,
    /// Lowest and highest frequency \[Hz\].
    pub hz: (f64, f64),
    /// Number of frequencies (≥ 1), log-spaced.
    pub frequencies: usize,
    /// Spacing of the coarse lattice the map is refined from ([`crate::refine`]), in
    /// points (1 to 64; 1: every point simulated).
    pub coarse: usize,
}

/// Lattice points per axis a load map is refined from by default ([`MapGrid::for_card`]): the
/// spacing is the axis's points over this, so a 300-point axis is simulated at every 8th point
/// first and a map of 36 or fewer points per axis at every point. Verdict regions of a load map
/// are bounded by the curves where a mechanism's threshold is crossed (the fast-slow domain's
/// edge, the response turning from overshoot to ringing, the sticking band's edge), each a wide
/// share of the map; 1/36 of an axis is 2.8 % of the amplitude range and 0.08 decade of the
/// default 0.01–10 Hz. A region narrower than the spacing, inside one block and touching none of
/// its computed points, would be missed: `coarse` 1 simulates every point.
pub const MAP_LATTICE: usize = 36;

impl MapGrid {
    /// The default grid of `card`: amplitudes up to its rated torque (T2 without a rating),
    /// 0.01–10 Hz, `n` points per axis, refined from a lattice of about [`MAP_LATTICE`] points
    /// per axis.
    pub fn for_card(card: &Card, n: usize) -> MapGrid {
        let c = card.curve();
        MapGrid {
            t_am_max: card.rated_torque().unwrap_or(c.t2),
            amplitudes: n,
            hz: (0.01, 10.0),
            frequencies: n,
            coarse: (n / MAP_LATTICE).max(1),
        }
    }

    /// Checks the grid.
    pub fn validate(&self) -> Result<()> {
        let bad = |name, value: f64, reason| {
            Err(crate::Error::InvalidOption {
                name,
                value,
                reason,
            })
        };
        if !(self.t_am_max.is_finite() && self.t_am_max > 0.0) {
            return bad("t_am_max", self.t_am_max, "must be finite and > 0");
        }
        let (lo, hi) = self.hz;
        if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && lo <= hi) {
            return bad("hz", lo, "must be a range 0 < LO <= HI");
        }
        for (name, n, max, reason) in [
            ("amplitudes", self.amplitudes, 1000, "must be 1 to 1000"),
            ("frequencies", self.frequencies, 1000, "must be 1 to 1000"),
            ("coarse", self.coarse, 64, "must be 1 to 64"),
        ] {
            if !(1..=max).contains(&n) {
                return bad(name, n as f64, reason);
            }
        }
        Ok(())
    }

    /// The amplitudes \[N m\].
    pub fn amplitude_values(&self) -> Vec<f64> {
        let n = self.amplitudes;
        (1..=n)
            .map(|i| self.t_am_max * i as f64 / n as f64)
            .collect()
    }

    /// The frequencies \[Hz\].
    pub fn frequency_values(&self) -> Vec<f64> {
        let (lo, hi, n) = (self.hz.0, self.hz.1, self.frequencies);
        if n == 1 {
            return vec![lo];
        }
        (0..n)
            .map(|i| lo * (hi / lo).powf(i as f64 / (n - 1) as f64))
            .collect()
    }
}

/// One point of a card's load map.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct MapPoint {
    /// Slow output-torque amplitude \[N m\].
    pub t_am: f64,
    /// Its frequency \[Hz\].
    pub frequency_hz: f64,
    /// The verdict there ([`super::design::judge`]).
    pub judgement: super::design::Judgement,
    /// The verdict with the card's friction law ([`super::friction::judge`]); `None` without a
    /// law, or where it could not be simulated.
    pub friction: Option<super::design::Judgement>,
    /// The verdict with the catalogue's piecewise-linear curve in place of the cubic fit, the
    /// rest of the drive the same ([`super::curve_law`]); `None` when not asked for, or where it
    /// could not be simulated (the reduced ω below [`super::design::MIN_SIMULATED_OMEGA`], or
    /// more steps than a search allows).
    pub catalogue: Option<super::design::Judgement>,
    /// The verdict with the wave generator held ([`super::design::judge_many_held`]).
    pub held: super::design::Judgement,
    /// Whether [`Self::judgement`] was computed (simulated or predicted); false: the point lies
    /// in a block of the coarse lattice whose computed points all agree, and takes their
    /// verdict ([`MapGrid::coarse`]).
    pub computed: bool,
    /// Whether [`Self::friction`] was computed (false also without a law).
    pub friction_computed: bool,
    /// Whether [`Self::catalogue`] was computed (false also when not asked for).
    pub catalogue_computed: bool,
    /// Whether [`Self::held`] was computed.
    pub held_computed: bool,
}

/// The verdict on the drive built from `card` (as [`check_card`] builds it, with `damping`) for
/// every amplitude and frequency of `grid`, amplitude-major, computed on all cores: with the
/// cubic fit (its wave generator free, and held: [`super::PhysicalParams::reduce_held`]), with
/// the catalogue's own curve ([`super::curve_law`], its knees rounded by the
/// given fraction of θ(T₁)), and with the card's friction law too, when it has one.
/// `catalogue_curve` `None` leaves the catalogue's verdict out (`None` at every point): the
/// piecewise law's knees make each response ring, and its simulation costs far more than the
/// fit's. The map is refined from a lattice of every [`MapGrid::coarse`]-th point
/// ([`crate::refine`]), each of the four verdicts on its own: a point is simulated where
/// its neighbours' verdicts differ, and otherwise takes theirs ([`MapPoint::computed`]).
pub fn load_map(
    card: &Card,
    sources: &BTreeMap<String, Source>,
    damping: DampingChoice,
    grid: &MapGrid,
    opts: &BurstOptions,
    catalogue_curve: Option<f64>,
) -> Result<Vec<MapPoint>> {
    card.validate(sources)?;
    grid.validate()?;
    catalogue_curve.map_or(Ok(()), super::curve_law::check_rounding)?;
    let zeta = chosen_zeta(damping, &loss_damping(card, sources));
    let d = assemble(card, None, zeta)?.drive;
    let law = card.friction_law()?;
    let (amps, freqs) = (grid.amplitude_values(), grid.frequency_values());
    let at = |i: usize, j: usize| super::PhysicalParams {
        t_am: amps[i],
        omega: std::f64::consts::TAU * freqs[j],
        ..d
    };
    // each verdict refined on its own: one model's boundaries cost the others nothing
    let fit = refined(grid, &at, |ds| super::design::judge_many(ds, opts))?;
    let held = refined(grid, &at, |ds| super::design::judge_many_held(ds, opts))?;
    let friction = law
        .map(|law| {
            refined(grid, &at, |ds| {
                ds.par_iter()
                    .map(
                        |d| Ok(super::friction::judge(d, &law, opts)?.map(|o| o.outcome.judgement)),
                    )
                    .collect()
            })
        })
        .transpose()?;
    let catalogue = catalogue_curve
        .map(|rounding| {
            refined(grid, &at, |ds| {
                ds.par_iter()
                    .map(|d| {
                        let m = super::curve_law::model(card, d, rounding)?;
                        Ok(super::design::judge_model(&m, opts)?.map(|(o, _)| o.judgement))
                    })
                    .collect()
            })
        })
        .transpose()?;
    let of = |c: &Option<crate::refine::Refined<Option<Judgement>>>, k: usize| {
        c.as_ref()
            .map_or((None, false), |c| (c.values[k], c.computed[k]))
    };
    Ok((0..amps.len() * freqs.len())
        .map(|k| {
            let (friction, friction_computed) = of(&friction, k);
            let (catalogue, catalogue_computed) = of(&catalogue, k);
            MapPoint {
                t_am: amps[k / freqs.len()],
                frequency_hz: freqs[k % freqs.len()],
                judgement: fit.values[k],
                friction,
                catalogue,
                held: held.values[k],
                computed: fit.computed[k],
                friction_computed,
                catalogue_computed,
                held_computed: held.computed[k],
            }
        })
        .collect())
}

/// One verdict of [`load_map`] over `grid`, refined ([`crate::refine`]): `judge` gives
/// the verdicts of many drives, `at(i, j)` is the drive at amplitude `i` and frequency `j`.
fn refined<V: Clone + PartialEq>(
    grid: &MapGrid,
    at: &impl Fn(usize, usize) -> super::PhysicalParams,
    judge: impl Fn(&[super::PhysicalParams]) -> Result<Vec<V>>,
) -> Result<crate::refine::Refined<V>> {
    crate::refine::refine(grid.amplitudes, grid.frequencies, grid.coarse, |cells| {
        judge(&cells.iter().map(|&(i, j)| at(i, j)).collect::<Vec<_>>())
    })
}
