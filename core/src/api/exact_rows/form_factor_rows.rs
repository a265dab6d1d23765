//! [`ExactFormFactorRows`]: some rows `F_p·` of a 3D scene's exact form factors with
//! occlusion, computed from only the job's rows they need, the same bits as the whole
//! matrix's rows ([`Measurement::from_exact_rows`], [`Measurement::exact_within`]).
//!
//! Row `i` of an [`ExactRows`] job holds the pairs `(i, j > i)`, so the whole row `p` of
//! `F` (every `F_pj`) needs the job's row `p` (its `j > p`) and every earlier row `i` (its
//! pair `(i, p)`): the rows `0..max(P) + 1` for a set `P` of wanted rows. Each entry is the
//! assembly's operation on its pair's flux (the module documentation of
//! [`ExactRows`]: `F_pj = min(flux / A_p, 1)`), made by the same code (`Assembled`), so the
//! same value. When some polygon may hide another, rows above 1 are capped, and the cap of
//! row `p` uses the sums of the rows it shares entries with, theirs use their neighbours'
//! (the cap's second step), and the cap is skipped only when no row at all is above 1
//! (`occluded_3d::cap_rows`): every row is computed then, and the rows are the complete
//! job's.
//!
//! [`Measurement::from_exact_rows`]: crate::Measurement::from_exact_rows
//! [`Measurement::exact_within`]: crate::Measurement::exact_within

use core::ops::Range;

use crate::error::{ErrorKind, Result};

use super::{Assembled, ExactRows};

/// Whole rows `0..m` of a 3D scene's exact form factors with occlusion (every `F_pj`, `j`
/// in `0..n`, with its error estimate), computed from the job's rows `0..m` alone when no
/// polygon may hide another, from every row otherwise (see the module documentation): the
/// same bits as the whole matrix's rows.
#[derive(Debug)]
pub struct ExactFormFactorRows {
    /// The rows held whole; also the job's rows computed (`0..m`, or `0..n`).
    rows: Range<usize>,
    n: usize,
    pairs: usize,
    may_occlude: bool,
    matrix: Assembled,
}

impl ExactFormFactorRows {
    /// The whole rows of `rows`, the first rows `0..m` of a job (its ranges
    /// [`ExactRows::merge`]d, or computed at once): rows `0..m` when no polygon may hide
    /// another; every row of a complete job; none of an incomplete job where some polygon
    /// may hide another (the cap needs every row).
    ///
    /// # Errors
    /// [`ErrorKind::MissingRows`] when `rows` does not begin at row 0.
    pub(super) fn from_rows(rows: &ExactRows) -> Result<ExactFormFactorRows> {
        let n = rows.n_patches();
        if rows.rows.start != 0 {
            return Err(ErrorKind::MissingRows {
                have: rows.rows.start as u64..rows.rows.end as u64,
                total: n as u64,
            }
            .into());
        }
        let whole = if rows.may_occlude && !rows.is_complete() {
            0..0
        } else {
            rows.rows()
        };
        let (matrix, _) = Assembled::of(rows);
        Ok(ExactFormFactorRows {
            rows: whole,
            n,
            pairs: rows.pair_count(),
            may_occlude: rows.may_occlude,
            matrix,
        })
    }

    /// The rows held whole (`0..m`): also the job's rows computed by
    /// [`ExactRows::form_factor_rows`].
    #[must_use]
    pub fn rows(&self) -> Range<usize> {
        self.rows.clone()
    }

    /// Number of patches of the scene (the job's rows are `0..n`).
    #[must_use]
    pub fn n_patches(&self) -> usize {
        self.n
    }

    /// Pairs `(i, j > i)` of the job's rows computed that see each other.
    #[must_use]
    pub fn pair_count(&self) -> usize {
        self.pairs
    }

    /// Whether some polygon may hide another (then the rows held are every row).
    #[must_use]
    pub fn may_occlude(&self) -> bool {
        self.may_occlude
    }

    /// Calls `f(j, F_pj, error estimate)` for each stored entry of row `p` (the pairs
    /// that see each other, `j` increasing; a stored `F_pj` may be 0 with a non-zero
    /// estimate: a pair decided hidden by its bound).
    ///
    /// # Errors
    /// [`ErrorKind::PatchIndex`] for `p ≥ n`; [`ErrorKind::MissingRows`] when row `p` is
    /// not held whole.
    pub fn for_each_in_row(&self, p: usize, mut f: impl FnMut(usize, f64, f64)) -> Result<()> {
        for k in self.entries_of(p)? {
            f(
                self.matrix.columns[k] as usize,
                self.matrix.values[k],
                self.matrix.errors[k],
            );
        }
        Ok(())
    }

    /// Row `p` of `F` into `out[..n]`, dense (`F_pj` for every patch `j`, 0 where the pair
    /// does not see each other).
    ///
    /// # Errors
    /// Those of [`ExactFormFactorRows::for_each_in_row`]; [`ErrorKind::BufferTooSmall`]
    /// when `out` has fewer than `n` entries.
    pub fn row_into(&self, p: usize, out: &mut [f64]) -> Result<()> {
        let entries = self.entries_of(p)?;
        let found = out.len();
        let out = out.get_mut(..self.n).ok_or(ErrorKind::BufferTooSmall {
            needed: self.n,
            found,
        })?;
        out.fill(0.0);
        for k in entries {
            out[self.matrix.columns[k] as usize] = self.matrix.values[k];
        }
        Ok(())
    }

    /// The stored entries of row `p`, when it is held whole.
    fn entries_of(&self, p: usize) -> Result<Range<usize>> {
        if p >= self.n {
            return Err(ErrorKind::PatchIndex {
                index: p,
                len: self.n,
            }
            .into());
        }
        if !self.rows.contains(&p) {
            return Err(ErrorKind::MissingRows {
                have: self.rows.start as u64..self.rows.end as u64,
                total: self.n as u64,
            }
            .into());
        }
        Ok(self.matrix.row(p))
    }
}
