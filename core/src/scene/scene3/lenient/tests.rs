use super::*;
use crate::scene::Scene3;
use crate::scene::scene3::tests::unit_cube_faces;
use alloc::vec;

fn p(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

/// Adds every face leniently, line k + 1 for face k, and builds leniently.
fn lenient(faces: &[Vec<DVec3>], s: Subdivision) -> (Result<Scene3>, LoadReport) {
    let mut b = Scene3::builder();
    let mut report = LoadReport::default();
    let mut lines = Vec::new();
    for (k, f) in faces.iter().enumerate() {
        let line = k as u32 + 1;
        b.face_as_drawn(f, s, &mut report, Some(line)).unwrap();
        lines.resize(b.face_count(), line);
    }
    (b.build_as_drawn(&mut report, &lines), report)
}

fn strict(faces: &[Vec<DVec3>], s: Subdivision) -> Scene3 {
    let mut b = Scene3::builder();
    for f in faces {
        b.polygon(f, s).unwrap();
    }
    b.build().unwrap()
}

#[test]
fn planar_convex_faces_give_the_strict_scene_bit_for_bit() {
    let hexagon: Vec<DVec3> = (0..6)
        .map(|k| {
            let a = f64::from(k) * core::f64::consts::FRAC_PI_3;
            p(
                3.0 + crate::math::cos(a) / 3.0,
                -7.1 + crate::math::sin(a),
                0.1 + 1e-9 * f64::from(k % 2),
            )
        })
        .collect();
    let mut faces: Vec<Vec<DVec3>> = unit_cube_faces().iter().map(|f| f.to_vec()).collect();
    faces.push(hexagon);
    for s in [
        Subdivision::None,
        Subdivision::Grid(3),
        Subdivision::Triangles(2),
    ] {
        let (scene, report) = lenient(&faces, s);
        assert_eq!(scene.unwrap(), strict(&faces, s), "{s:?}");
        assert_eq!(
            report,
            LoadReport {
                faces_read: 7,
                ..LoadReport::default()
            }
        );
    }
}

#[test]
fn repeated_vertices_are_removed_first() {
    let square = vec![p(0., 0., 0.), p(1., 0., 0.), p(1., 1., 0.), p(0., 1., 0.)];
    let doubled = vec![
        p(0., 0., 0.),
        p(1., 0., 0.),
        p(1., 0., 0.),
        p(1., 1., 0.),
        p(0., 1., 0.),
        p(0., 0., 0.),
    ];
    let (scene, report) = lenient(&[doubled], Subdivision::Grid(2));
    assert_eq!(scene.unwrap(), strict(&[square], Subdivision::Grid(2)));
    assert_eq!(report.repeated_vertices, 2);
    assert_eq!(
        report.messages(true),
        ["line 1: removed repeated vertices of a face"]
    );
}

#[test]
fn nearly_planar_convex_faces_are_flattened() {
    // A Cornell box wall a vertex 0.005 off in a 550-unit box
    let wall = vec![
        p(0., 0., 0.),
        p(550., 0., 0.),
        p(550., 0.005, 550.),
        p(0., 0., 550.),
    ];
    let (scene, report) = lenient(core::slice::from_ref(&wall), Subdivision::None);
    let scene = scene.unwrap();
    assert_eq!(scene.faces().len(), 1);
    assert_eq!(report.faces_flattened, 1);
    let size = geom::bounds_diagonal(&wall);
    let dev = geom::plane_deviation(&wall, geom::polygon_normal(&wall).normalize());
    assert_eq!(report.max_off_plane, dev / size);
    assert!(report.max_off_plane > PLANARITY_TOLERANCE);
    let flat = scene.face_vertices(0);
    let n = scene.faces()[0].normal;
    assert!(geom::plane_deviation(flat, n) <= 1e-12 * size);
    // Area kept to the flattening's order
    assert!((scene.total_area() - 550.0 * 550.0).abs() < 1e-6 * 550.0 * 550.0);
    assert_eq!(
        report.messages(true),
        ["line 1: flattened a slightly non-planar face onto its plane"]
    );
}

#[test]
fn concave_and_bent_faces_are_triangulated() {
    let l_shape = vec![
        p(0., 0., 0.),
        p(2., 0., 0.),
        p(2., 1., 0.),
        p(1., 1., 0.),
        p(1., 2., 0.),
        p(0., 2., 0.),
    ];
    // A quad bent far beyond the drawn tolerance: two triangles along the flatter diagonal
    let bent = vec![p(0., 0., 5.), p(1., 0., 5.), p(1., 1., 5.5), p(0., 1., 5.)];
    let (scene, report) = lenient(&[l_shape, bent], Subdivision::Grid(2));
    let scene = scene.unwrap();
    assert_eq!(scene.faces().len(), 4 + 2);
    assert_eq!(scene.n_patches(), 6 * 4);
    assert_eq!(report.faces_triangulated, 2);
    assert_eq!(report.triangles_added, 6);
    let l_area: f64 = scene.faces()[..4].iter().map(|f| f.area).sum();
    assert!((l_area - 3.0).abs() < 1e-15);
    // The bent quad's diagonal runs from its raised corner: 0 2 and 1 3 give cosines
    // 0.8 and 0.2 … the flatter (larger cosine) split is kept
    let n4 = scene.faces()[4].normal;
    let n5 = scene.faces()[5].normal;
    let other = {
        let t1 = (p(1., 0., 5.) - p(0., 0., 5.)).cross(p(0., 1., 5.) - p(0., 0., 5.));
        let t2 = (p(1., 1., 5.5) - p(1., 0., 5.)).cross(p(0., 1., 5.) - p(1., 0., 5.));
        t1.normalize().dot(t2.normalize())
    };
    assert!(n4.dot(n5) >= other);
    assert!(report.max_off_plane > DRAWN_PLANARITY_TOLERANCE);
}

#[test]
fn degenerate_faces_and_pieces_are_dropped_with_a_warning() {
    let square = vec![p(0., 0., 0.), p(1., 0., 0.), p(1., 1., 0.), p(0., 1., 0.)];
    let collinear = vec![p(0., 0., 1.), p(1., 0., 1.), p(2., 0., 1.)];
    let point = vec![p(3., 3., 3.); 4];
    let (scene, report) = lenient(&[square, collinear, point], Subdivision::None);
    assert_eq!(scene.unwrap().faces().len(), 1);
    assert_eq!(report.pieces_dropped, 2);
    assert_eq!(
        report.messages(true),
        [
            "line 2: dropped a face or piece of zero area (2 times)",
            "line 3: removed repeated vertices of a face",
        ]
    );
    // Nothing left at all: an empty scene, an error
    let (scene, _) = lenient(
        &[vec![p(0., 0., 0.), p(1., 1., 1.), p(2., 2., 2.)]],
        Subdivision::None,
    );
    assert_eq!(*scene.unwrap_err().kind(), ErrorKind::EmptyScene);
}

#[test]
fn bad_numbers_and_counts_stay_errors() {
    let mut b = Scene3::builder();
    let mut r = LoadReport::default();
    let tri = |z: f64| [p(0., 0., 0.), p(1., 0., 0.), p(0., 1., z)];
    let kind = |e: Result<()>| e.unwrap_err().kind().clone();
    assert_eq!(
        kind(b.face_as_drawn(&tri(f64::NAN), Subdivision::None, &mut r, None)),
        ErrorKind::NonFiniteNumber {
            field: "coordinate"
        }
    );
    assert_eq!(
        kind(b.face_as_drawn(&tri(1e301), Subdivision::None, &mut r, None)),
        ErrorKind::CoordinateRange
    );
    assert_eq!(
        kind(b.face_as_drawn(&tri(0.)[..2], Subdivision::None, &mut r, None)),
        ErrorKind::FaceVertexCount { given: 2, max: 256 }
    );
    assert_eq!(
        kind(b.face_as_drawn(&tri(0.), Subdivision::Grid(0), &mut r, None)),
        ErrorKind::BadSubdivision {
            given: 0,
            max: u64::from(crate::scene::scene3::MAX_GRID)
        }
    );
    assert_eq!(b.face_count(), 0);
    assert_eq!(r, LoadReport::default());
}

/// The inside of the unit cube, each face drawn as two concave hexagons split by a
/// staircase.
fn staircase_cube() -> Vec<Vec<DVec3>> {
    let mut out = Vec::new();
    for mut q in unit_cube_faces() {
        q.reverse();
        let at = |u: f64, v: f64| q[0] + (q[1] - q[0]) * u + (q[3] - q[0]) * v;
        out.push(
            [
                (0., 0.),
                (1., 0.),
                (1., 0.7),
                (0.6, 0.7),
                (0.6, 0.3),
                (0., 0.3),
            ]
            .map(|(u, v)| at(u, v))
            .to_vec(),
        );
        out.push(
            [
                (0., 0.3),
                (0.6, 0.3),
                (0.6, 0.7),
                (1., 0.7),
                (1., 1.),
                (0., 1.),
            ]
            .map(|(u, v)| at(u, v))
            .to_vec(),
        );
    }
    out
}

#[test]
fn a_cube_of_concave_halves_is_closed_and_has_the_cube_s_information() {
    use crate::formfactor::quadrature::{ContinuousQuadrature, QuadratureOptions};
    let halves = staircase_cube();
    let (scene, report) = lenient(&halves, Subdivision::None);
    let scene = scene.unwrap();
    assert_eq!(report.faces_triangulated, 12);
    assert_eq!(scene.faces().len(), 12 * 4);
    assert!((scene.total_area() - 6.0).abs() < 1e-14);
    // Rows of the exact form factors sum to 1: a closed enclosure
    let ff = crate::formfactor::exact_3d::scene_form_factors(&scene).unwrap();
    assert!(!ff.has_background(), "deficit {}", ff.max_row_deficit());
    let mut row = vec![0.0; ff.n_states()];
    for i in 0..ff.n_patches() {
        ff.dense_row_into(i, &mut row).unwrap();
        let sum: f64 = row.iter().sum();
        assert!((sum - 1.0).abs() < 1e-9, "row {i}: {sum}");
    }
    // I_S^c over faces is the plain cube's: coplanar pieces add nothing
    let cube: Vec<Vec<DVec3>> = unit_cube_faces()
        .iter()
        .map(|f| f.iter().rev().copied().collect())
        .collect();
    let plain = ContinuousQuadrature::of_scene(
        &strict(&cube, Subdivision::None),
        QuadratureOptions::STANDARD,
    )
    .unwrap();
    let cut = ContinuousQuadrature::of_scene(&scene, QuadratureOptions::STANDARD).unwrap();
    let allowed = 3.0 * (plain.error_estimate + cut.error_estimate) + 1e-12;
    assert!(
        (plain.value - cut.value).abs() <= allowed,
        "{} vs {} (allowed {allowed})",
        plain.value,
        cut.value
    );
}

mod props {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// Faces of random vertices on a coarse lattice (repeats, collinear runs, bends,
        /// self-intersections, duplicates and overlaps all likely): every face is taken or
        /// dropped without error, and the build gives a valid scene or a typed error,
        /// never a panic.
        #[test]
        fn random_faces_as_drawn_never_panic(
            faces in proptest::collection::vec(
                proptest::collection::vec((0i8..4, 0i8..4, 0i8..2), 3..9),
                1..8,
            ),
            s in prop_oneof![Just(Subdivision::None), Just(Subdivision::Grid(2))],
        ) {
            let mut b = Scene3::builder();
            let mut report = LoadReport::default();
            let mut lines = Vec::new();
            for (k, f) in faces.iter().enumerate() {
                let v: Vec<DVec3> = f
                    .iter()
                    .map(|&(x, y, z)| p(f64::from(x), f64::from(y), f64::from(z)))
                    .collect();
                b.face_as_drawn(&v, s, &mut report, Some(k as u32 + 1)).unwrap();
                lines.resize(b.face_count(), k as u32 + 1);
            }
            prop_assert_eq!(report.faces_read, faces.len() as u64);
            match b.build_as_drawn(&mut report, &lines) {
                Ok(scene) => {
                    prop_assert!(scene.total_area() > 0.0 && scene.total_area().is_finite());
                }
                Err(e) => prop_assert!(matches!(
                    e.kind(),
                    ErrorKind::EmptyScene
                        | ErrorKind::CoincidentSurfaces { .. }
                        | ErrorKind::TooLarge { .. }
                        | ErrorKind::FaceVertexCount { .. }
                ), "{e}"),
            }
        }
    }
}

#[test]
fn the_stored_frame_depends_on_the_scene_not_on_dropped_faces() {
    // A fuzz find: a huge first face that was dropped set the builder's units, and the
    // scene written back and read again was stored differently (same world coordinates)
    let unit = [p(0., 0., 0.), p(1., 0., 0.), p(0., 1., 0.)];
    let mut r = LoadReport::default();
    let mut plain = Scene3::builder();
    plain
        .face_as_drawn(&unit, Subdivision::None, &mut r, None)
        .unwrap();
    let plain = plain.build().unwrap();
    let mut b = Scene3::builder();
    let sliver = [p(0., 0., 0.), p(1e70, 0., 0.), p(2e70, 0., 0.)];
    b.face_as_drawn(&sliver, Subdivision::None, &mut r, None)
        .unwrap();
    b.face_as_drawn(&unit, Subdivision::None, &mut r, None)
        .unwrap();
    let scene = b.build().unwrap();
    assert!(scene.frame().is_identity());
    assert_eq!(scene, plain);
    // Built in other units (a first face 2⁷⁰ wide), a scene 2⁷⁵ wide is stored as if read
    // at once in its own units: extent in [1, 2), exponent 75
    let big = |v: &[DVec3]| v.iter().map(|&q| q * 2f64.powi(70)).collect::<Vec<_>>();
    let mut b = Scene3::builder();
    b.polygon(&big(&unit), Subdivision::None).unwrap();
    b.polygon(
        &big(&[p(0., 0., 1.), p(0., 32., 1.), p(32., 0., 1.)]),
        Subdivision::None,
    )
    .unwrap();
    let scene = b.build().unwrap();
    assert_eq!(scene.frame().exponent(), 75);
    let (lo, hi) = scene.bounds();
    assert_eq!((hi - lo).max_element(), 1.0);
}
