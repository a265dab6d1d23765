//! Occluder fusion by umbrae: a pair (or a triangle of the outer integral) hidden jointly
//! by several occluders, none of which hides it alone, is found without integration.
//!
//! **Umbra of one convex occluder.** For a convex occluder `O` and a point `t`, the points
//! `s` whose segment `[s, t]` meets `O` form the convex set `{t + λ (o − t) : o ∈ O, λ ≥ 1}`
//! (a convex combination of two such points is `t + Λ (o' − t)` with `Λ ≥ 1`, `o' ∈ O`).
//! So `t` is hidden by `O` from every point of a convex source `S` exactly when it is from
//! every vertex of `S`: the umbra of `O` on the target is the intersection over `S`'s
//! vertices `v` of `O`'s shadows from `v` (Durand et al. 2000 and Schaufler et al. 2000 use
//! the same property for conservative visibility from a region). A point of the target
//! in the union of the occluders' umbrae is hidden from all of `S`; when the union covers
//! the target, `F_ST = 0`.
//!
//! **Convex solids** (`solids.rs`) fuse further: the shadow from `v` of a convex solid `K`
//! is convex and holds the shadows of its faces, so the convex hull of its candidate
//! faces' shadows lies inside it; a segment through `K`'s interior from outside it meets a
//! face (for an open solid, when both ends are on `K`'s side of the open face, as
//! `Solid::hides` argues). The hull is used in place of the faces' shadows one by one,
//! which catches targets behind a box's silhouette edge.
//!
//! **Conservative.** Each shadow is the one of `visible.rs`, clipped to the pyramid from
//! `v` over the target and short of the near guard, so never larger than the true shadow;
//! the umbra is their intersection, clipped exactly (rounding only). What is left of the
//! target after subtracting the umbrae is dropped below the sliver area `10⁻¹³ A_T`, as
//! the inner integral itself drops it. Any source vertex not in front of the target's
//! plane, or an open solid with an end below its open face, and the test answers `false`
//! (that solid's faces then count one by one).

use alloc::vec::Vec;

use super::occluders::Occluder;
use super::solids::{NO_SOLID, Solid};
use super::visible::{Target, Workspace};
use crate::error::Result;
use crate::geom::{DVec2, DVec3, signed_area};

/// Buffers reused from pair to pair.
#[derive(Debug, Default)]
pub(crate) struct Fusion {
    /// `(group key, occluder)`, sorted: a group is a solid or a lone occluder.
    groups: Vec<(u64, u32)>,
    umbrae: Vec<Vec<DVec2>>,
    umbra: Vec<DVec2>,
    points: Vec<DVec2>,
    shadow: Vec<DVec2>,
    hull: Vec<DVec2>,
    scratch: Vec<DVec2>,
}

/// The occluders of a pair: all of them, their solids and which solid each is a face of.
pub(crate) type OccluderSet<'o> = (&'o [Occluder], &'o [Solid], &'o [u32]);

/// Whether the umbrae of the candidates `cands` from `src` cover `target` (whose polygon
/// is `tgt`, of area `tgt_area`), so every segment from `src` to `tgt` is hidden (see the module docs).
/// Conservative: `false` when unsure. `tol`: the contact tolerance.
///
/// # Errors
/// [`crate::error::ErrorKind::TooLarge`] beyond `MAX_VISIBLE_PIECES` pieces.
pub(crate) fn hidden_jointly(
    (src, tgt, tgt_area): (&[DVec3], &[DVec3], f64),
    target: &Target,
    (occ, solids, solid_of): OccluderSet<'_>,
    cands: &[u32],
    tol: f64,
    f: &mut Fusion,
    work: &mut Workspace,
) -> Result<bool> {
    if cands.len() < 2 || src.len() < 3 {
        return Ok(false);
    }
    let (_, sliver) = target.tolerances();
    f.groups.clear();
    for &k in cands {
        let s = solid_of.get(k as usize).copied().unwrap_or(NO_SOLID);
        let key = if s != NO_SOLID
            && solids[s as usize].below_open_face(src, tol)
            && solids[s as usize].below_open_face(tgt, tol)
        {
            u64::from(s)
        } else {
            (1u64 << 32) + u64::from(k)
        };
        f.groups.push((key, k));
    }
    f.groups.sort_unstable();
    f.umbrae.clear();
    let mut covered_area = 0.0;
    let mut g = 0;
    // Bounded: each pass consumes one group of `cands`.
    while g < f.groups.len() {
        let mut h = g + 1;
        while h < f.groups.len() && f.groups[h].0 == f.groups[g].0 {
            h += 1;
        }
        let mut empty = false;
        for (n, &v) in src.iter().enumerate() {
            f.points.clear();
            for &(_, k) in &f.groups[g..h] {
                if target.shadow_from(v, &occ[k as usize].vertices, work, &mut f.shadow) {
                    f.points.extend_from_slice(&f.shadow);
                }
            }
            if f.points.len() < 3 {
                empty = true;
                break;
            }
            convex_hull(&mut f.points, &mut f.hull);
            if n == 0 {
                core::mem::swap(&mut f.umbra, &mut f.hull);
            } else {
                intersect(&mut f.umbra, &f.hull, &mut f.scratch);
            }
            if f.umbra.len() < 3 || signed_area(&f.umbra) <= sliver {
                empty = true;
                break;
            }
        }
        if !empty {
            covered_area += signed_area(&f.umbra);
            f.umbrae.push(f.umbra.clone());
        }
        g = h;
    }
    // The union cannot cover the target with less area than it.
    if f.umbrae.is_empty() || covered_area < tgt_area * (1.0 - 1e-9) {
        return Ok(false);
    }
    target.covered_by(&f.umbrae, work)
}

/// The convex hull of `points` (reordered), counter-clockwise without collinear points,
/// into `out` (Andrew's monotone chain).
fn convex_hull(points: &mut [DVec2], out: &mut Vec<DVec2>) {
    points.sort_unstable_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    out.clear();
    let turn = |o: DVec2, a: DVec2, b: DVec2| (a - o).perp_dot(b - o);
    for &p in points.iter() {
        while out.len() >= 2 && turn(out[out.len() - 2], out[out.len() - 1], p) <= 0.0 {
            out.pop();
        }
        out.push(p);
    }
    let lower = out.len() + 1;
    for &p in points.iter().rev().skip(1) {
        while out.len() >= lower && turn(out[out.len() - 2], out[out.len() - 1], p) <= 0.0 {
            out.pop();
        }
        out.push(p);
    }
    out.pop();
}

/// `poly` replaced by its intersection with the convex counter-clockwise `clip`
/// (Sutherland–Hodgman, no tolerance: rounding only); `tmp` is scratch.
fn intersect(poly: &mut Vec<DVec2>, clip: &[DVec2], tmp: &mut Vec<DVec2>) {
    let m = clip.len();
    for e in 0..m {
        if poly.len() < 3 {
            poly.clear();
            return;
        }
        let (a, b) = (clip[e], clip[(e + 1) % m]);
        let d = b - a;
        let side = |p: DVec2| d.perp_dot(p - a);
        tmp.clear();
        let k = poly.len();
        for i in 0..k {
            let (p, q) = (poly[i], poly[(i + 1) % k]);
            let (dp, dq) = (side(p), side(q));
            if dp >= 0.0 {
                tmp.push(p);
            }
            if (dp > 0.0 && dq < 0.0) || (dp < 0.0 && dq > 0.0) {
                tmp.push(p + (q - p) * (dp / (dp - dq)));
            }
        }
        core::mem::swap(poly, tmp);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hull_and_intersection_of_squares() {
        let sq = |x: f64, y: f64, s: f64| {
            alloc::vec![
                DVec2::new(x, y),
                DVec2::new(x + s, y),
                DVec2::new(x + s, y + s),
                DVec2::new(x, y + s)
            ]
        };
        let mut pts = sq(0.0, 0.0, 1.0);
        pts.extend(sq(0.5, 0.5, 1.0));
        pts.push(DVec2::new(0.5, 0.5));
        let mut hull = Vec::new();
        convex_hull(&mut pts, &mut hull);
        assert_eq!(hull.len(), 6);
        // The two squares' union, 1.75, and the two corner triangles the hull adds.
        assert!((signed_area(&hull) - 2.0).abs() < 1e-15);
        let mut a = sq(0.0, 0.0, 1.0);
        intersect(&mut a, &sq(0.5, 0.25, 1.0), &mut Vec::new());
        assert!((signed_area(&a) - 0.375).abs() < 1e-15);
        let mut far = sq(0.0, 0.0, 1.0);
        intersect(&mut far, &sq(2.0, 2.0, 1.0), &mut Vec::new());
        assert!(far.len() < 3 || signed_area(&far) <= 0.0);
    }
}
