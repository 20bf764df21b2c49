//! Distributions of a toleranced parameter, the normal distribution's CDF and quantile, and the
//! Wilson interval of a binomial proportion: what a card's tolerances and [`crate::robust`]
//! read and compute with (it needs nothing but the error type).

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};

/// How far a normal or log-normal tolerance reaches for the worst case: ±3 standard deviations
/// (99.73 % of the parts).
pub const BOX_SIGMAS: f64 = 3.0;

/// The spread of one parameter.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Distribution {
    /// Uniform on [lo, hi].
    Uniform {
        /// Lower end.
        lo: f64,
        /// Upper end.
        hi: f64,
    },
    /// Normal.
    Normal {
        /// Mean.
        mean: f64,
        /// Standard deviation.
        sd: f64,
    },
    /// Log-normal: ln X ~ N(ln median, σ²).
    LogNormal {
        /// The median.
        median: f64,
        /// σ of ln X.
        sigma: f64,
    },
    /// Normal truncated to [lo, hi].
    TruncatedNormal {
        /// Mean of the untruncated normal.
        mean: f64,
        /// Its standard deviation.
        sd: f64,
        /// Lower end.
        lo: f64,
        /// Upper end.
        hi: f64,
    },
}

/// Φ(x), the standard normal CDF.
pub fn normal_cdf(x: f64) -> f64 {
    0.5 * libm::erfc(-x / std::f64::consts::SQRT_2)
}

/// Φ⁻¹(p) for p in (0, 1): Acklam's rational approximation (relative error 1.2e-9) polished by
/// one Halley step on Φ(x) − p, which brings it to rounding level.
pub fn normal_quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] = [
        7.784_695_709_041_462e-3,
        3.224_671_290_700_398e-1,
        2.445_134_137_142_996,
        3.754_408_661_907_416,
    ];
    if p <= 0.0 {
        return f64::NEG_INFINITY;
    }
    if p >= 1.0 {
        return f64::INFINITY;
    }
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    let x = if p < 0.02425 {
        tail((-2.0 * p.ln()).sqrt())
    } else if p > 1.0 - 0.02425 {
        -tail((-2.0 * (1.0 - p).ln()).sqrt())
    } else {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    };
    // Halley: e = Φ(x) − p, u = e·√(2π)·exp(x²/2), x ← x − u/(1 + x u/2)
    let e = normal_cdf(x) - p;
    let u = e * (2.0 * std::f64::consts::PI).sqrt() * (0.5 * x * x).exp();
    x - u / (1.0 + 0.5 * x * u)
}

impl Distribution {
    /// Checks the distribution's own parameters (finite, positive spreads, lo < hi).
    pub fn validate(&self) -> Result<()> {
        let bad = crate::error::bad_option;
        let finite = |name, v: f64| {
            if v.is_finite() {
                Ok(())
            } else {
                bad(name, v, "must be finite")
            }
        };
        match *self {
            Distribution::Uniform { lo, hi } => {
                finite("lo", lo)?;
                finite("hi", hi)?;
                if hi <= lo {
                    return bad("hi", hi, "must exceed lo");
                }
            }
            Distribution::Normal { mean, sd } => {
                finite("mean", mean)?;
                if !(sd > 0.0 && sd.is_finite()) {
                    return bad("sd", sd, "must be positive and finite");
                }
            }
            Distribution::LogNormal { median, sigma } => {
                if !(median > 0.0 && median.is_finite()) {
                    return bad("median", median, "must be positive and finite");
                }
                if !(sigma > 0.0 && sigma.is_finite()) {
                    return bad("sigma", sigma, "must be positive and finite");
                }
            }
            Distribution::TruncatedNormal { mean, sd, lo, hi } => {
                Distribution::Normal { mean, sd }.validate()?;
                Distribution::Uniform { lo, hi }.validate()?;
                let mass = normal_cdf((hi - mean) / sd) - normal_cdf((lo - mean) / sd);
                if mass < 1e-12 {
                    return bad("lo", lo, "the truncation keeps no probability mass");
                }
            }
        }
        Ok(())
    }

    /// The value with probability u below it (u in (0, 1)).
    pub fn quantile(&self, u: f64) -> f64 {
        match *self {
            Distribution::Uniform { lo, hi } => lo + u * (hi - lo),
            Distribution::Normal { mean, sd } => mean + sd * normal_quantile(u),
            Distribution::LogNormal { median, sigma } => {
                median * (sigma * normal_quantile(u)).exp()
            }
            Distribution::TruncatedNormal { mean, sd, lo, hi } => {
                let (fa, fb) = (normal_cdf((lo - mean) / sd), normal_cdf((hi - mean) / sd));
                let x = mean + sd * normal_quantile(fa + u * (fb - fa));
                x.clamp(lo, hi)
            }
        }
    }

    /// The value at standard-normal coordinate z (the quantile of Φ(z)); exact for the normal
    /// and log-normal, whose tails Φ would round away beyond |z| ≈ 8.
    pub fn from_standard(&self, z: f64) -> f64 {
        match *self {
            Distribution::Normal { mean, sd } => mean + sd * z,
            Distribution::LogNormal { median, sigma } => median * (sigma * z).exp(),
            _ => self.quantile(normal_cdf(z).clamp(f64::MIN_POSITIVE, 1.0 - f64::EPSILON / 2.0)),
        }
    }

    /// The distribution of c·X (c > 0): a band given in % of a nominal value scales with it.
    pub fn scaled(&self, c: f64) -> Distribution {
        match *self {
            Distribution::Uniform { lo, hi } => Distribution::Uniform {
                lo: c * lo,
                hi: c * hi,
            },
            Distribution::Normal { mean, sd } => Distribution::Normal {
                mean: c * mean,
                sd: c * sd,
            },
            Distribution::LogNormal { median, sigma } => Distribution::LogNormal {
                median: c * median,
                sigma,
            },
            Distribution::TruncatedNormal { mean, sd, lo, hi } => Distribution::TruncatedNormal {
                mean: c * mean,
                sd: c * sd,
                lo: c * lo,
                hi: c * hi,
            },
        }
    }

    /// The probability of a value at most x.
    pub fn cdf(&self, x: f64) -> f64 {
        match *self {
            Distribution::Uniform { lo, hi } => ((x - lo) / (hi - lo)).clamp(0.0, 1.0),
            Distribution::Normal { mean, sd } => normal_cdf((x - mean) / sd),
            Distribution::LogNormal { median, sigma } if x > 0.0 => {
                normal_cdf((x / median).ln() / sigma)
            }
            Distribution::LogNormal { .. } => 0.0,
            Distribution::TruncatedNormal { mean, sd, lo, hi } => {
                let (fa, fb) = (normal_cdf((lo - mean) / sd), normal_cdf((hi - mean) / sd));
                ((normal_cdf((x.clamp(lo, hi) - mean) / sd) - fa) / (fb - fa)).clamp(0.0, 1.0)
            }
        }
    }

    /// The tolerance box's edges for the worst case: the support when bounded, else ±
    /// [`BOX_SIGMAS`] standard deviations (of ln X for the log-normal).
    pub fn range(&self) -> (f64, f64) {
        match *self {
            Distribution::Uniform { lo, hi } | Distribution::TruncatedNormal { lo, hi, .. } => {
                (lo, hi)
            }
            Distribution::Normal { mean, sd } => (mean - BOX_SIGMAS * sd, mean + BOX_SIGMAS * sd),
            Distribution::LogNormal { median, sigma } => (
                median * (-BOX_SIGMAS * sigma).exp(),
                median * (BOX_SIGMAS * sigma).exp(),
            ),
        }
    }

    /// Reads a tolerance as users write it, around the nominal value `nominal`:
    ///
    /// | text | distribution |
    /// |---|---|
    /// | `±20%` or `+-20%` | uniform on nominal·(1 ± 0.2) |
    /// | `±0.5` | uniform on nominal ± 0.5 |
    /// | `LO..HI` | uniform on [LO, HI] |
    /// | `normal:5%` or `normal:0.1` | normal, mean the nominal, sd 5 % of it (or 0.1) |
    /// | `lognormal:10%` | log-normal, median the nominal, σ of ln X = 0.10 |
    /// | `tnormal:5%:±10%` | the normal truncated to the band |
    ///
    /// ```
    /// use hdgear::robust::Distribution;
    /// let d = Distribution::parse("±20%", 10.0).unwrap();
    /// assert_eq!(d, Distribution::Uniform { lo: 8.0, hi: 12.0 });
    /// assert!(Distribution::parse("±20", -1.0).is_ok());
    /// assert!(Distribution::parse("normal:x", 1.0).is_err());
    /// ```
    pub fn parse(text: &str, nominal: f64) -> Result<Distribution> {
        let bad = |reason: &str| Error::InvalidInput {
            what: "tolerance",
            text: text.to_string(),
            reason: reason.to_string(),
        };
        let number = |s: &str| -> Result<f64> {
            let v: f64 = s.trim().parse().map_err(|_| {
                bad("expected a number (±X%, ±X, LO..HI, normal:SD, lognormal:S%, tnormal:SD:±X)")
            })?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(bad("the number must be finite"))
            }
        };
        // an absolute amount, or a percentage of the nominal value
        let amount = |s: &str| -> Result<f64> {
            match s.trim().strip_suffix('%') {
                Some(p) => Ok(number(p)? / 100.0 * nominal.abs()),
                None => number(s),
            }
        };
        let band = |s: &str| -> Result<(f64, f64)> {
            let s = s.trim();
            let w = s
                .strip_prefix('±')
                .or_else(|| s.strip_prefix("+-"))
                .map(amount)
                .transpose()?;
            match w {
                Some(w) => Ok((nominal - w, nominal + w)),
                None => match s.split_once("..") {
                    Some((lo, hi)) => Ok((number(lo)?, number(hi)?)),
                    None => Err(bad("expected a band: ±X%, ±X or LO..HI")),
                },
            }
        };
        let d = match text.split_once(':') {
            None => {
                let (lo, hi) = band(text)?;
                Distribution::Uniform { lo, hi }
            }
            Some(("normal", sd)) => Distribution::Normal {
                mean: nominal,
                sd: amount(sd)?,
            },
            Some(("lognormal", s)) => Distribution::LogNormal {
                median: nominal,
                sigma: match s.trim().strip_suffix('%') {
                    Some(p) => number(p)? / 100.0,
                    None => number(s)?,
                },
            },
            Some(("tnormal", rest)) => {
                let (sd, b) = rest
                    .split_once(':')
                    .ok_or_else(|| bad("expected tnormal:SD:BAND (tnormal:5%:±10%)"))?;
                let (lo, hi) = band(b)?;
                Distribution::TruncatedNormal {
                    mean: nominal,
                    sd: amount(sd)?,
                    lo,
                    hi,
                }
            }
            Some((kind, _)) => {
                return Err(bad(&format!(
                    "unknown distribution '{kind}' (uniform bands, normal, lognormal, tnormal)"
                )));
            }
        };
        d.validate().map_err(|e| bad(&e.to_string()))?;
        Ok(d)
    }
}

impl std::fmt::Display for Distribution {
    /// `uniform 8 … 12`, `normal 10 ± 0.5 (sd)`, …
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Distribution::Uniform { lo, hi } => write!(f, "uniform {lo:.6e} … {hi:.6e}"),
            Distribution::Normal { mean, sd } => write!(f, "normal {mean:.6e}, sd {sd:.3e}"),
            Distribution::LogNormal { median, sigma } => {
                write!(f, "log-normal median {median:.6e}, sigma(ln) {sigma:.4}")
            }
            Distribution::TruncatedNormal { mean, sd, lo, hi } => write!(
                f,
                "normal {mean:.6e}, sd {sd:.3e}, truncated to {lo:.6e} … {hi:.6e}"
            ),
        }
    }
}

/// The Wilson score interval of k successes in n trials at two-sided confidence `level`.
///
/// ```
/// let (lo, hi) = hdgear::robust::wilson(0, 100, 0.95);
/// assert_eq!(lo, 0.0);
/// assert!((hi - 0.0370).abs() < 1e-4); // z²/(n + z²), the rule of three's cousin
/// ```
pub fn wilson(k: u64, n: u64, level: f64) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let z = normal_quantile(0.5 + 0.5 * level);
    let (n, p) = (n as f64, k as f64 / n as f64);
    let z2 = z * z;
    let centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
    let half = z / (1.0 + z2 / n) * (p * (1.0 - p) / n + z2 / (4.0 * n * n)).sqrt();
    // at k = 0 (k = n) the bound is exactly 0 (1): centre and half agree in exact arithmetic,
    // where rounding would leave ~1e-17
    let lo = if k == 0 {
        0.0
    } else {
        (centre - half).max(0.0)
    };
    let hi = if p == 1.0 {
        1.0
    } else {
        (centre + half).min(1.0)
    };
    (lo, hi)
}

/// The least number of samples whose Wilson interval at proportion `p` is at most `width` wide
/// (p = 1/2 when nothing is known: the widest).
pub fn samples_for_width(p: f64, width: f64, level: f64) -> u64 {
    let w = |n: u64| {
        let k = (p * n as f64).round() as u64;
        let (lo, hi) = wilson(k, n, level);
        hi - lo
    };
    let mut hi = 1u64;
    while w(hi) > width && hi < 1 << 50 {
        hi *= 2;
    }
    let mut lo = hi / 2;
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if w(mid) > width { lo = mid } else { hi = mid }
    }
    hi
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Φ⁻¹ inverts Φ to rounding level over eleven decades of tail probability.
    #[test]
    fn quantile_inverts_the_cdf() {
        for &p in &[1e-12, 1e-6, 0.01, 0.02425, 0.3, 0.5, 0.77, 0.99, 1.0 - 1e-9] {
            let x = normal_quantile(p);
            assert!(
                ((normal_cdf(x) - p) / p.min(1.0 - p)).abs() < 1e-12,
                "p = {p}"
            );
        }
        assert!((normal_quantile(0.975) - 1.959_963_984_540_054).abs() < 1e-14);
    }

    /// Each distribution's quantile and CDF are inverse to each other.
    #[test]
    fn quantile_and_cdf_agree() {
        let ds = [
            Distribution::Uniform { lo: 1.0, hi: 3.0 },
            Distribution::Normal { mean: 2.0, sd: 0.3 },
            Distribution::LogNormal {
                median: 2.0,
                sigma: 0.2,
            },
            Distribution::TruncatedNormal {
                mean: 2.0,
                sd: 1.0,
                lo: 1.5,
                hi: 3.0,
            },
        ];
        for d in ds {
            for &u in &[0.01, 0.25, 0.5, 0.9] {
                assert!((d.cdf(d.quantile(u)) - u).abs() < 1e-12, "{d} at {u}");
            }
        }
    }

    /// The Wilson interval covers its proportion at its nominal rate: the exact coverage over
    /// the binomial distribution at n = 200, p = 0.1 is within 1.5 points of 95 % (Brown, Cai
    /// and DasGupta 2001 show Wilson's coverage oscillating near, not at, the nominal level).
    #[test]
    fn wilson_covers() {
        let (n, p) = (200u64, 0.1f64);
        let mut cover = 0.0;
        let mut pmf = (1.0 - p).powi(n as i32);
        for k in 0..=n {
            let (lo, hi) = wilson(k, n, 0.95);
            if lo <= p && p <= hi {
                cover += pmf;
            }
            pmf *= (n - k) as f64 / (k + 1) as f64 * p / (1.0 - p);
        }
        assert!((cover - 0.95).abs() < 0.015, "coverage {cover}");
        // none or all bursting: the bound at the end is the end itself, not a rounding of it
        assert_eq!(wilson(0, 4096, 0.95).0, 0.0);
        assert_eq!(wilson(4096, 4096, 0.95).1, 1.0);
        let n = samples_for_width(0.5, 0.02, 0.95);
        // the normal approximation: n = z²/w² ≈ 9604 for half-width 0.01
        assert!((9590..=9610).contains(&n), "{n}");
    }
}
