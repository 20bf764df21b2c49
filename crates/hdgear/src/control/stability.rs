//! Where delayed feedback destabilises the loop, from its characteristic roots, before any
//! simulation ([`delay_limit`]).
//!
//! About an equilibrium of stiffness k the closed loop with ũ = K·(x(τ − τ_d) − x(τ)) is
//! y'' + y' + (k + K)·y − K·y(τ − τ_d) = 0, whose roots solve
//! λ² + λ + k + K − K·e^(−λτ_d) = 0. At K = 0 they are the damped oscillator's (k > 0: stable);
//! they move continuously with K and can reach the right half-plane only through λ = iw. There the
//! real and imaginary parts give K = −w / sin(wτ_d) and k = w² + w·tan(wτ_d/2), with
//! wτ_d ∈ ((2n − 1)π, 2nπ) for K > 0 (λ = 0 is a root only at k = 0). On branch n,
//! k(w) runs from −∞ to (2nπ/τ_d)², so it meets a given k once where k < (2nπ/τ_d)²; the least
//! K over the branches is where the first pair crosses. Below it the loop is stable at that
//! equilibrium; the limit of a plant is the least over the stiffnesses its state meets.

use super::Plant;
use crate::error::Result;
use crate::model::delay::Delay;
use crate::model::terms::Term;
use serde::Serialize;
use std::f64::consts::PI;

/// The gain at which delayed feedback first makes an equilibrium of the plant unstable.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct DelayLimit {
    /// The delay τ_d.
    pub taud: f64,
    /// The least gain K at which a pair of roots reaches the imaginary axis.
    pub gain: f64,
    /// The stiffness k of the equilibrium where it does.
    pub stiffness: f64,
    /// The crossing pair's angular frequency w (λ = ±iw).
    pub frequency: f64,
}

/// The least gain K > 0 at which λ² + λ + k + K − K·e^(−λτ_d) = 0 has a root on the imaginary
/// axis, with that root's w (module docs), for stiffness k > 0. Branch n's K exceeds
/// (2n − 1)π/τ_d (K = w/|sin wτ_d| ≥ w), so the branches stop once that passes the least found.
pub fn crossing_gain(k: f64, taud: f64) -> (f64, f64) {
    let mut best = (f64::INFINITY, f64::NAN);
    for n in 1.. {
        let (lo, hi) = ((2 * n - 1) as f64 * PI / taud, (2 * n) as f64 * PI / taud);
        if lo >= best.0 {
            break;
        }
        if k >= hi * hi {
            continue;
        }
        let h = |w: f64| w * w + w * (0.5 * w * taud).tan() - k;
        // strictly inside the branch: tan is finite there, −∞ and 0 at its ends
        let (a, b) = (lo * (1.0 + 1e-12), hi * (1.0 - 1e-12));
        let (ha, hb) = (h(a), h(b));
        if !(ha < 0.0 && hb > 0.0) {
            continue;
        }
        let w = crate::roots::brent(h, a, ha, b, hb, 4.0 * f64::EPSILON * hi);
        let gain = -w / (w * taud).sin();
        if gain > 0.0 && gain < best.0 {
            best = (gain, w);
        }
    }
    best
}

/// Stiffnesses sampled over a plant's range in [`delay_limit`]: the crossing gain is smooth in
/// k, and the least sample is then refined by golden sections to the range's 1e-9.
const SAMPLES: usize = 256;

/// The delayed feedback's stability limit on `p` with delay `taud`: the least crossing gain
/// over the stiffnesses of the equilibrium its state follows ([`Plant::stiffness_range`]).
/// `None` when that range holds no positive stiffness (a fold: the jumps are refused before).
pub fn delay_limit<P: Plant>(p: &P, taud: f64) -> Result<Option<DelayLimit>> {
    let (k_lo, k_hi) = p.stiffness_range()?;
    if k_hi.is_nan() || k_hi <= 0.0 || !taud.is_finite() || taud <= 0.0 {
        return Ok(None);
    }
    let k_lo = k_lo.max(f64::MIN_POSITIVE);
    let at = |j: usize| k_lo + (k_hi - k_lo) * j as f64 / SAMPLES as f64;
    let gain = |k: f64| crossing_gain(k, taud).0;
    // each sample's gain once, then the least
    let samples: Vec<f64> = (0..=SAMPLES).map(|j| gain(at(j))).collect();
    let best = (0..=SAMPLES)
        .min_by(|&i, &j| samples[i].total_cmp(&samples[j]))
        .unwrap_or(0);
    // golden sections over the samples around the least one, one new evaluation per section
    let (mut a, mut b) = (at(best.saturating_sub(1)), at((best + 1).min(SAMPLES)));
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - r * (b - a), a + r * (b - a));
    let (mut gc, mut gd) = (gain(c), gain(d));
    while b - a > 1e-9 * (k_hi - k_lo).max(k_hi * f64::EPSILON) {
        if gc <= gd {
            (b, d, gd) = (d, c, gc);
            c = b - r * (b - a);
            gc = gain(c);
        } else {
            (a, c, gc) = (c, d, gd);
            d = a + r * (b - a);
            gd = gain(d);
        }
    }
    let mid = 0.5 * (a + b);
    let k = if gain(mid) < samples[best] {
        mid
    } else {
        at(best)
    };
    let (g, w) = crossing_gain(k, taud);
    Ok(g.is_finite().then_some(DelayLimit {
        taud,
        gain: g,
        stiffness: k,
        frequency: w,
    }))
}

/// The stability limit of law `law` with its other parameters `rest` on `p`: the delayed
/// feedback's ([`delay_limit`]); `None` for the laws without a delay, stable at every gain.
pub(super) fn law_limit<P: Plant>(p: &P, law: &str, rest: &[f64]) -> Result<Option<DelayLimit>> {
    if law != Delay::KIND {
        return Ok(None);
    }
    delay_limit(p, rest.first().copied().unwrap_or(f64::NAN))
}
