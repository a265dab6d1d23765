//! A bounding volume hierarchy over flatland segments.
//!
//! # Layout
//!
//! A binary tree flattened depth-first into one `Vec` of 32-byte nodes (pbrt's
//! `LinearBVHNode`): a node's first child is the next node, the second child is at an
//! explicit index. Each node stores its box as an `f64` centre and `f32` half-extents
//! rounded *up*, so the stored box always contains the true one. Leaves index a range of
//! *runs*, stored in leaf order.
//!
//! # Runs
//!
//! A surface cut into `k` patches gives `k` consecutive, contiguous, collinear segments;
//! the tree holds such a chain as one primitive, a *run* (a lone segment is a run of one).
//! Against a line `o + t d` a run is first tested by the side of its two ends — both
//! farther than the margin `m` (below) on one side means no patch is hit — and otherwise
//! the line meets the run's supporting segment `A + σE` at
//!
//! ```text
//! σ* = ((o − A) × d) / (E × d),   δ = 10⁻⁹ (‖o − A‖₁ + ‖A‖₁ + ‖E‖₁) ‖d‖₁ / |E × d|
//! ```
//!
//! and only the patches whose interval `[σ_a, σ_b]` along `E` meets `[σ* − δ, σ* + δ]` go
//! through the exact per-segment test: for equal patches `k = ⌊σ* m⌋` (± the window),
//! otherwise a binary search over the `σ_b`. When `δ` is not small (a line grazing the
//! run, or NaN) every patch of the run is tested. `δ` bounds, with six orders of magnitude
//! to spare, both the rounding of `σ*` and the shift of the crossing caused by the
//! patches' deviation from exact collinearity, which the build checks to be below `10⁻¹²`
//! of the run's size. A surface of `k` patches thus costs one box path and `O(1)` (equal
//! patches) or `O(log k)` work instead of a subtree walk of `O(log k)` box tests — the
//! common case of the thesis' scenes, whose surfaces are cut into equal patches.
//!
//! # Build
//!
//! Binned surface-area heuristic (Wald 2007) over the runs' centroids, 16 bins along the
//! axis of widest centroid extent. In flatland the "surface area" of a box is its
//! perimeter, and this is exact for our queries: by Crofton's formula the probability that
//! a uniform line meeting a parent box also meets a child box is
//! `perimeter(child)/perimeter(parent)` (see [`crate::lines`]). Below depth 32 splits
//! follow the SAH; deeper (only reached on adversarial input) they are median splits,
//! which halve the count, so the depth stays below `32 + 31 < 64`, the size of the
//! queries' fixed stacks. The build uses an explicit work stack, no recursion, and costs
//! `O(n log n)`.
//!
//! # Queries
//!
//! A node is entered when the line passes within the box's half-width of its centre,
//!
//! ```text
//! |n·(c − o)| ≤ |n|·h + m,     n = d^⊥,  |n| componentwise
//! ```
//!
//! with `m = 10⁻⁹ (‖o‖∞ + scale) ‖d‖₁`, a margin many orders of magnitude above the
//! rounding of both this test and the segment test, so a segment the naive loop reports is
//! never culled. `first_hit` also culls by the box's extent along `d`, `d·(c − o) ± |d|·h`,
//! against `(t_min, t_best]`, and visits the nearer child first.

use alloc::vec::Vec;
use core::fmt;

use crate::error::{Error, ErrorKind, Result};
use crate::geom::{DVec2, Segment, cross};
use crate::lines::Line2;

use super::sah::{BINS, SahBox, best_plane, bin_of};
use super::{Hit2, LineQuery};

/// Most primitives a [`Bvh2`] accepts: `u32::MAX / 2`, so node indices (< 2n) fit `u32`.
pub(crate) const MAX_PRIMITIVES: usize = (u32::MAX / 2) as usize;

/// Depth below which splits follow the SAH; median splits beyond.
const SAH_DEPTH: u32 = 32;

/// Capacity of the traversal stacks: more than the deepest possible tree
/// (`SAH_DEPTH` + 31 median levels for at most 2³¹ primitives).
const STACK_SIZE: usize = 64;

/// Most primitives in a leaf (more are always split).
const MAX_LEAF: usize = 4;

/// SAH cost of one node visit, relative to one segment test.
const TRAVERSAL_COST: f64 = 1.0;

/// Relative size of the culling margin (see the module docs).
const MARGIN: f64 = 1e-9;

/// Relative size of a run's search window `δ` (see the module docs).
const RUN_SLACK: f64 = 1e-9;

/// Largest deviation from collinearity, relative to the run's size, accepted in a run.
const RUN_COLLINEAR: f64 = 1e-12;

/// Runs up to this length are tested patch by patch, without the search.
const SHORT_RUN: u32 = 4;

/// One node: box centre (`f64`) and half-extents (`f32`, rounded up), then either the
/// first primitive and the count (leaf) or the second child and the split axis (interior).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
struct Node {
    center: DVec2,
    half: [f32; 2],
    /// Leaf: index of the first primitive. Interior: index of the second child.
    offset: u32,
    /// `count << 1 | axis`: `count` = number of primitives, 0 for an interior node;
    /// `axis` = the split axis (0 = x, 1 = y) of an interior node.
    meta: u32,
}

/// A segment prepared for the intersection test: start `a`, edge `e = b − a`.
#[derive(Clone, Copy, Debug)]
struct Prim {
    a: DVec2,
    e: DVec2,
}

/// A chain of contiguous collinear segments `first .. first + len` (indices into the
/// prepared primitives), spanning `A + σE`, `σ ∈ [0, 1]`.
#[derive(Clone, Copy, Debug)]
struct Run {
    a: DVec2,
    e: DVec2,
    first: u32,
    len: u32,
    /// `len` when the patches are equal to within `tau` (`σ_a,k ≈ k/len`), else 0.
    uniform: f64,
    /// Largest deviation of the patch bounds from `k/len` (uniform runs only).
    tau: f64,
}

/// A bounding volume hierarchy over flatland segments, answering "every hit of a line,
/// sorted" ([`Bvh2::all_hits`]) and "nearest hit of a ray" ([`Bvh2::first_hit`]).
///
/// Queries allocate nothing (the caller's `Vec` is reused) and recurse nowhere (a
/// fixed-size stack); for segments and lines with coordinates below `10¹⁵⁰` in magnitude
/// they return exactly what `super::all_hits_naive` and `super::first_hit_naive`
/// return, in the same order — the naive loops run the same per-segment arithmetic, and
/// the tree only ever culls with a wide margin.
///
/// # Examples
///
/// ```
/// use sceneinfo::accel::{Bvh2, Hit2};
/// use sceneinfo::geom::{DVec2, Segment};
/// use sceneinfo::lines::Line2;
///
/// let square = [
///     Segment::new(DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0)),
///     Segment::new(DVec2::new(1.0, 0.0), DVec2::new(1.0, 1.0)),
///     Segment::new(DVec2::new(1.0, 1.0), DVec2::new(0.0, 1.0)),
///     Segment::new(DVec2::new(0.0, 1.0), DVec2::new(0.0, 0.0)),
/// ];
/// let bvh = Bvh2::build(&square).unwrap();
/// let mut hits = Vec::new();
/// bvh.all_hits(&Line2::new(DVec2::new(-1.0, 0.5), DVec2::X), &mut hits);
/// assert_eq!(hits, [Hit2 { t: 1.0, prim: 3 }, Hit2 { t: 2.0, prim: 1 }]);
/// let first = bvh.first_hit(DVec2::new(0.5, 0.5), DVec2::Y, 1e-9).unwrap();
/// assert_eq!((first.t, first.prim), (0.5, 2));
/// ```
#[derive(Clone)]
pub struct Bvh2 {
    nodes: Vec<Node>,
    runs: Vec<Run>,
    prims: Vec<Prim>,
    /// `[σ_a, σ_b]` of each primitive along its run (`[0, 1]` for runs of one).
    sigma: Vec<[f64; 2]>,
    ids: Vec<u32>,
    /// Largest coordinate magnitude of any endpoint (`∞` if any is infinite).
    scale: f64,
    depth: u32,
}

impl fmt::Debug for Bvh2 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Bvh2")
            .field("primitives", &self.prims.len())
            .field("runs", &self.runs.len())
            .field("nodes", &self.nodes.len())
            .field("depth", &self.depth)
            .finish()
    }
}

/// A primitive during the build: its box, centroid and original index.
#[derive(Clone, Copy, Debug)]
struct BuildPrim {
    lo: DVec2,
    hi: DVec2,
    centroid: DVec2,
    id: u32,
}

/// A pending subtree: primitives `start..end`, its depth, and the parent whose second
/// child it is (`u32::MAX` for the root and for first children).
#[derive(Clone, Copy, Debug)]
struct Task {
    start: usize,
    end: usize,
    depth: u32,
    parent: u32,
}

/// An axis-aligned box accumulated with `f64::min`/`max`, which skip NaN.
#[derive(Clone, Copy, Debug)]
struct Aabb {
    lo: DVec2,
    hi: DVec2,
}

impl Aabb {
    const EMPTY: Self = Self {
        lo: DVec2::INFINITY,
        hi: DVec2::NEG_INFINITY,
    };

    #[inline]
    fn grow(&mut self, lo: DVec2, hi: DVec2) {
        self.lo = DVec2::new(self.lo.x.min(lo.x), self.lo.y.min(lo.y));
        self.hi = DVec2::new(self.hi.x.max(hi.x), self.hi.y.max(hi.y));
    }

    #[inline]
    fn merged(mut self, other: &Self) -> Self {
        self.grow(other.lo, other.hi);
        self
    }

    /// Perimeter (the 2D "surface area" of the SAH); 0 for an empty box.
    #[inline]
    fn perimeter(&self) -> f64 {
        let d = self.hi - self.lo;
        if d.x >= 0.0 && d.y >= 0.0 {
            2.0 * (d.x + d.y)
        } else {
            0.0
        }
    }
}

impl SahBox for Aabb {
    const EMPTY: Self = Self::EMPTY;

    #[inline]
    fn merged(self, other: &Self) -> Self {
        Aabb::merged(self, other)
    }

    #[inline]
    fn measure(&self) -> f64 {
        self.perimeter()
    }
}

impl BuildPrim {
    /// The primitive's box.
    #[inline]
    fn bounds(&self) -> Aabb {
        Aabb {
            lo: self.lo,
            hi: self.hi,
        }
    }
}

/// `x` rounded up to an `f32` (`+∞` beyond its range; NaN stays NaN).
#[inline]
fn f32_up(x: f64) -> f32 {
    let y = x as f32;
    if f64::from(y) < x { y.next_up() } else { y }
}

impl Node {
    /// The node for box `b`: centre and rounded-up half-extents. A box that is empty,
    /// infinite or NaN becomes the whole plane (centre 0, half-extents ∞), which culls
    /// nothing — conservative, so queries still match the naive loop.
    fn new(b: &Aabb, offset: u32, meta: u32) -> Self {
        let center = b.lo * 0.5 + b.hi * 0.5;
        let half = DVec2::new(
            (b.hi.x - center.x).max(center.x - b.lo.x),
            (b.hi.y - center.y).max(center.y - b.lo.y),
        );
        let (center, half) =
            if center.is_finite() && half.is_finite() && half.cmpge(DVec2::ZERO).all() {
                (center, [f32_up(half.x), f32_up(half.y)])
            } else {
                (DVec2::ZERO, [f32::INFINITY; 2])
            };
        Self {
            center,
            half,
            offset,
            meta,
        }
    }
}

/// Per-query constants of the box tests.
#[derive(Clone, Copy, Debug)]
struct BoxQuery {
    o: DVec2,
    /// Normal of the line, `d^⊥ = (−d.y, d.x)`.
    n: DVec2,
    /// `|n|` componentwise.
    abs_n: DVec2,
    /// `|d|` componentwise.
    abs_d: DVec2,
    margin: f64,
}

impl BoxQuery {
    #[inline]
    fn new(o: DVec2, d: DVec2, scale: f64) -> Self {
        let extent = o.x.abs().max(o.y.abs()) + scale;
        let margin = MARGIN * extent * (d.x.abs() + d.y.abs()) + f64::MIN_POSITIVE;
        Self {
            o,
            n: DVec2::new(-d.y, d.x),
            abs_n: DVec2::new(d.y.abs(), d.x.abs()),
            abs_d: d.abs(),
            margin,
        }
    }

    /// Whether the line may meet the node's box (`true` when unsure).
    #[inline(always)]
    fn line_meets(&self, node: &Node) -> bool {
        let rel = node.center - self.o;
        let dist = self.n.x * rel.x + self.n.y * rel.y;
        let reach = self.abs_n.x * f64::from(node.half[0]) + self.abs_n.y * f64::from(node.half[1]);
        // Negated so that NaN (an unbounded node, a NaN line) visits: culling must only
        // ever be sure.
        !(dist.abs() > reach + self.margin)
    }
}

impl Bvh2 {
    /// Builds the hierarchy over `segments`; hits report indices into this slice.
    ///
    /// `O(n log n)` time, `O(n)` memory. Any input is accepted — degenerate, coincident,
    /// NaN or infinite segments included (they simply never produce a hit the naive loop
    /// would not).
    ///
    /// # Errors
    ///
    /// [`ErrorKind::TooLarge`] for more than `MAX_PRIMITIVES` segments.
    pub fn build(segments: &[Segment]) -> Result<Self> {
        let n = segments.len();
        if n > MAX_PRIMITIVES {
            return Err(Error::new(ErrorKind::TooLarge {
                what: "BVH primitive count",
                max: MAX_PRIMITIVES as u64,
            }));
        }
        // Scale of the margin, then runs and their boxes
        let mut scale: f64 = 0.0;
        for s in segments {
            scale = scale
                .max(s.a.abs().max_element())
                .max(s.b.abs().max_element());
        }
        let spans = find_runs(segments);
        let mut build: Vec<BuildPrim> = Vec::with_capacity(spans.len());
        for (span, id) in spans.iter().zip(0u32..) {
            let mut b = Aabb::EMPTY;
            for s in &segments[span.0 as usize..span.1 as usize] {
                let (lo, hi) = s.bounds();
                b.grow(lo, hi);
            }
            build.push(BuildPrim {
                lo: b.lo,
                hi: b.hi,
                centroid: b.lo * 0.5 + b.hi * 0.5,
                id,
            });
        }
        let n_runs = build.len();
        let mut bvh = Self {
            nodes: Vec::with_capacity((2 * n_runs).saturating_sub(1)),
            runs: Vec::with_capacity(n_runs),
            prims: Vec::with_capacity(n),
            sigma: Vec::with_capacity(n),
            ids: Vec::with_capacity(n),
            scale,
            depth: 0,
        };
        if n == 0 {
            return Ok(bvh);
        }

        // Depth-first construction with an explicit stack: a first child is always
        // popped right after its parent, so it lands at the parent's index + 1.
        let mut tasks: Vec<Task> = Vec::with_capacity(2 * STACK_SIZE);
        tasks.push(Task {
            start: 0,
            end: n_runs,
            depth: 0,
            parent: u32::MAX,
        });
        while let Some(task) = tasks.pop() {
            let index = bvh.nodes.len() as u32;
            if task.parent != u32::MAX {
                bvh.nodes[task.parent as usize].offset = index;
            }
            bvh.depth = bvh.depth.max(task.depth);
            let items = &mut build[task.start..task.end];
            let mut bounds = Aabb::EMPTY;
            for p in items.iter() {
                bounds.grow(p.lo, p.hi);
            }
            match split(items, &bounds, task.depth) {
                None => {
                    // Leaf: append its runs, and their segments, in leaf order
                    let first = bvh.runs.len() as u32;
                    for p in items.iter() {
                        bvh.push_run(segments, spans[p.id as usize]);
                    }
                    let count = items.len() as u32;
                    bvh.nodes.push(Node::new(&bounds, first, count << 1));
                }
                Some((mid, axis)) => {
                    // Interior: the second child patches our offset when it is built
                    bvh.nodes.push(Node::new(&bounds, 0, axis));
                    let mid = task.start + mid;
                    tasks.push(Task {
                        start: mid,
                        end: task.end,
                        depth: task.depth + 1,
                        parent: index,
                    });
                    tasks.push(Task {
                        start: task.start,
                        end: mid,
                        depth: task.depth + 1,
                        parent: u32::MAX,
                    });
                }
            }
        }
        debug_assert!((bvh.depth as usize) < STACK_SIZE);
        debug_assert_eq!(bvh.prims.len(), n);
        debug_assert_eq!(bvh.sigma.len(), n);
        Ok(bvh)
    }

    /// Appends the run of segments `span.0 .. span.1` (validated by [`find_runs`]).
    fn push_run(&mut self, segments: &[Segment], span: (u32, u32)) {
        let chain = &segments[span.0 as usize..span.1 as usize];
        let (a, e) = run_frame(chain);
        let inv_ee = 1.0 / e.length_squared();
        let first = self.prims.len();
        let m = chain.len() as f64;
        let mut tau: f64 = 0.0;
        for ((s, id), k) in chain.iter().zip(span.0..).zip(0u32..) {
            self.prims.push(Prim {
                a: s.a,
                e: s.b - s.a,
            });
            let sigma = if chain.len() == 1 {
                [0.0, 1.0]
            } else {
                [(s.a - a).dot(e) * inv_ee, (s.b - a).dot(e) * inv_ee]
            };
            let k = f64::from(k);
            tau = tau
                .max((sigma[0] - k / m).abs())
                .max((sigma[1] - (k + 1.0) / m).abs());
            self.sigma.push(sigma);
            self.ids.push(id);
        }
        // Equal patches (to a hundredth of one) are located by arithmetic, not search
        let uniform = tau <= 0.01 / m;
        self.runs.push(Run {
            a,
            e,
            first: first as u32,
            len: span.1 - span.0,
            uniform: if uniform { m } else { 0.0 },
            tau: if uniform { tau } else { 0.0 },
        });
    }

    /// The primitives of `run` that `q`'s line may meet (module docs, "Runs"): none when
    /// both ends of the run lie beyond `margin` on one side of the line; else all of a
    /// short run, or those whose interval along the run meets `[σ* − δ, σ* + δ]`.
    #[inline(always)]
    fn run_candidates(&self, run: &Run, q: &LineQuery, margin: f64) -> core::ops::Range<usize> {
        let first = run.first as usize;
        let end = first + run.len as usize;
        // Side of each end, times |d|: (A − o) × ... = w × d at A, and w × d − E × d at B
        let denom = cross(run.e, q.d);
        let w = q.o - run.a;
        let num = cross(w, q.d);
        let num_b = num - denom;
        if (num > margin && num_b > margin) || (num < -margin && num_b < -margin) {
            return first..first;
        }
        if run.len <= SHORT_RUN {
            return first..end;
        }
        let l1 = |v: DVec2| v.x.abs() + v.y.abs();
        let inv = 1.0 / denom;
        let s = num * inv;
        let delta = RUN_SLACK * (l1(w) + l1(run.a) + l1(run.e)) * l1(q.d) * inv.abs();
        // Grazing (δ not small), parallel (δ = ∞) or NaN: test every patch.
        if !(delta < 0.25) {
            return first..end;
        }
        if run.uniform > 0.0 {
            // [σ_a,k, σ_b,k] ⊆ [k/m − τ, (k+1)/m + τ] meets [s − δ, s + δ] only for
            // ⌈(s − δ − τ)m − 1⌉ ≤ k ≤ ⌊(s + δ + τ)m⌋ (with a rounding guard in τ). Both
            // bounds are clamped into [0, m] before the (then exact) conversion.
            let m = run.uniform;
            let reach = delta + run.tau + 1e-12;
            let x = ((s - reach) * m - 1.0).clamp(0.0, m);
            let lo = x as u32 + u32::from(f64::from(x as u32) < x);
            let hi = ((s + reach) * m).clamp(0.0, m - 1.0) as u32 + 1;
            return first + lo as usize..first + (hi.max(lo)) as usize;
        }
        let sigma = &self.sigma[first..end];
        let lo = sigma.partition_point(|x| x[1] < s - delta);
        let mut hi = lo;
        while hi < sigma.len() && sigma[hi][0] <= s + delta {
            hi += 1;
        }
        first + lo..first + hi
    }

    /// Number of segments.
    #[inline]
    #[must_use]
    pub fn len(&self) -> usize {
        self.prims.len()
    }

    /// Whether the hierarchy holds no segment.
    #[inline]
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.prims.is_empty()
    }

    /// Number of nodes (`2n − 1` at most).
    #[inline]
    #[must_use]
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Depth of the deepest leaf (0 for a single leaf); always below 64.
    #[inline]
    #[must_use]
    pub fn depth(&self) -> u32 {
        self.depth
    }

    /// Calls `f` once for every intersection of the infinite `line` with a segment, in no
    /// particular order (see [`Bvh2::all_hits`] for the sorted form). Allocates nothing.
    #[inline]
    pub fn for_each_hit<F: FnMut(Hit2)>(&self, line: &Line2, mut f: F) {
        if self.nodes.is_empty() {
            return;
        }
        let q = LineQuery::new(line.origin, line.dir);
        let bq = BoxQuery::new(line.origin, line.dir, self.scale);
        let mut stack = [0u32; STACK_SIZE];
        let mut sp = 0usize;
        let mut index = 0usize;
        loop {
            // Visit the node if the line meets its box
            let node = &self.nodes[index];
            if bq.line_meets(node) {
                let count = (node.meta >> 1) as usize;
                if count == 0 {
                    stack[sp] = node.offset;
                    sp += 1;
                    index += 1;
                    continue;
                }
                let first = node.offset as usize;
                for run in &self.runs[first..first + count] {
                    for k in self.run_candidates(run, &q, bq.margin) {
                        let p = &self.prims[k];
                        if let Some(t) = q.hit(p.a, p.e) {
                            f(Hit2 {
                                t,
                                prim: self.ids[k],
                            });
                        }
                    }
                }
            }
            // Next pending node
            if sp == 0 {
                break;
            }
            sp -= 1;
            index = stack[sp] as usize;
        }
    }

    /// Every intersection of the infinite `line` with a (closed) segment, sorted by `t`
    /// then `prim`; collinear overlaps ignored. Clears `out` first and only grows it, so a
    /// reused `out` makes the query allocation-free.
    ///
    /// Along a global line through a closed scene the consecutive hits pair up into the
    /// segments of Figure 2.8 of the thesis, each contributing to two form factors (2.37).
    pub fn all_hits(&self, line: &Line2, out: &mut Vec<Hit2>) {
        out.clear();
        self.for_each_hit(line, |h| out.push(h));
        super::sort_hits(out);
    }

    /// The nearest hit with `t > t_min` along the ray `origin + t·dir` (the smallest
    /// `prim` among equally near ones); `t_min > 0` skips the surface the ray leaves from.
    /// This is the query of local lines, estimator (2.36).
    #[must_use]
    pub fn first_hit(&self, origin: DVec2, dir: DVec2, t_min: f64) -> Option<Hit2> {
        if self.nodes.is_empty() {
            return None;
        }
        let q = LineQuery::new(origin, dir);
        let bq = BoxQuery::new(origin, dir, self.scale);
        let dd = dir.length_squared();
        let lo_limit = t_min * dd - bq.margin;
        let mut best_t = f64::INFINITY;
        let mut best_prim = u32::MAX;
        let mut stack = [0u32; STACK_SIZE];
        let mut sp = 0usize;
        let mut index = 0usize;
        loop {
            // Visit the node if the ray's live part (t_min, best_t] may meet its box
            let node = &self.nodes[index];
            let rel = node.center - origin;
            let along = dir.dot(rel);
            let reach = bq.abs_d.x * f64::from(node.half[0]) + bq.abs_d.y * f64::from(node.half[1]);
            let hi_limit = best_t * dd + bq.margin;
            if bq.line_meets(node) && !(along + reach < lo_limit) && !(along - reach > hi_limit) {
                let count = (node.meta >> 1) as usize;
                if count == 0 {
                    // Nearer child first
                    let axis = (node.meta & 1) as usize;
                    let second = node.offset;
                    if dir[axis] < 0.0 {
                        stack[sp] = index as u32 + 1;
                        index = second as usize;
                    } else {
                        stack[sp] = second;
                        index += 1;
                    }
                    sp += 1;
                    continue;
                }
                let first = node.offset as usize;
                for run in &self.runs[first..first + count] {
                    for k in self.run_candidates(run, &q, bq.margin) {
                        let p = &self.prims[k];
                        if let Some(t) = q.hit(p.a, p.e) {
                            let prim = self.ids[k];
                            if t > t_min && (t < best_t || (t == best_t && prim < best_prim)) {
                                best_t = t;
                                best_prim = prim;
                            }
                        }
                    }
                }
            }
            if sp == 0 {
                break;
            }
            sp -= 1;
            index = stack[sp] as usize;
        }
        (best_prim != u32::MAX).then_some(Hit2 {
            t: best_t,
            prim: best_prim,
        })
    }
}

/// The frame `(A, E)` of a chain: from the first start to the last end.
fn run_frame(chain: &[Segment]) -> (DVec2, DVec2) {
    match (chain.first(), chain.last()) {
        (Some(f), Some(l)) => (f.a, l.b - f.a),
        _ => (DVec2::ZERO, DVec2::ZERO),
    }
}

/// Cuts `segments` into runs `(start, end)`: maximal chains of consecutive segments, each
/// starting exactly where the previous one ends, in the same direction, whose endpoints
/// all lie within `10⁻¹²` of the chain's size from its supporting line and advance along
/// it. A chain that fails the check is split into runs of one.
fn find_runs(segments: &[Segment]) -> Vec<(u32, u32)> {
    let n = segments.len() as u32;
    let mut spans = Vec::new();
    let mut i = 0u32;
    while i < n {
        // Grow the chain while contiguous and parallel
        let t0 = segments[i as usize].tangent();
        let mut j = i + 1;
        while j < n {
            let (prev, next) = (&segments[j as usize - 1], &segments[j as usize]);
            let t = next.tangent();
            if next.a != prev.b || !(cross(t0, t).abs() <= 1e-9 && t0.dot(t) > 0.0) {
                break;
            }
            j += 1;
        }
        if j - i > 1 && chain_is_straight(&segments[i as usize..j as usize]) {
            spans.push((i, j));
        } else {
            spans.extend((i..j).map(|k| (k, k + 1)));
        }
        i = j;
    }
    spans
}

/// Whether every endpoint of `chain` lies within `RUN_COLLINEAR` of the chain's size from
/// its frame's line, with the projections non-decreasing along it.
fn chain_is_straight(chain: &[Segment]) -> bool {
    let (a, e) = run_frame(chain);
    let len = e.length();
    let size = a.abs().max_element() + e.abs().max_element();
    if !(len > 0.0 && size.is_finite()) {
        return false;
    }
    let tol = RUN_COLLINEAR * size;
    let mut last = f64::NEG_INFINITY;
    for s in chain {
        for p in [s.a, s.b] {
            let along = (p - a).dot(e);
            if !((cross(e, p - a) / len).abs() <= tol && along >= last) {
                return false;
            }
            last = along;
        }
    }
    true
}

/// Chooses how to split `items` (in place): `None` for a leaf, or `Some((mid, axis))`
/// with `items[..mid]` the first child, `items[mid..]` the second, `0 < mid < len`.
fn split(items: &mut [BuildPrim], bounds: &Aabb, depth: u32) -> Option<(usize, u32)> {
    let n = items.len();
    if n <= 1 {
        return None;
    }
    // Centroid bounds pick the axis of the median split and the bins of the SAH
    let mut cb = Aabb::EMPTY;
    for p in items.iter() {
        cb.grow(p.centroid, p.centroid);
    }
    let extent = cb.hi - cb.lo;
    let axis = usize::from(extent.y > extent.x);
    if depth < SAH_DEPTH
        && let Some(choice) = sah_split(items, bounds, &cb, axis)
    {
        return choice;
    }
    if n <= MAX_LEAF {
        return None;
    }
    Some((median_split(items, axis), axis as u32))
}

/// The binned SAH's choice along `axis` (that of the widest centroid extent, as in pbrt):
/// `Some(None)` = make a leaf, `Some(Some(split))` = split there (already partitioned),
/// `None` = no usable split (all centroids in one bin).
#[allow(clippy::option_option)]
fn sah_split(
    items: &mut [BuildPrim],
    bounds: &Aabb,
    cb: &Aabb,
    axis: usize,
) -> Option<Option<(usize, u32)>> {
    let n = items.len();
    let parent = bounds.perimeter();
    let (lo, width) = (cb.lo[axis], cb.hi[axis] - cb.lo[axis]);
    if !(width > 0.0 && width.is_finite()) {
        return None;
    }
    let inv = BINS as f64 / width;
    let (cost, plane) = best_plane(items, |p| p.centroid[axis], |p| p.bounds(), lo, inv)?;
    // SAH: C = C_trav + Σ P(child) n_child, P(child) = perimeter(child)/perimeter(parent)
    let split_cost = if parent > 0.0 && parent.is_finite() {
        TRAVERSAL_COST + cost / parent
    } else {
        f64::NAN
    };
    if n <= MAX_LEAF && !(split_cost < n as f64) {
        return Some(None);
    }
    let mid = partition(items, |p| bin_of(p.centroid[axis], lo, inv) < plane);
    if mid == 0 || mid == n {
        return None;
    }
    Some(Some((mid, axis as u32)))
}

/// Moves the items satisfying `left` to the front; returns how many there are.
fn partition<F: Fn(&BuildPrim) -> bool>(items: &mut [BuildPrim], left: F) -> usize {
    let mut mid = 0;
    for k in 0..items.len() {
        if left(&items[k]) {
            items.swap(mid, k);
            mid += 1;
        }
    }
    mid
}

/// Splits at the median centroid along `axis`: halves the count, whatever the geometry.
fn median_split(items: &mut [BuildPrim], axis: usize) -> usize {
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |p, q| p.centroid[axis].total_cmp(&q.centroid[axis]));
    mid
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_is_32_bytes() {
        assert_eq!(core::mem::size_of::<Node>(), 32);
    }

    #[test]
    fn f32_up_never_rounds_down() {
        for x in [0.1, 1.0 / 3.0, 1e-40, 1e12 + 0.3, 3.5e38, f64::MAX, 0.0] {
            assert!(f64::from(f32_up(x)) >= x, "{x}");
        }
        assert!(f32_up(f64::NAN).is_nan());
    }

    #[test]
    fn too_large_is_an_error_not_a_panic() {
        // Cannot allocate 2³¹ segments in a test; check the cap's arithmetic instead.
        assert!(MAX_PRIMITIVES <= (u32::MAX / 2) as usize);
        assert!(Bvh2::build(&[]).unwrap().is_empty());
    }

    #[test]
    fn adversarial_input_keeps_depth_bounded() {
        // Exponentially spaced segments drive the SAH to one-sided splits; identical
        // segments give no usable SAH plane at all.
        let mut segs = Vec::new();
        for k in 0..2000 {
            let x = libm::pow(1.01, f64::from(k));
            segs.push(Segment::new(DVec2::new(x, 0.0), DVec2::new(x, 1.0)));
        }
        for _ in 0..3000 {
            segs.push(Segment::new(DVec2::ZERO, DVec2::ONE));
        }
        let bvh = Bvh2::build(&segs).unwrap();
        assert!((bvh.depth() as usize) < STACK_SIZE, "depth {}", bvh.depth());
        assert_eq!(bvh.len(), segs.len());
        assert!(bvh.node_count() < 2 * segs.len());
    }
}
