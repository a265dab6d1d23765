//! Convex solids made of occluders (a cube, a building), and the conservative test "the
//! solid hides every sight line of a pair", which catches pairs that no single face hides
//! (sight lines entering a box through its front and its top).
//!
//! **The solids.** Occluders (after merging, `occluders.rs`) that share a whole edge in
//! opposite directions, each lying behind the other's plane (a convex fold of outward
//! faces), are joined; a set so joined is a solid `K` when every vertex of it lies behind
//! or on every face plane (convex), and its edges that no other face of it shares are all
//! missing: closed, or lie in one plane `P` with the solid behind it, the open face (a
//! building without a floor standing on the ground). `K` is the intersection of the faces'
//! half-spaces (and `P`'s).
//!
//! **The test** ([`Solid::hides`]). Let a plane `Π` strictly separate the source `S` from
//! the target `T`. Every segment `σ = [s, t]` crosses `Π` once, at a point `c` of the convex
//! hull of the crossings `c_ab` of the vertex-to-vertex segments (see `blocks_all`). If every
//! `c_ab` lies inside `K` by more than the contact tolerance, every `c` does, so `σ` passes
//! through `K`'s interior. (Crossings on the open face are allowed: they make an edge of
//! that hull, crossed by a set of sight lines of no measure — a street seen along the
//! ground under a building.) If moreover `S` lies strictly outside `K` (beyond one face
//! plane), `σ` enters `K` at a point `e` of `∂K` strictly between `s` and `c`; `e` lies on a
//! face `F`. `F` is not in the plane of `S` (`σ` meets that plane only at `s`), nor in the
//! plane of `T` (only at `t`, beyond `c`), and not the open face `P` when `S` and `T` lie
//! on `K`'s side of `P` (a linear function `≥ 0` at both ends of `σ` and `0` at an
//! interior point is `0` on all of `σ`, so `c` would lie on `P`, not inside `K`). So `F`
//! is an opaque face that meets `σ` strictly inside it, and `σ` is hidden. The same with
//! `T` outside and the exit point. Hence `F_ST = 0` exactly, without integration.
//! The planes `Π` tried pass through `K`'s centre: across the line between the two
//! polygons' centroids, and parallel to each face. Conservative: `false` when unsure.
//!
//! **Back faces.** By the same argument, when `S` lies outside `K` every sight line from
//! `S` through `K`'s interior enters it through a face whose front (outward side) holds its
//! start; a face with all of `S` behind or on its plane is never that face, so it can be
//! left out of the pair's occluders without changing what is hidden (the union of the
//! shadows is the same up to sight lines grazing `K`, a set of no area).
//!
//! Tolerances: "on `K`'s side of `P`" and "inside `K`" use the contact tolerance of the
//! parent module; sight lines from points within it of `P` may pass below it, a band of
//! area of that relative order, as for the near guard.

use alloc::vec::Vec;

use super::occluders::{Occluder, strict_side};
use crate::geom::DVec3;

/// No solid: the mark of an occluder that is a face of none.
pub(crate) const NO_SOLID: u32 = u32::MAX;

/// A convex solid: its face planes, outward (inside `n · y < d`), the open face's last.
#[derive(Clone, Debug)]
pub(crate) struct Solid {
    /// `(n, d)`, `n` a unit outward normal.
    planes: Vec<(DVec3, f64)>,
    /// Whether the last plane is the open face (no occluder on it).
    open: bool,
    /// The mean of its vertices (inside).
    centre: DVec3,
}

impl Solid {
    /// Whether `K` hides every segment from `src` to `tgt` (see the module docs).
    pub(crate) fn hides(&self, src: &[DVec3], tgt: &[DVec3], tol: f64) -> bool {
        let real = if self.open {
            &self.planes[..self.planes.len() - 1]
        } else {
            &self.planes[..]
        };
        if self.open {
            let &(n, d) = &self.planes[self.planes.len() - 1];
            if src.iter().chain(tgt).any(|&v| n.dot(v) - d > tol) {
                return false;
            }
        }
        let outside = |p: &[DVec3]| {
            real.iter()
                .any(|&(n, d)| p.iter().all(|&v| n.dot(v) - d > tol))
        };
        if !outside(src) && !outside(tgt) {
            return false;
        }
        let mean = |p: &[DVec3]| p.iter().copied().sum::<DVec3>() / p.len().max(1) as f64;
        let across = (mean(tgt) - mean(src)).normalize_or_zero();
        core::iter::once(across)
            .chain(real.iter().map(|&(n, _)| n))
            .any(|m| self.crossings_inside(src, tgt, m, tol))
    }

    /// Whether every point of `p` lies outside `K` (beyond one face plane by more than
    /// `tol`) and on `K`'s side of the open face (within `tol`): then a sight line from
    /// `p` that meets `K`'s interior enters it through a face `p` sees the front of.
    pub(crate) fn outside_of(&self, p: &[DVec3], tol: f64) -> bool {
        let (real, open) = if self.open {
            self.planes.split_at(self.planes.len() - 1)
        } else {
            (&self.planes[..], &[][..])
        };
        open.iter()
            .all(|&(n, d)| p.iter().all(|&v| n.dot(v) - d <= tol))
            && real
                .iter()
                .any(|&(n, d)| p.iter().all(|&v| n.dot(v) - d > tol))
    }

    /// Whether every point of `p` lies behind or on the plane of `face` (a face of `K`,
    /// either orientation) as `K`'s centre does: no sight line from `p` enters `K` there.
    pub(crate) fn faces_away(&self, face: &Occluder, p: &[DVec3], tol: f64) -> bool {
        let pl = &face.plane;
        let inward = if pl.distance(self.centre) < 0.0 {
            -1.0
        } else {
            1.0
        };
        p.iter().all(|&v| inward * pl.distance(v) >= -tol)
    }

    /// Whether the plane through the centre with normal `m` strictly separates `src` and
    /// `tgt` with every vertex-to-vertex crossing inside `K` by more than `tol`.
    fn crossings_inside(&self, src: &[DVec3], tgt: &[DVec3], m: DVec3, tol: f64) -> bool {
        if m == DVec3::ZERO {
            return false;
        }
        let off = m.dot(self.centre);
        let side = |p: &[DVec3]| strict_side(p, |v| m.dot(v) - off, tol);
        let (ss, st) = (side(src), side(tgt));
        if ss == 0 || st == 0 || ss == st {
            return false;
        }
        src.iter().all(|&a| {
            let da = m.dot(a) - off;
            tgt.iter().all(|&b| {
                let db = m.dot(b) - off;
                let c = a + (b - a) * (da / (da - db));
                // Strictly inside the real faces; on the open face allowed (those
                // crossings form an edge of the crossings' polygon: no area).
                let open = if self.open { 1 } else { 0 };
                let (real, open) = self.planes.split_at(self.planes.len() - open);
                real.iter().all(|&(n, d)| n.dot(c) - d < -tol)
                    && open.iter().all(|&(n, d)| n.dot(c) - d <= tol)
            })
        })
    }
}

/// The solids among `list` (see the module docs) and, per occluder, the solid it is a face
/// of ([`NO_SOLID`] if none). `tol`: vertices within it are one; distances within it are
/// on a plane. Deterministic: solids in the order of their first occluder.
pub(crate) fn find_solids(list: &[Occluder], tol: f64) -> (Vec<Solid>, Vec<u32>) {
    let key = |p: DVec3| {
        let q = |x: f64| crate::math::round(x / tol) as i64;
        [q(p.x), q(p.y), q(p.z)]
    };
    // Every edge: (from, to) keys, occluder, edge index.
    let mut edges: Vec<([i64; 3], [i64; 3], u32, u32)> = Vec::new();
    for (k, o) in list.iter().enumerate() {
        let m = o.vertices.len();
        for e in 0..m {
            let (a, b) = (key(o.vertices[e]), key(o.vertices[(e + 1) % m]));
            edges.push((a.min(b), a.max(b), k as u32, e as u32));
        }
    }
    edges.sort_unstable();
    // Union-find over convex folds.
    let mut parent: Vec<u32> = (0..list.len() as u32).collect();
    let find = |parent: &mut Vec<u32>, mut x: u32| {
        // Bounded: each step moves towards the root of a forest.
        while parent[x as usize] != x {
            let p = parent[parent[x as usize] as usize];
            parent[x as usize] = p;
            x = p;
        }
        x
    };
    let behind =
        |p: &Occluder, q: &Occluder| q.vertices.iter().all(|&v| p.plane.distance(v) <= tol);
    let mut matched = alloc::vec![false; edges.len()];
    let mut g = 0;
    while g < edges.len() {
        let mut h = g + 1;
        while h < edges.len() && edges[h].0 == edges[g].0 && edges[h].1 == edges[g].1 {
            h += 1;
        }
        if h == g + 2 {
            let (p, q) = (&list[edges[g].2 as usize], &list[edges[g + 1].2 as usize]);
            // Opposite directions: the edge runs a → b in one and b → a in the other.
            let dir = |o: &Occluder, e: u32| {
                let m = o.vertices.len();
                key(o.vertices[e as usize]) < key(o.vertices[(e as usize + 1) % m])
            };
            let opposite = dir(p, edges[g].3) != dir(q, edges[g + 1].3);
            let fold = p.plane.normal.cross(q.plane.normal).length() > 1e-6;
            if edges[g].2 != edges[g + 1].2 && opposite && fold && behind(p, q) && behind(q, p) {
                matched[g] = true;
                matched[g + 1] = true;
                let (a, b) = (
                    find(&mut parent, edges[g].2),
                    find(&mut parent, edges[g + 1].2),
                );
                parent[a.max(b) as usize] = a.min(b);
            }
        }
        g = h;
    }
    let roots: Vec<u32> = (0..list.len() as u32)
        .map(|k| find(&mut parent, k))
        .collect();
    let mut solid_of = alloc::vec![NO_SOLID; list.len()];
    let mut solids = Vec::new();
    for root in 0..list.len() as u32 {
        if roots[root as usize] != root {
            continue;
        }
        let faces: Vec<u32> = (0..list.len() as u32)
            .filter(|&k| roots[k as usize] == root)
            .collect();
        if faces.len() < 3 {
            continue;
        }
        let open: Vec<DVec3> = edges
            .iter()
            .zip(&matched)
            .filter(|(e, m)| !**m && roots[e.2 as usize] == root)
            .flat_map(|(e, _)| {
                let o = &list[e.2 as usize];
                let m = o.vertices.len();
                [o.vertices[e.3 as usize], o.vertices[(e.3 as usize + 1) % m]]
            })
            .collect();
        if let Some(solid) = solid_of_faces(list, &faces, &open, tol) {
            for &k in &faces {
                solid_of[k as usize] = solids.len() as u32;
            }
            solids.push(solid);
        }
    }
    // Bounded: the loop above visits each root once; this scan is linear.
    (solids, solid_of)
}

/// The solid of `faces` with the open edges' end points `open` (empty: closed), if convex
/// and the open edges lie in one plane with the solid behind it.
fn solid_of_faces(list: &[Occluder], faces: &[u32], open: &[DVec3], tol: f64) -> Option<Solid> {
    let verts: Vec<DVec3> = faces
        .iter()
        .flat_map(|&k| list[k as usize].vertices.iter().copied())
        .collect();
    let centre = verts.iter().copied().sum::<DVec3>() / verts.len() as f64;
    let mut planes: Vec<(DVec3, f64)> = Vec::with_capacity(faces.len() + 1);
    for &k in faces {
        let p = &list[k as usize].plane;
        let (n, d) = (p.normal, p.normal.dot(p.origin));
        if verts.iter().any(|&v| n.dot(v) - d > tol) {
            return None;
        }
        planes.push((n, d));
    }
    let is_open = !open.is_empty();
    if is_open {
        // The open face's plane from its farthest-apart points.
        let a = open[0];
        let b = *open
            .iter()
            .max_by(|p, q| (**p - a).length().total_cmp(&(**q - a).length()))?;
        let c = *open.iter().max_by(|p, q| {
            let area = |r: DVec3| (b - a).cross(r - a).length();
            area(**p).total_cmp(&area(**q))
        })?;
        let mut n = (b - a).cross(c - a).normalize_or_zero();
        if n == DVec3::ZERO {
            return None;
        }
        if n.dot(centre - a) > 0.0 {
            n = -n;
        }
        let d = n.dot(a);
        if open.iter().any(|&v| (n.dot(v) - d).abs() > tol)
            || verts.iter().any(|&v| n.dot(v) - d > tol)
        {
            return None;
        }
        planes.push((n, d));
    }
    // The centre strictly inside every plane (a solid of some thickness).
    if planes.len() < 4 || planes.iter().any(|&(n, d)| n.dot(centre) - d > -tol) {
        return None;
    }
    Some(Solid {
        planes,
        open: is_open,
        centre,
    })
}
