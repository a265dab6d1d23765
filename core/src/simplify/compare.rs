//! The criteria at equal patch count: the information each coarse mesh keeps, and how far
//! its radiosity solution lies from the fine one.
//!
//! The radiosity of a mesh is solved on its own form factors — for a coarse mesh the merged
//! chain's, `F'_cd = Σ_{i∈c} Σ_{j∈d} A_i F_ij / A_c`, which are exactly the form factors of
//! the merged patches (additivity) — by `crate::radiosity::rgb::solve_rgb` (Gauss–Seidel,
//! relative residual `1e-12`). Each fine patch `i` reads the radiosity `B'_{c(i)}` of the
//! coarse patch holding it, and the error is the area-weighted RMS over the fine patches and
//! the three colour channels:
//!
//! ```text
//! RMSE = sqrt( Σ_i a_i Σ_rgb (B_i − B'_{c(i)})² / (3 Σ_i a_i) )
//! ```
//!
//! reported also relative to the fine solution's own RMS, `sqrt(Σ_i a_i Σ_rgb B_i² / (3 Σ_i
//! a_i))` (0 when nothing is lit).

use alloc::vec;
use alloc::vec::Vec;

use super::chain::MergeChain;
use super::greedy::{MergeCriterion, Simplifier, StopReason};
use super::polish::Polished;
use crate::channel::DenseMatrix;
use crate::error::{ErrorKind, Result};
use crate::math::KahanSum;
use crate::radiosity::rgb::solve_rgb;
use crate::radiosity::{SolveOptions, Solver};
use crate::scene::Material;

/// The solver's relative residual for the comparison's solutions.
const SOLVE_TOLERANCE: f64 = 1e-12;

/// One criterion's coarse mesh at the comparison's patch count.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CriterionOutcome {
    /// The criterion.
    pub criterion: MergeCriterion,
    /// Patches of its coarse mesh (the target unless no pair could merge first).
    pub n_patches: usize,
    /// `I_S` of the coarse mesh (bits).
    pub i_s: f64,
    /// `I_S` kept: the coarse over the fine mesh's (1 when the fine `I_S` is 0).
    pub kept: f64,
    /// Area-weighted RMS radiosity error per fine patch against the fine solution (module
    /// docs).
    pub rmse: f64,
    /// `rmse` over the fine solution's RMS radiosity (0 when nothing is lit).
    pub relative_rmse: f64,
    /// Why its simplification stopped.
    pub stop: StopReason,
}

/// The three criteria simplified to one patch count ([`compare_criteria`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// Patches of the fine mesh.
    pub fine_patches: usize,
    /// `I_S` of the fine mesh (bits).
    pub fine_i_s: f64,
    /// The fine solution's area-weighted RMS radiosity.
    pub fine_rms: f64,
    /// One outcome per criterion, in [`MergeCriterion::ALL`] order.
    pub outcomes: Vec<CriterionOutcome>,
    /// The `mi` mesh: the greedy merge polished ([`Polished::of`]), so a caller that wants
    /// the mesh itself need not polish again.
    pub polished: Polished,
}

/// The radiosity of every patch state of `chain` as merged, solved on its coarse form
/// factors, read back per original patch (the first `n_patches` states): `B'_{c(i)}`.
/// `materials[i]` is patch `i`'s; a merged patch takes its representative's.
///
/// # Errors
/// [`ErrorKind::DimensionMismatch`] unless there is one material per patch; the errors of
/// `solve_rgb`.
pub(crate) fn radiosity_per_patch(
    chain: &MergeChain,
    n_patches: usize,
    materials: &[Material],
) -> Result<Vec<[f64; 3]>> {
    if materials.len() != n_patches || n_patches > chain.n_states() {
        return Err(ErrorKind::DimensionMismatch {
            expected: n_patches,
            found: materials.len(),
        }
        .into());
    }
    let (states, w, f) = chain.coarse_form_factors();
    let m = states.len();
    // Live states in index order: patches first, a background (black) after them.
    let coarse_materials: Vec<Material> = states
        .iter()
        .filter(|&&x| x < n_patches)
        .map(|&x| materials[x])
        .collect();
    let opts = SolveOptions {
        tolerance: SOLVE_TOLERANCE,
        ..SolveOptions::default()
    };
    let solution = solve_rgb(
        &DenseMatrix::new(m, &f)?,
        &w,
        &coarse_materials,
        Solver::GaussSeidel,
        &opts,
    )?;
    let mut index_of = vec![0; chain.n_states()];
    for (k, &x) in states.iter().enumerate() {
        index_of[x] = k;
    }
    Ok((0..n_patches)
        .map(|i| solution.radiosity[index_of[chain.cluster_of(i)]])
        .collect())
}

/// `(RMSE, RMS)`: the area-weighted RMS of `coarse − fine` and of `fine` over patches of
/// relative areas `a` and the three channels (module docs).
#[must_use]
pub(crate) fn radiosity_rmse(a: &[f64], fine: &[[f64; 3]], coarse: &[[f64; 3]]) -> (f64, f64) {
    let (mut err, mut norm, mut area) = (KahanSum::new(), KahanSum::new(), KahanSum::new());
    for ((&a, f), c) in a.iter().zip(fine).zip(coarse) {
        area.add(3.0 * a);
        for k in 0..3 {
            err.add(a * (f[k] - c[k]) * (f[k] - c[k]));
            norm.add(a * f[k] * f[k]);
        }
    }
    let area = area.total();
    if !(area > 0.0) {
        return (0.0, 0.0);
    }
    (
        crate::math::sqrt(err.total().max(0.0) / area),
        crate::math::sqrt(norm.total().max(0.0) / area),
    )
}

/// Simplifies `fine` (first `n_patches` states patches, pairs of `adjacency` mergeable,
/// `materials` one per patch) to `target` patches by each criterion of
/// [`MergeCriterion::ALL`], and measures each coarse mesh: `I_S` kept and the radiosity
/// error against the fine solution.
///
/// # Errors
/// The errors of [`Simplifier::new`], [`Simplifier::run`] and `radiosity_per_patch`.
pub fn compare_criteria(
    fine: &MergeChain,
    n_patches: usize,
    adjacency: &[(usize, usize)],
    materials: &[Material],
    target: usize,
) -> Result<Comparison> {
    let fine_b = radiosity_per_patch(fine, n_patches, materials)?;
    let a: Vec<f64> = (0..n_patches).map(|i| fine.weight(i)).collect();
    let fine_i_s = fine.i_s()?;
    let (_, fine_rms) = radiosity_rmse(&a, &fine_b, &fine_b);
    let mut outcomes = Vec::with_capacity(MergeCriterion::ALL.len());
    let mut greedy = Simplifier::new(
        fine.clone(),
        n_patches,
        adjacency,
        MergeCriterion::Information,
        None,
    )?;
    let (_, mi_stop) = greedy.run(target, None)?;
    let polished = Polished::of(fine, n_patches, adjacency, greedy.chain().clusters())?;
    for criterion in MergeCriterion::ALL {
        let other;
        let (chain, i_s, n, stop) = if criterion == MergeCriterion::Information {
            (&polished.chain, polished.i_s, greedy.n_patches(), mi_stop)
        } else {
            let mut s =
                Simplifier::new(fine.clone(), n_patches, adjacency, criterion, Some(&fine_b))?;
            let (_, stop) = s.run(target, None)?;
            other = s;
            (other.chain(), other.i_s(), other.n_patches(), stop)
        };
        let coarse_b = radiosity_per_patch(chain, n_patches, materials)?;
        let (rmse, _) = radiosity_rmse(&a, &fine_b, &coarse_b);
        outcomes.push(CriterionOutcome {
            criterion,
            n_patches: n,
            i_s,
            kept: if fine_i_s > 0.0 { i_s / fine_i_s } else { 1.0 },
            rmse,
            relative_rmse: if fine_rms > 0.0 { rmse / fine_rms } else { 0.0 },
            stop,
        });
    }
    Ok(Comparison {
        fine_patches: n_patches,
        fine_i_s,
        fine_rms,
        outcomes,
        polished,
    })
}
