//! Sample positions inside a pixel that stay well spread at every count: the first two
//! dimensions of the Sobol' sequence, a (0, 2)-sequence in base 2, with a random digit
//! scramble per pixel.
//!
//! ```text
//! x_i = (bitreverse(i) ⊕ s_x) / 2³²          van der Corput, radix 2
//! y_i = (P · bits(i)   ⊕ s_y) / 2³²          Sobol' dimension 2: P = Pascal's triangle mod 2
//! ```
//!
//! Any `2^m` consecutive points from index `0` form a (0, m, 2)-net: each elementary box
//! of area `2^−m` holds exactly one point — in particular the four quadrants of the pixel
//! hold `N/4` each for `N = 4, 8, 16, …`, which the mutual-information contrast relies
//! on. XOR-ing the digits with a fixed random word per pixel (random digit scrambling,
//! Kollig & Keller 2002, "Efficient multidimensional sampling") keeps that property and
//! makes each point uniformly distributed, so a pixel's mean over `N` samples is an
//! unbiased estimate (Owen 1997). A renderer that gives a pixel more samples takes the
//! next indices of the same sequence: uniform and adaptive renders then differ only in how
//! many samples each pixel gets.

/// The `i`-th point of the scrambled sequence in `[0, 1)²`; `scramble` holds the two
/// random words of the pixel.
#[must_use]
pub fn sobol_2d(i: u32, scramble: [u32; 2]) -> [f64; 2] {
    // Dimension 2: Σ over the set bits k of i of the direction word v_k, v_0 = 2³¹,
    // v_{k+1} = v_k ⊕ (v_k >> 1) (the columns of Pascal's triangle mod 2)
    let (mut y, mut v, mut bits) = (0u32, 1u32 << 31, i);
    while bits != 0 {
        if bits & 1 == 1 {
            y ^= v;
        }
        bits >>= 1;
        v ^= v >> 1;
    }
    let x = i.reverse_bits();
    let unit = |w: u32| f64::from(w) * (1.0 / 4_294_967_296.0);
    [unit(x ^ scramble[0]), unit(y ^ scramble[1])]
}

/// A pixel's two scramble words from a seed and the pixel's index (SplitMix64 of both, so
/// neighbouring pixels and seeds give unrelated words).
#[must_use]
pub fn pixel_scramble(seed: u64, pixel: u64) -> [u32; 2] {
    let w = split_mix(split_mix(seed) ^ pixel);
    [(w >> 32) as u32, w as u32]
}

/// SplitMix64's output function (Steele, Lea & Flood 2014).
fn split_mix(x: u64) -> u64 {
    let mut z = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every elementary box of area 2^-m holds one of the first 2^m points.
    #[test]
    fn prefixes_are_nets() {
        for seed in 0..4u64 {
            let s = pixel_scramble(seed, 7);
            for m in 0..=8u32 {
                for kx in 0..=m {
                    let ky = m - kx;
                    let mut seen = [false; 256];
                    for i in 0..(1u32 << m) {
                        let [x, y] = sobol_2d(i, s);
                        let cx = (x * f64::from(1u32 << kx)) as usize;
                        let cy = (y * f64::from(1u32 << ky)) as usize;
                        let cell = cx + (cy << kx);
                        assert!(!seen[cell], "m {m} box {kx}x{ky} cell {cell} twice");
                        seen[cell] = true;
                    }
                }
            }
        }
    }
}
