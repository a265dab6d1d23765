//! The source cut along the visibility events through the points where an occluder
//! touches it, so that no leaf of the outer integral has such an event inside it.
//!
//! **Why.** Where a convex occluder touches the source polygon at a point `c` (a vertex of
//! the occluder on the source's plane, or an occluder edge crossing that plane, inside the
//! source or within [`NEAR_CONTACT`] of its radius outside it: a block standing beside a
//! floor piece, its corner at the piece's vertex or just past its edge), the
//! occluder seen from `x = c + ε d` looks, as `ε → 0`, like its tangent cone at `c` seen from
//! `c + ε d`, so `F_{dx→vis(j)} → g(d)`: a function of the direction from `c` only
//! (homogeneous of degree 0 about `c`). Its steps — from the whole target seen to none of it
//! — lie along rays from `c`. A triangle with a corner at `c` and such a ray inside has the
//! same picture at every scale about `c`: its midpoint corner child is the triangle shrunk,
//! and the degree-5 rule on the parent and on the four children can agree closely while
//! both miss the step (issue 23: a Cornell floor piece at the short block's corner, 14 %
//! off with an estimate of 0.3 %).
//!
//! **The cut.** The steps of `g` are the directions `d` (in the source's plane) for which
//! the shadow of the tangent cone changes its combinatorics:
//!
//! - a shadow edge through a target vertex `w`: `d` in the plane through `c` spanned by an
//!   occluder edge `e` through `c` and `w − c` (an EV event);
//! - a face of the cone seen edge-on: `d` in the plane of an occluder face through `c`.
//!
//! Each such plane meets the source's plane in a line through `c`; the source is cut along
//! every one of them into convex cells, and each cell is fanned from a contact point among
//! its corners. On each cell `g` is then smooth in the direction from `c` (the shadow keeps
//! its combinatorics), and for a smooth degree-0 function the corner child carries a quarter
//! of the parent's error, so `|Q_fine − Q_coarse|` is about three quarters of the coarse
//! error and the estimate (`outer.rs`) holds again.
//!
//! **Events away from contacts.** The EV events between the target and the occluders
//! ([`event_segments`]) cut the cells they pass through as well, so the adaptive integral
//! meets no such kink inside a cell (discontinuity meshing: Heckbert 1992; Lischinski,
//! Tampieri & Greenberg 1992). So do the chords where the source crosses an occluder's
//! plane (the occluder seen edge-on: its near and far edges swap on the shadow's outline,
//! an EV event between the occluder's own edges; Cornell 810's pair (266, 486) missed it by
//! 10⁵ times its estimate before, at 10⁻⁶ and at 10⁻⁸ alike, the cells of the other events
//! holding the kink where both rules agreed). EV events between two occluders and EEE events
//! are not cut: the refinement follows them as before.
//!
//! Bounded: at most [`MAX_CONTACT_LINES`] lines per pair (beyond, the rest are not cut:
//! only the estimate's reliability is lost, never the value's correctness).

use alloc::vec::Vec;

use crate::formfactor::exact_3d::Plane;
use crate::geom::DVec3;

/// How far outside the source (relative to its radius) a contact point still counts:
/// the Cornell floor piece next to the one holding the block's corner (issue 23, pair
/// (417, 224)) has the corner 2.2 away, at 0.06 of its radius, and its estimate missed by
/// 2× without the cut.
pub const NEAR_CONTACT: f64 = 0.25;

/// Most cutting lines per pair (contact points times events through them).
pub const MAX_CONTACT_LINES: usize = 64;

/// Most visibility-event segments ([`event_segments`]) a pair's source is cut along; a
/// pair with more is cut at its contacts only (today's refinement then follows the rest).
pub const MAX_EVENT_LINES: usize = 24;

/// A line in the source's plane through `point` with in-plane unit normal `normal`.
#[derive(Clone, Copy, Debug)]
struct Line {
    point: DVec3,
    normal: DVec3,
}

/// The contact points of `occluders` with the convex polygon `src` (plane `ps`), within
/// `tol`: occluder vertices on the plane inside `src`, and crossings of occluder edges with
/// the plane inside `src`; each with the directions of the occluder edges through it.
fn contacts(
    src: &[DVec3],
    ps: &Plane,
    reach: f64,
    occluders: &[&[DVec3]],
    tol: f64,
) -> Vec<(DVec3, Vec<DVec3>, Vec<DVec3>)> {
    let n = ps.normal;
    // Within `reach` of the polygon (outside it by at most that much across every edge
    // line): a contact just outside the source shapes the integrand inside it alike.
    let inside = |c: DVec3| {
        let m = src.len();
        (0..m).all(|k| {
            let (p, q) = (src[k], src[(k + 1) % m]);
            let e = q - p;
            e.cross(c - p).dot(n) >= -(tol + reach) * e.length()
        })
    };
    // (point, edge directions through it, face normals through it)
    let mut out: Vec<(DVec3, Vec<DVec3>, Vec<DVec3>)> = Vec::new();
    let add = |c: DVec3, e: DVec3, face: DVec3, out: &mut Vec<(DVec3, Vec<DVec3>, Vec<DVec3>)>| {
        if let Some(k) = out.iter().position(|(p, _, _)| (*p - c).length() <= tol) {
            out[k].1.push(e);
            out[k].2.push(face);
        } else if out.len() < MAX_CONTACT_LINES {
            out.push((c, alloc::vec![e], alloc::vec![face]));
        }
    };
    for o in occluders {
        let Some(po) = Plane::of(o) else { continue };
        let m = o.len();
        for k in 0..m {
            let (u, v) = (o[k], o[(k + 1) % m]);
            let (du, dv) = (ps.distance(u), ps.distance(v));
            let c = if du.abs() <= tol {
                u
            } else if dv.abs() <= tol {
                continue; // counted as the next edge's start
            } else if (du > 0.0) != (dv > 0.0) {
                u + (v - u) * (du / (du - dv))
            } else {
                continue;
            };
            if !inside(c) {
                continue;
            }
            add(c, v - u, po.normal, &mut out);
            if du.abs() <= tol {
                // The edge ending at u is also through it.
                let w = o[(k + m - 1) % m];
                add(c, u - w, po.normal, &mut out);
            }
        }
    }
    out
}

/// The initial triangles of the outer integral over the convex polygon `src` (plane `ps`)
/// towards `target`: a fan about `src[0]`, or, where `occluders` touch `src`, the fans of
/// the cells of `src` cut along the visibility events through the contact points (see the
/// module documentation). `tol` is the contact tolerance (a length).
pub(crate) fn initial_triangles(
    src: &[DVec3],
    ps: &Plane,
    target: &[DVec3],
    occluders: &[&[DVec3]],
    tol: f64,
) -> Vec<[DVec3; 3]> {
    let n = ps.normal;
    let points = contacts(src, ps, NEAR_CONTACT * ps.radius, occluders, tol);
    let mut lines: Vec<Line> = Vec::new();
    for (c, edges, faces) in &points {
        let push = |plane_normal: DVec3, lines: &mut Vec<Line>| {
            // The line: plane ∩ source plane, through c; its in-plane normal is the plane
            // normal's part in the source plane.
            let inplane = plane_normal - n * n.dot(plane_normal);
            let len = inplane.length();
            if len > 1e-9 * plane_normal.length() && lines.len() < MAX_CONTACT_LINES {
                lines.push(Line {
                    point: *c,
                    normal: inplane / len,
                });
            }
        };
        for &e in edges {
            for &w in target {
                push(e.cross(w - *c), &mut lines);
            }
        }
        for &f in faces {
            push(f, &mut lines);
        }
    }
    let events = event_segments(src, ps, target, occluders, tol);
    let mut cuts: Vec<(Line, Option<(DVec3, DVec3)>)> = lines.iter().map(|&l| (l, None)).collect();
    if events.len() <= MAX_EVENT_LINES {
        cuts.extend(events.into_iter().map(|(l, a, b)| (l, Some((a, b)))));
    }
    let mut cells: Vec<Vec<DVec3>> = alloc::vec![src.to_vec()];
    if !cuts.is_empty() {
        let mut next = Vec::new();
        for (l, seg) in &cuts {
            next.clear();
            for cell in cells.drain(..) {
                let side = |p: DVec3| l.normal.dot(p - l.point);
                let hi = cell
                    .iter()
                    .map(|&p| side(p))
                    .fold(f64::NEG_INFINITY, f64::max);
                let lo = cell.iter().map(|&p| side(p)).fold(f64::INFINITY, f64::min);
                if hi <= tol
                    || lo >= -tol
                    || seg.is_some_and(|(a, b)| !segment_meets(&cell, n, a, b, tol))
                {
                    next.push(cell);
                    continue;
                }
                for s in [1.0, -1.0] {
                    let part = clip(&cell, *l, s, tol);
                    if part.len() >= 3 {
                        next.push(part);
                    }
                }
            }
            core::mem::swap(&mut cells, &mut next);
        }
    }
    // A contact point inside an edge of a cell becomes its corner (to fan from it).
    for cell in &mut cells {
        for (c, _, _) in &points {
            let m = cell.len();
            let on_edge = (0..m).find(|&k| {
                let (p, q) = (cell[k], cell[(k + 1) % m]);
                let e = q - p;
                let t = e.dot(*c - p);
                (p - *c).length() > tol
                    && (q - *c).length() > tol
                    && t > 0.0
                    && t < e.length_squared()
                    && e.cross(*c - p).length() <= tol * e.length()
            });
            if let Some(k) = on_edge {
                cell.insert(k + 1, *c);
            }
        }
    }
    let mut out = Vec::new();
    for cell in &cells {
        // Fan from a contact point among its corners, if any.
        let apex = cell
            .iter()
            .position(|&p| points.iter().any(|(c, _, _)| (p - *c).length() <= tol))
            .unwrap_or(0);
        let m = cell.len();
        for k in 1..m.saturating_sub(1) {
            out.push([cell[apex], cell[(apex + k) % m], cell[(apex + k + 1) % m]]);
        }
    }
    out
}

/// The part of convex `poly` with `s · (normal · (p − point)) ≥ 0` (points within `tol` of
/// the line count as on it).
fn clip(poly: &[DVec3], l: Line, s: f64, tol: f64) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(poly.len() + 1);
    let m = poly.len();
    let side = |p: DVec3| {
        let d = s * l.normal.dot(p - l.point);
        if d.abs() <= tol { 0.0 } else { d }
    };
    for k in 0..m {
        let (p, q) = (poly[k], poly[(k + 1) % m]);
        let (dp, dq) = (side(p), side(q));
        if dp >= 0.0 {
            out.push(p);
        }
        if (dp > 0.0 && dq < 0.0) || (dp < 0.0 && dq > 0.0) {
            out.push(p + (q - p) * (dp / (dp - dq)));
        }
    }
    out
}

/// Whether the segment `a b` of the source's plane (normal `n`) passes through the
/// interior of the convex `cell` (counter-clockwise about `n`), by more than `tol`.
fn segment_meets(cell: &[DVec3], n: DVec3, a: DVec3, b: DVec3, tol: f64) -> bool {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    let d = b - a;
    let m = cell.len();
    for k in 0..m {
        let (p, q) = (cell[k], cell[(k + 1) % m]);
        let e = q - p;
        let len = e.length();
        if !(len > 0.0) {
            continue;
        }
        // Inside: (e × (y − p)) · n / |e| ≥ tol, for y = a + t d.
        let f0 = e.cross(a - p).dot(n) / len - tol;
        let fd = e.cross(d).dot(n) / len;
        if fd == 0.0 {
            if f0 < 0.0 {
                return false;
            }
        } else {
            let t = -f0 / fd;
            if fd > 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
            if t0 >= t1 {
                return false;
            }
        }
    }
    true
}

/// The visibility events of the pair on the source's plane away from contacts, as
/// `(line, a, b)`: the segment `a b` of `line` where the event happens (clipped to the
/// source's neighbourhood), for the EV events (Heckbert 1992; Lischinski, Tampieri &
/// Greenberg 1992) between the target and the occluders:
///
/// - an occluder vertex `v` seen on a target edge `t₁ t₂`: the points `x` whose sight line
///   through `v` meets the edge, `x = t + λ (v − t)`, `λ > 1`, on the plane through `v`,
///   `t₁`, `t₂` (a shadow vertex crossing the target's outline);
/// - a target vertex `w` seen past an occluder edge `o₁ o₂`: `x = p + λ (p − w)`, `λ > 0`,
///   `p` on the edge (the target's corner crossing a shadow edge).
///
/// - an occluder seen edge-on: the chord of the source on the occluder's plane.
///
/// Across these the visible polygon changes its combinatorics and `F_{dx→vis(j)}` is not
/// smooth; between them (and away from events between two occluders' edges, not cut) it
/// is. Occluder vertices and edges shared by several occluders count once.
fn event_segments(
    src: &[DVec3],
    ps: &Plane,
    target: &[DVec3],
    occluders: &[&[DVec3]],
    tol: f64,
) -> Vec<(Line, DVec3, DVec3)> {
    let n = ps.normal;
    let mut verts: Vec<DVec3> = Vec::new();
    let mut edges: Vec<(DVec3, DVec3)> = Vec::new();
    for o in occluders {
        let m = o.len();
        for k in 0..m {
            let (u, w) = (o[k], o[(k + 1) % m]);
            if !verts.iter().any(|&p| (p - u).length() <= tol) {
                verts.push(u);
            }
            let same = |(p, q): &(DVec3, DVec3)| {
                ((*p - u).length() <= tol && (*q - w).length() <= tol)
                    || ((*p - w).length() <= tol && (*q - u).length() <= tol)
            };
            if !edges.iter().any(same) {
                edges.push((u, w));
            }
        }
    }
    let mut out = Vec::new();
    // The source's neighbourhood: a point of the plane within twice its radius.
    let reach = 2.0 * ps.radius;
    let push = |plane_normal: DVec3, a: DVec3, b: DVec3, out: &mut Vec<(Line, DVec3, DVec3)>| {
        if out.len() > MAX_EVENT_LINES {
            return;
        }
        let inplane = plane_normal - n * n.dot(plane_normal);
        let len = inplane.length();
        if !(len > 1e-9 * plane_normal.length()) {
            return;
        }
        // Clip the segment to the ball about the source's centroid.
        let d = b - a;
        let c = ps.centroid;
        let dd = d.length_squared();
        if !(dd > 0.0) || !dd.is_finite() {
            return;
        }
        let t = (d.dot(c - a) / dd).clamp(0.0, 1.0);
        let near = a + t * d;
        if (near - c).length() > reach || !near.is_finite() {
            return;
        }
        let half = crate::math::sqrt(reach * reach / dd);
        let (a2, b2) = (a + (t - half).max(0.0) * d, a + (t + half).min(1.0) * d);
        if segment_meets(src, n, a2, b2, tol) {
            out.push((
                Line {
                    point: near,
                    normal: inplane / len,
                },
                a2,
                b2,
            ));
        }
    };
    let mt = target.len();
    // Where y(u) = p + u (q − p) has its distance to the source's plane in (lo, hi):
    // the interval of u in [0, 1], if any.
    let interval = |dp: f64, dq: f64, lo: f64, hi: f64| -> Option<(f64, f64)> {
        let (mut u0, mut u1) = (0.0f64, 1.0f64);
        let dd = dq - dp;
        for (bound, above) in [(lo, true), (hi, false)] {
            // above: dp + u dd ≥ bound; else ≤ bound.
            if dd == 0.0 {
                if (above && dp < bound) || (!above && dp > bound) {
                    return None;
                }
            } else {
                let u = (bound - dp) / dd;
                if (dd > 0.0) == above {
                    u0 = u0.max(u);
                } else {
                    u1 = u1.min(u);
                }
            }
        }
        (u0 < u1).then_some((u0, u1))
    };
    // The margin keeping a projection's divisor away from 0 (the image then lies far
    // outside the neighbourhood anyway).
    let margin = |d: f64| 1e-6 * d.abs() + tol;
    for &v in &verts {
        let dv = ps.distance(v);
        if dv <= tol {
            continue;
        }
        for k in 0..mt {
            let (p, q) = (target[k], target[(k + 1) % mt]);
            let (dp, dq) = (ps.distance(p), ps.distance(q));
            // x = t + λ (v − t) on the plane, λ = d(t) / (d(t) − d(v)) > 1 ⇔ d(t) > d(v).
            let Some((u0, u1)) = interval(dp, dq, dv + margin(dv), f64::INFINITY) else {
                continue;
            };
            let image = |u: f64| {
                let t = p + u * (q - p);
                let dt = ps.distance(t);
                t + (dt / (dt - dv)) * (v - t)
            };
            push((p - v).cross(q - v), image(u0), image(u1), &mut out);
        }
    }
    for &w in target {
        let dw = ps.distance(w);
        if dw <= tol {
            continue;
        }
        for &(p, q) in &edges {
            let (dp, dq) = (ps.distance(p), ps.distance(q));
            // x = y + λ (y − w), λ = d(y) / (d(w) − d(y)) > 0 ⇔ 0 < d(y) < d(w).
            let Some((u0, u1)) = interval(dp, dq, tol, dw - margin(dw)) else {
                continue;
            };
            let image = |u: f64| {
                let y = p + u * (q - p);
                let dy = ps.distance(y);
                y + (dy / (dw - dy)) * (y - w)
            };
            push((p - w).cross(q - w), image(u0), image(u1), &mut out);
        }
    }
    // An occluder seen edge-on: where the source crosses an occluder's plane, the edge
    // of the occluder nearer the source and the one farther from it swap places on the
    // shadow's outline (a solid's top edge and the bottom edge of its side face, which
    // project onto one line there): the shadow's area has a kink along that chord.
    let m = src.len();
    for o in occluders {
        let Some(plane) = Plane::of(o) else {
            continue;
        };
        let side = |p: DVec3| plane.normal.dot(p - plane.origin);
        let (mut a, mut b) = (None, None);
        for k in 0..m {
            let (p, q) = (src[k], src[(k + 1) % m]);
            let (dp, dq) = (side(p), side(q));
            if (dp > tol && dq < -tol) || (dp < -tol && dq > tol) {
                let x = p + (q - p) * (dp / (dp - dq));
                if a.is_none() {
                    a = Some(x);
                } else {
                    b = Some(x);
                }
            }
        }
        if let (Some(a), Some(b)) = (a, b) {
            push(plane.normal, a, b, &mut out);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(h: f64, z: f64, up: bool) -> Vec<DVec3> {
        let s = alloc::vec![
            DVec3::new(-h, -h, z),
            DVec3::new(h, -h, z),
            DVec3::new(h, h, z),
            DVec3::new(-h, h, z),
        ];
        if up { s } else { s.into_iter().rev().collect() }
    }

    #[test]
    fn coaxial_events_cut_the_source_into_nine_cells() {
        // Unit source at z = 0, unit target at z = 2 facing it, a centred blocker of half
        // side 0.1 at z = 1: from x the blocker's shadow corner 2v − x crosses a target
        // edge ±0.5 where x = 2v ∓ 0.5, i.e. on the lines x = ±0.3 and y = ±0.3 inside the
        // source (the other events fall outside it).
        let src = square(0.5, 0.0, true);
        let tgt = square(0.5, 2.0, false);
        let blocker = square(0.1, 1.0, true);
        let ps = Plane::of(&src).unwrap();
        let tris = initial_triangles(&src, &ps, &tgt, &[blocker.as_slice()], 1e-12);
        let area: f64 = tris
            .iter()
            .map(|t| 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).dot(DVec3::Z))
            .sum();
        assert!(
            (area - 1.0).abs() < 1e-14,
            "the cells tile the source: {area}"
        );
        // No triangle straddles an event line.
        for t in &tris {
            for c in [-0.3, 0.3] {
                for side in [|p: DVec3| p.x, |p: DVec3| p.y] {
                    let lo = t.iter().map(|&p| side(p) - c).fold(f64::INFINITY, f64::min);
                    let hi = t
                        .iter()
                        .map(|&p| side(p) - c)
                        .fold(f64::NEG_INFINITY, f64::max);
                    assert!(lo >= -1e-12 || hi <= 1e-12, "{t:?} straddles {c}");
                }
            }
        }
        // 9 rectangular cells, 2 triangles each.
        assert_eq!(tris.len(), 18);
    }
}
