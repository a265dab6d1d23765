//! Partial Monte Carlo results: the tally of some seeded chunks of a line job, as a
//! versioned, checksummed binary file that merges exactly with the others of the same job.
//!
//! A job of `N` lines with seed `s` is the chunks `0 .. ⌈N / CHUNK_LINES⌉`, chunk `k`
//! drawing from [`crate::lines::chunk_rng`]`(s, k)`. A [`Partial`] holds the exact tally
//! (integers and 64.64 fixed-point sums, see [`LineTally`]) of a range of those chunks, the
//! patch sizes and what identifies the job: a fingerprint of the scene, the method, the
//! seed, `N`. `merge_partials` checks that the partials belong to one job and do not
//! overlap, and adds their tallies; when they cover every chunk, [`Partial::finish`] gives
//! exactly — bit for bit — the estimate of one run of the whole job on one machine.
//!
//! # File layout (version 1, little-endian)
//!
//! ```text
//! magic      8 bytes  "SCNINFOP"
//! version    u32      1
//! method     u32      0 = global lines, 1 = local lines, 2 = bundles of parallel lines
//!                     (code 2 added within version 1: older files read unchanged)
//! scene      u64      fingerprint of the scene file (caller's choice of bytes)
//! seed       u64
//! lines      u64      N, the lines of the whole job
//! chunks     u64 u64  first chunk, end chunk (half-open)
//! seconds    f64      wall time spent on these chunks (informative only)
//! n          u64      patches
//! sizes      n × f64  patch lengths or areas
//! tally      lines cast u64; leaves n × u64; per-patch I_i^c n × (i128, u8 saturated);
//!            continuous (3 × (i128, u8), u64, u128, u64);
//!            pair flag u8 (1 = per-pair I_ij^c follows each count);
//!            pairs u64, then per pair with a count (or information): i u32, j u32,
//!            C_ij u64 [, I_ij^c i128], sorted by (i, j)
//! checksum   u64      of every byte before it (see `checksum`)
//! ```
//!
//! Counts are stored sparsely whatever the in-memory layout: 16 bytes per non-zero pair
//! (32 with the per-pair information of scenes of at most
//! `crate::tally::DENSE_PAIR_LIMIT` patches).

use alloc::vec::Vec;
use core::ops::Range;

use crate::error::{ErrorKind, Result};
use crate::lines::chunk_count;
use crate::math::FixedSum;
use crate::tally::counts::PairCounts;
use crate::tally::{LineEstimate, LineMethod, LineTally};

/// First bytes of every partial file.
pub(crate) const PARTIAL_MAGIC: [u8; 8] = *b"SCNINFOP";

/// The layout version this code writes and reads.
pub(crate) const PARTIAL_VERSION: u32 = 1;

/// Most patches a partial file may declare (the largest scene any builder accepts).
const MAX_PARTIAL_PATCHES: u64 = 1 << 26;

/// What identifies a line job: partials merge only when all of it agrees.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct JobId {
    /// Fingerprint of the scene (e.g. `fingerprint` of its file).
    pub scene: u64,
    /// The sampling method.
    pub method: LineMethod,
    /// Seed of the chunk streams.
    pub seed: u64,
    /// Lines of the whole job.
    pub lines: u64,
}

/// The tally of chunks `chunks` of a job.
#[derive(Clone, Debug, PartialEq)]
pub struct Partial {
    /// The job the chunks belong to.
    pub job: JobId,
    /// The chunks tallied (half-open).
    pub chunks: Range<u64>,
    /// Wall-clock seconds spent (summed over merged partials; informative only).
    pub seconds: f64,
    /// Patch sizes (lengths or areas), the stationary distribution up to normalisation.
    pub sizes: Vec<f64>,
    /// The exact tally.
    pub tally: LineTally,
}

/// [`Partial::fingerprint`].
pub(crate) fn fingerprint(bytes: &[u8]) -> u64 {
    checksum(bytes)
}

/// Word hash: each 8-byte little-endian word `w` (the tail zero-padded) updates
/// `h ← (rotl(h, 23) ⊕ w) · φ₆₄` (φ₆₄ = 0x9E37…7C15, odd), then the length is mixed in.
/// Every step is a bijection of `h` for a given word, so changing any single word always
/// changes the result.
fn checksum(bytes: &[u8]) -> u64 {
    const PHI: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut h: u64 = 0x6A09_E667_F3BC_C908;
    let mut words = bytes.chunks_exact(8);
    for w in &mut words {
        let mut b = [0u8; 8];
        b.copy_from_slice(w);
        h = (h.rotate_left(23) ^ u64::from_le_bytes(b)).wrapping_mul(PHI);
    }
    let tail = words.remainder();
    if !tail.is_empty() {
        let mut b = [0u8; 8];
        b[..tail.len()].copy_from_slice(tail);
        h = (h.rotate_left(23) ^ u64::from_le_bytes(b)).wrapping_mul(PHI);
    }
    h = (h.rotate_left(23) ^ bytes.len() as u64).wrapping_mul(PHI);
    h ^ (h >> 29)
}

impl Partial {
    /// Merges the partials of one job into one (exact: any order gives the same bits).
    ///
    /// # Errors
    /// [`ErrorKind::NoLines`] for an empty list; [`ErrorKind::PartialMismatch`] when two
    /// partials come from different jobs (scene, method, seed, line count or patch count);
    /// [`ErrorKind::ChunkRanges`] when they share a chunk, or leave a gap between them
    /// (a merged partial is one contiguous chunk range; merge neighbours first).
    pub fn merge(parts: Vec<Partial>) -> Result<Partial> {
        merge_partials(parts)
    }

    /// A 64-bit fingerprint of `bytes` (the word hash of the file checksum): equal inputs give
    /// equal fingerprints; any change of one 8-byte word changes it.
    #[must_use]
    pub fn fingerprint(bytes: &[u8]) -> u64 {
        fingerprint(bytes)
    }

    /// Whether the chunks cover the whole job.
    #[must_use]
    pub fn is_complete(&self) -> bool {
        self.chunks.start == 0 && self.chunks.end == chunk_count(self.job.lines)
    }

    /// The estimate of the whole job.
    ///
    /// # Errors
    /// [`ErrorKind::MissingChunks`] when the partial does not cover the whole job;
    /// otherwise those of [`LineTally::finish_with_sizes`].
    pub fn finish(self) -> Result<LineEstimate> {
        if !self.is_complete() {
            return Err(ErrorKind::MissingChunks {
                have: self.chunks.start..self.chunks.end,
                total: chunk_count(self.job.lines),
            }
            .into());
        }
        self.tally.finish_with_sizes(&self.sizes)
    }

    /// The partial as a file (layout in the module docs).
    #[must_use]
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut w = Vec::new();
        w.extend_from_slice(&PARTIAL_MAGIC);
        put_u32(&mut w, PARTIAL_VERSION);
        put_u32(&mut w, method_code(self.job.method));
        put_u64(&mut w, self.job.scene);
        put_u64(&mut w, self.job.seed);
        put_u64(&mut w, self.job.lines);
        put_u64(&mut w, self.chunks.start);
        put_u64(&mut w, self.chunks.end);
        put_u64(&mut w, self.seconds.to_bits());
        put_u64(&mut w, self.sizes.len() as u64);
        for &s in &self.sizes {
            put_u64(&mut w, s.to_bits());
        }
        let t = &self.tally;
        put_u64(&mut w, t.lines);
        for &c in &t.leaves {
            put_u64(&mut w, c);
        }
        for s in &t.patch_info {
            put_fixed(&mut w, s);
        }
        let c = &t.continuous;
        put_fixed(&mut w, &c.sum_s);
        put_fixed(&mut w, &c.sum_ss);
        put_fixed(&mut w, &c.sum_sn);
        put_u64(&mut w, c.sum_n);
        w.extend_from_slice(&c.sum_nn.to_le_bytes());
        put_u64(&mut w, c.groups);
        let with_info = t.counts.has_pair_info();
        w.push(u8::from(with_info));
        let count_at = w.len();
        put_u64(&mut w, 0);
        let mut pairs = 0u64;
        t.counts.for_each_raw(|i, j, count, info| {
            put_u32(&mut w, i as u32);
            put_u32(&mut w, j as u32);
            put_u64(&mut w, count);
            if with_info {
                w.extend_from_slice(&info.to_le_bytes());
            }
            pairs += 1;
        });
        w[count_at..count_at + 8].copy_from_slice(&pairs.to_le_bytes());
        let sum = checksum(&w);
        put_u64(&mut w, sum);
        w
    }

    /// Reads a partial file, checking its magic, version, checksum and every count.
    ///
    /// # Errors
    /// [`ErrorKind::BadPartial`] saying what is wrong (not a partial file, another
    /// version, a checksum mismatch, truncated, or an inconsistent field).
    pub fn from_bytes(bytes: &[u8]) -> Result<Self> {
        let bad = |what: &'static str| ErrorKind::BadPartial { what };
        if bytes.len() < PARTIAL_MAGIC.len() || bytes[..8] != PARTIAL_MAGIC {
            return Err(bad("not a sceneinfo partial file (wrong magic bytes)").into());
        }
        if bytes.len() < 12 {
            return Err(bad("truncated header").into());
        }
        let mut r = Reader {
            bytes: &bytes[8..],
            bad: "truncated header",
        };
        let version = r.u32()?;
        if version != PARTIAL_VERSION {
            return Err(ErrorKind::PartialVersion {
                found: version,
                supported: PARTIAL_VERSION,
            }
            .into());
        }
        let (body, sum) = bytes.split_at(bytes.len().saturating_sub(8).max(12));
        if sum.len() != 8 {
            return Err(bad("truncated: no checksum").into());
        }
        let mut s = [0u8; 8];
        s.copy_from_slice(sum);
        if checksum(body) != u64::from_le_bytes(s) {
            return Err(bad("checksum mismatch (the file is corrupt or was cut short)").into());
        }
        let mut r = Reader {
            bytes: &body[12..],
            bad: "truncated",
        };
        let method = match r.u32()? {
            0 => LineMethod::Global,
            1 => LineMethod::Local,
            2 => LineMethod::Bundle,
            _ => return Err(bad("unknown sampling method").into()),
        };
        let job = JobId {
            method,
            scene: r.u64()?,
            seed: r.u64()?,
            lines: r.u64()?,
        };
        let chunks = r.u64()?..r.u64()?;
        if chunks.start > chunks.end || chunks.end > chunk_count(job.lines) {
            return Err(bad("chunk range outside the job").into());
        }
        let seconds = f64::from_bits(r.u64()?);
        let n64 = r.u64()?;
        if n64 > MAX_PARTIAL_PATCHES {
            return Err(bad("too many patches").into());
        }
        let n = n64 as usize;
        // 8 (size) + 8 (leaves) + 17 (info) bytes per patch must be present before we
        // allocate for them.
        if r.bytes.len() / 33 < n {
            return Err(bad("truncated patch data").into());
        }
        let mut sizes = Vec::with_capacity(n);
        for _ in 0..n {
            let s = f64::from_bits(r.u64()?);
            if !(s > 0.0 && s.is_finite()) {
                return Err(bad("a patch size is not a positive number").into());
            }
            sizes.push(s);
        }
        let mut tally = LineTally::new(n, method);
        tally.lines = r.u64()?;
        for c in &mut tally.leaves {
            *c = r.u64()?;
        }
        for s in &mut tally.patch_info {
            *s = r.fixed()?;
        }
        let c = &mut tally.continuous;
        c.sum_s = r.fixed()?;
        c.sum_ss = r.fixed()?;
        c.sum_sn = r.fixed()?;
        c.sum_n = r.u64()?;
        c.sum_nn = r.u128()?;
        c.groups = r.u64()?;
        let with_info = match r.u8()? {
            0 => false,
            1 => true,
            _ => return Err(bad("bad per-pair flag").into()),
        };
        let pairs = r.u64()?;
        let entry = if with_info { 32 } else { 16 };
        if r.bytes.len() as u64 / entry != pairs || !(r.bytes.len() as u64).is_multiple_of(entry) {
            return Err(bad("pair count disagrees with the file length").into());
        }
        let mut counts = PairCounts::new(n, method.is_global());
        if with_info != counts.has_pair_info() {
            return Err(bad("per-pair flag disagrees with the patch count").into());
        }
        let mut last: Option<u64> = None;
        // Symmetric (global-line) counts: every (i, j), i < j, is repeated as (j, i)
        let (mut upper, mut lower) = (0u64, 0u64);
        for _ in 0..pairs {
            let (i, j, count) = (r.u32()?, r.u32()?, r.u64()?);
            let info = if with_info { r.i128()? } else { 0 };
            let key = (u64::from(i) << 32) | u64::from(j);
            if u64::from(i) >= n64 || u64::from(j) >= n64 || (count == 0 && info == 0) {
                return Err(bad("a pair entry names a patch out of range or is empty").into());
            }
            if last.is_some_and(|l| l >= key) {
                return Err(bad("pair counts are not sorted").into());
            }
            last = Some(key);
            counts
                .push_sorted(i as usize, j as usize, count, info)
                .map_err(bad)?;
            upper += u64::from(i < j);
            lower += u64::from(i > j);
        }
        if counts.is_symmetric() && upper != lower {
            return Err(bad("global-line pair counts are not symmetric").into());
        }
        tally.counts = counts;
        Ok(Self {
            job,
            chunks,
            seconds,
            sizes,
            tally,
        })
    }
}

/// [`Partial::merge`].
pub(crate) fn merge_partials(mut parts: Vec<Partial>) -> Result<Partial> {
    parts.sort_by_key(|p| p.chunks.start);
    let mut iter = parts.into_iter();
    let Some(mut acc) = iter.next() else {
        return Err(ErrorKind::NoLines.into());
    };
    for p in iter {
        let field = if p.job.scene != acc.job.scene {
            Some("scene")
        } else if p.job.method != acc.job.method {
            Some("method")
        } else if p.job.seed != acc.job.seed {
            Some("seed")
        } else if p.job.lines != acc.job.lines {
            Some("lines")
        } else if p.sizes.len() != acc.sizes.len()
            || p.sizes.iter().zip(&acc.sizes).any(|(a, b)| a != b)
        {
            Some("patches")
        } else {
            None
        };
        if let Some(field) = field {
            return Err(ErrorKind::PartialMismatch { field }.into());
        }
        if p.chunks.start != acc.chunks.end {
            return Err(ErrorKind::ChunkRanges {
                first: acc.chunks.start..acc.chunks.end,
                second: p.chunks.start..p.chunks.end,
            }
            .into());
        }
        acc.tally.merge(&p.tally);
        acc.chunks.end = p.chunks.end;
        acc.seconds += p.seconds;
    }
    Ok(acc)
}

fn method_code(m: LineMethod) -> u32 {
    match m {
        LineMethod::Global => 0,
        LineMethod::Local => 1,
        LineMethod::Bundle => 2,
    }
}

fn put_u32(w: &mut Vec<u8>, v: u32) {
    w.extend_from_slice(&v.to_le_bytes());
}

fn put_u64(w: &mut Vec<u8>, v: u64) {
    w.extend_from_slice(&v.to_le_bytes());
}

fn put_fixed(w: &mut Vec<u8>, s: &FixedSum) {
    w.extend_from_slice(&s.raw().to_le_bytes());
    w.push(u8::from(s.saturated()));
}

/// A cursor over a file's bytes; every read fails with `bad` when the bytes run out (also
/// the reader of `api::ExactRows` files).
pub(crate) struct Reader<'a> {
    pub(crate) bytes: &'a [u8],
    pub(crate) bad: &'static str,
}

impl Reader<'_> {
    pub(crate) fn take<const K: usize>(&mut self) -> Result<[u8; K]> {
        if self.bytes.len() < K {
            return Err(ErrorKind::BadPartial { what: self.bad }.into());
        }
        let (head, rest) = self.bytes.split_at(K);
        self.bytes = rest;
        let mut out = [0u8; K];
        out.copy_from_slice(head);
        Ok(out)
    }

    pub(crate) fn u8(&mut self) -> Result<u8> {
        Ok(self.take::<1>()?[0])
    }

    pub(crate) fn u32(&mut self) -> Result<u32> {
        Ok(u32::from_le_bytes(self.take()?))
    }

    pub(crate) fn u64(&mut self) -> Result<u64> {
        Ok(u64::from_le_bytes(self.take()?))
    }

    pub(crate) fn u128(&mut self) -> Result<u128> {
        Ok(u128::from_le_bytes(self.take()?))
    }

    fn i128(&mut self) -> Result<i128> {
        Ok(i128::from_le_bytes(self.take()?))
    }

    fn fixed(&mut self) -> Result<FixedSum> {
        let raw = self.i128()?;
        let saturated = match self.u8()? {
            0 => false,
            1 => true,
            _ => {
                return Err(ErrorKind::BadPartial {
                    what: "bad saturation flag",
                }
                .into());
            }
        };
        Ok(FixedSum::from_raw_parts(raw, saturated))
    }
}

#[cfg(test)]
mod tests;
