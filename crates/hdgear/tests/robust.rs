//! The design check under manufacturing spread (issue: design under manufacturing spread): the
//! Sobol estimators on the Ishigami function's closed-form indices, P(burst) against Φ of an
//! independently bisected boundary, the worst corner and margin against a brute-force grid, and
//! the same bytes on any thread count and shard split.

use hdgear::Params;
use hdgear::burst::{BurstOptions, classify, response};
use hdgear::physical::PhysicalParams;
use hdgear::robust::{
    Distribution, McOptions, Measure, Nominal, Sampler, Space, Target, Tolerance, importance,
    normal_cdf, probability, sensitivity, sobol, worst_case,
};

/// Ishigami (a = 7, b = 0.1) on [−π, π]³: the closed-form indices (Ishigami & Homma 1990;
/// V = a²/8 + bπ⁴/5 + b²π⁸/18 + 1/2, V₁ = (1 + bπ⁴/5)²/2, V₂ = a²/8, V₁₃ = 8b²π⁸/225) are
/// S1 = (0.3139, 0.4424, 0), ST = (0.5576, 0.4424, 0.2437). At N = 2¹⁴ the estimators are
/// within ±0.01 of each, and each 95 % bootstrap interval holds its exact value ± 0.01.
#[test]
fn sobol_indices_of_the_ishigami_function() {
    let (a, b) = (7.0, 0.1);
    let pi = std::f64::consts::PI;
    let v = a * a / 8.0 + b * pi.powi(4) / 5.0 + b * b * pi.powi(8) / 18.0 + 0.5;
    let v1 = 0.5 * (1.0 + b * pi.powi(4) / 5.0).powi(2);
    let v2 = a * a / 8.0;
    let v13 = 8.0 * b * b * pi.powi(8) / 225.0;
    let s1 = [v1 / v, v2 / v, 0.0];
    let st = [(v1 + v13) / v, v2 / v, v13 / v];
    assert!((s1[0] - 0.3139).abs() < 1e-4 && (st[2] - 0.2437).abs() < 1e-4);
    let rows = sobol::design(3, 1 << 14, Sampler::Sobol, 11).unwrap();
    let f: Vec<f64> = rows
        .iter()
        .map(|u| {
            let x: Vec<f64> = u.iter().map(|u| -pi + 2.0 * pi * u).collect();
            x[0].sin() + a * x[1].sin().powi(2) + b * x[2].powi(4) * x[0].sin()
        })
        .collect();
    let s = sobol::indices(3, &f);
    for i in 0..3 {
        for (got, want) in [(s.first[i], s1[i]), (s.total[i], st[i])] {
            assert!(
                (got.value - want).abs() < 0.01,
                "index {i}: {got:?} against {want}"
            );
            assert!(
                got.lo - 0.01 <= want && want <= got.hi + 0.01,
                "{got:?} {want}"
            );
        }
    }
}

/// The burst verdict at the study's point with γ changed.
fn bursts(gamma: f64) -> bool {
    let p = Params {
        gamma,
        ..Params::default()
    };
    classify(&p, &response(&p, &BurstOptions::default()).unwrap()).bursting
}

/// With only γ ~ N(m, s) uncertain at the study's point, the verdict bursts below the boundary
/// γ_b, so P(burst) = Φ((γ_b − m)/s). γ_b is bisected here from single responses (not the
/// batches the estimate runs on) to 1e-4; P is estimated from 2048 Sobol samples for three m
/// and must lie in its 99 % Wilson interval.
/// The simulated γ boundary at the study's point, bisected from single responses (not the
/// batches the estimates run on) to 1e-4; once for all tests.
fn gamma_boundary() -> f64 {
    static B: std::sync::OnceLock<f64> = std::sync::OnceLock::new();
    *B.get_or_init(|| {
        let (mut lo, mut hi) = (1.5, 3.0);
        assert!(bursts(lo) && !bursts(hi));
        while hi - lo > 1e-4 {
            let mid = 0.5 * (lo + hi);
            if bursts(mid) { lo = mid } else { hi = mid }
        }
        0.5 * (lo + hi)
    })
}

/// Only γ ~ N(m, s) uncertain at the study's point.
fn gamma_space(m: f64, s: f64) -> Space {
    let nominal = Nominal::Study(Params {
        gamma: m,
        ..Params::default()
    });
    let t = Tolerance {
        target: Target::Study(hdgear::params::Param::Gamma),
        distribution: Distribution::Normal { mean: m, sd: s },
        source: "test".into(),
    };
    Space::new(nominal, vec![t]).unwrap()
}

#[test]
fn burst_probability_is_phi_of_the_boundary() {
    let gamma_b = gamma_boundary();
    let s = 0.25;
    for m in [gamma_b - 0.3, gamma_b, gamma_b + 0.2] {
        let space = gamma_space(m, s);
        let mc = McOptions {
            samples: 2048,
            level: 0.99,
            ..McOptions::default()
        };
        let p = probability(&space, &BurstOptions::default(), &mc, |_| Ok(())).unwrap();
        let want = normal_cdf((gamma_b - m) / s);
        assert_eq!(p.judged, 2048);
        assert!(
            p.interval.0 <= want && want <= p.interval.1,
            "m = {m}: P = {} in {:?}, Φ = {want} (γ_b = {gamma_b})",
            p.p,
            p.interval
        );
    }
}

/// Importance sampling of a small P: γ ~ N(γ_b + 1, 0.25) puts the boundary four standard
/// deviations out, P = Φ(−4) ≈ 3.2e-5, where 2048 plain samples would expect 0.06 bursting
/// ones. 2048 importance samples must hold Φ(−4) in their 99 % interval, with the design point
/// (from the *predicted* boundary, not the simulated one the exact P uses) within a quarter of
/// a standard deviation of −4 and a variance reduction of at least 100 (p(1 − p)/s² ≈ 1/(p·c)
/// for a relative variance c of order one: about 10⁴ here).
#[test]
fn importance_sampling_finds_a_small_probability() {
    let (gamma_b, s) = (gamma_boundary(), 0.25);
    let m = gamma_b + 4.0 * s;
    let space = gamma_space(m, s);
    let mc = McOptions {
        samples: 2048,
        level: 0.99,
        ..McOptions::default()
    };
    let want = normal_cdf(-4.0);
    let est = importance(&space, &BurstOptions::default(), &mc).unwrap();
    let d = est.design.as_ref().expect("a design point");
    assert!((d.z[0] + 4.0).abs() < 0.25, "design point {:?}", d.z);
    assert!(
        est.interval.0 <= want && want <= est.interval.1,
        "P = {} in {:?}, Φ(−4) = {want}",
        est.p,
        est.interval
    );
    assert!(est.bursting > 100, "{est:?}");
    assert!(est.variance_reduction > 100.0, "{est:?}");
    assert!(want <= est.upper_bound);
}

/// The estimate is unbiased whatever the design point: with the nominal set itself bursting
/// (no design point, plain samples, weights 1) it is the plain estimate: the same random
/// coordinates give the same values (z = Φ⁻¹(u), mean + sd·z either way) and the same verdicts.
#[test]
fn importance_without_a_design_point_is_plain_sampling() {
    let space = gamma_space(gamma_boundary() - 0.05, 0.25);
    let mc = McOptions {
        samples: 512,
        sampler: Sampler::Random,
        ..McOptions::default()
    };
    let est = importance(&space, &BurstOptions::default(), &mc).unwrap();
    assert!(est.design.is_none() && est.note.is_some(), "{est:?}");
    assert_eq!(est.sum, est.bursting as f64);
    let plain = probability(&space, &BurstOptions::default(), &mc, |_| Ok(())).unwrap();
    assert_eq!((est.bursting, est.judged), (plain.bursting, plain.judged));
    assert!(plain.bursting > 0 && (est.p - plain.p).abs() < 1e-15);
}

/// A drive near its boundary: CSF-20-50's preset with a soft k1 = 2000 N m/rad and a disturbance
/// T_am = 22 N m (its design check puts the boundary at T_am ≈ 26 N m).
fn near_boundary() -> PhysicalParams {
    PhysicalParams {
        k1: 2000.0,
        t_am: 22.0,
        ..hdgear::physical::catalogue::preset("CSF-20-50", None)
            .unwrap()
            .0
    }
}

fn band(nominal: &Nominal, text: &str) -> Tolerance {
    Space::parse_tolerance(nominal, text).unwrap()
}

/// On (k1, C, T_am) ± 20 % the worst corner and the margin agree with a brute-force 21³ grid
/// (steps of 2 %, scale steps of 0.1) within one grid step: the grid's margin is the largest
/// box (in scale steps) without a bursting grid point, and the first bursting grid point lies
/// within one grid step of the worst ray at its crossing.
#[test]
fn worst_case_matches_a_brute_force_grid() {
    let nominal = Nominal::Drive(near_boundary());
    let tol = ["k1=±20%", "c_eq=±20%", "t_am=±20%"].map(|t| band(&nominal, t));
    let space = Space::new(nominal, tol.to_vec()).unwrap();
    let opts = BurstOptions::default();
    let w = worst_case(&space, &opts).unwrap();
    assert!(!w.nominal.bursting);
    let margin = w.margin.expect("the box reaches the boundary");
    assert!(margin < 1.0, "margin {margin}");
    // the grid: offsets −10 … 10 steps of 0.1 box per parameter
    let nom = space.nominal_values();
    let steps: Vec<[i32; 3]> = (0..21i32.pow(3))
        .map(|i| [i % 21 - 10, i / 21 % 21 - 10, i / 441 - 10])
        .collect();
    let values: Vec<Vec<f64>> = steps
        .iter()
        .map(|s| {
            (0..3)
                .map(|j| nom[j] * (1.0 + 0.02 * f64::from(s[j])))
                .collect()
        })
        .collect();
    let judged = hdgear::robust::evaluate(&space, &values, &opts);
    let cheb = |s: &[i32; 3]| s.iter().map(|v| v.abs()).max().unwrap();
    let first = steps
        .iter()
        .zip(&judged)
        .filter(|(_, j)| j.outcome.as_ref().unwrap().bursting)
        .map(|(s, _)| *s)
        .min_by_key(cheb)
        .expect("the grid bursts somewhere");
    let grid_margin = 0.1 * f64::from(cheb(&first) - 1);
    assert!(
        (margin - grid_margin).abs() <= 0.1 + 1e-12,
        "margin {margin}, grid {grid_margin} (first bursting step {first:?})"
    );
    let worst = &w.corners[w.worst];
    let at = worst.crossing.as_ref().unwrap().outside;
    let ray: Vec<f64> = worst.signs.iter().map(|&s| at * f64::from(s)).collect();
    let near = steps.iter().zip(&judged).any(|(s, j)| {
        j.outcome.as_ref().unwrap().bursting
            && cheb(s) == cheb(&first)
            && (0..3).all(|d| (0.1 * f64::from(s[d]) - ray[d]).abs() <= 0.1 + 1e-12)
    });
    assert!(
        near,
        "worst ray {:?} at {at}; first grid burst {first:?}",
        worst.signs
    );
    assert_eq!(w.interior_differing, 0);
}

/// Sample i is a function of the seed and i: the same bytes on one thread and two, and in two
/// shards as in one run; another seed gives other samples.
#[test]
fn runs_are_reproducible() {
    let nominal = Nominal::Drive(near_boundary());
    let tol = ["k1=±20%", "c_eq=normal:10%", "t_am=lognormal:15%"].map(|t| band(&nominal, t));
    let space = Space::new(nominal, tol.to_vec()).unwrap();
    let opts = BurstOptions::default();
    let run = |first: u64, samples: u64, threads: usize, seed: u64| {
        let mc = McOptions {
            samples,
            first,
            seed,
            sampler: Sampler::Random,
            ..McOptions::default()
        };
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut out = Vec::new();
        pool.install(|| {
            probability(&space, &opts, &mc, |s| {
                out.extend_from_slice(s);
                Ok(())
            })
        })
        .unwrap();
        serde_json::to_string(&out).unwrap()
    };
    let one = run(0, 150, 1, 5);
    assert_eq!(one, run(0, 150, 2, 5));
    let (a, b) = (run(0, 61, 2, 5), run(61, 89, 1, 5));
    let joined = format!("{},{}", &a[..a.len() - 1], &b[1..]);
    assert_eq!(one, joined);
    assert_ne!(one, run(0, 150, 2, 6));
}

/// A parameter held to a spread a million times below another's has no share of the variance:
/// its total index on every measure that varies is below 1 %, the other's first-order index
/// above 90 %; a measure that does not vary (no overshoot anywhere here) has NaN indices.
#[test]
fn a_negligible_tolerance_has_no_sobol_index() {
    let nominal = Nominal::Study(Params {
        gamma: 2.2,
        ..Params::default()
    });
    let tol = ["gamma=±20%", "delta=±0.00002%"].map(|t| band(&nominal, t));
    let space = Space::new(nominal, tol.to_vec()).unwrap();
    let s = sensitivity(&space, &BurstOptions::default(), 256, Sampler::Sobol, 3).unwrap();
    assert_eq!(s.failed, 0);
    for (measure, ix) in &s.measures {
        let ix = ix.as_ref().expect("every run simulated");
        if ix.variance == 0.0 {
            assert!(ix.first[0].value.is_nan() && *measure != Measure::Burst);
            continue;
        }
        assert!(
            ix.total[1].value.abs() < 0.01,
            "{measure:?}: {:?}",
            ix.total[1]
        );
        assert!(ix.first[0].value > 0.9, "{measure:?}: {:?}", ix.first[0]);
    }
}
