//! The element kernels of the built-in shapes, compiled into this crate by
//! `build.rs` (every formalism and stiffening model; planar and spatial
//! scenes), and the choice between them and run-time tapes.

use crate::evaluated::TapeKernels;
use crate::runtime::spec::{Formalism, Params, Reference, Stiffening};
use crate::runtime::{
    ElementKernels, KernelBody, KernelInfo, KernelInput, MassOut, ResidualOut, TangentOut,
};

include!(concat!(env!("OUT_DIR"), "/builtin.rs"));

impl ElementKernels for BuiltinKernels {
    fn info(&self) -> &KernelInfo {
        dispatch!(self, k => k.info())
    }
    fn coefficients(&self, params: &Params, l: f64, c: &mut [f64]) {
        dispatch!(self, k => k.coefficients(params, l, c))
    }
    fn mass(&self, c: &[f64], x0: f64, q: &[f64], out: &mut MassOut, s: &mut [f64]) {
        dispatch!(self, k => k.mass(c, x0, q, out, s))
    }
    fn residual(&self, c: &[f64], x: &KernelInput, out: &mut ResidualOut, s: &mut [f64]) {
        dispatch!(self, k => k.residual(c, x, out, s))
    }
    fn tangent(
        &self,
        c: &[f64],
        x: &KernelInput,
        bp: f64,
        gp: f64,
        out: &mut TangentOut,
        s: &mut [f64],
    ) {
        dispatch!(self, k => k.tangent(c, x, bp, gp, out, s))
    }
    fn residual_elastic(&self, c: &[f64], x: &KernelInput, f_e: &mut [f64], s: &mut [f64]) {
        dispatch!(self, k => k.residual_elastic(c, x, f_e, s))
    }
    fn tangent_elastic(
        &self,
        c: &[f64],
        x: &KernelInput,
        bp: f64,
        gp: f64,
        f_e: &mut [f64],
        k_ee: &mut [f64],
        s: &mut [f64],
    ) {
        dispatch!(self, k => k.tangent_elastic(c, x, bp, gp, f_e, k_ee, s))
    }
    fn energy(&self, c: &[f64], q: &[f64], s: &mut [f64]) -> f64 {
        dispatch!(self, k => k.energy(c, q, s))
    }
    fn element_invariants(&self, c: &[f64], x0: f64, out: &mut [f64], s: &mut [f64]) {
        dispatch!(self, k => k.element_invariants(c, x0, out, s))
    }
    fn point_shape(&self, c: &[f64], xi: f64, sh: &mut [f64], psi: &mut [f64], s: &mut [f64]) {
        dispatch!(self, k => k.point_shape(c, xi, sh, psi, s))
    }
}

/// The compiled kernels of a built-in shape, if there are any for these options.
pub fn builtin(
    shape: &str,
    scene_dim: usize,
    formalism: Formalism,
    stiffening: Stiffening,
) -> Option<BuiltinKernels> {
    BUILTIN
        .iter()
        .find(|(s, d, f, st, _)| {
            *s == shape && *d == scene_dim && *f == formalism && *st == stiffening
        })
        .map(|e| e.4)
}

/// Kernels of a beam body: compiled (built-in shape) or on tapes (a shape
/// chosen at run time).
#[derive(Debug)]
pub enum Kernels {
    /// Compiled into the binary.
    Compiled(BuiltinKernels),
    /// Generated at run time and run on tapes (slower; same numbers).
    Tape(Box<TapeKernels>),
}

impl Kernels {
    /// `compiled` or `tape`.
    pub fn path(&self) -> &'static str {
        match self {
            Kernels::Compiled(_) => "compiled",
            Kernels::Tape(_) => "tape",
        }
    }
}

macro_rules! either {
    ($self:ident, $k:ident => $e:expr) => {
        match $self {
            Kernels::Compiled($k) => $e,
            Kernels::Tape($k) => $e,
        }
    };
}

impl ElementKernels for Kernels {
    fn info(&self) -> &KernelInfo {
        either!(self, k => k.info())
    }
    fn coefficients(&self, params: &Params, l: f64, c: &mut [f64]) {
        either!(self, k => k.coefficients(params, l, c))
    }
    fn mass(&self, c: &[f64], x0: f64, q: &[f64], out: &mut MassOut, s: &mut [f64]) {
        either!(self, k => k.mass(c, x0, q, out, s))
    }
    fn residual(&self, c: &[f64], x: &KernelInput, out: &mut ResidualOut, s: &mut [f64]) {
        either!(self, k => k.residual(c, x, out, s))
    }
    fn tangent(
        &self,
        c: &[f64],
        x: &KernelInput,
        bp: f64,
        gp: f64,
        out: &mut TangentOut,
        s: &mut [f64],
    ) {
        either!(self, k => k.tangent(c, x, bp, gp, out, s))
    }
    fn residual_elastic(&self, c: &[f64], x: &KernelInput, f_e: &mut [f64], s: &mut [f64]) {
        either!(self, k => k.residual_elastic(c, x, f_e, s))
    }
    fn tangent_elastic(
        &self,
        c: &[f64],
        x: &KernelInput,
        bp: f64,
        gp: f64,
        f_e: &mut [f64],
        k_ee: &mut [f64],
        s: &mut [f64],
    ) {
        either!(self, k => k.tangent_elastic(c, x, bp, gp, f_e, k_ee, s))
    }
    fn energy(&self, c: &[f64], q: &[f64], s: &mut [f64]) -> f64 {
        either!(self, k => k.energy(c, q, s))
    }
    fn element_invariants(&self, c: &[f64], x0: f64, out: &mut [f64], s: &mut [f64]) {
        either!(self, k => k.element_invariants(c, x0, out, s))
    }
    fn point_shape(&self, c: &[f64], xi: f64, sh: &mut [f64], psi: &mut [f64], s: &mut [f64]) {
        either!(self, k => k.point_shape(c, xi, sh, psi, s))
    }
}

/// How a beam body is made.
#[derive(Clone, Debug, PartialEq)]
pub struct BeamSpec {
    /// A built-in shape (`beam2`, `beam3`) or a path to a shape file.
    pub shape: String,
    /// Number of elements.
    pub elements: usize,
    /// Reference condition.
    pub reference: Reference,
    /// Inertia formalism.
    pub formalism: Formalism,
    /// Stiffening model.
    pub stiffening: Stiffening,
    /// Scene dimension (`None`: the shape's).
    pub scene_dim: Option<usize>,
    /// Parameter values.
    pub params: Params,
    /// Run on tapes even if compiled kernels exist (comparisons).
    pub force_tape: bool,
}

impl BeamSpec {
    /// `elements` clamped `shape` elements, consistent, no stiffening.
    pub fn new(shape: &str, elements: usize, params: Params) -> Self {
        Self {
            shape: shape.to_string(),
            elements,
            reference: Reference::Clamped,
            formalism: Formalism::Consistent,
            stiffening: Stiffening::Off,
            scene_dim: None,
            params,
            force_tape: false,
        }
    }

    /// The kernels: compiled for a built-in shape, else generated and taped.
    pub fn kernels(&self) -> Result<Kernels, crate::codegen::Error> {
        let shape = crate::codegen::Shape::resolve(&self.shape, None)?;
        let scene = self.scene_dim.unwrap_or(shape.dimension);
        if !self.force_tape && shape.path.is_none() {
            if let Some(k) = builtin(&self.shape, scene, self.formalism, self.stiffening) {
                return Ok(Kernels::Compiled(k));
            }
        }
        let model = crate::codegen::KernelModel {
            shape,
            formalism: self.formalism,
            stiffening: self.stiffening,
            scene_dim: scene,
            free_frame: true,
            zero_frame_acceleration: false,
        };
        Ok(Kernels::Tape(Box::new(TapeKernels::new(&model)?)))
    }

    /// The body.
    pub fn body(&self) -> Result<KernelBody<Kernels>, Box<dyn std::error::Error>> {
        Ok(KernelBody::new(
            self.kernels()?,
            self.params,
            self.elements,
            self.reference,
        )?)
    }
}
