//! The one door to `libm` and the summation helpers.
//!
//! Every transcendental function the crate uses goes through here, so native, wasm and
//! embedded builds compute bit-identical numbers (std's `f64::ln` may differ between
//! platforms; `libm` is the same Rust code everywhere).

mod clausen;
mod fast_log2;
mod fixed;
mod log_product;
mod turns;
pub(crate) use clausen::clausen2;
pub(crate) use fast_log2::log2_fast;
pub(crate) use fixed::FixedSum;
pub(crate) use log_product::Log2Product;
pub(crate) use turns::sin_cos_turns;

/// Base-2 logarithm, `log₂ x`. All entropies of the crate are in bits.
#[inline]
#[must_use]
pub fn log2(x: f64) -> f64 {
    libm::log2(x)
}

/// `−p log₂ p` with the convention `0 · log 0 = 0` (thesis §2.2.1).
///
/// ```text
/// η(p) = −p log₂ p   for p > 0,   η(0) = 0
/// ```
#[inline]
#[must_use]
pub(crate) fn eta(p: f64) -> f64 {
    if p > 0.0 { -p * libm::log2(p) } else { 0.0 }
}

/// Square root. IEEE 754 square roots are correctly rounded, so every implementation gives
/// the same bits: `libm::sqrt` (the hardware instruction on x86-64 and aarch64), except on
/// wasm32 with the `std` feature, where std's `f64::sqrt` is the `f64.sqrt` instruction and
/// libm's portable routine costs several times more.
#[inline]
#[must_use]
pub(crate) fn sqrt(x: f64) -> f64 {
    #[cfg(all(target_arch = "wasm32", feature = "std"))]
    return x.sqrt();
    #[cfg(not(all(target_arch = "wasm32", feature = "std")))]
    libm::sqrt(x)
}

/// Euclidean length `√(x² + y²)` of a vector, the same bits as glam's `DVec2::length` but
/// through [`sqrt`] (glam calls `libm::sqrt` directly, slow on wasm32).
#[inline]
#[must_use]
pub(crate) fn length(v: glam::DVec2) -> f64 {
    sqrt(v.x * v.x + v.y * v.y)
}

/// `atan2(y, x)`.
#[inline]
#[must_use]
pub(crate) fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}

/// Sine.
#[inline]
#[must_use]
pub(crate) fn sin(x: f64) -> f64 {
    libm::sin(x)
}

/// Cosine.
#[inline]
#[must_use]
pub(crate) fn cos(x: f64) -> f64 {
    libm::cos(x)
}

/// Euclidean length of `(x, y)` without undue overflow or underflow.
#[inline]
#[must_use]
pub(crate) fn hypot(x: f64, y: f64) -> f64 {
    libm::hypot(x, y)
}

/// Rounds half away from zero.
#[inline]
#[must_use]
pub(crate) fn round(x: f64) -> f64 {
    libm::round(x)
}

/// The largest integer not above `x`.
#[inline]
#[must_use]
pub(crate) fn floor(x: f64) -> f64 {
    libm::floor(x)
}

/// `x · 2^n`, exact unless the result leaves the normal range (C's `scalbn`).
#[inline]
#[must_use]
pub fn scale_by_power_of_two(x: f64, n: i32) -> f64 {
    libm::scalbn(x, n)
}

/// `⌊log₂ |x|⌋` for a finite non-zero `x` (subnormals included), from its binary exponent
/// (C's `frexp` gives `|x| = m · 2^e` with `m ∈ [½, 1)`, so `⌊log₂ |x|⌋ = e − 1`); 0 for 0,
/// infinities and NaN.
#[inline]
#[must_use]
pub(crate) fn exponent_of(x: f64) -> i32 {
    if x == 0.0 || !x.is_finite() {
        return 0;
    }
    libm::frexp(x).1 - 1
}

/// The smallest integer not below `x`.
#[inline]
#[must_use]
pub(crate) fn ceil(x: f64) -> f64 {
    libm::ceil(x)
}

/// Neumaier's compensated (Kahan–Babuška) summation.
///
/// Adding `n` terms loses at most a few ulps of the result instead of `O(n)` ulps, which
/// matters for entropies summed over 10⁵–10⁷ form factors.
#[derive(Clone, Copy, Debug, Default)]
pub struct KahanSum {
    sum: f64,
    compensation: f64,
}

impl KahanSum {
    /// An empty sum.
    #[must_use]
    pub const fn new() -> Self {
        Self {
            sum: 0.0,
            compensation: 0.0,
        }
    }

    /// Adds one term.
    #[inline]
    pub fn add(&mut self, x: f64) {
        let t = self.sum + x;
        // The lost low-order bits are recovered from whichever operand was larger. (`abs`,
        // not `libm::fabs`: the same bits, but libm's portable routine stays a call on wasm32,
        // 7 % of the 3D lab's exact cube.)
        if self.sum.abs() >= x.abs() {
            self.compensation += (self.sum - t) + x;
        } else {
            self.compensation += (x - t) + self.sum;
        }
        self.sum = t;
    }

    /// The compensated total.
    #[inline]
    #[must_use]
    pub fn total(&self) -> f64 {
        self.sum + self.compensation
    }
}

/// Compensated sum of a sequence.
#[must_use]
pub fn sum<I: IntoIterator<Item = f64>>(values: I) -> f64 {
    let mut s = KahanSum::new();
    for v in values {
        s.add(v);
    }
    s.total()
}

/// `log₂(p / q)` for `p, q > 0`, accurate to a few ulps even when `p ≈ q`.
///
/// ```text
/// log₂(p/q) = log1p((p − q)/q) / ln 2    when q/2 < p < 2q  (p − q is exact, Sterbenz)
///           = log₂(p/q)                  otherwise, or log₂ p − log₂ q if p/q leaves f64
/// ```
///
/// Rounding `p/q` first would cost all relative accuracy near 1: for `q = 1 − 10⁻¹⁰` the
/// quotient's last-bit error is 10⁻⁶ of its logarithm. Mutual-information terms
/// `p log(p/q)` of nearly independent pairs need this. Finite for any positive finite
/// inputs, including subnormals.
#[inline]
#[must_use]
pub(crate) fn log2_ratio(p: f64, q: f64) -> f64 {
    if p > 0.5 * q && p < 2.0 * q {
        libm::log1p((p - q) / q) * core::f64::consts::LOG2_E
    } else {
        let r = p / q;
        if r.is_finite() && r > 0.0 {
            libm::log2(r)
        } else {
            libm::log2(p) - libm::log2(q)
        }
    }
}

/// `x^y`.
#[inline]
#[must_use]
pub(crate) fn pow(x: f64, y: f64) -> f64 {
    libm::pow(x, y)
}

/// Natural logarithm, `ln x`.
#[inline]
#[must_use]
pub(crate) fn ln(x: f64) -> f64 {
    libm::log(x)
}

/// Natural exponential, `eˣ`.
#[inline]
#[must_use]
pub(crate) fn exp(x: f64) -> f64 {
    libm::exp(x)
}

/// Arctangent, `atan x ∈ (−π/2, π/2)`.
#[inline]
#[must_use]
pub(crate) fn atan(x: f64) -> f64 {
    libm::atan(x)
}

/// Tangent, `tan x`.
#[inline]
#[must_use]
pub(crate) fn tan(x: f64) -> f64 {
    libm::tan(x)
}

/// Arcsine, `asin x ∈ [−π/2, π/2]` for `x ∈ [−1, 1]`.
#[inline]
#[must_use]
pub(crate) fn asin(x: f64) -> f64 {
    libm::asin(x)
}

/// A uniform number in `[0, 1)` from a xorshift64 state (Marsaglia, "Xorshift RNGs", 2003:
/// shifts 13, 7, 17; the top 53 bits): the tests' cheap, reproducible random source.
#[cfg(test)]
pub(crate) fn xorshift_unit(state: &mut u64) -> f64 {
    *state ^= *state << 13;
    *state ^= *state >> 7;
    *state ^= *state << 17;
    (*state >> 11) as f64 / (1u64 << 53) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eta_handles_zero_and_one() {
        assert_eq!(eta(0.0), 0.0);
        assert_eq!(eta(1.0), 0.0);
        assert!((eta(0.5) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn compensated_sum_beats_naive() {
        // 1 + 10⁶ × 1e-16: naive summation loses every small term.
        let terms = core::iter::once(1.0).chain(core::iter::repeat_n(1e-16, 1_000_000));
        let s = sum(terms);
        assert!((s - (1.0 + 1e-10)).abs() < 1e-15, "{s}");
    }
}
