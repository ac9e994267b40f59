//! A beam body's element kernels: the built-in shapes' compiled kernels
//! (crate `ffr-kernels`, feature `builtin-kernels`) or tapes of the
//! generator's programs (a shape chosen at run time), and the choice
//! between them.

use crate::runtime::spec::{Formalism, KernelOptions, Params, Reference, SceneDim, Stiffening};
use crate::runtime::tape::TapeKernels;
use crate::runtime::{ElementKernels, KernelBody};

#[cfg(feature = "builtin-kernels")]
pub use ffr_kernels::{builtin, BuiltinKernels};

/// Kernels of a beam body: compiled (built-in shape) or on tapes (a shape
/// chosen at run time).
#[derive(Debug)]
pub enum Kernels {
    /// Compiled into the binary (feature `builtin-kernels`).
    #[cfg(feature = "builtin-kernels")]
    Compiled(BuiltinKernels),
    /// Generated at run time and run on tapes (slower; same numbers).
    Tape(Box<TapeKernels>),
}

impl Kernels {
    /// How the kernels run and what they are specialized for: `compiled`,
    /// `compiled, prescribed frame at rest`, `tape`, ….
    pub fn path(&self) -> &'static str {
        let info = self.info();
        match (self, info.free_frame(), info.zero_frame_acceleration()) {
            #[cfg(feature = "builtin-kernels")]
            (Kernels::Compiled(_), true, _) => "compiled",
            #[cfg(feature = "builtin-kernels")]
            (Kernels::Compiled(_), false, true) => "compiled, prescribed frame at rest",
            #[cfg(feature = "builtin-kernels")]
            (Kernels::Compiled(_), false, false) => "compiled, prescribed frame",
            (Kernels::Tape(_), true, _) => "tape",
            (Kernels::Tape(_), false, true) => "tape, prescribed frame at rest",
            (Kernels::Tape(_), false, false) => "tape, prescribed frame",
        }
    }
}

macro_rules! either {
    ($self:ident, $k:ident => $e:expr) => {
        match $self {
            #[cfg(feature = "builtin-kernels")]
            Kernels::Compiled($k) => $e,
            Kernels::Tape($k) => $e,
        }
    };
}

crate::runtime::forward_element_kernels!([] Kernels, either);

/// How a beam body is made.
#[derive(Clone, Debug, PartialEq)]
pub struct BeamSpec {
    /// A built-in shape (`beam2`, `beam3`) or a path to a shape file.
    pub shape: String,
    /// Number of elements.
    pub elements: usize,
    /// Reference condition.
    pub reference: Reference,
    /// The kernel options: formalism, stiffening, scene (`None`: the
    /// shape's) and frame model (free: general kernels; prescribed at rest:
    /// kernels without reference rows and `ā` terms, which the system
    /// refuses elsewhere).
    pub options: KernelOptions,
    /// Parameter values.
    pub params: Params,
    /// Run on tapes even if compiled kernels exist (comparisons).
    pub force_tape: bool,
}

pub use crate::runtime::spec::FrameModel;

impl BeamSpec {
    /// `elements` clamped `shape` elements, consistent, no stiffening.
    pub fn new(shape: &str, elements: usize, params: Params) -> Self {
        Self {
            shape: shape.to_string(),
            elements,
            reference: Reference::Clamped,
            options: KernelOptions::new(),
            params,
            force_tape: false,
        }
    }

    /// With these kernel options.
    pub fn options(mut self, options: KernelOptions) -> Self {
        self.options = options;
        self
    }

    /// With this stiffening model.
    pub fn stiffening(mut self, s: Stiffening) -> Self {
        self.options.stiffening = s;
        self
    }

    /// With this inertia formalism.
    pub fn formalism(mut self, f: Formalism) -> Self {
        self.options.formalism = f;
        self
    }

    /// For this scene dimension (2 or 3; any other leaves the shape's).
    pub fn scene_dim(mut self, d: usize) -> Self {
        self.options.scene = SceneDim::from_dim(d);
        self
    }

    /// With this frame model.
    pub fn frame(mut self, f: FrameModel) -> Self {
        self.options.frame = f;
        self
    }

    /// The kernels: compiled for a built-in shape, else generated and taped.
    pub fn kernels(&self) -> Result<Kernels, crate::codegen::Error> {
        let shape = crate::codegen::Shape::resolve(&self.shape, None)?;
        let scene = self.options.scene_or(shape.dimension);
        let options = KernelOptions {
            scene: Some(scene),
            ..self.options
        };
        #[cfg(feature = "builtin-kernels")]
        if !self.force_tape && shape.path.is_none() {
            if let Some(k) = builtin(
                &self.shape,
                scene.dim(),
                options.frame != FrameModel::PrescribedAtRest,
                options.formalism,
                options.stiffening,
            ) {
                return Ok(Kernels::Compiled(k));
            }
        }
        let model = crate::codegen::KernelModel::new(shape, options);
        Ok(Kernels::Tape(Box::new(TapeKernels::new(&model)?)))
    }

    /// The body.
    pub fn body(&self) -> crate::Result<KernelBody<Kernels>> {
        Ok(KernelBody::new(
            self.kernels()?,
            self.params,
            self.elements,
            self.reference,
        )?)
    }
}
