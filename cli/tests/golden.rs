//! Golden outputs: every number a set of commands prints, compared byte for byte with the
//! files committed in `tests/data/golden/` (wall-clock keys removed). A refactoring must not
//! move a single bit of what the program prints (issue 17); a change that means to move
//! numbers regenerates the files and says why in the CHANGELOG:
//!
//! ```text
//! SCENEINFO_BLESS=1 cargo test -p sceneinfo-cli --test golden
//! ```
//!
//! The whole `reproduce` (a minute or two in release) is checked the same way by
//! `scripts/golden-reproduce.sh`, before and after a refactoring.

mod common;

use std::path::{Path, PathBuf};

use common::bin;

/// The repository's root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// `text` without the values of keys that hold wall-clock times (`"seconds":…`,
/// `"lines_per_second":…`, `"cpu_seconds":…`): their number up to the next `,` or `}`.
fn without_clock(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find('"') {
        let Some(len) = rest[at + 1..].find('"') else {
            break;
        };
        let key = &rest[at + 1..at + 1 + len];
        let after = &rest[at + 2 + len..];
        out.push_str(&rest[..at + 2 + len]);
        rest = after;
        if key.contains("second") && rest.starts_with(':') {
            let end = rest.find([',', '}']).unwrap_or(rest.len());
            out.push_str(":<clock>");
            rest = &rest[end..];
        }
    }
    out.push_str(rest);
    out
}

/// Each golden case: its file name and the arguments of `sceneinfo`, run in the root.
const CASES: &[(&str, &[&str])] = &[
    (
        "measure_room620_exact.json",
        &["measure", "scenes/room620.flat", "--json"],
    ),
    (
        "measure_room620_global.json",
        &[
            "measure",
            "scenes/room620.flat",
            "--json",
            "--lines",
            "70000",
            "--seed",
            "5",
        ],
    ),
    (
        "measure_room620_local.json",
        &[
            "measure",
            "scenes/room620.flat",
            "--json",
            "--lines",
            "70000",
            "--seed",
            "5",
            "--method",
            "local",
        ],
    ),
    (
        "measure_room620_bundle.json",
        &[
            "measure",
            "scenes/room620.flat",
            "--json",
            "--lines",
            "70000",
            "--seed",
            "5",
            "--method",
            "bundle",
        ],
    ),
    (
        "measure_cornell_global.json",
        &[
            "measure",
            "tests/data/corpus/obj/cornell_box/cornell_box.obj",
            "--json",
            "--lines",
            "70000",
            "--seed",
            "5",
        ],
    ),
    (
        "measure_cornell_bundle.json",
        &[
            "measure",
            "tests/data/corpus/obj/cornell_box/cornell_box.obj",
            "--json",
            "--lines",
            "70000",
            "--seed",
            "5",
            "--method",
            "bundle",
        ],
    ),
    (
        "measure_teapot_local.json",
        &[
            "measure",
            "tests/data/corpus/obj/euc/teapot.obj",
            "--json",
            "--lines",
            "70000",
            "--seed",
            "5",
            "--method",
            "local",
        ],
    ),
    (
        "radiosity_room620.json",
        &["radiosity", "scenes/room620.flat", "--json"],
    ),
    (
        "radiosity_room620_global.json",
        &[
            "radiosity",
            "scenes/room620.flat",
            "--json",
            "--lines",
            "70000",
            "--seed",
            "5",
        ],
    ),
    (
        "radiosity_cornell_bundle.json",
        &[
            "radiosity",
            "tests/data/corpus/obj/cornell_box/cornell_box.obj",
            "--json",
            "--emit-from-ka",
            "--lines",
            "70000",
            "--seed",
            "5",
            "--method",
            "bundle",
        ],
    ),
    (
        "refine_room620_de.json",
        &[
            "refine",
            "scenes/room620.flat",
            "--oracle",
            "de",
            "--target",
            "640",
            "--lines",
            "70000",
            "--json",
        ],
    ),
    (
        "reproduce_chapter3.json",
        &["reproduce", "--chapter-3-only", "--json"],
    ),
];

#[test]
fn printed_numbers_match_the_golden_files() {
    let bless = std::env::var_os("SCENEINFO_BLESS").is_some();
    let dir = root().join("tests/data/golden");
    let mut moved = Vec::new();
    for (name, args) in CASES {
        let out = bin().current_dir(root()).args(*args).output().unwrap();
        assert!(
            out.status.success(),
            "sceneinfo {args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let got = without_clock(&String::from_utf8(out.stdout).unwrap());
        let path = dir.join(name);
        if bless {
            std::fs::write(&path, &got).unwrap();
            continue;
        }
        let want = std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("{}: {e} (bless with SCENEINFO_BLESS=1)", path.display()));
        if got != want {
            moved.push(format!(
                "sceneinfo {}\n  want {want}  got  {got}",
                args.join(" ")
            ));
        }
    }
    assert!(
        moved.is_empty(),
        "printed numbers moved (bless with SCENEINFO_BLESS=1 only if that is meant, and say \
         why in CHANGELOG.md):\n{}",
        moved.join("\n")
    );
}

#[test]
fn clock_values_are_removed_and_nothing_else() {
    assert_eq!(
        without_clock(r#"{"a":1,"seconds":0.25,"b":{"cpu_seconds":3e-4},"lines_per_second":7}"#),
        r#"{"a":1,"seconds":<clock>,"b":{"cpu_seconds":<clock>},"lines_per_second":<clock>}"#
    );
    assert_eq!(without_clock(r#"{"x":"seconds"}"#), r#"{"x":"seconds"}"#);
}
