//! Greedy simplification: merge the adjacent pair of patches a criterion ranks first, until
//! a patch count or a loss budget is reached.
//!
//! Criteria ([`MergeCriterion`]), smallest key first, ties to the smallest pair `(a, b)`:
//!
//! - `Information`: the information the merge loses, `loss(a, b)` (module docs of
//!   [`crate::simplify`]; Proposition 3 in reverse);
//! - `Regular`: the number of original patches the merged patch would hold, so a mesh of
//!   equal patches is merged in fixed pairs along each surface, then pairs of pairs — regular
//!   coarsening, the mirror of regular halving (`refine::refiner2`);
//! - `Power`: the power the merge displaces. Merged patches take the area-weighted mean of
//!   their fine radiosities, `B̄_c = (A_a B̄_a + A_b B̄_b) / (A_a + A_b)`, which moves
//!   `A_a |B̄_a − B̄_c| + A_b |B̄_b − B̄_c| = 2 A_a A_b |B̄_a − B̄_b| / (A_a + A_b)` of power,
//!   summed over the colour channels (areas relative to the scene's). It is the merging
//!   counterpart of the power oracle (2.48), which refines where the power `ρ_i A_i F_ij B_j`
//!   an element receives is large: here the merge that disturbs the least power goes first.
//!
//! Cost. A merge changes the information loss of *every* other candidate `(k, l)`: the
//! terms of `loss(k, l)` for the two merged states `a`, `b` become one term for their union
//! (a smaller one, by the log-sum inequality). A priority queue with lazy invalidation, which
//! re-keys only the candidates that touch `a` or `b`, would keep stale keys that overstate
//! the losses, and pop the wrong pair. So every candidate's loss is updated in place, in
//! `O(1)` from rows `k` and `l` at columns `a` and `b`,
//!
//! ```text
//! loss(k, l) += 2 [G((p_ka + p_kb, w_k), (p_la + p_lb, w_l)) − G((p_ka, w_k), (p_la, w_l))
//!                                                          − G((p_kb, w_k), (p_lb, w_l))]
//! ```
//!
//! (`G` the log-sum gap of `refine::proposition::two_state_split_gain`), the
//! candidates of the merged patch are recomputed (`O(n)` each), and the smallest is found by
//! one scan: `O(C + d n)` per merge for `C` candidates and `d` neighbours, `O(n²)` to simplify
//! a mesh of `n` patches with `O(n)` candidates. The updated keys drift by rounding (a few
//! ulps per merge), so they only choose: the loss a merge reports is recomputed exactly from
//! the rows before it merges.

use alloc::vec;
use alloc::vec::Vec;
use core::cmp::Ordering;

use super::adjacency::neighbour_lists;
use super::chain::MergeChain;
use crate::error::{ErrorKind, Result};
use crate::refine::proposition::pair_gap;

/// How a [`Simplifier`] ranks the candidate merges (module docs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum MergeCriterion {
    /// The least information lost (exact, Proposition 3 in reverse).
    Information,
    /// The fewest original patches in the merged patch (regular coarsening).
    Regular,
    /// The least power displaced, `2 A_a A_b |B̄_a − B̄_b| / (A_a + A_b)` over RGB.
    Power,
}

impl MergeCriterion {
    /// All three, in the order reports list them.
    pub const ALL: [Self; 3] = [Self::Information, Self::Regular, Self::Power];

    /// The criterion's name as the CLI spells it: `mi`, `regular`, `power`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Information => "mi",
            Self::Regular => "regular",
            Self::Power => "power",
        }
    }
}

/// One merge.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MergeStep {
    /// Merges so far, this one included.
    pub step: u64,
    /// The representative of the merged patch (the smaller of the two).
    pub kept: usize,
    /// The representative of the patch it absorbed.
    pub absorbed: usize,
    /// The criterion's key for this merge (bits for `Information`).
    pub key: f64,
    /// Information lost by this merge (bits), exact.
    pub loss: f64,
    /// Patches after the merge.
    pub n_patches: usize,
    /// `I_S` after the merge: the starting `I_S` less the losses so far.
    pub i_s: f64,
}

/// Why [`Simplifier::run`] stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StopReason {
    /// The patch count reached the target.
    Target,
    /// The next merge would have taken the total loss past the budget.
    Budget,
    /// No two patches may merge any more (every run of adjacent patches is one patch).
    NoCandidates,
}

impl StopReason {
    /// A short phrase for reports: `target`, `budget`, `no adjacent patches`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Target => "target",
            Self::Budget => "budget",
            Self::NoCandidates => "no adjacent patches",
        }
    }
}

/// A candidate merge of live states `a < b` and its key.
#[derive(Clone, Copy, Debug)]
struct Candidate {
    a: usize,
    b: usize,
    key: f64,
}

impl Candidate {
    fn order(&self, other: &Self) -> Ordering {
        self.key
            .total_cmp(&other.key)
            .then(self.a.cmp(&other.a))
            .then(self.b.cmp(&other.b))
    }
}

/// Greedy merges of adjacent patches of a [`MergeChain`] (module docs).
///
/// # Examples
///
/// ```
/// use sceneinfo::formfactor::exact_2d;
/// use sceneinfo::scene::Scene2;
/// use sceneinfo::simplify::{MergeChain, MergeCriterion, Simplifier, adjacency};
///
/// let scene = Scene2::regular_polygon(4, 4)?; // a square room, 16 patches
/// let ff = exact_2d::form_factors(&scene)?;
/// let chain = MergeChain::new(ff.weights(), &ff.matrix())?;
/// let pairs = adjacency::adjacency_2d(&scene);
/// let mut s = Simplifier::new(chain, 16, &pairs, MergeCriterion::Information, None)?;
/// let start = s.i_s();
/// let (steps, _) = s.run(8, None)?;
/// assert_eq!(s.n_patches(), 8);
/// assert!(steps.iter().all(|step| step.loss >= 0.0) && s.i_s() <= start);
/// # Ok::<(), sceneinfo::Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct Simplifier {
    chain: MergeChain,
    criterion: MergeCriterion,
    /// Sorted neighbours of each live patch state (empty for others).
    neighbours: Vec<Vec<usize>>,
    candidates: Vec<Candidate>,
    /// Original patches per state.
    counts: Vec<u64>,
    /// `Σ w_x B_x` per state and colour channel (the power criterion).
    power: Vec<[f64; 3]>,
    n_patches: usize,
    start_i_s: f64,
    i_s: f64,
    lost: f64,
    steps: u64,
}

impl Simplifier {
    /// Starts simplifying `chain`, whose first `n_patches` states are patches (any later
    /// state, such as an open scene's background, never merges), with the pairs of patches
    /// in `adjacency` allowed to merge ([`super::adjacency`]). `radiosity` (one RGB value per
    /// patch, the fine solution) is needed by [`MergeCriterion::Power`] only.
    ///
    /// # Errors
    /// [`ErrorKind::PatchIndex`] for a pair naming a state `≥ n_patches` or a patch twice,
    /// or `n_patches` above the chain's states; [`ErrorKind::DimensionMismatch`] when the
    /// power criterion has no radiosity or not one per patch; the errors of
    /// [`MergeChain::i_s`].
    pub fn new(
        chain: MergeChain,
        n_patches: usize,
        adjacency: &[(usize, usize)],
        criterion: MergeCriterion,
        radiosity: Option<&[[f64; 3]]>,
    ) -> Result<Self> {
        let n = chain.n_states();
        if n_patches > n {
            return Err(ErrorKind::PatchIndex {
                index: n_patches,
                len: n,
            }
            .into());
        }
        let mut power = vec![[0.0; 3]; n];
        match radiosity {
            Some(b) if b.len() == n_patches => {
                for (x, rgb) in b.iter().enumerate() {
                    let w = chain.weight(x);
                    power[x] = rgb.map(|v| w * v);
                }
            }
            Some(b) => {
                return Err(ErrorKind::DimensionMismatch {
                    expected: n_patches,
                    found: b.len(),
                }
                .into());
            }
            None if criterion == MergeCriterion::Power => {
                return Err(ErrorKind::DimensionMismatch {
                    expected: n_patches,
                    found: 0,
                }
                .into());
            }
            None => {}
        }
        let mut neighbours = neighbour_lists(adjacency, n_patches)?;
        if let Some(x) = (0..n_patches).find(|&x| !neighbours[x].is_empty() && !chain.is_live(x)) {
            return Err(ErrorKind::PatchIndex {
                index: x,
                len: n_patches,
            }
            .into());
        }
        neighbours.resize(n, Vec::new());
        let i_s = chain.i_s()?;
        let mut s = Self {
            chain,
            criterion,
            neighbours,
            candidates: Vec::new(),
            counts: vec![1; n],
            power,
            n_patches,
            start_i_s: i_s,
            i_s,
            lost: 0.0,
            steps: 0,
        };
        for a in 0..n_patches {
            for k in 0..s.neighbours[a].len() {
                let b = s.neighbours[a][k];
                if a < b {
                    let key = s.key(a, b);
                    s.candidates.push(Candidate { a, b, key });
                }
            }
        }
        Ok(s)
    }

    /// The criterion's key of merging live states `a` and `b`.
    fn key(&self, a: usize, b: usize) -> f64 {
        match self.criterion {
            MergeCriterion::Information => self.chain.merge_loss(a, b),
            MergeCriterion::Regular => (self.counts[a] + self.counts[b]) as f64,
            MergeCriterion::Power => {
                let (w_a, w_b) = (self.chain.weight(a), self.chain.weight(b));
                let w = w_a + w_b;
                if !(w > 0.0) {
                    return 0.0;
                }
                let moved: f64 = (0..3)
                    .map(|c| (self.power[a][c] / w_a - self.power[b][c] / w_b).abs())
                    .sum();
                2.0 * w_a * w_b / w * moved
            }
        }
    }

    /// The chain as merged so far.
    #[must_use]
    pub fn chain(&self) -> &MergeChain {
        &self.chain
    }

    /// The criterion.
    #[must_use]
    pub fn criterion(&self) -> MergeCriterion {
        self.criterion
    }

    /// Patches now (the background, if any, not counted).
    #[must_use]
    pub fn n_patches(&self) -> usize {
        self.n_patches
    }

    /// `I_S` of the starting mesh (bits).
    #[must_use]
    pub fn start_i_s(&self) -> f64 {
        self.start_i_s
    }

    /// `I_S` now: the starting `I_S` less every merge's loss.
    #[must_use]
    pub fn i_s(&self) -> f64 {
        self.i_s
    }

    /// Information lost so far (bits).
    #[must_use]
    pub fn lost(&self) -> f64 {
        self.lost
    }

    /// The merge the criterion ranks first, `(a, b)` with `a < b`, if any.
    #[must_use]
    pub fn best(&self) -> Option<(usize, usize)> {
        self.candidates
            .iter()
            .min_by(|x, y| x.order(y))
            .map(|c| (c.a, c.b))
    }

    /// Merges the pair the criterion ranks first; `None` when no pair may merge.
    ///
    /// # Errors
    /// None in practice (the pair is live); [`MergeChain::merge`]'s otherwise.
    pub fn step(&mut self) -> Result<Option<MergeStep>> {
        let Some(best) = self.candidates.iter().min_by(|x, y| x.order(y)).copied() else {
            return Ok(None);
        };
        let (a, b) = (best.a, best.b);
        if self.criterion == MergeCriterion::Information {
            self.update_losses(a, b);
        }
        let loss = self.chain.merge(a, b)?;
        // Neighbours: a takes b's.
        let moved = core::mem::take(&mut self.neighbours[b]);
        for &x in &moved {
            let list = &mut self.neighbours[x];
            for v in list.iter_mut() {
                if *v == b {
                    *v = a;
                }
            }
            list.sort_unstable();
            list.dedup();
        }
        let mut merged = core::mem::take(&mut self.neighbours[a]);
        merged.extend(moved);
        merged.retain(|&x| x != a && x != b);
        merged.sort_unstable();
        merged.dedup();
        self.neighbours[a] = merged;
        self.counts[a] += self.counts[b];
        self.counts[b] = 0;
        let pb = self.power[b];
        for (p, q) in self.power[a].iter_mut().zip(pb) {
            *p += q;
        }
        self.power[b] = [0.0; 3];
        // Candidates of a and b go; a's new ones come.
        self.candidates
            .retain(|c| c.a != a && c.b != a && c.a != b && c.b != b);
        for k in 0..self.neighbours[a].len() {
            let x = self.neighbours[a][k];
            let key = self.key(a, x);
            self.candidates.push(Candidate {
                a: a.min(x),
                b: a.max(x),
                key,
            });
        }
        self.n_patches -= 1;
        self.lost += loss;
        self.i_s = self.start_i_s - self.lost;
        self.steps += 1;
        Ok(Some(MergeStep {
            step: self.steps,
            kept: a,
            absorbed: b,
            key: best.key,
            loss,
            n_patches: self.n_patches,
            i_s: self.i_s,
        }))
    }

    /// Before `a` and `b` merge: every other candidate's loss takes the change of its terms
    /// for `a` and `b` (module docs).
    fn update_losses(&mut self, a: usize, b: usize) {
        let chain = &self.chain;
        for c in &mut self.candidates {
            let (k, l) = (c.a, c.b);
            if k == a || k == b || l == a || l == b {
                continue;
            }
            let (row_k, row_l) = (chain.joint_row(k), chain.joint_row(l));
            let (w_k, w_l) = (chain.weight(k), chain.weight(l));
            let before =
                pair_gap(row_k[a], w_k, row_l[a], w_l) + pair_gap(row_k[b], w_k, row_l[b], w_l);
            let after = pair_gap(row_k[a] + row_k[b], w_k, row_l[a] + row_l[b], w_l);
            c.key = (c.key + 2.0 * (after - before)).max(0.0);
        }
    }

    /// Merges until `target` patches are left, the next merge would take the information
    /// lost past `max_loss` bits (when given), or no pair may merge. At most one merge per
    /// patch.
    ///
    /// # Errors
    /// As [`Simplifier::step`].
    pub fn run(
        &mut self,
        target: usize,
        max_loss: Option<f64>,
    ) -> Result<(Vec<MergeStep>, StopReason)> {
        let mut steps = Vec::new();
        while self.n_patches > target {
            let Some((a, b)) = self.best() else {
                return Ok((steps, StopReason::NoCandidates));
            };
            if let Some(budget) = max_loss
                && self.lost + self.chain.merge_loss(a, b) > budget
            {
                return Ok((steps, StopReason::Budget));
            }
            match self.step()? {
                Some(step) => steps.push(step),
                None => return Ok((steps, StopReason::NoCandidates)),
            }
        }
        Ok((steps, StopReason::Target))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::formfactor::exact_2d;
    use crate::scene::Scene2;
    use crate::simplify::adjacency::adjacency_2d;

    #[test]
    fn updated_losses_stay_the_exact_losses() {
        // A room with occluders: every merge changes the other candidates' losses.
        let scene = Scene2::catalogue("three-objects-2", 6).unwrap();
        let ff = exact_2d::form_factors(&scene).unwrap();
        let chain = MergeChain::new(ff.weights(), &ff.matrix()).unwrap();
        let n = scene.n_patches();
        let pairs = adjacency_2d(&scene);
        let mut s = Simplifier::new(chain, n, &pairs, MergeCriterion::Information, None).unwrap();
        for _ in 0..n / 2 {
            s.step().unwrap();
            for c in &s.candidates {
                let exact = s.chain.merge_loss(c.a, c.b);
                assert!((c.key - exact).abs() < 1e-13, "{} vs {exact}", c.key);
            }
        }
    }
}
