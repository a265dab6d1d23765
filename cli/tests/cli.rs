//! The real `sceneinfo` binary, run as a user would.

use std::path::PathBuf;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_sceneinfo"))
}

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sceneinfo-cli-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Drops the keys whose values are wall-clock times from a flat JSON object.
fn without_timing(json: &str) -> String {
    json.split(',')
        .filter(|kv| !kv.contains("\"seconds\"") && !kv.contains("\"lines_per_second\""))
        .collect::<Vec<_>>()
        .join(",")
}

#[test]
fn scene_then_measure_reproduces_table_3_4_first_cell() {
    let path = temp("triangle.flat");
    let st = bin()
        .args(["scene", "polygon", "--sides", "3", "--per-side", "10", "-o"])
        .arg(&path)
        .status()
        .unwrap();
    assert!(st.success());
    let out = bin()
        .arg("measure")
        .arg(&path)
        .arg("--json")
        .output()
        .unwrap();
    assert!(out.status.success());
    let json = String::from_utf8(out.stdout).unwrap();
    for key in [
        "n_patches",
        "h_p",
        "h_s",
        "h_j",
        "i_s",
        "h_s_norm",
        "i_s_norm",
        "e_mse",
        "fano",
    ] {
        assert!(
            json.contains(&format!("\"{key}\":")),
            "missing {key} in {json}"
        );
    }
    assert!(json.contains("\"n_patches\":30"));
    assert!(json.contains("\"h_s\":3.739"), "{json}");
}

#[test]
fn errors_name_file_and_line_and_exit_2() {
    let path = temp("bad.flat");
    std::fs::write(&path, "seg 0 0 1 0\nseg 1 1 1 1\n").unwrap();
    let out = bin().arg("measure").arg(&path).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains(&format!("{}:2: segment has zero length", path.display())),
        "{err}"
    );
}

#[test]
fn zero_lines_is_an_error() {
    let path = temp("square.flat");
    let st = bin()
        .args(["scene", "rect", "-o"])
        .arg(&path)
        .status()
        .unwrap();
    assert!(st.success());
    let out = bin()
        .arg("measure")
        .arg(&path)
        .args(["--lines", "0"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8(out.stderr)
            .unwrap()
            .contains("line budget must be at least 1")
    );
}

/// Same seed and line count: bit-identical JSON (timing keys aside) on 1 and 2 threads.
#[test]
fn monte_carlo_is_identical_on_one_and_two_threads() {
    let path = temp("room.flat");
    std::fs::write(
        &path,
        "poly 4 0 0 4 0 4 3 0 3 per_side 6\npoly 4 1 1 1 2 2 2 2 1 per_side 2\n",
    )
    .unwrap();
    let run = |threads: &str| {
        let out = bin()
            .arg("measure")
            .arg(&path)
            .args([
                "--lines",
                "300000",
                "--seed",
                "9",
                "--json",
                "--threads",
                threads,
            ])
            .output()
            .unwrap();
        assert!(out.status.success());
        without_timing(&String::from_utf8(out.stdout).unwrap())
    };
    let one = run("1");
    assert!(one.contains("\"i_s_continuous\":"));
    assert_eq!(one, run("2"));
}
