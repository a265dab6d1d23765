//! Long-range mutual information `I(X_0; X_n)` (`Channel::long_range_information`,
//! issue 20 item 2): `= I_S` at `n = 1`, never rising in `n` (data processing inequality),
//! tending to 0 for an ergodic (irreducible, aperiodic) chain, its per-state split summing
//! to it, and above the block-entropy bound `H_P − n H_S`; on random reversible chains and
//! on the exact channels of random flatland rooms.

use proptest::prelude::*;
use sceneinfo::channel::{Channel, DenseMatrix};
use sceneinfo::formfactor::exact_2d;

use super::scenes::room_with_segments;

/// A reversible chain from a symmetric joint `p_ij ∝ s_ij` with every entry positive
/// (irreducible and aperiodic): `w_i = Σ_j p_ij`, `P_ij = p_ij / w_i`.
fn chain(n: usize, s: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let mut joint = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let v = s[i * n + j];
            joint[i * n + j] = v;
            joint[j * n + i] = v;
        }
    }
    let total: f64 = joint.iter().sum();
    let w: Vec<f64> = (0..n)
        .map(|i| joint[i * n..(i + 1) * n].iter().sum::<f64>() / total)
        .collect();
    let mut p = vec![0.0; n * n];
    for i in 0..n {
        let row: f64 = joint[i * n..(i + 1) * n].iter().sum();
        for j in 0..n {
            p[i * n + j] = joint[i * n + j] / row;
        }
    }
    (w, p)
}

fn random_chain() -> impl Strategy<Value = (usize, Vec<f64>)> {
    (2usize..9).prop_flat_map(|n| (Just(n), prop::collection::vec(0.01f64..1.0, n * n)))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn ergodic_chains_forget_their_start((n, s) in random_chain()) {
        let (w, p) = chain(n, &s);
        let ch = Channel::new(&w, DenseMatrix::new(n, &p).unwrap()).unwrap();
        let lr = ch.long_range_information(400).unwrap();
        prop_assert!((lr.curve[0] - ch.i_s()).abs() < 1e-12);
        for pair in lr.curve.windows(2) {
            prop_assert!(pair[1] <= pair[0] + 1e-12, "{} then {}", pair[0], pair[1]);
        }
        // Entries ≥ 0.01 / (n · max) keep the second eigenvalue well inside the unit disc
        prop_assert!(lr.curve[399] < 1e-9, "{}", lr.curve[399]);
        let split: f64 = lr.per_state.iter().sum();
        prop_assert!((split - lr.curve[399]).abs() < 1e-12);
        for (k, &v) in lr.curve.iter().enumerate() {
            prop_assert!(v >= lr.block_bound(k + 1) - 1e-12);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(24))]

    #[test]
    fn scene_chains_obey_data_processing(scene in room_with_segments()) {
        let ff = exact_2d::form_factors(&scene).unwrap();
        let ch = ff.channel().unwrap();
        let lr = ch.long_range_information(12).unwrap();
        prop_assert!((lr.curve[0] - ch.i_s()).abs() < 1e-12);
        // Excess entropy (Proposition 1): H_P − H_S = I_S
        prop_assert!((lr.h_p - lr.h_s - lr.curve[0]).abs() < 1e-9);
        for pair in lr.curve.windows(2) {
            prop_assert!(pair[1] <= pair[0] + 1e-12, "{} then {}", pair[0], pair[1]);
        }
        let first: f64 = lr.per_state_first.iter().sum();
        prop_assert!((first - ch.i_s()).abs() < 1e-12);
    }
}
