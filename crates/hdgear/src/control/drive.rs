//! Burst control on a physical drive: the laws compared on the drive's reduction
//! ([`super::compare`]), their control torque read back in N m and set against the drive's
//! torque ratings.
//!
//! A control torque at the motor enters the twist θ = θ_o − θ_i/N through the input inertia,
//! θ'' ∋ u_m/(N·J_i); referred to the output (u = N·u_m, the side the mean load T_m and the
//! catalogue's ratings are given on) that is u/(N²·J_i). With θ = L·x and t = T·τ the reduced
//! model's ũ is u·T²/(L·N²·J_i): u = ũ·L·N²·J_i/T² ([`torque_scale`]), and the motor delivers
//! u/N.

use super::{Assessment, Comparison, ControlOptions, compare};
use crate::burst::BurstOptions;
use crate::error::Result;
use crate::physical::card::Torque;
use crate::physical::{PhysicalParams, Reduction};
use serde::Serialize;

/// The drive's output torque ratings the efforts are set against, with where they come from.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Ratings {
    /// Rated torque \[N m\].
    pub rated: Option<f64>,
    /// Limit for repeated peak torque \[N m\].
    pub repeated_peak: Option<f64>,
    /// Whose ratings (a card's name and its source), or why there are none.
    pub origin: String,
}

impl Ratings {
    /// A card's `[torque]` section, named by `origin`.
    pub fn of(torque: Option<&Torque>, origin: String) -> Ratings {
        Ratings {
            rated: torque.and_then(|t| t.rated),
            repeated_peak: torque.and_then(|t| t.repeated_peak),
            origin,
        }
    }
}

/// N m of output-referred control torque per unit of the reduced model's ũ: L·N²·J_i/T².
pub fn torque_scale(d: &PhysicalParams, r: &Reduction) -> f64 {
    r.length_scale * d.ratio * d.ratio * d.j_in / (r.time_scale * r.time_scale)
}

/// One law's control torque on the drive, in N m.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DriveEffort {
    /// The law's kind.
    pub law: &'static str,
    /// The gain (dimensionless, the term's first parameter).
    pub gain: f64,
    /// Peak |u|/N, the torque the motor delivers \[N m\].
    pub motor_peak: f64,
    /// RMS of u/N at the motor \[N m\].
    pub motor_rms: f64,
    /// Peak |u|, referred to the output: what the ratings are set against \[N m\].
    pub output_peak: f64,
    /// The output speed the mean of u gives the rigid-body mode per slow period,
    /// ū·(2π/Ω)/(J_o + N²J_i) \[rad/s\]: how fast the drive drifts unless the position loop
    /// takes the mean back.
    pub rigid_drift: f64,
    /// `output_peak` over the repeated peak torque (None without the rating).
    pub of_repeated_peak: Option<f64>,
    /// `output_peak` over the rated torque (None without the rating).
    pub of_rated: Option<f64>,
}

impl DriveEffort {
    /// `a`'s effort on the drive `d` with reduction `r`, against `ratings`.
    pub fn of(a: &Assessment, d: &PhysicalParams, r: &Reduction, ratings: &Ratings) -> Self {
        let s = torque_scale(d, r);
        let output_peak = s * a.effort_peak;
        let period = std::f64::consts::TAU / d.omega;
        DriveEffort {
            law: a.term.kind(),
            gain: a.gain,
            motor_peak: output_peak / d.ratio,
            motor_rms: s * a.effort_rms / d.ratio,
            output_peak,
            rigid_drift: s * a.effort_mean * period / (d.j_out + d.ratio * d.ratio * d.j_in),
            of_repeated_peak: ratings.repeated_peak.map(|t| output_peak / t),
            of_rated: ratings.rated.map(|t| output_peak / t),
        }
    }

    /// The effort against the ratings: the first limit it exceeds, the repeated peak torque
    /// before the rated one.
    pub fn check(&self) -> RatingCheck {
        match (self.of_repeated_peak, self.of_rated) {
            (Some(f), _) if f > 1.0 => RatingCheck::AboveRepeatedPeak,
            (_, Some(f)) if f > 1.0 => RatingCheck::AboveRated,
            (None, None) => RatingCheck::NoRatings,
            _ => RatingCheck::Within,
        }
    }
}

/// A law's peak torque against the drive's ratings ([`DriveEffort::check`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum RatingCheck {
    /// Above the limit for repeated peak torque.
    AboveRepeatedPeak,
    /// Above the rated torque (within the repeated peak, or without that rating).
    AboveRated,
    /// Within every rating given.
    Within,
    /// The drive has no ratings to check against.
    NoRatings,
}

impl RatingCheck {
    /// In words.
    pub fn text(self) -> &'static str {
        match self {
            RatingCheck::AboveRepeatedPeak => "above the repeated peak torque",
            RatingCheck::AboveRated => "above the rated torque",
            RatingCheck::Within => "within the ratings",
            RatingCheck::NoRatings => "no ratings to check",
        }
    }
}

/// The laws compared on a physical drive: the dimensionless comparison on its reduction and each
/// law's effort in N m.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DriveControl {
    /// The drive.
    pub drive: PhysicalParams,
    /// Its reduction (the comparison's parameters and the scales).
    pub reduction: Reduction,
    /// The ratings the efforts are set against.
    pub ratings: Ratings,
    /// N m of output-referred control torque per unit ũ ([`torque_scale`]).
    pub torque_scale: f64,
    /// The comparison on the reduced model.
    pub comparison: Comparison,
    /// Each row's effort in N m, in [`Comparison::rows`]' order.
    pub efforts: Vec<DriveEffort>,
}

/// [`compare`] on the drive `d`'s reduction, each row's effort read back in N m against
/// `ratings`. An error when the drive does not reduce (no backlash or no cubic stiffness) or its
/// open loop does not burst (when tuning).
pub fn compare_drive(
    d: &PhysicalParams,
    ratings: Ratings,
    laws: &[&str],
    c: &ControlOptions,
    opts: &BurstOptions,
) -> Result<DriveControl> {
    let r = d.reduce()?;
    let comparison = compare(&r.params, laws, c, opts)?;
    let efforts = comparison
        .rows()
        .map(|a| DriveEffort::of(a, d, &r, &ratings))
        .collect();
    Ok(DriveControl {
        drive: *d,
        reduction: r,
        torque_scale: torque_scale(d, &r),
        ratings,
        comparison,
        efforts,
    })
}
