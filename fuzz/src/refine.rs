//! The check behind the `fuzz_refine` target: a flatland scene and a random sequence of
//! patch splits, each checked against Proposition 3 (thesis §5.4, (5.26)–(5.35)),
//! asserting the invariant stated in `fuzz/fuzz_targets/fuzz_refine.rs`.
//!
//! Input layout: `.flat` text, then optionally a NUL byte and the split sequence, two
//! bytes a split: patch `b₀ mod n` is cut at `t = (b₁ + 1) / 257` of its length.
//!
//! For each split, the exact form factors before (`F`, `n` states) and after (`F'`, the new
//! patch inserted at `i + 1`, later states shifted by one) give the split as Proposition 3
//! sees it: sub-state weights `w'_i, w'_{i+1}`, their rows and columns of `F'` and their
//! 2 × 2 block. `split_gain(F, split)` must accept it (the exact form factors satisfy
//! reciprocity and covering to rounding) and equal `I'(F') − I(F)` computed directly from
//! the two channels, and both must be `≥ 0`: refinement never loses information.
//!
//! Compiled by the fuzz crate and, through `#[path]`, by `tests/fuzz_replay.rs`.

use core::fmt;

use sceneinfo::formfactor::exact_2d;
use sceneinfo::refine::proposition::{StateSplit, split_gain};
use sceneinfo::scene::Scene2;

use super::invariants::{self, MAX_INPUT_BYTES, Outcome};

/// Largest scene, in patches, that is split (each split costs two exact solutions).
pub const MAX_PATCHES: usize = 24;

/// Most splits of one input.
pub const MAX_SPLITS: usize = 6;

/// Agreement of `split_gain` with `I' − I`, and how far below zero either may round.
/// Exact form factors are exact to ~1e-13 per entry and Proposition 3 accepts splits
/// within 1e-9 on joint probabilities; the two sides differ by rounding only, so this
/// leaves a wide margin while catching any real disagreement.
pub const GAIN_TOLERANCE: f64 = 1e-8;

/// Whether the exact flatland form factors of `scene` are within their guarantee: its
/// extent is at most [`exact_2d::RESOLVED_RANGE`] times its smallest feature — the
/// shortest patch or the closest approach of a surface's end to another surface
/// ([`Scene2::feature_range`]). Beyond it, distances of the scene's size are differenced
/// over a feature 10⁶ times smaller and rows drift by ~10⁻¹⁰ and worse (see
/// `tests/extremes.rs`; a triangle 4·10¹¹ long and 0.14 wide lost 0.08 of a row), so
/// Proposition 3's 1e-9 check on the split may fail on their rounding. For such scenes a
/// refused split is accepted; an accepted one must still satisfy everything.
fn resolved(scene: &Scene2) -> bool {
    scene.feature_range() <= exact_2d::RESOLVED_RANGE
}

/// One fuzz case: the scene text and the splits `(patch selector, t)`. Its `Debug`
/// output is a Rust reproducer.
pub struct RefineCase<'a> {
    /// The `.flat` text.
    pub text: &'a str,
    /// The splits: a patch selector (taken modulo the current patch count) and the cut.
    pub splits: Vec<(usize, f64)>,
}

impl fmt::Debug for RefineCase<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "reproducer:")?;
        writeln!(f, "    let text = {:?};", self.text)?;
        writeln!(f, "    let splits: &[(usize, f64)] = &{:?};", self.splits)?;
        write!(
            f,
            "    // scene = parse_flat(text); for (s, t): scene = scene.split_patch(s % n, t)"
        )
    }
}

/// Decodes an input; `None` when the text is not UTF-8.
#[must_use]
pub fn decode(data: &[u8]) -> Option<RefineCase<'_>> {
    let (text, tail) = match data.iter().position(|&b| b == 0) {
        Some(k) => (&data[..k], &data[k + 1..]),
        None => (data, &[][..]),
    };
    let text = core::str::from_utf8(text).ok()?;
    let splits = tail
        .chunks_exact(2)
        .take(MAX_SPLITS)
        .map(|c| (usize::from(c[0]), (f64::from(c[1]) + 1.0) / 257.0))
        .collect();
    Some(RefineCase { text, splits })
}

/// The states' weights, the dense matrix (row-major) and `I_S` (3.8) of a scene's exact
/// channel.
fn exact_channel(scene: &Scene2) -> Result<(Vec<f64>, Vec<f64>, f64), sceneinfo::Error> {
    let ff = exact_2d::form_factors(scene)?;
    let channel = ff.channel()?;
    let i_s = channel.measures().i_s;
    let n = ff.n_states();
    let mut matrix = vec![0.0; n * n];
    for (i, row) in matrix.chunks_mut(n).enumerate() {
        ff.dense_row_into(i, row)?;
    }
    Ok((ff.weights().to_vec(), matrix, i_s))
}

/// Runs one input through the splits.
///
/// # Panics
///
/// When the core panics or an invariant breaks (the message holds a reproducer).
pub fn check(data: &[u8]) -> Outcome {
    if data.len() > MAX_INPUT_BYTES {
        return Outcome::Rejected;
    }
    let Some(case) = decode(data) else {
        return Outcome::Rejected;
    };
    let fail = |problem: String| -> ! { panic!("{problem}\n{case:?}") };

    let mut scene = match sceneinfo::io::parse_flat(case.text) {
        Ok(scene) => scene,
        Err(err) => return invariants::refused(&err, &case),
    };
    if scene.n_patches() > MAX_PATCHES {
        return Outcome::TooLarge;
    }
    let (mut w, mut f, mut i_s) = match exact_channel(&scene) {
        Ok(c) => c,
        Err(err) => return invariants::refused(&err, &case),
    };
    for &(selector, t) in &case.splits {
        // Split, and solve the refined scene
        let i = selector % scene.n_patches();
        let refined = match scene.split_patch(i, t) {
            Ok(refined) => refined,
            Err(err) => return invariants::refused(&err, &case),
        };
        let (w2, f2, i_s2) = match exact_channel(&refined) {
            Ok(c) => c,
            Err(err) => return invariants::refused(&err, &case),
        };
        let (n, n2) = (w.len(), w2.len());
        if n2 != n + 1 {
            // The background state appeared or vanished (a row deficit crossed its
            // threshold): not a split of one state
            return Outcome::Checked;
        }

        // The split as Proposition 3 sees it: old state j is new state map(j)
        let map = |j: usize| if j < i { j } else { j + 1 };
        let weights = [w2[i], w2[i + 1]];
        let (mut rows, mut columns) = (vec![0.0; 2 * n], vec![0.0; 2 * n]);
        for k in 0..2 {
            for j in (0..n).filter(|&j| j != i) {
                rows[k * n + j] = f2[(i + k) * n2 + map(j)];
                columns[k * n + j] = f2[map(j) * n2 + i + k];
            }
        }
        let block = [
            f2[i * n2 + i],
            f2[i * n2 + i + 1],
            f2[(i + 1) * n2 + i],
            f2[(i + 1) * n2 + i + 1],
        ];
        let split = StateSplit {
            state: i,
            weights: &weights,
            rows: &rows,
            columns: &columns,
            block: &block,
        };
        let channel = match sceneinfo::channel::Channel::from_dense(&w, &f) {
            Ok(channel) => channel,
            Err(err) => fail(format!("the old channel no longer builds: {err}")),
        };
        let gain = match split_gain(&channel, &split) {
            Ok(gain) => gain,
            Err(err) if !resolved(&refined) => return invariants::refused(&err, &case),
            Err(err) => fail(format!(
                "Proposition 3 refused the split of patch {i} at t = {t}: {err}"
            )),
        };
        let direct = i_s2 - i_s;
        if !(gain.is_finite() && gain >= -GAIN_TOLERANCE && direct >= -GAIN_TOLERANCE) {
            fail(format!(
                "split of patch {i} at t = {t}: gain {gain}, I' - I = {direct}"
            ));
        }
        if (gain - direct).abs() > GAIN_TOLERANCE {
            fail(format!(
                "split of patch {i} at t = {t}: Proposition 3 gives {gain}, I' - I = {direct}"
            ));
        }
        (scene, w, f, i_s) = (refined, w2, f2, i_s2);
    }
    Outcome::Checked
}
