//! The owning CSR matrix [`CsrMatrixBuf`] (needs the `alloc` feature).

use alloc::vec::Vec;

use super::matrix::{CsrMatrix, DenseMatrix, Transitions, check_entry};
use crate::error::{Error, ErrorKind, Result};

/// An owning CSR matrix (needs the `alloc` feature); borrow it with
/// [`as_matrix`](Self::as_matrix).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CsrMatrixBuf {
    n: usize,
    row_ptr: Vec<usize>,
    col_idx: Vec<u32>,
    values: Vec<f64>,
}

/// Largest dimension whose column indices fit a `u32`.
const MAX_DIM: u64 = 1 << 32;

/// Rejects sizes whose column indices do not fit a `u32`.
fn check_size(n: usize) -> Result<()> {
    if n as u64 > MAX_DIM {
        return Err(Error::new(ErrorKind::TooLarge {
            what: "sparse matrix dimension",
            max: MAX_DIM,
        }));
    }
    Ok(())
}

impl CsrMatrixBuf {
    /// Copies a row-major dense `n × n` matrix, dropping its zeros.
    ///
    /// # Errors
    ///
    /// As [`DenseMatrix::new`]; [`ErrorKind::TooLarge`] if `n > 2³²`.
    pub fn from_dense(n: usize, data: &[f64]) -> Result<Self> {
        check_size(n)?;
        Ok(Self::from_transitions(&DenseMatrix::new(n, data)?))
    }

    /// Copies the non-zero entries of any validated [`Transitions`] (a
    /// [`DenseMatrix`], a [`CsrMatrix`], …). Columns reported out of order or out of
    /// range are dropped rather than trusted.
    #[must_use]
    pub fn from_transitions<M: Transitions>(p: &M) -> Self {
        let n = p
            .n_states()
            .min(usize::try_from(MAX_DIM).unwrap_or(usize::MAX));
        let mut out = Self {
            n,
            row_ptr: Vec::with_capacity(n + 1),
            ..Self::default()
        };
        out.row_ptr.push(0);
        for i in 0..n {
            let mut next = 0_usize;
            p.for_each_in_row(i, |j, v| {
                // Keep the CSR invariants even for a careless implementation.
                if v != 0.0 && j >= next && j < n && v.is_finite() && v > 0.0 {
                    out.col_idx.push(j as u32);
                    out.values.push(v);
                    next = j + 1;
                }
            });
            out.row_ptr.push(out.values.len());
        }
        out
    }

    /// Builds an `n × n` matrix from `(row, col, value)` triplets in any order.
    ///
    /// Duplicated positions are summed, in the order given; entries that are (or sum
    /// to) zero are dropped.
    ///
    /// # Errors
    ///
    /// - [`ErrorKind::MalformedSparse`] for a row or column `>= n`;
    /// - [`ErrorKind::NonFiniteEntry`] / [`ErrorKind::NegativeEntry`] for a bad value
    ///   (also when duplicates overflow to infinity);
    /// - [`ErrorKind::TooLarge`] if `n > 2³²`.
    pub fn from_triplets(n: usize, triplets: &[(usize, usize, f64)]) -> Result<Self> {
        check_size(n)?;
        for &(i, j, v) in triplets {
            if i >= n || j >= n {
                return Err(Error::new(ErrorKind::MalformedSparse));
            }
            check_entry(i, j, v)?;
        }
        // A stable sort keeps duplicates in input order, so their sum is reproducible.
        let mut sorted: Vec<(usize, usize, f64)> = triplets.to_vec();
        sorted.sort_by_key(|&(i, j, _)| (i, j));

        let mut out = Self {
            n,
            row_ptr: Vec::with_capacity(n + 1),
            ..Self::default()
        };
        let mut k = 0;
        out.row_ptr.push(0);
        for i in 0..n {
            while let Some(&(ti, tj, v)) = sorted.get(k) {
                if ti != i {
                    break;
                }
                // Sum every duplicate of (i, j).
                let mut total = v;
                k += 1;
                while let Some(&(ui, uj, u)) = sorted.get(k) {
                    if ui != ti || uj != tj {
                        break;
                    }
                    total += u;
                    k += 1;
                }
                check_entry(i, tj, total)?;
                if total != 0.0 {
                    out.col_idx.push(tj as u32);
                    out.values.push(total);
                }
            }
            out.row_ptr.push(out.values.len());
        }
        Ok(out)
    }

    /// Number of states `n`.
    #[must_use]
    pub fn n(&self) -> usize {
        self.n
    }

    /// Number of stored entries.
    #[must_use]
    pub fn nnz(&self) -> usize {
        self.values.len()
    }

    /// Borrows the matrix as a [`CsrMatrix`].
    #[must_use]
    pub fn as_matrix(&self) -> CsrMatrix<'_> {
        if self.row_ptr.is_empty() {
            // `Default` value: an empty 0 × 0 matrix.
            return CsrMatrix::from_validated(0, &[0], &[], &[]);
        }
        CsrMatrix::from_validated(self.n, &self.row_ptr, &self.col_idx, &self.values)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err_kind<T: core::fmt::Debug>(r: Result<T>) -> ErrorKind {
        r.unwrap_err().kind().clone()
    }

    #[test]
    fn owned_csr_round_trips() {
        let data = [0.0, 0.25, 0.75, 1.0, 0.0, 0.0, 0.5, 0.5, 0.0];
        let a = CsrMatrixBuf::from_dense(3, &data).unwrap();
        assert_eq!(a.nnz(), 5);
        let m = a.as_matrix();
        for i in 0..3 {
            for j in 0..3 {
                assert_eq!(m.get(i, j), data[i * 3 + j]);
            }
        }
        let b = CsrMatrixBuf::from_triplets(
            3,
            &[
                (2, 1, 0.5),
                (0, 2, 0.5),
                (1, 0, 1.0),
                (0, 1, 0.25),
                (2, 0, 0.5),
                (0, 2, 0.25),
                (1, 1, 0.0),
            ],
        )
        .unwrap();
        assert_eq!(a, b);
        assert_eq!(CsrMatrixBuf::from_transitions(&m), a);
        assert_eq!(
            err_kind(CsrMatrixBuf::from_triplets(3, &[(0, 3, 1.0)])),
            ErrorKind::MalformedSparse
        );
        assert_eq!(
            err_kind(CsrMatrixBuf::from_triplets(3, &[(0, 1, -1.0)])),
            ErrorKind::NegativeEntry { row: 0, col: 1 }
        );
        assert_eq!(
            err_kind(CsrMatrixBuf::from_triplets(
                3,
                &[(0, 1, f64::MAX), (0, 1, f64::MAX)]
            )),
            ErrorKind::NonFiniteEntry { row: 0, col: 1 }
        );
        let empty = CsrMatrixBuf::default();
        assert_eq!(empty.as_matrix().n_states(), 0);
        assert_eq!(
            CsrMatrixBuf::from_triplets(0, &[])
                .unwrap()
                .as_matrix()
                .row_ptr(),
            &[0]
        );
    }
}
