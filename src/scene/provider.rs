//! Where a scene's flexible bodies get their element kernels: the built-in
//! compiled ones or tapes (`ffr run`), the general ones (`ffr run
//! --general`), or a compiled scene's own.

use super::FlexSpec;
use crate::kernels::Kernels;
use crate::runtime::ElementKernels;

/// Supplies the element kernels of a scene's flexible bodies: the built-in
/// compiled ones or tapes (`ffr run`), or a compiled scene's own.
pub trait KernelProvider {
    /// The kernels for `spec`, and how they run (`compiled`, `tape`, …).
    #[allow(clippy::type_complexity)]
    fn kernels(&self, spec: &FlexSpec) -> crate::Result<(Box<dyn ElementKernels>, &'static str)>;
}

/// Built-in compiled kernels when they exist, else tapes of the body's
/// specialized kernels.
pub struct DefaultKernels;

/// The general kernels whatever the scene: a spatial scene and a free
/// frame, the body every scene could use (for comparisons with what
/// [`DefaultKernels`] specializes; `ffr run --general`).
pub struct GeneralKernels;

impl KernelProvider for GeneralKernels {
    fn kernels(&self, spec: &FlexSpec) -> crate::Result<(Box<dyn ElementKernels>, &'static str)> {
        let m = &spec.model;
        #[cfg(feature = "builtin-kernels")]
        if let Some(k) = crate::kernels::builtin(
            &spec.beam.shape,
            3,
            true,
            m.options.formalism,
            m.options.stiffening,
        ) {
            return Ok((Box::new(Kernels::Compiled(k)), "compiled, general"));
        }
        let shape = crate::codegen::Shape::resolve(&spec.beam.shape, None)?;
        let options = crate::runtime::spec::KernelOptions::new()
            .formalism(m.options.formalism)
            .stiffening(m.options.stiffening)
            .scene(crate::runtime::spec::SceneDim::Spatial);
        let model = crate::codegen::KernelModel::new(shape, options);
        let k = Kernels::Tape(Box::new(crate::runtime::tape::TapeKernels::new(&model)?));
        Ok((Box::new(k), "tape, general"))
    }
}

impl KernelProvider for DefaultKernels {
    /// The beam's own kernels: its options are the scene's model (the
    /// loader builds `spec.beam` from `spec.model`), so a shape file's tape
    /// is generated once.
    fn kernels(&self, spec: &FlexSpec) -> crate::Result<(Box<dyn ElementKernels>, &'static str)> {
        let k: Kernels = spec.beam.kernels()?;
        let path = k.path();
        Ok((Box::new(k), path))
    }
}
