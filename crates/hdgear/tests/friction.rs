//! Coulomb–Stribeck–viscous friction with sticking ([`hdgear::model::switching`]) against an
//! independent event-driven integration written here from the equations (classical RK4 with
//! restarts at every switch, each switch located by bisection on a single RK4 step), and the
//! regularised friction (tanh) converging to it.

use hdgear::Params;
use hdgear::integrate::{Method, Options};
use hdgear::model::Model;
use hdgear::model::switching::SwitchingMode;
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
    switches: Vec<(f64, f64, SwitchingMode)>,
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
    fn mode_at_rest(&self, t: f64, x: f64) -> SwitchingMode {
        let a = self.applied(t, x);
        if a.abs() <= self.f.fs {
            SwitchingMode::Stuck
        } else if a > 0.0 {
            SwitchingMode::Forward
        } else {
            SwitchingMode::Backward
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
                SwitchingMode::Forward
            } else {
                SwitchingMode::Backward
            }
        } else {
            self.mode_at_rest(0.0, y0[0])
        };
        let mut k = 1;
        let sample_at = |k: usize| (k as f64 * dt).min(t_end);
        while t < t_end {
            let next = sample_at(k);
            if mode == SwitchingMode::Stuck {
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
                            SwitchingMode::Forward
                        } else {
                            SwitchingMode::Backward
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
            let s = if mode == SwitchingMode::Forward {
                1.0
            } else {
                -1.0
            };
            let h = self.h.min(next - t);
            let y1 = self.rk4(t, y, h, s);
            if s * y1[1] < 0.0 {
                // the switch: s·x' = 0 on a single RK4 step from (t, y), by bisection
                let ts =
                    t + crate::common::crossing(t, h, |tau| s * self.rk4(t, y, tau, s)[1] > 0.0);
                y = [self.rk4(t, y, ts - t, s)[0], 0.0];
                t = ts;
                mode = self.mode_at_rest(t, y[0]);
                out.switches.push((t, y[0], mode));
                continue;
            }
            // a step clipped to the sample lands on it (t + (next − t) may round off it)
            (t, y) = (if h == next - t { next } else { t + h }, y1);
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
    let tol = crate::common::tight(method);
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
    let sticks = |r: &Run| {
        r.switches
            .iter()
            .filter(|s| s.2 == SwitchingMode::Stuck)
            .count()
    };
    let reversals = |r: &Run| {
        r.switches
            .windows(2)
            .filter(|w| w[0].2 != SwitchingMode::Stuck && w[1].2 != SwitchingMode::Stuck)
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
        let run = |method| crate::common::states_from_rest(&m, method, 1e-12, t_end, 0.05);
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

/// A term's step limit holds its truncation to the absolute tolerance per time unit, what the
/// state's own rule aims at: the regularised friction's run follows the tolerance (60 time units
/// against DOP853 at 1e-13, within tol per time unit; without the limits the state's rule alone
/// steps across tanh's turn and misses by far more), and tightening the tolerance costs steps
/// only as Taylor's reach does: from 1e-12 to 1e-15 the order rises to 19 and a truncation
/// bound (δ/last)^{1/p} shrinks by at most 1000^{1/16} ≈ 1.5, so at most twice the steps.
#[test]
fn regularised_friction_follows_the_tolerance_at_bounded_cost() {
    let (p, f, t_end) = cases()[0];
    for vr in [1e-2, 1e-3] {
        let term = AnyTerm::new("stribeck", &[f.fc, f.fs, f.vst, 0.05, vr]).unwrap();
        let m = Model::study(&p).with_term(term).unwrap();
        let end = |method, tol| crate::common::end_state(&m, method, tol, [0.0, 0.0], t_end);
        let (reference, _) = end(Method::Dop853, 1e-13);
        let mut steps = vec![];
        for tol in [1e-8, 1e-12, 1e-15] {
            let (y, n) = end(Method::Taylor, tol);
            let error = (y[0] - reference[0]).abs().max((y[1] - reference[1]).abs());
            // below 1e-12 the reference's own error decides
            let allowed = tol.max(1e-12) * t_end;
            assert!(error < allowed, "v_r {vr}, tol {tol}: error {error:e}");
            steps.push(n);
        }
        assert!(
            steps[2] <= 2 * steps[1],
            "v_r {vr}: steps at 1e-8, 1e-12, 1e-15 {steps:?}"
        );
    }
}

/// The first τ > τ₀ at which |a(τ)| leaves the static band `band`: scanned every 1e-4 (a fifth
/// of the fastest period below, 2π/40 ≈ 0.157, over 300: no crossing and return is missed), then
/// bisected to rounding.
fn breakaway(a: impl Fn(f64) -> f64, t0: f64, band: f64) -> f64 {
    let out = |t: f64| a(t).abs() > band;
    let mut t = t0;
    while !out(t + 1e-4) {
        t += 1e-4;
        assert!(t < t0 + 100.0, "no breakaway");
    }
    let (mut lo, mut hi) = (t, t + 1e-4);
    while hi - lo > 1e-15 * hi.max(1.0) {
        let mid = 0.5 * (lo + hi);
        if out(mid) { hi = mid } else { lo = mid }
    }
    0.5 * (lo + hi)
}

/// While the motion sticks, the internal states whose rates do not vanish at rest move on by
/// their own equations with x held: the wave generator turns (θ_wg = Ω_in·τ), a washout's
/// filter relaxes (ξ = x + (ξ₀ − x)·e^{−ω_w τ}) and a multisine's phase turns (θ = Ω_m·τ). The
/// breakaway comes when the applied torque — the error's base excitation
/// A(kΩ_in cos φ − (kΩ_in)² sin φ), the washout's k_w(x − ξ) or the multisine's included — leaves the static band ±f_s: that instant is found here from those closed forms by
/// [`breakaway`], and the stepper's switch equals it to 1e-9 (its events are located to 1e-13;
/// the states' closed forms are met to 1e-10), by Taylor and by DOP853; a simulation's summary
/// counts that drifting rest as time stuck.
#[test]
fn the_internal_states_move_on_while_the_motion_sticks() {
    let p = Params {
        gamma: 1.0,
        delta: 1.0,
        omega: 0.5,
        ..Params::default()
    };
    let g = |x: f64| p.alpha * x.powi(3) - x * x + p.gamma * (x - p.eps);
    let (fc, fs) = (0.3, 0.9);
    let coulomb = AnyTerm::new("coulomb", &[fc, fs, 0.1, 0.0]).unwrap();
    let study = Model::study(&p).with_term(coulomb).unwrap();
    let x0 = study.stable_equilibrium(0.0).unwrap();
    let load = |t: f64| p.mu + p.delta * (p.omega * t).sin() - g(x0);
    // (term, z0, the state's closed form while stuck, the term's torque on it)
    let (ak, k, w_in, psi) = (5e-4, 2.0, 20.0, 0.4);
    let f = k * w_in;
    let kinematic = |t: f64| {
        let phi = f * t + psi;
        ak * f * phi.cos() - ak * f * f * phi.sin()
    };
    let (kw, ww, xi0) = (0.5, 0.3, x0 - 0.8);
    let xi = |t: f64| x0 + (xi0 - x0) * (-ww * t).exp();
    type Case<'a> = (AnyTerm, f64, &'a dyn Fn(f64) -> f64, &'a dyn Fn(f64) -> f64);
    // a multisine a·Σ_{k=1}^{8} cos(kΩ_m τ + φ_k), φ_k = −π(k − 1)k/8, whose top line (40) is
    // faster than the forcing's sampling alone would resolve
    let (am, wm) = (0.15, 5.0);
    let multisine = |t: f64| -crate::common::schroeder(am, wm, 8, t);
    let cases: [Case; 3] = [
        (
            AnyTerm::new("kinematic", &[ak, k, w_in, psi]).unwrap(),
            0.0,
            &|t| w_in * t,
            &kinematic,
        ),
        (
            AnyTerm::new("washout", &[kw, ww]).unwrap(),
            xi0,
            &xi,
            &|t| kw * (x0 - xi(t)),
        ),
        (
            AnyTerm::new("multisine", &[am, wm, 1.0, 8.0]).unwrap(),
            0.0,
            &|t| wm * t,
            &multisine,
        ),
    ];
    for (i, (term, z0, state, torque)) in cases.into_iter().enumerate() {
        let m = study.with_term(term).unwrap();
        let expected = breakaway(|t| load(t) - torque(t), 0.0, fs);
        if i == 0 {
            // a simulation's summary counts the drifting rest as time stuck (the washout starts
            // on its own rest, ξ = x, where it does not drift)
            let opts = SimOptions {
                t_end: expected,
                dt: expected,
                start: Start::Given { x0, v0: 0.0 },
                tol: Options::default(),
            };
            let summary = simulate_model(&m, &opts, |_, _| {}).unwrap();
            // the rest it starts in is its time stuck, and its one stick
            let s = summary.sticking.unwrap();
            assert!(
                (s.time_stuck - expected).abs() < 1e-9 && s.sticks == 1,
                "{s:?}: time stuck vs {expected}"
            );
        }
        // the pre-fix behaviour (the state held at z0) would break away elsewhere
        let held = breakaway(|t| load(t) - torque(0.0), 0.0, fs);
        assert!(
            (held - expected).abs() > 1e-3,
            "{}: {held} vs {expected}",
            term.kind()
        );
        for method in [Method::Taylor, Method::Dop853] {
            let t = first_stick_end(&m, [x0, 0.0, z0], state, method);
            eprintln!(
                "{} {method:?}: breakaway {t} − {expected} = {:e} (held state: {held})",
                term.kind(),
                t - expected
            );
            assert!(
                (t - expected).abs() < 1e-9,
                "{}: {t} vs {expected}",
                term.kind()
            );
        }
    }
}

/// The end of the stick `m` starts in at y0 (t = 0), by `method` at 1e-13: x held and the internal
/// state equal to its closed form `state` to 1e-10 at nine points of every step of the rest.
fn first_stick_end(m: &Model, y0: [f64; 3], state: &dyn Fn(f64) -> f64, method: Method) -> f64 {
    use hdgear::integrate::{DenseOutput, Stepper};
    use hdgear::model::switching::{Pieces, Switching};
    let tol = crate::common::tight(method);
    let pieces = Pieces::new(m).unwrap();
    let mut s = Switching::new(&pieces, 0.0, y0, tol).unwrap();
    assert_eq!(s.mode(), SwitchingMode::Stuck);
    while s.mode() == SwitchingMode::Stuck {
        s.step(100.0).unwrap();
        let d = s.dense();
        for i in 0..=8 {
            let t = d.t_start() + (d.t_end() - d.t_start()) * f64::from(i) / 8.0;
            let y = d.eval(t);
            assert_eq!([y[0], y[1]], [y0[0], 0.0], "x held at {t}");
            let err = (y[2] - state(t)).abs();
            assert!(err < 1e-10 * state(t).abs().max(1.0), "{} at {t}", y[2]);
        }
    }
    s.last_switch().expect("the stick ends on a switch").t
}
