//! Proposition 3 (thesis §5.4): the exact gain in mutual information when one state of a
//! reversible Markov chain is split into sub-states, and its instances for visibility,
//! radiosity and importance.
//!
//! A chain `(w, P)` with reciprocity `w_i P_ij = w_j P_ji` has mutual information (5.26)
//! `I = Σ_ij w_i P_ij log₂(P_ij / w_j)`. Split state `i` into `m` sub-states `i_k` with
//! weights `w_{i_k}` such that
//!
//! ```text
//! (a)  w_{i_k} P_{i_k j} = w_j P_{j i_k}         reciprocity with the sub-states
//! (b)  P_ji = Σ_k P_{j i_k}                       the sub-states cover i
//! ```
//!
//! (with `Σ_k w_{i_k} = w_i`). Writing `p_xy = w_x P_xy` for the joint probabilities, the
//! terms that change are (5.29)
//!
//! ```text
//! ΔI = I' − I = 2 Σ_{j≠i} [ Σ_k p_{i_k j} log₂(p_{i_k j} / w_{i_k}) − p_ij log₂(p_ij / w_i) ]
//!             + Σ_kl p_{i_k i_l} log₂(p_{i_k i_l} / (w_{i_k} w_{i_l})) − p_ii log₂(p_ii / w_i²)
//! ```
//!
//! Each bracket is `P · D(q ‖ r)` for `q_k = p_k / P`, `r_k = w_k / W` (the log-sum
//! inequality 2.67 / 5.30), so every bracket is computed in that form and is `≥ 0` by
//! construction (a rounding residue below zero is clamped to 0). The patch-to-patch gain
//! (5.32) is one bracket, doubled.
//!
//! Everything here works on caller slices and allocates nothing.

use super::log_sum_gap;
use crate::channel::{Channel, Transitions};
use crate::error::{ErrorKind, Result};
use crate::math::{self, KahanSum};

/// Tolerance on the conditions of Proposition 3, on joint probabilities `w_x P_xy` (which
/// are at most 1): the same scale as [`crate::channel::ROW_SUM_TOLERANCE`].
pub(crate) const SPLIT_TOLERANCE: f64 = 1e-9;

/// The split of state `state` of an `n`-state chain into `m = weights.len()` sub-states.
///
/// The sub-states' transitions to and from the other states, and among themselves, are
/// given explicitly, so the conditions can be checked rather than assumed:
///
/// - `weights[k] = w_{i_k}` (`m` values, each `> 0`);
/// - `rows[k·n + j] = P'_{i_k j}`, sub-state `k` to old state `j ≠ state`;
/// - `columns[k·n + j] = P'_{j i_k}`, old state `j ≠ state` to sub-state `k`;
/// - `block[k·m + l] = P'_{i_k i_l}`.
///
/// Entries in column `state` of `rows` and `columns` are not transitions of the refined
/// chain and must be 0.
#[derive(Clone, Copy, Debug)]
pub struct StateSplit<'a> {
    /// The state `i` being split.
    pub state: usize,
    /// `w_{i_k}`.
    pub weights: &'a [f64],
    /// `P'_{i_k j}`, row-major `m × n`.
    pub rows: &'a [f64],
    /// `P'_{j i_k}`, row-major `m × n` (one row per sub-state).
    pub columns: &'a [f64],
    /// `P'_{i_k i_l}`, row-major `m × m`.
    pub block: &'a [f64],
}

/// Rejects a split whose entry is negative or not finite.
fn check_entries(values: &[f64], what: &'static str) -> Result<()> {
    match values.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
        Some(index) => Err(ErrorKind::InvalidSplit {
            condition: what,
            index,
            deviation: values[index],
        }
        .into()),
        None => Ok(()),
    }
}

/// Fails with [`ErrorKind::InvalidSplit`] when `|deviation| > SPLIT_TOLERANCE`.
fn within(deviation: f64, condition: &'static str, index: usize) -> Result<()> {
    if deviation.abs() <= SPLIT_TOLERANCE {
        Ok(())
    } else {
        Err(ErrorKind::InvalidSplit {
            condition,
            index,
            deviation,
        }
        .into())
    }
}

/// Checks the split's shapes, entries, weight conservation and conditions (a) and (b).
fn check_split<M: Transitions>(channel: &Channel<'_, M>, split: &StateSplit<'_>) -> Result<()> {
    let w = channel.weights();
    let p = channel.transitions();
    let n = w.len();
    let i = split.state;
    let m = split.weights.len();
    if i >= n {
        return Err(ErrorKind::PatchIndex { index: i, len: n }.into());
    }
    if m == 0 {
        return Err(ErrorKind::InvalidSplit {
            condition: "at least one sub-state",
            index: 0,
            deviation: 0.0,
        }
        .into());
    }
    for (len, expected) in [
        (split.rows.len(), m * n),
        (split.columns.len(), m * n),
        (split.block.len(), m * m),
    ] {
        if len != expected {
            return Err(ErrorKind::DimensionMismatch {
                expected,
                found: len,
            }
            .into());
        }
    }
    check_entries(split.weights, "sub-state weights finite and >= 0")?;
    if let Some(k) = split.weights.iter().position(|&v| v == 0.0) {
        return Err(ErrorKind::InvalidSplit {
            condition: "sub-state weights > 0",
            index: k,
            deviation: 0.0,
        }
        .into());
    }
    check_entries(split.rows, "transitions finite and >= 0")?;
    check_entries(split.columns, "transitions finite and >= 0")?;
    check_entries(split.block, "transitions finite and >= 0")?;
    for k in 0..m {
        within(split.rows[k * n + i], "no transition to the split state", k)?;
        within(
            split.columns[k * n + i],
            "no transition from the split state",
            k,
        )?;
    }
    // The sub-states carry the state's weight.
    within(
        math::sum(split.weights.iter().copied()) - w[i],
        "sub-state weights sum to the state's weight",
        i,
    )?;
    for j in (0..n).filter(|&j| j != i) {
        // (a) reciprocity with the sub-states.
        for k in 0..m {
            let out = split.weights[k] * split.rows[k * n + j];
            let back = w[j] * split.columns[k * n + j];
            within(out - back, "(a) reciprocity w_ik P_ik,j = w_j P_j,ik", j)?;
        }
        // (b) the sub-states cover i: P_ji = Σ_k P_{j i_k}.
        let cover = math::sum((0..m).map(|k| split.columns[k * n + j]));
        within(cover - p.get(j, i), "(b) cover P_ji = sum_k P_j,ik", j)?;
    }
    // (a) among the sub-states, and (b) for the state's transitions to itself.
    for k in 0..m {
        for l in 0..m {
            let kl = split.weights[k] * split.block[k * m + l];
            let lk = split.weights[l] * split.block[l * m + k];
            within(kl - lk, "(a) reciprocity among the sub-states", k)?;
        }
    }
    let self_flow = math::sum((0..m * m).map(|kl| split.weights[kl / m] * split.block[kl]));
    within(
        self_flow - w[i] * p.get(i, i),
        "(b) cover of the state's own transitions",
        i,
    )
}

/// The exact gain `ΔI = I' − I` (5.29) of splitting a state of a reversible chain, after
/// checking the split's conditions. `ΔI ≥ 0` (5.31); for a regular split
/// (`w_{i_k} = w_i / m`) `ΔI ≤ 2 w_i log₂ m` (5.35, [`regular_patch_gain_max`]), and for any
/// split `ΔI ≤ 2 w_i log₂(w_i / min_k w_{i_k})` (each bracket is a divergence from
/// `r_k = w_{i_k} / w_i`, at most `log₂(1 / min_k r_k)`).
///
/// # Errors
/// [`ErrorKind::PatchIndex`] for a bad state, [`ErrorKind::DimensionMismatch`] for slices of
/// the wrong length, [`ErrorKind::InvalidSplit`] when a weight or transition is negative or
/// not finite, a sub-state has weight 0, the weights do not add up to `w_i`, or condition
/// (a) or (b) fails by more than `SPLIT_TOLERANCE` — the gain is then not computed.
pub fn split_gain<M: Transitions>(channel: &Channel<'_, M>, split: &StateSplit<'_>) -> Result<f64> {
    check_split(channel, split)?;
    let w = channel.weights();
    let n = w.len();
    let m = split.weights.len();
    let mut total = KahanSum::new();
    // Transitions between the sub-states and every other state, counted both ways (2×).
    for j in (0..n).filter(|&j| j != split.state) {
        let terms = (0..m).map(|k| {
            let w_k = split.weights[k];
            (w_k * split.rows[k * n + j], w_k)
        });
        total.add(2.0 * log_sum_gap(terms));
    }
    // Transitions among the sub-states.
    let block = (0..m * m).map(|kl| {
        let (k, l) = (kl / m, kl % m);
        (
            split.weights[k] * split.block[kl],
            split.weights[k] * split.weights[l],
        )
    });
    total.add(log_sum_gap(block));
    Ok(total.total())
}

/// The patch-to-patch gain (5.32) when patch `i` is split into sub-patches with weights
/// `w_{i_k}` and transitions `P_{i_k j}` to a patch `j ≠ i`:
///
/// ```text
/// (ΔI)_ij = 2 (Σ_k w_{i_k} P_{i_k j} log₂ P_{i_k j} − w_i P_ij log₂ P_ij)
/// ```
///
/// with `w_i = Σ_k w_{i_k}` and `w_i P_ij = Σ_k w_{i_k} P_{i_k j}` (condition (b), checked).
/// `≥ 0` by construction.
///
/// # Errors
/// [`ErrorKind::DimensionMismatch`] when the slices differ in length;
/// [`ErrorKind::InvalidSplit`] for a negative or non-finite value, or when
/// `|Σ_k w_{i_k} − w_i|` or `|Σ_k w_{i_k} P_{i_k j} − w_i P_ij|` exceeds `SPLIT_TOLERANCE`.
pub(crate) fn pair_gain(
    w_i: f64,
    p_ij: f64,
    sub_weights: &[f64],
    sub_transitions: &[f64],
) -> Result<f64> {
    if sub_weights.len() != sub_transitions.len() {
        return Err(ErrorKind::DimensionMismatch {
            expected: sub_weights.len(),
            found: sub_transitions.len(),
        }
        .into());
    }
    check_entries(&[w_i, p_ij], "patch weight and transition finite and >= 0")?;
    check_entries(sub_weights, "sub-state weights finite and >= 0")?;
    check_entries(sub_transitions, "transitions finite and >= 0")?;
    within(
        math::sum(sub_weights.iter().copied()) - w_i,
        "sub-state weights sum to the state's weight",
        0,
    )?;
    let terms = sub_weights
        .iter()
        .zip(sub_transitions)
        .map(|(&w, &p)| (w * p, w));
    within(
        math::sum(terms.clone().map(|t| t.0)) - w_i * p_ij,
        "(b) cover w_i P_ij = sum_k w_ik P_ik,j",
        0,
    )?;
    Ok(2.0 * log_sum_gap(terms))
}

/// The gain (5.29) of splitting one state of a reversible chain into two sub-states `a` and
/// `b`, read from the joint probabilities `p_xy = w_x P_xy` of the two-state chain: the
/// information a merge of `a` and `b` loses (thesis §7.3; [`crate::simplify`]).
///
/// `joint_a[k] = p_ak`, `joint_b[k] = p_bk` over every state `k` of the chain before the
/// merge (reciprocity `p_ka = p_ak` is assumed, so the columns are the rows). With
/// `G(·)` the log-sum gap `Σ_k p_k log₂(p_k / v_k) − P log₂(P / V) ≥ 0` (2.67, 5.30):
///
/// ```text
/// ΔI = 2 Σ_{k ∉ {a, b}} G((p_ak, w_a), (p_bk, w_b))
///        + G((p_aa, w_a²), (p_ab, w_a w_b), (p_ba, w_b w_a), (p_bb, w_b²))
/// ```
///
/// which is [`split_gain`] for `m = 2` (the same brackets), needing rows `a` and `b` only:
/// `O(n)` and no allocation. `≥ 0` by construction; 0 when `a == b` or a slice is shorter
/// than the other (the caller's error, not a gain).
#[must_use]
pub(crate) fn two_state_split_gain(
    a: usize,
    b: usize,
    w_a: f64,
    w_b: f64,
    joint_a: &[f64],
    joint_b: &[f64],
) -> f64 {
    if a == b || joint_a.len() != joint_b.len() || a >= joint_a.len() || b >= joint_a.len() {
        return 0.0;
    }
    let mut total = KahanSum::new();
    for (k, (&p_ak, &p_bk)) in joint_a.iter().zip(joint_b).enumerate() {
        if k != a && k != b {
            total.add(2.0 * pair_gap(p_ak, w_a, p_bk, w_b));
        }
    }
    let block = [
        (joint_a[a], w_a * w_a),
        (joint_a[b], w_a * w_b),
        (joint_b[a], w_b * w_a),
        (joint_b[b], w_b * w_b),
    ];
    total.add(log_sum_gap(block.into_iter()));
    total.total()
}

/// `G((p_1, v_1), (p_2, v_2))`, the two-term log-sum gap of [`two_state_split_gain`]: the
/// bracket of (5.29) for one other state `k` when a state splits in two.
#[must_use]
pub(crate) fn pair_gap(p_1: f64, v_1: f64, p_2: f64, v_2: f64) -> f64 {
    log_sum_gap([(p_1, v_1), (p_2, v_2)].into_iter())
}

/// The largest patch-to-patch gain of a regular split into `m` (5.34): `2 w_i P_ij log₂ m`,
/// reached when all of `i`'s view of `j` falls on one sub-patch. 0 for `m = 0`.
#[must_use]
pub fn regular_pair_gain_max(w_i: f64, p_ij: f64, m: u32) -> f64 {
    if m == 0 {
        return 0.0;
    }
    2.0 * w_i * p_ij * math::log2(f64::from(m))
}

/// The largest gain of splitting patch `i` into `m` (5.35): `Σ_j 2 w_i P_ij log₂ m =
/// 2 w_i log₂ m` for a row-stochastic `P`. 0 for `m = 0`.
#[must_use]
pub fn regular_patch_gain_max(w_i: f64, m: u32) -> f64 {
    regular_pair_gain_max(w_i, 1.0, m)
}

/// Most sub-patches the area-based instances accept (they normalise into a stack buffer).
pub(crate) const MAX_SUB_STATES: usize = 64;

/// The patch-to-patch gain written with areas and form factors, scaled:
/// `2 · scale · (Σ_k A_{i_k} F_{i_k j} log₂ F_{i_k j} − A_i F_ij log₂ F_ij)`.
///
/// Areas are divided by `A_i` first, so the conditions are checked relative to the patch's
/// own size whatever the scene's units.
fn area_gain(scale: f64, a_i: f64, f_ij: f64, sub_areas: &[f64], sub_f: &[f64]) -> Result<f64> {
    check_entries(&[scale], "scale finite and >= 0")?;
    if !(a_i > 0.0 && a_i.is_finite()) {
        return Err(ErrorKind::BadParameter {
            name: "patch area",
            value: a_i,
        }
        .into());
    }
    let m = sub_areas.len();
    if m > MAX_SUB_STATES {
        return Err(ErrorKind::TooLarge {
            what: "number of sub-patches",
            max: MAX_SUB_STATES as u64,
        }
        .into());
    }
    let mut relative = [0.0; MAX_SUB_STATES];
    for (r, &a) in relative.iter_mut().zip(sub_areas) {
        *r = a / a_i;
    }
    // (5.32) with w_{i_k} = A_{i_k} / A_i; the common factor A_i · scale comes back after.
    Ok(scale * a_i * pair_gain(1.0, f_ij, &relative[..m], sub_f)?)
}

/// Visibility instance (5.36): `w_i = a_i = A_i / A_T`, `P_ij = F_ij`,
///
/// ```text
/// (ΔI)^v_ij = 2 (Σ_k a_{i_k} F_{i_k j} log₂ F_{i_k j} − a_i F_ij log₂ F_ij)
/// ```
///
/// Areas (lengths in flatland) are absolute; `total_area = A_T`. Its maximum for a regular
/// split is `2 a_i F_ij log₂ m` (5.37): [`regular_pair_gain_max`].
///
/// # Errors
/// As [`pair_gain`], on the areas relative to `A_i` (the sub-areas must add up to `A_i` and
/// their flux `Σ_k A_{i_k} F_{i_k j}` to `A_i F_ij`); [`ErrorKind::BadParameter`] for
/// `A_T ≤ 0` or `A_i ≤ 0`; [`ErrorKind::TooLarge`] above `MAX_SUB_STATES` sub-patches.
pub(crate) fn visibility_pair_gain(
    total_area: f64,
    a_i: f64,
    f_ij: f64,
    sub_areas: &[f64],
    sub_f: &[f64],
) -> Result<f64> {
    let scale = positive_scale("total area", total_area, 1.0)?;
    area_gain(scale, a_i, f_ij, sub_areas, sub_f)
}

/// Radiosity instance (5.42), for radiosity, emittance and reflectance constant on patch `i`
/// (so on its sub-patches) and on `j`: `w_i = A_i B_i B_i^in / A_T^c`,
/// `P_ij = ρ_i F_ij B_j / (B_i − E_i)`, and the constant factors cancel in (5.32):
///
/// ```text
/// (ΔI)^r_ij = 2 (B_i B_j / A_T^c) (Σ_k A_{i_k} F_{i_k j} log₂ F_{i_k j} − A_i F_ij log₂ F_ij)
/// ```
///
/// `total_weight = A_T^c = Σ_i A_i B_i (B_i − E_i)/ρ_i` (5.41), the normaliser the thesis
/// writes `A_T` in (5.42).
///
/// # Errors
/// As `pair_gain` on the areas; [`ErrorKind::BadParameter`] for `A_T^c ≤ 0` or a
/// negative or non-finite radiosity.
pub fn radiosity_pair_gain(
    total_weight: f64,
    b_i: f64,
    b_j: f64,
    a_i: f64,
    f_ij: f64,
    sub_areas: &[f64],
    sub_f: &[f64],
) -> Result<f64> {
    let scale = positive_scale("A_T^c", total_weight, b_i * b_j)?;
    area_gain(scale, a_i, f_ij, sub_areas, sub_f)
}

/// Importance instance (5.44, 5.45), for importance `I`, initial importance `V` and
/// reflectance constant on patch `i` (so on its sub-patches) and on `j`:
/// `w_i = A_i ρ_i I_i (I_i − V_i) / W`, `P_ij = ρ_j F_ij I_j / (I_i − V_i)`, so the joint
/// probability is `A_i F_ij ρ_i I_i ρ_j I_j / W` and (5.32) becomes
///
/// ```text
/// (ΔI)^imp_ij = 2 (ρ_i I_i ρ_j I_j / W) (Σ_k A_{i_k} F_{i_k j} log₂ F_{i_k j} − A_i F_ij log₂ F_ij)
/// ```
///
/// The thesis stops at "the increase may be calculated" (§5.4.5); this is that calculation,
/// the same cancellation as for radiosity. `total_weight = W = Σ_i A_i ρ_i I_i (I_i − V_i)`.
///
/// # Errors
/// As [`radiosity_pair_gain`].
#[allow(clippy::too_many_arguments)]
pub fn importance_pair_gain(
    total_weight: f64,
    rho_i_importance_i: f64,
    rho_j_importance_j: f64,
    a_i: f64,
    f_ij: f64,
    sub_areas: &[f64],
    sub_f: &[f64],
) -> Result<f64> {
    let scale = positive_scale("W", total_weight, rho_i_importance_i * rho_j_importance_j)?;
    area_gain(scale, a_i, f_ij, sub_areas, sub_f)
}

/// `numerator / total`, checked: `total > 0`, `numerator ≥ 0`, both finite.
fn positive_scale(name: &'static str, total: f64, numerator: f64) -> Result<f64> {
    if !(total > 0.0 && total.is_finite()) {
        return Err(ErrorKind::BadParameter { name, value: total }.into());
    }
    if !(numerator >= 0.0 && numerator.is_finite()) {
        return Err(ErrorKind::BadParameter {
            name: "product of the two patches' radiosities (importances)",
            value: numerator,
        }
        .into());
    }
    Ok(numerator / total)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::channel::Channel;

    /// A 3-state reversible chain from the symmetric joint matrix `[[0,2,2],[2,0,4],[2,4,0]]/16`.
    fn chain() -> ([f64; 3], [f64; 9]) {
        let joint = [0.0, 2.0, 2.0, 2.0, 0.0, 4.0, 2.0, 4.0, 0.0].map(|v| v / 16.0);
        let w = [4.0 / 16.0, 6.0 / 16.0, 6.0 / 16.0];
        let mut p = [0.0; 9];
        for i in 0..3 {
            for j in 0..3 {
                p[i * 3 + j] = joint[i * 3 + j] / w[i];
            }
        }
        (w, p)
    }

    #[test]
    fn splitting_state_zero_all_towards_one_side_gains_the_predicted_information() {
        // Split state 0 (weight 1/4) into two halves; sub-state 0 sees only state 1,
        // sub-state 1 only state 2: each keeps the joint mass 2/16 with one neighbour.
        let (w, p) = chain();
        let channel = Channel::from_dense(&w, &p).unwrap();
        let weights = [2.0 / 16.0, 2.0 / 16.0];
        let rows = [0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
        // P'_{j i_k} = w_{i_k} P'_{i_k j} / w_j.
        let columns = [0.0, (2.0 / 16.0) / w[1], 0.0, 0.0, 0.0, (2.0 / 16.0) / w[2]];
        let split = StateSplit {
            state: 0,
            weights: &weights,
            rows: &rows,
            columns: &columns,
            block: &[0.0; 4],
        };
        let gain = split_gain(&channel, &split).unwrap();
        // Each of the two brackets is P·log₂ 2 with P = 2/16: ΔI = 2 · 2 · (1/8) = 1/2.
        assert!((gain - 0.5).abs() < 1e-15, "{gain}");
        assert!(gain <= regular_patch_gain_max(w[0], 2) + 1e-15);
        // (5.34) is reached: the whole view of j falls on one sub-state.
        let pair = pair_gain(w[0], p[1], &weights, &[rows[1], rows[4]]).unwrap();
        assert!((pair - regular_pair_gain_max(w[0], p[1], 2)).abs() < 1e-15);
    }

    #[test]
    fn the_two_state_gain_is_split_gain_with_two_sub_states() {
        // The refined 4-state chain: state 0 of `chain()` split into a (sees 1 and itself)
        // and b (sees 2 and a), a symmetric joint matrix summing to 1.
        let joint = [
            [1.0, 1.0, 1.0, 0.0],
            [1.0, 0.0, 0.0, 2.0],
            [1.0, 0.0, 0.0, 4.0],
            [0.0, 2.0, 4.0, 0.0],
        ]
        .map(|row| row.map(|v| v / 17.0));
        let w_fine: [f64; 4] = joint.map(|row| row.iter().sum());
        let merged_joint =
            [[3.0, 1.0, 2.0], [1.0, 0.0, 4.0], [2.0, 4.0, 0.0]].map(|row| row.map(|v| v / 17.0));
        let w: [f64; 3] = merged_joint.map(|row| row.iter().sum());
        let mut p = [0.0; 9];
        for i in 0..3 {
            for j in 0..3 {
                p[i * 3 + j] = merged_joint[i][j] / w[i];
            }
        }
        let channel = Channel::from_dense(&w, &p).unwrap();
        // Sub-states 0 (= a) and 1 (= b) of merged state 0; other states 1, 2 are fine 2, 3.
        let weights = [w_fine[0], w_fine[1]];
        let rows = [
            0.0,
            1.0 / 17.0 / w_fine[0],
            0.0,
            0.0,
            0.0,
            2.0 / 17.0 / w_fine[1],
        ];
        let columns = [0.0, 1.0 / 17.0 / w[1], 0.0, 0.0, 0.0, 2.0 / 17.0 / w[2]];
        let block = [
            joint[0][0] / w_fine[0],
            joint[0][1] / w_fine[0],
            joint[1][0] / w_fine[1],
            joint[1][1] / w_fine[1],
        ];
        let split = StateSplit {
            state: 0,
            weights: &weights,
            rows: &rows,
            columns: &columns,
            block: &block,
        };
        let general = split_gain(&channel, &split).unwrap();
        let two = two_state_split_gain(0, 1, w_fine[0], w_fine[1], &joint[0], &joint[1]);
        assert!(general > 0.0);
        assert!((two - general).abs() < 1e-15, "{two} vs {general}");
        // And it is the difference of the two chains' I_S.
        let mut p_fine = [0.0; 16];
        for i in 0..4 {
            for j in 0..4 {
                p_fine[i * 4 + j] = joint[i][j] / w_fine[i];
            }
        }
        let fine = Channel::from_dense(&w_fine, &p_fine).unwrap().i_s();
        assert!((fine - channel.i_s() - two).abs() < 1e-15);
    }

    #[test]
    fn a_split_breaking_condition_b_is_reported() {
        let (w, p) = chain();
        let channel = Channel::from_dense(&w, &p).unwrap();
        let weights = [2.0 / 16.0, 2.0 / 16.0];
        // Sub-state 0 sends everything to state 1: together they send 3/16 there, not 2/16.
        let rows = [0.0, 1.0, 0.0, 0.0, 0.5, 0.5];
        let columns = [
            0.0,
            (2.0 / 16.0) / w[1],
            0.0,
            0.0,
            (1.0 / 16.0) / w[1],
            (1.0 / 16.0) / w[2],
        ];
        let split = StateSplit {
            state: 0,
            weights: &weights,
            rows: &rows,
            columns: &columns,
            block: &[0.0; 4],
        };
        let err = split_gain(&channel, &split).unwrap_err();
        assert!(
            matches!(err.kind(), ErrorKind::InvalidSplit { condition, .. } if condition.starts_with("(b)")),
            "{err}"
        );
        assert!(pair_gain(w[0], p[1], &weights, &[1.0, 0.5]).is_err());
    }

    #[test]
    fn the_instances_agree_with_the_general_gain() {
        // Patch of area 2 seeing j with F = 0.3, halves with F 0.5 and 0.1.
        let (a_i, f_ij, a_t) = (2.0, 0.3, 10.0);
        let sub_a = [1.0, 1.0];
        let sub_f = [0.5, 0.1];
        let v = visibility_pair_gain(a_t, a_i, f_ij, &sub_a, &sub_f).unwrap();
        let direct = 2.0
            * (0.1 * 0.5 * 0.5f64.log2() + 0.1 * 0.1 * 0.1f64.log2() - 0.2 * 0.3 * 0.3f64.log2());
        assert!((v - direct).abs() < 1e-15, "{v} vs {direct}");
        let r = radiosity_pair_gain(4.0, 2.0, 3.0, a_i, f_ij, &sub_a, &sub_f).unwrap();
        // B_i B_j / A_T^c times the area form: 6/4 · A_T · v.
        assert!((r - 1.5 * a_t * v).abs() < 1e-14);
        let imp = importance_pair_gain(4.0, 2.0, 3.0, a_i, f_ij, &sub_a, &sub_f).unwrap();
        assert_eq!(imp, r);
        assert!(visibility_pair_gain(0.0, a_i, f_ij, &sub_a, &sub_f).is_err());
        assert!(visibility_pair_gain(a_t, a_i, f_ij, &[1.0, 0.5], &sub_f).is_err());
    }
}
