//! The per-polygon data and the exact line–polygon test that [`super::Bvh3`] and the naive
//! loops share (see the parent module's docs for the formulas).

use crate::geom::{DVec3, polygon_normal};

/// Relative size of the spatial margin of the box tests (parent module docs).
const MARGIN: f64 = 1e-9;

/// The vertices of polygon `(first, count)`, or `None` when the range leaves `points`.
#[inline]
pub(super) fn vertices(points: &[DVec3], first: usize, count: usize) -> Option<&[DVec3]> {
    points.get(first..first.checked_add(count)?)
}

/// The frame of a polygon list: the centre `c` of the bounds of its finite vertices (the
/// origin of every coordinate the queries use) and `scale`, their largest coordinate
/// magnitude relative to `c` (the size of the margin). The tree and the naive loops compute it with the
/// same code, hence bit-identical.
#[derive(Clone, Copy, Debug)]
pub(super) struct Frame {
    pub(super) c: DVec3,
    pub(super) scale: f64,
}

impl Frame {
    /// The frame of every in-range polygon's finite vertices (origin and 0 if none).
    pub(super) fn new(points: &[DVec3], polygons: &[(usize, usize)]) -> Self {
        let mut lo = DVec3::INFINITY;
        let mut hi = DVec3::NEG_INFINITY;
        for &(first, count) in polygons {
            for &v in vertices(points, first, count).unwrap_or(&[]) {
                if v.is_finite() {
                    lo = lo.min(v);
                    hi = hi.max(v);
                }
            }
        }
        if lo.x <= hi.x {
            let c = lo * 0.5 + hi * 0.5;
            Self {
                c,
                scale: (lo - c).abs().max(hi - c).max_element(),
            }
        } else {
            Self {
                c: DVec3::ZERO,
                scale: 0.0,
            }
        }
    }
}

/// What a polygon needs besides its vertices: unit normal `n` (Newell, fan form), and,
/// relative to the frame's centre `c`, a point `p0` of its plane (the vertex mean) and its
/// bounds.
#[derive(Clone, Copy, Debug)]
pub(in crate::accel) struct Prepared {
    pub(in crate::accel) n: DVec3,
    pub(in crate::accel) p0: DVec3,
    /// `[lo, hi]`.
    pub(in crate::accel) bounds: [DVec3; 2],
}

/// The prepared data of a polygon, or `None` for one that can never be hit: fewer than
/// three vertices, a non-finite vertex (or vertex relative to `c`), or a zero (or
/// non-finite) normal.
pub(in crate::accel) fn prepare(c: DVec3, verts: &[DVec3]) -> Option<Prepared> {
    if verts.len() < 3 {
        return None;
    }
    let mut lo = DVec3::INFINITY;
    let mut hi = DVec3::NEG_INFINITY;
    let mut sum = DVec3::ZERO;
    for &v in verts {
        let v = v - c;
        if !v.is_finite() {
            return None;
        }
        lo = lo.min(v);
        hi = hi.max(v);
        sum += v;
    }
    let n = polygon_normal(verts);
    let len = n.length();
    let p0 = sum / verts.len() as f64;
    if !(len > 0.0 && len.is_finite() && p0.is_finite()) {
        return None;
    }
    Some(Prepared {
        n: n / len,
        p0,
        bounds: [lo, hi],
    })
}

/// `w / |w|`, accurate for tiny and huge `w` too (rescaled by its largest component
/// first); NaN for zero or non-finite `w`.
#[inline]
fn unit(w: DVec3) -> DVec3 {
    let ll = w.length_squared();
    if ll > 1e-200 && ll < 1e200 {
        return w / libm::sqrt(ll);
    }
    let m = w.abs().max_element();
    if !(m > 0.0 && w.is_finite()) {
        return DVec3::NAN;
    }
    let s = w / m;
    s / s.length()
}

/// A line prepared for many box and polygon tests, in the frame centred at `c`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Query {
    /// Origin relative to `c`.
    o: DVec3,
    d: DVec3,
    /// Foot of the perpendicular from the frame's centre `c` (relative to `c`): the
    /// line's reference point for the crossing test.
    f: DVec3,
    /// Orthonormal basis of the plane `d^⊥`, `(r1, r2, d/|d|)` right-handed.
    r1: DVec3,
    r2: DVec3,
    /// Per axis, which bound the line meets first: 0 (low) where `1/d ≥ +0`, 1 (high)
    /// where `1/d ≤ −0` (pbrt's `dirIsNeg`).
    pub(super) near: [usize; 3],
    /// The constants of the box tests.
    pub(super) slab: Slab,
}

/// The first half of a [`Query`]: the line relative to the frame's centre and the
/// constants of its box tests, without the crossing test's frame (`f`, `r₁`, `r₂`: a
/// division, a square root and an orthonormal pair). Enough to decide that a line misses
/// a box containing every polygon ([`BoxQuery::misses`]) before paying for the rest.
#[derive(Clone, Copy, Debug)]
pub(super) struct BoxQuery {
    /// Origin relative to `c`.
    rel: DVec3,
    d: DVec3,
    near: [usize; 3],
    slab: Slab,
}

impl BoxQuery {
    /// The box-test constants of the line `o + t d` in `frame` (those of [`Query::new`],
    /// bit for bit: the query is finished from them by [`BoxQuery::query`]).
    #[inline]
    pub(super) fn new(o: DVec3, d: DVec3, frame: &Frame) -> Self {
        let rel = o - frame.c;
        let margin = MARGIN * (rel.abs().max_element() + frame.scale) + f64::MIN_POSITIVE;
        let inv = (DVec3::ONE / d).to_array();
        // The low plane moved by −margin is the origin moved by +margin, and conversely;
        // the near plane is the low one unless 1/d ≤ −0.
        let (o_lo, o_hi) = ((rel + margin).to_array(), (rel - margin).to_array());
        // Without a branch: a global line's octant is random, and three sign branches
        // were mispredicted half the time each. `neg` is all ones where `1/d ≤ −0`; the
        // origins are chosen bit by bit (`x ^ ((x ^ y) & neg)` is `y` there, else `x`).
        let mut near = [0; 3];
        let mut o_near = o_lo;
        let mut o_far = o_hi;
        for i in 0..3 {
            let sign = inv[i].to_bits() >> 63;
            near[i] = sign as usize;
            let neg = 0u64.wrapping_sub(sign);
            let (lo, hi) = (o_lo[i].to_bits(), o_hi[i].to_bits());
            let diff = (lo ^ hi) & neg;
            o_near[i] = f64::from_bits(lo ^ diff);
            o_far[i] = f64::from_bits(hi ^ diff);
        }
        Self {
            rel,
            d,
            near,
            slab: Slab {
                o_near,
                o_far,
                inv,
                neg_inv: inv.map(|x| -x),
            },
        }
    }

    /// Whether the line surely misses every polygon whose bounds lie in `b = [lo, hi]`
    /// (relative to `c`): the slab interval of `b` ([`Slab::interval`], the arithmetic of
    /// the polygons' step 2) is empty. Exact, by the monotonicity of the parent module
    /// docs: a polygon's interval lies in `b`'s, so it is empty too and step 2 rejects
    /// the polygon. A NaN comparison answers `false` (test the polygons).
    #[cfg(feature = "alloc")]
    #[inline(always)]
    pub(super) fn misses(&self, b: &[DVec3; 2]) -> bool {
        let [i, j, k] = self.near;
        let (enter, exit) = self.slab.interval(
            [b[i].x, b[j].y, b[k].z],
            [b[1 - i].x, b[1 - j].y, b[1 - k].z],
        );
        enter > exit
    }

    /// The whole query: the crossing test's frame added.
    #[inline]
    pub(super) fn query(self) -> Query {
        let (rel, d) = (self.rel, self.d);
        let f = rel - d * (rel.dot(d) / d.length_squared());
        // NaN for a zero or non-finite direction: then no polygon is ever crossed.
        let (r1, r2) = unit(d).any_orthonormal_pair();
        Query {
            o: rel,
            d,
            f,
            r1,
            r2,
            near: self.near,
            slab: self.slab,
        }
    }
}

impl Query {
    /// The query of the line `o + t d` in `frame`.
    #[inline]
    pub(super) fn new(o: DVec3, d: DVec3, frame: &Frame) -> Self {
        BoxQuery::new(o, d, frame).query()
    }

    /// The conservative `f32` box tests of this query in a frame of scale `scale`
    /// ([`super::slab32`]), or `None` where their error bounds do not hold.
    #[cfg(feature = "alloc")]
    #[inline]
    pub(super) fn slab32(&self, scale: f64) -> Option<super::slab32::Slab32> {
        let s = &self.slab;
        super::slab32::Slab32::new(
            DVec3::from_array(s.o_near),
            DVec3::from_array(s.o_far),
            self.d,
            DVec3::from_array(s.inv),
            scale,
        )
    }

    /// [`Slab::interval`] of the box `b = [lo, hi]` (relative to `c`).
    #[inline(always)]
    pub(super) fn slab(&self, b: &[DVec3; 2]) -> (f64, f64) {
        let [i, j, k] = self.near;
        self.slab.interval(
            [b[i].x, b[j].y, b[k].z],
            [b[1 - i].x, b[1 - j].y, b[1 - k].z],
        )
    }

    /// Vertex `v' = v − c` projected on the plane `d^⊥`, relative to the line.
    #[inline(always)]
    pub(super) fn project(&self, v: DVec3) -> (f64, f64) {
        let a = v - self.f;
        (self.r1.dot(a), self.r2.dot(a))
    }

    /// Vector `w` projected on the plane `d^⊥`.
    #[cfg(feature = "alloc")]
    #[inline(always)]
    pub(super) fn project_dir(&self, w: DVec3) -> (f64, f64) {
        (self.r1.dot(w), self.r2.dot(w))
    }

    /// Whether the line passes through the closed polygon of the vertices `verts`
    /// (relative to `c`; `last` = the last of them): no two edge functions of opposite
    /// signs, and not all of them zero (a line in the polygon's plane). The edge function
    /// of `a → b` is the 2D cross product `a × b` of the projected vertices: that of
    /// `b → a` is exactly its negation.
    #[inline(always)]
    pub(super) fn crosses<I: IntoIterator<Item = DVec3>>(&self, last: DVec3, verts: I) -> bool {
        origin_in_closed_polygon(
            self.project(last),
            verts.into_iter().map(|v| self.project(v)),
        )
    }

    /// The line parameter of the hit of a polygon the line [`crosses`](Self::crosses)
    /// (`p0`, `bounds` relative to `c`): the plane's `t` clamped into the polygon's slab
    /// interval; `None` when that interval is empty, the line is parallel to the plane, or
    /// `t` is not finite.
    #[inline(always)]
    pub(super) fn hit_t(&self, n: DVec3, p0: DVec3, bounds: &[DVec3; 2]) -> Option<f64> {
        let (enter, exit) = self.slab(bounds);
        let denom = n.dot(self.d);
        if !(enter <= exit) || denom == 0.0 {
            return None;
        }
        let t = n.dot(p0 - self.o) / denom;
        if t.is_nan() {
            return None;
        }
        // `+ 0.0` turns −0 into +0.
        let t = t.max(enter).min(exit) + 0.0;
        t.is_finite().then_some(t)
    }
}

/// Whether the origin of the plane lies in the closed polygon of the 2D points `points`
/// (`last` = the last of them, where the walk starts): no two edge functions `a × b` of
/// opposite signs, and not all of them zero. The edge function of `b → a` is exactly the
/// negation of that of `a → b`, which makes the test watertight across shared edges (the
/// module docs of [`super`]). Shared by [`Query::crosses`] and the bundle raster.
#[inline(always)]
pub(in crate::accel) fn origin_in_closed_polygon(
    last: (f64, f64),
    points: impl Iterator<Item = (f64, f64)>,
) -> bool {
    let (mut pos, mut neg) = (false, false);
    let mut a = last;
    for b in points {
        let s = a.0 * b.1 - a.1 * b.0;
        pos |= s > 0.0;
        neg |= s < 0.0;
        if pos && neg {
            return false;
        }
        a = b;
    }
    pos != neg
}

/// The per-query constants of the box tests: the origins of the near and far planes (the
/// margin applied), `1/d` and `−1/d`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Slab {
    o_near: [f64; 3],
    o_far: [f64; 3],
    inv: [f64; 3],
    neg_inv: [f64; 3],
}

impl Slab {
    /// The parameter interval `[enter, exit]` in which the line is inside a box grown by
    /// the margin, given the box's near and far bounds per axis (`b[near[i]]` and
    /// `b[1 − near[i]]`, relative to `c`); empty when `enter > exit`.
    ///
    /// Monotone in the box: a box containing another gets an interval containing the
    /// other's. Each plane's `t = (bound ∓ margin − o)/d` is monotone in the bound (IEEE
    /// subtraction and multiplication are); a NaN `t` (a bound exactly at `o ± margin`
    /// with `d = 0` on that axis, where the slab is in fact unbounded) is ignored by the
    /// folds, as `±∞` would be, so it too keeps the order. A NaN line gives anything
    /// (it crosses no polygon).
    #[inline(always)]
    pub(super) fn interval(&self, near: [f64; 3], far: [f64; 3]) -> (f64, f64) {
        // `t > acc` is false for NaN: NaN planes are skipped. The far planes' `t` are
        // negated (exactly), so both folds are maxima (one `maxpd` per axis).
        let mut enter = f64::NEG_INFINITY;
        let mut neg_exit = f64::NEG_INFINITY;
        for i in 0..3 {
            let tn = (near[i] - self.o_near[i]) * self.inv[i];
            let tf = (far[i] - self.o_far[i]) * self.neg_inv[i];
            enter = if tn > enter { tn } else { enter };
            neg_exit = if tf > neg_exit { tf } else { neg_exit };
        }
        (enter, -neg_exit)
    }

    /// [`Slab::interval`] of four boxes at once, given per axis their near and far bounds
    /// in `f32` (`near[i][c]`, `far[i][c]` for box `c`), as `(enter, exit)` per box: per
    /// box the same subtractions and products in the same order on the same (exactly
    /// widened) values, laid out lane by lane so that they vectorise. The folds are
    /// `f64::max` (`maxpd`) instead of `interval`'s select: the accumulators start at
    /// `−∞` and are never NaN, so a NaN plane is skipped by both and the two agree but
    /// for the sign of a zero, which no comparison of `enter` and `exit` sees — the
    /// culling is the same, box by box.
    #[cfg(feature = "alloc")]
    #[inline(always)]
    pub(super) fn interval4(
        &self,
        near: [&[f32; 4]; 3],
        far: [&[f32; 4]; 3],
    ) -> ([f64; 4], [f64; 4]) {
        let mut enter = [f64::NEG_INFINITY; 4];
        let mut neg_exit = [f64::NEG_INFINITY; 4];
        for i in 0..3 {
            let (o_near, o_far) = (self.o_near[i], self.o_far[i]);
            let (inv, neg_inv) = (self.inv[i], self.neg_inv[i]);
            for c in 0..4 {
                let tn = (f64::from(near[i][c]) - o_near) * inv;
                let tf = (f64::from(far[i][c]) - o_far) * neg_inv;
                enter[c] = tn.max(enter[c]);
                neg_exit[c] = tf.max(neg_exit[c]);
            }
        }
        (enter, neg_exit.map(|x| -x))
    }
}
