//! The inner integral: the form factor from a point to the part of a convex polygon it
//! sees past convex occluders, exact up to rounding (see the parent module for the method).

use alloc::vec::Vec;

use crate::error::{ErrorKind, Result};
use crate::formfactor::exact_3d::{Plane, point_to_polygon};
use crate::geom::{DVec2, DVec3};

mod lambert;

/// Most convex pieces the visible part of one target may be cut into, from one point. A
/// point behind `s` shadows of `m` edges each needs at most `1 + s·m` pieces per piece cut,
/// so this allows scenes with hundreds of overlapping shadows per pair; beyond it
/// [`ErrorKind::TooLarge`] stops the job instead of an unbounded computation.
pub const MAX_VISIBLE_PIECES: usize = 4096;

/// Relative depth `η` of the guard near the point: occluder parts with
/// `d(y) > (1 − η) d(x)` (closer to the point than `η` times its distance to the target's
/// plane, along the sight line) are left out, so the central projection's divisor stays at
/// least `η` (see the parent module).
pub const NEAR_GUARD: f64 = 1e-9;

/// Relative area (of the target's) under which a clipped piece or shadow is rounding
/// debris and is dropped.
const SLIVER_AREA: f64 = 1e-13;

/// Relative length (of the target's radius) under which a point counts as lying on a
/// clipping line.
const ON_LINE: f64 = 1e-12;

/// Relative length (of the target's radius) under which two consecutive vertices of a
/// shadow are one vertex ([`merge_close_vertices`]).
///
/// Clipping an occluder vertex that lies on a pyramid plane up to rounding (an occluder
/// standing on the target's edge: a block beside a floor piece, seen from the ceiling)
/// yields the vertex and a crossing point a rounding error away from it. The edge between
/// them has a direction made of rounding, and [`Target::subtract_shadow`] would cut the
/// visible part along a line through the vertex in that direction: in Cornell 810 pair
/// (488, 547), `F_{dx→vis(j)}` jumped by 2.5 % between neighbouring points, at random,
/// and the adaptive integral spent its whole work cap on the noise. Merging the two moves
/// the shadow by at most this length (area `≤ 10⁻¹⁰ r` times the shadow's perimeter,
/// relative `~10⁻⁹`); a shadow vertex has a rounding error of about `10⁻¹⁴ r` (it was
/// `3·10⁻¹⁵ r` there), so edges left are long enough for their lines to be accurate
/// except where a genuine shadow edge is that short (near a visibility event: a set of
/// points too thin to matter).
const MERGE: f64 = 1e-10;

/// Relative length (of the target's radius) within which a shadow's vertex counts as on
/// the outside of another shadow's edge line when [`apart`] looks for a
/// separating line: about 64 roundings of a coordinate (`2⁻⁵²`), so that the shared edge
/// of two faces of one solid, whose clipped ends each shadow computes on its own, does
/// not hide that their shadows are apart (a shadow vertex's rounding is about `10⁻¹⁴`
/// of the radius, [`MERGE`]), while an overlap found apart is at most this wide.
const APART: f64 = 64.0 * f64::EPSILON;

/// Relative size (of the sum of the magnitudes of its terms, over `2π`) under which
/// `F_{dx→P} − Σ_k F_{dx→U_k}` is rounding ([`Target::whole_minus_shadows`]): the
/// compensated sums are good to a few units of `2⁻⁵³` of that, and each term to a few
/// units of its own size, so a difference below this is taken as no visible part.
const CANCELLED: f64 = 64.0 * f64::EPSILON;

/// Share of the target's area above which the shadows' union is said to cover the
/// target, and the part seen is computed as disjoint convex pieces
/// ([`Target::visible_by_pieces`]) rather than as the target less the union
/// ([`Target::whole_minus_shadows`]): then `F_{dx→vis(P)}` is at most about as large as
/// the union's (up to the variation of the kernel over the target), so the difference
/// loses at most a few bits to cancellation, and a part seen of a sliver's area is 0.
const COVERED_SHARE: f64 = 1.0 - 1.0 / 64.0;

/// A target polygon prepared for visibility queries: its plane and its outline in plane
/// coordinates `(u, v)` about its centroid, with `u × v = n`.
#[derive(Clone, Debug)]
pub(crate) struct Target {
    plane: Plane,
    vertices: Vec<DVec3>,
    u: DVec3,
    v: DVec3,
    outline: Vec<DVec2>,
    /// The outline's edge lines as (a point, the unit inward normal), zero-length edges
    /// left out: the same for every point, so found once.
    edges: Vec<(DVec2, DVec2)>,
    /// No two consecutive vertices of the outline (the last and the first included) are
    /// equal: then no piece cut from it has any either ([`cut`]).
    distinct: bool,
    tol: f64,
    sliver: f64,
    merge: f64,
    /// The outline's area (in plane coordinates).
    area: f64,
    /// The slack of [`apart`], `APART` times the radius.
    apart: f64,
}

impl Target {
    /// `vertices` (convex, planar, counter-clockwise about the front normal) with `plane`.
    pub fn new(vertices: &[DVec3], plane: Plane) -> Self {
        let n = plane.normal;
        let u = n.any_orthonormal_vector();
        let v = n.cross(u);
        let c = plane.centroid;
        let outline = vertices
            .iter()
            .map(|&p| DVec2::new(u.dot(p - c), v.dot(p - c)))
            .collect::<Vec<_>>();
        let m = outline.len();
        let edges = (0..m)
            .filter_map(|k| {
                let (a, b) = (outline[k], outline[if k + 1 == m { 0 } else { k + 1 }]);
                inward_normal(a, b).map(|inward| (a, inward))
            })
            .collect();
        let distinct = distinct_vertices(&outline);
        let area = crate::geom::signed_area(&outline);
        Self {
            plane,
            vertices: vertices.to_vec(),
            u,
            v,
            outline,
            edges,
            distinct,
            tol: ON_LINE * plane.radius,
            sliver: SLIVER_AREA * plane.area,
            merge: MERGE * plane.radius,
            area,
            apart: APART * plane.radius,
        }
    }

    /// Plane coordinates of a point of the target's plane.
    fn to_plane(&self, p: DVec3) -> DVec2 {
        let d = p - self.plane.centroid;
        DVec2::new(self.u.dot(d), self.v.dot(d))
    }

    /// The point of the target's plane at plane coordinates `q`.
    fn to_space(&self, q: DVec2) -> DVec3 {
        self.plane.centroid + q.x * self.u + q.y * self.v
    }

    /// `F_{dx→vis(P)}`: the form factor (2.16, with `V`) from a point `x` with normal `n`
    /// to the part of the target that `x` sees past `occluders` (convex planar polygons,
    /// either orientation, opaque from both sides): the target minus the shadows the
    /// occluders cast on its plane from `x`. Lambert's contour formula is additive over
    /// interior-disjoint regions, so this is `F_{dx→P}` less the form factor of the
    /// shadows' union as disjoint convex pieces ([`Self::disjoint_union`],
    /// [`Self::whole_minus_shadows`]); where the union covers more than
    /// [`COVERED_SHARE`] of the target, the visible part itself as disjoint convex pieces
    /// ([`Self::visible_by_pieces`]), each by [`point_to_polygon`].
    ///
    /// # Errors
    /// [`ErrorKind::TooLarge`] when the visible part or the union needs more than
    /// `MAX_VISIBLE_PIECES` pieces.
    pub fn visible_form_factor(
        &self,
        x: DVec3,
        n: DVec3,
        occluders: &[&[DVec3]],
        work: &mut Workspace,
    ) -> Result<f64> {
        self.visible_form_factor_with(x, n, occluders, &[], work)
    }

    /// [`Self::visible_form_factor`], the same bits, told for each occluder whether
    /// [`Self::keeps_in_front`] holds for it (`in_front[k]`; missing entries: not known),
    /// so that the clip to the target's front, which would leave it as it is, is skipped.
    ///
    /// # Errors
    /// Those of [`Self::visible_form_factor`].
    pub fn visible_form_factor_with(
        &self,
        x: DVec3,
        n: DVec3,
        occluders: &[&[DVec3]],
        in_front: &[bool],
        work: &mut Workspace,
    ) -> Result<f64> {
        let Some((dx, tol)) = self.begin_point(x, !occluders.is_empty(), work) else {
            return Ok(0.0);
        };
        // The shadows, each inside the target; one within a sliver of the target's area
        // leaves nothing seen.
        for (k, occluder) in occluders.iter().enumerate() {
            let in_front = in_front.get(k).copied().unwrap_or(false);
            let Some(area) = self.shadow(x, dx, occluder, in_front, work) else {
                continue;
            };
            if area >= self.area - self.sliver {
                return Ok(0.0);
            }
            let fresh = work.spare.pop().unwrap_or_default();
            let shadow = core::mem::replace(&mut work.shadow, fresh);
            work.shadows.push(Shadow::new(shadow, area));
        }
        if work.shadows.is_empty() {
            return Ok(point_to_polygon(x, n, &self.vertices));
        }
        let covered = self.disjoint_union(work)?;
        if self.area - covered <= self.sliver {
            return Ok(0.0);
        }
        // The shadows cover more than the part seen: the part seen, cut into pieces,
        // keeps its own relative accuracy (the difference would lose it to
        // cancellation) and its zeros (pieces of a sliver's area dropped).
        if covered > self.area * COVERED_SHARE {
            return self.visible_by_pieces(x, n, work);
        }
        Ok(self.whole_minus_shadows(x, n, tol, work))
    }

    /// The union of the point's shadows (`work.shadows`) as interior-disjoint convex
    /// pieces, and their summed area. The shadows are taken largest first (the union
    /// does not depend on the order); each is left out when it lies inside an earlier one
    /// kept ([`inside`]), kept whole when it is apart from every earlier one kept
    /// ([`apart`]: the common case, the front faces of one convex solid), else cut by the
    /// earlier ones kept that it may overlap ([`Self::subtract_shadow`]) into its pieces
    /// outside them, which go to `work.union`. Pieces of at most a sliver's area are
    /// dropped, as the visible part's pieces are.
    ///
    /// # Errors
    /// [`ErrorKind::TooLarge`] when the union needs more than `MAX_VISIBLE_PIECES` pieces.
    fn disjoint_union(&self, work: &mut Workspace) -> Result<f64> {
        let mut shadows = core::mem::take(&mut work.shadows);
        let mut order = core::mem::take(&mut work.order);
        order.clear();
        order.extend(0..shadows.len());
        order.sort_unstable_by(|&a, &b| shadows[b].area.total_cmp(&shadows[a].area));
        let mut covered = 0.0;
        let mut result = Ok(());
        for (at, &k) in order.iter().enumerate() {
            let earlier = order[..at].iter().map(|&e| &shadows[e]);
            let shadow = &shadows[k];
            let mut kept = earlier.clone().filter(|s| s.part != Part::Left);
            if kept
                .clone()
                .any(|s| inside(&shadow.outline, &s.outline, self.apart))
            {
                shadows[k].part = Part::Left;
                continue;
            }
            if kept.all(|s| apart(s, shadow, self.apart)) {
                covered += shadow.area;
                shadows[k].part = Part::Whole;
                continue;
            }
            work.recycle_pieces();
            let mut piece = work.spare.pop().unwrap_or_default();
            piece.clear();
            piece.extend_from_slice(&shadow.outline);
            work.pieces.push(piece);
            for cutter in earlier {
                if cutter.part == Part::Left || apart(cutter, shadow, self.apart) {
                    continue;
                }
                // A shadow has no two equal consecutive vertices (merged), so neither
                // has any piece cut from it.
                result = self.subtract_shadow(&cutter.outline, true, work);
                if result.is_err() || work.pieces.is_empty() {
                    break;
                }
            }
            shadows[k].part = Part::Cut;
            if result.is_err() {
                break;
            }
            covered += work
                .pieces
                .iter()
                .map(|p| crate::geom::signed_area(p))
                .sum::<f64>();
            work.union.append(&mut work.pieces);
            if work.union.len() > MAX_VISIBLE_PIECES {
                result = Err(ErrorKind::TooLarge {
                    what: "convex pieces of the shadows' union on a polygon from one point",
                    max: MAX_VISIBLE_PIECES as u64,
                }
                .into());
                break;
            }
        }
        work.shadows = shadows;
        work.order = order;
        result.map(|()| covered)
    }

    /// `F_{dx→vis(P)}` from the shadows' union as disjoint convex pieces
    /// ([`Self::disjoint_union`]: the shadows apart from every earlier one, and the
    /// pieces in `work.union`). The contour form factor is additive over
    /// interior-disjoint regions (Lambert's sum over a region's boundary; an edge two
    /// regions share is walked both ways and cancels), and the target is the disjoint
    /// union of the visible part and the pieces (each inside the target), so
    /// `F_{dx→vis(P)} = F_{dx→P} − Σ_k F_{dx→U_k}` ([`lambert`]; through
    /// [`point_to_polygon`] when the target reaches `x`'s horizon), clamped to `[0, 1]`.
    /// Rounding: a few units of `2⁻⁵³` of the terms' magnitudes, whatever the visible
    /// part's size (hence [`COVERED_SHARE`]); a difference below [`CANCELLED`] of them is
    /// 0.
    fn whole_minus_shadows(&self, x: DVec3, n: DVec3, tol: f64, work: &mut Workspace) -> f64 {
        let Workspace {
            shadows,
            union,
            space,
            ..
        } = work;
        let whole_shadows = shadows
            .iter()
            .filter(|s| s.part == Part::Whole)
            .map(|s| s.outline.as_slice());
        let pieces = whole_shadows.chain(union.iter().map(Vec::as_slice));
        // Every target vertex in front of x's horizon by more than the point's tolerance
        // and twice the outline clip's (a shadow vertex may lie that far outside the
        // target): no polygon needs the horizon clip, so one contour sum over the
        // target's edges and the pieces' edges walked backwards.
        let margin = tol + 2.0 * self.tol;
        let (scale, seen) = if self.vertices.iter().all(|&v| n.dot(v - x) > margin) {
            let mut magnitude = 0.0;
            let mut target = crate::math::KahanSum::new();
            lambert::add_outline((&mut target, &mut magnitude), x, n, &self.vertices);
            let mut shaded = crate::math::KahanSum::new();
            for piece in pieces {
                space.clear();
                space.extend(piece.iter().map(|&q| self.to_space(q)));
                lambert::add_outline((&mut shaded, &mut magnitude), x, n, space);
            }
            let whole = lambert::form_factor(&target);
            (
                magnitude / (2.0 * core::f64::consts::PI),
                whole - lambert::form_factor(&shaded),
            )
        } else {
            let whole = point_to_polygon(x, n, &self.vertices);
            let mut shaded = crate::math::KahanSum::new();
            for piece in pieces {
                space.clear();
                space.extend(piece.iter().map(|&q| self.to_space(q)));
                shaded.add(point_to_polygon(x, n, space));
            }
            (whole + shaded.total(), whole - shaded.total())
        };
        if seen <= CANCELLED * scale {
            0.0
        } else {
            seen.clamp(0.0, 1.0)
        }
    }

    /// [`Self::visible_form_factor`] as it was until session 21, for the tests: the
    /// visible part as disjoint convex pieces ([`Self::visible_by_pieces`]) instead of
    /// the target less the shadows' union.
    #[cfg(test)]
    fn visible_form_factor_by_pieces(
        &self,
        x: DVec3,
        n: DVec3,
        occluders: &[&[DVec3]],
        work: &mut Workspace,
    ) -> Result<f64> {
        let Some((dx, _)) = self.begin_point(x, !occluders.is_empty(), work) else {
            return Ok(0.0);
        };
        for occluder in occluders {
            let Some(area) = self.shadow(x, dx, occluder, false, work) else {
                continue;
            };
            let fresh = work.spare.pop().unwrap_or_default();
            let shadow = core::mem::replace(&mut work.shadow, fresh);
            work.shadows.push(Shadow::new(shadow, area));
        }
        if work.shadows.is_empty() {
            return Ok(point_to_polygon(x, n, &self.vertices));
        }
        self.visible_by_pieces(x, n, work)
    }

    /// The visible part of the target as disjoint convex pieces: the target cut by each
    /// of `work.shadows` in turn ([`Self::subtract_shadow`]), each piece by Lambert's
    /// contour formula ([`point_to_polygon`]), summed.
    fn visible_by_pieces(&self, x: DVec3, n: DVec3, work: &mut Workspace) -> Result<f64> {
        work.recycle_pieces();
        let mut whole = work.spare.pop().unwrap_or_default();
        whole.clear();
        whole.extend_from_slice(&self.outline);
        work.pieces.push(whole);
        let shadows = core::mem::take(&mut work.shadows);
        let mut result = Ok(());
        for shadow in &shadows {
            result = self.subtract_shadow(&shadow.outline, self.distinct, work);
            if result.is_err() || work.pieces.is_empty() {
                break;
            }
        }
        work.shadows = shadows;
        result?;
        if work.pieces.is_empty() {
            return Ok(0.0);
        }
        let mut sum = crate::math::KahanSum::new();
        for piece in &work.pieces {
            work.space.clear();
            work.space.extend(piece.iter().map(|&q| self.to_space(q)));
            sum.add(point_to_polygon(x, n, &work.space));
        }
        Ok(sum.total().clamp(0.0, 1.0))
    }

    /// A point's start: its distance `d(x)` in front of the target's plane and the
    /// rounding tolerance of that distance, or `None` when it lies on or behind the plane
    /// (within the tolerance: it sees nothing); the buffers of the last point recycled, and
    /// the point's clipping planes ([`Self::pyramid`]) when it has occluders.
    fn begin_point(&self, x: DVec3, occluded: bool, work: &mut Workspace) -> Option<(f64, f64)> {
        let dx = self.plane.distance(x);
        let tol = super::super::exact_3d::ON_PLANE
            * (self.plane.magnitude + x.abs().max_element() + self.plane.radius);
        if dx <= tol {
            return None;
        }
        work.recycle_pieces();
        work.recycle_shadows();
        if occluded {
            self.pyramid(x, dx, work);
        }
        Some((dx, tol))
    }

    /// Whether `occluder` lies on the kept side of the first clipping plane of every point,
    /// the target's own plane (`n · y − n · o ≥ 0`, the expression of [`Self::pyramid`]'s
    /// plane and of [`clip3`], for every vertex `y`), with no two consecutive vertices
    /// equal (the last and the first included). Then that clip leaves the occluder as it
    /// is at every point, whatever the point's tolerance (a snapped distance is 0 or the
    /// distance itself, both `≥ 0`), and no vertex is beyond it, so
    /// [`Self::visible_form_factor_with`] may skip the plane: the same bits. The plane
    /// does not depend on the point, so this is known once per target and occluder.
    pub fn keeps_in_front(&self, occluder: &[DVec3]) -> bool {
        let (n, o) = (self.plane.normal, self.plane.origin);
        let offset = n.dot(o);
        let m = occluder.len();
        m >= 3
            && (0..m).all(|k| {
                let y = occluder[k];
                n.dot(y) - offset >= 0.0 && y != occluder[if k + 1 == m { 0 } else { k + 1 }]
            })
    }

    /// The clipping planes of a point's shadows, as `(normal, offset, tolerance)` of the
    /// half-spaces `normal · y ≥ offset` into `work.planes`: in front of the target's plane,
    /// short of the near guard (`d(y) ≤ (1 − η) d(x)`), and the pyramid from `x` over the
    /// target (the planes through `x` and each target edge, facing the centroid).
    fn pyramid(&self, x: DVec3, dx: f64, work: &mut Workspace) {
        let n = self.plane.normal;
        let o = self.plane.origin;
        let scale = self.plane.radius + (x - self.plane.centroid).length();
        let tol = super::super::exact_3d::ON_PLANE * scale;
        work.planes.clear();
        work.planes.push((n, n.dot(o), tol));
        let near = n.dot(o) + (1.0 - NEAR_GUARD) * dx;
        work.planes.push((-n, -near, tol));
        let m = self.vertices.len();
        for k in 0..m {
            let (p, q) = (
                self.vertices[k],
                self.vertices[if k + 1 == m { 0 } else { k + 1 }],
            );
            let mut side = (q - x).cross(p - x);
            if side.dot(self.plane.centroid - x) < 0.0 {
                side = -side;
            }
            let len = side.length();
            if !(len > 0.0) {
                continue;
            }
            let side = side / len;
            work.planes.push((side, side.dot(x), 0.0));
        }
    }

    /// The shadow of `occluder` on the target from `x` (at distance `dx` in front of the
    /// target's plane), counter-clockwise in plane coordinates, into `work.shadow`, and its
    /// area; `None` when it is empty or a sliver.
    ///
    /// The occluder is clipped to the pyramid with apex `x` over the target (the planes
    /// through `x` and each target edge) and to `0 ≤ d(y) ≤ (1 − η) d(x)`; each remaining
    /// vertex `y` lies on a sight line from `x` to the target, between them, and is
    /// projected to where that line meets the target's plane,
    /// `y ↦ x + d(x) / (d(x) − d(y)) · (y − x)`.
    ///
    /// `in_front`: [`Self::keeps_in_front`] holds for `occluder`, so the first plane (the
    /// target's), whose clip would leave it as it is and which none of its vertices is
    /// beyond, is skipped.
    fn shadow(
        &self,
        x: DVec3,
        dx: f64,
        occluder: &[DVec3],
        in_front: bool,
        work: &mut Workspace,
    ) -> Option<f64> {
        let n = self.plane.normal;
        let o = self.plane.origin;
        let first = usize::from(in_front).min(work.planes.len());
        // Wholly outside one of the planes (beyond its tolerance): the clips below would
        // leave nothing, so skip them.
        if work.planes[first..]
            .iter()
            .any(|&(normal, offset, tol)| occluder.iter().all(|&y| normal.dot(y) - offset < -tol))
        {
            return None;
        }
        work.a.clear();
        work.a.extend_from_slice(occluder);
        // Whether `work.a` is known to have no two equal consecutive vertices: a clip that
        // changes a polygon leaves none (see `cut`), one that does not leaves it as it was.
        let mut distinct = false;
        // In front of the target's plane, short of the near guard, inside the pyramid from
        // x over the target (the planes of `pyramid`, in that order).
        for k in first..work.planes.len() {
            if work.a.len() < 3 {
                return None;
            }
            let (normal, offset, tol) = work.planes[k];
            distinct |= clip3(&mut work.a, &mut work.b, (normal, offset, tol), distinct);
        }
        if work.a.len() < 3 {
            return None;
        }
        work.shadow.clear();
        for &y in &work.a {
            let s = (dx - n.dot(y - o)) / dx;
            let s = s.max(NEAR_GUARD);
            work.shadow.push(self.to_plane(x + (y - x) / s));
        }
        // Counter-clockwise about the target's normal, then inside the target (rounding).
        let area = crate::geom::signed_area(&work.shadow);
        // Whether `work.shadow` is still the polygon whose area is `area`: then its area
        // need not be summed again (the same bits).
        let reversed = area < 0.0;
        if reversed {
            work.shadow.reverse();
        }
        let mut same = !reversed;
        // Two distinct points in space may project to one: look once, then as above.
        let mut distinct = distinct_vertices(&work.shadow);
        for &(a, inward) in &self.edges {
            let clipped = clip2(
                &mut work.shadow,
                &mut work.scratch,
                (a, inward, self.tol),
                distinct,
            );
            same &= !clipped;
            distinct |= clipped;
            if work.shadow.len() < 3 {
                return None;
            }
        }
        let before = work.shadow.len();
        merge_close_vertices(&mut work.shadow, self.merge);
        // Merging only drops vertices: as many left, none dropped.
        same &= work.shadow.len() == before;
        if work.shadow.len() < 3 {
            return None;
        }
        let area = if same {
            area
        } else {
            crate::geom::signed_area(&work.shadow)
        };
        (area > self.sliver).then_some(area)
    }

    /// Replaces `work.pieces` by their parts outside `shadow`: each piece is cut by
    /// the shadow's edge lines in turn, keeping the part outside each line as a new piece
    /// and going on with the part inside; what is inside every line is the shadow's and is
    /// dropped. The pieces stay disjoint and convex.
    fn subtract_shadow(
        &self,
        shadow: &[DVec2],
        distinct: bool,
        work: &mut Workspace,
    ) -> Result<()> {
        let Workspace {
            pieces,
            next,
            scratch,
            spare,
            lines,
            ..
        } = work;
        let (slo, shi) = bounds2(shadow);
        let m = shadow.len();
        lines.clear();
        lines.extend((0..m).filter_map(|k| {
            let (a, b) = (shadow[k], shadow[if k + 1 == m { 0 } else { k + 1 }]);
            inward_normal(a, b).map(|inward| (a, inward))
        }));
        let big = |p: &[DVec2]| p.len() >= 3 && crate::geom::signed_area(p) > self.sliver;
        next.clear();
        for piece in pieces.drain(..) {
            let (plo, phi) = bounds2(&piece);
            if plo.x >= shi.x || plo.y >= shi.y || slo.x >= phi.x || slo.y >= phi.y {
                next.push(piece);
                continue;
            }
            // The piece itself is cut (its outline becomes the part inside the lines).
            let mut rest = piece;
            // Whether `big(rest)` is known to hold for `rest` as it is now: a line that
            // leaves it unchanged needs no second look at its area (the same bits).
            let mut rest_big = false;
            for &(a, inward) in lines.iter() {
                // The part outside the line is written straight into a spare outline.
                let mut part = spare.pop().unwrap_or_default();
                match cut(
                    &mut rest,
                    scratch,
                    &mut part,
                    (a, inward, self.tol),
                    distinct,
                ) {
                    Cut::Inside => spare.push(part),
                    Cut::Outside => {
                        // `part` is what `rest` was; nothing is left inside.
                        if rest_big || big(&part) {
                            next.push(part);
                        } else {
                            spare.push(part);
                        }
                        break;
                    }
                    Cut::Both => {
                        if big(&part) {
                            next.push(part);
                        } else {
                            spare.push(part);
                        }
                        rest_big = false;
                    }
                }
                if !rest_big {
                    if !big(&rest) {
                        break;
                    }
                    rest_big = true;
                }
            }
            spare.push(rest);
            if next.len() > MAX_VISIBLE_PIECES {
                return Err(ErrorKind::TooLarge {
                    what: "convex pieces of a polygon's visible part from one point",
                    max: MAX_VISIBLE_PIECES as u64,
                }
                .into());
            }
        }
        core::mem::swap(pieces, next);
        Ok(())
    }
}

/// Buffers reused across points, so a point costs no allocation once they have grown.
#[derive(Debug, Default)]
pub(crate) struct Workspace {
    pieces: Vec<Vec<DVec2>>,
    next: Vec<Vec<DVec2>>,
    /// Outlines no longer in use, kept with their capacity for the next pieces (so
    /// cutting the visible part allocates nothing once the pool has grown).
    spare: Vec<Vec<DVec2>>,
    /// The current shadow's edge lines, as (a point, the unit inward normal).
    lines: Vec<(DVec2, DVec2)>,
    shadow: Vec<DVec2>,
    /// The current point's shadows ([`Target::shadow`]), in the occluders' order.
    shadows: Vec<Shadow>,
    /// The pieces of the shadows' union cut from shadows that overlap an earlier one
    /// ([`Target::disjoint_union`]).
    union: Vec<Vec<DVec2>>,
    /// The shadows' indices, largest first ([`Target::disjoint_union`]).
    order: Vec<usize>,
    scratch: Vec<DVec2>,
    space: Vec<DVec3>,
    a: Vec<DVec3>,
    b: Vec<DVec3>,
    /// The current point's clipping planes (`Target::pyramid`).
    planes: Vec<(DVec3, f64, f64)>,
}

impl Workspace {
    /// Moves the current pieces to the spare outlines (emptying `pieces`).
    fn recycle_pieces(&mut self) {
        self.spare.append(&mut self.pieces);
    }

    /// Moves the current shadows' outlines and the union's pieces to the spare outlines
    /// (emptying `shadows` and `union`).
    fn recycle_shadows(&mut self) {
        self.spare
            .extend(self.shadows.drain(..).map(|shadow| shadow.outline));
        self.spare.append(&mut self.union);
    }
}

/// One shadow on the target: its outline (convex, counter-clockwise, in plane
/// coordinates), axis-aligned bounds and area, and its part in the shadows' union
/// ([`Target::disjoint_union`]).
#[derive(Debug)]
struct Shadow {
    outline: Vec<DVec2>,
    lo: DVec2,
    hi: DVec2,
    area: f64,
    part: Part,
}

/// What [`Target::disjoint_union`] made of a shadow.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Part {
    /// Not yet decided.
    Open,
    /// Inside an earlier shadow: left out.
    Left,
    /// Apart from every earlier one kept: a piece of the union as it is.
    Whole,
    /// Cut by earlier ones: its pieces are in `Workspace::union`.
    Cut,
}

impl Shadow {
    fn new(outline: Vec<DVec2>, area: f64) -> Self {
        let (lo, hi) = bounds2(&outline);
        Self {
            outline,
            lo,
            hi,
            area,
            part: Part::Open,
        }
    }
}

/// Whether the interiors of shadows `a` and `b` are proven disjoint, by boxes apart or
/// by a separating line, with `tol` (a length) of slack: some edge line of one (both are
/// convex: if their interiors are disjoint, the line of an edge of one of them separates
/// them, the separating-axis theorem in the plane) with every vertex of the other at
/// most `tol` inside it. `tol` is a few roundings of a shadow vertex ([`APART`]), so that
/// two faces of one solid, which share an edge whose ends each shadow computes on its
/// own, are found apart, while shadows found apart overlap by at most that width.
/// `O(m_a m_b)` for shadows of `m_a` and `m_b` vertices.
fn apart(a: &Shadow, b: &Shadow, tol: f64) -> bool {
    a.hi.x <= b.lo.x + tol
        || b.hi.x <= a.lo.x + tol
        || a.hi.y <= b.lo.y + tol
        || b.hi.y <= a.lo.y + tol
        || edge_separates(&a.outline, &b.outline, tol)
        || edge_separates(&b.outline, &a.outline, tol)
}

/// Whether every vertex of `b` lies inside (or within `tol` outside) every edge line of
/// the convex, counter-clockwise `a`: then `b`, convex, lies in `a` widened by `tol`.
fn inside(b: &[DVec2], a: &[DVec2], tol: f64) -> bool {
    let m = a.len();
    (0..m).all(|k| {
        let (p, q) = (a[k], a[if k + 1 == m { 0 } else { k + 1 }]);
        inward_normal(p, q).is_none_or(|inward| b.iter().all(|&y| inward.dot(y - p) >= -tol))
    })
}

/// Whether the line of some edge of the convex, counter-clockwise `a` has every vertex of
/// `b` on its outside or within `tol` inside it.
fn edge_separates(a: &[DVec2], b: &[DVec2], tol: f64) -> bool {
    let m = a.len();
    (0..m).any(|k| {
        let (p, q) = (a[k], a[if k + 1 == m { 0 } else { k + 1 }]);
        inward_normal(p, q).is_some_and(|inward| b.iter().all(|&y| inward.dot(y - p) <= tol))
    })
}

/// Whether no two consecutive vertices of the closed polygon `poly` (the last and the first
/// included) are equal.
fn distinct_vertices(poly: &[DVec2]) -> bool {
    let m = poly.len();
    (0..m).all(|k| poly[k] != poly[if k + 1 == m { 0 } else { k + 1 }])
}

/// Drops each vertex of the closed polygon `poly` that lies within `merge` of the last one
/// kept (the first vertex against the last kept, too), so that no edge is shorter than
/// `merge` (see [`MERGE`]). Bounded: one pass.
fn merge_close_vertices(poly: &mut Vec<DVec2>, merge: f64) {
    // A coordinate difference above `merge` decides without the root: the computed
    // length is at least each |difference| (`√(fl(d²))` is `|d|` exactly, and adding the
    // other square and rounding never lowers it), so the answer is the same.
    let close = |a: DVec2, b: DVec2| {
        let d = a - b;
        d.x.abs() <= merge && d.y.abs() <= merge && crate::math::length(d) <= merge
    };
    let mut kept = 0;
    for k in 0..poly.len() {
        if kept == 0 || !close(poly[k], poly[kept - 1]) {
            poly[kept] = poly[k];
            kept += 1;
        }
    }
    poly.truncate(kept);
    while poly.len() > 1
        && poly
            .first()
            .zip(poly.last())
            .is_some_and(|(&a, &b)| close(a, b))
    {
        poly.pop();
    }
}

/// The unit normal pointing left of `a → b` (into a counter-clockwise polygon), `None`
/// for a zero-length edge.
fn inward_normal(a: DVec2, b: DVec2) -> Option<DVec2> {
    let e = b - a;
    let len = crate::math::length(e);
    (len > 0.0).then(|| DVec2::new(-e.y, e.x) / len)
}

/// Axis-aligned bounds of a 2D polygon, by plain comparisons (the values of
/// `f64::min`/`max` up to the sign of a zero, which the comparisons of the bounds do not
/// see, at a fifth of the instructions).
fn bounds2(p: &[DVec2]) -> (DVec2, DVec2) {
    let (mut lo, mut hi) = (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
    for &q in p {
        lo.x = if q.x < lo.x { q.x } else { lo.x };
        lo.y = if q.y < lo.y { q.y } else { lo.y };
        hi.x = if q.x > hi.x { q.x } else { hi.x };
        hi.y = if q.y > hi.y { q.y } else { hi.y };
    }
    (lo, hi)
}

/// Sutherland–Hodgman: `poly` replaced by its part where `normal · (p − a) ≥ 0` (points
/// within `tol` of the line count as on it); `tmp` is scratch. `false` when `poly` was
/// left as it was (wholly on the kept side), `true` when it was clipped. `distinct`: the
/// caller knows that `poly` has no two equal consecutive vertices, so that the test for
/// them is skipped (the same bits).
fn clip2(
    poly: &mut Vec<DVec2>,
    tmp: &mut Vec<DVec2>,
    (a, normal, tol): (DVec2, DVec2, f64),
    distinct: bool,
) -> bool {
    let m = poly.len();
    let side = |p: DVec2| {
        let d = normal.dot(p - a);
        if d.abs() <= tol { 0.0 } else { d }
    };
    // Wholly on the kept side with no repeated vertex: the loop below would give `poly`
    // back unchanged (no crossing, every vertex kept, none dropped as a repeat), so leave
    // it.
    if (0..m).all(|k| {
        side(poly[k]) >= 0.0 && (distinct || poly[k] != poly[if k + 1 == m { 0 } else { k + 1 }])
    }) {
        return false;
    }
    tmp.clear();
    for k in 0..m {
        let (p, q) = (poly[k], poly[if k + 1 == m { 0 } else { k + 1 }]);
        let (dp, dq) = (side(p), side(q));
        if dp >= 0.0 && tmp.last() != Some(&p) {
            tmp.push(p);
        }
        if (dp > 0.0 && dq < 0.0) || (dp < 0.0 && dq > 0.0) {
            let r = p + (q - p) * (dp / (dp - dq));
            if tmp.last() != Some(&r) {
                tmp.push(r);
            }
        }
    }
    if tmp.len() > 1 && tmp.first() == tmp.last() {
        tmp.pop();
    }
    core::mem::swap(poly, tmp);
    true
}

/// What [`cut`] did with a polygon.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Cut {
    /// No vertex outside: the polygon is left as it is, nothing of area outside.
    Inside,
    /// No vertex inside: the polygon moved to the outside part, nothing of area left
    /// inside.
    Outside,
    /// Anything else: both parts by [`split2`].
    Both,
}

/// [`split2`] of `poly`, with `poly` replaced by the inside part and `outside` by the
/// outside part, the same bits, except that a part of at most two vertices may be left
/// empty instead (the caller drops such parts either way). A polygon with no repeated
/// vertex, at most two vertices on the line (within `tol`) and the rest on one side is
/// not copied: `split2` would give it back whole on that side (every vertex kept, no
/// crossing, none dropped as a repeat) and only its vertices on the line on the other.
/// The classification stops at the first vertex that rules this out.
///
/// `distinct` says that `poly` is known to have no two equal consecutive vertices (the
/// last and the first included), so that the test is skipped: every part `split2` makes
/// has none (it pushes a vertex only when it differs from the last one pushed, and drops
/// the last when it equals the first, after which the new last differs from the first as
/// it differed from the dropped one), so pieces cut from an outline without any have none.
fn cut(
    poly: &mut Vec<DVec2>,
    scratch: &mut Vec<DVec2>,
    outside: &mut Vec<DVec2>,
    (a, normal, tol): (DVec2, DVec2, f64),
    distinct: bool,
) -> Cut {
    let m = poly.len();
    let (mut any_in, mut any_out, mut on_line) = (false, false, 0_usize);
    let mut whole = true;
    for k in 0..m {
        let p = poly[k];
        let d = normal.dot(p - a);
        if d.abs() <= tol {
            on_line += 1;
        } else if d > 0.0 {
            any_in = true;
        } else if d < 0.0 {
            any_out = true;
        } else {
            // Not a number: `split2` drops the vertex from both parts.
            whole = false;
            break;
        }
        if (any_in && any_out)
            || on_line > 2
            || (!distinct && p == poly[if k + 1 == m { 0 } else { k + 1 }])
        {
            whole = false;
            break;
        }
    }
    if whole && !any_out {
        outside.clear();
        Cut::Inside
    } else if whole && !any_in {
        core::mem::swap(poly, outside);
        poly.clear();
        Cut::Outside
    } else {
        split2(poly, a, normal, tol, scratch, outside);
        core::mem::swap(poly, scratch);
        Cut::Both
    }
}

/// Both sides of the line through `a` with normal `normal` in one pass: `inside` gets
/// `clip2(poly, a, normal, tol)` and `outside` gets `clip2(poly, a, -normal, tol)`, the
/// same bits. Why they are the same: each vertex's signed distance is computed once as
/// `d = normal · (p − a)`; the other side's is `(−normal) · (p − a) = −d` exactly (IEEE
/// negation commutes with products and sums under rounding to nearest), the snap to 0
/// within `tol` is symmetric, and a crossing point `p + (q − p) · dp / (dp − dq)` is the
/// same for `(−dp, −dq)`. Each distance is computed once instead of up to four times.
fn split2(
    poly: &[DVec2],
    a: DVec2,
    normal: DVec2,
    tol: f64,
    inside: &mut Vec<DVec2>,
    outside: &mut Vec<DVec2>,
) {
    inside.clear();
    outside.clear();
    let side = |p: DVec2| {
        let d = normal.dot(p - a);
        if d.abs() <= tol { 0.0 } else { d }
    };
    let m = poly.len();
    let Some(&first) = poly.first() else { return };
    let d_first = side(first);
    let (mut p, mut dp) = (first, d_first);
    for k in 0..m {
        let (q, dq) = if k + 1 == m {
            (first, d_first)
        } else {
            (poly[k + 1], side(poly[k + 1]))
        };
        if dp >= 0.0 && inside.last() != Some(&p) {
            inside.push(p);
        }
        if dp <= 0.0 && outside.last() != Some(&p) {
            outside.push(p);
        }
        if (dp > 0.0 && dq < 0.0) || (dp < 0.0 && dq > 0.0) {
            let r = p + (q - p) * (dp / (dp - dq));
            if inside.last() != Some(&r) {
                inside.push(r);
            }
            if outside.last() != Some(&r) {
                outside.push(r);
            }
        }
        (p, dp) = (q, dq);
    }
    for out in [inside, outside] {
        if out.len() > 1 && out.first() == out.last() {
            out.pop();
        }
    }
}

/// Sutherland–Hodgman in space: `poly` replaced by its part where `normal · p ≥ offset`
/// (within `tol` counts as on the plane); `tmp` is scratch. `true` when `poly` was
/// clipped; `distinct` as for [`clip2`].
///
/// The clip computes each vertex's snapped distance `normal · p − offset` once, carried
/// from one edge to the next as in [`split2`] (it used to compute it twice, for the edges
/// before and after the vertex: the same expression, so the same bits).
fn clip3(
    poly: &mut Vec<DVec3>,
    tmp: &mut Vec<DVec3>,
    (normal, offset, tol): (DVec3, f64, f64),
    distinct: bool,
) -> bool {
    let m = poly.len();
    let side = |p: DVec3| {
        let d = normal.dot(p) - offset;
        if d.abs() <= tol { 0.0 } else { d }
    };
    // Wholly on the kept side with no repeated vertex: the loop below would give `poly`
    // back unchanged, so leave it.
    if (0..m).all(|k| {
        side(poly[k]) >= 0.0 && (distinct || poly[k] != poly[if k + 1 == m { 0 } else { k + 1 }])
    }) {
        return false;
    }
    tmp.clear();
    let Some(&first) = poly.first() else {
        return false;
    };
    let d_first = side(first);
    let (mut p, mut dp) = (first, d_first);
    for k in 0..m {
        let (q, dq) = if k + 1 == m {
            (first, d_first)
        } else {
            (poly[k + 1], side(poly[k + 1]))
        };
        if dp >= 0.0 && tmp.last() != Some(&p) {
            tmp.push(p);
        }
        if (dp > 0.0 && dq < 0.0) || (dp < 0.0 && dq > 0.0) {
            let r = p + (q - p) * (dp / (dp - dq));
            if tmp.last() != Some(&r) {
                tmp.push(r);
            }
        }
        (p, dp) = (q, dq);
    }
    if tmp.len() > 1 && tmp.first() == tmp.last() {
        tmp.pop();
    }
    core::mem::swap(poly, tmp);
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The target less the shadows' union ([`Target::visible_form_factor_with`]) gives the
    /// value of the visible part cut into pieces (the path until session 21,
    /// [`Target::visible_form_factor_by_pieces`]) to rounding: random convex targets,
    /// points in front of them (some with the target across their horizon), and
    /// occluders of three kinds: the faces of a box (whose shadows meet along shared
    /// edges), loose quadrilaterals (overlapping each other and the box's shadows), and a
    /// small one beneath a large one (a shadow inside another). Each way of
    /// [`Target::disjoint_union`] (a shadow whole, cut, left out) is taken often.
    #[test]
    fn the_target_less_the_shadows_is_the_visible_pieces() {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || crate::math::xorshift_unit(&mut state) - 0.5;
        let v = DVec3::new;
        let mut work = Workspace::default();
        let mut old_work = Workspace::default();
        let mut parts = [0_usize; 3];
        let (mut compared, mut hidden, mut worst) = (0, 0, 0.0_f64);
        for case in 0..3000 {
            // A convex target in the plane z = 0, facing up, about the origin.
            let m = 3 + case % 4;
            let target: Vec<DVec3> = (0..m)
                .map(|k| {
                    let t = core::f64::consts::TAU * (k as f64 + 0.3 * next()) / m as f64;
                    v(libm::cos(t), libm::sin(t), 0.0) * (1.0 + 0.3 * next())
                })
                .collect();
            let Some(plane) = Plane::of(&target) else {
                continue;
            };
            let t = Target::new(&target, plane);
            let x = v(2.0 * next(), 2.0 * next(), 1.5 + next());
            // Facing down, tilted; every fifth point tilted far enough that the target
            // crosses its horizon.
            let tilt = if case % 5 == 0 { 1.5 } else { 0.4 };
            let n = v(tilt * next(), tilt * next(), -1.0).normalize();
            let mut occluders: Vec<Vec<DVec3>> = Vec::new();
            let h = x.z;
            if case % 3 != 1 {
                // A box between, some of its faces reaching above the point.
                let c = v(next(), next(), h * (0.35 + 0.3 * next()));
                let half = v(
                    0.1 + 0.3 * (next() + 0.5),
                    0.1 + 0.3 * (next() + 0.5),
                    0.05 + 0.3 * (next() + 0.5) * h,
                );
                occluders.extend(super::super::tests::box_faces(c - half, c + half, true));
            }
            if case % 3 != 0 {
                // Loose quadrilaterals at random heights and tilts.
                for _ in 0..1 + case % 3 {
                    let c = v(next(), next(), h * (0.5 + 0.9 * next()));
                    let (a, b) = (
                        v(0.6 * next(), 0.6 * next(), 0.2 * next()),
                        v(0.6 * next(), 0.6 * next(), 0.2 * next()),
                    );
                    occluders.push(alloc::vec![c - a - b, c + a - b, c + a + b, c - a + b]);
                }
            }
            if case % 4 == 2 {
                // A small quadrilateral under a large one: its shadow inside the other's.
                let c = v(0.5 * next(), 0.5 * next(), 0.5 * h);
                let r = 0.6;
                occluders.push(alloc::vec![
                    c + v(-r, -r, 0.0),
                    c + v(r, -r, 0.0),
                    c + v(r, r, 0.0),
                    c + v(-r, r, 0.0)
                ]);
                let c = c * 0.8;
                let r = 0.1;
                occluders.push(alloc::vec![
                    c + v(-r, -r, 0.0),
                    c + v(r, -r, 0.0),
                    c + v(r, r, 0.0),
                    c + v(-r, r, 0.0)
                ]);
            }
            let refs: Vec<&[DVec3]> = occluders.iter().map(Vec::as_slice).collect();
            let new = t.visible_form_factor(x, n, &refs, &mut work).unwrap();
            let old = t
                .visible_form_factor_by_pieces(x, n, &refs, &mut old_work)
                .unwrap();
            let whole = point_to_polygon(x, n, &target);
            let diff = (new - old).abs();
            assert!(
                diff <= 1e-14 * whole,
                "case {case}: {new:e} against {old:e} (F to the whole target {whole:e})"
            );
            worst = worst.max(diff / whole.max(f64::MIN_POSITIVE));
            if whole > 0.0 {
                compared += 1;
            }
            if old == 0.0 && whole > 0.0 {
                hidden += 1;
            }
            for s in &work.shadows {
                match s.part {
                    Part::Whole => parts[0] += 1,
                    Part::Cut => parts[1] += 1,
                    Part::Left => parts[2] += 1,
                    Part::Open => {}
                }
            }
        }
        std::println!("compared {compared}, hidden {hidden}, worst {worst:e}, parts {parts:?}");
        assert!(compared > 2000 && hidden > 20, "{compared} {hidden}");
        assert!(parts.iter().all(|&p| p > 300), "{parts:?}");
    }

    /// `split2` gives the bits of the two `clip2` calls it replaces, on polygons with
    /// vertices on, within the tolerance of, and on either side of the line.
    #[test]
    fn split2_is_the_two_clips() {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || crate::math::xorshift_unit(&mut state) - 0.5;
        let (mut i1, mut o1, mut i2, mut o2) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut cut = 0;
        for case in 0..2000 {
            let m = 3 + case % 6;
            let mut poly: Vec<DVec2> = (0..m)
                .map(|k| {
                    let t = core::f64::consts::TAU * (k as f64 + 0.3 * next()) / m as f64;
                    DVec2::new(libm::cos(t), libm::sin(t)) * (1.0 + 0.2 * next())
                })
                .collect();
            let normal = DVec2::new(next(), next()).normalize();
            let a = DVec2::new(next(), next());
            let tol = if case % 3 == 0 { 0.0 } else { 1e-3 };
            // Some vertices on the line, within the tolerance, or repeated.
            if case % 4 == 1 {
                let k = case % m;
                let off = normal.dot(poly[k] - a);
                poly[k] -= normal * off;
            }
            if case % 5 == 2 {
                let k = case % m;
                poly[(k + 1) % m] = poly[k];
            }
            let mut tmp = Vec::new();
            i1.clone_from(&poly);
            clip2(&mut i1, &mut tmp, (a, normal, tol), false);
            o1.clone_from(&poly);
            clip2(&mut o1, &mut tmp, (a, -normal, tol), false);
            split2(&poly, a, normal, tol, &mut i2, &mut o2);
            let bits = |v: &[DVec2]| {
                v.iter()
                    .map(|p| (p.x.to_bits(), p.y.to_bits()))
                    .collect::<Vec<_>>()
            };
            // Told that the polygon has no repeated vertex, when it has none: the same.
            if distinct_vertices(&poly) {
                let mut i3 = poly.clone();
                clip2(&mut i3, &mut tmp, (a, normal, tol), true);
                assert_eq!(bits(&i1), bits(&i3), "case {case}: distinct");
            }
            assert_eq!(bits(&i1), bits(&i2), "case {case}: inside");
            assert_eq!(bits(&o1), bits(&o2), "case {case}: outside");
            if i1.len() >= 3 && o1.len() >= 3 {
                cut += 1;
            }
        }
        // The line cut the polygon in a good share of the cases.
        assert!(cut > 200, "{cut}");
    }

    /// `cut` gives the bits of `split2`, except a part of at most two vertices that it may
    /// leave empty: on random convex polygons cut through, touched at one vertex or along
    /// one edge (every other vertex on one side), and wholly on one side.
    #[test]
    fn cut_is_split2() {
        let mut state = 0x1234_5678_9abc_def1_u64;
        let mut next = || crate::math::xorshift_unit(&mut state) - 0.5;
        let bits = |v: &[DVec2]| {
            v.iter()
                .map(|p| (p.x.to_bits(), p.y.to_bits()))
                .collect::<Vec<_>>()
        };
        let (mut inside, mut outside) = (Vec::new(), Vec::new());
        let (mut scratch, mut part) = (Vec::new(), Vec::new());
        let mut seen = [0; 3];
        for case in 0..4000 {
            let m = 3 + case % 6;
            let poly: Vec<DVec2> = (0..m)
                .map(|k| {
                    let t = core::f64::consts::TAU * (k as f64 + 0.3 * next()) / m as f64;
                    DVec2::new(libm::cos(t), libm::sin(t)) * (1.0 + 0.2 * next())
                })
                .collect();
            let tol = if case % 3 == 0 { 0.0 } else { 1e-3 };
            let (a, normal) = match case % 4 {
                // Through the polygon, or past it.
                0 => (
                    DVec2::new(2.0 * next(), 2.0 * next()),
                    DVec2::new(next(), next()).normalize(),
                ),
                // Touching one vertex, every other vertex on one side.
                1 => {
                    let normal = DVec2::new(next(), next()).normalize();
                    let low = poly
                        .iter()
                        .copied()
                        .min_by(|p, q| normal.dot(*p).total_cmp(&normal.dot(*q)))
                        .unwrap_or_default();
                    (low, if case % 8 == 1 { normal } else { -normal })
                }
                // Along one edge.
                _ => {
                    let k = case % m;
                    let (p, q) = (poly[k], poly[(k + 1) % m]);
                    let e = (q - p).normalize();
                    let inward = DVec2::new(-e.y, e.x);
                    (p, if case % 8 == 2 { inward } else { -inward })
                }
            };
            split2(&poly, a, normal, tol, &mut inside, &mut outside);
            let mut rest = poly.clone();
            // Random polygons have no repeated vertex: with and without the test.
            let how = cut(
                &mut rest,
                &mut scratch,
                &mut part,
                (a, normal, tol),
                case % 2 == 0,
            );
            assert!(distinct_vertices(&poly));
            match how {
                Cut::Inside => {
                    assert_eq!(bits(&rest), bits(&inside), "case {case}: inside");
                    assert!(part.is_empty() && outside.len() <= 2, "case {case}");
                    seen[0] += 1;
                }
                Cut::Outside => {
                    assert_eq!(bits(&part), bits(&outside), "case {case}: outside");
                    assert!(rest.is_empty() && inside.len() <= 2, "case {case}");
                    seen[1] += 1;
                }
                Cut::Both => {
                    assert_eq!(bits(&rest), bits(&inside), "case {case}: inside");
                    assert_eq!(bits(&part), bits(&outside), "case {case}: outside");
                    seen[2] += 1;
                }
            }
        }
        // Each way was taken often.
        assert!(seen.iter().all(|&n| n > 300), "{seen:?}");
    }
}
