//! Simplification invariants over random flatland scenes (issue 20, item 3): every merge
//! loses `≥ 0` bits, exactly the drop of the recomputed `I_S`, so `I_S` never rises under
//! merges — for random merge orders, not only the greedy one.

use proptest::prelude::*;
use sceneinfo::formfactor::exact_2d;
use sceneinfo::simplify::adjacency::adjacency_2d;
use sceneinfo::simplify::{MergeChain, MergeCriterion, Simplifier};

use super::scenes::{convex_polygon_scene, room_with_segments};

/// `|ΔI_S − loss|` allowed: sums of `O(n²)` terms of at most a few bits, compensated.
const TOLERANCE: f64 = 1e-12;

fn check_random_merges(
    scene: &sceneinfo::scene::Scene2,
    picks: &[usize],
) -> Result<(), TestCaseError> {
    let ff = exact_2d::form_factors(scene).unwrap();
    let mut chain = MergeChain::new(ff.weights(), &ff.matrix()).unwrap();
    let pairs = adjacency_2d(scene);
    let mut before = chain.i_s().unwrap();
    for &pick in picks {
        if pairs.is_empty() {
            break;
        }
        let (a, b) = pairs[pick % pairs.len()];
        let (a, b) = (chain.cluster_of(a), chain.cluster_of(b));
        if a == b {
            continue;
        }
        let loss = chain.merge(a, b).unwrap();
        let after = chain.i_s().unwrap();
        prop_assert!(loss >= 0.0);
        prop_assert!(after <= before + TOLERANCE, "I_S rose: {before} → {after}");
        prop_assert!(
            (before - after - loss).abs() <= TOLERANCE,
            "{before} − {after} ≠ {loss}"
        );
        before = after;
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn random_merges_in_convex_polygons_lose_what_i_s_loses(
        scene in convex_polygon_scene(),
        picks in prop::collection::vec(0usize..1000, 1..12),
    ) {
        check_random_merges(&scene, &picks)?;
    }

    #[test]
    fn random_merges_in_rooms_with_occluders_lose_what_i_s_loses(
        scene in room_with_segments(),
        picks in prop::collection::vec(0usize..1000, 1..12),
    ) {
        check_random_merges(&scene, &picks)?;
    }

    #[test]
    fn greedy_merges_never_raise_i_s(scene in room_with_segments()) {
        let ff = exact_2d::form_factors(&scene).unwrap();
        let chain = MergeChain::new(ff.weights(), &ff.matrix()).unwrap();
        let n = scene.n_patches();
        let pairs = adjacency_2d(&scene);
        for criterion in MergeCriterion::ALL {
            let b = vec![[1.0; 3]; n];
            let mut s = Simplifier::new(chain.clone(), n, &pairs, criterion, Some(&b)).unwrap();
            let mut before = s.i_s();
            let (steps, _) = s.run(1, None).unwrap();
            for step in steps {
                prop_assert!(step.loss >= 0.0);
                prop_assert!(step.i_s <= before);
                before = step.i_s;
            }
            prop_assert!((s.i_s() - s.chain().i_s().unwrap()).abs() <= TOLERANCE);
        }
    }
}
