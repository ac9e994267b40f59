//! An FE body's modal bases, through the beams' machinery
//! ([`modal_truncation`], [`craig_bampton`]): the same eigensolver, the
//! same exact removal of a free body's rigid motions, the same canonical
//! order and signs.

use super::{FeBody, FeError, FeReference};
use crate::modal::{craig_bampton, modal_truncation, ModalBasis, ModalModel, Reduction};
use crate::poly::Poly;
use ffr_spec::scene::ModalSettings;
use ffr_spec::Stiffening;
use nalgebra::DMatrix;

impl FeBody {
    /// The rigid motions on the elastic coordinates (`n_f × 6`) of a free
    /// body; `None` for a clamped one (its reference condition removes
    /// them).
    pub fn rigid_motions(&self) -> Option<DMatrix<f64>> {
        (self.reference == FeReference::Free)
            .then(|| self.model.rigid_motions().select_rows(&self.dofs))
    }

    /// Number of elastic modes: `n_f`, less the six rigid motions of a free
    /// body.
    pub fn available_modes(&self) -> usize {
        match self.reference {
            FeReference::Free => self.nf().saturating_sub(6),
            FeReference::Clamped => self.nf(),
        }
    }

    /// A basis for the body: modal truncation to `modes` modes (the lowest
    /// clamped modes, or a free body's lowest elastic modes), or
    /// Craig–Bampton with every elastic coordinate of the boundary nodes
    /// (FE node indices) as boundary coordinates. Uses the invariants'
    /// `m_ff` and `K_ff`.
    pub fn reduce(&self, reduction: &Reduction) -> Result<ModalBasis, FeError> {
        let inv = &self.invariants;
        match reduction {
            Reduction::Modal { modes } => Ok(modal_truncation(
                &inv.m_ff,
                &inv.k_ff,
                *modes,
                self.rigid_motions().as_ref(),
            )?),
            Reduction::CraigBampton {
                boundary_nodes,
                modes,
            } => {
                let n = self.model.len();
                let mut nodes = boundary_nodes.clone();
                nodes.sort_unstable();
                nodes.dedup();
                let mut boundary = Vec::new();
                for &node in &nodes {
                    if node >= n {
                        return Err(FeError::Model(format!(
                            "boundary node {node} out of range: the node file has {n} nodes (0 to {})",
                            n - 1
                        )));
                    }
                    let here: Vec<usize> = (0..self.nf())
                        .filter(|&a| self.dofs[a] / 3 == node)
                        .collect();
                    if here.is_empty() {
                        return Err(FeError::Model(format!(
                            "boundary node {node} is an interface node of the clamped body: it has no elastic coordinates"
                        )));
                    }
                    boundary.extend(here);
                }
                Ok(craig_bampton(
                    &inv.m_ff,
                    &inv.k_ff,
                    &boundary,
                    *modes,
                    &self.dof_names,
                )?)
            }
        }
    }

    /// The reduced body `settings` make (as a beam's in a scene): modal
    /// truncation to `settings.modes` modes, or Craig–Bampton on the FE
    /// nodes `settings.boundary`; the static modes of the frame's inertia
    /// loads if `settings.static_modes` (a clamped body: they need `K_ff`
    /// positive definite); the modal damping; the invariants projected
    /// ([`ModalModel::from_basis`], no stiffening: `M` and `K` do not give
    /// it).
    pub fn modal_model(&self, settings: &ModalSettings) -> Result<ModalModel, FeError> {
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
        let base = self.reduce(&reduction)?;
        Ok(ModalModel::from_basis(
            &self.invariants,
            base,
            settings,
            Stiffening::Off,
            &Poly::zero(),
        )?)
    }
}
