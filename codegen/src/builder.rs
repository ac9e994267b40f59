//! `build.rs` integration in the style of `prost-build`: generate one Rust
//! file per body (or per kernel set) into `OUT_DIR`.
//!
//! ```no_run
//! // build.rs
//! use ffr_codegen::builder::{BodyConfig, Builder};
//! use ffr_codegen::{Formalism, Reference, Stiffening};
//!
//! fn main() {
//!     Builder::new()
//!         .body(BodyConfig::new("arm", "beam3", 8, Reference::Clamped)
//!             .stiffening(Stiffening::FourthOrder))
//!         .body(BodyConfig::new("bar", "shapes/bar.toml", 4, Reference::Clamped)
//!             .formalism(Formalism::Lumped))
//!         .compile()
//!         .unwrap_or_else(|e| panic!("{e}"));
//! }
//! ```
//!
//! and in the crate, `include!(concat!(env!("OUT_DIR"), "/arm.rs"));` defines
//! `pub struct Arm` (all parameter fields, `f64`) implementing
//! `ffr::runtime::CompiledBody`, and its element kernels `ArmKernels` — the
//! same code the `#[ffr::flex_body]` attribute expands to. Every option
//! belongs to the body it is given for.

use crate::body::{BodySpec, Formalism, Reference};
use crate::emit::{emit_body_file, emit_kernels_file, EmitOptions};
#[cfg(feature = "scene")]
use crate::emit::{emit_scene_file, SceneKernels, SceneSegments};
use crate::eom::KernelModel;
use crate::error::Error;
use crate::kernel::generate_checked;
use crate::sanitize::{check_identifier, check_type_name};
use crate::shape::Shape;
use ffr_spec::{FrameModel, KernelOptions, SceneDim, SectionModel, Stiffening};
use std::path::{Path, PathBuf};

/// One set of element kernels: a name, a shape and the options.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct KernelConfig {
    /// Name: the file is `<name>.rs`, the type the CamelCase of the name
    /// (plus `Kernels` for a body).
    pub name: String,
    /// A built-in shape (`beam2`, `beam3`) or a path to a shape file.
    pub shape: String,
    /// The options (default: consistent, no stiffening, the shape's scene,
    /// free frame).
    pub options: KernelOptions,
    /// A scene dimension other than 2 or 3 given to
    /// [`KernelConfig::scene_dim`], refused by [`KernelConfig::model`].
    pub invalid_scene_dim: Option<usize>,
    /// One uniform section (the body's parameters) or sections varying
    /// along the span (the kernels read element moments; the runtime's
    /// `KernelBody::with_sections` gives them from a section table).
    pub sections: SectionModel,
}

impl KernelConfig {
    /// Kernels for `shape`, consistent, no stiffening, the shape's own scene
    /// dimension, free frame.
    pub fn new(name: &str, shape: impl AsRef<str>) -> Self {
        Self {
            name: name.to_string(),
            shape: shape.as_ref().to_string(),
            options: KernelOptions::new(),
            invalid_scene_dim: None,
            sections: SectionModel::Uniform,
        }
    }
    /// Kernels for sections that vary along the span (a section table),
    /// or for one uniform section (the default).
    pub fn sections(mut self, s: SectionModel) -> Self {
        self.sections = s;
        self
    }
    /// All options at once.
    pub fn options(mut self, o: KernelOptions) -> Self {
        self.options = o;
        self
    }
    /// The inertia formalism.
    pub fn formalism(mut self, f: Formalism) -> Self {
        self.options.formalism = f;
        self
    }
    /// The stiffening model.
    pub fn stiffening(mut self, s: Stiffening) -> Self {
        self.options.stiffening = s;
        self
    }
    /// The scene (a planar shape in a spatial scene needs [`SceneDim::Spatial`]).
    pub fn scene(mut self, d: SceneDim) -> Self {
        self.options.scene = Some(d);
        self.invalid_scene_dim = None;
        self
    }
    /// The scene by its dimension, 2 or 3; any other number is an error
    /// when the kernels are generated ([`KernelConfig::model`]).
    pub fn scene_dim(mut self, d: usize) -> Self {
        match SceneDim::from_dim(d) {
            Some(s) => {
                self.invalid_scene_dim = None;
                self.scene(s)
            }
            None => {
                self.invalid_scene_dim = Some(d);
                self
            }
        }
    }
    /// What the kernels assume about the frame's motion.
    pub fn frame(mut self, f: FrameModel) -> Self {
        self.options.frame = f;
        self
    }
    /// Whether the body's frame moves freely (else: prescribed, keeping
    /// [`FrameModel::PrescribedAtRest`] if it was set).
    pub fn free_frame(mut self, on: bool) -> Self {
        let (_, at_rest) = self.options.frame.flags();
        self.options.frame = FrameModel::from_flags(on, at_rest);
        self
    }

    /// The kernel model, with relative shape paths resolved against `base`.
    pub fn model(&self, base: &Path) -> Result<KernelModel, Error> {
        if let Some(d) = self.invalid_scene_dim {
            return Err(Error::Body(format!(
                "kernels `{}`: the scene dimension must be 2 or 3, found {d}",
                self.name
            )));
        }
        let shape = resolve_shape(&self.shape, base)?;
        let model = KernelModel::new(shape, self.options).with_sections(self.sections);
        if model.scene_dim() < model.shape.dimension {
            return Err(Error::Body(format!(
                "shape `{}` is spatial: it needs a spatial scene (scene dimension 3)",
                model.shape.name
            )));
        }
        Ok(model)
    }
}

/// A body with a fixed mesh: kernels plus element count and reference.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyConfig {
    /// The kernels' options (the name is the body's).
    pub kernels: KernelConfig,
    /// Number of elements.
    pub elements: usize,
    /// Reference condition.
    pub reference: Reference,
    /// A section table (a CSV file's path relative to the crate root; see
    /// [`BodyConfig::sections`]), or `None`: the uniform section of the
    /// struct's parameters.
    pub sections: Option<String>,
    /// Also a modal body type ([`BodyConfig::modes`]): the parameters and
    /// the reduction.
    #[cfg(feature = "modal")]
    pub modal: Option<(ffr_spec::Params, ffr_spec::scene::ModalSettings)>,
}

impl BodyConfig {
    /// `elements` equal elements of `shape` (a built-in name or a path to a
    /// `.toml` shape file, relative to the crate root) with the given
    /// reference condition, consistent formalism, no stiffening. It is
    /// written to `<name>.rs` and its type is the CamelCase of `name`
    /// (`two_link_arm` → `TwoLinkArm`), so `name` must be a Rust identifier.
    pub fn new(name: &str, shape: impl AsRef<str>, elements: usize, reference: Reference) -> Self {
        Self {
            kernels: KernelConfig::new(name, shape),
            elements,
            reference,
            sections: None,
            #[cfg(feature = "modal")]
            modal: None,
        }
    }
    /// Also generate `<Type>Modal`, the body at parameters `p` reduced as
    /// `settings` say (modal truncation to `settings.modes` normal modes, or
    /// Craig–Bampton on `settings.boundary`; static modes and modal damping
    /// as in a scene file): the basis and the projected invariants are
    /// computed here, at build time, and baked in as constants; its `body()`
    /// is the runtime's modal body over this body at `p` (docs/modal.md,
    /// "Generated modal bodies"). Uniform bodies only (no section table).
    #[cfg(feature = "modal")]
    pub fn modes(mut self, p: ffr_spec::Params, settings: ffr_spec::scene::ModalSettings) -> Self {
        self.modal = Some((p, settings));
        self
    }
    /// Sections that vary along the span, from the CSV file `path`
    /// (relative to the crate root; the columns of a scene's section table,
    /// `docs/scenes.md`): the kernels are generated for varying sections and
    /// the table is baked into the type (`CompiledBody::SECTIONS`); the body
    /// runs it on `elements` equal elements (`KernelBody::compiled`). Its
    /// length is the last station's x; the struct's parameters are not read.
    pub fn sections(mut self, path: impl AsRef<str>) -> Self {
        self.sections = Some(path.as_ref().to_string());
        self.kernels = self.kernels.sections(SectionModel::Varying);
        self
    }
    /// All kernel options at once.
    pub fn options(mut self, o: KernelOptions) -> Self {
        self.kernels.options = o;
        self
    }
    /// The inertia formalism.
    pub fn formalism(mut self, f: Formalism) -> Self {
        self.kernels = self.kernels.formalism(f);
        self
    }
    /// The stiffening model.
    pub fn stiffening(mut self, s: Stiffening) -> Self {
        self.kernels = self.kernels.stiffening(s);
        self
    }
    /// The scene.
    pub fn scene(mut self, d: SceneDim) -> Self {
        self.kernels = self.kernels.scene(d);
        self
    }
    /// The scene by its dimension ([`KernelConfig::scene_dim`]).
    pub fn scene_dim(mut self, d: usize) -> Self {
        self.kernels = self.kernels.scene_dim(d);
        self
    }
    /// What the kernels assume about the frame's motion.
    pub fn frame(mut self, f: FrameModel) -> Self {
        self.kernels = self.kernels.frame(f);
        self
    }
    /// Whether the body's frame moves freely ([`KernelConfig::free_frame`]).
    pub fn free_frame(mut self, on: bool) -> Self {
        self.kernels = self.kernels.free_frame(on);
        self
    }
}

#[derive(Clone, Debug)]
enum Entry {
    Body(BodyConfig),
    Kernels(KernelConfig),
    #[cfg(feature = "scene")]
    Scene {
        name: String,
        path: String,
    },
}

impl Entry {
    fn name(&self) -> &str {
        match self {
            Entry::Body(b) => &b.kernels.name,
            Entry::Kernels(k) => &k.name,
            #[cfg(feature = "scene")]
            Entry::Scene { name, .. } => name,
        }
    }
    /// The files the entry is generated from, resolved against `base`: a
    /// shape file, or a scene file and the shape files it names (as far as
    /// the scene file can be read; a file that cannot is still listed, so
    /// that fixing it reruns the build).
    fn inputs(&self, base: &Path) -> Vec<PathBuf> {
        let shape_file = |s: &str, dir: &Path| {
            (Shape::builtin(s).is_none() && looks_like_path(s)).then(|| dir.join(s))
        };
        match self {
            Entry::Body(BodyConfig {
                kernels: k,
                sections,
                ..
            }) => shape_file(&k.shape, base)
                .into_iter()
                .chain(sections.iter().map(|p| base.join(p)))
                .collect(),
            Entry::Kernels(k) => shape_file(&k.shape, base).into_iter().collect(),
            #[cfg(feature = "scene")]
            Entry::Scene { path, .. } => {
                let file = base.join(path);
                let dir = file.parent().map(Path::to_path_buf).unwrap_or_default();
                let mut out = vec![file.clone()];
                if let Ok(raw) =
                    crate::scene::read(&file).and_then(|text| crate::scene::parse(&text, path))
                {
                    out.extend(
                        raw.bodies
                            .values()
                            .filter_map(|b| b.shape.as_ref())
                            .filter_map(|s| shape_file(s.get_ref(), &dir)),
                    );
                }
                out
            }
        }
    }
}

/// `snake` in CamelCase: each `_`-separated part with its first letter
/// capitalized (`two_link_arm` → `TwoLinkArm`).
pub fn camel_case(snake: &str) -> String {
    snake
        .split('_')
        .map(|part| {
            let mut c = part.chars();
            let first = c.next().map(|f| f.to_ascii_uppercase());
            first.into_iter().chain(c).collect::<String>()
        })
        .collect()
}

/// `name` in snake case (`ArmScene` → `arm_scene`, `two-link arm` → `two_link_arm`).
pub fn snake_case(name: &str) -> String {
    let mut out = String::new();
    for (i, ch) in name.chars().enumerate() {
        if ch.is_ascii_uppercase() {
            if i > 0 && !out.ends_with('_') {
                out.push('_');
            }
            out.push(ch.to_ascii_lowercase());
        } else if ch.is_ascii_alphanumeric() {
            out.push(ch);
        } else if !out.ends_with('_') {
            out.push('_');
        }
    }
    out.trim_matches('_').to_string()
}

/// Generates FFR code from a build script (see the [module docs](self)).
#[derive(Clone, Debug)]
#[must_use = "a Builder does nothing until `compile` (or `render`) is called"]
pub struct Builder {
    entries: Vec<Entry>,
    out_dir: Option<PathBuf>,
    manifest_dir: Option<PathBuf>,
    runtime_path: String,
    rerun_if_changed: bool,
}

impl Default for Builder {
    fn default() -> Self {
        Self::new()
    }
}

/// One generated file, before it is written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GeneratedFile {
    /// The name given (e.g. `two_link_arm`).
    pub name: String,
    /// The generated type (CamelCase of the name, e.g. `TwoLinkArm`; for
    /// kernels only, `TwoLinkArm` is the kernel type).
    pub type_name: String,
    /// The file name in the output directory (`<name>.rs`).
    pub file_name: String,
    /// The formatted Rust source.
    pub contents: String,
    /// The files the code was generated from: its shape file (none for a
    /// built-in shape), or a scene file and the shape files it names.
    pub inputs: Vec<PathBuf>,
}

impl Builder {
    /// A builder without bodies; output goes to `OUT_DIR`, relative shape
    /// paths are resolved against `CARGO_MANIFEST_DIR`, generated code refers
    /// to the runtime as `::ffr::runtime`.
    pub fn new() -> Self {
        Self {
            entries: Vec::new(),
            out_dir: None,
            manifest_dir: None,
            runtime_path: EmitOptions::default().runtime_path,
            rerun_if_changed: true,
        }
    }

    /// Add a body with a fixed mesh.
    pub fn body(mut self, body: BodyConfig) -> Self {
        self.entries.push(Entry::Body(body));
        self
    }

    /// Add a scene file (relative to the crate root): the specialized kernels
    /// of its flexible bodies and a scene type (the CamelCase of the file
    /// stem plus `Scene`, e.g. `ArmScene` for `scenes/arm.toml`, in
    /// `arm.rs`) whose `spec()` is the scene resolved at build time, as data,
    /// and whose `load()` builds it with these kernels (no file is parsed at
    /// start-up; the crate needs `ffr`'s feature `scene`): it simulates bit
    /// for bit like `ffr run` on the file. A body run as segments
    /// (`segments = N`) gets its root segment's kernels (named by the body,
    /// also those of the whole body) and one set shared by its outboard
    /// segments `NAME[2]` … `NAME[N]` (free frames), and a modal body one
    /// reduction per distinct segment besides the whole body's.
    #[cfg(feature = "scene")]
    pub fn scene(self, path: impl AsRef<str>) -> Self {
        let p = path.as_ref().to_string();
        let stem = Path::new(&p)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "scene".into());
        let name = snake_case(&stem);
        self.scene_named(&name, p)
    }

    /// [`Builder::scene`] with an explicit name (file `<name>.rs`, type
    /// CamelCase of `name` plus `Scene`).
    #[cfg(feature = "scene")]
    pub fn scene_named(mut self, name: &str, path: impl AsRef<str>) -> Self {
        self.entries.push(Entry::Scene {
            name: name.to_string(),
            path: path.as_ref().to_string(),
        });
        self
    }

    /// Add element kernels only (the mesh is chosen at run time with
    /// `ffr_runtime::KernelBody::new`).
    pub fn kernels(mut self, kernels: KernelConfig) -> Self {
        self.entries.push(Entry::Kernels(kernels));
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

    /// Generate every entry without writing anything (for snapshot tests of
    /// the generated code; [`Builder::compile`] writes exactly these contents).
    pub fn render(&self) -> Result<Vec<GeneratedFile>, Error> {
        let base = self.base_dir();
        let mut seen: Vec<(&str, String)> = Vec::new();
        let mut files = Vec::new();
        for entry in &self.entries {
            let name = entry.name();
            let type_name = type_name_of(name)?;
            if let Some((other, _)) = seen.iter().find(|(n, t)| *n == name || *t == type_name) {
                return Err(Error::Body(format!(
                    "bodies `{other}` and `{name}` would both define `{type_name}`: names must differ"
                )));
            }
            seen.push((name, type_name.clone()));
            let contents = match entry {
                Entry::Body(b) => {
                    let model = b.kernels.model(&base)?;
                    let spec = BodySpec::new(model.shape.clone(), b.elements, b.reference)?
                        .with_formalism(b.kernels.options.formalism);
                    let set = generate_checked(&model)?;
                    let sections = match &b.sections {
                        None => None,
                        Some(p) => Some(body_stations(&base, p, name, model.shape.dimension)?),
                    };
                    let opts = EmitOptions {
                        type_name: type_name.clone(),
                        define_struct: true,
                        runtime_path: self.runtime_path.clone(),
                        sections,
                    };
                    #[cfg(feature = "modal")]
                    if let Some((p, settings)) = &b.modal {
                        let bad = |e: String| Error::Body(format!("body `{name}`: {e}"));
                        if b.sections.is_some() {
                            return Err(bad("a modal body of a section table cannot be generated yet (reduce it in a scene file)".into()));
                        }
                        crate::limits::check_params(p, &set.params_used())
                            .map_err(|e| bad(e.to_string()))?;
                        let modal = crate::modal::ModalModel::of_body(
                            &spec,
                            p,
                            settings,
                            b.kernels.options.stiffening,
                        )
                        .map_err(|e| bad(e.to_string()))?;
                        files.push(GeneratedFile {
                            name: name.to_string(),
                            type_name,
                            file_name: format!("{name}.rs"),
                            contents: crate::emit::emit_modal_body_file(
                                &set, &spec, &opts, &modal, p,
                            )?,
                            inputs: entry.inputs(&base),
                        });
                        continue;
                    }
                    emit_body_file(&set, &spec, &opts)
                }
                Entry::Kernels(k) => {
                    let set = generate_checked(&k.model(&base)?)?;
                    emit_kernels_file(&set, &type_name, &self.runtime_path)
                }
                #[cfg(feature = "scene")]
                Entry::Scene { path, .. } => generate_scene(
                    &base.join(path),
                    path,
                    &format!("{type_name}Scene"),
                    &self.runtime_path,
                )?,
            };
            files.push(GeneratedFile {
                name: name.to_string(),
                type_name,
                file_name: format!("{name}.rs"),
                contents,
                inputs: entry.inputs(&base),
            });
        }
        Ok(files)
    }

    /// Generate every entry and write `<name>.rs` into the output directory
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

    /// `cargo:rerun-if-changed=…` for every input file of every entry.
    fn rerun_lines(&self) -> Vec<String> {
        let base = self.base_dir();
        let mut lines: Vec<String> = Vec::new();
        for f in self.entries.iter().flat_map(|e| e.inputs(&base)) {
            let line = format!("cargo:rerun-if-changed={}", f.display());
            if !lines.contains(&line) {
                lines.push(line);
            }
        }
        lines
    }
}

/// The compiled form of the scene file at `path` (named `origin` as
/// written): read, parse, check and resolve it, generate the specialized kernels of
/// each flexible body (shape files resolved against the scene file's
/// directory) and emit them with the scene type `type_name`
/// ([`emit_scene_file`]).
#[cfg(feature = "scene")]
pub fn generate_scene(
    path: &Path,
    origin: &str,
    type_name: &str,
    runtime_path: &str,
) -> Result<String, Error> {
    let text = crate::scene::read(path)?;
    let raw = crate::scene::parse(&text, origin)?;
    crate::scene::check(&raw, &text, origin)?;
    let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
    let spec = crate::scene::resolve(&raw, &text, origin, &dir)?;
    if let Some(f) = spec.bodies.iter().find_map(|b| match &b.kind {
        ffr_spec::scene::BodyKind::Fe(f) => Some(f),
        _ => None,
    }) {
        return Err(Error::Scene {
            location: f.fe_at.clone(),
            message: format!(
                "FE body `{}`: a compiled scene does not take FE bodies yet (their matrices are read when the scene is loaded); run the scene file with `ffr run` or `ffr::scene::load`",
                f.name
            ),
        });
    }
    let flex = |name: &str| {
        spec.bodies.iter().find_map(|b| match &b.kind {
            ffr_spec::scene::BodyKind::Flexible(f) if f.name == name => Some(f),
            _ => None,
        })
    };
    let mut bodies = Vec::new();
    let mut segments = Vec::new();
    for m in crate::scene::flex_models(&raw, &text, origin)? {
        let shape = resolve_shape(&m.shape, &dir)?;
        let f = flex(&m.name);
        // Varying-section kernels for a body the scene resolves to a
        // section table (a uniform material table is `params`).
        let sections = if f.is_some_and(|f| f.sections.is_some()) {
            SectionModel::Varying
        } else {
            SectionModel::Uniform
        };
        // A body run as segments: its outboard segments are clamped with
        // free frames (`FlexSpec::segment`), all alike, so they share one
        // kernel set: the body's own when its frame is free too.
        if let Some(f) = f.filter(|f| f.segments > 1) {
            let options = f.segment(1).options;
            let kernels = if options == m.options {
                None
            } else {
                Some(generate_checked(
                    &KernelModel::new(shape.clone(), options).with_sections(sections),
                )?)
            };
            segments.push(SceneSegments {
                body: m.name.clone(),
                names: (1..f.segments).map(|k| f.segment_name(k)).collect(),
                kernels,
            });
        }
        bodies.push((
            m.name,
            generate_checked(&KernelModel::new(shape, m.options).with_sections(sections))?,
        ));
    }
    let modal = scene_modal_bodies(&spec, type_name, runtime_path)?;
    let scene = SceneKernels {
        origin,
        text: &text,
        spec: &spec,
        bodies,
        segments,
        modal,
    };
    emit_scene_file(&scene, type_name, runtime_path)
}

/// The modal bodies of a scene reduced now, as `ModalConsts` expressions
/// (equal elements of one section, no attached masses: the others are
/// reduced when the scene is built, as `ffr run` does), and the generated
/// inertia kernels of those with at most `MAX_GENERATED_MODES` modes. A
/// body run as segments has one reduction per distinct segment (each is
/// reduced by Craig–Bampton with its outboard cut as a boundary node, so
/// the root's and the last's differ from the others': `FlexSpec::segment`)
/// besides the whole body's (for `modes`, `invariants`; it has the root
/// segment's name, so its arm asks for its elements). A reduction that
/// fails is an error naming the body or segment and where `modes` is
/// written.
#[cfg(all(feature = "scene", feature = "modal"))]
fn scene_modal_bodies(
    spec: &ffr_spec::scene::SceneSpec,
    type_name: &str,
    runtime_path: &str,
) -> Result<Vec<crate::emit::SceneModal>, Error> {
    let scene = ffr_spec::SceneDim::from_dim(spec.dim)
        .ok_or_else(|| Error::Body(format!("a scene of dimension {}, not 2 or 3", spec.dim)))?;
    let mut out = Vec::new();
    for b in &spec.bodies {
        let ffr_spec::scene::BodyKind::Flexible(f) = &b.kind else {
            continue;
        };
        if f.modal.is_none() || f.nodes.is_some() || f.sections.is_some() || !f.masses.is_empty() {
            continue;
        }
        // What to reduce: (spec, names served, elements asked for, the
        // constant's name, the inertia kernels' type).
        #[allow(clippy::type_complexity)]
        let mut todo: Vec<(
            ffr_spec::scene::FlexSpec,
            Vec<String>,
            Option<usize>,
            String,
            String,
        )> = Vec::new();
        let whole = ffr_spec::scene::FlexSpec {
            segments: 1,
            ..f.clone()
        };
        todo.push((
            whole,
            vec![f.name.clone()],
            (f.segments > 1).then_some(f.elements),
            "MODAL".into(),
            crate::emit::scene_modal_kernels_type(type_name, &f.name),
        ));
        if f.segments > 1 {
            // Equal segments (all but their names) share one reduction.
            let mut groups: Vec<(usize, ffr_spec::scene::FlexSpec, Vec<String>)> = Vec::new();
            for k in 0..f.segments {
                let s = f.segment(k);
                let key = ffr_spec::scene::FlexSpec {
                    name: String::new(),
                    ..s.clone()
                };
                match groups.iter_mut().find(|(_, g, _)| *g == key) {
                    Some((_, _, names)) => names.push(s.name),
                    None => groups.push((k, key, vec![s.name])),
                }
            }
            for (k, s, names) in groups {
                let s = ffr_spec::scene::FlexSpec {
                    name: f.segment_name(k),
                    ..s
                };
                todo.push((
                    s,
                    names,
                    None,
                    format!("MODAL_SEGMENT_{}", k + 1),
                    crate::emit::scene_segment_modal_kernels_type(type_name, &f.name, k + 1),
                ));
            }
        }
        for (s, names, elements, konst, kt) in todo {
            let Some((settings, at)) = &s.modal else {
                continue;
            };
            let what = if konst == "MODAL" {
                format!("body `{}`", s.name)
            } else {
                format!("segment `{}`", s.name)
            };
            let bad = |e: String| Error::Body(format!("{at}: {what}: {e}"));
            // The scene resolved the shape's path against its directory
            // already; read it as the runtime's reduction does
            // (`ReducibleBody::from_parts`).
            let shape = Shape::resolve(&s.shape, None)?;
            let body =
                BodySpec::new(shape, s.elements, s.reference)?.with_formalism(s.options.formalism);
            let model =
                crate::modal::ModalModel::of_body(&body, &s.params, settings, s.options.stiffening)
                    .map_err(|e| bad(e.to_string()))?;
            let description = crate::emit::modal_description(&model, &body, &s.params);
            let consts = crate::emit::modal_consts(&model, &description, runtime_path)?;
            let kernels = crate::modal::generate_modal_kernels(&model, scene)
                .map_err(|e| bad(e.to_string()))?
                .map(|set| {
                    let items = crate::emit::scene_modal_kernel_items(
                        &set,
                        type_name,
                        &what,
                        &kt,
                        runtime_path,
                    );
                    (kt, items)
                });
            out.push(crate::emit::SceneModal {
                body: f.name.clone(),
                konst,
                names,
                elements,
                consts,
                kernels,
            });
        }
    }
    Ok(out)
}

/// Without the `modal` feature a compiled scene's modal bodies are reduced
/// when it is built.
#[cfg(all(feature = "scene", not(feature = "modal")))]
fn scene_modal_bodies(
    _: &ffr_spec::scene::SceneSpec,
    _: &str,
    _: &str,
) -> Result<Vec<crate::emit::SceneModal>, Error> {
    Ok(Vec::new())
}

/// The stations of a body's section table ([`crate::sections::body_stations`]).
#[cfg(feature = "sections")]
pub(crate) fn body_stations(
    base: &Path,
    path: &str,
    name: &str,
    dim: usize,
) -> Result<Vec<ffr_spec::scene::Station>, Error> {
    crate::sections::body_stations(base, path, name, dim)
}

/// Without the `sections` feature no table can be read.
#[cfg(not(feature = "sections"))]
pub(crate) fn body_stations(
    _: &Path,
    path: &str,
    name: &str,
    _: usize,
) -> Result<Vec<ffr_spec::scene::Station>, Error> {
    Err(Error::Body(format!(
        "body `{name}`: the section table `{path}` needs the feature `sections` (of `ffr` for `#[flex_body]`, of `ffr-codegen` in a build script)"
    )))
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
    let camel = camel_case(name);
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
            .body(
                BodyConfig::new("arm", "beam2", 2, Reference::Clamped)
                    .stiffening(Stiffening::FourthOrder),
            )
            .body(
                BodyConfig::new("my_bar", "shapes/bar.toml", 3, Reference::Pinned)
                    .formalism(Formalism::Lumped),
            );
        let paths = b.compile().unwrap();
        assert_eq!(paths, vec![out.join("arm.rs"), out.join("my_bar.rs")]);
        let bar = std::fs::read_to_string(&paths[1]).unwrap();
        assert!(bar.contains("pub struct MyBar {"), "{bar}");
        assert!(bar.contains("shape `bar` (shapes/bar.toml, fnv1a"), "{bar}");
        assert!(bar.contains("lumped formalism"), "{bar}");
        let arm = std::fs::read_to_string(&paths[0]).unwrap();
        assert!(
            arm.contains("stiffening FourthOrder") || arm.contains("stiffening fourth-order"),
            "{arm}"
        );
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
        assert_eq!(rendered[1].inputs, [dir.join("shapes/bar.toml")]);
        assert!(rendered[0].inputs.is_empty());
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
            err(Builder::new().body(BodyConfig::new("arm", "beam3", 0, Reference::Clamped))),
            "invalid body: elements must be at least 1, found 0"
        );
        assert_eq!(
            err(Builder::new().body(BodyConfig::new("arm", "beam4", 2, Reference::Clamped))),
            "unknown shape `beam4`: expected one of beam2, beam3, or a path to a .toml shape file"
        );
        assert_eq!(
            err(Builder::new().body(BodyConfig::new("arm", "bad.toml", 2, Reference::Clamped))),
            "bad.toml:2:13: dimension must be 2 (planar) or 3 (spatial), found 4"
        );
        assert!(err(Builder::new().body(BodyConfig::new(
            "arm",
            "missing.toml",
            2,
            Reference::Clamped
        )))
        .starts_with(&format!("{}: ", dir.join("missing.toml").display())));
        assert!(
            err(Builder::new().body(BodyConfig::new("arm-1", "beam3", 2, Reference::Clamped)))
                .contains("body name `arm-1` is not a Rust identifier")
        );
        assert!(err(Builder::new()
            .body(BodyConfig::new("arm", "beam3", 2, Reference::Clamped))
            .body(BodyConfig::new("arm", "beam2", 2, Reference::Clamped)))
        .contains("bodies `arm` and `arm` would both define `Arm`"));
        assert!(!dir.join("out").exists());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
