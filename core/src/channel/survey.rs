//! The validation, the measures and the checks of a channel in one pass over its matrix:
//! what a measurement of form factors needs, for the price of one visit per stored entry.

use alloc::vec;
use alloc::vec::Vec;
use core::ops::Range;

use super::checks::CheckSums;
use super::matrix::check_entry;
use super::measures::{MeasureSums, RowMeasureSums, RowTotals};
use super::{Channel, Checks, Measures, ROW_SUM_TOLERANCE, Transitions};
use crate::error::{Error, ErrorKind, Result};
use crate::math::KahanSum;

/// How [`measures_and_checks_by`] has its parts computed: `run(parts, part)` calls
/// `part(k)` for `k` in `0..parts`, on any threads in any order, and returns what it
/// computed at index `k` (a missing or short result is computed on the caller's thread).
/// A caller without threads returns nothing.
pub(crate) type PartRunner<'r> =
    dyn FnMut(usize, &(dyn Fn(usize) -> SurveyPart + Sync)) -> Vec<Option<SurveyPart>> + 'r;

/// `Channel::new(w, p)` followed by [`Channel::measures`] and [`Channel::checks`], in
/// one pass over the stored entries instead of four (the validation, the measures, the
/// row sums with reciprocity, the column sums `wP` of stationarity), on this thread.
///
/// # Errors
/// Those of `Channel::new`.
#[cfg(test)]
pub(crate) fn measures_and_checks<M: Transitions + Sync>(
    w: &[f64],
    p: M,
) -> Result<(Measures, Checks)> {
    measures_and_checks_by(w, p, &mut |_, _| Vec::new())
}

/// [`measures_and_checks`] with its parts computed by `run` (on threads: the same bits).
///
/// Every sum adds the same terms in the same order as those methods (the shared
/// [`RowMeasureSums`], [`MeasureSums`] and [`CheckSums`]; the column sums in increasing
/// row order), so the numbers are the same bits; a channel that `Channel::new` refuses
/// gives the same error (the weights first, then the rows in order, an entry's error
/// before its row's sum).
///
/// The work is cut into parts that depend on nothing but their index ([`SurveyPart`]):
/// blocks of [`BLOCK_ROWS`] rows, each row's entry checks, row sum, measure terms and
/// reciprocity, the reverse entry `w_j P_ji` of each stored `P_ij` gathered for the block
/// at once by [`ReverseEntries`] (`O(nnz)` in all for CSR storage). Row `i`'s reverse
/// entries are also the terms `w_k P_ki` of column `i`, in increasing `k`, when every
/// entry has its reverse (a symmetric pattern, as the counts of global lines give): then
/// the column sums of stationarity, `Σ_k w_k P_ki`, are added from them, the same terms in
/// the same order as a sweep over the rows; else by bands of columns, a second set of
/// parts, each column summed over the rows in increasing `k`. The parts are assembled in
/// order: each row's totals are added to the scene's sums in increasing `i`, as one sweep
/// adds them, and the largest errors are maxima, which do not depend on the grouping. So
/// any number of threads gives the bits of one thread. (A stored or skipped zero term
/// changes no compensated sum.)
///
/// # Errors
/// Those of `Channel::new`.
pub(crate) fn measures_and_checks_by<M: Transitions + Sync>(
    w: &[f64],
    p: M,
    run: &mut PartRunner<'_>,
) -> Result<(Measures, Checks)> {
    // The distribution and the shape, as `Channel::new` checks them (an O(n) pass)
    let channel = Channel::new(w, EmptyRows(p.n_states()))?;
    let w = channel.weights();
    let n = w.len();
    let row_blocks = n.div_ceil(BLOCK_ROWS);
    let block = |k: usize| {
        let start = k.saturating_mul(BLOCK_ROWS);
        survey_rows(&p, w, start..n.min(start.saturating_add(BLOCK_ROWS)))
    };
    let mut done = run(row_blocks, &|k| SurveyPart::Rows(block(k)));
    done.resize_with(row_blocks, || None);
    // Assembled in order; a part the runner did not compute (it stopped) is computed here
    let mut measures = MeasureSums::new();
    let mut checks = CheckSums::new();
    let mut stationarity: f64 = 0.0;
    let mut columns_from_rows = true;
    for (k, result) in done.into_iter().enumerate() {
        let rows = match result {
            Some(SurveyPart::Rows(r)) if r.start == k * BLOCK_ROWS => r,
            _ => block(k),
        };
        for (i, (totals, sum)) in (rows.start..).zip(&rows.rows) {
            measures.add_row(w.get(i).copied().unwrap_or(0.0), totals);
            checks.add_row_sum(*sum);
        }
        checks.add_reciprocity_error(rows.reciprocity_error);
        if let Some(e) = rows.error {
            return Err(e);
        }
        stationarity = stationarity.max(rows.column_error);
        columns_from_rows &= rows.columns_from_rows;
    }
    // A stored entry whose reverse is not (or a row out of order): the column sums by
    // bands of columns instead
    if !columns_from_rows {
        let band = band_columns(n);
        let bands = n.div_ceil(band);
        let band_error = |b: usize| {
            let start = b.saturating_mul(band);
            column_sum_error(&p, w, start..n.min(start.saturating_add(band)))
        };
        let mut done = run(bands, &|b| SurveyPart::Columns(band_error(b)));
        done.resize_with(bands, || None);
        stationarity = 0.0;
        for (b, result) in done.into_iter().enumerate() {
            let error = match result {
                Some(SurveyPart::Columns(e)) => e,
                _ => band_error(b),
            };
            stationarity = stationarity.max(error);
        }
    }
    Ok((measures.measures(w), checks.checks(n, stationarity)))
}

/// One part of a survey ([`measures_and_checks_by`]), computed apart.
#[derive(Debug)]
pub(crate) enum SurveyPart {
    /// A block of rows.
    Rows(SurveyedRows),
    /// A band of columns: the largest `|Σ_i w_i P_ij − w_j|` of its columns.
    Columns(f64),
}

/// What a block of rows contributes to a survey.
#[derive(Debug)]
pub(crate) struct SurveyedRows {
    /// The first row of the block.
    start: usize,
    /// Each row's measure totals and compensated sum `Σ_j P_ij`, up to the first error.
    rows: Vec<(RowTotals, f64)>,
    /// The largest relative reciprocity error of the block's entries.
    reciprocity_error: f64,
    /// The first error of the block's rows, in row order (after the rows in `rows`).
    error: Option<Error>,
    /// The largest `|Σ_k w_k P_ki − w_i|` of the block's rows `i`, the column sums taken
    /// from the rows' reverse entries (meaningful when `columns_from_rows`).
    column_error: f64,
    /// Whether the reverse entries of each row `i` are all the terms `w_k P_ki` of column
    /// `i`, in increasing `k`: every entry `w_i P_ij > 0` of the block has a reverse
    /// `w_j P_ji > 0` (so `P_ij` is among row `j`'s reverse entries) and the rows keep
    /// their columns increasing.
    columns_from_rows: bool,
}

/// Rows of a block of [`measures_and_checks_by`]: a few blocks of [`GATHER_ROWS`], so
/// that a row's cursor is placed (a bisection, a cache miss a step) once per block of
/// 1024 rows, not once per 256.
const BLOCK_ROWS: usize = 4 * GATHER_ROWS;

/// Rows whose reverse entries [`ReverseEntries::gather`] collects together.
const GATHER_ROWS: usize = 256;

/// Columns per band of the column sums at least ([`band_columns`]).
const BAND_COLUMNS: usize = 512;

/// Bands of column sums at most: each band visits every row (a bisection per row for CSR
/// storage), so their number is bounded for large scenes.
const MAX_BANDS: usize = 16;

/// The width of a band of column sums for `n` states.
fn band_columns(n: usize) -> usize {
    BAND_COLUMNS.max(n.div_ceil(MAX_BANDS))
}

/// The entry checks, row sums, measure terms and reciprocity of the rows `rows`.
fn survey_rows<M: Transitions>(p: &M, w: &[f64], rows: Range<usize>) -> SurveyedRows {
    let mut out = SurveyedRows {
        start: rows.start,
        rows: Vec::with_capacity(rows.len()),
        reciprocity_error: 0.0,
        error: None,
        column_error: 0.0,
        columns_from_rows: true,
    };
    let mut checks = CheckSums::new();
    let mut reverse = ReverseEntries::new(w.len(), rows.start);
    let mut gather_start = rows.start;
    while gather_start < rows.end {
        let gathered = gather_start..rows.end.min(gather_start.saturating_add(GATHER_ROWS));
        reverse.gather(p, w, gathered.clone());
        for (i, reverse_list) in gathered.clone().zip(&reverse.backward) {
            let w_i = w.get(i).copied().unwrap_or(0.0);
            let mut backward = reverse_list.iter();
            let mut last_column: Option<usize> = None;
            let mut columns_from_rows = true;
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
                    _ => {
                        columns_from_rows = false;
                        w_j * p.get(j, i)
                    }
                };
                let w_i_p_ij = w_i * p_ij;
                if w_i_p_ij > 0.0 && !(w_j_p_ji > 0.0) {
                    columns_from_rows = false;
                }
                checks.add_pair(w_i_p_ij, w_j_p_ji);
            });
            if backward.next().is_some() {
                columns_from_rows = false;
            }
            out.columns_from_rows &= columns_from_rows;
            out.reciprocity_error = checks.reciprocity_error();
            if let Some(e) = bad {
                out.error = Some(e);
                return out;
            }
            let sum = sum.total();
            if sum > 1.0 + ROW_SUM_TOLERANCE {
                out.error = Some(Error::new(ErrorKind::RowSumAboveOne { row: i, sum }));
                return out;
            }
            out.rows.push((row.totals(), sum));
            // Column i's sum: its terms `w_k P_ki` are row i's reverse entries, in increasing k
            // (when `columns_from_rows`), added as a sweep over the rows adds them
            let mut column = KahanSum::new();
            for &w_k_p_ki in reverse_list {
                column.add(w_k_p_ki);
            }
            out.column_error = out.column_error.max((column.total() - w_i).abs());
        }
        gather_start = gathered.end;
    }
    out
}

/// The largest `|Σ_i w_i P_ij − w_j|` over the columns `columns`, each column summed over
/// the rows in increasing `i` (compensated), as a sweep of the whole matrix adds them.
fn column_sum_error<M: Transitions>(p: &M, w: &[f64], columns: Range<usize>) -> f64 {
    let mut sums = vec![KahanSum::new(); columns.len()];
    for (i, &w_i) in w.iter().enumerate() {
        p.for_each_in_row_range(i, columns.clone(), |j, p_ij| {
            if let Some(c) = sums.get_mut(j.wrapping_sub(columns.start)) {
                c.add(w_i * p_ij);
            }
        });
    }
    let mut error: f64 = 0.0;
    for (c, &w_j) in sums.iter().zip(w.get(columns).unwrap_or(&[])) {
        error = error.max((c.total() - w_j).abs());
    }
    error
}

/// Columns per band of [`ReverseEntries::gather`]: the rows of a band are asked by all
/// the block's rows before the next band, so their current cache lines (and pages) are
/// used up while they are held (256 rows × 2 lines = 32 KiB).
const GATHER_BAND: usize = 64;

/// A row cursor not yet placed ([`ReverseEntries::gather`] places it at the block's first
/// row).
const UNPLACED: usize = usize::MAX;

/// The reverse entries `w_j P_ji` of the stored entries `P_ij` of a block of rows, in each
/// row's order: the transpose read with good locality.
///
/// Asked entry by entry in row order, `P_ji` of row `i`'s entries lies in as many other
/// rows as `i` has entries, each at its own front, so every query is a cache (and TLB)
/// miss. Gathered for [`GATHER_ROWS`] rows at once, band of [`GATHER_BAND`] columns after
/// band, each row `j` of a band is asked by the whole block in a burst (increasing `i`,
/// from its cursor, [`Transitions::get_ascending`]) and each line loaded serves several
/// entries. Row `j`'s cursor is placed at the block's first row when the block first asks
/// it ([`Transitions::cursor_at`], a bisection for CSR) and passes each of its stored
/// entries in the block's columns once: `O(nnz + n²/GATHER_BAND)` in all, plus a
/// bisection per block and row asked.
struct ReverseEntries {
    /// Row `j`'s cursor for the queries `P_ji`.
    reverse_cursors: Vec<usize>,
    /// `w_j P_ji` for each entry of the block's rows, one list per row.
    backward: Vec<Vec<f64>>,
    /// The first row of the block of [`BLOCK_ROWS`] rows whose reverse entries are
    /// gathered, [`GATHER_ROWS`] at a time, in increasing rows: where the cursors are placed.
    first_row: usize,
}

impl ReverseEntries {
    fn new(n: usize, first_row: usize) -> Self {
        Self {
            reverse_cursors: vec![UNPLACED; n],
            backward: vec![Vec::new(); GATHER_ROWS],
            first_row,
        }
    }

    /// Gathers the reverse entries of `rows` (at most [`GATHER_ROWS`] of them, after
    /// those of the block's rows before).
    fn gather<M: Transitions>(&mut self, p: &M, w: &[f64], rows: Range<usize>) {
        let n = p.n_states();
        let mut row_cursors = [0usize; GATHER_ROWS];
        for list in &mut self.backward {
            list.clear();
        }
        let cursors = &mut self.reverse_cursors;
        let first_row = self.first_row;
        let mut band_start = 0;
        while band_start < n {
            let band = band_start..n.min(band_start.saturating_add(GATHER_BAND));
            for ((i, cursor), list) in rows.clone().zip(&mut row_cursors).zip(&mut self.backward) {
                p.for_each_in_row_range_ascending(i, band.clone(), cursor, |j, _| {
                    let p_ji = match cursors.get_mut(j) {
                        Some(c) => {
                            if *c == UNPLACED {
                                place(p, j, first_row, c);
                            }
                            p.get_ascending(j, i, c)
                        }
                        None => p.get(j, i),
                    };
                    list.push(w.get(j).copied().unwrap_or(0.0) * p_ji);
                });
            }
            band_start = band.end;
        }
    }
}

/// Places row `j`'s cursor at its first stored column `≥ first_row`, once per block: out
/// of line, so that the gathering closure stays small enough to be inlined.
#[cold]
#[inline(never)]
fn place<M: Transitions>(p: &M, j: usize, first_row: usize, cursor: &mut usize) {
    *cursor = p.cursor_at(j, first_row);
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

    /// Parts computed out of order by the runner, some left out (an executor that
    /// stopped: computed by the caller), some at the wrong index: the bits of one sweep,
    /// with the column sums from the rows' reverse entries (a symmetric pattern: one set
    /// of parts) or by bands of columns (entries without a reverse: a second set).
    #[test]
    fn parts_in_any_order_give_the_bits_of_one_sweep() {
        parts_in_any_order(|i, j| (i * 7 + j * 13) % 11 < 3 || i == j, 2);
        parts_in_any_order(|i, j| (i * j + 5 * (i + j)) % 13 < 3, 1);
    }

    fn parts_in_any_order(stored: impl Fn(usize, usize) -> bool, calls: usize) {
        // Three blocks of rows, each of several gathers, and three bands of columns
        const N: usize = 2600;
        let mut triplets = Vec::new();
        for i in 0..N {
            let row: Vec<usize> = (0..N).filter(|&j| stored(i, j)).collect();
            for (k, &j) in row.iter().enumerate() {
                triplets.push((i, j, (1.0 + (k % 3) as f64) / (2.0 * row.len() as f64)));
            }
        }
        let weight_total: f64 = (0..N).map(|i| (2 + i % 5) as f64).sum();
        let w: Vec<f64> = (0..N).map(|i| (2 + i % 5) as f64 / weight_total).collect();
        let csr = CsrMatrixBuf::from_triplets(N, &triplets).unwrap();
        let m = csr.as_matrix();
        let one_sweep = measures_and_checks(&w, m).unwrap();
        let mut runs = 0;
        let mut shuffled = |parts: usize, part: &(dyn Fn(usize) -> SurveyPart + Sync)| {
            runs += 1;
            // Several row blocks, or column bands
            assert!(parts >= 3, "{parts}");
            let mut done: Vec<Option<SurveyPart>> = (0..parts).map(|_| None).collect();
            for k in (0..parts).rev().filter(|k| k % 3 != 1) {
                done[k] = Some(part(k));
            }
            // A result at the wrong index is not trusted
            done.swap(0, parts - 1);
            done
        };
        let by_parts = measures_and_checks_by(&w, m, &mut shuffled).unwrap();
        assert_eq!(runs, calls);
        assert_eq!(by_parts, one_sweep);
        let separate = Channel::new(&w, m).map(|c| (c.measures(), c.checks()));
        assert_eq!(Ok(by_parts), separate);
        assert!(by_parts.1.stationarity_error > 0.0);
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
