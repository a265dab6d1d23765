//! The check behind the `fuzz_flat_parse` target: `.flat` text → `parse_flat` → (small
//! scenes) `measure_flat_json`, asserting the invariant stated in
//! `fuzz/fuzz_targets/fuzz_flat_parse.rs`.
//!
//! This file is compiled twice: by the fuzz crate and, through `#[path]`, by the
//! integration tests (`tests/fuzz_replay.rs`). It depends on nothing but `sceneinfo` and
//! `std`.

use core::fmt;

/// Largest input, in bytes, the check accepts; longer inputs are [`Outcome::Rejected`].
pub const MAX_INPUT_BYTES: usize = 4096;

/// Largest scene, in patches, that is also measured (exact form factors cost O(n³)).
pub const MAX_MEASURED_PATCHES: usize = 64;

/// Keys that every `measure_flat_json` object holds, each a finite number.
pub const REQUIRED_KEYS: [&str; 9] = [
    "n_patches",
    "h_p",
    "h_s",
    "h_j",
    "i_s",
    "h_s_norm",
    "i_s_norm",
    "e_mse",
    "fano",
];

/// How far an input got through the pipeline (all of these are fine; a broken invariant
/// panics instead).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Too long or not UTF-8: not worth keeping in the corpus.
    Rejected,
    /// `parse_flat` returned a typed error.
    ParseError,
    /// Parsed, but has more than [`MAX_MEASURED_PATCHES`] patches, so was not measured.
    TooLarge,
    /// Parsed, but `measure_flat_json` returned a typed error (e.g. a degenerate channel).
    MeasureError,
    /// Parsed and measured; the JSON passed every check.
    Measured,
}

/// One fuzz case; its `Debug` output is a Rust reproducer (regex `fuzz_regex_match.rs`).
pub struct FlatCase<'a>(pub &'a str);

impl fmt::Debug for FlatCase<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "reproducer:")?;
        writeln!(f, "    let text = {:?};", self.0)?;
        writeln!(f, "    let scene = sceneinfo::io::parse_flat(text);")?;
        write!(
            f,
            "    let json = sceneinfo_report::measure_flat_json(text);"
        )
    }
}

/// Runs one input through the pipeline, panicking if the invariant breaks.
///
/// # Panics
///
/// When the core panics, returns an empty error message, or returns JSON that lacks a
/// required key, disagrees on `n_patches` or holds a non-finite number.
pub fn check(data: &[u8]) -> Outcome {
    // Cheap rejections first
    if data.len() > MAX_INPUT_BYTES {
        return Outcome::Rejected;
    }
    let Ok(text) = core::str::from_utf8(data) else {
        return Outcome::Rejected;
    };
    let case = FlatCase(text);

    // Parse; errors must explain themselves
    let scene = match sceneinfo::io::parse_flat(text) {
        Ok(scene) => scene,
        Err(err) => {
            let message = err.to_string();
            assert!(!message.is_empty(), "empty parse error message\n{case:?}");
            return Outcome::ParseError;
        }
    };
    let n_patches = scene.patches().len();
    if n_patches > MAX_MEASURED_PATCHES {
        return Outcome::TooLarge;
    }

    // Measure the small scenes; the JSON must be complete and finite
    let json = match sceneinfo_report::measure_flat_json(text) {
        Ok(json) => json,
        Err(err) => {
            let message = err.to_string();
            assert!(!message.is_empty(), "empty measure error message\n{case:?}");
            return Outcome::MeasureError;
        }
    };
    if let Err(problem) = check_json(&json, n_patches) {
        panic!("{problem}\njson: {json}\n{case:?}");
    }
    Outcome::Measured
}

/// Checks a `measure_flat_json` result: a JSON object with every [`REQUIRED_KEYS`] key,
/// `n_patches` equal to `n_patches`, and only finite numbers (no `NaN`, `inf`, `null`).
///
/// # Errors
///
/// Describes the first problem found.
pub fn check_json(json: &str, n_patches: usize) -> Result<(), String> {
    let trimmed = json.trim();
    if !(trimmed.starts_with('{') && trimmed.ends_with('}')) {
        return Err("not a JSON object".into());
    }
    for key in REQUIRED_KEYS {
        match value_of(trimmed, key) {
            None => return Err(format!("missing key {key:?}")),
            Some(v) if !v.parse::<f64>().is_ok_and(f64::is_finite) => {
                return Err(format!("key {key:?} is not a finite number: {v}"));
            }
            Some(_) => {}
        }
    }
    let found = value_of(trimmed, "n_patches").unwrap_or_default();
    if found.parse::<f64>().ok() != Some(n_patches as f64) {
        return Err(format!(
            "n_patches = {found}, but the scene has {n_patches} patches"
        ));
    }

    // Every bare (unquoted) token must be a finite number or a boolean
    for token in bare_tokens(trimmed) {
        let ok =
            token == "true" || token == "false" || token.parse::<f64>().is_ok_and(f64::is_finite);
        if !ok {
            return Err(format!(
                "bad JSON value {token:?} (NaN, inf and null are not allowed)"
            ));
        }
    }
    Ok(())
}

/// The bare value after `"key":` at any depth, if present.
fn value_of<'a>(json: &'a str, key: &str) -> Option<&'a str> {
    let pattern = format!("\"{key}\"");
    let after = &json[json.find(&pattern)? + pattern.len()..];
    let after = after.trim_start().strip_prefix(':')?.trim_start();
    let end = after.find([',', '}', ']']).unwrap_or(after.len());
    Some(after[..end].trim())
}

/// Unquoted tokens of a JSON text (numbers, literals), skipping strings and punctuation.
fn bare_tokens(json: &str) -> Vec<&str> {
    let mut tokens = Vec::new();
    let bytes = json.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            // A string: skip to its closing quote, honouring escapes
            b'"' => {
                i += 1;
                while i < bytes.len() && bytes[i] != b'"' {
                    i += if bytes[i] == b'\\' { 2 } else { 1 };
                }
                i += 1;
            }
            b'{' | b'}' | b'[' | b']' | b',' | b':' | b' ' | b'\t' | b'\n' | b'\r' => i += 1,
            _ => {
                let start = i;
                while i < bytes.len() && !b"{}[],: \t\n\r\"".contains(&bytes[i]) {
                    i += 1;
                }
                tokens.push(&json[start..i]);
            }
        }
    }
    tokens
}
