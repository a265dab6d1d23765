//! The sheets of a bundle's raster, row by row (parent module docs, "Sheets").
//!
//! # Method
//!
//! Along a row of the lattice (`b` fixed, `a = (first + q) h`) the crossing `(s, t)` of
//! the line with a sheet's ideal lattice ([`Sheet::window`]) is affine in `a`:
//!
//! ```text
//! s(a) = s₀ + a σ,   s₀ = (v'₀ (A'₁ − b) − v'₁ A'₀)/det,   σ =  v'₁/det
//! t(a) = t₀ + a θ,   t₀ = (A'₀ u'₁ − (A'₁ − b) u'₀)/det,  θ = −u'₁/det
//! ```
//!
//! (the window's own formulas with `A' − x` expanded), so each candidate costs a
//! multiplication and an addition per coordinate instead of the window and the closed
//! test of the quads in it. The result is the same as the exact path's — the window and
//! the closed test of [`Sheet::window`]'s quads, kept for the rest — candidate by candidate:
//!
//! - **Margins.** Per sheet and bundle, `w_s`, `w_t` are the window's allowances
//!   ([`ProjectedSheet::half_widths`], increasing in `|A' − x|₁`) at the largest
//!   `|A' − x|₁ ≤ |A'|₁ + a_max + b_max` of the bundle's points, and
//!   `ε_s = 10⁻¹³ (|v'|₁ (|A'|₁ + a_max + b_max) / |det| + m + 2)` bounds the difference
//!   between `s(a)` above and the window's `s` (both sums of products of magnitude at most
//!   `|v'|₁ (|A'|₁ + a_max + b_max)/|det|` with a few roundings of `2⁻⁵³` each), and the
//!   rounding of the window's `s − 1 − w`, `s + w` (`ε_t` alike with `|u'|₁`, `k`). The
//!   margin is `μ_s = w_s (1 + 10⁻⁶) + 2 ε_s`.
//! - **Outside**: `s(a) < −μ_s` or `s(a) > m + μ_s` (or `t` alike): the window's `s` is
//!   below `−w_s` or above `m + w_s`, its column range is empty and the exact path tests
//!   nothing.
//! - **Inside a cell**: `i = ⌊s(a)⌋`, `j = ⌊t(a)⌋` in the sheet and `s(a)`, `t(a)` more
//!   than `μ` from the cell's sides: the window's `s` is in `(i + w_s, i + 1 − w_s)`, so
//!   its window is the one cell `(i, j)`, and the closed test accepts the quad: the bound
//!   [`Sheet::window`] rests on, `|E_computed − E_ideal| ≤ δE + τ(|e'| + 2R)` for each
//!   edge function, holds both ways, so a crossing more than the allowance inside every
//!   side of the ideal cell gives every computed `E` the inside sign, none zero. Its hit
//!   is then computed by the exact path's own arithmetic ([`SheetCast::quad_hit`]).
//! - **Otherwise** (within `μ` of a side, rare: `μ` is ~10⁻⁹ of a cell): the exact path
//!   for that candidate.
//!
//! A sheet whose margins are not finite or not below a quarter of a cell (a grazing
//! direction, `det` near 0) takes the exact path for every candidate.

use crate::geom::DVec3;

use super::super::bvh3::sheet::ProjectedSheet;
use super::{
    BundleHits3, FoundHits, Frame, Hit3, ParallelRaster3, PlaneDots, RasterSheet, SHEET_ROUNDING,
    crosses, for_each_candidate, for_each_row, greater, lesser,
};

/// How a bundle casts its sheets: row by row where the margins allow (module docs), or
/// every candidate by the window and the closed test (the reference the row path must
/// equal bit for bit).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum SheetPath {
    Rows,
    #[cfg_attr(not(test), allow(dead_code))]
    Exact,
}

/// Relative allowance for the rounding of the affine crossing (module docs, `ε_s`).
const CROSSING_ROUNDING: f64 = 1e-13;

/// Relative allowance for the rounding of the window's allowances at the largest
/// distance (module docs, `μ_s`).
const WIDTH_ROUNDING: f64 = 1e-6;

/// What the candidates of one sheet share in one bundle.
struct SheetCast<'a> {
    frame: &'a Frame,
    /// `A'`: the sheet's lattice origin projected.
    pa: [f64; 3],
    projected: ProjectedSheet,
    m: u32,
    prim: u32,
    quads: &'a [[DVec3; 4]],
    planes: &'a [(DVec3, DVec3)],
    quad_corners: &'a [[u32; 4]],
    /// The sheets' vertices projected, if the bundle projected them all (else empty).
    sheet_projected: &'a [[f64; 3]],
    /// The sheet's one normal with the frame's axes, when its quads share it.
    dots: Option<PlaneDots>,
    /// The depths of the ideal lattice, `d·(A − c)`, `d·u`, `d·v`, and the allowance
    /// `4τ` that bounds the difference between a corner's depth and its ideal depth.
    depth_lattice: [f64; 3],
    depth_allowance: f64,
    /// Whether a hit may skip its corners' depths ([`SheetCast::quad_hit`]); not on the
    /// exact path, which the row path must equal bit for bit (tests).
    depth_shortcut: bool,
}

impl SheetCast<'_> {
    /// Bounds `(low, high)` with `near ≤ low` and `high ≤ far` for quad `(i, j)`'s
    /// corners' depths `near` (least) and `far` (greatest).
    ///
    /// A corner `P = A + i' u + j' v + e` (`|e|` at most the sheet's deviation) has the
    /// depth `d·(P − c)` computed to within `10⁻¹⁵ |P − c|₁` of its exact value, which is
    /// within `|e|` of the ideal `D(i', j') = d·(A − c) + i' d·u + j' d·v`, itself
    /// computed here to within `10⁻¹⁵` of the sheet's size; `τ` (the window's deviation
    /// plus `10⁻¹²` of the size) covers all three, and `4τ` leaves room. So `near`, at
    /// most the depth of the corner with the least ideal depth, is at most that ideal
    /// depth plus `4τ`, and `far` at least the greatest minus `4τ`.
    #[inline(always)]
    fn depth_cell(&self, i: u32, j: u32) -> (f64, f64) {
        let [da, du, dv] = self.depth_lattice;
        let base = da + f64::from(i) * du + f64::from(j) * dv;
        let low = base + du.min(0.0) + dv.min(0.0) + self.depth_allowance;
        let high = base + du.max(0.0) + dv.max(0.0) - self.depth_allowance;
        (low, high)
    }

    /// The exact path for the line through `(a, b)`: the window of its crossing, and the
    /// closed test of each quad in it.
    #[inline(always)]
    fn exact(&self, line: u32, a: f64, b: f64, found: &mut FoundHits) {
        let frame = self.frame;
        let rel = (self.pa[0] - a, self.pa[1] - b);
        let (cols, rws) = self.projected.window(rel);
        for j in rws {
            for i in cols.clone() {
                let o = (j * self.m + i) as usize;
                let (Some(q), Some(c)) = (self.quads.get(o), self.quad_corners.get(o)) else {
                    continue;
                };
                let vertex = |k: usize| self.sheet_projected.get(c[k] as usize).copied();
                // Written out: `q.map(…)` was not inlined (7 % of a cube job)
                let p = match (vertex(0), vertex(1), vertex(2), vertex(3)) {
                    (Some(p0), Some(p1), Some(p2), Some(p3)) => [p0, p1, p2, p3],
                    _ => [
                        frame.project_across(q[0]),
                        frame.project_across(q[1]),
                        frame.project_across(q[2]),
                        frame.project_across(q[3]),
                    ],
                };
                if crosses(p.iter().copied(), p[3], a, b) {
                    self.quad_hit(line, (i, j), a, b, found);
                }
            }
        }
    }

    /// The hit of the line through `(a, b)` with quad `(i, j)` (`o = j m + i`), which it
    /// crosses: `t` from the quad's plane, clamped into its depths.
    ///
    /// The clamp leaves `t` as it is when `near − δ ≤ t ≤ far + δ`, which holds without
    /// the corners' depths when `t` is inside the ideal cell's depths by the allowance
    /// `4τ` ([`SheetCast::depth_cell`]; the usual case, as a line that crosses the quad
    /// meets its plane between its corners' depths): then the corners' depths are not
    /// computed, and the result is the same bits.
    #[inline(always)]
    fn quad_hit(&self, line: u32, (i, j): (u32, u32), a: f64, b: f64, found: &mut FoundHits) {
        let frame = self.frame;
        let o = (j * self.m + i) as usize;
        let (Some(q), Some(c), Some(&(n, p0))) = (
            self.quads.get(o),
            self.quad_corners.get(o),
            self.planes.get(o),
        ) else {
            return;
        };
        let dots = self.dots.unwrap_or_else(|| frame.plane_dots(n));
        let (low, high) = self.depth_cell(i, j);
        if self.depth_shortcut
            && let Some(t) = frame.plane_t_inside(dots, n, p0, a, b, low, high)
        {
            found.push(
                line,
                Hit3 {
                    t,
                    prim: self.prim + o as u32,
                },
            );
            return;
        }
        // A projected vertex's depth is `Frame::depth`'s bits: read it where the bundle
        // projected every vertex, else compute it (most quads tested are not crossed)
        let depth = |k: usize| match self.sheet_projected.get(c[k] as usize) {
            Some(p) => p[2],
            None => frame.depth(q[k]),
        };
        let (d0, d1, d2, d3) = (depth(0), depth(1), depth(2), depth(3));
        // From ±∞, as `f64::min`/`max` fold (a NaN depth is passed over)
        let near = [d0, d1, d2, d3].into_iter().fold(f64::INFINITY, lesser);
        let far = [d0, d1, d2, d3]
            .into_iter()
            .fold(f64::NEG_INFINITY, greater);
        // The shortcut's bounds hold (`depth_cell`), and where it answers it gives the
        // clamp's bits (tests: every hit of the row path and of the exact path)
        #[cfg(test)]
        {
            assert!(!(near > low) && !(far < high), "{near} {low} {far} {high}");
            if let Some(t) = frame.plane_t_inside(dots, n, p0, a, b, low, high) {
                let clamped = frame.plane_t_with(dots, n, p0, a, b, near, far);
                assert_eq!(Some(t.to_bits()), clamped.map(f64::to_bits));
            }
        }
        if let Some(t) = frame.plane_t_with(dots, n, p0, a, b, near, far) {
            found.push(
                line,
                Hit3 {
                    t,
                    prim: self.prim + o as u32,
                },
            );
        }
    }
}

/// The affine crossing of one sheet along the rows (module docs): `1/det`, the slopes
/// `σ`, `θ` and the margins `μ_s`, `μ_t`.
struct RowCrossing {
    pu: (f64, f64),
    pv: (f64, f64),
    inv_det: f64,
    sigma: f64,
    theta: f64,
    mu_s: f64,
    mu_t: f64,
}

impl RowCrossing {
    /// The row crossing of a sheet with `m × k` quads, `A'` projecting at `pa`, if its
    /// margins are finite and below a quarter of a cell.
    fn new(
        frame: &Frame,
        pa: [f64; 3],
        projected: &ProjectedSheet,
        m: u32,
        k: u32,
    ) -> Option<Self> {
        let (pu, pv, inv_det) = projected.axes();
        let (nu, nv) = projected.norms();
        let reach = pa[0].abs() + pa[1].abs() + frame.a_max + frame.b_max;
        let (ws, wt) = projected.half_widths(reach);
        let eps_s = CROSSING_ROUNDING * (nv * reach * inv_det.abs() + f64::from(m) + 2.0);
        let eps_t = CROSSING_ROUNDING * (nu * reach * inv_det.abs() + f64::from(k) + 2.0);
        let mu_s = ws * (1.0 + WIDTH_ROUNDING) + 2.0 * eps_s;
        let mu_t = wt * (1.0 + WIDTH_ROUNDING) + 2.0 * eps_t;
        // Also refuses NaN
        (mu_s < 0.25 && mu_t < 0.25 && inv_det.is_finite()).then_some(Self {
            pu,
            pv,
            inv_det,
            sigma: pv.1 * inv_det,
            theta: -(pu.1 * inv_det),
            mu_s,
            mu_t,
        })
    }
}

impl ParallelRaster3 {
    /// Each sheet against the lattice points of its projected parallelogram, row by row
    /// where the margins allow ([`SheetPath::Rows`], module docs), else each point against
    /// the quads of its window (parent module docs, "Sheets").
    pub(super) fn cast_sheets(
        &self,
        frame: &Frame,
        r: f64,
        path: SheetPath,
        out: &mut BundleHits3,
    ) {
        let BundleHits3 {
            rows,
            found,
            sheet_projected,
            #[cfg(test)]
            row_paths,
            ..
        } = out;
        for rs in &self.sheets {
            let RasterSheet {
                sheet,
                first_quad,
                prim,
                normal,
            } = rs;
            let [a0, u, v] = sheet.lattice();
            let (m, k) = (sheet.cols(), sheet.rows());
            let pa = frame.project(a0);
            let pu = [frame.e1.dot(u), frame.e2.dot(u)];
            let pv = [frame.e1.dot(v), frame.e2.dot(v)];
            let norm1 = |w: DVec3| w.x.abs() + w.y.abs() + w.z.abs();
            let size = norm1(a0 - frame.c) + f64::from(m) * norm1(u) + f64::from(k) * norm1(v) + r;
            let tau = sheet.deviation() + SHEET_ROUNDING * size;
            // The projected parallelogram's bounds
            let (mf, kf) = (f64::from(m), f64::from(k));
            let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            for (i, j) in [(0.0, 0.0), (mf, 0.0), (0.0, kf), (mf, kf)] {
                let x = pa[0] + i * pu[0] + j * pv[0];
                let y = pa[1] + i * pu[1] + j * pv[1];
                lo = [lesser(lo[0], x), lesser(lo[1], y), 0.0];
                hi = [greater(hi[0], x), greater(hi[1], y), 0.0];
            }
            let first = *first_quad as usize;
            let cast = SheetCast {
                frame,
                pa,
                // What the window of every candidate shares (one division per sheet and
                // bundle)
                projected: sheet.projected((pu[0], pu[1]), (pv[0], pv[1]), tau),
                m,
                prim: *prim,
                quads: &self.quads[first..][..sheet.len()],
                planes: &self.quad_planes[first..][..sheet.len()],
                quad_corners: &self.quad_corners[first..][..sheet.len()],
                sheet_projected,
                dots: normal.map(|n| frame.plane_dots(n)),
                depth_lattice: [pa[2], frame.d.dot(u), frame.d.dot(v)],
                depth_allowance: 4.0 * tau,
                depth_shortcut: path == SheetPath::Rows,
            };
            let grow = frame.delta + tau;
            let crossing = match path {
                SheetPath::Rows => RowCrossing::new(frame, pa, &cast.projected, m, k),
                SheetPath::Exact => None,
            };
            let Some(x) = crossing else {
                for_each_candidate(frame, rows, lo, hi, grow, |line, a, b| {
                    cast.exact(line, a, b, found);
                });
                continue;
            };
            let (s_end, t_end) = (mf + x.mu_s, kf + x.mu_t);
            let (mi, ki) = (i64::from(m), i64::from(k));
            for_each_row(frame, rows, lo, hi, grow, |row| {
                let rel1 = pa[1] - row.b;
                let s0 = (x.pv.0 * rel1 - x.pv.1 * pa[0]) * x.inv_det;
                let t0 = (pa[0] * x.pu.1 - rel1 * x.pu.0) * x.inv_det;
                for q in row.q_lo..=row.q_hi {
                    let a = row.a(frame, q);
                    let (s, t) = (s0 + a * x.sigma, t0 + a * x.theta);
                    if s < -x.mu_s || s > s_end || t < -x.mu_t || t > t_end {
                        continue;
                    }
                    // ⌊s⌋ for s ≥ 0 (truncation); for s in [−μ, 0) it gives 0, and then
                    // `s − 0 > μ` fails. NaN (0 here) fails every comparison: the exact
                    // path
                    let (i, j) = (s as i64, t as i64);
                    let (fi, fj) = (i as f64, j as f64);
                    let inside = s - fi > x.mu_s
                        && fi + 1.0 - s > x.mu_s
                        && t - fj > x.mu_t
                        && fj + 1.0 - t > x.mu_t
                        && (0..mi).contains(&i)
                        && (0..ki).contains(&j);
                    #[cfg(test)]
                    {
                        row_paths[usize::from(inside)] += 1;
                    }
                    if inside {
                        cast.quad_hit(row.line(q), (i as u32, j as u32), a, row.b, found);
                    } else {
                        cast.exact(row.line(q), a, row.b, found);
                    }
                }
            });
        }
    }
}
