//! Every file of the real-world corpus (`tests/data/corpus/`: OBJ/MTL, glTF, GLB and PLY
//! written by other people, sources and licences in its `SOURCES.md`) through the real
//! binary, as a user would run it:
//!
//! - `measure FILE --lines 1000000 --json` exits 0 with finite numbers; where every patch
//!   received a line, the rows of `F` sum to 1 within 1e-9 (the background state included);
//!   where some did not, the discrete measures are `null` and `I_S^c` is still given;
//! - `radiosity FILE --lines auto --max-lines 2^22 --json` either solves (finite, non-negative
//!   radiosities, each at most the largest emittance / (1 − 0.99), the bound of B = E + ρFB
//!   with ρ ≤ 0.99 and rows of F summing to at most 1) or refuses because some patch is still
//!   unreached, naming the lines that would reach it;
//! - the Cornell box, whose lamp is written the old way (`Ka 20 20 20`, no `Ke`), is lit with
//!   `--emit-from-ka`: the lamp is the brightest patch, every patch receives light, and the
//!   red and green walls send back only their colour.

mod common;

use std::path::{Path, PathBuf};

use common::{bin, number};

/// The corpus folder.
fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/corpus")
}

/// Every scene file of the corpus (not the MTL, binary buffers or pictures), sorted.
fn scene_files() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(&path, out);
            } else if path
                .extension()
                .and_then(|e| e.to_str())
                .is_some_and(|e| ["obj", "gltf", "glb", "ply"].contains(&e))
            {
                out.push(path);
            }
        }
    }
    let mut files = Vec::new();
    walk(&corpus(), &mut files);
    files.sort();
    files
}

/// `json` with every string literal (escapes included) replaced by `""`.
fn without_strings(json: &str) -> String {
    let mut out = String::with_capacity(json.len());
    let mut chars = json.chars();
    while let Some(c) = chars.next() {
        out.push(c);
        if c == '"' {
            // Skip to the closing quote, stepping over escaped characters
            while let Some(c) = chars.next() {
                match c {
                    '\\' => {
                        chars.next();
                    }
                    '"' => break,
                    _ => {}
                }
            }
            out.push('"');
        }
    }
    out
}

/// Checks the numbers of a JSON text: every token between separators that is not a string,
/// `true`, `false` or `null` must parse as a finite number (no NaN, no inf).
fn assert_finite_json(json: &str, what: &str) {
    let bare = without_strings(json);
    for token in bare.split([',', ':', '[', ']', '{', '}']) {
        let t = token.trim();
        if t.is_empty() || t.starts_with('"') || ["true", "false", "null"].contains(&t) {
            continue;
        }
        let v: f64 = t
            .parse()
            .unwrap_or_else(|_| panic!("{what}: not a number: {t:?} in {json}"));
        assert!(v.is_finite(), "{what}: {t} in {json}");
    }
}

/// The array after `"key":[` inside the object after `"radiosity":`.
fn radiosity_channel(json: &str, channel: &str) -> Vec<f64> {
    let at = json.find("\"radiosity\":{").expect("radiosity object");
    common::array(&json[at..], channel)
}

#[test]
fn the_corpus_holds_every_format() {
    let files = scene_files();
    for ext in ["obj", "gltf", "glb", "ply"] {
        assert!(
            files
                .iter()
                .any(|f| f.extension().is_some_and(|e| e == ext)),
            "no .{ext} file in the corpus"
        );
    }
    assert!(files.len() >= 20, "{} files", files.len());
    let sources = std::fs::read_to_string(corpus().join("SOURCES.md")).unwrap();
    for f in &files {
        let name = f.file_name().unwrap().to_str().unwrap();
        assert!(sources.contains(name), "{name} is not in SOURCES.md");
    }
}

#[test]
fn every_corpus_file_is_measured() {
    for file in scene_files() {
        let out = bin()
            .args(["measure", "--lines", "1000000", "--json"])
            .arg(&file)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{}: {stderr}", file.display());
        let json = String::from_utf8(out.stdout).unwrap();
        let what = file.display().to_string();
        assert_finite_json(&json, &what);
        assert!(number(&json, "n_patches") >= 1.0, "{what}: {json}");
        let i_c = number(&json, "i_s_continuous");
        assert!(i_c.is_finite(), "{what}: {json}");
        assert!(
            number(&json, "i_s_continuous_stderr").is_finite(),
            "{what}: {json}"
        );
        if json.contains("\"i_s\":null") {
            // Too few lines for some patch: said, with the lines that would reach it
            assert!(number(&json, "unsampled_patches") >= 1.0, "{what}: {json}");
            assert!(stderr.contains("received none"), "{what}: {stderr}");
        } else {
            let row_error = number(&json, "max_row_sum_error");
            assert!(row_error <= 1e-9, "{what}: rows off by {row_error}");
            assert!(number(&json, "i_s") >= 0.0, "{what}: {json}");
        }
    }
}

#[test]
fn every_corpus_file_is_lit_or_refused_with_the_lines_it_needs() {
    for file in scene_files() {
        let out = bin()
            .args([
                "radiosity",
                "--lines",
                "auto",
                "--max-lines",
                "4194304",
                "--json",
            ])
            .arg(&file)
            .output()
            .unwrap();
        let what = file.display().to_string();
        let stderr = String::from_utf8_lossy(&out.stderr);
        if !out.status.success() {
            assert_eq!(out.status.code(), Some(2), "{what}: {stderr}");
            assert!(
                stderr.contains("received none") && stderr.contains("--lines"),
                "{what}: {stderr}"
            );
            continue;
        }
        let json = String::from_utf8(out.stdout).unwrap();
        assert_finite_json(&json, &what);
        for channel in ["red", "green", "blue"] {
            let b = radiosity_channel(&json, channel);
            assert!(b.iter().all(|&x| x >= 0.0), "{what}: {channel} {b:?}");
        }
    }
}

#[test]
fn the_cornell_box_lamp_written_with_ka_lights_the_box() {
    let file = corpus().join("obj/cornell_box/cornell_box.obj");
    // Without the flag: nothing emits, said plainly, with the flag offered
    let dark = bin()
        .args(["radiosity", "--lines", "1000000"])
        .arg(&file)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&dark.stderr);
    assert!(dark.status.success(), "{stderr}");
    assert!(stderr.contains("--emit-from-ka"), "{stderr}");
    // With it: the lamp (E = 20) is the brightest patch and lights every other one
    let out = bin()
        .args([
            "radiosity",
            "--emit-from-ka",
            "--lines",
            "auto",
            "--max-lines",
            "16777216",
            "--json",
        ])
        .arg(&file)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let json = String::from_utf8(out.stdout).unwrap();
    assert_finite_json(&json, "cornell_box.obj");
    let [red, green, blue] = ["red", "green", "blue"].map(|c| radiosity_channel(&json, c));
    let max = red.iter().copied().fold(0.0, f64::max);
    // B = E + ρFB with ρ ≤ 0.99 and rows of F summing to 1: max B ≤ E / (1 − 0.99)
    assert!((20.0..=2000.0).contains(&max), "lamp {max}");
    // Every patch sends back light in the channels its colour reflects, but for the two
    // floor faces written under the blocks facing down (out of the box: they see nothing)
    let black = (0..red.len())
        .filter(|&k| red[k] + green[k] + blue[k] == 0.0)
        .count();
    assert!(
        black <= 2,
        "{black} black patches: {red:?} {green:?} {blue:?}"
    );
    // The red wall (Kd 1 0 0) sends back red only, the green wall (Kd 0 1 0) green only
    assert!(
        red.iter().zip(&green).any(|(r, g)| *r > 0.0 && *g == 0.0),
        "no red-only patch: {red:?} {green:?}"
    );
    assert!(
        green.iter().zip(&red).any(|(g, r)| *g > 0.0 && *r == 0.0),
        "no green-only patch"
    );
}
