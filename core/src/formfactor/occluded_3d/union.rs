//! Pairs hidden by a union of occluders none of which hides them alone (two cubes each
//! covering part of the view between two patches), found without integration.
//!
//! **The test** ([`hidden_by_union`]). The sight lines of a pair of convex polygons
//! `(S, T)` are the segments `[s, t]`, `s ∈ S`, `t ∈ T`. When `S = S₁ ∪ S₂`, they are the
//! union of the sight lines of `(S₁, T)` and `(S₂, T)`; the same for `T`. So if `(S, T)` is
//! cut, by halving one side at a time, into sub-pairs `(S_a, T_b)` whose sides cover `S`
//! and `T`, and each sub-pair is hidden by one opaque body — one occluder
//! ([`blocks_all`], proof in `occluders.rs`) or one convex solid ([`Solid::hides`], proof
//! in `solids.rs`), both proven for any pair of convex polygons — then every sight line of
//! `(S, T)` meets an opaque face strictly inside it, and `F_ST = F_TS = 0` exactly. Which
//! body hides which sub-pair does not matter, and any body of the scene may serve (the
//! pair's candidates are the ones that can).
//!
//! The halves of a convex polygon are its parts on either side of the plane across its
//! longest edge through the middle of its extent along that edge (closed half-spaces, so
//! the two halves cover it, up to the rounding of the cut points: a strip of relative
//! width ~10⁻¹⁶, far inside the contact tolerance the single-body tests keep from every
//! face). A square becomes two strips, a strip two squares. Of a sub-pair, the side with
//! the larger such extent is halved.
//!
//! Conservative and bounded: a sight line found that crosses no candidate is not hidden,
//! so the answer is `false` at once — first the (up to 25) segments between five points of each
//! side (the centroid and the midpoints from it to four vertices), then, for each sub-pair
//! (taken breadth first), the segment between its centroids; this keeps the test cheap
//! on the many pairs that see part of each other. The answer is also `false`
//! when `MAX_UNION_TESTS` sub-pairs have been tried or one still unhidden is
//! `MAX_UNION_DEPTH` halvings deep. `false` only means "not proven": the pair is then
//! integrated.

use alloc::collections::VecDeque;
use alloc::vec::Vec;

use super::occluders::{Occluder, blocks_all};
use super::solids::{NO_SOLID, Solid};
use crate::formfactor::exact_3d::HalfSpace;
use crate::geom::DVec3;

/// Most sub-pairs tested for one pair (a cover of up to half as many hidden sub-pairs).
pub(crate) const MAX_UNION_TESTS: usize = 64;

/// Most halvings of a pair before a sub-pair still unhidden ends the test.
const MAX_UNION_DEPTH: u32 = 10;

/// The opaque bodies of a scene: its occluders and the convex solids they make, with the
/// solid of each occluder ([`NO_SOLID`] if none).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Bodies<'o> {
    pub occ: &'o [Occluder],
    pub solids: &'o [Solid],
    pub solid_of: &'o [u32],
}

/// Whether the candidates `cands` (indices into `bodies.occ`) and their solids hide every
/// sight line from `src` to `tgt` (convex polygons) between them, several bodies sharing
/// the work (see the module documentation). `tol` is the contact tolerance; `solids` is
/// reused. Conservative: `false` when unsure.
pub(crate) fn hidden_by_union(
    src: &[DVec3],
    tgt: &[DVec3],
    cands: &[u32],
    bodies: Bodies<'_>,
    tol: f64,
    solids: &mut Vec<u32>,
) -> bool {
    if cands.is_empty() || src.len() < 3 || tgt.len() < 3 {
        return false;
    }
    solids.clear();
    for &k in cands {
        let s = bodies.solid_of.get(k as usize).copied().unwrap_or(NO_SOLID);
        if s != NO_SOLID && (s as usize) < bodies.solids.len() && !solids.contains(&s) {
            solids.push(s);
        }
    }
    let probes = |p: &[DVec3]| {
        let c = mean(p);
        let mut out: heapless::Vec<DVec3, 5> = heapless::Vec::new();
        let _ = out.push(c);
        for &v in p.iter().take(4) {
            let _ = out.push(0.5 * (c + v));
        }
        out
    };
    let (ps, pt) = (probes(src), probes(tgt));
    if ps.iter().any(|&a| {
        pt.iter()
            .any(|&b| !segment_blocked(a, b, cands, bodies.occ))
    }) {
        return false;
    }
    let mut queue: VecDeque<(Vec<DVec3>, Vec<DVec3>, u32)> = VecDeque::new();
    queue.push_back((src.to_vec(), tgt.to_vec(), 0));
    let mut tests = 0;
    // Bounded: at most MAX_UNION_TESTS sub-pairs are taken, each adding two.
    while let Some((s, t, depth)) = queue.pop_front() {
        if tests >= MAX_UNION_TESTS {
            return false;
        }
        tests += 1;
        if !segment_blocked(mean(&s), mean(&t), cands, bodies.occ) {
            return false;
        }
        let hidden = cands.iter().any(|&k| {
            let o = &bodies.occ[k as usize];
            blocks_all(&s, &t, &o.vertices, &o.plane, tol)
        }) || solids
            .iter()
            .any(|&k| bodies.solids[k as usize].hides(&s, &t, tol));
        if hidden {
            continue;
        }
        if depth >= MAX_UNION_DEPTH {
            return false;
        }
        let (cs, ct) = (cut_of(&s), cut_of(&t));
        let halve_src = cs.2 >= ct.2;
        let (poly, (axis, origin, _)) = if halve_src { (&s, cs) } else { (&t, ct) };
        let Some((h1, h2)) = halves(poly, axis, origin) else {
            return false;
        };
        for h in [h1, h2] {
            if halve_src {
                queue.push_back((h, t.clone(), depth + 1));
            } else {
                queue.push_back((s.clone(), h, depth + 1));
            }
        }
    }
    true
}

/// The mean of `p`'s vertices (inside a convex polygon).
fn mean(p: &[DVec3]) -> DVec3 {
    p.iter().copied().sum::<DVec3>() / p.len().max(1) as f64
}

/// Where to halve convex `p`: the unit direction of its longest edge, the middle of its
/// extent along it, and that extent.
fn cut_of(p: &[DVec3]) -> (DVec3, DVec3, f64) {
    let m = p.len();
    let mut axis = DVec3::ZERO;
    let mut longest = 0.0;
    for k in 0..m {
        let e = p[(k + 1) % m] - p[k];
        let l = e.length();
        if l > longest {
            longest = l;
            axis = e / l;
        }
    }
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut at_lo, mut at_hi) = (p[0], p[0]);
    for &v in p {
        let d = axis.dot(v);
        if d < lo {
            lo = d;
            at_lo = v;
        }
        if d > hi {
            hi = d;
            at_hi = v;
        }
    }
    (axis, 0.5 * (at_lo + at_hi), (hi - lo).max(0.0))
}

/// The parts of convex `p` on either side of the plane through `origin` across the unit
/// `axis` (closed half-spaces); `None` if either is degenerate.
fn halves(p: &[DVec3], axis: DVec3, origin: DVec3) -> Option<(Vec<DVec3>, Vec<DVec3>)> {
    if axis == DVec3::ZERO {
        return None;
    }
    let part = |normal: DVec3| {
        let mut out = Vec::with_capacity(p.len() + 1);
        HalfSpace {
            origin,
            normal,
            tol: 0.0,
        }
        .for_each_clipped_edge(p, |u, _| out.push(u));
        out
    };
    let (h1, h2) = (part(axis), part(-axis));
    (h1.len() >= 3 && h2.len() >= 3).then_some((h1, h2))
}

/// Whether the segment `[p, q]` crosses one of the candidates (its plane strictly between
/// the ends, the crossing inside or on the polygon). Only a filter: `false` proves a sight
/// line is seen; `true` proves nothing.
fn segment_blocked(p: DVec3, q: DVec3, cands: &[u32], occ: &[Occluder]) -> bool {
    cands.iter().any(|&k| {
        let o = &occ[k as usize];
        let (dp, dq) = (o.plane.distance(p), o.plane.distance(q));
        if !(dp * dq < 0.0) {
            return false;
        }
        let c = p + (q - p) * (dp / (dp - dq));
        let m = o.vertices.len();
        (0..m).all(|e| {
            let (u, v) = (o.vertices[e], o.vertices[(e + 1) % m]);
            (v - u).cross(c - u).dot(o.plane.normal) >= 0.0
        })
    })
}
