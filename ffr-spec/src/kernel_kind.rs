//! The kernels of a set of element kernels, written once: the generator's
//! programs, the emitter, the tape and the runtime's `ElementKernels` follow
//! this list (by matching on it exhaustively), so that a new kernel is one
//! variant here plus the places the compiler then points at.

/// One kernel of a set of element kernels (one method of the runtime's
/// `ElementKernels`, besides `info`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum KernelKind {
    /// The coefficients `c` from the parameter values and `l` (once per body).
    Coefficients,
    /// The per-element coefficients `c` from the element moments `μ` of the
    /// section properties and `l` (kernels of varying sections only: once
    /// per element).
    SectionCoefficients,
    /// `S_t` and the acceleration-linear blocks at `q`.
    Mass,
    /// `f_r`, `f_θ`, `f_e` (free frame only).
    Residual,
    /// The residual and its derivatives (free frame only).
    Tangent,
    /// `f_e` only (frame motion prescribed).
    ResidualElastic,
    /// `f_e` and `β' ∂f_e/∂q̈ + γ' ∂f_e/∂q̇ + ∂f_e/∂q` (frame motion prescribed).
    TangentElastic,
    /// Elastic energy `½ qᵀ K q + U_nl(q)`.
    Energy,
    /// The element's invariants at offset `x₀` (see [`crate::invariant_layout`]).
    ElementInvariants,
    /// `S(ξ)` and the section rotation `ψ(ξ)` on the centre line.
    PointShape,
    /// The elastic force alone, `K_e q + ∇U_nl(q)` (stiffening models only:
    /// a modal body evaluates it at `q = Φ η`, where the inertial terms of
    /// `residual_elastic` are zero).
    ForceElastic,
    /// The element scalars `z = S q` of the stiffening energy (`z_j`, linear
    /// forms in the element coordinates: the slopes' coefficients), and
    /// their count (stiffening models only).
    ElasticScalars,
    /// `∂U_nl/∂z`, the stiffening energy's gradient in the element scalars
    /// (stiffening models only): a modal body evaluates it at `z = S Φ_e η`.
    ScalarForce,
    /// `∂U_nl/∂z` and the Hessian `∂²U_nl/∂z²` (stiffening models only).
    ScalarTangent,
}

impl KernelKind {
    /// Every kernel, in the order generated files define them.
    pub const ALL: [KernelKind; 14] = [
        KernelKind::Coefficients,
        KernelKind::SectionCoefficients,
        KernelKind::Mass,
        KernelKind::Residual,
        KernelKind::Tangent,
        KernelKind::ResidualElastic,
        KernelKind::TangentElastic,
        KernelKind::Energy,
        KernelKind::ElementInvariants,
        KernelKind::PointShape,
        KernelKind::ForceElastic,
        KernelKind::ElasticScalars,
        KernelKind::ScalarForce,
        KernelKind::ScalarTangent,
    ];

    /// The kernels run per element and call (all but the coefficients).
    pub fn per_call() -> impl Iterator<Item = KernelKind> {
        Self::ALL.into_iter().filter(|k| !k.is_coefficients())
    }

    /// Whether the kernel computes coefficients (per body or per element)
    /// rather than element quantities.
    pub const fn is_coefficients(self) -> bool {
        matches!(
            self,
            KernelKind::Coefficients | KernelKind::SectionCoefficients
        )
    }

    /// The method's name in `ElementKernels` (and in generated headers).
    pub const fn name(self) -> &'static str {
        match self {
            KernelKind::Coefficients => "coefficients",
            KernelKind::SectionCoefficients => "section_coefficients",
            KernelKind::Mass => "mass",
            KernelKind::Residual => "residual",
            KernelKind::Tangent => "tangent",
            KernelKind::ResidualElastic => "residual_elastic",
            KernelKind::TangentElastic => "tangent_elastic",
            KernelKind::Energy => "energy",
            KernelKind::ElementInvariants => "element_invariants",
            KernelKind::PointShape => "point_shape",
            KernelKind::ForceElastic => "force_elastic",
            KernelKind::ElasticScalars => "elastic_scalars",
            KernelKind::ScalarForce => "scalar_force",
            KernelKind::ScalarTangent => "scalar_tangent",
        }
    }

    /// Whether the kernel exists only for a free frame (the reference rows).
    pub const fn needs_free_frame(self) -> bool {
        matches!(self, KernelKind::Residual | KernelKind::Tangent)
    }

    /// Its position in [`KernelKind::ALL`] (for tables indexed by kernel).
    pub const fn index(self) -> usize {
        self as usize
    }
}

#[cfg(test)]
mod tests {
    use super::KernelKind;

    #[test]
    fn the_table_is_in_order_and_names_are_distinct() {
        for (i, k) in KernelKind::ALL.into_iter().enumerate() {
            assert_eq!(k.index(), i);
        }
        let mut names: Vec<&str> = KernelKind::ALL.iter().map(|k| k.name()).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), KernelKind::ALL.len());
        assert_eq!(KernelKind::per_call().count(), 12);
    }
}
