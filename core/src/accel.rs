//! Line queries against a flatland scene: "all hits of a line, sorted" and "first hit of a
//! ray" (thesis §2.1.6: a global line contributes to the form factors of every pair of
//! consecutive surfaces along it, Figure 2.8; a local line to the first surface it meets).
//!
//! # Overview
//!
//! - [`Bvh2`] (`alloc`): a bounding volume hierarchy over segments answering
//!   [`Bvh2::all_hits`] and [`Bvh2::first_hit`] without allocating.
//! - `all_hits_naive` (`alloc`), `first_hit_naive`: the `O(n)` loops the BVH must
//!   agree with exactly, kept as the baseline of the benchmarks and of the tests.
//!
//! # The intersection test
//!
//! Every query, naive or accelerated, runs the same arithmetic per segment `a → b`,
//! `e = b − a`, against the line `o + t d`:
//!
//! ```text
//! w = o − a,   denom = e × d,   s = (w × d) / denom       (× = 2D cross product)
//! hit  ⇔  0 ≤ s ≤ 1              (closed segment; denom = 0, parallel, never hits)
//! t = ((a + s e) − o)·d / (d·d)   (the hit point a + s e projected on the line)
//! ```
//!
//! Taking `t` from the projection of a point of the segment (rather than from the
//! equivalent `(w × e)/denom`) keeps it inside the segment's shadow on the line even for
//! grazing hits, which is what lets the BVH prune by `t` without ever disagreeing with the
//! naive loop. Collinear overlaps (`denom = 0`) are ignored: they have measure zero among
//! global and local lines. A line through a vertex shared by two segments hits both, at
//! the same `t`. Every reported `t` is finite (and never `−0`).

use crate::geom::{DVec2, Segment, cross};

#[cfg(feature = "alloc")]
mod bvh2;
mod bvh3;
#[cfg(feature = "alloc")]
mod raster3;
#[cfg(feature = "alloc")]
mod sah;
#[cfg(feature = "alloc")]
mod sweep2;
#[cfg(all(test, feature = "std"))]
mod tests;

#[cfg(feature = "alloc")]
pub use bvh2::Bvh2;
#[cfg(feature = "alloc")]
pub(crate) use bvh2::MAX_PRIMITIVES;
#[cfg(feature = "alloc")]
pub use bvh3::Bvh3;
#[cfg(feature = "alloc")]
pub(crate) use bvh3::all_hits_naive3;

pub use bvh3::Hit3;
pub(crate) use bvh3::first_hit_naive3;
#[cfg(feature = "alloc")]
pub(crate) use raster3::BundleHits3;
#[cfg(feature = "alloc")]
pub(crate) use raster3::ParallelRaster3;
#[cfg(feature = "alloc")]
pub(crate) use sweep2::{BundleHits2, ParallelSweep2};

#[cfg(feature = "alloc")]
use crate::lines::Line2;
#[cfg(feature = "alloc")]
use alloc::vec::Vec;

/// One intersection of a line with a segment: the line parameter `t` of the hit point
/// `origin + t·dir` and the segment's index `prim` in the slice the query was built from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit2 {
    /// Line parameter of the hit (a signed distance when `dir` is a unit vector).
    pub t: f64,
    /// Index of the segment hit.
    pub prim: u32,
}

impl Hit2 {
    /// Every intersection of the infinite `line` with a segment of `segments`, sorted by `t`
    /// then `prim`, written into `out` (cleared first): the `O(n)` baseline of
    /// [`Bvh2::all_hits`], which returns exactly the same hits in the same order.
    ///
    /// Only the first `2³²` segments are considered (hit indices are `u32`).
    #[cfg(feature = "alloc")]
    pub fn all_naive(segments: &[Segment], line: &Line2, out: &mut Vec<Hit2>) {
        all_hits_naive(segments, line, out);
    }

    /// The order of [`Bvh2::all_hits`]: by `t`, then by `prim`.
    #[inline]
    #[must_use]
    pub fn cmp_t_prim(&self, other: &Self) -> core::cmp::Ordering {
        self.t.total_cmp(&other.t).then(self.prim.cmp(&other.prim))
    }
}

/// Sorts hits by `(t, prim)` — a strict total order on hits, as every `prim` appears at
/// most once, so any sort gives the same result. Lines meet a few segments each, so short
/// lists get an inlined insertion sort (the library sort's call costs as much as the
/// sorting).
#[cfg(feature = "alloc")]
#[inline]
pub(crate) fn sort_hits<H: HitKey>(hits: &mut [H]) {
    if hits.len() > 16 {
        hits.sort_unstable_by(|a, b| a.t().total_cmp(&b.t()).then(a.prim().cmp(&b.prim())));
        return;
    }
    for i in 1..hits.len() {
        let h = hits[i];
        let mut j = i;
        // Plain comparisons: every `t` is finite and never −0, where they agree with
        // `cmp_t_prim`'s total order.
        while j > 0
            && (h.t() < hits[j - 1].t()
                || (h.t() == hits[j - 1].t() && h.prim() < hits[j - 1].prim()))
        {
            hits[j] = hits[j - 1];
            j -= 1;
        }
        hits[j] = h;
    }
}

/// What [`sort_hits`] orders by, and what the tallies read: the line parameter, then the
/// primitive (2D and 3D hits).
#[cfg(feature = "alloc")]
pub(crate) trait HitKey: Copy {
    /// Line parameter of the hit.
    fn t(&self) -> f64;
    /// Index of the primitive hit.
    fn prim(&self) -> u32;
}

#[cfg(feature = "alloc")]
impl HitKey for Hit2 {
    #[inline]
    fn t(&self) -> f64 {
        self.t
    }
    #[inline]
    fn prim(&self) -> u32 {
        self.prim
    }
}

/// A line prepared for many segment tests: origin `o`, direction `d` and `1/(d·d)`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct LineQuery {
    pub(crate) o: DVec2,
    pub(crate) d: DVec2,
    inv_dd: f64,
}

impl LineQuery {
    #[inline]
    pub(crate) fn new(o: DVec2, d: DVec2) -> Self {
        Self {
            o,
            d,
            inv_dd: 1.0 / d.length_squared(),
        }
    }

    /// The same direction from another origin (the lines of a bundle: `1/(d·d)` is
    /// shared, with the bits [`LineQuery::new`] computes).
    #[cfg(feature = "alloc")]
    #[inline]
    pub(crate) fn with_origin(&self, o: DVec2) -> Self {
        Self { o, ..*self }
    }

    /// The line parameter where the line meets the closed segment `a → a + e`, if it does
    /// (see the module docs for the formulas). Always finite.
    #[inline(always)]
    pub(crate) fn hit(&self, a: DVec2, e: DVec2) -> Option<f64> {
        let denom = cross(e, self.d);
        let w = self.o - a;
        let s = cross(w, self.d) / denom;
        // NaN (denom = 0 with w × d = 0, or NaN input) and ±∞ (parallel) fail here.
        if !(0.0..=1.0).contains(&s) {
            return None;
        }
        // Project the hit point on the line; `+ 0.0` turns −0 into +0.
        let t = (a + e * s - self.o).dot(self.d) * self.inv_dd + 0.0;
        if t.is_finite() { Some(t) } else { None }
    }
}

/// Every intersection of the infinite `line` with a segment of `segments`, sorted by `t`
/// then `prim`, written into `out` (cleared first): the `O(n)` baseline of
/// [`Bvh2::all_hits`], which returns exactly the same hits in the same order.
///
/// Only the first `2³²` segments are considered (hit indices are `u32`).
#[cfg(feature = "alloc")]
pub(crate) fn all_hits_naive(segments: &[Segment], line: &Line2, out: &mut Vec<Hit2>) {
    out.clear();
    let q = LineQuery::new(line.origin, line.dir);
    for (s, prim) in segments.iter().zip(0..=u32::MAX) {
        if let Some(t) = q.hit(s.a, s.b - s.a) {
            out.push(Hit2 { t, prim });
        }
    }
    sort_hits(out);
}

/// The nearest hit with `t > t_min` along the ray `origin + t·dir`, the smallest `prim`
/// among equally near ones: the `O(n)` baseline of [`Bvh2::first_hit`], which returns
/// exactly the same hit. Needs no allocator.
///
/// Only the first `2³²` segments are considered (hit indices are `u32`).
#[must_use]
pub(crate) fn first_hit_naive(
    segments: &[Segment],
    origin: DVec2,
    dir: DVec2,
    t_min: f64,
) -> Option<Hit2> {
    let q = LineQuery::new(origin, dir);
    let mut best: Option<Hit2> = None;
    for (s, prim) in segments.iter().zip(0..=u32::MAX) {
        if let Some(t) = q.hit(s.a, s.b - s.a) {
            // Strictly nearer wins; ties keep the earlier (smaller) prim.
            if t > t_min && best.is_none_or(|b| t < b.t) {
                best = Some(Hit2 { t, prim });
            }
        }
    }
    best
}
