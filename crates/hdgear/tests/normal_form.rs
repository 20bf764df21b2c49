//! The period doubling's normal form (`periodic::flip_coefficient`) against plain simulations:
//! at the doubling itself the stroboscopic map's centre coordinate η decays (c > 0) or grows
//! (c < 0) as 1/η² = 1/η₀² + 2c·n over n forcing periods (P∘P is η ↦ η − 2c·η³), which a long
//! simulation measures with no derivative taken.

use hdgear::Params;
use hdgear::integrate::{Method, Options};
use hdgear::params::Param;
use hdgear::periodic::{
    Box2, Codim2, ContinuationOptions, Curve2, CurveKind, CurvePoint2, End, OrbitBranch,
    OrbitPoint, Range, Scale, Special, continue_curve, continue_orbit, curves_from_branch,
    switch_at_gpd, switch_at_period_doubling,
};
use hdgear::simulate::{SimOptions, Start, simulate};

/// Continuation in ln ω.
fn log_omega() -> ContinuationOptions {
    ContinuationOptions {
        scale: Scale::Log,
        ..ContinuationOptions::default()
    }
}

/// The period-1 branch of γ = 10 at `mu` (δ = 15) in ω from 7 to `to`, with its period doublings.
fn doubling_branch(mu: f64, to: f64) -> (Params, OrbitBranch<Param>, Vec<OrbitPoint>) {
    let p = Params {
        gamma: 10.0,
        omega: 7.0,
        mu,
        ..Params::default()
    };
    let b = continue_orbit(&p, Param::Omega, 1, None, to, &log_omega()).unwrap();
    let pds = b
        .specials()
        .filter(|q| q.special == Some(Special::PeriodDoubling))
        .copied()
        .collect();
    (p, b, pds)
}

/// The period doublings of the γ = 10 bubble (ω from 7 to 10 at the study's μ and δ = 15).
fn bubble() -> (Params, Vec<OrbitPoint>) {
    let (p, _, pds) = doubling_branch(Params::default().mu, 10.0);
    (p, pds)
}

/// The states at phase 0 of n forcing periods from y0, by one plain simulation.
fn stroboscopic(p: &Params, y0: [f64; 2], n: usize) -> Vec<[f64; 2]> {
    let period = std::f64::consts::TAU / p.omega;
    let opts = SimOptions {
        t_end: n as f64 * period,
        dt: period,
        start: Start::Given {
            x0: y0[0],
            v0: y0[1],
        },
        tol: Options {
            rtol: 1e-12,
            atol: 1e-12,
            method: Method::Dop853,
            ..Options::default()
        },
    };
    let mut out = Vec::new();
    simulate(p, &opts, |_, y| out.push(*y)).unwrap();
    out
}

/// The stroboscopic map's eigenvalue nearest −1 with its right (unit) and left (⟨p, q⟩ = 1)
/// eigenvectors, from central differences of one-period simulations.
fn flip_vectors(p: &Params, y: [f64; 2]) -> (f64, [f64; 2], [f64; 2]) {
    let h = 1e-6;
    let mut m = [[0.0; 2]; 2];
    for j in 0..2 {
        let (mut plus, mut minus) = (y, y);
        plus[j] += h;
        minus[j] -= h;
        let (a, b) = (stroboscopic(p, plus, 1)[1], stroboscopic(p, minus, 1)[1]);
        for i in 0..2 {
            m[i][j] = (a[i] - b[i]) / (2.0 * h);
        }
    }
    let (tr, det) = (m[0][0] + m[1][1], m[0][0] * m[1][1] - m[0][1] * m[1][0]);
    let disc = (tr * tr - 4.0 * det).sqrt();
    let l = if (0.5 * (tr - disc) + 1.0).abs() < (0.5 * (tr + disc) + 1.0).abs() {
        0.5 * (tr - disc)
    } else {
        0.5 * (tr + disc)
    };
    // (M − l)q = 0 from its first row, pᵀ(M − l) = 0 from its first column
    let q = [m[0][1], l - m[0][0]];
    let n = q[0].hypot(q[1]);
    let q = [q[0] / n, q[1] / n];
    let pv = [m[1][0], l - m[0][0]];
    let pq = pv[0] * q[0] + pv[1] * q[1];
    (l, q, [pv[0] / pq, pv[1] / pq])
}

/// The slope of 1/η² against n over the even periods from n/5 on (least squares), η the centre
/// coordinate of a simulation started η₀ along q from the doubling's orbit.
fn measured_slope(p: &Params, pd: &OrbitPoint, eta0: f64, n: usize) -> f64 {
    let y = pd.start;
    let (_, q, pv) = flip_vectors(p, y);
    let states = stroboscopic(p, [y[0] + eta0 * q[0], y[1] + eta0 * q[1]], n);
    let pts: Vec<(f64, f64)> = states
        .iter()
        .enumerate()
        .filter(|(i, _)| i % 2 == 0 && *i >= n / 5)
        .map(|(i, s)| {
            let eta = pv[0] * (s[0] - y[0]) + pv[1] * (s[1] - y[1]);
            (i as f64, 1.0 / (eta * eta))
        })
        .collect();
    let k = pts.len() as f64;
    let (sx, sy) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| (a + x, b + y));
    let (mx, my) = (sx / k, sy / k);
    let (sxy, sxx) = pts.iter().fold((0.0, 0.0), |(a, b), (x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    sxy / sxx
}

/// At both doublings of the γ = 10 bubble (c ≈ 0.059 and 0.024, both supercritical) the slope
/// of 1/η² measured over 16,000 and 40,000 periods from η₀ = 0.04 is 2c to 2 %. The normal form
/// holds up to a near-identity change of coordinates, and η is measured along the linear
/// eigenvector: both make an error of relative order η₀ (4 %), measured 0.35 % and 0.13 %.
#[test]
fn the_coefficient_is_the_decay_rate_at_the_doubling() {
    let (p, pds) = bubble();
    assert_eq!(pds.len(), 2);
    for pd in &pds {
        let o = p.with(Param::Omega, pd.param);
        let c = pd
            .flip_coefficient
            .expect("a coefficient at a period doubling");
        let (l, _, _) = flip_vectors(&o, pd.start);
        assert!((l + 1.0).abs() < 1e-6, "the multiplier is {l}");
        let eta0 = 0.04;
        let n = (3.0 / (2.0 * c.abs() * eta0 * eta0)) as usize;
        assert!(n < 100_000, "c = {c} is too small for this check");
        let ratio = measured_slope(&o, pd, eta0, n) / (2.0 * c);
        assert!(
            (ratio - 1.0).abs() < 0.02,
            "ω = {}: c = {c}, measured 2c × {ratio}",
            pd.param
        );
    }
}

/// The side and stability of the doubled branch at a doubling, which continuation finds without
/// the normal form, agree with the sign of c: supercritical (c > 0), the doubled orbits lie
/// where the orbit is unstable and are stable; subcritical (c < 0), they lie where it is stable
/// and are unstable. At μ = 2.728 the doubling at ω ≈ 9.816 is subcritical (its doubled branch
/// folds back before it becomes stable) and the one at ω ≈ 10.381 supercritical; at the study's
/// μ both of the bubble are supercritical.
#[test]
fn the_sign_of_the_coefficient_is_the_side_of_the_doubled_branch() {
    let opts = log_omega();
    let mut signs = Vec::new();
    for mu in [Params::default().mu, 2.728] {
        let (p, b, pds) = doubling_branch(mu, 11.0);
        assert_eq!(pds.len(), 2, "μ = {mu}");
        let d = switch_at_period_doubling(&p, Param::Omega, 1, &pds[0], &pds, [7.0, 11.0], &opts)
            .unwrap();
        for pd in &pds {
            let c = pd.flip_coefficient.unwrap();
            // the doubled branch's point nearest the doubling, and the parent's on its side
            let near = |pts: &[OrbitPoint], side: Option<f64>| -> OrbitPoint {
                *pts.iter()
                    .filter(|q| q.special.is_none())
                    .filter(|q| side.is_none_or(|s| (q.param - pd.param) * s > 0.0))
                    .min_by(|x, y| {
                        (x.param - pd.param)
                            .abs()
                            .total_cmp(&(y.param - pd.param).abs())
                    })
                    .unwrap()
            };
            let doubled = near(&d.points, None);
            let side = (doubled.param - pd.param).signum();
            let parent = near(&b.points, Some(side));
            let super_critical = c > 0.0;
            assert_eq!(
                super_critical,
                !parent.stable,
                "μ = {mu}, ω = {}: c = {c}, the doubled branch is on the side where the orbit is {}",
                pd.param,
                if parent.stable { "stable" } else { "unstable" }
            );
            assert_eq!(
                super_critical, doubled.stable,
                "μ = {mu}, ω = {}: c = {c}",
                pd.param
            );
            signs.push(super_critical);
        }
    }
    assert_eq!(signs, [true, true, false, true]);
}

/// The curve of period doublings in (ω, μ) at γ = 10 holds two generalised period doublings,
/// where c passes through zero (|c| ≤ 1e-8 at the located points, against 0.13 at most along
/// the curve); the subcritical stretch between them contains the doubling at μ = 2.728 of the
/// test above.
#[test]
fn generalised_period_doublings_are_where_the_coefficient_vanishes() {
    let c = pd_curve_in_omega_mu();
    let coefficient = |q: &CurvePoint2| q.flip_coefficient.expect("a coefficient on the curve");
    let gpds: Vec<&CurvePoint2> = c
        .points
        .iter()
        .filter(|q| q.special == Some(Codim2::GeneralisedPeriodDoubling))
        .collect();
    let mut located: Vec<[f64; 2]> = gpds.iter().map(|q| q.params).collect();
    located.dedup_by(|a, b| (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9);
    assert_eq!(located.len(), 2, "{located:?}");
    for q in &gpds {
        assert!(coefficient(q).abs() < 1e-8, "{q:?}");
    }
    // the sign changes across each, and nowhere else
    let signs: Vec<bool> = c
        .points
        .iter()
        .filter(|q| q.special.is_none())
        .map(|q| coefficient(q) > 0.0)
        .collect();
    let changes = signs.windows(2).filter(|w| w[0] != w[1]).count();
    assert_eq!(changes, 2, "{signs:?}");
    let subcritical_mu: Vec<f64> = c
        .points
        .iter()
        .filter(|q| q.special.is_none() && coefficient(q) < 0.0)
        .map(|q| q.params[1])
        .collect();
    let (lo, hi) = subcritical_mu
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &m| {
            (l.min(m), h.max(m))
        });
    assert!(
        lo < 2.728 && 2.728 < hi,
        "subcritical for μ in [{lo}, {hi}]"
    );
}

/// The period-doubling curve of γ = 10 in (ω, μ), from the first doubling of the bubble.
fn pd_curve_in_omega_mu() -> Curve2<Param> {
    let (p, pds) = bubble();
    let pd = pds[0];
    let box2 = Box2 {
        ranges: [(4.0, 14.0), (-5.0, 5.0)],
        scales: [Scale::Log, Scale::Linear],
    };
    let o = p.with(Param::Omega, pd.param);
    let params = [Param::Omega, Param::Mu];
    continue_curve(
        &o,
        params,
        CurveKind::PeriodDoubling,
        1,
        pd.start,
        &box2,
        &ContinuationOptions::default(),
    )
    .unwrap()
}

/// Independent of c: the fold curve of the doubled orbits (period 2·2π/ω), started from the fold
/// of the doubled branch at μ = 2.728 (ω ≈ 9.8132), runs from one generalised period doubling to
/// the other, where the doubled orbits are born from the orbit (the normal form's unfolding: at a
/// GPD a fold of doubled cycles leaves the period-doubling curve). Its nearest points come within
/// 1e-4 of both GPDs in (ω, μ) (measured 1.3e-5 and 8.7e-8: near a GPD the doubled orbits shrink
/// onto the orbit and the fold degenerates, so the curve is followed to the corrector's
/// resolution of it).
#[test]
fn the_fold_curve_of_the_doubled_orbits_ends_at_the_generalised_period_doublings() {
    let gpds: Vec<[f64; 2]> = pd_curve_in_omega_mu()
        .points
        .iter()
        .filter(|q| q.special == Some(Codim2::GeneralisedPeriodDoubling))
        .map(|q| q.params)
        .collect();
    assert!(gpds.len() >= 2);
    let p = Params {
        gamma: 10.0,
        mu: 2.728,
        omega: 10.3,
        ..Params::default()
    };
    let ranges = [
        Range::parse("omega=10.3:9.4:log").unwrap(),
        Range::parse("mu=2:3.5").unwrap(),
    ];
    let curves = curves_from_branch(
        &p,
        ranges,
        CurveKind::Fold,
        None,
        2,
        &ContinuationOptions::default(),
    )
    .unwrap();
    assert_eq!(curves.len(), 1);
    for g in &gpds {
        let nearest = curves[0]
            .points
            .iter()
            .map(|q| (q.params[0] - g[0]).hypot(q.params[1] - g[1]))
            .fold(f64::INFINITY, f64::min);
        assert!(nearest < 1e-4, "GPD {g:?}: nearest point {nearest:e} away");
    }
}

/// The folds of the doubled orbits of the γ = 10 branch at `mu`, found by one-parameter
/// continuation of the doubled branches born at its period doublings (ω from 7 to 11).
fn doubled_folds(mu: f64) -> Vec<f64> {
    let (p, _, pds) = doubling_branch(mu, 11.0);
    let mut folds: Vec<f64> = Vec::new();
    for pd in &pds {
        let d = switch_at_period_doubling(&p, Param::Omega, 1, pd, &pds, [7.0, 11.0], &log_omega())
            .unwrap();
        for f in d.specials().filter(|q| q.special == Some(Special::Fold)) {
            if folds.iter().all(|w| (w - f.param).abs() > 1e-7) {
                folds.push(f.param);
            }
        }
    }
    folds.sort_by(f64::total_cmp);
    folds
}

/// Branch switching at a generalised period doubling (`switch_at_gpd`): the fold curve of the
/// doubled orbits started at the first GPD of the (ω, μ) period-doubling curve, with no
/// one-parameter branch behind it. At every point one multiplier is +1 to 1e-9 and the orbit is
/// a doubled one (it does not come back after one forcing period); the curve ends at the other
/// GPD, and it crosses the lines μ = 2.5, 2.728 and 3.0 exactly where one-parameter continuation
/// of the doubled branches finds their folds (to 1e-8 in ω).
#[test]
fn the_fold_curve_of_the_doubled_orbits_is_switched_onto_at_a_gpd() {
    let pd = pd_curve_in_omega_mu();
    let gpds: Vec<&CurvePoint2> = pd
        .points
        .iter()
        .filter(|q| q.special == Some(Codim2::GeneralisedPeriodDoubling))
        .collect();
    let box2 = Box2 {
        ranges: [(4.0, 14.0), (-5.0, 5.0)],
        scales: [Scale::Log, Scale::Linear],
    };
    let (p, _) = bubble();
    let opts = ContinuationOptions::default();
    let lpc = switch_at_gpd(&p, &pd, gpds[0], &box2, &opts).unwrap();
    assert_eq!((lpc.kind, lpc.subharmonic), (CurveKind::Fold, 2));
    assert_eq!(lpc.ends[0], End::Switched);
    assert!(
        matches!(lpc.ends[1], End::Rejoined { .. }),
        "{:?}",
        lpc.ends
    );
    let last = lpc.points.last().unwrap();
    assert_eq!(last.special, Some(Codim2::GeneralisedPeriodDoubling));
    assert!(
        (last.params[0] - gpds[0].params[0]).abs() > 0.1,
        "it ended where it started: {:?}",
        last.params
    );
    let n = lpc.points.len();
    let mut least = f64::INFINITY;
    for q in &lpc.points[1..n - 1] {
        let m = q.multipliers[0];
        assert!(m.log_abs.abs() < 1e-9 && m.arg.abs() < 1e-9, "{q:?}");
        let at = p
            .with(Param::Omega, q.params[0])
            .with(Param::Mu, q.params[1]);
        let s = stroboscopic(&at, q.start, 2);
        let scale = 1.0 + q.start[0].hypot(q.start[1]);
        let (back, half) = (
            (s[2][0] - q.start[0]).hypot(s[2][1] - q.start[1]) / scale,
            (s[1][0] - q.start[0]).hypot(s[1][1] - q.start[1]) / scale,
        );
        assert!(back < 1e-8, "not periodic: {back:e} at {:?}", q.params);
        least = least.min(half);
    }
    assert!(least > 1e-6, "a period-1 orbit on the curve: {least:e}");
    for mu in [2.5, 2.728, 3.0] {
        let crossings: Vec<f64> = lpc
            .crossings(&p, (1, mu), &box2, &opts)
            .unwrap()
            .iter()
            .map(|q| q.params[0])
            .collect();
        let folds = doubled_folds(mu);
        assert_eq!(
            crossings.len(),
            folds.len(),
            "μ = {mu}: {crossings:?} {folds:?}"
        );
        let mut crossings = crossings;
        crossings.sort_by(f64::total_cmp);
        for (c, f) in crossings.iter().zip(&folds) {
            assert!(
                (c - f).abs() < 1e-8,
                "μ = {mu}: curve at ω = {c}, fold at {f}"
            );
        }
    }
}
