//! Too few lines is an answer, not an error: line jobs that leave some patch without a
//! line report `I_S^c` with its standard error and the discrete measures as undefined;
//! `--lines auto` doubles the lines until every patch is reached. Through the real binary.

mod common;

use std::path::PathBuf;
use std::process::Output;

use common::{bin, number, preset, temp, without_timing};

/// A closed unit room (six inward-facing walls) with a square tile of side `side` just
/// above the floor, facing up: the tile is crossed by a global line with probability
/// `side² / (2π R²)`, `R² = 3/4` (Crofton), 2.1e-5 for `side = 0.01`.
fn room_with_tile(name: &str, side: f64) -> PathBuf {
    let (a, b) = (0.5, 0.5 + side);
    let obj = format!(
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
         v {a} {a} 0.001\nv {b} {a} 0.001\nv {b} {b} 0.001\nv {a} {b} 0.001\n\
         f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nf 4 8 5 1\nf 9 10 11 12\n"
    );
    let path = temp(name);
    std::fs::write(&path, obj).unwrap();
    path
}

fn run(args: &[&str], file: &PathBuf) -> Output {
    bin()
        .arg(args[0])
        .arg(file)
        .args(&args[1..])
        .output()
        .unwrap()
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// The JSON of a successful run, without its timing and `--lines auto` keys.
fn comparable(out: &Output) -> String {
    assert!(out.status.success(), "{}", text(&out.stderr));
    without_timing(&text(&out.stdout))
        .split(',')
        .filter(|kv| {
            // faces_read: the loader's, which a merge (reading no scene) does not write
            !kv.contains("\"lines_auto\"")
                && !kv.contains("\"faces_read\"")
                && !kv.contains("\"lines_budget\"")
                && !kv.contains("\"max_lines\"")
        })
        .collect::<Vec<_>>()
        .join(",")
}

/// 1000 global lines miss the 1e-4-area tile (expected hits 0.02): exit 0, a finite
/// `I_S^c` and standard error, every discrete measure `null`, the coverage keys and the
/// warning (JSON and stderr) with the suggested count: `ln(10)/p ≈ 108,500` lines rounded
/// up to whole chunks, 131,072. The table says "undefined"; no matrix is written.
#[test]
fn measure_with_too_few_lines_reports_i_s_c_and_undefined_discrete_measures() {
    let room = room_with_tile("few-lines-room.obj", 0.01);
    let out = run(&["measure", "--lines", "1000", "--json"], &room);
    let (json, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(out.status.success(), "{stderr}");
    let (ic, se) = (
        number(&json, "i_s_continuous"),
        number(&json, "i_s_continuous_stderr"),
    );
    assert!(
        ic.is_finite() && ic > 1.0 && se.is_finite() && se > 0.0,
        "{json}"
    );
    for key in [
        "h_p", "h_s", "h_j", "i_s", "e_mse", "fano", "n_states", "checks",
    ] {
        assert!(json.contains(&format!("\"{key}\":null")), "{key}: {json}");
    }
    assert!(json.contains("\"rel_discretisation_error\":null"), "{json}");
    assert_eq!(number(&json, "unsampled_patches"), 1.0);
    assert_eq!(number(&json, "lines_to_sample_all"), 131_072.0);
    assert_eq!(number(&json, "lines"), 1000.0);
    assert!(
        json.contains("\"warnings\":[\"1 of the 7 patches received none of the 1000 lines"),
        "{json}"
    );
    assert!(
        stderr.contains("warning")
            && stderr.contains("1 of the 7 patches")
            && stderr.contains("--lines 131072, or --lines auto"),
        "{stderr}"
    );
    // The table, and no matrix
    let matrix = temp("few-lines-f.csv");
    let out = bin()
        .args(["measure", "--lines", "1000", "--matrix"])
        .arg(&matrix)
        .arg(&room)
        .output()
        .unwrap();
    let table = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(table.contains("I_S   (3.8)           undefined"), "{table}");
    assert!(table.contains("I_S^c (4.8, 4.13)     1."), "{table}");
    assert!(table.contains("1 of 7 received no line"), "{table}");
    assert!(!matrix.exists());
    assert!(text(&out.stderr).contains("not written"));
}

/// Flatland too: a square of 4000 patches and 100 lines.
#[test]
fn flatland_with_too_few_lines_reports_the_missed_patches() {
    let square = preset(
        &["polygon", "--sides", "4", "--per-side", "1000"],
        "few-sq.flat",
    );
    let out = run(&["measure", "--lines", "100", "--json"], &square);
    let json = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let missed = number(&json, "unsampled_patches");
    assert!((3000.0..4000.0).contains(&missed), "{json}");
    assert!(number(&json, "i_s_continuous").is_finite());
    assert!(json.contains("\"i_s\":null"));
}

/// `--lines auto` doubles 131,072 → 262,144 on a 2.5e-5-area tile with seed 2 (seed 1
/// reaches it at once): every patch reached, the lines used reported, and the result is
/// that of one run of `--lines 262144`, the same bytes on 1 and 2 threads.
#[test]
fn lines_auto_doubles_until_every_patch_is_reached() {
    let room = room_with_tile("few-lines-auto.obj", 0.005);
    let auto = |threads: &str| {
        run(
            &[
                "measure",
                "--lines",
                "auto",
                "--seed",
                "2",
                "--json",
                "--threads",
                threads,
            ],
            &room,
        )
    };
    let one = auto("1");
    let json = text(&one.stdout);
    assert!(one.status.success(), "{}", text(&one.stderr));
    assert_eq!(number(&json, "lines"), 262_144.0, "{json}");
    assert!(number(&json, "i_s").is_finite(), "{json}");
    assert!(
        json.contains("\"lines_auto\":true,\"lines_budget\":262144,\"max_lines\":1073741824"),
        "{json}"
    );
    assert!(!json.contains("unsampled_patches"), "{json}");
    let fixed = run(
        &[
            "measure",
            "--lines",
            "262144",
            "--seed",
            "2",
            "--json",
            "--threads",
            "2",
        ],
        &room,
    );
    assert_eq!(comparable(&one), comparable(&fixed));
    assert_eq!(comparable(&one), comparable(&auto("2")));
    // 3D bundles cast about their budget: `lines_budget` is the `--lines` of the same run
    let bundles = |lines: &str| {
        let args = [
            "measure", "--lines", lines, "--method", "bundle", "--seed", "3", "--json",
        ];
        run(&args, &room)
    };
    let auto = bundles("auto");
    let budget = number(&text(&auto.stdout), "lines_budget");
    assert_eq!(budget, 262_144.0, "{}", text(&auto.stdout));
    assert_eq!(comparable(&auto), comparable(&bundles("262144")));
    // The table says how the count was reached
    let table = text(&run(&["measure", "--lines", "auto", "--seed", "2"], &room).stdout);
    assert!(
        table.contains(
            "--lines auto          doubled from 131072 to 262144 lines (every patch reached)"
        ),
        "{table}"
    );
}

/// A cap below what the 1e-6-area tile needs: auto stops at `--max-lines`, reports like
/// too few lines (exit 0, `null` measures, the suggestion: about 10⁷ lines), and says so.
#[test]
fn lines_auto_stops_at_max_lines() {
    let room = room_with_tile("few-lines-cap.obj", 0.001);
    let out = run(
        &[
            "measure",
            "--lines",
            "auto",
            "--max-lines",
            "262144",
            "--json",
        ],
        &room,
    );
    let json = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(number(&json, "lines"), 262_144.0);
    assert!(json.contains("\"i_s\":null"), "{json}");
    let m = number(&json, "lines_to_sample_all");
    assert!((5e6..2e7).contains(&m), "{json}");
    let table = text(
        &run(
            &["measure", "--lines", "auto", "--max-lines", "262144"],
            &room,
        )
        .stdout,
    );
    assert!(table.contains("(stopped at --max-lines 262144)"), "{table}");
    // --max-lines only bounds auto
    let out = run(
        &["measure", "--lines", "1000", "--max-lines", "5000"],
        &room,
    );
    assert_eq!(out.status.code(), Some(2));
}

/// `formfactors` and `radiosity` need every row of F: with too few lines they refuse
/// (exit 2) with the count of missed patches and the suggested lines, and write nothing;
/// with `--lines auto` they run on the count that reaches every patch.
#[test]
fn formfactors_and_radiosity_refuse_unknown_rows_and_run_with_auto() {
    let room = room_with_tile("few-lines-ff.obj", 0.01);
    let csv = temp("few-lines-ff.csv");
    let out = bin()
        .args(["formfactors", "--lines", "1000", "--out"])
        .arg(&csv)
        .arg(&room)
        .output()
        .unwrap();
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("1 of the 7 patches received none of the 1000 lines")
            && stderr.contains("no matrix written")
            && stderr.contains("--lines 131072, or --lines auto"),
        "{stderr}"
    );
    assert!(!csv.exists());
    let out = run(&["radiosity", "--lines", "1000"], &room);
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("B = E + ρFB cannot be solved"), "{stderr}");
    let out = run(&["radiosity", "--lines", "auto", "--json"], &room);
    let json = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(number(&json, "lines"), 131_072.0, "{json}");
    assert!(json.contains("\"lines_auto\":true"), "{json}");
    let out = bin()
        .args(["formfactors", "--lines", "auto", "--out"])
        .arg(&csv)
        .arg(&room)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert_eq!(std::fs::read_to_string(&csv).unwrap().lines().count(), 8);
}

/// Ctrl-C (SIGINT) during `--lines auto` on a 1e-10-area tile no budget reaches: exit 130,
/// the report marked partial with `null` discrete measures, and the numbers of one
/// complete run of the lines cast (a whole number of chunks).
#[cfg(unix)]
#[test]
fn ctrl_c_during_lines_auto_reports_the_lines_cast() {
    let room = room_with_tile("few-lines-ctrl-c.obj", 1e-5);
    // Interrupt after a wait; lengthen it if no chunk was done yet (a busy machine)
    let mut waited = None;
    for secs in [2u64, 5, 12] {
        let child = bin()
            .arg("measure")
            .arg(&room)
            .args(["--lines", "auto", "--threads", "2", "--json"])
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_secs(secs));
        let st = std::process::Command::new("kill")
            .args(["-INT", &child.id().to_string()])
            .status()
            .unwrap();
        assert!(st.success());
        let out = child.wait_with_output().unwrap();
        assert_eq!(out.status.code(), Some(130), "{}", text(&out.stderr));
        if !out.stdout.is_empty() {
            waited = Some(out);
            break;
        }
    }
    let out = waited.expect("no chunk finished in 12 s");
    let json = text(&out.stdout);
    assert!(json.contains("\"partial\":true"), "{json}");
    assert!(json.contains("\"i_s\":null"), "{json}");
    let lines = number(&json, "lines");
    assert!(lines > 0.0 && lines % 65536.0 == 0.0, "{json}");
    assert!(number(&json, "lines_requested") > lines, "{json}");
    let drop_partial = |j: &str| {
        j.split(',')
            .filter(|kv| !kv.contains("\"partial\"") && !kv.contains("\"lines_requested\""))
            .collect::<Vec<_>>()
            .join(",")
    };
    let full = run(
        &[
            "measure",
            "--lines",
            &lines.to_string(),
            "--threads",
            "1",
            "--json",
        ],
        &room,
    );
    let partial = Output {
        status: full.status,
        stdout: out.stdout.clone(),
        stderr: Vec::new(),
    };
    assert_eq!(drop_partial(&comparable(&partial)), comparable(&full));
}

/// A whole job's partials merged: when the job missed a patch, `merge` reports like
/// `measure` (exit 0, `null` measures, the warning), the same bytes as the one run.
#[test]
fn merge_of_a_job_that_missed_a_patch_reports_like_measure() {
    let room = room_with_tile("few-lines-merge.obj", 0.01);
    let lines = "131072";
    let mut parts = Vec::new();
    for (k, chunks) in ["0..1", "1..2"].iter().enumerate() {
        let part = temp(&format!("few-lines-part{k}.sip"));
        let out = bin()
            .args([
                "measure", "--lines", lines, "--seed", "5", "--chunks", chunks,
            ])
            .arg("--partial")
            .arg(&part)
            .arg(&room)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", text(&out.stderr));
        parts.push(part);
    }
    let merged = bin()
        .arg("merge")
        .args(&parts)
        .arg("--json")
        .output()
        .unwrap();
    let one = run(
        &["measure", "--lines", lines, "--seed", "5", "--json"],
        &room,
    );
    let json = text(&one.stdout);
    // Seed 5 misses the tile with 131072 lines (expected hits 2.8: seeds 5 and 8 of 1 to 12)
    assert!(json.contains("\"i_s\":null"), "{json}");
    assert!(text(&merged.stderr).contains("1 of the 7 patches"));
    assert_eq!(comparable(&merged), comparable(&one));
}
