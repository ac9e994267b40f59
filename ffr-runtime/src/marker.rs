//! Markers: points (with axes) attached to a body or to the ground, and
//! their kinematics with first and second derivatives.
//!
//! A marker on body `b` sits at `ū = ū₀ + Σ_j s_j q_f[dof_j]` (body axes)
//! with axes `c̃_k = c_k + ψ × c_k`, `ψ = Σ_j ψ_j q_f[dof_j]` (the small
//! rotation of the attached section), so in global axes
//!
//! `p = R + A(θ) ū`, `a_k = A(θ) c̃_k`.
//!
//! Its *local coordinates* are the body's frame coordinates `R` (d), `θ`
//! (n_θ) and the marker's elastic coordinates; the first and second
//! derivatives with respect to them are exact (`∂A/∂θ`, `∂²A/∂θ²`).

use crate::body::PointShape;
use crate::rotation::Rotation;
use nalgebra::{Matrix3, Vector3};

/// A body index in a system.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BodyId(pub usize);

/// A point with axes, on a body or on the ground.
#[derive(Clone, Debug, PartialEq)]
pub struct Marker {
    /// The body, or `None` for the ground.
    pub body: Option<BodyId>,
    /// Where: undeformed position and the elastic coordinates moving it.
    pub shape: PointShape,
    /// Marker axes in body (or global) axes, columns `x, y, z`.
    pub axes: Matrix3<f64>,
}

impl Marker {
    /// A fixed point of the ground (global axes).
    pub fn ground(p: Vector3<f64>) -> Self {
        Self {
            body: None,
            shape: PointShape {
                u0: [p.x, p.y, p.z],
                entries: Vec::new(),
            },
            axes: Matrix3::identity(),
        }
    }

    /// The origin of body `b`'s frame (a rigid point; body axes).
    pub fn origin(b: BodyId) -> Self {
        Self::at(b, Vector3::zeros())
    }

    /// A point fixed in body `b`'s frame at `u0` (not moved by elastic
    /// coordinates), with the body's axes.
    pub fn at(b: BodyId, u0: Vector3<f64>) -> Self {
        Self {
            body: Some(b),
            shape: PointShape {
                u0: [u0.x, u0.y, u0.z],
                entries: Vec::new(),
            },
            axes: Matrix3::identity(),
        }
    }

    /// A point of body `b` with the given shape (e.g. from
    /// [`crate::Body::point_shape`]), with the body's axes.
    pub fn point(b: BodyId, shape: PointShape) -> Self {
        Self {
            body: Some(b),
            shape,
            axes: Matrix3::identity(),
        }
    }

    /// The same marker with other axes (columns: the marker's x, y, z in
    /// body axes, or in global axes for a ground marker).
    pub fn with_axes(mut self, axes: Matrix3<f64>) -> Self {
        self.axes = axes;
        self
    }
}

/// The most local coordinates a marker can have (frame 3 + 4, point dofs).
pub const MAX_POINT_DOFS: usize = 48;

/// A marker evaluated at a configuration.
#[derive(Clone, Debug)]
pub struct MarkerKin {
    /// Global coordinate index of each local coordinate.
    pub idx: Vec<usize>,
    /// Number of frame coordinates among them (`d + n_θ`, 0 for ground).
    pub n_frame: usize,
    /// Frame translation coordinates `d`.
    pub d: usize,
    /// `p`.
    pub pos: Vector3<f64>,
    /// `∂p/∂q_local` (columns).
    pub dpos: Vec<Vector3<f64>>,
    /// `a_k`.
    pub axes: [Vector3<f64>; 3],
    /// `∂a_k/∂q_local`.
    pub daxes: [Vec<Vector3<f64>>; 3],
    rot: Option<Rotation>,
    u: Vector3<f64>,
    c_tilde: [Vector3<f64>; 3],
    s: Vec<Vector3<f64>>,
    psi_c: [Vec<Vector3<f64>>; 3],
}

impl MarkerKin {
    /// Workspace for `marker` on a body whose coordinates start at global
    /// index `offset` with `d` translations and `n_theta` rotations (`f_offset
    /// = d + n_theta`); allocates once.
    pub fn new(marker: &Marker, offset: usize, d: usize, n_theta: usize) -> Self {
        let mut idx = Vec::new();
        let n_frame = if marker.body.is_some() {
            idx.extend(offset..offset + d + n_theta);
            for (dof, _, _) in &marker.shape.entries {
                idx.push(offset + d + n_theta + dof);
            }
            d + n_theta
        } else {
            0
        };
        let n = idx.len();
        let z = Vector3::zeros();
        let m = marker.shape.entries.len();
        Self {
            idx,
            n_frame,
            d,
            pos: z,
            dpos: vec![z; n],
            axes: [z; 3],
            daxes: [vec![z; n], vec![z; n], vec![z; n]],
            rot: None,
            u: z,
            c_tilde: [z; 3],
            s: vec![z; m],
            psi_c: [vec![z; m], vec![z; m], vec![z; m]],
        }
    }

    /// Number of local coordinates.
    pub fn len(&self) -> usize {
        self.idx.len()
    }

    /// Whether the marker has no coordinates (ground).
    pub fn is_empty(&self) -> bool {
        self.idx.is_empty()
    }

    /// Evaluate at the global coordinates `q`.
    pub fn eval(&mut self, marker: &Marker, q: &[f64]) {
        let u0 = Vector3::from(marker.shape.u0);
        if marker.body.is_none() {
            self.pos = u0;
            for k in 0..3 {
                self.axes[k] = marker.axes.column(k).into();
            }
            return;
        }
        let o = self.idx[0];
        let (d, nth) = (self.d, self.n_frame - self.d);
        let rot = Rotation::new(&q[o + d..o + d + nth]);
        let mut u = u0;
        let mut psi = Vector3::zeros();
        for (j, (_, s, p)) in marker.shape.entries.iter().enumerate() {
            let qj = q[self.idx[self.n_frame + j]];
            let s = Vector3::from(*s);
            let p = Vector3::from(*p);
            u += s * qj;
            psi += p * qj;
            self.s[j] = s;
        }
        let mut r = Vector3::zeros();
        for k in 0..d {
            r[k] = q[o + k];
        }
        self.pos = r + rot.a * u;
        for k in 0..d {
            let mut e = Vector3::zeros();
            e[k] = 1.0;
            self.dpos[k] = e;
        }
        for i in 0..nth {
            self.dpos[d + i] = rot.da[i] * u;
        }
        for (j, s) in self.s.iter().enumerate() {
            self.dpos[self.n_frame + j] = rot.a * s;
        }
        for k in 0..3 {
            let c: Vector3<f64> = marker.axes.column(k).into();
            let ct = c + psi.cross(&c);
            self.c_tilde[k] = ct;
            self.axes[k] = rot.a * ct;
            for i in 0..d {
                self.daxes[k][i] = Vector3::zeros();
            }
            for i in 0..nth {
                self.daxes[k][d + i] = rot.da[i] * ct;
            }
            for (j, (_, _, p)) in marker.shape.entries.iter().enumerate() {
                let pc = Vector3::from(*p).cross(&c);
                self.psi_c[k][j] = pc;
                self.daxes[k][self.n_frame + j] = rot.a * pc;
            }
        }
        self.u = u;
        self.rot = Some(rot);
    }

    /// `∂²p/∂q_i∂q_j` (local indices).
    pub fn d2pos(&self, i: usize, j: usize) -> Vector3<f64> {
        let Some(rot) = &self.rot else {
            return Vector3::zeros();
        };
        let (d, nf) = (self.d, self.n_frame);
        let th = |k: usize| k >= d && k < nf;
        match (th(i), th(j)) {
            (true, true) => rot.d2a(i - d, j - d) * self.u,
            (true, false) if j >= nf => rot.da[i - d] * self.s[j - nf],
            (false, true) if i >= nf => rot.da[j - d] * self.s[i - nf],
            _ => Vector3::zeros(),
        }
    }

    /// `∂²a_k/∂q_i∂q_j` (local indices).
    pub fn d2axis(&self, k: usize, i: usize, j: usize) -> Vector3<f64> {
        let Some(rot) = &self.rot else {
            return Vector3::zeros();
        };
        let (d, nf) = (self.d, self.n_frame);
        let th = |m: usize| m >= d && m < nf;
        match (th(i), th(j)) {
            (true, true) => rot.d2a(i - d, j - d) * self.c_tilde[k],
            (true, false) if j >= nf => rot.da[i - d] * self.psi_c[k][j - nf],
            (false, true) if i >= nf => rot.da[j - d] * self.psi_c[k][i - nf],
            _ => Vector3::zeros(),
        }
    }
}
