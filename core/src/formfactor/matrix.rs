//! The owning form-factor matrix with its stationary distribution and background state.

use alloc::vec;
use alloc::vec::Vec;

use crate::channel::{Channel, DenseMatrix};
use crate::error::{ErrorKind, Result};
use crate::math::KahanSum;

/// Largest row deficit `1 − Σ_j F_ij` still read as a closed scene (rounding of exact form
/// factors is ~1e-14; any larger loss is energy leaving the scene and gets a background
/// state).
pub const BACKGROUND_TOLERANCE: f64 = 1e-9;

/// A dense form-factor matrix over the patches of a scene, plus — for open scenes — one
/// *background* state.
///
/// The background is the minimal reversible closure of an open scene: a virtual surface of
/// "length" (or area) `L_b = Σ_i L_i d_i`, where `d_i = 1 − Σ_j F_ij` is the part of patch
/// `i`'s power that leaves the scene or lands on the back of a one-sided surface. Then
///
/// ```text
/// F_ib = d_i,   F_bi = L_i d_i / L_b,   F_bb = 0
/// ```
///
/// so every row sums to one and reciprocity `L_i F_ib = L_b F_bi` holds. The background is
/// the last state, index `n_patches`.
#[derive(Clone, Debug, PartialEq)]
pub struct FormFactors {
    n_patches: usize,
    n_states: usize,
    weights: Vec<f64>,
    matrix: Vec<f64>,
    background_size: Option<f64>,
    max_row_deficit: f64,
}

impl FormFactors {
    /// Builds the matrix from the patch sizes `sizes` (lengths or areas) and the row-major
    /// `n × n` form factors `f`, adding a background state if some row loses more than
    /// [`BACKGROUND_TOLERANCE`].
    ///
    /// # Errors
    /// [`ErrorKind::DimensionMismatch`] if `f` is not `n × n`; [`ErrorKind::EmptyScene`] for
    /// no patches; [`ErrorKind::NonFiniteEntry`] / [`ErrorKind::NegativeEntry`] for bad
    /// entries or sizes.
    pub fn from_patch_matrix(sizes: &[f64], f: Vec<f64>) -> Result<Self> {
        let n = sizes.len();
        if n == 0 {
            return Err(ErrorKind::EmptyScene.into());
        }
        if f.len() != n * n {
            return Err(ErrorKind::DimensionMismatch {
                expected: n * n,
                found: f.len(),
            }
            .into());
        }
        for (k, &v) in f.iter().enumerate() {
            if !v.is_finite() {
                return Err(ErrorKind::NonFiniteEntry {
                    row: k / n,
                    col: k % n,
                }
                .into());
            }
            if v < 0.0 {
                return Err(ErrorKind::NegativeEntry {
                    row: k / n,
                    col: k % n,
                }
                .into());
            }
        }
        for (k, &s) in sizes.iter().enumerate() {
            if !(s.is_finite() && s > 0.0) {
                return Err(ErrorKind::NonFiniteEntry { row: k, col: 0 }.into());
            }
        }
        // Row deficits d_i = 1 − Σ_j F_ij.
        let deficits: Vec<f64> = f
            .chunks_exact(n)
            .map(|row| 1.0 - crate::math::sum(row.iter().copied()))
            .collect();
        let max_row_deficit = deficits.iter().fold(0.0f64, |m, &d| m.max(d));
        let mut total = KahanSum::new();
        sizes.iter().for_each(|&s| total.add(s));
        if max_row_deficit <= BACKGROUND_TOLERANCE {
            let t = total.total();
            let weights = sizes.iter().map(|&s| s / t).collect();
            return Ok(Self {
                n_patches: n,
                n_states: n,
                weights,
                matrix: f,
                background_size: None,
                max_row_deficit,
            });
        }
        // Open scene: append the background state.
        let m = n + 1;
        let mut flux = KahanSum::new();
        for (&s, &d) in sizes.iter().zip(&deficits) {
            flux.add(s * d.max(0.0));
        }
        let l_b = flux.total();
        let mut matrix = vec![0.0; m * m];
        for i in 0..n {
            matrix[i * m..i * m + n].copy_from_slice(&f[i * n..(i + 1) * n]);
            let d = deficits[i].max(0.0);
            matrix[i * m + n] = d;
            matrix[n * m + i] = sizes[i] * d / l_b;
        }
        total.add(l_b);
        let t = total.total();
        let mut weights: Vec<f64> = sizes.iter().map(|&s| s / t).collect();
        weights.push(l_b / t);
        Ok(Self {
            n_patches: n,
            n_states: m,
            weights,
            matrix,
            background_size: Some(l_b),
            max_row_deficit,
        })
    }

    /// Number of patches of the scene.
    #[must_use]
    pub fn n_patches(&self) -> usize {
        self.n_patches
    }

    /// Number of states: patches, plus one if there is a background.
    #[must_use]
    pub fn n_states(&self) -> usize {
        self.n_states
    }

    /// Whether the scene is open and a background state was added (as the last state).
    #[must_use]
    pub fn has_background(&self) -> bool {
        self.background_size.is_some()
    }

    /// The background's size `L_b = Σ_i L_i d_i`, if there is one.
    #[must_use]
    pub fn background_size(&self) -> Option<f64> {
        self.background_size
    }

    /// Largest row deficit `1 − Σ_j F_ij` over the patches before any background was added.
    #[must_use]
    pub fn max_row_deficit(&self) -> f64 {
        self.max_row_deficit
    }

    /// The stationary distribution: relative sizes of all states (including background).
    #[must_use]
    pub fn weights(&self) -> &[f64] {
        &self.weights
    }

    /// The row-major `n_states × n_states` matrix.
    #[must_use]
    pub fn as_slice(&self) -> &[f64] {
        &self.matrix
    }

    /// `F_ij`, or 0 when out of range.
    #[must_use]
    pub fn get(&self, i: usize, j: usize) -> f64 {
        if i < self.n_states && j < self.n_states {
            self.matrix[i * self.n_states + j]
        } else {
            0.0
        }
    }

    /// The matrix as a channel-ready [`DenseMatrix`] view (validated on construction).
    #[must_use]
    pub fn matrix(&self) -> DenseMatrix<'_> {
        DenseMatrix::from_validated(self.n_states, &self.matrix)
    }

    /// The scene's channel `(a, F)`.
    ///
    /// # Errors
    /// The validation errors of [`Channel::new`]; none for a matrix built by this crate.
    pub fn channel(&self) -> Result<Channel<'_, DenseMatrix<'_>>> {
        Channel::new(&self.weights, self.matrix())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn closed_matrix_has_no_background() {
        let f = vec![0.0, 1.0, 1.0, 0.0];
        let ff = FormFactors::from_patch_matrix(&[1.0, 1.0], f).unwrap();
        assert!(!ff.has_background());
        assert_eq!(ff.weights(), &[0.5, 0.5]);
    }

    #[test]
    fn open_matrix_gets_reversible_background() {
        // Two patches that see each other with F = 0.25 (lengths 1 and 2).
        let f = vec![0.0, 0.25, 0.125, 0.0];
        let ff = FormFactors::from_patch_matrix(&[1.0, 2.0], f).unwrap();
        assert!(ff.has_background());
        assert_eq!(ff.n_states(), 3);
        for i in 0..3 {
            let row: f64 = (0..3).map(|j| ff.get(i, j)).sum();
            assert!((row - 1.0).abs() < 1e-15);
            for j in 0..3 {
                let lhs = ff.weights()[i] * ff.get(i, j);
                let rhs = ff.weights()[j] * ff.get(j, i);
                assert!((lhs - rhs).abs() < 1e-15);
            }
        }
        // L_b = 1·0.75 + 2·0.875 = 2.5
        assert!((ff.background_size().unwrap() - 2.5).abs() < 1e-15);
    }
}
