//! Integer tallies of line samples between patch pairs, dense or sparse.

use alloc::vec;
use alloc::vec::Vec;

/// Largest patch count for which the per-pair continuous information `I_ij^c` is kept
/// (dense `n × n` 64.64 fixed-point sums: 1024² × 16 bytes = 16 MiB per tally).
pub const DENSE_PAIR_LIMIT: usize = 1024;

/// Largest patch count for which the counts `C_ij` are kept dense (`n² × 8` bytes ≤ 256 MiB
/// per tally): faster than sparse and, for scenes where most pairs see each other (a
/// subdivided cube), smaller too.
pub const DENSE_COUNT_LIMIT: usize = 5792;

/// Tallies `C_ij` of samples leaving patch `i` that reached patch `j`.
///
/// Dense for `n ≤` [`DENSE_COUNT_LIMIT`]: `C_ij` as `u64`, plus, for `n ≤`
/// [`DENSE_PAIR_LIMIT`], the per-pair sum of continuous-information terms (raw 64.64 fixed
/// point). Sparse beyond: keys `(i << 32) | j` are buffered and periodically sorted and merged
/// into a sorted `(key, count)` list — 16 bytes per non-zero pair. Counting is exact integer
/// arithmetic, so merging tallies gives the same result in any order.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum PairCounts {
    Dense {
        n: usize,
        counts: Vec<u64>,
        info: Option<Vec<i128>>,
    },
    Sparse {
        buffer: Vec<u64>,
        merged: Vec<(u64, u64)>,
    },
}

/// Raw fixed-point scale of [`crate::math::FixedSum`] (2⁶⁴), for the per-pair sums.
const SCALE: f64 = 18_446_744_073_709_551_616.0;

impl PairCounts {
    pub(crate) fn new(n: usize) -> Self {
        if n <= DENSE_COUNT_LIMIT {
            Self::Dense {
                n,
                counts: vec![0; n * n],
                info: (n <= DENSE_PAIR_LIMIT).then(|| vec![0; n * n]),
            }
        } else {
            Self::Sparse {
                buffer: Vec::new(),
                merged: Vec::new(),
            }
        }
    }

    /// Counts one sample `i → j`.
    #[inline]
    pub(crate) fn add(&mut self, i: usize, j: usize) {
        match self {
            Self::Dense { n, counts, .. } => {
                if let Some(c) = counts.get_mut(i * *n + j) {
                    *c += 1;
                }
            }
            Self::Sparse { buffer, merged } => {
                buffer.push(((i as u64) << 32) | j as u64);
                if buffer.len() >= merged.len().max(1 << 20) {
                    flush(buffer, merged);
                }
            }
        }
    }

    /// Adds a continuous-information term, quantised by
    /// [`crate::math::FixedSum::quantise`], to pair `(i, j)` (dense mode only; ignored
    /// when sparse).
    #[inline]
    pub(crate) fn add_info(&mut self, i: usize, j: usize, raw: i128) {
        if let Self::Dense {
            n,
            info: Some(info),
            ..
        } = self
            && let Some(v) = info.get_mut(i * *n + j)
        {
            *v = v.saturating_add(raw);
        }
    }

    /// Adds another tally exactly.
    pub(crate) fn merge(&mut self, other: &PairCounts) {
        match (self, other) {
            (
                Self::Dense { counts, info, .. },
                Self::Dense {
                    counts: oc,
                    info: oi,
                    ..
                },
            ) => {
                for (a, b) in counts.iter_mut().zip(oc) {
                    *a += *b;
                }
                if let (Some(info), Some(oi)) = (info, oi) {
                    for (a, b) in info.iter_mut().zip(oi) {
                        *a = a.saturating_add(*b);
                    }
                }
            }
            (
                Self::Sparse { buffer, merged },
                Self::Sparse {
                    buffer: ob,
                    merged: om,
                },
            ) => {
                flush(buffer, merged);
                let mut other_merged = om.clone();
                let mut other_buffer = ob.clone();
                flush(&mut other_buffer, &mut other_merged);
                *merged = merge_sorted(merged, &other_merged);
            }
            // Tallies of one tracer always share a mode; mixing modes is a caller bug that
            // we ignore rather than panic on.
            _ => debug_assert!(false, "merging dense and sparse pair counts"),
        }
    }

    /// Calls `f(i, j, C_ij, info_ij)` for every non-zero count in row-major order.
    pub(crate) fn for_each(&mut self, mut f: impl FnMut(usize, usize, u64, Option<f64>)) {
        match self {
            Self::Dense { n, counts, info } => {
                for (k, &c) in counts.iter().enumerate() {
                    if c > 0 {
                        let v = info.as_ref().and_then(|info| info.get(k));
                        f(k / *n, k % *n, c, v.map(|&v| v as f64 / SCALE));
                    }
                }
            }
            Self::Sparse { buffer, merged } => {
                flush(buffer, merged);
                for &(key, c) in merged.iter() {
                    f((key >> 32) as usize, (key & 0xffff_ffff) as usize, c, None);
                }
            }
        }
    }

    /// Calls `f(i, j, C_ij, raw I_ij^c)` for every pair with a non-zero count or
    /// information in row-major order, the per-pair information as raw 64.64 fixed point
    /// (0 when not kept). A local line `i → j` adds information to `(j, i)` too, so that
    /// pair may have information without a count. Does not change `self` (unflushed sparse
    /// keys are merged into a copy).
    pub(crate) fn for_each_raw(&self, mut f: impl FnMut(usize, usize, u64, i128)) {
        match self {
            Self::Dense { n, counts, info } => {
                for (k, &c) in counts.iter().enumerate() {
                    let v = info.as_ref().and_then(|info| info.get(k)).copied();
                    let v = v.unwrap_or(0);
                    if c > 0 || v != 0 {
                        f(k / *n, k % *n, c, v);
                    }
                }
            }
            Self::Sparse { buffer, merged } => {
                let mut copy;
                let list = if buffer.is_empty() {
                    merged
                } else {
                    copy = (buffer.clone(), merged.clone());
                    flush(&mut copy.0, &mut copy.1);
                    &copy.1
                };
                for &(key, c) in list.iter() {
                    f((key >> 32) as usize, (key & 0xffff_ffff) as usize, c, 0);
                }
            }
        }
    }

    /// Sets pair `(i, j)` to `count` (and raw information `info`, when kept), for pairs
    /// given in increasing `(i, j)` order into empty counts (reading a partial file).
    pub(crate) fn push_sorted(&mut self, i: usize, j: usize, count: u64, info: i128) {
        match self {
            Self::Dense {
                n,
                counts,
                info: pi,
            } => {
                let k = i * *n + j;
                if let Some(c) = counts.get_mut(k) {
                    *c = count;
                }
                if let Some(v) = pi.as_mut().and_then(|pi| pi.get_mut(k)) {
                    *v = info;
                }
            }
            Self::Sparse { merged, .. } => merged.push((((i as u64) << 32) | j as u64, count)),
        }
    }

    /// Bytes held per non-zero pair (sparse) or in total (dense): what `bench` reports.
    pub(crate) fn heap_bytes(&self) -> usize {
        match self {
            Self::Dense { counts, info, .. } => {
                counts.capacity() * 8 + info.as_ref().map_or(0, |i| i.capacity() * 16)
            }
            Self::Sparse { buffer, merged } => buffer.capacity() * 8 + merged.capacity() * 16,
        }
    }

    /// Whether per-pair continuous information is kept.
    pub(crate) fn has_pair_info(&self) -> bool {
        matches!(self, Self::Dense { info: Some(_), .. })
    }

    /// Whether the counts are dense.
    pub(crate) fn is_dense(&self) -> bool {
        matches!(self, Self::Dense { .. })
    }
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
    *merged = merge_sorted(merged, &runs);
}

/// Merges two sorted `(key, count)` lists, adding counts of equal keys.
fn merge_sorted(a: &[(u64, u64)], b: &[(u64, u64)]) -> Vec<(u64, u64)> {
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut x, mut y) = (0, 0);
    while x < a.len() && y < b.len() {
        let (ka, ca) = a[x];
        let (kb, cb) = b[y];
        if ka < kb {
            out.push((ka, ca));
            x += 1;
        } else if kb < ka {
            out.push((kb, cb));
            y += 1;
        } else {
            out.push((ka, ca + cb));
            x += 1;
            y += 1;
        }
    }
    out.extend_from_slice(&a[x..]);
    out.extend_from_slice(&b[y..]);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn collect(p: &mut PairCounts) -> Vec<(usize, usize, u64)> {
        let mut v = Vec::new();
        p.for_each(|i, j, c, _| v.push((i, j, c)));
        v
    }

    #[test]
    fn dense_and_sparse_count_alike() {
        let pairs = [(0, 1), (2, 0), (0, 1), (1, 1), (2, 0), (0, 1)];
        let mut d = PairCounts::new(3);
        let mut s = PairCounts::Sparse {
            buffer: Vec::new(),
            merged: Vec::new(),
        };
        for &(i, j) in &pairs {
            d.add(i, j);
            s.add(i, j);
        }
        let expected = vec![(0, 1, 3), (1, 1, 1), (2, 0, 2)];
        assert_eq!(collect(&mut d), expected);
        assert_eq!(collect(&mut s), expected);
    }

    #[test]
    fn merge_is_exact() {
        let mut a = PairCounts::Sparse {
            buffer: vec![5, 1, 5],
            merged: vec![(3, 2)],
        };
        let b = PairCounts::Sparse {
            buffer: vec![3, 9],
            merged: vec![(1, 1)],
        };
        a.merge(&b);
        let mut got = Vec::new();
        a.for_each(|i, j, c, _| got.push(((i as u64) << 32 | j as u64, c)));
        assert_eq!(got, vec![(1, 2), (3, 3), (5, 2), (9, 1)]);
    }
}
