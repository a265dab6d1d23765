//! Mesh simplification by mutual information (thesis §7.3: "a set of patches can be
//! clustered if the loss of information transfer is sufficiently small"; `docs/simplify.md`).
//!
//! Merging two states `a`, `b` of a reversible chain `(w, P)` into one state `c` gives the
//! chain with
//!
//! ```text
//! w_c = w_a + w_b
//! P_ck = (w_a P_ak + w_b P_bk) / w_c      rows combined by area weights
//! P_kc = P_ka + P_kb                      columns summed
//! ```
//!
//! i.e. the joint probabilities `p_xy = w_x P_xy` of `a` and `b` are added (`p_ck = p_ak +
//! p_bk`, `p_cc = p_aa + p_ab + p_ba + p_bb`). For form factors this is their additivity:
//! the coarse mesh's `F` is exactly the form factors of the merged patches. Splitting `c`
//! back into `a` and `b` is a split of Proposition 3 (§5.4: conditions (a) and (b) hold by
//! construction), so the merge loses exactly the gain of that split, `ΔI ≥ 0` (5.29–5.31),
//! computed by `refine::proposition::two_state_split_gain` from rows `a` and `b` of
//! the joint matrix and the weights alone:
//!
//! ```text
//! loss(a, b) = 2 Σ_{k ∉ {a,b}} [p_ak log₂(p_ak / w_a) + p_bk log₂(p_bk / w_b)
//!                               − (p_ak + p_bk) log₂((p_ak + p_bk) / (w_a + w_b))]
//!              + (the same log-sum gap over the 2 × 2 block p_aa, p_ab, p_ba, p_bb
//!                 against w_a², w_a w_b, w_b w_a, w_b²)
//! ```
//!
//! - [`chain`]: [`MergeChain`], a reversible chain held as its symmetric joint matrix;
//!   merges, losses, `I_S`, the coarse form factors.
//! - [`greedy`]: [`Simplifier`], greedy merges of adjacent patches by a [`MergeCriterion`]
//!   (least information lost, regular blocks, least power displaced), to a patch count or a
//!   loss budget.
//! - [`mod@polish`]: a local search after the greedy merge (boundary moves and transfers
//!   between adjacent clusters at a fixed patch count, taken only when `I_S` rises).
//! - [`adjacency`]: which patches may merge — flatland: neighbours along one surface;
//!   3D: patches of one plane sharing an edge; same material in both.
//! - [`compare`]: the three criteria at equal patch count — `I_S` kept and the radiosity
//!   error of the coarse mesh against the fine solution.
//!
//! Every loss is in bits.

pub mod adjacency;
pub mod chain;
pub mod compare;
pub mod greedy;
pub mod polish;
mod split;

pub use chain::MergeChain;
pub use compare::{Comparison, CriterionOutcome, compare_criteria};
pub use greedy::{MergeCriterion, MergeStep, Simplifier, StopReason};
pub use polish::Polished;

/// Most states (patches and a background) a [`MergeChain`] holds: it keeps a dense `n × n`
/// joint matrix (`8 n²` bytes: 134 MB at this cap).
pub(crate) const MAX_MERGE_STATES: usize = 4096;
