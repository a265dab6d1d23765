//! The exact best split of a set of fine patches in two, with every other cluster fixed:
//! the search behind the polish's re-split of two adjacent clusters and its top-down start
//! (`super::polish`).
//!
//! A set `U` of fine patches (one cluster, or the union of two) is cut into parts `S` and
//! `T = U \ S`; the other clusters `d` do not change. With `q_Sd = Σ_{x∈S} (p L)_xd`, the
//! weights `w_S`, `w_T` and the joint inside `U` (`q_SS`, `q_ST`, `q_TT`), the terms of
//! `I_S` (3.8) that depend on the cut are
//!
//! ```text
//! V(S) = 2 Σ_d [q_Sd log₂(q_Sd / (w_S W_d)) + q_Td log₂(q_Td / (w_T W_d))]
//!        + q_SS log₂(q_SS / w_S²) + q_TT log₂(q_TT / w_T²) + 2 q_ST log₂(q_ST / (w_S w_T))
//! ```
//!
//! so the cut with the largest `V` gives the largest `I_S`, and `V(S) − V(U unsplit)` is
//! the gain of the split (Proposition 3, 5.29). [`TwoParts`] keeps the sums for one `S` and
//! moves one patch in or out of `S` in `O(o + k)` (`o` other clusters, `k = |U|`);
//! [`best_bipartition`] visits every `S` containing the first patch's complement in Gray
//! code order (one move per step, `2^(k−1) − 1` cuts) and keeps the best whose two parts
//! are connected; [`TwoParts::best_prefix`] tries the `k − 1` cuts of a path in order.

use alloc::vec;
use alloc::vec::Vec;

use crate::math;

/// Largest set whose connected 2-partitions are all tried: `2^15` cuts of `O(o + k)` each.
pub(crate) const EXACT_SPLIT_PATCHES: usize = 16;

/// `q log₂(q / v)`, 0 unless both are positive.
fn term(q: f64, v: f64) -> f64 {
    if q > 0.0 && v > 0.0 {
        q * math::log2(q / v)
    } else {
        0.0
    }
}

/// A set `U` of `k` fine patches cut in two parts `S`, `T` (module docs), with the sums
/// that give `V(S)` kept up to date as patches enter and leave `S`.
pub(crate) struct TwoParts {
    k: usize,
    o: usize,
    /// `(p L)_{x_i d}`, `k × o`: member `i`'s joint with other cluster `d`.
    to_others: Vec<f64>,
    /// `W_d` of the other clusters.
    w_others: Vec<f64>,
    /// `w_{x_i}`.
    w_members: Vec<f64>,
    /// `p_{x_i x_l}`, `k × k`; empty when every entry is 0 (patches of one plane or one
    /// flatland surface do not see each other).
    inside: Vec<f64>,
    /// `Σ_l p_{x_i x_l}`.
    row_u: Vec<f64>,
    /// `q_Ud`, `w_U`, `q_UU`.
    q_u: Vec<f64>,
    w_u: f64,
    q_uu: f64,
    // The current S.
    in_s: Vec<bool>,
    q_s: Vec<f64>,
    w_s: f64,
    q_ss: f64,
    q_su: f64,
    /// `Σ_{l∈S} p_{x_i x_l}` (when `inside` is not empty).
    p_s: Vec<f64>,
}

impl TwoParts {
    /// `U`'s members by their joint with the other clusters (`to_others`, `k × o`), the
    /// other clusters' weights, the members' weights and their joint among themselves
    /// (`inside`, `k × k`). `S` starts empty.
    pub(crate) fn new(
        to_others: Vec<f64>,
        w_others: Vec<f64>,
        w_members: Vec<f64>,
        inside: Vec<f64>,
    ) -> Self {
        let (k, o) = (w_members.len(), w_others.len());
        let mut q_u = vec![0.0; o];
        for i in 0..k {
            for (d, q) in q_u.iter_mut().enumerate() {
                *q += to_others[i * o + d];
            }
        }
        let row_u: Vec<f64> = (0..k)
            .map(|i| {
                inside
                    .get(i * k..(i + 1) * k)
                    .map_or(0.0, |r| r.iter().sum())
            })
            .collect();
        let inside = if inside.iter().any(|&v| v != 0.0) {
            inside
        } else {
            Vec::new()
        };
        Self {
            k,
            o,
            w_u: w_members.iter().sum(),
            q_uu: row_u.iter().sum(),
            to_others,
            w_others,
            w_members,
            inside,
            row_u,
            q_u,
            in_s: vec![false; k],
            q_s: vec![0.0; o],
            w_s: 0.0,
            q_ss: 0.0,
            q_su: 0.0,
            p_s: vec![0.0; k],
        }
    }

    /// Members of `U`.
    pub(crate) fn len(&self) -> usize {
        self.k
    }

    /// Moves member `i` into `S` (`into`) or out of it; nothing if it is there already.
    pub(crate) fn set(&mut self, i: usize, into: bool) {
        if self.in_s[i] == into {
            return;
        }
        let sign = if into { 1.0 } else { -1.0 };
        let o = self.o;
        for (q, &v) in self.q_s.iter_mut().zip(&self.to_others[i * o..(i + 1) * o]) {
            *q += sign * v;
        }
        self.w_s += sign * self.w_members[i];
        self.q_su += sign * self.row_u[i];
        if !self.inside.is_empty() {
            let k = self.k;
            if into {
                self.q_ss += 2.0 * self.p_s[i] + self.inside[i * k + i];
            }
            for l in 0..k {
                self.p_s[l] += sign * self.inside[l * k + i];
            }
            if !into {
                self.q_ss -= 2.0 * self.p_s[i] + self.inside[i * k + i];
            }
        }
        self.in_s[i] = into;
    }

    /// `V(S)` for the current `S` (module docs).
    pub(crate) fn value(&self) -> f64 {
        let w_t = (self.w_u - self.w_s).max(0.0);
        let mut v = 0.0;
        for d in 0..self.o {
            let (q_s, w_d) = (self.q_s[d].max(0.0), self.w_others[d]);
            let q_t = (self.q_u[d] - self.q_s[d]).max(0.0);
            v += 2.0 * (term(q_s, self.w_s * w_d) + term(q_t, w_t * w_d));
        }
        let q_st = (self.q_su - self.q_ss).max(0.0);
        let q_tt = (self.q_uu - self.q_ss - 2.0 * q_st).max(0.0);
        v + term(self.q_ss.max(0.0), self.w_s * self.w_s)
            + term(q_tt, w_t * w_t)
            + 2.0 * term(q_st, self.w_s * w_t)
    }

    /// `V` of `U` left whole (`S` empty).
    pub(crate) fn whole(&self) -> f64 {
        let mut v = 0.0;
        for d in 0..self.o {
            v += 2.0 * term(self.q_u[d], self.w_u * self.w_others[d]);
        }
        v + term(self.q_uu, self.w_u * self.w_u)
    }

    /// The best cut of `U` read as a path in member order: `S` the first `t` members,
    /// `1 ≤ t < k`. Returns `(V, t)`; `None` below two members. Leaves `S` empty.
    pub(crate) fn best_prefix(&mut self) -> Option<(f64, usize)> {
        let mut best: Option<(f64, usize)> = None;
        for t in 1..self.k {
            self.set(t - 1, true);
            let v = self.value();
            if best.is_none_or(|(b, _)| v > b) {
                best = Some((v, t));
            }
        }
        for i in 0..self.k {
            self.set(i, false);
        }
        best
    }
}

/// Whether the members in `mask` are connected by `neighbours` (bit `i` of `neighbours[i]`'s
/// mask: the members adjacent to member `i`); false for an empty mask.
fn connected(mask: u32, neighbours: &[u32]) -> bool {
    if mask == 0 {
        return false;
    }
    let mut reached = mask & mask.wrapping_neg();
    loop {
        let mut next = reached;
        let mut bits = reached;
        while bits != 0 {
            let i = bits.trailing_zeros() as usize;
            bits &= bits - 1;
            next |= neighbours[i] & mask;
        }
        if next == reached {
            return reached == mask;
        }
        reached = next;
    }
}

/// The best cut of `U` (at most [`EXACT_SPLIT_PATCHES`] members) into two connected parts,
/// `neighbours[i]` the mask of members adjacent to member `i`: every `S` not holding member
/// 0, in Gray code order (module docs). Returns `(V(S), mask of S)`; `None` when no cut
/// leaves both parts connected or `U` is too large. Leaves `S` empty.
pub(crate) fn best_bipartition(parts: &mut TwoParts, neighbours: &[u32]) -> Option<(f64, u32)> {
    let k = parts.len();
    if !(2..=EXACT_SPLIT_PATCHES).contains(&k) || neighbours.len() != k {
        return None;
    }
    let full = (1u32 << k) - 1;
    let mut mask = 0u32;
    let mut best: Option<(f64, u32)> = None;
    for step in 1u32..(1u32 << (k - 1)) {
        let i = step.trailing_zeros() as usize + 1;
        mask ^= 1 << i;
        parts.set(i, mask & (1 << i) != 0);
        // Most cuts leave a part in pieces: check that first (bit operations, no logarithm).
        if !(connected(mask, neighbours) && connected(full & !mask, neighbours)) {
            continue;
        }
        let v = parts.value();
        if best.is_none_or(|(b, _)| v > b) {
            best = Some((v, mask));
        }
    }
    for i in 0..k {
        parts.set(i, false);
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4-member set, two other clusters, members seeing each other.
    fn parts() -> TwoParts {
        let to_others = vec![0.10, 0.02, 0.08, 0.03, 0.01, 0.09, 0.02, 0.07];
        let inside = vec![
            0.00, 0.01, 0.02, 0.00, //
            0.01, 0.00, 0.00, 0.01, //
            0.02, 0.00, 0.00, 0.02, //
            0.00, 0.01, 0.02, 0.01,
        ];
        TwoParts::new(
            to_others,
            vec![0.3, 0.25],
            vec![0.15, 0.12, 0.14, 0.11],
            inside,
        )
    }

    /// `V(S)` from scratch, for a mask.
    fn direct(p: &TwoParts, mask: u32) -> f64 {
        let (k, o) = (p.k, p.o);
        let full: Vec<f64> = if p.inside.is_empty() {
            vec![0.0; k * k]
        } else {
            p.inside.clone()
        };
        let side = |i: usize| mask & (1 << i) != 0;
        let (mut w_s, mut w_t) = (0.0, 0.0);
        let (mut q_s, mut q_t) = (vec![0.0; o], vec![0.0; o]);
        let (mut ss, mut st, mut tt) = (0.0, 0.0, 0.0);
        for i in 0..k {
            let (w, q) = if side(i) {
                (&mut w_s, &mut q_s)
            } else {
                (&mut w_t, &mut q_t)
            };
            *w += p.w_members[i];
            for (d, q_d) in q.iter_mut().enumerate() {
                *q_d += p.to_others[i * o + d];
            }
            for l in 0..k {
                let v = full[i * k + l];
                match (side(i), side(l)) {
                    (true, true) => ss += v,
                    (false, false) => tt += v,
                    _ => st += v / 2.0,
                }
            }
        }
        let mut v = 0.0;
        for d in 0..o {
            v += 2.0 * (term(q_s[d], w_s * p.w_others[d]) + term(q_t[d], w_t * p.w_others[d]));
        }
        v + term(ss, w_s * w_s) + term(tt, w_t * w_t) + 2.0 * term(st, w_s * w_t)
    }

    #[test]
    fn incremental_values_are_the_direct_ones() {
        let mut p = parts();
        for mask in 1u32..16 {
            for i in 0..4 {
                p.set(i, mask & (1 << i) != 0);
            }
            assert!((p.value() - direct(&p, mask)).abs() < 1e-15, "{mask:b}");
        }
        for i in 0..4 {
            p.set(i, false);
        }
        // S empty: V is U whole.
        assert!((p.value() - p.whole()).abs() < 1e-15);
    }

    #[test]
    fn the_exact_search_finds_the_best_connected_cut() {
        let mut p = parts();
        // A path 0 – 1 – 2 – 3.
        let neighbours = [0b0010, 0b0101, 0b1010, 0b0100];
        let (v, mask) = best_bipartition(&mut p, &neighbours).unwrap();
        let mut best = f64::NEG_INFINITY;
        for m in 1u32..15 {
            if m & 1 == 0 && connected(m, &neighbours) && connected(15 & !m, &neighbours) {
                best = best.max(direct(&p, m));
            }
        }
        assert!((v - best).abs() < 1e-15);
        assert!((direct(&p, mask) - v).abs() < 1e-15);
        // The path's prefixes are its connected cuts (S the prefix, or its complement).
        let (prefix, _) = p.best_prefix().unwrap();
        assert!((prefix - v).abs() < 1e-15);
        // Splitting never loses (Proposition 3).
        assert!(v >= p.whole() - 1e-15);
    }
}
