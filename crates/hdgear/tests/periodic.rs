//! The periodic response (issue 16, first part): shooting against long simulations, the monodromy
//! against finite differences, Liouville's formula, and Benettin's Lyapunov exponent against the
//! largest Floquet exponent.
//!
//! **Why one file.** The tests of one capability, periodic orbits and their continuation, in one
//! module of the test binary.

use hdgear::Params;
use hdgear::integrate::{Method, Options};
use hdgear::periodic::{PeriodicOptions, lyapunov, lyapunov_many, shoot};
use hdgear::simulate::{SimOptions, Start, simulate};

fn tight() -> Options {
    Options {
        rtol: 1e-12,
        atol: 1e-12,
        method: Method::Dop853,
        ..Options::default()
    }
}

/// The study's point with γ.
fn paper(g: f64) -> Params {
    Params::default().with(hdgear::params::Param::Gamma, g)
}

/// The state at τ = `t_end` from (0, y0).
fn state_at(p: &Params, y0: [f64; 2], t_end: f64) -> [f64; 2] {
    let opts = SimOptions {
        t_end,
        dt: t_end,
        start: Start::Given {
            x0: y0[0],
            v0: y0[1],
        },
        tol: tight(),
    };
    simulate(p, &opts, |_, _| {}).unwrap().final_state
}

#[test]
fn shooting_finds_the_orbit_a_long_simulation_settles_on() {
    for g in [30.0, 1.0, 0.1] {
        let p = paper(g);
        let orbit = shoot(&p, 1, &PeriodicOptions::default()).unwrap();
        assert!(
            orbit.residual < 1e-10,
            "γ = {g}: residual {:e}",
            orbit.residual
        );
        // five slow periods from the default start, ending at the same phase (τ = 5T)
        let y0 = hdgear::simulate::initial_state(&p, Start::Equilibrium);
        let y = state_at(&p, y0, 5.0 * p.slow_period());
        let d = (y[0] - orbit.start[0]).hypot(y[1] - orbit.start[1]);
        assert!(
            d < 1e-9,
            "γ = {g}: orbit {:?}, simulation {y:?}, distance {d:e}",
            orbit.start
        );
        assert!(orbit.stable && orbit.peak_to_peak > 0.0 && orbit.samples.len() > 1000);
    }
}

#[test]
fn liouville_the_product_of_the_multipliers_is_exp_minus_the_period() {
    for g in [30.0, 1.0, 0.1, 0.01] {
        for omega in [0.01, 0.1, 0.5] {
            let p = paper(g).with(hdgear::params::Param::Omega, omega);
            let o = shoot(&p, 1, &PeriodicOptions::default()).unwrap();
            let sum = o.log_abs_multipliers[0] + o.log_abs_multipliers[1];
            // trace J = −1 everywhere: det M = e^{−T}
            assert!(
                (sum + o.period).abs() < 1e-10 * o.period,
                "γ = {g}, ω = {omega}: ln|m1 m2| = {sum}, −T = {}",
                -o.period
            );
        }
    }
}

#[test]
fn the_multipliers_agree_with_a_finite_difference_monodromy() {
    // ω = 0.3: T = 21, multipliers ~e^{−10}, large enough for differences of the flow to resolve
    // (at the study's ω = 0.01 they are e^{−314}, below any difference of two trajectories)
    for g in [30.0, 1.0, 0.1] {
        let p = paper(g).with(hdgear::params::Param::Omega, 0.3);
        let o = shoot(&p, 1, &PeriodicOptions::default()).unwrap();
        let h = 1e-5;
        let mut fd = [[0.0; 2]; 2];
        for j in 0..2 {
            let mut plus = o.start;
            let mut minus = o.start;
            plus[j] += h;
            minus[j] -= h;
            let (a, b) = (state_at(&p, plus, o.period), state_at(&p, minus, o.period));
            for i in 0..2 {
                fd[i][j] = (a[i] - b[i]) / (2.0 * h);
            }
        }
        let tr = fd[0][0] + fd[1][1];
        let det = fd[0][0] * fd[1][1] - fd[0][1] * fd[1][0];
        let disc = tr * tr - 4.0 * det;
        let fd_abs: [f64; 2] = if disc < 0.0 {
            [det.abs().sqrt(); 2]
        } else {
            let big = 0.5 * (tr + tr.signum() * disc.sqrt());
            [big.abs(), (det / big).abs()]
        };
        for (k, (q, fd_k)) in o.multipliers.iter().zip(fd_abs).enumerate() {
            let m = q.log_abs.exp();
            assert!(
                (m - fd_k).abs() < 1e-6,
                "γ = {g}: |m{k}| = {m:e} from the variational equations, {fd_k:e} by differences"
            );
        }
        // the larger one to 1e-4 relative as well
        let m0 = o.multipliers[0].log_abs.exp();
        assert!(
            (m0 - fd_abs[0]).abs() < 1e-4 * m0,
            "γ = {g}: {m0:e} vs {:e}",
            fd_abs[0]
        );
    }
}

#[test]
fn converged_lyapunov_exponent_equals_the_floquet_exponent_at_fast_forcing() {
    // γ = 10, ω = 8: 50 forcing periods are only 39 time units, too short to align the tangent
    // vector; the converged estimate averages whole periods until its standard error is 1e-3.
    // Stable orbits only: from an unstable one (γ = 10, ω = 9, past the period doubling) the
    // trajectory leaves for the attractor, whose exponent is not the orbit's
    for (g, w) in [(10.0, 8.0), (10.0, 6.0), (1.0, 0.5), (30.0, 0.1)] {
        let p = Params {
            omega: w,
            ..paper(g)
        };
        let o = shoot(&p, 1, &PeriodicOptions::default()).unwrap();
        let e = hdgear::periodic::lyapunov_converged(&p, o.start, 1e-3, tight()).unwrap();
        let floquet = o.floquet_exponents[0];
        assert!(o.stable, "γ = {g}, ω = {w}");
        assert!(e.converged, "γ = {g}, ω = {w}: {e:?}");
        assert!(e.span >= 40.0 * 8.0);
        // the standard error is at most 1e-3·|λ|; the block means of a periodic orbit scatter
        // about the exact value, so the mean is within a few standard errors of it
        assert!(
            (e.exponent - floquet).abs() <= 5e-3 * floquet.abs(),
            "γ = {g}, ω = {w}: Benettin {e:?}, Floquet {floquet}"
        );
    }
}

#[test]
fn lyapunov_exponents_are_negative_and_equal_the_largest_floquet_exponent() {
    for g in [30.0, 10.0, 1.0, 0.1] {
        let p = paper(g);
        let o = shoot(&p, 1, &PeriodicOptions::default()).unwrap();
        let t = p.slow_period();
        // with a complex pair (a focus all along) the tangent vector's norm oscillates within a
        // bounded factor, so the average converges like 1/span: at γ = 1 the error was 3.4e-4,
        // 1.6e-4, 8.3e-5, 2.9e-5 after 5, 20, 40, 80 periods; 50 periods keep it under 1e-4
        let l = lyapunov(&p, o.start, t, 50.0 * t, tight()).unwrap();
        let floquet = o.floquet_exponents[0];
        assert!(l < 0.0, "γ = {g}: λ = {l}");
        assert!(
            (l - floquet).abs() < 1e-4,
            "γ = {g}: Benettin {l}, Floquet {floquet}"
        );
    }
}

#[test]
fn batched_lyapunov_exponents_equal_the_largest_floquet_exponent() {
    // the same four orbits as above, all in one batch ([`lyapunov_many`]: the tangent carried by
    // the batch integrator, the step chosen from the state alone)
    let points: Vec<Params> = [30.0, 10.0, 1.0, 0.1].iter().map(|&g| paper(g)).collect();
    let orbits: Vec<_> = points
        .iter()
        .map(|p| shoot(p, 1, &PeriodicOptions::default()).unwrap())
        .collect();
    let starts: Vec<[f64; 2]> = orbits.iter().map(|o| o.start).collect();
    let spans: Vec<(f64, f64)> = points
        .iter()
        .map(|p| (p.slow_period(), 50.0 * p.slow_period()))
        .collect();
    let l = lyapunov_many(&points, &starts, &spans, tight()).unwrap();
    for ((p, o), l) in points.iter().zip(&orbits).zip(l) {
        let (l, floquet) = (l.unwrap(), o.floquet_exponents[0]);
        // the bound of the one-by-one test above: Benettin's 1/span convergence
        assert!(
            (l - floquet).abs() < 1e-4,
            "γ = {}: Benettin {l}, Floquet {floquet}",
            p.gamma
        );
    }
}

#[test]
fn the_batch_tangent_obeys_liouville() {
    // two tangent vectors from one state span an area that evolves as e^{−(t − t0)} (the
    // linearised flow's trace is −1): tested on both vectors' returned growth and direction,
    // from t0 ≠ 0 (the batch's own start time) over spans of 2 to 40
    use hdgear::batch::integrate_batch_tangent;
    let points: Vec<Params> = [30.0, 10.0, 1.0, 0.1, 3.0]
        .iter()
        .map(|&g| Params {
            gamma: g,
            delta: 12.0,
            ..Params::default()
        })
        .collect();
    for (t0, span) in [(0.0, 2.0), (3.7, 10.0), (50.0, 40.0)] {
        let mut starts = Vec::new();
        let mut pts = Vec::new();
        for p in &points {
            let y = [hdgear::fast::stable_equilibrium(p, 0.0) + 0.1, 0.3];
            for d in [[1.0, 0.0], [0.3, 2.0]] {
                starts.push([y[0], y[1], d[0], d[1]]);
                pts.push(*p);
            }
        }
        let spans = vec![(t0, t0 + span); pts.len()];
        let out = integrate_batch_tangent(&pts, &starts, &spans, tight()).unwrap();
        for (i, pair) in out.chunks(2).enumerate() {
            let (a, b) = (pair[0].as_ref().unwrap(), pair[1].as_ref().unwrap());
            // one state, whatever the tangent (up to the steps, which the tangent shares in
            // choosing)
            for k in 0..2 {
                assert!((a.y[k] - b.y[k]).abs() < 1e-10 * (1.0 + a.y[k].abs()));
            }
            let unit = |d: [f64; 2]| {
                let n = d[0].hypot(d[1]);
                [d[0] / n, d[1] / n]
            };
            let (ua, ub) = (unit(a.tangent), unit(b.tangent));
            let cross = (ua[0] * ub[1] - ua[1] * ub[0]).abs();
            let (s0, s1) = (starts[2 * i], starts[2 * i + 1]);
            let area0 = (s0[2] * s1[3] - s0[3] * s1[2]).abs();
            let n0 = s0[2].hypot(s0[3]) * s1[2].hypot(s1[3]);
            let ln_area = (a.ln_growth + b.ln_growth + (cross * n0).ln()) - area0.ln();
            // per unit time 1e-10: a hundred times the tolerance (rtol 1e-12; it held at
            // 1e-13), divided by the sine of the vectors' angle (the cross product's condition)
            assert!(
                (ln_area + span).abs() < 1e-10 * span.max(1.0) / cross.min(1.0),
                "γ = {}, t0 = {t0}, span {span}: ln area {ln_area}, cross {cross}",
                points[i].gamma
            );
        }
    }
}

#[test]
fn a_subharmonic_request_reports_the_least_period() {
    let p = paper(1.0).with(hdgear::params::Param::Omega, 0.3);
    let o = shoot(&p, 2, &PeriodicOptions::default()).unwrap();
    assert_eq!((o.subharmonic, o.minimal_subharmonic), (2, 1));
    let one = shoot(&p, 1, &PeriodicOptions::default()).unwrap();
    assert!((o.start[0] - one.start[0]).abs() < 1e-9 && (o.start[1] - one.start[1]).abs() < 1e-9);
    // the period-2 multipliers are the squares of the period-1 ones
    assert!((o.log_abs_multipliers[0] - 2.0 * one.log_abs_multipliers[0]).abs() < 1e-8);
    assert!(matches!(
        shoot(&p, 0, &PeriodicOptions::default()),
        Err(hdgear::Error::InvalidOption {
            name: "subharmonic",
            ..
        })
    ));
}

// ---- continuation, frequency response, orbit diagram (issue 16, second part) ----

use hdgear::params::Param;
use hdgear::periodic::{
    ContinuationOptions, DiagramOptions, DiagramPoint, End, OrbitBranch, Oscillator, Scale,
    Special, SweepDirection, continue_orbit, frequency_response, orbit_diagram,
    switch_at_period_doubling,
};

/// The study's point with γ = 30: its frequency-response curve bends over with two folds.
fn bent() -> Params {
    paper(30.0)
}

fn specials<P>(b: &OrbitBranch<P>, kind: Special) -> Vec<f64> {
    b.specials()
        .filter(|q| q.special == Some(kind))
        .map(|q| q.param)
        .collect()
}

/// The diagram's points of one sweep, in sweep order.
fn sweep_of(points: &[DiagramPoint], s: SweepDirection) -> Vec<&DiagramPoint> {
    points.iter().filter(|q| q.sweep == s).collect()
}

#[test]
fn folds_of_the_frequency_response_are_where_slow_sweeps_jump() {
    let b =
        frequency_response(&bent(), Some((6.0, 10.0)), &ContinuationOptions::default()).unwrap();
    assert_eq!(b.end, End::Reached);
    let folds = specials(&b, Special::Fold);
    assert_eq!(folds.len(), 2, "folds {folds:?}");
    // hardening: the curve bends to the right, so the upper fold comes first along the branch
    let (upper, lower) = (folds[0], folds[1]);
    assert!(upper > lower, "{folds:?}");
    // between the folds the middle branch is unstable, outside them the response is stable
    for q in &b.points {
        if q.special.is_none() && (q.param < lower - 1e-3 || q.param > upper + 1e-3) {
            assert!(q.stable, "ω = {} outside the folds is unstable", q.param);
        }
    }
    // brute force: sweep ω up and down in steps of 0.005, each value from the previous state
    let step = 0.005;
    let values: Vec<f64> = (0..=400).map(|i| 7.0 + step * f64::from(i)).collect();
    let mut points = Vec::new();
    orbit_diagram(
        &bent(),
        Param::Omega,
        &values,
        &DiagramOptions::default(),
        |q| points.push(q),
    )
    .unwrap();
    let jump = |s: SweepDirection| {
        let pts = sweep_of(&points, s);
        let (i, size) = pts
            .windows(2)
            .map(|w| (w[1].section[0][0] - w[0].section[0][0]).abs())
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap();
        (pts[i].param, pts[i + 1].param, size)
    };
    let (a, b_, size) = jump(SweepDirection::Up);
    assert!(
        size > 0.5 && a.min(b_) - step <= upper && upper <= a.max(b_) + step,
        "the up-sweep jumps between ω = {a} and {b_} (by {size}); the upper fold is at {upper}"
    );
    let (a, b_, size) = jump(SweepDirection::Down);
    assert!(
        size > 0.5 && a.min(b_) - step <= lower && lower <= a.max(b_) + step,
        "the down-sweep jumps between ω = {a} and {b_} (by {size}); the lower fold is at {lower}"
    );
}

#[test]
fn liouville_holds_along_a_branch() {
    let b =
        frequency_response(&bent(), Some((0.5, 20.0)), &ContinuationOptions::default()).unwrap();
    assert!(b.points.len() > 50);
    for q in &b.points {
        let period = std::f64::consts::TAU / q.param;
        let sum = q.multipliers[0].log_abs + q.multipliers[1].log_abs;
        assert!(
            (sum + period).abs() < 1e-9 * period.max(1.0),
            "ω = {}: ln|m1 m2| = {sum}, −T = {}",
            q.param,
            -period
        );
    }
}

/// The multiplier nearest −1 of the period-1 orbit at ω, from a monodromy by central
/// differences of plain simulations (independent of the variational equations).
fn fd_multiplier_near_minus_one(p: &Params) -> f64 {
    let o = shoot(p, 1, &PeriodicOptions::default()).unwrap();
    let h = 1e-6;
    let mut fd = [[0.0; 2]; 2];
    for j in 0..2 {
        let (mut plus, mut minus) = (o.start, o.start);
        plus[j] += h;
        minus[j] -= h;
        let (a, b) = (state_at(p, plus, o.period), state_at(p, minus, o.period));
        for i in 0..2 {
            fd[i][j] = (a[i] - b[i]) / (2.0 * h);
        }
    }
    let tr = fd[0][0] + fd[1][1];
    let det = fd[0][0] * fd[1][1] - fd[0][1] * fd[1][0];
    let disc = tr * tr - 4.0 * det;
    assert!(disc >= 0.0, "complex multipliers near a period doubling");
    let r = [0.5 * (tr + disc.sqrt()), 0.5 * (tr - disc.sqrt())];
    *r.iter()
        .min_by(|a, b| (*a + 1.0).abs().total_cmp(&(*b + 1.0).abs()))
        .unwrap()
}

#[test]
fn a_period_doubling_is_located_to_1e_6_and_its_doubled_branch_followed() {
    // γ = 10, δ = 15: the period-1 response loses stability through −1 near ω = 8.14 and regains
    // it near 9.56 (a period-doubling bubble; found with the orbit diagram)
    let p = paper(10.0).with(Param::Omega, 7.0);
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
    assert_eq!(pds.len(), 2, "{:?}", specials(&b, Special::PeriodDoubling));
    let (w1, w2) = (pds[0].param, pds[1].param);
    assert!(w1 > 8.0 && w1 < 8.3 && w2 > 9.4 && w2 < 9.7, "{w1} {w2}");
    // located to 1e-6: an independent monodromy (differences of plain simulations) has a
    // multiplier on either side of −1 at ω ∓ 1e-6
    for w in [w1, w2] {
        let below = fd_multiplier_near_minus_one(&p.with(Param::Omega, w - 1e-6));
        let above = fd_multiplier_near_minus_one(&p.with(Param::Omega, w + 1e-6));
        assert!(
            (below + 1.0) * (above + 1.0) < 0.0,
            "ω = {w}: multipliers {below} and {above} at ω ∓ 1e-6 do not straddle −1"
        );
    }
    // the doubled branch from the first one ends at the second (the bubble closes)
    let d =
        switch_at_period_doubling(&p, Param::Omega, 1, &pds[0], &pds, [7.0, 10.0], &opts).unwrap();
    assert_eq!(d.subharmonic, 2);
    match d.end {
        End::Rejoined { param } => assert!((param - w2).abs() < 1e-9, "{param} vs {w2}"),
        e => panic!("the doubled branch ended with {e:?}"),
    }
    // inside the bubble its orbits have least period 2, and a long simulation settles on them
    let mid = d
        .points
        .iter()
        .filter(|q| q.stable && q.param > w1 + 0.3 && q.param < w2 - 0.3)
        .max_by(|a, b| {
            a.amplitude
                .peak_to_peak
                .total_cmp(&b.amplitude.peak_to_peak)
        })
        .expect("a stable doubled orbit inside the bubble");
    let pm = p.with(Param::Omega, mid.param);
    let t = std::f64::consts::TAU / mid.param;
    let after_one = state_at(&pm, mid.start, t);
    assert!(
        (after_one[0] - mid.start[0]).abs() > 1e-2,
        "not a period-2 orbit"
    );
    let settled = state_at(&pm, [mid.start[0] + 0.05, mid.start[1]], 400.0 * t);
    let d2 = (settled[0] - mid.start[0]).hypot(settled[1] - mid.start[1]);
    assert!(
        d2 < 1e-8,
        "a simulation of 400 periods ends {d2:e} from the doubled orbit"
    );
    // normal form of a period doubling: the split between x(0) and x(T) grows like √|ω − ω_pd|
    let split = |q: &hdgear::periodic::OrbitPoint| {
        let y = state_at(
            &p.with(Param::Omega, q.param),
            q.start,
            std::f64::consts::TAU / q.param,
        );
        (y[0] - q.start[0]).abs()
    };
    let near: Vec<_> = d.points[1..]
        .iter()
        .filter(|q| (q.param - w1).abs() < 0.02 && (q.param - w1).abs() > 1e-4)
        .take(2)
        .collect();
    assert_eq!(
        near.len(),
        2,
        "two doubled points close to the period doubling"
    );
    let ratio = split(near[1]) / split(near[0]);
    let predicted = ((near[1].param - w1).abs() / (near[0].param - w1).abs()).sqrt();
    assert!(
        (ratio / predicted - 1.0).abs() < 0.1,
        "split ratio {ratio}, √ of the distance ratio {predicted}"
    );
}

#[test]
fn the_diagrams_lyapunov_exponent_is_the_floquet_exponent() {
    // away from bifurcations, at γ = 10, δ = 15: a focus-type period-1 orbit (−1/2 exactly, the
    // complex pair has |m| = e^{−T/2}) and a node-type doubled orbit (ln|m1|/(2T))
    let p = paper(10.0);
    let opts = DiagramOptions {
        lyapunov: Some(400),
        ..DiagramOptions::default()
    };
    let mut points = Vec::new();
    orbit_diagram(&p, Param::Omega, &[6.5, 8.7], &opts, |q| points.push(q)).unwrap();
    let up = sweep_of(&points, SweepDirection::Up);
    // Benettin converges like 1/span: over 400 periods the error is a few 1e-3 (measured 0.2–
    // 5e-3 over ω ∈ [6, 7.5]); 1e-2 is the bound
    assert_eq!(up[0].period, Some(1));
    let l = up[0].lyapunov.unwrap();
    assert!((l + 0.5).abs() < 1e-2, "ω = 6.5: λ = {l}, Floquet −1/2");
    assert_eq!(up[1].period, Some(2));
    let o = shoot(&p.with(Param::Omega, 8.7), 2, &PeriodicOptions::default()).unwrap();
    assert_eq!(o.minimal_subharmonic, 2);
    let l = up[1].lyapunov.unwrap();
    assert!(
        (l - o.floquet_exponents[0]).abs() < 1e-2,
        "ω = 8.7: λ = {l}, Floquet {}",
        o.floquet_exponents[0]
    );
}

/// A forced Duffing oscillator x'' + c x' + x + x³ = F cos s, through the same seam.
#[derive(Clone, Copy, Debug)]
struct Duffing {
    c: f64,
    f: f64,
    omega: f64,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum DuffingParam {
    Omega,
}

impl std::fmt::Display for DuffingParam {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("omega")
    }
}

impl Oscillator for Duffing {
    type Param = DuffingParam;
    fn omega(&self) -> f64 {
        self.omega
    }
    fn accel(&self, s: f64, x: f64, v: f64) -> f64 {
        self.f * s.cos() - self.c * v - x - x * x * x
    }
    fn accel_gradient(&self, _s: f64, x: f64, _v: f64) -> [f64; 2] {
        [-1.0 - 3.0 * x * x, -self.c]
    }
    fn accel_derivative(&self, _p: DuffingParam, _s: f64, _x: f64, _v: f64) -> f64 {
        0.0
    }
    fn get(&self, _p: DuffingParam) -> f64 {
        self.omega
    }
    fn with(&self, _p: DuffingParam, value: f64) -> hdgear::Result<Self> {
        Ok(Duffing {
            omega: value,
            ..*self
        })
    }
    fn is_frequency(_p: DuffingParam) -> bool {
        true
    }
    fn check(&self) -> hdgear::Result<()> {
        Ok(())
    }
}

#[test]
fn a_duffing_oscillators_peak_matches_harmonic_balance() {
    // harmonic balance, x ≈ A cos(ωτ − θ): ((1 + 3A²/4 − ω²)² + (cω)²) A² = F²; at the peak
    // ω² = 1 + 3A²/4 and A = F/(cω). With c = 0.05, F = 0.02: ω⁴ − ω² − 0.12 = 0.
    let d = Duffing {
        c: 0.05,
        f: 0.02,
        omega: 0.8,
    };
    let w2 = (1.0 + 1.48f64.sqrt()) / 2.0;
    let (w_peak, a_peak) = (w2.sqrt(), 0.02 / (0.05 * w2.sqrt()));
    let opts = ContinuationOptions {
        scale: Scale::Log,
        ..ContinuationOptions::default()
    };
    let b = continue_orbit(&d, DuffingParam::Omega, 1, None, 1.4, &opts).unwrap();
    let top = b
        .points
        .iter()
        .max_by(|x, y| {
            x.amplitude
                .peak_to_peak
                .total_cmp(&y.amplitude.peak_to_peak)
        })
        .unwrap();
    let a = top.amplitude.peak_to_peak / 2.0;
    // the neglected third harmonic is O(A²/32) ≈ 0.5 % of A here; 2 % bounds it
    assert!(
        (a / a_peak - 1.0).abs() < 0.02,
        "peak amplitude {a}, harmonic balance {a_peak}"
    );
    assert!(
        (top.param / w_peak - 1.0).abs() < 0.02,
        "peak at ω = {}, harmonic balance {w_peak}",
        top.param
    );
    // the peak is (next to) the upper fold: a hardening bend with two folds
    assert_eq!(specials(&b, Special::Fold).len(), 2);
}

#[test]
fn batched_lyapunov_rows_equal_one_by_one_rows() {
    // a 5 × 4 grid (one full chunk and a partial one) across periodic responses, long
    // transients and the period-doubling range of γ = 10; DOP853 goes point by point
    use hdgear::periodic::{DiagramOptions, lyapunov_point, lyapunov_points};
    let grid = hdgear::sweep::Grid::new(
        Params {
            gamma: 10.0,
            ..Params::default()
        },
        vec![
            hdgear::sweep::Axis::parse("omega=2:14:5:log").unwrap(),
            hdgear::sweep::Axis::parse("delta=2:80:4:log").unwrap(),
        ],
    )
    .unwrap();
    let opts = DiagramOptions {
        discard: 100,
        lyapunov: Some(100),
        ..DiagramOptions::default()
    };
    let points: Vec<(usize, Params)> = (0..grid.len()).map(|i| (i, grid.point(i))).collect();
    let batched = lyapunov_points(&points, &opts);
    for ((i, p), b) in points.iter().zip(&batched) {
        let one = lyapunov_point(*i, p, &opts);
        assert_eq!(
            (b.index, b.period, &b.error),
            (one.index, one.period, &one.error)
        );
        // the exponent is ln(growth)/span: relative errors of ~1e-10 per step over ~1e3 steps
        // give ~1e-7 in the logarithm, over a span ≥ 45 time units ~2e-9 (measured over the
        // report's 640-point map: ≤ 1.3e-9)
        assert!(
            (b.lyapunov - one.lyapunov).abs() < 1e-7,
            "point {i}: batched {}, one by one {}",
            b.lyapunov,
            one.lyapunov
        );
    }
    // a point that cannot run gets its own error, its neighbours their values
    let mut bad = points.clone();
    bad[3].1.omega = -1.0;
    let rows = lyapunov_points(&bad, &opts);
    assert!(!rows[3].error.is_empty() && rows[3].lyapunov.is_nan());
    for (i, r) in rows.iter().enumerate().filter(|(i, _)| *i != 3) {
        assert_eq!(r.lyapunov, batched[i].lyapunov, "point {i}");
    }
}

/// The periodic machinery integrates with Taylor's method (the variational system's Taylor
/// coefficients from `Oscillator::phase_taylor`); DOP853, the independent method, gives the same
/// orbits, multipliers and special points: the orbit's start and Floquet exponents to 1e-8, the
/// folds and period doublings of the γ = 10 branch to 1e-7 relative (both at rtol 1e-12; the
/// special points are located to a relative 1e-9 by the continuation itself).
#[test]
fn taylor_and_dop853_give_the_same_periodic_responses() {
    let with = |method| {
        let mut o = ContinuationOptions {
            scale: Scale::Log,
            ..ContinuationOptions::default()
        };
        o.periodic.tol.method = method;
        o
    };
    for (g, w) in [(10.0, 8.6), (0.1, 1.67), (30.0, 8.0)] {
        let p = paper(g).with(Param::Omega, w);
        let orbit = |m| shoot(&p, 1, &with(m).periodic).unwrap();
        let (t, d) = (orbit(Method::Taylor), orbit(Method::Dop853));
        for i in 0..2 {
            assert!(
                (t.start[i] - d.start[i]).abs() < 1e-8,
                "{g} {w}: {t:?} {d:?}"
            );
            let (a, b) = (t.floquet_exponents[i], d.floquet_exponents[i]);
            assert!((a - b).abs() < 1e-8 * (1.0 + b.abs()), "{g} {w}: {a} {b}");
        }
    }
    // the period doublings of the γ = 10 branch, the folds of the bent γ = 30 response
    let p = paper(10.0).with(Param::Omega, 7.0);
    let branch = |m| continue_orbit(&p, Param::Omega, 1, None, 10.0, &with(m)).unwrap();
    let response = |m| frequency_response(&bent(), Some((6.0, 10.0)), &with(m)).unwrap();
    for (kind, t, d) in [
        (
            Special::PeriodDoubling,
            branch(Method::Taylor),
            branch(Method::Dop853),
        ),
        (
            Special::Fold,
            response(Method::Taylor),
            response(Method::Dop853),
        ),
    ] {
        let (a, b) = (specials(&t, kind), specials(&d, kind));
        assert_eq!(a.len(), 2, "{kind:?}: {a:?} {b:?}");
        assert_eq!(a.len(), b.len(), "{kind:?}: {a:?} {b:?}");
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() < 1e-7 * y, "{kind:?}: {a:?} {b:?}");
        }
    }
}
