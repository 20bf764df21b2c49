//! The two-inertia drive as a [`System`], with friction at its bearings ([`Bearings`]).
//!
//! **Why one file.** The two-inertia system's right-hand side, Jacobian and Taylor coefficients
//! must agree term by term, bearings included; they are written beside each other so that they are
//! read and changed together.

use crate::error::{Error, Result};
use crate::integrate::System;
use crate::integrate::taylor::{MAX_ORDER, Workspace};
use crate::model::terms::{AnyTerm, Damping, Friction, Spring, Stribeck, Term};
use crate::model::{MAX_TERMS, Model};
use serde::Serialize;

/// Friction where the reduction to one equation does not hold: at the output bearing, on the
/// output rate θo', and at the wave generator, on the input rate θi' (torques in N m, rates in
/// rad/s). Such friction acts on one inertia alone, so it moves the rigid-body mode and the twist
/// together: only the two-inertia model ([`Physical`]) carries it. Friction across the
/// compliance, on the twist rate θ', is the reduced model's ([`super::friction`]).
///
/// Each is a term of velocity alone, analytic on the step ([`BEARING_KINDS`]: the smooth
/// Coulomb and the regularised Stribeck laws), with its parameters in SI units.
///
/// ```
/// use hdgear::model::terms::AnyTerm;
/// use hdgear::physical::model::Bearings;
/// // 0.8 N m of Coulomb, 1.2 N m of breakaway friction at the output bearing
/// let output = AnyTerm::new("stribeck", &[0.8, 1.2, 0.05, 0.01, 1e-3]).unwrap();
/// let b = Bearings::new(Some(output), None).unwrap();
/// assert_eq!(b.torques(0.0, 0.0), [0.0, 0.0]);
/// assert!(Bearings::new(None, Some(AnyTerm::new("coulomb", &[0.8, 1.2, 0.05, 0.0]).unwrap())).is_err());
/// ```
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Bearings {
    /// Friction torque on θo', opposing the output's rotation.
    pub output: Option<AnyTerm>,
    /// Friction torque on θi', opposing the input's (the wave generator's) rotation.
    pub input: Option<AnyTerm>,
}

/// The kinds of term a bearing takes: friction laws of the velocity alone, analytic along a
/// step (a switched law's sign would need the piecewise integration of the reduced model).
pub const BEARING_KINDS: [&str; 2] = [Friction::KIND, Stribeck::KIND];

/// What a parameter of a bearing's law ([`BEARING_KINDS`]) measures, in SI units.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub enum Quantity {
    /// A torque \[N m\].
    Torque,
    /// A rate \[rad/s\].
    Rate,
    /// A viscous coefficient \[N m s/rad\].
    Viscous,
}

impl Quantity {
    /// Its unit as FMI and Modelica write it.
    pub fn unit(self) -> &'static str {
        match self {
            Quantity::Torque => "N.m",
            Quantity::Rate => "rad/s",
            Quantity::Viscous => "N.m.s/rad",
        }
    }
}

/// What each parameter of a bearing's law measures, in the order of its values; `None` for a
/// kind that is not one of [`BEARING_KINDS`].
///
/// ```
/// use hdgear::physical::model::{Quantity, law_quantities};
/// assert_eq!(law_quantities("friction"), Some(&[Quantity::Torque, Quantity::Rate][..]));
/// assert_eq!(law_quantities("lugre"), None);
/// ```
pub fn law_quantities(kind: &str) -> Option<&'static [Quantity]> {
    use Quantity::{Rate, Torque, Viscous};
    if kind == Friction::KIND {
        Some(&[Torque, Rate])
    } else if kind == Stribeck::KIND {
        Some(&[Torque, Torque, Rate, Viscous, Rate])
    } else {
        None
    }
}

/// What a law on `side` is called in an error: a bearing's (`output`, `input`), or the friction
/// across the compliance (`twist`, [`Physical::with_twist_friction`]).
fn law_of(side: &str) -> &'static str {
    if side == "twist" {
        "friction across the compliance"
    } else {
        "bearing friction"
    }
}

impl Bearings {
    /// Checks that each term is one of [`BEARING_KINDS`].
    pub fn new(output: Option<AnyTerm>, input: Option<AnyTerm>) -> Result<Bearings> {
        for (side, term) in [("output", output), ("input", input)] {
            if let Some(t) = term.filter(|t| !BEARING_KINDS.contains(&t.kind())) {
                return Err(Error::InvalidInput {
                    what: "bearing friction",
                    text: format!("{side}: {}", t.kind()),
                    reason: format!("a bearing takes {}", BEARING_KINDS.join(" or ")),
                });
            }
        }
        Ok(Bearings { output, input })
    }

    /// A bearing's law from its kind (one of [`BEARING_KINDS`]) and its values by name, in SI
    /// units (N m, rad/s, N m s/rad), each of the law's parameters named once: the terms'
    /// defaults are dimensionless and mean nothing here. What a scenario file's
    /// `[bearings.output.stribeck]` table and the CLI's `--output-bearing stribeck:fc=…` give.
    /// Errors name the side, the law and the key; the values' domains are the term's own
    /// ([`AnyTerm::new`]).
    ///
    /// ```
    /// use hdgear::physical::model::Bearings;
    /// let law = Bearings::law("output", "friction", [("fc", 0.8), ("vs", 1e-3)]).unwrap();
    /// assert_eq!(law.kind(), "friction");
    /// // vs missing: no default in SI units
    /// assert!(Bearings::law("output", "friction", [("fc", 0.8)]).is_err());
    /// ```
    pub fn law<'a>(
        side: &str,
        kind: &str,
        named: impl IntoIterator<Item = (&'a str, f64)>,
    ) -> Result<AnyTerm> {
        let invalid = |reason: String| Error::InvalidInput {
            what: law_of(side),
            text: format!("{side}: {kind}"),
            reason,
        };
        if !BEARING_KINDS.contains(&kind) {
            return Err(invalid(format!(
                "the law is {}",
                BEARING_KINDS.join(" or ")
            )));
        }
        let named: Vec<(&str, f64)> = named.into_iter().collect();
        let (kind, values) = crate::model::tables::term_values(kind, named.iter().copied())
            .map_err(|e| invalid(e.to_string()))?;
        let params = AnyTerm::params_of(kind).unwrap_or_default();
        for p in params {
            match named.iter().filter(|(k, _)| *k == p.name).count() {
                1 => {}
                0 => {
                    return Err(invalid(format!(
                        "{} missing (a bearing's law names all of {}, in SI units)",
                        p.name,
                        params.iter().map(|q| q.name).collect::<Vec<_>>().join(", ")
                    )));
                }
                _ => return Err(invalid(format!("{} given twice", p.name))),
            }
        }
        AnyTerm::new(kind, &values)
    }

    /// [`Bearings::law`] from the text `kind:key=value,key=value…` (the CLI's
    /// `--output-bearing` and `--input-bearing`).
    ///
    /// ```
    /// use hdgear::physical::model::Bearings;
    /// let law = Bearings::parse_law("input", "stribeck:fc=0.05,fs=0.08,vst=0.5,cv=1e-4,vr=0.01").unwrap();
    /// assert_eq!(law.values(), [0.05, 0.08, 0.5, 1e-4, 0.01]);
    /// assert!(Bearings::parse_law("input", "stribeck:fc=a").is_err());
    /// ```
    pub fn parse_law(side: &str, text: &str) -> Result<AnyTerm> {
        let invalid = |reason: &str| Error::InvalidInput {
            what: law_of(side),
            text: format!("{side}: {text}"),
            reason: reason.into(),
        };
        let (kind, list) = text
            .split_once(':')
            .ok_or_else(|| invalid("expected LAW:KEY=VALUE,… (e.g. friction:fc=0.5,vs=1e-3)"))?;
        let mut named = Vec::new();
        for pair in list.split(',') {
            let value = pair
                .split_once('=')
                .and_then(|(k, v)| Some((k.trim(), v.trim().parse::<f64>().ok()?)))
                .ok_or_else(|| invalid("each of KEY=VALUE,… a name and a number"))?;
            named.push(value);
        }
        Bearings::law(side, kind.trim(), named)
    }

    /// The friction torques (output, input) at the rates θo', θi'.
    pub fn torques(&self, out_rate: f64, in_rate: f64) -> [f64; 2] {
        let [o, i] = self.sides();
        let at = |t: Option<AnyTerm>, v: f64| t.map_or(0.0, |t| t.torque(0.0, v, 0.0));
        [at(o, out_rate), at(i, in_rate)]
    }

    /// The two laws in the order every pair of this module follows: (output, input), as the
    /// rates (θo', θi'), the inertias (J_o, J_i) and the workspace's rows 0 and 1.
    fn sides(&self) -> [Option<AnyTerm>; 2] {
        [self.output, self.input]
    }

    /// Whether either bearing has a law.
    pub fn any(&self) -> bool {
        self.sides().iter().any(Option::is_some)
    }
}

/// The physical two-inertia drive (guide: the model and its parameters), integrated in well-conditioned coordinates.
///
/// Internal state z = [θ, T_c·θ', θo, T_c·θo'] with physical time t \[s\], where θ = θo − θi/N is
/// the relative torsion and T_c = J_eq/C. Integrating θ rather than θi avoids computing the small
/// torsion as the difference of two large rotations (the rigid-body swing under a slow
/// disturbance can exceed the torsion by many orders of magnitude), and scaling the rates by T_c
/// gives every component the unit of an angle, so one absolute tolerance fits all. The
/// accelerations are the two-inertia equations themselves:
///
/// θo'' = (T_m + T_am sin Ωt − T_t − F_o(θo')) / J_o,
/// θi'' = (−T_m/N + T_t/N − F_i(θi')) / J_i,  θ'' = θo'' − θi''/N,
///
/// F_o and F_i the friction at the bearings ([`Bearings`], none by default) and T_t the torque
/// across the compliance: a [`Model`]'s terms ([`Physical::twist`]) in the drive's own units,
/// x = θ \[rad\], x' = dθ/dτ = T_c·θ' (τ = t/T_c) and torques in U = C²/J_eq \[N m\]
/// ([`Physical::unit`]). The drive's own law is the model's unit damping (C·θ' = U·x') and its
/// spring ([`Spring`], (k1 + k2θ²)(θ − φ) = U·(k1/U + (k2/U)·x²)(x − φ)); friction or
/// hysteresis across the compliance are more terms of it ([`Physical::with_twist`]). Its fields
/// are read through methods: T_c, U and the reciprocals are derived from the drive when it is
/// built.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Physical {
    /// The drive.
    d: super::PhysicalParams,
    /// T_c = J_eq/C \[s\].
    t_c: f64,
    /// The terms of the torque across the compliance, in the drive's units.
    twist: Model,
    /// U = C²/J_eq \[N m\], the twist model's unit of torque.
    unit: f64,
    /// The twist model's spring (its slot [`SPRING_SLOT`]), called directly where the model
    /// holds nothing else: its rows are then the model's to the bit without the dispatch over
    /// every kind of term, which doubled the drive's time.
    spring: Spring,
    /// Whether the twist model holds terms beyond its damping and spring.
    extra: bool,
    /// Whether a term of the twist model limits steps ([`AnyTerm::limits_steps`]).
    twist_limits: bool,
    /// Friction at the output bearing and the wave generator.
    bearings: Bearings,
    /// Friction across the compliance as given in SI units ([`Physical::with_twist_friction`]).
    twist_friction: Option<AnyTerm>,
    /// The reciprocals the equations multiply by, so that no division waits on a Taylor row.
    inv: Reciprocals,
    /// Torques a host applies, held constant (motor, load) \[N m\] ([`Physical::with_inputs`]).
    inputs: [f64; 2],
}

/// The factors the equations multiply by, so that no division waits on a Taylor row: 1/T_c,
/// 1/U (SI torques into the twist's unit), 1/N, and with s = T_c·U the scaled reciprocals s/J_o,
/// s/J_i, s/(N·J_i), which turn torques in U straight into the rates of the scaled velocities
/// T_c·θ'' and T_c·θo'' (one product fewer on each row's chain).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Reciprocals {
    t_c: f64,
    unit: f64,
    j_out: f64,
    j_in: f64,
    n_j_in: f64,
    ratio: f64,
}

/// The [`crate::integrate::Workspace`] sets the bearings' laws keep their rows in (output,
/// input): the last two, after the twist model's terms (at most [`TWIST_TERMS`] of them).
const BEARING_SETS: [usize; 2] = [MAX_TERMS - 2, MAX_TERMS - 1];

/// The twist model's slot of its damping ([`Model::damped`]'s).
const DAMPING_SLOT: usize = 0;

/// The twist model's slot of its spring.
const SPRING_SLOT: usize = 1;

/// The most terms the twist model holds (its damping and spring included): the sets of the
/// stepper's workspace the two bearings leave.
pub const TWIST_TERMS: usize = MAX_TERMS - 2;

impl Physical {
    /// Wraps a (validated) drive.
    pub fn new(d: super::PhysicalParams) -> Self {
        let t_c = d.j_eq() / d.c_eq;
        let unit = d.c_eq / t_c;
        let spring = Spring::from_values(&[d.k1 / unit, d.k2 / unit, d.backlash]);
        let twist = Model::damped(0.0, 0.0, 1.0)
            .with_term(AnyTerm::Spring(spring))
            .expect("a model of the damping alone has room for a spring");
        Physical {
            t_c,
            d,
            twist,
            unit,
            spring,
            extra: false,
            twist_limits: false,
            bearings: Bearings::default(),
            twist_friction: None,
            inv: Reciprocals {
                t_c: 1.0 / t_c,
                unit: 1.0 / unit,
                j_out: t_c * unit / d.j_out,
                j_in: t_c * unit / d.j_in,
                n_j_in: t_c * unit / (d.ratio * d.j_in),
                ratio: 1.0 / d.ratio,
            },
            inputs: [0.0; 2],
        }
    }

    /// The drive with torques applied from outside, held constant until changed (what a
    /// co-simulation host gives over one communication step, [`super::cosim`]): `motor` \[N m\]
    /// on the input inertia in θi's sense, `load` \[N m\] on the output inertia in θo's sense (the
    /// sense of T_m). They add to T_m and T_am sin Ωt; zero (the default) is the drive alone, to
    /// the bit.
    ///
    /// ```
    /// use hdgear::physical::{PhysicalParams, model::Physical};
    /// let d = PhysicalParams { j_in: 1e-4, j_out: 1.0, ratio: 50.0, k1: 2e3, k2: 1e9,
    ///     backlash: 1e-3, c_eq: 5.0, t_m: 0.0, t_am: 0.0, omega: 1.0 };
    /// let sys = Physical::new(d).with_inputs(0.0, 2.0);
    /// assert_eq!(sys.inputs(), [0.0, 2.0]);
    /// ```
    pub fn with_inputs(mut self, motor: f64, load: f64) -> Physical {
        self.inputs = [motor, load];
        self
    }

    /// The torques applied from outside (motor, load) \[N m\] ([`Physical::with_inputs`]).
    pub fn inputs(&self) -> [f64; 2] {
        self.inputs
    }

    /// The drive with friction at its bearings.
    pub fn with_bearings(d: super::PhysicalParams, bearings: Bearings) -> Self {
        Physical {
            bearings,
            ..Physical::new(d)
        }
    }

    /// The drive with one more term across the compliance, its parameters in the drive's units
    /// ([`Physical`]: x = θ in rad, x' = T_c·θ', torques over [`Physical::unit`]): a term of the
    /// twist and its rate alone and analytic along a step, or with its kinks located by its
    /// step limit (friction laws regularised at a stated speed, the catalogue's piecewise
    /// curve). Refused, naming the kind, for a term with an internal state or a switched law
    /// (those need the reduced model's piecewise integration), a load or a scheduled law, one
    /// whose parameter names the twist's terms take already, and beyond [`TWIST_TERMS`] terms.
    ///
    /// ```
    /// use hdgear::model::terms::AnyTerm;
    /// use hdgear::physical::{PhysicalParams, model::Physical};
    /// let d = PhysicalParams { j_in: 1e-4, j_out: 1.0, ratio: 50.0, k1: 2e3, k2: 1e9,
    ///     backlash: 1e-3, c_eq: 5.0, t_m: 1.0, t_am: 0.5, omega: 1.0 };
    /// let sys = Physical::new(d);
    /// // 0.1 N m of friction across the compliance, regularised over 1e-3 rad/s of twist rate
    /// let law = AnyTerm::new("friction", &[0.1 / sys.unit(), 1e-3 * sys.t_c()]).unwrap();
    /// let with = sys.with_twist(law).unwrap();
    /// assert_eq!(with.twist().terms().count(), 3);
    /// assert!(sys.with_twist(AnyTerm::new("coulomb", &[0.1, 0.2, 1.0, 0.0]).unwrap()).is_err());
    /// ```
    pub fn with_twist(mut self, term: AnyTerm) -> Result<Physical> {
        let refuse = |reason: &str| Error::InvalidInput {
            what: "term across the compliance",
            text: term.kind().to_string(),
            reason: reason.into(),
        };
        if term.state().is_some() || term.switches_at_rest() || term.switches_at_zero_state() {
            return Err(refuse(
                "the two-inertia model takes terms of the twist and its rate alone, analytic on \
                 a step (a state of its own or a switched law needs the reduced model)",
            ));
        }
        if term.is_load() || term.is_scheduled() || term.delay().is_some() {
            return Err(refuse(
                "the two-inertia model's loads are T_m and T_am sin Ωt (a load or a scheduled \
                 law needs the reduced model)",
            ));
        }
        if self.twist.terms().count() == TWIST_TERMS {
            return Err(refuse(&format!(
                "the twist holds at most {TWIST_TERMS} terms, its damping and spring included"
            )));
        }
        self.twist = self.twist.with_term(term)?;
        self.extra = true;
        self.twist_limits = self.twist.terms().any(AnyTerm::limits_steps);
        Ok(self)
    }

    /// [`Physical::with_twist`] for a friction law on the twist rate θ' in SI units, as a
    /// bearing's ([`Bearings::law`], one of [`BEARING_KINDS`]: torques in N m, rates in rad/s,
    /// viscous coefficients in N m s/rad), converted into the drive's units: torques over U
    /// ([`Physical::unit`]), rates times T_c, viscous coefficients over C (C·θ' = U·T_c·θ').
    /// Refused, naming the kind, for any other law, and for a second friction law.
    ///
    /// ```
    /// use hdgear::physical::model::{Bearings, Physical};
    /// use hdgear::physical::PhysicalParams;
    /// let d = PhysicalParams { j_in: 1e-4, j_out: 1.0, ratio: 50.0, k1: 2e3, k2: 1e9,
    ///     backlash: 1e-3, c_eq: 5.0, t_m: 1.0, t_am: 0.5, omega: 1.0 };
    /// let sys = Physical::new(d);
    /// let law = Bearings::parse_law("twist", "friction:fc=0.1,vs=1e-3").unwrap();
    /// let with = sys.with_twist_friction(law).unwrap();
    /// // 0.1 N m at a twist rate far above 1e-3 rad/s
    /// assert!((with.twist_torque(1e-3, 1.0) - sys.twist_torque(1e-3, 1.0) - 0.1).abs() < 1e-12);
    /// assert_eq!(with.twist_friction(), Some(law));
    /// ```
    pub fn with_twist_friction(self, law: AnyTerm) -> Result<Physical> {
        let Some(quantities) = law_quantities(law.kind()) else {
            return Err(Error::InvalidInput {
                what: "friction across the compliance",
                text: law.kind().to_string(),
                reason: format!("the twist's friction is {}", BEARING_KINDS.join(" or ")),
            });
        };
        let scales = quantities.iter().map(|q| match q {
            Quantity::Torque => 1.0 / self.unit,
            Quantity::Rate => self.t_c,
            Quantity::Viscous => 1.0 / self.d.c_eq,
        });
        let values: Vec<f64> = law
            .values()
            .iter()
            .zip(scales)
            .map(|(v, s)| v * s)
            .collect();
        let mut with = self.with_twist(AnyTerm::new(law.kind(), &values)?)?;
        with.twist_friction = Some(law);
        Ok(with)
    }

    /// Friction across the compliance as given in SI units, if any
    /// ([`Physical::with_twist_friction`]).
    pub fn twist_friction(&self) -> Option<AnyTerm> {
        self.twist_friction
    }

    /// The drive.
    pub fn drive(&self) -> &super::PhysicalParams {
        &self.d
    }

    /// T_c = J_eq/C \[s\], the time unit of the reduced model.
    pub fn t_c(&self) -> f64 {
        self.t_c
    }

    /// U = C²/J_eq \[N m\]: the unit of the twist model's torques.
    pub fn unit(&self) -> f64 {
        self.unit
    }

    /// The torque across the compliance as a model of terms, in the drive's units
    /// ([`Physical`]); its forcing is not used.
    pub fn twist(&self) -> &Model {
        &self.twist
    }

    /// The torque across the compliance \[N m\] at the twist θ \[rad\] and its rate θ' \[rad/s\].
    pub fn twist_torque(&self, theta: f64, theta_dot: f64) -> f64 {
        self.unit * self.twist.torque_at(&[theta, self.t_c * theta_dot])
    }

    /// Friction at the output bearing and the wave generator.
    pub fn bearings(&self) -> Bearings {
        self.bearings
    }

    /// (θo', θi') from the internal state's scaled rates z₁ = T_c·θ', z₃ = T_c·θo' (or from
    /// their Taylor rows): θi' = N(θo' − θ').
    #[inline(always)]
    fn rates(&self, z1: f64, z3: f64) -> (f64, f64) {
        (z3 * self.inv.t_c, self.d.ratio * (z3 - z1) * self.inv.t_c)
    }

    /// The two-inertia equations, written once for the right-hand side and for the Taylor rows
    /// (row k of each torque gives row k of each acceleration): (T_c·θ'', T_c·θo'') from the mean
    /// torque `load` (on both inertias), the torques applied from outside (motor, load), the
    /// disturbance on the output, the torque `twist` across the compliance and the bearings'
    /// friction (output, input), all in the twist's unit U. Zero outside torques leave every
    /// sum as it was without them, to the bit.
    #[inline(always)]
    fn accelerations(
        &self,
        load: f64,
        [motor, outside]: [f64; 2],
        disturbance: f64,
        twist: f64,
        [f_out, f_in]: [f64; 2],
    ) -> [f64; 2] {
        let inv = &self.inv;
        let acc_out = (load + outside + disturbance - twist - f_out) * inv.j_out;
        let acc_in = (twist - load) * inv.n_j_in - (f_in - motor) * inv.j_in;
        [acc_out - acc_in * inv.ratio, acc_out]
    }

    /// Internal state from (θi, θi', θo, θo').
    pub fn to_internal(
        &self,
        theta_in: f64,
        theta_in_dot: f64,
        theta_out: f64,
        theta_out_dot: f64,
    ) -> [f64; 4] {
        let n = self.d.ratio;
        [
            theta_out - theta_in / n,
            self.t_c * (theta_out_dot - theta_in_dot / n),
            theta_out,
            self.t_c * theta_out_dot,
        ]
    }

    /// (θi, θi', θo, θo', θ, θ') from the internal state.
    pub fn from_internal(&self, z: &[f64; 4]) -> [f64; 6] {
        let n = self.d.ratio;
        let (th, thd, to, tod) = (z[0], z[1] / self.t_c, z[2], z[3] / self.t_c);
        [n * (to - th), n * (tod - thd), to, tod, th, thd]
    }
}

impl System<4> for Physical {
    #[inline(always)]
    fn rhs(&self, t: f64, z: &[f64; 4]) -> [f64; 4] {
        let (d, u) = (&self.d, self.inv.unit);
        let twist = self.twist.torque_at(&[z[0], z[1]]);
        let friction = if self.bearings.any() {
            let (v_out, v_in) = self.rates(z[1], z[3]);
            self.bearings.torques(v_out, v_in).map(|f| f * u)
        } else {
            [0.0; 2]
        };
        let disturbance = d.t_am * u * libm::sin(d.omega * t);
        let outside = self.inputs.map(|f| f * u);
        let [acc_rel, acc_out] =
            self.accelerations(d.t_m * u, outside, disturbance, twist, friction);
        [z[1] * self.inv.t_c, acc_rel, z[3] * self.inv.t_c, acc_out]
    }

    /// The same equations order by order: the twist's rows from its terms' recurrences
    /// ([`Term::taylor`]), the disturbance's from the coefficients of sin Ωt.
    fn taylor(&self, t: f64, z: &[f64; 4], order: usize, c: &mut [[f64; 4]]) -> bool {
        let mut work = [crate::integrate::Scratch::default(); MAX_TERMS];
        self.rows(t, z, order, c, &mut work);
        true
    }

    fn taylor_in(
        &self,
        t: f64,
        z: &[f64; 4],
        order: usize,
        c: &mut [[f64; 4]],
        work: &mut Workspace,
    ) -> bool {
        self.rows(t, z, order, c, work);
        true
    }

    fn taylor_limits_steps(&self) -> bool {
        self.twist_limits
            || self
                .bearings
                .sides()
                .iter()
                .flatten()
                .any(|t| t.limits_steps())
    }

    /// The rows and the step rule's step, shortened where a law needs it
    /// ([`AnyTerm::step_limit`]): a torque F on inertia J moves the scaled rate T_c·θ' by
    /// T_c·F/J per second, so the torque negligible over a step h is atol·J/(T_c·h) (h at least
    /// T_c, the time over which the damping forgets). At a bearing J is its inertia's; across the
    /// compliance J_eq, which in the twist's unit U = J_eq/T_c² is atol·T_c/h.
    fn taylor_step<F: FnOnce(&[[f64; 4]]) -> f64>(
        &self,
        t: f64,
        z: &[f64; 4],
        order: usize,
        c: &mut [[f64; 4]],
        atol: f64,
        work: &mut Workspace,
        step: F,
    ) -> Option<f64> {
        let n = self.rows(t, z, order, c, work);
        let mut h = step(c);
        let forgets = |h: f64| self.t_c * h.max(self.t_c);
        if self.twist_limits {
            let negligible = atol * self.t_c * self.t_c / forgets(h);
            h = self.twist.limit_step_by(work, n, h, negligible);
        }
        let d = &self.d;
        let sides = self.bearings.sides();
        for ((term, set), j) in sides.iter().zip(BEARING_SETS).zip([d.j_out, d.j_in]) {
            if let Some(term) = term {
                h = term.step_limit(&work[set], n, h, atol * j / forgets(h));
            }
        }
        Some(h)
    }
}

impl Physical {
    /// Rows 0..=order (capped at the integrator's) of the Taylor coefficients through (t, z)
    /// into `c`, the twist's terms' own rows into `work` by slot and the bearings' into
    /// [`BEARING_SETS`]; returns the order reached.
    fn rows(
        &self,
        t: f64,
        z: &[f64; 4],
        order: usize,
        c: &mut [[f64; 4]],
        work: &mut [crate::integrate::Scratch],
    ) -> usize {
        use crate::integrate::taylor::{INV, sine_coefficients};
        let (d, u) = (&self.d, self.inv.unit);
        let n = order.min(MAX_ORDER).min(c.len() - 1);
        // the rows of θ and of T_c·θ' (the twist model's x and x'), and of sin Ωt
        let (mut x, mut v, mut s) = (
            [0.0; MAX_ORDER + 1],
            [0.0; MAX_ORDER + 1],
            [0.0; MAX_ORDER + 1],
        );
        // the bearings' rates θo', θi', row by row
        let bearings = self.bearings.any();
        let mut rates = [[0.0; MAX_ORDER + 1]; 2];
        sine_coefficients(d.omega, t, n, &mut s);
        c[0] = *z;
        for k in 0..n {
            (x[k], v[k]) = (c[k][0], c[k][1]);
            let (load, outside) = if k == 0 {
                (d.t_m * u, self.inputs.map(|f| f * u))
            } else {
                (0.0, [0.0; 2])
            };
            let twist = self.twist_row(k, &x, &v, work);
            let friction = if bearings {
                self.bearing_rows(k, &c[k], &mut rates, work).map(|f| f * u)
            } else {
                [0.0; 2]
            };
            let [acc_rel, acc_out] =
                self.accelerations(load, outside, d.t_am * u * s[k], twist, friction);
            c[k + 1] = [
                c[k][1] * self.inv.t_c * INV[k],
                acc_rel * INV[k],
                c[k][3] * self.inv.t_c * INV[k],
                acc_out * INV[k],
            ];
        }
        // the step limits read the laws' rows at order n too
        if self.twist_limits {
            (x[n], v[n]) = (c[n][0], c[n][1]);
            self.twist.torque_row(n, &x, &v, work);
        }
        if bearings {
            self.bearing_rows(n, &c[n], &mut rates, work);
        }
        n
    }

    /// Row k of the twist model's torque ([`Model::torque_row`]), its damping's and spring's
    /// own recurrences called directly when it holds nothing else (the same sum, to the bit).
    #[inline(always)]
    fn twist_row(
        &self,
        k: usize,
        x: &[f64],
        v: &[f64],
        work: &mut [crate::integrate::Scratch],
    ) -> f64 {
        const NONE: [f64; MAX_ORDER + 1] = [0.0; MAX_ORDER + 1];
        if self.extra {
            return self.twist.torque_row(k, x, v, work);
        }
        let damping = Damping::default().taylor(k, x, v, &NONE, &mut work[DAMPING_SLOT]);
        0.0 + damping + self.spring.taylor(k, x, v, &NONE, &mut work[SPRING_SLOT])
    }

    /// Row k of the bearings' torques (output, input) from the state's row k, keeping the
    /// rates' rows in `rates` and each law's own rows in its set of `work` ([`BEARING_SETS`]).
    #[inline(always)]
    fn bearing_rows(
        &self,
        k: usize,
        c_k: &[f64; 4],
        rates: &mut [[f64; MAX_ORDER + 1]; 2],
        work: &mut [crate::integrate::Scratch],
    ) -> [f64; 2] {
        const NONE: [f64; MAX_ORDER + 1] = [0.0; MAX_ORDER + 1];
        (rates[0][k], rates[1][k]) = self.rates(c_k[1], c_k[3]);
        let mut f = [0.0; 2];
        let sides = self.bearings.sides();
        for (((term, v), set), f) in sides.iter().zip(rates.iter()).zip(BEARING_SETS).zip(&mut f) {
            if let Some(term) = term {
                *f = term.taylor(k, &NONE, v, &NONE, &mut work[set]);
            }
        }
        f
    }
}
