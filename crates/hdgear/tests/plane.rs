//! Boundaries in a parameter plane (`burst::plane_boundaries`), each against an independent
//! reference: one-parameter bisections written here, closed forms of the fast subsystem.

use hdgear::burst::{
    BOUNDARY_REL_TOL, BoundaryKind, BurstOptions, PlaneCurve, PlaneOptions, classify,
    plane_boundaries, response,
};
use hdgear::params::{Param, Params};
use hdgear::periodic::{Box2, Scale};

fn curves(params: [Param; 2], ranges: [(f64, f64); 2], kind: BoundaryKind) -> Vec<PlaneCurve> {
    curves_with(params, ranges, kind, &PlaneOptions::default())
}

fn curves_with(
    params: [Param; 2],
    ranges: [(f64, f64); 2],
    kind: BoundaryKind,
    opts: &PlaneOptions,
) -> Vec<PlaneCurve> {
    let box2 = Box2 {
        ranges,
        scales: [Scale::Log; 2],
    };
    let base = Params::default();
    plane_boundaries(
        &base,
        params,
        &box2,
        &[kind],
        opts,
        &BurstOptions::default(),
    )
    .unwrap()
}

/// The local slope d ln λ₁ / d ln λ₂ of a curve at point `i` (from its neighbours).
fn slope(c: &PlaneCurve, i: usize) -> f64 {
    let (a, b) = (
        &c.points[i.saturating_sub(1)],
        &c.points[(i + 1).min(c.points.len() - 1)],
    );
    ((b.params[0] / a.params[0]).ln() / (b.params[1] / a.params[1]).ln()).abs()
}

/// Bisection in log scale of a verdict's switch in λ₁ at fixed λ₂ within [x/1.7, 1.9x] (not
/// centred on x, so that its values do not line up with the curve's): the
/// final bracket, at most `rel` wide.
fn bisect(x: f64, rel: f64, holds: impl Fn(f64) -> bool) -> (f64, f64) {
    let (mut lo, mut hi) = (x / 1.7, 1.9 * x);
    let below = holds(lo);
    assert_ne!(below, holds(hi), "no switch in [{lo}, {hi}]");
    while (hi / lo).ln() > rel {
        let m = (lo * hi).sqrt();
        if holds(m) == below {
            lo = m;
        } else {
            hi = m;
        }
    }
    (lo, hi)
}

/// The simulated boundary in (ω, γ), followed by the predictor–corrector, agrees with ten
/// independent bisections in ω at its points' γ (each response on its own, not in a batch):
/// both brackets are 1 % wide, so their midpoints differ by at most 1 % plus the curve's
/// bracket's extent in γ carried by the slope (0.5 %·|d ln ω/d ln γ|).
#[test]
fn the_simulated_curve_agrees_with_ten_bisections() {
    let c = curves(
        [Param::Omega, Param::Gamma],
        [(1e-4, 0.2), (0.3, 3.0)],
        BoundaryKind::Simulated,
    );
    assert_eq!(c.len(), 1, "{c:?}");
    let c = &c[0];
    assert!(c.points.len() > 20, "{}", c.points.len());
    let o = BurstOptions::default();
    let n = c.points.len();
    for k in 0..10 {
        let i = 1 + k * (n - 2) / 9;
        let [omega, gamma] = c.points[i].params;
        let bursting = |omega| {
            let p = Params {
                omega,
                gamma,
                ..Params::default()
            };
            classify(&p, &response(&p, &o).unwrap()).bursting
        };
        let (lo, hi) = bisect(omega, BOUNDARY_REL_TOL, bursting);
        let off = (omega / (lo * hi).sqrt()).ln().abs();
        let allowed = BOUNDARY_REL_TOL * (1.0 + 0.5 * slope(c, i));
        assert!(
            off <= allowed,
            "gamma {gamma}: curve {omega}, bisection [{lo}, {hi}]"
        );
    }
}

/// The predicted boundary in (γ, δ) agrees with bisections of the prediction in δ at every
/// point's γ to 1e-6 (the bisections' own tolerance), and in (ω, γ) it is the closed form
/// ω_b = ω·κ_c/max κ (checked in the function's example).
#[test]
fn the_predicted_curve_agrees_with_bisections() {
    let c = curves(
        [Param::Gamma, Param::Delta],
        [(0.005, 1.0), (0.3, 30.0)],
        BoundaryKind::Predicted,
    );
    assert_eq!(c.len(), 1);
    for q in &c[0].points {
        let [gamma, delta] = q.params;
        let at = |delta| Params {
            gamma,
            delta,
            ..Params::default()
        };
        let bursting = |d| hdgear::fast::predict(&at(d)).bursting;
        if q.params[0] == 1.0 || q.params[1] == 0.3 || q.params[1] == 30.0 {
            continue; // on the box's edge (its δ may sit at a range end)
        }
        let (lo, hi) = bisect(delta, 1e-7, bursting);
        let off = (delta / (lo * hi).sqrt()).ln().abs();
        assert!(
            off < 1e-6,
            "gamma {gamma}: curve {delta}, bisection [{lo}, {hi}]"
        );
    }
}

/// The fold set of the fast subsystem in (γ, δ), from the cubic written here: the folds are at
/// g'(x) = 0, x± = (1 ± √(1 − 3αγ))/(3α), and lie in a ∈ [−1, 1] when |g(x±) − μ| ≤ δ. So the
/// region with both in range is bounded by δ = max |g(x±) − μ| and the cusp line γ = 1/(3α),
/// the one with at least one by δ = min |g(x±) − μ| and the same line. Every point is on one
/// of them to 1e-8, and both pieces are followed.
#[test]
fn the_fold_set_is_the_closed_form() {
    let p0 = Params::default();
    let gc = 1.0 / (3.0 * p0.alpha);
    let deltas = |gamma: f64| {
        let p = Params { gamma, ..p0 };
        let s = (1.0 - 3.0 * p.alpha * gamma).sqrt();
        let g = |x: f64| p.alpha * x * x * x - x * x + gamma * (x - p.eps) - p.mu;
        let (a, b) = (
            g((1.0 - s) / (3.0 * p.alpha)).abs(),
            g((1.0 + s) / (3.0 * p.alpha)).abs(),
        );
        (a.min(b), a.max(b))
    };
    for (kind, both) in [
        (BoundaryKind::AFoldInRange, false),
        (BoundaryKind::BothFoldsInRange, true),
    ] {
        let c = curves(
            [Param::Gamma, Param::Delta],
            [(0.002, 0.1), (0.01, 30.0)],
            kind,
        );
        assert_eq!(c.len(), 1, "{kind:?}");
        let (mut on_fold, mut on_cusp) = (0, 0);
        for q in &c[0].points {
            let [gamma, delta] = q.params;
            if (gamma / gc - 1.0).abs() < 1e-8 {
                on_cusp += 1;
                continue;
            }
            let (one, two) = deltas(gamma);
            let d = if both { two } else { one };
            assert!(
                (delta / d - 1.0).abs() < 1e-8,
                "{kind:?} gamma {gamma}: {delta} vs {d}"
            );
            on_fold += 1;
        }
        assert!(
            on_fold > 10 && on_cusp > 10,
            "{kind:?}: {on_fold} {on_cusp}"
        );
    }
}

/// The edge of the fast-slow domain from the linearisation written here (rate 1/2 on a focus,
/// g' > 1/4; (1 − √(1 − 4g'))/2 on a node), for a monotone curve (γ > 1/(3α): one branch, the
/// state passes every x between the equilibria at a = ±1): the smaller of a tenth of the slower
/// turning point's rate and the path's slowest rate, where g' (a parabola in x) is least over
/// that interval, at its point nearest the vertex x = 1/(3α). Also whether the path decided.
fn fast_slow_edge(p: &Params) -> (f64, bool) {
    let rate = |gp: f64| {
        if gp > 0.25 {
            0.5
        } else {
            0.5 * (1.0 - (1.0 - 4.0 * gp).sqrt())
        }
    };
    let [x_lo, x_hi] = [-1.0, 1.0].map(|a| crate::common::monotone_equilibrium(p, a));
    let settling = rate(p.g_prime(x_lo)).min(rate(p.g_prime(x_hi))) / 10.0;
    let path = rate(p.g_prime((1.0 / (3.0 * p.alpha)).clamp(x_lo, x_hi)));
    (settling.min(path), path < settling)
}

/// Every point's bracket straddles [`fast_slow_edge`]; returns how many points the path decided.
fn check_fast_slow_edge(params: [Param; 2], ranges: [(f64, f64); 2]) -> usize {
    let c = curves(params, ranges, BoundaryKind::FastSlowEdge);
    assert_eq!(c.len(), 1);
    let at = |v: [f64; 2]| {
        Params::default()
            .with(params[0], v[0])
            .with(params[1], v[1])
    };
    let mut by_path = 0;
    // (where the edge is steep, at g' = 1/4 on a node, a bracket 1e-9 wide moves ω by more
    // than 1e-9, so the bracket is what is checked)
    for q in &c[0].points {
        let (out, inside) = (q.outside, q.inside);
        let (edge_in, path) = fast_slow_edge(&at(inside));
        assert!(inside[0] <= edge_in, "{q:?}");
        assert!(out[0] > fast_slow_edge(&at(out)).0, "{q:?}");
        for i in 0..2 {
            assert!((out[i] / inside[i] - 1.0).abs() <= 1e-9, "{q:?}");
        }
        by_path += usize::from(path);
    }
    by_path
}

/// The edge of the fast-slow domain in (ω, δ) at γ = 0.1 (δ from 0.05 to 2: at δ ≈ 0.14 the
/// equilibrium at a = −1 sits at the least g', 0.079, a node) is the turning points' decade;
/// in (ω, γ) near the cusp (γ − 1/48 from 1e-3) it is the node at the inflection, whose rate
/// ≈ γ − 1/48 falls below a tenth of the turning points' 1/2 for γ < 0.068.
#[test]
fn the_fast_slow_edge_is_the_relaxation_rate() {
    let by_path = check_fast_slow_edge([Param::Omega, Param::Delta], [(1e-3, 0.2), (0.05, 2.0)]);
    assert_eq!(by_path, 0);
    let by_path = check_fast_slow_edge(
        [Param::Omega, Param::Gamma],
        [(1e-4, 0.2), (1.0 / 48.0 + 1e-3, 0.3)],
    );
    assert!(by_path > 5, "{by_path} points decided by the path");
}

/// A curve's points in the unit square of its box (log scales).
fn unit(c: &PlaneCurve, ranges: [(f64, f64); 2]) -> Vec<[f64; 2]> {
    let v = |x: f64, (lo, hi): (f64, f64)| (x / lo).ln() / (hi / lo).ln();
    c.points
        .iter()
        .map(|q| [v(q.params[0], ranges[0]), v(q.params[1], ranges[1])])
        .collect()
}

/// The distance from `x` to the polyline `line`.
fn to_polyline(x: [f64; 2], line: &[[f64; 2]]) -> f64 {
    line.windows(2)
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            let d = [b[0] - a[0], b[1] - a[1]];
            let len2 = d[0] * d[0] + d[1] * d[1];
            let t = if len2 > 0.0 {
                (((x[0] - a[0]) * d[0] + (x[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (x[0] - a[0] - t * d[0]).hypot(x[1] - a[1] - t * d[1])
        })
        .fold(f64::INFINITY, f64::min)
}

/// How far a polyline traced with largest step `h` and turn limit `turn` lies from the curve
/// through its vertices. With the limit active (turn < π/2), a step's arc turns by at most
/// `turn`, and its sagitta is h·tan(turn/4)/2; corners are taken at the least step. At π/2 or
/// above there is no limit (the half circle's ends cap every turn at π/2), a step may cut across
/// a corner, and a chord of length h whose ends are on the two legs of a corner of at least 90°
/// passes within h/2 of it.
fn sagitta(h: f64, turn: f64) -> f64 {
    if turn >= std::f64::consts::FRAC_PI_2 {
        0.5 * h
    } else {
        0.5 * h * (turn / 4.0).tan()
    }
}

/// The tracer's constants (the largest turn per step, the angles of a round, the values per edge
/// in the search for starts), each a decade above and below its default (the round no lower
/// than 3, its least), give the same curves: as many, and every point of each within the other's
/// polyline's sagitta of it, both ways, ends included. Checked on the predicted boundary in
/// (ω, γ) for γ ≥ 0.3 and on the fold set in (γ, δ), which has a corner where it meets the cusp
/// line. Below γ ≈ 0.27 the settled branch passes a node part and the predicted boundary is the
/// lower of two criteria (κ and the cusp's normal form), with shallow corners where they
/// exchange, which no turn limit bounds (measured there at a tenth of the turn limit: 2.0e-4 of
/// the box, against a sagitta of 7.6e-5 for smooth arcs); the box stops above them. A
/// decade above the turn limit is no limit at all (see [`sagitta`]): the corner is then cut by
/// up to half a step, which this bound allows and the default's does not.
#[test]
fn the_tracer_constants_do_not_change_the_curves_over_a_decade() {
    let d = PlaneOptions::default();
    let variants = [
        PlaneOptions {
            max_turn: d.max_turn / 10.0,
            ..d
        },
        PlaneOptions {
            max_turn: d.max_turn * 10.0,
            ..d
        },
        PlaneOptions { round: 3, ..d },
        PlaneOptions {
            round: d.round * 10,
            ..d
        },
        PlaneOptions {
            edge_samples: d.edge_samples / 10,
            ..d
        },
        PlaneOptions {
            edge_samples: d.edge_samples * 10,
            ..d
        },
    ];
    let cases = [
        (
            [Param::Omega, Param::Gamma],
            [(1e-4, 0.2), (0.3, 3.0)],
            BoundaryKind::Predicted,
        ),
        (
            [Param::Gamma, Param::Delta],
            [(0.002, 0.1), (0.01, 30.0)],
            BoundaryKind::AFoldInRange,
        ),
    ];
    for (params, ranges, kind) in cases {
        let reference = curves_with(params, ranges, kind, &d);
        assert!(!reference.is_empty(), "{kind:?}");
        for o in &variants {
            let c = curves_with(params, ranges, kind, o);
            assert_eq!(c.len(), reference.len(), "{kind:?} {o:?}");
            for r in &reference {
                let a = unit(r, ranges);
                // the variant's curve through the reference's first point
                let b = c
                    .iter()
                    .map(|q| unit(q, ranges))
                    .min_by(|x, y| to_polyline(a[0], x).total_cmp(&to_polyline(a[0], y)))
                    .unwrap();
                for (from, to, o) in [(&a, &b, o), (&b, &a, &d)] {
                    let allowed = sagitta(o.step_max, o.max_turn) + 1e-6;
                    let worst = from.iter().map(|&x| to_polyline(x, to)).fold(0.0, f64::max);
                    eprintln!("{kind:?} {o:?}: {worst:.2e} (allowed {allowed:.2e})");
                    assert!(worst <= allowed, "{kind:?} {o:?}: {worst} > {allowed}");
                }
            }
        }
    }
}

/// The simulated boundary of a model with regularised friction in (f_c, γ): one curve from edge
/// to edge, and at every point the ends of its bracket are what `verdict_model` (the verdict
/// `hdgear bursts` gives) says on each side, bursting inside and not outside, evaluated here
/// afresh; the brackets are within the boundary's tolerance. The closed-form kinds are refused
/// for it, naming the kind.
#[test]
fn a_friction_models_simulated_boundary_separates_its_own_verdicts() {
    use hdgear::model::{Model, terms::AnyTerm};
    let study = Params {
        gamma: 2.0,
        ..Params::default()
    };
    // fc, vs: the [friction] table's defaults but its level
    let friction = AnyTerm::new("friction", &[0.1, 0.01]).unwrap();
    let m = Model::study(&study).with_term(friction).unwrap();
    let axes = [m.param("friction.fc").unwrap(), m.param("gamma").unwrap()];
    let box2 = Box2 {
        ranges: [(0.02, 0.5), (1.0, 3.0)],
        scales: [Scale::Linear; 2],
    };
    let opts = PlaneOptions::with_step(0.05);
    let burst = BurstOptions::default();
    let curves =
        plane_boundaries(&m, axes, &box2, &[BoundaryKind::Simulated], &opts, &burst).unwrap();
    assert_eq!(curves.len(), 1, "{curves:?}");
    let c = &curves[0];
    assert_eq!(c.end, hdgear::burst::PlaneEnd::Edge);
    let fcs: Vec<f64> = c.points.iter().map(|q| q.params[0]).collect();
    assert!(
        fcs.iter().any(|&f| f < 0.03) && fcs.iter().any(|&f| f > 0.49),
        "{fcs:?}"
    );
    let bursts = |l: [f64; 2]| {
        let at = m.with_all(&[(axes[0], l[0]), (axes[1], l[1])]).unwrap();
        hdgear::burst::verdict_model(&at, &burst)
            .unwrap()
            .0
            .bursting
    };
    for q in c.points.iter().step_by(4) {
        assert!(bursts(q.inside) && !bursts(q.outside), "{q:?}");
        for i in 0..2 {
            let gap = (q.inside[i] - q.outside[i]).abs();
            let bound = BOUNDARY_REL_TOL * q.params[i].abs() * (1.0 + BOUNDARY_REL_TOL);
            assert!(gap <= bound, "{q:?}");
        }
    }
    for kind in [BoundaryKind::Predicted, BoundaryKind::FastSlowEdge] {
        let e = plane_boundaries(&m, axes, &box2, &[kind], &opts, &burst).unwrap_err();
        assert!(e.to_string().contains(kind.name()), "{e}");
    }
}
