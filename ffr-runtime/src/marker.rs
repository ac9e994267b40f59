//! Markers: points (with axes) attached to a body or to the ground, and
//! their kinematics with first and second derivatives.
//!
//! A marker on body `b` sits at `ū = ū₀ + Σ_j s_j q_f[dof_j]` (body axes)
//! with axes `c̃_k = R(ψ) c_k`, where `ψ = Σ_j ψ_j q_f[dof_j]` is the
//! attached section's rotation vector to first order and `R(ψ)` its exact
//! rotation ([`crate::section`]: orthonormal, the rotation the beam's
//! kinematics give the section), so in global axes
//!
//! `p = R + A(θ) ū`, `a_k = A(θ) R(ψ) c_k`.
//!
//! A marker whose point shape carries no rotation (a frame point, an FE
//! node) keeps `c̃_k = c_k`.
//!
//! Its *local coordinates* are the body's frame coordinates `R` (d), `θ`
//! (n_θ) and the marker's elastic coordinates; the first and second
//! derivatives with respect to them are exact (`∂A/∂θ`, `∂²A/∂θ²`,
//! `∂R/∂ψ`, `∂²R/∂ψ²`).

use crate::body::PointShape;
use crate::rotation::Rotation;
use crate::section::SectionRotation;
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
    /// `ψ_j` of each elastic coordinate.
    p: Vec<Vector3<f64>>,
    /// Whether the point shape turns the section (some `ψ_j ≠ 0`).
    rotates: bool,
    /// `R(ψ)` and its derivatives at the last evaluation.
    section: SectionRotation,
    /// `∂²(R c_k)/∂ψ_i∂ψ_m`, by axis `k` and `3 i + m`.
    d2ct: [[Vector3<f64>; 9]; 3],
    /// `∂c̃_k/∂q_j = Σ_i ∂(R c_k)/∂ψ_i ψ_j[i]` (body axes).
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
            p: marker
                .shape
                .entries
                .iter()
                .map(|(_, _, p)| Vector3::from(*p))
                .collect(),
            rotates: marker
                .shape
                .entries
                .iter()
                .any(|(_, _, p)| p.iter().any(|x| *x != 0.0)),
            section: SectionRotation::identity(),
            d2ct: [[z; 9]; 3],
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
        if self.rotates {
            self.section = SectionRotation::new(&psi);
        }
        for k in 0..3 {
            let c: Vector3<f64> = marker.axes.column(k).into();
            let ct = if self.rotates { self.section.r * c } else { c };
            self.c_tilde[k] = ct;
            self.axes[k] = rot.a * ct;
            for i in 0..d {
                self.daxes[k][i] = Vector3::zeros();
            }
            for i in 0..nth {
                self.daxes[k][d + i] = rot.da[i] * ct;
            }
            if !self.rotates {
                for j in 0..self.p.len() {
                    self.psi_c[k][j] = Vector3::zeros();
                    self.daxes[k][self.n_frame + j] = Vector3::zeros();
                }
                continue;
            }
            let dct: [Vector3<f64>; 3] = std::array::from_fn(|i| self.section.dr[i] * c);
            for i in 0..3 {
                for m in 0..3 {
                    self.d2ct[k][3 * i + m] = self.section.d2r(i, m) * c;
                }
            }
            for (j, p) in self.p.iter().enumerate() {
                let pc = dct[0] * p.x + dct[1] * p.y + dct[2] * p.z;
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
            (false, false) if self.rotates && i >= nf && j >= nf => {
                let (pi, pj) = (&self.p[i - nf], &self.p[j - nf]);
                let mut v = Vector3::zeros();
                for a in 0..3 {
                    if pi[a] == 0.0 {
                        continue;
                    }
                    for b in 0..3 {
                        v += self.d2ct[k][3 * a + b] * (pi[a] * pj[b]);
                    }
                }
                rot.a * v
            }
            _ => Vector3::zeros(),
        }
    }

    /// `H_ij += w_p · ∂²p/∂q_i∂q_j + Σ_k w_k · ∂²a_k/∂q_i∂q_j` for all
    /// local `i, j`, into the row-major `n × n` matrix `out` at rows and
    /// columns `shift + i`, `shift + j`: the second derivatives of the
    /// marker contracted with weight vectors (global axes), as a joint's
    /// multipliers weight them (`Σ_r λ_r ∂²Φ_r/∂q²`). The same values as
    /// [`MarkerKin::d2pos`] and [`MarkerKin::d2axis`], without forming
    /// them pair by pair.
    pub fn add_contracted_hessian(
        &self,
        w_pos: &Vector3<f64>,
        w_axes: &[Vector3<f64>; 3],
        out: &mut [f64],
        n: usize,
        shift: usize,
    ) {
        let Some(rot) = &self.rot else {
            return;
        };
        let (d, nf) = (self.d, self.n_frame);
        let nth = nf - d;
        let ne = self.s.len();
        let at = |i: usize, j: usize| (shift + i) * n + shift + j;
        // (θ, θ): Σ_ab (∂²A/∂θ_i∂θ_j)_ab M_ab, M = w_p uᵀ + Σ_k w_k c̃_kᵀ.
        let mut mw = w_pos * self.u.transpose();
        for k in 0..3 {
            mw += w_axes[k] * self.c_tilde[k].transpose();
        }
        for i in 0..nth {
            for j in i..nth {
                let v = rot.d2a(i, j).component_mul(&mw).sum();
                out[at(d + i, d + j)] += v;
                if j != i {
                    out[at(d + j, d + i)] += v;
                }
            }
        }
        // (θ, elastic): (∂A/∂θ_iᵀ w_p)·s_j + Σ_k (∂A/∂θ_iᵀ w_k)·∂c̃_k/∂q_j.
        for i in 0..nth {
            let dat = rot.da[i].transpose();
            let wp = dat * w_pos;
            let wk: [Vector3<f64>; 3] = std::array::from_fn(|k| dat * w_axes[k]);
            for j in 0..ne {
                let mut v = wp.dot(&self.s[j]);
                if self.rotates {
                    for k in 0..3 {
                        v += wk[k].dot(&self.psi_c[k][j]);
                    }
                }
                out[at(d + i, nf + j)] += v;
                out[at(nf + j, d + i)] += v;
            }
        }
        // (elastic, elastic): p_iᵀ G p_j, G_ab = Σ_k (Aᵀ w_k)·∂²(R c_k)/∂ψ_a∂ψ_b.
        if self.rotates {
            let at_w: [Vector3<f64>; 3] = std::array::from_fn(|k| rot.a.transpose() * w_axes[k]);
            let g = Matrix3::from_fn(|a, b| {
                (0..3)
                    .map(|k| at_w[k].dot(&self.d2ct[k][3 * a + b]))
                    .sum::<f64>()
            });
            for i in 0..ne {
                let gp = g.transpose() * self.p[i];
                for j in 0..ne {
                    out[at(nf + i, nf + j)] += gp.dot(&self.p[j]);
                }
            }
        }
    }

    /// The section rotation `R(ψ)` at the last evaluation (the identity for
    /// a point without rotation).
    pub fn section(&self) -> &SectionRotation {
        &self.section
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::body::PointShape;

    /// A marker on a spatial body (frame at offset 0: R, e; then 6 elastic
    /// coordinates) whose point shape turns the section by all three
    /// rotations, with turned axes.
    fn marker() -> Marker {
        let entries = (0..6)
            .map(|j| {
                let f = j as f64;
                (
                    j,
                    [0.1 * f - 0.2, 0.3 - 0.05 * f, 0.07 * f],
                    [0.4 - 0.1 * f, 0.05 * f - 0.15, 0.2 + 0.03 * f * f - 0.1 * f],
                )
            })
            .collect();
        let axes = nalgebra::Rotation3::from_euler_angles(0.3, -0.2, 0.9).into_inner();
        Marker::point(
            BodyId(0),
            PointShape {
                u0: [1.0, 0.2, -0.1],
                entries,
            },
        )
        .with_axes(axes)
    }

    fn q0() -> Vec<f64> {
        let e = nalgebra::UnitQuaternion::from_euler_angles(0.5, -0.4, 1.2);
        let mut q = vec![0.3, -0.2, 0.1, e.w, e.i, e.j, e.k];
        q.extend([0.11, -0.23, 0.31, 0.17, -0.29, 0.13]);
        q
    }

    /// Axes orthonormal; first and second derivatives of the position and
    /// the axes against central differences.
    #[test]
    fn derivatives_against_differences() {
        let m = marker();
        let q = q0();
        let mut k = MarkerKin::new(&m, 0, 3, 4);
        k.eval(&m, &q);
        let a = nalgebra::Matrix3::from_columns(&k.axes);
        assert!((a.transpose() * a - Matrix3::identity()).amax() < 1e-14);
        let n = k.len();
        let h = 1e-6;
        let mut kp = MarkerKin::new(&m, 0, 3, 4);
        let mut km = MarkerKin::new(&m, 0, 3, 4);
        for i in 0..n {
            let (mut qp, mut qm) = (q.clone(), q.clone());
            qp[k.idx[i]] += h;
            qm[k.idx[i]] -= h;
            kp.eval(&m, &qp);
            km.eval(&m, &qm);
            let fd = (kp.pos - km.pos) / (2.0 * h);
            assert!((fd - k.dpos[i]).amax() < 1e-8, "dpos {i}");
            for ax in 0..3 {
                let fd = (kp.axes[ax] - km.axes[ax]) / (2.0 * h);
                let e = (fd - k.daxes[ax][i]).amax();
                assert!(e < 1e-8, "daxes {ax} {i}: {e:e}");
            }
            for j in 0..n {
                let fd = (kp.dpos[j] - km.dpos[j]) / (2.0 * h);
                let e = (fd - k.d2pos(i, j)).amax();
                assert!(e < 1e-7, "d2pos {i} {j}: {e:e}");
                for ax in 0..3 {
                    let fd = (kp.daxes[ax][j] - km.daxes[ax][j]) / (2.0 * h);
                    let e = (fd - k.d2axis(ax, i, j)).amax();
                    assert!(e < 1e-7, "d2axis {ax} {i} {j}: {e:e}");
                }
            }
        }
    }
}
