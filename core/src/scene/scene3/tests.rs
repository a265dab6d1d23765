use super::*;
use alloc::string::ToString;
use alloc::vec;

/// The unit cube `[0, 1]³`, each face counter-clockwise seen from outside (facing out).
pub(crate) fn unit_cube_faces() -> [[DVec3; 4]; 6] {
    let p = |x: f64, y: f64, z: f64| DVec3::new(x, y, z);
    [
        [p(0., 0., 0.), p(0., 1., 0.), p(1., 1., 0.), p(1., 0., 0.)], // z = 0, −z
        [p(0., 0., 1.), p(1., 0., 1.), p(1., 1., 1.), p(0., 1., 1.)], // z = 1, +z
        [p(0., 0., 0.), p(1., 0., 0.), p(1., 0., 1.), p(0., 0., 1.)], // y = 0, −y
        [p(0., 1., 0.), p(0., 1., 1.), p(1., 1., 1.), p(1., 1., 0.)], // y = 1, +y
        [p(0., 0., 0.), p(0., 0., 1.), p(0., 1., 1.), p(0., 1., 0.)], // x = 0, −x
        [p(1., 0., 0.), p(1., 1., 0.), p(1., 1., 1.), p(1., 0., 1.)], // x = 1, +x
    ]
}

fn cube(s: Subdivision, inward: bool) -> Scene3 {
    let mut b = Scene3::builder();
    for mut f in unit_cube_faces() {
        if inward {
            f.reverse();
        }
        b.polygon(&f, s).unwrap();
    }
    b.build().unwrap()
}

fn kind(r: Result<&mut Scene3Builder>) -> ErrorKind {
    r.map(|_| ()).unwrap_err().kind().clone()
}

fn message(r: Result<&mut Scene3Builder>) -> alloc::string::String {
    r.map(|_| ()).unwrap_err().to_string()
}

#[test]
fn unit_cube_faces_outward_and_inward() {
    for inward in [false, true] {
        let s = cube(Subdivision::None, inward);
        assert_eq!(s.n_patches(), 6);
        assert_eq!(s.faces().len(), 6);
        assert_eq!(s.total_area(), 6.0);
        for (f, p) in s.faces().iter().zip(s.patches()) {
            assert_eq!(f.area, 1.0);
            assert_eq!(p.area, 1.0);
            assert_eq!(p.normal, f.normal);
            // The normal points away from the centre (outward) or towards it (inward).
            let out = (p.centroid - DVec3::splat(0.5)).dot(p.normal);
            assert_eq!(out, if inward { -0.5 } else { 0.5 });
            assert!((p.centroid - DVec3::splat(0.5)).length() - 0.5 < 1e-15);
        }
        assert_eq!(s.bounds(), (DVec3::ZERO, DVec3::ONE));
        assert_eq!(s.objects(), ["default"]);
        assert_eq!(s.materials(), [Material::BLACK]);
    }
    let s = cube(Subdivision::None, false);
    assert_eq!(s.faces()[1].normal, DVec3::Z);
    assert_eq!(s.faces()[0].normal, -DVec3::Z);
    assert_eq!(s.patch_vertices(1), unit_cube_faces()[1]);
    assert_eq!(s.face_vertices(5), unit_cube_faces()[5]);
    assert!(s.patch_vertices(6).is_empty() && s.face_vertices(6).is_empty());
    assert!(s.patch_material(6).is_none());
}

#[test]
fn grid_10_cuts_the_cube_into_600_squares() {
    let s = cube(Subdivision::Grid(10), false);
    assert_eq!(s.n_patches(), 600);
    for (i, p) in s.patches().iter().enumerate() {
        assert!((p.area - 0.01).abs() < 1e-15, "{}", p.area);
        assert_eq!(p.count, 4);
        assert_eq!(p.normal, s.faces()[p.face].normal);
        assert!(s.faces()[p.face].patches.contains(&i));
        // Each cell is a 0.1 square.
        let v = s.patch_vertices(i);
        for k in 0..4 {
            assert!(((v[(k + 1) % 4] - v[k]).length() - 0.1).abs() < 1e-15);
        }
        assert!((geom::polygon_normal(v).normalize() - p.normal).length() < 1e-14);
    }
    assert!((s.total_area() - 6.0).abs() < 1e-14);
    let mut a = vec![0.0; 600];
    s.relative_areas_into(&mut a).unwrap();
    assert!((a.iter().sum::<f64>() - 1.0).abs() < 1e-14);
    assert!(matches!(
        s.relative_areas_into(&mut a[..5]).unwrap_err().kind(),
        ErrorKind::BufferTooSmall {
            needed: 600,
            found: 5
        }
    ));
}

#[test]
fn triangles_level_l_gives_two_times_four_to_the_l_per_quad() {
    for l in 0..4 {
        let s = cube(Subdivision::Triangles(l), true);
        assert_eq!(s.n_patches(), 6 * 2 * 4usize.pow(l));
        let each = 0.5 / 4f64.powi(l as i32);
        for p in s.patches() {
            assert_eq!(p.count, 3);
            assert!((p.area - each).abs() < 1e-15);
        }
        assert!((s.total_area() - 6.0).abs() < 1e-13);
    }
    // A triangle is cut into 4^l, a pentagon fanned into 3 triangles first.
    let tri = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let mut b = Scene3::builder();
    b.polygon(&tri, Subdivision::Triangles(2)).unwrap();
    assert_eq!(b.patch_count(), 16);
    b.polygon(&tri, Subdivision::Grid(3)).unwrap();
    assert_eq!(b.patch_count(), 16 + 9);
    let pentagon: Vec<DVec3> = (0..5)
        .map(|k| {
            let t = k as f64 * core::f64::consts::TAU / 5.0;
            DVec3::new(crate::math::cos(t), crate::math::sin(t), 2.0)
        })
        .collect();
    b.polygon(&pentagon, Subdivision::Triangles(1)).unwrap();
    assert_eq!(b.patch_count(), 25 + 12);
    b.polygon(&pentagon, Subdivision::Grid(2)).unwrap();
    assert_eq!(b.patch_count(), 37 + 12);
}

#[test]
fn straight_vertices_are_skipped_when_triangulating() {
    // A unit square with an extra vertex in the middle of its bottom edge.
    let v = [
        DVec3::ZERO,
        DVec3::new(0.5, 0.0, 0.0),
        DVec3::X,
        DVec3::new(1.0, 1.0, 0.0),
        DVec3::Y,
    ];
    let mut b = Scene3::builder();
    b.polygon(&v, Subdivision::Triangles(0)).unwrap();
    let s = b.build().unwrap();
    assert_eq!(s.n_patches(), 2);
    assert_eq!(s.total_area(), 1.0);
}

#[test]
fn subdivided_recuts_every_face() {
    let mut b = Scene3::builder();
    b.material(Material::new([0.5; 3], [0.0; 3]).unwrap())
        .object("walls");
    for f in &unit_cube_faces()[..5] {
        b.polygon(f, Subdivision::Grid(3)).unwrap();
    }
    b.material(Material::new([0.1; 3], [1.0; 3]).unwrap())
        .object("lamp");
    b.polygon(&unit_cube_faces()[5], Subdivision::None).unwrap();
    let s = b.build().unwrap();
    assert_eq!(s.n_patches(), 5 * 9 + 1);
    assert_eq!(s.objects(), ["walls", "lamp"]);
    assert_eq!(s.patch_material(45).unwrap().emittance, [1.0; 3]);
    let t = s.subdivided(Subdivision::Grid(2)).unwrap();
    assert_eq!(t.n_patches(), 24);
    assert_eq!(t.objects(), s.objects());
    assert_eq!(t.materials(), s.materials());
    assert_eq!(t.faces()[5].object, 1);
    assert_eq!(t.subdivided(Subdivision::None).unwrap(), cube_like(&s));
    assert_eq!(
        s.subdivided(Subdivision::Grid(0)).unwrap_err().kind(),
        &ErrorKind::BadSubdivision {
            given: 0,
            max: 2000
        }
    );
}

/// `s` with every face as its own patch.
fn cube_like(s: &Scene3) -> Scene3 {
    s.subdivided(Subdivision::None).unwrap()
}

#[test]
fn materials_and_objects_are_listed_once_in_first_use_order() {
    let red = Material::new([0.5, 0.0, 0.0], [0.0; 3]).unwrap();
    // Three parallel triangles (one triangle three times would be coincident faces)
    let tri = |z: f64| {
        [
            DVec3::new(0.0, 0.0, z),
            DVec3::new(1.0, 0.0, z),
            DVec3::new(0.0, 1.0, z),
        ]
    };
    let mut b = Scene3::builder();
    b.material(Material::new([0.9; 3], [0.0; 3]).unwrap()); // never used
    b.material(red).object("a");
    b.polygon(&tri(0.0), Subdivision::None).unwrap();
    b.material(Material::BLACK).object("b");
    b.polygon(&tri(1.0), Subdivision::None).unwrap();
    b.material(red).object("a");
    b.polygon(&tri(2.0), Subdivision::None).unwrap();
    let s = b.build().unwrap();
    assert_eq!(s.materials(), [red, Material::BLACK]);
    assert_eq!(s.objects(), ["a", "b"]);
    let f: Vec<(usize, usize)> = s.faces().iter().map(|f| (f.material, f.object)).collect();
    assert_eq!(f, [(0, 0), (1, 1), (0, 0)]);
}

#[test]
fn rejects_bad_faces_with_clear_messages() {
    let mut b = Scene3::builder();
    let sq = unit_cube_faces()[1];
    assert_eq!(
        message(b.polygon(&sq[..2], Subdivision::None)),
        "face needs 3 to 256 vertices, got 2"
    );
    let many = vec![DVec3::ZERO; 257];
    assert_eq!(
        kind(b.polygon(&many, Subdivision::None)),
        ErrorKind::FaceVertexCount {
            given: 257,
            max: 256
        }
    );
    let mut nan = sq;
    nan[2].y = f64::NAN;
    assert_eq!(
        message(b.polygon(&nan, Subdivision::None)),
        "coordinate: number is NaN, infinite or beyond the range of f64"
    );
    let mut far = sq;
    far[2].y = 2e301;
    assert_eq!(
        kind(b.polygon(&far, Subdivision::None)),
        ErrorKind::CoordinateRange
    );
    let line = [DVec3::ZERO, DVec3::X, DVec3::new(2.0, 0.0, 0.0)];
    assert_eq!(
        message(b.polygon(&line, Subdivision::None)),
        "face is degenerate (zero area or a zero-length edge)"
    );
    let repeated = [sq[0], sq[1], sq[1], sq[2], sq[3]];
    assert_eq!(
        kind(b.polygon(&repeated, Subdivision::None)),
        ErrorKind::DegenerateFace
    );
    let mut bent = sq;
    bent[2].z += 0.01;
    assert_eq!(
        message(b.polygon(&bent, Subdivision::None)),
        "face is not planar: a vertex lies 0.00249993750234371 from its plane (tolerance 1e-6 × its size)"
    );
    let mut slightly = sq;
    slightly[2].z += 1e-7; // within 1e-6 of the size
    assert!(b.polygon(&slightly, Subdivision::None).is_ok());
    let dart = [
        DVec3::ZERO,
        DVec3::new(2.0, 0.0, 0.0),
        DVec3::new(0.5, 0.5, 0.0),
        DVec3::new(0.0, 2.0, 0.0),
    ];
    assert_eq!(
        message(b.polygon(&dart, Subdivision::None)),
        "face is not convex"
    );
    let star: Vec<DVec3> = (0..5)
        .map(|k| {
            let t = (2 * k) as f64 * core::f64::consts::TAU / 5.0;
            DVec3::new(crate::math::cos(t), crate::math::sin(t), 0.0)
        })
        .collect();
    assert_eq!(
        kind(b.polygon(&star, Subdivision::None)),
        ErrorKind::NonConvexFace
    );
    assert_eq!(
        message(b.polygon(&sq, Subdivision::Grid(2001))),
        "subdivision parameter 2001 is out of range (at most 2000; a grid needs at least 1)"
    );
    assert_eq!(
        kind(b.polygon(&sq, Subdivision::Triangles(11))),
        ErrorKind::BadSubdivision { given: 11, max: 10 }
    );
    // Failed faces leave the builder as it was.
    assert_eq!((b.face_count(), b.patch_count()), (1, 1));
    assert_eq!(
        Scene3::builder().build().unwrap_err().kind(),
        &ErrorKind::EmptyScene
    );
}

#[test]
fn patch_cap_is_checked_before_allocating() {
    let mut b = Scene3::builder();
    let sq = unit_cube_faces()[1];
    b.polygon(&sq, Subdivision::Grid(2000)).unwrap();
    assert_eq!(b.patch_count(), 4_000_000);
    assert_eq!(
        message(b.polygon(&sq, Subdivision::None)),
        "scene has more than 4000000 patches"
    );
    let mut b = Scene3::builder();
    let big: Vec<DVec3> = (0..256)
        .map(|k| {
            let t = k as f64 * core::f64::consts::TAU / 256.0;
            DVec3::new(crate::math::cos(t), crate::math::sin(t), 0.0)
        })
        .collect();
    assert_eq!(
        kind(b.polygon(&big, Subdivision::Triangles(10))),
        ErrorKind::TooManyPatches { max: 4_000_000 }
    );
    assert_eq!(b.patch_count(), 0);
}

#[test]
fn faces_too_small_for_f64_are_degenerate() {
    // Areas near 1e-320 lose their precision (squared lengths underflow): rejected.
    let tri = [DVec3::ZERO, DVec3::X, DVec3::Y];
    let mut b = Scene3::builder();
    b.polygon(&tri.map(|v| v * 1e-70), Subdivision::Grid(2000))
        .unwrap();
    assert_eq!(
        kind(b.polygon(&tri.map(|v| v * 1e-160), Subdivision::None)),
        ErrorKind::DegenerateFace
    );
    assert_eq!(b.patch_count(), 4_000_000);
}

#[cfg(feature = "std")]
mod props {
    use super::*;
    use crate::math::{cos, sin};
    use proptest::prelude::*;

    /// A regular `n`-gon stretched by `(sx, sy)` in a random plane: convex and planar,
    /// counter-clockwise about the returned unit normal.
    fn polygon(
        n: usize,
        (theta, phi, spin): (f64, f64, f64),
        (sx, sy): (f64, f64),
        scale: f64,
        centre: [f64; 3],
    ) -> (Vec<DVec3>, DVec3) {
        let normal = DVec3::new(sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta));
        let u = normal.any_orthonormal_vector();
        let v = normal.cross(u);
        let c = DVec3::from_array(centre) * scale;
        let vertices = (0..n)
            .map(|k| {
                let t = spin + k as f64 * core::f64::consts::TAU / n as f64;
                c + (u * (sx * cos(t)) + v * (sy * sin(t))) * scale
            })
            .collect();
        (vertices, normal)
    }

    fn subdivision() -> impl Strategy<Value = Subdivision> {
        prop_oneof![
            Just(Subdivision::None),
            (1u32..7).prop_map(Subdivision::Grid),
            (0u32..4).prop_map(Subdivision::Triangles),
        ]
    }

    proptest! {
        /// The lenient entry adds a face the strict one accepts bit for bit as it does,
        /// and reports nothing repaired.
        #[test]
        fn convex_planar_polygons_as_drawn_are_the_strict_scene(
            n in 3usize..40,
            angles in (0.0..core::f64::consts::PI, 0.0..core::f64::consts::TAU, 0.0..1.0f64),
            stretch in (0.2..5.0f64, 0.2..5.0f64),
            log_scale in -3.0..4.0f64,
            centre in proptest::array::uniform3(-10.0..10.0f64),
            s in subdivision(),
        ) {
            let scale = libm::pow(10.0, log_scale);
            let (vertices, _) = polygon(n, angles, stretch, scale, centre);
            let mut b = Scene3::builder();
            b.polygon(&vertices, s).unwrap();
            let strict = b.build().unwrap();
            let mut l = Scene3::builder();
            let mut report = crate::io::LoadReport::default();
            l.face_as_drawn(&vertices, s, &mut report, Some(1)).unwrap();
            prop_assert_eq!(l.build_as_drawn(&mut report, &[1]).unwrap(), strict);
            prop_assert_eq!(
                report,
                crate::io::LoadReport { faces_read: 1, ..Default::default() }
            );
        }

        #[test]
        fn convex_planar_polygons_build_and_patches_tile_them(
            n in 3usize..40,
            angles in (0.0..core::f64::consts::PI, 0.0..core::f64::consts::TAU, 0.0..1.0f64),
            stretch in (0.2..5.0f64, 0.2..5.0f64),
            log_scale in -3.0..4.0f64,
            centre in proptest::array::uniform3(-10.0..10.0f64),
            s in subdivision(),
        ) {
            let scale = libm::pow(10.0, log_scale);
            let (vertices, normal) = polygon(n, angles, stretch, scale, centre);
            let mut b = Scene3::builder();
            b.polygon(&vertices, s).unwrap();
            let scene = b.build().unwrap();
            let face = &scene.faces()[0];
            prop_assert!((face.normal - normal).length() < 1e-12);
            let expected = match s {
                Subdivision::None => 1,
                Subdivision::Grid(k) if n == 4 => (k * k) as usize,
                Subdivision::Grid(k) => (n - 2) * (k * k) as usize,
                Subdivision::Triangles(l) => (n - 2) << (2 * l),
            };
            prop_assert_eq!(scene.n_patches(), expected);
            let sum = crate::math::sum(scene.patches().iter().map(|p| p.area));
            prop_assert!((sum - face.area).abs() <= 1e-12 * face.area, "{} vs {}", sum, face.area);
            prop_assert!((scene.total_area() - face.area).abs() <= 1e-12 * face.area);
            for (i, p) in scene.patches().iter().enumerate() {
                prop_assert!(p.area > 0.0);
                prop_assert_eq!(p.normal, face.normal);
                let pv = scene.patch_vertices(i);
                let own = geom::polygon_normal(pv).normalize();
                prop_assert!((own - face.normal).length() < 1e-9);
                // Every patch vertex lies in the face's plane
                for &q in pv {
                    prop_assert!((q - vertices[0]).dot(face.normal).abs() <= 1e-12 * scale * 10.0);
                }
            }
        }
    }
}
