//! The bytes of text scenes through the real binary: a UTF-8 byte-order mark, CRLF and
//! CR-only line ends read like plain LF text; control characters in names are escaped
//! in messages; text that is not UTF-8, in a scene or in its material library, is
//! reported with its file, line and byte offset.

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::{bin, stdout_of, temp, without_timing};

/// A flatland room: a grey square lit by one lamp segment.
const ROOM_FLAT: &str = "# a room\nmat rho 0.5 0.5 0.5\npoly 4 0 0 2 0 2 2 0 2 per_side 3\n\
                         mat emit 1 1 1\nseg 0.5 1 1.5 1 cuts 0.25 0.5\n";

/// The unit cube as a room (faces toward the inside), its walls in `room.mtl`.
const ROOM_OBJ: &str = "# a cube\nmtllib room.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
                        v 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\nusemtl wall\nf 1 2 3 4\n\
                        f 5 8 7 6\nf 1 5 6 2\nf 2 6 7 3\nf 3 7 8 4\nusemtl lamp\nf 4 8 5 1\n";

/// The material library of [`ROOM_OBJ`].
const ROOM_MTL: &str = "newmtl wall\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0.2 0.2 0.2\nKe 1 1 1\n";

/// Writes `bytes` to `dir/name` (a folder of the test's own: the tests run in parallel).
fn write(dir: &str, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
    let dir = temp(dir);
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// `measure FILE --json` without its timing keys.
fn measure(path: &Path) -> String {
    without_timing(stdout_of(&["measure", path.to_str().unwrap(), "--json"]).trim())
}

/// `measure FILE`, which must fail with code 2: its standard error.
fn failure(path: &Path) -> String {
    let out: Output = bin().arg("measure").arg(path).output().unwrap();
    assert_eq!(out.status.code(), Some(2), "{}", path.display());
    assert!(out.stdout.is_empty());
    String::from_utf8(out.stderr).unwrap()
}

#[test]
fn byte_order_mark_and_line_ends_measure_like_plain_text() {
    let plain = measure(&write("flat_lf", "room.flat", ROOM_FLAT));
    for (k, end) in ["\n", "\r\n", "\r"].into_iter().enumerate() {
        for (b, bom) in ["", "\u{feff}"].into_iter().enumerate() {
            let text = format!("{bom}{}", ROOM_FLAT.replace('\n', end));
            let dir = format!("flat_{k}_{b}");
            assert_eq!(
                measure(&write(&dir, "room.flat", text)),
                plain,
                "{end:?} {bom:?}"
            );
        }
    }
    let dir = "obj_lf";
    write(dir, "room.mtl", ROOM_MTL);
    let plain = measure(&write(dir, "room.obj", ROOM_OBJ));
    for (k, end) in ["\r\n", "\r"].into_iter().enumerate() {
        for (b, bom) in ["", "\u{feff}"].into_iter().enumerate() {
            let dir = format!("obj_{k}_{b}");
            write(
                &dir,
                "room.mtl",
                format!("{bom}{}", ROOM_MTL.replace('\n', end)),
            );
            let obj = format!("{bom}{}", ROOM_OBJ.replace('\n', end));
            assert_eq!(
                measure(&write(&dir, "room.obj", obj)),
                plain,
                "{end:?} {bom:?}"
            );
        }
    }
}

#[test]
fn errors_after_cr_only_lines_name_the_right_line() {
    let path = write(
        "cr_error",
        "room.flat",
        "\u{feff}# a\rseg 0 0 1 0\r\rseg 0 0 0 0\r",
    );
    assert_eq!(
        failure(&path),
        format!("sceneinfo: {}:4: segment has zero length\n", path.display())
    );
}

#[test]
fn control_characters_in_names_are_escaped_in_messages() {
    // An error: the terminal sees `\u{1b}`, not an escape sequence.
    let path = write(
        "esc_error",
        "room.flat",
        "seg 0 0 1 0\n\u{1b}[2Jseg\0 0 1 1 1\n",
    );
    let stderr = failure(&path);
    assert_eq!(
        stderr,
        format!(
            "sceneinfo: {}:2: unknown keyword '\\u{{1b}}[2Jseg\\0'\n",
            path.display()
        )
    );
    assert!(!stderr.contains(['\u{1b}', '\0']));
    // A warning: a statement with ESC and a letter outside ASCII in its keyword.
    let dir = "esc_warning";
    write(dir, "room.mtl", ROOM_MTL);
    let obj = ROOM_OBJ.replace("usemtl lamp", "lampé\u{1b}[31m 1\nusemtl lamp");
    let out = bin()
        .arg("measure")
        .arg(write(dir, "room.obj", obj))
        .output()
        .unwrap();
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        stderr.contains("skipped unknown 'lampé\\u{1b}[31m' statements"),
        "{stderr}"
    );
    assert!(!stderr.contains('\u{1b}'), "{stderr}");
}

#[test]
fn text_that_is_not_utf8_names_line_and_byte_offset() {
    // A Latin-1 `é` (0xE9) on line 3 after CR-only lines, at byte offset 21.
    let mut flat = b"# a\rseg 0 0 1 0\r# caf".to_vec();
    flat.extend_from_slice(b"\xe9\rseg 0 1 1 1\r");
    let path = write("latin1_flat", "room.flat", flat);
    assert_eq!(
        failure(&path),
        format!(
            "sceneinfo: {}:3: input is not valid UTF-8 at byte offset 21\n",
            path.display()
        )
    );
}

#[test]
fn a_latin1_material_library_is_an_error_naming_it_not_a_missing_one() {
    let dir = "latin1_mtl";
    // `newmtl lampé` in Latin-1: line 3, byte offset 38.
    let mut mtl = ROOM_MTL.replace("lamp", "lamp\u{e9}").into_bytes();
    let at = mtl.iter().position(|&b| b == 0xc3).unwrap();
    mtl.splice(at..at + 2, [0xe9]);
    assert_eq!(at, 38);
    let library = write(dir, "room.mtl", mtl);
    let obj = write(
        dir,
        "room.obj",
        ROOM_OBJ.replace("usemtl lamp", "usemtl lampé"),
    );
    assert_eq!(
        failure(&obj),
        format!(
            "sceneinfo: {}: material library: {}:3: input is not valid UTF-8 at byte \
             offset 38\n",
            obj.display(),
            library.display()
        )
    );
    // A library that cannot be read stays a warning: the room is measured, and
    // `radiosity` (which uses materials) says what is missing.
    let dir = "missing_mtl";
    let obj = write(dir, "room.obj", ROOM_OBJ);
    measure(&obj);
    let out = bin().arg("radiosity").arg(&obj).output().unwrap();
    let stderr = String::from_utf8(out.stderr).unwrap();
    assert!(
        stderr.contains("material library 'room.mtl' not found"),
        "{stderr}"
    );
}

/// Only regular files are read: a device (`/dev/zero`, which never ends) or a FIFO (whose
/// opening waits for a writer) named as the scene or as a material library is refused at
/// once with its path — never read until memory runs out, never waited on.
#[test]
fn devices_and_pipes_are_refused_not_read() {
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let zero_lib = write("devices", "zero.obj", format!("mtllib /dev/zero\n{tri}"));
    let err = failure(&zero_lib);
    assert!(
        err.contains("material library: /dev/zero: not a regular file"),
        "{err}"
    );
    let err = failure(Path::new("/dev/zero"));
    assert!(err.contains("/dev/zero: not a regular file"), "{err}");
    // A FIFO (mkfifo is POSIX; skipped where the command is missing)
    let fifo = temp("devices-fifo.obj");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success());
    if made {
        // (An output must be a regular file too: draw writes a temporary PLY that is
        // never created, as the scene is refused first)
        let ply = temp("devices-fifo-out.ply");
        let ply = ply.to_str().unwrap();
        for command in [&["measure"][..], &["draw", "--ply", ply]] {
            let out = bin().args(command).arg(&fifo).output().unwrap();
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{command:?}: {err}");
            let want = format!("{}: not a regular file", fifo.display());
            assert!(err.contains(&want), "{command:?}: {err}");
        }
        let lib = write(
            "devices",
            "fifo-lib.obj",
            format!("mtllib {}\n{tri}", fifo.display()),
        );
        let err = failure(&lib);
        assert!(err.contains("not a regular file"), "{err}");
    }
}
