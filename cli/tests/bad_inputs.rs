//! The bad-input catalogue `tests/data/bad/` through the real binary: for every file,
//! `sceneinfo measure FILE [ARGS]` exits with code 2, prints nothing on stdout and exactly
//! `sceneinfo: FILE:N: what` (or `sceneinfo: FILE: what`) on stderr, as listed in
//! `tests/data/bad/expected.txt`.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The catalogue's directory.
fn catalogue_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/bad")
}

/// One line of `expected.txt`.
struct Entry {
    file: String,
    args: Vec<String>,
    message: String,
}

/// The entries of `expected.txt` (comments and blank lines skipped).
fn entries() -> Vec<Entry> {
    let text = std::fs::read_to_string(catalogue_dir().join("expected.txt")).unwrap();
    text.lines()
        .filter(|l| !l.trim().is_empty() && !l.starts_with('#'))
        .map(|l| {
            let fields: Vec<&str> = l.splitn(3, " | ").collect();
            assert_eq!(fields.len(), 3, "malformed catalogue line {l:?}");
            Entry {
                file: fields[0].trim().to_string(),
                args: fields[1].split_whitespace().map(String::from).collect(),
                message: fields[2].trim().to_string(),
            }
        })
        .collect()
}

/// What the CLI prints for a core message about `file`: `line N: what` becomes
/// `FILE:N: what`, a message without a line `FILE: what`.
fn cli_message(file: &str, message: &str) -> String {
    let located = message.strip_prefix("line ").and_then(|rest| {
        let (n, what) = rest.split_once(": ")?;
        n.parse::<u32>().ok().map(|n| format!("{file}:{n}: {what}"))
    });
    format!(
        "sceneinfo: {}\n",
        located.unwrap_or_else(|| format!("{file}: {message}"))
    )
}

#[test]
fn every_bad_input_exits_2_with_its_located_message() {
    let entries = entries();
    let mut failures = Vec::new();
    for e in &entries {
        let out = Command::new(env!("CARGO_BIN_EXE_sceneinfo"))
            .current_dir(catalogue_dir())
            .arg("measure")
            .arg(&e.file)
            .args(&e.args)
            .output()
            .unwrap();
        let want = cli_message(&e.file, &e.message);
        let got = String::from_utf8_lossy(&out.stderr);
        if out.status.code() != Some(2) || !out.stdout.is_empty() || got != want {
            failures.push(format!(
                "{} {:?}: exit {:?}, stdout {} bytes\n  want {want:?}\n  got  {got:?}",
                e.file,
                e.args,
                out.status.code(),
                out.stdout.len()
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} catalogue entries failed:\n{}",
        failures.len(),
        entries.len(),
        failures.join("\n")
    );
}

#[test]
fn catalogue_lists_every_file_and_has_at_least_40() {
    let listed: BTreeSet<String> = entries().into_iter().map(|e| e.file).collect();
    let present: BTreeSet<String> = std::fs::read_dir(catalogue_dir())
        .unwrap()
        .map(|f| f.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".flat") || name.ends_with(".obj"))
        .collect();
    assert_eq!(listed, present, "expected.txt and the files differ");
    assert!(listed.len() >= 40, "only {} catalogue files", listed.len());
}

#[test]
fn cli_message_maps_core_lines_to_file_lines() {
    assert_eq!(
        cli_message("a.flat", "line 3: segment has zero length"),
        "sceneinfo: a.flat:3: segment has zero length\n"
    );
    assert_eq!(
        cli_message("a.flat", "the line budget must be at least 1"),
        "sceneinfo: a.flat: the line budget must be at least 1\n"
    );
}
