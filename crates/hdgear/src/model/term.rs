//! What a term is: the [`Term`] trait every torque of a drive model implements (its value,
//! derivatives, Taylor rows, parameters and text in one place), and the vocabulary the trait
//! speaks in ([`ParamInfo`], [`Domain`], [`StateInfo`], [`Side`]). The list of every term hdgear
//! has is [`super::terms::AnyTerm`].

pub use super::jet::MAX_ROWS;
use super::jet::{Jet, Lanes};
use super::relation::Relation;
use crate::error::{Error, Result};
use serde::Serialize;

/// A term's own Taylor rows (the coefficients of its intermediate functions, kept from order to
/// order by [`Term::taylor`]): the Taylor stepper's, which keeps one set per term.
pub use crate::integrate::taylor::Scratch;

/// The most numbers a term's copy on lanes reads ([`Term::lane_values`]).
pub const LANE_PARAMS: usize = 6;

/// A term's own Taylor rows on [`Lanes`] ([`Term::taylor_lanes`]): a [`Scratch`] per lane.
pub type LaneRows = [[Lanes; MAX_ROWS]; crate::integrate::taylor::SCRATCH_ROWS];

/// Where a parameter may lie.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Domain {
    /// Any finite value.
    Any,
    /// A finite value > 0.
    Positive,
    /// A finite value ≥ 0.
    NonNegative,
    /// A value in [0, 1].
    Fraction,
    /// A whole number from 1 to 4 (an exponent a Taylor recurrence takes as repeated products).
    Exponent,
    /// A whole number from 1 to [`MAX_LINE`] (a line of a multisine: each costs a sine and a
    /// cosine per step).
    Line,
}

/// The highest line a multisine may have ([`Domain::Line`]): beyond it one step's lines would
/// cost far more than the rest of the model (the benchmark multisines have a few thousand).
pub const MAX_LINE: f64 = 1e4;

impl Domain {
    /// The rule in words, as error messages and `hdgear model` show it.
    pub fn text(self) -> &'static str {
        match self {
            Domain::Any => "finite",
            Domain::Positive => "> 0",
            Domain::NonNegative => "≥ 0",
            Domain::Fraction => "[0, 1]",
            Domain::Exponent => "1,2,3,4",
            Domain::Line => "1 … 10⁴",
        }
    }

    /// Checks `value` of the parameter `name` (an error names both).
    pub fn check(self, name: &str, value: f64) -> Result<()> {
        let ok = value.is_finite()
            && match self {
                Domain::Any => true,
                Domain::Positive => value > 0.0,
                Domain::NonNegative => value >= 0.0,
                Domain::Fraction => (0.0..=1.0).contains(&value),
                Domain::Exponent => (1.0..=4.0).contains(&value) && value.fract() == 0.0,
                Domain::Line => (1.0..=MAX_LINE).contains(&value) && value.fract() == 0.0,
            };
        if ok {
            Ok(())
        } else {
            Err(Error::InvalidParameter {
                name: name.to_string(),
                value,
                reason: match self {
                    Domain::Any => "must be finite",
                    Domain::Positive => "must be finite and > 0",
                    Domain::NonNegative => "must be finite and ≥ 0",
                    Domain::Fraction => "must lie in [0, 1]",
                    Domain::Exponent => "must be a whole number from 1 to 4",
                    Domain::Line => "must be a whole number from 1 to 10000",
                },
            })
        }
    }
}

/// One parameter of a term: the one definition its name, symbol, meaning, domain and default are
/// read from.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ParamInfo {
    /// The name users write (flag, TOML key, keyword argument).
    pub name: &'static str,
    /// Its symbol in the equation's text.
    pub symbol: &'static str,
    /// Its symbol in LaTeX.
    pub latex: &'static str,
    /// What it is.
    pub meaning: &'static str,
    /// Where it may lie.
    pub domain: Domain,
    /// Its default value.
    pub default: f64,
    /// What it is in SI terms (the scale it is measured on).
    pub si: &'static str,
}

/// A term's internal state: its name (a state of the model beside x and x') and what it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct StateInfo {
    /// The state's name in output columns and `hdgear model`.
    pub name: &'static str,
    /// What it is.
    pub meaning: &'static str,
}

/// The piece of a switching term's law: sgn x' (`v`) and sgn z of its internal state (`z`)
/// fixed to +1 or −1, or 0 to read each sign from the state itself.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Side {
    /// sgn x' on the piece (0: read from x').
    pub v: f64,
    /// sgn z on the piece (0: read from z).
    pub z: f64,
}

/// The sign on a piece: `side` where it is fixed (±1), else the sign of `value` (0 at 0).
pub fn piece_sign(side: f64, value: f64) -> f64 {
    if side != 0.0 {
        side
    } else if value == 0.0 {
        0.0
    } else {
        value.signum()
    }
}

/// A torque contribution T(x, x', z) to the left-hand side of the drive's equation, z the
/// term's own internal state where it has one ([`Term::STATE`], with z' = [`Term::rate`]): the
/// one place its value, derivatives, Taylor recurrences, parameters and text are defined; every
/// machine ([`super::Model`]) is derived from these. A stateless term ignores z (0).
pub trait Term: Copy {
    /// The term's kind: its table name in scenario files (`[friction]`).
    const KIND: &'static str;
    /// What the term models, in a line.
    const ABOUT: &'static str;
    /// Its parameters, in the order of [`Term::values`].
    const PARAMS: &'static [ParamInfo];
    /// Rules between its parameters beyond their domains (none, the default).
    const RELATIONS: &'static [Relation] = &[];
    /// Its internal state, if it has one (`None`, the default: T depends on x and x' only).
    const STATE: Option<StateInfo> = None;
    /// Whether its law is not analytic across x' = 0 (sgn x', |x'|): a switching integration
    /// ([`super::switching`]) then cuts steps there.
    const SWITCHES_AT_REST: bool = false;
    /// Whether its law is not analytic across z = 0 (|z|): steps are cut there too.
    const SWITCHES_AT_ZERO_STATE: bool = false;
    /// Whether it is a load that acts whatever the motion, of mean 0 (a dither, a kinematic
    /// error, a multisine): it has no static part, so the fast subsystem's equilibria leave it
    /// out ([`super::Model::static_torque`]).
    const LOAD: bool = false;
    /// Whether its torque at rest depends on the slow load's phase (a scheduled stiffness,
    /// [`super::schedule::Scheduled`]): its fast subsystem's equilibria then move with a, so
    /// there is no static torque of x alone ([`super::Model::static_torque`] holds it at a = 0).
    const SCHEDULED: bool = false;
    /// The term with these parameter values (in [`Term::PARAMS`] order; the caller checks
    /// their count and domains).
    fn from_values(values: &[f64]) -> Self;
    /// Its parameter values, in [`Term::PARAMS`] order.
    fn values(&self) -> &[f64];
    /// T(x, v, z).
    fn torque(&self, x: f64, v: f64, z: f64) -> f64;
    /// (∂T/∂x, ∂T/∂v, ∂T/∂z).
    fn gradient(&self, x: f64, v: f64, z: f64) -> [f64; 3];
    /// ∂T/∂p for parameter `i` of [`Term::PARAMS`].
    fn param_derivative(&self, i: usize, x: f64, v: f64, z: f64) -> f64;
    /// Row k of T's normalised Taylor coefficients along a solution whose x, v and z rows
    /// 0..=k are given; `rows` keeps the term's own intermediate rows from order to order
    /// (called for k = 0, 1, 2, … in turn with the same `rows`, each after
    /// [`Term::rate_taylor`] of the same k).
    fn taylor(&self, k: usize, x: &[f64], v: &[f64], z: &[f64], rows: &mut Scratch) -> f64;
    /// Whether the kind has [`Term::taylor_lanes`] (the tests hold the two together).
    const ON_LANES: bool = false;
    /// [`Term::taylor`] of [`LANES`](crate::batch::LANES) terms of this kind at once, for a
    /// kind whose recurrence is written once over [`Jet`] numbers: value i of lane l's
    /// [`Term::lane_values`] in `values[i].0[l]`, x's, v's and z's rows on lanes, the terms' own
    /// rows in `rows`. Each lane gets what [`Term::taylor`] gives its own term, to the bit.
    /// `None` (the default): the kind has no such copy, and a batch of it runs term by term.
    fn taylor_lanes(
        _values: &[Lanes],
        _k: usize,
        _x: &[Lanes],
        _v: &[Lanes],
        _z: &[Lanes],
        _rows: &mut LaneRows,
    ) -> Option<Lanes> {
        None
    }
    /// [`Term::rate_taylor`] on lanes, as [`Term::taylor_lanes`] takes them (called before it
    /// for the same k): for a kind on lanes with a state. 0, the default, for a stateless kind.
    fn rate_taylor_lanes(
        _values: &[Lanes],
        _k: usize,
        _x: &[Lanes],
        _v: &[Lanes],
        _z: &[Lanes],
        _rows: &mut LaneRows,
    ) -> Lanes {
        Lanes::splat(0.0)
    }
    /// The numbers a copy on lanes ([`Term::taylor_lanes`]) reads from this term: its values
    /// (the default), or for a switching term on its piece ([`Term::directed`]) the values with
    /// the piece's signs folded in. At most [`LANE_PARAMS`] of them.
    fn lane_values(&self) -> [f64; LANE_PARAMS] {
        let mut out = [0.0; LANE_PARAMS];
        for (o, &v) in out.iter_mut().zip(self.values()) {
            *o = v;
        }
        out
    }
    /// What a copy on lanes takes as the same on every lane (an exponent its recurrence
    /// unrolls): terms of one kind run on lanes together only where it agrees. 0, the default.
    fn lane_shape(&self) -> usize {
        0
    }
    /// For a term whose state is a phase turning at a constant rate (a dither's, a wave
    /// generator's, a multisine's): the index of that rate among its parameters. The defaults of
    /// the state's equation z' = p_i (its rate, derivatives and Taylor rows) follow from it.
    const PHASE_RATE: Option<usize> = None;
    /// z' = r(x, v, z), the internal state's equation (0 for a stateless term; the phase rate
    /// for a phase, [`Term::PHASE_RATE`]).
    fn rate(&self, _x: f64, _v: f64, _z: f64) -> f64 {
        Self::PHASE_RATE.map_or(0.0, |i| self.values()[i])
    }
    /// (∂r/∂x, ∂r/∂v, ∂r/∂z).
    fn rate_gradient(&self, _x: f64, _v: f64, _z: f64) -> [f64; 3] {
        [0.0; 3]
    }
    /// ∂r/∂p for parameter `i`.
    fn rate_param_derivative(&self, i: usize, _x: f64, _v: f64, _z: f64) -> f64 {
        if Self::PHASE_RATE == Some(i) {
            1.0
        } else {
            0.0
        }
    }
    /// Row k of r's Taylor coefficients (called before [`Term::taylor`] of the same k, with
    /// the same `rows`).
    #[inline(always)]
    fn rate_taylor(&self, k: usize, _x: &[f64], _v: &[f64], _z: &[f64], _r: &mut Scratch) -> f64 {
        match Self::PHASE_RATE {
            Some(i) if k == 0 => self.values()[i],
            _ => 0.0,
        }
    }
    /// The term in the equation's text (`x'` the velocity), with a leading sign.
    fn text(&self) -> String;
    /// The term in LaTeX, with a leading sign.
    fn latex(&self) -> String;
    /// Its state's equation as text (`z' = …`), for a term with a state.
    fn rate_text(&self) -> Option<String> {
        None
    }
    /// Its state's equation in LaTeX, for a term with a state.
    fn rate_latex(&self) -> Option<String> {
        None
    }
    /// Whether [`Term::step_limit`] may shorten a step (the model skips the check otherwise).
    const LIMITS_STEPS: bool = false;
    /// The longest step, at most `h`, on which the term's own intermediate series (its `rows`
    /// after row `order`) are accurate or the term negligible (below `negligible`); `h`, the
    /// default, for terms whose series the state's rows already show.
    fn step_limit(&self, _rows: &Scratch, _order: usize, h: f64, _negligible: f64) -> f64 {
        h
    }
    /// [`Term::step_limit`] of [`LANES`](crate::batch::LANES) terms of this kind at once, for a
    /// kind on lanes ([`Term::ON_LANES`]) whose limit is written once over [`Jet`] numbers:
    /// parameters, rows, steps and thresholds lane by lane, as [`Term::taylor_lanes`] takes
    /// them. Each lane's limit is its term's [`Term::step_limit`] to ~1e-9 ([`Jet::ln`]). `h`,
    /// the default, for kinds that do not limit steps.
    fn step_limit_lanes(
        _values: &[Lanes],
        _rows: &LaneRows,
        _order: usize,
        h: Lanes,
        _negligible: Lanes,
    ) -> Lanes {
        h
    }
    /// The static band of a term that sticks at x' = 0 (Coulomb friction): x' stays 0 while the
    /// rest of the torque is within ± this value. `None` (the default) for a term without
    /// sticking.
    fn breakaway(&self) -> Option<f64> {
        None
    }
    /// The term on one piece of its law ([`Side`]). A smooth term ignores it (the default).
    fn directed(self, _side: Side) -> Self {
        self
    }
    /// Its internal state in a rest at twist x that the term has reached at rest (0, the
    /// default: the virgin state of a memory term; x for a washout filter, which follows x).
    fn state_at_rest(&self, _x: f64) -> f64 {
        0.0
    }
    /// The elastic twist's rate x' of a drive at rest with the term's state at rest: 0 (the
    /// default), or −e' for a kinematic error e, whose total twist x + e is then at rest
    /// ([`super::mesh::KinematicError`]).
    fn twist_rate_at_rest(&self) -> f64 {
        0.0
    }
    /// A sinusoidal torque the term applies whatever the motion, of amplitude D at the angular
    /// frequency Ω_d (its phase the term's state), as [D, Ω_d]: a dither
    /// ([`super::control::Dither`]) or a kinematic error ([`super::mesh::KinematicError`]), whose
    /// ripple the burst verdict averages out. `None` (the default) for a term of the motion.
    fn dither(&self) -> Option<[f64; 2]> {
        None
    }
    /// The highest angular frequency of a load that acts whatever the motion ([`Term::LOAD`]): its
    /// [`Term::dither`]'s Ω by default, 0 for a term of the motion.
    fn load_frequency(&self) -> f64 {
        self.dither().map_or(0.0, |[_, w]| w)
    }
    /// A delayed feedback's [K, τ_d]: its state is the twist τ_d ago, which only the run's history
    /// gives ([`super::delayed::Delayed`]). `None` (the default) for every other term.
    fn delay(&self) -> Option<[f64; 2]> {
        None
    }
}
