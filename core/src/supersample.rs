//! Entropy-based adaptive pixel **supersampling** (thesis §7.3, "Pixel adaptive supersampling
//! [65, 69, 68]"): an oracle a renderer calls per pixel with the samples it has, answering
//! *refine* or *stop* by an information-theoretic contrast of those samples.
//!
//! The thesis names two contrasts: "the first one is based on entropy, which measures the
//! homogeneity of a pixel. And the second one is based on the difference between continuous
//! and discrete mutual information field, which measures the distance to the ideal
//! representation" (§7.3). Its refs. 65, 68 and 69 (Rigau, Feixas & Sbert, SCCG 2001,
//! EGWR 2002 posters, CGI 2002) give the definitions; their texts could not be read here
//! (only abstracts and a public implementation's comments were reachable), so the
//! definitions below are stated in full, with where each piece comes from, and
//! `docs/supersampling.md` says what is the papers' and what is ours.
//!
//! ## Entropy contrast (ref. 68)
//!
//! The `N` samples of one colour channel `c` with values `c_j ≥ 0` are read as a
//! distribution over the samples, and its entropy compared with the largest possible,
//! `log N` (a constant pixel):
//!
//! ```text
//! p_j = c_j / Σ_k c_k                       H_c = −Σ_j p_j log₂ p_j
//! C_c = 1 − H_c / log₂ N  ∈ [0, 1]          channel contrast
//! C_H = Σ_c w_c C_c c̄_c                     pixel colour contrast, w = (0.2126, 0.7152, 0.0722)
//! ```
//!
//! `H_c`, `C_c` and `C_H` are the equations (6), (7) and (8) of Rigau, Feixas & Sbert,
//! "Entropy-based adaptive sampling" (Graphics Interface 2003, the journal version of
//! ref. 68), as a public implementation of that paper quotes them (lucille's
//! `entropy_as.c`): the pixel colour contrast weights each channel's contrast by a
//! perceptual coefficient (`0.213, 0.715, 0.072`; we use the Rec. 709 luminance weights
//! they round, which sum to 1, so eq. 8's division by `Σ w_c` is void) *and by the
//! channel's mean colour `c̄_c`*. The samples are **display-referred**: `1` is white (the
//! renderer's exposure already applied), and a mean above `1` counts as `1`, so `C_H ∈
//! [0, 1]`. The mean colour is what ties the contrast to the visible error: `C_c` alone is
//! invariant under scaling the channel, so an edge between two near-blacks scores as high
//! as one between grey and white, while its error in the picture is far smaller (measured:
//! leaving out `c̄_c` made adaptive sampling lose to uniform on the Cornell box,
//! `docs/supersampling.md`). `C_c = 0` when a channel is zero everywhere or `N < 2`;
//! `C_H` is exactly `0` for a constant pixel. `1 − H/log N` is also `D(p ‖ u) / log₂ N`,
//! the Kullback–Leibler divergence of the samples' light from the uniform spread a
//! constant pixel would have.
//!
//! ## Mutual-information contrast (ref. 69, as read here)
//!
//! The pixel as a channel between its area and the light it receives (the thesis' scene
//! channel, 3.1–3.5, with "patch" read as "sub-pixel"): `X` is the pixel's quadrant (the
//! cells one refinement step creates), with the share of samples `a_g = n_g / N` as its
//! area; the output is the colour channel `c` of a unit of luminous power,
//!
//! ```text
//! p(g, c) = w_c Σ_{j ∈ g} c_j / Σ_{k,c'} w_c' c'_k          luminous power of quadrant g, channel c
//! I_d = Σ_{g,c} p(g, c) log₂( p(g, c) / (a_g p(c)) )        = D(q ‖ a) + I(X; C),  q_g = Σ_c p(g, c)
//! C_I = Y · I_d / log₂(1 / min_g a_g)  ∈ [0, 1],   Y = min(1, Σ_c w_c c̄_c)
//! ```
//!
//! `a_g p(c)` is the pixel as displayed — one colour spread evenly over its area (the
//! "ideal representation" a pixel can give); `I_d` is the information the quadrants carry
//! beyond it: the discrete mutual information of the refined pixel, i.e. the gain of one
//! refinement step (the thesis' Proposition 3 for splitting a state, 5.32–5.44). The
//! continuous version, every sample its own cell, is bounded by `log₂ N − H` of the power
//! distribution; grouping samples into quadrants can only lose information (log-sum
//! inequality, 2.67), so `0 ≤ I_d ≤ I^c`, and `I^c − I_d` is what one step would still
//! miss. Unlike `C_H`, `C_I` ignores variation *within* quadrants: uncorrelated noise
//! spread evenly scores low, an edge or a shadow boundary through the pixel high. The
//! bound `I_d ≤ Σ p(g,c) log₂(1/a_g) ≤ log₂(1/min a_g)` makes `C_I ≤ 1`; it is `2` bits for
//! four equally sampled quadrants. The factor `Y`, the pixel's mean display luminance,
//! is eq. 8's mean-colour weighting carried over (same reason: an edge between near-blacks
//! is information but little visible error).
//!
//! ## Verdict and defaults
//!
//! A pixel is refined when its contrast exceeds the threshold; a constant pixel has
//! contrast exactly `0` and is never refined (the threshold is at least `0`). The papers'
//! threshold values could not be read; the defaults ([`DEFAULT_ENTROPY_THRESHOLD`],
//! `DEFAULT_MI_THRESHOLD`) are ours and their reasons are on the constants. Both
//! contrasts also need a pixel's *first* samples to see its edge; a renderer should compare
//! a pixel's samples with its neighbours' as well (the demonstration renderer does,
//! [`render3::RenderOptions::neighbours`]).
//!
//! Nothing here allocates: the samples are the caller's slices.

#[cfg(feature = "alloc")]
pub mod render3;
pub mod sequence;

use crate::error::{Error, ErrorKind, Result};
use crate::math;

/// Luminance weights of the red, green and blue channels (ITU-R BT.709; the perceptual
/// coefficients of the colour contrast of Rigau, Feixas & Sbert 2003, eq. 8, round them to
/// `0.213, 0.715, 0.072`). They sum to 1.
pub(crate) const LUMINANCE_WEIGHTS: [f64; 3] = [0.2126, 0.7152, 0.0722];

/// Default threshold of the entropy contrast: `0.02`. Ours, not the papers' (not
/// readable here). Meaning: a pixel split in halves between black and a grey of display
/// value `v` has `C_H = v / (2 log₂ N)`; `0.02` refines it while `v > 0.04 log₂ N` — at
/// 4 samples any edge brighter than `0.08` (about a fifth of the way up the sRGB curve),
/// at 16 samples one brighter than `0.16`; so faint edges stop early and bright ones go on
/// to the renderer's cap. Chosen after the measurements of `docs/supersampling.md`, which
/// show every threshold tried in `[0.01, 0.05]` beating uniform sampling on the Cornell box
/// at 2 resolutions and 2 budgets, so it is not a value tuned to one case.
pub const DEFAULT_ENTROPY_THRESHOLD: f64 = 0.02;

/// Default threshold of the mutual-information contrast: `0.02`, as for the entropy
/// contrast. Meaning: a pixel split in halves along a quadrant boundary between black and
/// a grey of display value `v` has `C_I = v/2 · 1/2 = v/4`, whatever `N`; `0.02` refines it
/// while `v > 0.08`.
pub(crate) const DEFAULT_MI_THRESHOLD: f64 = 0.02;

/// Which contrast the oracle computes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContrastMeasure {
    /// The entropy contrast `C_H` (ref. 68; module docs).
    Entropy,
    /// The mutual-information contrast `C_I` (ref. 69 as read here; module docs).
    MutualInformation,
}

impl ContrastMeasure {
    /// The spelling the CLI chooses it by: `entropy`, `mi`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Entropy => "entropy",
            Self::MutualInformation => "mi",
        }
    }
}

/// The oracle's answer for one pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// The samples are not homogeneous enough: take more.
    Refine,
    /// The samples represent the pixel well enough.
    Stop,
}

/// The refine-or-stop oracle: a contrast measure and its threshold.
///
/// # Examples
///
/// ```
/// use sceneinfo::supersample::{Oracle, Verdict};
///
/// let oracle = Oracle::entropy();
/// let grey = [[0.5, 0.5, 0.5]; 4];
/// let edge = [[1.0, 1.0, 1.0], [0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [0.0, 0.0, 0.0]];
/// let at = [[0.25, 0.25], [0.75, 0.25], [0.25, 0.75], [0.75, 0.75]];
/// assert_eq!(oracle.decide_rgb(&grey, &at), Verdict::Stop);
/// assert_eq!(oracle.decide_rgb(&edge, &at), Verdict::Refine);
/// assert_eq!(Oracle::mutual_information().decide_rgb(&edge, &at), Verdict::Refine);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Oracle {
    measure: ContrastMeasure,
    threshold: f64,
}

impl Oracle {
    /// The entropy contrast with [`DEFAULT_ENTROPY_THRESHOLD`].
    #[must_use]
    pub const fn entropy() -> Self {
        Self {
            measure: ContrastMeasure::Entropy,
            threshold: DEFAULT_ENTROPY_THRESHOLD,
        }
    }

    /// The mutual-information contrast with `DEFAULT_MI_THRESHOLD`.
    #[must_use]
    pub const fn mutual_information() -> Self {
        Self {
            measure: ContrastMeasure::MutualInformation,
            threshold: DEFAULT_MI_THRESHOLD,
        }
    }

    /// `measure` with its default threshold.
    #[must_use]
    pub const fn of(measure: ContrastMeasure) -> Self {
        match measure {
            ContrastMeasure::Entropy => Self::entropy(),
            ContrastMeasure::MutualInformation => Self::mutual_information(),
        }
    }

    /// The same measure with threshold `t`: refine when the contrast exceeds `t`.
    ///
    /// # Errors
    /// [`ErrorKind::BadParameter`] unless `0 ≤ t ≤ 1` (contrasts lie in `[0, 1]`; `t = 1`
    /// never refines).
    pub fn with_threshold(self, t: f64) -> Result<Self> {
        if !(0.0..=1.0).contains(&t) {
            return Err(Error::new(ErrorKind::BadParameter {
                name: "contrast threshold",
                value: t,
            }));
        }
        Ok(Self {
            threshold: t,
            ..self
        })
    }

    /// The contrast measure.
    #[must_use]
    pub const fn measure(&self) -> ContrastMeasure {
        self.measure
    }

    /// The threshold.
    #[must_use]
    pub const fn threshold(&self) -> f64 {
        self.threshold
    }

    /// The contrast of RGB samples; `positions[j]` is sample `j`'s position in the pixel,
    /// in `[0, 1)²` (used by the mutual-information contrast only; samples beyond
    /// `positions.len()` are ignored by it).
    #[must_use]
    pub fn contrast_rgb(&self, samples: &[[f64; 3]], positions: &[[f64; 2]]) -> f64 {
        match self.measure {
            ContrastMeasure::Entropy => entropy_contrast_rgb(samples),
            ContrastMeasure::MutualInformation => mi_contrast_rgb(samples, positions),
        }
    }

    /// The contrast of luminance (one-channel) samples; `positions` as for
    /// [`Oracle::contrast_rgb`].
    #[must_use]
    pub fn contrast_luminance(&self, samples: &[f64], positions: &[[f64; 2]]) -> f64 {
        match self.measure {
            ContrastMeasure::Entropy => {
                entropy_contrast(samples.len(), |j| samples[j])
                    * display_mean(samples.len(), |j| samples[j])
            }
            ContrastMeasure::MutualInformation => {
                let n = samples.len().min(positions.len());
                mi_contrast(n, 1, |j, _| samples[j], |j| positions[j])
            }
        }
    }

    /// Refine or stop, for RGB samples.
    #[must_use]
    pub fn decide_rgb(&self, samples: &[[f64; 3]], positions: &[[f64; 2]]) -> Verdict {
        self.verdict(self.contrast_rgb(samples, positions))
    }

    /// Refine or stop, for luminance samples.
    #[must_use]
    pub fn decide_luminance(&self, samples: &[f64], positions: &[[f64; 2]]) -> Verdict {
        self.verdict(self.contrast_luminance(samples, positions))
    }

    /// The verdict for a contrast: refine when it exceeds the threshold.
    #[must_use]
    pub fn verdict(&self, contrast: f64) -> Verdict {
        if contrast > self.threshold {
            Verdict::Refine
        } else {
            Verdict::Stop
        }
    }
}

/// A sample value as a non-negative finite number: NaN and negatives read as `0`
/// (no light), `+∞` as the largest finite value.
#[inline]
fn clean(x: f64) -> f64 {
    if x > 0.0 { x.min(f64::MAX) } else { 0.0 }
}

/// The entropy contrast `C = 1 − H / log₂ N` of one channel's `n` values `value(j)`
/// (module docs); `0` when `n < 2`, when every value is `0`, or when all are equal.
///
/// The values are first divided by their maximum, so sums stay finite for any input, and
/// a constant channel gives `H = log₂ N` to the last bit (contrast exactly `0`).
#[must_use]
pub(crate) fn entropy_contrast(n: usize, value: impl Fn(usize) -> f64) -> f64 {
    if n < 2 {
        return 0.0;
    }
    // Largest value, and whether all are equal
    let first = clean(value(0));
    let (mut max, mut constant) = (first, true);
    for j in 1..n {
        let x = clean(value(j));
        max = max.max(x);
        constant &= x == first;
    }
    if constant || max <= 0.0 {
        return 0.0;
    }
    // H = log₂ S − (1/S) Σ y_j log₂ y_j with y_j = c_j / max ∈ [0, 1], S = Σ y_j ∈ [1, N]
    let (mut s, mut s_log) = (0.0, 0.0);
    for j in 0..n {
        let y = clean(value(j)) / max;
        s += y;
        if y > 0.0 {
            s_log += y * math::log2(y);
        }
    }
    let h = math::log2(s) - s_log / s;
    (1.0 - h / math::log2(n as f64)).clamp(0.0, 1.0)
}

/// The mean of `n` display-referred values, each read by [`clean`], at most `1` (white);
/// `0` when `n = 0`.
fn display_mean(n: usize, value: impl Fn(usize) -> f64) -> f64 {
    if n == 0 {
        return 0.0;
    }
    // Each value capped at 1 first: the sum stays finite and the mean in [0, 1]
    let mut sum = 0.0;
    for j in 0..n {
        sum += clean(value(j)).min(1.0);
    }
    (sum / n as f64).clamp(0.0, 1.0)
}

/// The pixel colour contrast of display-referred RGB samples: `Σ_c w_c C_c c̄_c` with
/// [`LUMINANCE_WEIGHTS`] (GI 2003 eq. 8; module docs).
#[must_use]
pub(crate) fn entropy_contrast_rgb(samples: &[[f64; 3]]) -> f64 {
    let mut c = 0.0;
    for (k, w) in LUMINANCE_WEIGHTS.iter().enumerate() {
        let mean = display_mean(samples.len(), |j| samples[j][k]);
        if mean > 0.0 {
            c += w * entropy_contrast(samples.len(), |j| samples[j][k]) * mean;
        }
    }
    c.clamp(0.0, 1.0)
}

/// The mutual-information contrast of RGB samples at `positions` (module docs); the first
/// `min(samples.len(), positions.len())` samples are used.
#[must_use]
pub(crate) fn mi_contrast_rgb(samples: &[[f64; 3]], positions: &[[f64; 2]]) -> f64 {
    let n = samples.len().min(positions.len());
    mi_contrast(n, 3, |j, c| samples[j][c], |j| positions[j])
}

/// The quadrant `0..4` of a position in `[0, 1)²` (`u` right, `v` down); values outside
/// fall in the nearest quadrant, NaN in the first.
#[inline]
fn quadrant(p: [f64; 2]) -> usize {
    usize::from(p[0] >= 0.5) + 2 * usize::from(p[1] >= 0.5)
}

/// `C_I` over `n` samples of `channels` channels (1: luminance, 3: RGB weighted by
/// [`LUMINANCE_WEIGHTS`]), `value(j, c)` and `position(j)`.
fn mi_contrast(
    n: usize,
    channels: usize,
    value: impl Fn(usize, usize) -> f64,
    position: impl Fn(usize) -> [f64; 2],
) -> f64 {
    if n < 2 {
        return 0.0;
    }
    let weight = |c: usize| {
        if channels == 1 {
            1.0
        } else {
            LUMINANCE_WEIGHTS[c]
        }
    };
    // Largest value, and whether the pixel is constant (then exactly 0, not a rounding)
    let mut max = 0.0_f64;
    let mut constant = true;
    for j in 0..n {
        for c in 0..channels {
            let x = clean(value(j, c));
            max = max.max(x);
            constant &= x == clean(value(0, c));
        }
    }
    if constant || max <= 0.0 {
        return 0.0;
    }
    // Luminous power per quadrant and channel (values over max keep the sums finite)
    let mut count = [0usize; 4];
    let mut power = [[0.0_f64; 3]; 4];
    for j in 0..n {
        let g = quadrant(position(j));
        count[g] += 1;
        for (c, cell) in power[g].iter_mut().enumerate().take(channels) {
            *cell += weight(c) * clean(value(j, c)) / max;
        }
    }
    let total: f64 = power.iter().flatten().sum();
    if total <= 0.0 {
        return 0.0;
    }
    let mut p_c = [0.0_f64; 3];
    for row in &power {
        for (p, &x) in p_c.iter_mut().zip(row).take(channels) {
            *p += x / total;
        }
    }
    // I_d = Σ p(g,c) log₂(p(g,c) / (a_g p(c))), normalised by log₂(1 / min a_g)
    let (mut i_d, mut min_a) = (0.0, 1.0_f64);
    for (row, &n_g) in power.iter().zip(&count) {
        if n_g == 0 {
            continue;
        }
        let a = n_g as f64 / n as f64;
        min_a = min_a.min(a);
        for (&x, &p_of_c) in row.iter().zip(&p_c).take(channels) {
            let p = x / total;
            if p > 0.0 {
                i_d += p * math::log2(p / (a * p_of_c));
            }
        }
    }
    if min_a >= 1.0 {
        return 0.0;
    }
    // Y: the pixel's mean display luminance (module docs)
    let mut y = 0.0;
    for c in 0..channels {
        y += weight(c) * display_mean(n, |j| value(j, c));
    }
    (y.clamp(0.0, 1.0) * i_d / -math::log2(min_a)).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    const AT4: [[f64; 2]; 4] = [[0.25, 0.25], [0.75, 0.25], [0.25, 0.75], [0.75, 0.75]];

    #[test]
    fn constant_is_zero_and_split_matches_closed_form() {
        assert_eq!(entropy_contrast(4, |_| 0.3), 0.0);
        assert_eq!(entropy_contrast(4, |_| 0.0), 0.0);
        // Black and white halves: C = 1 / log₂ N, times the mean colour 1/2
        for n in [4usize, 8, 16, 64] {
            let c = entropy_contrast(n, |j| (j % 2) as f64);
            assert!((c - 1.0 / (n as f64).log2()).abs() < 1e-12, "{n}: {c}");
            let mut s = [[0.0; 3]; 64];
            for (j, x) in s.iter_mut().enumerate() {
                *x = [(j % 2) as f64; 3];
            }
            let c = entropy_contrast_rgb(&s[..n]);
            assert!((c - 0.5 / (n as f64).log2()).abs() < 1e-12, "{n}: {c}");
        }
        // Left/right halves, black and white: I_d = 1 bit of 2, times Y = 1/2
        let s = [1.0, 0.0, 1.0, 0.0];
        let c = Oracle::mutual_information().contrast_luminance(&s, &AT4);
        assert!((c - 0.25).abs() < 1e-12, "{c}");
        // All the light in one quadrant: 2 bits of 2, times Y = 1/4
        let s = [1.0, 0.0, 0.0, 0.0];
        let c = Oracle::mutual_information().contrast_luminance(&s, &AT4);
        assert!((c - 0.25).abs() < 1e-12, "{c}");
        // Display-referred: values above white count as white
        let bright = [[4.0; 3], [0.0; 3], [4.0; 3], [0.0; 3]];
        let c = entropy_contrast_rgb(&bright);
        assert!((c - 0.25).abs() < 1e-12, "{c}");
    }

    #[test]
    fn odd_inputs_give_finite_contrasts() {
        let bad = [f64::NAN, f64::INFINITY, -1.0, f64::MAX, 0.0];
        let c = entropy_contrast(bad.len(), |j| bad[j]);
        assert!((0.0..=1.0).contains(&c));
        let rgb = bad.map(|x| [x, x, x]);
        let pos = [
            [f64::NAN, 2.0],
            [-1.0, 0.5],
            [0.5, 0.5],
            [0.1, 0.9],
            [0.9, 0.1],
        ];
        let c = mi_contrast_rgb(&rgb, &pos);
        assert!((0.0..=1.0).contains(&c), "{c}");
        assert_eq!(entropy_contrast_rgb(&[]), 0.0);
        assert_eq!(mi_contrast_rgb(&[[1.0; 3]], &AT4), 0.0);
        assert!(Oracle::entropy().with_threshold(f64::NAN).is_err());
        assert!(Oracle::entropy().with_threshold(1.5).is_err());
    }
}
