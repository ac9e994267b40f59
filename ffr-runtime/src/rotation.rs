//! Rotational coordinates: one angle in the plane, Euler parameters in space.
//!
//! Each gives the rotation matrix `A(θ)` (3 × 3; a planar rotation is about z)
//! and `Ḡ(θ)` (3 × n_θ) with `ω̄ = Ḡ θ̇` the angular velocity in body axes.
//! Both satisfy `Ḡ̇ θ̇ = 0`, which the quadratic velocity vector relies on.

use nalgebra::{Matrix3, Matrix3xX, UnitQuaternion, Vector3, Vector4};

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

/// `Ḡ = 2 Ē`, `Ē = [−e1, e0, e3, −e2; −e2, −e3, e0, e1; −e3, e2, −e1, e0]`.
pub fn euler_g_bar(e: &Vector4<f64>) -> Matrix3xX<f64> {
    let (e0, e1, e2, e3) = (e[0], e[1], e[2], e[3]);
    Matrix3xX::from_row_slice(&[
        -e1, e0, e3, -e2, //
        -e2, -e3, e0, e1, //
        -e3, e2, -e1, e0,
    ]) * 2.0
}

/// Euler parameters of a unit quaternion (`e0 = w`).
pub fn euler_parameters(q: &UnitQuaternion<f64>) -> Vector4<f64> {
    Vector4::new(q.w, q.i, q.j, q.k)
}

/// `A(θ)` and `Ḡ(θ)` for rotational coordinates `theta` (1 angle or 4 Euler parameters).
pub fn rotation_and_g(theta: &[f64]) -> (Matrix3<f64>, Matrix3xX<f64>) {
    if theta.len() == 1 {
        (
            planar_rotation(theta[0]),
            Matrix3xX::from_column_slice(&[0.0, 0.0, 1.0]),
        )
    } else {
        let e = Vector4::from_column_slice(theta);
        (euler_rotation(&e), euler_g_bar(&e))
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
        let w = euler_g_bar(&e) * ed;
        let w = Vector3::new(w[0], w[1], w[2]);
        assert!((ad - euler_rotation(&e) * skew(&w)).norm() < 1e-8);
        // Ḡ̇ ė = 0 identically.
        assert!((euler_g_bar(&ed) * ed).norm() < 1e-15);
    }
}
