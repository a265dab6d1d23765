//! The module layers (issue 17): each core module may use only the modules below it in the
//! layer order written in `ARCHITECTURE.md` ("Layer order:"), and no CLI command may use
//! another command. Read from the sources as text (`crate::x` paths outside comments and
//! test modules), so a new upward edge fails here.
//!
//! The edges that break the order today are listed in [`KNOWN_CORE`] and [`KNOWN_CLI`], each
//! with what removes it; an entry that no longer occurs fails too, so the lists only shrink.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

/// Upward core edges that exist today, to be removed (issue 17).
const KNOWN_CORE: &[(&str, &str, &str)] = &[];
/// CLI commands that use another command today (issue 17: none left — shared CLI code
/// lives beside `commands/`, in `output`, `lines`, `job`, `report`, `picture`, …; a
/// command's own helper files are its submodules).
const KNOWN_CLI: &[(&str, &str)] = &[];

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// The layer order: the backticked names of the line starting `Layer order:` in
/// ARCHITECTURE.md, lowest first.
fn layer_order() -> Vec<String> {
    let text = std::fs::read_to_string(root().join("ARCHITECTURE.md")).unwrap();
    let line = text
        .lines()
        .find(|l| l.starts_with("Layer order:"))
        .expect("ARCHITECTURE.md has a 'Layer order:' line");
    line.split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect()
}

/// The `.rs` files of a module: `dir/name.rs` and everything under `dir/name/`, test files
/// left out.
fn module_files(dir: &Path, name: &str) -> Vec<PathBuf> {
    let mut files = vec![dir.join(format!("{name}.rs"))];
    let mut stack = vec![dir.join(name)];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries {
            let p = e.unwrap().path();
            let file = p.file_name().unwrap().to_string_lossy().to_string();
            if p.is_dir() {
                if file != "tests" {
                    stack.push(p);
                }
            } else if file.ends_with(".rs") && file != "tests.rs" && file != "proptests.rs" {
                files.push(p);
            }
        }
    }
    files.retain(|f| f.exists());
    files
}

/// A source file's code: cut at its test module (`#[cfg(test)]` or `#[cfg(all(test, …))]`
/// then `mod`), comments removed.
fn code_of(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let mut out = String::new();
    let mut lines = text.lines().peekable();
    while let Some(line) = lines.next() {
        let t = line.trim_start();
        if (t.starts_with("#[cfg(test)]") || t.starts_with("#[cfg(all(test"))
            && lines
                .peek()
                .is_some_and(|n| n.trim_start().starts_with("mod ") || n.contains(" mod "))
        {
            break;
        }
        let code = line.split("//").next().unwrap_or("");
        out.push_str(code);
        out.push('\n');
    }
    out
}

/// The first path segments after each `prefix` in `code` (`crate::a::b` → `a`; the names of
/// a `crate::{a, b::c}` group → `a`, `b`).
fn segments_after(code: &str, prefix: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let ident = |s: &str| -> String {
        s.chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect()
    };
    for (at, _) in code.match_indices(prefix) {
        let rest = &code[at + prefix.len()..];
        if let Some(group) = rest.strip_prefix('{') {
            let body = &group[..group.find('}').unwrap_or(group.len())];
            for item in body.split(',') {
                let name = ident(item.trim());
                if !name.is_empty() {
                    out.insert(name);
                }
            }
        } else {
            let name = ident(rest);
            if !name.is_empty() {
                out.insert(name);
            }
        }
    }
    out
}

#[test]
fn core_modules_use_only_the_layers_below_them() {
    let order = layer_order();
    let src = root().join("core/src");
    let mut modules: Vec<String> = std::fs::read_dir(&src)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .filter_map(|f| f.strip_suffix(".rs").map(str::to_string))
        .filter(|m| m != "lib")
        .collect();
    modules.sort();
    let unplaced: Vec<&String> = modules.iter().filter(|m| !order.contains(m)).collect();
    assert!(
        unplaced.is_empty(),
        "core modules missing from ARCHITECTURE.md's 'Layer order:' line: {unplaced:?}"
    );
    // And the line names only core modules: one that left the core (`report`, `thesis`:
    // now the `sceneinfo-report` crate) leaves the line too.
    let stale: Vec<&String> = order.iter().filter(|m| !modules.contains(m)).collect();
    assert!(
        stale.is_empty(),
        "ARCHITECTURE.md's 'Layer order:' line names modules the core does not have: {stale:?}"
    );
    let rank = |m: &str| order.iter().position(|x| x == m);
    let mut upward = BTreeSet::new();
    for m in &modules {
        for file in module_files(&src, m) {
            for d in segments_after(&code_of(&file), "crate::") {
                if let (Some(a), Some(b)) = (rank(m), rank(&d))
                    && b > a
                {
                    upward.insert((m.clone(), d));
                }
            }
        }
    }
    let known: BTreeSet<(String, String)> = KNOWN_CORE
        .iter()
        .map(|(a, b, _)| ((*a).to_string(), (*b).to_string()))
        .collect();
    let new: Vec<_> = upward.difference(&known).collect();
    let gone: Vec<_> = known.difference(&upward).collect();
    assert!(
        new.is_empty(),
        "core modules using a layer above them (order: {order:?}): {new:?}"
    );
    assert!(
        gone.is_empty(),
        "known upward edges no longer there: remove them from KNOWN_CORE: {gone:?}"
    );
}

#[test]
fn cli_commands_do_not_use_each_other() {
    let dir = root().join("cli/src/commands");
    let commands: BTreeSet<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().to_string())
        .filter_map(|f| f.strip_suffix(".rs").map(str::to_string))
        .collect();
    let mut edges = BTreeSet::new();
    for c in &commands {
        for file in module_files(&dir, c) {
            let code = code_of(&file);
            // `super::x` from commands/c.rs, `super::super::x` from commands/c/*.rs
            let nested = file.parent() != Some(dir.as_path());
            let mut used = segments_after(&code, "crate::commands::");
            let sup = if nested { "super::super::" } else { "super::" };
            used.extend(segments_after(&code, sup));
            if !nested {
                // `super::super::` also contains `super::`: only direct siblings count
                used.retain(|u| u != "super");
            }
            for u in used {
                if &u != c && commands.contains(&u) {
                    edges.insert((c.clone(), u));
                }
            }
        }
    }
    let known: BTreeSet<(String, String)> = KNOWN_CLI
        .iter()
        .map(|(a, b)| ((*a).to_string(), (*b).to_string()))
        .collect();
    let new: Vec<_> = edges.difference(&known).collect();
    let gone: Vec<_> = known.difference(&edges).collect();
    assert!(
        new.is_empty(),
        "CLI commands using another command: {new:?}"
    );
    assert!(
        gone.is_empty(),
        "known command edges no longer there: remove them from KNOWN_CLI: {gone:?}"
    );
}

#[test]
fn paths_are_read_as_the_compiler_reads_them() {
    let code = "use crate::{a, b::c};\nlet x = crate::d::e(); // crate::f\n";
    let got = segments_after(&code_of_text(code), "crate::");
    let want: BTreeSet<String> = ["a", "b", "d"].iter().map(|s| s.to_string()).collect();
    assert_eq!(got, want);
}

/// [`code_of`] for a text (the test above).
fn code_of_text(text: &str) -> String {
    let path = std::env::temp_dir().join(format!("layers-{}.rs", std::process::id()));
    std::fs::write(&path, text).unwrap();
    let code = code_of(&path);
    let _ = std::fs::remove_file(&path);
    code
}
