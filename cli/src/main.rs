//! The `sceneinfo` command line.
fn main() {}
