//! Catalogue drives and the fit of the cubic torque-twist law to their piecewise-linear curves.
//!
//! Source of the stiffness data: Harmonic Drive CSF series component-set catalogue, table
//! "Torsional stiffness" (T1, T2 \[N m\] and K1, K2, K3 \[N m/rad\]; the torque-twist curve is
//! linear with slope K1 up to T1, K2 from T1 to T2 and K3 above T2), with the values quoted in
//! hdgear's physical-model issue. Only the stiffness comes from the catalogue: inertias,
//! damping, load, disturbance and backlash are the user's, and the defaults below are stated
//! assumptions.

use super::PhysicalParams;
use crate::error::{Error, Result};
use serde::Serialize;

/// A drive's catalogue stiffness data.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CatalogueDrive {
    /// Model name, e.g. `CSF-14-50`.
    pub name: &'static str,
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
}

/// The catalogue drives: CSF-14-50, CSF-20-50, CSF-32-50, CSF-32-30.
pub const DRIVES: [CatalogueDrive; 4] = [
    CatalogueDrive {
        name: "CSF-14-50",
        ratio: 50.0,
        t1: 2.0,
        t2: 6.9,
        k1: 0.34e4,
        k2: 0.47e4,
        k3: None,
    },
    CatalogueDrive {
        name: "CSF-20-50",
        ratio: 50.0,
        t1: 7.0,
        t2: 25.0,
        k1: 1.3e4,
        k2: 1.8e4,
        k3: None,
    },
    CatalogueDrive {
        name: "CSF-32-50",
        ratio: 50.0,
        t1: 29.0,
        t2: 108.0,
        k1: 5.4e4,
        k2: 7.8e4,
        k3: None,
    },
    CatalogueDrive {
        name: "CSF-32-30",
        ratio: 30.0,
        t1: 29.0,
        t2: 108.0,
        k1: 2.4e4,
        k2: 3.0e4,
        k3: Some(4.9e4),
    },
];

impl CatalogueDrive {
    /// The drive by name (case-insensitive).
    pub fn by_name(name: &str) -> Result<CatalogueDrive> {
        DRIVES
            .iter()
            .find(|d| d.name.eq_ignore_ascii_case(name))
            .copied()
            .ok_or_else(|| Error::UnknownPreset {
                name: name.into(),
                known: DRIVES.map(|d| d.name).join(", "),
            })
    }

    /// Largest torque the piecewise-linear curve is defined to: T2, or 2·T2 with a K3 segment.
    pub fn max_torque(&self) -> f64 {
        if self.k3.is_some() {
            2.0 * self.t2
        } else {
            self.t2
        }
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
pub struct Fit {
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
pub fn fit(d: &CatalogueDrive, t_fit: f64) -> Result<Fit> {
    if !(t_fit.is_finite() && t_fit > 0.0 && t_fit <= d.max_torque()) {
        return Err(Error::InvalidOption {
            name: "fit_torque",
            value: t_fit,
            reason: "must be > 0 and within the catalogue curve (T2, or 2·T2 where K3 is given)",
        });
    }
    // sample the curve uniformly in twist: θ from 0 to θ(t_fit), T(θ) by inverting the segments
    let th_max = d.twist(t_fit);
    let torque = |th: f64| {
        let (th1, th2) = (d.twist(d.t1), d.twist(d.t2));
        if th <= th1 {
            d.k1 * th
        } else if th <= th2 {
            d.t1 + d.k2 * (th - th1)
        } else {
            d.t2 + d.k3.unwrap_or(d.k2) * (th - th2)
        }
    };
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
    Ok(Fit {
        t_fit,
        k1,
        k2,
        max_torque_error,
        twist_error_t1: rel(d.t1),
        twist_error_t2: if d.t2 <= t_fit { rel(d.t2) } else { f64::NAN },
    })
}

/// The assumptions behind a catalogue preset's non-catalogue values.
pub const ASSUMPTIONS: [&str; 6] = [
    "backlash = 1 arc-min (2.909e-4 rad): the order of the CSF catalogue's lost motion, used as phi",
    "j_in = 5e-5 kg m^2 (motor rotor + wave generator), j_out = 0.05 kg m^2 (load): typical, not catalogue values",
    "c_eq = 2 * 0.1 * sqrt(k1 * J_eq): 10 % damping ratio of the linear torsional mode",
    "t_m = T1 (mean load at the first knee of the torque-twist curve)",
    "t_am = 0.25 * T1 (slow output-torque disturbance)",
    "omega = 2 pi * 0.5 rad/s (a 0.5 Hz disturbance)",
];

/// A complete drive from catalogue stiffness (fitted up to `t_fit`, default T2) and the
/// documented assumptions ([`ASSUMPTIONS`]) for everything else.
pub fn preset(name: &str, t_fit: Option<f64>) -> Result<(PhysicalParams, Fit)> {
    let d = CatalogueDrive::by_name(name)?;
    let f = fit(&d, t_fit.unwrap_or(d.t2))?;
    let (j_in, j_out) = (5e-5, 0.05);
    let n2ji = d.ratio * d.ratio * j_in;
    let j_eq = n2ji * j_out / (n2ji + j_out);
    let p = PhysicalParams {
        j_in,
        j_out,
        ratio: d.ratio,
        k1: f.k1,
        k2: f.k2,
        backlash: (1.0f64 / 60.0).to_radians(),
        c_eq: 2.0 * 0.1 * (f.k1 * j_eq).sqrt(),
        t_m: d.t1,
        t_am: 0.25 * d.t1,
        omega: std::f64::consts::TAU * 0.5,
    };
    p.validate()?;
    Ok((p, f))
}
