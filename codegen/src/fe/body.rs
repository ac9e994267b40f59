//! An FE body: a model with a reference condition, its elastic coordinates
//! and the FFR invariants of the nodal-based FFRF (docs/theory.md).

use super::model::dof_name;
use super::{FeError, FeModel};
use crate::modal::Invariants;
use nalgebra::{Cholesky, DMatrix, DVector, Matrix3, Vector3};

/// How the body frame is attached to an FE body.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FeReference {
    /// Fixed to the interface nodes: their degrees of freedom are removed
    /// from the elastic coordinates (a clamped body).
    Clamped,
    /// Every degree of freedom kept; modal truncation keeps the elastic
    /// modes, mass-orthogonal to the six rigid motions.
    Free,
}

impl std::fmt::Display for FeReference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            FeReference::Clamped => "clamped",
            FeReference::Free => "free",
        })
    }
}

/// An FE body ready for reduction.
#[derive(Clone, Debug, PartialEq)]
pub struct FeBody {
    /// The model.
    pub model: FeModel,
    /// The reference condition.
    pub reference: FeReference,
    /// The interface nodes, ascending.
    pub interface: Vec<usize>,
    /// The elastic coordinates: the model's degrees of freedom (`3 i + k`
    /// for node `i`, direction `k`) in ascending order, less the interface
    /// nodes' of a clamped body.
    pub dofs: Vec<usize>,
    /// Their names (`ux_3`, …).
    pub dof_names: Vec<String>,
    /// The invariants on the elastic coordinates (`n_f = dofs.len()`).
    pub invariants: Invariants,
}

impl FeBody {
    /// One line naming the body: nodes, elastic coordinates, reference,
    /// interface (`FE body (65 nodes, 195 elastic coordinates, clamped
    /// reference, interface nodes [0, 1, 2])`).
    pub fn describe(&self) -> String {
        format!(
            "FE body ({} nodes, {} elastic coordinates, {} reference{})",
            self.model.len(),
            self.nf(),
            self.reference,
            if self.interface.is_empty() {
                String::new()
            } else {
                format!(", interface nodes {:?}", self.interface)
            }
        )
    }

    /// The body `model` makes with `reference` and the interface nodes
    /// `interface` (0-based, no repeats; at least one for a clamped body).
    /// A clamped body's `K_ff` must be positive definite (the interface
    /// holds the body).
    pub fn new(
        model: FeModel,
        reference: FeReference,
        interface: &[usize],
    ) -> Result<Self, FeError> {
        let n = model.len();
        let mut nodes = interface.to_vec();
        nodes.sort_unstable();
        if let Some(w) = nodes.windows(2).find(|w| w[0] == w[1]) {
            return Err(FeError::Model(format!(
                "interface node {} appears twice",
                w[0]
            )));
        }
        if let Some(&bad) = nodes.iter().find(|&&i| i >= n) {
            return Err(FeError::Model(format!(
                "interface node {bad} out of range: the node file has {n} nodes (0 to {})",
                n - 1
            )));
        }
        let dofs: Vec<usize> = match reference {
            FeReference::Free => (0..3 * n).collect(),
            FeReference::Clamped => {
                if nodes.is_empty() {
                    return Err(FeError::Model(
                        "a clamped FE body needs interface nodes (the frame is fixed to them)"
                            .into(),
                    ));
                }
                (0..3 * n)
                    .filter(|d| nodes.binary_search(&(d / 3)).is_err())
                    .collect()
            }
        };
        if dofs.is_empty() {
            return Err(FeError::Model(
                "every node is an interface node: the clamped body has no elastic coordinates"
                    .into(),
            ));
        }
        let invariants = invariants(&model, &dofs);
        let finite = |m: &DMatrix<f64>| m.iter().all(|v| v.is_finite());
        if !(inv_finite(&invariants) && finite(&invariants.m_ff) && finite(&invariants.k_ff)) {
            return Err(FeError::Model(
                "the invariants overflow f64: the node coordinates or the masses are too large"
                    .into(),
            ));
        }
        if reference == FeReference::Clamped && Cholesky::new(invariants.k_ff.clone()).is_none() {
            return Err(FeError::file(
                &model.stiffness_file,
                format!(
                    "with the interface nodes {nodes:?} clamped the stiffness matrix is not positive definite: the interface does not hold the body (e.g. its nodes lie on one line)"
                ),
            ));
        }
        Ok(Self {
            dof_names: dofs.iter().map(|&d| dof_name(d)).collect(),
            model,
            reference,
            interface: nodes,
            dofs,
            invariants,
        })
    }

    /// Number of elastic coordinates.
    pub fn nf(&self) -> usize {
        self.dofs.len()
    }
}

/// `m`, `S_t0`, `Θ`, `S̄`, `S̄_kl`, `Ī_kl` all finite.
fn inv_finite(inv: &Invariants) -> bool {
    inv.mass.is_finite()
        && inv.s_t0.iter().all(|v| v.is_finite())
        && inv.theta.iter().all(|v| v.is_finite())
        && inv.s_bar.iter().all(|v| v.is_finite())
        && inv
            .s_kl
            .iter()
            .flatten()
            .all(|m| m.iter().all(|v| v.is_finite()))
        && inv
            .i_kl
            .iter()
            .flatten()
            .all(|m| m.iter().all(|v| v.is_finite()))
}

/// The invariants of the nodal-based FFRF (docs/theory.md), on the elastic
/// coordinates `dofs` (ascending model degrees of freedom): with `1` the
/// vector of ones and `x̄_k` the nodes' k-coordinates (over all nodes),
/// `m = 1ᵀ M_s 1`, `S_t0,k = 1ᵀ M_s x̄_k`, `Θ_kl = x̄_kᵀ M_s x̄_l`; and for
/// elastic coordinate `a` at node `i`, direction `d`: `S̄[k][a] = δ_kd (M_s
/// 1)_i` (row k of `1ᵀ M_s P_k`), `Ī_kl[a] = δ_ld (M_s x̄_k)_i` (`x̄_kᵀ M_s
/// P_l`), `S̄_kl[a][b] = δ_kd δ_ld' M_s[i][j]` (`P_kᵀ M_s P_l`, `b` at node
/// `j`, direction `d'`). `m_ff = Σ_k S̄_kk` (= `M` on the elastic
/// coordinates), `K_ff = K` on them. `S̄_lk = S̄_klᵀ` and `Θ` are exactly
/// symmetric (`M_s` is; `Θ` is evaluated on its upper triangle).
fn invariants(model: &FeModel, dofs: &[usize]) -> Invariants {
    let n = model.len();
    let ms = &model.scalar_mass;
    let ones = DVector::from_element(n, 1.0);
    let x: [DVector<f64>; 3] =
        std::array::from_fn(|k| DVector::from_iterator(n, model.nodes.iter().map(|p| p[k])));
    let ms1 = ms * &ones;
    let msx: [DVector<f64>; 3] = std::array::from_fn(|k| ms * &x[k]);
    let mass = ones.dot(&ms1);
    let s_t0 = Vector3::from_fn(|k, _| ones.dot(&msx[k]));
    let mut theta = Matrix3::zeros();
    for k in 0..3 {
        for l in k..3 {
            let v = x[k].dot(&msx[l]);
            theta[(k, l)] = v;
            theta[(l, k)] = v;
        }
    }
    let nf = dofs.len();
    let node = |a: usize| dofs[a] / 3;
    let dir = |a: usize| dofs[a] % 3;
    let mut s_bar = DMatrix::zeros(3, nf);
    let mut i_kl: [[DVector<f64>; 3]; 3] =
        std::array::from_fn(|_| std::array::from_fn(|_| DVector::zeros(nf)));
    for a in 0..nf {
        s_bar[(dir(a), a)] = ms1[node(a)];
        for k in 0..3 {
            i_kl[k][dir(a)][a] = msx[k][node(a)];
        }
    }
    let mut s_kl: [[DMatrix<f64>; 3]; 3] =
        std::array::from_fn(|_| std::array::from_fn(|_| DMatrix::zeros(nf, nf)));
    for a in 0..nf {
        for b in 0..nf {
            s_kl[dir(a)][dir(b)][(a, b)] = ms[(node(a), node(b))];
        }
    }
    let m_ff = &s_kl[0][0] + &s_kl[1][1] + &s_kl[2][2];
    let k_ff = model.stiffness.select_rows(dofs).select_columns(dofs);
    Invariants {
        dim: 3,
        mass,
        s_t0,
        s_bar,
        s_kl,
        i_kl,
        theta,
        m_ff,
        k_ff,
    }
}
