//! Every hit of every line of a bundle of parallel lines, without a tree: the segments are
//! projected once on the bundle's normal, and each segment is tested only against the lines
//! whose offsets fall inside its projection.
//!
//! # Method
//!
//! The lines of a [`GlobalBundle2`] share the unit normal `n` and sit at non-decreasing
//! offsets `p_0 ≤ … ≤ p_{m−1}` from the circle's centre `c`. A line at offset `p` can meet
//! the segment `a → b` only if `p` lies between the projections `n·(a − c)` and
//! `n·(b − c)`, so per segment
//!
//! ```text
//! lo = min(n·(a − c), n·(b − c)) − δ,   hi = max(…) + δ,
//! candidates = {k : lo ≤ p_k ≤ hi}      (a range k₀ … k₁ − 1: the offsets are sorted)
//! ```
//!
//! found in `O(1)` from `k ≈ ((p/r + 1)/2)·m − u₁` and corrected against the stored
//! offsets. Every candidate then runs the exact per-segment test of [`super::all_hits_naive`]
//! (the module docs of [`crate::accel`]) against line `k` as [`GlobalBundle2::line`] builds it.
//! The margin `δ = 10⁻⁹ (‖c‖∞ + r + scale)` (scale: the largest endpoint coordinate) is many
//! orders of magnitude above the rounding of the projections and of the exact test, so the
//! candidates always contain the true hits, and each line gets exactly the hits
//! [`super::all_hits_naive`] and [`super::Bvh2::all_hits`] return for it, sorted the same way
//! (`t`, then `prim`): shared endpoints, lines through endpoints and segments parallel to the
//! lines are whatever the exact test says, as for a single line.
//!
//! The hits are bucketed per line by a counting sort (a difference array over the candidate
//! ranges), so a bundle of `m` lines over `n` segments costs `O(n + m + candidates)` plus a
//! short insertion sort per line: no per-line tree walk. The segments are tested in the
//! order of their midpoints' depth along the lines, kept from bundle to bundle and repaired
//! by insertion once the bundles have turned by `REORDER_TURN` (the bundles of a sheaf
//! turn by small steps), so each line's bucket fills nearly sorted and its sort moves few
//! hits: 8 % less time on the 64-squares room, none measurable on the triangle (session
//! 4, repaired every bundle); repairing it only every ~32 bundles saved another 12 %.
//!
//! [`ParallelSweep2::cast_unsorted`] skips the sort: a caller that checks the gaps between
//! consecutive hits anyway (the tally's `eps` test) knows that a line whose gaps are all
//! positive is strictly increasing in `t`, hence already in the order `(t, prim)`, and
//! sorts only the other lines ([`BundleHits2::sort_line`]): 9–12 % less time on the
//! 64-squares room (session 5), the same hits and the same results bit for bit.

use alloc::vec::Vec;

use crate::geom::{DVec2, Segment};
use crate::lines::GlobalBundle2;

use super::{Hit2, LineQuery, sort_hits};

/// Relative size of the candidate margin `δ` (see the module docs).
const MARGIN: f64 = 1e-9;

/// How far the bundles may turn (the chord between unit directions, about the angle in
/// radians) before the segments' depth order is repaired. The order only makes each
/// line's hits arrive nearly sorted, so a stale one costs a few more moves of the
/// per-line sort, while repairing it costs the depths and an insertion pass over all
/// segments. 64-squares room, 8·10⁶ lines, user time: repaired every bundle 1.04–1.06 s,
/// past a turn of 0.05: 0.96–0.97, 0.1: 0.95–0.98, 0.2: 0.92–0.96, **0.4: 0.90–0.94**,
/// 0.8: 0.90–0.92, never: 1.07–1.09. With a sheaf's 256 directions π/256 apart, 0.4
/// repairs every ~32 bundles, and at every sheaf (a new random rotation).
const REORDER_TURN: f64 = 0.4;

/// Segments prepared for bundles of parallel lines: start `a`, edge `e = b − a` (the same
/// values the naive loop tests), and the coordinate scale of the margin.
#[derive(Clone, Debug)]
pub(crate) struct ParallelSweep2 {
    a: Vec<DVec2>,
    e: Vec<DVec2>,
    scale: f64,
}

/// The hits of the lines of one bundle, bucketed per line (the caller's scratch space,
/// reused from bundle to bundle without allocating once it has grown).
#[derive(Clone, Debug, Default)]
pub(crate) struct BundleHits2 {
    /// Offsets `p_k` of the current bundle's lines.
    offsets: Vec<f64>,
    /// Origins `c + p_k n` of the current bundle's lines.
    origins: Vec<DVec2>,
    /// Candidate line range `k₀ .. k₁` of each segment.
    ranges: Vec<(u32, u32)>,
    /// Line `k`'s bucket starts at `start[k]`; `start[m]` = number of candidates.
    start: Vec<usize>,
    /// Line `k`'s bucket ends (so far) at `end[k]`.
    end: Vec<usize>,
    /// The buckets.
    hits: Vec<Hit2>,
    /// Depth `d · (midpoint − c)` of each segment along the lines of the bundle the order
    /// was last repaired for.
    depth: Vec<f64>,
    /// The segments sorted by depth, kept from bundle to bundle: the bundles of a sheaf
    /// turn by small steps, so the last order is nearly sorted for the next ones.
    order: Vec<u32>,
    /// The direction `order` was sorted for.
    order_dir: DVec2,
    /// Hits found on each segment by the last cast (indexed by segment).
    found: Vec<u32>,
}

impl ParallelSweep2 {
    /// Prepares `segments` (only the first `2³²` are considered: hit indices are `u32`).
    #[must_use]
    pub fn new(segments: &[Segment]) -> Self {
        let segments = &segments[..segments.len().min(u32::MAX as usize)];
        let a = segments.iter().map(|s| s.a).collect();
        let e = segments.iter().map(|s| s.b - s.a).collect();
        let scale = segments
            .iter()
            .map(|s| s.a.abs().max_element().max(s.b.abs().max_element()))
            .fold(0.0, f64::max);
        Self { a, e, scale }
    }

    /// Finds every hit of every line of `bundle` into `out`: afterwards
    /// [`BundleHits2::line_hits`]`(k)` is exactly [`super::all_hits_naive`] of
    /// `bundle.line(k)`.
    #[cfg(test)]
    pub fn cast(&self, bundle: &GlobalBundle2, out: &mut BundleHits2) {
        self.cast_unsorted(bundle, out);
        for k in 0..out.lines() {
            out.sort_line(k);
        }
    }

    /// [`ParallelSweep2::cast`] without the per-line sort: afterwards
    /// [`BundleHits2::line_hits`]`(k)` holds the hits of [`super::all_hits_naive`] of
    /// `bundle.line(k)` in the order they were found (the segments' depth order, nearly
    /// the order of `t`), and [`BundleHits2::sort_line`]`(k)` puts them in the order of
    /// `all_hits`. A line whose hits found are strictly increasing in `t` already is in
    /// that order (`(t, prim)` is then decided by `t` alone), which is what a caller
    /// checking the gaps between consecutive hits learns for free.
    pub(crate) fn cast_unsorted(&self, bundle: &GlobalBundle2, out: &mut BundleHits2) {
        let m = bundle.len();
        let mu = m as usize;
        let circle = bundle.circle();
        let (c, r, n) = (circle.center, circle.radius, bundle.normal());
        // The lines' offsets, as the lines themselves compute them
        out.offsets.clear();
        out.offsets.extend((0..m).map(|k| bundle.offset(k)));
        let delta = MARGIN * (c.abs().max_element() + r + self.scale);
        // Candidate ranges, counted per line in a difference array
        out.start.clear();
        out.start.resize(mu + 1, 0);
        out.ranges.clear();
        out.ranges.resize(self.a.len(), (0, 0));
        let to_k = 0.5 * f64::from(m) / r;
        let u1 = bundle.shift();
        let d = bundle.dir();
        // The depth order is repaired only when the direction has turned by more than
        // REORDER_TURN since it was last sorted (or the segments changed)
        let reorder = out.order.len() != self.a.len()
            || !((d - out.order_dir).length_squared() <= REORDER_TURN * REORDER_TURN);
        out.depth.clear();
        if reorder {
            out.depth.extend(
                self.a
                    .iter()
                    .zip(&self.e)
                    .map(|(a, e)| d.dot(*a - c) + 0.5 * d.dot(*e)),
            );
        }
        // (slices, so that their lengths and addresses stay in registers)
        let (offsets, start) = (&out.offsets[..], &mut out.start[..]);
        for ((a, e), range) in self.a.iter().zip(&self.e).zip(&mut out.ranges) {
            let pa = n.dot(*a - c);
            let pb = pa + n.dot(*e);
            // (a NaN projection gives an empty range below, or candidates the exact test
            // rejects: no hit either way)
            let (lo, hi) = if pa <= pb { (pa, pb) } else { (pb, pa) };
            let (lo, hi) = (lo - delta, hi + delta);
            let k0 = first_at_least(offsets, lo, (lo + r) * to_k - u1);
            let k1 = first_above(offsets, hi, (hi + r) * to_k - u1).max(k0);
            *range = (k0, k1);
            if let Some(s) = start.get_mut(k0 as usize) {
                *s = s.wrapping_add(1);
            }
            if let Some(s) = start.get_mut(k1 as usize) {
                *s = s.wrapping_sub(1);
            }
        }
        // Bucket starts: prefix sums of the counts (the wrapping differences add up to
        // counts ≥ 0, as every range has k₀ ≤ k₁)
        let mut running = 0usize;
        let mut total = 0usize;
        for s in &mut out.start {
            running = running.wrapping_add(*s);
            *s = total;
            total = total.wrapping_add(running);
        }
        out.end.clear();
        out.end.extend_from_slice(&out.start[..mu]);
        // Room for every candidate; what earlier bundles left there is never read (a
        // line's bucket is read up to its end, written in this bundle), so the buckets
        // are not cleared: they only grow
        if out.hits.len() < total {
            out.hits.resize(total, Hit2 { t: 0.0, prim: 0 });
        }
        // The exact test of every candidate, segment by segment in the order of their
        // midpoints' depth along the lines, so that each line's bucket fills nearly sorted
        if reorder {
            order_by_depth(&mut out.order, &out.depth);
            out.order_dir = d;
        }
        let query = LineQuery::new(c, d);
        // The lines' origins, as the lines compute them
        out.origins.clear();
        out.origins.extend(out.offsets.iter().map(|&p| c + n * p));
        out.found.clear();
        out.found.resize(self.a.len(), 0);
        let BundleHits2 {
            origins,
            ranges,
            end,
            hits,
            order,
            found,
            ..
        } = out;
        // (slices, so that the buckets' length and address stay in registers across the
        // stores)
        let (hits, end): (&mut [Hit2], &mut [usize]) = (hits, end);
        for &prim in order.iter() {
            let p = prim as usize;
            let (Some(&(k0, k1)), Some(a), Some(e), Some(found)) = (
                ranges.get(p),
                self.a.get(p),
                self.e.get(p),
                found.get_mut(p),
            ) else {
                continue;
            };
            let lines = k0 as usize..k1 as usize;
            let mut n = 0u32;
            for (&o, end) in origins[lines.clone()].iter().zip(&mut end[lines]) {
                if let Some(t) = query.with_origin(o).hit(*a, *e) {
                    hits[*end] = Hit2 { t, prim };
                    *end += 1;
                    n += 1;
                }
            }
            *found = n;
        }
    }
}

impl BundleHits2 {
    /// Empty scratch space.
    #[must_use]
    #[cfg(test)]
    pub fn new() -> Self {
        Self::default()
    }

    /// The hits of line `k` of the last bundle cast, sorted by `t` then `prim` after
    /// [`ParallelSweep2::cast`] or [`BundleHits2::sort_line`] (empty for `k` beyond the
    /// bundle).
    #[must_use]
    pub fn line_hits(&self, k: usize) -> &[Hit2] {
        match (self.start.get(k), self.end.get(k)) {
            (Some(&s), Some(&e)) => &self.hits[s..e],
            _ => &[],
        }
    }

    /// The number of hits the last cast found on each segment (indexed by segment, as
    /// [`ParallelSweep2::new`] got them), less those of the lines passed to
    /// [`BundleHits2::uncount_line`] since.
    #[must_use]
    pub fn found(&self) -> &[u32] {
        &self.found
    }

    /// Takes the hits of line `k` out of [`BundleHits2::found`] (a line the caller
    /// counts by itself); the hits stay readable.
    pub fn uncount_line(&mut self, k: usize) {
        if let (Some(&s), Some(&e)) = (self.start.get(k), self.end.get(k)) {
            for h in &self.hits[s..e] {
                if let Some(n) = self.found.get_mut(h.prim as usize) {
                    *n = n.saturating_sub(1);
                }
            }
        }
    }

    /// Number of lines of the last bundle cast.
    #[must_use]
    #[cfg(test)]
    pub fn lines(&self) -> usize {
        self.end.len()
    }

    /// Sorts the hits of line `k` by `t` then `prim` (the order of
    /// [`super::Bvh2::all_hits`]) and returns them (empty for `k` beyond the bundle).
    pub fn sort_line(&mut self, k: usize) -> &[Hit2] {
        match (self.start.get(k), self.end.get(k)) {
            (Some(&s), Some(&e)) => {
                let line = &mut self.hits[s..e];
                sort_nearly_sorted(line);
                line
            }
            _ => &[],
        }
    }
}

/// Sorts `order` (the indices `0 .. depth.len()`, reset if it is not) by `depth`: by
/// insertion while the order is nearly sorted (the bundle before turned only a little), by
/// the library sort once insertion has moved more than `8n` entries. The order only
/// decides in which order the exact tests run, never what they find.
fn order_by_depth(order: &mut Vec<u32>, depth: &[f64]) {
    let n = depth.len();
    if order.len() != n {
        order.clear();
        order.extend(0..n as u32);
    }
    let key = |i: u32| depth.get(i as usize).copied().unwrap_or(0.0);
    let mut budget = 8 * n + 8;
    for i in 1..n {
        let x = order[i];
        let kx = key(x);
        let mut j = i;
        while j > 0 && key(order[j - 1]) > kx {
            order[j] = order[j - 1];
            j -= 1;
        }
        order[j] = x;
        budget = budget.saturating_sub(i - j);
        if budget == 0 {
            order.sort_unstable_by(|&a, &b| key(a).total_cmp(&key(b)));
            return;
        }
    }
}

/// [`sort_hits`] for hits that arrive nearly sorted: insertion up to 64 hits (a few moves
/// each), the general sort beyond. The same result as [`sort_hits`]: `(t, prim)` is a
/// strict total order on one line's hits.
#[inline]
fn sort_nearly_sorted(hits: &mut [Hit2]) {
    if hits.len() > 64 {
        sort_hits(hits);
        return;
    }
    for i in 1..hits.len() {
        let h = hits[i];
        let mut j = i;
        while j > 0 && (h.t < hits[j - 1].t || (h.t == hits[j - 1].t && h.prim < hits[j - 1].prim))
        {
            hits[j] = hits[j - 1];
            j -= 1;
        }
        hits[j] = h;
    }
}

/// The index `⌊guess⌋` clamped to `0 ..= m` (NaN → 0), where a search over `m` offsets
/// starts. The clamp runs in `f64` and the conversion to `u32`: cheaper than a saturating
/// conversion to `usize` (`m ≤ 2³²`, as segment and line indices are `u32`).
#[inline]
fn start_at(guess: f64, m: usize) -> usize {
    // `max` turns NaN into 0; `as` truncates and saturates
    (guess.max(0.0).min(m as f64) as u32 as usize).min(m)
}

/// The first `k` with `offsets[k] ≥ x`, starting the search from the estimate `guess`.
#[inline]
fn first_at_least(offsets: &[f64], x: f64, guess: f64) -> u32 {
    let m = offsets.len();
    let mut k = start_at(guess, m);
    while k > 0 && offsets[k - 1] >= x {
        k -= 1;
    }
    while k < m && offsets[k] < x {
        k += 1;
    }
    k as u32
}

/// The first `k` with `offsets[k] > x`, starting the search from the estimate `guess`.
#[inline]
fn first_above(offsets: &[f64], x: f64, guess: f64) -> u32 {
    let m = offsets.len();
    let mut k = start_at(guess + 1.0, m);
    while k > 0 && offsets[k - 1] > x {
        k -= 1;
    }
    while k < m && offsets[k] <= x {
        k += 1;
    }
    k as u32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::accel::{Bvh2, all_hits_naive};
    use crate::lines::{BoundingCircle, canonical, canonical_2d, chunk_rng, sample_global_line_2d};
    use alloc::vec;
    use proptest::prelude::*;

    /// A scene-like soup: random segments, some sharing endpoints, some axis-aligned.
    fn soup(seed: u64, n: usize) -> Vec<Segment> {
        let mut rng = chunk_rng(seed, 0);
        let mut coord = || -10.0 + 20.0 * canonical(&mut rng);
        let mut segs: Vec<Segment> = Vec::with_capacity(n);
        for k in 0..n {
            let a = match segs.last() {
                Some(prev) if k % 3 == 0 => prev.b, // a shared endpoint
                _ => DVec2::new(coord(), coord()),
            };
            let b = match k % 4 {
                0 => DVec2::new(coord(), coord()),
                1 => a + DVec2::new(coord(), coord()) * 0.05,
                2 => DVec2::new(coord(), a.y),
                _ => DVec2::new(a.x, coord()),
            };
            if a != b {
                segs.push(Segment::new(a, b));
            }
        }
        segs
    }

    fn check(segs: &[Segment], circle: &BoundingCircle, u: [f64; 2], m: u32) {
        check_with(segs, circle, u, m, &mut BundleHits2::new());
    }

    /// Casts one bundle into `out` (possibly holding the depth order of earlier bundles)
    /// and compares every line with the naive loop and the BVH.
    fn check_with(
        segs: &[Segment],
        circle: &BoundingCircle,
        u: [f64; 2],
        m: u32,
        out: &mut BundleHits2,
    ) {
        let sweep = ParallelSweep2::new(segs);
        let bvh = Bvh2::build(segs).unwrap();
        let bundle = GlobalBundle2::new(circle, u, m);
        sweep.cast(&bundle, out);
        let (mut naive, mut tree) = (Vec::new(), Vec::new());
        for k in 0..m {
            let line = bundle.line(k);
            assert_eq!(
                line,
                sample_global_line_2d(circle, [u[0], bundle.canonical_offset(k)])
            );
            all_hits_naive(segs, &line, &mut naive);
            bvh.all_hits(&line, &mut tree);
            assert_eq!(
                out.line_hits(k as usize),
                &naive[..],
                "line {k} of {bundle:?}"
            );
            assert_eq!(naive, tree);
        }
        assert!(out.line_hits(m as usize).is_empty());
        // The hits found per segment: those of the lines, segment by segment
        let mut per_segment = vec![0u32; segs.len()];
        for k in 0..m as usize {
            for h in out.line_hits(k) {
                per_segment[h.prim as usize] += 1;
            }
        }
        assert_eq!(out.found(), &per_segment[..]);
        // The unsorted cast: the same hits, already in order wherever `t` strictly
        // increases, and in order once sorted
        let mut unsorted = out.clone();
        sweep.cast_unsorted(&bundle, &mut unsorted);
        assert_eq!(unsorted.lines(), m as usize);
        for k in 0..m as usize {
            let found = unsorted.line_hits(k).to_vec();
            if found.windows(2).all(|w| w[0].t < w[1].t) {
                assert_eq!(found, out.line_hits(k), "line {k}");
            }
            assert_eq!(unsorted.sort_line(k), out.line_hits(k), "line {k}");
        }
        assert!(unsorted.sort_line(m as usize).is_empty());
        assert_eq!(unsorted.found(), &per_segment[..]);
        // A line taken out of the counts: its hits leave them, and only its hits
        unsorted.uncount_line(0);
        for h in out.line_hits(0) {
            per_segment[h.prim as usize] -= 1;
        }
        assert_eq!(unsorted.found(), &per_segment[..]);
    }

    proptest! {
        /// Bundle hits equal the naive loop's and the BVH's, line by line.
        #[test]
        fn bundle_hits_equal_naive_and_bvh(
            seed in 0u64..1_000_000,
            n in 1usize..120,
            u0 in 0.0f64..1.0,
            u1 in 0.0f64..1.0,
            m in 1u32..300,
        ) {
            let segs = soup(seed, n);
            let circle = BoundingCircle::of_bounds(DVec2::splat(-10.0), DVec2::splat(10.0));
            check(&segs, &circle, [u0, u1], m);
        }

        /// The same for a sheaf: bundles turning by small steps, the scratch space (and
        /// its depth order) reused from one to the next.
        #[test]
        fn sheaf_hits_equal_naive_and_bvh(
            seed in 0u64..1_000_000,
            n in 1usize..80,
            u0 in 0.0f64..1.0,
            m in 1u32..64,
        ) {
            let segs = soup(seed, n);
            let circle = BoundingCircle::of_bounds(DVec2::splat(-10.0), DVec2::splat(10.0));
            let mut out = BundleHits2::new();
            for j in 0..8 {
                let u = [(f64::from(j) + u0) / 8.0, (u0 * 7.0 + f64::from(j) * 0.3) % 1.0];
                check_with(&segs, &circle, u, m, &mut out);
            }
        }
    }

    #[test]
    fn axis_directions_through_shared_endpoints() {
        // A grid of unit squares' edges: vertical and horizontal bundles pass exactly
        // through shared endpoints and along segments (u = 0 gives θ = 0).
        let mut segs = Vec::new();
        for i in 0..4 {
            for j in 0..4 {
                let p = DVec2::new(f64::from(i), f64::from(j));
                segs.push(Segment::new(p, p + DVec2::X));
                segs.push(Segment::new(p + DVec2::X, p + DVec2::ONE));
            }
        }
        let circle = BoundingCircle {
            center: DVec2::splat(2.0),
            radius: 4.0,
        };
        for u in [[0.0, 0.0], [0.5, 0.0], [0.25, 0.5], [0.0, 0.5], [0.5, 0.5]] {
            for m in [1, 2, 4, 8, 16, 64] {
                check(&segs, &circle, u, m);
            }
        }
        let mut rng = chunk_rng(9, 0);
        for _ in 0..50 {
            check(&segs, &circle, canonical_2d(&mut rng), 32);
        }
    }

    #[test]
    fn empty_and_degenerate_inputs() {
        let circle = BoundingCircle::of_bounds(DVec2::ZERO, DVec2::ONE);
        let sweep = ParallelSweep2::new(&[]);
        let mut out = BundleHits2::new();
        sweep.cast(&GlobalBundle2::new(&circle, [0.3, 0.7], 8), &mut out);
        assert!((0..8).all(|k| out.line_hits(k).is_empty()));
        let bad = [Segment::new(DVec2::new(f64::NAN, 0.0), DVec2::ONE)];
        ParallelSweep2::new(&bad).cast(&GlobalBundle2::new(&circle, [f64::NAN, 2.0], 0), &mut out);
        assert!(out.line_hits(0).iter().all(|h| h.t.is_finite()));
    }
}
