//! A rigid mass attached on a beam's axis (issue 19), by a discrete
//! distribution: the mass's centre at the axis point `P` (element
//! coordinate `ξ`), plus pairs of points `±a e_i` along the principal
//! directions of its second moments `D` (`D_xx = (J_yy + J_zz − J_xx)/2`, …)
//! with weights `λ_i / (2 a²)` each (`a = √(3 λ_i / m)`: weights `m/6`), the
//! centre carrying the rest of the mass (signed when `m = 0`: only the
//! moments of order ≤ 2 matter, and they are `m`, `0`, `D`). Each point `P + d` moves as the material point of the
//! beam section it is rigidly fixed to: `elem_s(ξ, d_y/l, d_z/l)` (the
//! section's own Euler–Bernoulli and torsion kinematics) plus, for the
//! offset along the axis, `d_x (0, v', w')` (the section's bending
//! rotation). Every invariant is then a weighted sum over the points.

use super::varying::ElementInvariants;
use super::Shape;
use nalgebra::{Matrix3, SymmetricEigen, Vector3};

/// The invariants (element coordinates) of a mass `m` with inertia tensor
/// `j` about its centre, attached at `ξ` of the element `[x₀, x₀ + l]`. In a
/// planar shape only `J_zz` acts (the distribution lies in the x–y plane).
pub fn attached_mass(
    shape: Shape,
    x0: f64,
    l: f64,
    xi: f64,
    m: f64,
    j: Matrix3<f64>,
) -> ElementInvariants {
    let planar = shape == Shape::Beam2;
    let d = if planar {
        Matrix3::new(
            0.5 * j[(2, 2)],
            0.0,
            0.0,
            0.0,
            0.5 * j[(2, 2)],
            0.0,
            0.0,
            0.0,
            0.0,
        )
    } else {
        Matrix3::new(
            0.5 * (j[(1, 1)] + j[(2, 2)] - j[(0, 0)]),
            -j[(0, 1)],
            -j[(0, 2)],
            -j[(1, 0)],
            0.5 * (j[(0, 0)] + j[(2, 2)] - j[(1, 1)]),
            -j[(1, 2)],
            -j[(2, 0)],
            -j[(2, 1)],
            0.5 * (j[(0, 0)] + j[(1, 1)] - j[(2, 2)]),
        )
    };
    rigid_body(shape, x0, l, xi, m, d)
}

/// The invariants (element coordinates) of a rigid body of mass `m` whose
/// centre is on the axis at `ξ` of the element `[x₀, x₀ + l]` and whose
/// mass distribution has the second moments `d` about it (positive
/// semi-definite), by the discrete distribution of the module documentation.
pub fn rigid_body(
    shape: Shape,
    x0: f64,
    l: f64,
    xi: f64,
    m: f64,
    d: Matrix3<f64>,
) -> ElementInvariants {
    let ne = shape.elem_dofs();
    let eig = SymmetricEigen::new(d);
    let mut points: Vec<(Vector3<f64>, f64)> = Vec::new();
    let mut rest = m;
    for i in 0..3 {
        let lam = eig.eigenvalues[i];
        if lam == 0.0 {
            continue;
        }
        let e: Vector3<f64> = eig.eigenvectors.column(i).into();
        // With mass, weights m/6 at `a = √(3λ/m)` (positive, no
        // cancellation); without, a signed pair at 0.1 m.
        let a = if m > 0.0 { (3.0 * lam / m).sqrt() } else { 0.1 };
        let w = lam / (2.0 * a * a);
        points.push((a * e, w));
        points.push((-a * e, w));
        rest -= 2.0 * w;
    }
    points.push((Vector3::zeros(), rest));
    let mut r = ElementInvariants::zeros(ne);
    let (_, vp, wp) = shape.centerline_grad(l, xi);
    for (dd, w) in points {
        let mut s = shape.elem_s(l, xi, dd[1] / l, dd[2] / l);
        for c in 0..ne {
            s[(1, c)] += dd[0] * vp[c];
            s[(2, c)] += dd[0] * wp[c];
        }
        let u0 = Vector3::new(x0 + xi * l + dd[0], dd[1], dd[2]);
        r.mass += w;
        r.s_t0 += w * u0;
        r.s_bar += w * &s;
        r.theta += w * u0 * u0.transpose();
        for k in 0..3 {
            for kk in 0..3 {
                let sk = s.row(k).transpose();
                let sl = s.row(kk);
                r.s_kl[k][kk] += w * &sk * sl;
                r.i_kl[k][kk] += (w * u0[k]) * sl.transpose();
            }
        }
    }
    r.m_ff = &r.s_kl[0][0] + &r.s_kl[1][1] + &r.s_kl[2][2];
    r
}
