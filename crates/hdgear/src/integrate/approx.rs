//! ln and exp to about 1e-9 relative by short polynomials, for step sizes: a step size is a
//! heuristic, and a relative change of 1e-9 in it changes nothing measurable. They work from the
//! bits alone and without branches, so a loop of them over a batch's lanes compiles to vector
//! instructions, where the library's functions are calls lane by lane. One call alone is slower
//! than the library's, whose table lookups make shorter dependency chains.
//!
//! `FMA` says whether the caller was compiled with fused multiply-adds ([`mul_add`]); the same
//! `FMA` gives the same bits on every lane and in every copy.

/// a·b + c, fused (one rounding, one instruction) where the caller was compiled for FMA.
#[inline(always)]
pub(crate) fn mul_add<const FMA: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FMA { a.mul_add(b, c) } else { a * b + c }
}

/// 1.5·2⁵²: adding and subtracting it rounds a double below 2⁵¹ in size to an integer, and a
/// double in [2⁵², 2⁵³) holds the integer in its low mantissa bits. Both stay in the vector
/// unit (a conversion to i64 and back does not, without AVX-512DQ).
const ROUND: f64 = 6_755_399_441_055_744.0;
/// 2⁵².
const TWO_52: f64 = 4_503_599_627_370_496.0;

/// The binary exponent e of a positive finite x (x = m·2^e, m ∈ [1, 2); −1023 for 0 and
/// subnormals), as a double, from the bits alone (it stays in the vector unit).
#[inline(always)]
pub(crate) fn exponent(x: f64) -> f64 {
    // the biased exponent as the low bits of a double in [2⁵², 2⁵³)
    f64::from_bits((x.to_bits() >> 52) | TWO_52.to_bits()) - (TWO_52 + 1023.0)
}

/// 2^k for an integer k ∈ [−1022, 1023] held in a double: k + 1023 in the low mantissa bits,
/// shifted into the exponent field.
#[inline(always)]
pub(crate) fn pow2(k: f64) -> f64 {
    f64::from_bits((k + (TWO_52 + 1023.0)).to_bits() << 52)
}

/// x = 2^e·m with m ∈ [√½, √2): (e, m), from the bits.
#[inline(always)]
fn split(x: f64) -> (f64, f64) {
    let e = exponent(x);
    let m = f64::from_bits((x.to_bits() & 0x000f_ffff_ffff_ffff) | 1.0f64.to_bits());
    let big = m > std::f64::consts::SQRT_2;
    (if big { e + 1.0 } else { e }, if big { 0.5 * m } else { m })
}

/// e·ln 2 + 2·atanh(z) by atanh's series to the 9th power: ln(2^e·m) with z = (m − 1)/(m + 1).
/// For m ∈ [√½, √2), |z| ≤ 0.172 and the series' remainder is below 1e-9 of it.
#[inline(always)]
fn ln_series<const FMA: bool>(e: f64, z: f64) -> f64 {
    let z2 = z * z;
    let fma = mul_add::<FMA>;
    let series = fma(
        z2,
        fma(
            z2,
            fma(z2, fma(z2, 1.0 / 9.0, 1.0 / 7.0), 1.0 / 5.0),
            1.0 / 3.0,
        ),
        1.0,
    );
    fma(e, std::f64::consts::LN_2, 2.0 * z * series)
}

/// ln(a), ln(b) to ~1e-9, both quotients (m − 1)/(m + 1) from one division. 0 gives a large
/// negative number (about −709), so a vanishing coefficient allows a huge step, as the exact
/// rule allows an unbounded one.
#[inline(always)]
pub(crate) fn ln_pair<const FMA: bool>(a: f64, b: f64) -> (f64, f64) {
    let ((ea, ma), (eb, mb)) = (split(a), split(b));
    let d = 1.0 / ((ma + 1.0) * (mb + 1.0));
    let (za, zb) = ((ma - 1.0) * (mb + 1.0) * d, (mb - 1.0) * (ma + 1.0) * d);
    (ln_series::<FMA>(ea, za), ln_series::<FMA>(eb, zb))
}

/// ln(x) to ~1e-9 for x ≥ 0: about −709 at 0, +∞ at +∞.
#[inline(always)]
pub(crate) fn ln<const FMA: bool>(x: f64) -> f64 {
    let (e, m) = split(x);
    let l = ln_series::<FMA>(e, (m - 1.0) / (m + 1.0));
    if x == f64::INFINITY { x } else { l }
}

/// ln(1 + x) to ~2e-9 relative for x ≥ 0, also where x is far below the rounding of 1 + x:
/// below √2 − 1 it is 2·atanh(x/(2 + x)), whose argument is then at most 0.172 (ln_series with
/// e = 0); above, ln(1 + x). +∞ at +∞.
#[inline(always)]
pub(crate) fn ln_1p<const FMA: bool>(x: f64) -> f64 {
    let small = x < std::f64::consts::SQRT_2 - 1.0;
    let (e, m) = split(1.0 + x);
    let (e, num, den) = if small {
        (0.0, x, 2.0 + x)
    } else {
        (e, m - 1.0, m + 1.0)
    };
    let l = ln_series::<FMA>(e, num / den);
    if x == f64::INFINITY { x } else { l }
}

/// exp(x) to ~1e-9 relative (x clamped to ±700): 2^k by the exponent bits, the rest by its Taylor
/// series to the 8th power on |r| ≤ ln 2/2 (remainder < 2e-10).
#[inline(always)]
pub(crate) fn exp<const FMA: bool>(x: f64) -> f64 {
    const INV_FACTORIAL: [f64; 9] = {
        let mut t = [1.0; 9];
        let mut k = 1;
        while k < 9 {
            t[k] = t[k - 1] / k as f64;
            k += 1;
        }
        t
    };
    let fma = mul_add::<FMA>;
    let x = x.clamp(-700.0, 700.0);
    let k = (x * std::f64::consts::LOG2_E + ROUND) - ROUND;
    let r = fma(-k, std::f64::consts::LN_2, x);
    let mut poly = INV_FACTORIAL[8];
    for c in INV_FACTORIAL[..8].iter().rev() {
        poly = fma(poly, r, *c);
    }
    poly * pow2(k)
}

#[cfg(test)]
mod tests {
    /// The arguments the tests take: from the smallest normal number to the largest, 0, and
    /// where the series' branches meet.
    const XS: [f64; 14] = [
        0.0,
        2.3e-308,
        1e-300,
        1e-20,
        1e-9,
        0.3,
        std::f64::consts::SQRT_2 - 1.0,
        0.5,
        1.0,
        1.7,
        1.999,
        123.0,
        1e200,
        1.7e308,
    ];

    /// |a − b| within 1e-9 of |b| (of 1 where b is smaller).
    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-9 * b.abs().max(1.0)
    }

    #[test]
    fn logarithms_agree_with_the_librarys() {
        for &a in &XS[1..] {
            for &b in &XS[1..] {
                let (la, lb) = super::ln_pair::<false>(a, b);
                assert!(close(la, a.ln()) && close(lb, b.ln()), "{a} {b}");
            }
            for fma in [super::ln::<false>(a), super::ln::<true>(a)] {
                assert!(close(fma, a.ln()), "{a}");
            }
        }
        assert_eq!(super::ln::<false>(f64::INFINITY), f64::INFINITY);
        assert!(super::ln::<false>(0.0) < -700.0);
    }

    #[test]
    fn ln_1p_keeps_its_relative_accuracy_at_small_arguments() {
        for &x in &XS {
            let (l, exact) = (super::ln_1p::<false>(x), x.ln_1p());
            // relative, also where 1 + x rounds to 1 (where ln(1 + x) would give 0); the
            // series' remainder at |z| = 0.172 (x = √2 − 1) is 7e-10 of ln √2 = 0.35, 2e-9 of it
            assert!((l - exact).abs() <= 3e-9 * exact, "{x}: {l} {exact}");
        }
        assert_eq!(super::ln_1p::<false>(f64::INFINITY), f64::INFINITY);
    }

    #[test]
    fn exponentials_agree_with_the_librarys() {
        for &x in &[-700.0, -600.0, -30.0, -2.7, -1e-12, 0.0, 1.3, 50.0, 700.0] {
            let e: f64 = f64::exp(x);
            assert!((super::exp::<false>(x) - e).abs() <= 1e-9 * e, "{x}");
        }
    }
}
