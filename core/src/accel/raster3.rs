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
//! 2. cover     per group of polygons, the lattice points in its projected bounds grown by δ
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
//! # Groups
//!
//! Loose polygons are set up per bundle in *groups*: runs of consecutive polygons with at
//! most 8 polygons and 8 distinct vertices whose bounding ball is at most 1.5 times the
//! largest of their own (a cube's 6 faces: 8 vertices, a ball 1.22 times a face's). A
//! group's bounds are those of its distinct projected vertices, and every lattice point in
//! them is tested against every polygon of the group by the exact test of step 3: the
//! hits are the same as polygon by polygon, and the bounds and row range are paid once per
//! group (the 512-cube room: 512 groups instead of 3,072 polygons).
//!
//! A group of at most 8 vertices is *compact* (unless a polygon walks an edge twice): at
//! each candidate its distinct edges' functions are computed once (a cube: 12, not 24),
//! a polygon's `E_k` being its edge's, negated where it walks the edge backwards, which is
//! exact (`(P_b − x) × (P_a − x)` has the same two rounded products as `(P_a − x) × (P_b −
//! x)`, subtracted the other way). The signs go into bit masks and each polygon's test is
//! two `AND`s of one word of signs with two masks of the polygon's edges
//! (`polygons_crossed`), without a branch per polygon (which polygons a candidate crosses
//! is a coin toss); a crossed polygon's depths are read from the group's gathered
//! vertices. For a group of a cube's 12 edges and 6 faces the ends of the edges are
//! gathered once per bundle, at the group's first candidate, into arrays by
//! edge (`EdgeEnds`), so that each candidate's edge functions are a loop over arrays
//! instead of a gather through the edges' vertex indices: the same differences `P − x`
//! and products, so the same bits (the 512-cube room: 415 → 399 million instructions for
//! 200,000 lines).
//!
//! # Sheets
//!
//! A face cut into a grid of quads is held as one item, a *sheet* (found as
//! [`super::Bvh3`] finds them: consecutive quads sharing bit-identical vertices, near a
//! lattice `A + i u + j v`). Per bundle a sheet costs `O(1)`: the lattice points inside
//! its projected parallelogram (grown by its deviation from the ideal lattice and the
//! margin) are its candidates, and each candidate tests only the quads of the window about
//! its crossing of the lattice, by the same error bound as the BVH's sheets
//! (`Sheet::window_projected`, with the rounding of these projections, `10⁻¹² (|A − c|₁ +
//! m|u|₁ + k|v|₁ + r)`, added to the deviation). A quad's vertices are projected by the
//! same arithmetic as every other vertex, so the seams stay watertight: all the sheets'
//! distinct vertices once per bundle when they are at most 4 per line of the bundle
//! (the room's walls: 726 for 1,024 lines), otherwise a tested quad's four at each
//! candidate (the 99,846-patch cube: about 100,000 vertices).
//!
//! A crossed quad's `t` needs its corners' depths only for the clamp (step 4), which
//! leaves `t` unchanged unless the line grazes the quad: where `t` lies inside the depths
//! of the ideal cell by an allowance for the sheet's deviation and rounding, the corners'
//! depths are not computed (`SheetCast::quad_hit`; the same bits).
//!
//! Most candidates need neither the window nor the closed test: along a row of the
//! lattice the crossing with the sheet's ideal lattice is affine in `a`, and a candidate
//! whose crossing lies inside a cell by more than the window's error bound is a hit of
//! that cell's quad alone, one outside the sheet by as much a hit of none; only those
//! within the bound of a cell's side take the window and the closed test (`sheets.rs`,
//! which proves that the hits are the same, bit for bit).
//!
//! Hits are bucketed per line by a counting sort and each line's hits sorted by `(t,
//! prim)` like [`super::Bvh3::all_hits`]. A bundle of `m` lines over `n` loose polygons
//! (not in a sheet, in `g` groups) and `s` sheets costs `O(V + n + s + m + candidates)`
//! (`g` bounds and row ranges; `V` distinct
//! vertices of the loose polygons): no per-line tree walk, so `m` is chosen large enough
//! that the per-item setup is amortised.

use alloc::vec::Vec;

use crate::geom::DVec3;
use crate::lines::GlobalBundle3;

use super::bvh3::sheet::{Sheet, Unit, find_units};
use super::bvh3::{origin_in_closed_polygon, prepare};
use super::{Hit3, sort_hits};

/// Relative size of the covering margin `δ` (module docs).
const MARGIN: f64 = 1e-9;

/// Relative size of the rounding of a sheet's projected lattice (module docs, "Sheets").
const SHEET_ROUNDING: f64 = 1e-12;

/// A polygon list prepared for bundles of parallel lines: sheets of quads, and the other
/// polygons by their distinct vertices, unit normal and a point of their plane.
#[derive(Clone, Debug)]
pub(crate) struct ParallelRaster3 {
    /// The distinct vertices of the polygons outside sheets (by their bits).
    vertices: Vec<DVec3>,
    /// Polygon `k`'s vertices are `vertices[corner[k]]` for the entries
    /// `corners[first[k]..first[k + 1]]`.
    first: Vec<u32>,
    corners: Vec<u32>,
    /// Per polygon outside sheets: its index in the input, unit normal and mean vertex.
    prim: Vec<u32>,
    normal: Vec<DVec3>,
    p0: Vec<DVec3>,
    /// Runs of consecutive loose polygons set up together per bundle (module docs,
    /// "Groups").
    groups: Vec<Group>,
    group_vertices: Vec<u32>,
    /// The distinct edges `[u, v]` (`u < v`) of compact groups, by the indices of their
    /// ends among the group's vertices.
    group_edges: Vec<[u8; 2]>,
    /// Per loose polygon of a compact group: its edges as the masks `[P, N]` of
    /// [`polygons_crossed`] (bit `e` of `P`: edge `e` of its group is one of the
    /// polygon's, walked from `u` to `v`, bit `32 + e`: walked from `v` to `u`; `N` the
    /// same with the walks swapped), and bit `v` of `vertex_mask` set when the group's
    /// vertex `v` is one of its corners.
    crossing_masks: Vec<[u64; 2]>,
    vertex_mask: Vec<u8>,
    /// The sheets, and their quads' vertices row by row (and apart, what only a hit reads:
    /// their unit normals and mean vertices).
    sheets: Vec<RasterSheet>,
    quads: Vec<[DVec3; 4]>,
    quad_planes: Vec<(DVec3, DVec3)>,
    /// The distinct vertices of all sheets' quads (by their bits), and each quad's
    /// corners among them: a bundle of at least a quarter as many lines projects them all
    /// once instead of a tested quad's four at each candidate (the same arithmetic, so
    /// the same bits).
    sheet_vertices: Vec<DVec3>,
    quad_corners: Vec<[u32; 4]>,
    /// The largest coordinate magnitude of the vertices (the margin's scale).
    scale: f64,
}

/// A run `polygons[first..end]` of loose polygons cast as one item (module docs,
/// "Groups").
#[derive(Clone, Copy, Debug)]
struct Group {
    first: u32,
    end: u32,
    /// Its distinct vertices are `group_vertices[vertices.0..vertices.1]`.
    vertices: (u32, u32),
    /// Whether it is *compact*: at most [`GROUP_VERTICES`] distinct vertices and no edge
    /// twice in a polygon; then its distinct edges are `group_edges[edges.0..edges.1]`
    /// and its polygons' edges the masks `edge_mask`, `reversed_mask`.
    compact: bool,
    edges: (u32, u32),
}

/// A group holds at most this many polygons and this many distinct vertices (a cube: 6
/// faces, 8 vertices).
const GROUP_POLYGONS: usize = 8;
const GROUP_VERTICES: usize = 8;

/// A polygon joins a group only while the group's ball stays within this factor of the
/// radius of its largest polygon's ball (a cube's ball is `√(3/2) ≈ 1.22` times a face's),
/// so a group's candidates are not many more than its polygons' own.
const GROUP_SPREAD: f64 = 1.5;

/// A sheet: its lattice, its first quad in `quads`, and the input index of its first quad
/// (quad `o = j·m + i` is input polygon `prim + o`).
#[derive(Clone, Copy, Debug)]
struct RasterSheet {
    sheet: Sheet,
    first_quad: u32,
    prim: u32,
    /// The unit normal of every quad, when all have the same bits (a flat grid): its
    /// products with the frame ([`PlaneDots`]) are then computed once per bundle.
    normal: Option<DVec3>,
}

/// The hits of the lines of one bundle, bucketed per line (the caller's scratch space,
/// reused from bundle to bundle without allocating once it has grown).
#[derive(Clone, Debug, Default)]
pub(crate) struct BundleHits3 {
    /// Projected vertices `P_v` and depths `D_v` of the current bundle.
    projected: Vec<[f64; 3]>,
    /// The sheets' vertices projected, when the bundle projects them all.
    sheet_projected: Vec<[f64; 3]>,
    rows: Rows,
    /// The hits as found, counted per line as they are pushed.
    found: FoundHits,
    /// Line `k`'s hits are `hits[start[k]..start[k + 1]]`.
    start: Vec<u32>,
    hits: Vec<Hit3>,
    /// Candidates of the sheets' row path by the exact path and inside a cell (tests).
    #[cfg(test)]
    row_paths: [usize; 2],
}

/// The hits of a bundle as found, `(line, hit)`, and per line their number (at
/// `per_line[line + 2]`, the layout the counting sort of [`ParallelRaster3::cast_by`]
/// turns into its bucket starts): counted as they are pushed, which spares that sort a
/// pass over the hits.
#[derive(Clone, Debug, Default)]
pub(crate) struct FoundHits {
    list: Vec<(u32, Hit3)>,
    per_line: Vec<u32>,
}

impl FoundHits {
    /// Empties the list, for a bundle of `lines` lines.
    fn reset(&mut self, lines: usize) {
        self.list.clear();
        self.per_line.clear();
        self.per_line.resize(lines + 2, 0);
    }

    /// A hit of line `line` (below the bundle's line count).
    #[inline(always)]
    fn push(&mut self, line: u32, hit: Hit3) {
        if let Some(count) = self.per_line.get_mut(line as usize + 2) {
            *count += 1;
        }
        self.list.push((line, hit));
    }
}

/// The rows of a bundle's lattice points: per row, `b`, `first` (in units of `h`), the
/// number of points and the index of its first line (one more entry: the line count).
#[derive(Clone, Debug, Default)]
struct Rows {
    b: Vec<f64>,
    first: Vec<f64>,
    count: Vec<u32>,
    line: Vec<u32>,
}

/// What every test of one bundle shares: the frame, the lattice and the margin.
#[derive(Clone, Copy, Debug)]
struct Frame {
    c: DVec3,
    e1: DVec3,
    e2: DVec3,
    d: DVec3,
    h: f64,
    inv_h: f64,
    delta: f64,
    /// `b` of the first row, and the number of rows.
    first_row_b: f64,
    rows: i64,
    /// The largest `|a|` and `|b|` of the bundle's lattice points (as computed for the
    /// candidates: `(first + q) h` and the rows' `b`).
    a_max: f64,
    b_max: f64,
}

/// A unit normal's products with a bundle's axes: `n·d`, `n·e₁`, `n·e₂`.
#[derive(Clone, Copy, Debug)]
struct PlaneDots {
    d: f64,
    e1: f64,
    e2: f64,
}

impl Frame {
    /// `(e₁·(v − c), e₂·(v − c), d·(v − c))`: the projection and depth of a vertex, by the
    /// one arithmetic every test uses (watertightness needs equal bits for equal vertices).
    #[inline(always)]
    fn project(&self, v: DVec3) -> [f64; 3] {
        let w = v - self.c;
        [self.e1.dot(w), self.e2.dot(w), self.d.dot(w)]
    }

    /// [`Frame::project`] without the depth (its third entry 0): the same bits for the
    /// first two.
    #[inline(always)]
    fn project_across(&self, v: DVec3) -> [f64; 3] {
        let w = v - self.c;
        [self.e1.dot(w), self.e2.dot(w), 0.0]
    }

    /// The depth of [`Frame::project`] alone (the same bits).
    #[inline(always)]
    fn depth(&self, v: DVec3) -> f64 {
        self.d.dot(v - self.c)
    }

    /// [`Frame::plane_t_with`] when it needs no clamp: `t` if `low − δ ≤ t ≤ high + δ`,
    /// for bounds `low ≥ near` and `high ≤ far` of the polygon's depths (then `t` is in
    /// `[near − δ, far + δ]`, where the clamp leaves it unchanged: the same bits), else
    /// `None` (the caller takes [`Frame::plane_t_with`]).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn plane_t_inside(
        &self,
        dots: PlaneDots,
        n: DVec3,
        p0: DVec3,
        a: f64,
        b: f64,
        low: f64,
        high: f64,
    ) -> Option<f64> {
        let t = self.plane_t_unclamped(dots, n, p0, a, b)?;
        // Fails for NaN; `+ 0.0` as in `plane_t_with`
        let t = (t >= low - self.delta && t <= high + self.delta).then_some(t + 0.0)?;
        t.is_finite().then_some(t)
    }

    /// The parameter of the hit of the line through `(a, b)` with the plane of unit normal
    /// `n` through `p0`, unclamped (`None` if the line is parallel to the plane), from `n`'s
    /// [`Frame::plane_dots`]: `t = (n·(p₀ − c) − a n·e₁ − b n·e₂) / n·d`.
    #[inline(always)]
    fn plane_t_unclamped(
        &self,
        dots: PlaneDots,
        n: DVec3,
        p0: DVec3,
        a: f64,
        b: f64,
    ) -> Option<f64> {
        if dots.d == 0.0 {
            return None;
        }
        Some((n.dot(p0 - self.c) - a * dots.e1 - b * dots.e2) / dots.d)
    }

    /// The products of a unit normal `n` with the frame's axes.
    #[inline(always)]
    fn plane_dots(&self, n: DVec3) -> PlaneDots {
        PlaneDots {
            d: n.dot(self.d),
            e1: n.dot(self.e1),
            e2: n.dot(self.e2),
        }
    }

    /// The parameter of the hit of the line through `(a, b)` with the plane of unit normal
    /// `n` through `p0`, clamped into the depths `[near − δ, far + δ]` of the polygon;
    /// `None` if the line is parallel to the plane or `t` is not finite.
    #[inline(always)]
    fn plane_t(&self, n: DVec3, p0: DVec3, a: f64, b: f64, near: f64, far: f64) -> Option<f64> {
        self.plane_t_with(self.plane_dots(n), n, p0, a, b, near, far)
    }

    /// [`Frame::plane_t`] with `n`'s [`Frame::plane_dots`] already computed (the same
    /// products, so the same bits):
    ///
    /// ```text
    /// t = (n·(p₀ − c) − a n·e₁ − b n·e₂) / n·d
    /// ```
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn plane_t_with(
        &self,
        dots: PlaneDots,
        n: DVec3,
        p0: DVec3,
        a: f64,
        b: f64,
        near: f64,
        far: f64,
    ) -> Option<f64> {
        let t = self.plane_t_unclamped(dots, n, p0, a, b)?;
        if t.is_nan() {
            return None;
        }
        // `+ 0.0` turns −0 into +0.
        let t = lesser(greater(t, near - self.delta), far + self.delta) + 0.0;
        t.is_finite().then_some(t)
    }
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
        let polygons = &polygons[..polygons.len().min(u32::MAX as usize)];
        let range = |&(first, count): &(usize, usize)| {
            first
                .checked_add(count)
                .and_then(|end| points.get(first..end))
        };
        let prepared: Vec<_> = polygons
            .iter()
            .map(|p| range(p).and_then(|v| prepare(DVec3::ZERO, v)))
            .collect();
        let mut raster = Self {
            vertices: Vec::new(),
            first: alloc::vec![0],
            corners: Vec::new(),
            prim: Vec::new(),
            normal: Vec::new(),
            p0: Vec::new(),
            groups: Vec::new(),
            group_vertices: Vec::new(),
            group_edges: Vec::new(),
            crossing_masks: Vec::new(),
            vertex_mask: Vec::new(),
            sheets: Vec::new(),
            quads: Vec::new(),
            quad_planes: Vec::new(),
            sheet_vertices: Vec::new(),
            quad_corners: Vec::new(),
            scale: 0.0,
        };
        for p in prepared.iter().flatten() {
            let size = p.bounds[0].abs().max(p.bounds[1].abs()).max_element();
            raster.scale = raster.scale.max(size);
        }
        // Sheets where the polygons form grids (ranges that leave `points` are not hit)
        let valid: Vec<_> = polygons
            .iter()
            .map(|p| if range(p).is_some() { *p } else { (0, 0) })
            .collect();
        let mut loose = Vec::new();
        for unit in find_units(points, &valid, &prepared, DVec3::ZERO) {
            match unit {
                Unit::Polygon(id) => loose.push(id),
                Unit::Sheet(start, sheet) => {
                    // Every quad of a sheet is a hittable quad (`find_units` makes sheets of
                    // nothing else); should one not be, the sheet's polygons go loose
                    let ids = start..start + sheet.len();
                    let quads: Option<Vec<_>> = ids
                        .clone()
                        .map(|id| match (range(&valid[id]), prepared[id]) {
                            (Some(&[a, b, c, d]), Some(p)) => Some(([a, b, c, d], (p.n, p.p0))),
                            _ => None,
                        })
                        .collect();
                    let Some(quads) = quads else {
                        loose.extend(ids);
                        continue;
                    };
                    let bits = |n: DVec3| n.to_array().map(f64::to_bits);
                    let normal = quads
                        .first()
                        .map(|&(_, (n, _))| n)
                        .filter(|&n| quads.iter().all(|&(_, (m, _))| bits(m) == bits(n)));
                    raster.sheets.push(RasterSheet {
                        sheet,
                        first_quad: raster.quads.len() as u32,
                        prim: start as u32,
                        normal,
                    });
                    for (quad, plane) in quads {
                        raster.quads.push(quad);
                        raster.quad_planes.push(plane);
                    }
                }
            }
        }
        // The sheets' quads by their distinct vertices (sorted by their bits)
        let corners: Vec<DVec3> = raster.quads.iter().flatten().copied().collect();
        let mut corner_id = alloc::vec![0u32; corners.len()];
        let all = (0..corners.len() as u32).collect();
        distinct_by_bits(&corners, all, &mut raster.sheet_vertices, &mut corner_id);
        raster.quad_corners = corner_id
            .chunks_exact(4)
            .map(|c| [c[0], c[1], c[2], c[3]])
            .collect();
        // The other polygons by their distinct vertices (sorted by their bits)
        let used: Vec<u32> = loose
            .iter()
            .flat_map(|&id| {
                let (first, count) = valid[id];
                first as u32..(first + count) as u32
            })
            .collect();
        let mut id = alloc::vec![0u32; points.len()];
        distinct_by_bits(points, used, &mut raster.vertices, &mut id);
        for index in loose {
            let (first, count) = valid[index];
            let Some(p) = prepared[index] else { continue };
            raster.corners.extend(&id[first..first + count]);
            raster.first.push(raster.corners.len() as u32);
            raster.prim.push(index as u32);
            raster.normal.push(p.n);
            raster.p0.push(p.p0);
        }
        raster.crossing_masks = alloc::vec![[0; 2]; raster.prim.len()];
        raster.vertex_mask = alloc::vec![0; raster.prim.len()];
        raster.group_polygons();
        raster
    }

    /// The polygons' vertex indices, polygon `k`.
    fn polygon_corners(&self, k: usize) -> &[u32] {
        &self.corners[self.first[k] as usize..self.first[k + 1] as usize]
    }

    /// The ball of the bounding box of the distinct vertices `ids`: its centre and the
    /// largest distance of a vertex from it.
    fn ball(&self, ids: &[u32]) -> (DVec3, f64) {
        let (mut lo, mut hi) = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        for &v in ids {
            lo = lo.min(self.vertices[v as usize]);
            hi = hi.max(self.vertices[v as usize]);
        }
        let center = (lo + hi) * 0.5;
        let radius = ids.iter().fold(0.0f64, |r, &v| {
            r.max((self.vertices[v as usize] - center).length())
        });
        (center, radius)
    }

    /// Runs of consecutive loose polygons joined into groups (module docs, "Groups"):
    /// a polygon joins the current group while the group keeps at most
    /// [`GROUP_POLYGONS`] polygons and [`GROUP_VERTICES`] distinct vertices, and its ball
    /// at most [`GROUP_SPREAD`] times the largest ball of its polygons.
    fn group_polygons(&mut self) {
        let mut ids: Vec<u32> = Vec::new();
        let mut trial: Vec<u32> = Vec::new();
        let (mut first, mut largest) = (0usize, 0.0f64);
        for k in 0..self.prim.len() {
            let corners = self.polygon_corners(k);
            let own = self.ball(corners).1;
            trial.clear();
            trial.extend(&ids);
            for &v in corners {
                if !trial.contains(&v) {
                    trial.push(v);
                }
            }
            let joined = self.ball(&trial);
            let fits = k > first
                && k - first < GROUP_POLYGONS
                && trial.len() <= GROUP_VERTICES
                && joined.1 <= GROUP_SPREAD * largest.max(own);
            if fits {
                core::mem::swap(&mut ids, &mut trial);
                largest = largest.max(own);
                continue;
            }
            if k > first {
                self.push_group(first, k, &ids);
            }
            first = k;
            largest = own;
            ids.clear();
            for &v in self.polygon_corners(k) {
                if !ids.contains(&v) {
                    ids.push(v);
                }
            }
        }
        if self.prim.len() > first {
            self.push_group(first, self.prim.len(), &ids);
        }
    }

    /// Adds the group of loose polygons `first..end` with the distinct vertices `ids`,
    /// and if it is compact its distinct edges and its polygons' edge masks.
    fn push_group(&mut self, first: usize, end: usize, ids: &[u32]) {
        let start = self.group_vertices.len() as u32;
        self.group_vertices.extend(ids);
        let edge_start = self.group_edges.len();
        let mut compact = ids.len() <= GROUP_VERTICES;
        for k in first..end {
            if !compact {
                break;
            }
            let corners = &self.corners[self.first[k] as usize..self.first[k + 1] as usize];
            let local = |v: u32| ids.iter().position(|&w| w == v).unwrap_or(0) as u8;
            let (mut mask, mut reversed, mut vertices) = (0u32, 0u32, 0u8);
            let mut a = corners.last().map_or(0, |&v| local(v));
            for &v in corners {
                let b = local(v);
                vertices |= 1 << (b % 8);
                // A repeated vertex gives `E = 0` exactly: no edge
                if a != b {
                    let edge = [a.min(b), a.max(b)];
                    let e = match self.group_edges[edge_start..]
                        .iter()
                        .position(|&x| x == edge)
                    {
                        Some(e) => e,
                        None => {
                            self.group_edges.push(edge);
                            self.group_edges.len() - 1 - edge_start
                        }
                    };
                    // At most 28 edges join 8 vertices; an edge walked twice is not compact
                    compact &= mask & (1 << e) == 0;
                    mask |= 1 << e;
                    reversed |= u32::from(a > b) << e;
                }
                a = b;
            }
            let (forward, backward) = (u64::from(mask & !reversed), u64::from(mask & reversed));
            self.crossing_masks[k] = [forward | (backward << 32), backward | (forward << 32)];
            self.vertex_mask[k] = vertices;
        }
        if !compact {
            self.group_edges.truncate(edge_start);
        }
        self.groups.push(Group {
            first: first as u32,
            end: end as u32,
            vertices: (start, self.group_vertices.len() as u32),
            compact,
            edges: (edge_start as u32, self.group_edges.len() as u32),
        });
    }

    /// Number of distinct vertices of the polygons outside sheets.
    #[must_use]
    #[cfg(test)]
    pub fn vertex_count(&self) -> usize {
        self.vertices.len()
    }

    /// Number of sheets.
    #[must_use]
    #[cfg(test)]
    pub fn sheet_count(&self) -> usize {
        self.sheets.len()
    }

    /// Number of items a bundle sets up: sheets and polygons outside them (the `O(n)`
    /// part of a bundle's cost).
    #[must_use]
    pub fn items(&self) -> usize {
        self.sheets.len() + self.prim.len()
    }

    /// Finds every hit of every line of `bundle` into `out`: afterwards
    /// [`BundleHits3::line_hits`]`(k)` holds the hits of line `k` (rows in order, points
    /// in order within a row; [`BundleHits3::line_point`]), sorted by `t` then `prim`.
    pub fn cast(&self, bundle: &GlobalBundle3, out: &mut BundleHits3) {
        self.cast_by(bundle, SheetPath::Rows, out);
    }

    /// [`ParallelRaster3::cast`] with the sheets cast by `path`.
    fn cast_by(&self, bundle: &GlobalBundle3, path: SheetPath, out: &mut BundleHits3) {
        let c = bundle.sphere().center;
        let r = bundle.sphere().radius;
        let (e1, e2) = bundle.frame();
        // The rows of lattice points and the index of each row's first line
        let rows = &mut out.rows;
        rows.b.clear();
        rows.first.clear();
        rows.count.clear();
        rows.line.clear();
        let mut lines = 0u32;
        let h = bundle.spacing();
        let (mut a_max, mut b_max) = (0.0f64, 0.0f64);
        for k in 0..bundle.rows() {
            let row = bundle.row(k);
            rows.b.push(row.b);
            rows.first.push(row.first);
            rows.count.push(row.count);
            rows.line.push(lines);
            lines = lines.saturating_add(row.count);
            if let Some(last) = row.count.checked_sub(1) {
                // The row's extreme points, by the candidates' arithmetic
                let ends = [row.first * h, (row.first + f64::from(last)) * h];
                a_max = greater(greater(a_max, ends[0].abs()), ends[1].abs());
                b_max = greater(b_max, row.b.abs());
            }
        }
        rows.line.push(lines);
        let frame = Frame {
            c,
            e1,
            e2,
            d: bundle.dir(),
            h,
            inv_h: 1.0 / h,
            delta: MARGIN * (c.abs().max_element() + r + self.scale),
            first_row_b: out.rows.b.first().copied().unwrap_or(0.0),
            rows: i64::from(bundle.rows()),
            a_max,
            b_max,
        };
        // Every distinct vertex of the loose polygons projected once
        out.projected.clear();
        out.projected
            .extend(self.vertices.iter().map(|&v| frame.project(v)));
        out.sheet_projected.clear();
        if self.sheet_vertices.len() <= 4 * lines as usize {
            out.sheet_projected
                .extend(self.sheet_vertices.iter().map(|&v| frame.project(v)));
        }
        out.found.reset(lines as usize);
        self.cast_polygons(&frame, out);
        self.cast_sheets(&frame, r, path, out);
        // Bucket the hits per line (a counting sort, the hits counted as they were
        // pushed), then sort each line's
        core::mem::swap(&mut out.start, &mut out.found.per_line);
        for k in 2..out.start.len() {
            out.start[k] += out.start[k - 1];
        }
        out.hits.clear();
        out.hits
            .resize(out.found.list.len(), Hit3 { t: 0.0, prim: 0 });
        for &(line, hit) in &out.found.list {
            let slot = &mut out.start[line as usize + 1];
            out.hits[*slot as usize] = hit;
            *slot += 1;
        }
        out.start.pop();
        // Only lines of two hits or more need sorting (most of a bundle's have fewer)
        for ends in out.start.windows(2) {
            let (s, e) = (ends[0] as usize, ends[1] as usize);
            if e > s + 1
                && let Some(hits) = out.hits.get_mut(s..e)
            {
                sort_hits(hits);
            }
        }
    }

    /// Each group of loose polygons against the lattice points of its projected bounds,
    /// each point against every polygon of the group.
    fn cast_polygons(&self, frame: &Frame, out: &mut BundleHits3) {
        for group in &self.groups {
            if group.compact {
                self.cast_compact_group(frame, group, out);
            } else {
                self.cast_group(frame, group, out);
            }
        }
    }

    /// A compact group (module docs, "Groups"): its vertices gathered once, and at each
    /// candidate each distinct edge function computed once; a polygon's edge functions
    /// are those of its edges, negated where it walks them backwards (exactly: the
    /// products commute and the difference changes sign), so the signs are the same as
    /// [`crosses`]' polygon by polygon.
    #[inline(always)]
    fn cast_compact_group(&self, frame: &Frame, group: &Group, out: &mut BundleHits3) {
        let BundleHits3 {
            projected,
            rows,
            found,
            ..
        } = out;
        let ids = &self.group_vertices[group.vertices.0 as usize..group.vertices.1 as usize];
        let mut local = [[0.0f64; 3]; GROUP_VERTICES];
        for (slot, &v) in local.iter_mut().zip(ids) {
            *slot = projected[v as usize];
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for p in &local[..ids.len()] {
            lo = [lesser(lo[0], p[0]), lesser(lo[1], p[1]), 0.0];
            hi = [greater(hi[0], p[0]), greater(hi[1], p[1]), 0.0];
        }
        let edges = &self.group_edges[group.edges.0 as usize..group.edges.1 as usize];
        let polygons = group.first as usize..group.end as usize;
        let masks = &self.crossing_masks[polygons.clone()];
        let vertex_masks = &self.vertex_mask[polygons];
        // A cube's 6 faces as arrays: the polygons' loop of a constant count, unrolled
        // (with the truncation in `sheets.rs`, the room's 2293 → 2090 instructions a line;
        // the 12 edges' loop as an array of vertex indices was not cheaper, the edges'
        // ends as arrays are: `EdgeEnds`)
        let cube = <&[[u8; 2]; 12]>::try_from(edges)
            .ok()
            .zip(<&[[u64; 2]; 6]>::try_from(masks).ok());
        // A cube's 12 edges by their ends' coordinates, edge by edge (SoA): at each
        // candidate the edge functions are a loop over arrays, without the gather of
        // `edge_signs`; gathered at the group's first candidate (most of the room's
        // cubes have none in a bundle)
        let mut ends: Option<EdgeEnds> = None;
        for_each_candidate(frame, rows, lo, hi, frame.delta, |line, a, b| {
            // Bit j of `crossed`: the line crosses polygon j of the group (no branch per
            // polygon: which polygons a candidate crosses is a coin toss)
            let crossed = match cube {
                Some((edges, masks)) => {
                    let ends = ends.get_or_insert_with(|| EdgeEnds::new(&local, edges));
                    let (gt, lt) = ends.signs(a, b);
                    polygons_crossed(gt, lt, masks)
                }
                None => {
                    let rel = local.map(|p| (p[0] - a, p[1] - b));
                    let (gt, lt) = edge_signs(&rel, edges);
                    polygons_crossed(gt, lt, masks)
                }
            };
            let mut crossed = crossed;
            while crossed != 0 {
                let j = crossed.trailing_zeros() as usize;
                crossed &= crossed - 1;
                let vertices = vertex_masks.get(j).copied().unwrap_or(0);
                let k = group.first as usize + j;
                let hit = self.compact_polygon_hit(frame, &local, vertices, k, a, b);
                // The same bits as polygon by polygon (tests)
                #[cfg(test)]
                assert_eq!(
                    hit.map(|h| (h.t.to_bits(), h.prim)),
                    self.polygon_hit(frame, projected, k, a, b)
                        .map(|h| (h.t.to_bits(), h.prim))
                );
                if let Some(hit) = hit {
                    found.push(line, hit);
                }
            }
        });
    }

    /// A group that is not compact: each polygon by [`crosses`].
    #[inline(always)]
    fn cast_group(&self, frame: &Frame, group: &Group, out: &mut BundleHits3) {
        let BundleHits3 {
            projected,
            rows,
            found,
            ..
        } = out;
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for &v in &self.group_vertices[group.vertices.0 as usize..group.vertices.1 as usize] {
            let p = projected[v as usize];
            lo = [lesser(lo[0], p[0]), lesser(lo[1], p[1]), 0.0];
            hi = [greater(hi[0], p[0]), greater(hi[1], p[1]), 0.0];
        }
        for_each_candidate(frame, rows, lo, hi, frame.delta, |line, a, b| {
            for k in group.first as usize..group.end as usize {
                let corners = self.polygon_corners(k);
                let Some(&last) = corners.last() else {
                    continue;
                };
                let vertex = |v: &u32| projected[*v as usize];
                if crosses(corners.iter().map(vertex), projected[last as usize], a, b)
                    && let Some(hit) = self.polygon_hit(frame, projected, k, a, b)
                {
                    found.push(line, hit);
                }
            }
        });
    }

    /// [`ParallelRaster3::polygon_hit`] for polygon `k` of a compact group, its corners
    /// the group's vertices `local[v]` for the bits `v` of `vertices`: the same depths
    /// (the group's vertices are gathered from the same projections), folded in another
    /// order, which gives the same `near − δ` and `far + δ` (the depths are finite; a
    /// minimum over finite values is the same whatever the order, but for the sign of a
    /// zero, which the margin's subtraction and addition erase), so the same bits.
    #[inline(always)]
    fn compact_polygon_hit(
        &self,
        frame: &Frame,
        local: &[[f64; 3]; GROUP_VERTICES],
        vertices: u8,
        k: usize,
        a: f64,
        b: f64,
    ) -> Option<Hit3> {
        let (mut near, mut far) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut rest = vertices;
        while rest != 0 {
            let depth = local[rest.trailing_zeros() as usize % GROUP_VERTICES][2];
            rest &= rest - 1;
            near = lesser(near, depth);
            far = greater(far, depth);
        }
        let (n, p0, prim) = (self.normal.get(k)?, self.p0.get(k)?, self.prim.get(k)?);
        let t = frame.plane_t(*n, *p0, a, b, near, far)?;
        Some(Hit3 { t, prim: *prim })
    }

    /// The hit of the line through `(a, b)` with loose polygon `k`, which it crosses: `t`
    /// from the polygon's plane, clamped into its projected depths.
    #[inline(always)]
    fn polygon_hit(
        &self,
        frame: &Frame,
        projected: &[[f64; 3]],
        k: usize,
        a: f64,
        b: f64,
    ) -> Option<Hit3> {
        let (mut near, mut far) = (f64::INFINITY, f64::NEG_INFINITY);
        for &v in self.polygon_corners(k) {
            let depth = projected[v as usize][2];
            near = lesser(near, depth);
            far = greater(far, depth);
        }
        let t = frame.plane_t(self.normal[k], self.p0[k], a, b, near, far)?;
        Some(Hit3 {
            t,
            prim: self.prim[k],
        })
    }
}

/// Appends the distinct points (by their bits) among `points[i]`, `i` in `used`, to
/// `distinct` (sorted by their bits), and sets `id[i]` to each one's index there.
fn distinct_by_bits(
    points: &[DVec3],
    mut used: Vec<u32>,
    distinct: &mut Vec<DVec3>,
    id: &mut [u32],
) {
    let key = |p: &DVec3| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
    used.sort_unstable_by_key(|&i| key(&points[i as usize]));
    for (k, &i) in used.iter().enumerate() {
        let p = points[i as usize];
        if k == 0 || key(&points[used[k - 1] as usize]) != key(&p) {
            distinct.push(p);
        }
        id[i as usize] = distinct.len() as u32 - 1;
    }
}

/// Calls `f(line, a, b)` for every lattice point `(a, b)` of the bundle inside the box
/// `[lo, hi]` of the plane (first two coordinates) grown by `grow`.
#[inline(always)]
fn for_each_candidate(
    frame: &Frame,
    rows: &Rows,
    lo: [f64; 3],
    hi: [f64; 3],
    grow: f64,
    mut f: impl FnMut(u32, f64, f64),
) {
    for_each_row(frame, rows, lo, hi, grow, |row| {
        for q in row.q_lo..=row.q_hi {
            f(row.line(q), row.a(frame, q), row.b);
        }
    });
}

/// The lattice points of one row inside a box: `q_lo ≤ q ≤ q_hi` (possibly empty).
#[derive(Clone, Copy, Debug)]
struct RowSpan {
    b: f64,
    first: f64,
    /// The line of the row's point `q = 0`.
    line0: u32,
    q_lo: i64,
    q_hi: i64,
}

impl RowSpan {
    /// `a` of the row's point `q`: `(first + q) h`, the one arithmetic of every caller.
    #[inline(always)]
    fn a(&self, frame: &Frame, q: i64) -> f64 {
        (self.first + q as f64) * frame.h
    }

    /// The line of the row's point `q`.
    #[inline(always)]
    fn line(&self, q: i64) -> u32 {
        self.line0 + q as u32
    }
}

/// Calls `f` for every row of the bundle with lattice points inside the box `[lo, hi]` of
/// the plane (first two coordinates) grown by `grow`, with the range of those points.
#[inline(always)]
fn for_each_row(
    frame: &Frame,
    rows: &Rows,
    lo: [f64; 3],
    hi: [f64; 3],
    grow: f64,
    mut f: impl FnMut(RowSpan),
) {
    // Rows whose b lies in [lo₁ − grow, hi₁ + grow] (rows are h apart from the first)
    let row_lo = ceil_index((lo[1] - grow - frame.first_row_b) * frame.inv_h).max(0);
    let row_hi = floor_index((hi[1] + grow - frame.first_row_b) * frame.inv_h).min(frame.rows - 1);
    if row_hi < row_lo {
        return;
    }
    let (x_lo, x_hi) = ((lo[0] - grow) * frame.inv_h, (hi[0] + grow) * frame.inv_h);
    for row in row_lo as usize..=row_hi as usize {
        let (b, first, count) = (rows.b[row], rows.first[row], rows.count[row]);
        let q_lo = ceil_index(x_lo - first).max(0);
        let q_hi = floor_index(x_hi - first).min(i64::from(count) - 1);
        if q_lo <= q_hi {
            f(RowSpan {
                b,
                first,
                line0: rows.line[row],
                q_lo,
                q_hi,
            });
        }
    }
}

/// The signs of a compact group's edge functions at a candidate, `rel` its vertices
/// relative to the candidate: bit `e` of the first (second) mask is set when edge `e`'s
/// function is `> 0` (`< 0`).
#[inline(always)]
fn edge_signs(rel: &[(f64, f64); GROUP_VERTICES], edges: &[[u8; 2]]) -> (u32, u32) {
    let (mut gt, mut lt) = (0u32, 0u32);
    for (e, &[u, v]) in edges.iter().enumerate() {
        let (p, q) = (
            rel[usize::from(u) % GROUP_VERTICES],
            rel[usize::from(v) % GROUP_VERTICES],
        );
        let s = p.0 * q.1 - p.1 * q.0;
        gt |= u32::from(s > 0.0) << e;
        lt |= u32::from(s < 0.0) << e;
    }
    (gt, lt)
}

/// The ends `(u, v)` of a cube's 12 edges, projected, as arrays (SoA) by edge.
struct EdgeEnds {
    ux: [f64; 12],
    uy: [f64; 12],
    vx: [f64; 12],
    vy: [f64; 12],
}

impl EdgeEnds {
    /// The ends of `edges` among the projected vertices `local`.
    #[inline(always)]
    fn new(local: &[[f64; 3]; GROUP_VERTICES], edges: &[[u8; 2]; 12]) -> Self {
        let end = |k: u8| local[usize::from(k) % GROUP_VERTICES];
        Self {
            ux: edges.map(|[u, _]| end(u)[0]),
            uy: edges.map(|[u, _]| end(u)[1]),
            vx: edges.map(|[_, v]| end(v)[0]),
            vy: edges.map(|[_, v]| end(v)[1]),
        }
    }

    /// [`edge_signs`] at the candidate `(a, b)`: the same differences and products, so
    /// the same bits (`(P_u − x) × (P_v − x)` with `P − x` taken first).
    #[inline(always)]
    fn signs(&self, a: f64, b: f64) -> (u32, u32) {
        let (mut gt, mut lt) = (0u32, 0u32);
        for e in 0..12 {
            let s = (self.ux[e] - a) * (self.vy[e] - b) - (self.uy[e] - b) * (self.vx[e] - a);
            gt |= u32::from(s > 0.0) << e;
            lt |= u32::from(s < 0.0) << e;
        }
        (gt, lt)
    }
}

/// Bit `j`: polygon `j` of a compact group is crossed (no two of its edge functions of
/// opposite signs, not all zero), from [`edge_signs`] and its polygons' masks `[P, N]`.
///
/// Polygon `j`'s edge function on edge `e` is the edge's, negated where it walks the edge
/// from `v` to `u`: it is positive where edge `e` is positive and walked forwards or
/// negative and walked backwards. With the signs in one word `w = gt | lt << 32`, the
/// polygon has a positive edge function when `w & P ≠ 0` (`P`: its forward edges' bits
/// and its backward edges' bits shifted by 32) and a negative one when `w & N ≠ 0` (the
/// walks swapped); it is crossed when exactly one of the two holds.
#[inline(always)]
fn polygons_crossed(gt: u32, lt: u32, masks: &[[u64; 2]]) -> u32 {
    let w = u64::from(gt) | (u64::from(lt) << 32);
    let mut crossed = 0u32;
    for (j, &[p, n]) in masks.iter().enumerate() {
        crossed |= u32::from((w & p != 0) != (w & n != 0)) << j;
    }
    crossed
}

/// The smaller of `a` and `b` by one comparison: [`f64::min`] without its NaN handling (a
/// few instructions more per call in the hot loops). It equals `f64::min` when `a` is not
/// NaN (a NaN `b` is passed over, as `f64::min` does): every caller folds from `±∞` or
/// clamps `t`, which is not NaN. Where `a` and `b` are zeros of both signs it may differ
/// from `f64::min` in the sign; every caller's result is the same either way (bounds grown
/// by a margin; `t` gets `+ 0.0`).
#[inline(always)]
fn lesser(a: f64, b: f64) -> f64 {
    if b < a { b } else { a }
}

/// The larger of `a` and `b` by one comparison (see [`lesser`]).
#[inline(always)]
fn greater(a: f64, b: f64) -> f64 {
    if b > a { b } else { a }
}

/// `⌊x⌋` as an integer, for the lattice indices of a bundle (`|x|` far below `2⁶³`; `as`
/// saturates, and NaN gives 0, which the callers' range checks absorb).
#[inline(always)]
fn floor_index(x: f64) -> i64 {
    // Branch-free: the sign of `x` decides the correction, and it is unpredictable
    let i = x as i64;
    i - i64::from((i as f64) > x)
}

/// `⌈x⌉` as an integer (see [`floor_index`]).
#[inline(always)]
fn ceil_index(x: f64) -> i64 {
    let i = x as i64;
    i + i64::from((i as f64) < x)
}

/// Whether the line through `x = (a, b)` crosses the closed polygon of the projected
/// vertices `corners` (`last` = the last of them): the origin in the polygon of the
/// differences `P − x` (the closed edge test of [`super::Bvh3`]).
#[inline(always)]
fn crosses(corners: impl Iterator<Item = [f64; 3]>, last: [f64; 3], a: f64, b: f64) -> bool {
    origin_in_closed_polygon(
        (last[0] - a, last[1] - b),
        corners.map(|p| (p[0] - a, p[1] - b)),
    )
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
    #[cfg(test)]
    pub fn line_point(&self, bundle: &GlobalBundle3, k: usize) -> Option<(f64, f64)> {
        let k = u32::try_from(k).ok()?;
        let rows = &self.rows;
        let row = rows.line.partition_point(|&s| s <= k).checked_sub(1)?;
        let q = k - rows.line[row];
        (q < *rows.count.get(row)?).then(|| {
            let a = (rows.first[row] + f64::from(q)) * bundle.spacing();
            (a, rows.b[row])
        })
    }
}

mod sheets;

use sheets::SheetPath;

#[cfg(all(test, feature = "std"))]
mod tests;
