//! Compile-fail tests of `#[ffr::flex_body]`: each misuse is an error at the
//! offending token whose message says what is allowed (tests/ui/*.stderr).
//! Regenerate the expected output with `TRYBUILD=overwrite`.

use std::path::{Path, PathBuf};

/// The target directory as trybuild finds it (`cargo metadata`).
fn target_dir() -> PathBuf {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let out = std::process::Command::new(cargo)
        .args(["metadata", "--format-version", "1", "--no-deps"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("cargo metadata runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let meta: serde_json::Value = serde_json::from_slice(&out.stdout).expect("metadata is JSON");
    PathBuf::from(meta["target_directory"].as_str().expect("target_directory"))
}

#[test]
fn ui() {
    // trybuild compiles the cases as a crate of its own in
    // <target>/tests/trybuild/ffr, which is their CARGO_MANIFEST_DIR and so
    // where relative shape paths resolve: put the shape files there.
    let shapes = target_dir().join("tests/trybuild/ffr/shapes");
    std::fs::create_dir_all(&shapes).unwrap();
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/ui/shapes");
    for entry in std::fs::read_dir(&src).unwrap() {
        let path = entry.unwrap().path();
        std::fs::copy(&path, shapes.join(path.file_name().unwrap())).unwrap();
    }
    trybuild::TestCases::new().compile_fail("tests/ui/*.rs");
}
