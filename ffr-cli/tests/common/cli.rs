//! Running the `ffr` binary (shared by the command-line tests).

use std::path::{Path, PathBuf};
use std::process::Command;

/// A fresh temporary directory `ffr-<prefix>-<tag>-<pid>` for one test.
pub fn temp_dir(prefix: &str, tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("ffr-{prefix}-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The path of `scenes/<name>` as a string argument.
pub fn scene(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../scenes")
        .join(name)
        .display()
        .to_string()
}

/// `p` as a string argument.
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Run `ffr args…`: (success, stdout, stderr). Never a panic (stderr is
/// checked) and the exit status is 0, 1 (our errors) or 2 (argument syntax,
/// from clap); 101 would be a panic.
pub fn ffr(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_ffr"))
        .args(args)
        .output()
        .expect("run ffr");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    assert!(
        matches!(out.status.code(), Some(0..=2)),
        "{args:?}: {:?}",
        out.status
    );
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr,
    )
}
