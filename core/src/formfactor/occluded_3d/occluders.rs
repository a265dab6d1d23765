//! The scene's occluders for the pairs' candidate searches: coplanar neighbours merged into
//! larger convex polygons, a bounding-box tree over them, and the conservative "one
//! occluder hides every sight line" test.
//!
//! **Merging.** Occlusion depends on the union of the opaque polygons only, so two convex
//! polygons of one plane and one facing that share a whole edge (`P` has `a → b`, `Q` has
//! `b → a`: they lie on opposite sides of the edge) can be replaced, as occluders, by their
//! union when that union is convex. Repeated until nothing merges, a face cut into a grid
//! of patches becomes one occluder again (a Cornell block's face: 1 occluder instead of
//! 100), which divides both the candidates per pair and the work per point. A merged
//! occluder lies in the plane of the patches it came from, so a pair with a patch in that
//! plane still excludes it (see the parent module's culling).
//!
//! **The tree.** A median-split tree of the occluders' bounding boxes answers "which boxes
//! overlap this box" in `O(log m + k)`: the candidates of a pair are the occluders whose
//! boxes overlap the box of the pair's hull, then the exact tests of the parent module.
//!
//! **Fully blocked.** If the plane of a convex occluder `O` strictly separates the source
//! `S` from the target `T`, every segment from `S` to `T` crosses that plane once, and the
//! crossings fill the convex hull of the crossings of the `|S|·|T|` vertex-to-vertex
//! segments (the crossing of `s → t`, `s = Σλ_a a`, `t = Σμ_b b`, is the convex
//! combination of the vertex crossings `c_ab` with weights `λ_a μ_b (d_a − d_b)`, `d` the
//! signed distances to the plane). So when every `c_ab` lies strictly inside `O`, `O` hides
//! every sight line and the flux is exactly 0 ([`blocks_all`]).

use alloc::vec;
use alloc::vec::Vec;

use super::solids::{Solid, find_solids};
use crate::formfactor::exact_3d::{ON_PLANE, Plane, bounds};
use crate::geom::DVec3;

/// Occluders per leaf of the tree.
const LEAF_SIZE: usize = 4;

/// Most passes of the merging loop over one plane's polygons (each pass merges every
/// pair it can; a grid needs two or three).
const MAX_MERGE_PASSES: usize = 64;

/// A convex occluder: its vertices (counter-clockwise about `plane.normal`), its plane and
/// its bounding box.
#[derive(Clone, Debug)]
pub(crate) struct Occluder {
    pub vertices: Vec<DVec3>,
    pub plane: Plane,
    pub lo: DVec3,
    pub hi: DVec3,
}

/// A node of the box tree: its bounds and either two children or a run of `order`.
#[derive(Clone, Copy, Debug)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Leaf: first index into `order`; inner: index of the left child (right = left + 1).
    first: u32,
    /// Leaf: occluder count (≥ 1); inner: 0.
    count: u32,
}

/// The occluders of a scene and their box tree.
#[derive(Clone, Debug)]
pub(crate) struct Occluders {
    pub list: Vec<Occluder>,
    /// The convex solids the occluders make (`solids.rs`), and per occluder its solid.
    pub solids: Vec<Solid>,
    pub solid_of: Vec<u32>,
    nodes: Vec<Node>,
    order: Vec<u32>,
}

impl Occluders {
    /// The occluders of `polys` (merged coplanar neighbours, see the module docs) with
    /// their tree. `scale` is the scene's size (vertices closer than `ON_PLANE · scale`
    /// are one).
    pub fn new(polys: &[(&[DVec3], Plane)], scale: f64) -> Self {
        let list = merge_coplanar(polys, scale);
        let (solids, solid_of) = find_solids(&list, ON_PLANE * scale);
        let mut order: Vec<u32> = (0..list.len() as u32).collect();
        let mut nodes = Vec::with_capacity(2 * list.len() / LEAF_SIZE + 1);
        if !list.is_empty() {
            nodes.push(Node {
                lo: DVec3::ZERO,
                hi: DVec3::ZERO,
                first: 0,
                count: 0,
            });
            // (node, start, end) still to build; bounded: each entry splits a range.
            let mut todo = vec![(0usize, 0usize, list.len())];
            while let Some((node, start, end)) = todo.pop() {
                let (lo, hi) = order[start..end].iter().map(|&k| &list[k as usize]).fold(
                    (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                    |(lo, hi), o| (lo.min(o.lo), hi.max(o.hi)),
                );
                if end - start <= LEAF_SIZE {
                    nodes[node] = Node {
                        lo,
                        hi,
                        first: start as u32,
                        count: (end - start) as u32,
                    };
                    continue;
                }
                // Split at the median centre along the longest axis of the node's box.
                let ext = hi - lo;
                let axis = if ext.x >= ext.y && ext.x >= ext.z {
                    0
                } else if ext.y >= ext.z {
                    1
                } else {
                    2
                };
                let key = |k: &u32| {
                    let o = &list[*k as usize];
                    (o.lo + o.hi)[axis]
                };
                order[start..end].sort_by(|a, b| key(a).total_cmp(&key(b)).then(a.cmp(b)));
                let mid = start + (end - start) / 2;
                let left = nodes.len();
                nodes.push(nodes[node]);
                nodes.push(nodes[node]);
                nodes[node] = Node {
                    lo,
                    hi,
                    first: left as u32,
                    count: 0,
                };
                todo.push((left + 1, mid, end));
                todo.push((left, start, mid));
            }
        }
        Self {
            list,
            solids,
            solid_of,
            nodes,
            order,
        }
    }

    /// The occluders whose boxes overlap the box `[lo, hi]` by more than `tol` on every
    /// axis and that no axis of `shaft` separates from it, into `out` (ascending).
    pub fn overlapping(&self, lo: DVec3, hi: DVec3, tol: f64, shaft: &Shaft, out: &mut Vec<u32>) {
        out.clear();
        if self.nodes.is_empty() {
            return;
        }
        let apart = |a: DVec3, b: DVec3| {
            (a - hi).max_element() >= -tol
                || (lo - b).max_element() >= -tol
                || shaft.separates(a, b)
        };
        // Bounded: each node is visited at most once.
        let mut stack = vec![0u32];
        while let Some(n) = stack.pop() {
            let node = self.nodes[n as usize];
            if apart(node.lo, node.hi) {
                continue;
            }
            if node.count == 0 {
                stack.push(node.first + 1);
                stack.push(node.first);
                continue;
            }
            let (a, b) = (node.first as usize, (node.first + node.count) as usize);
            for &k in &self.order[a..b] {
                let o = &self.list[k as usize];
                if !apart(o.lo, o.hi) {
                    out.push(k);
                }
            }
        }
        out.sort_unstable();
    }
}

/// Axes that separate a box from the convex hull of a pair of polygons, for pruning the
/// box tree before the exact separating-axis test (`hull_meets_polygon`): each axis `a`
/// with the hull's extent `[h_lo, h_hi]` along it and the slack `t = tol |a|` of that
/// test, so that a box with `min a·y ≥ h_hi − t` or `max a·y ≤ h_lo + t` holds only
/// polygons the exact test also finds apart (the same axes, the same inequalities, and a
/// polygon's extent lies inside its box's). The axes: the two polygons' normals, with the
/// condition "reaching strictly in front of both planes" (`max n·(y − o) ≤ tol`: apart),
/// and the hull's side facets (an edge of one polygon with a vertex of the other) that
/// support it (Haines and Wallace's shaft culling, 1994).
#[derive(Debug, Default)]
pub(crate) struct Shaft {
    /// `(axis, h_lo + t, h_hi − t)`: apart when the box's extent along `axis` lies at or
    /// below the first or at or above the second.
    axes: Vec<(DVec3, f64, f64)>,
}

impl Shaft {
    /// The shaft of the hull of `a` and `b` (planes `pa`, `pb`) at tolerance `tol`.
    pub fn of(&mut self, (a, pa): (&[DVec3], &Plane), (b, pb): (&[DVec3], &Plane), tol: f64) {
        self.axes.clear();
        // In front of both planes: apart when max n·y ≤ n·o + tol.
        for p in [pa, pb] {
            self.axes
                .push((p.normal, p.normal.dot(p.origin) + tol, f64::INFINITY));
        }
        for (p, q) in [(a, b), (b, a)] {
            let m = p.len();
            for k in 0..m {
                let (u, v) = (p[k], p[(k + 1) % m]);
                for &w in q {
                    let axis = (v - u).cross(w - u);
                    let len = axis.length();
                    if !(len > 0.0) {
                        continue;
                    }
                    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
                    // Plain comparisons: `f64::min`/`max`'s values up to the sign of a
                    // zero, which the sums and comparisons below do not see.
                    for &y in a.iter().chain(b) {
                        let d = axis.dot(y);
                        lo = if d < lo { d } else { lo };
                        hi = if d > hi { d } else { hi };
                    }
                    // A supporting plane of the hull: the facet's own offset is an extreme.
                    let at = axis.dot(u);
                    let slack = 1e-9 * (hi - lo).abs();
                    if hi - at > slack && at - lo > slack {
                        continue;
                    }
                    let t = tol * len;
                    self.axes.push((axis, lo + t, hi - t));
                }
            }
        }
    }

    /// Whether an axis of the shaft separates the box `[lo, hi]` from the hull.
    pub fn separates(&self, lo: DVec3, hi: DVec3) -> bool {
        let (c, e) = ((lo + hi) * 0.5, (hi - lo) * 0.5);
        self.axes.iter().any(|&(axis, below, above)| {
            let (mid, half) = (axis.dot(c), axis.abs().dot(e));
            // A margin for the rounding of the box's extent: pruning less is always safe.
            let r = 1e-12 * (mid.abs() + half);
            mid + half + r <= below || mid - half - r >= above
        })
    }
}

/// Which side of a plane, given by its signed distance `d`, every point of `p` lies on by
/// more than `tol`: `1` all in front, `-1` all behind, `0` straddling or too close.
pub(crate) fn strict_side(p: &[DVec3], d: impl Fn(DVec3) -> f64, tol: f64) -> i8 {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &v in p {
        let dv = d(v);
        lo = lo.min(dv);
        hi = hi.max(dv);
    }
    if lo > tol {
        1
    } else if hi < -tol {
        -1
    } else {
        0
    }
}

/// Whether the convex occluder `(o, po)` hides every segment from `src` to `tgt` (convex
/// polygons): its plane separates them strictly and every vertex-to-vertex segment crosses
/// it strictly inside `o` (see the module docs). Conservative: `false` when unsure.
pub(crate) fn blocks_all(src: &[DVec3], tgt: &[DVec3], o: &[DVec3], po: &Plane, tol: f64) -> bool {
    let side = |p: &[DVec3]| strict_side(p, |v| po.distance(v), tol);
    let (ss, st) = (side(src), side(tgt));
    if ss == 0 || st == 0 || ss == st {
        return false;
    }
    let m = o.len();
    for &a in src {
        let da = po.distance(a);
        for &b in tgt {
            let db = po.distance(b);
            let c = a + (b - a) * (da / (da - db));
            for e in 0..m {
                let (u, v) = (o[e], o[(e + 1) % m]);
                let edge = v - u;
                // Strictly left of the edge (inside), by more than tol.
                if !(edge.cross(c - u).dot(po.normal) > tol * edge.length()) {
                    return false;
                }
            }
        }
    }
    true
}

/// Quantised plane key: normal and offset, for grouping candidate merges (two polygons of
/// one plane may land in different groups by rounding: they are then not merged, which
/// only costs speed).
fn plane_key(p: &Plane, scale: f64) -> [i64; 4] {
    let q = |x: f64| crate::math::round(x * 1e9) as i64;
    let n = p.normal;
    [q(n.x), q(n.y), q(n.z), q(n.dot(p.centroid) / scale)]
}

/// The union of convex polygons `p` and `q` (one plane, normal `n`) when they share a
/// whole edge in opposite directions and the union is convex; vertices within `tol` are
/// one, collinear vertices are dropped.
fn try_merge(p: &[DVec3], q: &[DVec3], n: DVec3, tol: f64) -> Option<Vec<DVec3>> {
    let same = |a: DVec3, b: DVec3| (a - b).abs().max_element() <= tol;
    let (np, nq) = (p.len(), q.len());
    for ia in 0..np {
        let (a, b) = (p[ia], p[(ia + 1) % np]);
        for iq in 0..nq {
            if !(same(q[iq], b) && same(q[(iq + 1) % nq], a)) {
                continue;
            }
            // p from b round to a, then q after a up to before b.
            let mut m: Vec<DVec3> = (0..np).map(|s| p[(ia + 1 + s) % np]).collect();
            m.extend((2..nq).map(|s| q[(iq + s) % nq]));
            return convex_outline(m, n, tol);
        }
    }
    None
}

/// `m` with collinear (and repeated) vertices removed, if what is left is strictly convex
/// about `n`.
fn convex_outline(mut m: Vec<DVec3>, n: DVec3, tol: f64) -> Option<Vec<DVec3>> {
    // Bounded: each pass removes a vertex or ends.
    for _ in 0..m.len() {
        let k = m.len();
        if k < 3 {
            return None;
        }
        let flat = (0..k).find(|&i| {
            let (a, b, c) = (m[(i + k - 1) % k], m[i], m[(i + 1) % k]);
            let (e1, e2) = (b - a, c - b);
            e1.cross(e2).dot(n).abs() <= tol * (e1.length() + e2.length())
        });
        match flat {
            Some(i) => {
                m.remove(i);
            }
            None => break,
        }
    }
    let k = m.len();
    let convex = k >= 3
        && (0..k).all(|i| {
            let (a, b, c) = (m[(i + k - 1) % k], m[i], m[(i + 1) % k]);
            (b - a).cross(c - b).dot(n) > 0.0
        });
    convex.then_some(m)
}

/// Coplanar neighbours merged (see the module docs), in a deterministic order: groups by
/// plane key, within a group by first polygon index.
fn merge_coplanar(polys: &[(&[DVec3], Plane)], scale: f64) -> Vec<Occluder> {
    let tol = ON_PLANE * scale;
    let mut idx: Vec<usize> = (0..polys.len()).collect();
    let keys: Vec<[i64; 4]> = polys.iter().map(|(_, p)| plane_key(p, scale)).collect();
    idx.sort_by(|&a, &b| keys[a].cmp(&keys[b]).then(a.cmp(&b)));
    let mut out = Vec::with_capacity(polys.len());
    let mut start = 0;
    while start < idx.len() {
        let mut end = start + 1;
        while end < idx.len() && keys[idx[end]] == keys[idx[start]] {
            end += 1;
        }
        let n = polys[idx[start]].1.normal;
        let mut group: Vec<Option<Vec<DVec3>>> = idx[start..end]
            .iter()
            .map(|&i| Some(polys[i].0.to_vec()))
            .collect();
        let mut boxes: Vec<(DVec3, DVec3)> = idx[start..end]
            .iter()
            .map(|&i| bounds(polys[i].0.iter().copied()))
            .collect();
        for _ in 0..MAX_MERGE_PASSES {
            let mut merged_any = false;
            for a in 0..group.len() {
                if group[a].is_none() {
                    continue;
                }
                for b in a + 1..group.len() {
                    let (Some(pa), Some(pb)) = (&group[a], &group[b]) else {
                        continue;
                    };
                    let (la, ha) = boxes[a];
                    let (lb, hb) = boxes[b];
                    if (lb - ha).max_element() > tol || (la - hb).max_element() > tol {
                        continue;
                    }
                    if let Some(m) = try_merge(pa, pb, n, tol) {
                        boxes[a] = (la.min(lb), ha.max(hb));
                        group[a] = Some(m);
                        group[b] = None;
                        merged_any = true;
                    }
                }
            }
            if !merged_any {
                break;
            }
        }
        for (g, &i) in group.into_iter().zip(&idx[start..end]) {
            let Some(v) = g else { continue };
            // A merged outline's own plane (the polygon's if unmerged or degenerate).
            let plane = Plane::of(&v).unwrap_or(polys[i].1);
            let (lo, hi) = bounds(v.iter().copied());
            out.push(Occluder {
                vertices: v,
                plane,
                lo,
                hi,
            });
        }
        start = end;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(k: usize) -> Vec<Vec<DVec3>> {
        let mut cells = Vec::new();
        let h = 1.0 / k as f64;
        for i in 0..k {
            for j in 0..k {
                let (x, y) = (i as f64 * h, j as f64 * h);
                cells.push(vec![
                    DVec3::new(x, y, 0.0),
                    DVec3::new(x + h, y, 0.0),
                    DVec3::new(x + h, y + h, 0.0),
                    DVec3::new(x, y + h, 0.0),
                ]);
            }
        }
        cells
    }

    #[test]
    fn a_grid_merges_into_its_square_and_the_tree_finds_it() {
        let cells = grid(10);
        let mut polys: Vec<(&[DVec3], Plane)> = cells
            .iter()
            .map(|c| (c.as_slice(), Plane::of(c).unwrap()))
            .collect();
        // A square of another plane stays apart.
        let other = [
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(0.0, 1.0, 1.0),
        ];
        polys.push((&other, Plane::of(&other).unwrap()));
        let occ = Occluders::new(&polys, 1.0);
        assert_eq!(occ.list.len(), 2);
        let areas: Vec<f64> = occ.list.iter().map(|o| o.plane.area).collect();
        assert!(areas.iter().all(|a| (a - 1.0).abs() < 1e-12), "{areas:?}");
        assert!(occ.list.iter().all(|o| o.vertices.len() == 4));
        let mut out = Vec::new();
        occ.overlapping(
            DVec3::new(0.2, 0.2, 0.5),
            DVec3::new(0.3, 0.3, 2.0),
            0.0,
            &Shaft::default(),
            &mut out,
        );
        assert_eq!(out.len(), 1);
        assert_eq!(occ.list[out[0] as usize].lo.z, 1.0);
    }

    #[test]
    fn an_l_shape_does_not_merge_into_a_non_convex_occluder() {
        let cells = grid(2);
        let polys: Vec<(&[DVec3], Plane)> = cells[..3]
            .iter()
            .map(|c| (c.as_slice(), Plane::of(c).unwrap()))
            .collect();
        let occ = Occluders::new(&polys, 1.0);
        let total: f64 = occ.list.iter().map(|o| o.plane.area).sum();
        assert!((total - 0.75).abs() < 1e-12);
        assert_eq!(occ.list.len(), 2);
    }

    #[test]
    fn a_large_plate_between_two_squares_blocks_all() {
        let sq = |z: f64, s: f64| {
            [
                DVec3::new(-s, -s, z),
                DVec3::new(s, -s, z),
                DVec3::new(s, s, z),
                DVec3::new(-s, s, z),
            ]
        };
        let (src, tgt) = (sq(0.0, 0.5), sq(2.0, 0.5));
        let big = sq(1.0, 0.6);
        let small = sq(1.0, 0.4);
        assert!(blocks_all(
            &src,
            &tgt,
            &big,
            &Plane::of(&big).unwrap(),
            1e-12
        ));
        assert!(!blocks_all(
            &src,
            &tgt,
            &small,
            &Plane::of(&small).unwrap(),
            1e-12
        ));
        // A plate beyond the target separates nothing.
        let beyond = sq(3.0, 5.0);
        assert!(!blocks_all(
            &src,
            &tgt,
            &beyond,
            &Plane::of(&beyond).unwrap(),
            1e-12
        ));
    }
}
