//! Where a scene's flexible bodies get their element kernels: the built-in
//! compiled ones or tapes (`ffr run`), the general ones (`ffr run
//! --general`), or a compiled scene's own.

use super::FlexSpec;
#[cfg(feature = "scene-files")]
use crate::kernels::{BeamSpec, Kernels};
use crate::runtime::ElementKernels;

/// Supplies the element kernels of a scene's flexible bodies: the built-in
/// compiled ones or tapes (`ffr run`), or a compiled scene's own.
pub trait KernelProvider {
    /// The kernels for `spec`, and how they run (`compiled`, `tape`, …).
    #[allow(clippy::type_complexity)]
    fn kernels(&self, spec: &FlexSpec) -> crate::Result<(Box<dyn ElementKernels>, &'static str)>;

    /// A modal body's numbers computed when the scene was compiled (the
    /// basis and projected invariants of `spec`'s reduction), or `None`:
    /// reduce it when the scene is built (feature `scene-files`).
    fn modal(&self, _spec: &FlexSpec) -> Option<&'static crate::runtime::ModalConsts> {
        None
    }

    /// The generated inertia kernels of a modal body reduced when the scene
    /// was compiled ([`KernelProvider::modal`]), or `None`: the run-time
    /// equations.
    fn modal_kernels(&self, _spec: &FlexSpec) -> Option<Box<dyn crate::runtime::ModalKernels>> {
        None
    }
}

/// Built-in compiled kernels when they exist, else tapes of the body's
/// specialized kernels.
#[cfg(feature = "scene-files")]
pub struct DefaultKernels;

/// The general kernels whatever the scene: a spatial scene and a free
/// frame, the body every scene could use (for comparisons with what
/// [`DefaultKernels`] specializes; `ffr run --general`).
#[cfg(feature = "scene-files")]
pub struct GeneralKernels;

#[cfg(feature = "scene-files")]
impl KernelProvider for GeneralKernels {
    fn kernels(&self, spec: &FlexSpec) -> crate::Result<(Box<dyn ElementKernels>, &'static str)> {
        #[cfg(feature = "builtin-kernels")]
        if spec.sections.is_none() {
            if let Some(k) = crate::kernels::builtin(
                &spec.shape,
                3,
                true,
                spec.options.formalism,
                spec.options.stiffening,
            ) {
                return Ok((Box::new(Kernels::Compiled(k)), "compiled, general"));
            }
        }
        let shape = crate::codegen::Shape::resolve(&spec.shape, None)?;
        let options = crate::runtime::spec::KernelOptions::new()
            .formalism(spec.options.formalism)
            .stiffening(spec.options.stiffening)
            .scene(crate::runtime::spec::SceneDim::Spatial);
        let sections = if spec.sections.is_some() {
            crate::runtime::spec::SectionModel::Varying
        } else {
            crate::runtime::spec::SectionModel::Uniform
        };
        let model = crate::codegen::KernelModel::new(shape, options).with_sections(sections);
        let k = Kernels::Tape(Box::new(crate::runtime::tape::TapeKernels::new(&model)?));
        Ok((Box::new(k), "tape, general"))
    }
}

#[cfg(feature = "scene-files")]
impl KernelProvider for DefaultKernels {
    /// The beam's own kernels, with the options the scene fixes (so a
    /// shape file's tape is generated once).
    fn kernels(&self, spec: &FlexSpec) -> crate::Result<(Box<dyn ElementKernels>, &'static str)> {
        let beam = BeamSpec {
            shape: spec.shape.clone(),
            elements: spec.elements,
            reference: spec.reference,
            options: spec.options,
            params: spec.params,
            force_tape: false,
        };
        if spec.sections.is_some() {
            // Varying sections: the generator's program on a tape (no
            // built-in compiled kernels for them).
            let shape = crate::codegen::Shape::resolve(&spec.shape, None)?;
            let options = crate::runtime::spec::KernelOptions {
                scene: Some(spec.options.scene_or(shape.dimension)),
                ..spec.options
            };
            let model = crate::codegen::KernelModel::new(shape, options)
                .with_sections(crate::runtime::spec::SectionModel::Varying);
            let k = Kernels::Tape(Box::new(crate::runtime::tape::TapeKernels::new(&model)?));
            return Ok((Box::new(k), "tape, varying sections"));
        }
        let k: Kernels = beam.kernels()?;
        let path = k.path();
        Ok((Box::new(k), path))
    }
}
