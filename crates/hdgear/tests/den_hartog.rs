//! Periodic orbits of a model whose friction sticks, shot switch by switch with the saltation
//! matrices ([`hdgear::periodic::shoot`] on a `coulomb` model), held to an anchor written from
//! the equations alone: Den Hartog's (1931) closed-form steady state of a harmonically forced
//! linear oscillator with Coulomb and viscous friction,
//!
//!   x'' + c·x' + k·x + F·sgn x' = P·sin ωt   (here c = 1, the model's unit damping),
//!
//! in the regime without stops, and the boundary where stops begin; the multipliers are held to
//! finite differences of the flow map (the run itself, not its variational equations).

use hdgear::integrate::Options;
use hdgear::model::Model;
use hdgear::model::terms::AnyTerm;
use hdgear::periodic::{PeriodicOptions, PeriodicOrbit, shoot};
use hdgear::simulate::{SimOptions, Start, simulate_model};
use std::f64::consts::{PI, TAU};

type M2 = [[f64; 2]; 2];

fn mul(a: M2, b: M2) -> M2 {
    [
        [
            a[0][0] * b[0][0] + a[0][1] * b[1][0],
            a[0][0] * b[0][1] + a[0][1] * b[1][1],
        ],
        [
            a[1][0] * b[0][0] + a[1][1] * b[1][0],
            a[1][0] * b[0][1] + a[1][1] * b[1][1],
        ],
    ]
}

fn apply(a: M2, y: [f64; 2]) -> [f64; 2] {
    [
        a[0][0] * y[0] + a[0][1] * y[1],
        a[1][0] * y[0] + a[1][1] * y[1],
    ]
}

/// Den Hartog's steady state without stops of x'' + x' + kx + F·sgn x' = P sin ωt: each half
/// period is linear with the friction constant, x(t + π/ω) = −x(t), and the motion turns at
/// x = −X at t₁ (x' = 0), moving forward until t₁ + π/ω.
#[derive(Clone, Copy)]
struct DenHartog {
    k: f64,
    p: f64,
    f: f64,
    omega: f64,
}

impl DenHartog {
    const C: f64 = 1.0;

    /// exp(Λt) of Λ = [[0, 1], [−k, −c]] (under-damped: k > c²/4).
    fn expm(&self, t: f64) -> M2 {
        let wd = (self.k - Self::C * Self::C / 4.0).sqrt();
        let (e, c, s) = (
            (-Self::C * t / 2.0).exp(),
            (wd * t).cos(),
            (wd * t).sin() / wd,
        );
        let h = Self::C / 2.0;
        [
            [e * (c + h * s), e * s],
            [e * (-self.k * s), e * (c - h * s)],
        ]
    }

    /// The forced part's amplitude A and lag φ: x_p = −F/k + A sin(ωt − φ) on a forward half.
    fn forced(&self) -> (f64, f64) {
        let (k, w) = (self.k, self.omega);
        let a = self.p / ((k - w * w).powi(2) + (Self::C * w).powi(2)).sqrt();
        (a, (Self::C * w).atan2(k - w * w))
    }

    /// The particular solution (x, x') of a forward half at t.
    fn particular(&self, t: f64) -> [f64; 2] {
        let (a, phi) = self.forced();
        let th = self.omega * t - phi;
        [-self.f / self.k + a * th.sin(), a * self.omega * th.cos()]
    }

    /// (X, t₁): the amplitude and the time of the turn at −X. With H = π/ω, E = exp(ΛH) and
    /// G = (I + E)⁻¹(E − I), the antiperiodicity y(t₁ + H) = −y(t₁) gives y(t₁) = q + G·(−F/k, 0)
    /// with q the forced part at t₁, whence cos θ = G₂₁F/(kAω) and X = G₁₁F/k − A sin θ, θ =
    /// ωt₁ − φ, sin θ < 0 (the turn at the left end).
    fn solve(&self) -> Option<(f64, f64)> {
        let e = self.expm(PI / self.omega);
        let (ip, im) = (
            [[1.0 + e[0][0], e[0][1]], [e[1][0], 1.0 + e[1][1]]],
            [[e[0][0] - 1.0, e[0][1]], [e[1][0], e[1][1] - 1.0]],
        );
        let d = ip[0][0] * ip[1][1] - ip[0][1] * ip[1][0];
        let inv = [[ip[1][1] / d, -ip[0][1] / d], [-ip[1][0] / d, ip[0][0] / d]];
        let g = mul(inv, im);
        let (a, phi) = self.forced();
        let cos = g[1][0] * self.f / (self.k * a * self.omega);
        if cos.abs() > 1.0 {
            return None;
        }
        let sin = -(1.0 - cos * cos).sqrt();
        let x = g[0][0] * self.f / self.k - a * sin;
        let theta = sin.atan2(cos);
        Some((x, (theta + phi) / self.omega))
    }

    /// (x, x') at t on the steady state.
    fn state(&self, t: f64) -> [f64; 2] {
        let (x, t1) = self.solve().unwrap();
        let h = PI / self.omega;
        let mut s = (t - t1).rem_euclid(2.0 * h);
        let sign = if s >= h {
            s -= h;
            -1.0
        } else {
            1.0
        };
        let yp0 = self.particular(t1);
        let dy = apply(self.expm(s), [-x - yp0[0], -yp0[1]]);
        let yp = self.particular(t1 + s);
        [sign * (yp[0] + dy[0]), sign * (yp[1] + dy[1])]
    }

    /// Whether the closed form is a motion without stops: x' > 0 inside the forward half
    /// (sampled), and at the turn the spring and the load exceed the friction (else the motion
    /// sticks there).
    fn without_stops(&self) -> bool {
        let Some((x, t1)) = self.solve() else {
            return false;
        };
        let h = PI / self.omega;
        let moving = (1..400).all(|i| self.state(t1 + h * i as f64 / 400.0)[1] > 0.0);
        moving && self.push_at_turn(x, t1) > self.f
    }

    /// The torque that pushes the motion on at the turn: P sin ωt₁ + kX.
    fn push_at_turn(&self, x: f64, t1: f64) -> f64 {
        self.p * (self.omega * t1).sin() + self.k * x
    }

    /// The friction level where stops begin: the push at the turn equals F (bisection on the
    /// closed form, from a level without stops to one beyond).
    fn stop_level(&self) -> f64 {
        let at = |f: f64| {
            let d = DenHartog { f, ..*self };
            d.solve().map_or(-1.0, |(x, t1)| d.push_at_turn(x, t1) - f)
        };
        let (mut lo, mut hi) = (0.0, self.p);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if at(mid) > 0.0 { lo = mid } else { hi = mid }
        }
        0.5 * (lo + hi)
    }

    fn model(&self) -> Model {
        Model::damped(0.0, self.p, self.omega)
            .with_term(AnyTerm::new("spring", &[self.k, 0.0, 0.0]).unwrap())
            .unwrap()
            .with_term(AnyTerm::new("coulomb", &[self.f, self.f, 0.1, 0.0]).unwrap())
            .unwrap()
    }
}

fn orbit(d: &DenHartog) -> PeriodicOrbit<Model> {
    shoot(&d.model(), 1, &PeriodicOptions::default()).unwrap()
}

/// Sets spread over the regime without stops: below, at and above resonance (ω/√k from 0.6 to
/// 2), light and heavy friction (F/P from 0.05 to 0.5), soft and stiff springs.
const SETS: [(f64, f64, f64, f64); 8] = [
    // (k, P, F, ω)
    (1.0, 1.0, 0.1, 1.0),
    (4.0, 2.0, 0.3, 2.2),
    (4.0, 1.0, 0.05, 1.4),
    (9.0, 3.0, 0.6, 3.3),
    (2.0, 1.0, 0.2, 2.5),
    (25.0, 4.0, 1.0, 4.0),
    (25.0, 4.0, 0.5, 6.0),
    (1.0, 0.5, 0.2, 1.8),
];

/// Amplitude and phase: the shot orbit's extremes are ±X, and its start at τ = 0 is Den Hartog's
/// state there, to 1e-8 (Newton stops at 1e-11 on the map, the run is at 1e-12).
#[test]
fn stick_free_orbits_are_den_hartog_s() {
    for (k, p, f, omega) in SETS {
        let d = DenHartog { k, p, f, omega };
        assert!(
            d.without_stops(),
            "{k} {p} {f} {omega}: a set without stops"
        );
        let (x, _) = d.solve().unwrap();
        let o = orbit(&d);
        let want = d.state(0.0);
        for (got, want, what) in [
            (o.x_range[1], x, "x max"),
            (-o.x_range[0], x, "−x min"),
            (o.start[0], want[0], "x(0)"),
            (o.start[1], want[1], "x'(0)"),
        ] {
            assert!(
                (got - want).abs() <= 1e-8 * x.max(1.0),
                "k {k}, P {p}, F {f}, ω {omega}: {what} {got} against Den Hartog's {want}"
            );
        }
        assert!(o.stable, "{k} {p} {f} {omega}: stable");
    }
}

/// The run from `y` over one forcing period: the flow map itself.
fn flow_map(m: &Model, y: [f64; 2]) -> [f64; 2] {
    let t_end = TAU / m.forcing()[2];
    let opts = SimOptions {
        t_end,
        dt: t_end,
        start: Start::Given { x0: y[0], v0: y[1] },
        tol: Options {
            rtol: 1e-13,
            atol: 1e-13,
            ..Options::default()
        },
    };
    simulate_model(m, &opts, |_, _| {}).unwrap().final_state
}

/// The monodromy by central differences of the flow map at `y` (step `h`).
fn fd_monodromy(m: &Model, y: [f64; 2], h: f64) -> M2 {
    let col = |i: usize| {
        let (mut a, mut b) = (y, y);
        a[i] += h;
        b[i] -= h;
        let (fa, fb) = (flow_map(m, a), flow_map(m, b));
        [(fa[0] - fb[0]) / (2.0 * h), (fa[1] - fb[1]) / (2.0 * h)]
    };
    let (c0, c1) = (col(0), col(1));
    [[c0[0], c1[0]], [c0[1], c1[1]]]
}

/// The multipliers of a 2 × 2 matrix as (|m|, arg m), the larger first.
fn eig(a: M2) -> [(f64, f64); 2] {
    let tr = a[0][0] + a[1][1];
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let disc = tr * tr - 4.0 * det;
    if disc < 0.0 {
        let r = det.sqrt();
        let arg = (-disc).sqrt().atan2(tr).abs();
        return [(r, arg), (r, -arg)];
    }
    let big = 0.5 * (tr + tr.signum() * disc.sqrt());
    let small = if big == 0.0 { 0.0 } else { det / big };
    let polar = |m: f64| (m.abs(), if m < 0.0 { PI } else { 0.0 });
    [polar(big), polar(small)]
}

/// The multipliers from the saltation matrices agree with central differences of the flow map
/// to 1e-6: on orbits without stops (a complex pair or two real ones), and on stick-slip orbits,
/// where a rest forgets the speed and the second multiplier is exactly 0.
#[test]
fn multipliers_across_switches_are_the_flow_map_s() {
    let stops = |d: DenHartog| DenHartog {
        f: 1.2 * d.stop_level(),
        ..d
    };
    let cases = [
        DenHartog {
            k: 1.0,
            p: 1.0,
            f: 0.1,
            omega: 1.0,
        },
        DenHartog {
            k: 4.0,
            p: 2.0,
            f: 0.3,
            omega: 2.2,
        },
        stops(DenHartog {
            k: 4.0,
            p: 2.0,
            f: 0.0,
            omega: 1.2,
        }),
        stops(DenHartog {
            k: 1.0,
            p: 1.0,
            f: 0.0,
            omega: 0.5,
        }),
    ];
    let stribeck = |fs: f64| {
        let p = hdgear::Params {
            delta: 1.0,
            omega: 0.5,
            ..hdgear::Params::default()
        };
        Model::study(&p)
            .with_term(AnyTerm::new("coulomb", &[0.3, fs, 0.1, 0.0]).unwrap())
            .unwrap()
    };
    let models = cases
        .iter()
        .map(DenHartog::model)
        // the study's cubic with a Stribeck dip (f_s > f_c): one rest per period, then past a
        // period doubling
        .chain([0.45, 0.64, 0.85].map(stribeck));
    for m in models {
        let o = shoot(&m, 1, &PeriodicOptions::default()).unwrap();
        let fd = eig(fd_monodromy(&m, o.start, 1e-6));
        for (j, q) in o.multipliers.iter().enumerate() {
            let (abs, arg) = (q.log_abs.exp(), q.arg);
            let err = (abs * arg.cos() - fd[j].0 * fd[j].1.cos())
                .hypot(abs * arg.sin() - fd[j].0 * fd[j].1.sin());
            assert!(
                err < 1e-6,
                "{}: m{} = {abs:e}∠{arg} against the flow map's {:e}∠{} ({err:e})",
                m.equation(),
                j + 1,
                fd[j].0,
                fd[j].1
            );
        }
    }
}

/// Where stops begin: Den Hartog's boundary is the friction level at which the spring and the
/// load at the turn just equal F. A thousandth below it the shot orbit has no rest; a thousandth
/// above, it rests at both turns of each period (the boundary to 1e-3 of F, on sets below, at
/// and above resonance).
#[test]
fn stops_begin_at_den_hartog_s_boundary() {
    for (k, p, omega) in [
        (4.0, 2.0, 1.2),
        (1.0, 1.0, 0.5),
        (9.0, 3.0, 4.0),
        (1.0, 1.0, 1.0),
    ] {
        let d = DenHartog {
            k,
            p,
            f: 0.0,
            omega,
        };
        let level = d.stop_level();
        let rests = |f: f64| {
            let o = orbit(&DenHartog { f, ..d });
            o.rests
                .expect("a sticking model's orbit counts its rests")
                .rests
        };
        let (below, above) = (rests(level * (1.0 - 1e-3)), rests(level * (1.0 + 1e-3)));
        assert_eq!(
            (below, above),
            (0, 2),
            "k {k}, P {p}, ω {omega}: stops begin at F = {level} (rests just below, just above)"
        );
        assert!(
            DenHartog {
                f: level * (1.0 - 1e-3),
                ..d
            }
            .without_stops()
        );
    }
}

/// Continuation carries the parameter sensitivity w across the switches (the saltation's jump):
/// the branch in the load amplitude P from a large load down to where the friction stops the
/// motion at its turns, and the frequency response across resonance, are Den Hartog's amplitude
/// at every point without stops (to 1e-8).
#[test]
fn branches_across_switches_follow_den_hartog() {
    use hdgear::periodic::{ContinuationOptions, OrbitBranch, continue_orbit, frequency_response};
    let opts = ContinuationOptions::default();
    let compare = |branch: &OrbitBranch<_>, at: &dyn Fn(f64) -> DenHartog| {
        let mut compared = 0;
        for pt in &branch.points {
            let d = at(pt.param);
            if !d.without_stops() {
                continue;
            }
            let (x, _) = d.solve().unwrap();
            assert!(
                (pt.amplitude.x_max - x).abs() < 1e-8 * x,
                "{:?} at {}: x max {} against Den Hartog's {x}",
                (d.k, d.p, d.f, d.omega),
                pt.param,
                pt.amplitude.x_max
            );
            compared += 1;
        }
        assert!(compared >= 10, "{compared} points compared");
    };
    let d = DenHartog {
        k: 4.0,
        p: 3.0,
        f: 0.3,
        omega: 1.2,
    };
    let m = d.model();
    let delta = m.param("delta").unwrap();
    let branch = continue_orbit(&m, delta, 1, None, 0.3, &opts).unwrap();
    compare(&branch, &|p| DenHartog { p, ..d });
    let stops = branch
        .points
        .iter()
        .any(|pt| !DenHartog { p: pt.param, ..d }.without_stops());
    assert!(
        stops,
        "the branch reaches loads where the motion stops at its turns"
    );

    let d = DenHartog {
        k: 4.0,
        p: 2.0,
        f: 0.3,
        omega: 2.0,
    };
    let fr = frequency_response(&d.model(), Some((1.5, 4.0)), &opts).unwrap();
    compare(&fr, &|omega| DenHartog { omega, ..d });
}

/// A friction whose breakaway exceeds the load everywhere (F ≥ P: the band holds the spring at
/// rest at x = 0 with the load inside it all period) rests all period: its orbit is the rest, m₁ = 1
/// exactly (every x whose spring torque k·x stays within F − P of the band rests too), m₂ = 0,
/// neutral; and no branch follows from it, which the continuation says in one line rather than
/// failing on its singular tangent.
#[test]
fn a_drive_held_all_period_is_neutral_and_has_no_branch() {
    use hdgear::periodic::{ContinuationOptions, Stability, frequency_response};
    let d = DenHartog {
        k: 4.0,
        p: 1.0,
        f: 1.5,
        omega: 2.0,
    };
    let o = orbit(&d);
    assert_eq!(o.stability(), Stability::RestsAllPeriod);
    assert_eq!(o.multipliers[0].log_abs, 0.0);
    assert_eq!(o.multipliers[1].log_abs, f64::NEG_INFINITY);
    assert_eq!((o.peak_to_peak, o.max_abs_xdot), (0.0, 0.0));
    let e = frequency_response(
        &d.model(),
        Some((1.0, 3.0)),
        &ContinuationOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(!e.contains('\n'), "{e}");
    assert!(e.contains("at rest all period"), "{e}");
    // one slip per half period (F < P) is an isolated orbit: stable, and continued
    let slipping = DenHartog { f: 0.3, ..d };
    assert_eq!(orbit(&slipping).stability(), Stability::Stable);
    let b = frequency_response(
        &slipping.model(),
        Some((1.0, 3.0)),
        &ContinuationOptions::default(),
    )
    .unwrap();
    assert!(b.points.len() > 2);
}
