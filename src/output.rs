//! Files the command line writes: checked before a run (not a directory, no
//! two outputs on the same file), written atomically (a temporary file in the
//! same directory, then a rename, the temporary removed on any failure), with
//! errors that name the path; numbers in the shortest form that reads back
//! to the same `f64`.

use std::fmt;
use std::io::Write;
use std::path::{Component, Path, PathBuf};

/// A file that could not be written, or an output path that is not usable.
#[derive(Debug)]
pub struct OutputError {
    /// The path as given.
    pub path: PathBuf,
    /// What went wrong.
    pub message: String,
}

impl fmt::Display for OutputError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.path.display(), self.message)
    }
}

impl std::error::Error for OutputError {}

fn error(path: &Path, message: impl Into<String>) -> OutputError {
    OutputError {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// A number for a CSV file: the shortest decimal that reads back to the same
/// `f64` (Rust's `{:?}`), in exponent form for very small and very large
/// magnitudes (`1.2345e-25`, not 40 digits of `0.000…`: `{}` of an `f64`
/// never uses an exponent).
pub fn number(x: f64) -> String {
    format!("{x:?}")
}

/// Check an output path before a run: it must name a file (not a directory,
/// not end in `/` or `..`).
pub fn check_file_path(path: &Path, flag: &str) -> Result<(), OutputError> {
    if path.is_dir() {
        return Err(error(
            path,
            format!("is a directory: {flag} needs a file name (e.g. results/run.csv)"),
        ));
    }
    let s = path.as_os_str().to_string_lossy();
    if path.file_name().is_none() || s.ends_with('/') || s.ends_with(std::path::MAIN_SEPARATOR) {
        return Err(error(
            path,
            format!("does not name a file: {flag} needs a file name (e.g. results/run.csv)"),
        ));
    }
    Ok(())
}

/// `path` as an absolute path without `.` components and with its directory
/// resolved through symbolic links where it exists (for comparing outputs).
fn normalized(path: &Path) -> PathBuf {
    let abs = if path.is_absolute() {
        path.to_path_buf()
    } else {
        std::env::current_dir()
            .unwrap_or_else(|_| PathBuf::from("."))
            .join(path)
    };
    let mut out = PathBuf::new();
    for c in abs.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    if let (Some(dir), Some(name)) = (out.parent(), out.file_name()) {
        if let Ok(dir) = dir.canonicalize() {
            return dir.join(name);
        }
    }
    out
}

/// Refuse two outputs that would be the same file, e.g. `--csv x.svg` with
/// the plot going next to it as `x.svg`, or the same path for `--csv` and
/// `--svg`. `outputs` are `(flag, path)`.
pub fn check_distinct(outputs: &[(&str, &Path)]) -> Result<(), OutputError> {
    for (i, (flag_a, a)) in outputs.iter().enumerate() {
        for (flag_b, b) in &outputs[i + 1..] {
            if normalized(a) == normalized(b) {
                return Err(error(
                    a,
                    format!(
                        "{flag_a} and {flag_b} would both write this file: give them different paths"
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Write `contents` to `path` atomically: create the directory if needed,
/// write a temporary file next to the target and rename it over the target,
/// so that readers see the old file or the new one, never half a file. On any
/// failure the temporary file is removed and the error names `path`.
pub fn write_atomic(path: &Path, contents: &[u8]) -> Result<(), OutputError> {
    check_file_path(path, "the output")?;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    std::fs::create_dir_all(&dir).map_err(|e| {
        error(
            path,
            format!("cannot create the directory {}: {e}", dir.display()),
        )
    })?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let result = (|| -> std::io::Result<()> {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(contents)?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(error(path, format!("cannot write: {e}")));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("ffr-output-{tag}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn numbers_are_short_and_round_trip() {
        for x in [
            0.0,
            1.0,
            -0.5,
            0.1 + 0.2,
            1.2345678901234567e-25,
            -3.3e-7,
            6.02e23,
            f64::MIN_POSITIVE,
            f64::MAX,
        ] {
            let s = number(x);
            assert!(s.len() <= 24, "{s}");
            assert_eq!(s.parse::<f64>().unwrap(), x, "{s}");
        }
        assert_eq!(number(1.25e-25), "1.25e-25");
        assert_eq!(number(6.02e23), "6.02e23");
        assert_eq!(number(0.25), "0.25");
    }

    #[test]
    fn atomic_write_names_the_path_and_leaves_no_temporary() {
        let d = temp_dir("atomic");
        let f = d.join("sub/a.csv");
        write_atomic(&f, b"x\n").unwrap();
        assert_eq!(std::fs::read(&f).unwrap(), b"x\n");
        write_atomic(&f, b"y\n").unwrap();
        assert_eq!(std::fs::read(&f).unwrap(), b"y\n");
        // A directory in the way.
        let e = write_atomic(&d.join("sub"), b"z").unwrap_err().to_string();
        assert!(e.starts_with(&d.join("sub").display().to_string()), "{e}");
        assert!(e.contains("is a directory"), "{e}");
        // A file where the directory should be.
        let e = write_atomic(&f.join("b.csv"), b"z")
            .unwrap_err()
            .to_string();
        assert!(e.contains("a.csv/b.csv"), "{e}");
        let left: Vec<_> = std::fs::read_dir(d.join("sub"))
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(left, vec![std::ffi::OsString::from("a.csv")]);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn same_file_twice_is_refused() {
        let a = Path::new("out/x.svg");
        assert!(check_distinct(&[("--csv", a), ("--svg", Path::new("out/./x.svg"))]).is_err());
        assert!(check_distinct(&[("--csv", a), ("--svg", Path::new("out/y/../x.svg"))]).is_err());
        assert!(check_distinct(&[("--csv", Path::new("x.csv")), ("--svg", a)]).is_ok());
    }
}
