use super::*;
use std::path::PathBuf;

fn read_text(text: &str) -> Result<Scene3> {
    read(Path::new("t.vs3"), text, &mut LoadReport::default())
}

fn read_layout(text: &str) -> Result<(Scene3, Vs3Layout)> {
    read_with_layout(Path::new("t.vs3"), text, &mut LoadReport::default())
}

/// View3D's sample files (`tests/data/vs3/view3d-examples`).
fn example(name: &str) -> (PathBuf, String) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/vs3/view3d-examples")
        .join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    (path, text)
}

/// The corners of each patch, sorted, in the file's units.
fn corners(s: &Scene3) -> Vec<Vec<[f64; 3]>> {
    s.patches()
        .iter()
        .map(|p| {
            let mut c: Vec<[f64; 3]> = s.points()[p.first..p.first + p.count]
                .iter()
                .map(|q| s.frame().to_world(*q).to_array())
                .collect();
            c.sort_by(|x, y| x.partial_cmp(y).unwrap());
            c
        })
        .collect()
}

/// A unit cube's six faces (View3D's `cube.vs3`), with `extra` lines added before the end.
fn cube_with(extra: &str) -> String {
    format!(
        "F 3\nV 1 0 0 0\nV 2 1 0 0\nV 3 1 1 0\nV 4 0 1 0\nV 5 0 0 1\nV 6 1 0 1\nV 7 1 1 1\n\
         V 8 0 1 1\nV 9 .25 .25 0\nV 10 .75 .25 0\nV 11 .75 .75 0\nV 12 .25 .75 0\n\
         S 1 1 2 3 4 0 0 0.5 zeq0\nS 2 1 4 8 5 0 0 0.5 xeq0\nS 3 1 5 6 2 0 0 0.5 yeq0\n\
         S 4 7 6 5 8 0 0 0.5 zeq1\nS 5 7 3 2 6 0 0 0.5 xeq1\nS 6 7 8 4 3 0 0 0.5 yeq1\n\
         {extra}End of data\n"
    )
}

/// The manual's Pinney & Bean room, given in both geometry formats: `F 3a`'s planes and
/// shapes give the corners `F 3`'s vertices do, surface by surface, and the same output
/// surfaces (the L-shaped floor and ceiling, three pieces each, are one surface each).
#[test]
fn blast_geometry_is_the_vertex_geometry() {
    let (p3, t3) = example("pinney-bean-test-4.vs3");
    let (pa, ta) = example("pinney-bean-test-4-f3a.vs3");
    let mut report = LoadReport::default();
    let (s3, l3) = read_with_layout(&p3, &t3, &mut report).unwrap();
    let (sa, la) = read_with_layout(&pa, &ta, &mut report).unwrap();
    assert_eq!(s3.n_patches(), 12);
    assert_eq!(corners(&s3), corners(&sa));
    for (a, b) in s3.patches().iter().zip(sa.patches()) {
        assert!((a.normal - b.normal).length() < 1e-15);
    }
    // The same surfaces (their lines and the files' controls differ)
    let key = |l: &Vs3Layout| -> Vec<(usize, String, Option<usize>, Option<f64>)> {
        l.surfaces()
            .iter()
            .map(|s| (s.number, s.name.clone(), s.mask_of, s.emissivity))
            .collect()
    };
    assert_eq!(key(&l3), key(&la));
    assert_eq!(l3.areas(), la.areas());
    assert!(l3.controls().emit && l3.controls().encl && !la.controls().emit);
    assert_eq!(l3.areas(), [9.0, 3.0, 6.0, 6.0, 3.0, 9.0, 5.0, 5.0]);
}

/// The surface kinds of the manual on a unit cube's floor (the 0.5 × 0.5 square in its
/// middle): the output surfaces and areas View3D 4.0.0 reported for the same files.
#[test]
fn subsurfaces_masks_nulls_and_obstructions_give_view3d_s_surfaces() {
    // A window: the floor keeps 0.75, the window is the 7th surface
    let (scene, layout) = read_layout(&cube_with("S 7 9 10 11 12 1 0 0.5 win\n")).unwrap();
    assert_eq!(layout.areas(), [0.75, 1.0, 1.0, 1.0, 1.0, 1.0, 0.25]);
    assert!((scene.total_area() - 6.0).abs() < 1e-12);
    // A mask (facing the floor): the floor keeps its whole area; the mask has no patch
    let (scene, layout) = read_layout(&cube_with("M 7 12 11 10 9 1 0 0.5 mask\n")).unwrap();
    assert_eq!(layout.areas(), [1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.25]);
    assert_eq!(layout.surfaces()[6].mask_of, Some(0));
    assert!((scene.total_area() - 5.75).abs() < 1e-12);
    // A null surface: cut out, no row
    let (_, layout) = read_layout(&cube_with("N 7 12 11 10 9 1 0 0.5 null\n")).unwrap();
    assert_eq!(layout.areas(), [0.75, 1.0, 1.0, 1.0, 1.0, 1.0]);
    // An obstruction halfway up: patches, no row
    let (scene, layout) = read_layout(&cube_with(
        "V 13 .25 .25 .5\nV 14 .75 .25 .5\nV 15 .75 .75 .5\nV 16 .25 .75 .5\n\
         O 7 13 14 15 16 0 0 0.5 obs\n",
    ))
    .unwrap();
    assert_eq!(scene.n_patches(), 7);
    assert_eq!(layout.areas(), [1.0; 6]);
    assert_eq!(layout.n_patches(), scene.n_patches());
    assert!(!layout.is_one_to_one());
    // A mask's row is 1 at its base; the base's row gives the mask A_mask / A_base
    let (_, layout) = read_layout(&cube_with("M 7 12 11 10 9 1 0 0.5 mask\n")).unwrap();
    let np = layout.n_patches();
    let (mut buffer, mut out) = (vec![0.0; np], vec![0.0; 7]);
    layout
        .combined_row(6, &mut buffer, &mut out, |_, b| {
            b.fill(0.0);
            Ok(())
        })
        .unwrap();
    assert_eq!(out, [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    layout
        .combined_row(0, &mut buffer, &mut out, |_, b| {
            b.fill(0.0);
            Ok(())
        })
        .unwrap();
    assert_eq!(out[6], 0.25);
}

#[test]
fn surfaces_on_a_base_are_checked() {
    for (extra, what) in [
        // Facing away from its base's front
        ("S 7 12 11 10 9 1 0 0.5 win\n", "facing"),
        // Not in the plane
        ("V 13 .5 .5 .5\nS 7 9 10 13 0 1 0 0.5 win\n", "plane"),
        // Sticking out of the base
        ("V 13 2 .25 0\nS 7 9 13 11 0 1 0 0.5 win\n", "inside"),
        // A mask facing away from its base
        ("M 7 9 10 11 12 1 0 0.5 mask\n", "towards"),
        // A null surface without a base
        ("N 7 12 11 10 9 0 0 0.5 null\n", "base is 0"),
        // An obstruction on a base
        ("O 7 9 10 11 12 1 0 0.5 obs\n", "obstruction-only"),
        // A base numbered after
        (
            "S 7 9 10 11 12 8 0 0.5 win\nS 8 1 2 3 4 0 0 0.5 b\n",
            "numbered before",
        ),
        // Two windows overlapping
        (
            "S 7 9 10 11 12 1 0 0.5 w\nS 8 9 10 11 12 1 0 0.5 w\n",
            "overlap",
        ),
    ] {
        let e = read_layout(&cube_with(extra)).unwrap_err().to_string();
        assert!(
            e.starts_with("t.vs3:") && e.contains(what),
            "{extra:?}: {e}"
        );
    }
}

#[test]
fn combined_pieces_become_one_convex_patch() {
    // A hexagon as a quad and a quad sharing an edge (as obj2vs3.py cuts it)
    let text = "T hex\nF 3\nV 1 0 0 0\nV 2 2 0 0\nV 3 3 1 0\nV 4 2 2 0\nV 5 0 2 0\nV 6 -1 1 0\n\
                S 1 1 2 3 4 0 0 0.9 a\nS 2 1 4 5 6 0 1 0.9 a\nEnd of data\n";
    let scene = read_text(text).unwrap();
    assert_eq!(scene.n_patches(), 1);
    let area = scene.total_area();
    assert!((area - 6.0).abs() < 1e-12, "{area}");
    // An L made of three squares is not convex: three patches, one output surface
    let text = "F 3\nV 1 0 0 0\nV 2 1 0 0\nV 3 1 1 0\nV 4 0 1 0\nV 5 2 0 0\nV 6 2 1 0\n\
                V 7 1 2 0\nV 8 0 2 0\n\
                S 1 1 2 3 4 0 0 0.9 a\nS 2 2 5 6 3 0 1 0.9 a\nS 3 4 3 7 8 0 1 0.9 a\n";
    let (scene, layout) = read_layout(text).unwrap();
    assert_eq!(scene.n_patches(), 3);
    assert_eq!(layout.surfaces().len(), 1);
    assert!((layout.areas()[0] - 3.0).abs() < 1e-12);
    assert!(!layout.is_one_to_one());
}

#[test]
fn refusals_name_the_line() {
    for (text, line) in [
        ("F 2\n", 1),
        ("F 3\nV 1 0 0 0\nS 1 1 2 3 0 0 0 0.9 a\n", 3),
        ("F 3\nV 1 0 0 x\n", 2),
        ("F 3\nO 1 1 2 3 0\n", 2),
        ("F 3\nQ 1\n", 2),
    ] {
        let e = read_text(text).unwrap_err().to_string();
        assert!(e.starts_with(&format!("t.vs3:{line}: ")), "{text:?}: {e}");
    }
    assert!(read_text("V 1 0 0 0\n").is_err());
}

/// A file written by the View3D anchor's `obj2vs3.py` (tests/data/vs3, from the OBJ
/// beside it; a hexagon cut into two pieces joined by `cmb`) is the OBJ's scene: the
/// same patches, in the same order, with the same corners.
#[test]
fn obj2vs3_output_is_the_obj_scene() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/vs3");
    let options = crate::LoadOptions::default();
    let load = |name: &str| match crate::load_file(&dir.join(name), &options).unwrap() {
        (sceneinfo::Scene::Solid(s), _) => s,
        (sceneinfo::Scene::Flat(_), _) => panic!("{name}: read as flatland"),
    };
    let (vs3, obj) = (load("room_with_plate.vs3"), load("room_with_plate.obj"));
    assert_eq!(vs3.n_patches(), 9);
    assert_eq!(vs3.n_patches(), obj.n_patches());
    for (a, b) in vs3.patches().iter().zip(obj.patches()) {
        let corners = |s: &Scene3, first: usize, count: usize| {
            let mut c: Vec<[f64; 3]> = s.points()[first..first + count]
                .iter()
                .map(|p| p.to_array())
                .collect();
            c.sort_by(|x, y| x.partial_cmp(y).unwrap());
            c
        };
        assert_eq!(
            corners(&vs3, a.first, a.count),
            corners(&obj, b.first, b.count)
        );
    }
    assert!((vs3.total_area() - obj.total_area()).abs() < 1e-12);
}

/// A surface without area is dropped with a warning, as in the other formats; View3D's
/// rows (which divide by its area) are then refused, naming it.
#[test]
fn a_surface_without_area_is_dropped_and_its_row_refused() {
    let text = cube_with("V 13 2 0 0\nS 7 1 2 13 0 0 0 0.5 flat\n");
    let mut report = LoadReport::default();
    let scene = read(Path::new("t.vs3"), &text, &mut report).unwrap();
    assert_eq!(scene.n_patches(), 6);
    assert!(!report.warnings.is_empty());
    let e = read_layout(&text).unwrap_err().to_string();
    assert!(e.starts_with("t.vs3:21: surface 7 has no area"), "{e}");
    // Something on it: refused at once
    let text = cube_with("V 13 2 0 0\nS 7 1 2 13 0 0 0 0.5 flat\nS 8 1 2 13 0 7 0 0.5 w\n");
    let e = read_text(&text).unwrap_err().to_string();
    assert!(e.contains("has no area"), "{e}");
}

/// Seeded mutations of View3D's sample files and the surface-kind files (a token
/// replaced by another of the file's tokens, a number, a letter, or removed; a line
/// dropped or repeated): each is read or refused with an error, never a panic, and every
/// layout read has finite, positive areas.
#[test]
fn mutated_files_are_read_or_refused_without_panic() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/vs3");
    let mut texts = Vec::new();
    for sub in ["view3d-examples", "surface-kinds"] {
        let mut names: Vec<PathBuf> = std::fs::read_dir(dir.join(sub))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "vs3"))
            .collect();
        names.sort();
        texts.extend(names.iter().map(|p| std::fs::read_to_string(p).unwrap()));
    }
    assert_eq!(texts.len(), 10);
    // xorshift64*: a fixed sequence
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = move |bound: usize| {
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        (state.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 33) as usize % bound.max(1)
    };
    let replacements = [
        "0", "1", "-1", "7", "99", "1e308", "-0", "0.5", "S", "M", "N", "O", "R", "Q", "T", "F",
        "3a", "x", "",
    ];
    for round in 0..3000 {
        let text = &texts[round % texts.len()];
        let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
        for _ in 0..1 + next(3) {
            let k = next(lines.len());
            match next(4) {
                0 => {
                    lines.remove(k);
                }
                1 => {
                    let l = lines[k].clone();
                    lines.insert(k, l);
                }
                _ => {
                    let mut tokens: Vec<&str> = lines[k].split_whitespace().collect();
                    if !tokens.is_empty() {
                        let t = next(tokens.len());
                        tokens[t] = replacements[next(replacements.len())];
                        lines[k] = tokens.join(" ");
                    }
                }
            }
            if lines.is_empty() {
                break;
            }
        }
        let mutated = lines.join("\n");
        if let Ok((scene, layout)) = read_layout(&mutated) {
            assert_eq!(layout.n_patches(), scene.n_patches());
            assert!(
                layout.areas().iter().all(|a| a.is_finite() && *a > 0.0),
                "{mutated}"
            );
        }
    }
}
