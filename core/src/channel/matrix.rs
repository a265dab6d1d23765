//! Transition matrices: the [`Transitions`] row-access trait, a borrowed dense
//! [`DenseMatrix`], a borrowed sparse [`CsrMatrix`] and (with `alloc`) the owning
//! [`CsrMatrixBuf`].
//!
//! Every channel measure walks a matrix row by row, so one trait with a row visitor is all
//! the measures need: small scenes keep a dense `n × n` form-factor matrix, large ones a
//! compressed-sparse-row (CSR) matrix that stores only the non-zero form factors. Both
//! constructors validate their input once (finite, non-negative, well-formed), so the
//! measures never meet a NaN.

use core::ops::Range;

use crate::error::{Error, ErrorKind, Result};
use crate::math::KahanSum;

/// Row access to an `n × n` matrix of transition probabilities `P_ij` (form factors
/// `F_ij` for a scene).
///
/// This is the crate's extension point for matrix storage: implement it for your own
/// storage and every channel function accepts it. Implementations must visit the entries
/// of a row in increasing column order, report only columns `< n_states()`, and never
/// panic — an out-of-range row simply has no entries. Values are checked by
/// [`Channel::new`](super::Channel::new), not trusted.
pub trait Transitions {
    /// Number of states `n` (rows and columns).
    fn n_states(&self) -> usize;

    /// Calls `f(j, P_ij)` for each stored entry of row `i` in increasing `j` (zeros may be
    /// skipped). Does nothing when `i >= n_states()`.
    fn for_each_in_row<F: FnMut(usize, f64)>(&self, i: usize, f: F);

    /// `P_ij`, or 0 when the entry is not stored or the indices are out of range.
    fn get(&self, i: usize, j: usize) -> f64;

    /// `P_ij` for a caller that asks row `i` for increasing `j`: `cursor` is its position
    /// in row `i`, kept by the caller (one per row, starting at 0) and passed back
    /// unchanged at the next query of that row.
    ///
    /// Same value as [`get`](Self::get) whatever the order of the queries. The default
    /// ignores the cursor; CSR storage walks it forward instead of bisecting the row, so a
    /// sweep asking every row for increasing columns costs `O(nnz + queries)` in all (the
    /// reciprocity check's `P_ji` for each stored `P_ij`, rows in increasing `i`) instead of
    /// a chain of cache misses per query.
    #[inline]
    fn get_ascending(&self, i: usize, j: usize, cursor: &mut usize) -> f64 {
        let _ = cursor;
        self.get(i, j)
    }

    /// A cursor of row `i` for [`get_ascending`](Self::get_ascending) and
    /// [`for_each_in_row_range_ascending`](Self::for_each_in_row_range_ascending) whose
    /// queries start at column `j`: what a sweep that begins part-way (a block of rows
    /// surveyed apart) passes instead of 0, so the cursor does not walk the row's earlier
    /// entries. Any value gives the same answers; the default is 0, CSR storage bisects.
    #[inline]
    fn cursor_at(&self, i: usize, j: usize) -> usize {
        let _ = (i, j);
        0
    }

    /// Like [`for_each_in_row`](Self::for_each_in_row), restricted to columns in `cols`.
    ///
    /// The default filters the whole row; dense and CSR storage override it to touch only
    /// the requested columns, which keeps blocked column sweeps cheap.
    fn for_each_in_row_range<F: FnMut(usize, f64)>(&self, i: usize, cols: Range<usize>, mut f: F) {
        self.for_each_in_row(i, |j, p| {
            if cols.contains(&j) {
                f(j, p);
            }
        });
    }

    /// [`for_each_in_row_range`](Self::for_each_in_row_range) for a caller that asks row
    /// `i` for increasing, non-overlapping column ranges: `cursor` is its position in row
    /// `i` (start at 0, pass it back unchanged), so CSR storage resumes where the last
    /// range ended instead of bisecting the row again. The same entries whatever the
    /// ranges; the default ignores the cursor.
    #[inline]
    fn for_each_in_row_range_ascending<F: FnMut(usize, f64)>(
        &self,
        i: usize,
        cols: Range<usize>,
        cursor: &mut usize,
        f: F,
    ) {
        let _ = cursor;
        self.for_each_in_row_range(i, cols, f);
    }

    /// Compensated sum of row `i`, `Σ_j P_ij` (0 for an out-of-range row).
    #[must_use]
    fn row_sum(&self, i: usize) -> f64 {
        let mut s = KahanSum::new();
        self.for_each_in_row(i, |_, p| s.add(p));
        s.total()
    }
}

impl<T: Transitions + ?Sized> Transitions for &T {
    #[inline]
    fn n_states(&self) -> usize {
        (**self).n_states()
    }

    #[inline]
    fn for_each_in_row<F: FnMut(usize, f64)>(&self, i: usize, f: F) {
        (**self).for_each_in_row(i, f);
    }

    #[inline]
    fn get(&self, i: usize, j: usize) -> f64 {
        (**self).get(i, j)
    }

    #[inline]
    fn get_ascending(&self, i: usize, j: usize, cursor: &mut usize) -> f64 {
        (**self).get_ascending(i, j, cursor)
    }

    #[inline]
    fn cursor_at(&self, i: usize, j: usize) -> usize {
        (**self).cursor_at(i, j)
    }

    #[inline]
    fn for_each_in_row_range_ascending<F: FnMut(usize, f64)>(
        &self,
        i: usize,
        cols: Range<usize>,
        cursor: &mut usize,
        f: F,
    ) {
        (**self).for_each_in_row_range_ascending(i, cols, cursor, f);
    }

    #[inline]
    fn for_each_in_row_range<F: FnMut(usize, f64)>(&self, i: usize, cols: Range<usize>, f: F) {
        (**self).for_each_in_row_range(i, cols, f);
    }

    #[inline]
    fn row_sum(&self, i: usize) -> f64 {
        (**self).row_sum(i)
    }
}

/// Checks one matrix entry: finite and non-negative.
pub(crate) fn check_entry(row: usize, col: usize, value: f64) -> Result<()> {
    if !value.is_finite() {
        return Err(Error::new(ErrorKind::NonFiniteEntry { row, col }));
    }
    if value < 0.0 {
        return Err(Error::new(ErrorKind::NegativeEntry { row, col }));
    }
    Ok(())
}

// ---- dense --------------------------------------------------------------------------------

/// A borrowed dense `n × n` matrix stored row-major: `P_ij = data[i·n + j]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DenseMatrix<'a> {
    n: usize,
    data: &'a [f64],
}

impl<'a> DenseMatrix<'a> {
    /// Wraps a row-major slice of `n·n` entries.
    ///
    /// # Errors
    ///
    /// - [`ErrorKind::DimensionMismatch`] if `data.len() != n·n`;
    /// - [`ErrorKind::NonFiniteEntry`] for a NaN or infinite entry;
    /// - [`ErrorKind::NegativeEntry`] for a negative entry (`-0.0` is accepted).
    pub fn new(n: usize, data: &'a [f64]) -> Result<Self> {
        let expected = n.saturating_mul(n);
        if data.len() != expected || n.checked_mul(n).is_none() {
            return Err(Error::new(ErrorKind::DimensionMismatch {
                expected,
                found: data.len(),
            }));
        }
        for (k, &v) in data.iter().enumerate() {
            check_entry(k / n, k % n, v)?;
        }
        Ok(Self { n, data })
    }

    /// Wraps a slice the crate itself built and already knows to be valid, skipping the
    /// `O(n²)` scan of [`new`](Self::new).
    ///
    /// Safe even if the promise is broken: a short slice reads as zeros past its end, and
    /// [`Channel::new`](super::Channel::new) checks every entry it visits again.
    #[must_use]
    #[cfg_attr(not(feature = "alloc"), allow(dead_code))]
    pub(crate) fn from_validated(n: usize, data: &'a [f64]) -> Self {
        // Only the O(1) shape check: a full scan here would make every view O(n²) in debug
        // builds, and views are cheap by design.
        debug_assert_eq!(Some(data.len()), n.checked_mul(n));
        Self { n, data }
    }

    /// Number of states `n`.
    #[must_use]
    pub fn n(&self) -> usize {
        self.n
    }

    /// The row-major entries, `n·n` of them.
    #[must_use]
    pub fn as_slice(&self) -> &'a [f64] {
        self.data
    }

    /// Row `i` as a slice (empty when `i >= n`).
    #[must_use]
    pub fn row(&self, i: usize) -> &'a [f64] {
        let start = i.saturating_mul(self.n);
        self.data
            .get(start..start.saturating_add(self.n))
            .unwrap_or(&[])
    }
}

impl Transitions for DenseMatrix<'_> {
    #[inline]
    fn n_states(&self) -> usize {
        self.n
    }

    #[inline]
    fn for_each_in_row<F: FnMut(usize, f64)>(&self, i: usize, mut f: F) {
        // Zeros are skipped so that dense and sparse storage visit the same entries.
        for (j, &p) in self.row(i).iter().enumerate() {
            if p != 0.0 {
                f(j, p);
            }
        }
    }

    #[inline]
    fn get(&self, i: usize, j: usize) -> f64 {
        if j >= self.n {
            return 0.0;
        }
        self.row(i).get(j).copied().unwrap_or(0.0)
    }

    fn for_each_in_row_range<F: FnMut(usize, f64)>(&self, i: usize, cols: Range<usize>, mut f: F) {
        let row = self.row(i);
        let end = cols.end.min(row.len());
        let start = cols.start.min(end);
        for (k, &p) in row.get(start..end).unwrap_or(&[]).iter().enumerate() {
            if p != 0.0 {
                f(start + k, p);
            }
        }
    }
}

// ---- sparse -------------------------------------------------------------------------------

/// A borrowed `n × n` matrix in compressed sparse row (CSR) form.
///
/// Row `i` holds the entries `values[k]` at columns `col_idx[k]` for
/// `k ∈ row_ptr[i] .. row_ptr[i+1]`; columns increase strictly within a row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CsrMatrix<'a> {
    n: usize,
    row_ptr: &'a [usize],
    col_idx: &'a [u32],
    values: &'a [f64],
}

impl<'a> CsrMatrix<'a> {
    /// Wraps CSR arrays after checking their structure and values.
    ///
    /// # Errors
    ///
    /// - [`ErrorKind::MalformedSparse`] unless `row_ptr` has `n + 1` entries starting at 0,
    ///   never decreasing and ending at `col_idx.len() == values.len()`, and every row's
    ///   columns are `< n` and strictly increasing;
    /// - [`ErrorKind::NonFiniteEntry`] / [`ErrorKind::NegativeEntry`] for a bad value.
    pub fn new(
        n: usize,
        row_ptr: &'a [usize],
        col_idx: &'a [u32],
        values: &'a [f64],
    ) -> Result<Self> {
        let malformed = || Error::new(ErrorKind::MalformedSparse);
        if n.checked_add(1) != Some(row_ptr.len())
            || row_ptr.first() != Some(&0)
            || row_ptr.last() != Some(&col_idx.len())
            || col_idx.len() != values.len()
        {
            return Err(malformed());
        }
        for (i, w) in row_ptr.windows(2).enumerate() {
            let (start, end) = (w[0], w[1]);
            if start > end {
                return Err(malformed());
            }
            let cols = col_idx.get(start..end).ok_or_else(malformed)?;
            let vals = values.get(start..end).ok_or_else(malformed)?;
            let mut previous: Option<usize> = None;
            for (&c, &v) in cols.iter().zip(vals) {
                let j = c as usize;
                if j >= n || previous.is_some_and(|p| j <= p) {
                    return Err(malformed());
                }
                previous = Some(j);
                check_entry(i, j, v)?;
            }
        }
        Ok(Self {
            n,
            row_ptr,
            col_idx,
            values,
        })
    }

    /// Wraps CSR arrays the crate built itself (a [`CsrMatrixBuf`](super::CsrMatrixBuf)),
    /// skipping the checks of [`new`](Self::new). Never panics even if the promise is
    /// broken: [`row`](Self::row) bounds-checks every slice.
    #[cfg_attr(not(feature = "alloc"), allow(dead_code))]
    pub(crate) fn from_validated(
        n: usize,
        row_ptr: &'a [usize],
        col_idx: &'a [u32],
        values: &'a [f64],
    ) -> Self {
        // O(1) shape checks only (views must stay cheap; see DenseMatrix::from_validated).
        debug_assert_eq!(row_ptr.len(), n + 1);
        debug_assert_eq!(col_idx.len(), values.len());
        Self {
            n,
            row_ptr,
            col_idx,
            values,
        }
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

    /// The row pointers (`n + 1` of them).
    #[must_use]
    pub fn row_ptr(&self) -> &'a [usize] {
        self.row_ptr
    }

    /// The column index of each stored entry.
    #[must_use]
    pub fn col_idx(&self) -> &'a [u32] {
        self.col_idx
    }

    /// The value of each stored entry.
    #[must_use]
    pub fn values(&self) -> &'a [f64] {
        self.values
    }

    /// Columns and values of row `i` (both empty when `i >= n`).
    #[must_use]
    pub fn row(&self, i: usize) -> (&'a [u32], &'a [f64]) {
        let (Some(&start), Some(&end)) = (self.row_ptr.get(i), self.row_ptr.get(i.wrapping_add(1)))
        else {
            return (&[], &[]);
        };
        match (self.col_idx.get(start..end), self.values.get(start..end)) {
            (Some(c), Some(v)) => (c, v),
            _ => (&[], &[]),
        }
    }
}

impl Transitions for CsrMatrix<'_> {
    #[inline]
    fn n_states(&self) -> usize {
        self.n
    }

    #[inline]
    fn for_each_in_row<F: FnMut(usize, f64)>(&self, i: usize, mut f: F) {
        let (cols, vals) = self.row(i);
        for (&c, &v) in cols.iter().zip(vals) {
            f(c as usize, v);
        }
    }

    fn get(&self, i: usize, j: usize) -> f64 {
        let Ok(j) = u32::try_from(j) else {
            return 0.0;
        };
        let (cols, vals) = self.row(i);
        match cols.binary_search(&j) {
            Ok(k) => vals.get(k).copied().unwrap_or(0.0),
            Err(_) => 0.0,
        }
    }

    /// Walks `cursor` forward to the first stored column `≥ j` (each stored entry is
    /// passed once over a sweep of increasing `j`); a query behind the cursor (a stored
    /// column before it is `≥ j`) falls back to [`get`](Transitions::get).
    #[inline]
    fn get_ascending(&self, i: usize, j: usize, cursor: &mut usize) -> f64 {
        let Ok(j) = u32::try_from(j) else {
            return 0.0;
        };
        let (cols, vals) = self.row(i);
        let mut k = (*cursor).min(cols.len());
        if k > 0 && cols.get(k - 1).is_some_and(|&c| c >= j) {
            return self.get(i, j as usize);
        }
        while cols.get(k).is_some_and(|&c| c < j) {
            k += 1;
        }
        *cursor = k;
        match (cols.get(k), vals.get(k)) {
            (Some(&c), Some(&v)) if c == j => v,
            _ => 0.0,
        }
    }

    /// The first stored column `≥ j` of row `i`, by bisection.
    #[inline]
    fn cursor_at(&self, i: usize, j: usize) -> usize {
        self.row(i).0.partition_point(|&c| (c as usize) < j)
    }

    /// Resumes at `cursor` (bisects only when the range starts behind it), walks to the
    /// first stored column `≥ cols.start`, visits up to `cols.end` and leaves the cursor
    /// there: each stored entry is passed once over increasing ranges.
    #[inline]
    fn for_each_in_row_range_ascending<F: FnMut(usize, f64)>(
        &self,
        i: usize,
        cols: Range<usize>,
        cursor: &mut usize,
        mut f: F,
    ) {
        let (idx, vals) = self.row(i);
        let mut k = (*cursor).min(idx.len());
        if k > 0 && idx.get(k - 1).is_some_and(|&c| c as usize >= cols.start) {
            k = idx.partition_point(|&c| (c as usize) < cols.start);
        }
        while idx.get(k).is_some_and(|&c| (c as usize) < cols.start) {
            k += 1;
        }
        while let (Some(&c), Some(&v)) = (idx.get(k), vals.get(k)) {
            if c as usize >= cols.end {
                break;
            }
            f(c as usize, v);
            k += 1;
        }
        *cursor = k;
    }

    fn for_each_in_row_range<F: FnMut(usize, f64)>(&self, i: usize, cols: Range<usize>, mut f: F) {
        let (idx, vals) = self.row(i);
        // First stored column >= cols.start, found by bisection.
        let start = idx.partition_point(|&c| (c as usize) < cols.start);
        for (&c, &v) in idx.iter().zip(vals).skip(start) {
            let j = c as usize;
            if j >= cols.end {
                break;
            }
            f(j, v);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err_kind<T: core::fmt::Debug>(r: Result<T>) -> ErrorKind {
        r.unwrap_err().kind().clone()
    }

    #[test]
    fn dense_validates() {
        assert_eq!(
            err_kind(DenseMatrix::new(2, &[0.0; 3])),
            ErrorKind::DimensionMismatch {
                expected: 4,
                found: 3
            }
        );
        assert_eq!(
            err_kind(DenseMatrix::new(2, &[0.0, 0.0, f64::NAN, 0.0])),
            ErrorKind::NonFiniteEntry { row: 1, col: 0 }
        );
        assert_eq!(
            err_kind(DenseMatrix::new(2, &[0.0, -1e-300, 0.0, 0.0])),
            ErrorKind::NegativeEntry { row: 0, col: 1 }
        );
        assert!(matches!(
            err_kind(DenseMatrix::new(usize::MAX, &[])),
            ErrorKind::DimensionMismatch { .. }
        ));
        let m = DenseMatrix::new(2, &[0.25, 0.75, 1.0, 0.0]).unwrap();
        assert_eq!(m.get(0, 1), 0.75);
        assert_eq!(m.get(2, 0), 0.0);
        assert_eq!(m.get(0, 2), 0.0);
        assert_eq!(m.get(usize::MAX, usize::MAX), 0.0);
        assert_eq!(m.row_sum(0), 1.0);
        let mut seen = heapless::Vec::<(usize, f64), 4>::new();
        m.for_each_in_row(1, |j, p| seen.push((j, p)).unwrap());
        assert_eq!(seen.as_slice(), &[(0, 1.0)]);
        m.for_each_in_row(7, |_, _| panic!("no such row"));
    }

    #[test]
    fn csr_validates() {
        let v = [0.5, 0.5, 1.0];
        let ok = CsrMatrix::new(2, &[0, 2, 3], &[0, 1, 0], &v).unwrap();
        assert_eq!(ok.get(0, 1), 0.5);
        assert_eq!(ok.get(1, 1), 0.0);
        assert_eq!(ok.get(1, usize::MAX), 0.0);
        let bad: [(&[usize], &[u32]); 6] = [
            (&[0, 2], &[0, 1, 0]),    // row_ptr too short
            (&[1, 2, 3], &[0, 1, 0]), // does not start at 0
            (&[0, 2, 2], &[0, 1, 0]), // does not end at nnz
            (&[0, 2, 1], &[0, 1, 0]), // decreasing (and end mismatch)
            (&[0, 2, 3], &[1, 0, 0]), // columns not increasing
            (&[0, 2, 3], &[0, 2, 0]), // column out of range
        ];
        for (rp, ci) in bad {
            assert_eq!(
                err_kind(CsrMatrix::new(2, rp, ci, &v)),
                ErrorKind::MalformedSparse
            );
        }
        assert_eq!(
            err_kind(CsrMatrix::new(2, &[0, 1, 3], &[0, 0, 0], &v)),
            ErrorKind::MalformedSparse
        );
        assert_eq!(
            err_kind(CsrMatrix::new(2, &[0, 2, 3], &[0, 1, 0], &v[..2])),
            ErrorKind::MalformedSparse
        );
        assert_eq!(
            err_kind(CsrMatrix::new(
                2,
                &[0, 2, 3],
                &[0, 1, 0],
                &[0.5, f64::INFINITY, 1.0]
            )),
            ErrorKind::NonFiniteEntry { row: 0, col: 1 }
        );
        assert_eq!(
            err_kind(CsrMatrix::new(2, &[0, 2, 3], &[0, 1, 0], &[0.5, 0.5, -1.0])),
            ErrorKind::NegativeEntry { row: 1, col: 0 }
        );
        assert_eq!(
            err_kind(CsrMatrix::new(usize::MAX, &[0], &[], &[])),
            ErrorKind::MalformedSparse
        );
    }

    /// A 4-state matrix with empty and full rows, dense and CSR.
    const FOUR_STATES: [f64; 16] = [
        0.0, 0.2, 0.3, 0.5, 0.1, 0.0, 0.0, 0.9, 0.4, 0.4, 0.2, 0.0, 0.0, 0.0, 0.0, 1.0,
    ];
    const FOUR_ROW_PTR: [usize; 5] = [0, 3, 5, 8, 9];
    const FOUR_COLS: [u32; 9] = [1, 2, 3, 0, 3, 0, 1, 2, 3];
    const FOUR_VALUES: [f64; 9] = [0.2, 0.3, 0.5, 0.1, 0.9, 0.4, 0.4, 0.2, 1.0];

    fn four_states_dense_and_csr() -> (DenseMatrix<'static>, CsrMatrix<'static>) {
        (
            DenseMatrix::new(4, &FOUR_STATES).unwrap(),
            CsrMatrix::new(4, &FOUR_ROW_PTR, &FOUR_COLS, &FOUR_VALUES).unwrap(),
        )
    }

    #[test]
    fn ascending_queries_match_get_in_any_order() {
        let (dense, csr) = four_states_dense_and_csr();
        // Increasing columns (the fast walk), then backwards, repeats and jumps on the
        // same cursor (the fallback), rows past the end and huge columns included
        let orders: [&[usize]; 4] = [
            &[0, 1, 2, 3, 4, 5],
            &[5, 3, 2, 2, 1, 0],
            &[3, 0, 3, 1, 1, 2, usize::MAX, 0],
            &[2, 4, 1, 3, 0],
        ];
        for i in 0..6 {
            for order in orders {
                let (mut a, mut b) = (0, 0);
                for &j in order {
                    let expected = dense.get(i, j);
                    assert_eq!(csr.get(i, j), expected);
                    assert_eq!(csr.get_ascending(i, j, &mut a), expected, "csr ({i}, {j})");
                    assert_eq!(dense.get_ascending(i, j, &mut b), expected);
                }
            }
        }
    }

    #[test]
    fn row_ranges_match_filtered_rows() {
        let (dense, csr) = four_states_dense_and_csr();
        for i in 0..5 {
            for a in 0..5 {
                for b in 0..6 {
                    let mut x = heapless::Vec::<(usize, f64), 8>::new();
                    let mut y = heapless::Vec::<(usize, f64), 8>::new();
                    let mut z = heapless::Vec::<(usize, f64), 8>::new();
                    dense.for_each_in_row_range(i, a..b, |j, p| x.push((j, p)).unwrap());
                    csr.for_each_in_row_range(i, a..b, |j, p| y.push((j, p)).unwrap());
                    (&&dense).for_each_in_row(i, |j, p| {
                        if (a..b).contains(&j) {
                            z.push((j, p)).unwrap();
                        }
                    });
                    assert_eq!(x, y);
                    assert_eq!(x, z);
                    // From a cursor left anywhere by an earlier range, before or after
                    for (c0, c1) in [(0, a), (a, b), (b, 6), (3, 1)] {
                        let mut cursor = 0;
                        csr.for_each_in_row_range_ascending(i, c0..c1, &mut cursor, |_, _| {});
                        let mut u = heapless::Vec::<(usize, f64), 8>::new();
                        csr.for_each_in_row_range_ascending(i, a..b, &mut cursor, |j, p| {
                            u.push((j, p)).unwrap();
                        });
                        assert_eq!(x, u, "row {i}, {a}..{b} after {c0}..{c1}");
                    }
                }
            }
        }
    }
}
