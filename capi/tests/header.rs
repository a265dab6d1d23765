//! The committed C header, `capi/include/sceneinfo.h`, is cbindgen's output for `capi/src`
//! with `capi/cbindgen.toml`. Run with `SCENEINFO_WRITE_HEADER=1` to rewrite it after a
//! change to the Rust side (`scripts/capi.sh header` does).

use std::path::Path;

#[test]
fn the_committed_header_is_current() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = cbindgen::Config::from_file(dir.join("cbindgen.toml")).expect("cbindgen.toml");
    let bindings = cbindgen::Builder::new()
        .with_crate(dir)
        .with_config(config)
        .generate()
        .expect("cbindgen parses capi/src");
    let mut generated = Vec::new();
    bindings.write(&mut generated);
    let path = dir.join("include/sceneinfo.h");
    if std::env::var_os("SCENEINFO_WRITE_HEADER").is_some() {
        std::fs::write(&path, &generated).expect("write the header");
        return;
    }
    let committed = std::fs::read(&path).expect("capi/include/sceneinfo.h");
    assert!(
        committed == generated,
        "{} is out of date: run `scripts/capi.sh header` (SCENEINFO_WRITE_HEADER=1 cargo test \
         -p sceneinfo-capi --test header) and commit it",
        path.display()
    );
}
