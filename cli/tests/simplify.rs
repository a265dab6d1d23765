//! `sceneinfo simplify` through the real binary (issue 20, item 3): the JSON's numbers agree
//! with each other and with `measure` of the written coarse scene, a public 3D mesh from the
//! corpus simplifies, and refusals exit 2.

mod common;

use common::{bin, number, stdout_of, temp};

fn root() -> std::path::PathBuf {
    std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}

#[test]
fn lit_room_to_a_target_writes_a_scene_with_the_reported_i_s() {
    let scene = root().join("scenes/lit-room.flat");
    let out = temp("lit-room-34.flat");
    let json = stdout_of(&[
        "simplify",
        scene.to_str().unwrap(),
        "--to",
        "34",
        "--json",
        "-o",
        out.to_str().unwrap(),
    ]);
    assert_eq!(number(&json, "fine_patches"), 136.0);
    assert_eq!(number(&json, "n_patches"), 34.0);
    let (fine, i_s, lost) = (
        number(&json, "fine_i_s"),
        number(&json, "i_s"),
        number(&json, "lost"),
    );
    assert!(i_s < fine && (fine - i_s - lost).abs() < 1e-15, "{json}");
    for key in [
        "\"stop\":\"target\"",
        "\"mi\":{",
        "\"regular\":{",
        "\"power\":{",
        "\"rmse\":",
    ] {
        assert!(json.contains(key), "{key} missing: {json}");
    }
    // The written coarse scene, measured exactly, has the I_S the merges report.
    let measured = stdout_of(&["measure", out.to_str().unwrap(), "--json"]);
    assert_eq!(number(&measured, "n_patches"), 34.0);
    assert!((number(&measured, "i_s") - i_s).abs() < 1e-12, "{measured}");
}

#[test]
fn a_loss_budget_is_never_exceeded() {
    let scene = root().join("scenes/lit-room.flat");
    let json = stdout_of(&[
        "simplify",
        scene.to_str().unwrap(),
        "--max-loss",
        "0.05",
        "--json",
    ]);
    assert!(number(&json, "lost") <= 0.05);
    assert!(json.contains("\"stop\":\"budget\""), "{json}");
}

#[test]
fn a_corpus_cube_simplifies_in_3d() {
    // tests/data/corpus/ply/openmesh: a cube facing inwards (public, see SOURCES.md).
    let cube = root().join("tests/data/corpus/ply/openmesh/cube-minimal-extra-elements-binary.ply");
    let json = stdout_of(&[
        "simplify",
        cube.to_str().unwrap(),
        "--grid",
        "4",
        "--to",
        "24",
        "--json",
    ]);
    assert_eq!(number(&json, "fine_patches"), 96.0);
    assert_eq!(number(&json, "n_patches"), 24.0);
    assert!(number(&json, "i_s") > 0.0 && number(&json, "i_s") < number(&json, "fine_i_s"));
}

#[test]
fn refusals_exit_2() {
    let scene = root().join("scenes/lit-room.flat");
    let cornell = root().join("tests/data/corpus/obj/cornell_box/cornell_box.obj");
    let cube = root().join("tests/data/corpus/ply/openmesh/cube-minimal-extra-elements-binary.ply");
    for (args, says) in [
        (vec!["simplify", scene.to_str().unwrap()], "--to"),
        (
            vec!["simplify", scene.to_str().unwrap(), "--max-loss=-1"],
            "bits",
        ),
        (vec!["simplify", scene.to_str().unwrap(), "--to", "0"], "0"),
        (
            vec![
                "simplify",
                scene.to_str().unwrap(),
                "--to",
                "4",
                "--grid",
                "2",
            ],
            "3D faces only",
        ),
        (
            vec!["simplify", cornell.to_str().unwrap(), "--to", "4"],
            "hide others",
        ),
        (
            vec![
                "simplify",
                cube.to_str().unwrap(),
                "--to",
                "4",
                "-o",
                "/tmp/x.flat",
            ],
            ".flat",
        ),
    ] {
        let out = bin().args(&args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
    }
}
