//! Marker kinematics: a marker's workspace, position and velocity.

use super::Assembly;
use crate::body::Body;
use crate::marker::MarkerKin;
use crate::system::System;
use nalgebra::Vector3;

impl<B: Body> Assembly<'_, B> {
    /// Global position of a marker.
    pub fn marker_position(&self, m: &crate::Marker, q: &[f64]) -> Vector3<f64> {
        let mut k = kin(self.sys, m);
        k.eval(m, q);
        k.pos
    }
}

impl<B: Body> System<B> {
    /// Workspace to evaluate marker `m` of this system (allocates once; then
    /// [`MarkerKin::eval`] at any `q` allocates nothing).
    pub fn marker_kin(&self, m: &crate::Marker) -> MarkerKin {
        kin(self, m)
    }
}

impl MarkerKin {
    /// Global velocity `ṗ = J_p q̇` after [`MarkerKin::eval`].
    pub fn velocity(&self, v: &[f64]) -> Vector3<f64> {
        self.idx
            .iter()
            .zip(&self.dpos)
            .map(|(&g, d)| d * v[g])
            .sum()
    }
}

pub(super) fn kin<B: Body>(sys: &System<B>, m: &crate::Marker) -> MarkerKin {
    match m.body {
        Some(b) => {
            let e = &sys.bodies[b.0];
            MarkerKin::new(m, e.offset, e.d, e.n_theta)
        }
        None => MarkerKin::new(m, 0, 0, 0),
    }
}
