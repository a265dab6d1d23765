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

/// `out`, after checking the run succeeded (else its stderr is shown).
pub fn succeeded(out: std::process::Output) -> std::process::Output {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// A path in this test process' own temporary directory.
pub fn temp(name: &str) -> PathBuf {
    static DIR: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    let dir = DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("sceneinfo-cli-test-{}", std::process::id()));
        // Process ids are reused: a folder of this name left by a dead test process would
        // hand this one its files (a test asserting that a refused job wrote nothing then
        // fails), so each test process starts from an empty folder.
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    });
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

/// Runs `cmd` to its end, or kills it and fails the test after `limit`: a hang is a test
/// failure, not a stuck test run. Standard output and error go to files (a child that
/// writes much never blocks on a full pipe) and come back in the [`std::process::Output`].
pub fn output_within(cmd: &mut Command, limit: std::time::Duration) -> std::process::Output {
    let (out_path, err_path) = (temp_unique("stdout"), temp_unique("stderr"));
    let mut child = cmd
        .stdout(std::fs::File::create(&out_path).unwrap())
        .stderr(std::fs::File::create(&err_path).unwrap())
        .spawn()
        .unwrap();
    let status = wait_within(&mut child, limit);
    std::process::Output {
        status,
        stdout: std::fs::read(&out_path).unwrap(),
        stderr: std::fs::read(&err_path).unwrap(),
    }
}

/// Waits for `child`, polling every 20 ms; kills it and fails the test after `limit`.
pub fn wait_within(
    child: &mut std::process::Child,
    limit: std::time::Duration,
) -> std::process::ExitStatus {
    let deadline = std::time::Instant::now() + limit;
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status;
        }
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("sceneinfo still running after {limit:?}: killed");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// A fresh path in the temporary folder (a counter keeps parallel tests apart).
pub fn temp_unique(stem: &str) -> PathBuf {
    static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    temp(&format!("{stem}-{k}"))
}
