//! Axis-aligned rectangles: the double contour sum of `pair_flux` written out for them.
//!
//! For two rectangles whose edges run along the coordinate axes, every edge pair is either
//! parallel or exactly perpendicular (`J_pq ∝ e_p · e_q = 0`), and clipping one to the
//! other's half-space only shortens an interval. With the edge-pair integral of parallel
//! edges along axis `t` (`contour.rs`, `Kernel::parallel`: a mixed second difference of
//! `F₂(u, h) = ¼(u² − h²) ln((u² + h²)/ℓ²) + h u atan(u/h)`),
//!
//! ```text
//! A_i F_ij = 1/(2π) Σ_t Σ_{p ∥ q ∥ t} s_p s_q σ_i σ_j ε_t
//!            [F₂(b_p − a_q) + F₂(a_p − b_q) − F₂(a_p − a_q) − F₂(b_p − b_q)](h_pq)
//! ```
//!
//! where `[a, b]` are the edges' ranges along `t`, `h_pq` the distance between their lines,
//! `σ` the sign of a rectangle's normal along its axis, `s = −1` for the edge on the low side
//! of the rectangle's other in-plane axis and `+1` on the high side (a counter-clockwise
//! boundary runs `N × outward`), and `ε_t = +1` for parallel rectangles (`t` either in-plane
//! axis), `−1` for perpendicular ones (`t` the common axis). This is Howell's corner sum
//! (catalogue C-11/C-14 generalised to offset rectangles, Ehlert & Smith 1993) in the
//! contour form's scaled variables: the same terms as the general path, without its vector
//! algebra, clipping, or the twelve perpendicular edge pairs per rectangle pair. Parallel
//! rectangles share the logarithm of `r² = u² + v² + d²` between their `u` and `v` edge pairs
//! (16 instead of 32).
//!
//! A quadrilateral counts as an axis-aligned rectangle when each coordinate that should be
//! constant along an edge varies by at most [`SNAP`] times its largest coordinate (a few
//! ulps: meshes written with decimal coordinates, such as `0.30000000000000004` beside
//! `0.3`); it is then replaced by its bounding rectangle, which moves `F_ij` by about that
//! relative amount.

use core::f64::consts::PI;

use crate::geom::DVec3;
use crate::math::{self, KahanSum};

/// Largest deviation from axis alignment, relative to the polygon's largest coordinate,
/// snapped to its bounding rectangle: 16 ulps.
const SNAP: f64 = 16.0 * f64::EPSILON;

/// An axis-aligned rectangle: its normal axis and sign, and its extent.
#[derive(Clone, Copy, Debug)]
pub(crate) struct AxisRect {
    /// The axis of the normal (0, 1, 2 for x, y, z).
    axis: usize,
    /// `+1` when the front normal points along `+axis`, else `−1`.
    sign: f64,
    /// Coordinate of the plane along `axis` (the first vertex's).
    level: f64,
    /// Lower and upper corners (their `axis` coordinates are `level`).
    lo: [f64; 3],
    hi: [f64; 3],
}

impl AxisRect {
    /// The rectangle of `poly` (with unit front normal `normal` and largest coordinate
    /// magnitude `magnitude`) when it is a quadrilateral with axis-aligned edges to within
    /// [`SNAP`], else `None`.
    pub fn of(poly: &[DVec3], normal: DVec3, magnitude: f64) -> Option<Self> {
        let [v0, v1, v2, v3] = *poly else {
            return None;
        };
        let n = normal.abs();
        let axis = if n.x >= n.y && n.x >= n.z {
            0
        } else if n.y >= n.z {
            1
        } else {
            2
        };
        let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
        let slack = SNAP * magnitude;
        let v = [v0.to_array(), v1.to_array(), v2.to_array(), v3.to_array()];
        let level = v[0][axis];
        // Edge k runs along u (true) or w (false); the edges alternate.
        let mut along_u = [false; 4];
        for k in 0..4 {
            let (a, b) = (v[k], v[(k + 1) % 4]);
            if (b[axis] - level).abs() > slack {
                return None;
            }
            let (du, dw) = ((b[u] - a[u]).abs(), (b[w] - a[w]).abs());
            along_u[k] = if dw <= slack && du > slack {
                true
            } else if du <= slack && dw > slack {
                false
            } else {
                return None;
            };
        }
        if along_u[0] == along_u[1] || along_u[0] != along_u[2] || along_u[1] != along_u[3] {
            return None;
        }
        let mut lo = [level; 3];
        let mut hi = [level; 3];
        for t in [u, w] {
            lo[t] = v.iter().map(|p| p[t]).fold(f64::INFINITY, f64::min);
            hi[t] = v.iter().map(|p| p[t]).fold(f64::NEG_INFINITY, f64::max);
        }
        Some(Self {
            axis,
            sign: if normal.to_array()[axis] > 0.0 {
                1.0
            } else {
                -1.0
            },
            level,
            lo,
            hi,
        })
    }

    /// The extent along the in-plane axis `t` clipped to the front of `other`'s plane (whose
    /// axis is `t`), with the contact tolerance `tol`: `None` when nothing lies beyond it.
    /// A side within `tol` of the plane stays where it is, as in `HalfSpace` clipping.
    #[inline]
    fn clipped(&self, t: usize, other: &Self, tol: f64) -> Option<(f64, f64)> {
        let (lo, hi, p) = (self.lo[t], self.hi[t], other.level);
        if other.sign > 0.0 {
            (hi > p + tol).then_some((if lo < p - tol { p } else { lo }, hi))
        } else {
            (lo < p - tol).then_some((lo, if hi > p + tol { p } else { hi }))
        }
    }
}

/// `(A_i F_ij, M, 0)` of two axis-aligned rectangles (see the module documentation), `M`
/// the magnitude `Σ m / 2π` of the terms that cancel in it (`contour.rs`, "Rounding"; no
/// quadrature), with the contact tolerance `tol` and the log scale `1/ℓ²` of `pair_flux`.
pub(super) fn rect_flux(s: &AxisRect, t: &AxisRect, tol: f64, inv_l2: f64) -> (f64, f64, f64) {
    let mut sum = KahanSum::new();
    let mut magnitude = 0.0;
    let sign = s.sign * t.sign;
    if s.axis == t.axis {
        // Parallel: they face each other when the normals are opposite and each lies in
        // front of the other.
        let d = t.level - s.level;
        if sign > 0.0 || s.sign * d <= tol {
            return (0.0, 0.0, 0.0);
        }
        let d2 = d * d;
        let (u, w) = ((s.axis + 1) % 3, (s.axis + 2) % 3);
        // u[k] = the differences along u of the four corner pairs, in the order
        // (hi_s − lo_t, lo_s − hi_t, lo_s − lo_t, hi_s − hi_t) of the mixed difference.
        let diffs = |a: usize| {
            [
                s.hi[a] - t.lo[a],
                s.lo[a] - t.hi[a],
                s.lo[a] - t.lo[a],
                s.hi[a] - t.hi[a],
            ]
        };
        let (du, dw) = (diffs(u), diffs(w));
        // ln(r²/ℓ²) of every corner pair, shared by the u and w edge pairs.
        let mut logs = [[0.0; 4]; 4];
        for (i, x) in du.iter().enumerate() {
            for (k, y) in dw.iter().enumerate() {
                let r2 = x * x + y * y + d2;
                logs[i][k] = if r2 > 0.0 { math::ln(r2 * inv_l2) } else { 0.0 };
            }
        }
        // Which corner difference along the other axis an edge pair (p at side ps of s,
        // q at side qs of t) has: ps = 1 is s's high side.
        let index = |ps: usize, qs: usize| match (ps, qs) {
            (1, 0) => 0,
            (0, 1) => 1,
            (0, 0) => 2,
            _ => 3,
        };
        for ps in 0..2 {
            for qs in 0..2 {
                let side = if ps == qs { 1.0 } else { -1.0 };
                // Edges along u at w positions, then along w at u positions.
                let hw = math::sqrt(dw[index(ps, qs)] * dw[index(ps, qs)] + d2);
                let (j, m) = mixed(&du, hw, |i| logs[i][index(ps, qs)]);
                sum.add(side * sign * j);
                magnitude += m;
                let hu = math::sqrt(du[index(ps, qs)] * du[index(ps, qs)] + d2);
                let (j, m) = mixed(&dw, hu, |k| logs[index(ps, qs)][k]);
                sum.add(side * sign * j);
                magnitude += m;
            }
        }
    } else {
        // Perpendicular: s in the plane x_a = level, t in x_b = level, common axis c.
        let (a, b) = (s.axis, t.axis);
        let c = 3 - a - b;
        let (Some(sb), Some(ta)) = (s.clipped(b, t, tol), t.clipped(a, s, tol)) else {
            return (0.0, 0.0, 0.0);
        };
        let dc = [
            s.hi[c] - t.lo[c],
            s.lo[c] - t.hi[c],
            s.lo[c] - t.lo[c],
            s.hi[c] - t.hi[c],
        ];
        let (ends_s, ends_t) = ([sb.0, sb.1], [ta.0, ta.1]);
        // ε(a, b, c) ε(b, a, c) = −1.
        let sign = -sign;
        for (ps, &xb) in ends_s.iter().enumerate() {
            for (qs, &xa) in ends_t.iter().enumerate() {
                let side = if ps == qs { 1.0 } else { -1.0 };
                let (ea, eb) = (s.level - xa, xb - t.level);
                let h2 = ea * ea + eb * eb;
                let h = math::sqrt(h2);
                let (j, m) = mixed(&dc, h, |i| {
                    let r2 = dc[i] * dc[i] + h2;
                    if r2 > 0.0 { math::ln(r2 * inv_l2) } else { 0.0 }
                });
                sum.add(side * sign * j);
                magnitude += m;
            }
        }
    }
    (
        (sum.total() / (2.0 * PI)).max(0.0),
        magnitude / (2.0 * PI),
        0.0,
    )
}

/// `F₂(u₀) + F₂(u₁) − F₂(u₂) − F₂(u₃)` at distance `h`, with `ln(r²/ℓ²)` of `u_i` from
/// `log(i)`: `F₂(u) = ¼(u² − h²) ln(r²/ℓ²) + h u atan(u/h)` (`contour.rs`), and the
/// magnitude `Σ m` of its terms, `m = ¼ r² (|ln(r²/ℓ²)| + 2) + 2 |h u|` (`contour.rs`,
/// "Rounding").
#[inline]
fn mixed(u: &[f64; 4], h: f64, log: impl Fn(usize) -> f64) -> (f64, f64) {
    let f2 = |i: usize| {
        let x = u[i];
        let r2 = x * x + h * h;
        if r2 == 0.0 {
            return (0.0, 0.0);
        }
        let hx = h * x;
        let angle = if h > 0.0 { hx * math::atan(x / h) } else { 0.0 };
        let l = log(i);
        (
            0.25 * (x * x - h * h) * l + angle,
            0.25 * r2 * (l.abs() + 2.0) + 2.0 * hx.abs(),
        )
    };
    let ((f0, m0), (f1, m1), (f2_, m2), (f3, m3)) = (f2(0), f2(1), f2(2), f2(3));
    (f0 + f1 - f2_ - f3, m0 + m1 + m2 + m3)
}
