//! Frequency-response curves: the periodic response's amplitude against the forcing frequency ω,
//! by continuation in ln ω (so the bend of the hardening stiffness and its folds — the jumps of
//! an up- or down-sweep — come out with the unstable middle branch), for the dimensionless model
//! and for a physical drive in SI units.

use super::{ContinuationOptions, OrbitBranch, OrbitPoint, Scale, Special, continue_orbit};
use crate::error::{Error, Result};
use crate::model::terms::Term;
use crate::params::{Param, Params};
use crate::physical::{PhysicalParams, Reduction};
use serde::Serialize;

/// A continuation request `NAME=FROM:TO[:log]`: follow the orbit in NAME from FROM to TO. NAME
/// is one of the study's parameters ([`Range::parse`]) or any of a system's
/// ([`Range::parse_for`]: `friction.fc`).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Range<P = Param> {
    /// The parameter.
    pub param: P,
    /// Where the continuation starts (the parameter is set to it).
    pub from: f64,
    /// Where it ends.
    pub to: f64,
    /// Linear or logarithmic coordinate.
    pub scale: Scale,
}

impl Range {
    /// Parses `NAME=FROM:TO[:log]` with NAME one of the study's parameters; errors name the
    /// offending text.
    ///
    /// ```
    /// let r = hdgear::periodic::Range::parse("omega=0.5:20:log").unwrap();
    /// assert_eq!((r.from, r.to), (0.5, 20.0));
    /// ```
    pub fn parse(text: &str) -> Result<Range> {
        Range::parse_with(text, |name| {
            name.parse().map_err(|_| {
                format!(
                    "unknown parameter '{name}' (expected one of {})",
                    Param::ALL.map(Param::name).join(", ")
                )
            })
        })
    }
}

/// The parameter `name` of `system`, or the reason it is none, naming it: how a continuation
/// range or a sweep axis names a system's parameter.
pub(crate) fn lookup_in<S: super::Periodic>(
    system: &S,
    name: &str,
) -> std::result::Result<S::Param, String> {
    system.param_named(name).map_err(|e| match e {
        Error::InvalidInput { reason, .. } => format!("'{name}': {reason}"),
        other => other.to_string(),
    })
}

impl<P> Range<P> {
    /// Parses `NAME=FROM:TO[:log]` with NAME any parameter of `system` (a model's `fc` or
    /// `friction.fc`, [`crate::model::Model::param`]).
    ///
    /// ```
    /// use hdgear::{Params, model::{Model, terms::AnyTerm}, periodic::Range};
    /// let m = Model::study(&Params::default())
    ///     .with_term(AnyTerm::new("friction", &[0.1, 0.05]).unwrap())
    ///     .unwrap();
    /// let r = Range::parse_for("friction.fc=0:0.5", &m).unwrap();
    /// assert_eq!(r.param.name(), "fc");
    /// assert!(Range::parse_for("friction.nope=0:1", &m).is_err());
    /// ```
    pub fn parse_for<S: super::Periodic<Param = P>>(text: &str, system: &S) -> Result<Range<P>> {
        Range::parse_with(text, |name| lookup_in(system, name))
    }

    /// Parses `NAME=FROM:TO[:log]`, NAME by `lookup` (its error is the reason shown).
    fn parse_with(
        text: &str,
        lookup: impl FnOnce(&str) -> std::result::Result<P, String>,
    ) -> Result<Range<P>> {
        let bad = |reason: String| Error::InvalidInput {
            what: "continuation range",
            text: text.to_string(),
            reason,
        };
        let (name, spec) = text
            .split_once('=')
            .ok_or_else(|| bad("expected NAME=FROM:TO[:log]".into()))?;
        let param = lookup(name.trim()).map_err(bad)?;
        let parts: Vec<&str> = spec.split(':').map(str::trim).collect();
        if !(parts.len() == 2 || parts.len() == 3) {
            return Err(bad("expected NAME=FROM:TO[:log]".into()));
        }
        let num = |s: &str, what: &str| {
            s.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| bad(format!("{what} '{s}' is not a finite number")))
        };
        let (from, to) = (num(parts[0], "FROM")?, num(parts[1], "TO")?);
        let scale = match parts.get(2) {
            None => Scale::Linear,
            Some(&"log") => Scale::Log,
            Some(other) => {
                return Err(bad(format!("'{other}': the third field can only be 'log'")));
            }
        };
        if from == to {
            return Err(bad("FROM and TO must differ".into()));
        }
        if scale == Scale::Log && !(from > 0.0 && to > 0.0) {
            return Err(bad("a log range needs FROM > 0 and TO > 0".into()));
        }
        Ok(Range {
            param,
            from,
            to,
            scale,
        })
    }
}

/// The default ω range of a frequency-response curve: [ω_s/20, 3·ω_s] with ω_s = √g'(x) at the
/// stiffest equilibrium the forcing reaches statically (x at a = ±1; g' is a convex parabola, so
/// its largest value on the traversed x-range is at an end). The hardening resonance lies between
/// the small-amplitude frequency √g'(x*) ≤ ω_s and a few times ω_s; the low end is quasi-static.
pub fn default_frequency_range(p: &Params) -> (f64, f64) {
    let ends = [-1.0, 1.0].map(|a| crate::fast::equilibria(p, a));
    let stiffest = ends
        .iter()
        .flat_map(|e| e.roots.iter().map(|r| r.g_prime))
        .fold(p.g_prime(0.0).abs(), f64::max);
    let ws = stiffest.sqrt().max(1e-3);
    (ws / 20.0, 3.0 * ws)
}

/// The frequency-response curve of the period-1 response over ω ∈ `range` (default
/// [`default_frequency_range`]), continued upwards in ln ω from the settled response at the low
/// end.
///
/// ```
/// use hdgear::{Params, periodic::{ContinuationOptions, Special, frequency_response}};
/// // the study's point with γ = 30: a hardening bend with two folds near ω ≈ 8
/// let p = Params { gamma: 30.0, ..Params::default() };
/// let b = frequency_response(&p, Some((4.0, 12.0)), &ContinuationOptions::default()).unwrap();
/// let folds: Vec<f64> = b.specials().filter(|q| q.special == Some(Special::Fold)).map(|q| q.param).collect();
/// assert_eq!(folds.len(), 2);
/// assert!(folds[0] > folds[1], "the curve bends back: the upper fold comes first");
/// ```
pub fn frequency_response<S: super::Periodic>(
    p: &S,
    range: Option<(f64, f64)>,
    opts: &ContinuationOptions,
) -> Result<OrbitBranch<S::Param>> {
    let (lo, hi) = range.unwrap_or_else(|| p.frequency_range());
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        return Err(Error::InvalidOption {
            name: "omega range",
            value: if lo > 0.0 { hi } else { lo },
            reason: "needs 0 < low < high",
        });
    }
    p.check_periodic()?;
    let omega = p.frequency();
    let start = p.with(omega, lo)?;
    let opts = ContinuationOptions {
        scale: Scale::Log,
        ..*opts
    };
    continue_orbit(&start, omega, 1, None, hi, &opts)
}

/// One point of a physical drive's frequency-response curve, in SI units.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PhysicalPoint {
    /// Disturbance frequency f = Ω/2π \[Hz\].
    pub frequency_hz: f64,
    /// Ω \[rad/s\].
    pub omega_rad_s: f64,
    /// Smallest and largest relative torsion θ over the period \[rad\].
    pub twist_range: [f64; 2],
    /// Peak-to-peak θ \[rad\].
    pub twist_peak_to_peak: f64,
    /// Largest |θ'| \[rad/s\].
    pub max_twist_rate: f64,
    /// Smallest and largest elastic torque K(θ)(θ − φ) over the period \[N m\] (exact: θ(t)
    /// covers exactly the twist range, so the torque's range is the cubic's range on it).
    pub torque_range: [f64; 2],
    /// Both multipliers inside the unit circle.
    pub stable: bool,
    /// Fold or period doubling, at located points.
    pub special: Option<Special>,
}

/// A physical drive's frequency-response curve.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PhysicalResponse {
    /// The drive.
    pub drive: PhysicalParams,
    /// Its reduction (the dimensionless parameters and the scales).
    pub reduction: Reduction,
    /// The curve in SI units: one point per point of `branch`, in the same order.
    pub points: Vec<PhysicalPoint>,
    /// The dimensionless branch it comes from.
    #[serde(skip)]
    pub branch: OrbitBranch<Param>,
}

/// The frequency-response curve of a drive over `hz` (default: the dimensionless default range
/// converted), in SI units.
pub fn physical_frequency_response(
    d: &PhysicalParams,
    hz: Option<(f64, f64)>,
    opts: &ContinuationOptions,
) -> Result<PhysicalResponse> {
    let r = d.reduce()?;
    let to_omega = |f: f64| std::f64::consts::TAU * f * r.time_scale;
    let range = hz.map(|(a, b)| (to_omega(a), to_omega(b)));
    let branch = frequency_response(&r.params, range, opts)?;
    let points = branch
        .points
        .iter()
        .map(|q| physical_point(d, &r, q))
        .collect();
    Ok(PhysicalResponse {
        drive: *d,
        reduction: r,
        points,
        branch,
    })
}

fn physical_point(d: &PhysicalParams, r: &Reduction, q: &OrbitPoint) -> PhysicalPoint {
    let omega_rad_s = q.param / r.time_scale;
    let (t0, t1) = (r.theta(q.amplitude.x_min), r.theta(q.amplitude.x_max));
    PhysicalPoint {
        frequency_hz: omega_rad_s / std::f64::consts::TAU,
        omega_rad_s,
        twist_range: [t0, t1],
        twist_peak_to_peak: t1 - t0,
        max_twist_rate: r.theta_dot(q.amplitude.max_abs_xdot),
        torque_range: torque_range(d, t0, t1),
        stable: q.stable,
        special: q.special,
    }
}

/// The range of T(θ) = (k1 + k2θ²)(θ − φ) on [t0, t1]: at the ends and at the zeros of
/// T'(θ) = 3k2θ² − 2k2φθ + k1 inside.
pub fn torque_range(d: &PhysicalParams, t0: f64, t1: f64) -> [f64; 2] {
    let spring = d.spring();
    let t = |th: f64| spring.torque(th, 0.0, 0.0);
    let mut vals = vec![t(t0), t(t1)];
    let (a, b, c) = (3.0 * d.k2, -2.0 * d.k2 * d.backlash, d.k1);
    let disc = b * b - 4.0 * a * c;
    if a != 0.0 && disc >= 0.0 {
        for s in [-1.0, 1.0] {
            let th = (-b + s * disc.sqrt()) / (2.0 * a);
            if th > t0 && th < t1 {
                vals.push(t(th));
            }
        }
    }
    let lo = vals.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    [lo, hi]
}
