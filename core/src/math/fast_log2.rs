//! A table-driven base-2 logarithm for the Monte Carlo sample terms.

use core::f64::consts::LOG2_E;

/// Table size: the top `TABLE_BITS` bits of the mantissa pick the entry.
const TABLE_BITS: u32 = 7;
const TABLE_LEN: usize = 1 << TABLE_BITS;

/// `ln c` for `c ∈ [1, 2)` by the series `ln c = 2 Σ z^(2n+1)/(2n+1)`, `z = (c−1)/(c+1) ≤ ⅓`
/// (30 terms: the tail is below `3⁻⁶¹`), evaluated at compile time.
const fn ln_series(c: f64) -> f64 {
    let z = (c - 1.0) / (c + 1.0);
    let z2 = z * z;
    let mut term = z;
    let mut sum = 0.0;
    let mut n = 0;
    while n < 30 {
        sum += term / (2 * n + 1) as f64;
        term *= z2;
        n += 1;
    }
    2.0 * sum
}

/// Entry `k`: the centre `c_k = 1 + (k + ½)/128` of the `k`-th mantissa interval, `1/c_k` and
/// `log₂ c_k`.
const TABLE: [(f64, f64, f64); TABLE_LEN] = {
    let mut t = [(0.0, 0.0, 0.0); TABLE_LEN];
    let mut k = 0;
    while k < TABLE_LEN {
        let c = 1.0 + (k as f64 + 0.5) / TABLE_LEN as f64;
        t[k] = (c, 1.0 / c, ln_series(c) * LOG2_E);
        k += 1;
    }
    t
};

/// `log₂ x`, table-driven: within `2·10⁻¹⁵ · max(1, |log₂ x|)` of libm's `log2` (tested),
/// for the per-sample terms of the line estimators, where it is a hot spot.
///
/// ```text
/// x = 2^e m, m ∈ [1, 2);  k = the top 7 bits of m's fraction;  r = (m − c_k)/c_k, |r| ≤ 2⁻⁸
/// log₂ x = e + log₂ c_k + ln(1 + r)·log₂ e,   ln(1 + r) = Σ_{n=1..7} (−1)^(n+1) rⁿ/n
/// ```
///
/// `m − c_k` is exact (Sterbenz); the series' truncation is below `2⁻⁶⁴/8`. Zero, negative,
/// subnormal and non-finite `x` go to libm's `log2`.
#[inline]
#[must_use]
pub(crate) fn log2_fast(x: f64) -> f64 {
    if !(f64::MIN_POSITIVE..f64::INFINITY).contains(&x) {
        return libm::log2(x);
    }
    let bits = x.to_bits();
    let e = ((bits >> 52) as i64 - 1023) as f64;
    let m = f64::from_bits((bits & ((1u64 << 52) - 1)) | (1023u64 << 52));
    let k = ((bits >> (52 - TABLE_BITS)) as usize) & (TABLE_LEN - 1);
    let (c, inv_c, log2_c) = TABLE[k];
    let r = (m - c) * inv_c;
    let ln1p = r
        * (1.0
            + r * (-0.5
                + r * (1.0 / 3.0 + r * (-0.25 + r * (0.2 + r * (-1.0 / 6.0 + r * (1.0 / 7.0)))))));
    e + (log2_c + ln1p * LOG2_E)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn agrees_with_libm() {
        let mut rng = crate::lines::chunk_rng(8, 0);
        let mut worst: f64 = 0.0;
        for _ in 0..300_000 {
            let u = crate::lines::canonical(&mut rng);
            let v = crate::lines::canonical(&mut rng);
            let x = (1.0 + v) * libm::exp2(libm::floor(-300.0 + 600.0 * u));
            let (a, b) = (log2_fast(x), libm::log2(x));
            worst = worst.max((a - b).abs() / b.abs().max(1.0));
        }
        // Near 1 (log₂ x ≈ 0) and at the table's interval edges.
        for k in 0..=4096 {
            let x = 1.0 + f64::from(k) / 4096.0 * 0.999_999_999;
            let (a, b) = (log2_fast(x), libm::log2(x));
            worst = worst.max((a - b).abs());
            let y = 1.0 - f64::from(k) * 1e-7;
            worst = worst.max((log2_fast(y) - libm::log2(y)).abs());
        }
        assert!(worst < 2e-15, "worst {worst:e}");
        assert_eq!(log2_fast(1.0), 0.0);
        assert_eq!(log2_fast(8.0), 3.0);
        assert_eq!(log2_fast(0.0), f64::NEG_INFINITY);
        assert!(log2_fast(-1.0).is_nan() && log2_fast(f64::NAN).is_nan());
        assert_eq!(log2_fast(f64::INFINITY), f64::INFINITY);
        assert_eq!(log2_fast(5e-324), libm::log2(5e-324));
    }
}
