//! Helpers shared by the test modules.

use std::path::{Path, PathBuf};

pub mod cusp_sets;

/// A file of the vendored reference data (`tests/data/`, described in its README).
pub fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// The cases of a reference file (`tests/data/NAME`, a JSON document with a `cases` list), each
/// with its id, its parameter set (`params`) and the whole case.
pub fn reference_cases(name: &str) -> Vec<(String, hdgear::Params, serde_json::Value)> {
    let text = std::fs::read_to_string(data(name)).unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["cases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let q = &c["params"];
            let f = |k: &str| q[k].as_f64().unwrap();
            let p = hdgear::Params {
                alpha: f("alpha"),
                gamma: f("gamma"),
                eps: f("eps"),
                mu: f("mu"),
                delta: f("delta"),
                omega: f("omega"),
            };
            (c["id"].as_str().unwrap().to_string(), p, c.clone())
        })
        .collect()
}

/// The reference trajectories of the study's four γ (`tests/data/paper_trajectories.csv`):
/// rows (gamma, x0, v0, t, x, xdot).
pub fn reference_rows() -> Vec<[f64; 6]> {
    let path = data("paper_trajectories.csv");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap().trim(), "gamma,x0,v0,t,x,xdot");
    lines
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|s| s.trim().parse().unwrap()).collect();
            [v[0], v[1], v[2], v[3], v[4], v[5]]
        })
        .collect()
}

/// Files in a directory (to check that nothing, not even a temporary, was left behind).
pub fn files_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The set with one fold inside a ∈ [−1, 1]: a branch spans the whole range.
pub const SINGLE_FOLD: hdgear::Params = hdgear::Params {
    alpha: 0.5435,
    gamma: 0.2945,
    eps: 0.2397,
    mu: -0.2234,
    delta: 0.09737,
    omega: 0.003897,
};

/// The one equilibrium at a of a monotone g (γ > 1/(3α)), by bisection on [−100, 100]: an
/// independent solve of g(x) = μ + δa for the tests.
pub fn monotone_equilibrium(p: &hdgear::Params, a: f64) -> f64 {
    let f = p.mu + p.delta * a;
    let (mut lo, mut hi) = (-100.0, 100.0);
    for _ in 0..200 {
        let m = 0.5 * (lo + hi);
        if p.g(m) < f {
            lo = m;
        } else {
            hi = m;
        }
    }
    0.5 * (lo + hi)
}

/// One classical RK4 step of y' = f(t, y) from (t, y) with step h: the independent integrator
/// the tests compare hdgear against (error O(h⁴) over a run). `f` is called at t, t + h/2
/// (twice) and t + h, in that order.
pub fn rk4_step<const N: usize>(
    mut f: impl FnMut(f64, [f64; N]) -> [f64; N],
    t: f64,
    y: [f64; N],
    h: f64,
) -> [f64; N] {
    let add = |y: [f64; N], k: [f64; N], c: f64| std::array::from_fn(|i| y[i] + c * k[i]);
    let k1 = f(t, y);
    let k2 = f(t + h / 2.0, add(y, k1, h / 2.0));
    let k3 = f(t + h / 2.0, add(y, k2, h / 2.0));
    let k4 = f(t + h, add(y, k3, h));
    std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
}

/// [`rk4_step`] from (0, y0) to t_end in steps of h (t_end a whole number of them).
pub fn rk4_run<const N: usize>(
    mut f: impl FnMut(f64, [f64; N]) -> [f64; N],
    y0: [f64; N],
    h: f64,
    t_end: f64,
) -> [f64; N] {
    let steps = (t_end / h).round() as usize;
    assert!(
        (steps as f64 * h - t_end).abs() < 1e-9 * t_end,
        "t_end a whole number of steps"
    );
    (0..steps).fold(y0, |y, i| rk4_step(&mut f, i as f64 * h, y, h))
}

/// The state at t_end of `m` run from its equilibrium by `method` at rtol = atol = `tol`.
pub fn model_end_state(
    m: &hdgear::model::Model,
    t_end: f64,
    tol: f64,
    method: hdgear::integrate::Method,
) -> Vec<f64> {
    use hdgear::simulate::{SimOptions, Start, simulate_model};
    let opts = SimOptions {
        t_end,
        dt: t_end,
        start: Start::Equilibrium,
        tol: hdgear::integrate::Options {
            rtol: tol,
            atol: tol,
            method,
            ..hdgear::integrate::Options::default()
        },
    };
    let mut last = Vec::new();
    simulate_model(m, &opts, |_, y| last = y.to_vec()).unwrap();
    last
}

/// `m` run from its equilibrium to t_end by Taylor and by DOP853 (both at 1e-13): x and x' equal
/// `expected` to `tol`, and the phase state (component 2, θ' = `rate`) equals rate·t_end to 1e-9
/// of it (the rounding summed over the steps).
pub fn assert_both_methods_reach(
    m: &hdgear::model::Model,
    t_end: f64,
    expected: [f64; 2],
    tol: f64,
    rate: f64,
) {
    for method in [
        hdgear::integrate::Method::Taylor,
        hdgear::integrate::Method::Dop853,
    ] {
        let last = model_end_state(m, t_end, 1e-13, method);
        let phase = rate * t_end;
        assert!(
            (last[2] - phase).abs() < 1e-9 * phase,
            "{method}: θ = {}",
            last[2]
        );
        for j in 0..2 {
            assert!(
                (last[j] - expected[j]).abs() < tol,
                "{method}, component {j}: {} vs {}",
                last[j],
                expected[j]
            );
        }
    }
}

/// Uniform numbers in [0, 1) from a seeded generator (a 64-bit LCG's upper 53 bits): random
/// test cases that repeat from run to run.
pub fn uniform(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// rtol = atol = 1e-13 with `method`: the tolerance the comparisons against independent
/// integrations run hdgear at.
pub fn tight(method: hdgear::integrate::Method) -> hdgear::integrate::Options {
    hdgear::integrate::Options {
        rtol: 1e-13,
        atol: 1e-13,
        method,
        ..hdgear::integrate::Options::default()
    }
}

/// The state at `t_end` of `sys` from `y0` at t = 0, stepped with `method` at tolerance `tol`
/// (relative and absolute), and the steps taken.
pub fn end_state<S: hdgear::integrate::System<2>>(
    sys: &S,
    method: hdgear::integrate::Method,
    tol: f64,
    y0: [f64; 2],
    t_end: f64,
) -> ([f64; 2], u64) {
    use hdgear::integrate::Stepper;
    let o = hdgear::integrate::Options {
        rtol: tol,
        atol: tol,
        method,
        ..hdgear::integrate::Options::default()
    };
    let mut s = hdgear::integrate::stepper(sys, 0.0, y0, o).unwrap();
    while s.t() < t_end {
        s.step(t_end).unwrap();
    }
    (*s.y(), s.stats().steps)
}

/// The states of `m` sampled every `dt` from rest (x = 0) to `t_end` with `method` at tolerance
/// `tol` (relative and absolute), one vector per sample.
pub fn states_from_rest(
    m: &hdgear::model::Model,
    method: hdgear::integrate::Method,
    tol: f64,
    t_end: f64,
    dt: f64,
) -> Vec<Vec<f64>> {
    let opts = hdgear::simulate::SimOptions {
        t_end,
        dt,
        start: hdgear::simulate::Start::Rest,
        tol: hdgear::integrate::Options {
            rtol: tol,
            atol: tol,
            method,
            ..hdgear::integrate::Options::default()
        },
    };
    let mut out = vec![];
    hdgear::simulate::simulate_model(m, &opts, |_, y| out.push(y.to_vec())).unwrap();
    out
}

/// A multisine a·Σ_{k=1}^{lines} cos(k·w·t + φ_k) with Schroeder's phases φ_k = −π(k − 1)k/lines,
/// written from the formula (independent of hdgear's multisine term).
pub fn schroeder(a: f64, w: f64, lines: u32, t: f64) -> f64 {
    (1..=lines)
        .map(|k| {
            let j = f64::from(k - 1);
            let phi = -std::f64::consts::PI * j * (j + 1.0) / f64::from(lines);
            a * (f64::from(k) * w * t + phi).cos()
        })
        .sum()
}

/// Where on a step of length `h` from time `t` a watched value leaves its sign: bisection of
/// [0, h] while `before(τ)` (the value still on its old side after a sub-step of τ) holds, to
/// 1e-16 of the time reached; the midpoint of the last bracket. The event location of the
/// event-driven references.
pub fn crossing(t: f64, h: f64, before: impl Fn(f64) -> bool) -> f64 {
    let (mut lo, mut hi) = (0.0, h);
    while hi - lo > 1e-16 * (t + hi) {
        let mid = 0.5 * (lo + hi);
        if before(mid) { lo = mid } else { hi = mid }
    }
    0.5 * (lo + hi)
}
