//! Taylor's method on [`LANES`] parameter sets of the dimensionless model at once, in lock-step:
//! structure of arrays (every coefficient is a `[f64; LANES]`), each lane with its own time and
//! step, so the compiler turns each operation into one vector instruction over the lanes.
//!
//! The same order and step rule as [`super::Taylor`], with two differences that keep the lanes in
//! vector registers: sin ωt and cos ωt are carried as two more state components (their Taylor
//! coefficients by the recurrence s' = ωc, c' = −ωs, as heyoka does), so no lane calls a sine; and
//! the step's logarithm and exponential are evaluated by short polynomials to ~1e-6
//! (the step size is a heuristic: a relative change of 1e-6 in h changes nothing measurable).
//!
//! The shipped binary picks the widest vector unit the CPU has at run time (AVX-512, AVX2, else
//! the portable SSE2 path); all paths compute bit-identical results (no fused multiply-add).

use super::taylor::{INV, MAX_ORDER, order_for};
use super::{Options, SolverError};
use crate::error::Result;
use crate::params::Params;

/// Trajectories per batch.
pub const LANES: usize = 16;

type V = [f64; LANES];

/// The outcome of one lane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LaneResult {
    /// Final state [x, x'].
    pub y: [f64; 2],
    /// Steps taken by this lane.
    pub steps: u64,
}

/// Integrates each of `points` from its start `y0` at τ = 0 to `t_end`, [`LANES`] at a time, and
/// returns the final states in order.
///
/// ```
/// use hdgear::{Params, integrate::{Options, batch::integrate_batch}};
/// let points: Vec<Params> = [30.0, 10.0, 1.0, 0.1]
///     .iter()
///     .map(|&gamma| Params { gamma, ..Params::default() })
///     .collect();
/// let starts = vec![[0.0, 0.0]; 4];
/// let out = integrate_batch(&points, &starts, 100.0, Options::default()).unwrap();
/// assert_eq!(out.len(), 4);
/// ```
pub fn integrate_batch(
    points: &[Params],
    starts: &[[f64; 2]],
    t_end: f64,
    tol: Options,
) -> Result<Vec<LaneResult>> {
    tol.validate()?;
    if starts.len() != points.len() {
        return Err(crate::Error::InvalidInput {
            what: "batch",
            text: format!(
                "{} starts for {} parameter sets",
                starts.len(),
                points.len()
            ),
            reason: "one start per parameter set".into(),
        });
    }
    for p in points {
        p.validate()?;
    }
    super::check_budget(t_end, &tol)?;
    let mut out = Vec::with_capacity(points.len());
    for (chunk, y0) in points.chunks(LANES).zip(starts.chunks(LANES)) {
        out.extend_from_slice(&run_chunk(chunk, y0, t_end, &tol)?[..chunk.len()]);
    }
    Ok(out)
}

/// One chunk (padded with copies of its first lane), on the widest vector unit available.
fn run_chunk(
    points: &[Params],
    starts: &[[f64; 2]],
    t_end: f64,
    tol: &Options,
) -> Result<[LaneResult; LANES]> {
    let mut b = Lanes::new(points, starts, tol);
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("avx512f") {
            // SAFETY: the CPU has AVX-512F (checked just above).
            return unsafe { run_avx512(&mut b, t_end, tol) };
        }
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the CPU has AVX2 (checked just above).
            return unsafe { run_avx2(&mut b, t_end, tol) };
        }
    }
    run(&mut b, t_end, tol)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f")]
fn run_avx512(b: &mut Lanes, t_end: f64, tol: &Options) -> Result<[LaneResult; LANES]> {
    run(b, t_end, tol)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn run_avx2(b: &mut Lanes, t_end: f64, tol: &Options) -> Result<[LaneResult; LANES]> {
    run(b, t_end, tol)
}

#[inline(always)]
fn run(b: &mut Lanes, t_end: f64, tol: &Options) -> Result<[LaneResult; LANES]> {
    while b.t.iter().any(|&t| t < t_end) {
        if b.steps.iter().any(|&s| s >= tol.max_steps) {
            let t = b.t.iter().copied().fold(f64::INFINITY, f64::min);
            return Err(SolverError::TooManySteps {
                t,
                max_steps: tol.max_steps,
            }
            .into());
        }
        b.step(t_end);
        if let Some(l) =
            (0..LANES).find(|&l| !(b.x[l].abs() <= tol.blowup && b.v[l].abs() <= tol.blowup))
        {
            return Err(SolverError::BlowUp {
                t: b.t[l],
                value: if b.x[l].abs() > b.v[l].abs() {
                    b.x[l]
                } else {
                    b.v[l]
                },
            }
            .into());
        }
    }
    Ok(std::array::from_fn(|l| LaneResult {
        y: [b.x[l], b.v[l]],
        steps: b.steps[l],
    }))
}

/// The lanes' parameters and states.
struct Lanes {
    alpha: V,
    gamma: V,
    delta: V,
    omega: V,
    /// μ + γε: the constant term of the acceleration.
    constant: V,
    t: V,
    x: V,
    v: V,
    sin: V,
    cos: V,
    steps: [u64; LANES],
    order: usize,
    floor: f64,
    /// Coefficients of x, x', sin, cos and x² (rows 0..=order), kept between steps so that no
    /// step clears them.
    cx: Coefs,
    cv: Coefs,
    cs: Coefs,
    cc: Coefs,
    cx2: Coefs,
}

type Coefs = Box<[V; MAX_ORDER + 1]>;

impl Lanes {
    fn new(points: &[Params], starts: &[[f64; 2]], tol: &Options) -> Lanes {
        let pick = |l: usize| if l < points.len() { l } else { 0 };
        let get = |f: fn(&Params) -> f64| -> V { std::array::from_fn(|l| f(&points[pick(l)])) };
        Lanes {
            alpha: get(|p| p.alpha),
            gamma: get(|p| p.gamma),
            delta: get(|p| p.delta),
            omega: get(|p| p.omega),
            constant: get(|p| p.mu + p.gamma * p.eps),
            t: [0.0; LANES],
            x: std::array::from_fn(|l| starts[pick(l)][0]),
            v: std::array::from_fn(|l| starts[pick(l)][1]),
            sin: [0.0; LANES],
            cos: [1.0; LANES],
            steps: [0; LANES],
            order: order_for(tol.rtol),
            floor: tol.atol / tol.rtol,
            cx: Box::new([[0.0; LANES]; MAX_ORDER + 1]),
            cv: Box::new([[0.0; LANES]; MAX_ORDER + 1]),
            cs: Box::new([[0.0; LANES]; MAX_ORDER + 1]),
            cc: Box::new([[0.0; LANES]; MAX_ORDER + 1]),
            cx2: Box::new([[0.0; LANES]; MAX_ORDER + 1]),
        }
    }

    /// One step of every lane still short of `t_end`.
    #[inline(always)]
    fn step(&mut self, t_end: f64) {
        let p = self.order;
        let (x, v, s, c, x2) = (
            &mut *self.cx,
            &mut *self.cv,
            &mut *self.cs,
            &mut *self.cc,
            &mut *self.cx2,
        );
        (x[0], v[0], s[0], c[0]) = (self.x, self.v, self.sin, self.cos);
        for k in 0..p {
            let sq = cauchy(x, x, k);
            x2[k] = sq;
            let cube = cauchy(x2, x, k);
            let first = if k == 0 { 1.0 } else { 0.0 };
            for l in 0..LANES {
                let acc = first * self.constant[l] + self.delta[l] * s[k][l]
                    - v[k][l]
                    - self.alpha[l] * cube[l]
                    + sq[l]
                    - self.gamma[l] * x[k][l];
                x[k + 1][l] = v[k][l] * INV[k];
                v[k + 1][l] = acc * INV[k];
                s[k + 1][l] = self.omega[l] * c[k][l] * INV[k];
                c[k + 1][l] = -self.omega[l] * s[k][l] * INV[k];
            }
        }
        let h = step_sizes(p, self.floor, &self.t, x, v, t_end);
        let (mut nx, mut nv, mut ns, mut nc) = (x[p], v[p], s[p], c[p]);
        for k in (0..p).rev() {
            for l in 0..LANES {
                nx[l] = nx[l] * h[l] + x[k][l];
                nv[l] = nv[l] * h[l] + v[k][l];
                ns[l] = ns[l] * h[l] + s[k][l];
                nc[l] = nc[l] * h[l] + c[k][l];
            }
        }
        for l in 0..LANES {
            if h[l] > 0.0 {
                let last = self.t[l] + h[l] >= t_end;
                self.t[l] = if last { t_end } else { self.t[l] + h[l] };
                (self.x[l], self.v[l], self.sin[l], self.cos[l]) = (nx[l], nv[l], ns[l], nc[l]);
                self.steps[l] += 1;
            }
        }
    }
}

/// Σ_j a_j b_{k−j} lane by lane, in two partial sums (a single running sum is a chain of
/// dependent additions: the step costs 1.1× more with it, measured).
#[inline(always)]
fn cauchy(a: &[V; MAX_ORDER + 1], b: &[V; MAX_ORDER + 1], k: usize) -> V {
    let (mut s0, mut s1) = ([0.0; LANES], [0.0; LANES]);
    let mut j = 0;
    while j < k {
        for l in 0..LANES {
            s0[l] += a[j][l] * b[k - j][l];
            s1[l] += a[j + 1][l] * b[k - j - 1][l];
        }
        j += 2;
    }
    if j == k {
        for l in 0..LANES {
            s0[l] += a[k][l] * b[0][l];
        }
    }
    std::array::from_fn(|l| s0[l] + s1[l])
}

/// The Jorba–Zou step of each lane (0 for a lane already at `t_end`), clipped to `t_end`.
#[inline(always)]
fn step_sizes(
    p: usize,
    floor: f64,
    t: &V,
    x: &[V; MAX_ORDER + 1],
    v: &[V; MAX_ORDER + 1],
    t_end: f64,
) -> V {
    let mut h = [0.0; LANES];
    for l in 0..LANES {
        let sx = x[0][l].abs().max(floor);
        let sv = v[0][l].abs().max(floor);
        let n1 = (x[p - 1][l].abs() / sx).max(v[p - 1][l].abs() / sv);
        let n2 = (x[p][l].abs() / sx).max(v[p][l].abs() / sv);
        let ln_rho = (-ln(n1) * INV[p - 2]).min(-ln(n2) * INV[p - 1]);
        let hl = exp(ln_rho - 2.0 - 0.7 * INV[p - 2]);
        let remaining = t_end - t[l];
        h[l] = if remaining > 0.0 {
            hl.min(remaining)
        } else {
            0.0
        };
    }
    h
}

/// ln(x) to ~1e-6 for the step rule: exponent from the bits, the mantissa m ∈ [1, 2)
/// by ln(m) = 2·atanh((m − 1)/(m + 1)) to the 7th power. x = 0 gives a huge negative number, so
/// a vanishing coefficient allows an unbounded step, as the exact rule does.
#[inline(always)]
fn ln(x: f64) -> f64 {
    let bits = x.to_bits();
    let e = ((bits >> 52) & 0x7ff) as i64 - 1023;
    let m = f64::from_bits((bits & 0x000f_ffff_ffff_ffff) | 0x3ff0_0000_0000_0000);
    let z = (m - 1.0) / (m + 1.0);
    let z2 = z * z;
    let atanh = z * (1.0 + z2 * (1.0 / 3.0 + z2 * (1.0 / 5.0 + z2 * (1.0 / 7.0 + z2 / 9.0))));
    e as f64 * std::f64::consts::LN_2 + 2.0 * atanh
}

/// exp(x) to ~1e-9 relative for the step rule (x well inside ±700): 2^k by the exponent bits, the
/// rest by its Taylor series on |r| < ln 2.
#[inline(always)]
fn exp(x: f64) -> f64 {
    let x = x.clamp(-700.0, 700.0);
    // truncation toward zero (a conversion, not a libm call): |r| < ln 2
    let k = (x * std::f64::consts::LOG2_E) as i64;
    let r = x - k as f64 * std::f64::consts::LN_2;
    let mut poly = 1.0;
    for inv in INV[..12].iter().rev() {
        poly = 1.0 + poly * r * inv;
    }
    let two_k = f64::from_bits(((k + 1023) as u64) << 52);
    poly * two_k
}

#[cfg(test)]
mod tests {
    #[test]
    fn fast_ln_and_exp_are_close() {
        for &x in &[1e-300, 1e-20, 0.3, 1.0, 1.7, 123.0, 1e200] {
            assert!(
                (super::ln(x) - x.ln()).abs() <= 1e-6 * x.ln().abs().max(1.0),
                "{x}"
            );
        }
        for &x in &[-600.0, -30.0, -2.7, 0.0, 1.3, 50.0] {
            let e: f64 = f64::exp(x);
            assert!((super::exp(x) - e).abs() <= 1e-9 * e, "{x}");
        }
    }
}
