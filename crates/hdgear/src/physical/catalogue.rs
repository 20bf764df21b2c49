//! Catalogue stiffness curves and the fit of the cubic torque-twist law to them; a drive built
//! from a card ([`super::card`]) and the documented assumptions for what a card leaves out.
//!
//! The catalogue's torque-twist curve is linear with slope K1 up to T1, K2 from T1 to T2 and K3
//! above T2. Only the card's numbers come from a catalogue: inertias of the application,
//! damping (unless derived from the hysteresis loss), load, disturbance and backlash are the
//! user's, and the defaults below ([`ASSUMPTIONS`]) are stated assumptions.

use super::PhysicalParams;
use super::card::{Card, builtin_card};
use crate::error::{Error, Result};
use serde::Serialize;

/// A drive's piecewise-linear stiffness curve, from its card ([`Card::curve`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CatalogueDrive {
    /// Model name, e.g. `CSF-14-50`.
    pub name: String,
    /// Reduction ratio.
    pub ratio: f64,
    /// T1 \[N m\]: end of the first linear segment.
    pub t1: f64,
    /// T2 \[N m\]: end of the second linear segment.
    pub t2: f64,
    /// K1 \[N m/rad\]: stiffness from 0 to T1.
    pub k1: f64,
    /// K2 \[N m/rad\]: stiffness from T1 to T2.
    pub k2: f64,
    /// K3 \[N m/rad\]: stiffness above T2, where the catalogue gives it.
    pub k3: Option<f64>,
    /// The largest torque the curve is used to \[N m\]: the momentary peak torque where the
    /// card rates it, else T2 (2·T2 with a K3 segment).
    pub t_max: f64,
}

impl Card {
    /// The card's piecewise-linear stiffness curve.
    pub fn curve(&self) -> CatalogueDrive {
        let s = &self.stiffness;
        let (t2, k3) = (s.t2.unwrap_or(f64::NAN), s.k3);
        // The curve runs to the momentary peak torque where the catalogue rates it; without a
        // rating, to T2 (or 2·T2 with a K3 segment, whose end the catalogue does not give).
        let rated_end = self.torque.as_ref().and_then(|t| t.momentary_peak);
        let t_max = match (k3, rated_end) {
            (None, _) => t2,
            (Some(_), Some(m)) => m.max(t2),
            (Some(_), None) => 2.0 * t2,
        };
        CatalogueDrive {
            name: self.name.clone(),
            ratio: self.ratio,
            t1: s.t1.unwrap_or(f64::NAN),
            t2,
            k1: s.k1.unwrap_or(f64::NAN),
            k2: s.k2.unwrap_or(f64::NAN),
            k3,
            t_max,
        }
    }
}

impl CatalogueDrive {
    /// The built-in drive's curve by name (case-insensitive).
    pub fn by_name(name: &str) -> Result<CatalogueDrive> {
        Ok(builtin_card(name)?.curve())
    }

    /// Largest torque the curve is used to ([`Self::t_max`]).
    pub fn max_torque(&self) -> f64 {
        self.t_max
    }

    /// Torque T(θ) \[N m\] of the curve at twist θ ≥ 0 (the inverse of [`Self::twist`]).
    pub fn torque(&self, th: f64) -> f64 {
        let (th1, th2) = (self.twist(self.t1), self.twist(self.t2));
        if th <= th1 {
            self.k1 * th
        } else if th <= th2 {
            self.t1 + self.k2 * (th - th1)
        } else {
            self.t2 + self.k3.unwrap_or(self.k2) * (th - th2)
        }
    }

    /// Elastic energy ∫₀^θ(T) T dθ \[J\] stored at torque T ≥ 0 (exact: the curve is linear on
    /// each segment, so each contributes the mean of its end torques times its twist).
    pub fn energy(&self, t: f64) -> f64 {
        let mut e = 0.0;
        let mut lo = 0.0;
        for knee in [self.t1, self.t2, f64::INFINITY] {
            let hi = t.min(knee);
            if hi > lo {
                e += 0.5 * (lo + hi) * (self.twist(hi) - self.twist(lo));
            }
            lo = knee;
            if t <= knee {
                break;
            }
        }
        e
    }

    /// The equivalent damping ratio ζ = E_d/(4π E_s) of a ±`amplitude` torque cycle whose
    /// loop has the constant twist width `loss` (the catalogue's hysteresis loss): the loop is
    /// a parallelogram of width `loss` and height 2·amplitude, E_d = 2·loss·amplitude, and E_s
    /// is the elastic energy at the amplitude ([`Self::energy`]).
    ///
    /// ```
    /// let d = hdgear::physical::catalogue::CatalogueDrive::by_name("CSG-20-50").unwrap();
    /// let zeta = d.equivalent_damping(1f64.to_radians() / 60.0, 33.0);
    /// assert!((zeta - 0.0546).abs() < 1e-3);
    /// ```
    pub fn equivalent_damping(&self, loss: f64, amplitude: f64) -> f64 {
        2.0 * loss * amplitude / (4.0 * std::f64::consts::PI * self.energy(amplitude))
    }

    /// Catalogue twist θ(T) \[rad\] of the piecewise-linear curve, for 0 ≤ T ≤ max_torque.
    pub fn twist(&self, t: f64) -> f64 {
        if t <= self.t1 {
            t / self.k1
        } else if t <= self.t2 {
            self.t1 / self.k1 + (t - self.t1) / self.k2
        } else {
            let k3 = self.k3.unwrap_or(self.k2);
            self.t1 / self.k1 + (self.t2 - self.t1) / self.k2 + (t - self.t2) / k3
        }
    }
}

/// The least-squares fit T(θ) = k1 θ + k2 θ³ of a catalogue curve up to a torque.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CubicFit {
    /// The torque the fit runs to \[N m\].
    pub t_fit: f64,
    /// k1 \[N m/rad\].
    pub k1: f64,
    /// k2 \[N m/rad³\].
    pub k2: f64,
    /// Largest |T_fit(θ) − T_catalogue(θ)| over the fitted range, relative to t_fit.
    pub max_torque_error: f64,
    /// Relative twist error at T1: |θ_fit(T1) − θ_cat(T1)| / θ_cat(T1).
    pub twist_error_t1: f64,
    /// Relative twist error at T2 (when T2 ≤ t_fit).
    pub twist_error_t2: f64,
}

/// The twist θ ≥ 0 with k1 θ + k2 θ³ = T (monotone for k1, k2 ≥ 0), by bisection.
pub fn cubic_twist(k1: f64, k2: f64, t: f64) -> f64 {
    let f = |x: f64| k1 * x + k2 * x * x * x - t;
    let mut hi = 1e-6;
    while f(hi) < 0.0 && hi < 1e6 {
        hi *= 2.0;
    }
    let (lo, hi) = crate::roots::bisect(0.0, hi, 200, crate::roots::all_rounds, |m| f(m) < 0.0);
    0.5 * (lo + hi)
}

/// Fits k1 θ + k2 θ³ to the catalogue curve on 0 ≤ T ≤ `t_fit`: 2001 points uniform in twist,
/// least squares on the secant stiffness T/θ = k1 + k2 θ² (each point weighted by its relative
/// error).
///
/// ```
/// use hdgear::physical::catalogue::{CatalogueDrive, fit};
/// let d = CatalogueDrive::by_name("CSF-20-50").unwrap();
/// let f = fit(&d, d.t2).unwrap();
/// assert!(f.k1 > 0.0 && f.k2 > 0.0);
/// ```
pub fn fit(d: &CatalogueDrive, t_fit: f64) -> Result<CubicFit> {
    if !(t_fit.is_finite() && t_fit > 0.0 && t_fit <= d.max_torque()) {
        return Err(Error::InvalidOption {
            name: "fit_torque",
            value: t_fit,
            reason: "must be > 0 and within the catalogue curve (up to its momentary peak torque, T2 \
                     without K3, 2·T2 with K3 but no rating)",
        });
    }
    // sample the curve uniformly in twist: θ from 0 to θ(t_fit), T(θ) by inverting the segments
    let th_max = d.twist(t_fit);
    let torque = |th: f64| d.torque(th);
    let m = 2001;
    let pts: Vec<(f64, f64)> = (0..m)
        .map(|i| {
            let th = th_max * i as f64 / (m - 1) as f64;
            (th, torque(th))
        })
        .collect();
    // Fit the secant stiffness T/θ = k1 + k2 θ² (a straight line in θ²): every point then
    // weighs by its relative error, so the low-torque knee is not sacrificed to the high end.
    let (mut n, mut sx, mut sxx, mut sy, mut sxy) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for &(th, t) in pts.iter().skip(1) {
        let (x, y) = (th * th, t / th);
        n += 1.0;
        sx += x;
        sxx += x * x;
        sy += y;
        sxy += x * y;
    }
    let k2 = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    let k1 = (sy - k2 * sx) / n;
    let max_torque_error = pts
        .iter()
        .map(|&(th, t)| (k1 * th + k2 * th * th * th - t).abs())
        .fold(0.0, f64::max)
        / t_fit;
    let rel = |t: f64| (cubic_twist(k1, k2, t) - d.twist(t)).abs() / d.twist(t);
    Ok(CubicFit {
        t_fit,
        k1,
        k2,
        max_torque_error,
        twist_error_t1: rel(d.t1),
        twist_error_t2: if d.t2 <= t_fit { rel(d.t2) } else { f64::NAN },
    })
}

/// One value hdgear assumes when a card's `[application]` leaves it out.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Assumed {
    /// The application key it stands for.
    pub key: &'static str,
    /// What is assumed, and why.
    pub text: &'static str,
}

/// The assumptions behind a drive built from a card without an `[application]` section.
pub const ASSUMPTIONS: [Assumed; 7] = [
    Assumed {
        key: "backlash",
        text: "backlash = 1 arc-min (2.909e-4 rad): the order of the CSF catalogue's lost motion, used as phi",
    },
    Assumed {
        key: "j_motor",
        text: "j_in = 5e-5 kg m^2 (motor rotor, typical) plus the card's wave-generator inertia where it gives one",
    },
    Assumed {
        key: "j_load",
        text: "j_out = 0.05 kg m^2 (load): typical, not a catalogue value",
    },
    Assumed {
        key: "zeta",
        text: "c_eq = 2 * 0.1 * sqrt(k1 * J_eq): 10 % damping ratio of the linear torsional mode",
    },
    Assumed {
        key: "t_mean",
        text: "t_m = T1 (mean load at the first knee of the torque-twist curve)",
    },
    Assumed {
        key: "t_amp",
        text: "t_am = 0.25 * T1 (slow output-torque disturbance)",
    },
    Assumed {
        key: "frequency",
        text: "omega = 2 pi * 0.5 rad/s (a 0.5 Hz disturbance)",
    },
];

/// The texts of [`ASSUMPTIONS`].
pub fn assumption_texts() -> Vec<&'static str> {
    ASSUMPTIONS.iter().map(|a| a.text).collect()
}

/// A drive built from a card: the physical parameters, the stiffness fit and what was assumed.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Assembled {
    /// The drive.
    pub drive: PhysicalParams,
    /// The cubic fit of the card's curve.
    pub fit: CubicFit,
    /// The damping ratio of the linear torsional mode the drive was given.
    pub zeta: f64,
    /// The assumptions standing in for the application values the card leaves out.
    pub assumptions: Vec<&'static str>,
}

/// A complete drive from a card: its stiffness fitted up to `t_fit` (default T2), the card's
/// `[application]` values, and the documented assumptions ([`ASSUMPTIONS`]) for the rest. The
/// damping is `zeta` when given, else the application's, else the assumed 10 %.
pub fn assemble(card: &Card, t_fit: Option<f64>, zeta: Option<f64>) -> Result<Assembled> {
    let d = card.curve();
    let f = fit(&d, t_fit.unwrap_or(d.t2))?;
    let app = card.application.clone().unwrap_or_default();
    let mut assumptions = Vec::new();
    let mut pick = |key: &str, given: Option<f64>, default: f64| {
        given.unwrap_or_else(|| {
            let a = ASSUMPTIONS
                .iter()
                .find(|a| a.key == key)
                .expect("every key has a text");
            assumptions.push(a.text);
            default
        })
    };
    let backlash = pick("backlash", app.backlash, (1.0f64 / 60.0).to_radians());
    let wave_generator = card.inertia.as_ref().and_then(|i| i.input).unwrap_or(0.0);
    let j_in = pick("j_motor", app.j_motor, 5e-5) + wave_generator;
    let j_out = pick("j_load", app.j_load, 0.05);
    let zeta = match zeta {
        Some(z) => z,
        None => pick("zeta", app.zeta, 0.1),
    };
    let t_m = pick("t_mean", app.t_mean, d.t1);
    let t_am = pick("t_amp", app.t_amp, 0.25 * d.t1);
    let hz = pick("frequency", app.frequency, 0.5);
    let n2ji = d.ratio * d.ratio * j_in;
    let j_eq = n2ji * j_out / (n2ji + j_out);
    let p = PhysicalParams {
        j_in,
        j_out,
        ratio: d.ratio,
        k1: f.k1,
        k2: f.k2,
        backlash,
        c_eq: 2.0 * zeta * (f.k1 * j_eq).sqrt(),
        t_m,
        t_am,
        omega: std::f64::consts::TAU * hz,
    };
    // values each within range may still combine into a drive parameter out of it: the card is
    // named, and the parameter as the drive's
    p.validate().map_err(|e| match e {
        crate::Error::InvalidParameter {
            name,
            value,
            reason,
        } => crate::Error::Card {
            card: card.name.clone(),
            field: format!("the drive's {name} (from its values)"),
            value: format!("{value:e}"),
            reason,
        },
        other => other,
    })?;
    Ok(Assembled {
        drive: p,
        fit: f,
        zeta,
        assumptions,
    })
}

/// A complete built-in drive by name, fitted up to `t_fit` (default T2), with the documented
/// assumptions ([`ASSUMPTIONS`]) for everything the card does not give.
pub fn preset(name: &str, t_fit: Option<f64>) -> Result<(PhysicalParams, CubicFit)> {
    let a = assemble(builtin_card(name)?, t_fit, None)?;
    Ok((a.drive, a.fit))
}
