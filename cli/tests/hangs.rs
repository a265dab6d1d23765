//! Hostile input that used to hang (issue 16), through the real binary, each under a
//! harness timeout (a hang fails the test instead of stalling it; no timed assertion):
//!
//! - an emittance of 1e308 (`.flat` and OBJ + MTL): `refine` split every element pair down
//!   to the smallest element, build after build; now refused at its line;
//! - an emittance at the cap (1e100): the threshold search of `refine FILE.obj` started
//!   below every oracle value; now it ends in seconds;
//! - 200,000 copies of a segment, of a polygon, of an OBJ face: the coincidence check was
//!   quadratic in the copies;
//! - Ctrl-C during a job that does not poll for it (exact form factors): it ran on; now it
//!   exits with 130 at once, leaving no output and no temporary file.

mod common;

use std::path::Path;
use std::time::Duration;

use common::{bin, output_within, temp_unique};

/// Generous: every case here takes well under a second in a release build.
const LIMIT: Duration = Duration::from_secs(120);

/// Writes `text` to a fresh file named `name` in its own temporary folder.
fn write(name: &str, text: &str) -> std::path::PathBuf {
    let dir = temp_unique("hangs");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// `sceneinfo ARGS FILE` under the harness timeout: exit code, stderr.
fn run(args: &[&str], file: &Path) -> (Option<i32>, String) {
    let out = output_within(bin().args(args).arg(file), LIMIT);
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

const TOO_LARGE: &str = "emittance 1e308 is too large: at most 1e100, so that radiosities, \
                         powers and their squares stay finite";

/// A unit cube facing inwards whose floor uses material `lamp` and the rest `wall`.
const CUBE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
                    usemtl lamp\nf 1 2 3 4\nusemtl wall\nf 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\n\
                    f 3 7 8 4\nf 4 8 5 1\n";

#[test]
fn refine_with_emittance_1e308_is_refused_at_its_line() {
    let flat = write(
        "lamp.flat",
        "mat rho 0.5 0.5 0.5 emit 1e308 1e308 1e308\npoly 4 0 0 1 0 1 1 0 1 per_side 4\n",
    );
    for args in [
        &["refine", "--oracle", "de"][..],
        &["refine", "--oracle", "power"],
        &["radiosity"],
        &["measure"],
    ] {
        let (code, err) = run(args, &flat);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert_eq!(
            err,
            format!("sceneinfo: {}:1: {TOO_LARGE}\n", flat.display())
        );
    }
}

#[test]
fn refine_obj_with_emittance_1e308_in_its_mtl_is_refused_at_its_line() {
    let obj = write("cube.obj", &format!("mtllib cube.mtl\n{CUBE}"));
    let dir = obj.parent().unwrap();
    std::fs::write(
        dir.join("cube.mtl"),
        "newmtl lamp\nKd 0.5 0.5 0.5\nKe 1e308 1e308 1e308\nnewmtl wall\nKd 0.5 0.5 0.5\n",
    )
    .unwrap();
    for oracle in ["power", "ks-av", "mi", "mi-increase"] {
        let (code, err) = run(&["refine", "--oracle", oracle], &obj);
        assert_eq!(code, Some(2), "{oracle}: {err}");
        assert_eq!(
            err,
            format!(
                "sceneinfo: {}:1: material library 'cube.mtl' line 3: {TOO_LARGE}\n",
                obj.display()
            )
        );
    }
}

#[test]
fn refine_obj_emitting_at_the_cap_ends() {
    let obj = write("cube.obj", &format!("mtllib cube.mtl\n{CUBE}"));
    std::fs::write(
        obj.parent().unwrap().join("cube.mtl"),
        "newmtl lamp\nKd 0.5 0.5 0.5\nKe 1e100 1e100 1e100\nnewmtl wall\nKd 0.5 0.5 0.5\n",
    )
    .unwrap();
    for oracle in ["power", "mi-increase"] {
        let (code, err) = run(
            &[
                "refine", "--oracle", oracle, "--target", "200", "--lines", "65536",
            ],
            &obj,
        );
        assert_eq!(code, Some(0), "{oracle}: {err}");
    }
}

#[test]
fn two_hundred_thousand_identical_segments_are_refused_fast() {
    for (line, name) in [
        ("seg 0 0 1 0 1\n", "segments.flat"),
        ("poly 4 0 0 1 0 1 1 0 1\n", "polygons.flat"),
    ] {
        let file = write(name, &line.repeat(200_000));
        let (code, err) = run(&["measure"], &file);
        assert_eq!(code, Some(2), "{err}");
        assert_eq!(
            err,
            format!(
                "sceneinfo: {}:2: coincides with a surface of line 1: same line or plane, \
                 same facing, overlapping (reverse one of them for a two-sided wall)\n",
                file.display()
            )
        );
    }
}

#[test]
fn two_hundred_thousand_identical_obj_faces_load_as_drawn() {
    let file = write(
        "faces.obj",
        &format!(
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n{}",
            "f 1 2 3 4\n".repeat(200_000)
        ),
    );
    let (code, err) = run(&["measure"], &file);
    assert_eq!(code, Some(0), "{err}");
}

/// Ctrl-C (SIGINT) during exact form factors of 9,900 patches, a job that does not poll
/// for it: exit 130 at once, "nothing written", no `--matrix` file and no temporary file.
#[cfg(unix)]
#[test]
fn ctrl_c_stops_a_job_that_does_not_poll() {
    let scene = write(
        "big.flat",
        "poly 4 0 0 1 0 1 1 0 1 per_side 2400\nseg 0.2 0.5 0.8 0.5 300\n",
    );
    let dir = scene.parent().unwrap();
    let matrix = dir.join("F.csv");
    let mut child = bin()
        .arg("measure")
        .arg(&scene)
        .arg("--matrix")
        .arg(&matrix)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_secs(2));
    assert!(
        child.try_wait().unwrap().is_none(),
        "the job ended before Ctrl-C: make the scene larger"
    );
    let st = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(st.success());
    let status = common::wait_within(&mut child, Duration::from_secs(20));
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    assert_eq!(status.code(), Some(130), "{err}");
    assert_eq!(
        err,
        "sceneinfo: interrupted before the results were complete: nothing written\n"
    );
    let left: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left, vec![std::ffi::OsString::from("big.flat")], "{left:?}");
}
