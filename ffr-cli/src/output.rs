//! Files the command line writes, and its standard output.
//!
//! Outputs are checked before a run: each path must name a file (not a
//! directory, not end in `/` or `..`), be a regular file or not exist yet
//! (a character or block device, a FIFO or a socket is refused: the rename
//! below would replace it, or writing to it could block or fail; a symbolic
//! link is followed, and the regular file it points to is replaced, the link
//! kept), lie in a directory that exists or can be created and is writable,
//! and no two outputs may be the same file. They are written atomically: each
//! to a temporary file in its target's directory, every one of them first,
//! then all renamed over their targets, so that readers see the old files
//! or the new ones, never half a file, and a failure leaves no temporary and
//! no new file. Errors name the path. Writes to standard output go through
//! [`print()`] (and [`outln!`](crate::outln)), whose errors are reported as
//! `standard output: …` instead of a panic. Numbers are written in the
//! shortest form that reads back to the same `f64`.

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
        write!(
            f,
            "{}: {}",
            ffr_spec::text::path_text(&self.path.display().to_string()),
            self.message
        )
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

/// Whether `a` and `b` are the same file: the same path after
/// [`normalized`], the same file after resolving symbolic links, or (on
/// Unix) the same device and inode (a hard link).
fn same_file(a: &Path, b: &Path) -> bool {
    if normalized(a) == normalized(b) {
        return true;
    }
    if let (Ok(x), Ok(y)) = (a.canonicalize(), b.canonicalize()) {
        if x == y {
            return true;
        }
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (std::fs::metadata(a), std::fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
    false
}

/// Refuse an output that would replace an input of the command (`ffr
/// static scene.toml --csv scene.toml`): the same path, a symbolic or hard
/// link to it. `outputs` and `inputs` are `(flag or role, path)`.
pub fn check_not_inputs(
    outputs: &[(&str, &Path)],
    inputs: &[(&str, &Path)],
) -> Result<(), OutputError> {
    for (flag, out) in outputs {
        for (role, input) in inputs {
            if same_file(out, input) {
                return Err(error(
                    out,
                    format!(
                        "{flag} would overwrite {role}, an input of the command: give another path"
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Refuse an output that would replace a file of the ParaView series the
/// same command writes into `dir` (`DIR/STEM….pvd`, `DIR/STEM_….vtp`, see
/// docs/vtk.md): `ffr run s.toml --vtk out --csv out/s_0001.vtp`.
/// `outputs` are `(flag, path)`.
pub fn check_not_in_series(
    outputs: &[(&str, &Path)],
    dir: &Path,
    stem: &str,
) -> Result<(), OutputError> {
    let series_dir = normalized(&dir.join("x"));
    let series_dir = series_dir.parent();
    for (flag, out) in outputs {
        let n = normalized(out);
        let name = n
            .file_name()
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_default();
        let ext = n.extension().and_then(|e| e.to_str()).unwrap_or("");
        if n.parent() == series_dir
            && name.starts_with(stem)
            && (ext.eq_ignore_ascii_case("vtp") || ext.eq_ignore_ascii_case("pvd"))
        {
            return Err(error(
                out,
                format!("{flag} would replace a file of the --vtk series in the same directory: give another path"),
            ));
        }
    }
    Ok(())
}

/// Refuse to replace a file in a directory a command was given (`linearize
/// --out DIR`) unless ffr wrote it: an existing file must be a regular file
/// (a symbolic link is not followed out of the directory) whose contents
/// start with `mark`, the line every such file of ffr's starts with. A path
/// that does not exist yet is fine. `flag` names the option in messages.
pub fn check_marked(path: &Path, mark: &[u8], flag: &str) -> Result<(), OutputError> {
    use std::io::Read;
    let meta = match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(error(path, format!("cannot be examined: {e}"))),
        Ok(m) => m,
    };
    let t = meta.file_type();
    if t.is_symlink() {
        return Err(error(
            path,
            format!("is a symbolic link: {flag} does not follow links out of its directory; remove it or give another directory"),
        ));
    }
    if !t.is_file() {
        return Err(error(
            path,
            format!("is {}, not a file ffr wrote: {flag} replaces only its own files; remove it or give another directory", kind_of(&t)),
        ));
    }
    let mut head = Vec::with_capacity(mark.len());
    std::fs::File::open(path)
        .and_then(|f| f.take(mark.len() as u64).read_to_end(&mut head))
        .map_err(|e| error(path, format!("cannot be read: {e}")))?;
    if head != mark {
        return Err(error(
            path,
            format!("exists and was not written by ffr: {flag} replaces only its own files; remove it or give another directory"),
        ));
    }
    Ok(())
}

/// [`check_not_inputs`] against the files a scene is read from
/// (`ffr::scene::Scene::input_files`: the scene file, shape files, section
/// tables, FE files).
pub fn check_not_scene_files(
    outputs: &[(&str, &Path)],
    files: &[PathBuf],
) -> Result<(), OutputError> {
    let inputs: Vec<(&str, &Path)> = files
        .iter()
        .map(|p| ("a file the scene is read from", p.as_path()))
        .collect();
    check_not_inputs(outputs, &inputs)
}

/// What a file that is not a regular file is, for messages.
fn kind_of(t: &std::fs::FileType) -> &'static str {
    if t.is_dir() {
        "a directory"
    } else {
        ffr_codegen::limits::special_kind(t)
    }
}

/// The nearest ancestor of `dir` that exists (`dir` itself if it does).
fn existing_ancestor(dir: &Path) -> Option<&Path> {
    dir.ancestors()
        .map(|a| {
            if a.as_os_str().is_empty() {
                Path::new(".")
            } else {
                a
            }
        })
        .find(|a| std::fs::symlink_metadata(a).is_ok())
}

/// The directory of `path` (`.` for a bare file name).
fn dir_of(path: &Path) -> PathBuf {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Whether this process may create files in the existing directory `dir`.
#[cfg(unix)]
fn writable_dir(dir: &Path) -> bool {
    use std::os::unix::ffi::OsStrExt;
    let Ok(c) = std::ffi::CString::new(dir.as_os_str().as_bytes()) else {
        return false;
    };
    // SAFETY: `c` is a valid NUL-terminated string for the call's duration.
    unsafe { libc::access(c.as_ptr(), libc::W_OK | libc::X_OK) == 0 }
}

#[cfg(not(unix))]
fn writable_dir(dir: &Path) -> bool {
    std::fs::metadata(dir).is_ok_and(|m| !m.permissions().readonly())
}

/// Check that an output's directory exists or can be created: its nearest
/// existing ancestor must be a directory this process can write in.
fn check_dir(given: &Path, target: &Path) -> Result<(), OutputError> {
    let dir = dir_of(target);
    let Some(base) = existing_ancestor(&dir) else {
        return Ok(());
    };
    if !base.is_dir() {
        return Err(error(
            given,
            format!(
                "cannot create the directory {}: {} is not a directory",
                dir.display(),
                base.display()
            ),
        ));
    }
    if !writable_dir(base) {
        let what = if base == dir {
            format!("cannot create a file in the directory {}", dir.display())
        } else {
            format!(
                "cannot create the directory {} in {}",
                dir.display(),
                base.display()
            )
        };
        return Err(error(given, format!("{what}: permission denied")));
    }
    Ok(())
}

/// Check an output path before a run and return the file to replace: the
/// path itself when it is a regular file or does not exist, the file a
/// symbolic link points to when that is a regular file (the link is kept).
/// Anything else is refused with a message saying what it is (`is a
/// character device, not a regular file`); so is a directory that cannot be
/// created or written in. `flag` names the option in messages.
pub fn check_output(path: &Path, flag: &str) -> Result<PathBuf, OutputError> {
    check_file_path(path, flag)?;
    let refuse = |what: &str| {
        error(
            path,
            format!(
                "is {what}, not a regular file: {flag} is written only to a new path or over a regular file"
            ),
        )
    };
    let target = match std::fs::symlink_metadata(path) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => path.to_path_buf(),
        Err(e) => {
            // e.g. a file where a directory of the path should be
            check_dir(path, path)?;
            return Err(error(path, format!("cannot be examined: {e}")));
        }
        Ok(m) if m.file_type().is_file() => path.to_path_buf(),
        Ok(m) if m.file_type().is_symlink() => match std::fs::metadata(path) {
            Ok(t) if t.is_file() => std::fs::canonicalize(path)
                .map_err(|e| error(path, format!("cannot resolve the symbolic link: {e}")))?,
            Ok(t) => return Err(refuse(&format!("a symbolic link to {}", kind_of(&t.file_type())))),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                return Err(error(
                    path,
                    "is a symbolic link to a file that does not exist: not followed (remove the link or give another path)",
                ))
            }
            Err(e) => return Err(error(path, format!("cannot follow the symbolic link: {e}"))),
        },
        Ok(m) => return Err(refuse(kind_of(&m.file_type()))),
    };
    check_dir(path, &target)?;
    Ok(target)
}

/// Check every output of a command before it runs (see [`check_output`])
/// and that no two are the same file ([`check_distinct`]). `outputs` are
/// `(flag, path)`.
pub fn check_outputs(outputs: &[(&str, &Path)]) -> Result<(), OutputError> {
    for (flag, path) in outputs {
        check_output(path, flag)?;
    }
    check_distinct(outputs)
}

/// Write `contents` to `path` atomically ([`write_all_atomic`] with one file).
pub fn write_atomic(path: &Path, contents: &[u8]) -> Result<(), OutputError> {
    write_all_atomic(&[(path, contents)])
}

/// Write several files atomically and together: check every path again
/// ([`check_output`]), create the directories needed, write and sync every
/// file to a temporary file next to its target, and only then rename each
/// over its target. A failure before the renames leaves none of the new
/// files and no temporary; the error names the path. (A rename that fails
/// after others succeeded, which takes a change of the directory meanwhile,
/// is reported with the files already replaced.)
pub fn write_all_atomic(files: &[(&Path, &[u8])]) -> Result<(), OutputError> {
    let mut staged = Vec::with_capacity(files.len());
    for (path, contents) in files {
        let target = check_output(path, "the output")?;
        staged.push((*path, target.clone(), stage(path, &target, contents)?));
    }
    let mut done: Vec<String> = Vec::new();
    for (path, target, tmp) in staged.drain(..) {
        // Checked once more just before the rename replaces the target.
        if let Err(e) = check_output(path, "the output") {
            return Err(with_done(e, &done));
        }
        if let Err(e) = tmp.persist(&target) {
            return Err(with_done(
                error(path, format!("cannot write: {}", e.error)),
                &done,
            ));
        }
        done.push(path.display().to_string());
    }
    Ok(())
}

/// `e` with the list of files a multi-file write had already replaced.
fn with_done(mut e: OutputError, done: &[String]) -> OutputError {
    if !done.is_empty() {
        e.message
            .push_str(&format!(" (already written: {})", done.join(", ")));
    }
    e
}

/// `contents` in a synced temporary file in `target`'s directory (created
/// if needed), with the permissions of the file it replaces or, for a new
/// file, those the umask gives.
fn stage(
    path: &Path,
    target: &Path,
    contents: &[u8],
) -> Result<tempfile::NamedTempFile, OutputError> {
    let dir = dir_of(target);
    std::fs::create_dir_all(&dir).map_err(|e| {
        error(
            path,
            format!("cannot create the directory {}: {e}", dir.display()),
        )
    })?;
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let prefix = format!(".{name}.");
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(target).map_or(0o666, |m| m.permissions().mode() & 0o7777);
        builder.permissions(std::fs::Permissions::from_mode(mode));
    }
    let write = || -> std::io::Result<tempfile::NamedTempFile> {
        let mut tmp = builder.tempfile_in(&dir)?;
        tmp.write_all(contents)?;
        tmp.as_file().sync_all()?;
        Ok(tmp)
    };
    write().map_err(|e| error(path, format!("cannot write: {e}")))
}

/// What standard output is called in messages.
pub const STDOUT: &str = "standard output";

/// Write `text` to standard output and flush it. An error (`ffr emit >
/// /dev/full`, a closed standard output) is returned as `standard output:
/// cannot write: …` instead of the panic of `print!`. A reader that went
/// away (`ffr emit | head`) still ends the process by SIGPIPE (see
/// `main.rs`).
pub fn print(text: &str) -> Result<(), OutputError> {
    let mut out = std::io::stdout().lock();
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .map_err(|e| error(Path::new(STDOUT), format!("cannot write: {e}")))
}

/// `println!` through [`output::print`](crate::output::print): evaluates to
/// a `Result<(), OutputError>`, so callers write `outln!(…)?`.
#[macro_export]
macro_rules! outln {
    () => {
        $crate::output::print("\n")
    };
    ($($arg:tt)*) => {
        $crate::output::print(&format!("{}\n", format_args!($($arg)*)))
    };
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
    fn an_output_may_not_replace_an_input() {
        let d = temp_dir("inputs");
        let scene = d.join("s.toml");
        std::fs::write(&scene, b"x").unwrap();
        let other = d.join("out.csv");
        assert!(check_not_inputs(&[("--csv", &other)], &[("the scene file", &scene)]).is_ok());
        for same in [scene.clone(), d.join("./s.toml"), d.join("sub/../s.toml")] {
            let e = check_not_inputs(&[("--csv", &same)], &[("the scene file", &scene)])
                .unwrap_err()
                .to_string();
            assert!(e.contains("--csv would overwrite the scene file"), "{e}");
        }
        #[cfg(unix)]
        {
            let link = d.join("link.toml");
            std::os::unix::fs::symlink(&scene, &link).unwrap();
            let hard = d.join("hard.toml");
            std::fs::hard_link(&scene, &hard).unwrap();
            for p in [link, hard] {
                assert!(
                    check_not_inputs(&[("--csv", &p)], &[("the scene file", &scene)]).is_err(),
                    "{}",
                    p.display()
                );
            }
        }
        std::fs::remove_dir_all(&d).unwrap();
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

    /// A FIFO at `path` (unix).
    #[cfg(unix)]
    fn mkfifo(path: &Path) {
        use std::os::unix::ffi::OsStrExt;
        let c = std::ffi::CString::new(path.as_os_str().as_bytes()).unwrap();
        // SAFETY: a valid NUL-terminated path.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
    }

    #[cfg(unix)]
    #[test]
    fn special_files_are_refused_before_anything_is_written() {
        use std::os::unix::fs::FileTypeExt;
        // Was: the temporary file was renamed over /dev/null (as root).
        let null = Path::new("/dev/null");
        if std::fs::metadata(null).is_ok_and(|m| m.file_type().is_char_device()) {
            let e = check_output(null, "--csv").unwrap_err().to_string();
            assert_eq!(
                e,
                "/dev/null: is a character device, not a regular file: --csv is written only to a new path or over a regular file"
            );
            // write_atomic checks the same before it creates its temporary
            // (which would be in /dev) or renames anything.
            assert!(write_atomic(null, b"x").is_err());
            assert!(std::fs::metadata(null)
                .unwrap()
                .file_type()
                .is_char_device());
        }
        let d = temp_dir("special");
        let fifo = d.join("fifo");
        mkfifo(&fifo);
        let e = write_atomic(&fifo, b"x").unwrap_err().to_string();
        assert!(
            e.contains("fifo: is a FIFO (named pipe), not a regular file"),
            "{e}"
        );
        // A link to a FIFO is refused as well.
        std::os::unix::fs::symlink(&fifo, d.join("to-fifo")).unwrap();
        let e = check_output(&d.join("to-fifo"), "--svg")
            .unwrap_err()
            .to_string();
        assert!(e.contains("is a symbolic link to a FIFO"), "{e}");
        assert!(std::fs::symlink_metadata(&fifo)
            .unwrap()
            .file_type()
            .is_fifo());
        let mut left: Vec<_> = std::fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(left, ["fifo", "to-fifo"]);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn a_symbolic_link_is_followed_and_kept() {
        let d = temp_dir("symlink");
        std::fs::write(d.join("real.csv"), "old\n").unwrap();
        std::os::unix::fs::symlink("real.csv", d.join("link.csv")).unwrap();
        write_atomic(&d.join("link.csv"), b"new\n").unwrap();
        assert!(std::fs::symlink_metadata(d.join("link.csv"))
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(std::fs::read(d.join("real.csv")).unwrap(), b"new\n");
        // A link to nothing is not followed.
        std::os::unix::fs::symlink("absent.csv", d.join("dangling.csv")).unwrap();
        let e = write_atomic(&d.join("dangling.csv"), b"x")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("dangling.csv: is a symbolic link to a file that does not exist"),
            "{e}"
        );
        assert!(!d.join("absent.csv").exists());
        assert_eq!(
            std::fs::read_dir(&d).unwrap().count(),
            3,
            "no temporary left"
        );
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn several_files_are_written_all_or_none() {
        let d = temp_dir("all-or-none");
        std::fs::write(d.join("a.csv"), "old a\n").unwrap();
        mkfifo(&d.join("c.md"));
        let (a, b, c) = (d.join("a.csv"), d.join("b.svg"), d.join("c.md"));
        // The last path is unusable: nothing is replaced or created.
        let e = write_all_atomic(&[(&a, b"new a"), (&b, b"new b"), (&c, b"new c")])
            .unwrap_err()
            .to_string();
        assert!(e.contains("c.md: is a FIFO"), "{e}");
        assert_eq!(std::fs::read(&a).unwrap(), b"old a\n");
        assert!(!b.exists());
        assert_eq!(
            std::fs::read_dir(&d).unwrap().count(),
            2,
            "no temporary left"
        );
        // And checked before a run, with the flag named.
        let e = check_outputs(&[("--csv", &a), ("--svg", &c)])
            .unwrap_err()
            .to_string();
        assert!(e.contains("--svg is written only to a new path"), "{e}");
        std::fs::remove_file(&c).unwrap();
        write_all_atomic(&[(&a, b"new a"), (&b, b"new b"), (&c, b"new c")]).unwrap();
        assert_eq!(std::fs::read(&c).unwrap(), b"new c");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 3);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn a_replaced_file_keeps_its_permissions() {
        use std::os::unix::fs::PermissionsExt;
        let d = temp_dir("mode");
        let f = d.join("run.csv");
        std::fs::write(&f, "x").unwrap();
        std::fs::set_permissions(&f, std::fs::Permissions::from_mode(0o640)).unwrap();
        write_atomic(&f, b"y").unwrap();
        let mode = std::fs::metadata(&f).unwrap().permissions().mode() & 0o777;
        assert_eq!(mode, 0o640);
        std::fs::remove_dir_all(&d).unwrap();
    }

    #[test]
    fn a_file_in_place_of_the_directory_is_found_before_a_run() {
        let d = temp_dir("parent");
        std::fs::write(d.join("file"), "x").unwrap();
        let e = check_output(&d.join("file/sub/run.csv"), "--csv")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("file/sub/run.csv: cannot create the directory"),
            "{e}"
        );
        assert!(e.ends_with("file is not a directory"), "{e}");
        assert!(check_output(&d.join("new/sub/run.csv"), "--csv").is_ok());
        assert!(!d.join("new").exists(), "the check creates nothing");
        assert!(check_output(Path::new("run.csv"), "--csv").is_ok());
        std::fs::remove_dir_all(&d).unwrap();
    }
}
