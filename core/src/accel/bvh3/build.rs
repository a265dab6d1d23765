//! Binned-SAH construction of the [`super::Bvh3`] tree (Wald 2007; pbrt-v4 §7.3).

use alloc::vec::Vec;

use crate::geom::DVec3;

use super::STACK_SIZE;
use crate::accel::sah::{BINS, SahBox, best_plane, bin_of};

/// Depth below which splits follow the SAH; median splits beyond.
const SAH_DEPTH: u32 = 32;

/// Most polygons in a leaf (more are always split).
const MAX_LEAF: usize = 4;

/// SAH cost of one node visit, relative to one polygon test. A visit of the 4-wide tree
/// tests four boxes in one `f32` pass (some 35 instructions against 60–100 for a polygon
/// test), and covers two binary levels. 0.5 (it was 1.0) splits the room of 512 cubes
/// into smaller leaves: 7 % fewer instructions a global line, 4 % a local one, the same
/// hits; 0.25 builds the same trees on the three benchmark scenes.
const TRAVERSAL_COST: f64 = 0.5;

/// An item during the build: its bounds, their centre, its index among the units, and
/// whether it must have a leaf of its own (a sheet: the leaf's box test then stands for
/// the sheet's).
#[derive(Clone, Copy, Debug)]
pub(super) struct BuildPrim {
    pub(super) lo: DVec3,
    pub(super) hi: DVec3,
    pub(super) centroid: DVec3,
    pub(super) id: u32,
    pub(super) alone: bool,
}

/// A node of the tree as built (pbrt's `LinearBVHNode`, flattened depth-first: a first
/// child is the next node): bounds, and either the first item and the count (leaf) or the
/// index of the second child and a count of 0 (interior).
#[derive(Clone, Copy, Debug)]
pub(super) struct BuildNode {
    pub(super) lo: DVec3,
    pub(super) hi: DVec3,
    pub(super) offset: u32,
    pub(super) count: u32,
}

/// A pending subtree: items `start..end`, its depth, and the parent whose second child it
/// is (`u32::MAX` for the root and for first children).
#[derive(Clone, Copy, Debug)]
struct Task {
    start: usize,
    end: usize,
    depth: u32,
    parent: u32,
}

/// An axis-aligned box accumulated with `f64::min`/`max`.
#[derive(Clone, Copy, Debug)]
struct Aabb {
    lo: DVec3,
    hi: DVec3,
}

impl Aabb {
    const EMPTY: Self = Self {
        lo: DVec3::INFINITY,
        hi: DVec3::NEG_INFINITY,
    };

    #[inline]
    fn grow(&mut self, lo: DVec3, hi: DVec3) {
        self.lo = self.lo.min(lo);
        self.hi = self.hi.max(hi);
    }

    #[inline]
    fn merged(mut self, other: &Self) -> Self {
        self.grow(other.lo, other.hi);
        self
    }

    /// Surface area `2(xy + yz + zx)`; 0 for an empty box. By Cauchy–Crofton a uniform
    /// line meeting a box meets a box inside it with probability `S(inner)/S(outer)`, so
    /// the SAH is exact for global lines.
    #[inline]
    fn area(&self) -> f64 {
        let d = self.hi - self.lo;
        if d.cmpge(DVec3::ZERO).all() {
            2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
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
        self.area()
    }
}

/// Builds the tree over `items`, reordering them in place into leaf order: each leaf's
/// `offset .. offset + count` indexes the reordered `items`. Returns the nodes and the
/// depth of the deepest leaf. `items` must not be empty.
pub(super) fn build_nodes(items: &mut [BuildPrim]) -> (Vec<BuildNode>, u32) {
    let n = items.len();
    let mut nodes: Vec<BuildNode> = Vec::with_capacity((2 * n).saturating_sub(1));
    let mut depth = 0;
    // Depth-first with an explicit stack: a first child is always popped right after its
    // parent, so it lands at the parent's index + 1.
    let mut tasks: Vec<Task> = Vec::with_capacity(2 * STACK_SIZE);
    tasks.push(Task {
        start: 0,
        end: n,
        depth: 0,
        parent: u32::MAX,
    });
    while let Some(task) = tasks.pop() {
        let index = nodes.len() as u32;
        if task.parent != u32::MAX {
            nodes[task.parent as usize].offset = index;
        }
        depth = depth.max(task.depth);
        let part = &mut items[task.start..task.end];
        let mut bounds = Aabb::EMPTY;
        for p in part.iter() {
            bounds.grow(p.lo, p.hi);
        }
        match split(part, &bounds, task.depth) {
            None => {
                nodes.push(BuildNode {
                    lo: bounds.lo,
                    hi: bounds.hi,
                    offset: task.start as u32,
                    count: part.len() as u32,
                });
            }
            Some(mid) => {
                nodes.push(BuildNode {
                    lo: bounds.lo,
                    hi: bounds.hi,
                    offset: 0,
                    count: 0,
                });
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
    (nodes, depth)
}

/// Chooses how to split `items` (in place): `None` for a leaf, or `Some(mid)` with
/// `items[..mid]` the first child, `items[mid..]` the second, `0 < mid < len`.
fn split(items: &mut [BuildPrim], bounds: &Aabb, depth: u32) -> Option<usize> {
    let n = items.len();
    if n <= 1 {
        return None;
    }
    let leaf_ok = n <= MAX_LEAF && !items.iter().any(|p| p.alone);
    let mut cb = Aabb::EMPTY;
    for p in items.iter() {
        cb.grow(p.centroid, p.centroid);
    }
    if depth < SAH_DEPTH
        && let Some(choice) = sah_split(items, bounds, &cb, leaf_ok)
    {
        return choice;
    }
    if leaf_ok {
        return None;
    }
    // Median split along the widest centroid extent: halves the count whatever the
    // geometry, so the depth stays below SAH_DEPTH + 31.
    let e = cb.hi - cb.lo;
    let axis = if e.x >= e.y && e.x >= e.z {
        0
    } else if e.y >= e.z {
        1
    } else {
        2
    };
    let mid = n / 2;
    items.select_nth_unstable_by(mid, |p, q| p.centroid[axis].total_cmp(&q.centroid[axis]));
    Some(mid)
}

/// The binned SAH's choice over the three axes: `Some(None)` = make a leaf (only if
/// `leaf_ok`), `Some(Some(mid))` = split there (already partitioned), `None` = no usable
/// split (all centroids in one bin on every axis).
#[allow(clippy::option_option)]
fn sah_split(
    items: &mut [BuildPrim],
    bounds: &Aabb,
    cb: &Aabb,
    leaf_ok: bool,
) -> Option<Option<usize>> {
    let n = items.len();
    // (cost, axis, first bin of the right side, lo, inv)
    let mut best: Option<(f64, usize, usize, f64, f64)> = None;
    for axis in 0..3 {
        let (lo, width) = (cb.lo[axis], cb.hi[axis] - cb.lo[axis]);
        if !(width > 0.0 && width.is_finite()) {
            continue;
        }
        let inv = BINS as f64 / width;
        let bounds = |p: &BuildPrim| Aabb { lo: p.lo, hi: p.hi };
        if let Some((cost, b)) = best_plane(items, |p| p.centroid[axis], bounds, lo, inv)
            && best.is_none_or(|c| cost < c.0)
        {
            best = Some((cost, axis, b, lo, inv));
        }
    }
    let (cost, axis, plane, lo, inv) = best?;
    // C = C_trav + Σ P(child) n_child,  P(child) = S(child)/S(parent)
    let parent = bounds.area();
    let split_cost = if parent > 0.0 && parent.is_finite() {
        TRAVERSAL_COST + cost / parent
    } else {
        f64::NAN
    };
    if leaf_ok && !(split_cost < n as f64) {
        return Some(None);
    }
    let mut mid = 0;
    for k in 0..n {
        if bin_of(items[k].centroid[axis], lo, inv) < plane {
            items.swap(mid, k);
            mid += 1;
        }
    }
    if mid == 0 || mid == n {
        return None;
    }
    Some(Some(mid))
}
