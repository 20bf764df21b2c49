//! Terms with an internal state (LuGre friction, Bouc–Wen and Dahl hysteresis) in the drive's
//! model: against an independent event-driven integration written here from the equations (classical
//! RK4 with the signs of x' and z fixed on each piece, restarts at every sign change located by
//! bisection on a single RK4 step), the derived Jacobian against finite differences, LuGre's
//! presliding stiffness against the linear response it implies, Bouc–Wen's energy balance and
//! rate independence, Noël & Schoukens' Bouc–Wen benchmark under a multisine, and Dahl's law
//! against its closed-form branch and the two laws it equals at exponent 1.
//!
//! **Why one file.** The tests of one capability, the terms with memory (LuGre, Bouc–Wen, Dahl), in
//! one module of the test binary.

use hdgear::Params;
use hdgear::integrate::{DenseOutput, Method, Options, Stepper, System};
use hdgear::model::Model;
use hdgear::model::switching::{Pieces, Switching};
use hdgear::model::terms::AnyTerm;
use hdgear::simulate::{SimOptions, Start, simulate_model};

/// The stateful law, written out from its equations (not from hdgear's terms).
#[derive(Clone, Copy, Debug)]
enum Law {
    /// f_c, f_s, v_st, σ₀, σ₁, σ₂.
    LuGre([f64; 6]),
    /// k_h, ρ, A, β, γ_h, n.
    BoucWen([f64; 6]),
    /// σ, T_c, n.
    Dahl([f64; 3]),
}

impl Law {
    fn term(self) -> AnyTerm {
        match self {
            Law::LuGre(v) => AnyTerm::new("lugre", &v).unwrap(),
            Law::BoucWen(v) => AnyTerm::new("boucwen", &v).unwrap(),
            Law::Dahl(v) => AnyTerm::new("dahl", &v).unwrap(),
        }
    }
    /// (torque, z') at (x, v, z) on the piece sgn x' = sv, sgn z = sz.
    fn eval(self, x: f64, v: f64, z: f64, sv: f64, sz: f64) -> (f64, f64) {
        match self {
            Law::LuGre([fc, fs, vst, s0, s1, s2]) => {
                let g = fc + (fs - fc) * (-(v / vst) * (v / vst)).exp();
                let rate = v - s0 * (sv * v) * z / g;
                (s0 * z + s1 * rate + s2 * v, rate)
            }
            Law::BoucWen([kh, rho, a, beta, gamma, n]) => {
                let abs_z = sz * z;
                let rate =
                    a * v - beta * (sv * v) * abs_z.powf(n - 1.0) * z - gamma * v * abs_z.powf(n);
                (kh * (rho * x + (1.0 - rho) * z), rate)
            }
            Law::Dahl([sigma, tc, n]) => (z, sigma * v * (1.0 - sv * z / tc).powf(n)),
        }
    }
    fn switches_at_zero_state(self) -> bool {
        matches!(self, Law::BoucWen(_))
    }
}

/// What the stateful law is part of: the study's drive, or a unit mass and damper with no
/// stiffness of its own under a given load u(t).
#[derive(Clone, Copy)]
enum Drive<'a> {
    Study(Params),
    Loaded(&'a dyn Fn(f64) -> f64),
}

/// x'' = μ + δ sin ωt − x' − (αx³ − x² + γ(x − ε)) − T(x, x', z) (the study's drive) or
/// x'' = u(t) − x' − T(x, x', z) (a loaded one), z' = r(x, x', z).
#[derive(Clone, Copy)]
struct Reference<'a> {
    drive: Drive<'a>,
    law: Law,
    h: f64,
}

impl Reference<'_> {
    fn rhs(&self, t: f64, y: [f64; 3], sv: f64, sz: f64) -> [f64; 3] {
        let [x, v, z] = y;
        let (torque, rate) = self.law.eval(x, v, z, sv, sz);
        let rest = match self.drive {
            Drive::Study(p) => {
                let stiffness = p.alpha * x * x * x - x * x + p.gamma * (x - p.eps);
                p.mu + p.delta * (p.omega * t).sin() - stiffness
            }
            Drive::Loaded(u) => u(t),
        };
        [v, rest - v - torque, rate]
    }
    fn rk4(&self, t: f64, y: [f64; 3], h: f64, sv: f64, sz: f64) -> [f64; 3] {
        crate::common::rk4_step(|t, y| self.rhs(t, y, sv, sz), t, y, h)
    }
    /// The sign a component leaves 0 with: x' along the acceleration at rest, z along z'
    /// (whose |z| parts vanish at z = 0), or where z' = 0 too (x' = 0 with it, as at a start
    /// from rest) along x', whose sign on the piece is `sv`: a Bouc–Wen z' is A·x' at z = 0.
    fn leaving(&self, t: f64, y: [f64; 3], i: usize, sv: f64) -> f64 {
        match self.rhs(t, y, sv, 1.0)[i] {
            0.0 if i == 2 => sv,
            r => r.signum(),
        }
    }
    /// Samples every `dt` from (0, y0) to `t_end`.
    fn run(&self, y0: [f64; 3], t_end: f64, dt: f64) -> Vec<[f64; 3]> {
        let sv = if y0[1] != 0.0 {
            y0[1].signum()
        } else {
            self.leaving(0.0, y0, 1, 1.0)
        };
        let sz = if y0[2] != 0.0 {
            y0[2].signum()
        } else {
            self.leaving(0.0, y0, 2, sv)
        };
        self.run_on(y0, t_end, dt, (sv, sz))
    }
    /// [`Reference::run`] from the piece of the given signs (sgn x', sgn z).
    fn run_on(&self, y0: [f64; 3], t_end: f64, dt: f64, (sv, sz): (f64, f64)) -> Vec<[f64; 3]> {
        let (mut t, mut y, mut sv, mut sz) = (0.0, y0, sv, sz);
        let mut out = vec![y];
        let mut k = 1;
        while t < t_end {
            let next = (k as f64 * dt).min(t_end);
            let h = self.h.min(next - t);
            let y1 = self.rk4(t, y, h, sv, sz);
            // the first sign change on the step: x' (i = 1), or z (i = 2) where it switches
            let watched = [(1, sv), (2, sz)];
            let crossed = watched
                .into_iter()
                .filter(|&(i, s)| (i == 1 || self.law.switches_at_zero_state()) && s * y1[i] < 0.0)
                .map(|(i, s)| {
                    let before = |tau| s * self.rk4(t, y, tau, sv, sz)[i] > 0.0;
                    (i, crate::common::crossing(t, h, before))
                })
                .min_by(|a, b| a.1.total_cmp(&b.1));
            if let Some((i, tau)) = crossed {
                y = self.rk4(t, y, tau, sv, sz);
                y[i] = 0.0;
                t += tau;
                if i == 1 {
                    sv = self.leaving(t, y, 1, sv);
                } else {
                    sz = self.leaving(t, y, 2, sv);
                }
                continue;
            }
            // a step clipped to the sample lands on it (t + (next − t) may round off it)
            (t, y) = (if h == next - t { next } else { t + h }, y1);
            if t == next {
                out.push(y);
                k += 1;
            }
        }
        out
    }
}

fn model(p: &Params, law: Law) -> Model {
    Model::study(p).with_term(law.term()).unwrap()
}

fn hdgear_run(p: &Params, law: Law, method: Method, t_end: f64, dt: f64) -> Vec<[f64; 3]> {
    hdgear_run_from(Start::Rest, p, law, method, t_end, dt)
}

/// [`hdgear_run`] from the start `start`.
fn hdgear_run_from(
    start: Start,
    p: &Params,
    law: Law,
    method: Method,
    t_end: f64,
    dt: f64,
) -> Vec<[f64; 3]> {
    let opts = SimOptions {
        t_end,
        dt,
        start,
        tol: crate::common::tight(method),
    };
    let mut out = vec![];
    simulate_model(&model(p, law), &opts, |_, y| out.push([y[0], y[1], y[2]])).unwrap();
    out
}

fn worst(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .flat_map(|(a, b)| (0..3).map(move |i| (a[i] - b[i]).abs()))
        .fold(0.0, f64::max)
}

/// LuGre in stick-slip (the motion reverses and rests in presliding), Bouc–Wen with n = 1 and
/// n = 2 and Dahl with n = 3 through many loops.
fn cases() -> [(Params, Law, f64); 4] {
    let p = Params::default();
    let slow = Params {
        delta: 1.0,
        omega: 0.5,
        ..p
    };
    let loops = Params {
        delta: 3.0,
        omega: 0.7,
        gamma: 1.0,
        ..p
    };
    [
        (slow, Law::LuGre([0.3, 0.4, 0.1, 20.0, 2.0, 0.1]), 40.0),
        (loops, Law::BoucWen([0.8, 0.2, 1.0, 0.6, 0.3, 1.0]), 40.0),
        (loops, Law::BoucWen([0.8, 0.0, 1.5, 0.5, -0.2, 2.0]), 40.0),
        (loops, Law::Dahl([2.0, 0.5, 3.0]), 40.0),
    ]
}

#[test]
fn stateful_terms_match_an_independent_event_driven_integration() {
    for (p, law, t_end) in cases() {
        let dt = 0.05;
        let reference = |h| {
            Reference {
                drive: Drive::Study(p),
                law,
                h,
            }
            .run([0.0; 3], t_end, dt)
        };
        let (r, r2) = (reference(2e-4), reference(1e-4));
        // RK4's error is of order h⁴: the finer run's is |r − r2|/15 (Richardson)
        let own = worst(&r, &r2) / 15.0;
        assert!(own < 1e-10, "{law:?}: reference not converged: {own:e}");
        for method in Method::ALL {
            let e = worst(&hdgear_run(&p, law, method, t_end, dt), &r2);
            eprintln!("{law:?} {method:?}: max |Δ| {e:.2e}");
            assert!(e < 1e-9, "{law:?} {method:?}: differs by {e:e}");
        }
    }
}

/// Each case crosses what makes it non-smooth: LuGre's x' = 0 several times, Bouc–Wen's z = 0
/// and x' = 0 in every loop (else the test above would not test the cuts).
#[test]
fn the_cases_cross_their_switches() {
    for (p, law, t_end) in cases() {
        let m = model(&p, law);
        let pieces = Pieces::new(&m).unwrap();
        let mut s = Switching::<3>::new(&pieces, 0.0, [0.0; 3], Options::default()).unwrap();
        let (mut v_changes, mut z_changes) = (0, 0);
        let mut last = [0.0; 3];
        while s.t() < t_end {
            s.step(t_end).unwrap();
            let y = s.dense().end_state();
            v_changes += usize::from(y[1] == 0.0 && last[1] != 0.0);
            z_changes += usize::from(y[2] == 0.0 && last[2] != 0.0);
            last = y;
        }
        assert!(v_changes >= 4, "{law:?}: x' through 0 {v_changes} times");
        if law.switches_at_zero_state() {
            assert!(z_changes >= 4, "{law:?}: z through 0 {z_changes} times");
        }
    }
}

/// The Jacobian derived from the terms equals a central finite difference of the right-hand
/// side, for LuGre and Bouc–Wen alone and together and for Dahl, at states away from the switches.
#[test]
fn stateful_jacobian_matches_finite_differences() {
    let p = Params::default();
    let lugre = Law::LuGre([0.3, 0.4, 0.1, 20.0, 2.0, 0.1]).term();
    let bw = Law::BoucWen([0.8, 0.2, 1.0, 0.6, 0.3, 2.0]).term();
    let dahl = Law::Dahl([2.0, 0.5, 3.0]).term();
    let one = |term| Model::study(&p).with_term(term).unwrap();
    let both = one(lugre).with_term(bw).unwrap();
    let check = |m: &Model, y: &[f64]| {
        fn fd<const N: usize>(m: &Model, y: [f64; N]) -> f64 {
            let j = System::<N>::jacobian(m, 1.3, &y).unwrap();
            let mut worst: f64 = 0.0;
            for c in 0..N {
                let h = 1e-6 * y[c].abs().max(1.0);
                let (mut a, mut b) = (y, y);
                a[c] += h;
                b[c] -= h;
                let (fa, fb) = (m.rhs(1.3, &a), m.rhs(1.3, &b));
                for r in 0..N {
                    let d = (fa[r] - fb[r]) / (2.0 * h);
                    worst = worst.max((d - j[r][c]).abs() / d.abs().max(1.0));
                }
            }
            worst
        }
        match y.len() {
            3 => fd(m, [y[0], y[1], y[2]]),
            _ => fd(m, [y[0], y[1], y[2], y[3]]),
        }
    };
    for y in [[0.4, 0.3, 0.01], [-0.2, -0.8, -0.02], [0.9, 0.05, 0.015]] {
        assert!(check(&one(lugre), &y) < 1e-7, "lugre at {y:?}");
        let yz = [y[0], y[1], 0.7 * y[0] + 0.1];
        assert!(check(&one(bw), &yz) < 1e-7, "boucwen at {yz:?}");
        let all = [y[0], y[1], y[2], 0.7 * y[0] + 0.1];
        assert!(check(&both, &all) < 1e-7, "both at {all:?}");
        let yd = [y[0], y[1], 0.2 * y[0] + 0.1];
        assert!(check(&one(dahl), &yd) < 1e-7, "dahl at {yd:?}");
    }
}

/// LuGre at rest inside the static band: a small forcing meets the presliding stiffness σ₀ and
/// bristle damping σ₁ in parallel with the drive's own, so the response is that of the linear
/// oscillator x'' + (1 + σ₁ + σ₂)x' + (g'(x_eq) + σ₀)x = δ sin ωτ (within 1 %: the |x'|·s part
/// is of second order in the amplitude).
#[test]
fn lugre_presliding_meets_the_bristle_stiffness() {
    let (s0, s1, s2) = (50.0, 3.0, 0.2);
    let p = Params {
        delta: 1e-3,
        omega: 2.0,
        ..Params::default()
    };
    let m = model(&p, Law::LuGre([0.3, 0.5, 0.1, s0, s1, s2]));
    let x_eq = m.stable_equilibrium(0.0).unwrap();
    let slope = 3.0 * p.alpha * x_eq * x_eq - 2.0 * x_eq + p.gamma;
    let (k, c, w) = (slope + s0, 1.0 + s1 + s2, p.omega);
    let predicted = p.delta / ((k - w * w).powi(2) + (c * w).powi(2)).sqrt();
    let opts = SimOptions {
        t_end: 60.0,
        dt: 0.001,
        start: Start::Equilibrium,
        tol: Options::default(),
    };
    // the amplitude over the last forcing period (the transient decays as e^{−cτ/2})
    let period = std::f64::consts::TAU / w;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    simulate_model(&m, &opts, |t, y| {
        if t > 60.0 - period {
            (lo, hi) = (lo.min(y[0]), hi.max(y[0]));
        }
    })
    .unwrap();
    let amplitude = (hi - lo) / 2.0;
    let ratio = amplitude / predicted;
    eprintln!("LuGre presliding: amplitude {amplitude:.4e}, linear prediction {predicted:.4e}");
    assert!((ratio - 1.0).abs() < 0.01, "ratio {ratio}");
    // without the bristles' stiffness the same forcing moves x far more: σ₀ is what is measured
    let soft = predicted * ((k - w * w).powi(2) + (c * w).powi(2)).sqrt()
        / ((slope - w * w).powi(2) + (c * w).powi(2)).sqrt();
    assert!(soft > 5.0 * amplitude);
}

/// Gauss–Legendre nodes and weights on [0, 1] (5 points: exact for degree 9).
const GAUSS: [(f64, f64); 5] = [
    (0.046_910_077_030_668, 0.118_463_442_528_095),
    (0.230_765_344_947_158, 0.239_314_335_249_683),
    (0.5, 0.284_444_444_444_444),
    (0.769_234_655_052_842, 0.239_314_335_249_683),
    (0.953_089_922_969_332, 0.118_463_442_528_095),
];

/// Bouc–Wen's energy balance over a forcing period: the work of the forcing equals the viscous
/// dissipation, the hysteretic work ∮ k_h(1 − ρ)z dx and the change of the stored energy
/// ½x'² + G(x) + k_hρx²/2 (G the stiffness's potential), each integral by Gauss–Legendre on every
/// step of the dense output; and the hysteretic work of a steady loop is a dissipation (> 0).
#[test]
fn bouc_wen_energy_balance_holds_per_period() {
    let (p, law, _) = cases()[1];
    let Law::BoucWen([kh, rho, ..]) = law else {
        unreachable!()
    };
    let m = model(&p, law);
    let pieces = Pieces::new(&m).unwrap();
    let tol = crate::common::tight(Method::Taylor);
    let period = std::f64::consts::TAU / p.omega;
    let stored = |y: [f64; 3]| {
        let x = y[0];
        let g = p.alpha * x.powi(4) / 4.0 - x.powi(3) / 3.0 + p.gamma * (x * x / 2.0 - p.eps * x);
        0.5 * y[1] * y[1] + g + kh * rho * x * x / 2.0
    };
    for n in 3..6 {
        let (t0, t1) = (n as f64 * period, (n + 1) as f64 * period);
        let mut s = Switching::<3>::new(&pieces, 0.0, [0.0; 3], tol).unwrap();
        while s.t() < t0 {
            s.step(t0).unwrap();
        }
        let e0 = stored(*s.y());
        let (mut work, mut viscous, mut hysteretic) = (0.0, 0.0, 0.0);
        while s.t() < t1 {
            s.step(t1).unwrap();
            let d = s.dense();
            let (a, b) = (d.t_start(), d.t_end());
            for (u, w) in GAUSS {
                let t = a + u * (b - a);
                let [_, v, z] = d.eval(t);
                let w = w * (b - a);
                work += w * v * (p.mu + p.delta * (p.omega * t).sin());
                viscous += w * v * v;
                hysteretic += w * kh * (1.0 - rho) * z * v;
            }
        }
        let change = stored(*s.y()) - e0;
        let imbalance = work - viscous - hysteretic - change;
        eprintln!(
            "period {n}: work {work:.10}, viscous {viscous:.10}, hysteretic {hysteretic:.10}, \
             stored change {change:.3e}, imbalance {imbalance:.2e}"
        );
        assert!(
            imbalance.abs() < 1e-8 * work.abs(),
            "imbalance {imbalance:e}"
        );
        assert!(hysteretic > 0.0);
    }
}

/// Bouc–Wen's loop does not depend on the rate: driven quasi-statically (ω = 1e-3 and 1e-4),
/// its hysteretic work per cycle ∮ k_h(1 − ρ)z dx (the loop's area, by the trapezoidal rule on
/// 20,000 samples a period) changes by less than 0.1 %. (The x–forcing loop of the whole drive
/// does change: its viscous part is proportional to ω.)
#[test]
fn bouc_wen_loops_are_rate_independent() {
    let law = Law::BoucWen([0.8, 0.0, 1.0, 0.6, 0.3, 1.0]);
    let area = |omega: f64| {
        let p = Params {
            delta: 3.0,
            omega,
            gamma: 1.0,
            ..Params::default()
        };
        let period = std::f64::consts::TAU / omega;
        let opts = SimOptions {
            t_end: 2.0 * period,
            dt: period / 20_000.0,
            start: Start::Rest,
            tol: Options::default(),
        };
        let (mut area, mut last) = (0.0, None::<[f64; 3]>);
        simulate_model(&model(&p, law), &opts, |t, y| {
            if t > period * (1.0 - 1e-12) {
                if let Some(l) = last {
                    area += 0.8 * 0.5 * (l[2] + y[2]) * (y[0] - l[0]);
                }
                last = Some([y[0], y[1], y[2]]);
            }
        })
        .unwrap();
        area
    };
    let (a, b) = (area(1e-3), area(1e-4));
    eprintln!("Bouc–Wen hysteretic work per cycle at ω = 1e-3: {a:.8}, at 1e-4: {b:.8}");
    assert!(a > 0.01, "no loop: {a}");
    assert!((a - b).abs() < 1e-3 * b, "{a} vs {b}");
}

/// With its stiffness at 0 a Bouc–Wen term moves nothing: x and x' are the study model's.
#[test]
fn a_zero_hysteresis_term_leaves_the_study_model() {
    let (p, _, t_end) = cases()[1];
    let law = Law::BoucWen([0.0, 0.2, 1.0, 0.6, 0.3, 1.0]);
    let with = hdgear_run(&p, law, Method::Taylor, t_end, 0.05);
    let opts = SimOptions {
        t_end,
        dt: 0.05,
        start: Start::Rest,
        tol: crate::common::tight(Method::Taylor),
    };
    let mut without = vec![];
    simulate_model(&Model::study(&p), &opts, |_, y| without.push([y[0], y[1]])).unwrap();
    let e = with
        .iter()
        .zip(&without)
        .map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs()))
        .fold(0.0, f64::max);
    assert!(e < 1e-10, "{e:e}");
}

/// Random models with memory (LuGre, Bouc–Wen with n from 1 to 4, or both; Dahl with n from 1 to
/// 4, alone or with LuGre) at random parameters and forcings: Taylor's method and DOP853, each
/// piece by piece, agree to 1e-8 at τ = 10, 20 and 30 (both at 1e-12; the seed is fixed so
/// failures repeat). The states are compared where a step ends; the interpolants between step
/// ends, which DOP853 holds to the equation on such models, are compared in `dop853_terms.rs`.
#[test]
fn random_models_with_memory_agree_across_methods() {
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut u = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut between = |lo: f64, hi: f64| lo + (hi - lo) * u();
    for case in 0..16 {
        let p = Params {
            gamma: between(0.1, 2.0),
            delta: between(0.5, 4.0),
            omega: between(0.1, 1.5),
            ..Params::default()
        };
        let fc = between(0.05, 0.3);
        let lugre = Law::LuGre([
            fc,
            fc + between(0.0, 0.2),
            between(0.05, 0.5),
            between(5.0, 40.0),
            between(0.0, 3.0),
            between(0.0, 0.5),
        ])
        .term();
        let (kh, rho, ah, beta, gammah) = (
            between(0.1, 1.0),
            between(0.0, 1.0),
            between(0.5, 2.0),
            between(0.1, 1.0),
            between(-0.3, 0.5),
        );
        let n = (1 + case % 4) as f64;
        // β + γ_h ≥ 0 where n ≥ 2 (below it z blows up within a finite twist: refused)
        let gammah = if n >= 2.0 { gammah.max(-beta) } else { gammah };
        let bw = Law::BoucWen([kh, rho, ah, beta, gammah, n]).term();
        let m = match case % 3 {
            // the last four: Dahl, alone or with LuGre (drawn after the others, so that the
            // first twelve cases keep their values)
            _ if case >= 12 => {
                let dahl =
                    Law::Dahl([between(0.5, 5.0), between(0.05, 0.5), (1 + case % 4) as f64])
                        .term();
                let m = Model::study(&p).with_term(dahl).unwrap();
                if case % 2 == 0 {
                    m
                } else {
                    m.with_term(lugre).unwrap()
                }
            }
            0 => Model::study(&p).with_term(lugre).unwrap(),
            1 => Model::study(&p).with_term(bw).unwrap(),
            _ => Model::study(&p)
                .with_term(lugre)
                .unwrap()
                .with_term(bw)
                .unwrap(),
        };
        for t_end in [10.0, 20.0, 30.0] {
            let worst = methods_differ(&m, t_end);
            assert!(
                worst < 1e-8,
                "case {case} {m:?}: methods differ by {worst:e}"
            );
        }
    }
}

/// The largest difference of the states at `t_end` between Taylor's method and DOP853, both at
/// 1e-12, each piece by piece.
fn methods_differ(m: &Model, t_end: f64) -> f64 {
    let run = |method| crate::common::states_from_rest(m, method, 1e-12, t_end, t_end).concat();
    let (a, b) = (run(Method::Taylor), run(Method::Dop853));
    a.iter()
        .zip(&b)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
}

/// LuGre's steady sliding: at a constant speed v the bristle state, integrated from rest with
/// the term's own rate (RK4 in the test, over 60 of its time constants g(v)/(σ₀|v|)), settles
/// where the term's torque is the Stribeck curve g(v)·sgn v + σ₂v written out here, to 1e-9.
#[test]
fn lugre_steady_sliding_friction_is_the_stribeck_curve() {
    let (fc, fs, vst, s0, s1, s2) = (0.3, 0.5, 0.1, 50.0, 3.0, 0.2);
    let t = AnyTerm::new("lugre", &[fc, fs, vst, s0, s1, s2]).unwrap();
    for v in [1e-4, 1e-3, 0.05, 0.1, 0.3, 2.0, -1e-3, -0.1, -2.0] {
        let g = fc + (fs - fc) * (-(v / vst) * (v / vst)).exp();
        let tau = g / (s0 * f64::abs(v));
        let n = 6000;
        let h = 60.0 * tau / n as f64;
        let mut s = 0.0;
        for _ in 0..n {
            let r = |s: f64| t.rate(0.0, v, s);
            let k1 = r(s);
            let k2 = r(s + 0.5 * h * k1);
            let k3 = r(s + 0.5 * h * k2);
            let k4 = r(s + h * k3);
            s += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        }
        let steady = g * v.signum() + s2 * v;
        let got = t.torque(0.0, v, s);
        assert!(
            ((got - steady) / steady).abs() < 1e-9,
            "v = {v}: {got} against {steady}"
        );
    }
}

/// Noël & Schoukens' Bouc–Wen benchmark (Workshop on Nonlinear System Identification
/// Benchmarks, 2016): m·ÿ + c·ẏ + k·y + z = u(t), ż = α·ẏ − β·(γ·|ẏ|·|z|^{ν−1}·z + δ·ẏ·|z|^ν),
/// m = 2 kg, c = 10 N s/m, k = 5e4 N/m, α = 5e4 N/m, β = 1e3 m⁻¹, γ = 0.8, δ = −1.1, ν = 1.
/// On the time scale m/c (a fifth of a second) and the length 1 mm it is x'' + x' + 1000·x + 1000·z_d =
/// 20·u/N with z_d' = x' − 0.8·|x'|·z_d + 1.1·x'·|z_d|: a model with no stiffness of its own
/// ([`Model::damped`]) and the Bouc–Wen term k_h = 2000, ρ = 1/2, A = 1, β = 0.8, γ_h = −1.1,
/// n = 1. The benchmark's input is a multisine in 5–150 Hz of 50 N RMS; here its lines are
/// 5 Hz apart (k = 1 … 30 of Ω₀ = 2π·5 Hz·m/c = 2π), 1000/√15 each in the reduced units. Over
/// two of its periods, from rest, hdgear's Taylor and DOP853 (at 1e-13, piece by piece) agree
/// with the event-driven RK4 of this file (step 2e-5, its own error below 1e-10 by Richardson against 4e-5), whose load is
/// written here from Schroeder's formula, to 1e-8 of each component's largest value.
#[test]
fn the_bouc_wen_benchmark_under_a_multisine_matches_an_independent_integration() {
    let (a, w0, lines) = (1000.0 / 15f64.sqrt(), std::f64::consts::TAU, 30);
    let load = move |t: f64| crate::common::schroeder(a, w0, lines, t);
    let law = [2000.0, 0.5, 1.0, 0.8, -1.1, 1.0];
    let (t_end, dt) = (2.0, 0.01);
    let reference = |h| {
        Reference {
            drive: Drive::Loaded(&load),
            law: Law::BoucWen(law),
            h,
        }
        .run([0.0; 3], t_end, dt)
    };
    let (coarse, expected) = (reference(4e-5), reference(2e-5));
    let m = Model::damped(0.0, 0.0, 1.0)
        .with_term(AnyTerm::new("boucwen", &law).unwrap())
        .unwrap()
        .with_term(AnyTerm::new("multisine", &[a, w0, 1.0, f64::from(lines)]).unwrap())
        .unwrap();
    let scale: [f64; 3] =
        std::array::from_fn(|i| expected.iter().fold(0.0, |s: f64, y| s.max(y[i].abs())));
    // RK4's error is of order h⁴: the finer run's is |coarse − fine|/15 (Richardson)
    let own = (0..3).fold(0.0_f64, |w, i| {
        let d = coarse
            .iter()
            .zip(&expected)
            .fold(0.0_f64, |d, (c, e)| d.max((c[i] - e[i]).abs()));
        w.max(d / 15.0 / scale[i])
    });
    assert!(own < 1e-10, "reference not converged: {own:e}");
    for method in [Method::Taylor, Method::Dop853] {
        let tol = crate::common::tight(method);
        let opts = SimOptions {
            t_end,
            dt,
            start: Start::Given { x0: 0.0, v0: 0.0 },
            tol,
        };
        let mut got = Vec::new();
        simulate_model(&m, &opts, |_, y| got.push([y[0], y[1], y[2]])).unwrap();
        assert_eq!(got.len(), expected.len());
        let worst = (0..3).fold(0.0_f64, |w, i| {
            let d = got
                .iter()
                .zip(&expected)
                .fold(0.0_f64, |d, (g, e)| d.max((g[i] - e[i]).abs()));
            w.max(d / scale[i])
        });
        eprintln!("benchmark {method:?}: worst relative difference {worst:e} (scales {scale:?})");
        assert!(worst < 1e-8, "{method:?}: {worst:e}");
    }
}

/// Dahl's law with exponent 1 is two other terms in disguise: Bouc–Wen with A = σ, β = σ/T_c,
/// γ_h = 0, k_h = 1, ρ = 0 (z = T_h), and LuGre with f_s = f_c = T_c and σ₀ = σ, σ₁ = σ₂ = 0
/// (s = T_h/σ). The three runs, each through its own recurrences, agree to 1e-9.
#[test]
fn dahl_with_exponent_one_is_bouc_wen_and_lugre() {
    let (p, _, t_end) = cases()[3];
    let (sigma, tc) = (2.0, 0.5);
    let dahl = hdgear_run(&p, Law::Dahl([sigma, tc, 1.0]), Method::Taylor, t_end, 0.05);
    let bw = Law::BoucWen([1.0, 0.0, sigma, sigma / tc, 0.0, 1.0]);
    let lugre = Law::LuGre([tc, tc, 0.1, sigma, 0.0, 0.0]);
    let scaled = |run: Vec<[f64; 3]>, k: f64| -> Vec<[f64; 3]> {
        run.into_iter().map(|[x, v, z]| [x, v, k * z]).collect()
    };
    for (name, other) in [
        ("boucwen", hdgear_run(&p, bw, Method::Taylor, t_end, 0.05)),
        (
            "lugre",
            scaled(hdgear_run(&p, lugre, Method::Taylor, t_end, 0.05), sigma),
        ),
    ] {
        let e = worst(&dahl, &other);
        assert!(e < 1e-9, "{name}: differs by {e:e}");
    }
    let swing = dahl.iter().map(|y| y[2].abs()).fold(0.0, f64::max);
    assert!(
        swing > 0.5 * tc,
        "the hysteresis torque barely moves: {swing}"
    );
}

/// On the virgin branch (from T_h = 0 at the start, x' ≥ 0 until the first reversal) Dahl's law
/// integrates in closed form: T_h = T_c·(1 − e^{−σΔx/T_c}) for n = 1, and
/// (1 − T_h/T_c)^{1−n} = 1 + (n − 1)·σΔx/T_c for n > 1 (Δx the twist since the start). Every
/// sample of that branch satisfies it to 1e-9, for n = 1 … 4: the torque depends on the path of
/// x alone, not on its speed.
#[test]
fn dahl_virgin_branch_is_the_closed_form() {
    let (p, _, _) = cases()[3];
    let (sigma, tc) = (2.0, 0.5);
    for n in 1..=4 {
        let run = hdgear_run(
            &p,
            Law::Dahl([sigma, tc, f64::from(n)]),
            Method::Taylor,
            4.0,
            1e-3,
        );
        let x0 = run[0][0];
        let branch: Vec<&[f64; 3]> = run.iter().take_while(|y| y[1] >= 0.0).collect();
        let closed = |dx: f64| match n {
            1 => tc * (1.0 - (-sigma * dx / tc).exp()),
            _ => {
                let m = f64::from(n - 1);
                tc * (1.0 - (1.0 + m * sigma * dx / tc).powf(-1.0 / m))
            }
        };
        let e = branch
            .iter()
            .map(|y| (y[2] - closed(y[0] - x0)).abs())
            .fold(0.0, f64::max);
        let reached = branch.last().map_or(0.0, |y| y[2]);
        eprintln!(
            "n = {n}: {} samples, T_h up to {reached:.4}, worst {e:.1e}",
            branch.len()
        );
        assert!(
            reached > 0.3 * tc,
            "n = {n}: the branch is too short ({reached})"
        );
        assert!(e < 1e-9, "n = {n}: off the closed form by {e:e}");
    }
}

/// A run from the fast subsystem's equilibrium (`simulate`'s default start), where the applied
/// torque A vanishes to its rounding, leaves rest as the rising load pushes (x' > 0): on the
/// other piece Dahl's base 1 − sgn(x')·T_h/T_c would grow instead of shrink, and with n = 3 T_h
/// would run past T_c and blow up within a unit of time. Both methods keep |T_h| < T_c over many
/// loops and agree to 1e-8.
#[test]
fn an_equilibrium_start_leaves_rest_as_the_load_pushes() {
    let (p, law, t_end) = cases()[3];
    let Law::Dahl([_, tc, _]) = law else {
        unreachable!()
    };
    let run = |method| hdgear_run_from(Start::Equilibrium, &p, law, method, t_end, 0.05);
    let (taylor, dop853) = (run(Method::Taylor), run(Method::Dop853));
    assert!(taylor[1][1] > 0.0, "left rest backwards: {:?}", taylor[1]);
    let peak = taylor.iter().map(|y| y[2].abs()).fold(0.0, f64::max);
    assert!(
        peak < tc && peak > 0.5 * tc,
        "|T_h| up to {peak} (T_c = {tc})"
    );
    let e = worst(&taylor, &dop853);
    assert!(e < 1e-8, "methods differ by {e:e}");
}

/// Bouc–Wen from the equilibrium start against the independent integration started there on
/// the piece the rising load drives (x' > 0, and z > 0, which leaves 0 as A·x'): to 1e-9. Its
/// x'(0) = 0 with A(0) a rounding error from 0, so the reference is told the piece rather than
/// reading it off A's sign.
#[test]
fn an_equilibrium_start_matches_the_independent_integration() {
    let (p, law, t_end) = cases()[1];
    let ours = hdgear_run_from(Start::Equilibrium, &p, law, Method::Taylor, t_end, 0.05);
    let reference = Reference {
        drive: Drive::Study(p),
        law,
        h: 1e-4,
    }
    .run_on(ours[0], t_end, 0.05, (1.0, 1.0));
    let e = worst(&ours, &reference);
    assert!(e < 1e-9, "differs by {e:e}");
}
