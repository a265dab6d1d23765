//! `sceneinfo render` through the real binary (issue 20, item 4): the corpus Cornell box
//! rendered small, its pictures written, the `--rmse` comparison's rows, and refusals (a
//! flatland scene, a threshold outside [0, 1]) with exit 2.

mod common;

use common::{bin, stdout_of, temp};

/// The corpus Cornell box (its lamp is an old-style `Ka` one).
const CORNELL: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../tests/data/corpus/obj/cornell_box/cornell_box.obj"
);

/// The arguments of a small, quick render of the Cornell box.
fn small<'a>(extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "render",
        CORNELL,
        "--emit-from-ka",
        "--grid",
        "2",
        "--lines",
        "100000",
        "--size",
        "16x16",
        "--spp",
        "4",
    ];
    args.extend_from_slice(extra);
    args
}

#[test]
fn renders_the_cornell_box_with_its_sample_map() {
    let (png, map) = (temp("cornell.png"), temp("cornell-samples.png"));
    let out = stdout_of(&small(&[
        "--adaptive",
        "mi",
        "--png",
        png.to_str().unwrap(),
        "--samples-png",
        map.to_str().unwrap(),
    ]));
    // Equal budget: 16 × 16 pixels × 4 spp
    assert!(out.contains("samples               1024 in all"), "{out}");
    assert!(
        out.contains("adaptive, mi contrast > 0.02, pixel and its 4 neighbours"),
        "{out}"
    );
    for p in [&png, &map] {
        let bytes = std::fs::read(p).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        // IHDR: width and height 16
        assert_eq!(&bytes[16..24], &[0, 0, 0, 16, 0, 0, 0, 16]);
    }
}

#[test]
fn rmse_compares_three_allocations_at_equal_samples() {
    let out = stdout_of(&small(&["--rmse", "--seeds", "2", "--reference-spp", "16"]));
    for method in ["uniform ", "entropy ", "mi "] {
        let row = out
            .lines()
            .find(|l| l.trim_start().starts_with(method))
            .unwrap_or_else(|| panic!("no {method} row in {out}"));
        let mean: f64 = row.split_whitespace().nth(1).unwrap().parse().unwrap();
        assert!(mean.is_finite() && mean >= 0.0, "{row}");
    }
}

#[test]
fn refuses_a_flatland_scene_and_a_bad_threshold() {
    let flat = temp("square.flat");
    std::fs::write(&flat, "poly 4 0 0 1 0 1 1 0 1\n").unwrap();
    let out = bin()
        .args(["render", flat.to_str().unwrap()])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("3D scenes"));
    let out = bin().args(small(&["--threshold", "2"])).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("threshold"));
}
