//! A reversible chain whose states merge: its joint matrix `p_xy = w_x P_xy`, the loss of a
//! merge (Proposition 3 in reverse) and the merged chain's form factors and `I_S`.

use alloc::vec;
use alloc::vec::Vec;

use super::MAX_MERGE_STATES;
use crate::channel::{Channel, DenseMatrix, Transitions};
use crate::error::{ErrorKind, Result};
use crate::refine::proposition::two_state_split_gain;

/// A reversible chain `(w, P)` held as its joint matrix, whose states can be merged
/// (module docs of [`crate::simplify`] for the equations).
///
/// States keep their indices: a merge of `a < b` keeps `a` (the merged state) and empties
/// `b`. A merged state is named by the smallest original state it holds, its
/// *representative*.
#[derive(Clone, Debug, PartialEq)]
pub struct MergeChain {
    n: usize,
    /// `p_xy`, row-major `n × n`, exactly symmetric; rows and columns of absorbed states 0.
    joint: Vec<f64>,
    /// `w_x`; 0 for absorbed states.
    weights: Vec<f64>,
    /// For every original state, the representative of the state that holds it now.
    cluster: Vec<usize>,
}

impl MergeChain {
    /// The chain of weights `w` and transitions `P`, with the joint matrix made exactly
    /// symmetric: `p_xy = p_yx = (w_x P_xy + w_y P_yx) / 2`. For form factors that are
    /// reciprocal to rounding (`A_i F_ij = A_j F_ji`) this moves entries by rounding only,
    /// and it makes the reciprocity the loss formula assumes (rows = columns) exact.
    ///
    /// # Errors
    /// [`ErrorKind::DimensionMismatch`] when `w` and `P` differ in size;
    /// [`ErrorKind::TooLarge`] above `MAX_MERGE_STATES` states; the errors of
    /// [`Channel::new`] (`w` a distribution, rows summing to at most one).
    pub fn new<M: Transitions>(w: &[f64], p: &M) -> Result<Self> {
        let n = p.n_states();
        if n > MAX_MERGE_STATES {
            return Err(ErrorKind::TooLarge {
                what: "states of a chain to simplify",
                max: MAX_MERGE_STATES as u64,
            }
            .into());
        }
        // Validates w and P once (shapes, entries, normalisation).
        Channel::new(w, p)?;
        let mut joint = vec![0.0; n * n];
        for x in 0..n {
            p.for_each_in_row(x, |y, v| joint[x * n + y] = w[x] * v);
        }
        for x in 0..n {
            for y in x + 1..n {
                let mean = 0.5 * (joint[x * n + y] + joint[y * n + x]);
                joint[x * n + y] = mean;
                joint[y * n + x] = mean;
            }
        }
        Ok(Self {
            n,
            joint,
            weights: w.to_vec(),
            cluster: (0..n).collect(),
        })
    }

    /// The chain of weights `w` and joint matrix `joint` (row-major `n × n`, `p_xy = w_x
    /// P_xy`), made exactly symmetric as in [`MergeChain::new`]. Used to simplify a chain
    /// whose states are already clusters (the split search of [`super::polish`]); no check
    /// beyond the sizes, as its entries come from a validated chain.
    ///
    /// # Errors
    /// [`ErrorKind::DimensionMismatch`] when `joint` is not `w.len()²` long;
    /// [`ErrorKind::TooLarge`] above [`MAX_MERGE_STATES`] states.
    pub(crate) fn from_joint(w: Vec<f64>, mut joint: Vec<f64>) -> Result<Self> {
        let n = w.len();
        if n > MAX_MERGE_STATES {
            return Err(ErrorKind::TooLarge {
                what: "states of a chain to simplify",
                max: MAX_MERGE_STATES as u64,
            }
            .into());
        }
        if joint.len() != n * n {
            return Err(ErrorKind::DimensionMismatch {
                expected: n * n,
                found: joint.len(),
            }
            .into());
        }
        for x in 0..n {
            for y in x + 1..n {
                let mean = 0.5 * (joint[x * n + y] + joint[y * n + x]);
                joint[x * n + y] = mean;
                joint[y * n + x] = mean;
            }
        }
        Ok(Self {
            n,
            joint,
            weights: w,
            cluster: (0..n).collect(),
        })
    }

    /// States, merged or not (the original count).
    #[must_use]
    pub fn n_states(&self) -> usize {
        self.n
    }

    /// Whether state `x` still exists (was not absorbed by a merge).
    #[must_use]
    pub fn is_live(&self, x: usize) -> bool {
        self.weights.get(x).is_some_and(|&w| w > 0.0)
    }

    /// The states that exist, in index order.
    #[must_use]
    pub fn live_states(&self) -> Vec<usize> {
        (0..self.n).filter(|&x| self.is_live(x)).collect()
    }

    /// `w_x` (0 for an absorbed state or a bad index).
    #[must_use]
    pub fn weight(&self, x: usize) -> f64 {
        self.weights.get(x).copied().unwrap_or(0.0)
    }

    /// Row `x` of the joint matrix, `p_xy` for every `y` (empty for a bad index).
    #[must_use]
    pub fn joint_row(&self, x: usize) -> &[f64] {
        self.joint.get(x * self.n..(x + 1) * self.n).unwrap_or(&[])
    }

    /// The representative of the state holding original state `x` now (`x` itself for a bad
    /// index).
    #[must_use]
    pub fn cluster_of(&self, x: usize) -> usize {
        self.cluster.get(x).copied().unwrap_or(x)
    }

    /// For every original state, the representative of the state holding it.
    #[must_use]
    pub fn clusters(&self) -> &[usize] {
        &self.cluster
    }

    /// The information (bits) merging live states `a` and `b` would lose: the gain of
    /// Proposition 3 for splitting the merged state back (5.29), from rows `a` and `b` and
    /// `w_a`, `w_b` only (`O(n)`). 0 when `a == b` or either is not live.
    #[must_use]
    pub fn merge_loss(&self, a: usize, b: usize) -> f64 {
        if !(self.is_live(a) && self.is_live(b)) {
            return 0.0;
        }
        two_state_split_gain(
            a,
            b,
            self.weights[a],
            self.weights[b],
            self.joint_row(a),
            self.joint_row(b),
        )
    }

    /// Merges live states `a` and `b` into the smaller index of the two: weights and joint
    /// rows and columns added. Returns the information lost, [`MergeChain::merge_loss`]
    /// before the merge. `O(n)`.
    ///
    /// # Errors
    /// [`ErrorKind::PatchIndex`] when `a` or `b` is not a live state or `a == b`.
    pub fn merge(&mut self, a: usize, b: usize) -> Result<f64> {
        for x in [a, b] {
            if !self.is_live(x) || a == b {
                return Err(ErrorKind::PatchIndex {
                    index: x,
                    len: self.n,
                }
                .into());
            }
        }
        let loss = self.merge_loss(a, b);
        let (keep, gone) = (a.min(b), a.max(b));
        let n = self.n;
        for y in 0..n {
            let moved = self.joint[gone * n + y];
            self.joint[keep * n + y] += moved;
            self.joint[gone * n + y] = 0.0;
        }
        for x in 0..n {
            let moved = self.joint[x * n + gone];
            self.joint[x * n + keep] += moved;
            self.joint[x * n + gone] = 0.0;
        }
        self.weights[keep] += self.weights[gone];
        self.weights[gone] = 0.0;
        for c in &mut self.cluster {
            if *c == gone {
                *c = keep;
            }
        }
        Ok(loss)
    }

    /// The merged chain compacted to its live states: `(states, w', F')` with `states` the
    /// live representatives in index order, `w'` their weights and `F'_xy = p_xy / w_x`
    /// row-major — the form factors of the coarse mesh (their additivity).
    #[must_use]
    pub fn coarse_form_factors(&self) -> (Vec<usize>, Vec<f64>, Vec<f64>) {
        let states = self.live_states();
        let m = states.len();
        let w: Vec<f64> = states.iter().map(|&x| self.weights[x]).collect();
        let mut f = vec![0.0; m * m];
        for (r, &x) in states.iter().enumerate() {
            for (c, &y) in states.iter().enumerate() {
                f[r * m + c] = self.joint[x * self.n + y] / w[r];
            }
        }
        (states, w, f)
    }

    /// `I_S` (3.8) of the merged chain, recomputed from its compacted form factors by
    /// [`Channel::i_s`] (independently of the losses).
    ///
    /// # Errors
    /// The errors of [`Channel::new`] (none for a chain built by [`MergeChain::new`] beyond
    /// rounding of the row sums).
    pub fn i_s(&self) -> Result<f64> {
        let (_, w, f) = self.coarse_form_factors();
        let m = w.len();
        let channel = Channel::new(&w, DenseMatrix::new(m, &f)?)?;
        Ok(channel.i_s())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 4-state chain from a symmetric joint matrix.
    fn chain() -> MergeChain {
        let joint = [
            [1.0, 1.0, 1.0, 0.0],
            [1.0, 0.0, 2.0, 2.0],
            [1.0, 2.0, 0.0, 3.0],
            [0.0, 2.0, 3.0, 0.0],
        ]
        .map(|row| row.map(|v: f64| v / 19.0));
        let w: Vec<f64> = joint.iter().map(|r| r.iter().sum()).collect();
        let mut p = vec![0.0; 16];
        for x in 0..4 {
            for y in 0..4 {
                p[x * 4 + y] = joint[x][y] / w[x];
            }
        }
        MergeChain::new(&w, &DenseMatrix::new(4, &p).unwrap()).unwrap()
    }

    #[test]
    fn every_merge_loses_what_i_s_loses() {
        let mut c = chain();
        let before = c.i_s().unwrap();
        let loss = c.merge(2, 1).unwrap();
        let after = c.i_s().unwrap();
        assert!(loss > 0.0);
        assert!(
            (before - after - loss).abs() < 1e-15,
            "{before} {after} {loss}"
        );
        assert_eq!(c.clusters(), &[0, 1, 1, 3]);
        assert_eq!(c.live_states(), vec![0, 1, 3]);
        let loss = c.merge(0, 3).unwrap();
        assert!((after - c.i_s().unwrap() - loss).abs() < 1e-15);
    }

    #[test]
    fn bad_merges_are_refused() {
        let mut c = chain();
        assert!(c.merge(1, 1).is_err());
        assert!(c.merge(0, 9).is_err());
        c.merge(0, 1).unwrap();
        assert!(c.merge(1, 2).is_err());
        assert_eq!(c.merge_loss(1, 2), 0.0);
    }

    #[test]
    fn merging_everything_leaves_no_information() {
        let mut c = chain();
        let mut lost = c.merge(0, 1).unwrap();
        lost += c.merge(0, 2).unwrap();
        lost += c.merge(0, 3).unwrap();
        let start = chain().i_s().unwrap();
        assert!((lost - start).abs() < 1e-15);
        assert!(c.i_s().unwrap().abs() < 1e-15);
    }
}
