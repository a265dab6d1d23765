//! Integer tallies of line samples between patch pairs, dense or sparse.
//!
//! # Symmetric counts
//!
//! A global-line segment between mutually facing patches `i` and `j` is one sample for
//! each end (2.37): it adds one to `C_ij` *and* to `C_ji`, so the counts of a global-line
//! tally are symmetric. They are stored once per unordered pair — `s_ij` segments, with
//! `C_ij = C_ji = s_ij` and `C_ii = 2 s_ii` — which halves both the memory and the random
//! accesses per segment. Local lines count one direction only and keep the full matrix.
//! The per-pair information `I_ij^c` is split half to `(i, j)`, half to `(j, i)` (6.35)
//! for either method, so it is always stored once per unordered pair. The layout is
//! private: every reader sees the ordered pairs `(i, j)` in row-major order, exactly as
//! a full matrix would give them.

use alloc::collections::BTreeMap;
use alloc::vec;
use alloc::vec::Vec;

/// Largest patch count for which the per-pair continuous information `I_ij^c` is kept
/// (dense 64.64 fixed-point sums, one per unordered pair: 1024·1025/2 × 16 bytes = 8 MiB
/// per tally).
pub(crate) const DENSE_PAIR_LIMIT: usize = 1024;

/// Largest patch count for which the counts `C_ij` are kept dense (`u32`, `n(n+1)/2 × 4`
/// bytes ≤ 64 MiB per global-line tally, `n² × 4` ≤ 128 MiB for local lines): faster than
/// sparse and, for scenes where most pairs see each other (a subdivided cube), smaller too.
pub(crate) const DENSE_COUNT_LIMIT: usize = 5792;

/// Tallies `C_ij` of samples leaving patch `i` that reached patch `j`.
///
/// Dense for `n ≤` [`DENSE_COUNT_LIMIT`]: `u32` counts, with the wraps past `2³²` kept
/// aside (`C = carries·2³² + low`, so no count ever saturates), plus, for `n ≤`
/// [`DENSE_PAIR_LIMIT`], the per-pair sum of continuous-information terms (raw 64.64 fixed
/// point). Sparse beyond: pair keys `(i << 32) | j` are buffered and periodically sorted
/// and merged into a sorted `(key, count)` list — 16 bytes per stored pair, that is 8
/// bytes per non-zero `C_ij` for global lines (see the module docs). Counting is exact
/// integer arithmetic, so merging tallies gives the same result in any order.
// The dense variant carries its `Pending` buffers inline (about 700 bytes): one
// `PairCounts` per tally, never in arrays, and boxing them would put a pointer load in
// front of every held increment
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum PairCounts {
    Dense {
        n: usize,
        /// One count per unordered pair (global lines), else per ordered pair.
        symmetric: bool,
        counts: Vec<u32>,
        /// Index → number of wraps of `counts[index]` past `2³²`.
        carries: BTreeMap<usize, u64>,
        /// One sum per unordered pair, at [`tri`].
        info: Option<Vec<i128>>,
        /// Increments not yet applied to `counts` (see [`Pending`]).
        pending: Pending,
    },
    Sparse {
        n: usize,
        /// Keys `(min << 32) | max` per unordered pair (global lines), else per ordered
        /// pair.
        symmetric: bool,
        buffer: Vec<u64>,
        merged: Vec<(u64, u64)>,
    },
}

/// Number of count increments [`Pending`] holds before applying them.
const PENDING: usize = 32;

/// Dense count increments, and per-pair information terms, held back and applied
/// together, `PENDING` at a time.
///
/// The counts of a large scene (58 MB for 5400 patches) are far larger than the caches,
/// so each increment is a cache (and TLB) miss. Applied one per segment, between the line
/// queries, each miss stalls the core for its whole latency: the queries' work behind it
/// fills the reorder window. Applied in a tight loop of independent read-modify-writes,
/// the misses overlap. Integer additions commute, so the counts are exactly those of
/// applying each increment at once. The per-pair information (64.64 sums of 16 bytes,
/// 5.2 MB for the 810-patch Cornell box, more than the 2 MB second-level cache) is held
/// alike: each held term is added to its sum in the order the terms came, so every sum
/// sees the same sequence of saturating additions as when each was applied at once (the
/// same bits even where a sum saturates). The buffer is empty whenever a tally is
/// observed: [`PairCounts::settle`] ends every chunk of lines, and every reader applies
/// what is pending first (or reads a settled copy).
#[derive(Clone, Debug)]
pub(crate) struct Pending {
    index: [u32; PENDING],
    len: usize,
    /// Information terms held: `info_raw[k]` to be added to `info[info_index[k]]`.
    info_index: [u32; PENDING],
    info_raw: [i128; PENDING],
    info_len: usize,
}

impl Pending {
    pub(crate) const fn new() -> Self {
        Self {
            index: [0; PENDING],
            len: 0,
            info_index: [0; PENDING],
            info_raw: [0; PENDING],
            info_len: 0,
        }
    }

    /// Whether nothing is held.
    #[inline]
    fn is_empty(&self) -> bool {
        self.len == 0 && self.info_len == 0
    }

    /// The increments held, as indices into the counts.
    fn held(&self) -> &[u32] {
        self.index.get(..self.len).unwrap_or(&[])
    }

    /// The information terms held, as indices into the sums and raw terms.
    fn held_info(&self) -> impl Iterator<Item = (u32, i128)> + '_ {
        let n = self.info_len.min(PENDING);
        self.info_index[..n]
            .iter()
            .copied()
            .zip(self.info_raw[..n].iter().copied())
    }

    /// Holds an increment of `counts[k]`, applying all of them once `PENDING` are held.
    #[inline(always)]
    fn hold(&mut self, counts: &mut [u32], carries: &mut BTreeMap<usize, u64>, k: usize) {
        // Dense indices are below DENSE_COUNT_LIMIT², which fits a u32.
        if let Some(slot) = self.index.get_mut(self.len) {
            *slot = k as u32;
            self.len += 1;
        }
        if self.len == PENDING {
            self.apply_counts(counts, carries);
        }
    }

    /// Holds the addition of `raw` to `info[k]`, applying all held terms once `PENDING`
    /// are held.
    #[inline(always)]
    fn hold_info(&mut self, info: &mut [i128], k: usize, raw: i128) {
        // Pair indices are below DENSE_PAIR_LIMIT², which fits a u32.
        if let (Some(slot), Some(term)) = (
            self.info_index.get_mut(self.info_len),
            self.info_raw.get_mut(self.info_len),
        ) {
            *slot = k as u32;
            *term = raw;
            self.info_len += 1;
        }
        if self.info_len == PENDING {
            self.apply_info(info);
        }
    }

    /// Applies the increments and terms held (tight loops: their cache misses overlap).
    #[inline]
    fn apply(
        &mut self,
        counts: &mut [u32],
        carries: &mut BTreeMap<usize, u64>,
        info: Option<&mut Vec<i128>>,
    ) {
        self.apply_counts(counts, carries);
        match info {
            Some(info) => self.apply_info(info),
            None => self.info_len = 0,
        }
    }

    /// Applies the count increments held.
    #[inline]
    fn apply_counts(&mut self, counts: &mut [u32], carries: &mut BTreeMap<usize, u64>) {
        for &k in self.held() {
            bump(counts, carries, k as usize);
        }
        self.len = 0;
    }

    /// Applies the information terms held, in the order they came.
    #[inline]
    fn apply_info(&mut self, info: &mut [i128]) {
        for (k, raw) in self.held_info() {
            if let Some(v) = info.get_mut(k as usize) {
                *v = v.saturating_add(raw);
            }
        }
        self.info_len = 0;
    }
}

/// Equal when the same increments and terms are held (in the same order).
impl PartialEq for Pending {
    fn eq(&self, other: &Self) -> bool {
        self.held() == other.held() && self.held_info().eq(other.held_info())
    }
}

/// Raw fixed-point scale of [`crate::math::FixedSum`] (2⁶⁴), for the per-pair sums.
const SCALE: f64 = 18_446_744_073_709_551_616.0;

/// Buffered sparse keys are flushed once there are this many, or half as many as merged
/// pairs, whichever is more (amortised `O(1)` merging work per key, and the buffer stays
/// a fraction of the list).
const MIN_FLUSH: usize = 1 << 20;

/// Index of the unordered pair `{i, j}` in a packed lower triangle: `b(b+1)/2 + a` with
/// `a = min(i, j)`, `b = max(i, j)`.
#[inline(always)]
fn tri(i: usize, j: usize) -> usize {
    let (a, b) = if i <= j { (i, j) } else { (j, i) };
    b * (b + 1) / 2 + a
}

/// Rows of the packed triangle gathered at once by [`for_each_dense_symmetric`].
const GATHER_ROWS: usize = 16;

/// [`PairCounts::for_each_raw`] of dense symmetric counts: `f(i, j, C_ij, raw I_ij^c)` in
/// row-major order for every ordered pair with a count or information, `C_ii` doubled.
///
/// Row `i` of the full matrix is `(i, j ≤ i)`, a contiguous run of the packed triangle,
/// then `(i, j > i)`, a column of it (one cache line per entry). The columns of
/// [`GATHER_ROWS`] rows are gathered together, walking the triangle's rows in memory
/// order, into a buffer of `GATHER_ROWS × n` entries (350 KB for 5400 patches), read
/// back row by row: the same values in the same order as a walk of the full matrix,
/// with sequential reads instead of one miss per upper entry.
fn for_each_dense_symmetric(
    n: usize,
    counts: &[u32],
    carries: &BTreeMap<usize, u64>,
    info: Option<&[i128]>,
    mut f: impl FnMut(usize, usize, u64, i128),
) {
    let count_at = |k: usize| {
        let low = u64::from(counts.get(k).copied().unwrap_or(0));
        if carries.is_empty() {
            low
        } else {
            low + (carries.get(&k).copied().unwrap_or(0) << 32)
        }
    };
    let info_at = |k: usize| info.and_then(|v| v.get(k)).copied().unwrap_or(0);
    if carries.is_empty() && info.is_none() {
        return for_each_dense_counts(n, counts, f);
    }
    let rows = GATHER_ROWS.min(n);
    let mut upper_counts = vec![0u64; rows * n];
    let mut upper_info = vec![0i128; if info.is_some() { rows * n } else { 0 }];
    for i0 in (0..n).step_by(GATHER_ROWS) {
        let i1 = (i0 + GATHER_ROWS).min(n);
        // (i, j) for i0 ≤ i < min(i1, j): row j of the triangle, entries i0.., in order
        for j in i0 + 1..n {
            let base = j * (j + 1) / 2;
            for i in i0..i1.min(j) {
                let at = (i - i0) * n + j;
                if let Some(c) = upper_counts.get_mut(at) {
                    *c = count_at(base + i);
                }
                if let Some(v) = upper_info.get_mut(at) {
                    *v = info_at(base + i);
                }
            }
        }
        for i in i0..i1 {
            let base = i * (i + 1) / 2;
            for j in 0..=i {
                let c = count_at(base + j) << u32::from(i == j);
                let v = info_at(base + j);
                if c > 0 || v != 0 {
                    f(i, j, c, v);
                }
            }
            let row = (i - i0) * n;
            for j in i + 1..n {
                let c = upper_counts.get(row + j).copied().unwrap_or(0);
                let v = upper_info.get(row + j).copied().unwrap_or(0);
                if c > 0 || v != 0 {
                    f(i, j, c, v);
                }
            }
        }
    }
}

/// [`for_each_dense_symmetric`] of counts without carries or information (the common
/// case: every count below `2³²`, more than [`DENSE_PAIR_LIMIT`] patches), on slices.
///
/// Most counts of a short job are zero (10⁵ lines fill 1.5 % of the 5400-patch cube's
/// pairs), so runs of zeros are skipped a block at a time ([`for_each_nonzero`]): a
/// triangle run that is all zero is not gathered (the columns gathered are cleared after
/// their block), a block of a row that is all zero is not visited entry by entry.
fn for_each_dense_counts(n: usize, counts: &[u32], mut f: impl FnMut(usize, usize, u64, i128)) {
    let rows = GATHER_ROWS.min(n);
    let mut upper = vec![0u32; rows * n];
    // The columns gathered in the current block, cleared again after it
    let mut gathered: Vec<usize> = Vec::new();
    for i0 in (0..n).step_by(GATHER_ROWS) {
        let i1 = (i0 + GATHER_ROWS).min(n);
        for &j in &gathered {
            for r in 0..rows {
                if let Some(u) = upper.get_mut(r * n + j) {
                    *u = 0;
                }
            }
        }
        gathered.clear();
        for j in i0 + 1..n {
            let base = j * (j + 1) / 2;
            let run = counts.get(base + i0..base + i1.min(j)).unwrap_or(&[]);
            if run.iter().fold(0, |a, &c| a | c) == 0 {
                continue;
            }
            gathered.push(j);
            for (r, &c) in run.iter().enumerate() {
                if let Some(u) = upper.get_mut(r * n + j) {
                    *u = c;
                }
            }
        }
        for i in i0..i1 {
            let base = i * (i + 1) / 2;
            let lower = counts.get(base..=base + i).unwrap_or(&[]);
            for_each_nonzero(lower, 0, |j, c| {
                f(i, j, u64::from(c) << u32::from(i == j), 0);
            });
            let row = (i - i0) * n;
            let upper_row = upper.get(row + i + 1..row + n).unwrap_or(&[]);
            for_each_nonzero(upper_row, i + 1, |j, c| f(i, j, u64::from(c), 0));
        }
    }
}

/// Dense symmetric counts that hold nothing but `u32` counts (no carries, no per-pair
/// information, nothing pending): the packed triangle itself, `s_ab` at [`tri`]`(a, b)`.
/// What [`PairCounts::triangle`] lends to a one-pass reader.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Triangle<'a> {
    n: usize,
    counts: &'a [u32],
}

impl Triangle<'_> {
    /// Calls `f(b, a, s_ab)` for every non-zero `s_ab`, `a ≤ b`, in memory order (`b`
    /// increasing, then `a`): one sequential read of the counts, runs of zeros skipped a
    /// block at a time. Full row `i` of `C` is `(i, a ≤ i)` from triangle row `i`, then
    /// `(i, b > i)` from the later rows `b` in increasing `b`, so each full row receives
    /// its entries in increasing column order.
    #[inline]
    pub(crate) fn for_each_nonzero(&self, mut f: impl FnMut(usize, usize, u32)) {
        for b in 0..self.n {
            let base = b * (b + 1) / 2;
            let row = self.counts.get(base..=base + b).unwrap_or(&[]);
            // Mostly zeros: a wide block tested at once, then its narrow blocks
            let mut wide = row.chunks_exact(WIDE_ZERO_RUN);
            let mut a = 0;
            for block in &mut wide {
                if block.iter().fold(0, |x, &c| x | c) != 0 {
                    for_each_nonzero(block, a, |a, s| f(b, a, s));
                }
                a += WIDE_ZERO_RUN;
            }
            for_each_nonzero(wide.remainder(), a, |a, s| f(b, a, s));
        }
    }

    /// Number of non-zero entries in each full row of `C` (`C_ab` and `C_ba` both count
    /// `s_ab`, the diagonal once), and the non-zero `(b, a, s_ab)` in memory order when
    /// there are at most `cap` of them (else `None`: read them again with
    /// [`Self::for_each_nonzero`]): one sequential pass over the counts.
    pub(crate) fn row_lengths(&self, cap: usize) -> (Vec<usize>, Option<Vec<TriangleEntry>>) {
        let mut lengths = vec![0usize; self.n];
        // Reserved at once (untouched pages cost no memory): no copy as it grows, and
        // never more than `cap` entries however far it gets
        let mut entries = Some(Vec::with_capacity(cap));
        self.for_each_nonzero(|b, a, s| {
            if let Some(l) = lengths.get_mut(b) {
                *l += 1;
            }
            if a != b
                && let Some(l) = lengths.get_mut(a)
            {
                *l += 1;
            }
            if let Some(list) = &mut entries {
                // Dense counts have at most DENSE_COUNT_LIMIT rows: indices fit a u16
                match (u16::try_from(b), u16::try_from(a)) {
                    (Ok(b), Ok(a)) if list.len() < cap => list.push((b, a, s)),
                    _ => entries = None,
                }
            }
        });
        (lengths, entries)
    }
}

/// A non-zero count of a [`Triangle`]: `(b, a, s_ab)`, `a ≤ b`; 8 bytes, half of a
/// triangle's 4 bytes a pair when a quarter of the pairs are non-zero.
pub(crate) type TriangleEntry = (u16, u16, u32);

// Row indices of dense counts fit a TriangleEntry
const _: () = assert!(DENSE_COUNT_LIMIT <= 1 << 16);

/// Entries a wide block of `Triangle::for_each_nonzero` tests at once.
const WIDE_ZERO_RUN: usize = 64;

/// Entries a block of [`for_each_nonzero`] tests at once.
const ZERO_RUN: usize = 8;

/// Calls `f(first + k, c)` for every non-zero `c = counts[k]` in order, skipping blocks
/// of [`ZERO_RUN`] zeros with one test.
#[inline(always)]
fn for_each_nonzero(counts: &[u32], first: usize, mut f: impl FnMut(usize, u32)) {
    let mut blocks = counts.chunks_exact(ZERO_RUN);
    let mut j = first;
    for block in &mut blocks {
        if block.iter().fold(0, |a, &c| a | c) != 0 {
            for (k, &c) in block.iter().enumerate() {
                if c > 0 {
                    f(j + k, c);
                }
            }
        }
        j += ZERO_RUN;
    }
    for (k, &c) in blocks.remainder().iter().enumerate() {
        if c > 0 {
            f(j + k, c);
        }
    }
}

/// Sparse key of the ordered pair `(i, j)`.
#[inline(always)]
fn key(i: usize, j: usize) -> u64 {
    ((i as u64) << 32) | j as u64
}

/// The ordered pair of a sparse key.
#[inline(always)]
fn unkey(k: u64) -> (usize, usize) {
    ((k >> 32) as usize, (k & 0xffff_ffff) as usize)
}

/// Adds one to `counts[k]`, recording a wrap past `2³²` in `carries`.
#[inline(always)]
fn bump(counts: &mut [u32], carries: &mut BTreeMap<usize, u64>, k: usize) {
    if let Some(c) = counts.get_mut(k) {
        *c = c.wrapping_add(1);
        if *c == 0 {
            *carries.entry(k).or_insert(0) += 1;
        }
    }
}

/// Adds `c` to `counts[k]`, recording a wrap past `2³²` in `carries`.
#[inline(always)]
fn add_count(counts: &mut [u32], carries: &mut BTreeMap<usize, u64>, k: usize, c: u32) {
    if let Some(x) = counts.get_mut(k) {
        let (sum, wrapped) = x.overflowing_add(c);
        *x = sum;
        if wrapped {
            *carries.entry(k).or_insert(0) += 1;
        }
    }
}

impl PairCounts {
    /// Empty counts over `n` patches; `symmetric` for global lines (module docs).
    pub(crate) fn new(n: usize, symmetric: bool) -> Self {
        if n <= DENSE_COUNT_LIMIT {
            let pairs = n * (n + 1) / 2;
            Self::Dense {
                n,
                symmetric,
                counts: vec![0; if symmetric { pairs } else { n * n }],
                carries: BTreeMap::new(),
                info: (n <= DENSE_PAIR_LIMIT).then(|| vec![0; pairs]),
                pending: Pending::new(),
            }
        } else {
            Self::Sparse {
                n,
                symmetric,
                buffer: Vec::new(),
                merged: Vec::new(),
            }
        }
    }

    /// Counts one sample `i → j` (local lines; not representable in symmetric counts,
    /// where it is ignored — global-line tallies never call it).
    #[inline]
    pub(crate) fn add(&mut self, i: usize, j: usize) {
        match self {
            Self::Dense {
                n,
                symmetric: false,
                counts,
                carries,
                pending,
                ..
            } => pending.hold(counts, carries, i * *n + j),
            Self::Sparse {
                symmetric: false,
                buffer,
                merged,
                ..
            } => push_key(buffer, merged, key(i, j)),
            _ => debug_assert!(false, "a directed count in symmetric counts"),
        }
    }

    /// Counts one global-line segment between `i` and `j`: a sample `i → j` and a sample
    /// `j → i`.
    #[inline]
    pub(crate) fn add_pair(&mut self, i: usize, j: usize) {
        match self {
            Self::Dense {
                n,
                symmetric,
                counts,
                carries,
                pending,
                ..
            } => {
                if *symmetric {
                    pending.hold(counts, carries, tri(i, j));
                } else {
                    pending.hold(counts, carries, i * *n + j);
                    pending.hold(counts, carries, j * *n + i);
                }
            }
            Self::Sparse {
                symmetric,
                buffer,
                merged,
                ..
            } => {
                if *symmetric {
                    push_key(buffer, merged, key(i.min(j), i.max(j)));
                } else {
                    push_key(buffer, merged, key(i, j));
                    push_key(buffer, merged, key(j, i));
                }
            }
        }
    }

    /// Counts `count` global-line segments between `i` and `j` at once: the same counts
    /// as `count` calls of [`PairCounts::add_pair`] (dense counts are added directly,
    /// wraps past `2³²` kept; sparse keys are buffered `count` times).
    #[inline]
    pub(crate) fn add_pair_block(&mut self, i: usize, j: usize, count: u32) {
        match self {
            Self::Dense {
                n,
                symmetric,
                counts,
                carries,
                ..
            } => {
                if *symmetric {
                    add_count(counts, carries, tri(i, j), count);
                } else {
                    add_count(counts, carries, i * *n + j, count);
                    add_count(counts, carries, j * *n + i, count);
                }
            }
            Self::Sparse { .. } => {
                for _ in 0..count {
                    self.add_pair(i, j);
                }
            }
        }
    }

    /// Adds a continuous-information term, quantised by
    /// [`crate::math::FixedSum::quantise`], to pair `(i, j)` *and* to pair `(j, i)`
    /// (dense mode only; ignored when sparse).
    #[inline]
    pub(crate) fn add_info(&mut self, i: usize, j: usize, raw: i128) {
        if let Self::Dense {
            info: Some(info),
            pending,
            ..
        } = self
        {
            // Held (see [`Pending`]): the same additions in the same order
            let k = tri(i, j);
            pending.hold_info(info, k, raw);
            if i == j {
                pending.hold_info(info, k, raw);
            }
        }
    }

    /// Adds another tally exactly.
    pub(crate) fn merge(&mut self, other: &PairCounts) {
        match (self, other) {
            (
                Self::Dense {
                    counts,
                    carries,
                    info,
                    pending,
                    ..
                },
                Self::Dense {
                    counts: oc,
                    carries: ocarries,
                    info: oi,
                    pending: op,
                    ..
                },
            ) => {
                pending.apply(counts, carries, info.as_mut());
                for &k in op.held() {
                    bump(counts, carries, k as usize);
                }
                for (k, (a, b)) in counts.iter_mut().zip(oc).enumerate() {
                    let (sum, wrapped) = a.overflowing_add(*b);
                    *a = sum;
                    if wrapped {
                        *carries.entry(k).or_insert(0) += 1;
                    }
                }
                for (&k, &c) in ocarries {
                    *carries.entry(k).or_insert(0) += c;
                }
                if let (Some(info), Some(oi)) = (info, oi) {
                    for (a, b) in info.iter_mut().zip(oi) {
                        *a = a.saturating_add(*b);
                    }
                    // The other's held terms, after its applied ones (without saturation,
                    // in any order the same sums)
                    for (k, raw) in op.held_info() {
                        if let Some(v) = info.get_mut(k as usize) {
                            *v = v.saturating_add(raw);
                        }
                    }
                }
            }
            (
                Self::Sparse { buffer, merged, .. },
                Self::Sparse {
                    buffer: ob,
                    merged: om,
                    ..
                },
            ) => {
                flush(buffer, merged);
                if ob.is_empty() {
                    merge_into(merged, om);
                } else {
                    let mut other_merged = om.clone();
                    let mut other_buffer = ob.clone();
                    flush(&mut other_buffer, &mut other_merged);
                    drop(other_buffer);
                    merge_into(merged, &other_merged);
                }
            }
            // Tallies of one tracer always share a mode; mixing modes is a caller bug that
            // we ignore rather than panic on.
            _ => debug_assert!(false, "merging dense and sparse pair counts"),
        }
    }

    /// Merges the pending sparse keys into the sorted list, so that
    /// [`PairCounts::merge`] of these counts into others copies nothing (and applies the
    /// pending dense increments).
    pub(crate) fn flush_pending(&mut self) {
        self.settle();
        if let Self::Sparse { buffer, merged, .. } = self {
            flush(buffer, merged);
            *buffer = Vec::new();
        }
    }

    /// Applies the pending dense increments ([`Pending`]; nothing to do when sparse, whose
    /// buffered keys are part of its amortised merging). Ends every chunk of lines.
    #[inline]
    pub(crate) fn settle(&mut self) {
        if let Self::Dense {
            counts,
            carries,
            info,
            pending,
            ..
        } = self
        {
            pending.apply(counts, carries, info.as_mut());
        }
    }

    /// Applies every held increment: pending dense ones, and buffered sparse keys merged
    /// into the sorted list (so that readers borrow it instead of flushing a copy), whose
    /// buffer is then freed (it grows to half the list: hundreds of MB on large scenes).
    pub(crate) fn apply_held(&mut self) {
        self.settle();
        if let Self::Sparse { buffer, merged, .. } = self {
            flush(buffer, merged);
            buffer.shrink_to_fit();
        }
    }

    /// Calls `f(i, j, C_ij, info_ij)` for every non-zero count in row-major order.
    pub(crate) fn for_each(&mut self, mut f: impl FnMut(usize, usize, u64, Option<f64>)) {
        self.apply_held();
        let with_info = self.has_pair_info();
        self.for_each_raw(|i, j, c, info| {
            if c > 0 {
                f(i, j, c, with_info.then(|| info as f64 / SCALE));
            }
        });
    }

    /// Calls `f(i, j, C_ij, raw I_ij^c)` for every pair with a non-zero count or
    /// information in row-major order, the per-pair information as raw 64.64 fixed point
    /// (0 when not kept). A local line `i → j` adds information to `(j, i)` too, so that
    /// pair may have information without a count. Does not change `self` (unflushed sparse
    /// keys, or pending dense increments, are applied to a copy).
    pub(crate) fn for_each_raw(&self, mut f: impl FnMut(usize, usize, u64, i128)) {
        match self {
            // Pending increments (only between the lines of a chunk): read a settled copy
            Self::Dense { pending, .. } if !pending.is_empty() => {
                let mut settled = self.clone();
                settled.settle();
                settled.for_each_raw(f);
            }
            Self::Dense {
                n,
                symmetric: true,
                counts,
                carries,
                info,
                ..
            } => for_each_dense_symmetric(*n, counts, carries, info.as_deref(), f),
            Self::Dense {
                n,
                symmetric,
                counts,
                carries,
                info,
                ..
            } => {
                let n = *n;
                let count_at = |k: usize| {
                    let low = u64::from(counts.get(k).copied().unwrap_or(0));
                    if carries.is_empty() {
                        low
                    } else {
                        low + (carries.get(&k).copied().unwrap_or(0) << 32)
                    }
                };
                for i in 0..n {
                    for j in 0..n {
                        let t = tri(i, j);
                        let c = if *symmetric {
                            count_at(t) << u32::from(i == j)
                        } else {
                            count_at(i * n + j)
                        };
                        let v = info.as_ref().and_then(|info| info.get(t)).copied();
                        let v = v.unwrap_or(0);
                        if c > 0 || v != 0 {
                            f(i, j, c, v);
                        }
                    }
                }
            }
            Self::Sparse {
                n,
                symmetric,
                buffer,
                merged,
            } => {
                let list = flushed(buffer, merged);
                if *symmetric {
                    for_each_symmetric(*n, &list, |i, j, c| f(i, j, c, 0));
                } else {
                    for &(k, c) in list.iter() {
                        let (i, j) = unkey(k);
                        f(i, j, c, 0);
                    }
                }
            }
        }
    }

    /// Number of ordered pairs with a non-zero count or information (what
    /// [`PairCounts::for_each_raw`] visits), without visiting them in order.
    pub(crate) fn nonzero_pairs(&self) -> u64 {
        match self {
            Self::Sparse {
                symmetric,
                buffer,
                merged,
                ..
            } => {
                let list = flushed(buffer, merged);
                list.iter()
                    .map(|&(k, _)| {
                        let (i, j) = unkey(k);
                        if *symmetric && i != j { 2 } else { 1 }
                    })
                    .sum()
            }
            Self::Dense { .. } => {
                let mut pairs = 0;
                self.for_each_raw(|_, _, _, _| pairs += 1);
                pairs
            }
        }
    }

    /// Number of ordered pairs with a non-zero count `C_ij` (what
    /// [`PairCounts::for_each`] visits), without visiting them in order: for dense counts
    /// one pass over the stored counts (pending increments ignored: apply them first).
    pub(crate) fn nonzero_counts(&self) -> u64 {
        match self {
            Self::Sparse { .. } => self.nonzero_pairs(),
            Self::Dense {
                n,
                symmetric,
                counts,
                carries,
                ..
            } => {
                let nonzero = |k: usize, c: u32| c > 0 || carries.contains_key(&k);
                // A count whose low part wrapped to zero is held in `carries`
                let wrapped = |range: core::ops::Range<usize>| {
                    carries
                        .range(range)
                        .filter(|&(&k, _)| counts.get(k) == Some(&0))
                        .count() as u64
                };
                if !*symmetric {
                    let low = counts.iter().filter(|&&c| c > 0).count() as u64;
                    return low + wrapped(0..counts.len());
                }
                // Off-diagonal pairs count twice (C_ij and C_ji), the diagonal once
                let all =
                    counts.iter().filter(|&&c| c > 0).count() as u64 + wrapped(0..counts.len());
                let diagonal = (0..*n)
                    .filter(|&i| {
                        let k = i * (i + 3) / 2;
                        counts.get(k).is_some_and(|&c| nonzero(k, c))
                    })
                    .count() as u64;
                2 * all - diagonal
            }
        }
    }

    /// Sets pair `(i, j)` to `count` (and raw information `info`, when kept), for pairs
    /// given in increasing `(i, j)` order into empty counts (reading a partial file).
    ///
    /// # Errors
    /// What is wrong when the entry cannot belong to symmetric counts: `(i, j)` with
    /// `i > j` must repeat the `(j, i)` given before, and a diagonal count must be even.
    /// (That every `(j, i)` is repeated is checked by the caller, by counting.)
    pub(crate) fn push_sorted(
        &mut self,
        i: usize,
        j: usize,
        count: u64,
        info: i128,
    ) -> core::result::Result<(), &'static str> {
        const ASYMMETRIC: &str = "global-line pair counts are not symmetric";
        let symmetric = matches!(
            self,
            Self::Dense {
                symmetric: true,
                ..
            } | Self::Sparse {
                symmetric: true,
                ..
            }
        );
        if symmetric && i == j && !count.is_multiple_of(2) {
            return Err("a global-line count of a patch with itself is odd");
        }
        let stored = if symmetric && i == j {
            count / 2
        } else {
            count
        };
        match self {
            Self::Dense {
                n,
                counts,
                carries,
                info: pi,
                ..
            } => {
                let t = tri(i, j);
                let k = if symmetric { t } else { i * *n + j };
                let old_info = pi.as_ref().and_then(|pi| pi.get(t)).copied().unwrap_or(0);
                if symmetric && i > j {
                    let low = u64::from(counts.get(k).copied().unwrap_or(0));
                    let old = low + (carries.get(&k).copied().unwrap_or(0) << 32);
                    return if old == count && old_info == info && (old > 0 || info != 0) {
                        Ok(())
                    } else {
                        Err(ASYMMETRIC)
                    };
                }
                if let Some(c) = counts.get_mut(k) {
                    *c = stored as u32;
                }
                if stored >> 32 > 0 {
                    carries.insert(k, stored >> 32);
                }
                // Information is per unordered pair: (j, i) must repeat (i, j)'s.
                if let Some(v) = pi.as_mut().and_then(|pi| pi.get_mut(t)) {
                    if i > j && *v != info {
                        return Err("per-pair information is not symmetric");
                    }
                    *v = info;
                }
                Ok(())
            }
            Self::Sparse { merged, .. } => {
                if symmetric && i > j {
                    let found = merged
                        .binary_search_by_key(&key(j, i), |e| e.0)
                        .ok()
                        .map(|p| merged[p].1);
                    return if found == Some(count) {
                        Ok(())
                    } else {
                        Err(ASYMMETRIC)
                    };
                }
                merged.push((key(i, j), stored));
                Ok(())
            }
        }
    }

    /// Whether the counts hold one entry per unordered pair (global lines).
    pub(crate) fn is_symmetric(&self) -> bool {
        matches!(
            self,
            Self::Dense {
                symmetric: true,
                ..
            } | Self::Sparse {
                symmetric: true,
                ..
            }
        )
    }

    /// Bytes held per non-zero pair (sparse) or in total (dense): what `bench` reports.
    pub(crate) fn heap_bytes(&self) -> usize {
        match self {
            Self::Dense {
                counts,
                carries,
                info,
                ..
            } => {
                counts.capacity() * 4
                    + carries.len() * 16
                    + info.as_ref().map_or(0, |i| i.capacity() * 16)
            }
            Self::Sparse { buffer, merged, .. } => buffer.capacity() * 8 + merged.capacity() * 16,
        }
    }

    /// Whether per-pair continuous information is kept.
    pub(crate) fn has_pair_info(&self) -> bool {
        matches!(self, Self::Dense { info: Some(_), .. })
    }

    /// The packed triangle of dense symmetric counts, when that is all they hold (no
    /// carries, no per-pair information, nothing pending): the one-pass route of
    /// [`crate::tally::LineTally::finish_with_sizes`] to sparse form factors.
    pub(crate) fn triangle(&self) -> Option<Triangle<'_>> {
        match self {
            Self::Dense {
                n,
                symmetric: true,
                counts,
                carries,
                info: None,
                pending,
            } if carries.is_empty() && pending.is_empty() => Some(Triangle { n: *n, counts }),
            _ => None,
        }
    }

    /// Whether the counts are dense.
    pub(crate) fn is_dense(&self) -> bool {
        matches!(self, Self::Dense { .. })
    }
}

/// Buffers a sparse key, flushing when the buffer is full.
#[inline(always)]
fn push_key(buffer: &mut Vec<u64>, merged: &mut Vec<(u64, u64)>, k: u64) {
    buffer.push(k);
    if buffer.len() >= (merged.len() / 2).max(MIN_FLUSH) {
        flush(buffer, merged);
    }
}

/// Calls `f(i, j, C_ij)` in row-major order over the ordered pairs of symmetric sparse
/// counts `list` (sorted keys `(a << 32) | b`, `a ≤ b`, holding `s_ab`): row `i` is the
/// transposed entries `(a, i)`, `a < i`, then the diagonal (`C_ii = 2 s_ii`), then the
/// entries `(i, b)`, `b > i`. The transposed entries are found through a column index
/// built by a counting sort (8 bytes per entry, while it runs).
fn for_each_symmetric(n: usize, list: &[(u64, u64)], mut f: impl FnMut(usize, usize, u64)) {
    // Column index of the strictly upper entries: col_start[b]..col_start[b + 1]
    let mut col_start = vec![0usize; n + 1];
    for &(k, _) in list {
        let (a, b) = unkey(k);
        if a < b && b < n {
            col_start[b + 1] += 1;
        }
    }
    for b in 0..n {
        col_start[b + 1] += col_start[b];
    }
    let mut fill = col_start.clone();
    let mut by_column = vec![0usize; col_start[n]];
    for (e, &(k, _)) in list.iter().enumerate() {
        let (a, b) = unkey(k);
        if a < b && b < n {
            by_column[fill[b]] = e;
            fill[b] += 1;
        }
    }
    drop(fill);
    // Rows: the transposed part, then the list's own row
    let mut next = 0;
    for i in 0..n {
        for &e in &by_column[col_start[i]..col_start[i + 1]] {
            let (k, c) = list[e];
            f(i, unkey(k).0, c);
        }
        while next < list.len() && unkey(list[next].0).0 == i {
            let (k, c) = list[next];
            let j = unkey(k).1;
            f(i, j, if j == i { 2 * c } else { c });
            next += 1;
        }
    }
}

/// The merged sparse list with the unflushed `buffer` folded in, without touching either:
/// borrowed when nothing is pending, else a flushed copy.
fn flushed<'a>(buffer: &[u64], merged: &'a [(u64, u64)]) -> alloc::borrow::Cow<'a, [(u64, u64)]> {
    if buffer.is_empty() {
        return alloc::borrow::Cow::Borrowed(merged);
    }
    let (mut b, mut m) = (buffer.to_vec(), merged.to_vec());
    flush(&mut b, &mut m);
    alloc::borrow::Cow::Owned(m)
}

/// Sorts and run-length encodes the buffered keys into the sorted list.
fn flush(buffer: &mut Vec<u64>, merged: &mut Vec<(u64, u64)>) {
    if buffer.is_empty() {
        return;
    }
    buffer.sort_unstable();
    let mut runs: Vec<(u64, u64)> = Vec::new();
    for &k in buffer.iter() {
        match runs.last_mut() {
            Some((last, c)) if *last == k => *c += 1,
            _ => runs.push((k, 1)),
        }
    }
    buffer.clear();
    merge_into(merged, &runs);
}

/// Merges the sorted `(key, count)` list `b` into the sorted list `a`, adding counts of
/// equal keys, in place: `a` grows by `b`'s length, is filled from the back, and the gap
/// left by equal keys is closed. Peak memory `|a| + |b|` entries.
fn merge_into(a: &mut Vec<(u64, u64)>, b: &[(u64, u64)]) {
    let old = a.len();
    // Exactly: the list is the bulk of sparse counts' memory, and doubling would waste
    // up to half of it (a large block grows in place, without a copy).
    a.reserve_exact(b.len());
    a.resize(old + b.len(), (0, 0));
    // Backwards: x = entries of the old `a` left, y = of `b`, w = the write position
    let (mut x, mut y, mut w) = (old, b.len(), old + b.len());
    while y > 0 {
        w -= 1;
        if x > 0 && a[x - 1].0 > b[y - 1].0 {
            a[w] = a[x - 1];
            x -= 1;
        } else if x > 0 && a[x - 1].0 == b[y - 1].0 {
            a[w] = (b[y - 1].0, a[x - 1].1 + b[y - 1].1);
            x -= 1;
            y -= 1;
        } else {
            a[w] = b[y - 1];
            y -= 1;
        }
    }
    // a[..x] is in place; a[w..] holds the rest: close the gap
    if w > x {
        a.copy_within(w.., x);
        a.truncate(a.len() - (w - x));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn collect(p: &mut PairCounts) -> Vec<(usize, usize, u64)> {
        let mut v = Vec::new();
        p.for_each(|i, j, c, _| v.push((i, j, c)));
        v
    }

    fn sparse(n: usize, symmetric: bool) -> PairCounts {
        PairCounts::Sparse {
            n,
            symmetric,
            buffer: Vec::new(),
            merged: Vec::new(),
        }
    }

    #[test]
    fn dense_and_sparse_count_alike() {
        let pairs = [(0, 1), (2, 0), (0, 1), (1, 1), (2, 0), (0, 1)];
        let mut d = PairCounts::new(3, false);
        let mut s = sparse(3, false);
        for &(i, j) in &pairs {
            d.add(i, j);
            s.add(i, j);
        }
        let expected = vec![(0, 1, 3), (1, 1, 1), (2, 0, 2)];
        assert_eq!(collect(&mut d), expected);
        assert_eq!(collect(&mut s), expected);
    }

    #[test]
    fn symmetric_counts_read_as_the_full_matrix() {
        // Segments between unordered pairs, the diagonal included
        let segments = [(0, 2), (2, 0), (1, 1), (3, 1), (0, 2), (2, 3)];
        let mut full = PairCounts::new(4, false);
        let mut dense = PairCounts::new(4, true);
        let mut sp = sparse(4, true);
        for &(i, j) in &segments {
            full.add_pair(i, j);
            dense.add_pair(i, j);
            sp.add_pair(i, j);
        }
        let expected = collect(&mut full);
        assert_eq!(
            expected,
            vec![
                (0, 2, 3),
                (1, 1, 2),
                (1, 3, 1),
                (2, 0, 3),
                (2, 3, 1),
                (3, 1, 1),
                (3, 2, 1)
            ]
        );
        assert_eq!(collect(&mut dense), expected);
        assert_eq!(collect(&mut sp), expected);
        assert_eq!(sp.nonzero_pairs(), 7);
        assert_eq!(dense.nonzero_pairs(), 7);
    }

    #[test]
    fn gathered_walk_reads_the_full_matrix_across_row_blocks() {
        // 37 patches: two whole blocks of GATHER_ROWS rows and a partial one
        let n = 37;
        let mut full = PairCounts::new(n, false);
        let mut dense = PairCounts::new(n, true);
        let mut sp = sparse(n, true);
        let mut x = 12_345u64;
        let mut next = || {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (x >> 33) as usize % n
        };
        for k in 0..500i128 {
            let (i, j) = (next(), next());
            full.add_pair(i, j);
            dense.add_pair(i, j);
            sp.add_pair(i, j);
            dense.add_info(i, j, k * 1_000_003 - 7);
        }
        dense.settle();
        let expected = collect(&mut full);
        assert!(expected.len() > 300, "{}", expected.len());
        assert_eq!(collect(&mut dense), expected);
        assert_eq!(collect(&mut sp), expected);
        // The information, against a plain walk of the packed triangle
        let PairCounts::Dense {
            info: Some(info), ..
        } = &dense
        else {
            panic!("dense counts of 37 patches keep the per-pair information")
        };
        let mut walked = Vec::new();
        dense.for_each_raw(|i, j, _, v| walked.push((i, j, v)));
        let plain: Vec<(usize, usize, i128)> = expected
            .iter()
            .map(|&(i, j, _)| (i, j, info[tri(i, j)]))
            .collect();
        assert_eq!(walked, plain);
        // Without information (more than DENSE_PAIR_LIMIT patches): the counts-only walk
        let mut counts_only = dense.clone();
        if let PairCounts::Dense { info, .. } = &mut counts_only {
            *info = None;
        }
        assert_eq!(collect(&mut counts_only), expected);
    }

    #[test]
    fn sparse_fills_walk_and_count_like_the_full_matrix() {
        // Few pairs among many patches (whole zero runs skipped, in the triangle and in
        // the rows), a fuller matrix, a tiny one; counts only (no per-pair information)
        let mut x = 99u64;
        let mut next = |n: usize| {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            (x >> 33) as usize % n
        };
        for (n, segments) in [(61, 40), (37, 500), (5, 3), (1, 2)] {
            let mut full = PairCounts::new(n, false);
            let mut dense = PairCounts::new(n, true);
            for _ in 0..segments {
                let (i, j) = (next(n), next(n));
                full.add_pair(i, j);
                dense.add_pair(i, j);
            }
            if let PairCounts::Dense { info, .. } = &mut dense {
                *info = None;
            }
            let expected = collect(&mut full);
            assert_eq!(collect(&mut dense), expected, "{n} patches");
            assert_eq!(dense.nonzero_counts(), expected.len() as u64);
            assert_eq!(full.nonzero_counts(), expected.len() as u64);
        }
    }

    #[test]
    fn dense_counts_carry_past_u32() {
        let mut a = PairCounts::new(2, true);
        if let PairCounts::Dense { counts, .. } = &mut a {
            counts[tri(0, 1)] = u32::MAX;
        }
        a.add_pair(1, 0);
        a.add_pair(0, 1);
        let mut b = a.clone();
        b.merge(&a);
        assert_eq!(
            collect(&mut a),
            vec![(0, 1, 1 << 32 | 1), (1, 0, 1 << 32 | 1)]
        );
        assert_eq!(
            collect(&mut b),
            vec![(0, 1, 2 << 32 | 2), (1, 0, 2 << 32 | 2)]
        );
        assert_eq!(b.nonzero_counts(), 2);
        // A count whose low part wrapped to exactly zero is still a count
        let mut c = PairCounts::new(2, true);
        if let PairCounts::Dense { counts, .. } = &mut c {
            counts[tri(1, 1)] = u32::MAX;
        }
        c.add_pair(1, 1);
        c.settle();
        assert_eq!(collect(&mut c), vec![(1, 1, 2 << 32)]);
        assert_eq!(c.nonzero_counts(), 1);
    }

    #[test]
    fn pending_increments_are_seen_by_every_reader() {
        // 101 segments: three full batches applied, five increments still pending
        let segments: Vec<(usize, usize)> = (0..101).map(|k| (k * 7 % 13, k * 5 % 11)).collect();
        let mut reference = vec![0u64; 13 * 13];
        let mut counts = PairCounts::new(13, true);
        for &(i, j) in &segments {
            reference[i * 13 + j] += 1;
            reference[j * 13 + i] += 1;
            counts.add_pair(i, j);
        }
        let expected: Vec<(usize, usize, u64)> = (0..13 * 13)
            .filter(|&k| reference[k] > 0)
            .map(|k| (k / 13, k % 13, reference[k]))
            .collect();
        // A read through `&self` with increments pending, then merges of pending counts
        let mut raw = Vec::new();
        counts.for_each_raw(|i, j, c, _| raw.push((i, j, c)));
        assert_eq!(raw, expected);
        assert_eq!(counts.nonzero_pairs(), expected.len() as u64);
        let mut twice = PairCounts::new(13, true);
        twice.add_pair(0, 0);
        twice.merge(&counts);
        twice.merge(&counts);
        let doubled: Vec<_> = expected
            .iter()
            .map(|&(i, j, c)| (i, j, 2 * c + if (i, j) == (0, 0) { 2 } else { 0 }))
            .collect();
        assert_eq!(collect(&mut twice), doubled);
        // Settling changes what is stored, not what is read
        let before = counts.clone();
        counts.settle();
        assert_ne!(counts, before);
        assert_eq!(collect(&mut counts), expected);
    }

    #[test]
    fn pending_information_is_seen_by_every_reader_in_order() {
        // 77 terms on 13 patches (diagonal pairs twice): two full batches applied, the rest
        // pending; the reference adds each term at once, saturating, in the same order
        let n = 13;
        let terms: Vec<(usize, usize, i128)> = (0..77i128)
            .map(|k| {
                let (i, j) = ((k * 7 % 13) as usize, (k * 5 % 11) as usize);
                (i, j, ((k - 38) * 1_000_000_007) << 60)
            })
            .collect();
        let mut reference = vec![0i128; n * (n + 1) / 2];
        let mut counts = PairCounts::new(n, true);
        for &(i, j, raw) in &terms {
            let v = &mut reference[tri(i, j)];
            *v = v.saturating_add(raw);
            if i == j {
                *v = v.saturating_add(raw);
            }
            counts.add_info(i, j, raw);
        }
        let expected: Vec<(usize, usize, i128)> = (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .map(|(i, j)| (i, j, reference[tri(i, j)]))
            .filter(|&(_, _, v)| v != 0)
            .collect();
        let read = |c: &PairCounts| {
            let mut v = Vec::new();
            c.for_each_raw(|i, j, _, info| v.push((i, j, info)));
            v
        };
        // Through `&self` with terms pending, after a merge, and settled
        assert_eq!(read(&counts), expected);
        let mut merged = PairCounts::new(n, true);
        merged.merge(&counts);
        assert_eq!(read(&merged), expected);
        let before = counts.clone();
        counts.settle();
        assert_ne!(counts, before, "terms were pending");
        assert_eq!(read(&counts), expected);
        // A sum pushed past i128::MAX is clamped there and the next term adds to the
        // clamped sum: the order of the terms shows, and is the order they came in (−5
        // first would end at i128::MAX)
        let mut saturating = PairCounts::new(2, true);
        for raw in [i128::MAX / 2 + 1, i128::MAX / 2 + 1, -5] {
            saturating.add_info(0, 1, raw);
        }
        let clamped = i128::MAX - 5;
        assert_eq!(read(&saturating), vec![(0, 1, clamped), (1, 0, clamped)]);
    }

    #[test]
    fn merge_is_exact() {
        let mut a = PairCounts::Sparse {
            n: 10,
            symmetric: false,
            buffer: vec![5, 1, 5],
            merged: vec![(3, 2)],
        };
        let b = PairCounts::Sparse {
            n: 10,
            symmetric: false,
            buffer: vec![3, 9],
            merged: vec![(1, 1)],
        };
        a.merge(&b);
        let mut got = Vec::new();
        a.for_each(|i, j, c, _| got.push((key(i, j), c)));
        assert_eq!(got, vec![(1, 2), (3, 3), (5, 2), (9, 1)]);
    }

    #[test]
    fn symmetric_entries_must_repeat_on_reading() {
        for mut c in [PairCounts::new(3, true), sparse(3, true)] {
            assert_eq!(c.push_sorted(0, 1, 3, 0), Ok(()));
            assert_eq!(c.push_sorted(1, 1, 4, 0), Ok(()));
            assert!(c.push_sorted(1, 1, 3, 0).is_err(), "odd diagonal");
            assert!(
                c.push_sorted(1, 0, 2, 0).is_err(),
                "(1, 0) differs from (0, 1)"
            );
            assert!(c.push_sorted(2, 0, 1, 0).is_err(), "(2, 0) without (0, 2)");
            assert_eq!(c.push_sorted(1, 0, 3, 0), Ok(()));
            assert_eq!(collect(&mut c), vec![(0, 1, 3), (1, 0, 3), (1, 1, 4)]);
        }
    }

    #[test]
    fn merge_into_matches_a_plain_merge() {
        let a0 = vec![(1, 1), (4, 2), (6, 1), (9, 5)];
        let b = vec![(0, 3), (4, 1), (5, 1), (9, 1), (12, 2)];
        let mut a = a0.clone();
        merge_into(&mut a, &b);
        assert_eq!(
            a,
            vec![(0, 3), (1, 1), (4, 3), (5, 1), (6, 1), (9, 6), (12, 2)]
        );
        let mut empty = Vec::new();
        merge_into(&mut empty, &b);
        assert_eq!(empty, b);
        let mut same = a0.clone();
        merge_into(&mut same, &[]);
        assert_eq!(same, a0);
    }
}
