//! Robustness of the real binary (issue 8): bit-identical results across runs and thread
//! counts, Ctrl-C during a long line job, resource caps.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use common::{bin, without_timing};

/// A fresh directory for one test.
fn temp_dir(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "sceneinfo-robustness-{test}-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A flatland room with a two-sided wall and a box: occlusion, 34 patches.
const ROOM: &str = "poly 4 0 0 4 0 4 3 0 3 per_side 6\n\
                    seg 2 0.5 2 2.5 3\nseg 2 2.5 2 0.5 3\n\
                    poly 4 3 1 3 2 3.5 2 3.5 1 per_side 1\n";

/// Writes the flatland room and the Cornell box into `dir`.
fn scenes(dir: &Path) -> [PathBuf; 2] {
    let flat = dir.join("room.flat");
    std::fs::write(&flat, ROOM).unwrap();
    let obj = dir.join("cornell.obj");
    let st = bin()
        .args(["scene", "solid", "cornell", "-o"])
        .arg(&obj)
        .status()
        .unwrap();
    assert!(st.success());
    [flat, obj]
}

fn run(args: &[&str], file: &Path) -> Output {
    bin().arg("measure").arg(file).args(args).output().unwrap()
}

/// Same input, seed and line budget: the same JSON text (timing keys aside) and the same
/// matrix file, byte for byte, on repeated runs and on 1 and 2 threads, for flatland and
/// 3D scenes and for global and local lines and bundles of parallel lines; exact measures
/// are repeatable too (`radiosity` by bundles: `tests/radiosity.rs`).
#[test]
fn results_are_bit_identical_across_runs_and_threads() {
    let dir = temp_dir("determinism");
    for scene in scenes(&dir) {
        for method in ["global", "local", "bundle"] {
            let mut results = Vec::new();
            for (k, threads) in ["1", "2", "2"].into_iter().enumerate() {
                let matrix = dir.join(format!("F{k}.csv"));
                let out = run(
                    &[
                        "--lines",
                        "200000",
                        "--seed",
                        "11",
                        "--method",
                        method,
                        "--threads",
                        threads,
                        "--json",
                        "--matrix",
                        matrix.to_str().unwrap(),
                    ],
                    &scene,
                );
                assert!(
                    out.status.success(),
                    "{}",
                    String::from_utf8_lossy(&out.stderr)
                );
                let json = without_timing(&String::from_utf8(out.stdout).unwrap());
                results.push((json, std::fs::read(&matrix).unwrap()));
            }
            assert!(
                results[0].0.contains("\"i_s_continuous\":"),
                "{}",
                results[0].0
            );
            for other in &results[1..] {
                assert_eq!(&results[0], other, "{} {method}", scene.display());
            }
        }
    }
    let exact = |_| {
        without_timing(&String::from_utf8(run(&["--json"], &dir.join("room.flat")).stdout).unwrap())
    };
    assert_eq!(exact(0), exact(1));
}

/// Ctrl-C (SIGINT) during `measure --lines 1e12`: the job stops at a chunk boundary,
/// prints its report marked `"partial": true` with the lines it cast (a whole number of
/// 2^16-line chunks), writes a complete `--matrix` file (and no stray temporary file),
/// and exits with 130. Its numbers are those of a complete run of that many lines.
#[cfg(unix)]
#[test]
fn ctrl_c_reports_a_partial_result_equal_to_the_shorter_run() {
    let dir = temp_dir("ctrl-c");
    let [scene, _] = scenes(&dir);
    let matrix = dir.join("F.csv");

    // Interrupt after a wait; lengthen it if no chunk was done yet (a busy machine)
    let mut waited = None;
    for secs in [2u64, 5, 12] {
        let child = bin()
            .arg("measure")
            .arg(&scene)
            .args([
                "--lines",
                "1e12",
                "--seed",
                "5",
                "--threads",
                "2",
                "--json",
                "--matrix",
            ])
            .arg(&matrix)
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_secs(secs));
        let st = Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status()
            .unwrap();
        assert!(st.success());
        let out = child.wait_with_output().unwrap();
        assert_eq!(
            out.status.code(),
            Some(130),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        if !out.stdout.is_empty() {
            waited = Some(out);
            break;
        }
        assert_eq!(
            String::from_utf8_lossy(&out.stderr),
            "sceneinfo: interrupted before the results were complete: nothing written\n"
        );
    }
    let out = waited.expect("no chunk finished in 12 s");

    // The partial report
    let json = String::from_utf8(out.stdout).unwrap();
    assert!(json.contains("\"partial\":true"), "{json}");
    assert!(json.contains("\"lines_requested\":1000000000000"), "{json}");
    let lines: u64 = json
        .split("\"lines\":")
        .nth(1)
        .and_then(|rest| rest.split([',', '}']).next())
        .and_then(|v| v.parse().ok())
        .expect("a lines key");
    assert!(
        lines > 0 && lines < 1_000_000_000_000 && lines.is_multiple_of(65536),
        "{lines}"
    );
    assert_eq!(
        String::from_utf8(out.stderr).unwrap(),
        format!(
            "sceneinfo: interrupted: the report covers {lines} of the 1000000000000 lines \
             asked for (marked partial; --lines {lines} gives the same numbers)\n"
        )
    );

    // A whole matrix file, nothing else left behind
    let csv = std::fs::read_to_string(&matrix).unwrap();
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows.len(), 34, "{csv}");
    assert!(rows.iter().all(|r| r.split(',').count() == 34));
    let stray: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(stray.is_empty(), "{stray:?}");

    // The same numbers as a complete run of that many lines (on one thread)
    let full = run(
        &[
            "--lines",
            &lines.to_string(),
            "--seed",
            "5",
            "--threads",
            "1",
            "--json",
        ],
        &scene,
    );
    assert!(full.status.success());
    let partial_keys = |json: &str| {
        without_timing(json)
            .split(',')
            .filter(|kv| !kv.contains("\"partial\"") && !kv.contains("\"lines_requested\""))
            .collect::<Vec<_>>()
            .join(",")
    };
    assert_eq!(
        partial_keys(&json),
        partial_keys(&String::from_utf8(full.stdout).unwrap())
    );
}
