//! What a modal body is made of: a basis with the static modes and the
//! modal damping a body's settings ask for, and the invariants projected
//! onto it. One home for the step from a basis of normal (or constraint)
//! modes to the reduced body, shared by the runtime's modal bodies (built
//! when a scene is loaded) and the generated ones (built by
//! [`crate::Builder`] and `ffr emit --modes`, the numbers baked in).

use super::Reduction;
use super::{augment, reduce, static_loads, substitute_params, Invariants, ModalBasis, ModalError};
use crate::body::BodySpec;
use crate::poly::Poly;
use ffr_spec::scene::ModalSettings;
use ffr_spec::{Params, Stiffening};
use nalgebra::DMatrix;

/// A reduced body's numbers.
#[derive(Clone, Debug, PartialEq)]
pub struct ModalModel {
    /// The basis: the normal (or fixed-interface and constraint) modes, then
    /// the static modes if asked.
    pub basis: ModalBasis,
    /// How many of its modes are normal modes (the first ones).
    pub normal: usize,
    /// The invariants projected onto the basis (`n_f = k`).
    pub projected: Invariants,
    /// `D = diag(2 ζ_i ω_i m_i)` on the normal modes (`k × k`); `None`: no
    /// damping.
    pub damping: Option<DMatrix<f64>>,
    /// The stiffening model of the full body (its elastic kernels give the
    /// elastic force at `Φ η` when it is on).
    pub stiffening: Stiffening,
}

impl ModalModel {
    /// The reduced body `settings` make of `base` (normal or Craig–Bampton
    /// modes of the body `spec` at parameters `p`, invariants `inv`): the
    /// static modes (inertia loads and, with `stiffening`, the modal
    /// derivatives; [`static_loads`], [`augment`]) if
    /// `settings.static_modes`, the damping ratios (none, one for all
    /// normal modes, or one each; finite and ≥ 0) and the projection.
    pub fn new(
        spec: &BodySpec,
        p: &Params,
        inv: &Invariants,
        base: ModalBasis,
        settings: &ModalSettings,
        stiffening: Stiffening,
    ) -> Result<Self, ModalError> {
        let u_nl = if settings.static_modes {
            substitute_params(&spec.stiffening_energy(stiffening), p)?
        } else {
            Poly::zero()
        };
        Self::from_basis(inv, base, settings, stiffening, &u_nl)
    }

    /// [`ModalModel::new`] of a body given by its invariants `inv` alone
    /// (e.g. an FE body, `fe::FeBody`): `u_nl` is its stiffening
    /// energy at the parameters, a polynomial in its elastic coordinates
    /// (zero without stiffening), for the modal derivatives among the
    /// static modes.
    pub fn from_basis(
        inv: &Invariants,
        base: ModalBasis,
        settings: &ModalSettings,
        stiffening: Stiffening,
        u_nl: &Poly,
    ) -> Result<Self, ModalError> {
        let normal = base.frequencies.len();
        let basis = if settings.static_modes {
            let loads = static_loads(inv, u_nl, &base.phi, normal)?;
            augment(&base, &inv.m_ff, &inv.k_ff, &loads)?
        } else {
            base
        };
        let k = basis.len();
        let zeta: Vec<f64> = match settings.damping.len() {
            0 => vec![0.0; normal],
            1 => vec![settings.damping[0]; normal],
            l if l == normal => settings.damping.clone(),
            l => {
                return Err(ModalError::Input(format!(
                    "`modal_damping` has {l} ratios: give one, or one per normal mode ({normal})"
                )))
            }
        };
        if let Some(z) = zeta.iter().find(|z| !(z.is_finite() && **z >= 0.0)) {
            return Err(ModalError::Input(format!(
                "a modal damping ratio must be finite and ≥ 0, found {z}"
            )));
        }
        let damping = zeta.iter().any(|z| *z > 0.0).then(|| {
            let mut d = DMatrix::zeros(k, k);
            for (i, (z, w)) in zeta.iter().zip(&basis.frequencies).enumerate() {
                d[(i, i)] = 2.0 * z * w * basis.modal_mass[(i, i)];
            }
            d
        });
        let projected = inv.project(&basis.phi);
        Ok(Self {
            basis,
            normal,
            projected,
            damping,
            stiffening,
        })
    }

    /// The body `spec` of one section at parameters `p` (its exact
    /// invariants, correctly rounded: [`Invariants::from_exact_elements`]) reduced
    /// as `settings` say: modal truncation to `settings.modes` modes, or
    /// Craig–Bampton on `settings.boundary` with that many fixed-interface
    /// modes; then [`ModalModel::new`].
    pub fn of_body(
        spec: &BodySpec,
        p: &Params,
        settings: &ModalSettings,
        stiffening: Stiffening,
    ) -> Result<Self, ModalError> {
        let exact = spec
            .exact_invariants_in_element_length()
            .map_err(|e| ModalError::Input(e.to_string()))?;
        let inv = Invariants::from_exact_elements(&exact, p, spec.elements)?;
        let reduction = if settings.boundary.is_empty() {
            Reduction::Modal {
                modes: settings.modes,
            }
        } else {
            Reduction::CraigBampton {
                boundary_nodes: settings.boundary.clone(),
                modes: settings.modes,
            }
        };
        let base = reduce(spec, p, &inv, &reduction)?;
        Self::new(spec, p, &inv, base, settings, stiffening)
    }

    /// Number of modes `k`.
    pub fn len(&self) -> usize {
        self.basis.len()
    }

    /// Whether there are no modes.
    pub fn is_empty(&self) -> bool {
        self.basis.is_empty()
    }

    /// One line saying what the reduced body is, `body` naming the full
    /// body.
    pub fn describe(&self, body: &str) -> String {
        let (k, n) = (self.len(), self.normal);
        format!(
            "{body} reduced to {k} modes ({}: {n} normal{}), stiffening {}",
            self.basis.reduction_name(),
            if k > n {
                format!(", {} more", k - n)
            } else {
                String::new()
            },
            self.stiffening
        )
    }
}

/// One line naming a body to be reduced: shape, mesh, reference,
/// formalism, its elastic coordinates and `available` elastic modes
/// (`graded`: a graded mesh; `varying`: a section table).
pub fn describe_body(spec: &BodySpec, graded: bool, varying: bool, available: usize) -> String {
    format!(
        "{} ({}), {} {}elements{}, {}, {} formalism: {} elastic coordinates, {} elastic modes",
        spec.shape.name,
        spec.shape.origin,
        spec.elements,
        if graded { "graded " } else { "" },
        if varying {
            " with varying sections"
        } else {
            ""
        },
        spec.reference,
        spec.formalism,
        spec.nf(),
        available
    )
}

/// The elastic modes of `spec` at body length `length`: its elastic
/// coordinates less the rigid-body motions of a free body.
pub fn elastic_modes(spec: &BodySpec, length: f64) -> usize {
    let rigid = if spec.reference == ffr_spec::Reference::Free {
        super::rigid_body_modes(spec, length).ncols()
    } else {
        0
    };
    spec.nf().saturating_sub(rigid)
}
