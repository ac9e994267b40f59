//! Writers of a reduced body in formats other engines read:
//! MBDyn's modal `.fem` ([`mbdyn_fem`]) and Wallrapp's Standard Input Data
//! ([`sid`]). Each takes an [`ExportBody`] and returns the file's text; file
//! I/O is the caller's. Numbers are written with 17 significant digits
//! (`{:.16e}`), which read back to the same `f64`.
//!
//! What each target recomputes from the file and what it takes as given is
//! documented in `docs/export.md`.

mod mbdyn;
mod sid;

pub use mbdyn::mbdyn_fem;
pub use sid::sid;

use crate::body::BodySpec;
use crate::modal::{Invariants, ModalBasis, ModalError, ModeKind};
use crate::shape::Kind;
use ffr_spec::Params;
use nalgebra::{Matrix3xX, Vector3};

/// One body node as the writers need it.
#[derive(Clone, Debug, PartialEq)]
pub struct ExportNode {
    /// Body node index `0..=N` (also the node's label in the files).
    pub node: usize,
    /// Undeformed position in the body frame, `(j L/N, 0, 0)` (computed as
    /// `(j·L)/N`).
    pub position: Vector3<f64>,
    /// Nodal translation of each mode (3 × k; zero where the reference
    /// condition removes the coordinate or the shape has none).
    pub translation: Matrix3xX<f64>,
    /// Nodal (infinitesimal) rotation of each mode (3 × k).
    pub rotation: Matrix3xX<f64>,
    /// Lumped mass: `ρ A` times the node's share of the length (`l/2` at the
    /// ends, `l` inside).
    pub mass: f64,
    /// Lumped rotary inertia about the node's x, y, z axes:
    /// `ρ (I_y + I_z)`, `ρ I_y`, `ρ I_z` times the node's share of the length
    /// (`I_y` taken as 0 in a planar body, whose invariants have no z extent).
    pub inertia: Vector3<f64>,
}

/// A reduced body ready for export.
#[derive(Clone, Debug, PartialEq)]
pub struct ExportBody {
    /// One line describing the body (written as a comment).
    pub title: String,
    /// The invariants projected onto the basis (`n_f = k`): `mass`, `S_t0`,
    /// `Θ` of the body, `S̄Φ`, `Φᵀ S̄_kl Φ`, `Ī_kl Φ`, modal mass
    /// `Φᵀ m_ff Φ` and stiffness `Φᵀ K_ff Φ`.
    pub invariants: Invariants,
    /// Mode labels (`mode_1`, …, `constraint_uy_16`).
    pub labels: Vec<String>,
    /// Mode kinds (normal with `ω`, or constraint).
    pub kinds: Vec<ModeKind>,
    /// Every body node, in order.
    pub nodes: Vec<ExportNode>,
}

impl ExportBody {
    /// Assemble the export data of body `spec` at parameters `p`, with
    /// `full` its invariants (n_f nodal coordinates) and `basis` a reduction
    /// of it.
    pub fn new(
        spec: &BodySpec,
        p: &Params,
        full: &Invariants,
        basis: &ModalBasis,
    ) -> Result<Self, ModalError> {
        let dofs = spec.dofs();
        if full.nf() != dofs.len() || basis.phi.nrows() != dofs.len() {
            return Err(ModalError::Input(format!(
                "the body has {} elastic coordinates; the invariants have {} and the basis {} rows",
                dofs.len(),
                full.nf(),
                basis.phi.nrows()
            )));
        }
        if full.mass.is_nan() || full.mass <= 0.0 {
            return Err(ModalError::Input(format!(
                "the body's mass must be positive, found {}",
                full.mass
            )));
        }
        let k = basis.phi.ncols();
        let n = spec.elements;
        let h = p.length / n as f64;
        let iy = if spec.shape.dimension == 3 { p.iy } else { 0.0 };
        let mut nodes: Vec<ExportNode> = (0..=n)
            .map(|node| {
                let share = if node == 0 || node == n { h / 2.0 } else { h };
                ExportNode {
                    node,
                    position: Vector3::new(node as f64 * p.length / n as f64, 0.0, 0.0),
                    translation: Matrix3xX::zeros(k),
                    rotation: Matrix3xX::zeros(k),
                    mass: p.rho * p.area * share,
                    inertia: Vector3::new(
                        p.rho * (iy + p.iz) * share,
                        p.rho * iy * share,
                        p.rho * p.iz * share,
                    ),
                }
            })
            .collect();
        for (i, d) in dofs.iter().enumerate() {
            let (target, row) = match d.kind {
                Kind::Ux => (&mut nodes[d.node].translation, 0),
                Kind::Uy => (&mut nodes[d.node].translation, 1),
                Kind::Uz => (&mut nodes[d.node].translation, 2),
                Kind::Rx => (&mut nodes[d.node].rotation, 0),
                Kind::Ry => (&mut nodes[d.node].rotation, 1),
                Kind::Rz => (&mut nodes[d.node].rotation, 2),
            };
            for j in 0..k {
                target[(row, j)] = basis.phi[(i, j)];
            }
        }
        let reduction = if basis
            .kinds
            .iter()
            .any(|m| matches!(m, ModeKind::Constraint { .. }))
        {
            "Craig-Bampton"
        } else {
            "modal truncation"
        };
        let title = format!(
            "{} ({}), {} elements, {}, {}; {} modes ({reduction}); length {}, rho {}, area {}, iy {}, iz {}, e {}, g {}, j {}",
            spec.shape.name,
            spec.shape.origin,
            n,
            spec.reference,
            spec.formalism,
            k,
            p.length,
            p.rho,
            p.area,
            p.iy,
            p.iz,
            p.e,
            p.g,
            p.j
        );
        Ok(Self {
            title,
            invariants: full.project(&basis.phi),
            labels: basis.labels.clone(),
            kinds: basis.kinds.clone(),
            nodes,
        })
    }

    /// The export data of an FE body reduced to `basis` (a reduction of
    /// `body`, e.g. [`crate::fe::FeBody::reduce`]): every FE node at its
    /// coordinates, its translations the rows of `Φ` of its elastic
    /// coordinates (zero where a clamped interface removes them), no
    /// rotations; record 11's lumped mass of a node is its row sum of the
    /// scalar mass matrix, `(M_s 1)_i` (the consistent mass lumped; the
    /// total is exact, the distribution approximate), and no rotary inertia
    /// (translational nodes). A negative row sum (some higher-order
    /// elements have them) is refused.
    #[cfg(feature = "fe")]
    pub fn from_fe(body: &crate::fe::FeBody, basis: &ModalBasis) -> Result<Self, ModalError> {
        let full = &body.invariants;
        if basis.phi.nrows() != body.nf() {
            return Err(ModalError::Input(format!(
                "the FE body has {} elastic coordinates; the basis {} rows",
                body.nf(),
                basis.phi.nrows()
            )));
        }
        let k = basis.phi.ncols();
        let ms = &body.model.scalar_mass;
        let mut nodes = Vec::with_capacity(body.model.len());
        for (i, x) in body.model.nodes.iter().enumerate() {
            let mass: f64 = ms.row(i).iter().sum();
            if !(mass >= 0.0 && mass.is_finite()) {
                return Err(ModalError::Input(format!(
                    "node {i}'s lumped mass (its row sum of the mass matrix) is {mass}: the consistent mass cannot be lumped by row sums for the export's nodal masses"
                )));
            }
            nodes.push(ExportNode {
                node: i,
                position: *x,
                translation: Matrix3xX::zeros(k),
                rotation: Matrix3xX::zeros(k),
                mass,
                inertia: Vector3::zeros(),
            });
        }
        for (a, &d) in body.dofs.iter().enumerate() {
            for j in 0..k {
                nodes[d / 3].translation[(d % 3, j)] = basis.phi[(a, j)];
            }
        }
        let title = format!(
            "{}, from {} and {}; {} modes ({})",
            body.describe(),
            body.model.mass_file,
            body.model.stiffness_file,
            k,
            basis.reduction_name()
        );
        Ok(Self {
            title,
            invariants: full.project(&basis.phi),
            labels: basis.labels.clone(),
            kinds: basis.kinds.clone(),
            nodes,
        })
    }

    /// Number of modes `k`.
    pub fn modes(&self) -> usize {
        self.labels.len()
    }
}

/// A number with 17 significant digits (reads back to the same `f64`);
/// `-0` written as `0`.
pub(crate) fn num(v: f64) -> String {
    format!("{:.16e}", v + 0.0)
}
