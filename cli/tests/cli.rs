//! The real `sceneinfo` binary, run as a user would.

mod common;

use std::path::PathBuf;

use common::{bin, number as json_number, preset, stdout_of, temp, without_timing};

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
fn bench_split_casts_the_same_lines_alone_and_with_the_tally() {
    // A 3D scene file: global lines and bundles, 1 and 2 threads, each job with its tally
    // and cast alone; both find the same hits (the tally's samples)
    let obj = preset(&["cube", "--grid", "4"], "split_cube.obj");
    let obj = obj.to_str().unwrap();
    // `bench --split --scene obj --lines L --threads T --reps 1 --json`, and `extra`
    let split = |lines: &str, threads: &str, extra: &[&str]| {
        let mut args = vec![
            "bench",
            "--split",
            "--scene",
            obj,
            "--lines",
            lines,
            "--threads",
            threads,
            "--reps",
            "1",
            "--json",
        ];
        args.extend_from_slice(extra);
        stdout_of(&args)
    };
    let json = split("20000", "2", &[]);
    for method in ["global", "bundle"] {
        for t in [1, 2] {
            assert!(
                json.contains(&format!("split_cube.obj {method} {t}t\":{{")),
                "{method} {t}t: {json}"
            );
        }
    }
    assert_eq!(json.matches("\"same_hits\":true").count(), 4, "{json}");
    // A cube meets a global line 2 · 6/(3π) ≈ 1.27 times on average (Crofton)
    let hits = json_number(&json, "hits_per_line_alone");
    assert!((1.0..2.0).contains(&hits), "{hits}");
    assert_eq!(hits, json_number(&json, "hits_per_line_full"));
    for key in ["full_lines_per_second", "alone_lines_per_second"] {
        let v = json_number(&json, key);
        assert!(v > 0.0 && v.is_finite(), "{key} = {v}");
    }
    // One method only
    let json = split("5000", "1", &["--method", "bundle"]);
    assert!(!json.contains(" global "), "{json}");
    assert_eq!(json.matches("\"same_hits\":true").count(), 1, "{json}");
    // Flatland is refused with the file named
    let flat = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/room620.flat");
    let out = bin()
        .args(["bench", "--split", "--scene"])
        .arg(&flat)
        .args(["--lines", "1000"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("room620.flat") && err.contains("3D"), "{err}");
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

/// The standard error says how many independent observations it rests on, and the text
/// report warns when they are few: a bundle job of 10⁵ lines is one full sheaf (a chunk of
/// 65,536 lines), a sheaf of the last chunk's 134 whole bundles of 256 lines and one single
/// bundle of the 160 left (3 groups); 2,000 global lines on a closed room are 2,000.
#[test]
fn the_standard_error_reports_its_groups_and_warns_when_few() {
    let path = temp("groups.flat");
    std::fs::write(&path, "poly 4 0 0 4 0 4 3 0 3 per_side 4\n").unwrap();
    let measure = |method: &str, lines: &str, json: bool| {
        let mut cmd = bin();
        cmd.arg("measure")
            .arg(&path)
            .args(["--lines", lines, "--method", method]);
        if json {
            cmd.arg("--json");
        }
        let out = cmd.output().unwrap();
        assert!(out.status.success());
        String::from_utf8(out.stdout).unwrap()
    };
    let bundles = measure("bundle", "100000", true);
    assert_eq!(json_number(&bundles, "stderr_groups"), 3.0, "{bundles}");
    let text = measure("bundle", "100000", false);
    assert!(text.contains("from 3 independent groups"), "{text}");
    assert!(text.contains("rests on 3 observations only"), "{text}");
    let global = measure("global", "2000", true);
    assert_eq!(json_number(&global, "stderr_groups"), 2000.0, "{global}");
    let text = measure("global", "2000", false);
    assert!(text.contains("from 2000 independent groups"), "{text}");
    assert!(!text.contains("observations only"), "{text}");
}

/// `draw FILE.obj --ply`: a coloured PLY mesh, one face per patch; .flat still needs --svg.
#[test]
fn draw_obj_writes_a_ply_of_one_face_per_patch() {
    let obj = temp("cube.obj");
    let st = bin()
        .args(["scene", "cube", "--grid", "3", "-o"])
        .arg(&obj)
        .status()
        .unwrap();
    assert!(st.success());
    let ply = temp("cube.ply");
    let faces_of = |extra: &[&str]| {
        let out = bin()
            .arg("draw")
            .arg(&obj)
            .arg("--ply")
            .arg(&ply)
            .args(extra)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{stderr}");
        let stdout = String::from_utf8(out.stdout).unwrap();
        assert!(stdout.contains("54 patches"), "{stdout}");
        let text = std::fs::read_to_string(&ply).unwrap();
        let (header, body) = text.split_once("end_header\n").unwrap();
        let count = |element: &str| -> usize {
            header
                .lines()
                .find_map(|l| l.strip_prefix(&format!("element {element} ")))
                .unwrap()
                .parse()
                .unwrap()
        };
        let (nv, nf) = (count("vertex"), count("face"));
        let lines: Vec<&str> = body.lines().collect();
        assert_eq!(lines.len(), nv + nf);
        for face in &lines[nv..] {
            let nums: Vec<usize> = face.split(' ').map(|w| w.parse().unwrap()).collect();
            assert_eq!(nums.len(), 1 + nums[0] + 3, "{face}");
            assert!(nums[1..=nums[0]].iter().all(|&k| k < nv), "{face}");
        }
        (nf, header.to_owned())
    };
    let (nf, header) = faces_of(&[]);
    assert_eq!(nf, 54);
    assert!(header.contains("form factors: exact"), "{header}");
    let (nf, header) = faces_of(&["--color", "ic", "--lines", "200000", "--per-area"]);
    assert_eq!(nf, 54);
    assert!(header.contains("200000 global lines"), "{header}");

    let out = bin().arg("draw").arg(&obj).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--ply OUT.ply"));
    let flat = temp("draw-square.flat");
    let st = bin()
        .args(["scene", "rect", "-o"])
        .arg(&flat)
        .status()
        .unwrap();
    assert!(st.success());
    let out = bin().arg("draw").arg(&flat).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--svg OUT.svg"));
}

/// `measure --chunks A..B --partial` on 4 ranges, then `merge`: the JSON and the
/// form-factor CSV of one whole run, bit for bit (flatland and 3D, global and local lines);
/// partials of another job, a gap and a damaged file are refused with exit 2.
/// `json` without its `"faces_read":N` key (written for 3D scenes by the loader).
fn without_faces_read(json: &str) -> String {
    json.split(',')
        .filter(|kv| !kv.starts_with("\"faces_read\":"))
        .collect::<Vec<_>>()
        .join(",")
}

#[test]
fn four_partials_merged_equal_one_run_bit_for_bit() {
    let flat = temp("merge-room.flat");
    std::fs::write(
        &flat,
        "poly 4 0 0 4 0 4 3 0 3 per_side 6\npoly 4 1 1 1 2 2 2 2 1 per_side 2\n",
    )
    .unwrap();
    let obj = temp("merge-cube.obj");
    assert!(
        bin()
            .args(["scene", "cube", "--grid", "2", "-o"])
            .arg(&obj)
            .status()
            .unwrap()
            .success()
    );
    // 7 chunks: the last one is short.
    let lines = (6 * 65536 + 1234).to_string();
    for (scene, method) in [
        (&flat, "global"),
        (&flat, "bundle"),
        (&obj, "local"),
        (&obj, "global"),
        (&obj, "bundle"),
    ] {
        let common = ["--lines", &lines, "--seed", "5", "--method", method];
        let kind = scene.extension().unwrap().to_str().unwrap();
        let whole_csv = temp(&format!("whole-{method}-{kind}.csv"));
        let whole = bin()
            .arg("measure")
            .arg(scene)
            .args(common)
            .args(["--json", "--threads", "2", "--matrix"])
            .arg(&whole_csv)
            .output()
            .unwrap();
        assert!(whole.status.success());
        let mut parts = Vec::new();
        for (k, range) in ["4..7", "0..1", "1..3", "3..4"].iter().enumerate() {
            let part = temp(&format!("part{k}-{method}-{kind}.sip"));
            let st = bin()
                .arg("measure")
                .arg(scene)
                .args(common)
                .args(["--threads", "1", "--chunks", range, "--partial"])
                .arg(&part)
                .status()
                .unwrap();
            assert!(st.success());
            parts.push(part);
        }
        let merged_csv = temp(&format!("merged-{method}-{kind}.csv"));
        let merged = bin()
            .arg("merge")
            .args(&parts)
            .args(["--json", "--matrix"])
            .arg(&merged_csv)
            .output()
            .unwrap();
        assert!(merged.status.success(), "{merged:?}");
        // The loader's `faces_read` is the one key a merge (which reads no scene) lacks
        let (w, m) = (
            without_faces_read(&without_timing(&String::from_utf8(whole.stdout).unwrap())),
            without_timing(&String::from_utf8(merged.stdout).unwrap()),
        );
        assert!(w.contains("\"i_s_continuous\":"));
        assert_eq!(w, m);
        assert_eq!(
            std::fs::read(&whole_csv).unwrap(),
            std::fs::read(&merged_csv).unwrap()
        );
    }
    // Another seed, a missing range, a damaged file: clear errors, exit 2.
    let other = temp("other-seed.sip");
    assert!(
        bin()
            .arg("measure")
            .arg(&obj)
            .args(["--lines", &lines, "--seed", "6", "--chunks", "0..1"])
            .arg("--partial")
            .arg(&other)
            .status()
            .unwrap()
            .success()
    );
    let part = |k: usize| temp(&format!("part{k}-global-obj.sip"));
    let fail = |files: Vec<PathBuf>, expect: &str| {
        let out = bin().arg("merge").args(&files).output().unwrap();
        assert_eq!(out.status.code(), Some(2));
        let err = String::from_utf8(out.stderr).unwrap();
        assert!(err.contains(expect), "{err}");
    };
    fail(vec![other.clone(), part(2)], "their seed differs");
    fail(
        vec![part(1), part(3), part(0)],
        "chunks 1..3 are in no partial",
    );
    fail(
        vec![part(1), part(2)],
        "cover chunks 0..3 of the job's 0..7",
    );
    let damaged = temp("damaged.sip");
    let mut bytes = std::fs::read(part(2)).unwrap();
    let mid = bytes.len() / 2;
    bytes[mid] ^= 0x10;
    std::fs::write(&damaged, bytes).unwrap();
    fail(vec![damaged], "checksum mismatch");
}

#[test]
fn refine_flat_reports_its_keys_draws_and_writes_the_mesh() {
    let scene = preset(&["catalogue", "refinement-1"], "refine-room.flat");
    let (svg, mesh) = (temp("refine.svg"), temp("refined.flat"));
    let run = |threads: &str| {
        bin()
            .arg("refine")
            .arg(&scene)
            .args(["--oracle", "de", "--target", "40", "--lines", "100000"])
            .args(["--json", "--threads", threads, "--svg"])
            .arg(&svg)
            .arg("-o")
            .arg(&mesh)
            .output()
            .unwrap()
    };
    let out = run("1");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json = String::from_utf8(out.stdout).unwrap();
    for key in [
        "n_patches",
        "i_s",
        "h_s",
        "h_j",
        "i_s_continuous",
        "rel_discretisation_error",
        "history",
    ] {
        assert!(
            json.contains(&format!("\"{key}\":")),
            "missing {key} in {json}"
        );
    }
    assert!(json.contains("\"n_patches\":40"), "{json}");
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
    let text = std::fs::read_to_string(&mesh).unwrap();
    assert_eq!(sceneinfo::io::parse_flat(&text).unwrap().n_patches(), 40);
    let two = run("2");
    assert_eq!(
        without_timing(&json),
        without_timing(&String::from_utf8(two.stdout).unwrap())
    );
}

#[test]
fn refine_rejects_mismatched_oracles_and_obj_scenes_clearly() {
    let scene = temp("refine-square.flat");
    std::fs::write(&scene, "poly 4 0 0 1 0 1 1 0 1 per_side 2\n").unwrap();
    let out = bin()
        .arg("refine")
        .arg(&scene)
        .args(["--oracle", "mi"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("a .flat scene takes de, power or regular"),
        "{err}"
    );
    let obj = temp("refine-tri.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let out = bin()
        .arg("refine")
        .arg(&obj)
        .args(["--oracle", "de"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--oracle de refines flatland scenes"), "{err}");
}

#[test]
fn refine_obj_runs_hierarchical_radiosity_draws_and_compares() {
    let obj = preset(&["solid", "cornell"], "hr-cornell.obj");
    let (ply, png) = (temp("hr-mi.ply"), temp("hr-mi.png"));
    // Thresholds rather than --target keep the debug binary quick: mi at 1.5e-4 gives about
    // 150 leaves, power at 1e4 about 40.
    let run = |oracle: &str, eps: &str, threads: &str, extra: &[&std::ffi::OsStr]| {
        let out = bin()
            .arg("refine")
            .arg(&obj)
            .args(["--oracle", oracle, "--eps", eps, "--lines", "30000"])
            .args(["--threads", threads, "--json"])
            .args(extra)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{stderr}");
        String::from_utf8(out.stdout).unwrap()
    };
    let mi = run(
        "mi",
        "1.5e-4",
        "2",
        &[
            "--ply".as_ref(),
            ply.as_os_str(),
            "--png".as_ref(),
            png.as_os_str(),
        ],
    );
    for key in [
        "n_patches",
        "i_s",
        "h_s",
        "h_j",
        "i_s_continuous",
        "rel_discretisation_error",
        "elements",
        "links",
        "rays",
        "rms_error",
    ] {
        assert!(mi.contains(&format!("\"{key}\":")), "{key} missing: {mi}");
    }
    assert!(mi.contains("\"rms_error\":null"), "{mi}");
    let leaves = json_number(&mi, "n_patches");
    assert!((100.0..=220.0).contains(&leaves), "{mi}");
    assert!(json_number(&mi, "rays") > 0.0 && json_number(&mi, "links") > 0.0);
    // The same on one thread, bit for bit.
    assert_eq!(
        without_timing(&run("mi", "1.5e-4", "1", &[])),
        without_timing(&mi)
    );
    // The PLY carries the radiosities; the PNG is an image of the default size.
    let text = std::fs::read_to_string(&ply).unwrap();
    assert!(text.contains("property float radiosity_red"));
    let bytes = std::fs::read(&png).unwrap();
    assert_eq!(&bytes[1..4], b"PNG");
    assert_eq!(u32::from_be_bytes(bytes[16..20].try_into().unwrap()), 800);
    // Against itself the RMS error is zero (up to the PLY's single precision); a coarser
    // power mesh is off.
    let reference: [&std::ffi::OsStr; 2] = ["--reference".as_ref(), ply.as_os_str()];
    let itself = json_number(&run("mi", "1.5e-4", "2", &reference), "rms_error");
    let power = json_number(&run("power", "1e4", "2", &reference), "rms_error");
    assert!(itself < 1e-4, "{itself}");
    assert!(power > 1e-3, "{power}");
    // --target searches the threshold.
    let out = bin()
        .arg("refine")
        .arg(&obj)
        .args([
            "--oracle", "power", "--target", "40", "--lines", "20000", "--json",
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let n = json_number(&String::from_utf8(out.stdout).unwrap(), "n_patches");
    assert!((30.0..=50.0).contains(&n), "{n}");
}

/// A fine mesh whose smallest leaves miss the lines still gives its pictures and mesh
/// counts: the channel's measures are `null` with a warning saying how to get them, and the
/// exit status is 0. Without `--lines` the budget doubles until every leaf is sampled.
#[test]
fn refine_obj_writes_its_outputs_when_some_leaf_misses_the_lines() {
    let obj = preset(&["solid", "cornell"], "hr-fine-cornell.obj");
    let (ply, png) = (temp("hr-fine.ply"), temp("hr-fine.png"));
    // KS at 0.02 refines the junctions down to the smallest elements (2e-6 of the area).
    let out = bin()
        .arg("refine")
        .arg(&obj)
        .args([
            "--oracle", "ks", "--eps", "0.02", "--lines", "2000", "--json",
        ])
        .arg("--ply")
        .arg(&ply)
        .arg("--png")
        .arg(&png)
        .args(["--size", "64x64"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("warning") && stderr.contains("received none of the 2000 global lines"),
        "{stderr}"
    );
    let json = String::from_utf8(out.stdout).unwrap();
    assert!(json.contains("\"i_s\":null"), "{json}");
    assert!(json_number(&json, "n_patches") > 500.0, "{json}");
    assert!(
        std::fs::read_to_string(&ply)
            .unwrap()
            .contains("radiosity_red")
    );
    assert_eq!(&std::fs::read(&png).unwrap()[1..4], b"PNG");
    // The automatic budget: the same mesh is measured once the lines reach every leaf.
    let out = bin()
        .arg("refine")
        .arg(&obj)
        .args(["--oracle", "ks", "--eps", "0.02", "--json"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let json = String::from_utf8(out.stdout).unwrap();
    assert!(json_number(&json, "i_s") > 0.0, "{json}");
    assert!(json_number(&json, "lines") > 1048576.0, "{json}");
}

#[test]
fn bench_prints_rates_beside_the_naive_baseline_and_the_load() {
    // One small scene only: naive, 1 and 2 threads, each a pair of short jobs.
    let json = stdout_of(&[
        "bench",
        "--only",
        "triangle",
        "--json",
        "--threads",
        "2",
        "--reps",
        "2",
    ]);
    assert!(json.contains("\"triangle (30)\""), "{json}");
    assert!(
        !json.contains("cube"),
        "--only runs only the matching scene: {json}"
    );
    for key in [
        "naive_lines_per_cpu_second",
        "lines_per_cpu_second_1_thread",
        "lines_per_second_1_thread",
        "lines_per_second",
        "speedup_over_naive",
    ] {
        let v = json_number(&json, key);
        assert!(v > 0.0 && v.is_finite(), "{key} = {v} in {json}");
    }
    // The triangle's 30 patches meet a line 1.44 times on average (Crofton)
    let hits = json_number(&json, "hits_per_line");
    assert!((1.3..1.6).contains(&hits), "{hits}");
    assert_eq!(json_number(&json, "patches"), 30.0);
    assert_eq!(json_number(&json, "threads"), 2.0);
    // Repeated measurements: min <= median <= max, the repetitions, cores and noise flag
    assert_eq!(json_number(&json, "repetitions"), 2.0);
    assert!(json_number(&json, "cores") >= 1.0, "{json}");
    assert!(
        json.contains("\"noisy\":true") || json.contains("\"noisy\":false"),
        "{json}"
    );
    let (lo, mid, hi) = (
        json_number(&json, "lines_per_cpu_second_1_thread_min"),
        json_number(&json, "lines_per_cpu_second_1_thread"),
        json_number(&json, "lines_per_cpu_second_1_thread_max"),
    );
    assert!(lo > 0.0 && lo <= mid && mid <= hi, "{lo} {mid} {hi}");
}
