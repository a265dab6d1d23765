//! Sine and cosine of an angle given in turns, without a general range reduction.

use core::f64::consts::FRAC_PI_2;

/// `(sin 2πu, cos 2πu)` — the angle in turns, as the line samplers draw it.
///
/// ```text
/// v = 4u,  q = round(v),  r = (v − q)·π/2 ∈ [−π/4, π/4]
/// (sin, cos)(2πu) = (sin r, cos r) rotated by q quarter turns
/// ```
///
/// `v − q` is exact, so the reduction costs one rounding (of `r`), where libm's `sin` and
/// `cos` reduce `2πu` modulo `π/2` in extended precision, twice. `sin r` and `cos r` are
/// their Taylor polynomials through `r¹⁷` and `r¹⁶`, whose truncation error below
/// `(π/4)¹⁹/19! < 10⁻¹⁹` and `(π/4)¹⁸/18! < 3·10⁻¹⁸` is below the rounding. Tested: within
/// `2.5·10⁻¹⁶` of libm's `sin r`, `cos r`, and within `10⁻¹⁵` of libm's `sin(2πu)`,
/// `cos(2πu)` (whose rounded argument `2πu` costs up to `4·10⁻¹⁶` itself). Non-finite `u`
/// gives NaN.
#[inline]
#[must_use]
pub(crate) fn sin_cos_turns(u: f64) -> (f64, f64) {
    let v = 4.0 * u;
    let q = rint(v);
    let r = (v - q) * FRAC_PI_2;
    let r2 = r * r;
    // Horner in r²: sin r = r Σ (−r²)^k/(2k+1)!,  cos r = Σ (−r²)^k/(2k)!
    let s = r
        * (1.0
            + r2 * (-1.0 / 6.0
                + r2 * (1.0 / 120.0
                    + r2 * (-1.0 / 5040.0
                        + r2 * (1.0 / 362_880.0
                            + r2 * (-1.0 / 39_916_800.0
                                + r2 * (1.0 / 6_227_020_800.0
                                    + r2 * (-1.0 / 1_307_674_368_000.0
                                        + r2 * (1.0 / 355_687_428_096_000.0)))))))));
    let c = 1.0
        + r2 * (-0.5
            + r2 * (1.0 / 24.0
                + r2 * (-1.0 / 720.0
                    + r2 * (1.0 / 40_320.0
                        + r2 * (-1.0 / 3_628_800.0
                            + r2 * (1.0 / 479_001_600.0
                                + r2 * (-1.0 / 87_178_291_200.0
                                    + r2 * (1.0 / 20_922_789_888_000.0))))))));
    // Quarter turns: q mod 4 (the cast saturates for huge or NaN v, whose r is NaN anyway).
    quarter_turns(s, c, q as i64)
}

/// `(s, c)` rotated by `k mod 4` quarter turns: `(s, c)`, `(c, −s)`, `(−s, −c)`, `(−c, s)`
/// for `k ≡ 0, 1, 2, 3` — the same bits as that `match`, without a branch. A global
/// line's quarter is random, so the `match` (a jump table) was mispredicted about three
/// times in four, twice a line: here bit 0 of `k` swaps the pair and the sign bits are
/// flipped by exclusive or (`−x` flips the sign bit, nothing else), the first where
/// bit 1 is set (`k ≡ 2, 3`), the second where bits 0 and 1 differ (`k ≡ 1, 2`).
#[inline(always)]
fn quarter_turns(s: f64, c: f64, k: i64) -> (f64, f64) {
    let k = k as u64;
    let swap = 0u64.wrapping_sub(k & 1);
    let (sb, cb) = (s.to_bits(), c.to_bits());
    let diff = (sb ^ cb) & swap;
    let (a, b) = (sb ^ diff, cb ^ diff);
    let neg_a = (k >> 1) & 1;
    let neg_b = ((k >> 1) ^ k) & 1;
    (
        f64::from_bits(a ^ (neg_a << 63)),
        f64::from_bits(b ^ (neg_b << 63)),
    )
}

/// Two to the 52: from here on every `f64` is an integer.
const TWO_52: f64 = 4_503_599_627_370_496.0;

/// `v` rounded to the nearest integer, ties to even — `libm::rint` in the default
/// rounding mode, bit for bit, without its software path (on x86-64 without SSE 4.1 it
/// cost some 28 instructions a call):
///
/// ```text
/// |v| < 2⁵²:  rint(v) = ((v + s) − s) with the sign of v,   s = 2⁵² with the sign of v
/// ```
///
/// `v + s` lies in `[2⁵², 2⁵³]` in magnitude, where doubles are spaced by 1, so the
/// addition rounds `v` to an integer, ties to even (as `2⁵²` is even), and the subtraction
/// is exact; the sign is put back for the results `−0` (`rint(−0.3) = −0`). Larger `|v|`
/// are integers already, and infinities and NaN are returned as they are.
#[inline]
#[must_use]
fn rint(v: f64) -> f64 {
    if v.abs() < TWO_52 {
        let s = TWO_52.copysign(v);
        ((v + s) - s).copysign(v)
    } else {
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::TAU;

    #[test]
    fn agrees_with_libm() {
        let mut rng = crate::lines::chunk_rng(3, 0);
        let (mut worst, mut worst_poly): (f64, f64) = (0.0, 0.0);
        for k in 0..200_000 {
            let u = if k < 4096 {
                f64::from(k) / 4096.0 // quarter and octant boundaries exactly
            } else {
                crate::lines::canonical(&mut rng)
            };
            let (s, c) = sin_cos_turns(u);
            // The polynomials against libm on the same reduced angle ...
            let v = 4.0 * u;
            let q = libm::rint(v);
            let r = (v - q) * core::f64::consts::FRAC_PI_2;
            let (sr, cr) = (libm::sin(r), libm::cos(r));
            let (s1, c1) = match (q as i64) & 3 {
                0 => (sr, cr),
                1 => (cr, -sr),
                2 => (-sr, -cr),
                _ => (-cr, sr),
            };
            worst_poly = worst_poly.max((s - s1).abs()).max((c - c1).abs());
            // ... and against libm's sin(2πu), whose argument 2πu is itself rounded.
            let (s0, c0) = (libm::sin(TAU * u), libm::cos(TAU * u));
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
            assert!((s * s + c * c - 1.0).abs() < 5e-16);
        }
        assert!(worst_poly < 2.5e-16, "polynomials: worst {worst_poly:e}");
        assert!(worst < 1e-15, "worst {worst:e}");
        assert_eq!(sin_cos_turns(0.0), (0.0, 1.0));
        assert_eq!(sin_cos_turns(0.25), (1.0, 0.0));
        assert_eq!(sin_cos_turns(0.5), (0.0, -1.0));
        let (s, c) = sin_cos_turns(f64::NAN);
        assert!(s.is_nan() && c.is_nan());
    }

    #[test]
    fn quarter_turns_is_the_match_bit_for_bit() {
        let by_match = |s: f64, c: f64, k: i64| match k & 3 {
            0 => (s, c),
            1 => (c, -s),
            2 => (-s, -c),
            _ => (-c, s),
        };
        let values = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.3,
            -0.7,
            f64::MIN_POSITIVE,
            -5e-324,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            -f64::NAN,
        ];
        for &s in &values {
            for &c in &values {
                for k in [
                    -5,
                    -4,
                    -3,
                    -2,
                    -1,
                    0,
                    1,
                    2,
                    3,
                    4,
                    5,
                    6,
                    7,
                    i64::MAX,
                    i64::MIN,
                ] {
                    let (a, b) = quarter_turns(s, c, k);
                    let (x, y) = by_match(s, c, k);
                    assert_eq!((a.to_bits(), b.to_bits()), (x.to_bits(), y.to_bits()));
                }
            }
        }
    }

    #[test]
    fn rint_is_libm_rint_bit_for_bit() {
        let mut rng = crate::lines::chunk_rng(5, 0);
        let special = [
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            2.5,
            -2.5,
            0.49999999999999994,
            -0.49999999999999994,
            TWO_52 - 0.5,
            TWO_52,
            -TWO_52 + 0.5,
            TWO_52 * 2.0 - 1.0,
            1e300,
            -1e300,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        let random = (0..100_000).map(|k| {
            let u = crate::lines::canonical(&mut rng);
            // [0, 4) as the sampler's 4u, halves exactly, and signed values of all sizes
            match k % 3 {
                0 => 4.0 * u,
                1 => f64::from(k / 3) * 0.5 - 4000.0,
                _ => (u - 0.5) * libm::exp2(f64::from(k % 120) - 60.0),
            }
        });
        for v in special.into_iter().chain(random) {
            assert_eq!(rint(v).to_bits(), libm::rint(v).to_bits(), "{v:e}");
        }
        assert!(rint(f64::NAN).is_nan());
    }
}
