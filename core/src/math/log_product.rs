//! `Σ log₂ x_k` as the logarithm of a running product: one multiplication per term instead
//! of one logarithm.

use super::log2_fast;

/// Mask of an `f64`'s 52 fraction bits.
const FRACTION: u64 = (1 << 52) - 1;

/// Biased exponent of `1.0`.
const ONE: u64 = 1023;

/// The product is kept while its biased exponent lies in `ONE ± SAFE` (`2^±960`): then one
/// more factor `x ∈ [2⁻⁶², 2⁶²]` can neither overflow nor become subnormal.
const SAFE: u64 = 960;

/// `Σ_k log₂ x_k` of positive factors, accumulated as `Π_k x_k = m · 2^e` with the binary
/// exponent `e` kept apart, so the product never overflows or underflows:
///
/// ```text
/// push(x):  m ← m·x;  when m leaves [2⁻⁹⁶⁰, 2⁹⁶⁰]:  m = m'·2^k, m' ∈ [1, 2)  →  m ← m', e ← e + k
/// log2():   Σ_k log₂ x_k = e + log₂ m          (m first renormalised into [1, 2))
/// ```
///
/// One `f64` multiplication per factor, exact exponent bookkeeping and one [`log2_fast`]
/// at the end, where the direct sum needs one logarithm per term (the per-segment
/// `log₂ r` of the line estimators, 4.13).
///
/// # Error bound
///
/// Each multiplication rounds once (relative error `≤ u = 2⁻⁵³`); splitting off the
/// exponent is exact. After `K` factors the product's relative error is at most
/// `(1 + u)^K − 1 ≤ 1.01·K·u` (for `K ≤ 10¹³`), hence, with [`log2_fast`]'s `2·10⁻¹⁵` on
/// `[1, 2)` and the final addition's rounding,
///
/// ```text
/// |log2() − Σ_k log₂ x_k| ≤ 1.46·K·u + 2·10⁻¹⁵ + u·|Σ_k log₂ x_k|
/// ```
///
/// (`1.01/ln 2 < 1.46`): below the error of the direct sum of `K` table logarithms
/// ([`log2_fast`], up to `2·10⁻¹⁵ · max(1, |log₂ x_k|)` each). Tested against the sum of
/// libm logarithms by a proptest.
///
/// A factor that is zero, negative, infinite or NaN makes the product invalid
/// ([`Log2Product::log2`] returns `None`); subnormal factors are exact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Log2Product {
    /// The running product `m` (positive and normal while valid), NaN once a factor was
    /// not a positive finite number (no flag beside it: 16 bytes, so that a table of
    /// products stays small in the cache).
    mantissa: f64,
    /// The exponent `e` split off so far.
    exponent: i64,
}

impl Default for Log2Product {
    fn default() -> Self {
        Self::new()
    }
}

impl Log2Product {
    /// The empty product (`Σ = 0`).
    #[must_use]
    pub const fn new() -> Self {
        Self {
            mantissa: 1.0,
            exponent: 0,
        }
    }

    /// The product of one factor `x`.
    #[inline]
    #[must_use]
    #[cfg(test)]
    pub fn of(x: f64) -> Self {
        let mut p = Self::new();
        p.push(x);
        p
    }

    /// Multiplies by `x` (adds `log₂ x` to the sum).
    #[inline]
    pub fn push(&mut self, x: f64) {
        let m = self.mantissa * x;
        // The biased exponent of `m` within ONE ± SAFE, and its sign bit clear: the
        // product is positive, normal, and exact up to its rounding (one subtraction and
        // one comparison: NaN, ±∞, zero, subnormals and negatives all fall outside)
        if (m.to_bits() >> 52).wrapping_sub(ONE - SAFE) <= 2 * SAFE {
            self.mantissa = m;
        } else {
            self.push_slow(x);
        }
    }

    /// [`Log2Product::push`] when the product would leave the safe range, or `x` is not a
    /// positive normal number: both are renormalised into `[1, 2)` first.
    #[cold]
    fn push_slow(&mut self, x: f64) {
        if !(x > 0.0 && x < f64::INFINITY) || self.mantissa.is_nan() {
            // Invalid for good: a NaN mantissa stays NaN (and out of the safe range)
            self.mantissa = f64::NAN;
            return;
        }
        let (xm, xe) = split(x);
        let (m, e) = split(self.mantissa);
        // Both in [1, 2): their product is in [1, 4), normal and exact up to one rounding
        let (pm, pe) = split(m * xm);
        self.mantissa = pm;
        self.exponent += e + xe + pe;
    }

    /// `Σ_k log₂ x_k` over the factors pushed (0 for none), or `None` when a factor was
    /// zero, negative, infinite or NaN.
    #[inline]
    #[must_use]
    pub fn log2(&self) -> Option<f64> {
        if self.mantissa.is_nan() {
            return None;
        }
        let (m, e) = split(self.mantissa);
        Some((self.exponent + e) as f64 + log2_fast(m))
    }
}

/// `x = m · 2^e` with `m ∈ [1, 2)`, for a positive finite `x` (subnormals included).
#[inline]
fn split(x: f64) -> (f64, i64) {
    let (x, bias) = if x < f64::MIN_POSITIVE {
        (x * 18_446_744_073_709_551_616.0, 64) // · 2⁶⁴: exact, and normal
    } else {
        (x, 0)
    };
    let bits = x.to_bits();
    let e = (bits >> 52) as i64 - ONE as i64 - bias;
    (f64::from_bits((bits & FRACTION) | (ONE << 52)), e)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// The direct sum of libm's logarithms, with its own error bound (each `log₂` within
    /// an ulp of its result, and the compensated sum's few roundings). The sum is
    /// compensated: a plain left-to-right sum of `k` terms can be off by `O(k u Σ|log|)`,
    /// more than this bound allows (proptest found 389 factors off by 6.3e-13 against a
    /// bound of 4.8e-13 — the reference's error, not `Log2Product`'s).
    fn direct(xs: &[f64]) -> (f64, f64) {
        let logs: alloc::vec::Vec<f64> = xs.iter().map(|&x| libm::log2(x)).collect();
        let sum = crate::math::sum(logs.iter().copied());
        let magnitude: f64 = logs.iter().map(|l| l.abs()).sum();
        (sum, 4.0 * f64::EPSILON * magnitude)
    }

    /// The documented bound on [`Log2Product::log2`] for `k` factors with sum `s`.
    fn bound(k: usize, s: f64) -> f64 {
        let u = f64::EPSILON / 2.0;
        1.46 * k as f64 * u + 2e-15 + u * s.abs()
    }

    fn check(xs: &[f64]) {
        let mut p = Log2Product::new();
        xs.iter().for_each(|&x| p.push(x));
        let got = p.log2().unwrap();
        let (want, reference_error) = direct(xs);
        let tolerance = bound(xs.len(), want) + reference_error;
        assert!(
            (got - want).abs() <= tolerance,
            "{got} vs {want} (tolerance {tolerance:e}, {} factors)",
            xs.len()
        );
    }

    proptest! {
        /// Factors of the line estimators' size (`r/R ∈ [10⁻¹², 2]`), many of them.
        #[test]
        fn equals_the_sum_of_logarithms(
            xs in proptest::collection::vec(1e-12f64..2.0, 0..400),
        ) {
            check(&xs);
        }

        /// Any positive finite factors, subnormals and huge ones included.
        #[test]
        fn any_positive_factors(
            exps in proptest::collection::vec((-1074i32..1023, 1.0f64..2.0), 0..100),
        ) {
            let xs: alloc::vec::Vec<f64> =
                exps.iter().map(|&(e, m)| libm::ldexp(m, e)).filter(|x| *x > 0.0).collect();
            check(&xs);
        }
    }

    #[test]
    fn edge_cases() {
        assert_eq!(Log2Product::new().log2(), Some(0.0));
        assert_eq!(Log2Product::of(8.0).log2(), Some(3.0));
        assert_eq!(Log2Product::of(5e-324).log2(), Some(-1074.0));
        let mut big = Log2Product::new();
        for _ in 0..10_000 {
            big.push(f64::MAX);
        }
        assert!((big.log2().unwrap() - 10_000.0 * libm::log2(f64::MAX)).abs() < 1e-9);
        for bad in [0.0, -1.0, f64::INFINITY, f64::NAN] {
            let mut p = Log2Product::of(3.0);
            p.push(bad);
            p.push(2.0);
            assert_eq!(p.log2(), None, "{bad}");
        }
    }
}
