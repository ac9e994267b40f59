//! Rotational coordinates: one angle in the plane, Euler parameters in space.
//!
//! Each gives the rotation matrix `A(θ)` (3 × 3; a planar rotation is about
//! z), `Ḡ(θ)` (3 × n_θ) with `ω̄ = Ḡ θ̇` the angular velocity in body axes,
//! and the derivatives `∂A/∂θ_i`, `∂²A/∂θ_i∂θ_j`, `∂Ḡ/∂θ_i` that the
//! analytic Newton matrix needs. Both parameterizations satisfy `Ḡ̇ θ̇ = 0`
//! (so `ω̄̇ = Ḡ θ̈`).

use nalgebra::{Matrix3, UnitQuaternion, Vector3, Vector4};

/// `ã` with `ã b = a × b`.
pub fn skew(a: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -a.z, a.y, a.z, 0.0, -a.x, -a.y, a.x, 0.0)
}

/// Planar rotation by `θ` about z: `A = [cos θ, −sin θ, 0; sin θ, cos θ, 0; 0, 0, 1]`.
pub fn planar_rotation(theta: f64) -> Matrix3<f64> {
    let (s, c) = theta.sin_cos();
    Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
}

/// Euler parameters `e = [e0, e1, e2, e3]`:
/// `A = (2e0² − 1) I + 2 (ē ēᵀ + e0 ẽ)`, `ē = [e1, e2, e3]`.
pub fn euler_rotation(e: &Vector4<f64>) -> Matrix3<f64> {
    let v = Vector3::new(e[1], e[2], e[3]);
    Matrix3::identity() * (2.0 * e[0] * e[0] - 1.0) + (v * v.transpose() + skew(&v) * e[0]) * 2.0
}

/// Euler parameters of a unit quaternion (`e0 = w`).
pub fn euler_parameters(q: &UnitQuaternion<f64>) -> Vector4<f64> {
    Vector4::new(q.w, q.i, q.j, q.k)
}

fn unit(i: usize) -> Vector3<f64> {
    let mut v = Vector3::zeros();
    v[i] = 1.0;
    v
}

/// The rotation kinematics of one body at its rotational coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rotation {
    /// Number of rotational coordinates (1 or 4).
    pub n: usize,
    /// `A`.
    pub a: Matrix3<f64>,
    /// `Ḡ`, columns `0..n` (3 × n).
    pub g: [Vector3<f64>; 4],
    /// `∂A/∂θ_i`, `i < n`.
    pub da: [Matrix3<f64>; 4],
    /// `∂Ḡ/∂θ_i` (column j of `∂Ḡ/∂θ_i` is `dg[i][j]`).
    pub dg: [[Vector3<f64>; 4]; 4],
    planar_theta: f64,
    e: Vector4<f64>,
}

impl Rotation {
    /// At rotational coordinates `theta` (one angle, or four Euler parameters).
    pub fn new(theta: &[f64]) -> Self {
        let z = Vector3::zeros();
        if theta.len() == 1 {
            let a = planar_rotation(theta[0]);
            let (s, c) = theta[0].sin_cos();
            let da0 = Matrix3::new(-s, -c, 0.0, c, -s, 0.0, 0.0, 0.0, 0.0);
            Self {
                n: 1,
                a,
                g: [Vector3::z(), z, z, z],
                da: [da0, Matrix3::zeros(), Matrix3::zeros(), Matrix3::zeros()],
                dg: [[z; 4]; 4],
                planar_theta: theta[0],
                e: Vector4::zeros(),
            }
        } else {
            let e = Vector4::from_column_slice(theta);
            let v = Vector3::new(e[1], e[2], e[3]);
            let a = euler_rotation(&e);
            // Ḡ = 2 [−ē, e0 I − ẽ].
            let sk = skew(&v);
            let mut g = [z; 4];
            g[0] = -v * 2.0;
            for j in 0..3 {
                g[j + 1] = (Matrix3::identity() * e[0] - sk).column(j) * 2.0;
            }
            let mut da = [Matrix3::zeros(); 4];
            da[0] = Matrix3::identity() * (4.0 * e[0]) + sk * 2.0;
            for i in 0..3 {
                let ei = unit(i);
                da[i + 1] = (ei * v.transpose() + v * ei.transpose() + skew(&ei) * e[0]) * 2.0;
            }
            let mut dg = [[z; 4]; 4];
            // ∂Ḡ/∂e0 = 2 [0, I]; ∂Ḡ/∂e_i = 2 [−E_i, −Ẽ_i].
            for j in 0..3 {
                dg[0][j + 1] = unit(j) * 2.0;
            }
            for i in 0..3 {
                let ei = unit(i);
                dg[i + 1][0] = -ei * 2.0;
                let s = skew(&ei);
                for j in 0..3 {
                    dg[i + 1][j + 1] = -s.column(j) * 2.0;
                }
            }
            Self {
                n: 4,
                a,
                g,
                da,
                dg,
                planar_theta: 0.0,
                e,
            }
        }
    }

    /// `∂²A/∂θ_i∂θ_j`.
    pub fn d2a(&self, i: usize, j: usize) -> Matrix3<f64> {
        if self.n == 1 {
            -planar_rotation(self.planar_theta)
                + Matrix3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0)
        } else {
            let _ = self.e;
            match (i, j) {
                (0, 0) => Matrix3::identity() * 4.0,
                (0, k) | (k, 0) => skew(&unit(k - 1)) * 2.0,
                (a, b) => {
                    let (ea, eb) = (unit(a - 1), unit(b - 1));
                    (ea * eb.transpose() + eb * ea.transpose()) * 2.0
                }
            }
        }
    }

    /// `ω̄ = Ḡ θ̇`.
    pub fn omega(&self, theta_dot: &[f64]) -> Vector3<f64> {
        (0..self.n).map(|j| self.g[j] * theta_dot[j]).sum()
    }

    /// `Ḡᵀ f`.
    pub fn g_t(&self, f: &Vector3<f64>) -> [f64; 4] {
        let mut out = [0.0; 4];
        for (o, g) in out.iter_mut().zip(&self.g).take(self.n) {
            *o = g.dot(f);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn euler_matches_quaternion_and_g_gives_omega() {
        let q = UnitQuaternion::from_euler_angles(0.3, -1.1, 2.0);
        let e = euler_parameters(&q);
        assert!((euler_rotation(&e) - q.to_rotation_matrix().into_inner()).norm() < 1e-14);
        // Ȧ = A ω̃ with ω̄ = Ḡ ė, for ė tangent to the unit sphere.
        let ed = Vector4::new(0.2, -0.4, 0.1, 0.7);
        let ed = ed - e * e.dot(&ed);
        let h = 1e-6;
        let ad = (euler_rotation(&(e + ed * h)) - euler_rotation(&(e - ed * h))) / (2.0 * h);
        let r = Rotation::new(e.as_slice());
        let w = r.omega(ed.as_slice());
        assert!((ad - euler_rotation(&e) * skew(&w)).norm() < 1e-8);
        // Ḡ̇ ė = 0 identically.
        let rd = Rotation::new(ed.as_slice());
        assert!(rd.omega(ed.as_slice()).norm() < 1e-15);
    }

    #[test]
    fn derivatives_match_differences() {
        for theta in [vec![0.7], vec![0.6, -0.3, 0.5, 0.2]] {
            let r = Rotation::new(&theta);
            let h = 1e-6;
            for i in 0..r.n {
                let mut p = theta.clone();
                let mut m = theta.clone();
                p[i] += h;
                m[i] -= h;
                let (rp, rm) = (Rotation::new(&p), Rotation::new(&m));
                let da = (rp.a - rm.a) / (2.0 * h);
                assert!((da - r.da[i]).norm() < 1e-8, "dA/dθ{i}");
                for j in 0..r.n {
                    let dg = (rp.g[j] - rm.g[j]) / (2.0 * h);
                    assert!((dg - r.dg[i][j]).norm() < 1e-8, "dG/dθ{i} col {j}");
                    let d2 = (rp.da[j] - rm.da[j]) / (2.0 * h);
                    assert!((d2 - r.d2a(i, j)).norm() < 1e-7, "d2A/dθ{i}dθ{j}");
                }
            }
        }
    }
}
