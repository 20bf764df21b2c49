//! Student's t quantile, exact for the whole-number degrees of freedom a fit has.

/// P(|T| ≤ t) for Student's t with `nu` degrees of freedom, by the finite series of Abramowitz
/// & Stegun 26.7.3–4 (exact for whole ν); the normal law past 10⁵, where the two agree to 1e-5
/// of the quantile.
fn two_sided(t: f64, nu: u64) -> f64 {
    if nu > 100_000 {
        return 1.0 - 2.0 * crate::distribution::normal_cdf(-t);
    }
    let theta = (t / (nu as f64).sqrt()).atan();
    let (s, c) = theta.sin_cos();
    let c2 = c * c;
    if nu % 2 == 1 {
        // (2/π)(θ + sin θ (cos θ + (2/3)cos³θ + … + (2·4⋯(ν−3))/(1·3⋯(ν−2)) cos^{ν−2} θ))
        let (mut term, mut sum) = (c, if nu > 1 { c } else { 0.0 });
        let mut j = 3;
        while j < nu {
            term *= c2 * (j - 1) as f64 / j as f64;
            sum += term;
            j += 2;
        }
        std::f64::consts::FRAC_2_PI * (theta + s * sum)
    } else {
        // sin θ (1 + ½cos²θ + (1·3)/(2·4)cos⁴θ + … + (1·3⋯(ν−3))/(2·4⋯(ν−2)) cos^{ν−2} θ)
        let (mut term, mut sum) = (1.0, 1.0);
        let mut j = 2;
        while j < nu {
            term *= c2 * (j - 1) as f64 / j as f64;
            sum += term;
            j += 2;
        }
        s * sum
    }
}

/// The t with P(|T| ≤ t) = `level` for `nu` ≥ 1 degrees of freedom (bisection to 1e-12).
pub fn t_quantile(level: f64, nu: u64) -> f64 {
    let (mut lo, mut hi) = (0.0, 1.0);
    while two_sided(hi, nu) < level {
        hi *= 2.0;
    }
    while hi - lo > 1e-12 * hi {
        let mid = 0.5 * (lo + hi);
        if two_sided(mid, nu) < level {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn t_quantiles_match_the_tables() {
        // 97.5 % points of Student's t (scipy.stats.t.ppf(0.975, ν), to 12 digits)
        for (nu, want) in [
            (1, 12.706204736174),
            (2, 4.302652729749),
            (3, 3.182446305284),
            (10, 2.228138851986),
            (30, 2.042272456301),
            (1000, 1.962339080826),
        ] {
            let got = t_quantile(0.95, nu);
            assert!(
                (got - want).abs() < 1e-10 * want,
                "ν = {nu}: {got} against {want}"
            );
        }
    }
}
