//! Drive cards: a drive's catalogue numbers with the source of every one, read from TOML.
//!
//! A card file holds `format`, a table of `[sources]` (each with a `kind`: catalogue, fit,
//! measured or assumption, and a citation) and one or more `[[card]]`s. A card has a name, a
//! ratio and sections (stiffness, torque, speed, inertia, hysteresis, friction, application);
//! every section names the source its numbers come from. Values without a source are left out,
//! and [`Card::missing`] lists them. hdgear's built-in cards ([`builtin`]) are such a file,
//! compiled into the library; a user's card is read with [`CardFile::parse`].
//!
//! ```
//! let card = hdgear::physical::card::builtin_card("CSG-20-50").unwrap();
//! assert_eq!(card.stiffness.k3, Some(2.3e4));
//! assert_eq!(card.torque.as_ref().unwrap().rated, Some(33.0));
//! ```
//!
//! **Why one file.** A card's sections, their fields with units and sources, and the checks that
//! tie them are one format: its reader, its writer and its checks change together.

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::sync::OnceLock;

/// The card format this library reads and writes.
pub const FORMAT: u32 = 1;

/// The built-in cards' file (Harmonic Drive CSG, HFUC, SHG, HFUS and CSF drives).
pub const BUILTIN_TOML: &str = include_str!("../../cards/harmonic-drive.toml");

/// What kind of evidence a number rests on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SourceKind {
    /// A manufacturer's catalogue value.
    Catalogue,
    /// Fitted to a catalogue curve or to measurements.
    Fit,
    /// Measured on a drive.
    Measured,
    /// Assumed: a typical value standing in for a missing one.
    Assumption,
}

impl SourceKind {
    /// Its name in a card file.
    pub fn name(self) -> &'static str {
        match self {
            SourceKind::Catalogue => "catalogue",
            SourceKind::Fit => "fit",
            SourceKind::Measured => "measured",
            SourceKind::Assumption => "assumption",
        }
    }
}

/// Where a section's numbers come from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Source {
    /// The kind of evidence.
    pub kind: SourceKind,
    /// The citation: document, table, page, transcription.
    pub cite: String,
}

/// The quantities for which 0 has no meaning (a speed limit, an inertia, a frequency), as
/// `section.key`: a card refuses 0 there, where every other quantity may be 0.
const POSITIVE: [&str; 4] = [
    "speed.max_input_rpm",
    "inertia.input",
    "application.frequency",
    "application.resonance_required",
];

/// Checks a card's name: not blank, and without `#` (which separates a file from a card's name
/// on the command line), `"` or line breaks (which a card file cannot hold in a plain string).
pub fn check_name(name: &str) -> Result<()> {
    if name.trim().is_empty() || name.contains(['#', '"', '\n', '\r']) {
        return Err(Error::Card {
            card: if name.trim().is_empty() {
                "(unnamed)".into()
            } else {
                name.to_string()
            },
            field: "name".into(),
            value: format!("'{name}'"),
            reason: "must be non-empty, without #, \" or line breaks",
        });
    }
    Ok(())
}

/// One quantity of a section: its TOML key, unit and meaning.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Field {
    /// The key in the card.
    pub key: &'static str,
    /// The unit.
    pub unit: &'static str,
    /// What it is.
    pub meaning: &'static str,
}

/// Defines a card section from one list of its quantities: the struct, its serde form and the
/// field table that `show`, `missing` and the template are derived from.
macro_rules! section {
    ($(#[$m:meta])* $name:ident = $key:literal { $($field:ident : $unit:literal, $meaning:literal;)* }) => {
        $(#[$m])*
        #[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
        #[serde(deny_unknown_fields)]
        pub struct $name {
            /// The key in `[sources]` every number of this section comes from.
            pub source: String,
            /// A remark kept with the values (a correction, a conversion).
            #[serde(default, skip_serializing_if = "Option::is_none")]
            pub note: Option<String>,
            $(
                #[doc = concat!($meaning, " \\[", $unit, "\\].")]
                #[serde(default, skip_serializing_if = "Option::is_none")]
                pub $field: Option<f64>,
            )*
        }
        impl $name {
            /// The section's key in a card.
            pub const KEY: &'static str = $key;
            /// Its quantities, in order.
            pub const FIELDS: &'static [Field] =
                &[$(Field { key: stringify!($field), unit: $unit, meaning: $meaning }),*];
            /// Its values, in the order of [`Self::FIELDS`].
            pub fn values(&self) -> Vec<Option<f64>> {
                vec![$(self.$field),*]
            }
        }
        impl CardSection for $name {
            fn key(&self) -> &'static str { Self::KEY }
            fn fields(&self) -> &'static [Field] { Self::FIELDS }
            fn values(&self) -> Vec<Option<f64>> { $name::values(self) }
            fn source(&self) -> &str { &self.source }
            fn note(&self) -> Option<&str> { self.note.as_deref() }
        }
    };
}

/// What every card section offers: its key, quantities, values, source and note.
pub trait CardSection {
    /// The section's key.
    fn key(&self) -> &'static str;
    /// Its quantities.
    fn fields(&self) -> &'static [Field];
    /// Its values, in the order of the quantities.
    fn values(&self) -> Vec<Option<f64>>;
    /// Its source key.
    fn source(&self) -> &str;
    /// Its note.
    fn note(&self) -> Option<&str>;
}

section!(
    /// The catalogue's piecewise-linear torque–twist curve (output side, input locked).
    Stiffness = "stiffness" {
        t1: "N m", "end of the first linear segment";
        t2: "N m", "end of the second linear segment";
        k1: "N m/rad", "stiffness from 0 to T1";
        k2: "N m/rad", "stiffness from T1 to T2";
        k3: "N m/rad", "stiffness above T2";
    }
);
section!(
    /// Torque ratings at the output.
    Torque = "torque" {
        rated: "N m", "rated torque at 2000 rpm input";
        repeated_peak: "N m", "limit for repeated peak torque";
        average: "N m", "limit for average torque";
        momentary_peak: "N m", "limit for momentary peak torque";
    }
);
section!(
    /// Speed limits.
    Speed = "speed" {
        max_input_rpm: "rpm", "maximum input speed";
    }
);
section!(
    /// Inertia of the gear itself.
    Inertia = "inertia" {
        input: "kg m^2", "moment of inertia at the input (wave generator)";
    }
);
section!(
    /// Hysteresis and lost motion of the torque–twist curve.
    Hysteresis = "hysteresis" {
        loss: "rad", "hysteresis loss: twist width of the loop at zero torque after cycling to the rated torque";
        lost_motion: "rad", "lost motion: twist width at small torque";
    }
);
section!(
    /// Friction of the gear.
    Friction = "friction" {
        starting: "N m", "starting torque at the input";
        backdriving: "N m", "back-driving torque at the output";
        no_load_running: "N m", "no-load running torque at the input";
        coulomb: "N m", "fitted Coulomb friction at the output";
        breakaway: "N m", "fitted static (breakaway) friction at the output";
        stribeck_speed: "rad/s", "fitted Stribeck speed at the output";
        viscous: "N m s/rad", "fitted viscous friction at the output";
        efficiency: "-", "efficiency at rated torque, whose loss 1/η − 1 is taken as a torque-proportional mesh loss";
    }
);
section!(
    /// The application: what the drive drives. Not the catalogue's; hdgear assumes typical
    /// values for what is left out ([`super::catalogue::ASSUMPTIONS`]).
    Application = "application" {
        j_motor: "kg m^2", "motor rotor inertia on the input";
        j_load: "kg m^2", "load inertia on the output";
        t_mean: "N m", "mean output load torque";
        t_amp: "N m", "amplitude of the slow output torque variation";
        frequency: "Hz", "frequency of the slow output torque variation";
        backlash: "rad", "backlash of the stiffness law";
        zeta: "-", "damping ratio of the linear torsional mode, when not derived from the hysteresis loss";
        resonance_required: "Hz", "lowest torsional natural frequency the application needs";
    }
);

/// One drive's card.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Card {
    /// The drive's name, e.g. `CSG-20-50`.
    pub name: String,
    /// The series, e.g. `CSG`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub series: Option<String>,
    /// The size.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub size: Option<u32>,
    /// The reduction ratio.
    pub ratio: f64,
    /// The torque–twist curve.
    pub stiffness: Stiffness,
    /// Torque ratings.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub torque: Option<Torque>,
    /// Speed limits.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed: Option<Speed>,
    /// Inertia of the gear.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia: Option<Inertia>,
    /// Hysteresis loss and lost motion.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hysteresis: Option<Hysteresis>,
    /// Friction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<Friction>,
    /// The application.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub application: Option<Application>,
    /// The spreads of the drive's parameters (`hdgear robust`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<Tolerances>,
}

/// A card's manufacturing spreads: drive parameter name (`k1`, `c_eq`, …) → spread as
/// `hdgear robust --tolerance` writes it (`±15%`, `normal:5%`, …), with their source.
///
/// ```toml
/// [card.tolerance]
/// source = "measured-batch"
/// bands = { k1 = "±12%", c_eq = "normal:15%" }
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tolerances {
    /// Key of the source in the file's `[sources]`.
    pub source: String,
    /// Spread per drive parameter.
    pub bands: BTreeMap<String, String>,
}

/// A card file: its format, sources and cards.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CardFile {
    /// The card format ([`FORMAT`]).
    pub format: u32,
    /// The sources, by key.
    #[serde(default)]
    pub sources: BTreeMap<String, Source>,
    /// The cards.
    pub card: Vec<Card>,
}

/// The quantities every card needs: without them there is no torque–twist curve.
const REQUIRED: [&str; 4] = ["t1", "t2", "k1", "k2"];

impl Card {
    /// Its sections that are present, in the card's order.
    pub fn sections(&self) -> Vec<&dyn CardSection> {
        let mut s: Vec<&dyn CardSection> = vec![&self.stiffness];
        let opt: [Option<&dyn CardSection>; 6] = [
            self.torque.as_ref().map(|v| v as &dyn CardSection),
            self.speed.as_ref().map(|v| v as &dyn CardSection),
            self.inertia.as_ref().map(|v| v as &dyn CardSection),
            self.hysteresis.as_ref().map(|v| v as &dyn CardSection),
            self.friction.as_ref().map(|v| v as &dyn CardSection),
            self.application.as_ref().map(|v| v as &dyn CardSection),
        ];
        s.extend(opt.into_iter().flatten());
        s
    }

    /// The quantities the card has no value for, as `section.key` (the application's are the
    /// user's and not listed).
    pub fn missing(&self) -> Vec<String> {
        let (t, sp, i, h, f) = (
            Torque::default(),
            Speed::default(),
            Inertia::default(),
            Hysteresis::default(),
            Friction::default(),
        );
        let all: [&dyn CardSection; 6] = [
            &self.stiffness,
            or_empty(&self.torque, &t),
            or_empty(&self.speed, &sp),
            or_empty(&self.inertia, &i),
            or_empty(&self.hysteresis, &h),
            or_empty(&self.friction, &f),
        ];
        all.iter()
            .flat_map(|s| {
                let key = s.key();
                s.fields()
                    .iter()
                    .zip(s.values())
                    .filter(|(_, v)| v.is_none())
                    .map(move |(f, _)| format!("{key}.{}", f.key))
            })
            .collect()
    }

    /// The source of each of its sections, by section key (`sources` is its file's table; the
    /// card is assumed valid against it, see [`Card::validate`]).
    pub fn cited(&self, sources: &BTreeMap<String, Source>) -> BTreeMap<&'static str, Source> {
        self.sections()
            .iter()
            .filter_map(|s| Some((s.key(), sources.get(s.source())?.clone())))
            .collect()
    }

    /// The rated torque, when the card has it.
    pub fn rated_torque(&self) -> Option<f64> {
        self.torque.as_ref().and_then(|t| t.rated)
    }

    /// The rated torque when it lies on the card's curve (up to [`Card::curve`]'s t_max).
    pub fn rated_on_curve(&self) -> Option<f64> {
        let t_max = self.curve().t_max;
        self.rated_torque().filter(|&t| t <= t_max)
    }

    /// Checks the card against its file's `sources`: every section names a known source, every
    /// number is finite and positive, the curve's quantities are there, T1 < T2 and
    /// K1 ≤ K2 ≤ K3 (a transcription typo shows up as a broken order).
    pub fn validate(&self, sources: &BTreeMap<String, Source>) -> Result<()> {
        check_name(&self.name)?;
        let bad = |field: String, value: String, reason: &'static str| Error::Card {
            card: self.name.clone(),
            field,
            value,
            reason,
        };
        if !(self.ratio.is_finite() && self.ratio >= 1.0) {
            return Err(bad("ratio".into(), fmt(self.ratio), "must be ≥ 1"));
        }
        if crate::params::beyond_magnitude(self.ratio) {
            return Err(bad("ratio".into(), fmt(self.ratio), OUT_OF_SCALE));
        }
        for s in self.sections() {
            if !sources.contains_key(s.source()) {
                let known = sources.keys().cloned().collect::<Vec<_>>().join(", ");
                return Err(Error::Card {
                    card: self.name.clone(),
                    field: format!("{}.source", s.key()),
                    value: s.source().to_string(),
                    reason: if known.is_empty() {
                        "names no entry of [sources] (the file has none)"
                    } else {
                        "names no entry of [sources]"
                    },
                });
            }
            for (f, v) in s.fields().iter().zip(s.values()) {
                let key = format!("{}.{}", s.key(), f.key);
                match v {
                    Some(v) if !(v.is_finite() && v >= 0.0) => {
                        return Err(bad(key, fmt(v), "must be finite and ≥ 0"));
                    }
                    Some(v) if v == 0.0 && POSITIVE.contains(&key.as_str()) => {
                        return Err(bad(key, fmt(v), "must be > 0 (0 has no meaning here)"));
                    }
                    Some(v) if crate::params::beyond_magnitude(v) => {
                        return Err(bad(key, fmt(v), OUT_OF_SCALE));
                    }
                    _ => {}
                }
            }
        }
        if let Some(t) = &self.tolerance {
            self.validate_tolerances(t, sources)?;
        }
        let s = &self.stiffness;
        for (key, v) in REQUIRED.iter().zip([s.t1, s.t2, s.k1, s.k2]) {
            match v {
                None => {
                    return Err(bad(
                        format!("stiffness.{key}"),
                        "missing".into(),
                        "is needed",
                    ));
                }
                Some(v) if v <= 0.0 => {
                    return Err(bad(format!("stiffness.{key}"), fmt(v), "must be > 0"));
                }
                _ => {}
            }
        }
        let c = self.curve();
        if c.t1 >= c.t2 {
            return Err(bad("stiffness.t1".into(), fmt(c.t1), "must be below t2"));
        }
        if c.k2 < c.k1 {
            return Err(bad("stiffness.k2".into(), fmt(c.k2), "must be ≥ k1"));
        }
        if let Some(k3) = c.k3
            && k3 < c.k2
        {
            return Err(bad("stiffness.k3".into(), fmt(k3), "must be ≥ k2"));
        }
        self.friction_law()?;
        Ok(())
    }
}

impl Card {
    /// The card's fitted friction law, `None` when the card has neither a fitted Coulomb level nor an
    /// efficiency. A fit needs F_c; F_s defaults to F_c, c_v to 0; a drop (F_s > F_c) needs its
    /// Stribeck speed; F_s < F_c is refused. An efficiency η in (0, 1] gives the mesh loss
    /// μ_m = 1/η − 1 (with no fitted level the law is that loss alone, F_c = F_s = 0). Measured
    /// torques alone (starting, back-driving, no-load running) are not turned into a law: they are
    /// friction of the rigid-body rotation, not of the twist.
    pub fn friction_law(&self) -> Result<Option<FrictionLaw>> {
        let Some(f) = &self.friction else {
            return Ok(None);
        };
        let bad = |field: &str, value: Option<f64>, reason: &'static str| Error::Card {
            card: self.name.clone(),
            field: format!("friction.{field}"),
            value: value.map_or("(absent)".into(), |v| v.to_string()),
            reason,
        };
        let mesh_loss = match f.efficiency {
            Some(eta) if eta > 0.0 && eta <= 1.0 => Some(1.0 / eta - 1.0),
            None => None,
            eta => return Err(bad("efficiency", eta, "must lie in (0, 1]")),
        };
        let Some(coulomb) = f.coulomb else {
            return match (f.breakaway, f.stribeck_speed, f.viscous, mesh_loss) {
                (None, None, None, None) => Ok(None),
                (None, None, None, Some(_)) => Ok(Some(FrictionLaw {
                    coulomb: 0.0,
                    breakaway: 0.0,
                    stribeck_speed: NO_DROP_SPEED,
                    viscous: 0.0,
                    mesh_loss,
                })),
                _ => Err(bad(
                    "coulomb",
                    None,
                    "a fitted friction law needs its Coulomb level",
                )),
            };
        };
        let breakaway = f.breakaway.unwrap_or(coulomb);
        // the friction terms' own rule, on the card's keys
        let rule = crate::model::terms::STATIC_AT_LEAST_SLIDING;
        if !rule.holds(&[coulomb, breakaway]) {
            return Err(bad("breakaway", Some(breakaway), rule.reason()));
        }
        let stribeck_speed = match f.stribeck_speed {
            Some(v) if v > 0.0 => v,
            None if breakaway == coulomb => NO_DROP_SPEED,
            v => {
                return Err(bad(
                    "stribeck_speed",
                    v,
                    "must be > 0 where the breakaway exceeds the Coulomb level",
                ));
            }
        };
        Ok(Some(FrictionLaw {
            coulomb,
            breakaway,
            stribeck_speed,
            viscous: f.viscous.unwrap_or(0.0),
            mesh_loss,
        }))
    }

    /// A tolerance table names a known source, drive parameters, and spreads that read (the
    /// nominal value is the drive's, known only when it is built: checked here at 1).
    fn validate_tolerances(
        &self,
        t: &Tolerances,
        sources: &BTreeMap<String, Source>,
    ) -> Result<()> {
        let bad = |field: String, value: String, reason: &'static str| Error::Card {
            card: self.name.clone(),
            field,
            value,
            reason,
        };
        if !sources.contains_key(&t.source) {
            let reason = "names no entry of [sources]";
            return Err(bad("tolerance.source".into(), t.source.clone(), reason));
        }
        for (name, spec) in &t.bands {
            if name.parse::<super::DriveParam>().is_err() {
                let reason = "is not a drive parameter (j_in, j_out, ratio, k1, k2, backlash, c_eq, t_m, t_am, omega)";
                return Err(bad(format!("tolerance.bands.{name}"), spec.clone(), reason));
            }
            if crate::distribution::Distribution::parse(spec, 1.0).is_err() {
                let reason =
                    "is not a spread (±X%, ±X, LO..HI, normal:SD, lognormal:S%, tnormal:SD:±X)";
                return Err(bad(format!("tolerance.bands.{name}"), spec.clone(), reason));
            }
        }
        Ok(())
    }
}

/// The section, or its empty default when the card has none (every value then missing).
/// The Stribeck speed a card without a Stribeck drop is given: with F_s = F_c it has no effect.
const NO_DROP_SPEED: f64 = 1.0;

/// A fitted Coulomb–Stribeck–viscous friction law with sticking, at the output, in SI units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FrictionLaw {
    /// F_c: Coulomb (sliding) friction \[N m\].
    pub coulomb: f64,
    /// F_s ≥ F_c: static (breakaway) friction \[N m\], the sticking band.
    pub breakaway: f64,
    /// v_s: Stribeck speed \[rad/s\] of the drop from F_s to F_c.
    pub stribeck_speed: f64,
    /// c_v: viscous friction \[N m s/rad\].
    pub viscous: f64,
    /// μ_m = 1/η − 1: the torque-proportional mesh loss from the card's efficiency η, if it
    /// gives one ([`super::friction::MESH_ASSUMPTION`]).
    pub mesh_loss: Option<f64>,
}

fn or_empty<'a, S: CardSection>(s: &'a Option<S>, empty: &'a S) -> &'a dyn CardSection {
    s.as_ref().unwrap_or(empty)
}

/// Why a card's value beyond [`crate::params::MAGNITUDE_LIMIT`] is refused.
const OUT_OF_SCALE: &str = "magnitude outside 1e-100 to 1e100 (0 aside): the drive's scales \
                            built from it would overflow";

fn fmt(v: f64) -> String {
    crate::error::shown(v)
}

impl CardFile {
    /// Reads a card file from its text and validates it: the format, every card, unique names.
    pub fn parse(text: &str) -> Result<CardFile> {
        let f: CardFile = toml::from_str(text).map_err(|e| Error::InvalidInput {
            what: "card file",
            text: e.message().to_string(),
            reason: e
                .span()
                .map(|s| format!("at line {}", 1 + text[..s.start].matches('\n').count()))
                .unwrap_or_default(),
        })?;
        if f.format != FORMAT {
            return Err(Error::Card {
                card: String::new(),
                field: "format".into(),
                value: f.format.to_string(),
                reason: "this hdgear reads card format 1",
            });
        }
        let mut seen = std::collections::HashSet::new();
        for c in &f.card {
            c.validate(&f.sources)?;
            if !seen.insert(c.name.to_ascii_lowercase()) {
                return Err(Error::Card {
                    card: c.name.clone(),
                    field: "name".into(),
                    value: c.name.clone(),
                    reason: "appears twice in the file",
                });
            }
        }
        Ok(f)
    }

    /// The card called `name` (case-insensitive).
    pub fn get(&self, name: &str) -> Result<&Card> {
        self.card
            .iter()
            .find(|c| c.name.eq_ignore_ascii_case(name))
            .ok_or_else(|| Error::UnknownCard {
                name: name.into(),
                known: known_names(self),
            })
    }

    /// The file as TOML.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("a card file is always representable in TOML")
    }
}

fn known_names(f: &CardFile) -> String {
    if f.card.len() <= 12 {
        return f
            .card
            .iter()
            .map(|c| c.name.as_str())
            .collect::<Vec<_>>()
            .join(", ");
    }
    let first: Vec<&str> = f.card.iter().take(8).map(|c| c.name.as_str()).collect();
    format!(
        "{}, … {} in all: hdgear card list",
        first.join(", "),
        f.card.len()
    )
}

/// hdgear's built-in cards, parsed once.
pub fn builtin() -> &'static CardFile {
    static CARDS: OnceLock<CardFile> = OnceLock::new();
    CARDS.get_or_init(|| CardFile::parse(BUILTIN_TOML).expect("the built-in cards are valid"))
}

/// The built-in card called `name` (case-insensitive).
pub fn builtin_card(name: &str) -> Result<&'static Card> {
    builtin().get(name)
}
