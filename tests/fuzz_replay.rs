//! Replays the fuzz inputs: the seed corpus `fuzz/seeds/<target>/` and the saved failures
//! `tests/data/fuzz/<target>/` (regex `tests/fuzz/mod.rs`), each through the very check the
//! fuzz target runs, compiled in here by `#[path]`. A new crash found by `cargo fuzz` goes
//! into `tests/data/fuzz/<target>/` and stays replayed by `cargo test` from then on.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};

#[path = "../fuzz/src/channel.rs"]
mod channel;
#[path = "../fuzz/src/flat_parse.rs"]
mod flat_parse;
#[path = "../fuzz/src/flat_pipeline.rs"]
mod flat_pipeline;
#[path = "../fuzz/src/invariants.rs"]
mod invariants;
#[path = "../fuzz/src/obj_parse.rs"]
mod obj_parse;
#[path = "../fuzz/src/obj_pipeline.rs"]
mod obj_pipeline;
#[path = "../fuzz/src/refine.rs"]
mod refine;

/// Directories holding one sub-directory of inputs per fuzz target.
fn corpus_roots() -> [PathBuf; 2] {
    let tests = Path::new(env!("CARGO_MANIFEST_DIR"));
    [tests.join("../fuzz/seeds"), tests.join("data/fuzz")]
}

/// The input files under `root/<target>/`, as `(target, path)` pairs; files whose names
/// start with `.` (e.g. `.gitkeep`) are skipped.
fn inputs(root: &Path) -> Vec<(String, PathBuf)> {
    let mut found = Vec::new();
    let Ok(targets) = std::fs::read_dir(root) else {
        return found;
    };
    for target in targets {
        let target = target.expect("readable directory entry").path();
        if !target.is_dir() {
            continue;
        }
        let name = target.file_name().unwrap().to_string_lossy().into_owned();
        for file in std::fs::read_dir(&target).expect("readable corpus directory") {
            let path = file.expect("readable directory entry").path();
            let hidden = path.file_name().unwrap().to_string_lossy().starts_with('.');
            if path.is_file() && !hidden {
                found.push((name.clone(), path));
            }
        }
    }
    found.sort();
    found
}

/// Runs one input through the check of its target; whether it went through every stage
/// (`Measured` / `Checked`) rather than being refused or skipped.
///
/// # Panics
///
/// When the invariant breaks, or the directory names no known target.
fn replay(target: &str, data: &[u8]) -> bool {
    use invariants::Outcome::Checked;
    match target {
        "fuzz_flat_parse" => flat_parse::check(data) == flat_parse::Outcome::Measured,
        "fuzz_obj_parse" => obj_parse::check(data) == Checked,
        "fuzz_flat_pipeline" => flat_pipeline::check(data) == Checked,
        "fuzz_obj_pipeline" => obj_pipeline::check(data) == Checked,
        "fuzz_channel" => channel::check(data) == Checked,
        "fuzz_refine" => refine::check(data) == Checked,
        other => panic!("no replay for fuzz target {other:?}: add it to tests/fuzz_replay.rs"),
    }
}

#[test]
fn fuzz_inputs_replay_without_panics() {
    // Gather every input of every target
    let [seeds, saved] = corpus_roots();
    let seed_inputs = inputs(&seeds);
    assert!(
        seed_inputs.len() >= 10,
        "expected at least 10 seed inputs under {}, found {}",
        seeds.display(),
        seed_inputs.len()
    );
    let all = seed_inputs.into_iter().chain(inputs(&saved));

    // Replay each one, collecting failures so one run reports all of them
    let mut failures = Vec::new();
    let mut count = 0;
    let mut complete: std::collections::BTreeMap<String, usize> = Default::default();
    for (target, path) in all {
        count += 1;
        let data = std::fs::read(&path).expect("readable input");
        match catch_unwind(AssertUnwindSafe(|| replay(&target, &data))) {
            Ok(through) => *complete.entry(target).or_default() += usize::from(through),
            Err(_) => failures.push(path.display().to_string()),
        }
    }
    // Every target has seeds that go all the way through its pipeline
    for (target, n) in &complete {
        assert!(*n > 0, "no input of {target} passes every stage");
    }
    assert_eq!(complete.len(), 6, "targets replayed: {complete:?}");
    assert!(
        failures.is_empty(),
        "{} of {count} fuzz inputs failed:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

#[test]
fn check_json_rejects_non_finite_values() {
    let good = r#"{"n_patches":3,"h_p":1.5,"h_s":1,"h_j":2.5,"i_s":0.5,"h_s_norm":0.1,"i_s_norm":0.2,"e_mse":0,"fano":0,"closed":true,"rows":[1,2e-3]}"#;
    assert_eq!(flat_parse::check_json(good, 3), Ok(()));
    assert!(
        flat_parse::check_json(good, 4).is_err(),
        "n_patches mismatch"
    );
    for bad in ["NaN", "inf", "-inf", "null", "Infinity"] {
        let json = good.replace("\"fano\":0", &format!("\"fano\":{bad}"));
        assert!(
            flat_parse::check_json(&json, 3).is_err(),
            "{json} must be rejected"
        );
        let json = good.replace("2e-3", bad);
        assert!(
            flat_parse::check_json(&json, 3).is_err(),
            "{json} must be rejected"
        );
    }
    let missing = good.replace("\"h_j\":2.5,", "");
    assert!(flat_parse::check_json(&missing, 3).is_err(), "missing key");
}

#[test]
fn oversized_and_non_utf8_inputs_are_rejected() {
    let big = vec![b'#'; flat_parse::MAX_INPUT_BYTES + 1];
    assert_eq!(flat_parse::check(&big), flat_parse::Outcome::Rejected);
    assert_eq!(
        flat_parse::check(b"seg 0 0 1 0\xff"),
        flat_parse::Outcome::Rejected
    );
}
