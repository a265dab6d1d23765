//! Every hit of every line of a bundle of parallel lines in 3D, without a tree: the scene's
//! vertices are projected once per bundle on the plane `d^⊥`, and each polygon is tested
//! only against the lattice points inside its projected bounds (a rasteriser whose pixels
//! are the bundle's lines).
//!
//! # Method
//!
//! A [`GlobalBundle3`] has the direction `d`, the frame `(e₁, e₂)` of `d^⊥` and lattice
//! points `x = (a, b)` in rows; its line through `x` is `c + a e₁ + b e₂ + t d` (`c` the
//! sphere's centre). Per bundle:
//!
//! ```text
//! 1. project   P_v = (e₁·(v − c), e₂·(v − c)),  D_v = d·(v − c)    each distinct vertex once
//! 2. cover     per polygon, the lattice points in its projected bounds grown by δ
//! 3. cross     E_k = (P_k − x) × (P_{k+1} − x)                     (2D cross product)
//!              hit ⇔ no two E_k of opposite signs, and not all E_k = 0
//! 4. depth     t = (n·(p₀ − c) − a n·e₁ − b n·e₂) / n·d,  clamped into [min D_v − δ, max D_v + δ]
//! ```
//!
//! Step 3 is the closed test of [`super::Bvh3`] (module docs there) with the line at `x`:
//! the polygon is closed, a line in its plane (all `E_k = 0`, or `n·d = 0`) is ignored.
//! It is **watertight** for the same reason: vertices with the same coordinates are one
//! vertex here (found once, by their bits, when the scene is prepared), projected once, so
//! the edge `b → a` of a neighbour gets `(P_b − x) × (P_a − x)`, exactly the negation of
//! `(P_a − x) × (P_b − x)` (IEEE rounding is symmetric under negation): a line near a
//! shared edge is caught by at least one of its two polygons. The differences `P − x` are
//! taken first, so near a shared vertex the rounding of each `E_k` is relative to the
//! distances of the vertices from the line, and the signs around the vertex keep turning:
//! no line slips through the seams of a closed mesh (tested on a closed cube mesh far from
//! the origin). The margin `δ = 10⁻⁹ (‖c‖∞ + r + scale)` (scale: the largest vertex
//! coordinate) is many orders of magnitude above the rounding of the projections, so the
//! covered points always contain every point step 3 accepts.
//!
//! The arithmetic differs from [`super::Bvh3::all_hits`]' (which projects relative to the
//! foot of each line), so the two agree on which polygons a line meets except for lines
//! within rounding (~10⁻¹⁶ of the scene's size) of a polygon's edge, where each is
//! watertight on its own; `t` agrees to rounding for lines that are not grazing, and both
//! clamp it into the polygon's extent, so it is always finite (tests compare them on
//! random scenes and bundles).
//!
//! Hits are bucketed per line by a counting sort and each line's hits sorted by `(t,
//! prim)` like [`super::Bvh3::all_hits`]. A bundle of `m` lines over `n` polygons costs
//! `O(V + n + m + candidates)` (`V` distinct vertices): no per-line tree walk, so `m` is
//! chosen large enough that the per-polygon setup is amortised.

use alloc::vec::Vec;

use crate::geom::DVec3;
use crate::lines::GlobalBundle3;

use super::{Hit3, bvh3::prepare, sort_hits};

/// Relative size of the covering margin `δ` (module docs).
const MARGIN: f64 = 1e-9;

/// A polygon list prepared for bundles of parallel lines: distinct vertices, each
/// polygon's vertex indices, unit normal and a point of its plane.
#[derive(Clone, Debug)]
pub struct ParallelRaster3 {
    /// The distinct vertices (by their bits).
    vertices: Vec<DVec3>,
    /// Polygon `k`'s vertices are `vertices[corner[k]]` for the entries
    /// `corners[first[k]..first[k + 1]]`.
    first: Vec<u32>,
    corners: Vec<u32>,
    /// Per hittable polygon: its index in the input, unit normal and mean vertex.
    prim: Vec<u32>,
    normal: Vec<DVec3>,
    p0: Vec<DVec3>,
    /// The largest coordinate magnitude of the vertices (the margin's scale).
    scale: f64,
}

/// The hits of the lines of one bundle, bucketed per line (the caller's scratch space,
/// reused from bundle to bundle without allocating once it has grown).
#[derive(Clone, Debug, Default)]
pub struct BundleHits3 {
    /// Projected vertices `P_v` and depths `D_v` of the current bundle.
    projected: Vec<[f64; 2]>,
    depth: Vec<f64>,
    /// Per row: `b`, `first` (in units of `h`), number of points, index of its first line.
    row_b: Vec<f64>,
    row_first: Vec<f64>,
    row_count: Vec<u32>,
    row_line: Vec<u32>,
    /// The hits as found: `(line, hit)`.
    found: Vec<(u32, Hit3)>,
    /// Line `k`'s hits are `hits[start[k]..start[k + 1]]`.
    start: Vec<u32>,
    hits: Vec<Hit3>,
}

impl ParallelRaster3 {
    /// Prepares the polygons `points[first..first + count]`, one per entry of `polygons`
    /// (hits report indices into `polygons`). Polygons that can never be hit (as for
    /// [`super::Bvh3::build`]: fewer than three vertices, non-finite ones, zero area) and
    /// ranges that leave `points` are left out; only the first `2³²` polygons and vertices
    /// are considered.
    #[must_use]
    pub fn new(points: &[DVec3], polygons: &[(usize, usize)]) -> Self {
        let points = &points[..points.len().min(u32::MAX as usize)];
        // Distinct vertices: points sorted by their bits, equal runs merged
        let key = |p: &DVec3| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
        let mut order: Vec<u32> = (0..points.len() as u32).collect();
        order.sort_unstable_by_key(|&i| key(&points[i as usize]));
        let mut id = alloc::vec![0u32; points.len()];
        let mut vertices = Vec::new();
        for (k, &i) in order.iter().enumerate() {
            let p = points[i as usize];
            if k == 0 || key(&points[order[k - 1] as usize]) != key(&p) {
                vertices.push(p);
            }
            id[i as usize] = vertices.len() as u32 - 1;
        }
        let mut raster = Self {
            vertices,
            first: alloc::vec![0],
            corners: Vec::new(),
            prim: Vec::new(),
            normal: Vec::new(),
            p0: Vec::new(),
            scale: 0.0,
        };
        for (&(first, count), index) in polygons.iter().zip(0..=u32::MAX) {
            let Some(verts) = first
                .checked_add(count)
                .and_then(|end| points.get(first..end))
            else {
                continue;
            };
            let Some(p) = prepare(DVec3::ZERO, verts) else {
                continue;
            };
            raster.corners.extend(&id[first..first + count]);
            raster.first.push(raster.corners.len() as u32);
            raster.prim.push(index);
            raster.normal.push(p.n);
            raster.p0.push(p.p0);
            let size = p.bounds[0].abs().max(p.bounds[1].abs()).max_element();
            raster.scale = raster.scale.max(size);
        }
        raster
    }

    /// Number of distinct vertices.
    #[must_use]
    pub fn vertex_count(&self) -> usize {
        self.vertices.len()
    }

    /// Finds every hit of every line of `bundle` into `out`: afterwards
    /// [`BundleHits3::line_hits`]`(k)` holds the hits of line `k` (rows in order, points
    /// in order within a row; [`BundleHits3::line_point`]), sorted by `t` then `prim`.
    pub fn cast(&self, bundle: &GlobalBundle3, out: &mut BundleHits3) {
        let c = bundle.sphere().center;
        let r = bundle.sphere().radius;
        let (e1, e2) = bundle.frame();
        let d = bundle.dir();
        let h = bundle.spacing();
        let inv_h = 1.0 / h;
        let delta = MARGIN * (c.abs().max_element() + r + self.scale);
        // The rows of lattice points and the index of each row's first line
        out.row_b.clear();
        out.row_first.clear();
        out.row_count.clear();
        out.row_line.clear();
        let mut lines = 0u32;
        for k in 0..bundle.rows() {
            let row = bundle.row(k);
            out.row_b.push(row.b);
            out.row_first.push(row.first);
            out.row_count.push(row.count);
            out.row_line.push(lines);
            lines = lines.saturating_add(row.count);
        }
        out.row_line.push(lines);
        // Every distinct vertex projected once
        out.projected.clear();
        out.depth.clear();
        for &v in &self.vertices {
            let w = v - c;
            out.projected.push([e1.dot(w), e2.dot(w)]);
            out.depth.push(d.dot(w));
        }
        // Each polygon against the lattice points of its projected bounds
        out.found.clear();
        let rows = i64::from(bundle.rows());
        let first_row_b = out.row_b.first().copied().unwrap_or(0.0);
        let BundleHits3 {
            projected,
            depth,
            row_b,
            row_first,
            row_count,
            row_line,
            found,
            ..
        } = out;
        for (k, ((&index, &n), &p0)) in self.prim.iter().zip(&self.normal).zip(&self.p0).enumerate()
        {
            let nd = n.dot(d);
            if nd == 0.0 {
                continue;
            }
            let corners = &self.corners[self.first[k] as usize..self.first[k + 1] as usize];
            let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
            let (mut near, mut far) = (f64::INFINITY, f64::NEG_INFINITY);
            for &v in corners {
                let p = projected[v as usize];
                lo = [lo[0].min(p[0]), lo[1].min(p[1])];
                hi = [hi[0].max(p[0]), hi[1].max(p[1])];
                near = near.min(depth[v as usize]);
                far = far.max(depth[v as usize]);
            }
            // Rows whose b lies in [lo₁ − δ, hi₁ + δ] (rows are h apart from the first)
            let row_lo = ceil_index((lo[1] - delta - first_row_b) * inv_h).max(0);
            let row_hi = floor_index((hi[1] + delta - first_row_b) * inv_h).min(rows - 1);
            if row_hi < row_lo {
                continue;
            }
            let (x_lo, x_hi) = ((lo[0] - delta) * inv_h, (hi[0] + delta) * inv_h);
            let (t0, t1) = (near - delta, far + delta);
            let k0 = n.dot(p0 - c);
            let (k1, k2) = (n.dot(e1), n.dot(e2));
            let Some(&last) = corners.last() else {
                continue;
            };
            for row in row_lo as usize..=row_hi as usize {
                let (b, first, count) = (row_b[row], row_first[row], row_count[row]);
                let q_lo = ceil_index(x_lo - first).max(0);
                let q_hi = floor_index(x_hi - first).min(i64::from(count) - 1);
                for q in q_lo..=q_hi {
                    let a = (first + q as f64) * h;
                    if !crosses(projected, corners, last, a, b) {
                        continue;
                    }
                    let t = (k0 - a * k1 - b * k2) / nd;
                    if t.is_nan() {
                        continue;
                    }
                    // `+ 0.0` turns −0 into +0.
                    let t = t.max(t0).min(t1) + 0.0;
                    if t.is_finite() {
                        found.push((row_line[row] + q as u32, Hit3 { t, prim: index }));
                    }
                }
            }
        }
        // Bucket the hits per line (a counting sort), then sort each line's
        out.start.clear();
        out.start.resize(lines as usize + 2, 0);
        for &(line, _) in &out.found {
            out.start[line as usize + 2] += 1;
        }
        for k in 2..out.start.len() {
            out.start[k] += out.start[k - 1];
        }
        out.hits.clear();
        out.hits.resize(out.found.len(), Hit3 { t: 0.0, prim: 0 });
        for &(line, hit) in &out.found {
            let slot = &mut out.start[line as usize + 1];
            out.hits[*slot as usize] = hit;
            *slot += 1;
        }
        out.start.pop();
        for k in 0..lines as usize {
            let (s, e) = (out.start[k] as usize, out.start[k + 1] as usize);
            sort_hits(&mut out.hits[s..e]);
        }
    }
}

/// Whether the line through `x = (a, b)` crosses the closed polygon of the projected
/// vertices `corners` (`last` = the last of them): no two edge functions of opposite
/// signs, and not all of them zero.
/// `⌊x⌋` as an integer, for the lattice indices of a bundle (`|x|` far below `2⁶³`; `as`
/// saturates, and NaN gives 0, which the callers' range checks absorb).
#[inline(always)]
fn floor_index(x: f64) -> i64 {
    let i = x as i64;
    if (i as f64) > x { i - 1 } else { i }
}

/// `⌈x⌉` as an integer (see [`floor_index`]).
#[inline(always)]
fn ceil_index(x: f64) -> i64 {
    let i = x as i64;
    if (i as f64) < x { i + 1 } else { i }
}

#[inline(always)]
fn crosses(projected: &[[f64; 2]], corners: &[u32], last: u32, a: f64, b: f64) -> bool {
    let (mut pos, mut neg) = (false, false);
    let p = projected[last as usize];
    let mut u = (p[0] - a, p[1] - b);
    for &v in corners {
        let p = projected[v as usize];
        let w = (p[0] - a, p[1] - b);
        let s = u.0 * w.1 - u.1 * w.0;
        pos |= s > 0.0;
        neg |= s < 0.0;
        if pos && neg {
            return false;
        }
        u = w;
    }
    pos != neg
}

impl BundleHits3 {
    /// Empty scratch space.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Number of lines of the last bundle cast.
    #[must_use]
    pub fn lines(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// The hits of line `k` of the last bundle cast, sorted by `t` then `prim` (empty for
    /// `k` beyond the bundle).
    #[must_use]
    pub fn line_hits(&self, k: usize) -> &[Hit3] {
        match (self.start.get(k), self.start.get(k + 1)) {
            (Some(&s), Some(&e)) => &self.hits[s as usize..e as usize],
            _ => &[],
        }
    }

    /// The lattice point `(a, b)` of line `k` of the last bundle cast (of `bundle`, the
    /// one cast), or `None` beyond the bundle: pass it to [`GlobalBundle3::line_at`].
    #[must_use]
    pub fn line_point(&self, bundle: &GlobalBundle3, k: usize) -> Option<(f64, f64)> {
        let k = u32::try_from(k).ok()?;
        let row = self.row_line.partition_point(|&s| s <= k).checked_sub(1)?;
        let q = k - self.row_line[row];
        (q < *self.row_count.get(row)?).then(|| {
            let a = (self.row_first[row] + f64::from(q)) * bundle.spacing();
            (a, self.row_b[row])
        })
    }
}

#[cfg(all(test, feature = "std"))]
mod tests;
