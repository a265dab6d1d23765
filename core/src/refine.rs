//! Refinement (thesis §5.4 and chapter 6): how much mutual information a finer mesh gains,
//! how much a mesh loses against the continuous scene, and meshes that chase the loss.
//!
//! - [`proposition`]: Proposition 3 — the exact gain `ΔI ≥ 0` of splitting a state of any
//!   reversible Markov chain (5.26–5.31), the patch-to-patch gain (5.32), its regular-split
//!   maxima (5.34, 5.35) and the visibility, radiosity and importance instances (5.36, 5.42,
//!   5.44–5.45). Slices in, numbers out; no allocation.
//! - [`cuts`]: the best single cut of the configurations of §6.1 (squares sharing an
//!   edge, a square in a corner, a radiosity gradient `lⁿ`).
//! - [`discretisation`]: the discretisation error between two patches, `δ_ij = I_ij^c − I_ij`,
//!   for visibility and radiosity, from patch-to-patch random point pairs (6.19, 6.24) or from
//!   local/global lines (6.21, 6.27; for every pair at once from one line estimate:
//!   `visibility_errors_from_lines`, `radiosity_errors_from_lines`), and per patch
//!   `I_i^c − I_i`.
//! - [`profile`] (alloc): `I^c` along every surface, tallied once from lines over a fine
//!   copy of the scene, so the `I_i^c` of any patch of any later mesh is a difference of two
//!   cumulative values.
//! - [`symmetric`] (alloc): `I_S` maximised over mirrored cut positions of a regular polygon
//!   (§6.5.1, Fig. 6.12, Table 6.1).
//! - [`refiner2`] (alloc): flatland refinement one step at a time (§6.5.2): the
//!   discretisation-error (DE) oracle, the "power-based" rival and regular halving.
//!
//! Every gain and error is in bits.

pub mod cuts;
pub mod discretisation;
#[cfg(feature = "alloc")]
pub mod profile;
pub mod proposition;
#[cfg(feature = "alloc")]
pub mod refiner2;
#[cfg(feature = "alloc")]
pub mod symmetric;

use crate::math::{self, KahanSum};

/// `Σ_k p_k log₂((p_k / P) / (v_k / V))` for `P = Σ p_k`, `V = Σ v_k`: by the log-sum
/// inequality (2.67, 5.30) `Σ p_k log(p_k / v_k) ≥ P log(P / V)`, and this is the
/// difference of the two sides, `P · D(p/P ‖ v/V) ≥ 0`. Terms with `p_k = 0` are 0; a
/// rounding residue below zero is clamped to 0; 0 when `P` or `V` is not positive.
pub(crate) fn log_sum_gap(terms: impl Iterator<Item = (f64, f64)> + Clone) -> f64 {
    let mut p_total = KahanSum::new();
    let mut v_total = KahanSum::new();
    for (p, v) in terms.clone() {
        p_total.add(p);
        v_total.add(v);
    }
    let (p_total, v_total) = (p_total.total(), v_total.total());
    if !(p_total > 0.0 && v_total > 0.0 && p_total.is_finite() && v_total.is_finite()) {
        return 0.0;
    }
    let mut s = KahanSum::new();
    for (p, v) in terms {
        if p > 0.0 && v > 0.0 {
            s.add(p * math::log2_ratio(p / p_total, v / v_total));
        }
    }
    s.total().max(0.0)
}
