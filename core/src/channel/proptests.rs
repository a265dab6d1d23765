//! Property tests of the channel measures over random reversible chains.
//!
//! A reversible chain is generated from a random symmetric non-negative joint matrix `J`
//! (with zeros, and states whose weights differ by up to twelve orders of magnitude):
//! `w_i = Σ_j J_ij`, `P_ij = J_ij / w_i` — exactly the structure of a scene, where
//! `J_ij = a_i F_ij = a_j F_ji`.

#![cfg(feature = "std")]

use proptest::prelude::*;
use std::vec::Vec;

use super::*;
use crate::math;

/// A reversible chain: `(n, w, P row-major, J row-major)`.
#[derive(Clone, Debug)]
struct Chain {
    n: usize,
    w: Vec<f64>,
    p: Vec<f64>,
    j: Vec<f64>,
}

/// Builds `w` and `P` from a symmetric non-negative `J` (normalised here).
fn chain_from_joint(n: usize, mut j: Vec<f64>) -> Chain {
    let total = math::sum(j.iter().copied());
    for v in &mut j {
        *v /= total;
    }
    let w: Vec<f64> = (0..n)
        .map(|r| math::sum(j[r * n..(r + 1) * n].iter().copied()))
        .collect();
    let p = (0..n * n)
        .map(|k| if j[k] > 0.0 { j[k] / w[k / n] } else { 0.0 })
        .collect();
    Chain { n, w, p, j }
}

/// Random symmetric joint matrices of `n ∈ sizes` states; per-state scales `10^e` with
/// `|e| ≤ max_exp`; about `zero_pct`% of the pairs are zero; `path` forces `J_{i,i+1} > 0`
/// (an irreducible chain).
fn chains(
    sizes: core::ops::Range<usize>,
    max_exp: i32,
    zero_pct: u32,
    path: bool,
) -> impl Strategy<Value = Chain> {
    sizes
        .prop_flat_map(move |n| {
            (
                Just(n),
                proptest::collection::vec(-max_exp..=max_exp, n),
                proptest::collection::vec((0u32..100, 0.01f64..1.0), n * n),
            )
        })
        .prop_map(move |(n, exps, cells)| {
            let scale: Vec<f64> = exps
                .iter()
                .map(|&e| libm::pow(10.0, f64::from(e)))
                .collect();
            let mut j = std::vec![0.0; n * n];
            for r in 0..n {
                for c in r..n {
                    let (coin, u) = cells[r * n + c];
                    let forced = path && c == r + 1;
                    if coin >= zero_pct || forced {
                        let v = u * scale[r] * scale[c];
                        j[r * n + c] = v;
                        j[c * n + r] = v;
                    }
                }
            }
            // Every state keeps some weight, so no row is empty.
            for r in 0..n {
                if j[r * n..(r + 1) * n].iter().all(|&v| v == 0.0) {
                    j[r * n + r] = scale[r] * scale[r];
                }
            }
            chain_from_joint(n, j)
        })
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn identities_and_bounds(ch in chains(1..12, 3, 35, false)) {
        let c = Channel::from_dense(&ch.w, &ch.p).unwrap();
        let m = c.measures();
        let tol = 1e-12 * (m.h_j + 1.0);
        // H_J = H_P + H_S = 2H_S + I_S (§3.1.3)
        prop_assert!(close(m.h_j, m.h_p + m.h_s, tol), "{m:?}");
        prop_assert!(close(m.h_j, 2.0 * m.h_s + m.i_s, tol), "{m:?}");
        prop_assert!(close(m.h_j, 2.0 * m.h_p - m.i_s, tol), "{m:?}");
        // 0 ≤ I_S ≤ H_P, 0 ≤ H_S ≤ H_P ≤ log₂ n
        prop_assert!(m.i_s >= -tol && m.i_s <= m.h_p + tol, "{m:?}");
        prop_assert!(m.h_s >= 0.0 && m.h_s <= m.h_p + tol, "{m:?}");
        prop_assert!(m.h_p <= math::log2(ch.n as f64) + 1e-12);
        let one = if m.h_p > 0.0 { 1.0 } else { 0.0 };
        let norm_tol = if m.h_p > 0.0 { 1e-12 + tol / m.h_p } else { 0.0 };
        prop_assert!(close(m.h_s_norm + m.i_s_norm, one, norm_tol), "{m:?}");
        // E(MSE) = n − ΣΣ P² for a closed scene (3.20)
        let sq = math::sum(ch.p.iter().map(|v| v * v));
        prop_assert!(close(m.e_mse, ch.n as f64 - sq, 1e-12 * ch.n as f64));
        // The one-pass measures are the single methods, bit for bit.
        prop_assert_eq!(
            (m.h_p, m.h_s, m.h_j, m.i_s, m.e_mse, m.fano),
            (c.h_p(), c.h_s(), c.h_j(), c.i_s(), c.e_mse(), c.fano_bound())
        );
        prop_assert_eq!(Channel::entropy_rate(&ch.w, c.transitions()), m.h_s);
    }

    #[test]
    fn per_patch_and_per_pair_split(ch in chains(1..12, 3, 35, false)) {
        let n = ch.n;
        let c = Channel::from_dense(&ch.w, &ch.p).unwrap();
        let m = c.measures();
        let (mut h, mut ii, mut mat) = (std::vec![0.0; n], std::vec![0.0; n], std::vec![0.0; n * n]);
        c.patch_entropies(&mut h).unwrap();
        c.patch_mutual_information(&mut ii).unwrap();
        c.mutual_information_matrix(&mut mat).unwrap();
        // H_S = Σ w_i H_i (3.3); I_S = Σ I_i = ΣΣ I_ij (6.9)
        let tol = 1e-13 * (1.0 + m.h_j);
        prop_assert!(close(math::sum((0..n).map(|i| ch.w[i] * h[i])), m.h_s, tol));
        prop_assert_eq!(math::sum(ii.iter().copied()), m.i_s);
        prop_assert!(close(math::sum(mat.iter().copied()), m.i_s, tol));
        for i in 0..n {
            // I_i = w_i D_KL(P_i· ‖ w) ≥ 0 (log-sum inequality, §6.3.1)
            prop_assert!(ii[i] >= -1e-15, "I_{} = {}", i, ii[i]);
            prop_assert!(close(math::sum(mat[i * n..(i + 1) * n].iter().copied()), ii[i], tol));
            for k in 0..n {
                // I_ij = I_ji by reciprocity
                let (a, b) = (mat[i * n + k], mat[k * n + i]);
                prop_assert!(close(a, b, 1e-13 * (ch.j[i * n + k] + a.abs())), "{a} {b}");
            }
        }
        let mut seen = 0;
        c.for_each_pair_information(|i, k, v| {
            seen += 1;
            assert_eq!(v, mat[i * n + k]);
        });
        prop_assert_eq!(seen, ch.p.iter().filter(|&&v| v > 0.0).count());
    }

    #[test]
    fn fano_bounds_the_map_error(ch in chains(1..12, 3, 35, false)) {
        let n = ch.n;
        let c = Channel::from_dense(&ch.w, &ch.p).unwrap();
        // Guess X from Y = j by the most likely source: P_e = 1 − Σ_j max_i w_i P_ij.
        let hit = math::sum((0..n).map(|k| (0..n).map(|i| ch.w[i] * ch.p[i * n + k]).fold(0.0, f64::max)));
        let p_e = 1.0 - hit;
        let fano = c.fano_bound();
        prop_assert!(p_e >= fano - 1e-12, "P_e = {p_e}, bound = {fano}");
        // The unweakened form (2.70): H(P_e) + P_e log₂(n) ≥ H(X|Y) = H_S.
        let p_e = p_e.clamp(0.0, 1.0);
        let lhs = math::eta(p_e) + math::eta(1.0 - p_e) + p_e * math::log2(n as f64);
        prop_assert!(lhs >= c.h_s() - 1e-12, "{lhs} < {}", c.h_s());
    }

    #[test]
    fn merging_states_never_increases_information(
        ch in chains(2..12, 3, 35, false),
        a in 0usize..64,
        b in 0usize..64,
    ) {
        let n = ch.n;
        // Two distinct states.
        let (a, b) = (a % n, (a + 1 + b % (n - 1)) % n);
        let (a, b) = (a.min(b), a.max(b));
        // Group b into a: sum rows and columns of J (2.67, 2.68).
        let target = |s: usize| {
            let s = if s == b { a } else { s };
            if s > b { s - 1 } else { s }
        };
        let mut j = std::vec![0.0; (n - 1) * (n - 1)];
        for r in 0..n {
            for s in 0..n {
                j[target(r) * (n - 1) + target(s)] += ch.j[r * n + s];
            }
        }
        let merged = chain_from_joint(n - 1, j);
        let before = Channel::from_dense(&ch.w, &ch.p).unwrap().i_s();
        let after = Channel::from_dense(&merged.w, &merged.p).unwrap().i_s();
        prop_assert!(after <= before + 1e-12 * (1.0 + before), "{after} > {before}");
    }

    #[test]
    fn checks_report_reversible_and_stationary(ch in chains(1..12, 3, 35, false)) {
        let c = Channel::from_dense(&ch.w, &ch.p).unwrap();
        let k = c.checks();
        prop_assert!(k.is_row_stochastic(1e-13), "{k:?}");
        prop_assert!(k.is_reversible(1e-13), "{k:?}");
        prop_assert!(k.is_stationary(1e-13), "{k:?}");
    }

    #[test]
    fn excess_entropy_is_mutual_information(ch in chains(1..7, 2, 35, false)) {
        // Proposition 1: H(X_1..X_L) = H_P + (L−1)H_S, so E_L = I_S, by path enumeration.
        let c = Channel::from_dense(&ch.w, &ch.p).unwrap();
        let m = c.measures();
        for len in 1..=4 {
            let block = c.block_entropy(len).unwrap();
            let expected = m.h_p + (len - 1) as f64 * m.h_s;
            prop_assert!(close(block, expected, 1e-12 * (1.0 + expected)), "L = {len}: {block} vs {expected}");
            let e = c.excess_entropy(len).unwrap();
            prop_assert!(close(e, m.i_s, 1e-12 * (1.0 + len as f64 * m.h_j)), "L = {len}: {e} vs {}", m.i_s);
        }
    }

    #[test]
    fn stationary_distribution_recovers_w(ch in chains(1..12, 1, 35, true)) {
        let (mut x, mut scratch) = (std::vec![0.0; ch.n], std::vec![0.0; ch.n]);
        let p = DenseMatrix::new(ch.n, &ch.p).unwrap();
        let it = Channel::stationary_distribution(&p, &mut x, &mut scratch, 1e-15, 2_000_000);
        prop_assert!(it.is_ok(), "{it:?}");
        for (xi, wi) in x.iter().zip(&ch.w) {
            prop_assert!(close(*xi, *wi, 1e-10), "{x:?} vs {:?}", ch.w);
        }
    }

    #[test]
    fn dense_and_csr_agree(ch in chains(1..12, 3, 50, false)) {
        let n = ch.n;
        let dense = Channel::from_dense(&ch.w, &ch.p).unwrap();
        let buf = CsrMatrixBuf::from_dense(n, &ch.p).unwrap();
        let sparse = Channel::new(&ch.w, buf.as_matrix()).unwrap();
        prop_assert_eq!(dense.measures(), sparse.measures());
        prop_assert_eq!(dense.checks(), sparse.checks());
        let (mut a, mut b) = (std::vec![0.0; n * n], std::vec![0.0; n * n]);
        dense.mutual_information_matrix(&mut a).unwrap();
        sparse.mutual_information_matrix(&mut b).unwrap();
        prop_assert_eq!(&a, &b);
        dense.patch_entropies(&mut a).unwrap();
        sparse.patch_entropies(&mut b).unwrap();
        prop_assert_eq!(&a, &b);
        if n <= 5 {
            prop_assert_eq!(dense.block_entropy(3), sparse.block_entropy(3));
        }
        // Through a reference, too.
        let view = buf.as_matrix();
        let by_ref = Channel::new(&ch.w, &view).unwrap();
        prop_assert_eq!(by_ref.measures(), sparse.measures());
    }

    #[test]
    fn arbitrary_input_never_panics_nor_leaks_nan(
        n in 0usize..5,
        w in proptest::collection::vec(prop_oneof![Just(0.0), Just(f64::NAN), -1.0f64..2.0, 0.0f64..1.0], 0..6),
        p in proptest::collection::vec(prop_oneof![Just(0.0), Just(f64::INFINITY), -0.5f64..1.0, 0.0f64..0.5], 0..26),
        normalise in any::<bool>(),
    ) {
        // Normalising makes valid channels frequent; not normalising exercises errors.
        let mut w = w;
        if normalise {
            let s: f64 = w.iter().filter(|v| v.is_finite() && **v > 0.0).sum();
            for v in &mut w {
                *v = if v.is_finite() && *v > 0.0 { *v / s } else { 0.0 };
            }
        }
        let p = p.get(..n * n).unwrap_or(&p);
        if let Ok(c) = Channel::from_dense(&w, p) {
            let m = c.measures();
            for v in [m.h_p, m.h_s, m.h_j, m.i_s, m.h_s_norm, m.i_s_norm, m.h_s_joint_norm,
                      m.i_s_joint_norm, m.e_mse, m.fano] {
                prop_assert!(v.is_finite(), "{m:?}");
            }
            let k = c.checks();
            for v in [k.min_row_sum, k.max_row_sum, k.max_row_sum_error, k.max_reciprocity_error,
                      k.stationarity_error] {
                prop_assert!(v.is_finite(), "{k:?}");
            }
            let mut buf = std::vec![0.0; n * n];
            c.mutual_information_matrix(&mut buf).unwrap();
            prop_assert!(buf.iter().all(|v| v.is_finite()));
            if let Ok(h) = c.block_entropy(4) {
                prop_assert!(h.is_finite());
            }
        }
        let mut x = std::vec![0.0; n];
        let mut s = std::vec![0.0; n];
        if let Ok(d) = DenseMatrix::new(n, p) {
            let _ = Channel::stationary_distribution(&d, &mut x, &mut s, 1e-12, 1000);
            prop_assert!(x.iter().all(|v| v.is_finite()));
            prop_assert!(Channel::entropy_rate(&w, &d).is_finite());
        }
    }
}
