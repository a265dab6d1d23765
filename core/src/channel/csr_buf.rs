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
        let mut out = Self::row_major(n, sorted.len())?;
        let mut k = 0;
        while let Some(&(i, j, v)) = sorted.get(k) {
            // Sum every duplicate of (i, j); a zero sum is dropped.
            let mut total = v;
            k += 1;
            while let Some(&(ui, uj, u)) = sorted.get(k) {
                if (ui, uj) != (i, j) {
                    break;
                }
                total += u;
                k += 1;
            }
            out.push(i, j, total)?;
        }
        Ok(out.finish())
    }

    /// Starts an `n × n` matrix received entry by entry in row-major order, with room for
    /// `capacity` entries. Building from such a stream holds every entry once: no triplets,
    /// no sorted copy (a sparse form-factor matrix of 10⁸ entries is 1.2 GB as CSR, 2.4 GB
    /// more as `(usize, usize, f64)` triplets and as much again for their sorted copy).
    ///
    /// # Errors
    ///
    /// [`ErrorKind::TooLarge`] if `n > 2³²`.
    pub(crate) fn row_major(n: usize, capacity: usize) -> Result<RowMajorCsr> {
        check_size(n)?;
        let mut row_ptr = Vec::with_capacity(n + 1);
        row_ptr.push(0);
        Ok(RowMajorCsr {
            n,
            row_ptr,
            col_idx: Vec::with_capacity(capacity),
            values: Vec::with_capacity(capacity),
            last: None,
        })
    }

    /// Starts an `n × n` matrix whose row `i` will hold exactly `lengths[i]` entries,
    /// received in any interleaving of rows but in increasing column order within each
    /// row (a symmetric matrix read from its packed triangle in memory order gives that:
    /// `tally`'s counts). The entries are written in place, once.
    ///
    /// # Errors
    ///
    /// [`ErrorKind::DimensionMismatch`] unless `lengths` has `n` entries;
    /// [`ErrorKind::TooLarge`] if `n > 2³²`.
    pub(crate) fn by_row_lengths(n: usize, lengths: &[usize]) -> Result<ScatteredCsr> {
        check_size(n)?;
        if lengths.len() != n {
            return Err(Error::new(ErrorKind::DimensionMismatch {
                expected: n,
                found: lengths.len(),
            }));
        }
        let mut row_ptr = Vec::with_capacity(n + 1);
        let mut total = 0usize;
        row_ptr.push(0);
        for &len in lengths {
            total = total.saturating_add(len);
            row_ptr.push(total);
        }
        let next = row_ptr.get(..n).unwrap_or(&[]).to_vec();
        Ok(ScatteredCsr {
            n,
            row_ptr,
            next,
            col_idx: alloc::vec![0; total],
            values: alloc::vec![0.0; total],
        })
    }

    /// Borders the `n × n` matrix with a last column and a last row, giving an
    /// `(n + 1) × (n + 1)` matrix: entry `(i, n)` is `column[i]` and `(n, j)` is `row[j]`
    /// (`row` has `n + 1` entries, the corner last); zeros are dropped. The entries move once,
    /// in place, from the last row to the first, so the only allocation is the room for the
    /// new entries.
    ///
    /// # Errors
    ///
    /// [`ErrorKind::DimensionMismatch`] unless `column` has `n` and `row` `n + 1` entries;
    /// [`ErrorKind::NonFiniteEntry`] / [`ErrorKind::NegativeEntry`] for a bad new entry;
    /// [`ErrorKind::TooLarge`] if `n + 1 > 2³²`.
    pub fn bordered(mut self, column: &[f64], row: &[f64]) -> Result<Self> {
        let n = self.n;
        for (len, expected) in [(column.len(), n), (row.len(), n + 1)] {
            if len != expected {
                return Err(Error::new(ErrorKind::DimensionMismatch {
                    expected,
                    found: len,
                }));
            }
        }
        check_size(n + 1)?;
        for (i, &v) in column.iter().enumerate() {
            check_entry(i, n, v)?;
        }
        for (j, &v) in row.iter().enumerate() {
            check_entry(n, j, v)?;
        }
        if self.row_ptr.is_empty() {
            self.row_ptr.push(0); // `Default` value: the empty 0 × 0 matrix
        }
        let added_to_rows = column.iter().filter(|&&v| v != 0.0).count();
        let last_row = row.iter().filter(|&&v| v != 0.0).count();
        let old_len = self.values.len();
        let len = old_len + added_to_rows;
        self.col_idx.reserve_exact(added_to_rows + last_row);
        self.values.reserve_exact(added_to_rows + last_row);
        self.col_idx.resize(len, 0);
        self.values.resize(len, 0.0);
        // From the last row back: row i moves right by the column entries of rows < i
        let mut shift = added_to_rows;
        for i in (0..n).rev() {
            let (start, end) = (self.row_ptr[i], self.row_ptr[i + 1]);
            if column[i] != 0.0 {
                self.col_idx[end + shift - 1] = n as u32;
                self.values[end + shift - 1] = column[i];
                shift -= 1;
            }
            self.col_idx.copy_within(start..end, start + shift);
            self.values.copy_within(start..end, start + shift);
            self.row_ptr[i + 1] = end + shift + usize::from(column[i] != 0.0);
        }
        for (j, &v) in row.iter().enumerate() {
            if v != 0.0 {
                self.col_idx.push(j as u32);
                self.values.push(v);
            }
        }
        self.row_ptr.push(self.values.len());
        self.n = n + 1;
        Ok(self)
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

/// An `n × n` CSR matrix being received in row-major order (from
/// [`CsrMatrixBuf::row_major`]): [`push`](Self::push) the entries, then
/// [`finish`](Self::finish).
#[derive(Clone, Debug)]
pub(crate) struct RowMajorCsr {
    n: usize,
    /// One entry per row closed so far, plus the leading 0.
    row_ptr: Vec<usize>,
    col_idx: Vec<u32>,
    values: Vec<f64>,
    /// The last position pushed.
    last: Option<(usize, usize)>,
}

impl RowMajorCsr {
    /// Appends entry `(i, j) = v`, after every entry pushed before in row-major order;
    /// a zero is skipped.
    ///
    /// # Errors
    ///
    /// [`ErrorKind::MalformedSparse`] if `(i, j)` is out of range or not after the last
    /// position pushed; [`ErrorKind::NonFiniteEntry`] / [`ErrorKind::NegativeEntry`] for a
    /// bad `v`.
    pub fn push(&mut self, i: usize, j: usize, v: f64) -> Result<()> {
        if i >= self.n || j >= self.n || self.last.is_some_and(|last| (i, j) <= last) {
            return Err(Error::new(ErrorKind::MalformedSparse));
        }
        check_entry(i, j, v)?;
        self.last = Some((i, j));
        if v == 0.0 {
            return Ok(());
        }
        self.close_rows_before(i);
        self.col_idx.push(j as u32);
        self.values.push(v);
        Ok(())
    }

    /// Closes every row before row `i`.
    fn close_rows_before(&mut self, i: usize) {
        while self.row_ptr.len() <= i {
            self.row_ptr.push(self.values.len());
        }
    }

    /// The matrix, the rows after the last entry empty.
    #[must_use]
    pub fn finish(mut self) -> CsrMatrixBuf {
        self.close_rows_before(self.n);
        CsrMatrixBuf {
            n: self.n,
            row_ptr: self.row_ptr,
            col_idx: self.col_idx,
            values: self.values,
        }
    }
}

/// An `n × n` CSR matrix whose row lengths are known, filled row by row in any
/// interleaving (from [`CsrMatrixBuf::by_row_lengths`]): [`push`](Self::push) the
/// entries, then [`finish`](Self::finish).
#[derive(Clone, Debug)]
pub(crate) struct ScatteredCsr {
    n: usize,
    row_ptr: Vec<usize>,
    /// Where row `i`'s next entry goes.
    next: Vec<usize>,
    col_idx: Vec<u32>,
    values: Vec<f64>,
}

impl ScatteredCsr {
    /// Puts entry `(i, j) = v` after the entries of row `i` pushed before.
    ///
    /// # Errors
    ///
    /// [`ErrorKind::MalformedSparse`] if `(i, j)` is out of range, row `i` is full, `j`
    /// is not after the row's last column, or `v` is zero (the lengths count stored
    /// entries); [`ErrorKind::NonFiniteEntry`] / [`ErrorKind::NegativeEntry`] for a bad
    /// `v`.
    #[inline]
    pub(crate) fn push(&mut self, i: usize, j: usize, v: f64) -> Result<()> {
        check_entry(i, j, v)?;
        let malformed = || Error::new(ErrorKind::MalformedSparse);
        let (Some(&start), Some(&end), Some(at)) = (
            self.row_ptr.get(i),
            self.row_ptr.get(i + 1),
            self.next.get_mut(i),
        ) else {
            return Err(malformed());
        };
        let k = *at;
        let after_last = k == start || self.col_idx.get(k - 1).is_some_and(|&c| (c as usize) < j);
        if k >= end || j >= self.n || !after_last || v == 0.0 {
            return Err(malformed());
        }
        *at = k + 1;
        if let (Some(c), Some(x)) = (self.col_idx.get_mut(k), self.values.get_mut(k)) {
            *c = j as u32;
            *x = v;
        }
        Ok(())
    }

    /// The matrix.
    ///
    /// # Errors
    ///
    /// [`ErrorKind::MalformedSparse`] if some row got fewer entries than its length.
    pub(crate) fn finish(self) -> Result<CsrMatrixBuf> {
        if self
            .next
            .iter()
            .zip(self.row_ptr.get(1..).unwrap_or(&[]))
            .any(|(a, b)| a != b)
        {
            return Err(Error::new(ErrorKind::MalformedSparse));
        }
        Ok(CsrMatrixBuf {
            n: self.n,
            row_ptr: self.row_ptr,
            col_idx: self.col_idx,
            values: self.values,
        })
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

    #[test]
    fn row_major_refuses_what_is_out_of_order_or_range() {
        let mut rows = CsrMatrixBuf::row_major(3, 4).unwrap();
        rows.push(0, 2, 0.5).unwrap();
        assert_eq!(err_kind(rows.push(0, 2, 0.5)), ErrorKind::MalformedSparse);
        assert_eq!(err_kind(rows.push(0, 1, 0.5)), ErrorKind::MalformedSparse);
        assert_eq!(err_kind(rows.push(3, 0, 0.5)), ErrorKind::MalformedSparse);
        assert_eq!(err_kind(rows.push(1, 3, 0.5)), ErrorKind::MalformedSparse);
        assert_eq!(
            err_kind(rows.push(1, 0, f64::NAN)),
            ErrorKind::NonFiniteEntry { row: 1, col: 0 }
        );
        assert_eq!(
            err_kind(rows.push(1, 1, -1.0)),
            ErrorKind::NegativeEntry { row: 1, col: 1 }
        );
        rows.push(2, 0, 0.0).unwrap();
        rows.push(2, 1, 1.0).unwrap();
        let m = rows.finish();
        assert_eq!(
            m,
            CsrMatrixBuf::from_triplets(3, &[(0, 2, 0.5), (2, 1, 1.0)]).unwrap()
        );
        assert_eq!(m.as_matrix().row_ptr(), &[0, 1, 1, 2]);
        assert_eq!(
            err_kind(m.clone().bordered(&[0.0; 2], &[0.0; 4])),
            ErrorKind::DimensionMismatch {
                expected: 3,
                found: 2
            }
        );
        assert_eq!(
            err_kind(m.bordered(&[0.0, -1.0, 0.0], &[0.0; 4])),
            ErrorKind::NegativeEntry { row: 1, col: 3 }
        );
        let empty = CsrMatrixBuf::default().bordered(&[], &[0.5]).unwrap();
        assert_eq!(
            empty,
            CsrMatrixBuf::from_triplets(1, &[(0, 0, 0.5)]).unwrap()
        );
    }

    /// A random `n × n` matrix with about a third of its entries zero, row-major.
    fn sparse_dense(max_n: usize) -> impl proptest::strategy::Strategy<Value = (usize, Vec<f64>)> {
        use proptest::prelude::*;
        (0..=max_n).prop_flat_map(|n| {
            let entry = prop_oneof![Just(0.0), 0.0f64..2.0, 1e-300f64..1e-290];
            (Just(n), proptest::collection::vec(entry, n * n))
        })
    }

    proptest::proptest! {
        /// Entries pushed in row-major order give the matrix the triplets give.
        #[test]
        fn row_major_equals_triplets((n, dense) in sparse_dense(7)) {
            let triplets: Vec<(usize, usize, f64)> = (0..n * n)
                .map(|k| (k / n.max(1), k % n.max(1), dense[k]))
                .collect();
            let mut rows = CsrMatrixBuf::row_major(n, 0).unwrap();
            for &(i, j, v) in &triplets {
                rows.push(i, j, v).unwrap();
            }
            let built = rows.finish();
            proptest::prop_assert_eq!(&built, &CsrMatrixBuf::from_triplets(n, &triplets).unwrap());
            proptest::prop_assert_eq!(&built, &CsrMatrixBuf::from_dense(n, &dense).unwrap());
        }

        /// Bordering in place gives the matrix the triplets give with the border's entries.
        #[test]
        fn bordered_equals_triplets_with_the_border(
            (n, dense) in sparse_dense(7),
            border in proptest::collection::vec(
                proptest::prop_oneof![proptest::strategy::Just(0.0), 0.0f64..1.0], 15),
        ) {
            let (column, row) = (&border[..n], &border[n..=2 * n]);
            let mut triplets: Vec<(usize, usize, f64)> = (0..n * n)
                .map(|k| (k / n.max(1), k % n.max(1), dense[k]))
                .collect();
            triplets.extend(column.iter().enumerate().map(|(i, &v)| (i, n, v)));
            triplets.extend(row.iter().enumerate().map(|(j, &v)| (n, j, v)));
            let bordered = CsrMatrixBuf::from_dense(n, &dense)
                .unwrap()
                .bordered(column, row)
                .unwrap();
            proptest::prop_assert_eq!(bordered, CsrMatrixBuf::from_triplets(n + 1, &triplets).unwrap());
        }
    }
}
