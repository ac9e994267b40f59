//! From a [`KernelModel`] to the straight-line programs of its element
//! kernels, sharing one coefficient array.

use crate::eom::{KernelModel, KernelPolys, Outputs};
use crate::error::Error;
use crate::poly::{Param, SectionProp};
use crate::program::{Coefficients, Program, ProgramBuilder};
use ffr_spec::{KernelKind, SectionModel};

/// Every program of one kernel set.
#[derive(Clone, Debug)]
pub struct KernelSet {
    /// The exact polynomials the programs were built from.
    pub polys: KernelPolys,
    /// The coefficients all kernels read.
    pub coefficients: Coefficients,
    /// Parameters (and `l`) → coefficients (a varying section: those of a
    /// uniform body, every moment at its constant-property value).
    pub coefficient_program: Program,
    /// The element moments `(P, k)` the coefficients read, in the order of
    /// the section coefficient program's `mu` (empty for a uniform section).
    pub section_moments: Vec<(SectionProp, u8)>,
    /// Element moments `mu` (and `l`) → coefficients (varying section only).
    pub section_coefficient_program: Option<Program>,
    /// `mass(q)`.
    pub mass: Program,
    /// `residual(…)` with reference rows (free frame only).
    pub residual: Option<Program>,
    /// `tangent(…)` (free frame only).
    pub tangent: Option<Program>,
    /// `residual_elastic(…)`.
    pub residual_elastic: Program,
    /// `tangent_elastic(…)`.
    pub tangent_elastic: Program,
    /// `energy(q)`.
    pub energy: Program,
    /// `element_invariants(x₀)`.
    pub element_invariants: Program,
    /// `point_shape(ξ)`.
    pub point_shape: Program,
    /// `force_elastic(q)` (stiffening models only).
    pub force_elastic: Option<Program>,
    /// `elastic_scalars(q)` (stiffening models only).
    pub elastic_scalars: Option<Program>,
    /// `scalar_force(z)` (stiffening models only).
    pub scalar_force: Option<Program>,
    /// `scalar_tangent(z)` (stiffening models only).
    pub scalar_tangent: Option<Program>,
}

impl KernelSet {
    /// The model.
    pub fn model(&self) -> &KernelModel {
        &self.polys.model
    }

    /// Element coordinates.
    pub fn n(&self) -> usize {
        self.polys.n
    }

    /// The program of kernel `kind` (`None`: not generated for this model,
    /// the reference rows of a prescribed frame).
    pub fn program(&self, kind: KernelKind) -> Option<&Program> {
        match kind {
            KernelKind::Coefficients => Some(&self.coefficient_program),
            KernelKind::SectionCoefficients => self.section_coefficient_program.as_ref(),
            KernelKind::Mass => Some(&self.mass),
            KernelKind::Residual => self.residual.as_ref(),
            KernelKind::Tangent => self.tangent.as_ref(),
            KernelKind::ResidualElastic => Some(&self.residual_elastic),
            KernelKind::TangentElastic => Some(&self.tangent_elastic),
            KernelKind::Energy => Some(&self.energy),
            KernelKind::ElementInvariants => Some(&self.element_invariants),
            KernelKind::PointShape => Some(&self.point_shape),
            KernelKind::ForceElastic => self.force_elastic.as_ref(),
            KernelKind::ElasticScalars => self.elastic_scalars.as_ref(),
            KernelKind::ScalarForce => self.scalar_force.as_ref(),
            KernelKind::ScalarTangent => self.scalar_tangent.as_ref(),
        }
    }

    /// The per-call kernels by name, in emission order (the coefficients
    /// left out).
    pub fn programs(&self) -> Vec<(&'static str, &Program)> {
        KernelKind::per_call()
            .filter_map(|k| self.program(k).map(|p| (k.name(), p)))
            .collect()
    }

    /// Parameters the coefficients read, in field order (`l` excluded: it is
    /// derived from `length`).
    pub fn params_used(&self) -> Vec<Param> {
        let mut v: Vec<Param> = self
            .coefficient_program
            .params()
            .into_iter()
            .filter(|p| *p != Param::ElemLength)
            .collect();
        v.push(Param::Length);
        v.sort();
        v.dedup();
        v
    }
}

/// Generate every kernel program of `model`.
pub fn generate_kernels(model: &KernelModel) -> Result<KernelSet, Error> {
    let polys = model.polys()?;
    let mut coefficients = Coefficients::default();
    let mut build =
        |outputs: &Outputs| ProgramBuilder::new(Some(&mut coefficients)).build(&polys.dag, outputs);
    // In the order of `KernelKind::ALL` (it numbers the coefficients).
    let mass = build(&polys.mass);
    let residual = polys.residual.as_ref().map(&mut build);
    let tangent = polys.tangent.as_ref().map(&mut build);
    let residual_elastic = build(&polys.residual_elastic);
    let tangent_elastic = build(&polys.tangent_elastic);
    let energy = build(&polys.energy);
    let element_invariants = build(&polys.element_invariants);
    let point_shape = build(&polys.point_shape);
    let force_elastic = polys.force_elastic.as_ref().map(&mut build);
    let elastic_scalars = polys.elastic_scalars.as_ref().map(&mut build);
    let scalar_force = polys.scalar_force.as_ref().map(&mut build);
    let scalar_tangent = polys.scalar_tangent.as_ref().map(&mut build);
    let (coefficient_program, section_moments, section_coefficient_program) = match model.sections {
        SectionModel::Uniform => (coefficients.program(), Vec::new(), None),
        SectionModel::Varying => {
            let moments = coefficients.moments();
            let section = coefficients.section_program(&moments);
            (coefficients.uniform_program(), moments, Some(section))
        }
    };
    Ok(KernelSet {
        polys,
        coefficients,
        coefficient_program,
        section_moments,
        section_coefficient_program,
        mass,
        residual,
        tangent,
        residual_elastic,
        tangent_elastic,
        energy,
        element_invariants,
        point_shape,
        force_elastic,
        elastic_scalars,
        scalar_force,
        scalar_tangent,
    })
}

/// [`generate_kernels`], then the literal check every emitted file needs
/// ([`crate::limits::check_literals`]: every literal finite in `f64`).
pub fn generate_checked(model: &KernelModel) -> Result<KernelSet, Error> {
    let set = generate_kernels(model)?;
    crate::limits::check_literals(&set)?;
    Ok(set)
}
