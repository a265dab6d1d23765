use super::*;
use super::{cornell::*, cubes::*, furniture::*, solids::*};
use crate::geom::DVec3;
use crate::math;
use crate::scene::scene3::{MAX_GRID, MAX_TRIANGLE_LEVEL};
use std::collections::BTreeMap;
use std::vec;
use std::vec::Vec;

/// Whether object `o` of `scene` belongs to the enclosure (faces the room's interior).
fn is_enclosure(scene: &Scene3, o: usize) -> bool {
    matches!(scene.objects()[o].as_str(), ENCLOSURE | "light")
}

/// Mean of the vertices of every face of each object.
fn object_centres(scene: &Scene3) -> Vec<DVec3> {
    let mut sum = vec![(DVec3::ZERO, 0.0); scene.objects().len()];
    for (f, face) in scene.faces().iter().enumerate() {
        for &v in scene.face_vertices(f) {
            sum[face.object].0 += v;
            sum[face.object].1 += 1.0;
        }
    }
    sum.into_iter().map(|(s, n)| s / n).collect()
}

/// Enclosure faces see `centre` in front of them; every other face points away from its
/// object's centre; patches share their face's normal.
fn check_orientation(scene: &Scene3, centre: DVec3) {
    let centres = object_centres(scene);
    for (f, face) in scene.faces().iter().enumerate() {
        let mean = vertex_mean(scene.face_vertices(f));
        let facing = if is_enclosure(scene, face.object) {
            (centre - mean).dot(face.normal)
        } else {
            (mean - centres[face.object]).dot(face.normal)
        };
        assert!(
            facing > 0.0,
            "face {f} of {} faces the wrong way",
            scene.objects()[face.object]
        );
        for p in &scene.patches()[face.patches.clone()] {
            assert_eq!(p.normal, face.normal);
        }
    }
}

/// Closed surfaces: every face edge, split at the vertices of other faces lying on it, is
/// traversed exactly once in each direction (an oriented 2-manifold without boundary, with
/// T-junctions allowed). Quadratic: small scenes only.
fn check_closed(scene: &Scene3) {
    let (lo, hi) = scene.bounds();
    let scale = (hi - lo).length();
    let key = |p: DVec3| (p / (1e-7 * scale)).round().to_array().map(|c| c as i64);
    let mut unique = BTreeMap::new();
    for f in 0..scene.faces().len() {
        for &v in scene.face_vertices(f) {
            unique.entry(key(v)).or_insert(v);
        }
    }
    let points: Vec<DVec3> = unique.into_values().collect();
    let mut directed: BTreeMap<([i64; 3], [i64; 3]), u32> = BTreeMap::new();
    for f in 0..scene.faces().len() {
        let v = scene.face_vertices(f);
        for k in 0..v.len() {
            let (a, b) = (v[k], v[(k + 1) % v.len()]);
            let d = b - a;
            let mut inner: Vec<(f64, DVec3)> = points
                .iter()
                .filter_map(|&p| {
                    let t = (p - a).dot(d) / d.length_squared();
                    let off = (a + d * t - p).length();
                    (t > 1e-9 && t < 1.0 - 1e-9 && off <= 1e-9 * scale).then_some((t, p))
                })
                .collect();
            inner.sort_by(|x, y| x.0.total_cmp(&y.0));
            let mut chain = vec![a];
            chain.extend(inner.into_iter().map(|(_, p)| p));
            chain.push(b);
            for w in chain.windows(2) {
                *directed.entry((key(w[0]), key(w[1]))).or_default() += 1;
            }
        }
    }
    for (&(a, b), &n) in &directed {
        assert_eq!(n, 1, "edge {a:?} → {b:?} used {n} times");
        assert_eq!(
            directed.get(&(b, a)),
            Some(&1),
            "edge {a:?} → {b:?} unmatched"
        );
    }
}

/// Σ of the faces' vector areas: zero over closed surfaces.
fn vector_area(scene: &Scene3, faces: impl Iterator<Item = usize>) -> DVec3 {
    faces
        .map(|f| crate::geom::polygon_normal(scene.face_vertices(f)))
        .sum()
}

/// The whole scene's, and each non-enclosure object's, vector areas vanish (relative to the
/// total area); `closed_objects = false` skips the per-object check (blocks on the floor).
fn check_vector_areas(scene: &Scene3, closed_objects: bool) {
    let tol = 1e-9 * scene.total_area();
    let all = vector_area(scene, 0..scene.faces().len());
    assert!(all.length() < tol, "open scene: Σ vector area {all}");
    if closed_objects {
        for o in (0..scene.objects().len()).filter(|&o| !is_enclosure(scene, o)) {
            let faces = (0..scene.faces().len()).filter(|&f| scene.faces()[f].object == o);
            let s = vector_area(scene, faces);
            assert!(s.length() < tol, "{} open: {s}", scene.objects()[o]);
        }
    }
}

/// Vertices and face normals of each non-enclosure object.
fn objects(scene: &Scene3) -> Vec<(Vec<DVec3>, Vec<DVec3>)> {
    let mut out = vec![(Vec::new(), Vec::new()); scene.objects().len()];
    for (f, face) in scene.faces().iter().enumerate() {
        out[face.object].0.extend_from_slice(scene.face_vertices(f));
        out[face.object].1.push(face.normal);
    }
    (0..out.len())
        .filter(|&o| !is_enclosure(scene, o))
        .map(|o| core::mem::take(&mut out[o]))
        .collect()
}

/// The gap between two convex objects along the separating axes among their face normals
/// (exact for boxes and vertical prisms), negative if none separates them.
fn gap(a: &(Vec<DVec3>, Vec<DVec3>), b: &(Vec<DVec3>, Vec<DVec3>)) -> f64 {
    let range = |v: &[DVec3], n: DVec3| {
        v.iter()
            .map(|p| p.dot(n))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                (lo.min(x), hi.max(x))
            })
    };
    a.1.iter()
        .chain(&b.1)
        .map(|&n| {
            let (a_lo, a_hi) = range(&a.0, n);
            let (b_lo, b_hi) = range(&b.0, n);
            (b_lo - a_hi).max(a_lo - b_hi)
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

/// Objects at least `min_gap` apart and from the walls of the box room `[lo, hi]`, except
/// from the floor (the low side of axis `floor.0`), which they keep `floor.1` from.
fn check_separated(scene: &Scene3, lo: DVec3, hi: DVec3, min_gap: f64, floor: (usize, f64)) {
    let objs = objects(scene);
    for (i, a) in objs.iter().enumerate() {
        let (o_lo, o_hi) = a.0.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(l, h), &p| (l.min(p), h.max(p)),
        );
        let (below, above) = ((o_lo - lo).to_array(), (hi - o_hi).to_array());
        for axis in 0..3 {
            let low = if axis == floor.0 { floor.1 } else { min_gap };
            assert!(below[axis] >= low, "object {i} {} from a wall", below[axis]);
            assert!(
                above[axis] >= min_gap,
                "object {i} {} from a wall",
                above[axis]
            );
        }
        for (j, b) in objs.iter().enumerate().skip(i + 1) {
            let g = gap(a, b);
            assert!(g >= min_gap, "objects {i} and {j} {g} apart");
        }
    }
}

/// Casts `lines` random lines through the scene (through two uniform points of a sphere
/// around it) and checks what closed, consistently oriented surfaces imply: along each line
/// the faces met alternate between being crossed from behind (`d · n > 0`: leaving a solid,
/// or entering the room through its back) and from the front, starting from behind and
/// ending at a front, so every free segment joins two faces that face it.
fn check_lines(scene: &Scene3, lines: u64, seed: u64) {
    let (lo, hi) = scene.bounds();
    let (centre, radius) = (0.5 * (lo + hi), (hi - lo).length());
    let mut rng = crate::lines::chunk_rng(seed, 0);
    let mut sphere = || {
        let z = 1.0 - 2.0 * crate::lines::canonical(&mut rng);
        let phi = 2.0 * core::f64::consts::PI * crate::lines::canonical(&mut rng);
        let r = math::sqrt((1.0 - z * z).max(0.0));
        centre + radius * DVec3::new(r * math::cos(phi), r * math::sin(phi), z)
    };
    for line in 0..lines {
        let (o, d) = {
            let (p, q) = (sphere(), sphere());
            (p, q - p)
        };
        let mut hits: Vec<(f64, bool)> = Vec::new();
        for (f, face) in scene.faces().iter().enumerate() {
            let v = scene.face_vertices(f);
            let n = face.normal;
            let dn = d.dot(n);
            if dn == 0.0 {
                continue;
            }
            let t = (v[0] - o).dot(n) / dn;
            let x = o + d * t;
            let inside = (0..v.len()).all(|k| {
                let (a, b) = (v[k], v[(k + 1) % v.len()]);
                (b - a).cross(x - a).dot(n) > 0.0
            });
            if inside {
                hits.push((t, dn > 0.0));
            }
        }
        hits.sort_by(|a, b| a.0.total_cmp(&b.0));
        assert!(
            hits.len().is_multiple_of(2),
            "line {line}: {} hits",
            hits.len()
        );
        for (k, &(t, behind)) in hits.iter().enumerate() {
            assert_eq!(behind, k % 2 == 0, "line {line}: hit {k} at t = {t}");
        }
    }
}

/// Positional entropy `H_P = −Σ a_i log₂ a_i` (thesis (3.4)).
fn positional_entropy(scene: &Scene3) -> f64 {
    let a_t = scene.total_area();
    -math::sum(scene.patches().iter().map(|p| {
        let a = p.area / a_t;
        a * math::log2(a)
    }))
}

fn kind(r: Result<Scene3>) -> ErrorKind {
    r.unwrap_err().kind().clone()
}

#[test]
fn cube_grids_match_figure_3_5() {
    for (grid, n, h_p) in [(10, 600, 9.229), (20, 2400, 11.229), (30, 5400, 12.399)] {
        let s = Scene3::cube(grid).unwrap();
        assert_eq!(s.n_patches(), n);
        assert_eq!(s.faces().len(), 6);
        assert!((s.total_area() - 6.0).abs() < 1e-12);
        assert!((positional_entropy(&s) - h_p).abs() < 5e-4);
        assert_eq!(s.bounds(), (DVec3::ZERO, DVec3::ONE));
        check_orientation(&s, DVec3::splat(0.5));
        check_vector_areas(&s, true);
    }
    check_closed(&Scene3::cube(2).unwrap());
}

#[test]
fn platonic_solids_inscribed_in_the_unit_sphere() {
    let phi = 0.5 * (1.0 + math::sqrt(5.0));
    let sqrt3 = math::sqrt(3.0);
    // (name, faces, vertices per face, edge length)
    let solids = [
        ("tetrahedron", 4, 3, math::sqrt(8.0 / 3.0)),
        ("cube", 6, 4, 2.0 / sqrt3),
        ("octahedron", 8, 3, math::sqrt(2.0)),
        ("dodecahedron", 12, 5, 2.0 / (sqrt3 * phi)),
        (
            "icosahedron",
            20,
            3,
            4.0 / math::sqrt(10.0 + 2.0 * math::sqrt(5.0)),
        ),
    ];
    for (name, n, corners, edge) in solids {
        let s = Scene3::platonic(name, Subdivision::None).unwrap();
        assert_eq!(s.n_patches(), n, "{name}");
        for f in 0..n {
            let v = s.face_vertices(f);
            assert_eq!(v.len(), corners, "{name}");
            for k in 0..corners {
                assert!((v[k].length() - 1.0).abs() < 1e-12);
                assert!(((v[(k + 1) % corners] - v[k]).length() - edge).abs() < 1e-12);
            }
        }
        // Area: n regular polygons of this edge
        let half_angle = core::f64::consts::PI / corners as f64;
        let polygon =
            0.25 * corners as f64 * edge * edge * math::cos(half_angle) / math::sin(half_angle);
        assert!(
            (s.total_area() - n as f64 * polygon).abs() < 1e-10,
            "{name}"
        );
        check_orientation(&s, DVec3::ZERO);
        check_vector_areas(&s, true);
        check_closed(&s);
    }
    assert_eq!(Scene3::tetrahedron().unwrap().n_patches(), 4);
    assert_eq!(Scene3::octahedron().unwrap().n_patches(), 8);
    assert_eq!(Scene3::dodecahedron().unwrap().n_patches(), 12);
    assert_eq!(Scene3::icosahedron().unwrap().n_patches(), 20);
    let fine = Scene3::platonic("octahedron", Subdivision::Grid(3)).unwrap();
    assert_eq!(fine.n_patches(), 72);
    assert!(matches!(
        kind(Scene3::platonic("cuboid", Subdivision::None)),
        ErrorKind::UnknownPreset(_)
    ));
    assert!(matches!(
        kind(Scene3::platonic("cube", Subdivision::Grid(0))),
        ErrorKind::BadSubdivision { .. }
    ));
}

#[test]
fn tetrahedron_meshes_and_spheres() {
    let area = Scene3::tetrahedron().unwrap().total_area();
    for level in 0..4 {
        let s = Scene3::tetrahedron_mesh(level).unwrap();
        assert_eq!(s.n_patches(), 4 << (2 * level));
        assert!((s.total_area() - area).abs() < 1e-12);
        assert_eq!(s.materials().iter().filter(|m| m.is_emitter()).count(), 1);
        // One face only has a blue component (Table 5.3).
        let blue = s.materials().iter().filter(|m| m.reflectance[2] > 0.0);
        assert_eq!(blue.count(), 1);
        check_orientation(&s, DVec3::ZERO);
    }
    check_closed(&Scene3::tetrahedron_mesh(1).unwrap());
    let mut last = 0.0;
    for level in 0..=4 {
        let s = Scene3::sphere(level).unwrap();
        assert_eq!(s.n_patches(), 20 << (2 * level));
        for &p in s.points() {
            assert!((p.length() - 1.0).abs() < 1e-12);
        }
        // Inscribed polyhedra grow towards the sphere's area 4π.
        assert!(s.total_area() > last && s.total_area() < 4.0 * core::f64::consts::PI);
        last = s.total_area();
        check_orientation(&s, DVec3::ZERO);
        check_vector_areas(&s, true);
    }
    assert!(4.0 * core::f64::consts::PI - last < 0.04);
    check_closed(&Scene3::sphere(2).unwrap());
    assert!(matches!(
        kind(Scene3::sphere(MAX_SPHERE_LEVEL + 1)),
        ErrorKind::TooLarge { .. }
    ));
    assert!(matches!(
        kind(Scene3::tetrahedron_mesh(MAX_TRIANGLE_LEVEL + 1)),
        ErrorKind::BadSubdivision { .. }
    ));
    assert!(matches!(
        kind(Scene3::tetrahedron_mesh(MAX_TRIANGLE_LEVEL)),
        ErrorKind::TooManyPatches { .. }
    ));
}

/// Area of the polygon `(x, z)` by the shoelace formula.
fn footprint_area(corners: &[[f64; 2]]) -> f64 {
    let n = corners.len();
    0.5 * (0..n)
        .map(|k| {
            let ([x0, z0], [x1, z1]) = (corners[k], corners[(k + 1) % n]);
            x0 * z1 - x1 * z0
        })
        .sum::<f64>()
        .abs()
}

#[test]
fn cornell_box_geometry() {
    let [sx, sy, sz] = CORNELL_ROOM;
    let room = 2.0 * (sx * sy + sx * sz + sy * sz);
    let short = [[130.0, 65.0], [82.0, 225.0], [240.0, 272.0], [290.0, 114.0]];
    let tall = [
        [423.0, 247.0],
        [265.0, 296.0],
        [314.0, 456.0],
        [472.0, 406.0],
    ];
    let sides = |c: &[[f64; 2]], h: f64| {
        (0..4)
            .map(|k| {
                let ([x0, z0], [x1, z1]) = (c[k], c[(k + 1) % 4]);
                h * math::hypot(x1 - x0, z1 - z0)
            })
            .sum::<f64>()
    };
    let blocks = sides(&short, 165.0) + sides(&tall, 330.0);
    let (a_short, a_tall) = (footprint_area(&short), footprint_area(&tall));
    let centre = DVec3::new(0.5 * sx, 0.5 * sy, 0.5 * sz);
    for lifted in [false, true] {
        for grid in [1, 2, 5] {
            let s = Scene3::cornell_box(lifted, grid).unwrap();
            // Lifted: floor whole, blocks closed by bottoms; standing: floor minus footprints.
            let expected = if lifted {
                room + blocks + 2.0 * (a_short + a_tall)
            } else {
                room + blocks
            };
            assert!(
                (s.total_area() - expected).abs() < 1e-9 * expected,
                "{lifted} {grid}: {} vs {expected}",
                s.total_area()
            );
            assert_eq!(
                s.objects(),
                [ENCLOSURE, "light", "short-block", "tall-block"]
            );
            check_orientation(&s, centre);
            check_vector_areas(&s, lifted);
            if grid <= 2 {
                check_closed(&s);
            }
            let up = (1, if lifted { 1.0976 - 1e-9 } else { 0.0 });
            check_separated(&s, DVec3::ZERO, DVec3::from(CORNELL_ROOM), 1.0, up);
            let light = s
                .patches()
                .iter()
                .filter(|p| s.materials()[p.material].is_emitter());
            let light_area: f64 = light.map(|p| p.area).sum();
            assert!((light_area - 130.0 * 105.0).abs() < 1e-9);
        }
    }
    // The coarsest lifted box: 5 walls, 4 ceiling pieces around the light, the light and
    // 12 block faces.
    let coarse = Scene3::cornell_box(true, 1).unwrap();
    assert_eq!(coarse.faces().len(), 22);
    assert_eq!(coarse.n_patches(), 22);
    // Grid 10: 400 wall, 100 floor and 104 ceiling patches around a 2 × 2 light, blocks of
    // 3 × 3 and 6 × 6 cells a side (54 + 162 lifted); standing, the floor gains pieces
    // around the footprints and the blocks lose their bottoms.
    assert_eq!(Scene3::cornell_box(true, 10).unwrap().n_patches(), 824);
    assert_eq!(Scene3::cornell_box(false, 10).unwrap().n_patches(), 810);
    assert!(matches!(
        kind(Scene3::cornell_box(true, 0)),
        ErrorKind::BadSubdivision { .. }
    ));
    assert!(matches!(
        kind(Scene3::cornell_box(false, MAX_GRID + 1)),
        ErrorKind::BadSubdivision { .. }
    ));
    assert!(matches!(
        kind(Scene3::cornell_box(false, 1000)),
        ErrorKind::TooManyPatches { .. }
    ));
}

#[test]
fn cornell_thesis_meshes_have_the_thesis_patch_counts() {
    // Table 4.6 (19, 1924 patches) and Tables 5.2/5.5 (121, 481, 1924), then one level finer.
    let [sx, sy, sz] = CORNELL_ROOM;
    let room = 2.0 * (sx * sy + sx * sz + sy * sz);
    let light = 130.0 * 105.0;
    for (level, patches) in [(0, 19), (1, 121), (2, 481), (3, 1924), (4, 7696)] {
        let s = Scene3::cornell_box_thesis(level).unwrap();
        assert_eq!(s.n_patches(), patches, "level {level}");
        assert_eq!(s.faces().len(), 19);
        assert_eq!(
            s.objects(),
            [ENCLOSURE, "light", "short-block", "tall-block"]
        );
        // Every patch edge within the level's bound.
        let bound = CORNELL_THESIS_EDGE[level as usize];
        for i in 0..s.n_patches() {
            let v = s.patch_vertices(i);
            for k in 0..v.len() {
                assert!((v[(k + 1) % v.len()] - v[k]).length() <= bound);
            }
        }
        // The whole room (ceiling under the light included), the light, the closed blocks.
        let lifted = Scene3::cornell_box(true, 1).unwrap();
        let blocks = lifted.total_area() - room;
        let expected = room + light + blocks;
        assert!((s.total_area() - expected).abs() < 1e-9 * expected);
        check_orientation(&s, DVec3::new(0.5 * sx, 0.5 * sy, 0.5 * sz));
        let emitters: f64 = s
            .patches()
            .iter()
            .filter(|p| s.materials()[p.material].is_emitter())
            .map(|p| p.area)
            .sum();
        assert!((emitters - light).abs() < 1e-9);
    }
    // Level 2 leaves only the light whole; level 3 splits it in four.
    let light_patches = |level| {
        let s = Scene3::cornell_box_thesis(level).unwrap();
        s.patches()
            .iter()
            .filter(|p| s.materials()[p.material].is_emitter())
            .count()
    };
    assert_eq!((light_patches(2), light_patches(3)), (1, 4));
    assert!(matches!(
        kind(Scene3::cornell_box_thesis(5)),
        ErrorKind::BadSubdivision { .. }
    ));
    assert_eq!(preset_3d("cornell-thesis", 1).unwrap().n_patches(), 121);
}

#[test]
fn cube_rooms_reproduce_the_thesis_positional_entropy() {
    // H_P = H_S + I_S of Tables 3.1 and 3.3.
    for (m, h_p) in [(0, 9.229), (3, 9.4495), (4, 9.718), (8, 11.5405)] {
        for clustered in [false, true] {
            let s = Scene3::cube_room_with_cubes(m, clustered, 7).unwrap();
            let cubes = (m * m * m) as usize;
            assert_eq!(s.n_patches(), 600 + 6 * cubes);
            assert_eq!(s.objects().len(), 1 + cubes);
            let area = 6.0 + 6.0 * cubes as f64 * CUBE_ROOM_SIDE * CUBE_ROOM_SIDE;
            assert!((s.total_area() - area).abs() < 1e-12);
            assert!((positional_entropy(&s) - h_p).abs() < 1.5e-3, "{m}");
            check_orientation(&s, DVec3::splat(0.5));
            check_vector_areas(&s, true);
            let gap = CUBE_ROOM_MIN_GAP - 1e-12;
            check_separated(&s, DVec3::ZERO, DVec3::ONE, gap, (2, gap));
        }
    }
    check_closed(&Scene3::cube_room_with_cubes(3, false, 1).unwrap());
    check_closed(&Scene3::cube_room_with_cubes(3, true, 1).unwrap());
    // Random placements depend on the seed only.
    let a = Scene3::cube_room_with_cubes(4, false, 11).unwrap();
    assert_eq!(a, Scene3::cube_room_with_cubes(4, false, 11).unwrap());
    assert_ne!(a, Scene3::cube_room_with_cubes(4, false, 12).unwrap());
    // The clustered block is centred and tight.
    let block = Scene3::cube_room_with_cubes(8, true, 0).unwrap();
    let objs = objects(&block);
    let extent = 8.0 * CUBE_ROOM_SIDE + 7.0 * CUBE_ROOM_SPACING;
    let (lo, hi) = objs.iter().flat_map(|o| &o.0).fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(l, h), &p| (l.min(p), h.max(p)),
    );
    assert!((hi - lo - DVec3::splat(extent)).abs().max_element() < 1e-12);
    assert!((lo + hi - DVec3::ONE).abs().max_element() < 1e-12);
    assert!(matches!(
        kind(Scene3::cube_room_with_cubes(
            MAX_CUBES_PER_SIDE + 1,
            true,
            0
        )),
        ErrorKind::TooLarge { .. }
    ));
}

#[test]
fn sixty_four_cubes_expand_from_the_centre_to_the_walls() {
    let s = SIXTY_FOUR_CUBES_SIDE;
    for step in 0..SIXTY_FOUR_CUBES_STEPS {
        for fine in [false, true] {
            let scene = Scene3::sixty_four_cubes(step, fine).unwrap();
            assert_eq!(scene.n_patches(), 1920);
            let walls = scene
                .patches()
                .iter()
                .filter(|p| is_enclosure(&scene, scene.faces()[p.face].object))
                .count();
            assert_eq!(walls, if fine { 1536 } else { 384 });
            assert!((scene.total_area() - (6.0 + 64.0 * 6.0 * s * s)).abs() < 1e-12);
            check_orientation(&scene, DVec3::splat(0.5));
            check_vector_areas(&scene, true);
            check_separated(
                &scene,
                DVec3::ZERO,
                DVec3::ONE,
                0.1 * s - 1e-12,
                (2, 0.1 * s - 1e-12),
            );
        }
    }
    // The ends: neighbours s/10 apart at step 0, outer cubes s/8 from the walls at step 8.
    let first = objects(&Scene3::sixty_four_cubes(0, false).unwrap());
    assert!((gap(&first[0], &first[1]) - 0.1 * s).abs() < 1e-12);
    let last = Scene3::sixty_four_cubes(8, true).unwrap();
    let (lo, hi) = objects(&last)
        .iter()
        .flat_map(|o| o.0.clone())
        .fold((DVec3::ONE, DVec3::ZERO), |(l, h), p| (l.min(p), h.max(p)));
    assert!((lo - DVec3::splat(0.125 * s)).abs().max_element() < 1e-12);
    assert!((hi - DVec3::splat(1.0 - 0.125 * s)).abs().max_element() < 1e-12);
    check_closed(&Scene3::sixty_four_cubes(0, false).unwrap());
    assert!(matches!(
        kind(Scene3::sixty_four_cubes(SIXTY_FOUR_CUBES_STEPS, false)),
        ErrorKind::TooLarge { .. }
    ));
}

#[test]
fn tables_and_chairs_in_six_arrangements() {
    let room = DVec3::from(TABLE_ROOM);
    for (letter, sets) in [
        ('a', 1),
        ('b', 4),
        ('c', 16),
        ('d', 16),
        ('e', 16),
        ('f', 16),
    ] {
        let s = Scene3::table_and_chairs_room(letter).unwrap();
        assert_eq!(s.n_patches(), 1280 + 174 * sets, "{letter}");
        assert_eq!(s.objects().len(), 1 + 29 * sets);
        check_orientation(&s, 0.5 * room);
        check_vector_areas(&s, true);
        check_separated(
            &s,
            DVec3::ZERO,
            room,
            FURNITURE_GAP - 1e-12,
            (2, FURNITURE_GAP - 1e-12),
        );
    }
    // Against the walls: some set 0.1 m from a wall; in the middle: none nearer than 1 m.
    let near = |letter| {
        let s = Scene3::table_and_chairs_room(letter).unwrap();
        objects(&s)
            .iter()
            .flat_map(|o| o.0.clone())
            .map(|p| p.x.min(p.y).min(room.x - p.x).min(room.y - p.y))
            .fold(f64::INFINITY, f64::min)
    };
    for letter in ['d', 'e', 'f'] {
        assert!((near(letter) - 0.1).abs() < 1e-9, "{letter}");
    }
    assert!(near('c') > 1.0);
    check_closed(&Scene3::table_and_chairs_room('a').unwrap());
    assert!(matches!(
        kind(Scene3::table_and_chairs_room('g')),
        ErrorKind::UnknownPreset(_)
    ));
}

#[test]
fn every_listed_preset_builds_by_name() {
    let mut names = std::collections::BTreeSet::new();
    for e in presets_3d() {
        assert!(names.insert(e.name), "{} listed twice", e.name);
        let s = preset_3d(e.name, 2).unwrap_or_else(|err| panic!("{}: {err}", e.name));
        assert!(s.n_patches() > 0);
        if e.name == "cornell-thesis" || e.name == "city-block" {
            // Not closed by design: the light is a polygon of its own below the ceiling;
            // the city has no sky.
            continue;
        }
        check_vector_areas(&s, !e.name.starts_with("cornell"));
        check_lines(&s, 200, 3);
    }
    assert_eq!(preset_3d("cube", 10).unwrap().n_patches(), 600);
    assert_eq!(preset_3d("cubes-512-random", 0).unwrap().n_patches(), 3672);
    assert_eq!(
        preset_3d("cubes-64-random", 1).unwrap(),
        Scene3::cube_room_with_cubes(4, false, PRESET_SEED).unwrap()
    );
    assert_eq!(
        preset_3d("64-cubes-3-fine", 1).unwrap(),
        Scene3::sixty_four_cubes(3, true).unwrap()
    );
    assert_eq!(preset_3d("sphere-3", 1).unwrap().n_patches(), 1280);
    assert_eq!(preset_3d("city-block", 1).unwrap().n_patches(), 10_000);
    assert_eq!(Scene3::city_block(2, PRESET_SEED).unwrap().n_patches(), 736);
    assert_eq!(preset_3d("tetra-mesh-2", 1).unwrap().n_patches(), 64);
    for bad in [
        "",
        "cubes",
        "cubes-27",
        "64-cubes-9",
        "sphere-5",
        "table-chairs-g",
        "Cube",
    ] {
        assert!(
            matches!(kind(preset_3d(bad, 10)), ErrorKind::UnknownPreset(_)),
            "{bad}"
        );
    }
    assert!(matches!(
        kind(preset_3d("cube", 0)),
        ErrorKind::BadSubdivision { .. }
    ));
    assert!(matches!(
        kind(preset_3d("cube", 1000)),
        ErrorKind::TooManyPatches { .. }
    ));
}

/// The unit cube room with face `skip` left out, or reversed if `flip`.
fn broken_cube(skip: usize, flip: bool) -> Scene3 {
    let mut b = Scene3::builder();
    b.object(ENCLOSURE);
    for (k, f) in box_faces(DVec3::ZERO, DVec3::ONE).iter().enumerate() {
        let facing = DVec3::splat(0.5) - vertex_mean(f);
        if k != skip {
            add_facing(&mut b, f, facing, Subdivision::Grid(2)).unwrap();
        } else if flip {
            add_facing(&mut b, f, -facing, Subdivision::Grid(2)).unwrap();
        }
    }
    b.build().unwrap()
}

#[test]
#[should_panic(expected = "hits")]
fn line_check_catches_a_hole() {
    check_lines(&broken_cube(3, false), 200, 3);
}

#[test]
#[should_panic(expected = "hit")]
fn line_check_catches_a_flipped_face() {
    check_lines(&broken_cube(3, true), 200, 3);
}

#[test]
#[should_panic(expected = "unmatched")]
fn edge_check_catches_a_hole() {
    check_closed(&broken_cube(0, false));
}
