//! What a Monte Carlo run counts, shared by the flatland and 3D tracers.
//!
//! A [`LineTracer`] (the real extension point: one per kind of scene) casts the lines of one
//! seeded chunk into a [`LineTally`]; tallies merge exactly, in any order; a finished tally
//! becomes a [`LineEstimate`]: form factors `F_ij ≈ C_ij / N_i` (2.36, 2.37) and the
//! continuous mutual information with its per-patch and per-pair split.
//!
//! - [`coverage`]: which patches a line job reached, and about how many lines would reach
//!   them all (Crofton's formula).
//! - [`memory`]: lower bounds on what a job will allocate, checked by front ends before it
//!   starts.
//!
//! The pair counts are sparse or dense by size (`counts`); bundles of parallel lines count
//! row blocks (`pair_blocks`).

pub(crate) mod counts;
pub mod coverage;
pub mod memory;
pub(crate) mod pair_blocks;

pub(crate) use counts::DENSE_COUNT_LIMIT;
pub(crate) use counts::DENSE_PAIR_LIMIT;

use alloc::boxed::Box;
use alloc::vec;
use alloc::vec::Vec;
use core::any::Any;

use crate::accel::HitKey;
use crate::channel::{CsrMatrixBuf, RowMajorCsr};
use crate::continuous::{ContinuousEstimate, ContinuousTally};
use crate::error::{ErrorKind, Result};
use crate::formfactor::FormFactors;
use crate::lines::{chunk_count, chunk_range, chunk_rng};
use crate::math::FixedSum;
use crate::tally::counts::{PairCounts, TriangleEntry};

/// Which lines sample the scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LineMethod {
    /// Uniformly distributed global lines (2.37).
    Global,
    /// Cosine-distributed local lines from patches picked by size (2.36).
    Local,
    /// Bundles of parallel global lines: each bundle shares one uniform direction and
    /// covers the bounding circle (sphere) with evenly spaced lines under one uniform shift
    /// (`crate::lines::GlobalBundle2`, `crate::lines::GlobalBundle3`); every line is
    /// tallied as a global line, and each sheaf of bundles is one observation of the
    /// standard error. Cast by a sweep (`crate::accel::ParallelSweep2`) or a raster
    /// (`crate::accel::ParallelRaster3`) instead of one tree query per line.
    Bundle,
}

impl LineMethod {
    /// Every method, in the order of their codes.
    pub const ALL: [LineMethod; 3] = [LineMethod::Global, LineMethod::Local, LineMethod::Bundle];

    /// Whether each line is tallied as a global line (2.37): a segment between two
    /// intersections counts for both ends, so pair counts are symmetric.
    #[inline]
    #[must_use]
    pub const fn is_global(self) -> bool {
        matches!(self, LineMethod::Global | LineMethod::Bundle)
    }

    /// The name of the method on the command line (`--method NAME`).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            LineMethod::Global => "global",
            LineMethod::Local => "local",
            LineMethod::Bundle => "bundle",
        }
    }

    /// What reports print: `"global lines"`, `"local lines"`, `"bundles of parallel
    /// lines"`.
    #[must_use]
    pub const fn description(self) -> &'static str {
        match self {
            LineMethod::Global => "global lines",
            LineMethod::Local => "local lines",
            LineMethod::Bundle => "bundles of parallel lines",
        }
    }
}

/// The reason of [`ErrorKind::UnsupportedMethod`] for a method a tracer does not
/// [`LineTracer::supports`].
pub(crate) const UNSUPPORTED_BY_TRACER: &str = "this kind of scene cannot cast them";

/// A scene prepared for line casting.
pub trait LineTracer {
    /// Number of patches.
    fn n_patches(&self) -> usize;

    /// Patch sizes (lengths or areas), the stationary distribution up to normalisation.
    fn patch_sizes(&self) -> &[f64];

    /// Casts the lines of chunk `chunk` of an `n_lines` job into `tally` (using the tally's
    /// method). Chunk `k` draws from [`crate::lines::chunk_rng`]`(seed, k)`, so the result
    /// depends only on `(seed, n_lines)`. A method the tracer does not
    /// [`LineTracer::supports`] casts nothing.
    fn trace_chunk(&self, seed: u64, n_lines: u64, chunk: u64, tally: &mut LineTally);

    /// Whether this tracer casts lines of `method` (every tracer casts global and local
    /// lines; the flatland and 3D scene tracers also cast bundles of parallel lines).
    fn supports(&self, method: LineMethod) -> bool {
        method != LineMethod::Bundle
    }

    /// An empty tally for this scene.
    fn new_tally(&self, method: LineMethod) -> LineTally {
        LineTally::new(self.n_patches(), method)
    }

    /// Casts all `n_lines` lines on this thread.
    ///
    /// # Errors
    /// [`ErrorKind::NoLines`] if `n_lines == 0`; [`ErrorKind::UnsupportedMethod`] for a
    /// method this tracer does not [`LineTracer::supports`].
    fn run(&self, method: LineMethod, seed: u64, n_lines: u64) -> Result<LineTally> {
        if n_lines == 0 {
            return Err(ErrorKind::NoLines.into());
        }
        if !self.supports(method) {
            return Err(ErrorKind::UnsupportedMethod {
                method: method.description(),
                reason: UNSUPPORTED_BY_TRACER,
            }
            .into());
        }
        let mut tally = self.new_tally(method);
        for chunk in 0..chunk_count(n_lines) {
            self.trace_chunk(seed, n_lines, chunk, &mut tally);
        }
        Ok(tally)
    }
}

/// The tallies of some chunks of lines; merge them, then [`LineTally::finish`].
///
/// Only integers and 64.64 fixed-point sums: merging is exact and order-independent.
#[derive(Clone, Debug, PartialEq)]
pub struct LineTally {
    method: LineMethod,
    pub(crate) lines: u64,
    pub(crate) leaves: Vec<u64>,
    pub(crate) counts: PairCounts,
    pub(crate) patch_info: Vec<FixedSum>,
    pub(crate) continuous: ContinuousTally,
    /// What the tracer that made the tally also counts from the same samples (the radiosity
    /// terms of (5.20) when a [`crate::radiosity::continuous::RadiosityTracer`] made it).
    terms: Terms,
}

/// Something tallied alongside a line job's form factors from the same samples, which the
/// tally carries without knowing what it is (the radiosity terms of (5.20),
/// `crate::radiosity::continuous::RadiosityLineTally`, are one): told of every pair
/// sample and every closed line or group, merged exactly as the tally is.
pub(crate) trait SampleTerms: core::fmt::Debug + Send + Sync + Any {
    /// `weight` copies of the terms of a sample with continuous term `s` between patches
    /// `i` and `j` (2 for a global-line segment, which serves both ends; 1 for a local
    /// line).
    fn pair(&mut self, i: usize, j: usize, s: f64, weight: f64);
    /// Closes the current line (or group of correlated lines) of `samples` samples.
    fn end_line(&mut self, samples: u64);
    /// Adds the terms of another tally of the same job (an `other` of another type is
    /// ignored).
    fn merge(&mut self, other: &dyn SampleTerms);
    /// A copy, boxed.
    fn clone_box(&self) -> Box<dyn SampleTerms>;
    /// Whether `other` holds the same terms.
    fn same_as(&self, other: &dyn SampleTerms) -> bool;
    /// For the owner to get its type back (`downcast_ref`).
    fn as_any(&self) -> &dyn Any;
    /// For the owner to take its type back (`downcast`).
    fn into_any(self: Box<Self>) -> Box<dyn Any>;
}

/// The optional [`SampleTerms`] of a tally, with the value semantics of the tally's other
/// fields (clone, compare).
#[derive(Debug, Default)]
struct Terms(Option<Box<dyn SampleTerms>>);

impl Clone for Terms {
    fn clone(&self) -> Self {
        Self(self.0.as_ref().map(|t| t.clone_box()))
    }
}

impl PartialEq for Terms {
    fn eq(&self, other: &Self) -> bool {
        match (&self.0, &other.0) {
            (None, None) => true,
            (Some(a), Some(b)) => a.same_as(b.as_ref()),
            _ => false,
        }
    }
}

/// The result of a Monte Carlo run.
#[derive(Clone, Debug, PartialEq)]
pub struct LineEstimate {
    /// Estimated form factors (with a background state if the scene is open).
    pub form_factors: FormFactors,
    /// `I_S^c` (4.8, 4.13) and its standard error.
    pub continuous: ContinuousEstimate,
    /// Per-patch `I_i^c` (6.37); they sum to `I_S^c`.
    pub patch_continuous: Vec<f64>,
    /// Per-pair `I_ij^c` (6.35, 6.36), row-major `n × n`, kept for scenes of at most
    /// `crate::tally::DENSE_PAIR_LIMIT` patches.
    pub pair_continuous: Option<Vec<f64>>,
    /// Lines cast.
    pub lines: u64,
    /// The sampling method.
    pub method: LineMethod,
}

impl LineTally {
    /// The reason of [`ErrorKind::UnsupportedMethod`] for a method a tracer does not
    /// [`LineTracer::supports`].
    pub const UNSUPPORTED_BY_TRACER: &str = UNSUPPORTED_BY_TRACER;

    /// Largest patch count for which the counts `C_ij` are kept dense (`u32`, `n(n+1)/2 × 4`
    /// bytes ≤ 64 MiB per global-line tally, `n² × 4` ≤ 128 MiB for local lines): faster than
    /// sparse and, for scenes where most pairs see each other (a subdivided cube), smaller too.
    pub const DENSE_COUNT_LIMIT: usize = DENSE_COUNT_LIMIT;

    /// An empty tally over `n` patches.
    #[must_use]
    pub fn new(n: usize, method: LineMethod) -> Self {
        Self {
            method,
            lines: 0,
            leaves: vec![0; n],
            counts: PairCounts::new(n, method.is_global()),
            patch_info: vec![FixedSum::new(); n],
            continuous: ContinuousTally::new(),
            terms: Terms(None),
        }
    }

    /// Also accumulates `terms` from the same samples ([`SampleTerms`]).
    pub(crate) fn set_terms(&mut self, terms: Box<dyn SampleTerms>) {
        self.terms = Terms(Some(terms));
    }

    /// The terms accumulated alongside, if any.
    #[must_use]
    pub(crate) fn terms(&self) -> Option<&dyn SampleTerms> {
        self.terms.0.as_deref()
    }

    /// Takes the terms accumulated alongside out of the tally.
    pub(crate) fn take_terms(&mut self) -> Option<Box<dyn SampleTerms>> {
        self.terms.0.take()
    }

    /// The sampling method.
    #[must_use]
    pub fn method(&self) -> LineMethod {
        self.method
    }

    /// A sample leaves patch `i` from its front side (it counts in `N_i`).
    #[inline]
    pub(crate) fn leave(&mut self, i: usize) {
        if let Some(c) = self.leaves.get_mut(i) {
            *c += 1;
        }
    }

    /// `counts[i]` samples leave patch `i` from its front side, for every `i` ([`LineTally::leave`]
    /// `counts[i]` times).
    #[inline]
    pub(crate) fn leave_counts(&mut self, counts: &[u32]) {
        for (c, &n) in self.leaves.iter_mut().zip(counts) {
            *c += u64::from(n);
        }
    }

    /// A global-line segment between mutually facing patches `i` and `j` with continuous
    /// term `s` (if not degenerate): one sample for each end. Returns the line-sum
    /// contribution (`2s`).
    #[inline]
    pub(crate) fn global_pair(&mut self, i: usize, j: usize, s: Option<f64>) -> f64 {
        self.counts.add_pair(i, j);
        match s {
            Some(s) => {
                self.add_info(i, j, s);
                if let Some(r) = &mut self.terms.0 {
                    r.pair(i, j, s, 2.0);
                }
                2.0 * s
            }
            None => 0.0,
        }
    }

    /// `count` global-line segments between mutually facing patches `i` and `j` whose
    /// continuous terms add up to `info` (`None`: terms that were degenerate, which count
    /// as samples without information): the same counts as `count` calls of
    /// [`LineTally::global_pair`], and the same information up to rounding — the sum is
    /// quantised once ([`FixedSum::quantise`], error below `2⁻⁶⁴`) instead of each term.
    /// Returns the line-sum contribution (`2·info`). What a tracer calls once per pair and
    /// bundle of parallel lines (module [`super::pair_blocks`]), so the fixed-point work
    /// is per pair instead of per segment.
    ///
    /// For tallies without terms alongside only ([`LineTally::terms`] is `None`):
    /// those need every segment's term, and are left unchanged here.
    #[inline]
    pub(crate) fn add_pair_block(
        &mut self,
        i: usize,
        j: usize,
        count: u32,
        info: Option<f64>,
    ) -> f64 {
        debug_assert!(self.terms.0.is_none(), "pair blocks in a tally with terms");
        self.counts.add_pair_block(i, j, count);
        match info {
            Some(s) => {
                self.add_info(i, j, s);
                2.0 * s
            }
            None => 0.0,
        }
    }

    /// A local line from `i` that reached the front of `j`, with continuous term `s`.
    /// Returns the line-sum contribution (`s`).
    #[inline]
    pub(crate) fn local_pair(&mut self, i: usize, j: usize, s: Option<f64>) -> f64 {
        self.counts.add(i, j);
        match s {
            Some(s) => {
                self.add_info(i, j, 0.5 * s);
                if let Some(r) = &mut self.terms.0 {
                    r.pair(i, j, s, 1.0);
                }
                s
            }
            None => 0.0,
        }
    }

    /// Splits a term half to `I_ij^c`, half to `I_ji^c` (6.35): `w` to each.
    #[inline(always)]
    fn add_info(&mut self, i: usize, j: usize, w: f64) {
        // Quantised once for the four sums (the same bits as four separate additions).
        let Some(raw) = FixedSum::quantise(w) else {
            for k in [i, j] {
                if let Some(p) = self.patch_info.get_mut(k) {
                    p.add(w); // records the saturation
                }
            }
            return;
        };
        if let Some(p) = self.patch_info.get_mut(i) {
            p.add_quantised(raw);
        }
        if let Some(p) = self.patch_info.get_mut(j) {
            p.add_quantised(raw);
        }
        self.counts.add_info(i, j, raw);
    }

    /// Closes one line: `n` samples whose terms add up to `sum`.
    #[inline]
    pub(crate) fn end_line(&mut self, sum: f64, n: u64) {
        self.continuous.add_group(sum, n);
        if let Some(r) = &mut self.terms.0 {
            r.end_line(n);
        }
        self.lines += 1;
    }

    /// Closes a group of `lines` lines tallied together (a bundle of parallel lines,
    /// whose lines are correlated): `n` samples whose terms add up to `sum`, one
    /// observation of the standard error.
    #[inline]
    pub(crate) fn end_group(&mut self, sum: f64, n: u64, lines: u64) {
        self.continuous.add_group(sum, n);
        if let Some(r) = &mut self.terms.0 {
            r.end_line(n);
        }
        self.lines += lines;
    }

    /// Closes one line from its `(Σ terms, samples)`, or as a discarded degenerate line
    /// when `None` ([`LineTally::end_line`], [`LineTally::skip_line`]).
    #[inline]
    pub(crate) fn close_line(&mut self, terms: Option<(f64, u64)>) {
        match terms {
            Some((sum, n)) => self.end_line(sum, n),
            None => self.skip_line(),
        }
    }

    /// Closes one line that was discarded (a degenerate line of measure zero): counted as
    /// cast, contributes no sample.
    #[inline]
    pub(crate) fn skip_line(&mut self) {
        self.lines += 1;
    }

    /// Adds another tally of the same scene and method (exact, order-independent).
    pub fn merge(&mut self, other: &LineTally) {
        self.lines += other.lines;
        for (a, b) in self.leaves.iter_mut().zip(&other.leaves) {
            *a += *b;
        }
        self.counts.merge(&other.counts);
        for (a, b) in self.patch_info.iter_mut().zip(&other.patch_info) {
            a.merge(b);
        }
        self.continuous.merge(&other.continuous);
        if let (Some(a), Some(b)) = (&mut self.terms.0, &other.terms.0) {
            a.merge(b.as_ref());
        }
    }

    /// [`LineTally::merge`] of a tally that is no longer needed: the same result, with
    /// less memory for sparse counts (the other tally's pending keys are sorted in place
    /// instead of in a copy).
    pub fn merge_owned(&mut self, mut other: LineTally) {
        other.counts.flush_pending();
        self.merge(&other);
    }

    /// Lines tallied so far.
    #[must_use]
    pub fn lines(&self) -> u64 {
        self.lines
    }

    /// Memory of the pair counts `C_ij`: `(heap bytes, pairs with a count or
    /// information)`. Sparse counts (more than `crate::tally::DENSE_COUNT_LIMIT`
    /// patches) take 16 bytes per stored pair once merged, plus the pending buffer: 16 per
    /// non-zero pair for local lines, 8 for global lines (whose counts are symmetric and
    /// stored once per unordered pair).
    #[must_use]
    pub fn count_memory(&self) -> (usize, u64) {
        (self.counts.heap_bytes(), self.counts.nonzero_pairs())
    }

    /// `I_S^c` and its standard error so far. Unlike [`LineTally::finish`] this needs no
    /// sample on every patch: the continuous estimate is over the whole scene.
    #[must_use]
    pub fn continuous(&self) -> ContinuousEstimate {
        self.continuous.estimate()
    }

    /// Per-patch `I_i^c` (6.37) so far, like [`LineEstimate::patch_continuous`] but without
    /// [`LineTally::finish`]'s form factors, so patches without a sample are allowed (their
    /// value is 0). Used to tally `I^c` along surfaces on a fine grid of patches.
    #[must_use]
    pub fn patch_continuous(&self) -> Vec<f64> {
        let samples = self.continuous.samples().max(1) as f64;
        self.patch_info
            .iter()
            .map(|s| s.value() / samples)
            .collect()
    }

    /// Whether a sum of `I^c` terms (the scene's, or a patch's `I_i^c`) left its
    /// fixed-point range or dropped a non-finite term: `I_S^c`, its standard error or an
    /// `I_i^c` then misses something, and [`crate::Warning::SumsOutOfRange`] says so.
    #[must_use]
    pub fn sums_out_of_range(&self) -> bool {
        self.continuous.saturated() || self.patch_info.iter().any(FixedSum::saturated)
    }

    /// Turns the tallies into form factors and continuous measures.
    ///
    /// # Errors
    /// [`ErrorKind::NoLines`] for an empty tally; [`ErrorKind::UnsampledPatch`] when some patch
    /// got no sample (its row of `F` would be unknown).
    pub fn finish<T: LineTracer + ?Sized>(self, tracer: &T) -> Result<LineEstimate> {
        self.finish_with_sizes(tracer.patch_sizes())
    }

    /// [`LineTally::finish`] given the patch sizes (lengths or areas) instead of the tracer:
    /// what merging partial results from files needs.
    ///
    /// # Errors
    /// Those of [`LineTally::finish`], and [`ErrorKind::DimensionMismatch`] when `sizes`
    /// does not have one entry per patch.
    pub fn finish_with_sizes(mut self, sizes: &[f64]) -> Result<LineEstimate> {
        if sizes.len() != self.leaves.len() {
            return Err(ErrorKind::DimensionMismatch {
                expected: self.leaves.len(),
                found: sizes.len(),
            }
            .into());
        }
        if self.lines == 0 {
            return Err(ErrorKind::NoLines.into());
        }
        if let Some(patch) = self.leaves.iter().position(|&c| c == 0) {
            return Err(ErrorKind::UnsampledPatch {
                patch,
                lines: self.lines,
            }
            .into());
        }
        let n = self.leaves.len();
        let samples = self.continuous.samples().max(1) as f64;
        let mut pair = self.counts.has_pair_info().then(|| vec![0.0; n * n]);
        let leaves = &self.leaves;
        // The counts are taken out and dropped before the matrix is finished: for sparse
        // counts they are a large part of the peak memory. Sparse counts are read in
        // row-major order straight into CSR with room for exactly their pairs, so each
        // form factor is held once (10⁸ lines on the 99,846-patch cube: 117 M pairs, a
        // peak of 7.1 GB through triplets and their sorted copy).
        let mut counts = core::mem::replace(
            &mut self.counts,
            PairCounts::new(0, self.method.is_global()),
        );
        counts.apply_held();
        if let Some(form_factors) = sparse_from_triangle(&mut counts, leaves, sizes)? {
            drop(counts);
            return Ok(self.estimate_with(form_factors, pair));
        }
        // Stored sparse unless CSR would take more memory ([`stored_dense`]): every later pass (the background's row sums, the
        // channel's checks and measures) then visits the non-zero entries only, and gives
        // the same bits as over the dense matrix, whose zeros those passes skip (and a
        // compensated sum of the row adds exactly: `KahanSum::add(0.0)` changes nothing).
        let pairs = usize::try_from(counts.nonzero_counts()).unwrap_or(usize::MAX);
        let mut matrix = if counts.is_dense() && stored_dense(pairs, n) {
            Matrix::Dense(vec![0.0; n * n])
        } else {
            Matrix::Sparse(CsrMatrixBuf::row_major(n, pairs.min(n.saturating_mul(n)))?)
        };
        let mut misordered = None;
        counts.for_each(|i, j, c, info| {
            let f = c as f64 / leaves[i] as f64;
            match &mut matrix {
                Matrix::Dense(m) => m[i * n + j] = f,
                Matrix::Sparse(rows) => {
                    if let Err(err) = rows.push(i, j, f) {
                        misordered.get_or_insert(err);
                    }
                }
            }
            if let (Some(p), Some(v)) = (&mut pair, info) {
                p[i * n + j] = v / samples;
            }
        });
        drop(counts);
        if let Some(err) = misordered {
            return Err(err);
        }
        let form_factors = match matrix {
            Matrix::Dense(m) => FormFactors::from_patch_matrix(sizes, m)?,
            Matrix::Sparse(rows) => FormFactors::from_patch_csr(sizes, rows.finish())?,
        };
        Ok(self.estimate_with(form_factors, pair))
    }

    /// The estimate of finished form factors, with the tally's `I_S^c`, per-patch `I_i^c`
    /// and the given per-pair `I_ij^c`.
    fn estimate_with(
        &self,
        form_factors: FormFactors,
        pair_continuous: Option<Vec<f64>>,
    ) -> LineEstimate {
        LineEstimate {
            form_factors,
            continuous: self.continuous.estimate(),
            patch_continuous: self.patch_continuous(),
            pair_continuous,
            lines: self.lines,
            method: self.method,
        }
    }
}

/// The sparse form factors `F_ij = C_ij / N_i` of dense symmetric counts that hold
/// nothing else (every scene over [`DENSE_PAIR_LIMIT`] patches, unless a count passed
/// `2³²`), built straight from the packed triangle: one sequential pass finds the row
/// lengths (and keeps the non-zero counts while they are few), then each non-zero `s_ab`
/// is put into rows `b` and `a` (both in increasing column order, see
/// `counts::Triangle::for_each_nonzero`) from the kept list, or from a second pass. The same entries, values and
/// order as the row-major walk of [`PairCounts::for_each`] into [`RowMajorCsr`], without
/// gathering the triangle's columns. `None` when the counts are not such a triangle or fill
/// so much of the matrix that it is [`stored_dense`] (then the caller's dense route).
fn sparse_from_triangle(
    counts: &mut PairCounts,
    leaves: &[u64],
    sizes: &[f64],
) -> Result<Option<FormFactors>> {
    let n = leaves.len();
    // The non-zero counts are kept from the first pass (8 bytes each) while they take
    // less memory than the counts (4 bytes a pair): the counts are then freed before the
    // matrix is allocated and never read again. The peak is the list and the matrix,
    // below the counts and the matrix: 10⁷ lines on the 5400-patch cube put 4.1 M counts
    // in the 14.6 M pairs, a list of 33 MB where the counts take 58 MB
    let cap = n * (n + 1) / 2 / 2;
    let Some((lengths, entries)) = counts.triangle().map(|t| t.row_lengths(cap)) else {
        return Ok(None);
    };
    let pairs: usize = lengths.iter().sum();
    if stored_dense(pairs, n) {
        return Ok(None);
    }
    if entries.is_some() {
        // Not read again: freed before the matrix is allocated (58 MB for the cube), so
        // the peak is below that of the counts and the matrix together
        *counts = PairCounts::new(0, true);
    }
    let mut rows = CsrMatrixBuf::by_row_lengths(n, &lengths)?;
    drop(lengths);
    let leaf = |i: usize| leaves.get(i).copied().unwrap_or(0) as f64;
    let mut misordered = None;
    let mut push = |i: usize, j: usize, f: f64| {
        if let Err(err) = rows.push(i, j, f) {
            misordered.get_or_insert(err);
        }
    };
    match (entries, counts.triangle()) {
        (Some(list), _) => scatter_by_row_blocks(&list, n, leaves, SCATTER_ROWS, &mut push),
        (None, Some(triangle)) => triangle.for_each_nonzero(|b, a, s| {
            let s = u64::from(s);
            if a == b {
                push(b, b, (s << 1) as f64 / leaf(b));
            } else {
                push(b, a, s as f64 / leaf(b));
                push(a, b, s as f64 / leaf(a));
            }
        }),
        // (The counts were a triangle above; were they not, `finish` finds rows short)
        (None, None) => {}
    }
    if let Some(err) = misordered {
        return Err(err);
    }
    Ok(Some(FormFactors::from_patch_csr(sizes, rows.finish()?)?))
}

/// Rows of the form factors [`scatter_by_row_blocks`] fills at a time in
/// [`sparse_from_triangle`]: their write
/// positions (a line of columns and one of values each, 64 KiB) stay in the second-level
/// cache.
const SCATTER_ROWS: usize = 512;

/// Calls `push(i, j, F_ij)` for every non-zero `F_ij = C_ij / N_i` of the symmetric counts
/// whose non-zero `s_ab` are `list` (`(b, a, s_ab)`, `a ≤ b`, in memory order: `b`
/// increasing, then `a`), each row's entries in increasing column order — the same
/// entries, values and per-row order as putting each `s_ab` into rows `b` and `a` in list
/// order — but a block of `block_rows` rows after another ([`SCATTER_ROWS`]), so that the
/// pushes go to a few rows at a time instead of to every row of the matrix (a cache miss
/// each).
///
/// Row `i` is `(i, a ≤ i)` from list row `b = i`, then `(i, b > i)` from the later list
/// rows, where the entries with `a` in a block are a run found by bisection:
///
/// ```text
/// F_ba = s_ab / N_b,  F_ab = s_ab / N_a  (a < b),   F_bb = 2 s_bb / N_b
/// ```
fn scatter_by_row_blocks(
    list: &[TriangleEntry],
    n: usize,
    leaves: &[u64],
    block_rows: usize,
    push: &mut impl FnMut(usize, usize, f64),
) {
    let block_rows = block_rows.max(1);
    let leaf = |i: usize| leaves.get(i).copied().unwrap_or(0) as f64;
    // Where each list row `b` starts (the list is sorted by `b`)
    let mut starts = vec![0usize; n + 1];
    for &(b, _, _) in list {
        if let Some(c) = starts.get_mut(usize::from(b) + 1) {
            *c += 1;
        }
    }
    let mut total = 0;
    for c in &mut starts {
        total += *c;
        *c = total;
    }
    let list_row = |b: usize| {
        let (Some(&start), Some(&end)) = (starts.get(b), starts.get(b + 1)) else {
            return &[][..];
        };
        list.get(start..end).unwrap_or(&[])
    };
    let mut block_start = 0;
    while block_start < n {
        let block = block_start..n.min(block_start.saturating_add(block_rows));
        // The block's own list rows: all their entries into row b, those of the block's
        // columns into rows a too (each after its own list row, which came earlier)
        for b in block.clone() {
            for &(_, a, s) in list_row(b) {
                let (a, s) = (usize::from(a), u64::from(s));
                if a == b {
                    push(b, b, (s << 1) as f64 / leaf(b));
                } else {
                    push(b, a, s as f64 / leaf(b));
                    if a >= block.start {
                        push(a, b, s as f64 / leaf(a));
                    }
                }
            }
        }
        // The later list rows: their run of the block's columns into rows a
        for b in block.end..n {
            let row = list_row(b);
            let first = row.partition_point(|&(_, a, _)| usize::from(a) < block.start);
            let rest = row.get(first..).unwrap_or(&[]);
            for &(_, a, s) in rest {
                let a = usize::from(a);
                if a >= block.end {
                    break;
                }
                push(a, b, u64::from(s) as f64 / leaf(a));
            }
        }
        block_start = block.end;
    }
}

/// Whether [`LineTally::finish_with_sizes`] stores `pairs` non-zero form factors of `n`
/// patches dense: when CSR (12 bytes an entry, a `u32` column and an `f64`) would take
/// more than the dense matrix (8 bytes a pair), above two thirds of the `n²` pairs.
///
/// The threshold was a third while the channel's reciprocity check bisected a CSR row for
/// every entry; with its cursors the sparse passes cost `O(nnz)`. 3·10⁷ lines on the
/// 5400-patch cube (half the pairs non-zero) now keep CSR instead of the 233 MB dense
/// matrix: a peak of 239 MB against 279 MB, the same bits.
fn stored_dense(pairs: usize, n: usize) -> bool {
    pairs.saturating_mul(3) > n.saturating_mul(n).saturating_mul(2)
}

/// The form factors [`LineTally::finish_with_sizes`] fills from the counts.
enum Matrix {
    Dense(Vec<f64>),
    Sparse(RowMajorCsr),
}

/// One intersection of a global line with a patch, as [`global_line_terms`] sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Crossing {
    /// Parameter along the line.
    pub t: f64,
    /// The patch met.
    pub patch: u32,
    /// The surface (flatland) or face (3D) the patch belongs to.
    pub surface: u32,
    /// `dir · n`: positive when the patch's front faces along the line.
    pub cos: f64,
}

/// Tallies one global line from its crossings, sorted by `t` (2.37, 4.8, 4.13), except
/// for closing the line: returns the line's `(Σ terms, samples)`, or `None` for a
/// degenerate line, which adds nothing (the caller counts it as cast).
///
/// First the crossings are normalised: a line through the common end or edge of two
/// patches of one surface counts once; at one point, a surface facing backwards comes
/// before one facing forwards (a two-sided wall, or a grazed corner of an object); two
/// surfaces met at one point facing the same way make the line degenerate (it passes
/// exactly through a corner — a set of measure zero). Then every crossing is a sample
/// leaving its front side, and consecutive mutually facing crossings `i`, `j` give `C_ij`,
/// `C_ji` and two continuous terms `sample(cos θ_i, cos θ_j, r)`.
pub(crate) fn global_line_terms(
    crossings: &mut Vec<Crossing>,
    eps: f64,
    tally: &mut LineTally,
    sample: impl Fn(f64, f64, f64) -> Option<f64>,
) -> Option<(f64, u64)> {
    crossings.dedup_by(|b, a| b.surface == a.surface && b.t - a.t <= eps);
    for k in 1..crossings.len() {
        if crossings[k].t - crossings[k - 1].t <= eps {
            match (crossings[k - 1].cos > 0.0, crossings[k].cos > 0.0) {
                (true, false) => crossings.swap(k - 1, k),
                (false, true) => {}
                _ => return None,
            }
        }
    }
    Some(normalised_crossing_terms(
        crossings.iter().copied(),
        tally,
        sample,
    ))
}

/// The counting part of [`global_line_terms`], for crossings already normalised: each is
/// a sample leaving its patch; a crossing facing along the line followed by one facing
/// back is a segment between them. Returns the line's `(Σ terms, samples)`.
#[inline]
fn normalised_crossing_terms(
    crossings: impl Iterator<Item = Crossing>,
    tally: &mut LineTally,
    sample: impl Fn(f64, f64, f64) -> Option<f64>,
) -> (f64, u64) {
    let mut line_sum = 0.0;
    let mut n = 0u64;
    let mut previous: Option<Crossing> = None;
    for c in crossings {
        tally.leave(c.patch as usize);
        n += 1;
        // A segment from the front of the previous surface to the back of this one
        if let Some(p) = previous
            && p.cos > 0.0
            && c.cos < 0.0
        {
            let s = sample(p.cos, -c.cos, c.t - p.t);
            line_sum += tally.global_pair(p.patch as usize, c.patch as usize, s);
        }
        previous = Some(c);
    }
    (line_sum, n)
}

/// The terms of one global line from the hits of a line query, sorted by `t` (2.37, 4.8,
/// 4.13), for either tracer: each hit becomes a [`Crossing`] with its patch's surface
/// (`surface[prim]`) and `cos(prim)` = `dir · n_prim`, then [`global_line_terms`] counts
/// them, `sample(cos θ_i, cos θ_j, r)` giving each segment's continuous term. Returns the
/// line's `(Σ terms, samples)`, or `None` for a degenerate line; the caller closes the
/// line ([`LineTally::close_line`]) or its group.
#[inline]
pub(crate) fn global_hit_terms<H: HitKey>(
    hits: &[H],
    surface: &[u32],
    cos: impl Fn(usize) -> f64,
    eps: f64,
    crossings: &mut Vec<Crossing>,
    tally: &mut LineTally,
    sample: impl Fn(f64, f64, f64) -> Option<f64>,
) -> Option<(f64, u64)> {
    let crossing = |h: &H| {
        let p = h.prim() as usize;
        Crossing {
            t: h.t(),
            patch: h.prim(),
            surface: surface.get(p).copied().unwrap_or(u32::MAX),
            cos: cos(p),
        }
    };
    // No two hits within `eps` (nearly every line): nothing to normalise, so the hits are
    // counted as they are, without the crossing list (the same counts, bit for bit)
    if hits.windows(2).all(|w| !(w[1].t() - w[0].t() <= eps)) {
        return Some(normalised_crossing_terms(
            hits.iter().map(crossing),
            tally,
            sample,
        ));
    }
    crossings.clear();
    crossings.extend(hits.iter().map(crossing));
    global_line_terms(crossings, eps, tally, sample)
}

/// The line loop of [`LineTracer::trace_chunk`], for either tracer: the lines of chunk
/// `chunk` of an `n_lines` job, drawn from [`chunk_rng`]`(seed, chunk)`, each cast by
/// `global` or `local` (the tally's method) with the generator and scratch buffers reused
/// across the chunk (no allocation per line).
#[inline]
pub(crate) fn trace_chunk_lines<H>(
    seed: u64,
    n_lines: u64,
    chunk: u64,
    tally: &mut LineTally,
    mut global: impl FnMut(&mut rand_pcg::Pcg64, &mut Vec<H>, &mut Vec<Crossing>, &mut LineTally),
    mut local: impl FnMut(&mut rand_pcg::Pcg64, &mut Vec<H>, &mut LineTally),
) {
    let mut rng = chunk_rng(seed, chunk);
    let mut hits = Vec::new();
    let mut crossings = Vec::new();
    match tally.method() {
        LineMethod::Global => {
            for _ in chunk_range(n_lines, chunk) {
                global(&mut rng, &mut hits, &mut crossings, tally);
            }
        }
        LineMethod::Local => {
            for _ in chunk_range(n_lines, chunk) {
                local(&mut rng, &mut hits, tally);
            }
        }
        // Cast by the tracers that support bundles before this loop; nothing otherwise
        // (see `LineTracer::supports`).
        LineMethod::Bundle => {}
    }
    // Counts are observed only between chunks: apply the increments held back
    tally.counts.settle();
}

/// Test support shared by the flatland and 3D tracers' tests.
#[cfg(test)]
pub(crate) mod test_support {
    use super::{LineMethod, LineTally, LineTracer};

    /// The chunks of a job tallied separately and merged in reverse order.
    pub(crate) fn merged_in_reverse<T: LineTracer + ?Sized>(
        tracer: &T,
        method: LineMethod,
        seed: u64,
        n: u64,
    ) -> LineTally {
        let mut merged = tracer.new_tally(method);
        for chunk in (0..crate::lines::chunk_count(n)).rev() {
            let mut t = tracer.new_tally(method);
            tracer.trace_chunk(seed, n, chunk, &mut t);
            merged.merge(&t);
        }
        merged
    }

    /// `lines` cast one by one, each tallied into `tally` by `terms` as a lone global line
    /// (`Some((Σ terms, samples))`, or `None` for a degenerate line), all closed as one
    /// group of `group_lines` lines; the counts settled. Returns the tally and the group's
    /// `(Σ terms, samples)`: what a bundle's tally is compared against.
    pub(crate) fn lone_lines_as_one_group<L>(
        mut tally: LineTally,
        lines: impl IntoIterator<Item = L>,
        group_lines: u64,
        mut terms: impl FnMut(L, &mut LineTally) -> Option<(f64, u64)>,
    ) -> (LineTally, (f64, u64)) {
        let (mut sum, mut n) = (0.0, 0);
        for line in lines {
            if let Some((s, c)) = terms(line, &mut tally) {
                sum += s;
                n += c;
            }
        }
        tally.end_group(sum, n, group_lines);
        tally.counts.settle();
        (tally, (sum, n))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tally::counts::PairCounts;

    /// The row-major route of `finish_with_sizes`: counts walked in row-major order into
    /// a `RowMajorCsr`.
    fn by_rows(counts: &mut PairCounts, leaves: &[u64], sizes: &[f64]) -> Result<FormFactors> {
        let n = leaves.len();
        let mut rows = CsrMatrixBuf::row_major(n, 0)?;
        counts.for_each(|i, j, c, _| {
            rows.push(i, j, c as f64 / leaves[i] as f64).unwrap();
        });
        FormFactors::from_patch_csr(sizes, rows.finish())
    }

    proptest::proptest! {
        /// The triangle's entries scattered a block of rows at a time are those put into
        /// rows `b` and `a` in list order, row by row, for any block size.
        #[test]
        fn scatter_by_blocks_is_the_list_order(
            n in 1usize..30,
            cells in proptest::collection::vec((0usize..30, 0usize..30, 1u32..5000), 0..80),
            block_rows in 1usize..12,
        ) {
            let mut packed = alloc::collections::BTreeMap::new();
            for &(i, j, c) in &cells {
                let (a, b) = ((i % n).min(j % n), (i % n).max(j % n));
                packed.insert((b as u16, a as u16), c);
            }
            let list: Vec<TriangleEntry> = packed.iter().map(|(&(b, a), &s)| (b, a, s)).collect();
            let leaves: Vec<u64> = (0..n as u64).map(|i| 7 + i).collect();
            let mut rows_by_list: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
            for &(b, a, s) in &list {
                let (b, a, s) = (usize::from(b), usize::from(a), u64::from(s));
                if a == b {
                    rows_by_list[b].push((b, (s << 1) as f64 / leaves[b] as f64));
                } else {
                    rows_by_list[b].push((a, s as f64 / leaves[b] as f64));
                    rows_by_list[a].push((b, s as f64 / leaves[a] as f64));
                }
            }
            let mut rows_by_blocks: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
            scatter_by_row_blocks(&list, n, &leaves, block_rows, &mut |i, j, f| {
                rows_by_blocks[i].push((j, f));
            });
            proptest::prop_assert_eq!(rows_by_blocks, rows_by_list);
        }

        /// Sparse form factors straight from the packed triangle are those of the
        /// row-major walk, bit for bit (random sparse triangles, some rows empty but every
        /// patch sampled, open and closed scenes).
        #[test]
        fn triangle_route_is_the_row_major_route(
            n in 1usize..40,
            cells in proptest::collection::vec((0usize..40, 0usize..40, 1u32..5000), 0..60),
            extra in proptest::collection::vec(0u64..1000, 40),
            sizes in proptest::collection::vec(0.01f64..1.0, 40),
        ) {
            let mut packed = vec![0u32; n * (n + 1) / 2];
            for &(i, j, c) in &cells {
                let (a, b) = (i.min(j) % n, i.max(j) % n);
                let (a, b) = (a.min(b), a.max(b));
                packed[b * (b + 1) / 2 + a] = c;
            }
            let mut counts = PairCounts::Dense {
                n,
                symmetric: true,
                counts: packed,
                carries: alloc::collections::BTreeMap::new(),
                info: None,
                pending: counts::Pending::new(),
            };
            // Leaves: each row's samples plus some that left the scene (open scenes)
            let mut leaves = vec![0u64; n];
            counts.for_each(|i, _, c, _| leaves[i] += c);
            for (l, &e) in leaves.iter_mut().zip(&extra) {
                *l += e.max(u64::from(*l == 0));
            }
            let sizes = &sizes[..n];
            let triangle = sparse_from_triangle(&mut counts.clone(), &leaves, sizes);
            let rows = by_rows(&mut counts, &leaves, sizes);
            match (triangle, rows) {
                (Ok(Some(a)), Ok(b)) => proptest::prop_assert_eq!(a, b),
                (Ok(None), _) => {
                    // Too full for sparse: the caller's dense route
                    let pairs = counts.nonzero_counts() as usize;
                    proptest::prop_assert!(stored_dense(pairs, leaves.len()));
                }
                (Err(a), Err(b)) => proptest::prop_assert_eq!(a, b),
                (a, b) => proptest::prop_assert!(false, "{a:?} against {b:?}"),
            }
        }
    }
}
