//! The `#[flex_body]` attribute's one call into the generator (as
//! `serde_derive` calls its backend): the attribute parses its options and
//! the struct, [`expand`] resolves the shape, generates the kernels and
//! emits the code, and the attribute checks the struct's fields against
//! [`FlexBody::params_used`] and expands.

use crate::body::BodySpec;
use crate::builder::resolve_shape;
use crate::emit::{body_items, EmitOptions};
use crate::eom::KernelModel;
use crate::error::Error;
use crate::kernel::generate_checked;
use crate::poly::Param;
use ffr_spec::{KernelOptions, Reference};
use std::path::{Path, PathBuf};

/// What the attribute asks for.
#[derive(Clone, Debug)]
pub struct FlexBodyInput<'a> {
    /// The shape as written: a built-in name or a path to a shape file.
    pub shape: &'a str,
    /// The directory a relative shape path is resolved against (the crate
    /// root, `CARGO_MANIFEST_DIR`).
    pub base: &'a Path,
    /// Number of elements.
    pub elements: usize,
    /// Reference condition.
    pub reference: Reference,
    /// A section table: a CSV file's path relative to `base` (the kernels
    /// are generated for varying sections and the table baked into the
    /// type); `None`: the uniform section of the struct's parameters.
    pub sections: Option<&'a str>,
    /// The kernel options (scene `None`: the shape's).
    pub options: KernelOptions,
    /// The user's struct: the generated impls are for it, its kernels are
    /// `{type_name}Kernels`.
    pub type_name: &'a str,
    /// Path of the runtime crate as the generated code sees it.
    pub runtime_path: &'a str,
    /// Also `{type_name}Modal`: the body at these parameters reduced as the
    /// settings say ([`crate::BodyConfig::modes`]); needs the feature
    /// `modal`.
    pub modal: Option<(ffr_spec::Params, ffr_spec::scene::ModalSettings)>,
    /// `segments = N`: also `{type_name}::segments()`, the body split into
    /// `N` segments for `System::add_segments` (uniform sections, not
    /// modal).
    pub segments: Option<usize>,
}

/// The generated code and what the attribute checks the struct against.
#[derive(Clone, Debug)]
pub struct FlexBody {
    /// Unformatted items: the kernel type and the `CompiledBody` impl for
    /// the user's struct (which is not redefined).
    pub items: String,
    /// The shape's name (for messages).
    pub shape_name: String,
    /// The shape file, if the shape is not built in (the crate must be
    /// rebuilt when it changes).
    pub shape_file: Option<PathBuf>,
    /// The section table's file (the crate must be rebuilt when it changes).
    pub sections_file: Option<PathBuf>,
    /// The parameters the body reads: each must be an `f64` field.
    pub params_used: Vec<Param>,
}

/// A failure of [`expand`], by the option it is about (for the
/// attribute's error spans).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FlexBodyError {
    /// The shape cannot be resolved or read.
    #[error("{0}")]
    Shape(Error),
    /// The shape's kernels cannot be generated (or emitted).
    #[error("{0}")]
    Kernels(Error),
    /// The scene cannot hold the shape (a spatial shape in a planar scene).
    #[error("shape `{0}` is spatial: it needs scene = \"spatial\"")]
    Scene(String),
    /// The mesh is not valid (element count).
    #[error("{0}")]
    Elements(Error),
    /// The section table cannot be read or is not valid.
    #[error("{0}")]
    Sections(Error),
    /// The modal body cannot be made (parameters, mode counts, a section
    /// table, the generator built without `modal`).
    #[error("{0}")]
    Modal(String),
    /// The body cannot be split as `segments` asks.
    #[error("{0}")]
    Segments(String),
}

/// Resolve, generate and emit the body the attribute describes.
pub fn expand(input: &FlexBodyInput) -> Result<FlexBody, FlexBodyError> {
    let shape = resolve_shape(input.shape, input.base).map_err(FlexBodyError::Shape)?;
    let mut model = KernelModel::new(shape, input.options);
    let sections = match input.sections {
        None => None,
        Some(p) => {
            model = model.with_sections(ffr_spec::SectionModel::Varying);
            Some(
                crate::builder::body_stations(
                    input.base,
                    p,
                    input.type_name,
                    model.shape.dimension,
                )
                .map_err(FlexBodyError::Sections)?,
            )
        }
    };
    if model.scene_dim() < model.shape.dimension {
        return Err(FlexBodyError::Scene(model.shape.name.clone()));
    }
    let spec = BodySpec::new(model.shape.clone(), input.elements, input.reference)
        .map_err(FlexBodyError::Elements)?
        .with_formalism(input.options.formalism);
    if let Some(n) = input.segments {
        let bad = |m: String| Err(FlexBodyError::Segments(m));
        if input.sections.is_some() {
            return bad("a body of a section table cannot be split here yet (use `segments = N` in a scene file, which splits the table at the cuts)".into());
        }
        if input.modal.is_some() {
            return bad("`segments` with `modes`: a modal body is reduced whole here; reduce each segment in a scene file (`segments = N` with `modes = K`)".into());
        }
        ffr_spec::check_segments(n as i64, input.elements)
            .map_err(|e| FlexBodyError::Segments(e.to_string()))?;
    }
    let set = generate_checked(&model).map_err(FlexBodyError::Kernels)?;
    let has_sections = sections.is_some();
    let mut items = body_items(
        &set,
        &spec,
        &EmitOptions {
            type_name: input.type_name.to_string(),
            define_struct: false,
            runtime_path: input.runtime_path.to_string(),
            sections,
        },
    );
    if let Some(n) = input.segments {
        items.push_str(&segments_items(input, n));
    }
    if let Some((p, settings)) = &input.modal {
        items.push_str(&modal_items(
            input,
            &spec,
            p,
            settings,
            has_sections,
            &set.params_used(),
            model.scene(),
        )?);
    }
    Ok(FlexBody {
        items,
        shape_name: model.shape.name.clone(),
        shape_file: model.shape.path.clone(),
        sections_file: input.sections.map(|p| input.base.join(p)),
        // A section table's body reads no parameter fields.
        params_used: if input.sections.is_some() {
            Vec::new()
        } else {
            set.params_used()
        },
    })
}

/// `{type_name}::SEGMENTS` and `{type_name}::segments()` (unformatted):
/// the body of `input.elements` equal elements split into `n` segments at
/// nodes, as a scene file's `segments = n` splits it (`FlexSpec::segment`:
/// the same section positions, [`ffr_spec::uniform_bounds`], and each
/// segment's length their difference).
fn segments_items(input: &FlexBodyInput, n: usize) -> String {
    let (ty, rt) = (input.type_name, input.runtime_path);
    let kt = format!("{ty}Kernels");
    let per = input.elements / n;
    let reference = match input.reference {
        Reference::Clamped => "Clamped",
        Reference::Pinned => "Pinned",
        Reference::Free => "Free",
    };
    format!(
        r#"impl {ty} {{
#[doc = " The number of segments the body runs as (`#[flex_body(segments = {n})]`)."]
pub const SEGMENTS: usize = {n};
#[doc = " The body split at nodes into `SEGMENTS` segments of {per} equal elements, as a scene file's `segments = {n}` splits it:"]
#[doc = " the root segment (this body's reference condition), the others (clamped at their roots) and the `SEGMENTS + 1`"]
#[doc = " section positions bounding them on the body's axis. Add the root with `System::add_body` and the others with"]
#[doc = " `System::add_segments(root, others, &bounds)`, which fixes each segment's frame to the previous one's end section."]
pub fn segments(&self) -> {rt}::Result<({rt}::KernelBody<{kt}>, ::std::vec::Vec<{rt}::KernelBody<{kt}>>, ::std::vec::Vec<f64>)> {{
let p = <Self as {rt}::CompiledBody>::params(self);
let bounds = {rt}::spec::uniform_bounds(p.length, {elements}, {n});
let segment = |k: usize, reference: {rt}::spec::Reference| {{
let mut q = p;
q.length = bounds[k + 1] - bounds[k];
{rt}::KernelBody::new({kt}, q, {per}, reference)
}};
let root = segment(0, {rt}::spec::Reference::{reference})?;
let others = (1..{n}).map(|k| segment(k, {rt}::spec::Reference::Clamped)).collect::<{rt}::Result<::std::vec::Vec<_>>>()?;
::core::result::Result::Ok((root, others, bounds))
}}
}}
"#,
        elements = input.elements
    )
}

/// The `{type_name}Modal` items of [`expand`].
#[cfg(feature = "modal")]
fn modal_items(
    input: &FlexBodyInput,
    spec: &BodySpec,
    p: &ffr_spec::Params,
    settings: &ffr_spec::scene::ModalSettings,
    has_sections: bool,
    used: &[crate::poly::Param],
    scene: ffr_spec::SceneDim,
) -> Result<String, FlexBodyError> {
    let bad = |e: String| FlexBodyError::Modal(format!("modal body: {e}"));
    if has_sections {
        return Err(bad(
            "a body of a section table cannot be reduced here yet (reduce it in a scene file)"
                .into(),
        ));
    }
    crate::limits::check_params(p, used).map_err(|e| bad(e.to_string()))?;
    let model = crate::modal::ModalModel::of_body(spec, p, settings, input.options.stiffening)
        .map_err(|e| bad(e.to_string()))?;
    let description = crate::emit::modal_description(&model, spec, p);
    crate::emit::modal_items(
        &model,
        p,
        &description,
        input.type_name,
        input.runtime_path,
        scene,
    )
    .map_err(|e| bad(e.to_string()))
}

#[cfg(not(feature = "modal"))]
fn modal_items(
    _: &FlexBodyInput,
    _: &BodySpec,
    _: &ffr_spec::Params,
    _: &ffr_spec::scene::ModalSettings,
    _: bool,
    _: &[crate::poly::Param],
    _: ffr_spec::SceneDim,
) -> Result<String, FlexBodyError> {
    Err(FlexBodyError::Modal(
        "`modes` needs the feature `modal` of ffr (the modal reduction in the attribute's generator)"
            .into(),
    ))
}
