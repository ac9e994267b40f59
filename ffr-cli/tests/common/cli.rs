//! Running the `ffr` binary (shared by the command-line tests).

use std::process::Command;

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
