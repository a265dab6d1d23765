//! Exact, order-independent accumulation of `f64` samples in 64.64 fixed point.

/// Scale of the fixed-point representation: `2⁶⁴` (64 fractional bits).
const SCALE: f64 = 18_446_744_073_709_551_616.0;

/// Largest magnitude a single added value may have; larger values saturate.
pub(crate) const FIXED_MAX_TERM: f64 = 1.0e18;

/// A sum of `f64` values kept in 64.64 fixed point (`i128`).
///
/// Each term is rounded once to a multiple of `2⁻⁶⁴` (error ≤ 5.5e-20 per term); after
/// that, addition is exact integer arithmetic, hence associative and commutative. Monte
/// Carlo tallies built from seeded chunks therefore give bit-identical totals whatever the
/// number of threads or the order in which chunks or partial files are merged.
///
/// Range: totals up to `2⁶³ ≈ 9.2e18` in magnitude; terms beyond `FIXED_MAX_TERM` and
/// totals beyond the range saturate instead of wrapping (so no panic, no NaN), and
/// [`FixedSum::saturated`] reports it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct FixedSum {
    acc: i128,
    saturated: bool,
}

impl FixedSum {
    /// Zero.
    #[must_use]
    pub const fn new() -> Self {
        Self {
            acc: 0,
            saturated: false,
        }
    }

    /// Adds `x` (non-finite values count as saturation and are otherwise ignored).
    #[inline]
    pub fn add(&mut self, x: f64) {
        match Self::quantise(x) {
            Some(v) => self.add_raw(v),
            None => self.saturated = true,
        }
    }

    /// `x` in raw 64.64 fixed point, rounded toward zero — exactly `(x·2⁶⁴) as i128` —
    /// or `None` when `x` is not finite or beyond `FIXED_MAX_TERM`.
    ///
    /// ```text
    /// |x| = m · 2^(e − 1075)       (m the 53-bit integer significand, e the biased exponent)
    /// raw = ±⌊m · 2^(e − 1011)⌋    (a shift of m: left for e ≥ 1011, right otherwise)
    /// ```
    ///
    /// Shifting the significand truncates exactly as the conversion does, with integer
    /// operations only: no `f64 → integer` conversion, which on x86-64 is a software
    /// routine for `i128` and a chain of dependent conversions and fix-ups for `u64` (a
    /// hot spot of the line tallies: one term per segment of every line). `|x| ≤ 10¹⁸ <
    /// 2⁶⁰` keeps the left shift below 72 bits, so the result fits `i128`.
    #[inline]
    #[must_use]
    pub fn quantise(x: f64) -> Option<i128> {
        let a = x.abs();
        if !(a <= FIXED_MAX_TERM) {
            return None;
        }
        let bits = a.to_bits();
        let biased = (bits >> 52) as i32; // the sign bit of |x| is 0
        let fraction = bits & ((1u64 << 52) - 1);
        // Subnormals have no implicit bit and the exponent of the smallest normals.
        let (m, biased) = if biased == 0 {
            (fraction, 1)
        } else {
            (fraction | (1u64 << 52), biased)
        };
        let shift = biased - 1011;
        let v = if shift >= 0 {
            i128::from(m) << shift
        } else if shift > -64 {
            i128::from(m >> -shift)
        } else {
            0
        };
        Some(if x < 0.0 { -v } else { v })
    }

    /// Adds a term already quantised by [`FixedSum::quantise`].
    #[inline]
    pub fn add_quantised(&mut self, v: i128) {
        self.add_raw(v);
    }

    #[inline]
    fn add_raw(&mut self, v: i128) {
        match self.acc.checked_add(v) {
            Some(a) => self.acc = a,
            None => {
                self.acc = if v > 0 { i128::MAX } else { i128::MIN };
                self.saturated = true;
            }
        }
    }

    /// Adds another sum exactly.
    #[inline]
    pub fn merge(&mut self, other: &FixedSum) {
        self.saturated |= other.saturated;
        self.add_raw(other.acc);
    }

    /// The total as `f64` (one rounding).
    #[must_use]
    pub fn value(&self) -> f64 {
        self.acc as f64 / SCALE
    }

    /// The raw 64.64 fixed-point total (for serialising partial results).
    #[must_use]
    pub fn raw(&self) -> i128 {
        self.acc
    }

    /// Rebuilds a sum from [`FixedSum::raw`].
    #[must_use]
    pub const fn from_raw(raw: i128) -> Self {
        Self {
            acc: raw,
            saturated: false,
        }
    }

    /// Rebuilds a sum from [`FixedSum::raw`] and [`FixedSum::saturated`].
    #[must_use]
    pub const fn from_raw_parts(raw: i128, saturated: bool) -> Self {
        Self {
            acc: raw,
            saturated,
        }
    }

    /// Whether a term or the total ever left the representable range.
    #[must_use]
    pub fn saturated(&self) -> bool {
        self.saturated
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn order_independent_and_accurate() {
        let xs = [1.5, -2.25e-7, 3.0e5, -0.1, 7.0 / 3.0, -3.0e5];
        let mut a = FixedSum::new();
        xs.iter().for_each(|&x| a.add(x));
        let mut b = FixedSum::new();
        xs.iter().rev().for_each(|&x| b.add(x));
        assert_eq!(a, b);
        let exact: f64 = 1.5 - 2.25e-7 - 0.1 + 7.0 / 3.0;
        assert!((a.value() - exact).abs() < 1e-15);
    }

    #[test]
    fn quantise_is_the_i128_truncation() {
        let mut rng = crate::lines::chunk_rng(5, 1);
        for k in 0..100_000 {
            let u = crate::lines::canonical(&mut rng);
            // Magnitudes from 1e-30 to 1e18, both signs, and some integers.
            let mut x = libm::pow(10.0, -30.0 + 48.0 * u);
            if k % 3 == 0 {
                x = -x;
            }
            if k % 7 == 0 {
                x = libm::trunc(x);
            }
            assert_eq!(FixedSum::quantise(x), Some((x * SCALE) as i128), "{x:e}");
        }
        for x in [
            0.0,
            -0.0,
            1.0,
            -1.0,
            FIXED_MAX_TERM,
            -FIXED_MAX_TERM,
            0.5,
            -2.5e-20,
            // Around the shift's turning points: a·2⁶⁴ near 1 and 2⁵², subnormals.
            libm::ldexp(1.0, -12),
            libm::ldexp(1.0, -12) * (1.0 - f64::EPSILON),
            libm::ldexp(1.0, -64),
            libm::ldexp(1.0, -64) * (1.0 - f64::EPSILON),
            -libm::ldexp(1.0, -75),
            f64::MIN_POSITIVE,
            5e-324,
            libm::ldexp(1.0, 59) - 1.0,
        ] {
            assert_eq!(FixedSum::quantise(x), Some((x * SCALE) as i128), "{x:e}");
        }
        assert_eq!(FixedSum::quantise(f64::NAN), None);
        assert_eq!(FixedSum::quantise(f64::INFINITY), None);
        assert_eq!(FixedSum::quantise(2.0 * FIXED_MAX_TERM), None);
    }

    #[test]
    fn saturates_instead_of_wrapping() {
        let mut a = FixedSum::new();
        a.add(f64::NAN);
        assert!(a.saturated());
        let mut b = FixedSum::new();
        for _ in 0..20 {
            b.add(9.0e17);
        }
        assert!(b.saturated() && b.value() > 0.0);
    }
}
