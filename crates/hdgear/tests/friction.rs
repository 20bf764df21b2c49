//! Coulomb–Stribeck–viscous friction with sticking ([`hdgear::model::switching`]) against an
//! independent event-driven integration written here from the equations (classical RK4 with
//! restarts at every switch, each switch located by bisection on a single RK4 step), and the
//! regularised friction (tanh) converging to it.

use hdgear::Params;
use hdgear::integrate::{Method, Options};
use hdgear::model::Model;
use hdgear::model::switching::Mode;
use hdgear::model::terms::AnyTerm;
use hdgear::simulate::{SimOptions, Start, simulate_model};

/// The friction law's parameters: f_c, f_s, v_st, c_v.
#[derive(Clone, Copy)]
struct Law {
    fc: f64,
    fs: f64,
    vst: f64,
    cv: f64,
}

/// The reference: x'' = μ + δ sin ωt − x' − (αx³ − x² + γ(x − ε)) − f(x'), written out.
struct Reference {
    p: Params,
    f: Law,
    /// RK4 step.
    h: f64,
}

/// What the reference records: the samples on the grid and the switches (t, x, mode entered).
struct Run {
    samples: Vec<(f64, [f64; 2])>,
    switches: Vec<(f64, f64, Mode)>,
}

impl Reference {
    fn stiffness(&self, x: f64) -> f64 {
        let p = &self.p;
        p.alpha * x * x * x - x * x + p.gamma * (x - p.eps)
    }
    /// The torque the static band holds: everything but friction, at rest.
    fn applied(&self, t: f64, x: f64) -> f64 {
        self.p.mu + self.p.delta * (self.p.omega * t).sin() - self.stiffness(x)
    }
    fn accel(&self, t: f64, x: f64, v: f64, s: f64) -> f64 {
        let Law { fc, fs, vst, cv } = self.f;
        let friction = (fc + (fs - fc) * (-(v / vst) * (v / vst)).exp()) * s + cv * v;
        self.applied(t, x) - v - friction
    }
    fn rk4(&self, t: f64, y: [f64; 2], h: f64, s: f64) -> [f64; 2] {
        let f = |t: f64, y: [f64; 2]| [y[1], self.accel(t, y[0], y[1], s)];
        crate::common::rk4_step(f, t, y, h)
    }
    fn mode_at_rest(&self, t: f64, x: f64) -> Mode {
        let a = self.applied(t, x);
        if a.abs() <= self.f.fs {
            Mode::Stuck
        } else if a > 0.0 {
            Mode::Forward
        } else {
            Mode::Backward
        }
    }
    /// From (0, y0) to `t_end`, samples every `dt`.
    fn run(&self, y0: [f64; 2], t_end: f64, dt: f64) -> Run {
        let mut out = Run {
            samples: vec![(0.0, y0)],
            switches: vec![],
        };
        let (mut t, mut y) = (0.0, y0);
        let mut mode = if y0[1] != 0.0 {
            if y0[1] > 0.0 {
                Mode::Forward
            } else {
                Mode::Backward
            }
        } else {
            self.mode_at_rest(0.0, y0[0])
        };
        let mut k = 1;
        let sample_at = |k: usize| (k as f64 * dt).min(t_end);
        while t < t_end {
            let next = sample_at(k);
            if mode == Mode::Stuck {
                let g = |t: f64| self.applied(t, y[0]).abs() - self.f.fs;
                // scan to the next sample for |A| reaching the band, then bisect
                let mut ta = t;
                let mut unstick = None;
                while ta < next {
                    let tb = (ta + 1e-3).min(next);
                    if g(tb) > 0.0 {
                        let (mut lo, mut hi) = (ta, tb);
                        while hi - lo > 1e-15 * hi.max(1.0) {
                            let mid = 0.5 * (lo + hi);
                            if g(mid) > 0.0 { hi = mid } else { lo = mid }
                        }
                        unstick = Some(hi);
                        break;
                    }
                    ta = tb;
                }
                match unstick {
                    Some(tu) => {
                        t = tu;
                        mode = if self.applied(tu, y[0]) > 0.0 {
                            Mode::Forward
                        } else {
                            Mode::Backward
                        };
                        out.switches.push((t, y[0], mode));
                    }
                    None => {
                        t = next;
                        out.samples.push((t, y));
                        k += 1;
                    }
                }
                continue;
            }
            let s = if mode == Mode::Forward { 1.0 } else { -1.0 };
            let h = self.h.min(next - t);
            let y1 = self.rk4(t, y, h, s);
            if s * y1[1] < 0.0 {
                // the switch: s·x' = 0 on a single RK4 step from (t, y), by bisection
                let (mut lo, mut hi) = (0.0, h);
                while hi - lo > 1e-16 * (t + hi) {
                    let mid = 0.5 * (lo + hi);
                    if s * self.rk4(t, y, mid, s)[1] > 0.0 {
                        lo = mid
                    } else {
                        hi = mid
                    }
                }
                let ts = t + 0.5 * (lo + hi);
                y = [self.rk4(t, y, ts - t, s)[0], 0.0];
                t = ts;
                mode = self.mode_at_rest(t, y[0]);
                out.switches.push((t, y[0], mode));
                continue;
            }
            (t, y) = (t + h, y1);
            if t == next {
                out.samples.push((t, y));
                k += 1;
            }
        }
        out
    }
}

/// hdgear's run of the same model: samples and switches (from the summary's count and the
/// samples' rests are not enough, so the switches are read from a [`Switching`] stepper).
fn hdgear_run(p: &Params, f: Law, method: Method, t_end: f64, dt: f64) -> Run {
    use hdgear::integrate::Stepper;
    use hdgear::model::switching::{Pieces, Switching};
    let m = model(p, f);
    let tol = Options {
        rtol: 1e-13,
        atol: 1e-13,
        method,
        ..Options::default()
    };
    let opts = SimOptions {
        t_end,
        dt,
        start: Start::Rest,
        tol,
    };
    let mut samples = vec![];
    let summary = simulate_model(&m, &opts, |t, y| samples.push((t, [y[0], y[1]]))).unwrap();
    let pieces = Pieces::new(&m).unwrap();
    let mut s = Switching::new(&pieces, 0.0, [0.0, 0.0], tol).unwrap();
    let mut switches = vec![];
    while s.t() < t_end {
        s.step(t_end).unwrap();
        if let Some(w) = s.last_switch() {
            switches.push((w.t, w.x, w.to));
        }
    }
    let sticking = summary.sticking.unwrap();
    assert_eq!(sticking.switches, switches.len() as u64);
    Run { samples, switches }
}

fn model(p: &Params, f: Law) -> Model {
    Model::study(p)
        .with_term(AnyTerm::new("coulomb", &[f.fc, f.fs, f.vst, f.cv]).unwrap())
        .unwrap()
}

/// Largest difference of switch times and x there, and of the sampled states.
fn compare(a: &Run, b: &Run) -> (f64, f64) {
    assert_eq!(a.switches.len(), b.switches.len(), "switch counts differ");
    let mut dswitch: f64 = 0.0;
    for (s, r) in a.switches.iter().zip(&b.switches) {
        assert_eq!(s.2, r.2, "mode entered at t = {} vs {}", s.0, r.0);
        dswitch = dswitch.max((s.0 - r.0).abs()).max((s.1 - r.1).abs());
    }
    assert_eq!(a.samples.len(), b.samples.len());
    let mut dstate: f64 = 0.0;
    for ((ta, ya), (tb, yb)) in a.samples.iter().zip(&b.samples) {
        assert!((ta - tb).abs() < 1e-12, "{ta} vs {tb}");
        dstate = dstate.max((ya[0] - yb[0]).abs()).max((ya[1] - yb[1]).abs());
    }
    (dswitch, dstate)
}

/// The cases: stick-slip under a slow sine (sticks and slips), and a faster, stronger forcing
/// with viscous friction where the motion also reverses at rest without sticking.
fn cases() -> [(Params, Law, f64); 2] {
    let p = Params::default();
    [
        (
            Params {
                delta: 1.0,
                omega: 0.5,
                ..p
            },
            Law {
                fc: 0.3,
                fs: 0.4,
                vst: 0.1,
                cv: 0.0,
            },
            60.0,
        ),
        (
            Params {
                delta: 3.0,
                omega: 2.0,
                gamma: 1.0,
                ..p
            },
            Law {
                fc: 0.2,
                fs: 0.5,
                vst: 0.05,
                cv: 0.3,
            },
            30.0,
        ),
    ]
}

#[test]
fn sticking_friction_matches_an_independent_event_driven_integration() {
    for (p, f, t_end) in cases() {
        let dt = 0.05;
        let reference = |h| Reference { p, f, h }.run([0.0, 0.0], t_end, dt);
        let (r, r2) = (reference(2e-4), reference(1e-4));
        // the reference's own accuracy: halving its step changes nothing at the 1e-10 level
        let (ds, dy) = compare(&r, &r2);
        assert!(
            ds < 1e-10 && dy < 1e-10,
            "reference not converged: {ds:e} {dy:e}"
        );
        for method in Method::ALL {
            let h = hdgear_run(&p, f, method, t_end, dt);
            let (ds, dy) = compare(&h, &r2);
            assert!(
                ds < 1e-9 && dy < 1e-9,
                "{method:?}: switches differ by {ds:e}, states by {dy:e}"
            );
        }
    }
    // the cases cover both: the first sticks (and slips), the second reverses at rest
    let runs =
        cases().map(|(p, f, t_end)| Reference { p, f, h: 2e-4 }.run([0.0, 0.0], t_end, 0.05));
    let sticks = |r: &Run| r.switches.iter().filter(|s| s.2 == Mode::Stuck).count();
    let reversals = |r: &Run| {
        r.switches
            .windows(2)
            .filter(|w| w[0].2 != Mode::Stuck && w[1].2 != Mode::Stuck)
            .count()
    };
    assert!(sticks(&runs[0]) >= 4, "{:?}", runs[0].switches);
    assert!(reversals(&runs[1]) >= 10, "{:?}", runs[1].switches);
}

#[test]
fn regularised_friction_converges_to_sticking() {
    let (p, f, t_end) = cases()[0];
    let exact = hdgear_run(&p, f, Method::Taylor, t_end, 0.05);
    let error = |vr: f64| {
        let m = Model::study(&p)
            .with_term(AnyTerm::new("stribeck", &[f.fc, f.fs, f.vst, f.cv, vr]).unwrap())
            .unwrap();
        let opts = SimOptions {
            t_end,
            dt: 0.05,
            start: Start::Rest,
            tol: Options::default(),
        };
        let mut e: f64 = 0.0;
        let mut k = 0;
        simulate_model(&m, &opts, |_, y| {
            e = e.max((y[0] - exact.samples[k].1[0]).abs());
            k += 1;
        })
        .unwrap();
        e
    };
    let errors: Vec<f64> = [1e-2, 1e-3, 1e-4].iter().map(|&vr| error(vr)).collect();
    eprintln!("regularised vs sticking, max |Δx|: {errors:?}");
    // first order in v_r: the creep while stuck is x' ≈ v_r·A/f_s
    for w in errors.windows(2) {
        assert!(w[1] < w[0] / 3.0 && w[1] > w[0] / 30.0, "{errors:?}");
    }
}

/// The regularised terms near their switch (steep tanh, a Stribeck dip the state's series do not
/// show until it acts): Taylor's method against DOP853, both at 1e-12, over a stick-slip run.
#[test]
fn regularised_terms_taylor_agrees_with_dop853() {
    let (p, f, t_end) = cases()[0];
    let terms = [
        AnyTerm::new("stribeck", &[f.fc, f.fs, f.vst, f.cv, 1e-3]).unwrap(),
        AnyTerm::new("stribeck", &[f.fc, f.fs, 0.03, 0.2, 1e-4]).unwrap(),
        AnyTerm::new("friction", &[f.fs, 1e-4]).unwrap(),
    ];
    for term in terms {
        let m = Model::study(&p).with_term(term).unwrap();
        let run = |method| {
            let opts = SimOptions {
                t_end,
                dt: 0.05,
                start: Start::Rest,
                tol: Options {
                    rtol: 1e-12,
                    atol: 1e-12,
                    method,
                    ..Options::default()
                },
            };
            let mut xs = vec![];
            simulate_model(&m, &opts, |_, y| xs.push([y[0], y[1]])).unwrap();
            xs
        };
        let (a, b) = (run(Method::Taylor), run(Method::Dop853));
        let worst = a
            .iter()
            .zip(&b)
            .map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs()))
            .fold(0.0, f64::max);
        assert!(
            worst < 1e-8,
            "{term:?}: Taylor and DOP853 differ by {worst:e}"
        );
    }
}
