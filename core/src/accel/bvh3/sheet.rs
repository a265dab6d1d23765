//! Sheets: regular grids of quads held by the tree as one item (see the parent module's
//! docs, "Sheets"), found at build time and queried in `O(1)`.

use alloc::vec::Vec;
use core::ops::Range;

use crate::geom::DVec3;

use super::prim::{Prepared, Query};

/// Fewest quads a sheet holds.
const MIN_SHEET: usize = 4;

/// Largest deviation of a lattice point from the ideal lattice accepted in a sheet, as a
/// fraction of the shorter cell side (scenes cut faces into lattices exact to rounding).
/// Only the size of the query windows depends on it.
const MAX_DEVIATION: f64 = 1e-6;

/// Relative size of the windows' allowance for rounding (parent module docs).
const WINDOW_SLACK: f64 = 1e-9;

/// A sheet: the `m × k` quads `q(i, j)`, `i < m`, `j < k`, stored row by row, of the
/// lattice `P(i, j) ≈ A + i u + j v` (relative to the frame's centre).
#[derive(Clone, Copy, Debug)]
pub(in crate::accel) struct Sheet {
    a: DVec3,
    u: DVec3,
    v: DVec3,
    m: u32,
    k: u32,
    /// Largest distance of a lattice point from the ideal lattice.
    tau: f64,
    /// The union of the quads' bounds.
    pub(super) bounds: [DVec3; 2],
}

/// What the tree holds: a polygon (by input index) or a sheet over the `m·k` polygons
/// `start..` of the input.
#[derive(Clone, Copy, Debug)]
pub(in crate::accel) enum Unit {
    Polygon(usize),
    Sheet(usize, Sheet),
}

impl Unit {
    /// Bounds of the unit (relative to the frame's centre).
    pub(super) fn bounds(&self, prepared: &[Option<Prepared>]) -> [DVec3; 2] {
        match self {
            Self::Polygon(id) => prepared[*id].map_or([DVec3::ZERO; 2], |p| p.bounds),
            Self::Sheet(_, s) => s.bounds,
        }
    }
}

/// The vertices of quad `id` (relative to the frame's centre), if it is a hittable quad.
fn quad(
    points: &[DVec3],
    polygons: &[(usize, usize)],
    prepared: &[Option<Prepared>],
    c: DVec3,
    id: usize,
) -> Option<[DVec3; 4]> {
    let &(first, count) = polygons.get(id)?;
    if count != 4 || prepared[id].is_none() {
        return None;
    }
    let v = &points[first..first + 4];
    Some([v[0] - c, v[1] - c, v[2] - c, v[3] - c])
}

/// Cuts the hittable polygons into units: sheets where consecutive quads form a grid row
/// by row, `q(i, j) = [P(i, j), P(i + 1, j), P(i + 1, j + 1), P(i, j + 1)]` with shared
/// vertices bit-identical (as scenes cut faces into patches) and every vertex on the
/// lattice the first quad spans, and single polygons elsewhere. `O(n)`.
pub(in crate::accel) fn find_units(
    points: &[DVec3],
    polygons: &[(usize, usize)],
    prepared: &[Option<Prepared>],
    c: DVec3,
) -> Vec<Unit> {
    let n = polygons.len();
    let q = |id: usize| quad(points, polygons, prepared, c, id);
    let mut units = Vec::new();
    let mut s = 0;
    while s < n {
        let Some(first) = q(s) else {
            if prepared[s].is_some() {
                units.push(Unit::Polygon(s));
            }
            s += 1;
            continue;
        };
        // The lattice the first quad predicts; a grid stops where it leaves it (at the fold
        // onto an adjacent face that shares its edge, say)
        let a = first[0];
        let (u0, v0) = (first[1] - a, first[3] - a);
        let tol = MAX_DEVIATION * u0.length().min(v0.length());
        let on = |p: DVec3, i: usize, j: usize| {
            (p - (a + u0 * i as f64 + v0 * j as f64)).length() <= tol
        };
        // First row: each quad starts on the previous one's right edge
        let mut m = 1;
        let mut prev = first;
        while let Some(next) = q(s + m) {
            if next[0] != prev[1]
                || next[3] != prev[2]
                || !on(next[1], m + 1, 0)
                || !on(next[2], m + 1, 1)
            {
                break;
            }
            prev = next;
            m += 1;
        }
        // Further rows: each quad on the one below's top edge and its left neighbour's
        let mut k = 1;
        'rows: while s + (k + 1) * m <= n {
            for i in 0..m {
                let (Some(here), Some(below)) = (q(s + k * m + i), q(s + (k - 1) * m + i)) else {
                    break 'rows;
                };
                let left_ok = i == 0
                    || q(s + k * m + i - 1).is_some_and(|l| here[0] == l[1] && here[3] == l[2]);
                let shared = here[0] == below[3] && here[1] == below[2] && left_ok;
                if !shared || !on(here[2], i + 1, k + 1) || !on(here[3], i, k + 1) {
                    break 'rows;
                }
            }
            k += 1;
        }
        let sheet = if m * k >= MIN_SHEET {
            make_sheet(&q, prepared, s, m, k)
        } else {
            None
        };
        if let Some(sheet) = sheet {
            units.push(Unit::Sheet(s, sheet));
            s += m * k;
        } else {
            // Not a grid: the first row's quads one by one
            units.extend((s..s + m).map(Unit::Polygon));
            s += m;
        }
    }
    units
}

/// The sheet of the `m × k` quads from `s`, if they lie near enough to a lattice.
fn make_sheet<Q: Fn(usize) -> Option<[DVec3; 4]>>(
    q: &Q,
    prepared: &[Option<Prepared>],
    s: usize,
    m: usize,
    k: usize,
) -> Option<Sheet> {
    let at = |i: usize, j: usize| q(s + j * m + i);
    // Lattice point P(i, j), 0 ≤ i ≤ m, 0 ≤ j ≤ k
    let point = |i: usize, j: usize| -> Option<DVec3> {
        let (ci, vi) = if i < m { (i, 0) } else { (m - 1, 1) };
        Some(if j < k {
            at(ci, j)?[vi]
        } else {
            at(ci, k - 1)?[3 - vi]
        })
    };
    let a = point(0, 0)?;
    let u = (point(m, 0)? - a) / m as f64;
    let v = (point(0, k)? - a) / k as f64;
    let (lu, lv) = (u.length(), v.length());
    if !(lu > 0.0 && lv > 0.0 && u.cross(v).length() > 1e-6 * lu * lv) {
        return None;
    }
    let ideal = |i: f64, j: f64| a + u * i + v * j;
    // Every lattice point near the ideal lattice
    let mut tau: f64 = 0.0;
    for j in 0..=k {
        for i in 0..=m {
            tau = tau.max((point(i, j)? - ideal(i as f64, j as f64)).length());
        }
    }
    if !(tau <= MAX_DEVIATION * lu.min(lv)) {
        return None;
    }
    // The union of the quads' bounds
    let mut lo = DVec3::INFINITY;
    let mut hi = DVec3::NEG_INFINITY;
    for id in s..s + m * k {
        let b = prepared.get(id).copied().flatten()?.bounds;
        lo = lo.min(b[0]);
        hi = hi.max(b[1]);
    }
    Some(Sheet {
        a,
        u,
        v,
        m: m as u32,
        k: k as u32,
        // A guard for the rounding of the ideal points and of the distances
        tau: tau * (1.0 + 1e-9) + 1e-15 * (a.abs().max_element() + lu * m as f64 + lv * k as f64),
        bounds: [lo, hi],
    })
}

impl Sheet {
    /// Number of quads, `m·k`.
    pub(in crate::accel) fn len(&self) -> usize {
        self.m as usize * self.k as usize
    }

    /// Number of quads a row, `m`.
    pub(in crate::accel) fn cols(&self) -> u32 {
        self.m
    }

    /// Number of rows, `k`.
    pub(in crate::accel) fn rows(&self) -> u32 {
        self.k
    }

    /// The ideal lattice `(A, u, v)` (relative to the centre it was found in).
    pub(in crate::accel) fn lattice(&self) -> [DVec3; 3] {
        [self.a, self.u, self.v]
    }

    /// The largest distance of a lattice point from the ideal lattice (with its guard).
    pub(in crate::accel) fn deviation(&self) -> f64 {
        self.tau
    }

    /// The quads the line may hit, as ranges of columns `i` and rows `j`.
    ///
    /// On `d^⊥` (primes: projected; the line is the origin) the line meets the ideal
    /// lattice at `(s, t)`, `a + s u' + t v' = 0`:
    ///
    /// ```text
    /// det = u' × v',   s = (v' × a)/det,   t = (a × u')/det
    /// ```
    ///
    /// The crossing test accepts quad `(i, j)` only if no edge function has the outside
    /// sign; with each computed `E` within `δE ≤ 20ε R²` of its exact value (`R` bounds the
    /// projected vertices' distance from the origin) and the quad's edges within `τ` of
    /// the ideal lattice lines, the origin then lies within `δE/|e'| + τ(1 + 2R/|e'|)` of
    /// each edge line of the ideal cell (`|e'|` = the projected edge's length), that is
    ///
    /// ```text
    /// s ∈ [i − w_s, i + 1 + w_s],  w_s = (δE + τ(|v'| + 2R))/|det|     (t, w_t alike)
    /// δE = 10⁻⁹ R²,   R = |a|₁ + m|u'|₁ + k|v'|₁ + τ
    /// ```
    ///
    /// The lengths are the 1-norms `|x| + |y| ≥ √(x² + y²)`: larger bounds only widen the
    /// window, and need no square roots. `10⁻⁹` is seven orders above `20ε` and also
    /// covers the rounding of `(s, t)`, computed with the one reciprocal `1/det` (its
    /// rounding adds `2ε` relative to `|v' × a|/|det| ≤ R²/|det|`). The window is one or
    /// two cells a side; a grazing line (tiny `det`, huge windows, `1/det` overflowing)
    /// or NaN gives the whole sheet.
    #[inline(always)]
    pub(super) fn window(&self, q: &Query) -> (Range<u32>, Range<u32>) {
        self.window_projected(
            q.project(self.a),
            q.project_dir(self.u),
            q.project_dir(self.v),
            self.tau,
        )
    }

    /// [`Sheet::window`] from the projections on `d^⊥`, relative to the line, of `A`
    /// (`a`), `u` and `v`, for a lattice deviation `tau` (at least [`Sheet::deviation`];
    /// more if the projections carry more rounding than the query's).
    #[inline(always)]
    pub(in crate::accel) fn window_projected(
        &self,
        a: (f64, f64),
        pu: (f64, f64),
        pv: (f64, f64),
        tau: f64,
    ) -> (Range<u32>, Range<u32>) {
        self.projected(pu, pv, tau).window(a)
    }

    /// What [`Sheet::window_projected`] computes from `u`'s and `v`'s projections alone,
    /// for many lines of one direction.
    #[inline(always)]
    pub(in crate::accel) fn projected(
        &self,
        pu: (f64, f64),
        pv: (f64, f64),
        tau: f64,
    ) -> ProjectedSheet {
        let det = pu.0 * pv.1 - pu.1 * pv.0;
        let norm = |p: (f64, f64)| p.0.abs() + p.1.abs();
        ProjectedSheet {
            pu,
            pv,
            // One division per sheet visit (it was four, and three square roots)
            inv_det: 1.0 / det,
            nu: norm(pu),
            nv: norm(pv),
            tau,
            m: self.m,
            k: self.k,
        }
    }
}

/// A sheet projected on the plane `d^⊥` of one direction: [`Sheet::window`] for any
/// line of that direction from the projection of `A` relative to the line.
#[derive(Clone, Copy, Debug)]
pub(in crate::accel) struct ProjectedSheet {
    pu: (f64, f64),
    pv: (f64, f64),
    inv_det: f64,
    nu: f64,
    nv: f64,
    tau: f64,
    m: u32,
    k: u32,
}

impl ProjectedSheet {
    /// The window of [`Sheet::window`] for the line to which `A` projects at `a`.
    #[inline(always)]
    pub(in crate::accel) fn window(&self, a: (f64, f64)) -> (Range<u32>, Range<u32>) {
        let (s, t) = self.crossing(a);
        let (ws, wt) = self.half_widths(a.0.abs() + a.1.abs());
        (cells(s, ws, self.m), cells(t, wt, self.k))
    }

    /// The crossing `(s, t)` of the line with the ideal lattice ([`Sheet::window`]), `A`
    /// projecting at `a`.
    #[inline(always)]
    pub(in crate::accel) fn crossing(&self, a: (f64, f64)) -> (f64, f64) {
        let (pu, pv, inv_det) = (self.pu, self.pv, self.inv_det);
        let s = (pv.0 * a.1 - pv.1 * a.0) * inv_det;
        let t = (a.0 * pu.1 - a.1 * pu.0) * inv_det;
        (s, t)
    }

    /// The window's allowances `(w_s, w_t)` ([`Sheet::window`]) for a line to which `A`
    /// projects at 1-norm `na`; they grow with `na`.
    #[inline(always)]
    pub(in crate::accel) fn half_widths(&self, na: f64) -> (f64, f64) {
        let (inv_det, tau) = (self.inv_det, self.tau);
        let r = na + f64::from(self.m) * self.nu + f64::from(self.k) * self.nv + tau;
        let de = WINDOW_SLACK * r * r;
        let ws = (de + tau * (self.nv + 2.0 * r)) * inv_det.abs() + WINDOW_SLACK;
        let wt = (de + tau * (self.nu + 2.0 * r)) * inv_det.abs() + WINDOW_SLACK;
        (ws, wt)
    }

    /// The projections `u'`, `v'` and `1/det` the crossing is computed from.
    #[inline(always)]
    pub(in crate::accel) fn axes(&self) -> ((f64, f64), (f64, f64), f64) {
        (self.pu, self.pv, self.inv_det)
    }

    /// The 1-norms `|u'|₁`, `|v'|₁`.
    #[inline(always)]
    pub(in crate::accel) fn norms(&self) -> (f64, f64) {
        (self.nu, self.nv)
    }
}

/// The cells `i < n` with `c ∈ [i − w, i + 1 + w]`; all of them when `c` or `w` is not
/// finite.
#[inline(always)]
fn cells(c: f64, w: f64, n: u32) -> Range<u32> {
    if !(c.is_finite() && w.is_finite()) {
        return 0..n;
    }
    let nf = f64::from(n);
    // i from ⌈c − 1 − w⌉ to ⌊c + w⌋, clamped into [0, n − 1]; the casts are exact floors
    // of non-negative numbers.
    let lo = (c - 1.0 - w).clamp(0.0, nf);
    let lo = lo as u32 + u32::from(f64::from(lo as u32) < lo);
    let hi = c + w;
    let hi = if hi >= 0.0 {
        hi.min(nf - 1.0) as u32 + 1
    } else {
        0
    };
    lo..hi.max(lo)
}
