//! The validation, the measures and the checks of a channel in one pass over its matrix:
//! what a measurement of form factors needs, for the price of one visit per stored entry.

use alloc::vec;

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
/// that is most of `measure`'s fixed cost after the lines.
///
/// # Errors
/// Those of `Channel::new`.
pub(crate) fn measures_and_checks<M: Transitions>(w: &[f64], p: M) -> Result<(Measures, Checks)> {
    // The distribution and the shape, as `Channel::new` checks them (an O(n) pass)
    let channel = Channel::new(w, EmptyRows(p.n_states()))?;
    let w = channel.weights();
    let n = w.len();
    let weight = |j: usize| w.get(j).copied().unwrap_or(0.0);
    let mut measures = MeasureSums::new();
    let mut checks = CheckSums::new();
    let mut columns = vec![KahanSum::new(); n];
    for (i, &w_i) in w.iter().enumerate() {
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
            checks.add_pair(w_i * p_ij, weight(j) * p.get(j, i));
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
    let mut stationarity: f64 = 0.0;
    for (c, &w_j) in columns.iter().zip(w) {
        stationarity = stationarity.max((c.total() - w_j).abs());
    }
    Ok((measures.measures(w), checks.checks(n, stationarity)))
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
    use super::super::{CsrMatrixBuf, DenseMatrix};
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
