//! A body on the nodal coordinates of a finite-element model (the nodal-based
//! FFRF, `docs/theory.md`): its invariants come from the FE mass and
//! stiffness matrices (computed by `ffr_codegen::fe`), its elastic
//! coordinates are the nodes' translations `ux, uy, uz` less those its
//! reference condition removes, and a node is a point with those
//! coordinates: `ū = x̄_N + (u_x, u_y, u_z)_N`, no section rotation (solid
//! elements have translational nodes only).
//!
//! Scenes run FE bodies reduced ([`crate::ModalBody`] with this body as its
//! full body: markers at nodes are its node shapes times `Φ`). The full
//! body's equations are those of its invariants (the modal bodies' `InertiaTerms`, dense),
//! built on first use: a scene that only places markers never builds them.

use crate::body::{
    Body, BodyForces, BodyLayout, BodyMass, BodyState, BodyTangent, BodyWork, Invariants,
    PointShape,
};
use crate::error::{Error, Result};
use crate::inertia::{bilinear, InertiaTerms, Inputs};
use std::sync::OnceLock;

/// An FE body on its nodal coordinates (see the module documentation).
pub struct NodalBody {
    layout: BodyLayout,
    inv: Invariants,
    nodes: Vec<[f64; 3]>,
    /// For each node and direction, its elastic coordinate (if kept).
    coords: Vec<[Option<usize>; 3]>,
    terms: OnceLock<InertiaTerms>,
    identity: Vec<usize>,
}

impl std::fmt::Debug for NodalBody {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("NodalBody")
            .field("nodes", &self.nodes.len())
            .field("nf", &self.layout.nf)
            .finish()
    }
}

impl NodalBody {
    /// The body of invariants `inv` (spatial) on the elastic coordinates
    /// `dofs` (ascending FE degrees of freedom `3 i + k`: node `i`,
    /// direction `k`), named `labels`, of the nodes `nodes` (body frame).
    pub fn new(
        inv: Invariants,
        nodes: Vec<[f64; 3]>,
        dofs: &[usize],
        labels: Vec<String>,
        description: String,
    ) -> Result<Self> {
        let bad = |m: String| Err(Error::InvalidInput(format!("FE body: {m}")));
        let nf = inv.nf();
        if inv.dim != 3 {
            return bad(format!("invariants of dimension {}, expected 3", inv.dim));
        }
        if nf == 0 || dofs.len() != nf || labels.len() != nf {
            return bad(format!(
                "{} elastic coordinates, {} degrees of freedom and {} labels",
                nf,
                dofs.len(),
                labels.len()
            ));
        }
        if dofs.windows(2).any(|w| w[0] >= w[1]) || dofs[nf - 1] >= 3 * nodes.len() {
            return bad(format!(
                "the degrees of freedom must ascend and lie below 3 × {} nodes",
                nodes.len()
            ));
        }
        if nodes.iter().flatten().any(|x| !x.is_finite()) {
            return bad("a node coordinate is not finite".into());
        }
        let mut coords = vec![[None; 3]; nodes.len()];
        for (a, &d) in dofs.iter().enumerate() {
            coords[d / 3][d % 3] = Some(a);
        }
        Ok(Self {
            layout: BodyLayout {
                dim: 3,
                scene_dim: 3,
                nf,
                half_bandwidth: nf - 1,
                free_frame: true,
                zero_frame_acceleration: false,
                labels,
                length: None,
                description,
            },
            inv,
            nodes,
            coords,
            terms: OnceLock::new(),
            identity: (0..nf).collect(),
        })
    }

    fn terms(&self) -> &InertiaTerms {
        self.terms
            .get_or_init(|| InertiaTerms::new(self.inv.clone(), true, false))
    }
}

impl Body for NodalBody {
    fn layout(&self) -> &BodyLayout {
        &self.layout
    }

    fn work(&self) -> BodyWork {
        BodyWork::default()
    }

    fn forces(&self, state: &BodyState, frame_rows: bool, _w: &mut BodyWork, out: &mut BodyForces) {
        out.clear();
        self.terms()
            .add_forces(&Inputs::of(state), frame_rows, &self.identity, out);
    }

    fn tangent(
        &self,
        state: &BodyState,
        bp: f64,
        gp: f64,
        frame_rows: bool,
        _w: &mut BodyWork,
        out: &mut BodyForces,
        t: &mut BodyTangent,
    ) {
        out.clear();
        t.clear();
        let x = Inputs::of(state);
        let terms = self.terms();
        terms.add_forces(&x, frame_rows, &self.identity, out);
        terms.add_tangent(&x, bp, gp, frame_rows, &self.identity, t);
    }

    fn mass(&self, q_f: &[f64], _w: &mut BodyWork, out: &mut BodyMass) {
        out.clear();
        self.terms().add_mass(q_f, &self.identity, out);
    }

    fn elastic_energy(&self, q_f: &[f64], _w: &mut BodyWork) -> f64 {
        0.5 * bilinear(&self.inv.k_ff, q_f, q_f)
    }

    fn invariants(&self) -> Invariants {
        self.inv.clone()
    }

    fn point_shape(&self, _x: f64) -> Result<PointShape> {
        Err(Error::InvalidInput(
            "an FE body has no axis: name one of its nodes (`@node=N`)".into(),
        ))
    }

    fn node_count(&self) -> usize {
        self.nodes.len()
    }

    fn node_shape(&self, node: usize) -> Result<PointShape> {
        let n = self.nodes.len();
        let Some(x) = self.nodes.get(node) else {
            return Err(Error::InvalidInput(format!(
                "node {node} out of range: the FE body has nodes 0 to {}",
                n - 1
            )));
        };
        let mut entries = Vec::new();
        for (k, a) in self.coords[node].iter().enumerate() {
            if let Some(a) = a {
                let mut s = [0.0; 3];
                s[k] = 1.0;
                entries.push((*a, s, [0.0; 3]));
            }
        }
        Ok(PointShape { u0: *x, entries })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    /// Two point masses on x, node 0 clamped: the elastic coordinates are
    /// node 1's `ux, uy, uz` (FE degrees of freedom 3, 4, 5).
    fn body() -> NodalBody {
        let mut inv = Invariants::zeros(3, 3);
        inv.mass = 3.0;
        inv.m_ff = DMatrix::identity(3, 3) * 2.0;
        inv.k_ff = DMatrix::identity(3, 3) * 5.0;
        NodalBody::new(
            inv,
            vec![[0.0; 3], [1.0, 0.0, 0.0]],
            &[3, 4, 5],
            vec!["ux_1".into(), "uy_1".into(), "uz_1".into()],
            "two masses".into(),
        )
        .unwrap()
    }

    #[test]
    fn nodes_are_points_with_their_coordinates() {
        let b = body();
        assert_eq!(b.node_count(), 2);
        let tip = b.node_shape(1).unwrap();
        assert_eq!(tip.u0, [1.0, 0.0, 0.0]);
        assert_eq!(
            tip.entries,
            vec![
                (0, [1.0, 0.0, 0.0], [0.0; 3]),
                (1, [0.0, 1.0, 0.0], [0.0; 3]),
                (2, [0.0, 0.0, 1.0], [0.0; 3]),
            ]
        );
        // The clamped node moves with the frame only.
        assert!(b.node_shape(0).unwrap().entries.is_empty());
        let e = b.node_shape(2).unwrap_err().to_string();
        assert!(
            e.contains("node 2 out of range: the FE body has nodes 0 to 1"),
            "{e}"
        );
        assert!(b.point_shape(0.5).is_err());
        let mut w = b.work();
        assert_eq!(b.elastic_energy(&[1.0, 2.0, 0.0], &mut w), 0.5 * 5.0 * 5.0);
    }

    #[test]
    fn inconsistent_parts_are_refused() {
        let inv = Invariants::zeros(3, 3);
        let nodes = vec![[0.0; 3], [1.0, 0.0, 0.0]];
        let labels = || vec!["a".to_string(), "b".into(), "c".into()];
        for (dofs, nodes) in [
            (vec![3, 4], nodes.clone()),    // too few coordinates
            (vec![4, 3, 5], nodes.clone()), // not ascending
            (vec![3, 4, 6], nodes.clone()), // beyond the nodes
            (vec![3, 4, 5], vec![[0.0; 3], [f64::NAN, 0.0, 0.0]]),
        ] {
            assert!(NodalBody::new(inv.clone(), nodes, &dofs, labels(), String::new()).is_err());
        }
    }
}
