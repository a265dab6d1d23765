//! The owning form-factor matrix with its stationary distribution and background state.

use alloc::vec::Vec;

use core::ops::Range;

use crate::channel::{Channel, CsrMatrix, CsrMatrixBuf, DenseMatrix, Transitions};
use crate::error::{ErrorKind, Result};
use crate::math::KahanSum;

/// Largest row deficit `1 − Σ_j F_ij` still read as a closed scene (rounding of exact form
/// factors is ~1e-14; any larger loss is energy leaving the scene and gets a background
/// state).
pub(crate) const BACKGROUND_TOLERANCE: f64 = 1e-9;

/// Storage of a [`FormFactors`] matrix.
#[derive(Clone, Debug, PartialEq)]
enum Storage {
    Dense(Vec<f64>),
    Sparse(CsrMatrixBuf),
}

/// A form-factor matrix over the patches of a scene — dense (exact form factors, small
/// scenes) or sparse CSR (Monte Carlo estimates, large scenes) — plus, for open scenes, one
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
    storage: Storage,
    background_size: Option<f64>,
    max_row_deficit: f64,
}

/// Validates patch sizes and returns their compensated total.
fn check_sizes(sizes: &[f64]) -> Result<f64> {
    if sizes.is_empty() {
        return Err(ErrorKind::EmptyScene.into());
    }
    let mut total = KahanSum::new();
    for (k, &s) in sizes.iter().enumerate() {
        if !(s.is_finite() && s > 0.0) {
            return Err(ErrorKind::NonFiniteEntry { row: k, col: 0 }.into());
        }
        total.add(s);
    }
    Ok(total.total())
}

/// The background closure of rows with deficits `d_i`: `(L_b, F_ib, F_bi)` or `None` when
/// every deficit is within [`BACKGROUND_TOLERANCE`].
fn background(sizes: &[f64], deficits: &[f64]) -> Option<(f64, Vec<f64>, Vec<f64>)> {
    let max = deficits.iter().fold(0.0f64, |m, &d| m.max(d));
    if max <= BACKGROUND_TOLERANCE {
        return None;
    }
    let mut flux = KahanSum::new();
    for (&s, &d) in sizes.iter().zip(deficits) {
        flux.add(s * d.max(0.0));
    }
    let l_b = flux.total();
    let to_b: Vec<f64> = deficits.iter().map(|&d| d.max(0.0)).collect();
    let from_b = sizes
        .iter()
        .zip(&to_b)
        .map(|(&s, &d)| s * d / l_b)
        .collect();
    Some((l_b, to_b, from_b))
}

fn weights_of(sizes: &[f64], total: f64, background: Option<f64>) -> Vec<f64> {
    let t = total + background.unwrap_or(0.0);
    let mut w: Vec<f64> = sizes.iter().map(|&s| s / t).collect();
    if let Some(l_b) = background {
        w.push(l_b / t);
    }
    w
}

fn check_entries(n: usize, entries: impl Iterator<Item = (usize, usize, f64)>) -> Result<()> {
    for (i, j, v) in entries {
        if i >= n || j >= n {
            return Err(ErrorKind::MalformedSparse.into());
        }
        if !v.is_finite() {
            return Err(ErrorKind::NonFiniteEntry { row: i, col: j }.into());
        }
        if v < 0.0 {
            return Err(ErrorKind::NegativeEntry { row: i, col: j }.into());
        }
    }
    Ok(())
}

impl FormFactors {
    /// Builds a dense matrix from the patch sizes `sizes` (lengths or areas) and the
    /// row-major `n × n` form factors `f`, adding a background state if some row loses more
    /// than `BACKGROUND_TOLERANCE`.
    ///
    /// # Errors
    /// [`ErrorKind::DimensionMismatch`] if `f` is not `n × n`; [`ErrorKind::EmptyScene`] for
    /// no patches; [`ErrorKind::NonFiniteEntry`] / [`ErrorKind::NegativeEntry`] for bad
    /// entries or sizes.
    pub fn from_patch_matrix(sizes: &[f64], f: Vec<f64>) -> Result<Self> {
        let n = sizes.len();
        let total = check_sizes(sizes)?;
        if f.len() != n * n {
            return Err(ErrorKind::DimensionMismatch {
                expected: n * n,
                found: f.len(),
            }
            .into());
        }
        // One pass: each row's entries checked, then summed (its zeros skipped: adding
        // 0 to a compensated sum changes nothing)
        let mut deficits = Vec::with_capacity(n);
        for (i, row) in f.chunks_exact(n.max(1)).take(n).enumerate() {
            check_entries(n, row.iter().enumerate().map(|(j, &v)| (i, j, v)))?;
            let sum = crate::math::sum(row.iter().copied().filter(|&v| v != 0.0));
            deficits.push(1.0 - sum);
        }
        let max_row_deficit = deficits.iter().fold(0.0f64, |m, &d| m.max(d));
        let Some((l_b, to_b, from_b)) = background(sizes, &deficits) else {
            return Ok(Self {
                n_patches: n,
                n_states: n,
                weights: weights_of(sizes, total, None),
                storage: Storage::Dense(f),
                background_size: None,
                max_row_deficit,
            });
        };
        // Open scene: append the background state, moving the rows in place from the
        // last (each moves to a higher index, past the rows not yet moved)
        let m = n + 1;
        let mut matrix = f;
        matrix.resize(m * m, 0.0);
        for i in (0..n).rev() {
            matrix.copy_within(i * n..(i + 1) * n, i * m);
            matrix[i * m + n] = to_b[i];
        }
        // The background row (the last `m` entries: the first of them held row n − 1's
        // tail before it moved)
        for (i, &v) in from_b.iter().enumerate() {
            matrix[n * m + i] = v;
        }
        matrix[n * m + n] = 0.0;
        Ok(Self {
            n_patches: n,
            n_states: m,
            weights: weights_of(sizes, total, Some(l_b)),
            storage: Storage::Dense(matrix),
            background_size: Some(l_b),
            max_row_deficit,
        })
    }

    /// Builds a sparse (CSR) matrix from patch sizes and `(i, j, F_ij)` triplets (duplicates
    /// are summed, zeros dropped), adding a background state as
    /// [`FormFactors::from_patch_matrix`] does.
    ///
    /// # Errors
    /// As [`FormFactors::from_patch_matrix`]; [`ErrorKind::MalformedSparse`] for an index
    /// out of range.
    pub fn from_patch_triplets(sizes: &[f64], triplets: Vec<(usize, usize, f64)>) -> Result<Self> {
        check_sizes(sizes)?;
        // Indices and entries are checked as the CSR is built
        let csr = CsrMatrixBuf::from_triplets(sizes.len(), &triplets)?;
        drop(triplets);
        Self::from_patch_csr(sizes, csr)
    }

    /// Builds a sparse matrix from patch sizes and the `n × n` patch form factors as CSR
    /// (for example received row by row through `CsrMatrixBuf::row_major`, which holds
    /// each entry once), adding a background state as [`FormFactors::from_patch_matrix`]
    /// does: its column and row border the matrix in place
    /// ([`CsrMatrixBuf::bordered`]).
    ///
    /// # Errors
    /// As [`FormFactors::from_patch_matrix`]; [`ErrorKind::DimensionMismatch`] when `f` is
    /// not `sizes.len()` square.
    pub fn from_patch_csr(sizes: &[f64], f: CsrMatrixBuf) -> Result<Self> {
        let n = sizes.len();
        let total = check_sizes(sizes)?;
        if f.n() != n {
            return Err(ErrorKind::DimensionMismatch {
                expected: n,
                found: f.n(),
            }
            .into());
        }
        let deficits: Vec<f64> = {
            let m = f.as_matrix();
            (0..n)
                .map(|i| {
                    let mut row = KahanSum::new();
                    m.for_each_in_row(i, |_, v| row.add(v));
                    1.0 - row.total()
                })
                .collect()
        };
        let max_row_deficit = deficits.iter().fold(0.0f64, |m, &d| m.max(d));
        let (csr, n_states, background_size) = match background(sizes, &deficits) {
            Some((l_b, to_b, mut from_b)) => {
                from_b.push(0.0); // F_bb
                (f.bordered(&to_b, &from_b)?, n + 1, Some(l_b))
            }
            None => (f, n, None),
        };
        Ok(Self {
            n_patches: n,
            n_states,
            weights: weights_of(sizes, total, background_size),
            storage: Storage::Sparse(csr),
            background_size,
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

    /// Whether the matrix is stored sparse (CSR).
    #[must_use]
    pub fn is_sparse(&self) -> bool {
        matches!(self.storage, Storage::Sparse(_))
    }

    /// `F_ij`, or 0 when out of range or not stored.
    #[must_use]
    pub fn get(&self, i: usize, j: usize) -> f64 {
        if i >= self.n_states || j >= self.n_states {
            return 0.0;
        }
        match &self.storage {
            Storage::Dense(d) => d.get(i * self.n_states + j).copied().unwrap_or(0.0),
            Storage::Sparse(c) => c.as_matrix().get(i, j),
        }
    }

    /// Writes row `i` densely into `out` (length `n_states`).
    ///
    /// # Errors
    /// [`ErrorKind::BufferTooSmall`] if `out` is shorter than `n_states`;
    /// [`ErrorKind::PatchIndex`] if `i` is out of range.
    pub fn dense_row_into(&self, i: usize, out: &mut [f64]) -> Result<()> {
        if i >= self.n_states {
            return Err(ErrorKind::PatchIndex {
                index: i,
                len: self.n_states,
            }
            .into());
        }
        let found = out.len();
        let out = out
            .get_mut(..self.n_states)
            .ok_or(ErrorKind::BufferTooSmall {
                needed: self.n_states,
                found,
            })?;
        out.fill(0.0);
        self.matrix().for_each_in_row(i, |j, v| out[j] = v);
        Ok(())
    }

    /// The matrix as a channel-ready view (validated on construction).
    #[must_use]
    pub fn matrix(&self) -> FormFactorView<'_> {
        match &self.storage {
            Storage::Dense(d) => {
                FormFactorView::Dense(DenseMatrix::from_validated(self.n_states, d))
            }
            Storage::Sparse(c) => FormFactorView::Sparse(c.as_matrix()),
        }
    }

    /// The scene's channel `(a, F)`.
    ///
    /// # Errors
    /// The validation errors of [`Channel::new`]; none for a matrix built by this crate.
    pub fn channel(&self) -> Result<Channel<'_, FormFactorView<'_>>> {
        Channel::new(&self.weights, self.matrix())
    }
}

/// A borrowed view of a [`FormFactors`] matrix, dense or sparse.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FormFactorView<'a> {
    /// Dense row-major storage.
    Dense(DenseMatrix<'a>),
    /// CSR storage.
    Sparse(CsrMatrix<'a>),
}

impl Transitions for FormFactorView<'_> {
    #[inline]
    fn n_states(&self) -> usize {
        match self {
            Self::Dense(m) => m.n_states(),
            Self::Sparse(m) => m.n_states(),
        }
    }

    #[inline]
    fn for_each_in_row<F: FnMut(usize, f64)>(&self, i: usize, f: F) {
        match self {
            Self::Dense(m) => m.for_each_in_row(i, f),
            Self::Sparse(m) => m.for_each_in_row(i, f),
        }
    }

    #[inline]
    fn get(&self, i: usize, j: usize) -> f64 {
        match self {
            Self::Dense(m) => m.get(i, j),
            Self::Sparse(m) => m.get(i, j),
        }
    }

    #[inline]
    fn get_ascending(&self, i: usize, j: usize, cursor: &mut usize) -> f64 {
        match self {
            Self::Dense(m) => m.get(i, j),
            Self::Sparse(m) => m.get_ascending(i, j, cursor),
        }
    }

    #[inline]
    fn cursor_at(&self, i: usize, j: usize) -> usize {
        match self {
            Self::Dense(_) => 0,
            Self::Sparse(m) => m.cursor_at(i, j),
        }
    }

    #[inline]
    fn for_each_in_row_range_ascending<F: FnMut(usize, f64)>(
        &self,
        i: usize,
        cols: Range<usize>,
        cursor: &mut usize,
        f: F,
    ) {
        match self {
            Self::Dense(m) => m.for_each_in_row_range(i, cols, f),
            Self::Sparse(m) => m.for_each_in_row_range_ascending(i, cols, cursor, f),
        }
    }

    #[inline]
    fn for_each_in_row_range<F: FnMut(usize, f64)>(&self, i: usize, cols: Range<usize>, f: F) {
        match self {
            Self::Dense(m) => m.for_each_in_row_range(i, cols, f),
            Self::Sparse(m) => m.for_each_in_row_range(i, cols, f),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use alloc::vec;

    #[test]
    fn closed_matrix_has_no_background() {
        let f = vec![0.0, 1.0, 1.0, 0.0];
        let ff = FormFactors::from_patch_matrix(&[1.0, 1.0], f).unwrap();
        assert!(!ff.has_background());
        assert_eq!(ff.weights(), &[0.5, 0.5]);
    }

    #[test]
    fn sparse_and_dense_agree() {
        let f = vec![0.0, 0.25, 0.125, 0.0];
        let dense = FormFactors::from_patch_matrix(&[1.0, 2.0], f).unwrap();
        let sparse =
            FormFactors::from_patch_triplets(&[1.0, 2.0], vec![(0, 1, 0.25), (1, 0, 0.125)])
                .unwrap();
        assert!(sparse.is_sparse() && !dense.is_sparse());
        assert_eq!(dense.weights(), sparse.weights());
        for i in 0..3 {
            for j in 0..3 {
                assert_eq!(dense.get(i, j), sparse.get(i, j));
            }
        }
        let a = dense.channel().unwrap().measures();
        let b = sparse.channel().unwrap().measures();
        assert!((a.i_s - b.i_s).abs() < 1e-15 && (a.h_s - b.h_s).abs() < 1e-15);
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

    proptest::proptest! {
        /// A patch matrix received row by row as CSR (what a sparse line tally gives) is
        /// the matrix its triplets give, bit for bit, background included, and so is the
        /// dense matrix, with its measures and checks (what lets a line tally store
        /// sparse form factors).
        #[test]
        fn csr_triplets_and_dense_give_the_same_form_factors(
            n in 1usize..7,
            sizes in proptest::collection::vec(0.1f64..10.0, 7),
            raw in proptest::collection::vec(
                proptest::prop_oneof![proptest::strategy::Just(0.0), 0.0f64..1.0], 49),
            closed in proptest::bool::ANY,
        ) {
            let sizes = &sizes[..n];
            // Rows scaled to sum to one (closed) or to at most one (open, with a background)
            let mut f = raw[..n * n].to_vec();
            for row in f.chunks_mut(n) {
                let sum: f64 = row.iter().sum();
                let scale = if closed || sum > 1.0 { sum } else { 1.0 };
                for x in row.iter_mut() {
                    *x = if scale > 0.0 { *x / scale } else { 0.0 };
                }
            }
            let triplets: Vec<(usize, usize, f64)> =
                (0..n * n).map(|k| (k / n, k % n, f[k])).collect();
            let mut rows = CsrMatrixBuf::row_major(n, n * n).unwrap();
            for &(i, j, v) in &triplets {
                rows.push(i, j, v).unwrap();
            }
            let csr = FormFactors::from_patch_csr(sizes, rows.finish()).unwrap();
            let from_triplets = FormFactors::from_patch_triplets(sizes, triplets).unwrap();
            proptest::prop_assert_eq!(&csr, &from_triplets);
            // Bit for bit: a compensated sum that adds the zeros of a dense row
            // (`KahanSum::add(0.0)` changes nothing) is the sum of the stored entries
            let dense = FormFactors::from_patch_matrix(sizes, f).unwrap();
            proptest::prop_assert_eq!(csr.n_states(), dense.n_states());
            proptest::prop_assert_eq!(csr.weights(), dense.weights());
            proptest::prop_assert_eq!(csr.max_row_deficit(), dense.max_row_deficit());
            proptest::prop_assert_eq!(csr.background_size(), dense.background_size());
            for i in 0..csr.n_states() {
                for j in 0..csr.n_states() {
                    proptest::prop_assert_eq!(csr.get(i, j), dense.get(i, j));
                }
            }
            let (a, b) = (csr.channel().unwrap(), dense.channel().unwrap());
            proptest::prop_assert_eq!(a.measures(), b.measures());
            proptest::prop_assert_eq!(a.checks(), b.checks());
        }
    }

    #[test]
    fn csr_of_the_wrong_size_is_refused() {
        let f = CsrMatrixBuf::from_triplets(3, &[(0, 1, 0.5)]).unwrap();
        assert_eq!(
            FormFactors::from_patch_csr(&[1.0, 1.0], f)
                .unwrap_err()
                .kind(),
            &ErrorKind::DimensionMismatch {
                expected: 2,
                found: 3
            }
        );
    }
}
