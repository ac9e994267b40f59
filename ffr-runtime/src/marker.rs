//! Markers: points (with axes) attached to a body, possibly at an elastic node,
//! or fixed to the ground. Joints and force elements act between markers.
//!
//! A body point moves as `r_P = R + A (ū₀_P + S_P q_f)` with
//! `∂r_P/∂q = [I, −A ũ_P Ḡ, A S_P]`. Marker axes `c̄_i` turn with the node's
//! small rotation `ψ = Ψ_P q_f`: `a_i = A (c̄_i + ψ × c̄_i)`,
//! `∂a_i/∂q = [0, −A ã̄_i Ḡ, −A c̃̄_i Ψ_P]`.

use crate::model::BodyModel;
use crate::rotation::skew;
use nalgebra::{DVector, Matrix3, Matrix3xX, Vector3};

/// Index of a body in a [`System`](crate::System).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BodyId(pub usize);

/// A point with axes on a body (or on the ground when `body` is `None`).
#[derive(Clone, Debug, PartialEq)]
pub struct Marker {
    /// The body, or `None` for the ground (then `u0` and `axes` are global).
    pub body: Option<BodyId>,
    /// Undeformed position `ū₀_P` in body axes.
    pub u0: Vector3<f64>,
    /// Shape at the point `S_P` (3 × n_f), `None` for a rigid attachment.
    pub shape: Option<Matrix3xX<f64>>,
    /// Small-rotation shape `Ψ_P` (3 × n_f, rotation `ψ = Ψ_P q_f`), `None` if the axes do not turn with the node.
    pub rotation_shape: Option<Matrix3xX<f64>>,
    /// Marker axes as columns, in body axes (identity by default).
    pub axes: Matrix3<f64>,
}

impl Marker {
    /// A fixed ground point (global position).
    pub fn ground(position: Vector3<f64>) -> Self {
        Self {
            body: None,
            u0: position,
            shape: None,
            rotation_shape: None,
            axes: Matrix3::identity(),
        }
    }
    /// A rigidly attached point `u0` (body axes) of `body`.
    pub fn at(body: BodyId, u0: Vector3<f64>) -> Self {
        Self {
            body: Some(body),
            u0,
            shape: None,
            rotation_shape: None,
            axes: Matrix3::identity(),
        }
    }
    /// The body-frame origin of `body`.
    pub fn origin(body: BodyId) -> Self {
        Self::at(body, Vector3::zeros())
    }
    /// The point follows the elastic deformation: `ū = ū₀ + S_P q_f`.
    pub fn with_shape(mut self, s_p: Matrix3xX<f64>) -> Self {
        self.shape = Some(s_p);
        self
    }
    /// The axes follow the node's small rotation `ψ = Ψ_P q_f`.
    pub fn with_rotation_shape(mut self, psi_p: Matrix3xX<f64>) -> Self {
        self.rotation_shape = Some(psi_p);
        self
    }
    /// Marker axes (columns, body axes; global for a ground marker).
    pub fn with_axes(mut self, axes: Matrix3<f64>) -> Self {
        self.axes = axes;
        self
    }
    /// Marker at node `node` of a beam body whose elastic coordinates carry
    /// labels `kind_node` (kinds `ux, uy, uz` for `S_P`, `rx, ry, rz` for `Ψ_P`);
    /// coordinates a node lacks (removed by the reference conditions) are zero.
    pub fn node(body: BodyId, u0: Vector3<f64>, labels: &[String], node: usize) -> Self {
        let (s, psi) = node_shapes(labels, node);
        Self::at(body, u0).with_shape(s).with_rotation_shape(psi)
    }
}

/// `S_P` and `Ψ_P` of beam node `node` from elastic-coordinate labels.
pub fn node_shapes(labels: &[String], node: usize) -> (Matrix3xX<f64>, Matrix3xX<f64>) {
    let nf = labels.len();
    let mut s = Matrix3xX::zeros(nf);
    let mut psi = Matrix3xX::zeros(nf);
    for (j, lab) in labels.iter().enumerate() {
        let Some((kind, idx)) = lab.split_once('_') else {
            continue;
        };
        if idx.parse::<usize>().ok() != Some(node) {
            continue;
        }
        match kind {
            "ux" => s[(0, j)] = 1.0,
            "uy" => s[(1, j)] = 1.0,
            "uz" => s[(2, j)] = 1.0,
            "rx" => psi[(0, j)] = 1.0,
            "ry" => psi[(1, j)] = 1.0,
            "rz" => psi[(2, j)] = 1.0,
            _ => {}
        }
    }
    (s, psi)
}

/// Index of the elastic coordinate labelled `label`, if any.
pub fn dof_index(labels: &[String], label: &str) -> Option<usize> {
    labels.iter().position(|l| l == label)
}

/// A marker evaluated at a configuration: global position and axes and their
/// Jacobians with respect to the body's coordinates (3 × n_b; empty for ground).
#[derive(Clone, Debug)]
pub(crate) struct MarkerState {
    pub pos: Vector3<f64>,
    pub pos_jac: Matrix3xX<f64>,
    pub axes: [Vector3<f64>; 3],
    pub axes_jac: [Matrix3xX<f64>; 3],
}

impl Marker {
    /// Evaluate at body coordinates `q` of `model` (ignored for ground markers).
    pub(crate) fn state(&self, model: Option<&BodyModel>, q: &[f64]) -> MarkerState {
        let Some(model) = model else {
            return MarkerState {
                pos: self.u0,
                pos_jac: Matrix3xX::zeros(0),
                axes: [
                    self.axes.column(0).into(),
                    self.axes.column(1).into(),
                    self.axes.column(2).into(),
                ],
                axes_jac: std::array::from_fn(|_| Matrix3xX::zeros(0)),
            };
        };
        let (d, nth, nf) = (model.dim(), model.n_theta(), model.nf());
        let fo = model.f_offset();
        let fr = model.frame(q);
        let qf = DVector::from_column_slice(&q[fo..]);
        let mut u = self.u0;
        if let Some(s) = &self.shape {
            u += s * &qf;
        }
        let n = model.n_coords();
        let mut pos_jac = Matrix3xX::zeros(n);
        for i in 0..d {
            pos_jac[(i, i)] = 1.0;
        }
        pos_jac
            .columns_mut(d, nth)
            .copy_from(&(-(fr.a * skew(&u) * &fr.g)));
        if let Some(s) = &self.shape {
            pos_jac.columns_mut(fo, nf).copy_from(&(fr.a * s));
        }
        let psi = self
            .rotation_shape
            .as_ref()
            .map(|p| p * &qf)
            .unwrap_or_else(Vector3::zeros);
        let mut axes = [Vector3::zeros(); 3];
        let axes_jac = std::array::from_fn(|i| {
            let c: Vector3<f64> = self.axes.column(i).into();
            let cb = c + psi.cross(&c);
            axes[i] = fr.a * cb;
            let mut j = Matrix3xX::zeros(n);
            j.columns_mut(d, nth)
                .copy_from(&(-(fr.a * skew(&cb) * &fr.g)));
            if let Some(p) = &self.rotation_shape {
                j.columns_mut(fo, nf).copy_from(&(-(fr.a * skew(&c) * p)));
            }
            j
        });
        MarkerState {
            pos: fr.r + fr.a * u,
            pos_jac,
            axes,
            axes_jac,
        }
    }
}
