//! Hostile arguments through the real binary (issue 16): outputs that cannot be written are
//! refused before the job starts, naming the user's path and leaving no file behind;
//! malformed picture and camera arguments are refused while the arguments are read;
//! `--max-input` caps every file read; and every command gives one file the same load
//! verdict — accepted, or refused with the same message — a job refusal (the scene is
//! valid, the flags ask for what cannot be done) worded apart from it.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::{bin, succeeded, temp};

/// The repository's root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The flatland room of `scenes/` (620 patches).
fn room() -> PathBuf {
    root().join("scenes/room620.flat")
}

/// A fresh, empty folder of this test process.
fn folder(name: &str) -> PathBuf {
    let dir = temp(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `command`, killing it and failing the test if it has not ended within `limit` (a
/// harness timeout, not a timed assertion: a check made only after the job would run
/// the `--lines 1e9` jobs below for many minutes).
fn run_within(command: &mut Command, limit: Duration) -> Output {
    let mut child = command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{command:?} still ran after {limit:?}: the output was not checked first");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// The files in `dir` (names), sorted.
fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Every command with every output flag, on a big job: `(args before the output path,
/// args after it)`; the output path goes between.
fn output_commands(scene: &Path, obj: &Path, partial: &Path) -> Vec<(Vec<String>, Vec<String>)> {
    let s = |v: &[&str]| v.iter().map(|a| (*a).to_owned()).collect::<Vec<String>>();
    let flat = scene.to_str().unwrap();
    let obj = obj.to_str().unwrap();
    let partial = partial.to_str().unwrap();
    let big = ["--lines", "1e9"];
    let cases = vec![
        (s(&["measure", flat, "--matrix"]), s(&big)),
        (s(&["measure", flat, "--partial"]), s(&big)),
        (s(&["formfactors", flat, "--out"]), s(&big)),
        (
            s(&["formfactors", obj, "--tol", "1e-9", "--partial"]),
            vec![],
        ),
        (s(&["radiosity", obj, "--ply"]), s(&big)),
        (
            s(&["draw", flat, "--svg"]),
            s(&["--color", "ic", "--lines", "1e9"]),
        ),
        (
            s(&["draw", obj, "--ply"]),
            s(&["--color", "ic", "--lines", "1e9"]),
        ),
        (
            s(&["draw", flat, "--svg", "ok.svg", "--matrix-svg"]),
            s(&["--color", "ic", "--lines", "1e9"]),
        ),
        (s(&["refine", flat, "--oracle", "de", "--svg"]), s(&big)),
        (s(&["refine", flat, "--oracle", "de", "--output"]), s(&big)),
        (
            s(&["refine", obj, "--oracle", "power", "--ply"]),
            s(&["--target", "1000000"]),
        ),
        (
            s(&["refine", obj, "--oracle", "power", "--png"]),
            s(&["--target", "1000000"]),
        ),
        (s(&["simplify", flat, "--to", "2", "--output"]), vec![]),
        (s(&["merge", partial, "--matrix"]), vec![]),
        (s(&["merge", partial, "--partial"]), vec![]),
        (s(&["merge", partial, "--out"]), vec![]),
        (s(&["scene", "polygon", "--sides", "5", "--output"]), vec![]),
        (s(&["scene", "cube", "--output"]), vec![]),
    ];
    // `refine --svg` and `-o` are flatland flags, `--ply`/`--png` 3D ones: each is given
    // where it applies, so the refusal can only come from the output check
    cases
}

/// Every output flag of every command, given a path under a folder that does not exist or
/// a path that is a folder: exit 2 at once (a `--lines 1e9` job would take minutes), the
/// user's path in the message (never the hidden `.NAME.tmpPID`), nothing written anywhere.
#[test]
fn unwritable_outputs_are_refused_before_the_job() {
    let work = folder("outputs-unwritable");
    let obj = common::preset(&["cube", "--grid", "3"], "outputs-cube.obj");
    // A partial result for merge (one chunk of a small job)
    let partial = work.join("part.sip");
    succeeded(
        bin()
            .args([
                "measure",
                room().to_str().unwrap(),
                "--lines",
                "65536",
                "--partial",
            ])
            .arg(&partial)
            .output()
            .unwrap(),
    );
    let existing_dir = work.join("a-folder");
    std::fs::create_dir(&existing_dir).unwrap();
    let before = files_in(&work);
    let missing = work.join("no-such-folder").join("out.file");
    for (head, tail) in output_commands(&room(), &obj, &partial) {
        for (target, why) in [
            (&missing, "does not exist"),
            (&existing_dir, "it is a folder"),
        ] {
            let out = run_within(
                bin().current_dir(&work).args(&head).arg(target).args(&tail),
                Duration::from_secs(60),
            );
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{head:?} {target:?}: {err}");
            let want = format!("sceneinfo: {}: cannot write: ", target.display());
            assert!(err.starts_with(&want), "{head:?}: {err}");
            assert!(err.contains(why), "{head:?}: {err}");
            assert!(
                !err.contains(".tmp"),
                "{head:?}: names the temporary file: {err}"
            );
            assert!(out.stdout.is_empty(), "{head:?}: printed a result");
        }
    }
    // Nothing written: no temporary file, no `ok.svg` of the draw whose second output failed
    assert_eq!(files_in(&work), before);
    assert!(files_in(&existing_dir).is_empty());
    assert!(!work.join("no-such-folder").exists());
}

/// A device or a path ending in `/` is no file to write; one path given for two outputs
/// would lose the first. All refused before the job.
#[test]
fn devices_folders_and_twice_given_outputs_are_refused() {
    let work = folder("outputs-odd");
    let room = room();
    let room = room.to_str().unwrap();
    let cases: [(&[&str], &str); 4] = [
        (
            &["formfactors", room, "--out", "/dev/null", "--lines", "1e9"],
            "sceneinfo: /dev/null: cannot write: it is a device or pipe, not a regular file\n",
        ),
        (
            &["measure", room, "--matrix", "new-folder/", "--lines", "1e9"],
            "sceneinfo: new-folder/: cannot write: it names a folder; give a file name\n",
        ),
        (
            &[
                "draw",
                room,
                "--svg",
                "a.svg",
                "--matrix-svg",
                "a.svg",
                "--color",
                "ic",
            ],
            "sceneinfo: a.svg: given as two outputs (--svg and --matrix-svg); the second would \
             replace the first\n",
        ),
        (
            &["scene", "cube", "-o", "c.mtl"],
            "sceneinfo: c.mtl: given as two outputs (--output and its .mtl); the second would \
             replace the first\n",
        ),
    ];
    for (args, want) in cases {
        let out = run_within(bin().current_dir(&work).args(args), Duration::from_secs(60));
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert_eq!(String::from_utf8_lossy(&out.stderr), want, "{args:?}");
    }
    assert!(files_in(&work).is_empty(), "{:?}", files_in(&work));
}

/// An output whose "folder" is a plain file: refused with the user's path and why.
#[test]
fn an_output_under_a_file_is_refused_with_its_path() {
    let work = folder("outputs-under-file");
    std::fs::write(work.join("plain"), "x").unwrap();
    let target = work.join("plain").join("out.csv");
    let out = bin()
        .args(["measure", room().to_str().unwrap(), "--matrix"])
        .arg(&target)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(
        err,
        format!(
            "sceneinfo: {}: cannot write: {} is not a folder\n",
            target.display(),
            work.join("plain").display()
        )
    );
    assert_eq!(files_in(&work), ["plain"]);
}

/// A good output is still written, whole, and nothing else beside it.
#[test]
fn good_outputs_are_written_and_nothing_else() {
    let work = folder("outputs-good");
    succeeded(
        bin()
            .current_dir(&work)
            .args(["formfactors", room().to_str().unwrap(), "--out", "f.csv"])
            .output()
            .unwrap(),
    );
    assert_eq!(files_in(&work), ["f.csv"]);
    assert_eq!(
        std::fs::read_to_string(work.join("f.csv"))
            .unwrap()
            .lines()
            .count(),
        620
    );
}

/// `--size 0x0` and other malformed picture or camera arguments: clap's usage error (exit
/// 2) naming the flag and why, before the scene is read (the scene file does not exist).
#[test]
fn malformed_picture_and_camera_arguments_are_refused_when_read() {
    let cases: [(&[&str], &str); 7] = [
        (
            &["--size", "0x0"],
            "width and height must be whole numbers of pixels, 16 to 8192",
        ),
        (&["--size", "800"], "is not a picture size WxH"),
        (&["--size", "100x99999"], "16 to 8192"),
        (
            &["--eye", "1,2"],
            "is not a point x,y,z of three finite numbers",
        ),
        (
            &["--look", "1,nan,3"],
            "is not a point x,y,z of three finite numbers",
        ),
        (&["--fov", "0"], "degrees strictly between 0 and 180"),
        (&["--fov", "180"], "degrees strictly between 0 and 180"),
    ];
    for (args, want) in cases {
        let out = run_within(
            bin()
                .args([
                    "refine",
                    "no-such-scene.obj",
                    "--oracle",
                    "power",
                    "--png",
                    "x.png",
                ])
                .args(args),
            Duration::from_secs(60),
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(want), "{args:?}: {err}");
        assert!(err.contains(args[0]), "{args:?}: {err}");
        assert!(
            !err.contains("no-such-scene"),
            "{args:?}: read the scene: {err}"
        );
    }
}

/// The same point for `--eye` and `--look` is refused before the hierarchy is built.
#[test]
fn eye_and_look_must_differ() {
    let obj = common::preset(&["cube", "--grid", "2"], "outputs-eye.obj");
    let png = temp("outputs-eye.png");
    let out = run_within(
        bin()
            .arg("refine")
            .arg(&obj)
            .args(["--oracle", "power", "--target", "1000000", "--png"])
            .arg(&png)
            .args(["--eye", "1,1,1", "--look", "1,1,1"]),
        Duration::from_secs(60),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("--eye and --look must differ"), "{err}");
    assert!(!png.exists());
}

/// `--max-input` caps every file read — the scene, a glTF's external buffer, a partial
/// result of `merge`, a `--reference` PLY — with one message; suffixes as `--max-memory`.
#[test]
fn max_input_caps_every_file_read() {
    let work = folder("outputs-max-input");
    let refused = |args: &[&str], want: &str| {
        let out = bin().current_dir(&work).args(args).output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err, format!("sceneinfo: {want}\n"), "{args:?}");
    };
    let room = room();
    let room = room.to_str().unwrap();
    let size = std::fs::metadata(room).unwrap().len();
    refused(
        &["measure", room, "--max-input", "100"],
        &format!(
            "{room}: {size} bytes, larger than 100 bytes, the cap on scene files; \
             raise --max-input"
        ),
    );
    // The flag may come before the command, and takes K, M, G suffixes
    succeeded(
        bin()
            .args(["--max-input", "1K", "measure", room])
            .output()
            .unwrap(),
    );
    refused(
        &["measure", room, "--max-input", "0.1K"],
        &format!(
            "{room}: {size} bytes, larger than 102 bytes, the cap on scene files; \
             raise --max-input"
        ),
    );
    let out = bin()
        .args(["measure", room, "--max-input", "lots"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("is not a memory size"));
    // A glTF's external buffer (48 bytes) under a cap its JSON (863 bytes) fits
    let gltf = root().join("tests/data/corpus/gltf/Mesh_PrimitiveMode/Mesh_PrimitiveMode_04.gltf");
    succeeded(
        bin()
            .arg("measure")
            .arg(&gltf)
            .args(["--max-input", "900"])
            .output()
            .unwrap(),
    );
    let out = bin()
        .arg("measure")
        .arg(&gltf)
        .args(["--max-input", "40"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2));
    assert!(err.contains("larger than 40 bytes"), "{err}");
    // A partial result for merge
    succeeded(
        bin()
            .args(["measure", room, "--lines", "65536", "--partial", "p.sip"])
            .current_dir(&work)
            .output()
            .unwrap(),
    );
    let part = std::fs::metadata(work.join("p.sip")).unwrap().len();
    refused(
        &["merge", "p.sip", "--max-input", "64"],
        &format!(
            "p.sip: {part} bytes, larger than 64 bytes, the cap on partial results; \
             raise --max-input"
        ),
    );
    // merge reads regular files only: a folder or a device is refused at once
    std::fs::create_dir(work.join("dir.sip")).unwrap();
    refused(
        &["merge", "dir.sip"],
        "dir.sip: not a regular file (a device, pipe or folder): refused",
    );
    refused(
        &["merge", "/dev/zero"],
        "/dev/zero: not a regular file (a device, pipe or folder): refused",
    );
    // A reference PLY of refine
    let obj = common::preset(&["cube", "--grid", "1"], "outputs-reference.obj");
    let reference = work.join("ref.ply");
    std::fs::write(&reference, "ply\nformat ascii 1.0\n".repeat(20)).unwrap(); // 420 bytes
    // (read before the job: a million-element refinement would not end in time)
    let out = run_within(
        bin()
            .arg("refine")
            .arg(&obj)
            .args(["--oracle", "power", "--target", "1000000"])
            .arg("--reference")
            .arg(&reference)
            .args(["--max-input", "300"]),
        Duration::from_secs(60),
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.contains(&format!(
            "{}: 420 bytes, larger than 300 bytes, the cap on reference solutions; \
             raise --max-input",
            reference.display()
        )),
        "{err}"
    );
}

/// The load verdict of one command on one file: `accepted` (the command ran, or refused
/// the job with [`JOB_REFUSAL`] — the scene itself loaded), else its error line.
fn verdict(out: &Output) -> String {
    let err = String::from_utf8_lossy(&out.stderr);
    let errors: Vec<&str> = err
        .lines()
        .filter(|l| l.starts_with("sceneinfo: ") && !l.starts_with("sceneinfo: warning"))
        .collect();
    if out.status.success() || errors.iter().any(|l| l.contains(JOB_REFUSAL)) {
        "accepted".to_owned()
    } else {
        errors.join("\n")
    }
}

/// What a job refusal says (`output::job_refused`).
const JOB_REFUSAL: &str = "the scene is valid, but this job cannot run on it: ";

/// One verdict per file: `measure`, `formfactors`, `radiosity`, `draw` and `refine` accept
/// the same files (good ones of `scenes/` and the corpus) and refuse the same bad ones
/// (`tests/data/bad/`, a folder, a device) with the same message.
#[test]
fn every_command_gives_a_file_the_same_load_verdict() {
    let work = folder("outputs-verdict");
    let corpus = root().join("tests/data/corpus");
    let bad = root().join("tests/data/bad");
    let good = [
        room(),
        corpus.join("obj/cornell_box/cornell_box.obj"),
        corpus.join("obj/pywavefront/arbitrary-faces.obj"),
        corpus.join("ply/assimp/cube.ply"),
        corpus.join("gltf/BoxTextured-Binary/BoxTextured.glb"),
        corpus.join("gltf/Mesh_PrimitiveMode/Mesh_PrimitiveMode_04.gltf"),
    ];
    let refused = [
        bad.join("empty.flat"),
        bad.join("duplicate_segment.flat"),
        bad.join("invalid_utf8.flat"),
        bad.join("nan_coordinate.flat"),
        bad.join("obj_zero_area_face.obj"),
        bad.join("obj_emittance_negative.obj"),
        bad.join("obj_face_index_zero.obj"),
        bad.join("obj_invalid_utf8.obj"),
        work.clone(),
        PathBuf::from("/dev/zero"),
        work.join("missing.obj"),
    ];
    let mut failures = Vec::new();
    for file in good.iter().chain(&refused) {
        // The picture flag by extension, as `draw` chooses before it reads the file
        let is_flat = file.extension().is_none_or(|e| e == "flat");
        let picture = if is_flat { "--svg" } else { "--ply" };
        let runs: [(&str, Vec<&str>); 5] = [
            ("measure", vec!["--lines", "100000"]),
            ("formfactors", vec!["--out", "f.csv", "--lines", "100000"]),
            ("radiosity", vec!["--lines", "100000"]),
            ("draw", vec![picture, "picture", "--lines", "100000"]),
            (
                "refine",
                vec!["--oracle", "power", "--target", "20", "--lines", "100000"],
            ),
        ];
        let verdicts: Vec<(&str, String)> = runs
            .iter()
            .map(|(command, args)| {
                let out = bin()
                    .current_dir(&work)
                    .arg(command)
                    .arg(file)
                    .args(args)
                    .output()
                    .unwrap();
                (*command, verdict(&out))
            })
            .collect();
        let first = &verdicts[0].1;
        let expected_good = good.contains(file);
        if verdicts.iter().any(|(_, v)| v != first) || (first == "accepted") != expected_good {
            failures.push(format!("{}:\n  {verdicts:#?}", file.display()));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Exact form factors of a 3D scene whose patches may hide one another are computed with
/// occlusion (they were refused before): `measure` prints the error estimate.
#[test]
fn an_occluded_scene_is_measured_exactly_with_an_error_estimate() {
    let cornell = root().join("tests/data/corpus/obj/cornell_box/cornell_box.obj");
    let out = bin()
        .arg("measure")
        .arg(&cornell)
        .args(["--tol", "1e-3"])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        text.contains("F with occlusion: error estimate max"),
        "{text}"
    );
    // --tol belongs to exact form factors
    let out = bin()
        .arg("measure")
        .arg(&cornell)
        .args(["--tol", "1e-3", "--lines", "1000"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}
