//! Line queries against convex planar polygons in 3D: a bounding volume hierarchy
//! ([`Bvh3`]) and the `O(n)` loops it must agree with exactly ([`all_hits_naive3`],
//! [`first_hit_naive3`]).
//!
//! # Input
//!
//! Polygons are given as in a 3D scene: a vertex array `points` and, per polygon, the
//! range `(first, count)` of its vertices, `points[first..first + count]`, counter-clockwise
//! about the front normal (DESIGN.md, "Orientation"). Hits report a polygon's index in
//! that list.
//!
//! # The intersection test
//!
//! Every query, naive or accelerated, runs the same arithmetic per polygon against the line
//! `o + t d`, in three steps. All coordinates are taken relative to the centre `c` of the
//! polygons' bounds (`v' = v − c`), which keeps them small wherever the scene is.
//!
//! ```text
//! 1. crossing   p_k = (r₁·(v'_k − f), r₂·(v'_k − f))     vertex k seen along the line
//!               E_k = p_k × p_{k+1}                       (2D cross product)
//!               hit ⇔ no two E_k of opposite signs, and not all E_k = 0
//! 2. bounds     [t₀, t₁] = the slab interval of the polygon's bounds grown by the margin
//!               hit ⇔ t₀ ≤ t₁
//! 3. parameter  t = clamp(n·(p₀ − o') / n·d, t₀, t₁),  n·d ≠ 0, t finite
//! ```
//!
//! `(r₁, r₂, d/|d|)` is an orthonormal frame (Duff et al. 2017) and `f` the foot of the
//! perpendicular from `c` to the line: step 1 projects the polygon on the plane `d^⊥`,
//! where the line is the origin, and asks whether the origin lies in the projected polygon
//! (Woop, Benthin and Wald 2013, "Watertight ray/triangle intersection", for polygons).
//! `E_k` is the signed volume `d·((v_k − x) × (v_{k+1} − x))/|d|` for any point `x` of the
//! line: for a line through the polygon all `E_k` share the sign of `n·d`, and a line
//! through an edge or a vertex gives `E_k = 0` there — the polygon is *closed*. A line in
//! the polygon's plane (all `E_k = 0`, or `n·d = 0`) is ignored.
//!
//! The test is **watertight**. A vertex shared by several polygons is projected once per
//! polygon with the same arithmetic, hence to the same `p`, and the edge `b → a` of a
//! neighbour gets `E = p_b × p_a`, exactly the negation of `p_a × p_b`: a line near a
//! shared edge is caught by at least one of its two polygons. Near a shared vertex the
//! rounding of each `E_k` is relative to `|p_k| |p_{k+1}|`, the distance of the vertex from
//! the line, so the signs around the vertex keep turning: no global line slips through the
//! seams of a closed mesh, along edges or through vertices (tested on quad and triangle
//! meshes far from the origin).
//!
//! The margin is `m = 10⁻⁹ (‖o'‖∞ + scale)` (`scale` = the largest `|v'|` coordinate), far
//! above the rounding of steps 1–2, so step 2 never rejects a crossing found by step 1.
//! Its purpose is exactness of the tree: the slab interval is *monotone* in the box (IEEE
//! subtraction and multiplication are monotone), so a node whose bounds contain a
//! polygon's gets an interval containing the polygon's, and the clamped `t` lies in both.
//! Hence the tree never culls a polygon the naive loop reports (step 2 passed, so the
//! node's interval is not empty) nor one whose `t` could be the nearest (`t ∈ [t₀, t₁]` ⊆
//! the node's interval) — by construction, not by error bounds. The clamp only acts on
//! grazing lines, whose plane crossing is ill-conditioned; it keeps every reported `t`
//! finite and near the polygon. Every `t` is finite and never `−0`.
//!
//! # Sheets
//!
//! A face cut into an `m × k` grid of quads, pushed row by row with shared vertices
//! bit-identical (as scenes cut faces into patches, `q(i, j) = [P(i, j), P(i + 1, j),
//! P(i + 1, j + 1), P(i, j + 1)]`), is held as one item, a *sheet*, when its lattice points
//! lie within `10⁻⁶` of a cell of the ideal lattice `A + i u + j v`. A line meets the
//! lattice at `(s, t)`, found from the projections of `A`, `u`, `v` on `d^⊥` (a 2×2
//! solve), and only the quads of a window about it — one or two cells a side, derived
//! from the rounding of the edge functions and the lattice's deviation, with seven orders
//! of magnitude to spare — go through the exact test above. Sheets thus change the cost,
//! not the results: a face of 30 × 30 patches costs one box test and one to four polygon
//! tests instead of some twenty box tests. (Unlike the tree's culling, the window rests on
//! an error bound, like [`super::Bvh2`]'s runs; a grazing line, whose window would be
//! wide, tests the whole sheet.) Each sheet has a leaf of its own, whose box test stands
//! for the sheet's.
//!
//! # Layout
//!
//! A 4-wide tree of 128-byte interior nodes, two cache lines each, holding the bounds of
//! their (up to) four children and references to them (an interior node, or a leaf: a
//! range of items, each a polygon or a sheet). The build makes a binary tree; each wide
//! node holds the grandchildren of one of its interior nodes (a child that is a leaf
//! stands for itself), so the culling is that of the binary tree, one wide level per two
//! binary ones. Bounds are stored relative to `c` in `f32`, rounded outwards, so they
//! contain the `f64` bounds of every polygon below and the monotonicity argument holds as
//! is; they are laid out by side, axis and child (`[f32; 4]` per plane), so that the
//! four children's box tests run lane by lane, vectorised: in `f32` with a second,
//! larger margin (conservative, see "Queries"), or in `f64` — per child the very same
//! operations on the same values as a single box test. Polygons are stored in leaf
//! order (a sheet's row by row),
//! each as one contiguous record — plane, bounds, then vertices, relative to `c` — in a
//! flat array, and their original indices in another: a polygon test touches two or three
//! adjacent cache lines of one page, where separate arrays of vertices, planes and bounds
//! cost a cache and TLB miss each once the scene outgrows the caches (a cube of 10⁶
//! patches: 200 MB of polygon data). Polygons that can never be hit (fewer than three
//! vertices, zero area, non-finite coordinates) are left out of the tree.
//!
//! # Queries
//!
//! `all_hits` first tests the box of all the polygons in `f64` with the query's box
//! constants alone (`BoxQuery`: origin, margins, `1/d`), and stops there when the line
//! misses it — no polygon can then pass step 2, by the monotonicity above — before the
//! crossing test's frame (a division, a square root, an orthonormal pair) and the `f32`
//! constants are computed: about a third of the uniform global lines through a box's
//! bounding sphere miss the box.
//!
//! A walk keeps pending subtrees on a fixed stack and allocates nothing. A visit tests
//! the four children's boxes at once, descends into the first one the line meets and
//! pushes the others it meets. The walks are
//! monomorphised for the 8 octants of `d` (found without a branch, then one jump on the
//! octant's number: a global line's octant is random, and three sign branches in turn were
//! mispredicted half the time each), so each box test reads its near and far bounds
//! directly (pbrt's `dirIsNeg`): per axis `(bound ∓ m − o')/d`, 6 subtractions, 6
//! multiplications and 6 maxima (the far planes' `t` negated, exactly). `all_hits` runs
//! them in `f32`, four boxes a packed operation (6 of each on SSE2), with the origins
//! moved outwards by a second margin `δ = 2⁻¹⁹ R` that covers the rounding of `f32`, so
//! that a node's `f32` interval contains the `f64` interval of every polygon below (the
//! `slab32` module's docs prove it): the culling stays exact by construction, and the
//! hits are the naive loop's. A line outside that proof's bounds (a direction component
//! below `2⁻⁴⁰` but not zero, coordinates beyond `2⁶⁰`) takes the `f64` test: for four
//! boxes 12 `f32 → f64` conversions and 12 of each operation on pairs of `f64`, per box
//! the very arithmetic of the polygons' step 2. `first_hit` uses the `f64` test, also
//! culls by `(t_min, t_best]`, pushes the children it keeps by decreasing entry (the
//! nearest is visited first) and drops a pending subtree whose entry is beyond the best
//! hit found since it was pushed.
//!
//! # Build
//!
//! Binned surface-area heuristic (Wald 2007), 16 bins on each of the three axes. By
//! Cauchy–Crofton (see [`crate::lines::sample_global_line_3d`]) a uniform line meeting a
//! box meets a box inside it with probability `S(inner)/S(outer)`, so the SAH is exact for
//! global lines. Below depth 32 splits follow the SAH; deeper (only on adversarial input)
//! they are median splits, so the depth stays below 64 and the 4-wide tree's below 32,
//! which sizes the queries' fixed stacks. Sheets are found first, in one `O(n)` pass over the polygons in order.
//! `O(n log n)` time, explicit work stack, no recursion.

#[cfg(feature = "alloc")]
use alloc::vec::Vec;
#[cfg(feature = "alloc")]
use core::fmt;

use crate::geom::DVec3;
#[cfg(feature = "alloc")]
use crate::lines::Line3;

#[cfg(feature = "alloc")]
use crate::error::{Error, ErrorKind, Result};

#[cfg(feature = "alloc")]
mod build;
mod prim;
#[cfg(feature = "alloc")]
pub(super) mod sheet;
#[cfg(feature = "alloc")]
mod slab32;
#[cfg(all(test, feature = "std"))]
pub(super) mod tests;

#[cfg(feature = "alloc")]
use prim::Slab;
use prim::{BoxQuery, Frame, Query, vertices};
pub(super) use prim::{origin_in_closed_polygon, prepare};
#[cfg(feature = "alloc")]
use slab32::{Slab32, f32_down, f32_up};

/// Entries of a polygon's record before its vertices: `n, p0, lo, hi` ([`Bvh3`]'s
/// `records`).
#[cfg(feature = "alloc")]
const RECORD_HEAD: usize = 4;

/// Length of a quad's record (a sheet's quads are stored back to back).
#[cfg(feature = "alloc")]
const QUAD_RECORD: usize = RECORD_HEAD + 4;

/// One intersection of a line with a polygon: the line parameter `t` of the hit point
/// `origin + t·dir` and the polygon's index `prim` in the list the query was built from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit3 {
    /// Line parameter of the hit (a signed distance when `dir` is a unit vector).
    pub t: f64,
    /// Index of the polygon hit.
    pub prim: u32,
}

impl Hit3 {
    /// Every intersection of the infinite `line` with a polygon, sorted by `t` then `prim`,
    /// written into `out` (cleared first): the `O(n)` baseline of [`Bvh3::all_hits`], which
    /// returns exactly the same hits in the same order. Polygons whose range leaves `points`
    /// are skipped ([`Bvh3::build`] rejects them).
    ///
    /// Only the first `2³²` polygons are considered (hit indices are `u32`).
    #[cfg(feature = "alloc")]
    pub fn all_naive(
        points: &[DVec3],
        polygons: &[(usize, usize)],
        line: &Line3,
        out: &mut Vec<Hit3>,
    ) {
        all_hits_naive3(points, polygons, line, out);
    }

    /// The order of [`Bvh3::all_hits`]: by `t`, then by `prim`.
    #[inline]
    #[must_use]
    pub fn cmp_t_prim(&self, other: &Self) -> core::cmp::Ordering {
        self.t.total_cmp(&other.t).then(self.prim.cmp(&other.prim))
    }
}

/// Sorts hits by `(t, prim)` — a strict total order, as every `prim` appears at most once.
#[cfg(feature = "alloc")]
impl super::HitKey for Hit3 {
    #[inline]
    fn t(&self) -> f64 {
        self.t
    }
    #[inline]
    fn prim(&self) -> u32 {
        self.prim
    }
}

/// The hit of polygon `verts` by the query's line, if any: the three steps of the module
/// docs, computing the polygon's data on the fly (the naive loops).
#[inline]
fn naive_hit(frame: &Frame, q: &Query, verts: &[DVec3]) -> Option<f64> {
    let &last = verts.last()?;
    if !q.crosses(last - frame.c, verts.iter().map(|&v| v - frame.c)) {
        return None;
    }
    let p = prepare(frame.c, verts)?;
    q.hit_t(p.n, p.p0, &p.bounds)
}

/// Every intersection of the infinite `line` with a polygon, sorted by `t` then `prim`,
/// written into `out` (cleared first): the `O(n)` baseline of [`Bvh3::all_hits`], which
/// returns exactly the same hits in the same order. Polygons whose range leaves `points`
/// are skipped ([`Bvh3::build`] rejects them).
///
/// Only the first `2³²` polygons are considered (hit indices are `u32`).
#[cfg(feature = "alloc")]
pub(crate) fn all_hits_naive3(
    points: &[DVec3],
    polygons: &[(usize, usize)],
    line: &Line3,
    out: &mut Vec<Hit3>,
) {
    out.clear();
    let frame = Frame::new(points, polygons);
    let q = Query::new(line.origin, line.dir, &frame);
    for (&(first, count), prim) in polygons.iter().zip(0..=u32::MAX) {
        if let Some(t) = vertices(points, first, count).and_then(|v| naive_hit(&frame, &q, v)) {
            out.push(Hit3 { t, prim });
        }
    }
    super::sort_hits(out);
}

/// The nearest hit with `t > t_min` along the ray `origin + t·dir`, the smallest `prim`
/// among equally near ones: the `O(n)` baseline of [`Bvh3::first_hit`], which returns
/// exactly the same hit. Needs no allocator. Polygons whose range leaves `points` are
/// skipped.
///
/// Only the first `2³²` polygons are considered (hit indices are `u32`).
#[must_use]
pub(crate) fn first_hit_naive3(
    points: &[DVec3],
    polygons: &[(usize, usize)],
    origin: DVec3,
    dir: DVec3,
    t_min: f64,
) -> Option<Hit3> {
    let frame = Frame::new(points, polygons);
    let q = Query::new(origin, dir, &frame);
    let mut best: Option<Hit3> = None;
    for (&(first, count), prim) in polygons.iter().zip(0..=u32::MAX) {
        if let Some(t) = vertices(points, first, count).and_then(|v| naive_hit(&frame, &q, v)) {
            // Strictly nearer wins; ties keep the earlier (smaller) prim.
            if t > t_min && best.is_none_or(|b| t < b.t) {
                best = Some(Hit3 { t, prim });
            }
        }
    }
    best
}

/// A reference to a subtree: an interior node (`count` = [`INTERIOR`], `offset` = its
/// index) or a leaf (`count` items from `offset`, in leaf order; an empty leaf when
/// `count = 0`, as in the unused child slots of a node).
#[cfg(feature = "alloc")]
#[derive(Clone, Copy, Debug, Default)]
struct Ref {
    offset: u32,
    count: u32,
}

/// The `count` of a [`Ref`] to an interior node (a leaf holds far fewer items: at most
/// `super::MAX_PRIMITIVES`).
#[cfg(feature = "alloc")]
const INTERIOR: u32 = u32::MAX;

#[cfg(feature = "alloc")]
impl Ref {
    #[inline(always)]
    fn is_leaf(self) -> bool {
        self.count != INTERIOR
    }
}

/// Children of an interior node.
#[cfg(feature = "alloc")]
const WIDTH: usize = 4;

/// Capacity of the traversal stacks. Interior nodes are at most 32 levels deep: each
/// holds the grandchildren of a node of the binary tree of the build (its children where
/// they are leaves), whose leaves are less than 64 levels deep (32 SAH levels plus 31
/// median levels for at most 2³¹ polygons), so its interior nodes at binary depths
/// 0, 2, …, 62. `all_hits` keeps at most `WIDTH − 1` pending children per level above the
/// node it visits (≤ 3 · 32); `first_hit`, popping an interior node of level `l ≤ 31`,
/// leaves at most `3 l` pending and pushes `WIDTH` (≤ 97).
#[cfg(feature = "alloc")]
const STACK_SIZE: usize = 3 * 32 + WIDTH;

/// Capacity of `all_hits`' stack in trees of at most 13 levels of interior nodes
/// (`3 · 13 < 40`: most scenes). The stack is zeroed at every query, and a smaller one
/// costs less to clear (800 bytes were 63 instructions a line, a twentieth of a line on
/// the 5400-patch cube).
#[cfg(feature = "alloc")]
const SMALL_STACK: usize = 40;

/// Capacity of `all_hits`' stack in trees of at most 5 levels of interior nodes
/// (`3 · 5 < 16`: scenes of a few sheets, such as a cube cut into patches), cheaper
/// still to clear.
#[cfg(feature = "alloc")]
const TINY_STACK: usize = 16;

/// An interior node: the bounds of its (up to) four children, relative to the frame's
/// centre, in `f32` rounded outwards (so they contain the `f64` bounds of every polygon
/// below), and the references to them; an unused slot has the empty box (`lo = +∞`,
/// `hi = −∞`, which no line meets) and an empty leaf. 128 bytes, two cache lines. The
/// bounds are stored by side, axis, then child (`bounds[side][axis][child]`) so that a
/// visit computes the four children's slab intervals lane by lane in vectorisable loops
/// (in `f32`, conservative, [`Slab32::interval4`]; or the same `f64` arithmetic per child
/// as a single box test, [`Slab::interval4`]).
#[cfg(feature = "alloc")]
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
struct Node {
    /// `bounds[0]` = the children's low corners, `bounds[1]` the high ones, per axis.
    bounds: [[[f32; WIDTH]; 3]; 2],
    child: [Ref; WIDTH],
}

#[cfg(feature = "alloc")]
impl Node {
    /// A node with no child (every slot empty).
    const EMPTY: Self = Self {
        bounds: [[[f32::INFINITY; WIDTH]; 3], [[f32::NEG_INFINITY; WIDTH]; 3]],
        child: [Ref {
            offset: 0,
            count: 0,
        }; WIDTH],
    };

    /// Sets slot `c` to `child` with the bounds `[lo, hi]` rounded outwards to `f32`.
    fn set(&mut self, c: usize, child: Ref, lo: DVec3, hi: DVec3) {
        for axis in 0..3 {
            self.bounds[0][axis][c] = f32_down(lo[axis]);
            self.bounds[1][axis][c] = f32_up(hi[axis]);
        }
        self.child[c] = child;
    }

    /// The query's slab intervals of the four children's bounds ([`Slab::interval4`]),
    /// for a line whose near bounds are `[I, J, K]` (`Query::near`, fixed per
    /// monomorphised walk): `(enter, exit)` per child.
    #[inline(always)]
    fn slab<const I: usize, const J: usize, const K: usize>(
        &self,
        s: &Slab,
    ) -> ([f64; WIDTH], [f64; WIDTH]) {
        let b = &self.bounds;
        s.interval4(
            [&b[I][0], &b[J][1], &b[K][2]],
            [&b[1 - I][0], &b[1 - J][1], &b[1 - K][2]],
        )
    }
}

/// A box test of a node's four children: the mask of the children the line may meet
/// (bit `c` for child `c`), for a line whose near bounds are `[I, J, K]`. A NaN
/// comparison visits: culling must only ever be sure.
#[cfg(feature = "alloc")]
trait NodeTest {
    fn meets<const I: usize, const J: usize, const K: usize>(&self, node: &Node) -> u32;
}

/// The `f64` test ([`Slab::interval4`]): the same arithmetic per child as the polygons'.
#[cfg(feature = "alloc")]
impl NodeTest for Slab {
    #[inline(always)]
    fn meets<const I: usize, const J: usize, const K: usize>(&self, node: &Node) -> u32 {
        let (enter, exit) = node.slab::<I, J, K>(self);
        let mut mask = 0u32;
        for c in 0..WIDTH {
            mask |= u32::from(!(enter[c] > exit[c])) << c;
        }
        mask
    }
}

/// The `f32` test ([`Slab32::interval4`]): four boxes a packed operation, conservative
/// with respect to the polygons' `f64` test (the `slab32` module docs).
#[cfg(feature = "alloc")]
impl NodeTest for Slab32 {
    #[inline(always)]
    fn meets<const I: usize, const J: usize, const K: usize>(&self, node: &Node) -> u32 {
        let b = &node.bounds;
        let (enter, exit) = self.interval4(
            [&b[I][0], &b[J][1], &b[K][2]],
            [&b[1 - I][0], &b[1 - J][1], &b[1 - K][2]],
        );
        let mut mask = 0u32;
        for c in 0..WIDTH {
            mask |= u32::from(!(enter[c] > exit[c])) << c;
        }
        mask
    }
}

/// What a leaf holds: a polygon or a sheet, by its first polygon (storage order).
#[cfg(feature = "alloc")]
#[derive(Clone, Copy, Debug)]
struct Item {
    first: u32,
    /// Index into the sheets, `u32::MAX` for a single polygon.
    sheet: u32,
}

/// Packs the depth-first binary tree of the build (one node per subtree, first child
/// next) into 4-wide interior nodes: each holds the grandchildren of an interior node of
/// the binary tree (a child that is a leaf stands for itself), in depth-first order.
/// Returns them and the root's reference.
#[cfg(feature = "alloc")]
fn pack(tree: &[build::BuildNode]) -> (Vec<Node>, Ref, u32) {
    let leaf = |k: usize| Ref {
        offset: tree[k].offset,
        count: tree[k].count,
    };
    let is_interior = |k: usize| tree[k].count == 0;
    if !is_interior(0) {
        return (Vec::new(), leaf(0), 0);
    }
    // The binary children of interior node `k`.
    let children = |k: usize| [k + 1, tree[k].offset as usize];
    let mut nodes: Vec<Node> = Vec::new();
    // (binary interior node, the wide node to fill): depth-first, first child popped
    // first. Bounded by the tree: each binary node is pushed at most once.
    let mut todo: Vec<(usize, usize, u32)> = alloc::vec![(0, 0, 1)];
    let mut levels = 0;
    nodes.push(Node::EMPTY);
    while let Some((k, at, level)) = todo.pop() {
        levels = levels.max(level);
        let mut slots = [0usize; WIDTH];
        let mut n = 0;
        for ch in children(k) {
            if is_interior(ch) {
                for g in children(ch) {
                    slots[n] = g;
                    n += 1;
                }
            } else {
                slots[n] = ch;
                n += 1;
            }
        }
        let mut node = Node::EMPTY;
        let mut pending = [(0usize, 0usize, level + 1); WIDTH];
        let mut n_pending = 0;
        for (c, &g) in slots[..n].iter().enumerate() {
            let r = if is_interior(g) {
                nodes.push(Node::EMPTY);
                pending[n_pending] = (g, nodes.len() - 1, level + 1);
                n_pending += 1;
                Ref {
                    offset: (nodes.len() - 1) as u32,
                    count: INTERIOR,
                }
            } else {
                leaf(g)
            };
            node.set(c, r, tree[g].lo, tree[g].hi);
        }
        nodes[at] = node;
        // Reversed, so that the first child is packed next.
        todo.extend(pending[..n_pending].iter().rev());
    }
    (
        nodes,
        Ref {
            offset: 0,
            count: INTERIOR,
        },
        levels,
    )
}

/// Calls `Self::$walk::<I, J, K $g>(args)` for the octant `[I, J, K]` of the query's
/// direction (`Query::near`): the walks are monomorphised per octant, so the box tests
/// pick their near and far bounds at no cost (pbrt's `dirIsNeg`).
#[cfg(feature = "alloc")]
macro_rules! by_octant {
    ($near:expr, $walk:ident[$($g:tt)*]($($arg:expr),*)) => {{
        // One jump on the octant's number (a table), not three random branches in turn.
        let near: [usize; 3] = $near;
        match (near[0] != 0) as usize * 4 + (near[1] != 0) as usize * 2 + (near[2] != 0) as usize {
            0 => Self::$walk::<0, 0, 0 $($g)*>($($arg),*),
            1 => Self::$walk::<0, 0, 1 $($g)*>($($arg),*),
            2 => Self::$walk::<0, 1, 0 $($g)*>($($arg),*),
            3 => Self::$walk::<0, 1, 1 $($g)*>($($arg),*),
            4 => Self::$walk::<1, 0, 0 $($g)*>($($arg),*),
            5 => Self::$walk::<1, 0, 1 $($g)*>($($arg),*),
            6 => Self::$walk::<1, 1, 0 $($g)*>($($arg),*),
            _ => Self::$walk::<1, 1, 1 $($g)*>($($arg),*),
        }
    }};
}

/// A bounding volume hierarchy over convex planar polygons, answering "every hit of a
/// line, sorted" ([`Bvh3::all_hits`], the query of global lines) and "nearest hit of a ray"
/// ([`Bvh3::first_hit`], the query of local lines).
///
/// Queries allocate nothing (the caller's `Vec` is reused) and recurse nowhere (a
/// fixed-size stack); they return exactly what `all_hits_naive3` and `first_hit_naive3`
/// return, in the same order (see the module docs for why: the tree's culling is exact by
/// construction, the sheets' windows by an error bound with seven orders of magnitude to
/// spare).
///
/// # Examples
///
/// ```
/// use sceneinfo::accel::{Bvh3, Hit3};
/// use sceneinfo::geom::DVec3;
/// use sceneinfo::lines::Line3;
///
/// // Two unit squares, at z = 0 and z = 2.
/// let points = [
///     DVec3::new(0.0, 0.0, 0.0), DVec3::new(1.0, 0.0, 0.0),
///     DVec3::new(1.0, 1.0, 0.0), DVec3::new(0.0, 1.0, 0.0),
///     DVec3::new(0.0, 0.0, 2.0), DVec3::new(0.0, 1.0, 2.0),
///     DVec3::new(1.0, 1.0, 2.0), DVec3::new(1.0, 0.0, 2.0),
/// ];
/// let bvh = Bvh3::build(&points, &[(0, 4), (4, 4)]).unwrap();
/// let mut hits = Vec::new();
/// bvh.all_hits(&Line3::new(DVec3::new(0.5, 0.5, -1.0), DVec3::Z), &mut hits);
/// assert_eq!(hits, [Hit3 { t: 1.0, prim: 0 }, Hit3 { t: 3.0, prim: 1 }]);
/// let first = bvh.first_hit(DVec3::new(0.5, 0.5, 0.0), DVec3::Z, 1e-9).unwrap();
/// assert_eq!((first.t, first.prim), (2.0, 1));
/// ```
#[cfg(feature = "alloc")]
#[derive(Clone)]
pub struct Bvh3 {
    nodes: Vec<Node>,
    /// The root: an interior node, a leaf, or an empty leaf (no polygon in the tree).
    root: Ref,
    /// The leaves' items, in leaf order.
    items: Vec<Item>,
    sheets: Vec<sheet::Sheet>,
    /// The record of polygon `k` (leaf order): `records[start[k]..start[k + 1]]` =
    /// `[n, p0, lo, hi, v₀, v₁, …]`, its unit normal, a point of its plane, its bounds and
    /// its vertices, all but `n` relative to the frame's centre ([`RECORD_HEAD`] entries
    /// before the vertices).
    start: Vec<u32>,
    records: Vec<DVec3>,
    /// Original index of each polygon.
    ids: Vec<u32>,
    frame: Frame,
    /// The bounds of every polygon in the tree, relative to the frame's centre (`f64`,
    /// the union of the polygons' own): a line whose slab interval of this box is empty
    /// misses every polygon, decided before the crossing test's frame is computed.
    bounds: [DVec3; 2],
    /// Number of polygons given (hittable or not).
    len: usize,
    depth: u32,
    /// Levels of interior nodes (0 without any): a walk has at most `3 · levels` pending
    /// subtrees.
    levels: u32,
}

#[cfg(feature = "alloc")]
impl fmt::Debug for Bvh3 {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Bvh3")
            .field("polygons", &self.len)
            .field("in_tree", &self.ids.len())
            .field(
                "vertices",
                &(self.records.len() - RECORD_HEAD * self.ids.len()),
            )
            .field("sheets", &self.sheets.len())
            .field("nodes", &self.nodes.len())
            .field("depth", &self.depth)
            .finish()
    }
}

#[cfg(feature = "alloc")]
impl Bvh3 {
    /// Builds the hierarchy over the polygons `points[first..first + count]`, one per
    /// entry of `polygons`; hits report indices into `polygons`.
    ///
    /// `O(n log n)` time, `O(n)` memory. Any polygon is accepted — degenerate, repeated,
    /// non-finite or with fewer than three vertices (they simply never produce a hit).
    ///
    /// # Errors
    ///
    /// [`ErrorKind::TooLarge`] for more than `super::MAX_PRIMITIVES` polygons or more
    /// than `u32::MAX` vertices in all (counting four more per polygon); [`ErrorKind::DimensionMismatch`] for a range that
    /// leaves `points` (`expected` = `points.len()`, `found` = the range's end).
    pub fn build(points: &[DVec3], polygons: &[(usize, usize)]) -> Result<Self> {
        if polygons.len() > super::MAX_PRIMITIVES {
            return Err(Error::new(ErrorKind::TooLarge {
                what: "BVH primitive count",
                max: super::MAX_PRIMITIVES as u64,
            }));
        }
        for &(first, count) in polygons {
            if vertices(points, first, count).is_none() {
                return Err(Error::new(ErrorKind::DimensionMismatch {
                    expected: points.len(),
                    found: first.saturating_add(count),
                }));
            }
        }
        let frame = Frame::new(points, polygons);
        let c = frame.c;
        // Prepare every polygon that can be hit, then group them into units
        let prepared: Vec<_> = polygons
            .iter()
            .map(|&(first, count)| prepare(c, &points[first..first + count]))
            .collect();
        let units = sheet::find_units(points, polygons, &prepared, c);
        let mut n_polys = 0usize;
        let mut n_verts = 0usize;
        let mut items: Vec<build::BuildPrim> = Vec::with_capacity(units.len());
        for (unit, id) in units.iter().zip(0u32..) {
            let range = match unit {
                sheet::Unit::Polygon(p) => *p..*p + 1,
                sheet::Unit::Sheet(start, s) => *start..*start + s.len(),
            };
            n_polys += range.len();
            n_verts += polygons[range].iter().map(|p| p.1).sum::<usize>();
            let [lo, hi] = unit.bounds(&prepared);
            items.push(build::BuildPrim {
                lo,
                hi,
                centroid: lo * 0.5 + hi * 0.5,
                id,
                alone: matches!(unit, sheet::Unit::Sheet(..)),
            });
        }
        // Each polygon's record: a head, then its vertices
        let n_records = n_verts + RECORD_HEAD * n_polys;
        if n_records > u32::MAX as usize {
            return Err(Error::new(ErrorKind::TooLarge {
                what: "BVH vertex count (plus four per polygon)",
                max: u64::from(u32::MAX),
            }));
        }
        let mut bvh = Self {
            nodes: Vec::new(),
            root: Ref::default(),
            items: Vec::with_capacity(units.len()),
            sheets: Vec::new(),
            start: Vec::with_capacity(n_polys + 1),
            records: Vec::with_capacity(n_records),
            ids: Vec::with_capacity(n_polys),
            frame,
            bounds: items
                .iter()
                .fold([DVec3::INFINITY, DVec3::NEG_INFINITY], |[lo, hi], item| {
                    [lo.min(item.lo), hi.max(item.hi)]
                }),
            len: polygons.len(),
            depth: 0,
            levels: 0,
        };
        bvh.start.push(0);
        if items.is_empty() {
            return Ok(bvh);
        }
        let (tree, depth) = build::build_nodes(&mut items);
        (bvh.nodes, bvh.root, bvh.levels) = pack(&tree);
        bvh.depth = depth;
        // Items and their polygons' data in leaf order
        for item in &items {
            let (range, sheet) = match units[item.id as usize] {
                sheet::Unit::Polygon(p) => (p..p + 1, u32::MAX),
                sheet::Unit::Sheet(start, s) => {
                    bvh.sheets.push(s);
                    (start..start + s.len(), bvh.sheets.len() as u32 - 1)
                }
            };
            bvh.items.push(Item {
                first: bvh.ids.len() as u32,
                sheet,
            });
            for id in range {
                let (first, count) = polygons[id];
                let Some(p) = prepared[id] else { continue };
                bvh.records.extend([p.n, p.p0, p.bounds[0], p.bounds[1]]);
                bvh.records
                    .extend(points[first..first + count].iter().map(|&v| v - c));
                bvh.start.push(bvh.records.len() as u32);
                bvh.ids.push(id as u32);
            }
        }
        Ok(bvh)
    }

    /// Number of polygons given to [`Bvh3::build`] (including those that can never be hit).
    #[inline]
    #[must_use]
    pub fn len(&self) -> usize {
        self.len
    }

    /// Whether no polygon was given.
    #[inline]
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Number of interior nodes (`n − 1` at most).
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

    /// The hit of polygon `k` (leaf order) by the query's line, if any.
    #[inline(always)]
    fn hit(&self, q: &Query, k: usize) -> Option<f64> {
        Self::hit_record(
            q,
            &self.records[self.start[k] as usize..self.start[k + 1] as usize],
        )
    }

    /// The hit of the polygon of `record` (`[n, p0, lo, hi, v₀, …]`) by the query's line.
    #[inline(always)]
    fn hit_record(q: &Query, record: &[DVec3]) -> Option<f64> {
        let (head, vs) = record.split_at(RECORD_HEAD);
        // Every polygon in the tree has at least three vertices.
        if !q.crosses(vs[vs.len() - 1], vs.iter().copied()) {
            return None;
        }
        q.hit_t(head[0], head[1], &[head[2], head[3]])
    }

    /// Calls `f` once for every intersection of the infinite `line` with a polygon, in no
    /// particular order (see [`Bvh3::all_hits`] for the sorted form). Allocates nothing.
    #[inline]
    pub fn for_each_hit<F: FnMut(Hit3)>(&self, line: &Line3, f: F) {
        if self.nodes.is_empty() && self.root.count == 0 {
            return;
        }
        let boxes = BoxQuery::new(line.origin, line.dir, &self.frame);
        // A line that misses the box of all the polygons (a third of the global lines
        // of a closed box or a cube) has no hit: the rest of the query, the `f32`
        // constants and the root's visit are skipped (exact: `BoxQuery::misses`).
        if boxes.misses(&self.bounds) {
            return;
        }
        let q = boxes.query();
        let Some(slab32) = q.slab32(self.frame.scale) else {
            // A line outside the f32 test's error bounds (practically never a sampled one)
            let mut f = f;
            by_octant!(q.near, walk_all[, F, STACK_SIZE, Slab](self, &q, &q.slab, &mut f));
            return;
        };
        let levels = 3 * self.levels as usize;
        if levels < TINY_STACK {
            self.for_each_hit_with::<F, TINY_STACK>(&q, &slab32, f);
        } else if levels < SMALL_STACK {
            self.for_each_hit_with::<F, SMALL_STACK>(&q, &slab32, f);
        } else {
            self.for_each_hit_with::<F, STACK_SIZE>(&q, &slab32, f);
        }
    }

    /// [`Bvh3::for_each_hit`] with the `f32` node tests and a stack of `N ≥ 3 · levels`
    /// entries.
    #[inline(always)]
    fn for_each_hit_with<F: FnMut(Hit3), const N: usize>(
        &self,
        q: &Query,
        slab32: &Slab32,
        mut f: F,
    ) {
        by_octant!(q.near, walk_all[, F, N, Slab32](self, q, slab32, &mut f));
    }

    /// [`Bvh3::for_each_hit`] by the walks that the scenes at hand may not take: with the
    /// `f32` node tests and the large stack (deep trees; `None` where the line is outside
    /// the `f32` tests' error bounds) and with the `f64` node tests (lines outside them).
    #[cfg(all(test, feature = "std"))]
    fn for_each_hit_other_walks(&self, line: &Line3) -> (Option<Vec<Hit3>>, Vec<Hit3>) {
        let (mut large, mut by_f64) = (Vec::new(), Vec::new());
        if self.nodes.is_empty() && self.root.count == 0 {
            return (Some(large), by_f64);
        }
        let q = Query::new(line.origin, line.dir, &self.frame);
        let large = q.slab32(self.frame.scale).map(|s| {
            self.for_each_hit_with::<_, STACK_SIZE>(&q, &s, |h| large.push(h));
            large
        });
        let mut f = |h| by_f64.push(h);
        by_octant!(q.near, walk_all[, _, STACK_SIZE, Slab](self, &q, &q.slab, &mut f));
        (large, by_f64)
    }

    /// The polygons of a leaf that the query's line hits, each passed to `f`.
    #[inline(always)]
    fn leaf<F: FnMut(u32, f64)>(&self, q: &Query, leaf: Ref, f: &mut F) {
        let first = leaf.offset as usize;
        for item in &self.items[first..first + leaf.count as usize] {
            let k = item.first as usize;
            if item.sheet == u32::MAX {
                if let Some(t) = self.hit(q, k) {
                    f(self.ids[k], t);
                }
                continue;
            }
            // A sheet, alone in its leaf (whose box test stood for the sheet's): the quads
            // in the window about the line's crossing. Its quads' records have one length
            // and its quads consecutive input indices, so quad `o` of the sheet is found
            // without reading `start` or `ids`: in a scene larger than the caches, that
            // is one memory access per quad tested instead of three dependent ones.
            let sheet = &self.sheets[item.sheet as usize];
            let (cols, rows) = sheet.window(q);
            let m = sheet.cols() as usize;
            let (base, id) = (self.start[k] as usize, self.ids[k]);
            for j in rows {
                let row = j as usize * m;
                for i in cols.clone() {
                    let o = row + i as usize;
                    let at = base + o * QUAD_RECORD;
                    let Some(record) = self.records.get(at..at + QUAD_RECORD) else {
                        continue;
                    };
                    if let Some(t) = Self::hit_record(q, record) {
                        f(id + o as u32, t);
                    }
                }
            }
        }
    }

    /// The walk of [`Bvh3::for_each_hit`] for the octant `[I, J, K]`, with a stack of `N`
    /// entries (at least `3 · levels`): the four children's boxes tested at once, down
    /// the first one the line meets, the others it meets pushed (all hits are wanted, so
    /// the order does not matter).
    #[inline(always)]
    fn walk_all<
        const I: usize,
        const J: usize,
        const K: usize,
        F: FnMut(Hit3),
        const N: usize,
        T: NodeTest,
    >(
        &self,
        q: &Query,
        test: &T,
        f: &mut F,
    ) {
        let mut stack = [Ref::default(); N];
        let mut sp = 0usize;
        let mut r = self.root;
        loop {
            if r.is_leaf() {
                self.leaf(q, r, &mut |prim, t| f(Hit3 { t, prim }));
            } else {
                let node = &self.nodes[r.offset as usize];
                let mut mask = test.meets::<I, J, K>(node);
                if mask != 0 {
                    // The first child met is visited next, the others pushed.
                    let first = mask.trailing_zeros() as usize;
                    mask &= mask - 1;
                    while mask != 0 {
                        stack[sp] = node.child[mask.trailing_zeros() as usize];
                        sp += 1;
                        mask &= mask - 1;
                    }
                    r = node.child[first];
                    continue;
                }
            }
            // Next pending subtree
            if sp == 0 {
                break;
            }
            sp -= 1;
            r = stack[sp];
        }
    }

    /// Every intersection of the infinite `line` with a (closed) polygon, sorted by `t`
    /// then `prim`; lines in a polygon's plane ignored. Clears `out` first and only grows
    /// it, so a reused `out` makes the query allocation-free.
    ///
    /// Along a global line through a closed scene the consecutive hits pair up into the
    /// segments of Figure 2.8 of the thesis, each contributing to two form factors (2.37).
    pub fn all_hits(&self, line: &Line3, out: &mut Vec<Hit3>) {
        out.clear();
        self.for_each_hit(line, |h| out.push(h));
        super::sort_hits(out);
    }

    /// The nearest hit with `t > t_min` along the ray `origin + t·dir` (the smallest
    /// `prim` among equally near ones); `t_min > 0` skips the surface the ray leaves from.
    /// This is the query of local lines, estimator (2.36).
    #[must_use]
    pub fn first_hit(&self, origin: DVec3, dir: DVec3, t_min: f64) -> Option<Hit3> {
        if self.root.count == 0 && self.nodes.is_empty() {
            return None;
        }
        let q = Query::new(origin, dir, &self.frame);
        by_octant!(q.near, walk_first[](self, &q, t_min))
    }

    /// The walk of [`Bvh3::first_hit`] for the octant `[I, J, K]`: children in the order
    /// the ray enters their boxes, each pushed with its entry parameter so that a pending
    /// subtree is dropped once a nearer hit is known.
    #[inline(always)]
    fn walk_first<const I: usize, const J: usize, const K: usize>(
        &self,
        q: &Query,
        t_min: f64,
    ) -> Option<Hit3> {
        let slab = q.slab;
        let mut best_t = f64::INFINITY;
        let mut best_prim = u32::MAX;
        let mut stack = [(Ref::default(), 0.0f64); STACK_SIZE];
        stack[0] = (self.root, f64::NEG_INFINITY);
        let mut sp = 1usize;
        while sp > 0 {
            sp -= 1;
            let (r, enter) = stack[sp];
            // Negated so that NaN visits: culling must only ever be sure.
            if enter > best_t {
                continue;
            }
            if r.is_leaf() {
                self.leaf(q, r, &mut |prim, t| {
                    if t > t_min && (t < best_t || (t == best_t && prim < best_prim)) {
                        best_t = t;
                        best_prim = prim;
                    }
                });
                continue;
            }
            // The ray's live part (t_min, best_t] may meet a child's box
            let node = &self.nodes[r.offset as usize];
            let (e, x) = node.slab::<I, J, K>(&slab);
            let base = sp;
            for c in 0..WIDTH {
                let live = !(e[c] > x[c]) && !(x[c] <= t_min) && !(e[c] > best_t);
                if live {
                    // Insertion by decreasing entry, so that the nearest is popped first
                    // (NaN entries sort as the nearest: `>` is false for them).
                    let mut k = sp;
                    while k > base && e[c] > stack[k - 1].1 {
                        stack[k] = stack[k - 1];
                        k -= 1;
                    }
                    stack[k] = (node.child[c], e[c]);
                    sp += 1;
                }
            }
        }
        (best_prim != u32::MAX).then_some(Hit3 {
            t: best_t,
            prim: best_prim,
        })
    }
}
