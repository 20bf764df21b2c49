//! Sobol sensitivity indices by the Saltelli design: which input's spread makes the output
//! spread.
//!
//! Two matrices A and B of N points each (coordinates 0 … k−1 and k … 2k−1 of one sample
//! sequence), and for each input i the matrix A_B⁽ⁱ⁾, A with column i from B: N(k + 2) model
//! runs. With f_A, f_B, f_AB⁽ⁱ⁾ the outputs and V the variance of f over A and B together,
//!
//! * first-order (Saltelli et al. 2010): S_i = mean((f_B − f̄)·(f_AB⁽ⁱ⁾ − f_A)) / V, with the
//!   mean f̄ subtracted (it does not change the expectation, as E(f_AB⁽ⁱ⁾ − f_A) = 0, but it
//!   removes the mean's share of the estimator's variance, large when f̄² ≫ V),
//! * total (Jansen 1999): ST_i = mean((f_A − f_AB⁽ⁱ⁾)²) / (2V),
//!
//! with bootstrap intervals: the N rows resampled with replacement (a fixed seed), the indices
//! recomputed, the 2.5 % and 97.5 % quantiles of the replicates.

use super::sequence::{Points, Sampler, splitmix};
use super::{Measure, Space, evaluate};
use crate::burst::BurstOptions;
use crate::error::{Error, Result};
use serde::Serialize;

/// Bootstrap replicates of each interval.
pub const BOOTSTRAP: usize = 200;

/// An estimate with its 95 % bootstrap interval.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BootstrapEstimate {
    /// The estimate from all N rows.
    pub value: f64,
    /// 2.5 % quantile of the bootstrap replicates (the estimate itself without any).
    pub lo: f64,
    /// 97.5 % quantile of the bootstrap replicates (the estimate itself without any).
    pub hi: f64,
    /// The replicates the interval is taken from: those whose resampled rows vary. A nearly
    /// constant output (a few runs differ) leaves some resamples without variance, and so
    /// without an index; fewer than [`BOOTSTRAP`] says the interval rests on fewer, and 0
    /// that there is none.
    pub replicates: usize,
}

/// The indices of one output.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Indices {
    /// Mean of the output over A and B.
    pub mean: f64,
    /// Its variance V (0: the output does not vary, and the indices are NaN).
    pub variance: f64,
    /// First-order index of each input.
    pub first: Vec<BootstrapEstimate>,
    /// Total index of each input.
    pub total: Vec<BootstrapEstimate>,
}

/// The Saltelli design's unit points: rows of A (j < N), B (N ≤ j < 2N) and A_B⁽ⁱ⁾
/// ((2 + i)N ≤ j < (3 + i)N), k coordinates each, in that order.
pub fn design(k: usize, n: usize, sampler: Sampler, seed: u64) -> Result<Vec<Vec<f64>>> {
    let points = Points::new(sampler, seed, 2 * k)?;
    let mut rows = Vec::with_capacity(n * (k + 2));
    let ab = |j: usize| -> (Vec<f64>, Vec<f64>) {
        let mut p = vec![0.0; 2 * k];
        points.point(j as u64, &mut p);
        let b = p.split_off(k);
        (p, b)
    };
    let pairs: Vec<_> = (0..n).map(ab).collect();
    rows.extend(pairs.iter().map(|(a, _)| a.clone()));
    rows.extend(pairs.iter().map(|(_, b)| b.clone()));
    for i in 0..k {
        rows.extend(pairs.iter().map(|(a, b)| {
            let mut r = a.clone();
            r[i] = b[i];
            r
        }));
    }
    Ok(rows)
}

/// The indices from the outputs `f` of [`design`]'s rows (in its order) for `k` inputs.
pub fn indices(k: usize, f: &[f64]) -> Indices {
    let n = f.len() / (k + 2);
    let all: Vec<usize> = (0..n).collect();
    let point = estimate(k, n, f, &all);
    let mut replicates: Vec<Vec<f64>> = vec![Vec::with_capacity(BOOTSTRAP); 2 * k];
    let mut rows = vec![0usize; n];
    for b in 0..BOOTSTRAP {
        for (j, r) in rows.iter_mut().enumerate() {
            *r = (splitmix(splitmix(b as u64 + 1) ^ j as u64) % n as u64) as usize;
        }
        let e = estimate(k, n, f, &rows);
        for (i, v) in e.first.iter().chain(&e.total).enumerate() {
            replicates[i].push(*v);
        }
    }
    for r in &mut replicates {
        // a resample whose outputs are all equal has no variance and no index
        r.retain(|v| v.is_finite());
        r.sort_by(f64::total_cmp);
    }
    let interval = |i: usize, value: f64| {
        let r = &replicates[i];
        let q = |p: f64| {
            r.get(((p * r.len().saturating_sub(1) as f64).round()) as usize)
                .copied()
                .unwrap_or(value)
        };
        BootstrapEstimate {
            value,
            lo: q(0.025),
            hi: q(0.975),
            replicates: r.len(),
        }
    };
    Indices {
        mean: point.mean,
        variance: point.variance,
        first: (0..k).map(|i| interval(i, point.first[i])).collect(),
        total: (0..k).map(|i| interval(k + i, point.total[i])).collect(),
    }
}

struct Point {
    mean: f64,
    variance: f64,
    first: Vec<f64>,
    total: Vec<f64>,
}

/// The estimators over the rows `rows` (indices into 0 … N−1, repeated when resampled).
fn estimate(k: usize, n: usize, f: &[f64], rows: &[usize]) -> Point {
    let fa = |j: usize| f[j];
    let fb = |j: usize| f[n + j];
    let fab = |i: usize, j: usize| f[(2 + i) * n + j];
    let m = rows.len() as f64;
    let mean = rows.iter().map(|&j| fa(j) + fb(j)).sum::<f64>() / (2.0 * m);
    let variance = rows
        .iter()
        .map(|&j| (fa(j) - mean).powi(2) + (fb(j) - mean).powi(2))
        .sum::<f64>()
        / (2.0 * m - 1.0);
    let first = (0..k)
        .map(|i| {
            let s = rows.iter().map(|&j| (fb(j) - mean) * (fab(i, j) - fa(j)));
            s.sum::<f64>() / m / variance
        })
        .collect();
    let total = (0..k)
        .map(|i| {
            rows.iter()
                .map(|&j| (fa(j) - fab(i, j)).powi(2))
                .sum::<f64>()
                / (2.0 * m)
                / variance
        })
        .collect();
    Point {
        mean,
        variance,
        first,
        total,
    }
}

/// Sobol indices of each measure over a space.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sensitivity {
    /// N, the rows of the Saltelli design (N(k + 2) runs).
    pub n: usize,
    /// The parameters, in the order of the indices.
    pub parameters: Vec<&'static str>,
    /// Per measure ([`Measure::ALL`]): its indices, or None when some run has no value of it
    /// (a failed or predicted sample).
    pub measures: Vec<(Measure, Option<Indices>)>,
    /// Runs without a verdict.
    pub failed: usize,
}

/// The most runs a Saltelli design may hold, N(k + 2): the design, its runs' measures and their
/// bootstrap are held in memory together (about a kilobyte a run), and each run is an
/// integration, so 10⁷ runs are already gigabytes and CPU-hours; a larger design is refused
/// before anything is allocated.
pub const MAX_DESIGN_RUNS: usize = 10_000_000;

/// Checks a Saltelli design of `n` rows for `k` parameters: at least 2 rows, at most
/// [`MAX_DESIGN_RUNS`] runs (the product checked without overflow).
pub(super) fn check_design(n: usize, k: usize) -> Result<()> {
    let bad = |reason| Error::InvalidOption {
        name: "sobol",
        value: n as f64,
        reason,
    };
    if n < 2 {
        return Err(bad("the Saltelli design needs at least 2 rows"));
    }
    match n.checked_mul(k + 2) {
        Some(runs) if runs <= MAX_DESIGN_RUNS => Ok(()),
        _ => Err(bad(
            "N(k + 2) runs over the 10⁷ a design may hold in memory (k: the parameters spread)",
        )),
    }
}

/// Sobol first-order and total indices of every [`Measure`] over `space`, from the Saltelli
/// design of `n` rows ([`design`]).
pub fn sensitivity(
    space: &Space,
    opts: &BurstOptions,
    n: usize,
    sampler: Sampler,
    seed: u64,
) -> Result<Sensitivity> {
    opts.validate()?;
    let k = space.dims();
    check_design(n, k)?;
    let rows = design(k, n, sampler, seed)?;
    let values: Vec<Vec<f64>> = rows.iter().map(|u| space.values(u)).collect();
    let samples = evaluate(space, &values, opts);
    let failed = samples.iter().filter(|s| s.outcome.is_err()).count();
    let measures = Measure::ALL
        .iter()
        .enumerate()
        .map(|(m, &measure)| {
            let f: Option<Vec<f64>> = samples
                .iter()
                .map(|s| s.outcome.as_ref().ok().map(|o| o.measures[m]))
                .map(|v| v.filter(|v| v.is_finite()))
                .collect();
            (measure, f.map(|f| indices(k, &f)))
        })
        .collect();
    Ok(Sensitivity {
        n,
        parameters: space.tolerances.iter().map(|t| t.target.name()).collect(),
        measures,
        failed,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A linear function's indices are its terms' variance shares, first and total alike:
    /// f = x₀ + 2x₁ on the unit square (variances 1/12 and 4/12: S = 0.2, 0.8).
    #[test]
    fn linear_function() {
        let rows = design(2, 1 << 12, Sampler::Sobol, 1).unwrap();
        let f: Vec<f64> = rows.iter().map(|r| r[0] + 2.0 * r[1]).collect();
        let s = indices(2, &f);
        for (i, want) in [0.2, 0.8].into_iter().enumerate() {
            assert!(
                (s.first[i].value - want).abs() < 2e-3,
                "S{i} {:?}",
                s.first[i]
            );
            assert!(
                (s.total[i].value - want).abs() < 2e-3,
                "ST{i} {:?}",
                s.total[i]
            );
            assert!(s.first[i].lo <= s.first[i].value && s.first[i].value <= s.first[i].hi);
        }
    }

    /// An output that one run in 2N makes vary: the resamples that leave that row out have no
    /// variance. The intervals come from the others, finite, and say how many; a constant
    /// output has NaN indices and no replicate.
    #[test]
    fn a_nearly_constant_output_has_finite_intervals() {
        let (k, n) = (2, 8);
        let mut f = vec![0.0; n * (k + 2)];
        // row 0 of A differs, and with it A_B's rows 0 (column 0 and 1 taken from B, which
        // is 0 there: f_AB = 0, as if the change came from either input together)
        f[0] = 1.0;
        let s = indices(k, &f);
        assert!(s.variance > 0.0);
        // P(a resample of 8 rows misses row 0) = (7/8)^8 ≈ 0.34: some, not all, lack variance
        for e in s.first.iter().chain(&s.total) {
            assert!(e.replicates > 0 && e.replicates < BOOTSTRAP, "{e:?}");
            assert!(
                e.lo.is_finite() && e.hi.is_finite() && e.lo <= e.hi,
                "{e:?}"
            );
        }
        let constant = indices(k, &vec![1.0; n * (k + 2)]);
        assert_eq!(constant.variance, 0.0);
        assert!(
            constant
                .first
                .iter()
                .all(|e| e.value.is_nan() && e.replicates == 0)
        );
    }
}
