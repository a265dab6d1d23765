use super::*;
use alloc::format;
use alloc::string::ToString;

/// The unit cube, faces counter-clockwise from inside (facing in, as a room).
const ROOM: &str = "\
# unit cube, faces towards the inside
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
o room
f 1 2 3 4
f 5 8 7 6
f 1 5 6 2
f 4 3 7 8
f 1 4 8 5
f 2 6 7 3
";

fn no_mtl(_: &str) -> Option<String> {
    None
}

fn err(obj: &str) -> String {
    parse_obj(obj, Subdivision::None, no_mtl)
        .unwrap_err()
        .to_string()
}

fn err_with(obj: &str, mtl: &str) -> String {
    parse_obj(obj, Subdivision::None, |_| Some(mtl.into()))
        .unwrap_err()
        .to_string()
}

#[test]
fn parses_the_unit_cube_facing_in() {
    let s = parse_obj(ROOM, Subdivision::None, no_mtl).unwrap();
    assert_eq!(s.n_patches(), 6);
    assert_eq!(s.total_area(), 6.0);
    assert_eq!(s.objects(), ["room"]);
    assert_eq!(s.materials(), [Material::BLACK]);
    for p in s.patches() {
        assert_eq!((p.centroid - DVec3::splat(0.5)).dot(p.normal), -0.5);
    }
    assert_eq!(s.faces()[0].normal, DVec3::Z);
}

#[test]
fn subdivisions_of_the_cube() {
    let s = parse_obj(ROOM, Subdivision::Grid(10), no_mtl).unwrap();
    assert_eq!(s.n_patches(), 600);
    assert!(s.patches().iter().all(|p| (p.area - 0.01).abs() < 1e-15));
    let s = parse_obj(ROOM, Subdivision::Triangles(2), no_mtl).unwrap();
    assert_eq!(s.n_patches(), 6 * 2 * 16);
    assert_eq!(
        parse_obj(ROOM, Subdivision::Triangles(11), no_mtl)
            .unwrap_err()
            .to_string(),
        "subdivision parameter 11 is out of range (at most 10; a grid needs at least 1)"
    );
}

#[test]
fn face_vertex_forms_and_negative_indices() {
    let forms = "v 0 0 0\nv 1 0 0\nv 1 1 0 1.0\nv 0 1 0 0.5 0.5 0.5\nvt 0 0\nvt 1 0\nvn 0 0 1\n\
                 s off\nf 1/1 2/2/1 3//1 4\nf -1 -2//-1 -3 -4/-2/-1\nl 1 2\np 3\n";
    // (The second face is the first one reversed: the same face twice would be two
    // coincident surfaces.)
    let s = parse_obj(forms, Subdivision::None, no_mtl).unwrap();
    assert_eq!(s.n_patches(), 2);
    let mut reversed = s.face_vertices(1).to_vec();
    reversed.reverse();
    assert_eq!(s.face_vertices(0), reversed);
    assert_eq!(s.face_vertices(0)[2], DVec3::new(1.0, 1.0, 0.0));
    // A negative index counts back from the vertices defined so far.
    let rel = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 0 1\nv 5 1 1\nf -5 -2 -1\n";
    let s = parse_obj(rel, Subdivision::None, no_mtl).unwrap();
    assert_eq!(
        s.face_vertices(1),
        [
            DVec3::ZERO,
            DVec3::new(5.0, 0.0, 1.0),
            DVec3::new(5.0, 1.0, 1.0)
        ]
    );
}

#[test]
fn errors_name_line_and_problem() {
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let e = |tail: &str| err(&[tri, tail].concat());
    assert_eq!(
        e("f 1 2 4"),
        "line 4: vertex index 4 out of range (3 vertices defined so far; 0 is never valid)"
    );
    assert_eq!(
        e("f 0 1 2"),
        "line 4: vertex index 0 out of range (3 vertices defined so far; 0 is never valid)"
    );
    assert_eq!(
        e("f -4 1 2"),
        "line 4: vertex index -4 out of range (3 vertices defined so far; 0 is never valid)"
    );
    assert_eq!(
        e("f 1 2 99999999999999999999"),
        "line 4: vertex index: '99999999999999999999' is not a number"
    );
    assert_eq!(
        e("f 1 2 3/x"),
        "line 4: texture index: '3/x' is not a number"
    );
    assert_eq!(
        e("f 1 2 3/1/0"),
        "line 4: normal index: '3/1/0' is not a number"
    );
    assert_eq!(
        e("f 1 2 3/1/1/1"),
        "line 4: vertex index: '3/1/1/1' is not a number"
    );
    assert_eq!(e("f 1 2"), "line 4: face needs 3 to 256 vertices, got 2");
    assert_eq!(
        err(&format!("v 0 0 0\nf{}", " 1".repeat(300))),
        "line 2: face needs 3 to 256 vertices, got 300"
    );
    // Faces as drawn are repaired (SceneBuilder::face_as_drawn): a degenerate face alone
    // leaves nothing, a bent or concave one is triangulated.
    assert_eq!(e("f 1 2 2"), "line 4: scene has no patches");
    let ok = |tail: &str| parse_obj(&[tri, tail].concat(), Subdivision::None, no_mtl);
    assert_eq!(ok("v 1 1 0.5\nf 1 2 4 3").unwrap().faces().len(), 2);
    assert_eq!(
        ok("v 0.2 0.2 0\nv 0 2 0\nf 1 2 4 5").unwrap().faces().len(),
        2
    );
    assert_eq!(err("v 0 0\n"), "line 1: missing field z");
    assert_eq!(err("v 0 x 0\n"), "line 1: y: 'x' is not a number");
    assert_eq!(
        err("v 0 0 nan\n"),
        "line 1: z: number is NaN, infinite or beyond the range of f64"
    );
    assert_eq!(
        err("v 0 0 1e13\nv 1 0 0\nv 0 1 0\nf 1 2 3"),
        "line 4: coordinate too large: every coordinate must lie within ±1000000000000"
    );
    assert_eq!(
        err("v 0 0 0 1 2 3 4\n"),
        "line 1: unexpected extra field '4'"
    );
    assert_eq!(err("vt 0 q\n"), "line 1: vt: 'q' is not a number");
    assert_eq!(err("\n\nbevel on\n"), "line 3: unknown keyword 'bevel'");
    assert_eq!(e("usemtl\n"), "line 4: missing field material name");
    assert_eq!(
        e("usemtl white\n"),
        "line 4: material 'white' is not defined by any mtllib"
    );
    assert_eq!(e("mtllib\n"), "line 4: missing field library name");
    assert_eq!(
        e("mtllib a.mtl\n"),
        "line 4: material library 'a.mtl' was not provided"
    );
    assert_eq!(err("# nothing\nv 0 0 0\n"), "line 2: scene has no patches");
    assert_eq!(err(""), "line 1: scene has no patches");
}

#[test]
fn material_library_errors_name_both_lines() {
    let obj = "v 0 0 0\nmtllib box.mtl\n";
    let e = |mtl: &str| err_with(obj, mtl);
    assert_eq!(
        e("newmtl a\nKd 1 0.5 0.5\n"),
        "line 2: material library 'box.mtl' line 2: reflectance 1 is outside [0, 1)"
    );
    assert_eq!(
        e("# x\nnewmtl a\nKe 0 -1 0\n"),
        "line 2: material library 'box.mtl' line 3: emittance -1 is negative"
    );
    assert_eq!(
        e("Kd 0.5 0.5 0.5\n"),
        "line 2: material library 'box.mtl' line 1: property before any newmtl"
    );
    assert_eq!(
        e("newmtl a\nKd 0.5 x 0.5\n"),
        "line 2: material library 'box.mtl' line 2: Kd: not a number"
    );
    assert_eq!(
        e("newmtl a\nKe 1 inf 1\n"),
        "line 2: material library 'box.mtl' line 2: Ke: number is NaN, infinite or beyond the range of f64"
    );
    assert_eq!(
        e("newmtl a\nKd 0.5 0.5\n"),
        "line 2: material library 'box.mtl' line 2: missing field Kd"
    );
    assert_eq!(
        e("newmtl a\nKd\n"),
        "line 2: material library 'box.mtl' line 2: missing field Kd"
    );
    assert_eq!(
        e("newmtl a\nKd 0.1 0.1 0.1 0.1\n"),
        "line 2: material library 'box.mtl' line 2: unexpected extra field"
    );
    assert_eq!(
        e("newmtl a\nnewmtl a\n"),
        "line 2: material library 'box.mtl' line 2: material defined twice"
    );
    assert_eq!(
        e("newmtl\n"),
        "line 2: material library 'box.mtl' line 1: missing field material name"
    );
    let err = parse_obj(obj, Subdivision::None, |_| Some("newmtl a\nKd 2\n".into())).unwrap_err();
    assert_eq!(err.line(), Some(2));
    assert!(matches!(
        err.kind(),
        ErrorKind::InMaterialLibrary {
            line: 2,
            problem: MaterialProblem::Reflectance { value: 2.0 },
            ..
        }
    ));
}

/// A Cornell-box-like room: white, red and green walls, a lamp under the ceiling.
const CORNELL_OBJ: &str = "\
mtllib cornell.mtl walls.mtl
v 0 0 0
v 5.56 0 0
v 5.56 0 5.59
v 0 0 5.59
v 0 5.48 0
v 5.56 5.48 0
v 5.56 5.48 5.59
v 0 5.48 5.59
v 2.13 5.47 2.27
v 3.43 5.47 2.27
v 3.43 5.47 3.32
v 2.13 5.47 3.32
g floor
usemtl white
f 1 4 3 2
g ceiling
f 5 6 7 8
g back
f 4 8 7 3
g left
usemtl red
f 1 5 8 4
g right
usemtl green
f 2 3 7 6
g light
usemtl light
f 9 10 11 12 # faces down
";

const CORNELL_MTL: &str = "\
# the lamp and the white walls
newmtl light
Ka 0 0 0
Kd 0.78 0.78 0.78
Ke 17 12 4
illum 1
newmtl white
Kd 0.75 0.75 0.75
Ns 10
";

const WALLS_MTL: &str = "newmtl red\nKd 0.63 0.065 0.05\nnewmtl green\nKd 0.14 0.45 0.091\n";

fn cornell_mtl(name: &str) -> Option<String> {
    match name {
        "cornell.mtl" => Some(CORNELL_MTL.into()),
        "walls.mtl" => Some(WALLS_MTL.into()),
        _ => None,
    }
}

#[test]
fn cornell_box_with_materials_through_the_callback() {
    let s = parse_obj(CORNELL_OBJ, Subdivision::Grid(4), cornell_mtl).unwrap();
    assert_eq!(s.n_patches(), 6 * 16);
    assert_eq!(
        s.objects(),
        ["floor", "ceiling", "back", "left", "right", "light"]
    );
    assert_eq!(s.materials().len(), 4);
    let light = s.faces()[5].clone();
    assert_eq!(light.normal, -DVec3::Y);
    assert!((light.area - 1.3 * 1.05).abs() < 1e-12);
    let m = s.patch_material(light.patches.start).unwrap();
    assert_eq!(m.emittance, [17.0, 12.0, 4.0]);
    assert_eq!(m.reflectance, [0.78; 3]);
    assert_eq!(s.patch_material(0).unwrap().reflectance, [0.75; 3]);
    assert_eq!(
        s.patch_material(3 * 16).unwrap().reflectance,
        [0.63, 0.065, 0.05]
    );
    // The walls face into the box.
    let centre = DVec3::new(2.78, 2.74, 2.795);
    for (k, f) in s.faces()[..5].iter().enumerate() {
        assert!((centre - s.face_vertices(k)[0]).dot(f.normal) > 0.0);
    }
    let (lo, hi) = s.bounds();
    assert_eq!((lo, hi), (DVec3::ZERO, DVec3::new(5.56, 5.48, 5.59)));
}

#[test]
fn round_trips_exactly() {
    let s = parse_obj(CORNELL_OBJ, Subdivision::None, cornell_mtl).unwrap();
    let (obj, mtl) = write_obj(&s, "out.mtl");
    let again = parse_obj(&obj, Subdivision::None, |name| {
        (name == "out.mtl").then(|| mtl.clone())
    })
    .unwrap();
    assert_eq!(again, s);
    // Awkward numbers survive the shortest round-trip formatting.
    let mut b = Scene::builder();
    b.material(Material::new([0.1, 1.0 / 3.0, 0.7], [1e-300, 0.0, 2.5e10]).unwrap())
        .object("odd numbers");
    let tri = [
        DVec3::new(0.1, -0.0, 1e-7),
        DVec3::new(1.0 / 3.0, 1e11, -5e-5),
        DVec3::new(-2.0 / 7.0, 3.0, 0.1 + 0.2),
    ];
    b.polygon(&tri, Subdivision::None).unwrap();
    let s = b.build().unwrap();
    let (obj, mtl) = write_obj(&s, "m.mtl");
    assert_eq!(
        parse_obj(&obj, Subdivision::None, |_| Some(mtl.clone())).unwrap(),
        s
    );
}

#[test]
fn round_trip_keeps_the_patches_of_a_subdivided_scene() {
    let s = parse_obj(CORNELL_OBJ, Subdivision::Triangles(1), cornell_mtl).unwrap();
    let (obj, mtl) = write_obj(&s, "out.mtl");
    assert!(obj.starts_with("# sceneinfo scene: 48 patches\nmtllib out.mtl\nv "));
    // Shared vertices are written once: 12 corners, the midpoints of the box's 12 edges,
    // of the lamp's 4, and of the 6 diagonals.
    assert_eq!(
        obj.lines().filter(|l| l.starts_with("v ")).count(),
        12 + 12 + 4 + 6
    );
    let again = parse_obj(&obj, Subdivision::None, |_| Some(mtl.clone())).unwrap();
    assert_eq!(again.n_patches(), s.n_patches());
    assert_eq!(again.objects(), s.objects());
    assert_eq!(again.materials(), s.materials());
    for (i, (p, q)) in s.patches().iter().zip(again.patches()).enumerate() {
        assert_eq!(s.patch_vertices(i), again.patch_vertices(i));
        assert_eq!(p.material, q.material);
        assert_eq!(p.area, q.area);
        assert!((p.normal - q.normal).length() < 1e-15);
    }
    // Writing the re-read scene gives the same files.
    assert_eq!(write_obj(&again, "out.mtl"), (obj, mtl));
}

#[test]
fn default_material_is_black_and_objects_default() {
    let s = parse_obj(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\ng\nf 3 2 1\n",
        Subdivision::None,
        no_mtl,
    )
    .unwrap();
    assert_eq!(s.materials(), [Material::BLACK]);
    assert_eq!(s.objects(), ["default"]);
    assert_eq!(s.faces()[1].normal, -DVec3::Z);
    // Kd with one value is grey; a library named twice is read once.
    let s = parse_obj(
        "mtllib a\nmtllib a\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl g\nf 1 2 3\n",
        Subdivision::None,
        |_| Some("newmtl g\nKd 0.25\n".into()),
    )
    .unwrap();
    assert_eq!(s.materials()[0].reflectance, [0.25; 3]);
}

#[test]
fn absurd_subdivisions_are_capped_before_allocating() {
    let quads = ROOM.to_string() + "f 1 2 3 4\n";
    assert_eq!(
        parse_obj(&quads, Subdivision::Grid(1000), no_mtl)
            .unwrap_err()
            .to_string(),
        "line 15: scene has more than 4000000 patches"
    );
}
