//! Two-parameter continuation (issue: two-parameter continuation): the fold curves of the study's
//! frequency response in (ω, δ) hold a multiplier at +1 and pass through the folds that
//! one-parameter continuation finds at ten fixed δ; their cusp is where the hysteresis width of
//! one-parameter scans shrinks to zero; a period-doubling curve holds a multiplier at −1 and
//! closes the period-doubling bubble at γ = 10.

use hdgear::Params;
use hdgear::params::Param;
use hdgear::periodic::{
    Box2, Codim2, ContinuationOptions, Curve2, CurveKind, Scale, Special, continue_curve,
    continue_orbit, frequency_response, point_on_curve,
};

const PARAMS: [Param; 2] = [Param::Omega, Param::Delta];

fn plane() -> Box2 {
    Box2 {
        ranges: [(0.3, 20.0), (0.5, 40.0)],
        scales: [Scale::Log, Scale::Log],
    }
}

/// The folds (ω) of the frequency response of `p` over `range`.
fn folds(p: &Params, range: (f64, f64), opts: &ContinuationOptions) -> Vec<f64> {
    let r = frequency_response(p, Some(range), opts).unwrap();
    r.specials()
        .filter(|q| q.special == Some(Special::Fold))
        .map(|q| q.param)
        .collect()
}

/// The study's two fold curves in (ω, δ): from the first fold of each pair of the frequency
/// response at δ = 15 (the resonance near ω ≈ 5 … 7, and the narrow pair near 1.67).
fn fold_curves() -> &'static [Curve2<Param>; 2] {
    static C: std::sync::OnceLock<[Curve2<Param>; 2]> = std::sync::OnceLock::new();
    C.get_or_init(|| {
        let p = Params::default();
        let opts = ContinuationOptions::default();
        let r = frequency_response(&p, None, &opts).unwrap();
        let f: Vec<_> = r
            .specials()
            .filter(|q| q.special == Some(Special::Fold))
            .copied()
            .collect();
        assert_eq!(f.len(), 4, "{f:?}");
        [f[0], f[2]].map(|f| {
            let o = Params {
                omega: f.param,
                ..p
            };
            continue_curve(&o, PARAMS, CurveKind::Fold, 1, f.start, &plane(), &opts).unwrap()
        })
    })
}

/// At every point of both curves the larger multiplier is +1 to 1e-9 (ln|m| within 1e-9, real
/// and positive); each curve runs from edge to edge of the box. At ten δ from 0.6 to 38 every
/// crossing of a curve with the line δ = const (corrected onto it) is a fold of the
/// one-parameter frequency response at that δ within 1e-8 in ω, and every such fold is a
/// crossing: the two curves are all the folds there are.
#[test]
fn fold_curves_hold_a_unit_multiplier_and_pass_through_every_one_parameter_fold() {
    let curves = fold_curves();
    let opts = ContinuationOptions::default();
    for c in curves {
        assert!(c.points.len() > 20, "{} points", c.points.len());
        for q in &c.points {
            let m = q.multipliers[0];
            assert!(m.log_abs.abs() < 1e-9 && m.arg == 0.0, "{q:?}");
        }
    }
    let p = Params::default();
    for j in 0..10 {
        let d = 0.6 * (38.0f64 / 0.6).powf(f64::from(j) / 9.0);
        let ones = folds(&Params { delta: d, ..p }, (0.3, 20.0), &opts);
        let mut crossings = Vec::new();
        for c in curves {
            let xs = c.crossings(&p, (1, d), &plane(), &opts).unwrap();
            crossings.extend(xs.iter().map(|q| q.params[0]));
        }
        let gap = |a: &[f64], b: &[f64]| {
            a.iter()
                .map(|x| {
                    b.iter()
                        .map(|y| (x - y).abs())
                        .fold(f64::INFINITY, f64::min)
                })
                .fold(0.0f64, f64::max)
        };
        assert_eq!(
            crossings.len(),
            ones.len(),
            "δ = {d}: {crossings:?} {ones:?}"
        );
        assert!(
            gap(&crossings, &ones) < 1e-8,
            "δ = {d}: {crossings:?} {ones:?}"
        );
        assert!(
            gap(&ones, &crossings) < 1e-8,
            "δ = {d}: {crossings:?} {ones:?}"
        );
    }
}

/// The resonance's fold curve has one cusp, near (ω, δ) = (1.853, 0.917): located the same to
/// 1e-9 when the curve is followed again from another point with another step. Independently, one-parameter scans at
/// δ = δ_c(1 + e), e = 1, 2, 4, 8 %, each over a window around the cusp, find the two folds
/// with a hysteresis width w that halves like (δ − δ_c)^{3/2} (w ratio 2^{3/2} = 2.83 per
/// doubling of e, within 0.1), w^{2/3} through the three smallest e extrapolates to zero at δ_c
/// within 1e-5 (the next term of the width's expansion, O(e²), limits the fit; measured
/// 2.4e-6), and no fold is found at δ_c(1 − 0.5 %).
#[test]
fn the_cusp_is_where_the_hysteresis_vanishes() {
    let curve = &fold_curves()[1];
    let cusps: Vec<_> = curve
        .points
        .iter()
        .filter(|q| q.special == Some(Codim2::Cusp))
        .collect();
    assert_eq!(cusps.len(), 1, "{cusps:?}");
    let [wc, dc] = cusps[0].params;
    assert!(
        (wc - 1.853).abs() < 1e-3 && (dc - 0.917).abs() < 1e-3,
        "{wc} {dc}"
    );
    let p = Params::default();
    let finer = ContinuationOptions {
        max_step: 0.01,
        ..ContinuationOptions::default()
    };
    let start = curve.points.iter().find(|q| q.params[1] > 10.0).unwrap();
    let o = Params {
        omega: start.params[0],
        delta: start.params[1],
        ..p
    };
    let again = continue_curve(
        &o,
        PARAMS,
        CurveKind::Fold,
        1,
        start.start,
        &plane(),
        &finer,
    )
    .unwrap();
    let c2 = again
        .points
        .iter()
        .find(|q| q.special == Some(Codim2::Cusp))
        .unwrap();
    let moved = [c2.params[0] - wc, c2.params[1] - dc];
    assert!(moved.iter().all(|m| m.abs() < 1e-9), "{moved:?}");
    let fine = ContinuationOptions {
        initial_step: 1e-3,
        max_step: 2e-3,
        max_points: 20_000,
        ..ContinuationOptions::default()
    };
    let mut widths = Vec::new();
    for e in [0.01, 0.02, 0.04, 0.08] {
        let d = dc * (1.0 + e);
        let f = folds(&Params { delta: d, ..p }, (wc * 0.92, wc * 1.1), &fine);
        assert_eq!(f.len(), 2, "δ = {d}: {f:?}");
        widths.push((d, (f[0] - f[1]).abs()));
    }
    for w in widths.windows(2) {
        let ratio = w[1].1 / w[0].1;
        assert!((ratio - 2f64.powf(1.5)).abs() < 0.1, "{widths:?}");
    }
    let root = zero_of_width(&widths[..3], dc);
    assert!((root - dc).abs() < 1e-5, "fit {root} against {dc}");
    let below = folds(
        &Params {
            delta: dc * (1.0 - 5e-3),
            ..p
        },
        (wc * 0.92, wc * 1.1),
        &fine,
    );
    assert!(below.is_empty(), "{below:?}");
}

/// The root near `guess` of the quadratic through (δ, w^{2/3}) at three widths: where the
/// hysteresis width extrapolates to zero.
fn zero_of_width(widths: &[(f64, f64)], guess: f64) -> f64 {
    let (x, y): (Vec<f64>, Vec<f64>) = widths.iter().map(|&(d, w)| (d, w.powf(2.0 / 3.0))).unzip();
    let q = |t: f64| -> f64 {
        (0..3)
            .map(|i| {
                (0..3)
                    .filter(|&j| j != i)
                    .fold(y[i], |l, j| l * (t - x[j]) / (x[i] - x[j]))
            })
            .sum()
    };
    let mut root = guess;
    for _ in 0..50 {
        let h = 1e-7;
        root -= q(root) * 2.0 * h / (q(root + h) - q(root - h));
    }
    root
}

/// γ = 10: the period-doubling bubble of the frequency response (ω ≈ 8.14 and 9.56 at δ = 15)
/// is one period-doubling curve in (ω, δ). At every point one multiplier is −1 to 1e-9, the
/// curve passes through both one-parameter period doublings at δ = 15 within 1e-8, and it closes
/// (an isola) or leaves the box.
#[test]
fn the_period_doubling_bubble_is_one_curve() {
    let p = Params {
        gamma: 10.0,
        omega: 7.0,
        ..Params::default()
    };
    let opts = ContinuationOptions {
        scale: Scale::Log,
        ..ContinuationOptions::default()
    };
    let b = continue_orbit(&p, Param::Omega, 1, None, 10.0, &opts).unwrap();
    let pds: Vec<_> = b
        .specials()
        .filter(|q| q.special == Some(Special::PeriodDoubling))
        .copied()
        .collect();
    assert_eq!(pds.len(), 2);
    let o = Params {
        omega: pds[0].param,
        ..p
    };
    let c = continue_curve(
        &o,
        PARAMS,
        CurveKind::PeriodDoubling,
        1,
        pds[0].start,
        &plane(),
        &ContinuationOptions::default(),
    )
    .unwrap();
    for q in &c.points {
        let m = q
            .multipliers
            .iter()
            .find(|m| m.arg != 0.0 || m.log_abs.abs() < 1e-6);
        let m = m.expect("a multiplier at −1");
        assert!(
            m.log_abs.abs() < 1e-9 && m.arg == std::f64::consts::PI,
            "{q:?}"
        );
    }
    for pd in &pds {
        let near = c
            .points
            .iter()
            .min_by(|a, b| {
                (a.params[0] - pd.param)
                    .abs()
                    .total_cmp(&(b.params[0] - pd.param).abs())
            })
            .unwrap();
        let q = point_on_curve(
            &p,
            PARAMS,
            CurveKind::PeriodDoubling,
            1,
            near,
            (1, 15.0),
            &plane(),
            &ContinuationOptions::default(),
        )
        .unwrap();
        assert!(
            (q.params[0] - pd.param).abs() < 1e-8,
            "{} vs {}",
            q.params[0],
            pd.param
        );
    }
}

/// A box far larger than the curve (μ ∈ ±5000 around a fold curve that spans μ ∈ [−50.6, 36.9]
/// at γ = 10): the steps, a share of the box's diagonal, are then longer than the curve is wide.
/// The curve is still followed whole and closed (the other fold branch passing within a step of
/// the start is not taken for the start), with the same two cusps as in a box that fits it, and
/// the corrector does not wander to parameters the box never asked for (a Newton iterate at
/// ω ≈ 1e-5 took seconds per flow before).
#[test]
fn a_box_much_larger_than_the_curve_gives_the_same_closed_curve() {
    use hdgear::periodic::{End, Range, curves_from_branch};
    let p = Params {
        gamma: 10.0,
        ..Params::default()
    };
    let opts = ContinuationOptions::default();
    let cusps = |half: f64| {
        let ranges = [
            Range::parse("omega=4:14:log").unwrap(),
            Range::parse(&format!("mu=-{half}:{half}")).unwrap(),
        ];
        let curves = curves_from_branch(&p, ranges, CurveKind::Fold, Some(1), 1, &opts).unwrap();
        let c = &curves[0];
        assert_eq!(c.ends, [End::Closed, End::Closed], "±{half}");
        let mut mu: Vec<f64> = c
            .points
            .iter()
            .filter(|q| q.special == Some(Codim2::Cusp))
            .map(|q| q.params[1])
            .collect();
        mu.sort_by(f64::total_cmp);
        assert_eq!(mu.len(), 2, "±{half}: {mu:?}");
        mu
    };
    let (fits, wide) = (cusps(100.0), cusps(5000.0));
    for (a, b) in fits.iter().zip(&wide) {
        assert!((a - b).abs() < 1e-7 * a.abs(), "{fits:?} vs {wide:?}");
    }
    // an independent check of both: x = y + s, s = 1/(3α), removes the quadratic term and
    // leaves y'' + y' + αy³ + (γ − s)y = μ − μ_s + δ sin ωτ with μ_s = −2·s²/3 + γ(s − ε), which
    // y ↦ −y (with half a period's shift) maps onto μ ↦ 2μ_s − μ: the cusps straddle μ_s
    let s = 1.0 / (3.0 * p.alpha);
    let mu_s = -2.0 * s * s / 3.0 + p.gamma * (s - p.eps);
    let mid = 0.5 * (wide[0] + wide[1]);
    assert!((mid - mu_s).abs() < 1e-7 * mu_s.abs(), "{mid} vs {mu_s}");
}

/// A period-doubling bubble cut by the box's top edge (γ = 30, δ = 40 = the edge): the branch in
/// ω at δ = 40 has two doublings, and both lie on the one curve, which leaves the box through
/// each of them. It is traced once, not once from each doubling (the curve's first point, on the
/// edge, was not taken for a crossing of the line δ = 40 before). Its least δ is reported as a
/// turning point and checked against the branch in ω on either side of it.
#[test]
fn a_doubling_bubble_cut_by_the_box_is_traced_once() {
    use hdgear::periodic::{End, Range, curves_from_branch};
    let p = Params {
        gamma: 30.0,
        delta: 40.0,
        ..Params::default()
    };
    let opts = ContinuationOptions::default();
    let ranges = [
        Range::parse("omega=4:16:log").unwrap(),
        Range::parse("delta=5:40").unwrap(),
    ];
    // the doublings of the one-parameter branch in ω from 4 to 16 at this δ
    let doublings_at = |delta: f64| -> Vec<f64> {
        let start = Params {
            omega: 4.0,
            delta,
            ..p
        };
        let one = ContinuationOptions {
            scale: Scale::Log,
            ..opts
        };
        let branch = continue_orbit(&start, Param::Omega, 1, None, 16.0, &one).unwrap();
        branch
            .specials()
            .filter(|q| q.special == Some(Special::PeriodDoubling))
            .map(|q| q.param)
            .collect()
    };
    let doublings = doublings_at(40.0);
    assert_eq!(doublings.len(), 2, "{doublings:?}");
    let kind = CurveKind::PeriodDoubling;
    let curves = curves_from_branch(&p, ranges, kind, None, 1, &opts).unwrap();
    assert_eq!(curves.len(), 1, "{curves:?}");
    let c = &curves[0];
    assert_eq!(c.ends, [End::Reached, End::Reached]);
    let ends = [c.points[0].params, c.points[c.points.len() - 1].params];
    for w in doublings {
        let on_end = |e: &[f64; 2]| e[1] == 40.0 && (e[0] - w).abs() < 1e-6 * w;
        assert!(ends.iter().any(on_end), "{w} vs {ends:?}");
    }
    // its one turning point is the bubble's least δ: no traced point lies below it, and the
    // branch in ω has two doublings 1 % above it and none 1 % below
    let turning: Vec<[f64; 2]> = c
        .points
        .iter()
        .filter(|q| q.special == Some(Codim2::TurningPoint))
        .map(|q| q.params)
        .collect();
    assert_eq!(turning.len(), 1, "{turning:?}");
    let least = turning[0][1];
    assert!(
        c.points
            .iter()
            .all(|q| q.params[1] >= least - 1e-12 * least)
    );
    assert_eq!(doublings_at(1.01 * least).len(), 2);
    assert_eq!(doublings_at(0.99 * least).len(), 0);
}
