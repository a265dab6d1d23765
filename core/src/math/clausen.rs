//! The Clausen function `Cl₂`, needed for the closed-form inner integral of the
//! continuous-mutual-information quadrature (`∫ cos²φ ln cos φ dφ` is not elementary).

use core::f64::consts::PI;

/// `ζ(2n) / (n (2n + 1))` for `n = 1, …, 28`: the coefficients of the series below
/// (computed with 40-digit arithmetic; a unit test recomputes them from `ζ`).
const SERIES: [f64; 28] = [
    0.548_311_355_616_075_5,
    0.108_232_323_371_113_83,
    0.048_444_907_713_545_2,
    0.027_891_037_672_165_12,
    0.018_199_901_365_960_33,
    0.012_823_667_776_324_462,
    0.009_524_392_839_381_512,
    0.007_353_053_546_025_064,
    0.005_847_975_539_726_696,
    0.004_761_909_304_581_114,
    0.003_952_570_112_452_58,
    0.003_333_333_532_027_296_7,
    0.002_849_002_891_457_421,
    0.002_463_054_196_367_818,
    0.002_150_537_636_411_456_6,
    0.001_893_939_394_380_362,
    0.001_680_672_269_005_391_1,
    0.001_501_501_501_523_351_2,
    0.001_349_527_665_322_048_6,
    0.001_219_512_195_123_060_4,
    0.001_107_419_712_071_126_6,
    0.001_010_101_010_101_067_6,
    0.000_925_069_380_203_528_4,
    0.000_850_340_136_054_424_8,
    0.000_784_313_725_490_196_8,
    0.000_725_689_404_934_688_2,
    0.000_673_400_673_400_673_4,
    0.000_626_566_416_040_100_2,
];

/// The Clausen function
///
/// ```text
/// Cl₂(θ) = −∫₀^θ ln|2 sin(t/2)| dt = Σ_{k≥1} sin(kθ) / k²
/// ```
///
/// odd and `2π`-periodic, with `Cl₂(π/2) = G` (Catalan's constant) and its maximum
/// `Cl₂(π/3) = 1.0149…`. For `|θ| ≤ π` it is summed as (Abramowitz & Stegun 27.8.2, with
/// `|B₂ₙ| = 2 (2n)! ζ(2n) / (2π)²ⁿ`)
///
/// ```text
/// Cl₂(θ) = θ − θ ln|θ| + θ Σ_{n≥1} ζ(2n) / (n (2n + 1)) · (θ / 2π)²ⁿ
/// ```
///
/// whose terms shrink at least fourfold each, so 28 terms reach the rounding level;
/// other arguments are first reduced by periodicity. Absolute error about `10⁻¹⁵` on
/// `[−π, π]`; NaN in, NaN out; 0 for infinite `θ` (no meaningful value).
///
/// Used for `∫₀^θ ln cos φ dφ = −θ ln 2 + ½ Cl₂(π − 2θ)` on `|θ| < π/2`.
#[must_use]
pub(crate) fn clausen2(theta: f64) -> f64 {
    if theta.is_nan() {
        return theta;
    }
    if !theta.is_finite() {
        return 0.0;
    }
    // Reduce to (−π, π] by periodicity, then to [0, π] by oddness.
    let two_pi = 2.0 * PI;
    let mut x = theta - two_pi * libm::floor(theta / two_pi + 0.5);
    let sign = if x < 0.0 { -1.0 } else { 1.0 };
    x = libm::fabs(x);
    if x == 0.0 {
        return 0.0;
    }
    let z = (x / two_pi) * (x / two_pi);
    // Horner in z over the series coefficients.
    let tail = SERIES.iter().rev().fold(0.0, |acc, &c| (acc + c) * z);
    sign * x * (1.0 - libm::log(x) + tail)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_values() {
        // Catalan's constant and the maximum Cl₂(π/3), rounded to f64.
        let catalan = 0.915_965_594_177_219;
        assert!((clausen2(PI / 2.0) - catalan).abs() < 2e-15);
        assert!((clausen2(PI / 3.0) - 1.014_941_606_409_653_6).abs() < 2e-15);
        // mpmath clsin(2, x) for x = 0.1 and 3.0.
        assert!((clausen2(0.1) - 0.330_272_398_882_816_6).abs() < 2e-15);
        assert!((clausen2(3.0) - 0.098_026_209_391_301_42).abs() < 2e-15);
        assert_eq!(clausen2(0.0), 0.0);
        assert!(clausen2(PI).abs() < 1e-15);
    }

    #[test]
    fn symmetries() {
        for k in 1..50 {
            let x = 0.123 * f64::from(k);
            assert!((clausen2(-x) + clausen2(x)).abs() < 1e-15);
            assert!((clausen2(x + 2.0 * PI) - clausen2(x)).abs() < 1e-13);
        }
        assert!(clausen2(f64::NAN).is_nan());
        assert_eq!(clausen2(f64::INFINITY), 0.0);
    }

    #[test]
    fn series_coefficients_are_zeta_over_n_two_n_plus_one() {
        // ζ(2n) summed directly (tail below 10⁻¹⁸ for n ≥ 2 with 10⁵ terms and an integral
        // tail estimate); ζ(2) = π²/6.
        for (i, &c) in SERIES.iter().enumerate() {
            let n = i as i32 + 1;
            let zeta = if n == 1 {
                PI * PI / 6.0
            } else {
                let m = 100_000.0f64;
                let head: f64 = (1..100_000).rev().map(|k| (k as f64).powi(-2 * n)).sum();
                head + m.powi(1 - 2 * n) / f64::from(2 * n - 1) + 0.5 * m.powi(-2 * n)
            };
            let expected = zeta / f64::from(n * (2 * n + 1));
            assert!(
                (c / expected - 1.0).abs() < 1e-14,
                "n = {n}: {c} vs {expected}"
            );
        }
    }

    #[test]
    fn log_cos_integral() {
        // ∫₀^θ ln cos φ dφ = −θ ln 2 + ½ Cl₂(π − 2θ), against mpmath quad.
        let cases = [
            (0.3, -0.004_541_209_400_788_73),
            (1.2, -0.347_288_709_293_154),
            (-0.7, 0.060_264_100_649_734_9),
            (1.5, -0.830_511_999_718_837),
        ];
        for (theta, expected) in cases {
            let got = -theta * core::f64::consts::LN_2 + 0.5 * clausen2(PI - 2.0 * theta);
            assert!(
                (got - expected).abs() < 1e-14,
                "{theta}: {got} vs {expected}"
            );
        }
    }
}
