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

/// The scene alone, faces cut by `subdivision`.
fn parse(
    obj: &str,
    subdivision: Subdivision,
    mtl: impl Fn(&str) -> Option<String>,
) -> Result<Scene3> {
    parse_obj(obj, &ObjOptions::new(subdivision), mtl).map(|(s, _)| s)
}

/// The scene and its report, with `options`.
fn load(
    obj: &str,
    options: ObjOptions,
    mtl: impl Fn(&str) -> Option<String>,
) -> (Scene3, LoadReport) {
    parse_obj(obj, &options, mtl).unwrap()
}

fn no_mtl(_: &str) -> Option<String> {
    None
}

fn err(obj: &str) -> String {
    parse(obj, Subdivision::None, no_mtl)
        .unwrap_err()
        .to_string()
}

fn err_with(obj: &str, mtl: &str) -> String {
    parse(obj, Subdivision::None, |_| Some(mtl.into()))
        .unwrap_err()
        .to_string()
}

#[test]
fn parses_the_unit_cube_facing_in() {
    let s = parse(ROOM, Subdivision::None, no_mtl).unwrap();
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
    let s = parse(ROOM, Subdivision::Grid(10), no_mtl).unwrap();
    assert_eq!(s.n_patches(), 600);
    assert!(s.patches().iter().all(|p| (p.area - 0.01).abs() < 1e-15));
    let s = parse(ROOM, Subdivision::Triangles(2), no_mtl).unwrap();
    assert_eq!(s.n_patches(), 6 * 2 * 16);
    assert_eq!(
        parse(ROOM, Subdivision::Triangles(11), no_mtl)
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
    let s = parse(forms, Subdivision::None, no_mtl).unwrap();
    assert_eq!(s.n_patches(), 2);
    let mut reversed = s.face_vertices(1).to_vec();
    reversed.reverse();
    assert_eq!(s.face_vertices(0), reversed);
    assert_eq!(s.face_vertices(0)[2], DVec3::new(1.0, 1.0, 0.0));
    // A negative index counts back from the vertices defined so far.
    let rel = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 0 1\nv 5 1 1\nf -5 -2 -1\n";
    let s = parse(rel, Subdivision::None, no_mtl).unwrap();
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
    // Faces as drawn are repaired (Scene3Builder::face_as_drawn): a degenerate face alone
    // leaves nothing, a bent or concave one is triangulated.
    assert_eq!(e("f 1 2 2"), "line 4: scene has no patches");
    let ok = |tail: &str| parse_obj(&[tri, tail].concat(), &ObjOptions::default(), no_mtl);
    assert_eq!(ok("v 1 1 0.5\nf 1 2 4 3").unwrap().0.faces().len(), 2);
    assert_eq!(
        ok("v 0.2 0.2 0\nv 0 2 0\nf 1 2 4 5")
            .unwrap()
            .0
            .faces()
            .len(),
        2
    );
    assert_eq!(err("v 0 0\n"), "line 1: missing field z");
    assert_eq!(err("v 0 x 0\n"), "line 1: y: 'x' is not a number");
    assert_eq!(
        err("v 0 0 nan\n"),
        "line 1: z: number is NaN, infinite or beyond the range of f64"
    );
    assert_eq!(
        err("v 0 0 1e301\nv 1 0 0\nv 0 1 0\nf 1 2 3"),
        "line 4: coordinate too large: every coordinate must lie within ±1e300"
    );
    assert_eq!(
        err("v 0 0 0 1 2 3 4\n"),
        "line 1: unexpected extra field '4'"
    );
    assert_eq!(err("vt 0 q\n"), "line 1: vt: 'q' is not a number");
    // Skipped statements, unknown materials and missing libraries are warnings now (below);
    // a file of nothing else still has no patches.
    assert_eq!(err("\n\nbevel on\n"), "line 3: scene has no patches");
    assert_eq!(err("# nothing\nv 0 0 0\n"), "line 2: scene has no patches");
    assert_eq!(err(""), "line 1: scene has no patches");
}

#[test]
fn material_library_errors_name_both_lines() {
    let obj = "v 0 0 0\nmtllib box.mtl\n";
    let e = |mtl: &str| err_with(obj, mtl);
    assert_eq!(
        e("newmtl a\nKd -0.5 0.5 0.5\n"),
        "line 2: material library 'box.mtl' line 2: reflectance -0.5 is outside [0, 1)"
    );
    assert_eq!(
        e("newmtl a\nKa 1 1 x\n"),
        "line 2: material library 'box.mtl' line 2: Ka: not a number"
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
    let err = parse(obj, Subdivision::None, |_| {
        Some("newmtl a\n\nKd 0.5\nKd -2\n".into())
    })
    .unwrap_err();
    assert_eq!(err.line(), Some(2));
    assert!(matches!(
        err.kind(),
        ErrorKind::InMaterialLibrary {
            line: 4,
            problem: MaterialProblem::Reflectance { value: -2.0 },
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
    let s = parse(CORNELL_OBJ, Subdivision::Grid(4), cornell_mtl).unwrap();
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
    let s = parse(CORNELL_OBJ, Subdivision::None, cornell_mtl).unwrap();
    let (obj, mtl) = write_obj(&s, "out.mtl");
    let again = parse(&obj, Subdivision::None, |name| {
        (name == "out.mtl").then(|| mtl.clone())
    })
    .unwrap();
    assert_eq!(again, s);
    // Awkward numbers survive the shortest round-trip formatting.
    let mut b = Scene3::builder();
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
        parse(&obj, Subdivision::None, |_| Some(mtl.clone())).unwrap(),
        s
    );
}

#[test]
fn round_trip_keeps_the_patches_of_a_subdivided_scene() {
    let s = parse(CORNELL_OBJ, Subdivision::Triangles(1), cornell_mtl).unwrap();
    let (obj, mtl) = write_obj(&s, "out.mtl");
    assert!(obj.starts_with("# sceneinfo scene: 48 patches\nmtllib out.mtl\nv "));
    // Shared vertices are written once: 12 corners, the midpoints of the box's 12 edges,
    // of the lamp's 4, and of the 6 diagonals.
    assert_eq!(
        obj.lines().filter(|l| l.starts_with("v ")).count(),
        12 + 12 + 4 + 6
    );
    let again = parse(&obj, Subdivision::None, |_| Some(mtl.clone())).unwrap();
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
    let s = parse(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\ng\nf 3 2 1\n",
        Subdivision::None,
        no_mtl,
    )
    .unwrap();
    assert_eq!(s.materials(), [Material::BLACK]);
    assert_eq!(s.objects(), ["default"]);
    assert_eq!(s.faces()[1].normal, -DVec3::Z);
    // Kd with one value is grey; a library named twice is read once.
    let s = parse(
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
        parse(&quads, Subdivision::Grid(1000), no_mtl)
            .unwrap_err()
            .to_string(),
        "line 15: scene has more than 4000000 patches"
    );
}

/// Three triangles of one plane's two sides and a third plane: a scene to hang statements on.
const TRIS: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";

fn warnings(report: &LoadReport) -> Vec<String> {
    report.warnings.iter().map(ToString::to_string).collect()
}

#[test]
fn skipped_statements_are_counted_once_per_keyword_with_their_first_line() {
    let obj = [
        TRIS,
        "cstype bspline\ndeg 3\ncurv 0 1 1 2 3\nparm u 0 0 0 1 1 1\nend\n",
        "cstype bspline\nlod 2\nbevel on\nt 1 2\nmy_exporter_hint 42\nf 1 2 3\n",
        "my_exporter_hint 7\nc_interp off\nshadow_obj a.obj\nf 1 3 4\n",
    ]
    .concat();
    let (s, report) = load(&obj, ObjOptions::default(), no_mtl);
    assert_eq!(s.n_patches(), 2);
    assert_eq!(report.faces_read, 2);
    assert_eq!(
        warnings(&report),
        [
            "line 5: skipped 'cstype' statements (nothing sceneinfo uses) (2 times)",
            "line 6: skipped 'deg' statements (nothing sceneinfo uses)",
            "line 7: skipped 'curv' statements (nothing sceneinfo uses)",
            "line 8: skipped 'parm' statements (nothing sceneinfo uses)",
            "line 9: skipped 'end' statements (nothing sceneinfo uses)",
            "line 11: skipped 'lod' statements (nothing sceneinfo uses)",
            "line 12: skipped 'bevel' statements (nothing sceneinfo uses)",
            "line 13: skipped 't' statements (nothing sceneinfo uses)",
            "line 14: skipped unknown 'my_exporter_hint' statements (not an OBJ statement \
             sceneinfo knows) (2 times)",
            "line 17: skipped 'c_interp' statements (nothing sceneinfo uses)",
            "line 18: skipped 'shadow_obj' statements (nothing sceneinfo uses)",
        ]
    );
    // None of them is about materials: visibility commands print them all.
    assert_eq!(report.messages(false).len(), 11);
    // Every statement of the specification without geometry sceneinfo uses is skipped.
    for k in SKIPPED_STATEMENTS {
        let (_, r) = load(
            &[TRIS, *k, " 1\nf 1 2 3\n"].concat(),
            ObjOptions::default(),
            no_mtl,
        );
        assert!(
            matches!(&r.warnings[0].kind, LoadWarningKind::SkippedStatement { keyword } if keyword == k),
            "{k}"
        );
    }
    // Malformed data of the statements that are read stays an error.
    assert_eq!(
        err(&[TRIS, "lod 1\nv 1 x 0\n"].concat()),
        "line 6: y: 'x' is not a number"
    );
}

#[test]
fn line_continuations_are_joined_and_lines_stay_right() {
    let obj = "v 0 0 \\\n  0\nv 1 0 0\nv 0 1 0 # a comment \\ is no continuation\n\
               f 1 \\\n 2 \\\n3\nf 1 3 \\\n2\nbevel off\nf 1 2 9\n";
    // The face after the joined ones is on line 11; 'bevel' on line 10.
    assert_eq!(
        err(obj),
        "line 11: vertex index 9 out of range (3 vertices defined so far; 0 is never valid)"
    );
    let good = obj.replace("f 1 2 9\n", "");
    let (s, report) = load(&good, ObjOptions::default(), no_mtl);
    assert_eq!(s.n_patches(), 2);
    assert_eq!(s.face_vertices(0)[0], DVec3::ZERO);
    assert_eq!(
        warnings(&report),
        ["line 10: skipped 'bevel' statements (nothing sceneinfo uses)"]
    );
    // An empty line ends a statement: this face has two vertices, an error at its first line.
    assert_eq!(
        err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 \\\n\n3\n"),
        "line 4: face needs 3 to 256 vertices, got 2"
    );
    // MTL lines continue too.
    let (s, _) = load(
        "mtllib m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n",
        ObjOptions::default(),
        |_| Some("newmtl a\nKd 0.5 \\\n 0.25 0.125\nKe 1\n".into()),
    );
    assert_eq!(s.materials()[0].reflectance, [0.5, 0.25, 0.125]);
}

#[test]
fn mtllib_takes_the_whole_line_first_then_each_word() {
    let obj = |line: &str| {
        [
            line,
            "\n",
            TRIS,
            "usemtl red\nf 1 2 3\nusemtl blue\nf 1 3 4\n",
        ]
        .concat()
    };
    let libs = |name: &str| match name {
        "my walls.mtl" => Some("newmtl red\nKd 0.5 0 0\nnewmtl blue\nKd 0 0 0.5\n".into()),
        "a.mtl" => Some("newmtl red\nKd 0.5 0 0\n".into()),
        "b.mtl" => Some("newmtl blue\nKd 0 0 0.5\n".into()),
        _ => None,
    };
    for line in [
        "mtllib my walls.mtl",
        "mtllib \"my walls.mtl\"",
        "mtllib   my walls.mtl  ",
        "mtllib a.mtl b.mtl",
        "mtllib a.mtl \\\n b.mtl",
    ] {
        let (s, report) = load(&obj(line), ObjOptions::default(), libs);
        assert!(report.warnings.is_empty(), "{line}: {report:?}");
        assert_eq!(
            s.patch_material(0).unwrap().reflectance,
            [0.5, 0.0, 0.0],
            "{line}"
        );
        assert_eq!(
            s.patch_material(1).unwrap().reflectance,
            [0.0, 0.0, 0.5],
            "{line}"
        );
    }
    // A word that is no library: a warning for it, the others still read.
    let (s, report) = load(
        &obj("mtllib a.mtl gone.mtl b.mtl"),
        ObjOptions::default(),
        libs,
    );
    assert_eq!(s.patch_material(1).unwrap().reflectance, [0.0, 0.0, 0.5]);
    assert_eq!(
        warnings(&report),
        [
            "line 1: material library 'gone.mtl' not found: its materials get the default \
          (reflectance 0, emittance 0)"
        ]
    );
}

#[test]
fn missing_library_and_unknown_material_are_warnings_with_the_default_material() {
    let obj = [
        "mtllib gone.mtl\nmtllib\n",
        TRIS,
        "usemtl white\nf 1 2 3\nusemtl\nf 1 3 4\nusemtl white\nf 4 2 1\n",
    ]
    .concat();
    let (s, report) = load(&obj, ObjOptions::default(), no_mtl);
    assert_eq!(s.n_patches(), 3);
    assert_eq!(s.materials(), [Material::BLACK]);
    assert_eq!(
        warnings(&report),
        [
            "line 1: material library 'gone.mtl' not found: its materials get the default \
             (reflectance 0, emittance 0)",
            "line 2: 'mtllib' without a file name: skipped",
            "line 7: material 'white' is not defined by any mtllib: its faces get the default \
             (reflectance 0, emittance 0) (2 times)",
            "line 9: 'usemtl' without a name: the faces that follow get the default material \
             (reflectance 0, emittance 0)",
        ]
    );
    // All about materials: visibility commands print none of them.
    assert!(report.warnings.iter().all(|w| w.kind.is_material()));
    assert!(report.messages(false).is_empty());
}

#[test]
fn reflectance_one_is_clamped_with_a_warning_naming_value_library_and_line() {
    let obj = [
        "v 9 9 9\nmtllib white.mtl\n",
        TRIS,
        "usemtl a\nf 2 3 4\nusemtl c\nf 2 4 5\n",
    ]
    .concat();
    let mtl =
        |_: &str| Some("newmtl a\nKd 1 1 1\nnewmtl b\nKd 0.5\nnewmtl c\nKd 0.2 1.5 0.3\n".into());
    let (s, report) = load(&obj, ObjOptions::default(), mtl);
    let max = Material::MAX_REFLECTANCE;
    assert_eq!(s.patch_material(0).unwrap().reflectance, [max; 3]);
    assert_eq!(s.patch_material(1).unwrap().reflectance, [0.2, max, 0.3]);
    assert_eq!(
        warnings(&report),
        [
            "line 2: material library 'white.mtl' line 2: reflectance 1 clamped to 0.99 \
          (it must be below 1) (2 times)"
        ]
    );
    assert!(matches!(
        report.warnings[0].kind,
        LoadWarningKind::ReflectanceClamped {
            line: 2,
            value: 1.0,
            ..
        }
    ));
    assert!(report.warnings[0].kind.is_material());
}

/// A closed unit box lit only by an old-style lamp: `Ka 20 20 20` and no `Ke` on the ceiling.
const KA_LAMP_OBJ: &str = "mtllib lamp.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
                           v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nusemtl wall\nf 1 2 3 4\n\
                           f 1 5 6 2\nf 4 3 7 8\nf 1 4 8 5\nf 2 6 7 3\nusemtl lamp\nf 5 8 7 6\n";
const KA_LAMP_MTL: &str = "newmtl wall\nKa 1 1 1\nKd 0.5 0.5 0.5\nKs 0.1 0.1 0.1\nNs 10\n\
                           illum 2\nmap_Kd -s 1 1 1 wall.png\nPr 0.5\nnewmtl lamp\n\
                           Ka 20 20 20\nKd 0.7\nd 1\nTr 0\nTf 1 1 1\nNi 1.5\n";

#[test]
fn ka_is_kept_and_emitted_only_with_emit_from_ka() {
    let mtl = |_: &str| Some(KA_LAMP_MTL.into());
    let (s, report) = load(KA_LAMP_OBJ, ObjOptions::default(), mtl);
    assert!(s.materials().iter().all(|m| !m.is_emitter()));
    // Nothing emits, and two materials have Ka > 0 without Ke.
    assert_eq!(
        warnings(&report),
        [
            "line 10: no material emits (no Ke > 0), but material 'wall' and 1 more have an \
          ambient Ka > 0 and no Ke: old-style lamps emit only when Ka is read as the \
          emittance (emit_from_ka)"
        ]
    );
    assert!(report.warnings[0].kind.is_material());
    let options = ObjOptions::new(Subdivision::Grid(2)).with_emit_from_ka(true);
    let (s, report) = load(KA_LAMP_OBJ, options, mtl);
    assert!(report.warnings.is_empty());
    assert_eq!(s.n_patches(), 24);
    let lamp = s.patch_material(20).unwrap();
    assert_eq!((lamp.reflectance, lamp.emittance), ([0.7; 3], [20.0; 3]));
    let wall = s.patch_material(0).unwrap();
    assert_eq!((wall.reflectance, wall.emittance), ([0.5; 3], [1.0; 3]));
    // Ke wins over Ka; with Ke anywhere, Ka-only materials are not reported.
    let with_ke = KA_LAMP_MTL.replace("Ka 20 20 20", "Ka 20 20 20\nKe 5 5 5");
    let (s, report) = load(KA_LAMP_OBJ, ObjOptions::default(), |_| {
        Some(with_ke.clone())
    });
    assert!(report.warnings.is_empty());
    assert_eq!(s.patch_material(5).unwrap().emittance, [5.0; 3]);
    let (s, _) = load(
        KA_LAMP_OBJ,
        ObjOptions::default().with_emit_from_ka(true),
        |_| Some(with_ke.clone()),
    );
    assert_eq!(s.patch_material(5).unwrap().emittance, [5.0; 3]);
    // A negative Ka is an error only where it is read as emittance.
    let negative = KA_LAMP_MTL.replace("Ka 20 20 20", "Ka 20 -1 20");
    assert!(
        parse_obj(KA_LAMP_OBJ, &ObjOptions::default(), |_| Some(
            negative.clone()
        ))
        .is_ok()
    );
    assert_eq!(
        parse_obj(
            KA_LAMP_OBJ,
            &ObjOptions::default().with_emit_from_ka(true),
            |_| { Some(negative.clone()) }
        )
        .unwrap_err()
        .to_string(),
        "line 1: material library 'lamp.mtl' line 10: emittance -1 is negative"
    );
}

#[test]
fn faces_read_counts_the_faces_as_written() {
    let (s, report) = load(ROOM, ObjOptions::new(Subdivision::Grid(3)), no_mtl);
    assert_eq!((report.faces_read, s.n_patches()), (6, 54));
    assert!(report.warnings.is_empty());
}

/// `text` with every `\n` made `end`.
fn with_line_ends(text: &str, end: &str) -> String {
    text.replace('\n', end)
}

#[test]
fn byte_order_mark_and_every_line_end_read_alike() {
    let plain = parse(CORNELL_OBJ, Subdivision::Grid(2), cornell_mtl).unwrap();
    for end in ["\r\n", "\r"] {
        for bom in ["", "\u{feff}"] {
            let obj = format!("{bom}{}", with_line_ends(CORNELL_OBJ, end));
            let mtl =
                |name: &str| cornell_mtl(name).map(|m| format!("{bom}{}", with_line_ends(&m, end)));
            let s = parse(&obj, Subdivision::Grid(2), mtl).unwrap();
            assert_eq!(s.n_patches(), plain.n_patches(), "{end:?} {bom:?}");
            assert_eq!(s.materials(), plain.materials(), "{end:?} {bom:?}");
            assert_eq!(s.objects(), plain.objects(), "{end:?} {bom:?}");
            assert_eq!(s.bounds(), plain.bounds(), "{end:?} {bom:?}");
        }
    }
    // A byte-order mark before a `newmtl` no longer hides it.
    let (s, _) = load(
        "mtllib m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl a\nf 1 2 3\n",
        ObjOptions::default(),
        |_| Some("\u{feff}newmtl a\r\rKd 0.5 0.25 0.125\r".into()),
    );
    assert_eq!(s.materials()[0].reflectance, [0.5, 0.25, 0.125]);
}

#[test]
fn line_numbers_count_cr_only_and_mixed_line_ends() {
    // Lines 1-3 end in CR, CRLF and LF; the bad face is on line 5.
    let obj = "\u{feff}v 0 0 0\rv 1 0 0\r\nv 0 1 0\n\rf 1 2 9\r";
    assert_eq!(
        err(obj),
        "line 5: vertex index 9 out of range (3 vertices defined so far; 0 is never valid)"
    );
    // Continuations join across a CR-only break.
    assert_eq!(
        err("v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 \\\r2 \\\r\r3\r"),
        "line 4: face needs 3 to 256 vertices, got 2"
    );
    // Errors inside a CR-only library name its line too.
    assert_eq!(
        err_with("v 0 0 0\rmtllib box.mtl\r", "# x\rnewmtl a\rKe 0 -1 0\r"),
        "line 2: material library 'box.mtl' line 3: emittance -1 is negative"
    );
}
