//! Proposition 3 and the discretisation errors as properties over random inputs.
//!
//! A random reversible chain is built from a random symmetric joint matrix `S` (`p_ij = S_ij`,
//! `w_i = Σ_j S_ij`, `P_ij = S_ij / w_i`). A random valid split of state `i` into `m`
//! sub-states divides every joint mass `S_ij` (`j ≠ i`) among the sub-states and `S_ii` into a
//! symmetric `m × m` block; the sub-states' weights are their row sums, their transitions
//! follow, so conditions (a) and (b) hold by construction. "Regular" splits additionally give
//! every sub-state `w_i / m`, by moving mass around cycles of the `m × n` table (which keeps
//! its row and column sums).

use proptest::prelude::*;
use sceneinfo::channel::Channel;
use sceneinfo::refine::discretisation::{
    radiosity_error_point_pairs, visibility_error_lines, visibility_error_point_pairs,
};
use sceneinfo::refine::proposition::{StateSplit, split_gain};
use sceneinfo::{ErrorKind, math};

/// A chain `(w, P)` from raw values: `n × n`, symmetrised, some entries zeroed, a positive
/// diagonal so every state has weight, normalised to a joint distribution.
fn joint_matrix(n: usize, raw: &[f64]) -> Vec<f64> {
    let mut s = vec![0.0; n * n];
    for i in 0..n {
        for j in i..n {
            let v = raw[i * n + j];
            let v = if v < 0.3 { 0.0 } else { v };
            let v = if i == j { v + 0.05 } else { v };
            s[i * n + j] = v;
            s[j * n + i] = v;
        }
    }
    let total: f64 = s.iter().sum();
    s.iter().map(|v| v / total).collect()
}

fn chain(s: &[f64], n: usize) -> (Vec<f64>, Vec<f64>) {
    let w: Vec<f64> = (0..n).map(|i| s[i * n..(i + 1) * n].iter().sum()).collect();
    let mut p = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            p[i * n + j] = s[i * n + j] / w[i];
        }
    }
    (w, p)
}

/// The split as joint masses: `x[k·n + j]` = `p_{i_k j}` (column `i` unused), `block[k·m + l]`.
struct JointSplit {
    x: Vec<f64>,
    block: Vec<f64>,
    m: usize,
}

impl JointSplit {
    /// Random proportions of each `S_ij` and a random symmetric block of total `S_ii`.
    fn random(s: &[f64], n: usize, i: usize, m: usize, u: &[f64]) -> Self {
        let mut x = vec![0.0; m * n];
        let mut u = u.iter().cycle();
        for j in (0..n).filter(|&j| j != i) {
            let shares: Vec<f64> = (0..m).map(|_| 0.05 + u.next().unwrap()).collect();
            let total: f64 = shares.iter().sum();
            for k in 0..m {
                x[k * n + j] = s[i * n + j] * shares[k] / total;
            }
        }
        let mut block = vec![0.0; m * m];
        for k in 0..m {
            for l in k..m {
                let v = 0.05 + u.next().unwrap();
                block[k * m + l] = v;
                block[l * m + k] = v;
            }
        }
        let total: f64 = block.iter().sum();
        block.iter_mut().for_each(|b| *b *= s[i * n + i] / total);
        Self { x, block, m }
    }

    /// A regular split (every sub-state weighs `w_i / m`): start from equal shares, then move
    /// mass around random 2 × 2 cycles of the table.
    fn regular(
        s: &[f64],
        n: usize,
        i: usize,
        m: usize,
        moves: &[(usize, usize, usize, usize, f64)],
    ) -> Self {
        let mut x = vec![0.0; m * n];
        for k in 0..m {
            for j in (0..n).filter(|&j| j != i) {
                x[k * n + j] = s[i * n + j] / m as f64;
            }
        }
        for &(k1, k2, j1, j2, f) in moves {
            let (k1, k2, j1, j2) = (k1 % m, k2 % m, j1 % n, j2 % n);
            if k1 == k2 || j1 == j2 || j1 == i || j2 == i {
                continue;
            }
            // +ε at (k1, j1), (k2, j2); −ε at (k2, j1), (k1, j2).
            let room = x[k2 * n + j1].min(x[k1 * n + j2]);
            let eps = f * room;
            x[k1 * n + j1] += eps;
            x[k2 * n + j2] += eps;
            x[k2 * n + j1] -= eps;
            x[k1 * n + j2] -= eps;
        }
        let block = vec![s[i * n + i] / (m * m) as f64; m * m];
        Self { x, block, m }
    }

    fn weights(&self, n: usize) -> Vec<f64> {
        let m = self.m;
        (0..m)
            .map(|k| {
                math::sum(self.x[k * n..(k + 1) * n].iter().copied())
                    + math::sum(self.block[k * m..(k + 1) * m].iter().copied())
            })
            .collect()
    }

    /// The split in the form `split_gain` takes, from the chain's weights `w`.
    fn transitions(&self, w: &[f64], n: usize) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
        let m = self.m;
        let wk = self.weights(n);
        let mut rows = vec![0.0; m * n];
        let mut cols = vec![0.0; m * n];
        for k in 0..m {
            for j in 0..n {
                rows[k * n + j] = self.x[k * n + j] / wk[k];
                cols[k * n + j] = self.x[k * n + j] / w[j];
            }
        }
        let block = (0..m * m).map(|kl| self.block[kl] / wk[kl / m]).collect();
        (wk, rows, cols, block)
    }

    /// `I` of the explicitly split chain: states `j ≠ i` in order, then the sub-states.
    fn refined_i_s(&self, s: &[f64], n: usize, i: usize) -> f64 {
        let m = self.m;
        let others: Vec<usize> = (0..n).filter(|&j| j != i).collect();
        let big = others.len() + m;
        let mut joint = vec![0.0; big * big];
        for (a, &ja) in others.iter().enumerate() {
            for (b, &jb) in others.iter().enumerate() {
                joint[a * big + b] = s[ja * n + jb];
            }
            for k in 0..m {
                let v = self.x[k * n + ja];
                joint[a * big + others.len() + k] = v;
                joint[(others.len() + k) * big + a] = v;
            }
        }
        for k in 0..m {
            for l in 0..m {
                joint[(others.len() + k) * big + others.len() + l] = self.block[k * m + l];
            }
        }
        let (w2, p2) = chain(&joint, big);
        Channel::from_dense(&w2, &p2).unwrap().i_s()
    }
}

fn check_split(
    s: &[f64],
    n: usize,
    i: usize,
    split: &JointSplit,
    regular: bool,
) -> Result<(), TestCaseError> {
    let (w, p) = chain(s, n);
    let channel = Channel::from_dense(&w, &p).unwrap();
    let (wk, rows, cols, block) = split.transitions(&w, n);
    let gain = split_gain(
        &channel,
        &StateSplit {
            state: i,
            weights: &wk,
            rows: &rows,
            columns: &cols,
            block: &block,
        },
    )
    .unwrap();
    // ΔI ≥ 0 (5.31), exactly (the brackets are computed as divergences).
    prop_assert!(gain >= 0.0);
    // ΔI = I' − I, against the channel on the explicitly refined chain. Both sides are sums
    // of O(n²) terms of size ≤ 1 rounded to ~1e-16: 1e-12 is a wide margin.
    let direct = split.refined_i_s(s, n, i) - channel.i_s();
    prop_assert!(
        (gain - direct).abs() < 1e-12,
        "ΔI {gain} but I' − I = {direct}"
    );
    // Upper bounds: 2 w_i log₂ m for a regular split (5.35); 2 w_i log₂(w_i / min w_ik) in
    // general (each bracket is a divergence from r_k = w_ik / w_i).
    let m = split.m as f64;
    if regular {
        prop_assert!(
            gain <= 2.0 * w[i] * m.log2() + 1e-12,
            "{gain} > 2 w_i log m"
        );
    }
    let min_w = wk.iter().cloned().fold(f64::INFINITY, f64::min);
    prop_assert!(gain <= 2.0 * w[i] * (w[i] / min_w).log2() + 1e-12);
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn random_valid_splits_gain_exactly_what_the_refined_chain_gains(
        n in 2usize..6,
        raw in prop::collection::vec(0.0f64..1.0, 25),
        pick in 0usize..5,
        m in 1usize..5,
        u in prop::collection::vec(0.0f64..1.0, 40),
    ) {
        let s = joint_matrix(n, &raw);
        let i = pick % n;
        let split = JointSplit::random(&s, n, i, m, &u);
        check_split(&s, n, i, &split, false)?;
    }

    #[test]
    fn regular_splits_gain_at_most_two_w_i_log_m(
        n in 2usize..6,
        raw in prop::collection::vec(0.0f64..1.0, 25),
        pick in 0usize..5,
        m in 2usize..5,
        moves in prop::collection::vec((0usize..5, 0usize..5, 0usize..6, 0usize..6, 0.0f64..=1.0), 0..12),
    ) {
        let s = joint_matrix(n, &raw);
        let i = pick % n;
        let split = JointSplit::regular(&s, n, i, m, &moves);
        check_split(&s, n, i, &split, true)?;
    }

    #[test]
    fn a_split_that_does_not_cover_its_state_is_reported_not_computed(
        n in 2usize..6,
        raw in prop::collection::vec(0.0f64..1.0, 25),
        pick in 0usize..5,
        m in 2usize..5,
        u in prop::collection::vec(0.0f64..1.0, 40),
        scale in 1.001f64..2.0,
    ) {
        let s = joint_matrix(n, &raw);
        let i = pick % n;
        let (w, p) = chain(&s, n);
        let channel = Channel::from_dense(&w, &p).unwrap();
        let split = JointSplit::random(&s, n, i, m, &u);
        let (wk, rows, mut cols, block) = split.transitions(&w, n);
        // Break (b) for the first other state j that i sees: the sub-states now receive
        // more of j than i did.
        let Some(j) = (0..n).find(|&j| j != i && s[i * n + j] > 1e-6) else {
            return Ok(());
        };
        cols[j] *= scale;
        let err = split_gain(
            &channel,
            &StateSplit { state: i, weights: &wk, rows: &rows, columns: &cols, block: &block },
        )
        .unwrap_err();
        prop_assert!(matches!(err.kind(), ErrorKind::InvalidSplit { .. }), "{err}");
    }

    /// (6.19) and (6.24) are ≥ 0 and symmetric in (i, j) by construction; (6.21) is
    /// symmetric under reciprocity.
    #[test]
    fn discretisation_errors_are_non_negative_and_symmetric(
        kernel in prop::collection::vec(prop_oneof![Just(0.0), 0.0f64..50.0], 1..64),
        a_i in 0.01f64..10.0,
        a_j in 0.01f64..10.0,
        extra in 0.0f64..10.0,
        b_i in 0.0f64..5.0,
        b_j in 0.0f64..5.0,
        f_ij in 0.001f64..1.0,
        mean_log in -10.0f64..10.0,
    ) {
        let a_t = a_i + a_j + extra;
        let d_ij = visibility_error_point_pairs(a_i, a_j, a_t, &kernel).unwrap();
        let d_ji = visibility_error_point_pairs(a_j, a_i, a_t, &kernel).unwrap();
        prop_assert!(d_ij >= 0.0);
        prop_assert!((d_ij - d_ji).abs() <= 1e-14 * d_ij.max(1e-300));
        let r_ij = radiosity_error_point_pairs((b_i, b_j), a_i, a_j, a_t, &kernel).unwrap();
        let r_ji = radiosity_error_point_pairs((b_j, b_i), a_j, a_i, a_t, &kernel).unwrap();
        prop_assert!(r_ij >= 0.0);
        prop_assert!((r_ij - r_ji).abs() <= 1e-14 * r_ij.max(1e-300));
        // Reciprocity: F_ji = A_i F_ij / A_j.
        let f_ji = a_i * f_ij / a_j;
        let l_ij = visibility_error_lines(a_i, f_ij, a_j, a_t, mean_log).unwrap();
        let l_ji = visibility_error_lines(a_j, f_ji, a_i, a_t, mean_log).unwrap();
        prop_assert!((l_ij - l_ji).abs() <= 1e-12 * (1.0 + l_ij.abs()));
    }
}
