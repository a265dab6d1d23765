//! Figures 6.6 and 6.9: the oracles of hierarchical radiosity on the Cornell box at matched
//! leaf counts, each mesh's RMS radiosity error against a reference that is fine everywhere
//! (`sceneinfo::hierarchy::compare`; `sceneinfo reproduce` prints the full table).
//!
//! What was measured (reference: receivers split 4× = 7180 leaves, 64 pairs, seed 1, power
//! links at 10⁻⁴ of the emitted power, its change from 3× splits RMS 0.0057; oracles: seed
//! 2, default `min_area` 10⁻⁶):
//!
//! | leaves | power 10 | KS-av 10 | MI 10 | KS-av 4 | MI 4 |
//! |---|---|---|---|---|---|
//! | 1000 | 0.00941 | 0.01168 | 0.01203 | 0.01171 (×1.003) | 0.01175 (×0.977) |
//! | 2000 | 0.00863 | 0.01186 | 0.01135 | 0.01185 (×0.999) | 0.01149 (×1.012) |
//!
//! Over four oracle seeds (2–5) at 1000 leaves the means are: power 0.00928, KS-av 0.01200,
//! MI 0.01200; with 4 pairs KS-av 0.01393 (×1.16), MI 0.01395 (×1.16), single seeds ranging
//! from ×0.98 to ×1.29 for both. The RMS of display values (exposure: brightest non-emitter
//! white, gamma 1/2.2) ranks them the same (power 0.0160, KS-av 0.0199, MI 0.0197). Bounding
//! every oracle's elements at 10⁻⁴ of the area (`min_area`, near the reference's element
//! size, so KS cannot spend elements below it on the junctions) changes little: seeds 2
//! and 3 give power 0.00941 / 0.00925, KS-av 0.01180 / 0.01110, MI 0.01202 / 0.01180.
//!
//! The thesis' first claim — MI no worse than power and KS at equal leaf counts — fails in
//! RMS: power is best by 20–25 % at both sizes, in radiosity and in display values; MI and
//! KS-av are level (KS-av spends its elements on the junctions and gets no better from 1000
//! to 2000 leaves). The thesis judged pictures — shadow boundaries, a small part of the
//! area — which an area-weighted RMS does not single out. Its second claim — with 4 pairs
//! KS degrades while MI keeps its quality — is not seen: both degrade alike, by as much as
//! the seed-to-seed spread.

use sceneinfo::hierarchy::{Hierarchy, HrOptions, OracleComparison};
use sceneinfo::scene::Scene3;

fn cornell() -> Scene3 {
    Scene3::cornell_box(false, 1).unwrap()
}

fn reference(level: u32, pairs: usize) -> Hierarchy {
    let opts = HrOptions {
        pairs,
        ..HrOptions::default()
    };
    Hierarchy::build_reference(&cornell(), level, 1e-4, &opts).unwrap()
}

/// The oracles draw their point pairs with seed 2, the reference with seed 1: with one
/// seed the same element pairs would share their first samples with the reference's, and
/// the meshes' visibility noise would be correlated with the reference's.
fn run(
    reference: &Hierarchy,
    oracle: &'static str,
    pairs: usize,
    target: usize,
) -> OracleComparison {
    let opts = HrOptions {
        pairs,
        seed: 2,
        ..HrOptions::default()
    };
    let c = OracleComparison::at_size(&cornell(), reference, oracle, target, &opts).unwrap();
    // Matched sizes: the threshold search lands within 6 % of the target (KS-av's count
    // jumps as whole junctions refine at once: 1906 for 2000 with 4 pairs).
    assert!(c.leaves.abs_diff(target) * 100 <= 6 * target, "{c:?}");
    c
}

/// A small version that runs with the other tests: against a coarser reference (3 splits,
/// 16 pairs), power beats MI at 300 leaves as at 1000 and 2000 (seen: RMS 0.0125 against
/// 0.0151), and MI's error falls as its mesh grows (0.0119 at 600 leaves).
#[test]
fn at_300_leaves_power_beats_mi_in_rms_and_finer_mi_meshes_are_better() {
    let reference = reference(3, 16);
    let power = run(&reference, "power", 10, 300);
    let mi = run(&reference, "mi", 10, 300);
    let finer = run(&reference, "mi", 10, 600);
    assert!(power.rms_error < 0.95 * mi.rms_error, "{power:?} {mi:?}");
    assert!(finer.rms_error < 0.95 * mi.rms_error, "{finer:?} {mi:?}");
}

/// The full comparison (40 s in release on two free cores, measured 2026-11-22):
/// `cargo test --release -p sceneinfo-tests --test integration figures_6_6 -- --ignored`.
#[test]
#[ignore = "40 s in release, far longer in debug: the thesis' 1000 and 2000 leaves against a 7180-leaf reference; run with --release -- --ignored"]
fn figures_6_6_and_6_9_power_has_the_lowest_rms_and_4_pairs_affect_mi_and_ks_alike() {
    let reference = reference(4, HrOptions::MAX_PAIRS);
    for target in [1000, 2000] {
        let rms: Vec<f64> = OracleComparison::RUNS
            .iter()
            .map(|&(oracle, pairs)| run(&reference, oracle, pairs, target).rms_error)
            .collect();
        let [power, ks, mi, ks4, mi4] = rms[..] else {
            unreachable!()
        };
        // The thesis' first claim fails in RMS: power is best by more than 10 %.
        assert!(power < 0.9 * mi && power < 0.9 * ks, "{target}: {rms:?}");
        // MI and KS-av within 10 % of each other.
        assert!((mi / ks - 1.0).abs() < 0.1, "{target}: {rms:?}");
        // Its second is not seen: 4 pairs change MI's error as much as KS-av's (seen with
        // this seed: ×0.98 and ×1.00 at 1000 leaves, ×1.01 and ×1.00 at 2000).
        assert!((mi4 / mi - ks4 / ks).abs() < 0.1, "{target}: {rms:?}");
    }
}
