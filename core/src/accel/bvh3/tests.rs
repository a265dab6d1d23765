//! Agreement of [`Bvh3`] with the naive loops on random polygon soups and lines, the
//! degenerate configurations (lines through vertices and edges, axis-aligned and in-plane
//! lines, shared edges), watertightness of closed meshes, and the Crofton hit statistics.

use proptest::prelude::*;
use std::vec::Vec;

use super::*;
use crate::lines::{
    BoundingSphere, canonical, canonical_2d, chunk_rng, sample_global_line_3d,
    sample_local_line_3d, sample_uniform_sphere,
};

/// Polygons as the BVH takes them.
#[derive(Clone, Debug, Default)]
pub(in crate::accel) struct Soup {
    pub(in crate::accel) points: Vec<DVec3>,
    pub(in crate::accel) polys: Vec<(usize, usize)>,
}

impl Soup {
    pub(in crate::accel) fn push(&mut self, verts: &[DVec3]) {
        self.polys.push((self.points.len(), verts.len()));
        self.points.extend_from_slice(verts);
    }

    fn verts(&self, k: usize) -> &[DVec3] {
        let (f, c) = self.polys[k];
        &self.points[f..f + c]
    }

    pub(in crate::accel) fn bvh(&self) -> Bvh3 {
        Bvh3::build(&self.points, &self.polys).unwrap()
    }
}

fn canonical_4d<R: rand_core::Rng + ?Sized>(rng: &mut R) -> [f64; 4] {
    let [a, b] = canonical_2d(rng);
    let [c, d] = canonical_2d(rng);
    [a, b, c, d]
}

/// A convex planar polygon of `k` vertices on an ellipse of axes `e1`, `e2` about `c`
/// (counter-clockwise about `e1 × e2`), at sorted random angles.
fn ellipse_polygon<R: rand_core::Rng>(
    rng: &mut R,
    c: DVec3,
    e1: DVec3,
    e2: DVec3,
    k: usize,
) -> Vec<DVec3> {
    let mut angles: Vec<f64> = (0..k)
        .map(|_| core::f64::consts::TAU * canonical(rng))
        .collect();
    angles.sort_by(f64::total_cmp);
    angles
        .iter()
        .map(|&a| c + e1 * libm::cos(a) + e2 * libm::sin(a))
        .collect()
}

/// A random soup of `n` polygons in `[-10, 10]³`: tilted triangles to hexagons of sizes
/// from tiny to large, axis-aligned rectangles, and lattice triangles sharing vertices.
pub(in crate::accel) fn soup(seed: u64, n: usize) -> Soup {
    let mut rng = chunk_rng(seed, 0);
    let mut s = Soup::default();
    for k in 0..n {
        let c = DVec3::new(
            -10.0 + 20.0 * canonical(&mut rng),
            -10.0 + 20.0 * canonical(&mut rng),
            -10.0 + 20.0 * canonical(&mut rng),
        );
        match k % 4 {
            0 | 1 => {
                let size = if k % 4 == 0 { 3.0 } else { 0.05 };
                let a = sample_uniform_sphere(canonical_2d(&mut rng));
                let (b1, b2) = a.any_orthonormal_pair();
                let r1 = size * (0.2 + canonical(&mut rng));
                let r2 = size * (0.2 + canonical(&mut rng));
                let m = 3 + (k / 4) % 4;
                let poly = ellipse_polygon(&mut rng, c, b1 * r1, b2 * r2, m);
                s.push(&poly);
            }
            2 => {
                // Axis-aligned rectangle in a random axis plane.
                let (w, h) = (4.0 * canonical(&mut rng), 4.0 * canonical(&mut rng));
                let axis = (k / 4) % 3;
                let (u, v) = match axis {
                    0 => (DVec3::Y, DVec3::Z),
                    1 => (DVec3::Z, DVec3::X),
                    _ => (DVec3::X, DVec3::Y),
                };
                s.push(&[c, c + u * w, c + u * w + v * h, c + v * h]);
            }
            _ => {
                // Lattice triangles: coincident vertices and exact coordinates.
                let mut lat = || {
                    DVec3::new(
                        f64::from((canonical(&mut rng) * 9.0) as i32 - 4),
                        f64::from((canonical(&mut rng) * 9.0) as i32 - 4),
                        f64::from((canonical(&mut rng) * 9.0) as i32 - 4),
                    )
                };
                let tri = [lat(), lat(), lat()];
                s.push(&tri);
            }
        }
    }
    s
}

/// Both queries, naive and accelerated, for one line.
fn check_line(s: &Soup, bvh: &Bvh3, line: &Line3, a: &mut Vec<Hit3>, b: &mut Vec<Hit3>) {
    all_hits_naive3(&s.points, &s.polys, line, a);
    bvh.all_hits(line, b);
    assert_eq!(a, b, "line {line:?}");
    assert!(
        a.iter()
            .all(|h| h.t.is_finite() && !(h.t == 0.0 && h.t.is_sign_negative()))
    );
    assert!(a.windows(2).all(|w| w[0].cmp_t_prim(&w[1]).is_lt()));
    // The walks with the large stack, which only deep trees take, and with the f64 node
    // tests, which only lines outside the f32 tests' error bounds take.
    let (large, by_f64) = bvh.for_each_hit_other_walks(line);
    if let Some(mut large) = large {
        crate::accel::sort_hits(&mut large);
        assert_eq!(*a, large, "line {line:?}, large stack");
    }
    b.clear();
    b.extend(by_f64);
    crate::accel::sort_hits(b);
    assert_eq!(a, b, "line {line:?}, f64 node tests");
    for t_min in [-f64::INFINITY, 0.0, 1e-9, 3.0] {
        let naive = first_hit_naive3(&s.points, &s.polys, line.origin, line.dir, t_min);
        let fast = bvh.first_hit(line.origin, line.dir, t_min);
        assert_eq!(naive, fast, "ray {line:?} t_min {t_min}");
        // The first hit is the first of all hits past t_min.
        assert_eq!(a.iter().find(|h| h.t > t_min).copied(), fast);
    }
}

/// Lines through every vertex, edge midpoint and vertex mean of the polygons: in a random
/// direction, along the axes, along an edge (in the plane), along the normal, and
/// slightly off the plane.
fn torture_lines(s: &Soup, seed: u64) -> Vec<Line3> {
    let mut rng = chunk_rng(seed, 7);
    let mut lines = Vec::new();
    for k in 0..s.polys.len() {
        let v = s.verts(k);
        if v.len() < 3 {
            continue;
        }
        let n = crate::geom::polygon_normal(v).normalize_or_zero();
        let mean = v.iter().copied().sum::<DVec3>() / v.len() as f64;
        let e = (v[1] - v[0]).normalize_or_zero();
        for p in [v[0], v[1], (v[1] + v[2]) * 0.5, mean] {
            for dir in [
                sample_uniform_sphere(canonical_2d(&mut rng)),
                DVec3::X,
                DVec3::Y,
                -DVec3::Z,
                e,
                n,
                (e + n * 1e-13).normalize_or_zero(),
                (e - n * 1e-7).normalize_or_zero(),
            ] {
                lines.push(Line3::new(p, dir));
            }
        }
        // In the plane, a hair above it.
        lines.push(Line3::new(mean + n * 1e-14, e));
    }
    lines
}

#[test]
fn soups_agree_with_naive_for_random_lines() {
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for (seed, n) in [(1, 1), (2, 2), (3, 7), (4, 50), (5, 333), (6, 3000)] {
        let s = soup(seed, n);
        let bvh = s.bvh();
        assert_eq!(bvh.len(), n);
        let sphere = BoundingSphere::of_bounds(DVec3::splat(-12.0), DVec3::splat(12.0));
        let mut rng = chunk_rng(seed, 1);
        let mut total = 0;
        for _ in 0..2000 {
            let line = sample_global_line_3d(&sphere, canonical_4d(&mut rng));
            check_line(&s, &bvh, &line, &mut a, &mut b);
            total += a.len();
        }
        assert!(n < 50 || total > 100, "{total}");
    }
}

#[test]
fn lines_through_vertices_edges_and_axis_aligned_lines_agree() {
    let (mut a, mut b) = (Vec::new(), Vec::new());
    let s = soup(7, 400);
    let bvh = s.bvh();
    let mut total = 0;
    for line in torture_lines(&s, 7) {
        check_line(&s, &bvh, &line, &mut a, &mut b);
        total += a.len();
    }
    assert!(total > 1000, "{total}");
}

/// The surface of the cube `offset + [0, scale]³` cut into `m × m` squares a face, with
/// shared (bit-identical) vertices, each facing inwards; with `triangles`, each square cut
/// into two triangles along alternating diagonals (vertices with 4 to 8 spokes). With
/// `face_major`, face by face, each row by row as scenes cut faces (the tree makes sheets
/// of them); else the six faces' patches interleaved (no sheets).
pub(in crate::accel) fn cube_mesh(
    m: usize,
    scale: f64,
    offset: DVec3,
    triangles: bool,
    face_major: bool,
) -> Soup {
    let mut s = Soup::default();
    let p = |(x, y, z): (usize, usize, usize)| {
        offset + DVec3::new(x as f64, y as f64, z as f64) * (scale / m as f64)
    };
    // Lattice point (i, j) of each face, counter-clockwise seen from inside.
    let faces: [&dyn Fn(usize, usize) -> (usize, usize, usize); 6] = [
        &|i, j| (i, j, 0),
        &|i, j| (j, i, m),
        &|i, j| (0, i, j),
        &|i, j| (m, j, i),
        &|i, j| (j, 0, i),
        &|i, j| (i, m, j),
    ];
    let mut push = |f: usize, i: usize, j: usize| {
        let q = [
            p(faces[f](i, j)),
            p(faces[f](i + 1, j)),
            p(faces[f](i + 1, j + 1)),
            p(faces[f](i, j + 1)),
        ];
        if !triangles {
            s.push(&q);
        } else if (i + j).is_multiple_of(2) {
            s.push(&[q[0], q[1], q[2]]);
            s.push(&[q[0], q[2], q[3]]);
        } else {
            s.push(&[q[0], q[1], q[3]]);
            s.push(&[q[1], q[2], q[3]]);
        }
    };
    for outer in 0..m.max(6) {
        for mid in 0..m {
            for inner in 0..m.max(6) {
                let (f, i, j) = if face_major {
                    (outer, inner, mid)
                } else {
                    (inner, outer, mid)
                };
                if f < 6 && i < m {
                    push(f, i, j);
                }
            }
        }
    }
    s
}

#[test]
fn cube_mesh_is_watertight_and_agrees_with_naive() {
    // Lines aimed exactly at mesh vertices and edge points (the seams), from inside and
    // from outside the closed surface, cross it: from an interior point there are hits on
    // both sides, and a line through two interior points has an even number ≥ 2 of hits.
    let cases = [
        (10, 10.0, DVec3::ZERO, false, false),
        (10, 10.0, DVec3::ZERO, true, false),
        (10, 10.0, DVec3::ZERO, false, true),
        (7, 0.3, DVec3::new(1e6, -2e5, 3.0), false, false),
        (7, 0.3, DVec3::new(1e6, -2e5, 3.0), false, true),
        (5, 1e-4, DVec3::new(-0.3, 0.1, 7.0), true, true),
        (6, 3e7, DVec3::new(2e8, 0.0, -1e8), true, false),
        (6, 3e7, DVec3::new(2e8, 0.0, -1e8), false, true),
    ];
    for (m, scale, offset, triangles, face_major) in cases {
        let s = cube_mesh(m, scale, offset, triangles, face_major);
        let bvh = s.bvh();
        // Six sheets, one a face, when the quads come face by face.
        let sheets = if face_major && !triangles { 6 } else { 0 };
        assert_eq!(bvh.sheets.len(), sheets);
        let (mut a, mut b) = (Vec::new(), Vec::new());
        let mut rng = chunk_rng(41, m as u64);
        let centre = offset + DVec3::splat(scale * 0.5);
        let mut inner = || centre + sample_uniform_sphere(canonical_2d(&mut rng)) * 0.45 * scale;
        for k in 0..s.polys.len() {
            let v = s.verts(k);
            for target in [v[0], v[1], (v[0] + v[1]) * 0.5, v[0] + (v[1] - v[0]) * 0.3] {
                for origin in [centre, inner(), inner()] {
                    let line = Line3::new(origin, (target - origin).normalize());
                    check_line(&s, &bvh, &line, &mut a, &mut b);
                    assert!(a.iter().any(|h| h.t > 0.0), "{line:?}");
                    assert!(a.iter().any(|h| h.t < 0.0), "{line:?}");
                    // From far outside, through the target and an interior point.
                    let far = Line3::new(target + (target - origin) * 3.0, origin - target);
                    all_hits_naive3(&s.points, &s.polys, &far, &mut a);
                    assert!(a.len() >= 2, "{far:?}");
                }
            }
        }
        // Axis-aligned lines along the grid lines run in the faces' planes, across seams.
        for i in 0..=m {
            for j in 0..=m {
                let g = |x: usize| x as f64 * scale / m as f64;
                for line in [
                    Line3::new(offset + DVec3::new(g(i), g(j), -1.0), DVec3::Z),
                    Line3::new(offset + DVec3::new(-1.0, g(i), g(j)), DVec3::X),
                    Line3::new(
                        offset + DVec3::new(g(i) + 0.01 * scale, -1.0, g(j)),
                        DVec3::Y,
                    ),
                ] {
                    check_line(&s, &bvh, &line, &mut a, &mut b);
                }
            }
        }
    }
}

#[test]
fn lines_grazing_the_scene_box_agree_and_the_early_miss_is_exact() {
    // `for_each_hit` drops a line whose slab interval of the box of all polygons is empty
    // before the rest of the query. Lines through the box's corners and along its edges,
    // offset by 0, by less than the margin (10⁻⁹ of the scale), by about the margin and
    // by far more, inwards and outwards: the tree's hits are the naive loop's, every line
    // dropped early has no naive hit, and both outcomes occur.
    let (mut a, mut b) = (Vec::new(), Vec::new());
    let (mut dropped, mut kept) = (0usize, 0usize);
    for (m, scale, offset, face_major) in [
        (6, 1.0, DVec3::ZERO, true),
        (5, 3e4, DVec3::new(1e6, -2e5, 3.0), true),
        (4, 0.01, DVec3::new(-0.3, 0.1, 7.0), false),
    ] {
        let s = cube_mesh(m, scale, offset, false, face_major);
        let bvh = s.bvh();
        let mut rng = chunk_rng(97, m as u64);
        for corner in 0..8u32 {
            let bit = |k: u32| f64::from((corner >> k) & 1);
            let c = offset + DVec3::new(bit(0), bit(1), bit(2)) * scale;
            let out = (DVec3::new(bit(0), bit(1), bit(2)) * 2.0 - DVec3::ONE).normalize();
            for rel in [
                0.0, 1e-12, -1e-12, 5e-10, -5e-10, 2e-9, -2e-9, 1e-6, -1e-6, 1e-2,
            ] {
                for k in 0..12 {
                    let dir = match k {
                        0 => DVec3::X,
                        1 => DVec3::Y,
                        2 => DVec3::Z,
                        _ => sample_uniform_sphere(canonical_2d(&mut rng)),
                    };
                    // The direction's component along `out` removed, so the line grazes
                    // the corner (or runs along an edge) before the offset moves it.
                    let graze = dir - out * dir.dot(out);
                    let dir = if graze.length() > 1e-3 { graze } else { dir };
                    let line = Line3::new(c + out * (rel * scale), dir);
                    check_line(&s, &bvh, &line, &mut a, &mut b);
                    let q = BoxQuery::new(line.origin, line.dir, &bvh.frame);
                    if q.misses(&bvh.bounds) {
                        assert!(a.is_empty(), "dropped {line:?} has naive hits {a:?}");
                        dropped += 1;
                    } else {
                        kept += 1;
                    }
                }
            }
        }
    }
    assert!(
        dropped > 100 && kept > 100,
        "dropped {dropped}, kept {kept}"
    );
}

/// An `m × k` grid of quads, row by row as scenes cut faces: lattice points
/// `a + (i + δ) u + (j + δ') v` with interior jitters `δ, δ' ∈ [−jitter, jitter]` (in the
/// plane, so the quads stay planar), shared bit-identically.
fn grid<R: rand_core::Rng>(
    s: &mut Soup,
    rng: &mut R,
    (a, u, v): (DVec3, DVec3, DVec3),
    (m, k): (usize, usize),
    jitter: f64,
) {
    let mut lattice = Vec::with_capacity((m + 1) * (k + 1));
    for j in 0..=k {
        for i in 0..=m {
            let inner = i > 0 && i < m && j > 0 && j < k;
            let mut jig = || {
                if inner {
                    jitter * (2.0 * canonical(rng) - 1.0)
                } else {
                    0.0
                }
            };
            let (x, y) = (i as f64 + jig(), j as f64 + jig());
            lattice.push(a + u * x + v * y);
        }
    }
    let at = |i: usize, j: usize| lattice[j * (m + 1) + i];
    for j in 0..k {
        for i in 0..m {
            s.push(&[at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
}

/// Lines through every lattice point of `s` (random direction, along the grid, across it,
/// grazing it, in its plane), plus global lines through `sphere`.
fn lattice_lines(s: &Soup, seed: u64, sphere: &BoundingSphere) -> Vec<Line3> {
    let mut rng = chunk_rng(seed, 9);
    let mut lines = torture_lines(s, seed);
    for k in 0..s.polys.len() {
        let v = s.verts(k);
        if v.len() != 4 {
            continue;
        }
        let n = crate::geom::polygon_normal(v).normalize_or_zero();
        let (e1, e2) = (
            (v[1] - v[0]).normalize_or_zero(),
            (v[3] - v[0]).normalize_or_zero(),
        );
        let g = (e1 + e2 * 0.37).normalize_or_zero();
        for (p, dir) in [
            (v[2], e2),
            (v[2], (g + n * 1e-3).normalize_or_zero()),
            (v[2], (g - n * 1e-9).normalize_or_zero()),
            (v[0] + n * 1e-12, g),
            ((v[0] + v[2]) * 0.5, (n + e1 * 1e3).normalize_or_zero()),
        ] {
            lines.push(Line3::new(p, dir));
        }
    }
    for _ in 0..3000 {
        lines.push(sample_global_line_3d(sphere, canonical_4d(&mut rng)));
    }
    lines
}

#[test]
fn sheets_agree_with_naive() {
    // Tilted, sheared, slightly jittered, long and thin grids, single rows, a grid too
    // irregular to be a sheet, and a bilinear (trapezoid) grid, in several coordinate
    // ranges.
    let mut rng = chunk_rng(43, 0);
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for (offset, size) in [(0.0, 1.0), (1e6, 1e-3), (-3e8, 5e3), (0.0, 1e-7)] {
        let o = DVec3::new(offset, -0.5 * offset, 0.25 * offset);
        let mut s = Soup::default();
        let t = |x: f64, y: f64, z: f64| DVec3::new(x, y, z) * size;
        let specs = [
            (
                (t(0.1, 0.2, 0.3), t(0.1, 0.0, 0.02), t(0.013, 0.09, -0.01)),
                (12, 9),
                0.0,
            ),
            (
                (t(-1.0, 0.5, 0.0), t(0.0, 0.05, 0.05), t(0.3, 0.0, 0.0)),
                (40, 3),
                1e-8,
            ),
            (
                (t(0.7, -0.9, 0.4), t(0.021, 0.0, 0.0), t(0.0, 0.0, 0.033)),
                (1, 17),
                0.0,
            ),
            (
                (t(0.0, 0.0, -1.0), t(0.2, 0.1, 0.0), t(0.25, -0.1, 0.0)),
                (5, 1),
                0.0,
            ),
            (
                (t(0.3, 0.3, 0.9), t(0.1, 0.0, 0.0), t(0.0, 0.1, 0.0)),
                (6, 6),
                0.45,
            ),
        ];
        for ((a0, u, v), mk, jitter) in specs {
            grid(&mut s, &mut rng, (o + a0, u, v), mk, jitter);
        }
        // A trapezoid cut bilinearly, as scenes cut a non-parallelogram quad.
        let q = [
            t(-0.9, -0.9, 0.5),
            t(0.9, -0.9, 0.5),
            t(0.3, 0.2, 0.5),
            t(-0.3, 0.2, 0.5),
        ];
        let kq = 8;
        let lerp = |p: DVec3, r: DVec3, w: f64| p * (1.0 - w) + r * w;
        let pt = |i: usize, j: usize| {
            let (x, y) = (i as f64 / kq as f64, j as f64 / kq as f64);
            o + lerp(lerp(q[0], q[1], x), lerp(q[3], q[2], x), y)
        };
        for j in 0..kq {
            for i in 0..kq {
                s.push(&[pt(i, j), pt(i + 1, j), pt(i + 1, j + 1), pt(i, j + 1)]);
            }
        }
        let bvh = s.bvh();
        // Sheets: all but the 6 × 6 grid jittered by 0.45 cell and the trapezoid.
        assert_eq!(bvh.sheets.len(), 4, "{bvh:?}");
        let sphere =
            BoundingSphere::of_bounds(o - DVec3::splat(2.0 * size), o + DVec3::splat(2.0 * size));
        let mut total = 0;
        for line in lattice_lines(&s, 44, &sphere) {
            check_line(&s, &bvh, &line, &mut a, &mut b);
            total += a.len();
        }
        assert!(total > 3000, "{total}");
    }
}

#[test]
fn scene_faces_become_sheets() {
    // The scenes' cubes cut their faces into grids whose edges meet the next face's
    // bit-identically: each face is one sheet (not folded onto its neighbour), and the
    // tree still equals the naive loops.
    for (scene, sheets) in [
        (crate::scene::Scene3::cube(12).unwrap(), 6),
        (
            crate::scene::Scene3::cube_room_with_cubes(2, false, 3).unwrap(),
            6,
        ),
    ] {
        let mut s = Soup::default();
        for i in 0..scene.n_patches() {
            s.push(scene.patch_vertices(i));
        }
        let bvh = s.bvh();
        assert_eq!(bvh.sheets.len(), sheets, "{bvh:?}");
        let (lo, hi) = scene.bounds();
        let sphere = BoundingSphere::of_bounds(lo, hi);
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for line in lattice_lines(&s, 45, &sphere) {
            check_line(&s, &bvh, &line, &mut a, &mut b);
        }
    }
}

#[test]
fn local_lines_first_hit_in_a_closed_cube() {
    // Inside a closed mesh facing inwards every local ray hits another patch.
    let s = cube_mesh(6, 2.0, DVec3::new(-1.0, -1.0, -1.0), false, true);
    let bvh = s.bvh();
    let mut rng = chunk_rng(42, 0);
    for k in 0..20_000 {
        let i = k % s.polys.len();
        let v = s.verts(i);
        let n = crate::geom::polygon_normal(v).normalize();
        let line = sample_local_line_3d(v, n, canonical_4d(&mut rng));
        let hit = bvh.first_hit(line.origin, line.dir, 1e-9);
        assert_eq!(
            hit,
            first_hit_naive3(&s.points, &s.polys, line.origin, line.dir, 1e-9)
        );
        let hit = hit.expect("a closed mesh catches every ray");
        assert!(hit.t > 0.0 && hit.t <= 2.0 * 3f64.sqrt() + 1e-9);
        assert_ne!(hit.prim as usize, i);
    }
}

#[test]
fn crofton_hit_frequency_through_the_bvh() {
    // (a) N uniform global lines meeting a sphere of radius R hit a convex polygon of area
    // A with frequency 2A/(4πR²) (Cauchy–Crofton), within 5 binomial σ; 10⁶ lines.
    let s = soup(9, 24);
    let bvh = s.bvh();
    let sphere = BoundingSphere::of_bounds(DVec3::splat(-14.0), DVec3::splat(14.0));
    let n = 1_000_000u32;
    let mut counts = std::vec![0u32; s.polys.len()];
    let mut rng = chunk_rng(10, 0);
    let mut out = Vec::new();
    for _ in 0..n {
        bvh.all_hits(
            &sample_global_line_3d(&sphere, canonical_4d(&mut rng)),
            &mut out,
        );
        for h in &out {
            counts[h.prim as usize] += 1;
        }
    }
    for (k, &c) in counts.iter().enumerate() {
        let area = crate::geom::polygon_area(s.verts(k));
        let p = 2.0 * area / sphere.surface_area();
        let sigma = libm::sqrt(p * (1.0 - p) / f64::from(n));
        let f = f64::from(c) / f64::from(n);
        assert!(
            (f - p).abs() <= 5.0 * sigma + 1e-12,
            "A = {area}: f = {f}, p = {p}"
        );
    }
}

#[test]
fn weird_inputs_never_panic_or_give_nan() {
    let mut s = Soup::default();
    s.push(&[DVec3::NAN, DVec3::ONE, DVec3::X]);
    s.push(&[DVec3::INFINITY, DVec3::ZERO, DVec3::Y]);
    s.push(&[DVec3::ONE, DVec3::ONE, DVec3::ONE]); // a point
    s.push(&[DVec3::ZERO, DVec3::X, DVec3::X * 2.0]); // collinear
    s.push(&[DVec3::ZERO, DVec3::X]); // two vertices
    s.push(&[]);
    s.push(&[
        DVec3::splat(-1e300),
        DVec3::new(1e300, -1e300, 0.0),
        DVec3::splat(1e300),
    ]);
    s.push(&[
        DVec3::new(1e-310, 0.0, 0.0),
        DVec3::new(0.0, 1e-310, 0.0),
        DVec3::new(0.0, 0.0, 1e-310),
    ]);
    // A valid square x ∈ [0, 1], y ∈ [0, 1] at z = 0.5 (index 8).
    s.push(&[
        DVec3::new(0.0, 0.0, 0.5),
        DVec3::new(1.0, 0.0, 0.5),
        DVec3::new(1.0, 1.0, 0.5),
        DVec3::new(0.0, 1.0, 0.5),
    ]);
    let bvh = s.bvh();
    assert_eq!(bvh.len(), 9);
    let mut out = Vec::new();
    for line in [
        Line3::new(DVec3::ZERO, DVec3::ZERO),
        Line3::new(DVec3::NAN, DVec3::X),
        Line3::new(DVec3::new(0.5, 0.5, -5.0), DVec3::Z),
        Line3::new(
            DVec3::new(0.5, 0.5, -5.0),
            DVec3::new(0.0, 0.0, f64::INFINITY),
        ),
        Line3::new(DVec3::new(1e300, 0.0, 0.0), DVec3::Y),
        Line3::new(DVec3::new(0.5, 0.5, 0.0), DVec3::new(1e-300, 0.0, 1e-300)),
    ] {
        bvh.all_hits(&line, &mut out);
        assert!(out.iter().all(|h| h.t.is_finite()));
        let mut naive = Vec::new();
        all_hits_naive3(&s.points, &s.polys, &line, &mut naive);
        assert_eq!(out, naive);
        for t_min in [f64::NAN, 0.0, f64::INFINITY] {
            let h = bvh.first_hit(line.origin, line.dir, t_min);
            assert!(h.is_none_or(|h| h.t.is_finite()));
            assert_eq!(
                h,
                first_hit_naive3(&s.points, &s.polys, line.origin, line.dir, t_min)
            );
        }
    }
    bvh.all_hits(&Line3::new(DVec3::new(0.5, 0.5, -5.0), DVec3::Z), &mut out);
    assert_eq!(out, [Hit3 { t: 5.5, prim: 8 }]);
    // Out-of-range polygons are an error for the tree and skipped by the naive loop.
    let bad = [(0usize, 3usize), (usize::MAX, 2)];
    assert!(Bvh3::build(&s.points[..3], &bad).is_err());
    assert!(Bvh3::build(&s.points[..3], &[(1, 3)]).is_err());
    all_hits_naive3(
        &s.points[..3],
        &bad,
        &Line3::new(DVec3::ZERO, DVec3::Z),
        &mut out,
    );
    assert!(out.is_empty());
    // Empty input.
    let empty = Bvh3::build(&[], &[]).unwrap();
    assert!(empty.is_empty());
    empty.all_hits(&Line3::new(DVec3::ZERO, DVec3::Z), &mut out);
    assert!(out.is_empty() && empty.first_hit(DVec3::ZERO, DVec3::Z, 0.0).is_none());
}

/// The `f32` node test never culls a box whose `f64` slab interval (the polygon test's
/// step 2) is not empty: boxes of every size, near and far from the frame's centre, and
/// lines grazing their corners and edges by a few margins, along random, axis-aligned and
/// nearly axis-aligned directions. It also culls many of the lines that miss by more than
/// its second margin.
#[test]
fn f32_node_test_is_conservative() {
    let mut rng = chunk_rng(41, 0);
    let (mut grazing, mut culled, mut declined) = (0, 0, 0);
    for k in 0..4000 {
        let size = libm::pow(10.0, canonical(&mut rng) * 12.0 - 6.0);
        let offset = libm::pow(10.0, canonical(&mut rng) * 8.0 - 4.0);
        let centre = (DVec3::new(
            canonical(&mut rng),
            canonical(&mut rng),
            canonical(&mut rng),
        ) - 0.5)
            * offset;
        let lo = centre - size * DVec3::new(canonical(&mut rng), canonical(&mut rng), 0.3);
        let hi = centre + size * DVec3::new(canonical(&mut rng), 0.5, canonical(&mut rng));
        // The frame of the box and a far point: its centre is not the box's.
        let far = DVec3::splat(offset * (1.0 + canonical(&mut rng)));
        let points = [lo, hi, far];
        let frame = Frame::new(&points, &[(0, 3)]);
        let (lo_c, hi_c) = (lo - frame.c, hi - frame.c);
        // The node's f32 box, rounded outwards, in the four lanes.
        let mut node = Node::EMPTY;
        for c in 0..WIDTH {
            node.set(c, Ref::default(), lo_c, hi_c);
        }
        // A corner or an edge point of the box, moved off it by a few margins.
        let pick = |u: f64| if u < 0.5 { 0 } else { 1 };
        let corner = DVec3::new(
            [lo.x, hi.x][pick(canonical(&mut rng))],
            [lo.y, hi.y][pick(canonical(&mut rng))],
            [lo.z, hi.z][pick(canonical(&mut rng))],
        );
        let on_edge = corner.lerp(lo, if k % 2 == 0 { 0.0 } else { canonical(&mut rng) });
        // A few margins (grazing), or far beyond the second margin δ (clear misses).
        let reach = if (k / 5) % 2 == 0 { 8e-9 } else { 1e-3 };
        let push = (canonical(&mut rng) - 0.5) * reach * (offset + size);
        let mut dir = sample_uniform_sphere(canonical_2d(&mut rng));
        match k % 5 {
            0 => dir.x = 0.0,
            1 => dir = DVec3::Z * dir.z.signum(),
            2 => dir.y = 1e-13,
            _ => {}
        }
        let dir = dir.normalize_or_zero();
        let origin = on_edge + sample_uniform_sphere(canonical_2d(&mut rng)) * push
            - dir * (canonical(&mut rng) * 3.0 * (offset + size));
        let q = Query::new(origin, dir, &frame);
        let (enter, exit) = q.slab(&[lo_c, hi_c]);
        let Some(s32) = q.slab32(frame.scale) else {
            declined += 1;
            continue;
        };
        let mask = by_octant_mask(&q, &s32, &node);
        if enter <= exit {
            grazing += 1;
            assert_eq!(mask, 0b1111, "box {lo:?} {hi:?} line {origin:?} {dir:?}");
        } else if mask == 0 {
            culled += 1;
        }
    }
    assert!(grazing > 500 && culled > 500, "{grazing} {culled}");
    // Only the direction with a 1e-13 component is outside the error bounds.
    assert!(declined <= 800, "{declined}");
}

/// The `f32` test's mask of `node` for the query's octant.
fn by_octant_mask(q: &Query, s: &Slab32, node: &Node) -> u32 {
    match q.near {
        [0, 0, 0] => s.meets::<0, 0, 0>(node),
        [0, 0, _] => s.meets::<0, 0, 1>(node),
        [0, _, 0] => s.meets::<0, 1, 0>(node),
        [0, _, _] => s.meets::<0, 1, 1>(node),
        [_, 0, 0] => s.meets::<1, 0, 0>(node),
        [_, 0, _] => s.meets::<1, 0, 1>(node),
        [_, _, 0] => s.meets::<1, 1, 0>(node),
        [_, _, _] => s.meets::<1, 1, 1>(node),
    }
}

#[test]
fn nodes_are_two_cache_lines_and_depth_is_bounded() {
    assert_eq!(core::mem::size_of::<Node>(), 128);
    // Exponentially spaced squares drive the SAH to one-sided splits; identical ones give
    // no usable SAH plane at all.
    let mut s = Soup::default();
    for k in 0..2000 {
        let x = libm::pow(1.01, f64::from(k));
        s.push(&[
            DVec3::new(x, 0.0, 0.0),
            DVec3::new(x, 1.0, 0.0),
            DVec3::new(x, 1.0, 1.0),
            DVec3::new(x, 0.0, 1.0),
        ]);
    }
    for _ in 0..3000 {
        s.push(&[DVec3::ZERO, DVec3::X, DVec3::Y]);
    }
    let bvh = s.bvh();
    assert!(bvh.depth() < 64, "depth {}", bvh.depth());
    assert!(bvh.levels <= 32, "levels {}", bvh.levels);
    assert!(bvh.node_count() < s.polys.len());
    let (mut a, mut b) = (Vec::new(), Vec::new());
    let line = Line3::new(DVec3::new(-1.0, 0.25, 0.25), DVec3::X);
    check_line(&s, &bvh, &line, &mut a, &mut b);
    assert_eq!(a.len(), 2000);
    let line = Line3::new(DVec3::new(0.1, 0.1, -1.0), DVec3::Z);
    check_line(&s, &bvh, &line, &mut a, &mut b);
    assert_eq!(a.len(), 3000);
}

/// Finite coordinates for the property tests, and small lattice points (shared vertices,
/// exact hits through vertices and edges).
fn point() -> impl Strategy<Value = DVec3> {
    prop_oneof![
        (-50.0..50.0f64, -50.0..50.0f64, -50.0..50.0f64).prop_map(|(x, y, z)| DVec3::new(x, y, z)),
        (-3i32..=3, -3i32..=3, -3i32..=3).prop_map(|(x, y, z)| DVec3::new(
            f64::from(x),
            f64::from(y),
            f64::from(z)
        )),
    ]
}

/// Triangles and parallelograms of any three points (planar and convex by construction).
fn polygon() -> impl Strategy<Value = Vec<DVec3>> {
    (point(), point(), point(), any::<bool>()).prop_map(|(a, b, c, quad)| {
        if quad {
            std::vec![a, b, b + (c - a), c]
        } else {
            std::vec![a, b, c]
        }
    })
}

fn line() -> impl Strategy<Value = Line3> {
    let dir = prop_oneof![
        (0.0..1.0f64, 0.0..1.0f64).prop_map(|(a, b)| sample_uniform_sphere([a, b])),
        Just(DVec3::X),
        Just(DVec3::Y),
        Just(-DVec3::Z),
        Just(DVec3::new(1.0, 1.0, 0.0).normalize()),
        (-2i32..=2, -2i32..=2, -2i32..=2).prop_map(|(x, y, z)| DVec3::new(
            f64::from(x),
            f64::from(y),
            f64::from(z)
        )),
    ];
    (point(), dir).prop_map(|(o, d)| Line3::new(o, d))
}

/// A grid of 1–12 × 1–12 quads with random frame and jitter, among a few loose polygons.
pub(in crate::accel) fn sheet_soup() -> impl Strategy<Value = (Soup, Vec<DVec3>)> {
    let vec3 = |r: f64| (-r..r, -r..r, -r..r).prop_map(|(x, y, z)| DVec3::new(x, y, z));
    (
        vec3(20.0),
        vec3(3.0),
        vec3(3.0),
        (1usize..12, 1usize..12),
        prop_oneof![Just(0.0), 0.0..1e-7f64, 0.0..0.4f64],
        any::<u64>(),
        proptest::collection::vec(polygon(), 0..6),
    )
        .prop_map(|(a, u, v, mk, jitter, seed, extra)| {
            let mut s = Soup::default();
            let mut rng = chunk_rng(seed, 0);
            grid(&mut s, &mut rng, (a, u, v), mk, jitter);
            for p in &extra {
                s.push(p);
            }
            let lattice = s.points.clone();
            (s, lattice)
        })
}

proptest! {
    #[test]
    fn bvh_sheets_equal_naive((s, lattice) in sheet_soup(),
                              lines in proptest::collection::vec(line(), 1..12)) {
        let bvh = s.bvh();
        let (mut a, mut b) = (Vec::new(), Vec::new());
        let mut all = lines.clone();
        // Lines through the lattice points, in the given directions.
        for (k, p) in lattice.iter().enumerate().step_by(3) {
            all.push(Line3::new(*p, lines[k % lines.len()].dir));
        }
        for l in &all {
            all_hits_naive3(&s.points, &s.polys, l, &mut a);
            bvh.all_hits(l, &mut b);
            prop_assert_eq!(&a, &b);
            for t_min in [0.0, 1e-9] {
                prop_assert_eq!(
                    bvh.first_hit(l.origin, l.dir, t_min),
                    first_hit_naive3(&s.points, &s.polys, l.origin, l.dir, t_min)
                );
            }
        }
    }

    #[test]
    fn bvh_all_hits_equals_naive(polys in proptest::collection::vec(polygon(), 0..120),
                                 lines in proptest::collection::vec(line(), 1..16)) {
        let mut s = Soup::default();
        for p in &polys {
            s.push(p);
        }
        let bvh = s.bvh();
        prop_assert_eq!(bvh.len(), polys.len());
        let (mut a, mut b) = (Vec::new(), Vec::new());
        let mut all = lines.clone();
        // Lines through the polygons' vertices and edge midpoints too.
        for (k, p) in polys.iter().enumerate() {
            let d = lines[k % lines.len()].dir;
            all.push(Line3::new(p[0], d));
            all.push(Line3::new((p[1] + p[2]) * 0.5, d));
        }
        for l in &all {
            all_hits_naive3(&s.points, &s.polys, l, &mut a);
            bvh.all_hits(l, &mut b);
            prop_assert_eq!(&a, &b);
            // The walks with the large stack and with the f64 node tests.
            let (large, mut by_f64) = bvh.for_each_hit_other_walks(l);
            if let Some(mut large) = large {
                crate::accel::sort_hits(&mut large);
                prop_assert_eq!(&a, &large);
            }
            crate::accel::sort_hits(&mut by_f64);
            prop_assert_eq!(&a, &by_f64);
        }
    }

    #[test]
    fn bvh_first_hit_equals_naive(polys in proptest::collection::vec(polygon(), 0..120),
                                  lines in proptest::collection::vec(line(), 1..16),
                                  t_min in prop_oneof![Just(0.0), Just(1e-9), -50.0..50.0f64]) {
        let mut s = Soup::default();
        for p in &polys {
            s.push(p);
        }
        let bvh = s.bvh();
        for l in &lines {
            prop_assert_eq!(
                bvh.first_hit(l.origin, l.dir, t_min),
                first_hit_naive3(&s.points, &s.polys, l.origin, l.dir, t_min)
            );
        }
    }
}
