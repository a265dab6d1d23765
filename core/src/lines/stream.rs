//! Seeded, splittable random streams: a job of `N` lines cut into fixed-size chunks.
//!
//! Chunk `k` covers line indices `k·C .. min((k+1)·C, N)` with `C =` [`CHUNK_LINES`] and
//! draws from its own generator [`chunk_rng`]`(seed, k)`. Whoever runs the chunks — one
//! thread or many, in any order — the lines drawn are the same, so every estimate depends
//! on `(seed, N)` only (DESIGN.md, "Randomness"; pbrt `RNG::SetSequence`).

use core::ops::Range;

use rand_core::Rng;
use rand_pcg::Pcg64;

/// Lines per seeded chunk: the unit of work (and of reproducibility) of a line job.
pub(crate) const CHUNK_LINES: u64 = 1 << 16;

/// SplitMix64's finaliser (Steele, Lea & Flood 2014): a bijection of `u64` that spreads
/// every input bit over every output bit.
#[inline]
#[must_use]
pub(crate) const fn mix64(z: u64) -> u64 {
    let z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    let z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// The independent generator of chunk `chunk` of the job seeded with `seed`.
///
/// ```text
/// Pcg64::new(state = h(seed, chunk), stream = chunk)
/// ```
///
/// The stream (PCG increment) is the chunk index, as in pbrt's `RNG::SetSequence`. The
/// 128-bit starting state is a SplitMix64 hash of both the seed and the chunk: PCG streams
/// that start from the *same* state with different increments are visibly correlated
/// (their LCG states differ by a fixed affine sequence), so the state is decorrelated too.
/// Different seeds, or different chunks of one seed, give different streams.
///
/// # Examples
///
/// ```
/// use rand_core::Rng;
/// use sceneinfo::lines::chunk_rng;
///
/// let (mut a, mut b) = (chunk_rng(7, 3), chunk_rng(7, 3));
/// assert_eq!(a.next_u64(), b.next_u64());
/// assert_ne!(chunk_rng(7, 3).next_u64(), chunk_rng(7, 4).next_u64());
/// ```
#[must_use]
pub fn chunk_rng(seed: u64, chunk: u64) -> Pcg64 {
    let hi = mix64(mix64(seed) ^ chunk);
    let lo = mix64(hi ^ 0x6A09_E667_F3BC_C908);
    let state = (u128::from(hi) << 64) | u128::from(lo);
    Pcg64::new(state, u128::from(chunk))
}

/// Number of chunks of a job of `n_lines` lines: `⌈n_lines / CHUNK_LINES⌉`.
#[inline]
#[must_use]
pub(crate) const fn chunk_count(n_lines: u64) -> u64 {
    n_lines.div_ceil(CHUNK_LINES)
}

/// The line indices chunk `chunk` of a job of `n_lines` lines draws:
///
/// ```text
/// k·C .. min((k+1)·C, N)        (empty, N..N, for k ≥ chunk_count(N))
/// ```
#[inline]
#[must_use]
pub(crate) const fn chunk_range(n_lines: u64, chunk: u64) -> Range<u64> {
    let start = match chunk.checked_mul(CHUNK_LINES) {
        Some(s) if s < n_lines => s,
        _ => return n_lines..n_lines,
    };
    let end = start.saturating_add(CHUNK_LINES);
    start..if end < n_lines { end } else { n_lines }
}

/// A canonical sample: uniform in `[0, 1)` on the grid `k·2⁻⁵³` (53 random bits, the top
/// bits of one `next_u64`, which are PCG's best).
#[inline]
#[must_use]
pub fn canonical<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    // 2⁻⁵³ exactly: every k < 2⁵³ times it is exact, so the result is < 1.
    const SCALE: f64 = 1.0 / (1u64 << 53) as f64;
    (rng.next_u64() >> 11) as f64 * SCALE
}

/// Two canonical samples `[u₀, u₁]`, drawn in that order.
#[inline]
#[must_use]
pub(crate) fn canonical_2d<R: Rng + ?Sized>(rng: &mut R) -> [f64; 2] {
    let u0 = canonical(rng);
    [u0, canonical(rng)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_and_chunk_give_same_stream() {
        let (mut a, mut b) = (chunk_rng(42, 5), chunk_rng(42, 5));
        for _ in 0..1000 {
            assert_eq!(a.next_u64(), b.next_u64());
        }
    }

    #[test]
    fn different_chunks_and_seeds_give_different_streams() {
        // First 64 outputs of 64 chunks × 4 seeds: no output repeats anywhere, and no two
        // streams agree in any position (a shared or shifted stream would).
        let mut firsts: [u64; 256] = [0; 256];
        for seed in 0..4u64 {
            for chunk in 0..64u64 {
                let mut rng = chunk_rng(seed, chunk);
                let first = rng.next_u64();
                firsts[(seed * 64 + chunk) as usize] = first;
                let mut other = chunk_rng(seed, chunk + 1);
                let mut equal = 0;
                for _ in 0..64 {
                    if rng.next_u64() == other.next_u64() {
                        equal += 1;
                    }
                }
                assert_eq!(equal, 0, "seed {seed} chunk {chunk}");
            }
        }
        firsts.sort_unstable();
        assert!(firsts.windows(2).all(|w| w[0] != w[1]));
        // A chunk's stream is not the next chunk's stream shifted by a few steps.
        let mut a = chunk_rng(9, 0);
        let xs: [u64; 8] = core::array::from_fn(|_| a.next_u64());
        let mut b = chunk_rng(9, 1);
        for _ in 0..10_000 {
            assert!(!xs.contains(&b.next_u64()));
        }
    }

    #[test]
    fn streams_are_statistically_independent() {
        // Correlation of paired canonical samples of neighbouring chunks: |ρ| ≈ 1/√n.
        let n = 200_000;
        let (mut a, mut b) = (chunk_rng(1, 10), chunk_rng(1, 11));
        let (mut sxy, mut sx, mut sy, mut sxx, mut syy) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for _ in 0..n {
            let (x, y) = (canonical(&mut a), canonical(&mut b));
            sx += x;
            sy += y;
            sxy += x * y;
            sxx += x * x;
            syy += y * y;
        }
        let nf = f64::from(n);
        let cov = sxy / nf - (sx / nf) * (sy / nf);
        let rho = cov
            / crate::math::sqrt((sxx / nf - (sx / nf).powi(2)) * (syy / nf - (sy / nf).powi(2)));
        assert!(rho.abs() < 5.0 / crate::math::sqrt(nf), "rho = {rho}");
        assert!((sx / nf - 0.5).abs() < 5.0 * crate::math::sqrt(1.0 / 12.0 / nf));
    }

    #[test]
    fn chunks_tile_the_job() {
        for n in [
            0,
            1,
            CHUNK_LINES - 1,
            CHUNK_LINES,
            CHUNK_LINES + 1,
            5 * CHUNK_LINES + 17,
        ] {
            let k = chunk_count(n);
            let mut next = 0;
            for c in 0..k {
                let r = chunk_range(n, c);
                assert_eq!(r.start, next);
                assert!(!r.is_empty() && r.end - r.start <= CHUNK_LINES);
                next = r.end;
            }
            assert_eq!(next, n);
            assert!(chunk_range(n, k).is_empty());
        }
        assert_eq!(chunk_count(u64::MAX), u64::MAX / CHUNK_LINES + 1);
        assert_eq!(chunk_range(u64::MAX, u64::MAX), u64::MAX..u64::MAX);
        let last = chunk_range(u64::MAX, u64::MAX / CHUNK_LINES);
        assert_eq!(last.end, u64::MAX);
    }

    #[test]
    fn canonical_is_in_unit_interval() {
        struct Fixed(u64);
        impl rand_core::TryRng for Fixed {
            type Error = core::convert::Infallible;
            fn try_next_u32(&mut self) -> Result<u32, Self::Error> {
                Ok(self.0 as u32)
            }
            fn try_next_u64(&mut self) -> Result<u64, Self::Error> {
                Ok(self.0)
            }
            fn try_fill_bytes(&mut self, _: &mut [u8]) -> Result<(), Self::Error> {
                Ok(())
            }
        }
        assert_eq!(canonical(&mut Fixed(0)), 0.0);
        let top = canonical(&mut Fixed(u64::MAX));
        assert!(top < 1.0 && top == crate::lines::ONE_MINUS_EPSILON);
    }
}
