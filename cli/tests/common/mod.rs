//! Helpers shared by the tests that run the real `sceneinfo` binary.
//!
//! Each test binary uses only some of them.
#![allow(dead_code)]

use std::path::PathBuf;
use std::process::Command;

/// The `sceneinfo` binary under test.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_sceneinfo"))
}

/// The standard output of `sceneinfo ARGS`, which must succeed (else its stderr is shown).
pub fn stdout_of(args: &[&str]) -> String {
    let out = bin().args(args).output().unwrap();
    assert!(
        out.status.success(),
        "sceneinfo {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

/// A path in this test process' own temporary directory.
pub fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("sceneinfo-cli-test-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Writes a preset scene with `sceneinfo scene ARGS -o FILE` into the temporary folder.
pub fn preset(args: &[&str], file: &str) -> PathBuf {
    let path = temp(file);
    let st = bin()
        .arg("scene")
        .args(args)
        .arg("-o")
        .arg(&path)
        .status()
        .unwrap();
    assert!(st.success(), "scene {args:?}");
    path
}

/// Drops the keys whose values are wall-clock times from a flat JSON object.
pub fn without_timing(json: &str) -> String {
    json.split(',')
        .filter(|kv| !kv.contains("\"seconds\"") && !kv.contains("\"lines_per_second\""))
        .collect::<Vec<_>>()
        .join(",")
}

/// The number after `"key":` (NaN when it is not a number, e.g. `null`).
pub fn number(json: &str, key: &str) -> f64 {
    let at = json
        .find(&format!("\"{key}\":"))
        .unwrap_or_else(|| panic!("no {key} in {json}"));
    let rest = &json[at + key.len() + 3..];
    let end = rest.find([',', '}', ']']).unwrap();
    rest[..end].parse().unwrap_or(f64::NAN)
}

/// The array of numbers after `"key":`.
pub fn array(json: &str, key: &str) -> Vec<f64> {
    let at = json
        .find(&format!("\"{key}\":["))
        .unwrap_or_else(|| panic!("no {key} in {json}"));
    let rest = &json[at + key.len() + 4..];
    let end = rest.find(']').unwrap();
    rest[..end].split(',').map(|x| x.parse().unwrap()).collect()
}
