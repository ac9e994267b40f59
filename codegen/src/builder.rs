//! `build.rs` integration in the style of `prost-build`: generate one Rust
//! file per body into `OUT_DIR`.
//!
//! ```no_run
//! // build.rs
//! use ffr_codegen::{Builder, Formalism, Reference};
//!
//! fn main() {
//!     Builder::new()
//!         .body("arm", "beam3", 8, Reference::Clamped)
//!         .body("bar", "shapes/bar.toml", 4, Reference::Clamped)
//!         .formalism(Formalism::Lumped) // applies to `bar`, the last body added
//!         .compile()
//!         .unwrap_or_else(|e| panic!("{e}"));
//! }
//! ```
//!
//! and in the crate, `include!(concat!(env!("OUT_DIR"), "/arm.rs"));` defines
//! `pub struct Arm` (all parameter fields, `f64`) implementing
//! `ffr::runtime::FlexBody` and `CompiledBody` — the same code the
//! `#[ffr::flex_body]` attribute expands to.

use crate::body::{BodySpec, Formalism, Reference};
use crate::emit::{emit_file, EmitOptions};
use crate::error::Error;
use crate::generate::{generate, Options};
use crate::limits::check_literals;
use crate::sanitize::{check_identifier, check_type_name};
use crate::shape::Shape;
use std::path::{Path, PathBuf};

/// A body to generate: what [`Builder::body`] records.
#[derive(Clone, Debug)]
struct BodyConfig {
    name: String,
    shape: String,
    elements: usize,
    reference: Reference,
    formalism: Formalism,
    stiffening: bool,
}

/// Generates FFR body code from a build script (see the [module docs](self)).
#[derive(Clone, Debug)]
#[must_use = "a Builder does nothing until `compile` (or `render`) is called"]
pub struct Builder {
    bodies: Vec<BodyConfig>,
    out_dir: Option<PathBuf>,
    manifest_dir: Option<PathBuf>,
    runtime_path: String,
    rerun_if_changed: bool,
    misuse: Option<String>,
}

impl Default for Builder {
    fn default() -> Self {
        Self::new()
    }
}

/// One generated file, before it is written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GeneratedFile {
    /// The body name given to [`Builder::body`] (e.g. `two_link_arm`).
    pub name: String,
    /// The generated type (CamelCase of the name, e.g. `TwoLinkArm`).
    pub type_name: String,
    /// The file name in the output directory (`<name>.rs`).
    pub file_name: String,
    /// The formatted Rust source.
    pub contents: String,
    /// The shape file the body was generated from (`None` for a built-in shape).
    pub shape_file: Option<PathBuf>,
}

impl Builder {
    /// A builder without bodies; output goes to `OUT_DIR`, relative shape
    /// paths are resolved against `CARGO_MANIFEST_DIR`, generated code refers
    /// to the runtime as `::ffr::runtime`.
    pub fn new() -> Self {
        Self {
            bodies: Vec::new(),
            out_dir: None,
            manifest_dir: None,
            runtime_path: EmitOptions::default().runtime_path,
            rerun_if_changed: true,
            misuse: None,
        }
    }

    /// Add a body: `elements` equal elements of `shape` (a built-in name such
    /// as `beam3`, or a path to a `.toml` shape file, relative to the crate
    /// root) with the given reference condition, consistent formalism and no
    /// geometric stiffening. It is written to `<name>.rs` and its type is the
    /// CamelCase of `name` (`two_link_arm` → `TwoLinkArm`), so `name` must be
    /// a Rust identifier.
    pub fn body(
        mut self,
        name: &str,
        shape: impl AsRef<str>,
        elements: usize,
        reference: Reference,
    ) -> Self {
        self.bodies.push(BodyConfig {
            name: name.to_string(),
            shape: shape.as_ref().to_string(),
            elements,
            reference,
            formalism: Formalism::Consistent,
            stiffening: false,
        });
        self
    }

    fn last_body(&mut self, what: &str) -> Option<&mut BodyConfig> {
        if self.bodies.is_empty() && self.misuse.is_none() {
            self.misuse = Some(format!(
                "Builder::{what} applies to the last body added, but no body was added before it (call Builder::body first)"
            ));
        }
        self.bodies.last_mut()
    }

    /// The inertia formalism of the last body added (default: consistent).
    pub fn formalism(mut self, formalism: Formalism) -> Self {
        if let Some(b) = self.last_body("formalism") {
            b.formalism = formalism;
        }
        self
    }

    /// Whether the last body added gets geometric stiffening (default: no).
    pub fn stiffening(mut self, stiffening: bool) -> Self {
        if let Some(b) = self.last_body("stiffening") {
            b.stiffening = stiffening;
        }
        self
    }

    /// Write the files here instead of `OUT_DIR`.
    pub fn out_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.out_dir = Some(dir.into());
        self
    }

    /// Resolve relative shape paths against this directory instead of
    /// `CARGO_MANIFEST_DIR`.
    pub fn manifest_dir(mut self, dir: impl Into<PathBuf>) -> Self {
        self.manifest_dir = Some(dir.into());
        self
    }

    /// The path under which generated code finds the runtime crate
    /// (default `::ffr::runtime`; `::ffr_runtime` for a crate that depends on
    /// `ffr-runtime` directly).
    pub fn runtime_path(mut self, path: impl Into<String>) -> Self {
        self.runtime_path = path.into();
        self
    }

    /// Whether [`Builder::compile`] prints `cargo:rerun-if-changed` for every
    /// shape file (default: yes).
    pub fn emit_rerun_if_changed(mut self, on: bool) -> Self {
        self.rerun_if_changed = on;
        self
    }

    fn base_dir(&self) -> PathBuf {
        self.manifest_dir
            .clone()
            .or_else(|| std::env::var_os("CARGO_MANIFEST_DIR").map(PathBuf::from))
            .unwrap_or_else(|| PathBuf::from("."))
    }

    /// Generate every body without writing anything (for snapshot tests of
    /// the generated code; [`Builder::compile`] writes exactly these contents).
    pub fn render(&self) -> Result<Vec<GeneratedFile>, Error> {
        if let Some(m) = &self.misuse {
            return Err(Error::Body(m.clone()));
        }
        let base = self.base_dir();
        let mut seen: Vec<(&str, String)> = Vec::new();
        let mut files = Vec::new();
        for b in &self.bodies {
            let type_name = type_name_of(&b.name)?;
            if let Some((other, _)) = seen.iter().find(|(n, t)| *n == b.name || *t == type_name) {
                return Err(Error::Body(format!(
                    "bodies `{other}` and `{}` would both define `{type_name}`: body names must differ",
                    b.name
                )));
            }
            seen.push((&b.name, type_name.clone()));
            let shape = resolve_shape(&b.shape, &base)?;
            let shape_file = shape.path.clone();
            let spec = BodySpec::new(shape, b.elements, b.reference)?.with_formalism(b.formalism);
            let g = generate(
                &spec,
                Options {
                    stiffening: b.stiffening,
                },
            )?;
            check_literals(&g)?;
            let contents = emit_file(
                &g,
                &EmitOptions {
                    type_name: type_name.clone(),
                    define_struct: true,
                    runtime_path: self.runtime_path.clone(),
                },
            );
            files.push(GeneratedFile {
                name: b.name.clone(),
                type_name,
                file_name: format!("{}.rs", b.name),
                contents,
                shape_file,
            });
        }
        Ok(files)
    }

    /// Generate every body and write `<name>.rs` into the output directory
    /// (`OUT_DIR` unless [`Builder::out_dir`] was given). A file is written
    /// only when its contents change, through a temporary file and a rename,
    /// so an interrupted build never leaves half a file. Prints
    /// `cargo:rerun-if-changed` for every shape file. Returns the paths of
    /// the files.
    pub fn compile(&self) -> Result<Vec<PathBuf>, Error> {
        let out_dir = match &self.out_dir {
            Some(d) => d.clone(),
            None => std::env::var_os("OUT_DIR")
                .map(PathBuf::from)
                .ok_or_else(|| Error::Io {
                    path: "OUT_DIR".into(),
                    message: "not set: run from a build script or call Builder::out_dir".into(),
                })?,
        };
        let files = self.render();
        if self.rerun_if_changed {
            // Even when generation failed, so that fixing a shape file reruns it.
            for line in self.rerun_lines() {
                println!("{line}");
            }
        }
        let files = files?;
        std::fs::create_dir_all(&out_dir).map_err(|e| io_error(&out_dir, e))?;
        files
            .iter()
            .map(|f| {
                let path = out_dir.join(&f.file_name);
                write_if_changed(&path, f.contents.as_bytes())?;
                Ok(path)
            })
            .collect()
    }

    /// `cargo:rerun-if-changed=…` for each body whose shape is a file.
    fn rerun_lines(&self) -> Vec<String> {
        let base = self.base_dir();
        let mut lines: Vec<String> = self
            .bodies
            .iter()
            .filter(|b| Shape::builtin(&b.shape).is_none() && looks_like_path(&b.shape))
            .map(|b| format!("cargo:rerun-if-changed={}", base.join(&b.shape).display()))
            .collect();
        lines.dedup();
        lines
    }
}

fn looks_like_path(s: &str) -> bool {
    s.ends_with(".toml") || s.contains('/') || s.contains('\\')
}

/// Resolve a shape like [`Shape::resolve`] (relative paths against `base`),
/// but name a file as it was written — not as the joined path — in error
/// locations and in the generated header, so messages read like the CLI's and
/// generated files do not depend on where the crate is checked out.
/// [`Shape::path`] still holds the full path.
pub fn resolve_shape(name_or_path: &str, base: &Path) -> Result<Shape, Error> {
    match Shape::resolve(name_or_path, Some(base)) {
        Ok(mut shape) => {
            if shape.path.is_some() {
                shape.origin = name_or_path.to_string();
            }
            Ok(shape)
        }
        Err(Error::Shape {
            mut location,
            message,
        }) if looks_like_path(name_or_path) => {
            location.file = name_or_path.to_string();
            Err(Error::Shape { location, message })
        }
        Err(e) => Err(e),
    }
}

/// The generated type name of body `name`: its CamelCase, after checking
/// that `name` is a plain ASCII Rust identifier that is not a keyword (see
/// [`crate::sanitize::check_identifier`]) and that the CamelCase is a valid
/// type name.
pub fn type_name_of(name: &str) -> Result<String, Error> {
    check_identifier(name, "body name").map_err(|m| {
        Error::Name(format!(
            "{m} (a body name must be a Rust identifier, e.g. `arm` or `two_link_arm`)"
        ))
    })?;
    let camel: String = name
        .split('_')
        .filter(|part| !part.is_empty())
        .map(|part| {
            let mut c = part.chars();
            let first = c.next().map(|f| f.to_ascii_uppercase());
            first.into_iter().chain(c).collect::<String>()
        })
        .collect();
    if camel.is_empty() {
        return Err(Error::Name(format!(
            "body name `{name}` has no letters or digits for its type name (expected e.g. `arm` or `two_link_arm`)"
        )));
    }
    check_type_name(&camel, "type name").map_err(|m| {
        Error::Name(format!(
            "body name `{name}` gives a type name that is not allowed: {m}"
        ))
    })?;
    Ok(camel)
}

fn io_error(path: &Path, e: std::io::Error) -> Error {
    Error::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// Write `contents` to `path` unless it already holds exactly that; through a
/// temporary file in the same directory and a rename (atomic on one file
/// system). Returns whether the file was written.
pub fn write_if_changed(path: &Path, contents: &[u8]) -> Result<bool, Error> {
    if std::fs::read(path).is_ok_and(|old| old == contents) {
        return Ok(false);
    }
    let dir = path.parent().unwrap_or(Path::new("."));
    let file_name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let tmp = dir.join(format!(".{file_name}.{}.tmp", std::process::id()));
    let result = (|| {
        use std::io::Write;
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(contents)?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(io_error(path, e));
    }
    Ok(true)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!(
            "ffr-builder-{tag}-{}-{:?}",
            std::process::id(),
            std::thread::current().id()
        ));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    const BAR: &str = r#"name = "bar"
dimension = 2
coordinates = [
  { name = "u1", node = 0, kind = "ux" },
  { name = "v1", node = 0, kind = "uy" },
  { name = "u2", node = 1, kind = "ux" },
  { name = "v2", node = 1, kind = "uy" },
]
[S]
x = ["1 - xi", "0", "xi", "0"]
y = ["0", "1 - xi", "0", "xi"]
"#;

    #[test]
    fn type_names() {
        assert_eq!(type_name_of("arm").unwrap(), "Arm");
        assert_eq!(type_name_of("two_link_arm").unwrap(), "TwoLinkArm");
        assert_eq!(type_name_of("arm_2").unwrap(), "Arm2");
        for bad in [
            "", "2arm", "my-arm", "arm.rs", "self", "r#arm", "_", "self_", "fn", "gen", "ärm", "__",
        ] {
            let e = type_name_of(bad).unwrap_err().to_string();
            assert!(e.starts_with(&format!("body name `{bad}`")), "{e}");
        }
    }

    #[test]
    fn writes_once_atomically_and_reports_shape_files() {
        let dir = temp_dir("write");
        std::fs::create_dir_all(dir.join("shapes")).unwrap();
        std::fs::write(dir.join("shapes/bar.toml"), BAR).unwrap();
        let out = dir.join("out");
        let b = Builder::new()
            .manifest_dir(&dir)
            .out_dir(&out)
            .body("arm", "beam2", 2, Reference::Clamped)
            .stiffening(true)
            .body("my_bar", "shapes/bar.toml", 3, Reference::Pinned)
            .formalism(Formalism::Lumped);
        let paths = b.compile().unwrap();
        assert_eq!(paths, vec![out.join("arm.rs"), out.join("my_bar.rs")]);
        let bar = std::fs::read_to_string(&paths[1]).unwrap();
        assert!(bar.contains("pub struct MyBar {"), "{bar}");
        assert!(bar.contains("shape `bar` (shapes/bar.toml, fnv1a"), "{bar}");
        assert!(bar.contains("lumped formalism"), "{bar}");
        let arm = std::fs::read_to_string(&paths[0]).unwrap();
        assert!(arm.contains("fn has_stiffening(&self) -> bool"), "{arm}");
        assert_eq!(
            b.rerun_lines(),
            vec![format!(
                "cargo:rerun-if-changed={}",
                dir.join("shapes/bar.toml").display()
            )]
        );
        // Same contents: not rewritten.
        let before = std::fs::metadata(&paths[0]).unwrap().modified().unwrap();
        std::thread::sleep(std::time::Duration::from_millis(20));
        b.compile().unwrap();
        let after = std::fs::metadata(&paths[0]).unwrap().modified().unwrap();
        assert_eq!(before, after);
        assert!(!write_if_changed(&paths[0], arm.as_bytes()).unwrap());
        // Changed contents: replaced, and no temporary file is left behind.
        assert!(write_if_changed(&paths[0], b"// old").unwrap());
        b.compile().unwrap();
        assert_eq!(std::fs::read_to_string(&paths[0]).unwrap(), arm);
        let mut names: Vec<String> = std::fs::read_dir(&out)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names, ["arm.rs", "my_bar.rs"]);
        // The render is exactly what was written.
        let rendered = b.render().unwrap();
        assert_eq!(rendered[0].contents, arm);
        assert_eq!(rendered[1].type_name, "MyBar");
        assert_eq!(
            rendered[1].shape_file.as_deref(),
            Some(dir.join("shapes/bar.toml").as_path())
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn errors_read_like_the_cli() {
        let dir = temp_dir("errors");
        std::fs::write(
            dir.join("bad.toml"),
            BAR.replace("dimension = 2", "dimension = 4"),
        )
        .unwrap();
        let err = |b: Builder| {
            b.manifest_dir(&dir)
                .out_dir(dir.join("out"))
                .compile()
                .unwrap_err()
                .to_string()
        };
        assert_eq!(
            err(Builder::new().body("arm", "beam3", 0, Reference::Clamped)),
            "invalid body: elements must be at least 1, found 0"
        );
        assert_eq!(
            err(Builder::new().body("arm", "beam4", 2, Reference::Clamped)),
            "unknown shape `beam4`: expected one of beam2, beam3, or a path to a .toml shape file"
        );
        assert_eq!(
            err(Builder::new().body("arm", "bad.toml", 2, Reference::Clamped)),
            "bad.toml:2:13: dimension must be 2 (planar) or 3 (spatial), found 4"
        );
        assert!(
            err(Builder::new().body("arm", "missing.toml", 2, Reference::Clamped))
                .starts_with(&format!("{}: ", dir.join("missing.toml").display()))
        );
        assert!(
            err(Builder::new().body("arm-1", "beam3", 2, Reference::Clamped))
                .contains("body name `arm-1` is not a Rust identifier")
        );
        assert!(err(Builder::new()
            .body("arm", "beam3", 2, Reference::Clamped)
            .body("arm", "beam2", 2, Reference::Clamped))
        .contains("bodies `arm` and `arm` would both define `Arm`"));
        assert!(err(Builder::new()
            .stiffening(true)
            .body("arm", "beam3", 2, Reference::Clamped))
        .contains("Builder::stiffening applies to the last body added"));
        assert!(!dir.join("out").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
