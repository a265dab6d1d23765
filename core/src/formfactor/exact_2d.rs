//! Exact flatland form factors with occlusion.
//!
//! # Method
//!
//! Place the source patch `i` on the axis of a local frame, `x(t) = (t, 0)` for
//! `t ∈ [0, L_i]`, front side `h > 0`. From a point `x`, the point-to-patch form factor
//! (the flatland form of 2.16) is half the sine-measure of the directions in which `x` sees
//! the front of `j`:
//!
//! ```text
//! F_{x→j} = ½ Σ_k (sin φ_hi,k − sin φ_lo,k)
//! ```
//!
//! over the visible angular intervals `k`, with `φ` measured from the normal. Each interval
//! bound is the direction towards a *point* `p` — an endpoint of `j` or of an occluder — and
//! `sin φ = (p_t − t)/|p − x(t)|`, whose integral along the patch is exact:
//!
//! ```text
//! ∫_{t0}^{t1} (p_t − t)/|p − x(t)| dt = |p − x(t0)| − |p − x(t1)|
//! ```
//!
//! which is where the crossed-strings rule comes from. The *which points bound which
//! intervals* structure only changes where `x(t)` is collinear with two such points (a
//! visibility event), so the method
//!
//! 1. clips `j` and every occluder that can block sight lines (those meeting the convex hull
//!    of `i ∪ j`) to the front half-plane of `i`, splitting an occluder where it crosses `j`;
//! 2. collects the events: the points `t*` where the line through two of those points
//!    crosses `i`, kept when the common direction falls inside `j`'s angular range;
//! 3. between consecutive events, finds the visible intervals at the midpoint and integrates
//!    each bound in closed form with the formula above.
//!
//! With no occluder this *is* the crossed-strings rule `L_i F_ij = ½(crossed − uncrossed)`.
//! The result is exact up to rounding: each sub-interval adds a few ulps of
//! `max |p − x|` (about 1e-15 relative), and an event located with error `δ` moves the
//! integral by at most `δ/2` because `F_{x→j}` is continuous in `x`. Tests check rows of
//! closed scenes sum to 1 within 1e-12 and agree with independent adaptive quadrature of
//! `F_{x→j}` within 1e-10.
//!
//! Cost per pair is `O(m + e·k log k)` for `m` surfaces, `k` relevant occluders and `e`
//! events; the whole matrix is computed once per unordered pair, integrating over the
//! shorter patch of the two (which keeps digits when it is tiny and far from the other),
//! and filled by reciprocity, `F_ji = L_i F_ij / L_j` (2.21).

use crate::geom::{DVec2, Segment, cross, distance};
use crate::math;

#[cfg(feature = "alloc")]
use crate::error::{ErrorKind, Result};
#[cfg(feature = "alloc")]
use crate::formfactor::FormFactors;
#[cfg(feature = "alloc")]
use crate::scene::Scene2;
#[cfg(feature = "alloc")]
use alloc::vec::Vec;

/// Largest patch count for which [`form_factors`] builds the dense `n × n` matrix
/// (10 000² doubles = 800 MB). Larger scenes need the Monte Carlo sparse estimators.
pub(crate) const MAX_DENSE_PATCHES: usize = 10_000;

/// Extent-to-smallest-feature ratio (the scene's extent over its shortest patch or the
/// closest approach of a surface's end to another surface) up to which the exact flatland form
/// factors are guaranteed to close (rows sum to one within 1e-9): each sine integral carries
/// a few ulps of the distances involved, up to the scene's extent, relative to the source
/// patch's length. Tested at 10⁷ (`tests::extreme_aspect_sliver_rows_sum_to_one`) and on
/// rooms of aspect 10⁸ (`tests/extremes.rs`). Beyond it [`form_factors`] may refuse with
/// [`ErrorKind::PrecisionLoss`] rather than return rows that overflow.
pub const RESOLVED_RANGE: f64 = 1e6;

/// Relative tolerance (about 500 ulps) under which a point counts as lying on a supporting
/// line: coincident surfaces built from different endpoints differ by a few ulps.
const ON_LINE: f64 = 1e-13;

/// A patch's local frame: `origin` = its start, `u` = unit tangent, `n` = unit normal, and
/// `eps` = the distance below which a point counts as lying on the axis.
#[derive(Clone, Copy, Debug)]
struct Frame {
    origin: DVec2,
    u: DVec2,
    n: DVec2,
    eps: f64,
}

impl Frame {
    fn of(seg: &Segment) -> Self {
        let u = seg.tangent();
        Self::new(seg.a, u, seg.length())
    }

    /// Frame at `origin` with unit tangent `u`; `len` is the source's extent along `u`.
    fn new(origin: DVec2, u: DVec2, len: f64) -> Self {
        // Coordinates carry rounding of a few ulps of their magnitude, so "on the axis" is
        // judged relative to the frame's position and size, not to the point's distance.
        let eps = ON_LINE * (origin.x.abs().max(origin.y.abs()) + len);
        Self {
            origin,
            u,
            n: DVec2::new(-u.y, u.x),
            eps,
        }
    }

    /// Local coordinates `(t, h)` of a world point.
    fn local(&self, p: DVec2) -> DVec2 {
        let d = p - self.origin;
        DVec2::new(d.dot(self.u), d.dot(self.n))
    }

    /// Whether local point `v` lies on the axis to within rounding.
    fn on_axis(&self, v: DVec2) -> bool {
        v.y.abs() <= self.eps + ON_LINE * math::length(v)
    }
}

/// Clips the local segment `p q` to the closed front half-plane `h ≥ 0` of `frame`,
/// snapping points within rounding of the axis onto it. `None` if nothing with `h > 0`
/// remains.
fn clip_front(frame: &Frame, p: DVec2, q: DVec2) -> Option<(DVec2, DVec2)> {
    let snap = |v: DVec2| -> DVec2 {
        if frame.on_axis(v) {
            DVec2::new(v.x, 0.0)
        } else {
            v
        }
    };
    let (p, q) = (snap(p), snap(q));
    match (p.y > 0.0, q.y > 0.0) {
        (false, false) => None,
        (true, true) => Some((p, q)),
        (true, false) | (false, true) => {
            if p.y == 0.0 || q.y == 0.0 {
                return Some((p, q));
            }
            // One endpoint strictly behind: cut at h = 0.
            let s = p.y / (p.y - q.y);
            let c = DVec2::new(p.x + s * (q.x - p.x), 0.0);
            if p.y > 0.0 {
                Some((p, c))
            } else {
                Some((c, q))
            }
        }
    }
}

/// Whether two segments lie on one line, to within rounding: the shorter one's endpoints
/// are tested against the longer one's supporting line, whose direction its rounded
/// endpoints give far better (a segment 1e-4 long has a direction good to ~1e-12 only,
/// enough to lift a collinear neighbour 2 units away off its axis by 5e-12 and make it
/// "seen" at grazing distance; `fuzz_refine` found that). Segments on one line exchange no
/// light and hide nothing from each other.
fn collinear(p: Segment, q: Segment) -> bool {
    let (long, short) = if p.length() >= q.length() {
        (p, q)
    } else {
        (q, p)
    };
    let len = long.length();
    if !(len > 0.0) {
        return false;
    }
    let scale = long.a.abs().max_element().max(long.b.abs().max_element()) + len;
    let tolerance = ON_LINE * scale * len;
    let d = long.b - long.a;
    cross(d, short.a - long.a).abs() <= tolerance && cross(d, short.b - long.a).abs() <= tolerance
}

/// Direction angle of `p` seen from `(t, 0)`, measured from the normal towards the tangent:
/// `ψ = atan2(p_t − t, p_h) ∈ [−π/2, π/2]` for `p_h ≥ 0`.
#[inline]
fn angle(p: DVec2, t: f64) -> f64 {
    math::atan2(p.x - t, p.y)
}

/// `|p − (t, 0)|`.
#[inline]
fn dist(p: DVec2, t: f64) -> f64 {
    math::hypot(p.x - t, p.y)
}

/// `∫_{t0}^{t1} sin φ_p(t) dt = |p − x(t0)| − |p − x(t1)|`, evaluated without cancellation:
///
/// ```text
/// d0 − d1 = (d0² − d1²) / (d0 + d1) = (t1 − t0) ((p_t − t0) + (p_t − t1)) / (d0 + d1)
/// ```
///
/// The plain difference of two distances loses `log10(d / (t1 − t0))` digits when the
/// point is far from a short interval (a patch 2.5e-4 long seen from 2.5e3 away lost 7 of
/// them and rows summed to `1 + 3.6e-9`, found by `fuzz_flat_pipeline`); the product form
/// keeps a few ulps relative error whatever the ratio.
#[inline]
fn sine_integral(p: DVec2, t0: f64, t1: f64) -> f64 {
    let sum = dist(p, t0) + dist(p, t1);
    if sum > 0.0 {
        (t1 - t0) * ((p.x - t0) + (p.x - t1)) / sum
    } else {
        0.0
    }
}

impl Segment {
    /// Unoccluded flux `L_i F_ij` between two segments that see each other (or partly, where
    /// they cross each other's supporting lines), without allocating: the crossed-strings rule
    /// generalised to one-sided segments. `F_ij = flux / L_i`, `F_ji = flux / L_j`.
    ///
    /// ```text
    /// L_i F_ij = ½ (|a_i a_j| + |b_i b_j| − |a_i b_j| − |b_i a_j|)     (fully facing)
    /// ```
    ///
    /// Returns 0 when they do not face each other.
    #[must_use]
    pub fn unoccluded_flux(i: Segment, j: Segment) -> f64 {
        let len_i = i.length();
        if !(len_i > 0.0) || !(j.length() > 0.0) || collinear(i, j) {
            return 0.0;
        }
        let frame = Frame::of(&i);
        let Some((p0, p1)) = clip_front(&frame, frame.local(j.a), frame.local(j.b)) else {
            return 0.0;
        };
        let ja = frame.local(j.a);
        let jb = frame.local(j.b);
        // The one possible event: where j's supporting line crosses i.
        let mut cuts = [0.0, len_i, len_i];
        let mut n_cuts = 2;
        if let Some(t) = line_crossing_axis(p0, p1)
            && t > 0.0
            && t < len_i
        {
            cuts = [0.0, t, len_i];
            n_cuts = 3;
        }
        let mut flux = 0.0;
        for w in cuts[..n_cuts].windows(2) {
            let (t0, t1) = (w[0], w[1]);
            let tm = 0.5 * (t0 + t1);
            if cross(jb - ja, DVec2::new(tm, 0.0) - ja) <= 0.0 {
                continue; // j shows its back here
            }
            let (lo, hi) = if angle(p0, tm) <= angle(p1, tm) {
                (p0, p1)
            } else {
                (p1, p0)
            };
            flux += sine_integral(hi, t0, t1) - sine_integral(lo, t0, t1);
        }
        (0.5 * flux).max(0.0)
    }
}

/// Where the line through local points `p`, `q` crosses the axis `h = 0`, if not parallel.
#[inline]
fn line_crossing_axis(p: DVec2, q: DVec2) -> Option<f64> {
    let dh = p.y - q.y;
    if dh == 0.0 {
        return None;
    }
    let s = p.y / dh;
    let t = p.x + s * (q.x - p.x);
    t.is_finite().then_some(t)
}

impl Segment {
    /// Point-to-segment form factor `F_{x→j}` without occlusion (flatland form of 2.16): half
    /// the difference of the sines of the angles, from the normal `normal` at `x`, under which
    /// the front of `j` is seen.
    ///
    /// ```text
    /// F_{x→j} = ½ (sin φ_hi − sin φ_lo)
    /// ```
    #[must_use]
    pub fn point_to_segment_unoccluded(x: DVec2, normal: DVec2, j: Segment) -> f64 {
        let n = normal.normalize_or_zero();
        if n == DVec2::ZERO || j.side(x) <= 0.0 {
            return 0.0;
        }
        let frame = Frame::new(x, DVec2::new(n.y, -n.x), 0.0);
        let Some((p0, p1)) = clip_front(&frame, frame.local(j.a), frame.local(j.b)) else {
            return 0.0;
        };
        let s = |p: DVec2| p.x / math::hypot(p.x, p.y);
        (0.5 * (s(p0) - s(p1)).abs()).min(1.0)
    }
}

// ---------------------------------------------------------------------------------------
// With occlusion (needs scratch space)
// ---------------------------------------------------------------------------------------

/// One endpoint-bounded angular interval: directions from `lo` to `hi`.
#[cfg(feature = "alloc")]
#[derive(Clone, Copy, Debug)]
struct Bound {
    angle: f64,
    point: DVec2,
}

/// Reusable buffers of the occluded computation.
#[cfg(feature = "alloc")]
#[derive(Debug, Default)]
struct Scratch {
    occluders: Vec<(DVec2, DVec2)>,
    points: Vec<DVec2>,
    /// Occluders with an end outside the sight region (see `occluded_flux`, step 2).
    edge_on: Vec<(DVec2, DVec2)>,
    /// Per occluder, whether each end is where it crosses the target (step 1): a point of
    /// `j`, so of the sight region, whatever rounding did to it.
    on_target: Vec<[bool; 2]>,
    events: Vec<f64>,
    shadows: Vec<(Bound, Bound)>,
    visible: Vec<(DVec2, DVec2)>,
}

/// Visible intervals of target `(j0, j1)` (local, clipped; `ja jb` its full oriented
/// segment for the facing test) from `x = (t, 0)`, as `(lo point, hi point)` pairs.
#[cfg(feature = "alloc")]
fn visible_intervals(
    t: f64,
    target: (DVec2, DVec2),
    facing: (DVec2, DVec2),
    occluders: &[(DVec2, DVec2)],
    shadows: &mut Vec<(Bound, Bound)>,
    out: &mut Vec<(DVec2, DVec2)>,
) {
    out.clear();
    let x = DVec2::new(t, 0.0);
    let (ja, jb) = facing;
    if cross(jb - ja, x - ja) <= 0.0 {
        return; // j shows its back to x
    }
    let (a0, a1) = (angle(target.0, t), angle(target.1, t));
    let (lo, hi) = if a0 <= a1 {
        (
            Bound {
                angle: a0,
                point: target.0,
            },
            Bound {
                angle: a1,
                point: target.1,
            },
        )
    } else {
        (
            Bound {
                angle: a1,
                point: target.1,
            },
            Bound {
                angle: a0,
                point: target.0,
            },
        )
    };
    if !(hi.angle > lo.angle) {
        return;
    }
    // Shadows: the parts of j's angular range where an occluder is nearer than j.
    shadows.clear();
    for &(q0, q1) in occluders {
        let (b0, b1) = (angle(q0, t), angle(q1, t));
        let (klo, khi) = if b0 <= b1 {
            (
                Bound {
                    angle: b0,
                    point: q0,
                },
                Bound {
                    angle: b1,
                    point: q1,
                },
            )
        } else {
            (
                Bound {
                    angle: b1,
                    point: q1,
                },
                Bound {
                    angle: b0,
                    point: q0,
                },
            )
        };
        let s_lo = if klo.angle > lo.angle { klo } else { lo };
        let s_hi = if khi.angle < hi.angle { khi } else { hi };
        if !(s_hi.angle > s_lo.angle) {
            continue;
        }
        // Compare depths along the middle direction of the overlap. The two segments do not
        // cross (occluders were split at j), so the order holds over the whole overlap.
        let mid = 0.5 * (s_lo.angle + s_hi.angle);
        let d = DVec2::new(math::sin(mid), math::cos(mid));
        // j's full segment gives its line accurately even when the clipped piece is a sliver.
        let r_j = ray_line_distance(x, d, ja, jb);
        let r_k = ray_line_distance(x, d, q0, q1);
        // A ray (nearly) parallel to the occluder meets its line nowhere or behind x: no
        // shadow, whatever rounding made of the overlap.
        if r_k.is_finite() && r_k > 0.0 && r_k < r_j {
            shadows.push((s_lo, s_hi));
        }
    }
    shadows.sort_unstable_by(|a, b| a.0.angle.total_cmp(&b.0.angle));
    // Sweep: j's range minus the union of shadows.
    let mut cur = lo;
    for &(s_lo, s_hi) in shadows.iter() {
        if s_lo.angle > cur.angle {
            out.push((cur.point, s_lo.point));
        }
        if s_hi.angle > cur.angle {
            cur = s_hi;
        }
    }
    if hi.angle > cur.angle {
        out.push((cur.point, hi.point));
    }
}

/// Distance along the ray `x + r d` to the line through `p`, `q` (∞ if parallel).
#[cfg(feature = "alloc")]
#[inline]
fn ray_line_distance(x: DVec2, d: DVec2, p: DVec2, q: DVec2) -> f64 {
    let e = q - p;
    let denom = cross(d, e);
    if denom == 0.0 {
        return f64::INFINITY;
    }
    cross(p - x, e) / denom
}

/// Whether local point `p` lies in the closed convex quadrilateral hull of the source axis
/// `[0, len]` and the target `(j0, j1)` — the only region whose points can bound a visible
/// interval of `j` seen from `i`.
#[cfg(feature = "alloc")]
fn in_sight_region(p: DVec2, len: f64, j0: DVec2, j1: DVec2) -> bool {
    let pts = [DVec2::ZERO, DVec2::new(len, 0.0), j0, j1];
    // p is in the hull of 4 points iff it is in one of the triangles they span.
    let tri = |a: DVec2, b: DVec2, c: DVec2| -> bool {
        let s = cross(b - a, c - a);
        let edge = math::length(b - a).max(math::length(c - a));
        let tol = ON_LINE * edge * edge;
        if s.abs() <= tol {
            return false;
        }
        let d1 = cross(b - a, p - a) * s.signum();
        let d2 = cross(c - b, p - b) * s.signum();
        let d3 = cross(a - c, p - c) * s.signum();
        let eps = -tol;
        d1 >= eps && d2 >= eps && d3 >= eps
    };
    tri(pts[0], pts[1], pts[2])
        || tri(pts[0], pts[1], pts[3])
        || tri(pts[0], pts[2], pts[3])
        || tri(pts[1], pts[2], pts[3])
}

/// The visibility event of local points `p`, `q`: where the line through them crosses the
/// open source axis `(0, len)`, kept only if their common direction from there lies within
/// the target `(j0, j1)`'s angular range (elsewhere it bounds nothing that is integrated).
#[cfg(feature = "alloc")]
fn event_in_target_range(p: DVec2, q: DVec2, len: f64, j0: DVec2, j1: DVec2) -> Option<f64> {
    let t = line_crossing_axis(p, q)?;
    if !(t > 0.0 && t < len) {
        return None;
    }
    let x = DVec2::new(t, 0.0);
    let v = if p.y > 0.0 { p - x } else { q - x };
    let (v0, v1) = (j0 - x, j1 - x);
    let s = cross(v0, v1);
    let tol = ON_LINE * math::length(v) * math::length(v0).max(math::length(v1));
    let inside = if s >= 0.0 {
        cross(v0, v) >= -tol && cross(v, v1) >= -tol
    } else {
        cross(v0, v) <= tol && cross(v, v1) <= tol
    };
    inside.then_some(t)
}

/// Flux `L_i F_ij` between patch segments `i` and `j` with the given candidate occluders
/// (world coordinates; those not meeting the sight region are ignored).
#[cfg(feature = "alloc")]
fn occluded_flux<'a>(
    i: Segment,
    j: Segment,
    occluders: impl Iterator<Item = &'a Segment>,
    scratch: &mut Scratch,
) -> f64 {
    let len_i = i.length();
    if collinear(i, j) {
        return 0.0;
    }
    let frame = Frame::of(&i);
    let (ja, jb) = (frame.local(j.a), frame.local(j.b));
    let Some((j0, j1)) = clip_front(&frame, ja, jb) else {
        return 0.0;
    };
    // Quick reject: j faces away from the whole of i.
    if cross(jb - ja, -ja) <= 0.0 && cross(jb - ja, DVec2::new(len_i, 0.0) - ja) <= 0.0 {
        return 0.0;
    }
    let hull_world = [i.a, i.b, frame.origin + frame.u * j0.x + frame.n * j0.y, {
        frame.origin + frame.u * j1.x + frame.n * j1.y
    }];

    // 1. Relevant occluders, clipped to the front and split where they cross j.
    scratch.occluders.clear();
    scratch.on_target.clear();
    let (hlo, hhi) = hull_world.iter().fold(
        (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    for occ in occluders {
        let (olo, ohi) = occ.bounds();
        if ohi.x < hlo.x || ohi.y < hlo.y || olo.x > hhi.x || olo.y > hhi.y {
            continue;
        }
        // Collinear with i or with j: it hides nothing (on j's line it is at j's own
        // depth). Judged in world coordinates, the shorter segment against the longer one's
        // line: in i's frame a short i tilts every far point by its direction's rounding,
        // and snapping onto i's axis moves the occluder's ends (`fuzz_refine` found a wall
        // coincident with a 0.016-long j, seen from a 0.0006-long i, taken off j's line by
        // 2.5e-15 and hiding all of j: `L_i F_ij` 0 against 1.85e-9 the other way).
        if !crate::geom::segment_may_meet_hull(occ.a, occ.b, &hull_world, 0.0)
            || collinear(i, *occ)
            || collinear(j, *occ)
        {
            continue;
        }
        let Some((q0, q1)) = clip_front(&frame, frame.local(occ.a), frame.local(occ.b)) else {
            continue;
        };
        match crate::geom::proper_crossing(q0, q1, j0, j1) {
            Some((_, c)) => {
                scratch.occluders.push((q0, c));
                scratch.occluders.push((c, q1));
                scratch.on_target.push([false, true]);
                scratch.on_target.push([true, false]);
            }
            None => {
                scratch.occluders.push((q0, q1));
                scratch.on_target.push([false, false]);
            }
        }
    }
    if scratch.occluders.is_empty() {
        return Segment::unoccluded_flux(i, j);
    }

    // 2. Events: lines through two candidate points crossing the open patch, and lines of
    //    occluders with an end outside the sight region (their edge-on positions).
    scratch.points.clear();
    scratch.points.push(j0);
    scratch.points.push(j1);
    scratch.edge_on.clear();
    // A crossing with j is a candidate however far its occluder reaches: computed from a
    // long occluder's far end, it can sit off j's line by more than the region test's
    // tolerance, which is relative to the region's size (`fuzz_refine` found one from a
    // 22,222-long side 2.8e-12 off a 29-long target; without it the event where the
    // crossing and a wall's end line up was missed, and a sub-interval was integrated with
    // the wrong visible interval: a flux 0.27 % low).
    for (&(q0, q1), on_target) in scratch.occluders.iter().zip(&scratch.on_target) {
        let mut both = true;
        for (q, on_j) in [(q0, on_target[0]), (q1, on_target[1])] {
            if on_j || in_sight_region(q, len_i, j0, j1) {
                scratch.points.push(q);
            } else {
                both = false;
            }
        }
        if !both {
            scratch.edge_on.push((q0, q1));
        }
    }
    scratch.events.clear();
    scratch.events.push(0.0);
    scratch.events.push(len_i);
    let pts = &scratch.points;
    for (a, &p) in pts.iter().enumerate() {
        for &q in &pts[a + 1..] {
            if let Some(t) = event_in_target_range(p, q, len_i, j0, j1) {
                scratch.events.push(t);
            }
        }
    }
    // Where an occluder is seen edge-on (its own line crosses the patch), its angular span
    // shrinks to nothing and flips, and the depth test of `visible_intervals` along that
    // span's middle direction runs parallel to the occluder. With both ends candidates the
    // pair above gives this event; with an end outside the sight region nothing did, and a
    // sub-interval's midpoint could fall on the edge-on position, where a shadow of zero
    // width but with far-apart bounding points was integrated over the whole sub-interval
    // (fuzz_refine, tests/data/fuzz/fuzz_refine/ci_session5_split_crash.bin).
    for &(q0, q1) in &scratch.edge_on {
        if let Some(t) = event_in_target_range(q0, q1, len_i, j0, j1) {
            scratch.events.push(t);
        }
    }
    scratch.events.sort_unstable_by(f64::total_cmp);
    let min_gap = 1e-14 * len_i;
    scratch.events.dedup_by(|b, a| *b - *a <= min_gap);

    // 3. Integrate each sub-interval in closed form.
    let mut flux = math::KahanSum::new();
    let Scratch {
        occluders,
        events,
        shadows,
        visible,
        ..
    } = scratch;
    for w in events.windows(2) {
        let (t0, t1) = (w[0], w[1]);
        if !(t1 > t0) {
            continue;
        }
        visible_intervals(
            0.5 * (t0 + t1),
            (j0, j1),
            (ja, jb),
            occluders,
            shadows,
            visible,
        );
        for &(lo, hi) in visible.iter() {
            flux.add(sine_integral(hi, t0, t1) - sine_integral(lo, t0, t1));
        }
    }
    (0.5 * flux.total()).max(0.0)
}

#[cfg(feature = "alloc")]
impl Scene2 {
    /// The flux `L_i F_ij` from patch `i` to patch `j`, integrated over the source patch `i`
    /// with occlusion by every other surface. [`form_factors`] computes each unordered pair once
    /// and fills both directions by reciprocity; this function lets a caller (or a test) compute
    /// `L_j F_ji` independently by integrating over `j` instead.
    ///
    /// # Errors
    /// [`ErrorKind::PatchIndex`] if `i` or `j` is out of range.
    #[cfg(feature = "alloc")]
    pub fn pair_flux(&self, i: usize, j: usize) -> Result<f64> {
        let scene = self;
        let n = scene.n_patches();
        let (Some(pi), Some(pj)) = (scene.patches().get(i), scene.patches().get(j)) else {
            return Err(ErrorKind::PatchIndex {
                index: i.max(j),
                len: n,
            }
            .into());
        };
        if pi.surface == pj.surface {
            return Ok(0.0);
        }
        let occ = scene
            .surfaces()
            .iter()
            .enumerate()
            .filter(|&(k, _)| k != pi.surface && k != pj.surface)
            .map(|(_, s)| &s.segment);
        Ok(occluded_flux(
            pi.segment,
            pj.segment,
            occ,
            &mut Scratch::default(),
        ))
    }
}

#[cfg(feature = "alloc")]
impl Scene2 {
    /// Point-to-patch form factor `F_{x→j}` (flatland form of 2.16) with occlusion by every
    /// other surface of the scene: `x` is a point with front normal `normal`, `j` a patch index.
    ///
    /// # Errors
    /// [`ErrorKind::PatchIndex`] if `j` is out of range.
    #[cfg(feature = "alloc")]
    pub fn point_to_patch(&self, x: DVec2, normal: DVec2, j: usize) -> Result<f64> {
        let scene = self;
        let patch = scene.patches().get(j).ok_or(ErrorKind::PatchIndex {
            index: j,
            len: scene.n_patches(),
        })?;
        let n = normal.normalize_or_zero();
        if n == DVec2::ZERO {
            return Ok(0.0);
        }
        let frame = Frame::new(x, DVec2::new(n.y, -n.x), 0.0);
        let (ja, jb) = (frame.local(patch.segment.a), frame.local(patch.segment.b));
        let Some((j0, j1)) = clip_front(&frame, ja, jb) else {
            return Ok(0.0);
        };
        let mut occluders = Vec::new();
        for (k, s) in scene.surfaces().iter().enumerate() {
            // On j's line, at j's own depth: it cannot hide j (judged as in `occluded_flux`)
            if k == patch.surface || collinear(patch.segment, s.segment) {
                continue;
            }
            let Some((q0, q1)) =
                clip_front(&frame, frame.local(s.segment.a), frame.local(s.segment.b))
            else {
                continue;
            };
            match crate::geom::proper_crossing(q0, q1, j0, j1) {
                Some((_, c)) => {
                    occluders.push((q0, c));
                    occluders.push((c, q1));
                }
                None => occluders.push((q0, q1)),
            }
        }
        let mut shadows = Vec::new();
        let mut visible = Vec::new();
        visible_intervals(
            0.0,
            (j0, j1),
            (ja, jb),
            &occluders,
            &mut shadows,
            &mut visible,
        );
        let s = |p: DVec2| p.x / math::hypot(p.x, p.y);
        let f: f64 = visible.iter().map(|&(lo, hi)| 0.5 * (s(hi) - s(lo))).sum();
        Ok(f.clamp(0.0, 1.0))
    }
}

/// The exact form-factor matrix of a flatland scene (2.20), with occlusion by every surface,
/// plus a background state if the scene is open (see [`FormFactors`]).
///
/// # Errors
/// [`ErrorKind::TooLarge`] above `MAX_DENSE_PATCHES` patches; [`ErrorKind::PrecisionLoss`]
/// when a row sums above one beyond rounding, which only a scene spanning more than
/// [`RESOLVED_RANGE`] times its smallest feature can cause.
#[cfg(feature = "alloc")]
pub fn form_factors(scene: &Scene2) -> Result<FormFactors> {
    let n = scene.n_patches();
    if n > MAX_DENSE_PATCHES {
        return Err(ErrorKind::TooLarge {
            what: "patch count for exact form factors",
            max: MAX_DENSE_PATCHES as u64,
        }
        .into());
    }
    let mut f = alloc::vec![0.0; n * n];
    form_factors_into(scene, &mut f)?;
    let lengths: Vec<f64> = scene.patches().iter().map(|p| p.length).collect();
    check_closure(scene, &lengths, &f)?;
    FormFactors::from_patch_matrix(&lengths, f)
}

/// Refuses rows that sum above one by more than the channel accepts
/// ([`crate::channel::ROW_SUM_TOLERANCE`]) with [`ErrorKind::PrecisionLoss`], which says
/// why, rather than leaving the channel to refuse them without a reason.
#[cfg(feature = "alloc")]
fn check_closure(scene: &Scene2, lengths: &[f64], f: &[f64]) -> Result<()> {
    let n = lengths.len();
    for (patch, row) in f.chunks_exact(n.max(1)).enumerate() {
        let sum = math::sum(row.iter().copied());
        if sum > 1.0 + crate::channel::ROW_SUM_TOLERANCE {
            return Err(ErrorKind::PrecisionLoss {
                patch,
                sum,
                range: scene.feature_range(),
                guaranteed: RESOLVED_RANGE,
            }
            .into());
        }
    }
    Ok(())
}

#[cfg(feature = "alloc")]
impl Scene2 {
    /// The scene's extent (bounding-box diagonal) over its smallest feature: the shortest patch,
    /// or the closest approach of a surface's end to another surface it does not end on (a
    /// vertex a hair's breadth from a long wall is a feature as small as that gap, whatever the
    /// patch lengths). Ends that touch another surface exactly are joints, not features.
    /// Up to [`RESOLVED_RANGE`], [`form_factors`] guarantees rows that close within 1e-9 and
    /// reciprocal fluxes; beyond it, rounding may move a row by more (rows that sum above one are
    /// refused with [`ErrorKind::PrecisionLoss`], rows that fall short read as an open scene).
    /// Costs `O(surfaces²)`.
    #[cfg(feature = "alloc")]
    #[must_use]
    pub fn feature_range(&self) -> f64 {
        let scene = self;
        let (lo, hi) = scene.bounds();
        let mut smallest = scene
            .patches()
            .iter()
            .fold(f64::INFINITY, |m, p| m.min(p.length));
        let surfaces = scene.surfaces();
        for (k, s) in surfaces.iter().enumerate() {
            for end in [s.segment.a, s.segment.b] {
                for (m, other) in surfaces.iter().enumerate() {
                    let o = other.segment;
                    if m == k || end == o.a || end == o.b {
                        continue;
                    }
                    let gap = o.distance_to(end);
                    if gap > 0.0 {
                        smallest = smallest.min(gap);
                    }
                }
            }
        }
        math::length(hi - lo) / smallest
    }
}

/// Writes the exact `n × n` patch form factors (no background state) row-major into `out`.
///
/// # Errors
/// [`ErrorKind::BufferTooSmall`] if `out.len() < n²`.
#[cfg(feature = "alloc")]
pub(crate) fn form_factors_into(scene: &Scene2, out: &mut [f64]) -> Result<()> {
    let n = scene.n_patches();
    let needed = n.saturating_mul(n);
    if out.len() < needed {
        return Err(ErrorKind::BufferTooSmall {
            needed,
            found: out.len(),
        }
        .into());
    }
    let patches = scene.patches();
    let surfaces: Vec<Segment> = scene.surfaces().iter().map(|s| s.segment).collect();
    let mut scratch = Scratch::default();
    for i in 0..n {
        out[i * n + i] = 0.0;
        for j in i + 1..n {
            let (pi, pj) = (&patches[i], &patches[j]);
            let flux = if pi.surface == pj.surface {
                0.0 // collinear pieces of one surface
            } else {
                let occ = surfaces
                    .iter()
                    .enumerate()
                    .filter(|&(k, _)| k != pi.surface && k != pj.surface)
                    .map(|(_, s)| s);
                // Integrate over the shorter patch: the flux is the same either way (2.21),
                // but over the longer one it is a difference of sine integrals of size
                // L_long, which for a short far target loses digits relative to L_short.
                let (source, target) = if pj.length < pi.length {
                    (pj.segment, pi.segment)
                } else {
                    (pi.segment, pj.segment)
                };
                occluded_flux(source, target, occ, &mut scratch)
            };
            // Reciprocity (2.21): one flux, two form factors.
            out[i * n + j] = (flux / pi.length).min(1.0);
            out[j * n + i] = (flux / pj.length).min(1.0);
        }
    }
    Ok(())
}

impl Segment {
    /// `½ (|a_i a_j| + |b_i b_j| − |a_i b_j| − |b_i a_j|)`: Hottel's crossed-strings flux for
    /// two segments that face each other completely (each wholly in front of the other). Facing
    /// segments run in opposite senses, so the "crossed" strings join `a_i` to `a_j` and `b_i`
    /// to `b_j`. Given for reference and tests; [`Segment::unoccluded_flux`] handles every configuration.
    #[must_use]
    pub fn crossed_strings(i: Segment, j: Segment) -> f64 {
        0.5 * (distance(i.a, j.a) + distance(i.b, j.b) - distance(i.a, j.b) - distance(i.b, j.a))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seg(ax: f64, ay: f64, bx: f64, by: f64) -> Segment {
        Segment::new(DVec2::new(ax, ay), DVec2::new(bx, by))
    }

    #[test]
    fn parallel_facing_unit_segments() {
        // Bottom faces up, top (reversed) faces down; distance 1. Crossed strings: √2 − 1.
        let i = seg(0.0, 0.0, 1.0, 0.0);
        let j = seg(1.0, 1.0, 0.0, 1.0);
        let f = Segment::unoccluded_flux(i, j);
        assert!((f - (2f64.sqrt() - 1.0)).abs() < 1e-15, "{f}");
        assert!((Segment::crossed_strings(i, j) - f).abs() < 1e-15);
        // Seen from behind: nothing.
        assert_eq!(Segment::unoccluded_flux(i, j.reversed()), 0.0);
    }

    #[test]
    fn perpendicular_corner() {
        // Two unit sides meeting at a right angle: F = (1 + 1 − √2)/2.
        let i = seg(0.0, 0.0, 1.0, 0.0);
        let j = seg(1.0, 0.0, 1.0, 1.0);
        let f = Segment::unoccluded_flux(i, j);
        assert!((f - (2.0 - 2f64.sqrt()) / 2.0).abs() < 1e-15, "{f}");
    }

    #[test]
    fn point_to_segment_matches_sines() {
        // From the origin facing +y, a segment spanning 45° either side: ½(sin45 + sin45).
        let f =
            Segment::point_to_segment_unoccluded(DVec2::ZERO, DVec2::Y, seg(1.0, 1.0, -1.0, 1.0));
        assert!((f - 0.5f64.sqrt()).abs() < 1e-15);
    }

    #[cfg(feature = "alloc")]
    #[test]
    fn half_blocking_occluder() {
        // i = [0,1]×{0} facing up, j = [0,1]×{2} facing down, a two-sided blocker covering
        // x ∈ [−10, 0.5] at height 1. Compare with adaptive quadrature of F_{x→j}.
        let mut b = Scene2::builder();
        b.segment(DVec2::new(0.0, 0.0), DVec2::new(1.0, 0.0), 1)
            .unwrap();
        b.segment(DVec2::new(1.0, 2.0), DVec2::new(0.0, 2.0), 1)
            .unwrap();
        b.segment(DVec2::new(-10.0, 1.0), DVec2::new(0.5, 1.0), 1)
            .unwrap();
        let scene = b.build().unwrap();
        let ff = form_factors(&scene).unwrap();
        let reference = quadrature(&scene, 0, 1);
        assert!(
            (ff.get(0, 1) - reference).abs() < 1e-10,
            "{} vs {reference}",
            ff.get(0, 1)
        );
        assert!(
            ff.get(0, 1) > 0.0
                && ff.get(0, 1)
                    < Segment::unoccluded_flux(
                        scene.patches()[0].segment,
                        scene.patches()[1].segment
                    )
        );
    }

    /// Adaptive Simpson quadrature of `F_{x→j}` over patch `i` (an independent check).
    #[cfg(feature = "alloc")]
    fn quadrature(scene: &Scene2, i: usize, j: usize) -> f64 {
        let p = scene.patches()[i].segment;
        let n = p.normal();
        let g = |t: f64| scene.point_to_patch(p.point_at(t), n, j).unwrap();
        fn simpson(
            g: &dyn Fn(f64) -> f64,
            a: f64,
            b: f64,
            fa: f64,
            fm: f64,
            fb: f64,
            depth: u32,
        ) -> f64 {
            let m = 0.5 * (a + b);
            let (lm, rm) = (0.5 * (a + m), 0.5 * (m + b));
            let (flm, frm) = (g(lm), g(rm));
            let whole = (b - a) / 6.0 * (fa + 4.0 * fm + fb);
            let left = (m - a) / 6.0 * (fa + 4.0 * flm + fm);
            let right = (b - m) / 6.0 * (fm + 4.0 * frm + fb);
            if depth == 0 || (left + right - whole).abs() < 1e-14 {
                return left + right + (left + right - whole) / 15.0;
            }
            simpson(g, a, m, fa, flm, fm, depth - 1) + simpson(g, m, b, fm, frm, fb, depth - 1)
        }
        let (fa, fm, fb) = (g(1e-12), g(0.5), g(1.0 - 1e-12));
        simpson(&g, 1e-12, 1.0 - 1e-12, fa, fm, fb, 40)
    }

    /// A short piece of a wall and a long wall on the same line, back to back (a polygon
    /// whose vertex lies on one of its own edges): no light passes between them, however
    /// badly the short piece's rounded endpoints give its direction (`fuzz_refine` found
    /// the piece "seeing" all of the other wall, `F = 1`).
    #[cfg(feature = "alloc")]
    #[test]
    fn collinear_back_to_back_segments_exchange_nothing() {
        let wall = seg(2.0, 1.0, 0.0, 2.0);
        let piece = seg(0.0, 2.0, 9.472977730894943e-5, 1.9999526351113455);
        assert_eq!(Segment::unoccluded_flux(piece, wall), 0.0);
        assert_eq!(Segment::unoccluded_flux(wall, piece), 0.0);
        let scene = crate::io::parse_flat("poly 4 0 2 4 0 2 2 2 1\n")
            .unwrap()
            .split_patch(0, 2.3689e-5)
            .unwrap();
        let last = scene.n_patches() - 1;
        assert_eq!(scene.pair_flux(0, last).unwrap(), 0.0);
        assert_eq!(scene.pair_flux(last, 0).unwrap(), 0.0);
    }

    /// A wall coincident with the target (back to back) hides nothing from a source so short
    /// that its own frame tilts the wall off the target's line (found by `fuzz_refine`: from
    /// the 0.0006-long piece the flux was 0, from the target 1.85e-9).
    #[cfg(feature = "alloc")]
    #[test]
    fn wall_back_to_back_with_a_short_target_hides_nothing() {
        let pair = "seg 0.0 1.0 0.0006056109857832822 0.9998485972535541\n\
                    seg 4.0 0.0 3.9961089494163424 0.01556420233463035\n";
        let open = crate::io::parse_flat(pair).unwrap();
        let walled = crate::io::parse_flat(&alloc::format!("{pair}seg 3 4 4 0\n")).unwrap();
        let free = open.pair_flux(0, 1).unwrap();
        assert!(free > 1e-9, "{free}");
        for (i, j) in [(0, 1), (1, 0)] {
            let flux = walled.pair_flux(i, j).unwrap();
            assert!(
                (flux - free).abs() < 1e-6 * free,
                "{i} → {j}: {flux} vs {free}"
            );
        }
    }

    /// An occluder touching the target from behind (its end on the target, the rest beyond
    /// it) hides nothing, even where the source sees it edge-on at the midpoint between two
    /// visibility events. Found by `fuzz_refine`: integrated over `i`, the flux came out
    /// 1.681009 instead of 1.767767, so `L_i F_ij ≠ L_j F_ji` and a split changed the
    /// background's size. Both directions must equal the unoccluded crossed strings.
    #[cfg(feature = "alloc")]
    #[test]
    fn occluder_touching_the_target_from_behind_hides_nothing() {
        let open = crate::io::parse_flat("seg 2 4.5 0 5\nseg 0 5 2.5 2.5\n").unwrap();
        let touched =
            crate::io::parse_flat("seg 2 4.5 0 5\nseg 0 5 2.5 2.5\nseg 1 2 1 4\n").unwrap();
        let free = open.pair_flux(0, 1).unwrap();
        assert!(
            (free - 1.25 * core::f64::consts::SQRT_2).abs() < 1e-12,
            "{free}"
        );
        for (i, j) in [(0, 1), (1, 0)] {
            let flux = touched.pair_flux(i, j).unwrap();
            assert!((flux - free).abs() < 1e-12, "{i} → {j}: {flux} vs {free}");
        }
    }

    /// A 10⁴ × 10⁻³ quadrilateral (aspect 10⁷) in 4 patches per side: every row of the
    /// closed scene sums to one within 1e-12 (found by `fuzz_flat_pipeline`: the difference
    /// of two far distances made row 12 sum to `1 + 3.6e-9`).
    #[cfg(feature = "alloc")]
    #[test]
    fn extreme_aspect_sliver_rows_sum_to_one() {
        let scene =
            crate::io::parse_flat("poly 4 0 0 10000 0 100 0.001 0 0.001 per_side 4\n").unwrap();
        let ff = form_factors(&scene).unwrap();
        for i in 0..ff.n_states() {
            let row: f64 = (0..ff.n_states()).map(|j| ff.get(i, j)).sum();
            assert!((row - 1.0).abs() < 1e-12, "row {i}: {row}");
        }
    }

    #[cfg(feature = "alloc")]
    #[test]
    fn closed_room_with_box_rows_sum_to_one() {
        let room = [
            DVec2::ZERO,
            DVec2::new(4.0, 0.0),
            DVec2::new(4.0, 3.0),
            DVec2::new(0.0, 3.0),
        ];
        let boxv = [
            DVec2::new(1.0, 1.0),
            DVec2::new(2.2, 1.0),
            DVec2::new(2.2, 1.7),
            DVec2::new(1.0, 1.7),
        ];
        let scene = Scene2::room_with_objects((&room, 5), &[(&boxv, 3)]).unwrap();
        let ff = form_factors(&scene).unwrap();
        assert!(!ff.has_background(), "deficit {}", ff.max_row_deficit());
        for i in 0..ff.n_states() {
            let row: f64 = (0..ff.n_states()).map(|j| ff.get(i, j)).sum();
            assert!((row - 1.0).abs() < 1e-12, "row {i}: {row}");
        }
        // Spot-check occluded pairs against quadrature.
        for &(i, j) in &[(0, 12), (2, 27), (5, 16), (20, 31)] {
            let q = quadrature(&scene, i, j);
            assert!(
                (ff.get(i, j) - q).abs() < 1e-10,
                "F[{i}][{j}] = {} vs {q}",
                ff.get(i, j)
            );
        }
    }
}
