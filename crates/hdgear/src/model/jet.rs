//! Taylor arithmetic on normalised coefficients, one order at a time: what a term's Taylor
//! recurrence is made of.
//!
//! A function u(t + h) = Σ u_k h^k along the solution is known by its coefficients; a term's
//! value is built from them by Cauchy products ([`cauchy`], [`square_coefficient`]) and the
//! recurrences of the elementary functions below, each derived from the function's differential
//! equation (heyoka and Jorba–Zou build theirs the same way):
//!
//! * e = exp(u): e' = u'e, so k·e_k = Σ_{j=1..k} j·u_j·e_{k−j};
//! * t = tanh(u): t' = (1 − t²)u', so k·t_k = Σ_{j=1..k} j·u_j·(1 − t²)_{k−j};
//! * s = sin u, c = cos u: s' = c·u', c' = −s·u', so k·s_k = Σ j·u_j·c_{k−j} and
//!   k·c_k = −Σ j·u_j·s_{k−j};
//! * p = u^a (u₀ > 0): u·p' = a·p·u', so k·u₀·p_k = Σ_{j=1..k} (a·j − k + j)·u_j·p_{k−j};
//! * q = n/d: n = q·d, so d₀·q_k = n_k − Σ_{j=1..k} d_j·q_{k−j}.
//! * p = √w: p² = w, so 2p₀·p_k = w_k − Σ_{j=1..k−1} p_j·p_{k−j}.
//!
//! Each function takes the argument's rows 0..=k and the result's rows 0..k (computed at the
//! earlier orders) and returns row k, so a recurrence runs order by order beside the state's.
//!
//! A step's pass is one chain: each row waits for the rows it is made of. So the rows just
//! computed enter a sum last where the sum allows it ([`quotient_coefficient`]), and a row is
//! divided by multiplying it with the divisor's reciprocal (1/k from a table, 1/v_r from the
//! parameter): the reciprocal does not wait for the row, a division would.
//!
//! **Why one file.** Every term's Taylor rows are built from these few operations (products,
//! exponentials, step limits) on any jet, scalar or lanes; one place for Taylor arithmetic.

pub use crate::integrate::lanes::{Jet, LaneMask, Lanes};

/// Rows kept per Taylor coefficient row: orders 0..=[`crate::integrate::taylor::MAX_ORDER`].
pub const MAX_ROWS: usize = crate::integrate::taylor::MAX_ORDER + 1;
use crate::integrate::taylor::INV;
pub use crate::integrate::taylor::{cauchy, square_coefficient};

/// Σ_{j=1..=k} j·u_j·w_{k−j} / k: the sum every recurrence of this module shares.
#[inline(always)]
fn weighted<J: Jet>(u: &[J], w: &[J], k: usize) -> J {
    // rows 0..=k only: the loop's indices need no checks; the loops in this module run over
    // half-open ranges (an inclusive range's iterator costs an extra test at every turn)
    let (u, w) = (&u[..=k], &w[..k]);
    weighted_by(|j| u[j], |j| w[j], k)
}

/// [`weighted`] over rows read by index (u's rows 0..=k, w's 0..k).
#[inline(always)]
fn weighted_by<J: Jet>(u: impl Fn(usize) -> J, w: impl Fn(usize) -> J, k: usize) -> J {
    let mut s = J::splat(0.0);
    for j in 1..k + 1 {
        s = s + J::splat(j as f64) * u(j) * w(k - j);
    }
    s * J::splat(INV[k - 1])
}

/// Row k of exp(u) from u's rows 0..=k and exp(u)'s rows 0..k.
///
/// ```
/// use hdgear::model::jet::exp_coefficient;
/// // exp(2t) = Σ 2^k/k! t^k
/// let u = [0.0, 2.0, 0.0, 0.0];
/// let mut e = [0.0; 4];
/// for k in 0..4 { e[k] = exp_coefficient(&u, &e, k); }
/// assert_eq!(e, [1.0, 2.0, 2.0, 4.0 / 3.0]);
/// ```
#[inline(always)]
pub fn exp_coefficient<J: Jet>(u: &[J], e: &[J], k: usize) -> J {
    if k == 0 {
        u[0].map(f64::exp)
    } else {
        weighted(u, e, k)
    }
}

/// [`exp_coefficient`] over rows read by index (u's rows 0..=k, exp(u)'s 0..k): for rows kept
/// where no plain slice of them exists ([`crate::model::law`]'s intermediates).
#[inline(always)]
pub fn exp_coefficient_by<J: Jet>(u: impl Fn(usize) -> J, e: impl Fn(usize) -> J, k: usize) -> J {
    if k == 0 {
        u(0).map(f64::exp)
    } else {
        weighted_by(u, e, k)
    }
}

/// The longest step, at most `h`, on which a term `amplitude`·e^{u(t)} either changes
/// negligibly (by less than `negligible`: e^u is bounded by e^{u₀ + δ(h)}, δ(h) = Σ_{k≥1}|u_k|h^k)
/// or its series, rows 0..=`order` of `e`, has converged (the Jorba–Zou step of the row scaled by
/// its own e₀). Jorba–Zou's rule on the state alone misses a factor e^u that is tiny where the
/// step starts and grows within it: its coefficients still grow at the truncation order (e_k ≈
/// e^{u₀}u₁^k/k! peaks at k ≈ u₁h), yet are too small to show in the state's last rows.
///
/// On any [`Jet`]: on [`Lanes`] its logarithms and exponentials are short polynomials to ~1e-9
/// ([`Jet::ln`]), so each lane's limit is its scalar limit to about that (a step size is a
/// heuristic; that changes nothing measurable).
///
/// ```
/// use hdgear::model::jet::{exp_coefficient, exp_step_limit};
/// // e^{u}, u = −5 + 4t: its size grows 55-fold over a step of 1
/// let u = [-5.0, 4.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
/// let mut e = [0.0; 8];
/// for k in 0..8 { e[k] = exp_coefficient(&u, &e, k); }
/// let h = exp_step_limit(&u, &e, 7, 1.0, 1.0, 1e-10);
/// assert!(h < 0.5 && h > 0.0);
/// // at amplitude 0 the term changes nothing
/// assert_eq!(exp_step_limit(&u, &e, 7, 1.0, 0.0, 1e-10), 1.0);
/// ```
#[inline(always)]
pub fn exp_step_limit<J: Jet>(
    u: &[J],
    e: &[J],
    order: usize,
    h: J,
    amplitude: J,
    negligible: J,
) -> J {
    let negligible = resolvable(negligible, amplitude);
    let converged = within_tolerance(
        own_step(e[0].abs(), e[order - 1].abs(), e[order].abs(), order),
        amplitude * e[order].abs(),
        order,
        negligible,
    );
    if settled(h, converged) {
        return h;
    }
    // amplitude·(e^{u₀ + δ} − e^{u₀}) > negligible ⇔ ln(e^δ − 1) > L = ln(negligible/amplitude) − u₀
    // ⇔ δ > ln(1 + e^L)
    let reach = softplus((negligible / amplitude).ln() - u[0]);
    shorten(h, converged, u, order, reach)
}

/// [`exp_step_limit`] for a term `amplitude`·tanh(u(t)), rows 0..=`order` of u and of `sq` =
/// tanh², where |u| is large: tanh is ±1 up to sech²(u) ≤ 4e^{−2|u|}, a factor of the same kind.
/// Its series (rows of sech² = 1 − tanh²) is judged against sech²(u₀) itself; where that is
/// below 1e-14 the rows, from 1 − tanh² in rounded arithmetic, hold nothing, and only the change
/// of the bound 4e^{−2|u|} over the step counts.
#[inline(always)]
pub fn tanh_step_limit<J: Jet>(
    u: &[J],
    sq: &[J],
    order: usize,
    h: J,
    amplitude: J,
    negligible: J,
) -> J {
    let negligible = resolvable(negligible, amplitude);
    let size = u[0].abs();
    // sech²(u₀) = 4e/(1 + e)² with e = e^{−2|u₀|}
    let sech2 = sech_squared((J::splat(-2.0) * size).exp() * J::splat(4.0));
    let resolved = sech2.gt(J::splat(1e-14));
    let zero = J::splat(0.0);
    let converged = if J::any(resolved) {
        let step = within_tolerance(
            own_step(sech2, sq[order - 1].abs(), sq[order].abs(), order),
            amplitude * sq[order].abs(),
            order,
            negligible,
        );
        J::select(resolved, step, zero)
    } else {
        zero
    };
    if settled(h, converged) {
        return h;
    }
    // the bound's change over a step on which |u| falls by δ < |u₀|: amplitude·4e^{−2|u₀|}·
    // (e^{2δ} − 1) > negligible ⇔ δ > ln(1 + e^L)/2, L = ln(negligible/(4·amplitude)) + 2|u₀|;
    // where that is not below |u₀|, not even the bound's whole rise to 4 is relevant
    let l = (negligible / (J::splat(4.0) * amplitude)).ln() + J::splat(2.0) * size;
    let reach = J::splat(0.5) * softplus(l);
    let reach = J::select(size.gt(reach), reach, J::splat(f64::INFINITY));
    shorten(h, converged, u, order, reach)
}

/// ln(1 + e^l) ≥ max(l, 0), without overflow for large l: max(l, 0) + ln(1 + e^{−|l|}). +∞ at
/// l = +∞.
#[inline(always)]
fn softplus<J: Jet>(l: J) -> J {
    l.max(J::splat(0.0)) + (-l.abs()).exp().ln_1p()
}

/// sech²(u) = 4e/(1 + e)² from `bound` = 4e, e = e^{−2|u|} (the tanh bound's value at u).
#[inline(always)]
fn sech_squared<J: Jet>(bound: J) -> J {
    let q = J::splat(1.0) + J::splat(0.25) * bound;
    bound / (q * q)
}

/// [`exp_step_limit`] for a term `amplitude`·√(y(t)² + r²), a corner |y| rounded over r, with
/// y's row 0 `y0` and rows 1..=`order` in `y`. Away from the corner the rows show |y|'s straight
/// line: the bend r²/(2|y|) stays below their rounding when r ≪ |y|, yet a step may carry y across
/// the corner, where it bends all at once (as heyoka's issue 474 describes for a series that
/// converges later than the rows show). The series of √(y² + r²) in y about y₀ has radius
/// q₀ = √(y₀² + r²), the distance to its branch points y = ±ir, so its rows in y are about
/// q₀^{1−n} and a step on which y moves by δ = Σ_{k≥1}|y_k|·h^k truncates it at order p by about
/// `amplitude`·q₀·(δ/q₀)^{p+1}: the step is halved until that is below `negligible`. Near the
/// corner the steps shrink to a fraction of r/|y'|, and away from it they grow with |y|.
pub fn hyperbola_step_limit(
    y0: f64,
    y: &[f64],
    r: f64,
    order: usize,
    h: f64,
    amplitude: f64,
    negligible: f64,
) -> f64 {
    let q0 = (y0 * y0 + r * r).sqrt();
    let size = amplitude * q0;
    let negligible = resolvable(negligible, size);
    if size <= negligible {
        return h;
    }
    let allowed = q0 * (negligible / size).powf(1.0 / (order + 1) as f64);
    shorten(h, 0.0, y, order, allowed)
}

/// `negligible`, or the rounding of the term's own value (ε·`amplitude`) where that is larger: a
/// change below it is below what any step resolves, and asking for one would shrink the steps
/// without bound at the tightest tolerances.
#[inline(always)]
fn resolvable<J: Jet>(negligible: J, amplitude: J) -> J {
    negligible.max(J::splat(f64::EPSILON) * amplitude)
}

/// Σ_{k=1}^{order} |u_k|·h^k, by Horner's rule.
#[inline(always)]
fn tail_bound<J: Jet>(u: &[J], order: usize, h: J) -> J {
    u[1..=order]
        .iter()
        .rev()
        .fold(J::splat(0.0), |b, &c| (b + c.abs()) * h)
}

/// The Jorba–Zou step of a series whose row 0 is `scale` and rows p − 1, p are `n1`, `n2` (in
/// magnitude), each scaled by `scale`: the radius the series shows, whatever its size.
/// 0 (no step is known good) when `scale` underflowed or is NaN.
#[inline(always)]
fn own_step<J: Jet>(scale: J, n1: J, n2: J, p: usize) -> J {
    let known = scale.gt(J::splat(f64::MIN_POSITIVE));
    let zero = J::splat(0.0);
    if !J::any(known) {
        return zero;
    }
    let (l1, l2) = ((n1 / scale).ln(), (n2 / scale).ln());
    let step = crate::integrate::taylor::ln_step(p, J::splat(2.0), l1, l2).exp();
    J::select(known, step, zero)
}

/// The step a series allows with its truncation held below `negligible`, from its Jorba–Zou step
/// `converged` (the radius ρ its rows show, times e^{−2 − 0.7/(p − 1)}: [`own_step`]) and its
/// last row `last` (times the term's amplitude) at order p = `order`: the first dropped row is
/// about `last`·h^p, and within ρ/2 the rows past it shrink at least geometrically by half, so a
/// step with `last`·h^p ≤ `negligible` and h ≤ ρ/2 truncates the term by about that much. Never
/// below `converged`: a series whose rows are large keeps Jorba–Zou's step.
#[inline(always)]
fn within_tolerance<J: Jet>(converged: J, last: J, order: usize, negligible: J) -> J {
    use crate::integrate::taylor::INV;
    let zero = J::splat(0.0);
    let usable = converged.gt(zero) & last.gt(zero);
    if !J::any(usable) {
        return converged;
    }
    let rho = converged * J::splat(RADIUS_OVER_STEP[order]);
    // (negligible/last)^{1/p}
    let by_tolerance = ((negligible / last).ln() * J::splat(INV[order - 1])).exp();
    J::select(
        usable,
        converged.max(by_tolerance.min(J::splat(0.5) * rho)),
        converged,
    )
}

/// e^{2 + 0.7/(p − 1)} for each order p ≥ 2: the radius ρ a series' rows show over its Jorba–Zou
/// step ([`own_step`], s = 2). Each entry from the exponential's series, summed until its terms
/// vanish against the sum (the exponent is at most 2.7).
const RADIUS_OVER_STEP: [f64; MAX_ROWS] = {
    let mut table = [0.0; MAX_ROWS];
    let mut p = 2;
    while p < MAX_ROWS {
        let x = 2.0 + 0.7 / (p - 1) as f64;
        let (mut sum, mut term, mut n) = (1.0, 1.0, 1.0);
        while sum + term != sum {
            term *= x / n;
            sum += term;
            n += 1.0;
        }
        table[p] = sum;
        p += 1;
    }
    table
};

/// Sub-intervals of a step in which a term samples a function of the step's polynomial for
/// leaving the piece it started on ([`first_exit`]): an excursion off the piece and back inside
/// one eighth of a step is not seen (the motion would have to turn round within it).
const SUBDIVISIONS: usize = 8;

/// The value at τ of the polynomial with rows 0..=`order` of `u`, by Horner's rule.
#[inline]
pub fn horner(u: &[f64], order: usize, tau: f64) -> f64 {
    u[..=order].iter().rev().fold(0.0, |acc, &c| acc * tau + c)
}

/// The longest step, at most `h`, over which the polynomial with rows 0..=`order` of `u` stays
/// in [lo, hi] ([`first_exit`] on it). A polynomial whose reach over the step, Σ_{k≥1} |u_k|·h^k
/// (with a margin of a few rounding errors), keeps it inside is not sampled: every sample
/// [`first_exit`] would take lies within that reach of u₀, so it would return `h` too.
pub fn exit_from(u: &[f64], order: usize, h: f64, (lo, hi): (f64, f64)) -> f64 {
    let reach = u[1..=order]
        .iter()
        .rev()
        .fold(0.0, |acc, &c| (acc + c.abs()) * h);
    let margin = reach * 1e-12 + 4.0 * f64::EPSILON * u[0].abs();
    if u[0] - reach - margin >= lo && u[0] + reach + margin <= hi {
        return h;
    }
    first_exit(h, |tau| (lo..=hi).contains(&horner(u, order, tau)))
}

/// The longest step, at most `h`, over which `on` (a step's polynomial still on the piece it
/// started on, at τ) holds: the first of eight samples off the piece brackets the exit, which
/// bisection narrows to the last bits of the step, ending on the exit's far side (so the next step
/// starts on the boundary or just past it). `h` when every sample is on the piece. The one root
/// finder of the terms whose law changes piece with the state (a catalogue curve's kinks, the
/// sign of a mesh loss's transmitted torque).
pub fn first_exit(h: f64, on: impl Fn(f64) -> bool) -> f64 {
    // at `inside` the polynomial is on the piece (at 0 on its edge at most)
    let mut inside = 0.0;
    for j in 1..=SUBDIVISIONS {
        let off = h * j as f64 / SUBDIVISIONS as f64;
        if !on(off) {
            return crate::roots::bisect(inside, off, 64, crate::roots::at_resolution, on).1;
        }
        inside = off;
    }
    h
}

/// Whether no lane's `h` is above `converged`: then [`shorten`] keeps `h`, and its threshold
/// need not be computed.
#[inline(always)]
fn settled<J: Jet>(h: J, converged: J) -> bool {
    !J::any(h.gt(converged))
}

/// `h` halved (on each lane on its own) until it is at most `converged` or the reach of u's
/// polynomial over it, Σ_{k≥1}|u_k|h^k, is at most `reach` (which it is as h → 0).
#[inline(always)]
fn shorten<J: Jet>(mut h: J, converged: J, u: &[J], order: usize, reach: J) -> J {
    loop {
        let go = h.gt(converged) & tail_bound(u, order, h).gt(reach);
        if !J::any(go) {
            return h;
        }
        h = J::select(go, (J::splat(0.5) * h).max(converged), h);
    }
}

/// Row k of tanh(u) from u's rows 0..=k, tanh(u)'s rows 0..k and `sq` = tanh(u)²'s rows 0..k
/// (the caller keeps `sq` with [`square_coefficient`] once row k is known).
#[inline(always)]
pub fn tanh_coefficient<J: Jet>(u: &[J], sq: &[J], k: usize) -> J {
    let (u, sq) = (&u[..=k], &sq[..k]);
    tanh_coefficient_by(|j| u[j], |j| sq[j], k)
}

/// [`tanh_coefficient`] over rows read by index (u's rows 0..=k, tanh(u)²'s 0..k): for rows kept
/// where no plain slice of them exists ([`crate::model::law`]'s intermediates).
#[inline(always)]
pub fn tanh_coefficient_by<J: Jet>(u: impl Fn(usize) -> J, sq: impl Fn(usize) -> J, k: usize) -> J {
    if k == 0 {
        return u(0).map(f64::tanh);
    }
    // (1 − t²)_{k−j}: 1 − (t²)₀ at j = k, −(t²)_{k−j} below
    let mut s = J::splat(0.0);
    for j in 1..k {
        s = s + J::splat(j as f64) * u(j) * -sq(k - j);
    }
    s = s + J::splat(k as f64) * u(k) * (J::splat(1.0) - sq(0));
    s * J::splat(INV[k - 1])
}

/// Rows k of (sin u, cos u) from u's rows 0..=k and their rows 0..k.
#[inline(always)]
pub fn sin_cos_coefficients(u: &[f64], s: &[f64], c: &[f64], k: usize) -> (f64, f64) {
    if k == 0 {
        libm::sincos(u[0])
    } else {
        (weighted(u, c, k), -weighted(u, s, k))
    }
}

/// Row k of q = n/d from n's and d's rows 0..=k and q's rows 0..k (d₀ ≠ 0), on any [`Jet`]:
/// n = q·d, so q_k = (n_k − Σ_{j=1..k} d_j·q_{k−j})/d₀.
#[inline(always)]
pub fn quotient_coefficient<J: Jet>(n: &[J], d: &[J], q: &[J], k: usize) -> J {
    quotient_coefficient_by(n[k], |j| d[j], |j| q[j], k)
}

/// [`quotient_coefficient`] from n's row k and d's (rows 0..=k) and q's (rows 0..k) read by
/// index: for rows kept where no plain slice of them exists ([`crate::model::law`]'s
/// intermediates).
#[inline(always)]
pub fn quotient_coefficient_by<J: Jet>(
    n_k: J,
    d: impl Fn(usize) -> J,
    q: impl Fn(usize) -> J,
    k: usize,
) -> J {
    // n_k, the new row, last (as in `cauchy`)
    let mut s = J::splat(-0.0);
    for j in 1..k + 1 {
        s = s + d(j) * q(k - j);
    }
    (n_k - s) * (J::splat(1.0) / d(0))
}

/// Row k of p = √w (w₀ > 0) from w's row k and p's rows 0..k: p² = w, so
/// 2p₀p_k = w_k − Σ_{j=1..k−1} p_j p_{k−j}. Only row k of w is read, so w's rows need not be
/// kept (a sum of squares can be formed row by row).
///
/// ```
/// use hdgear::model::jet::sqrt_coefficient;
/// // √(1 + 2t + t²) = 1 + t
/// let w = [1.0, 2.0, 1.0, 0.0];
/// let mut p = [0.0; 4];
/// for k in 0..4 { p[k] = sqrt_coefficient(w[k], &p, k); }
/// assert_eq!(p, [1.0, 1.0, 0.0, 0.0]);
/// ```
#[inline(always)]
pub fn sqrt_coefficient(w_k: f64, p: &[f64], k: usize) -> f64 {
    if k == 0 {
        return w_k.sqrt();
    }
    // a plain loop from −0 (an iterator's `sum`, to the bit)
    let p = &p[..k];
    let mut inner = -0.0;
    for j in 1..k {
        inner += p[j] * p[k - j];
    }
    (w_k - inner) * (0.5 / p[0])
}

/// Row k of u^a (u₀ > 0) from u's rows 0..=k and u^a's rows 0..k.
#[inline(always)]
pub fn pow_coefficient(u: &[f64], a: f64, p: &[f64], k: usize) -> f64 {
    if k == 0 {
        return u[0].powf(a);
    }
    let mut s = 0.0;
    for j in 1..k + 1 {
        s += (a * j as f64 - (k - j) as f64) * u[j] * p[k - j];
    }
    s * (INV[k - 1] / u[0])
}

/// Row k of a whole power uⁿ (n = 1 … 4) by repeated products, from u's rows 0..=k: the rows
/// of u², …, uⁿ are kept in `powers[0..n − 1]` (their rows 0..k from the earlier orders, row k
/// written here). Returns uⁿ's rows, u's own for n = 1.
///
/// ```
/// use hdgear::model::jet::whole_power_rows;
/// // (1 + t)³ = 1 + 3t + 3t² + t³
/// let u = [1.0, 1.0, 0.0, 0.0];
/// let mut powers = [[0.0; hdgear::model::terms::MAX_ROWS]; 2];
/// for k in 0..4 {
///     let cube = whole_power_rows(&u, 3, &mut powers, k);
///     assert_eq!(cube[k], [1.0, 3.0, 3.0, 1.0][k]);
/// }
/// ```
#[inline(always)]
pub fn whole_power_rows<'a, J: Jet>(
    u: &'a [J],
    n: usize,
    powers: &'a mut [[J; MAX_ROWS]],
    k: usize,
) -> &'a [J] {
    for m in 0..n.saturating_sub(1) {
        let (done, next) = powers.split_at_mut(m);
        next[0][k] = match done.last() {
            None => square_coefficient(u, k),
            Some(lower) => cauchy(lower, u, k),
        };
    }
    if n <= 1 { u } else { &powers[n - 2] }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_radius_table_is_the_exponential_of_its_exponent() {
        // the table summed at compile time against the library's exponential: within 4 ulp
        for (p, &r) in RADIUS_OVER_STEP.iter().enumerate().skip(2) {
            let exact = (2.0 + 0.7 / (p - 1) as f64).exp();
            assert!(
                (r - exact).abs() <= 4.0 * f64::EPSILON * exact,
                "{p}: {r} {exact}"
            );
        }
    }

    /// The limits' definition, written out as a search: `h` halved while above `converged` and
    /// `grows(h)`, the change of the term's bound over a step of h, exceeds `negligible`.
    fn halved(mut h: f64, converged: f64, grows: impl Fn(f64) -> f64, negligible: f64) -> f64 {
        while h > converged && grows(h) > negligible {
            h = (0.5 * h).max(converged);
        }
        h
    }

    #[test]
    fn the_limits_thresholds_are_their_bounds_changes() {
        // exp_step_limit and tanh_step_limit find the halving's end from a threshold on the
        // series' reach (one logarithm); written here as the bound's change itself, evaluated at
        // each halving, for series of u from small to large |u₀| and growth, amplitudes and
        // tolerances: the same step to the rounding (a halving decided the other way would be a
        // factor of 2)
        let mut state = 7u64;
        let mut u01 = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let order = 12;
        let (mut cases, mut shortened) = (0, 0);
        for i in 0..400 {
            // a quarter of the cases near u = 0, where the tanh bound's whole rise to 4 may be
            // negligible
            let u0 = if i % 4 == 0 {
                (-1.0 + 2.0 * u01()) * 10f64.powf(-6.0 + 6.0 * u01())
            } else {
                -40.0 + 60.0 * u01()
            };
            let growth = 10f64.powf(-2.0 + 4.0 * u01());
            let mut u = [0.0; MAX_ROWS];
            u[0] = u0;
            for (k, uk) in u.iter_mut().enumerate().take(order + 1).skip(1) {
                *uk = (-1.0 + 2.0 * u01()) * growth.powi(k as i32) / k as f64;
            }
            let (mut e, mut t, mut sq) = ([0.0; MAX_ROWS], [0.0; MAX_ROWS], [0.0; MAX_ROWS]);
            for k in 0..=order {
                e[k] = exp_coefficient(&u, &e, k);
                t[k] = tanh_coefficient(&u, &sq, k);
                sq[k] = square_coefficient(&t, k);
            }
            let amplitude = 10f64.powf(-6.0 + 7.0 * u01());
            let negligible = 10f64.powf(-14.0 + 10.0 * u01());
            let h = 10f64.powf(-2.0 + 2.5 * u01());
            let tail = |h: f64| tail_bound(&u, order, h);
            // exp: the bound e^{u₀ + δ} against e^{u₀}
            let eps = resolvable(negligible, amplitude);
            let converged = within_tolerance(
                own_step(e[0], e[order - 1].abs(), e[order].abs(), order),
                amplitude * e[order].abs(),
                order,
                eps,
            );
            let want = halved(
                h,
                converged,
                |h| amplitude * ((u0 + tail(h)).exp() - e[0]),
                eps,
            );
            let got = exp_step_limit(&u, &e, order, h, amplitude, negligible);
            assert!((got - want).abs() <= 1e-12 * want, "exp {u0}: {got} {want}");
            // tanh: the bound 4e^{−2 max(|u₀| − δ, 0)} against its start
            let bound = |least: f64| 4.0 * (-2.0 * least.max(0.0)).exp();
            let sech2 = sech_squared(bound(u0.abs()));
            let converged = if sech2 > 1e-14 {
                within_tolerance(
                    own_step(sech2, sq[order - 1].abs(), sq[order].abs(), order),
                    amplitude * sq[order].abs(),
                    order,
                    eps,
                )
            } else {
                0.0
            };
            let want_tanh = halved(
                h,
                converged,
                |h| amplitude * (bound(u0.abs() - tail(h)) - bound(u0.abs())),
                eps,
            );
            let got = tanh_step_limit(&u, &sq, order, h, amplitude, negligible);
            assert!(
                (got - want_tanh).abs() <= 1e-12 * want_tanh,
                "tanh {u0}: {got} {want_tanh}"
            );
            cases += 2;
            shortened += usize::from(want < h) + usize::from(want_tanh < h);
        }
        // most cases shorten the step, and not all
        assert!(
            shortened > cases / 4 && shortened < cases,
            "{shortened} of {cases}"
        );
    }

    #[test]
    fn sech_squared_from_the_bound_is_the_hyperbolic_one() {
        // tanh_step_limit's sech²(u₀) = 4e/(1 + e)², e = e^{−2|u₀|}, against 1/cosh²
        for u in [0.0, 1e-3, -0.4, 2.5, -17.0, 300.0] {
            let sech2 = sech_squared(4.0 * (-2.0 * f64::abs(u)).exp());
            let exact = 1.0 / (u.cosh() * u.cosh());
            assert!(
                (sech2 - exact).abs() <= 1e-15 * exact,
                "{u}: {sech2} {exact}"
            );
        }
    }

    /// The coefficients of f(u(t)) at t = 0.3 with u = 0.4 + 1.3t − 0.7t², against the closed
    /// forms' derivatives by a 4th-order finite difference of f∘u (rows 1 and 2).
    fn check(f: impl Fn(f64) -> f64, rows: &dyn Fn(&[f64]) -> Vec<f64>) {
        let t0 = 0.3;
        let u_of = |t: f64| 0.4 + 1.3 * t - 0.7 * t * t;
        let u = [u_of(t0), 1.3 - 1.4 * t0, -0.7, 0.0, 0.0];
        let c = rows(&u);
        let g = |t: f64| f(u_of(t));
        let h = 1e-3;
        let d1 =
            (g(t0 - 2.0 * h) - 8.0 * g(t0 - h) + 8.0 * g(t0 + h) - g(t0 + 2.0 * h)) / (12.0 * h);
        let d2 = (-g(t0 - 2.0 * h) + 16.0 * g(t0 - h) - 30.0 * g(t0) + 16.0 * g(t0 + h)
            - g(t0 + 2.0 * h))
            / (12.0 * h * h);
        assert!((c[0] - g(t0)).abs() < 1e-15);
        assert!((c[1] - d1).abs() < 1e-9, "{} vs {d1}", c[1]);
        assert!((c[2] - d2 / 2.0).abs() < 1e-6, "{} vs {}", c[2], d2 / 2.0);
    }

    #[test]
    fn recurrences_match_the_derivatives_of_the_closed_forms() {
        check(f64::exp, &|u| {
            let mut e = vec![0.0; 5];
            (0..5).for_each(|k| e[k] = exp_coefficient(u, &e, k));
            e
        });
        check(f64::tanh, &|u| {
            let (mut t, mut sq) = (vec![0.0; 5], vec![0.0; 5]);
            for k in 0..5 {
                t[k] = tanh_coefficient(u, &sq, k);
                sq[k] = square_coefficient(&t, k);
            }
            t
        });
        check(f64::sin, &|u| {
            let (mut s, mut c) = (vec![0.0; 5], vec![0.0; 5]);
            for k in 0..5 {
                (s[k], c[k]) = sin_cos_coefficients(u, &s, &c, k);
            }
            s
        });
        check(|x| x.sin() / x.exp(), &|u| {
            let (mut s, mut c, mut e, mut q) =
                (vec![0.0; 5], vec![0.0; 5], vec![0.0; 5], vec![0.0; 5]);
            for k in 0..5 {
                (s[k], c[k]) = sin_cos_coefficients(u, &s, &c, k);
                e[k] = exp_coefficient(u, &e, k);
                q[k] = quotient_coefficient(&s, &e, &q, k);
            }
            q
        });
        check(|x| (x * x + 0.09).sqrt(), &|u| {
            let (mut w, mut p) = (vec![0.0; 5], vec![0.0; 5]);
            for k in 0..5 {
                w[k] = square_coefficient(u, k) + if k == 0 { 0.09 } else { 0.0 };
                p[k] = sqrt_coefficient(w[k], &p, k);
            }
            p
        });
        check(|x| x.powf(2.5), &|u| {
            let mut p = vec![0.0; 5];
            (0..5).for_each(|k| p[k] = pow_coefficient(u, 2.5, &p, k));
            p
        });
    }
}
