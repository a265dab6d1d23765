//! Exact 3D form factors with occlusion split over machines (`formfactors --rows A..B
//! --partial`, `merge`), and View3D's output format (`.vf3`), through the real binary.

mod common;

use std::path::{Path, PathBuf};

use common::{bin, number, stdout_of, succeeded, temp, without_timing};

/// View3D's `.vs3` of a room with a plate and a hexagon (`tests/data/vs3`), written by the
/// View3D anchor's converter, not by sceneinfo.
fn room_vs3() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/vs3/room_with_plate.vs3")
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Rows computed in three ranges (on 1, 2 and 3 threads), merged in another order, give the
/// one job's sparse matrix and View3D file byte for byte, and its measures.
#[test]
fn row_ranges_merge_into_the_one_job_byte_for_byte() {
    let scene = room_vs3();
    let (one_ijv, one_vf3) = (temp("one.ijv"), temp("one.vf3"));
    for out in [&one_ijv, &one_vf3] {
        stdout_of(&["formfactors", s(&scene), "--tol", "1e-3", "--out", s(out)]);
    }
    let ijv = std::fs::read_to_string(&one_ijv).unwrap();
    let n = ijv.lines().skip(1).filter(|l| l.starts_with("0,")).count();
    assert!(n > 3, "{ijv}");
    // Some entry carries a non-zero error estimate (the plate hides part of the room)
    assert!(
        ijv.lines().skip(1).any(|l| l
            .rsplit(',')
            .next()
            .is_some_and(|e| e.parse::<f64>().unwrap() > 0.0)),
        "{ijv}"
    );
    let patches: usize = std::fs::read_to_string(&one_vf3)
        .unwrap()
        .lines()
        .next()
        .unwrap()
        .split_whitespace()
        .nth(5)
        .unwrap()
        .parse()
        .unwrap();
    let (a, b) = (patches / 3, 2 * patches / 3);
    let mut parts = Vec::new();
    for (k, (rows, threads)) in [
        (format!("{b}..{patches}"), "1"),
        (format!("0..{a}"), "2"),
        (format!("{a}..{b}"), "3"),
    ]
    .iter()
    .enumerate()
    {
        let part = temp(&format!("part{k}.sir"));
        let text = stdout_of(&[
            "formfactors",
            s(&scene),
            "--tol",
            "1e-3",
            "--rows",
            rows,
            "--threads",
            threads,
            "--partial",
            s(&part),
        ]);
        assert!(
            text.starts_with(&format!("wrote {}: rows {rows}", s(&part))),
            "{text}"
        );
        parts.push(part);
    }
    let (merged_ijv, merged_vf3) = (temp("merged.ijv"), temp("merged.vf3"));
    let report = stdout_of(&[
        "merge",
        s(&parts[0]),
        s(&parts[2]),
        s(&parts[1]),
        "--json",
        "--out",
        s(&merged_ijv),
    ]);
    stdout_of(&[
        "merge",
        s(&parts[1]),
        s(&parts[0]),
        s(&parts[2]),
        "--out",
        s(&merged_vf3),
        "--scene",
        s(&scene),
    ]);
    assert_eq!(ijv, std::fs::read_to_string(&merged_ijv).unwrap());
    assert_eq!(
        std::fs::read(&one_vf3).unwrap(),
        std::fs::read(&merged_vf3).unwrap()
    );
    // The report of the merge is `measure`'s (the measures to rounding: sparse storage)
    let measured = stdout_of(&["measure", s(&scene), "--tol", "1e-3", "--json"]);
    for key in ["i_s", "h_s", "max_error_estimate"] {
        let (x, y) = (number(&report, key), number(&measured, key));
        assert!(
            (x - y).abs() <= 1e-12,
            "{key}: {x} vs {y}\n{report}\n{measured}"
        );
    }
    assert!(
        without_timing(&report).contains("\"pairs_integrated\""),
        "{report}"
    );
    // Merged in stages
    let stage = temp("stage.sir");
    stdout_of(&["merge", s(&parts[1]), s(&parts[2]), "--partial", s(&stage)]);
    let staged = temp("staged.ijv");
    stdout_of(&["merge", s(&stage), s(&parts[0]), "--out", s(&staged)]);
    assert_eq!(ijv, std::fs::read_to_string(&staged).unwrap());
}

/// Row ranges that overlap, leave a gap or come from another tolerance are refused with
/// exit 2 and a message that says so; so are rows past the scene and line-job flags.
#[test]
fn bad_row_ranges_are_refused() {
    let scene = room_vs3();
    let part = |rows: &str, tol: &str, name: &str| {
        let p = temp(name);
        stdout_of(&[
            "formfactors",
            s(&scene),
            "--tol",
            tol,
            "--rows",
            rows,
            "--partial",
            s(&p),
        ]);
        p
    };
    let (a, b, c) = (
        part("0..3", "1e-3", "a.sir"),
        part("2..5", "1e-3", "b.sir"),
        part("3..5", "1e-2", "c.sir"),
    );
    let d = part("4..5", "1e-3", "d.sir");
    let refused = |args: &[&str], says: &str| {
        let out = bin().args(args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
    };
    refused(
        &["merge", s(&a), s(&b)],
        "partial results overlap: rows 0..3 and 2..5",
    );
    refused(&["merge", s(&a), s(&c)], "their tolerance differs");
    refused(
        &["merge", s(&a), s(&d)],
        "rows 3..4 are in no partial result",
    );
    refused(
        &["merge", s(&a)],
        "compute the rest (formfactors --rows A..B --partial)",
    );
    refused(
        &[
            "formfactors",
            s(&scene),
            "--rows",
            "0..99",
            "--partial",
            s(&temp("x.sir")),
        ],
        "has rows 0..",
    );
    refused(
        &[
            "formfactors",
            s(&scene),
            "--lines",
            "1000",
            "--partial",
            s(&temp("y.sir")),
        ],
        "holds exact rows",
    );
    refused(
        &["formfactors", s(&scene), "--out", s(&temp("f.bad"))],
        ".csv, .txt, .ijv or .vf3",
    );
    let flat = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/room620.flat");
    refused(
        &["formfactors", s(&flat), "--out", s(&temp("f.vf3"))],
        "View3D's format (.vf3)",
    );
    let _ = succeeded;
}

/// The `i,j,F_ij,err` entries of a `.ijv` file (`err` 0 where it is empty).
fn entries(path: &Path) -> Vec<(usize, usize, f64, f64)> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                f[0].parse().unwrap(),
                f[1].parse().unwrap(),
                f[2].parse().unwrap(),
                // The background's entries carry no estimate (an empty field)
                if f[3].is_empty() {
                    0.0
                } else {
                    f[3].parse().unwrap()
                },
            )
        })
        .collect()
}

/// `scene convert` writes View3D's input back: a `.vs3` written by View3D's own converter
/// (combined pieces included), converted by sceneinfo to `.vs3` (its records and controls
/// kept, `--eps` applied) and to OBJ, gives the same form factors and estimates (to
/// rounding: a combined surface's corners may come back starting at another corner); a 3D
/// scene is not written as `.flat`.
#[test]
fn a_scene_converted_to_vs3_keeps_its_form_factors() {
    let scene = room_vs3();
    let (vs3, obj) = (temp("converted.vs3"), temp("converted.obj"));
    for out in [&vs3, &obj] {
        succeeded(
            bin()
                .args(["scene", "convert", s(&scene), "-o", s(out), "--eps", "1e-6"])
                .output()
                .unwrap(),
        );
    }
    let text = std::fs::read_to_string(&vs3).unwrap();
    assert!(
        text.contains("\nC encl=0 emit=0 out=0 list=0 eps=1e-6 maxU=12 maxO=8 minO=0\n"),
        "{text}"
    );
    let mut results = Vec::new();
    for (k, input) in [&scene, &vs3, &obj].into_iter().enumerate() {
        let out = temp(&format!("converted{k}.ijv"));
        stdout_of(&["formfactors", s(input), "--tol", "1e-3", "--out", s(&out)]);
        results.push(entries(&out));
    }
    for other in &results[1..] {
        assert_eq!(other.len(), results[0].len());
        for (a, b) in results[0].iter().zip(other) {
            assert_eq!((a.0, a.1), (b.0, b.1));
            assert!((a.2 - b.2).abs() <= 1e-12, "{a:?} against {b:?}");
            assert!((a.3 - b.3).abs() <= 1e-12, "{a:?} against {b:?}");
        }
    }
    let out = bin()
        .args(["scene", "convert", s(&scene), "-o", s(&temp("x.flat"))])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("not .flat"), "{err}");
}
