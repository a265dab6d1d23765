//! Agreement of [`ParallelRaster3`] with [`Bvh3::all_hits`] and [`all_hits_naive3`] line by
//! line on random soups, cube meshes and the presets, and watertightness on a closed mesh
//! far from the origin.

use proptest::prelude::*;
use std::vec::Vec;

use super::*;
use crate::accel::bvh3::tests::{Soup, cube_mesh, sheet_soup, soup};
use crate::accel::{Bvh3, all_hits_naive3};
use crate::lines::{BoundingSphere, canonical, canonical_2d, chunk_rng};

/// The sphere the tracer would use: circumscribing the soup's bounds.
fn sphere_of(s: &Soup) -> BoundingSphere {
    let lo = s.points.iter().fold(DVec3::INFINITY, |a, &p| a.min(p));
    let hi = s.points.iter().fold(DVec3::NEG_INFINITY, |a, &p| a.max(p));
    BoundingSphere::of_bounds(lo, hi)
}

/// Casts one bundle over `s` and compares every line's hits with the BVH's and the naive
/// loop's for the same `Line3` (built from the line's lattice point by
/// [`GlobalBundle3::line_at`]). Primitives must agree exactly; `t` within
/// `10⁻⁶ (r + ‖c‖∞ + scale)`: both compute the plane crossing to rounding (relative
/// `10⁻¹⁶` of those sizes over the cosine of incidence) and clamp it into the polygon's
/// extent, so they differ more only for lines within 10⁻⁹ of grazing a polygon, which
/// random bundles do not produce. Returns the number of hits.
fn check_bundle(s: &Soup, bvh: &Bvh3, sphere: &BoundingSphere, bundle: &GlobalBundle3) -> usize {
    let raster = ParallelRaster3::new(&s.points, &s.polys);
    let mut out = BundleHits3::new();
    raster.cast(bundle, &mut out);
    assert_eq!(out.lines() as u64, bundle.len());
    let scale = s
        .points
        .iter()
        .fold(0.0f64, |m, p| m.max(p.abs().max_element()));
    let bound = 1e-6 * (sphere.radius + sphere.center.abs().max_element() + scale);
    let (mut tree, mut naive) = (Vec::new(), Vec::new());
    let mut total = 0;
    for k in 0..out.lines() {
        let (a, b) = out.line_point(bundle, k).unwrap();
        let line = bundle.line_at(a, b);
        bvh.all_hits(&line, &mut tree);
        all_hits_naive3(&s.points, &s.polys, &line, &mut naive);
        assert_eq!(tree, naive);
        let got = out.line_hits(k);
        let prims = |h: &[Hit3]| h.iter().map(|h| h.prim).collect::<Vec<_>>();
        let mut sorted_got = prims(got);
        let mut sorted_tree = prims(&tree);
        sorted_got.sort_unstable();
        sorted_tree.sort_unstable();
        assert_eq!(sorted_got, sorted_tree, "line {k} ({a}, {b}) of {bundle:?}");
        for h in got {
            let t = tree.iter().find(|x| x.prim == h.prim).unwrap().t;
            assert!((h.t - t).abs() <= bound, "line {k}: t {} vs {t}", h.t);
        }
        assert!(got.windows(2).all(|w| w[0].cmp_t_prim(&w[1]).is_lt()));
        total += got.len();
    }
    assert!(out.line_hits(out.lines()).is_empty());
    assert!(out.line_point(bundle, out.lines()).is_none());
    total
}

fn bundle<R: rand_core::Rng>(rng: &mut R, sphere: &BoundingSphere, m: f64) -> GlobalBundle3 {
    GlobalBundle3::new(sphere, canonical_2d(rng), canonical_2d(rng), m)
}

proptest! {
    /// Random soups (tilted polygons of all sizes, axis-aligned rectangles, lattice
    /// triangles sharing vertices) and random bundles: the same hits as the BVH.
    #[test]
    fn bundle_hits_equal_bvh_and_naive(
        seed in 0u64..1_000_000,
        n in 1usize..60,
        m in 1.0f64..400.0,
    ) {
        let s = soup(seed, n);
        let bvh = s.bvh();
        let sphere = sphere_of(&s);
        let mut rng = chunk_rng(seed, 1);
        for _ in 0..3 {
            check_bundle(&s, &bvh, &sphere, &bundle(&mut rng, &sphere, m));
        }
    }

    /// Sheets: tilted, sheared, jittered grids (up to 0.4 of a cell, beyond which no sheet
    /// is made) among loose polygons.
    #[test]
    fn sheet_hits_equal_bvh((s, _) in sheet_soup(), seed in 0u64..1_000_000, m in 1.0f64..600.0) {
        let bvh = s.bvh();
        let sphere = sphere_of(&s);
        let mut rng = chunk_rng(seed, 3);
        for _ in 0..3 {
            check_bundle(&s, &bvh, &sphere, &bundle(&mut rng, &sphere, m));
        }
    }

    /// Cube meshes of quads or triangles (shared vertices and edges, sheets in the BVH),
    /// near and far from the origin.
    #[test]
    fn cube_mesh_hits_equal_bvh(
        seed in 0u64..1_000_000,
        grid in 1usize..7,
        triangles in any::<bool>(),
        far in any::<bool>(),
    ) {
        let offset = if far { DVec3::new(1e4, -3e3, 7e2) } else { DVec3::splat(-0.5) };
        let s = cube_mesh(grid, 1.0, offset, triangles, true);
        let bvh = s.bvh();
        let sphere = sphere_of(&s);
        let mut rng = chunk_rng(seed, 2);
        check_bundle(&s, &bvh, &sphere, &bundle(&mut rng, &sphere, 300.0));
    }
}

/// Casts `bundle` over `s` with the sheets row by row and by the exact path: the same
/// hits for every line, bit for bit. Returns the row path's candidates by the exact path
/// and inside a cell.
fn rows_equal_exact(s: &Soup, bundle: &GlobalBundle3) -> [usize; 2] {
    let raster = ParallelRaster3::new(&s.points, &s.polys);
    let (mut rows, mut exact) = (BundleHits3::new(), BundleHits3::new());
    raster.cast_by(bundle, SheetPath::Rows, &mut rows);
    raster.cast_by(bundle, SheetPath::Exact, &mut exact);
    assert_eq!(exact.row_paths, [0, 0]);
    assert_eq!(rows.start, exact.start, "{bundle:?}");
    let bits = |h: &[Hit3]| {
        h.iter()
            .map(|h| (h.t.to_bits(), h.prim))
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&rows.hits), bits(&exact.hits), "{bundle:?}");
    rows.row_paths
}

/// A soup with one `n × n` sheet whose vertices are (to rounding) lattice points of
/// `bundle`, `step` lattice spacings apart, tilted in depth: the bundle's lines run
/// along the quads' edges and through their vertices.
fn sheet_on_the_lattice(bundle: &GlobalBundle3, n: u32, step: u32, tilt: f64) -> Soup {
    let (e1, e2) = bundle.frame();
    let (c, d) = (bundle.sphere().center, bundle.dir());
    let mid = bundle.row(bundle.rows() / 2);
    let row0 = bundle.rows() / 2 - n * step / 2;
    let q0 = mid.count / 2 - n * step / 2;
    let point = |i: u32, j: u32| {
        let a = bundle.row_point(&mid, q0 + i * step);
        let b = bundle.row(row0 + j * step).b;
        c + e1 * a + e2 * b + d * (tilt * a + 0.1 * b)
    };
    let mut s = Soup::default();
    for j in 0..n {
        for i in 0..n {
            s.push(&[
                point(i, j),
                point(i + 1, j),
                point(i + 1, j + 1),
                point(i, j + 1),
            ]);
        }
    }
    s
}

proptest! {
    /// The sheets' row path equals the exact path bit for bit: sheet soups (tilted,
    /// sheared, jittered grids among loose polygons) and cube meshes near and far.
    #[test]
    fn sheet_rows_equal_exact_path(
        (s, _) in sheet_soup(),
        seed in 0u64..1_000_000,
        m in 1.0f64..3000.0,
        far in any::<bool>(),
    ) {
        let sphere = sphere_of(&s);
        let mut rng = chunk_rng(seed, 7);
        for _ in 0..3 {
            rows_equal_exact(&s, &bundle(&mut rng, &sphere, m));
        }
        let offset = if far { DVec3::new(1e4, -3e3, 7e2) } else { DVec3::splat(-0.5) };
        let cube = cube_mesh(1 + (seed % 9) as usize, 1.0, offset, false, true);
        rows_equal_exact(&cube, &bundle(&mut rng, &sphere_of(&cube), m));
    }

    /// A sheet whose edges and vertices lie on the bundle's lines (to rounding): the row
    /// path leaves those candidates to the exact path and equals it bit for bit.
    #[test]
    fn sheet_on_the_lines_rows_equal_exact_path(
        seed in 0u64..1_000_000,
        step in 1u32..4,
        tilt in -3.0f64..3.0,
    ) {
        let sphere = BoundingSphere::of_bounds(DVec3::splat(-1.0), DVec3::new(2.0, 1.0, 1.0));
        let mut rng = chunk_rng(seed, 8);
        let b = bundle(&mut rng, &sphere, 4000.0);
        let s = sheet_on_the_lattice(&b, 6, step, tilt);
        let [exact, inside] = rows_equal_exact(&s, &b);
        // Every candidate on a line of the sheet's lattice is near a side
        prop_assert!(exact >= 36, "{exact}");
        if step > 1 {
            prop_assert!(inside > 0);
        }
    }
}

#[test]
fn the_cubes_sheets_take_the_row_path() {
    // The cube of 30 × 30 quads a face: nearly every candidate of its sheets is inside a
    // cell or outside the sheet, and the hits are those of the exact path.
    let s = cube_mesh(30, 1.0, DVec3::splat(-0.5), false, true);
    let sphere = sphere_of(&s);
    let mut rng = chunk_rng(9, 0);
    let (mut exact, mut inside) = (0, 0);
    for _ in 0..20 {
        let [e, i] = rows_equal_exact(&s, &bundle(&mut rng, &sphere, 1024.0));
        (exact, inside) = (exact + e, inside + i);
    }
    // 20 bundles of ~1,024 lines, about 1.3 crossings a line
    assert!(inside > 20_000, "{inside}");
    assert!(exact * 1000 < inside, "{exact} of {inside}");
}

#[test]
fn preset_scenes_hits_equal_bvh() {
    let mut rng = chunk_rng(4, 0);
    for (name, grid) in [("cornell", 3), ("cubes-512-random", 1), ("octahedron", 2)] {
        let scene = crate::scene::Scene3::preset(name, grid).unwrap();
        let s = Soup {
            points: scene.points().to_vec(),
            polys: scene.patches().iter().map(|p| (p.first, p.count)).collect(),
        };
        let bvh = s.bvh();
        let sphere = sphere_of(&s);
        let b = bundle(&mut rng, &sphere, 2000.0);
        let hits = check_bundle(&s, &bvh, &sphere, &b);
        assert!(hits > 500, "{name}: {hits}");
        rows_equal_exact(&s, &b);
    }
}

#[test]
fn closed_mesh_far_from_the_origin_is_watertight() {
    // Every line of many bundles that meets a closed cube mesh crosses it an even number
    // of times, once crossings at one point of one face (a shared edge) are merged: no
    // line slips through a seam, none is caught twice.
    for (triangles, grid) in [(false, 7), (true, 5)] {
        let s = cube_mesh(grid, 2.0, DVec3::new(3e5, -1e5, 4e4), triangles, true);
        let raster = ParallelRaster3::new(&s.points, &s.polys);
        let normals: Vec<DVec3> = s
            .polys
            .iter()
            .map(|&(f, c)| crate::geom::polygon_normal(&s.points[f..f + c]).normalize())
            .collect();
        let sphere = sphere_of(&s);
        let eps = 1e-9 * sphere.radius;
        let mut rng = chunk_rng(5, 0);
        let mut out = BundleHits3::new();
        let mut crossed = 0;
        for _ in 0..40 {
            let m = 4000.0 * canonical(&mut rng) + 100.0;
            let b = bundle(&mut rng, &sphere, m);
            raster.cast(&b, &mut out);
            for k in 0..out.lines() {
                let hits = out.line_hits(k);
                let mut merged: Vec<(f64, DVec3)> = Vec::new();
                for h in hits {
                    let n = normals[h.prim as usize];
                    let same = merged
                        .iter()
                        .any(|&(t, m)| (h.t - t).abs() <= eps && (m - n).length() < 1e-9);
                    if !same {
                        merged.push((h.t, n));
                    }
                }
                assert!(
                    merged.len().is_multiple_of(2),
                    "line {k} of {b:?}: {} crossings {hits:?}",
                    merged.len()
                );
                crossed += usize::from(!merged.is_empty());
            }
        }
        assert!(crossed > 10_000, "{crossed}");
    }
}

#[test]
fn shared_vertices_are_one_vertex_and_grids_are_sheets() {
    // A cube mesh of 4 × 4 quads a face, its faces' quads interleaved (no grid in input
    // order), has 6·16 quads of 4 corners but 98 distinct vertices (6·25 − 12·5 + 8).
    let s = cube_mesh(4, 1.0, DVec3::ZERO, false, false);
    let raster = ParallelRaster3::new(&s.points, &s.polys);
    assert_eq!(s.points.len(), 6 * 16 * 4);
    assert_eq!((raster.vertex_count(), raster.sheet_count()), (98, 0));
    // Face by face, row by row: six sheets and no loose polygon.
    let s = cube_mesh(4, 1.0, DVec3::ZERO, false, true);
    let raster = ParallelRaster3::new(&s.points, &s.polys);
    assert_eq!((raster.vertex_count(), raster.sheet_count()), (0, 6));
    // The sheets' quads by their 98 distinct vertices, the same points as the quads'
    assert_eq!(raster.sheet_vertices.len(), 98);
    for (q, c) in raster.quads.iter().zip(&raster.quad_corners) {
        assert!((0..4).all(|k| raster.sheet_vertices[c[k] as usize] == q[k]));
    }
}

#[test]
fn degenerate_polygons_never_hit() {
    let mut s = Soup::default();
    s.push(&[DVec3::ZERO, DVec3::X]);
    s.push(&[DVec3::ZERO, DVec3::X, DVec3::X * 2.0]);
    s.push(&[DVec3::ZERO, DVec3::NAN, DVec3::Y]);
    s.push(&[DVec3::ZERO, DVec3::X, DVec3::Y]);
    let raster = ParallelRaster3::new(&s.points, &s.polys);
    let sphere = BoundingSphere::of_bounds(DVec3::splat(-1.0), DVec3::splat(1.0));
    let mut rng = chunk_rng(6, 0);
    let mut out = BundleHits3::new();
    for _ in 0..50 {
        raster.cast(&bundle(&mut rng, &sphere, 500.0), &mut out);
        for k in 0..out.lines() {
            assert!(
                out.line_hits(k)
                    .iter()
                    .all(|h| h.prim == 3 && h.t.is_finite())
            );
        }
    }
}

#[test]
fn the_rooms_cubes_are_one_group_each() {
    // The 512-cube room: 6 gridded walls are sheets, and each cube's 6 faces (consecutive,
    // 8 distinct vertices) one group, so a bundle sets up 512 groups, not 3,072 polygons.
    let scene = crate::scene::Scene3::preset("cubes-512-random", 1).unwrap();
    let polys: Vec<_> = scene.patches().iter().map(|p| (p.first, p.count)).collect();
    let raster = ParallelRaster3::new(scene.points(), &polys);
    assert_eq!((raster.sheet_count(), raster.prim.len()), (6, 3072));
    assert_eq!(raster.groups.len(), 512);
    assert!(raster.groups.iter().all(|g| g.end - g.first == 6));
    assert!(
        raster
            .groups
            .iter()
            .all(|g| g.vertices.1 - g.vertices.0 == 8)
    );
    // In random soups no group of several polygons breaks the limits
    for seed in 0..20 {
        let s = soup(seed, 50);
        let raster = ParallelRaster3::new(&s.points, &s.polys);
        for g in &raster.groups {
            assert!((1..=GROUP_POLYGONS as u32).contains(&(g.end - g.first)));
            let corners = raster.polygon_corners(g.first as usize).len() as u32;
            let vertices = g.vertices.1 - g.vertices.0;
            assert!(
                vertices <= GROUP_VERTICES as u32 || (g.end - g.first == 1 && vertices <= corners)
            );
        }
        assert_eq!(
            raster.groups.iter().map(|g| g.end - g.first).sum::<u32>() as usize,
            raster.prim.len()
        );
    }
}

proptest! {
    /// The edge functions of a cube's edges from the ends' arrays ([`EdgeEnds::signs`])
    /// have the signs of [`edge_signs`]' bit for bit: random vertices and candidates, and
    /// candidates on a vertex or an edge's midpoint (where a function is zero or within
    /// rounding of it).
    #[test]
    fn edge_ends_signs_are_edge_signs(
        coords in proptest::collection::vec(-3.0f64..3.0, 16),
        point in (-3.0f64..3.0, -3.0f64..3.0),
        on in 0usize..40,
    ) {
        let mut local = [[0.0f64; 3]; GROUP_VERTICES];
        for (v, p) in local.iter_mut().enumerate() {
            *p = [coords[2 * v], coords[2 * v + 1], 0.0];
        }
        // A cube's 12 edges (vertices 0–7 by their bits x, y, z), both orders of ends
        let mut edges = [[0u8; 2]; 12];
        let mut e = 0;
        for u in 0u8..8 {
            for bit in [1u8, 2, 4] {
                if u & bit == 0 {
                    edges[e] = if e % 2 == 0 { [u, u | bit] } else { [u | bit, u] };
                    e += 1;
                }
            }
        }
        let (a, b) = match on {
            0..8 => (local[on][0], local[on][1]),
            8..20 => {
                let [u, v] = edges[on - 8];
                let (p, q) = (local[usize::from(u)], local[usize::from(v)]);
                (0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]))
            }
            _ => point,
        };
        let rel = local.map(|p| (p[0] - a, p[1] - b));
        prop_assert_eq!(EdgeEnds::new(&local, &edges).signs(a, b), edge_signs(&rel, &edges));
    }
}
