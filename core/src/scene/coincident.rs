//! Coincident surfaces: two flatland segments on one line, or two 3D faces in one plane,
//! facing the same way and overlapping over a positive length or area.
//!
//! Such a pair is two surfaces in one place: which one a line meets first is decided by
//! rounding, so form factors to either are arbitrary (and Monte Carlo may starve one of
//! samples). The builders refuse them ([`ErrorKind::CoincidentSurfaces`]). Opposite facings
//! are legal (a two-sided wall), as are surfaces that only touch (a wall cut into pieces).
//!
//! # Tolerances
//!
//! With `R` the largest coordinate magnitude of the scene, two surfaces coincide when
//!
//! ```text
//! |n_i − n_j|_∞ ≤ 1e-9          unit directions (2D) or normals (3D), same facing
//! |dist(v, plane_i)| ≤ 1e-12 R  for every vertex v of j (and of i to plane j)
//! overlap depth > 1e-12 R        along every separating axis (convex sets)
//! ```
//!
//! `1e-12 R` is ten times the exact flatland form factors' "on a line" tolerance, so what
//! this refuses is what they could not tell apart; nearly coincident surfaces further
//! apart are legal and measured.
//!
//! # Cost
//!
//! `O(n log n)` to accept a scene: surfaces are sorted by their quantised direction and line
//! offset (cells of `1e-6`, `1e-6 R`), then each is compared with those of its cell (and of
//! a neighbour cell when it lies within the tolerance of a cell boundary) whose extent
//! along the direction overlaps its own (3D: whose box overlaps, through a box tree per
//! cell). Refusing a scene needs the *first* coincident pair in input order, and a search
//! that looked at every candidate pair would be quadratic in `k` copies of one surface
//! (`k (k − 1) / 2` pairs: 200,000 copies of a segment took minutes). So the search stops
//! at the first pair it meets, and the first pair is found by bisection on the input
//! prefix (`first_in_order`): `O(n log² n)`, whatever the duplicates.
//!
//! What stays quadratic: many surfaces of one cell (directions within `1e-6`, offsets
//! within `1e-6 R`) whose extents overlap yet none of which coincide, a flood of nearly
//! coincident surfaces; no scene of the catalogue or the corpus comes near one.

use alloc::vec::Vec;

use crate::error::{ErrorKind, Result};
use crate::geom::{DVec2, DVec3, cross};

/// Largest difference of unit directions or normals, per component, between coincident
/// surfaces.
const DIRECTION_TOLERANCE: f64 = 1e-9;

/// Distance tolerance, relative to the scene's largest coordinate magnitude.
const DISTANCE_TOLERANCE: f64 = 1e-12;

/// Cell width of the direction components.
const DIRECTION_CELL: f64 = 1e-6;

/// Cell width of the line or plane offset, relative to the largest coordinate magnitude.
const OFFSET_CELL: f64 = 1e-6;

/// One surface in the sort: its cell, its extent along the sweep axis, its index.
struct Entry<const K: usize> {
    cell: [i64; K],
    /// Fractional positions inside the cell, per dimension, to find near-boundary ones.
    frac: [f64; K],
    lo: f64,
    hi: f64,
    index: usize,
}

/// Quantises `x` into cells of width `w`: the cell and the position inside it in `[0, 1)`.
fn quantise(x: f64, w: f64) -> (i64, f64) {
    let x = x / w;
    // Floor by a saturating cast (the values are bounded: unit vectors, offsets ≤ 2R)
    let t = x as i64;
    let q = if (t as f64) > x { t - 1 } else { t };
    (q, x - q as f64)
}

/// The first coincident pair in input order, `(i, j)` with `i < j`, `j` as small as
/// possible and then `i`, from `any_among(m)`, which finds some coincident pair among the
/// surfaces `0..m` (or none), and `coincide(i, j)`.
///
/// The surfaces `0..m` contain a pair exactly when `m > j*`, the second index of the first
/// pair, so `j*` is found by bisection on `m`, a pair found for a prefix tightening the upper
/// end; then `i*` is the smallest `i` that coincides with `j*`. `⌈log₂ n⌉ + 1` searches
/// and `j*` tests.
fn first_in_order(
    n: usize,
    any_among: impl Fn(usize) -> Option<(usize, usize)>,
    coincide: impl Fn(usize, usize) -> bool,
) -> Option<(usize, usize)> {
    // `hi` always contains a pair, `lo` is the smallest prefix that may
    let (_, first) = any_among(n)?;
    let (mut lo, mut hi) = (2, first + 1);
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        match any_among(mid) {
            Some((_, j)) => hi = j + 1,
            None => lo = mid + 1,
        }
    }
    let j = hi - 1;
    (0..j).find(|&i| coincide(i, j)).map(|i| (i, j))
}

/// Sweeps the entries (sorted by cell, then `lo`) of the surfaces `0..limit` and returns the
/// first pair `precise` accepts, `(i, j)` with `i < j`.
fn sweep<const K: usize>(
    entries: &[Entry<K>],
    limit: usize,
    slack: [f64; K],
    window: f64,
    precise: impl Fn(usize, usize) -> bool,
) -> Option<(usize, usize)> {
    // The prefix, still sorted
    let kept: Vec<&Entry<K>> = entries.iter().filter(|e| e.index < limit).collect();
    for e in &kept {
        // The cells to search: this one, and a neighbour per dimension where e lies
        // within the tolerance of the boundary.
        let mut offsets: heapless::Vec<[i64; K], 81> = heapless::Vec::new();
        let _ = offsets.push([0; K]);
        for d in 0..K {
            let steps: heapless::Vec<i64, 2> = [
                (e.frac[d] < slack[d]).then_some(-1),
                (e.frac[d] > 1.0 - slack[d]).then_some(1),
            ]
            .into_iter()
            .flatten()
            .collect();
            let current = offsets.clone();
            for step in steps {
                for o in &current {
                    let mut o = *o;
                    o[d] = step;
                    let _ = offsets.push(o);
                }
            }
        }
        for o in &offsets {
            let mut cell = e.cell;
            for d in 0..K {
                cell[d] = cell[d].saturating_add(o[d]);
            }
            // Entries of that cell starting before e ends (those starting before e's start
            // are found from their own side, unless they start within the window)
            let from =
                kept.partition_point(|x| x.cell < cell || (x.cell == cell && x.lo < e.lo - window));
            let to =
                kept.partition_point(|x| x.cell < cell || (x.cell == cell && x.lo < e.hi - window));
            for x in &kept[from..to.max(from)] {
                if x.index == e.index {
                    continue;
                }
                let pair = (x.index.min(e.index), x.index.max(e.index));
                if precise(pair.0, pair.1) {
                    return Some(pair);
                }
            }
        }
    }
    None
}

/// The first pair of coincident flatland segments `(a, b)` (each facing its left), as
/// indices `(i, j)` with `i < j` and `j` as small as possible.
#[must_use]
pub(crate) fn coincident_segments(segments: &[(DVec2, DVec2)]) -> Option<(usize, usize)> {
    let r = segments
        .iter()
        .flat_map(|&(a, b)| [a.x, a.y, b.x, b.y])
        .fold(f64::MIN_POSITIVE, |m, v| m.max(v.abs()));
    let tol = DISTANCE_TOLERANCE * r;
    let unit = |k: usize| {
        let (a, b) = segments[k];
        (b - a) / crate::math::hypot(b.x - a.x, b.y - a.y)
    };
    let mut entries: Vec<Entry<3>> = Vec::with_capacity(segments.len());
    for (k, &(a, b)) in segments.iter().enumerate() {
        let d = unit(k);
        let c = cross(d, a);
        let cells = [
            quantise(d.x, DIRECTION_CELL),
            quantise(d.y, DIRECTION_CELL),
            quantise(c, OFFSET_CELL * r),
        ];
        let (t0, t1) = (d.dot(a), d.dot(b));
        entries.push(Entry {
            cell: cells.map(|c| c.0),
            frac: cells.map(|c| c.1),
            lo: t0.min(t1),
            hi: t0.max(t1),
            index: k,
        });
    }
    let direction_slack = DIRECTION_TOLERANCE / DIRECTION_CELL;
    // Offsets c = d × a of coincident segments differ by the tolerance plus the direction
    // difference times |a| ≤ √2 R.
    let offset_slack = (tol + 2.0 * DIRECTION_TOLERANCE * r) / (OFFSET_CELL * r);
    let precise = |i: usize, j: usize| {
        let (di, dj) = (unit(i), unit(j));
        let (ai, bi) = segments[i];
        let (aj, bj) = segments[j];
        let length = (bi - ai).dot(di);
        let (s0, s1) = ((aj - ai).dot(di), (bj - ai).dot(di));
        (di - dj).abs().max_element() <= DIRECTION_TOLERANCE
            && di.dot(dj) > 0.0
            && cross(di, aj - ai).abs() <= tol
            && cross(di, bj - ai).abs() <= tol
            && cross(dj, ai - aj).abs() <= tol
            && cross(dj, bi - aj).abs() <= tol
            && s1.min(length) - s0.max(0.0) > tol
    };
    entries.sort_by(|a, b| a.cell.cmp(&b.cell).then(a.lo.total_cmp(&b.lo)));
    let slack = [direction_slack, direction_slack, offset_slack];
    let window = 2.0 * DIRECTION_TOLERANCE * r + tol;
    first_in_order(
        segments.len(),
        |m| sweep(&entries, m, slack, window, precise),
        precise,
    )
}

/// The first pair of coincident convex planar faces, given as vertex lists with unit
/// normals, as indices `(i, j)` with `i < j` and `j` as small as possible.
#[must_use]
pub(crate) fn coincident_faces(faces: &[(&[DVec3], DVec3)]) -> Option<(usize, usize)> {
    let any_among = |m: usize| {
        let mut pair = None;
        visit_face_pairs(faces, m, &mut |p| {
            pair = Some(p);
            false
        });
        pair
    };
    let tol = face_tolerance(faces);
    first_in_order(faces.len(), any_among, |i, j| {
        faces_coincide(faces[i], faces[j], tol)
    })
}

/// Whether two faces (vertices, unit normal) coincide with distance tolerance `tol`: same
/// facing, each one's vertices on the other's plane, overlapping (module docs).
fn faces_coincide((vi, ni): (&[DVec3], DVec3), (vj, nj): (&[DVec3], DVec3), tol: f64) -> bool {
    let on_plane = |vs: &[DVec3], n: DVec3, p: DVec3| vs.iter().all(|v| n.dot(*v - p).abs() <= tol);
    let (Some(&pi), Some(&pj)) = (vi.first(), vj.first()) else {
        return false;
    };
    (ni - nj).abs().max_element() <= DIRECTION_TOLERANCE
        && ni.dot(nj) > 0.0
        && on_plane(vj, ni, pi)
        && on_plane(vi, nj, pj)
        && convex_overlap(vi, vj, ni, tol)
}

/// The distance tolerance of coincidence for these faces: `1e-12 R`, with `R` their
/// largest coordinate magnitude (module docs).
#[must_use]
pub(crate) fn face_tolerance(faces: &[(&[DVec3], DVec3)]) -> f64 {
    DISTANCE_TOLERANCE * largest_magnitude(faces)
}

/// The largest coordinate magnitude `R` of the faces (at least the smallest normal).
fn largest_magnitude(faces: &[(&[DVec3], DVec3)]) -> f64 {
    faces
        .iter()
        .flat_map(|(v, _)| v.iter().flat_map(|p| p.to_array()))
        .fold(f64::MIN_POSITIVE, |m, v| m.max(v.abs()))
}

/// Most coincident pairs [`coincident_face_pairs`] gathers.
pub(crate) const MAX_COINCIDENT_PAIRS: usize = 1_000_000;

/// The pairs of coincident faces, as `(i, j)` with `i < j`, sorted by `j` then `i`: every
/// pair, except that a later exact copy of a face (the same vertices in the same cyclic
/// order, bit for bit, and the same normal) is paired with the face's first copy only.
///
/// A copy coincides with whatever its original coincides with, so the pairs left out say
/// nothing new; without them `k` copies of one face make `k − 1` pairs instead of
/// `k (k − 1) / 2`, and 200,000 copies load in a fraction of a second instead of running
/// into the cap after half a minute. Copies are found by sorting a canonical key (the
/// vertex list rotated to start at its smallest vertex): `O(n log n)`.
///
/// # Errors
/// [`ErrorKind::TooLarge`] beyond [`MAX_COINCIDENT_PAIRS`] pairs.
pub(crate) fn coincident_face_pairs(faces: &[(&[DVec3], DVec3)]) -> Result<Vec<(usize, usize)>> {
    // The first copy of each face, and the distinct faces alone
    let first = first_copies(faces);
    let distinct: Vec<usize> = (0..faces.len()).filter(|&k| first[k] == k).collect();
    let list: Vec<(&[DVec3], DVec3)> = distinct.iter().map(|&k| faces[k]).collect();
    let mut pairs: Vec<(usize, usize)> = (0..faces.len())
        .filter(|&k| first[k] != k)
        .map(|k| (first[k], k))
        .collect();
    let mut overflow = pairs.len() > MAX_COINCIDENT_PAIRS;
    // (The distinct faces span the same coordinates, so the tolerance is the scene's.)
    visit_face_pairs(&list, list.len(), &mut |(i, j)| {
        // A pair may be met from both of its faces: room for each twice
        if overflow || pairs.len() >= 3 * MAX_COINCIDENT_PAIRS {
            overflow = true;
            return false;
        }
        pairs.push((distinct[i], distinct[j]));
        true
    });
    pairs.sort_unstable_by_key(|&(i, j)| (j, i));
    pairs.dedup();
    if overflow || pairs.len() > MAX_COINCIDENT_PAIRS {
        return Err(ErrorKind::TooLarge {
            what: "pairs of coincident faces",
            max: MAX_COINCIDENT_PAIRS as u64,
        }
        .into());
    }
    Ok(pairs)
}

/// For each face, the index of its first exact copy (itself when it is the first).
fn first_copies(faces: &[(&[DVec3], DVec3)]) -> Vec<usize> {
    // The canonical rotation of a face: the start of its smallest vertex (by bits)
    let bits = |p: &DVec3| p.to_array().map(f64::to_bits);
    // Each face's vertex count, normal and start, found once rather than per comparison
    let heads: Vec<(usize, [u64; 3], usize)> = faces
        .iter()
        .map(|&(v, n)| {
            let start = (0..v.len()).min_by_key(|&k| bits(&v[k])).unwrap_or(0);
            (v.len(), bits(&n), start)
        })
        .collect();
    let key = |k: usize| {
        let (v, _) = faces[k];
        let (len, n, s) = heads[k];
        (len, n, v[s..].iter().chain(&v[..s]).map(bits))
    };
    // Faces by (vertex count, normal, rotated vertices), then index: a total order, so
    // an unstable sort gives the one result
    let mut order: Vec<usize> = (0..faces.len()).collect();
    order.sort_unstable_by(|&a, &b| {
        let ((la, na, va), (lb, nb, vb)) = (key(a), key(b));
        la.cmp(&lb)
            .then(na.cmp(&nb))
            .then_with(|| va.cmp(vb))
            .then(a.cmp(&b))
    });
    let mut first: Vec<usize> = (0..faces.len()).collect();
    for w in 1..order.len() {
        let (a, b) = (order[w - 1], order[w]);
        let ((la, na, va), (lb, nb, vb)) = (key(a), key(b));
        if la == lb && na == nb && va.eq(vb) {
            first[b] = first[a];
        }
    }
    first
}

/// One face in the search: its cell (normal and plane offset), its position inside the
/// cell, its bounding box widened by the tolerance, its index.
#[derive(Clone, Copy)]
struct FaceEntry {
    cell: [i64; 4],
    frac: [f64; 4],
    lo: DVec3,
    hi: DVec3,
    index: usize,
}

/// A node of a bounding-box tree over one cell's faces: its box and either its two
/// children or its range of entries.
#[derive(Clone, Copy)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    /// Entries `start..end` of the cell (a leaf) when `children` is `None`.
    start: usize,
    end: usize,
    children: Option<(usize, usize)>,
}

/// Most entries of a leaf.
const LEAF: usize = 4;

/// Builds the tree over `entries` (reordering them), appending its nodes to `nodes` with
/// entry ranges offset by `base`; returns the root's index. Median splits along the widest
/// axis of the boxes' centres: depth `⌈log₂(n / LEAF)⌉ + 1`, `O(n log n)`.
fn build_tree(entries: &mut [FaceEntry], base: usize, nodes: &mut Vec<Node>) -> usize {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    let (mut clo, mut chi) = (lo, hi);
    for e in entries.iter() {
        lo = lo.min(e.lo);
        hi = hi.max(e.hi);
        let c = (e.lo + e.hi) * 0.5;
        clo = clo.min(c);
        chi = chi.max(c);
    }
    let me = nodes.len();
    nodes.push(Node {
        lo,
        hi,
        start: base,
        end: base + entries.len(),
        children: None,
    });
    if entries.len() <= LEAF {
        return me;
    }
    let extent = chi - clo;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let mid = entries.len() / 2;
    let centre = |e: &FaceEntry| (e.lo[axis] + e.hi[axis]) * 0.5;
    entries.select_nth_unstable_by(mid, |a, b| centre(a).total_cmp(&centre(b)));
    let (left, right) = entries.split_at_mut(mid);
    let l = build_tree(left, base, nodes);
    let r = build_tree(right, base + mid, nodes);
    nodes[me].children = Some((l, r));
    me
}

/// Calls `found((i, j))`, `i < j`, for pairs of coincident faces among the faces
/// `0..limit`, stopping when it returns false; a pair may be met twice.
///
/// Faces are grouped by cell (quantised normal and plane offset, as the module docs say);
/// each group gets a bounding-box tree, and each face queries its own group's tree (and a
/// neighbour group's when it lies within the tolerance of a cell boundary) with its box:
/// `O(n log n)` for faces whose boxes overlap a bounded number of others — a floor of 10⁶
/// triangles in one plane included, where a sweep along one axis is quadratic along a row.
fn visit_face_pairs(
    faces: &[(&[DVec3], DVec3)],
    limit: usize,
    found: &mut dyn FnMut((usize, usize)) -> bool,
) {
    // `dyn`: one copy of this search serves both callers (it is the larger part of the
    // loaders' code in the browser's module)
    // The whole scene's tolerance, whatever the prefix
    let r = largest_magnitude(faces);
    let tol = DISTANCE_TOLERANCE * r;
    let mut entries: Vec<FaceEntry> = Vec::with_capacity(faces.len().min(limit));
    for (k, &(vertices, n)) in faces.iter().enumerate().take(limit) {
        let Some(&p0) = vertices.first() else {
            continue;
        };
        let cells = [
            quantise(n.x, DIRECTION_CELL),
            quantise(n.y, DIRECTION_CELL),
            quantise(n.z, DIRECTION_CELL),
            quantise(n.dot(p0), OFFSET_CELL * r),
        ];
        let (lo, hi) = vertices.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        entries.push(FaceEntry {
            cell: cells.map(|c| c.0),
            frac: cells.map(|c| c.1),
            lo: lo - DVec3::splat(tol),
            hi: hi + DVec3::splat(tol),
            index: k,
        });
    }
    let direction_slack = DIRECTION_TOLERANCE / DIRECTION_CELL;
    let offset_slack = (tol + 2.0 * DIRECTION_TOLERANCE * r) / (OFFSET_CELL * r);
    let slack = [
        direction_slack,
        direction_slack,
        direction_slack,
        offset_slack,
    ];
    let precise = |i: usize, j: usize| faces_coincide(faces[i], faces[j], tol);
    // Groups of one cell, each with its tree
    entries.sort_unstable_by_key(|e| e.cell);
    let mut groups: Vec<([i64; 4], usize)> = Vec::new();
    let mut nodes: Vec<Node> = Vec::new();
    let mut start = 0;
    while start < entries.len() {
        let cell = entries[start].cell;
        let end = start + entries[start..].partition_point(|e| e.cell == cell);
        let root = build_tree(&mut entries[start..end], start, &mut nodes);
        groups.push((cell, root));
        start = end;
    }
    let mut stack: Vec<usize> = Vec::new();
    for e in &entries {
        // This cell, and a neighbour per dimension where e lies near the boundary
        let mut offsets: heapless::Vec<[i64; 4], 81> = heapless::Vec::new();
        let _ = offsets.push([0; 4]);
        for d in 0..4 {
            let steps = [
                (e.frac[d] < slack[d]).then_some(-1),
                (e.frac[d] > 1.0 - slack[d]).then_some(1),
            ];
            let current = offsets.clone();
            for step in steps.into_iter().flatten() {
                for o in &current {
                    let mut o = *o;
                    o[d] = step;
                    let _ = offsets.push(o);
                }
            }
        }
        for o in &offsets {
            let own = *o == [0; 4];
            let mut cell = e.cell;
            for d in 0..4 {
                cell[d] = cell[d].saturating_add(o[d]);
            }
            let Ok(g) = groups.binary_search_by(|x| x.0.cmp(&cell)) else {
                continue;
            };
            // The tree walk: every node is pushed at most once
            stack.clear();
            stack.push(groups[g].1);
            while let Some(k) = stack.pop() {
                let node = nodes[k];
                if node.lo.cmpgt(e.hi).any() || node.hi.cmplt(e.lo).any() {
                    continue;
                }
                if let Some((l, r)) = node.children {
                    stack.push(l);
                    stack.push(r);
                    continue;
                }
                for x in &entries[node.start..node.end] {
                    // In its own cell a pair is met from both faces: tested from the later
                    if x.index == e.index
                        || (own && x.index > e.index)
                        || x.lo.cmpgt(e.hi).any()
                        || x.hi.cmplt(e.lo).any()
                    {
                        continue;
                    }
                    let pair = (x.index.min(e.index), x.index.max(e.index));
                    if precise(pair.0, pair.1) && !found(pair) {
                        return;
                    }
                }
            }
        }
    }
}

/// Whether two coplanar convex polygons (plane normal `n`) overlap deeper than `tol` along
/// every edge normal of both (the separating axis theorem): touching along an edge or at a
/// vertex is not overlap.
fn convex_overlap(a: &[DVec3], b: &[DVec3], n: DVec3, tol: f64) -> bool {
    // A basis of the plane
    let u = n.any_orthonormal_vector();
    let v = n.cross(u);
    let flat = |p: &DVec3| DVec2::new(p.dot(u), p.dot(v));
    let separated_by_edges_of = |p: &[DVec3]| {
        (0..p.len()).any(|k| {
            let e = flat(&p[(k + 1) % p.len()]) - flat(&p[k]);
            let len = crate::math::hypot(e.x, e.y);
            if !(len > 0.0) {
                return false;
            }
            let axis = DVec2::new(-e.y, e.x) / len;
            let span = |q: &[DVec3]| {
                q.iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                        let s = flat(x).dot(axis);
                        (lo.min(s), hi.max(s))
                    })
            };
            let ((a0, a1), (b0, b1)) = (span(a), span(b));
            a1.min(b1) - a0.max(b0) <= tol
        })
    };
    !(separated_by_edges_of(a) || separated_by_edges_of(b))
}

/// Refuses coincident surfaces found by `find`.
///
/// # Errors
///
/// [`ErrorKind::CoincidentSurfaces`] naming the pair.
pub(crate) fn refuse(found: Option<(usize, usize)>) -> Result<()> {
    match found {
        Some((first, second)) => Err(ErrorKind::CoincidentSurfaces { first, second }.into()),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn v2(x: f64, y: f64) -> DVec2 {
        DVec2::new(x, y)
    }

    #[test]
    fn segments_on_one_line_facing_one_way_and_overlapping_coincide() {
        let floor = (v2(0.0, 0.0), v2(1.0, 0.0));
        assert_eq!(coincident_segments(&[floor, floor]), Some((0, 1)));
        let shifted = (v2(0.5, 0.0), v2(1.5, 0.0));
        assert_eq!(coincident_segments(&[floor, shifted]), Some((0, 1)));
        // A two-sided wall, pieces that only touch, parallel neighbours: all legal
        let reversed = (v2(1.0, 0.0), v2(0.0, 0.0));
        let next = (v2(1.0, 0.0), v2(2.0, 0.0));
        let above = (v2(0.0, 1e-6), v2(1.0, 1e-6));
        let tilted = (v2(0.0, 0.0), v2(1.0, 1e-7));
        for other in [reversed, next, above, tilted] {
            assert_eq!(coincident_segments(&[floor, other]), None, "{other:?}");
        }
        // The first coincidence in input order is reported
        let far = (v2(5.0, 5.0), v2(6.0, 5.0));
        assert_eq!(
            coincident_segments(&[far, floor, next, far, floor]),
            Some((0, 3))
        );
    }

    #[test]
    fn faces_in_one_plane_facing_one_way_and_overlapping_coincide() {
        let square = |dx: f64, z: f64| {
            [
                DVec3::new(dx, 0.0, z),
                DVec3::new(dx + 1.0, 0.0, z),
                DVec3::new(dx + 1.0, 1.0, z),
                DVec3::new(dx, 1.0, z),
            ]
        };
        let (a, b, c, d) = (
            square(0.0, 0.0),
            square(0.5, 0.0),
            square(1.0, 0.0),
            square(0.0, 1e-6),
        );
        let mut rotated = a;
        rotated.rotate_left(1);
        let mut reversed = a;
        reversed.reverse();
        let (up, down) = (DVec3::Z, -DVec3::Z);
        assert_eq!(coincident_faces(&[(&a, up), (&rotated, up)]), Some((0, 1)));
        assert_eq!(coincident_faces(&[(&a, up), (&b, up)]), Some((0, 1)));
        for (other, n) in [(&reversed, down), (&c, up), (&d, up)] {
            assert_eq!(coincident_faces(&[(&a, up), (other, n)]), None, "{other:?}");
        }
    }

    #[test]
    fn many_copies_are_refused_by_their_first_pair() {
        // 200,000 copies of one segment or one square: k (k − 1) / 2 pairs, found in
        // O(n log² n); the first pair in input order is named.
        let floor = (v2(0.0, 0.0), v2(1.0, 0.0));
        let far = (v2(5.0, 5.0), v2(6.0, 5.0));
        let mut segments = alloc::vec![floor; 200_000];
        segments[0] = far;
        assert_eq!(coincident_segments(&segments), Some((1, 2)));
        let square = [
            DVec3::new(0.0, 0.0, 0.0),
            DVec3::new(1.0, 0.0, 0.0),
            DVec3::new(1.0, 1.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let faces = alloc::vec![(&square[..], DVec3::Z); 200_000];
        assert_eq!(coincident_faces(&faces), Some((0, 1)));
        // Loaded as drawn: each copy paired with the first only
        let mut rotated = square;
        rotated.rotate_left(1);
        let mut faces = faces;
        faces[7] = (&rotated[..], DVec3::Z);
        let pairs = coincident_face_pairs(&faces).unwrap();
        assert_eq!(pairs.len(), 199_999, "a rotated copy is a copy");
        assert_eq!(&pairs[..3], &[(0, 1), (0, 2), (0, 3)]);
        assert!(pairs.contains(&(0, 7)));
        // Distinct surfaces before the copies: the first pair lies deep in the input
        let mut segments: Vec<_> = (0..100_000)
            .map(|k| (v2(k as f64, 0.0), v2(k as f64 + 1.0, 0.0)))
            .collect();
        segments.extend(core::iter::repeat_n((v2(7.5, 0.0), v2(8.5, 0.0)), 1000));
        assert_eq!(coincident_segments(&segments), Some((7, 100_000)));
    }

    #[test]
    fn preset_scenes_have_no_coincident_surfaces() {
        // Their builders run the check: cut faces only touch, packed cubes face each other.
        for name in [
            "cube",
            "cornell",
            "cornell-lifted",
            "cubes-27-clustered",
            "64-cubes-0",
        ] {
            let scene = crate::scene::Scene3::preset(name, 3);
            assert!(scene.is_ok(), "{name}: {scene:?}");
        }
        for name in ["16-squares-0", "three-objects-5", "koch-3", "l-room-3"] {
            let scene = crate::scene::Scene2::catalogue(name, 4);
            assert!(scene.is_ok(), "{name}: {scene:?}");
        }
    }

    proptest! {
        /// A copy of a segment slid along its own line by less than its length coincides
        /// with it; slid by its length or more (touching or apart), or reversed, it does
        /// not. Anywhere in the plane, at any scale.
        #[test]
        fn sliding_a_segment_along_its_line(
            ax in -1e3..1e3f64, ay in -1e3..1e3f64,
            angle in 0.0..core::f64::consts::TAU, length in 1e-3..1e3f64,
            slide in -0.99..0.99f64, apart in 1.0..3.0f64,
        ) {
            let a = v2(ax, ay);
            let d = v2(crate::math::cos(angle), crate::math::sin(angle));
            let b = a + d * length;
            let seg = (a, b);
            let slid = |t: f64| (a + d * (t * length), b + d * (t * length));
            prop_assert_eq!(coincident_segments(&[seg, slid(slide)]), Some((0, 1)));
            prop_assert_eq!(coincident_segments(&[seg, slid(apart)]), None);
            prop_assert_eq!(coincident_segments(&[seg, slid(-apart)]), None);
            prop_assert_eq!(coincident_segments(&[seg, (b, a)]), None);
        }
    }
}
