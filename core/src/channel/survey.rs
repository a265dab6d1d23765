//! The validation, the measures and the checks of a channel in one pass over its matrix:
//! what a measurement of form factors needs, for the price of one visit per stored entry.

use alloc::vec;
use alloc::vec::Vec;
use core::ops::Range;

use super::checks::CheckSums;
use super::matrix::check_entry;
use super::measures::{MeasureSums, RowMeasureSums};
use super::{Channel, Checks, Measures, ROW_SUM_TOLERANCE, Transitions};
use crate::error::{Error, ErrorKind, Result};
use crate::math::KahanSum;

/// `Channel::new(w, p)` followed by [`Channel::measures`] and [`Channel::checks`], in
/// one pass over the stored entries instead of four (the validation, the measures, the
/// row sums with reciprocity, the column sums `wP` of stationarity).
///
/// Every sum adds the same terms in the same order as those methods (the shared
/// [`RowMeasureSums`], [`MeasureSums`] and [`CheckSums`]; the column sums in increasing
/// row order), so the numbers are the same bits; a channel that `Channel::new` refuses
/// gives the same error (the weights first, then the rows in order, an entry's error
/// before its row's sum).
///
/// A dense `n × n` matrix is scanned once instead of four times; for the 5400-patch cube
/// that is most of `measure`'s fixed cost after the lines. The reverse entry `P_ji` of each
/// stored `P_ij` is gathered for a block of rows at a time ([`ReverseEntries`]): `O(nnz)`
/// in all for CSR storage, where a bisection per entry was half of a 10⁷-line `measure`
/// of the cube.
///
/// # Errors
/// Those of `Channel::new`.
pub(crate) fn measures_and_checks<M: Transitions>(w: &[f64], p: M) -> Result<(Measures, Checks)> {
    // The distribution and the shape, as `Channel::new` checks them (an O(n) pass)
    let channel = Channel::new(w, EmptyRows(p.n_states()))?;
    let w = channel.weights();
    let n = w.len();
    let mut measures = MeasureSums::new();
    let mut checks = CheckSums::new();
    let mut columns = vec![KahanSum::new(); n];
    let mut reverse = ReverseEntries::new(n);
    let mut block_start = 0;
    while block_start < n {
        let block = block_start..n.min(block_start + GATHER_ROWS);
        reverse.gather(&p, w, block.clone());
        for (i, backward) in block.clone().zip(&reverse.backward) {
            let w_i = w.get(i).copied().unwrap_or(0.0);
            let mut backward = backward.iter();
            let mut last_column: Option<usize> = None;
            let mut sum = KahanSum::new();
            let mut row = RowMeasureSums::new();
            let mut bad: Option<Error> = None;
            p.for_each_in_row(i, |j, p_ij| {
                if bad.is_some() {
                    return;
                }
                if let Err(e) = check_entry(i, j, p_ij) {
                    bad = Some(e);
                    return;
                }
                let w_j = match w.get(j) {
                    None => {
                        bad = Some(Error::new(ErrorKind::MalformedSparse));
                        return;
                    }
                    Some(&w_j) if p_ij > 0.0 && w_j == 0.0 => {
                        bad = Some(Error::new(ErrorKind::TransitionToNullState {
                            row: i,
                            col: j,
                        }));
                        return;
                    }
                    Some(&w_j) => w_j,
                };
                sum.add(p_ij);
                row.add(w_i, p_ij, w_j);
                // The gathered `w_j P_ji` follow the row's entries while its columns
                // increase, as `Transitions` promises; a row that breaks the promise is
                // asked directly from there on
                let in_order = last_column.is_none_or(|l| l < j);
                last_column = if in_order { Some(j) } else { Some(usize::MAX) };
                let gathered = backward.next().copied();
                let w_j_p_ji = match gathered {
                    Some(b) if in_order => b,
                    _ => w_j * p.get(j, i),
                };
                checks.add_pair(w_i * p_ij, w_j_p_ji);
                if let Some(c) = columns.get_mut(j) {
                    c.add(w_i * p_ij);
                }
            });
            if let Some(e) = bad {
                return Err(e);
            }
            let sum = sum.total();
            if sum > 1.0 + ROW_SUM_TOLERANCE {
                return Err(Error::new(ErrorKind::RowSumAboveOne { row: i, sum }));
            }
            measures.add_row(w_i, &row);
            checks.add_row_sum(sum);
        }
        block_start = block.end;
    }
    let mut stationarity: f64 = 0.0;
    for (c, &w_j) in columns.iter().zip(w) {
        stationarity = stationarity.max((c.total() - w_j).abs());
    }
    Ok((measures.measures(w), checks.checks(n, stationarity)))
}

/// Rows whose reverse entries [`ReverseEntries::gather`] collects together.
const GATHER_ROWS: usize = 256;

/// Columns per band of [`ReverseEntries::gather`]: the rows of a band are asked by all
/// the block's rows before the next band, so their current cache lines (and pages) are
/// used up while they are held (256 rows × 2 lines = 32 KiB).
const GATHER_BAND: usize = 64;

/// The reverse entries `w_j P_ji` of the stored entries `P_ij` of a block of rows, in each
/// row's order: the transpose read with good locality.
///
/// Asked entry by entry in row order, `P_ji` of row `i`'s entries lies in as many other
/// rows as `i` has entries, each at its own front, so every query is a cache (and TLB)
/// miss. Gathered for [`GATHER_ROWS`] rows at once, band of [`GATHER_BAND`] columns after
/// band, each row `j` of a band is asked by the whole block in a burst (increasing `i`,
/// from its cursor, [`Transitions::get_ascending`]) and each line loaded serves several
/// entries. Every row `j` is asked for increasing `i` over the whole sweep, so its cursor
/// passes each stored entry once: `O(nnz + n²/GATHER_BAND)` in all.
struct ReverseEntries {
    /// Row `j`'s cursor for the queries `P_ji`.
    reverse_cursors: Vec<usize>,
    /// `w_j P_ji` for each entry of the block's rows, one list per row.
    backward: Vec<Vec<f64>>,
}

impl ReverseEntries {
    fn new(n: usize) -> Self {
        Self {
            reverse_cursors: vec![0; n],
            backward: vec![Vec::new(); GATHER_ROWS],
        }
    }

    /// Gathers the reverse entries of `rows` (at most [`GATHER_ROWS`] of them, after
    /// those of the rows before).
    fn gather<M: Transitions>(&mut self, p: &M, w: &[f64], rows: Range<usize>) {
        let n = p.n_states();
        let mut row_cursors = [0usize; GATHER_ROWS];
        for list in &mut self.backward {
            list.clear();
        }
        let cursors = &mut self.reverse_cursors;
        let mut band_start = 0;
        while band_start < n {
            let band = band_start..n.min(band_start.saturating_add(GATHER_BAND));
            for ((i, cursor), list) in rows.clone().zip(&mut row_cursors).zip(&mut self.backward) {
                p.for_each_in_row_range_ascending(i, band.clone(), cursor, |j, _| {
                    let p_ji = match cursors.get_mut(j) {
                        Some(c) => p.get_ascending(j, i, c),
                        None => p.get(j, i),
                    };
                    list.push(w.get(j).copied().unwrap_or(0.0) * p_ji);
                });
            }
            band_start = band.end;
        }
    }
}

/// A matrix of `n` states with no entries: `Channel::new` of it checks the distribution
/// and the shape only.
#[derive(Clone, Copy, Debug)]
struct EmptyRows(usize);

impl Transitions for EmptyRows {
    fn n_states(&self) -> usize {
        self.0
    }

    fn for_each_in_row<F: FnMut(usize, f64)>(&self, _: usize, _: F) {}

    fn get(&self, _: usize, _: usize) -> f64 {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::super::{CsrMatrix, CsrMatrixBuf, DenseMatrix};
    use super::*;
    use alloc::vec::Vec;

    /// The single pass against the four passes, value or error, dense and sparse.
    fn agree(w: &[f64], p: &[f64]) {
        let n = w.len();
        let dense = DenseMatrix::from_validated(n, p);
        let separate = Channel::new(w, dense).map(|c| (c.measures(), c.checks()));
        assert_eq!(measures_and_checks(w, dense), separate);
        if let Ok(csr) = CsrMatrixBuf::from_dense(n, p) {
            let m = csr.as_matrix();
            let separate = Channel::new(w, m).map(|c| (c.measures(), c.checks()));
            assert_eq!(measures_and_checks(w, m), separate);
        }
    }

    #[test]
    fn one_pass_is_the_four_passes_bit_for_bit() {
        agree(&[0.5, 0.5], &[0.0, 1.0, 1.0, 0.0]);
        agree(&[0.25, 0.75], &[0.1, 0.3, 0.1, 0.0]);
        let w = [0.2, 0.3, 0.5];
        let p = [0.0, 0.3, 0.7, 0.2, 0.1, 0.7, 0.28, 0.42, 0.3];
        agree(&w, &p);
    }

    /// A sparse channel of 700 states: several blocks of gathered rows and many bands,
    /// rows of different lengths, every entry with its reverse (of another value), so the
    /// reciprocity error depends on pairing each entry with the right one.
    #[test]
    fn one_pass_agrees_across_blocks_and_bands() {
        const N: usize = 700;
        let stored = |i: usize, j: usize| (i * j + 3 * (i + j)) % 17 < 2 + (i + j) % 5;
        let mut triplets = Vec::new();
        for i in 0..N {
            let row: Vec<usize> = (0..N).filter(|&j| stored(i, j)).collect();
            let total = row.len() as f64 * if i % 3 == 0 { 1.25 } else { 1.0 };
            for (k, &j) in row.iter().enumerate() {
                triplets.push((i, j, (1.0 + (k % 4) as f64) / (2.5 * total)));
            }
        }
        let weight_total: f64 = (0..N).map(|i| (1 + i % 7) as f64).sum();
        let w: Vec<f64> = (0..N).map(|i| (1 + i % 7) as f64 / weight_total).collect();
        let csr = CsrMatrixBuf::from_triplets(N, &triplets).unwrap();
        assert!(csr.nnz() > 40_000);
        let m = csr.as_matrix();
        let separate = Channel::new(&w, m).map(|c| (c.measures(), c.checks()));
        let (measures, checks) = measures_and_checks(&w, m).unwrap();
        assert_eq!(Ok((measures, checks)), separate);
        assert!(checks.max_reciprocity_error > 0.0 && checks.max_reciprocity_error < 1.0);
    }

    /// A matrix that breaks the promise of increasing columns (row 1 backwards): its
    /// reverse entries are asked directly, and the checks still pair each entry with its
    /// own reverse.
    #[test]
    fn rows_out_of_order_are_paired_right() {
        #[derive(Clone, Copy)]
        struct Backwards<'a>(CsrMatrix<'a>);
        impl Transitions for Backwards<'_> {
            fn n_states(&self) -> usize {
                self.0.n_states()
            }
            fn for_each_in_row<F: FnMut(usize, f64)>(&self, i: usize, mut f: F) {
                let (cols, vals) = self.0.row(i);
                let mut entries: Vec<(u32, f64)> =
                    cols.iter().copied().zip(vals.iter().copied()).collect();
                if i == 1 {
                    entries.reverse();
                }
                for (j, v) in entries {
                    f(j as usize, v);
                }
            }
            fn get(&self, i: usize, j: usize) -> f64 {
                self.0.get(i, j)
            }
        }
        let w = [0.2, 0.3, 0.5];
        let p = [0.0, 0.3, 0.7, 0.2, 0.1, 0.7, 0.28, 0.42, 0.3];
        let csr = CsrMatrixBuf::from_dense(3, &p).unwrap();
        let m = Backwards(csr.as_matrix());
        let separate = Channel::new(&w, m).map(|c| (c.measures(), c.checks()));
        let (measures, checks) = measures_and_checks(&w, m).unwrap();
        assert_eq!(Ok(checks), separate.map(|s| s.1));
        let ordered = measures_and_checks(&w, csr.as_matrix()).unwrap();
        assert_eq!(
            checks.max_reciprocity_error,
            ordered.1.max_reciprocity_error
        );
        assert!(measures.h_s > 0.0);
    }

    #[test]
    fn one_pass_refuses_what_new_refuses() {
        // Not normalised, a row above one, a transition into a state of weight 0
        agree(&[0.5, 0.6], &[0.0, 1.0, 1.0, 0.0]);
        agree(&[0.5, 0.5], &[0.0, 1.0, 0.5, 0.6]);
        agree(&[1.0, 0.0], &[0.0, 1.0, 1.0, 0.0]);
        agree(&[], &[]);
        // A negative and a non-finite entry (the dense view does not check them itself)
        let separate = |w: &[f64], p: &[f64]| {
            let m = DenseMatrix::from_validated(w.len(), p);
            (
                measures_and_checks(w, m).unwrap_err(),
                Channel::new(w, m).unwrap_err(),
            )
        };
        let (a, b) = separate(&[0.5, 0.5], &[0.0, -1.0, 1.0, 0.0]);
        assert_eq!(a, b);
        let (a, b) = separate(&[0.5, 0.5], &[0.0, 1.0, f64::NAN, 0.0]);
        assert_eq!(a, b);
    }

    proptest::proptest! {
        /// Random rows (some entries zero, rows summing to one or less, weights from a
        /// random vector): the same measures and checks, bit for bit.
        #[test]
        fn one_pass_agrees_on_random_channels(
            n in 1usize..9,
            raw in proptest::collection::vec(
                proptest::prop_oneof![proptest::strategy::Just(0.0), 0.0f64..1.0], 81),
            weights in proptest::collection::vec(0.01f64..1.0, 9),
            closed in proptest::bool::ANY,
        ) {
            let total: f64 = weights[..n].iter().sum();
            let w: Vec<f64> = weights[..n].iter().map(|x| x / total).collect();
            let mut p = raw[..n * n].to_vec();
            for row in p.chunks_mut(n) {
                let sum: f64 = row.iter().sum();
                let scale = if closed || sum > 1.0 { sum } else { 1.0 };
                for x in row.iter_mut() {
                    *x = if scale > 0.0 { *x / scale } else { 0.0 };
                }
            }
            agree(&w, &p);
        }
    }
}
