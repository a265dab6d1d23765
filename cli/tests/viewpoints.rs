//! `sceneinfo viewpoints` through the real binary: the JSON equals the golden file the wasm
//! test also checks (so CLI and wasm agree byte for byte), any thread count gives the same
//! bytes, the pictures are written, bad input is refused, and mesh saliency is higher on the
//! horns and ears of Keenan Crane's Spot cow than on its back.

mod common;

use std::path::{Path, PathBuf};

use common::{array, bin, stdout_of, temp};

fn data(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data")
        .join(rel)
}

#[test]
fn json_equals_the_golden_file_shared_with_wasm() {
    let obj = data("viewpoints/octahedron_and_tetrahedron.obj");
    let json = stdout_of(&[
        "viewpoints",
        obj.to_str().unwrap(),
        "--views",
        "42",
        "--resolution",
        "32",
        "--best",
        "3",
        "--json",
    ]);
    let golden =
        std::fs::read_to_string(data("viewpoints/octahedron_and_tetrahedron_42_32_3.json"))
            .unwrap();
    assert_eq!(json, golden);
}

#[test]
fn any_thread_count_prints_the_same_bytes_and_pictures_are_written() {
    let teapot = data("corpus/obj/euc/teapot.obj");
    let run = |threads: &str, ply: &Path, png: &Path, sphere: &Path| {
        stdout_of(&[
            "viewpoints",
            teapot.to_str().unwrap(),
            "--views",
            "42",
            "--resolution",
            "64",
            "--json",
            "--threads",
            threads,
            "--ply",
            ply.to_str().unwrap(),
            "--png",
            png.to_str().unwrap(),
            "--png-size",
            "64",
            "--sphere-ply",
            sphere.to_str().unwrap(),
        ])
    };
    let (ply, png, sphere) = (temp("vp.ply"), temp("vp.png"), temp("vp-sphere.ply"));
    let one = run("1", &ply, &png, &sphere);
    let two = run(
        "2",
        &temp("vp2.ply"),
        &temp("vp2.png"),
        &temp("vp2-sphere.ply"),
    );
    let five = run(
        "5",
        &temp("vp5.ply"),
        &temp("vp5.png"),
        &temp("vp5-sphere.ply"),
    );
    assert_eq!(one, two);
    assert_eq!(one, five);
    let text = std::fs::read_to_string(&ply).unwrap();
    assert!(text.starts_with("ply\n") && text.contains("element face 2464"));
    assert_eq!(text, std::fs::read_to_string(temp("vp2.ply")).unwrap());
    let sphere = std::fs::read_to_string(&sphere).unwrap();
    assert!(sphere.contains("element vertex 42") && sphere.contains("element face 80"));
    let png = std::fs::read(&png).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    assert_eq!(png, std::fs::read(temp("vp2.png")).unwrap());
    // One picture per best view (--best defaults to 5): OUT.png, OUT-2.png … OUT-5.png
    for k in 2..=5 {
        let other = std::fs::read(temp(&format!("vp-{k}.png"))).unwrap();
        assert_eq!(&other[..8], b"\x89PNG\r\n\x1a\n");
        assert_ne!(other, png);
    }
    assert!(!temp("vp-6.png").exists());
    // The table mentions the best views and the measures
    let table = stdout_of(&[
        "viewpoints",
        teapot.to_str().unwrap(),
        "--views",
        "12",
        "--resolution",
        "32",
    ]);
    assert!(table.contains("best views (least VMI)") && table.contains("I(V;O) = "));
    // --fraction stops the greedy selection early: at 1 % of I(V;O), after one view of 12
    let json = stdout_of(&[
        "viewpoints",
        teapot.to_str().unwrap(),
        "--views",
        "12",
        "--resolution",
        "32",
        "--fraction",
        "0.01",
        "--json",
    ]);
    assert_eq!(array(&json, "selection").len(), 1, "{json}");
    // The sphere coloured by VE
    let ve = temp("vp-ve.ply");
    stdout_of(&[
        "viewpoints",
        teapot.to_str().unwrap(),
        "--views",
        "12",
        "--resolution",
        "32",
        "--sphere-ply",
        ve.to_str().unwrap(),
        "--sphere-color",
        "ve",
    ]);
    let ve = std::fs::read_to_string(&ve).unwrap();
    assert!(ve.contains("viewpoint entropy") && ve.contains("element vertex 12"));
}

#[test]
fn bad_input_is_refused() {
    let obj = data("viewpoints/octahedron_and_tetrahedron.obj");
    for extra in [
        &["--views", "100"][..],
        &["--resolution", "0"],
        &["--resolution", "100000"],
        &["--distance", "0.5"],
        &["--distance", "NaN"],
        &["--fraction", "1.5"],
        &["--fraction", "NaN"],
    ] {
        let out = bin()
            .args(["viewpoints", obj.to_str().unwrap()])
            .args(extra)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{extra:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.contains("octahedron_and_tetrahedron.obj"),
            "{extra:?}: {err}"
        );
    }
    let flat = temp("square.flat");
    std::fs::write(&flat, "poly 4 0 0 1 0 1 1 0 1\n").unwrap();
    let out = bin()
        .args(["viewpoints", flat.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}

/// A single quad (the Cornell floor of `pbr-mat-ext.obj`) is seen edge-on from the
/// viewpoints in its plane: they are blind (p(v) = 0), named in a warning, and the run
/// succeeds.
#[test]
fn a_flat_scene_runs_with_blind_viewpoints() {
    let quad = data("corpus/obj/tinyobjloader/pbr-mat-ext.obj");
    let out = bin()
        .args(["viewpoints", quad.to_str().unwrap(), "--views", "42"])
        .args(["--resolution", "32", "--json"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("8 of 42 viewpoints see no polygon"), "{err}");
    let json = String::from_utf8(out.stdout).unwrap();
    assert!(json.contains("\"blind\":8,"), "{json}");
    assert!(common::number(&json, "i_vo").abs() < 1e-15);
}

/// Face centroids of `spot.ply` (binary little-endian: 2 930 `float x y z` vertices, then
/// 5 856 faces of `uchar 3, int ×3`), read here so the regions are named by position.
fn spot_centroids(path: &Path) -> Vec<[f64; 3]> {
    let bytes = std::fs::read(path).unwrap();
    let end = b"end_header\n";
    let at = bytes.windows(end.len()).position(|w| w == end).unwrap() + end.len();
    let header = std::str::from_utf8(&bytes[..at]).unwrap();
    assert!(header.contains("element vertex 2930") && header.contains("element face 5856"));
    let f32_at = |k: usize| f64::from(f32::from_le_bytes(bytes[k..k + 4].try_into().unwrap()));
    let vertices: Vec<[f64; 3]> = (0..2930)
        .map(|v| {
            let k = at + 12 * v;
            [f32_at(k), f32_at(k + 4), f32_at(k + 8)]
        })
        .collect();
    let faces = at + 12 * 2930;
    (0..5856)
        .map(|f| {
            let k = faces + 13 * f;
            assert_eq!(bytes[k], 3);
            let idx = |j: usize| {
                let s = k + 1 + 4 * j;
                i32::from_le_bytes(bytes[s..s + 4].try_into().unwrap()) as usize
            };
            let (a, b, c) = (vertices[idx(0)], vertices[idx(1)], vertices[idx(2)]);
            [0, 1, 2].map(|ax| (a[ax] + b[ax] + c[ax]) / 3.0)
        })
        .collect()
}

/// Spot (Keenan Crane, public domain; `tests/data/corpus/SOURCES.md`) stands with +y up,
/// its head towards −z (the top of the head, with the horns, reaches y ≈ 0.95 at
/// z ≈ −0.3), its body lower and longer towards +z (top at y ≈ 0.2–0.3). Regions by face
/// centroid (the loader keeps the PLY's face order: one patch per triangle):
/// - horns: `y > 0.85` (only the horn tips and the crown between them reach that high);
/// - ears: head faces (`z < −0.1`, `y > 0.5`) with `|x| > 0.3` (the ears stick out
///   sideways; the skull is narrower);
/// - back: the top of the body, `|x| < 0.15`, `0.3 < z < 0.8`, `y > 0.15`: a smooth,
///   gently curved surface every neighbouring polygon sees alike.
///
/// Saliency (mean JS divergence of a polygon's `p(V|o)` from its neighbours') must be
/// higher on the thin, strongly curved horns and ears than on the smooth back.
#[test]
fn spot_is_more_salient_at_its_horns_and_ears_than_on_its_back() {
    let spot = data("corpus/ply/geometry-central/spot.ply");
    let json = stdout_of(&[
        "viewpoints",
        spot.to_str().unwrap(),
        "--views",
        "162",
        "--resolution",
        "256",
        "--best",
        "1",
        "--json",
    ]);
    let saliency = array(&json, "saliency");
    let centroids = spot_centroids(&spot);
    assert_eq!(saliency.len(), centroids.len());
    let mean = |pick: &dyn Fn(&[f64; 3]) -> bool| {
        let values: Vec<f64> = centroids
            .iter()
            .zip(&saliency)
            .filter(|(c, _)| pick(c))
            .map(|(_, &s)| s)
            .collect();
        assert!(values.len() > 50, "region too small: {}", values.len());
        values.iter().sum::<f64>() / values.len() as f64
    };
    let horns = mean(&|c| c[1] > 0.85);
    let ears = mean(&|c| c[2] < -0.1 && c[1] > 0.5 && c[0].abs() > 0.3);
    let back = mean(&|c| c[0].abs() < 0.15 && c[2] > 0.3 && c[2] < 0.8 && c[1] > 0.15);
    assert!(horns > 2.0 * back, "horns {horns} back {back}");
    assert!(ears > 2.0 * back, "ears {ears} back {back}");
}
