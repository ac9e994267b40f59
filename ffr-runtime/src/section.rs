//! The exact rotation of a beam section from its small-rotation coordinates,
//! with first and second derivatives.
//!
//! A beam body's point shapes give, at a point of its axis, the section's
//! rotation vector to first order, `ψ = (φ, θ_y, θ_z)`: the torsion angle `φ`
//! and the slopes `θ_y = −w'`, `θ_z = v'` (`docs/theory.md` §8, §9). The
//! section's exact rotation consistent with the beam's kinematics is the one
//! the fourth-order bending energy measures curvature with (§10): the
//! smallest rotation taking the body's x axis to the inextensible axis'
//! tangent `t = (c, v', w') = (c, θ_z, −θ_y)`, `c = √(1 − θ_y² − θ_z²)`,
//! after the twist `φ` about x. With `k = e_x × t = (0, θ_y, θ_z)`,
//! `h = 1/(1 + c)` (Rodrigues' formula for the rotation between two unit
//! vectors, `I + k̃ + h k̃²`):
//!
//! ```text
//! R_min = [ c     −θ_z        θ_y      ]
//!         [ θ_z   1 − h θ_z²  h θ_y θ_z ]
//!         [ −θ_y  h θ_y θ_z   1 − h θ_y² ]
//! R(ψ) = R_min(θ_y, θ_z) R_x(φ)
//! ```
//!
//! `R` is orthonormal for every `θ_y² + θ_z² < 1` (a section turned by less
//! than 90° from its frame), and `R = I + ψ̃ + O(ψ²)`, the linearized
//! `c + ψ × c` the markers used before. Its derivatives by `ψ` are exact
//! (second-order forward differentiation, `Jet`).

use nalgebra::{Matrix3, Vector3};

/// The largest `θ_y² + θ_z²` evaluated: beyond it (a section turned by 90°
/// or more from its frame, where the inextensible tangent has no
/// x component) the slopes are scaled back to it so that the values stay
/// finite; the divergence monitor stops a run whose section gets there
/// ([`crate::monitor`]).
pub const MAX_SLOPE_SQUARED: f64 = 1.0 - 1e-8;

/// A value with its gradient and Hessian over three variables (the Hessian
/// packed as `(0,0), (0,1), (0,2), (1,1), (1,2), (2,2)`).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Jet {
    v: f64,
    g: [f64; 3],
    h: [f64; 6],
}

/// Packed index of the Hessian entry `(i, j)`.
const fn hidx(i: usize, j: usize) -> usize {
    let (i, j) = if i <= j { (i, j) } else { (j, i) };
    match (i, j) {
        (0, 0) => 0,
        (0, 1) => 1,
        (0, 2) => 2,
        (1, 1) => 3,
        (1, 2) => 4,
        _ => 5,
    }
}

const PAIRS: [(usize, usize); 6] = [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)];

impl Jet {
    fn constant(v: f64) -> Self {
        Self {
            v,
            g: [0.0; 3],
            h: [0.0; 6],
        }
    }
    fn var(v: f64, i: usize) -> Self {
        let mut g = [0.0; 3];
        g[i] = 1.0;
        Self { v, g, h: [0.0; 6] }
    }
    fn add(self, o: Self) -> Self {
        Self {
            v: self.v + o.v,
            g: std::array::from_fn(|i| self.g[i] + o.g[i]),
            h: std::array::from_fn(|i| self.h[i] + o.h[i]),
        }
    }
    fn sub(self, o: Self) -> Self {
        self.add(o.scale(-1.0))
    }
    fn scale(self, s: f64) -> Self {
        Self {
            v: s * self.v,
            g: self.g.map(|x| s * x),
            h: self.h.map(|x| s * x),
        }
    }
    fn mul(self, o: Self) -> Self {
        Self {
            v: self.v * o.v,
            g: std::array::from_fn(|i| self.v * o.g[i] + o.v * self.g[i]),
            h: std::array::from_fn(|p| {
                let (i, j) = PAIRS[p];
                self.v * o.h[p] + o.v * self.h[p] + self.g[i] * o.g[j] + self.g[j] * o.g[i]
            }),
        }
    }
    /// `f(self)` for `f` with value `f0`, first derivative `f1` and second
    /// `f2` at `self.v`.
    fn chain(self, f0: f64, f1: f64, f2: f64) -> Self {
        Self {
            v: f0,
            g: self.g.map(|x| f1 * x),
            h: std::array::from_fn(|p| {
                let (i, j) = PAIRS[p];
                f1 * self.h[p] + f2 * self.g[i] * self.g[j]
            }),
        }
    }
    fn sqrt(self) -> Self {
        let r = self.v.sqrt();
        self.chain(r, 0.5 / r, -0.25 / (r * self.v))
    }
    fn recip(self) -> Self {
        let r = 1.0 / self.v;
        self.chain(r, -r * r, 2.0 * r * r * r)
    }
    fn sin(self) -> Self {
        let (s, c) = self.v.sin_cos();
        self.chain(s, c, -s)
    }
    fn cos(self) -> Self {
        let (s, c) = self.v.sin_cos();
        self.chain(c, -s, -c)
    }
}

/// The section rotation `R(ψ)` and its derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SectionRotation {
    /// `R` (body axes: the section's axes as columns).
    pub r: Matrix3<f64>,
    /// `∂R/∂ψ_i`.
    pub dr: [Matrix3<f64>; 3],
    /// `∂²R/∂ψ_i∂ψ_j`, packed (`(0,0), (0,1), (0,2), (1,1), (1,2), (2,2)`);
    /// see [`SectionRotation::d2r`].
    d2r: [Matrix3<f64>; 6],
}

impl SectionRotation {
    /// The identity (an undeformed section, or a point without rotation).
    pub fn identity() -> Self {
        Self {
            r: Matrix3::identity(),
            dr: [Matrix3::zeros(); 3],
            d2r: [Matrix3::zeros(); 6],
        }
    }

    /// `R(ψ)` with its derivatives, `ψ = (φ, θ_y, θ_z)` (slopes beyond
    /// [`MAX_SLOPE_SQUARED`] scaled back to it).
    pub fn new(psi: &Vector3<f64>) -> Self {
        let (mut ty, mut tz) = (psi.y, psi.z);
        let s2 = ty * ty + tz * tz;
        // `!(s2 <= …)`: a NaN slope is scaled too (and stays NaN).
        #[allow(clippy::neg_cmp_op_on_partial_ord)]
        if !(s2 <= MAX_SLOPE_SQUARED) && s2.is_finite() {
            let f = (MAX_SLOPE_SQUARED / s2).sqrt();
            ty *= f;
            tz *= f;
        }
        let phi = Jet::var(psi.x, 0);
        let ty = Jet::var(ty, 1);
        let tz = Jet::var(tz, 2);
        let one = Jet::constant(1.0);
        let c = one.sub(ty.mul(ty)).sub(tz.mul(tz)).sqrt();
        let h = one.add(c).recip();
        let hyz = h.mul(ty).mul(tz);
        // Columns of R_min.
        let m0 = [c, tz, ty.scale(-1.0)];
        let m1 = [tz.scale(-1.0), one.sub(h.mul(tz).mul(tz)), hyz];
        let m2 = [ty, hyz, one.sub(h.mul(ty).mul(ty))];
        let (cp, sp) = (phi.cos(), phi.sin());
        let col1: [Jet; 3] = std::array::from_fn(|i| cp.mul(m1[i]).add(sp.mul(m2[i])));
        let col2: [Jet; 3] = std::array::from_fn(|i| cp.mul(m2[i]).sub(sp.mul(m1[i])));
        let cols = [m0, col1, col2];
        let entry = |f: &dyn Fn(&Jet) -> f64| Matrix3::from_fn(|row, col| f(&cols[col][row]));
        Self {
            r: entry(&|j| j.v),
            dr: std::array::from_fn(|i| entry(&|j| j.g[i])),
            d2r: std::array::from_fn(|p| entry(&|j| j.h[p])),
        }
    }

    /// `∂²R/∂ψ_i∂ψ_j`.
    pub fn d2r(&self, i: usize, j: usize) -> &Matrix3<f64> {
        &self.d2r[hidx(i, j)]
    }

    /// The rotation angle of `R` (rad, in `[0, π]`).
    pub fn angle(&self) -> f64 {
        let c = 0.5 * (self.r.trace() - 1.0);
        c.clamp(-1.0, 1.0).acos()
    }
}

/// The angle of the section rotation `R(ψ)` (`acos((tr R − 1)/2)`, in
/// `[0, π]`) in closed form: `tr R = c + cos φ (1 + c)`, so
/// `cos angle = (1 + c)(1 + cos φ)/2 − 1` (slopes beyond
/// [`MAX_SLOPE_SQUARED`] scaled back to it, as [`SectionRotation::new`]
/// does). Planar (`ψ = (0, 0, θ_z)`): `asin |θ_z|`.
pub fn rotation_angle(psi: &Vector3<f64>) -> f64 {
    let s2 = (psi.y * psi.y + psi.z * psi.z).min(MAX_SLOPE_SQUARED);
    let c = (1.0 - s2).sqrt();
    let cos = 0.5 * (1.0 + c) * (1.0 + psi.x.cos()) - 1.0;
    cos.clamp(-1.0, 1.0).acos()
}

/// The section's slope `√(θ_y² + θ_z²)`: the sine of the angle between the
/// body's x axis and the inextensible axis' tangent (1 at 90°, where
/// [`SectionRotation`] is no longer defined).
pub fn slope(psi: &Vector3<f64>) -> f64 {
    (psi.y * psi.y + psi.z * psi.z).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn psis() -> Vec<Vector3<f64>> {
        vec![
            Vector3::zeros(),
            Vector3::new(0.0, 0.0, 0.3),
            Vector3::new(0.2, -0.4, 0.5),
            Vector3::new(-1.3, 0.6, -0.7),
            Vector3::new(2.5, 0.05, 0.98),
        ]
    }

    #[test]
    fn orthonormal_and_first_order() {
        for p in psis() {
            let s = SectionRotation::new(&p);
            let e = (s.r.transpose() * s.r - Matrix3::identity()).amax();
            assert!(e < 1e-15, "RᵀR − I = {e:e} at {p:?}");
            assert!((s.r.determinant() - 1.0).abs() < 1e-15);
            // The x column is the inextensible tangent (c, θ_z, −θ_y).
            let c = (1.0 - p.y * p.y - p.z * p.z).sqrt();
            let t = Vector3::new(c, p.z, -p.y);
            assert!((s.r.column(0) - t).amax() < 1e-15);
        }
        // R = I + ψ̃ + O(ψ²).
        let p = Vector3::new(1e-5, -2e-5, 3e-5);
        let s = SectionRotation::new(&p);
        let lin = Matrix3::identity() + crate::rotation::skew(&p);
        assert!((s.r - lin).amax() < 1e-9);
    }

    #[test]
    fn twist_about_the_tangent() {
        // R_min R_x(φ) = R_t(φ) R_min: a twist after bending turns about t.
        let p = Vector3::new(0.7, -0.3, 0.4);
        let s = SectionRotation::new(&p);
        let b = SectionRotation::new(&Vector3::new(0.0, p.y, p.z));
        let t = b.r.column(0).into_owned();
        let rt = nalgebra::Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(t), p.x);
        assert!((s.r - rt.matrix() * b.r).amax() < 1e-14);
    }

    #[test]
    fn planar_rotation_is_the_slope_angle() {
        // In the x–y plane the section turns by asin(v') about z.
        let v = 0.6f64;
        let s = SectionRotation::new(&Vector3::new(0.0, 0.0, v));
        let a = crate::rotation::planar_rotation(v.asin());
        assert!((s.r - a).amax() < 1e-15);
        assert!((s.angle() - v.asin()).abs() < 1e-15);
    }

    #[test]
    fn derivatives_against_differences() {
        for p in psis().into_iter().skip(1) {
            let s = SectionRotation::new(&p);
            let h = 1e-6;
            for i in 0..3 {
                let mut pp = p;
                let mut pm = p;
                pp[i] += h;
                pm[i] -= h;
                let (sp, sm) = (SectionRotation::new(&pp), SectionRotation::new(&pm));
                let fd = (sp.r - sm.r) / (2.0 * h);
                let e = (fd - s.dr[i]).amax();
                assert!(e < 1e-8, "∂R/∂ψ_{i} off by {e:e} at {p:?}");
                for j in 0..3 {
                    let fd2 = (sp.dr[j] - sm.dr[j]) / (2.0 * h);
                    // Relative to the entries' size (near 90° they grow
                    // like 1/c³ and the differences' error with them).
                    let e = (fd2 - s.d2r(i, j)).amax() / (1.0 + s.d2r(i, j).amax());
                    assert!(e < 1e-7, "∂²R/∂ψ_{i}∂ψ_{j} off by {e:e} at {p:?}");
                }
            }
        }
    }

    #[test]
    fn beyond_ninety_degrees_stays_finite() {
        let s = SectionRotation::new(&Vector3::new(0.0, 0.9, 0.9));
        assert!(s.r.iter().all(|x| x.is_finite()));
        assert!((s.r.transpose() * s.r - Matrix3::identity()).amax() < 1e-12);
    }

    #[test]
    fn the_closed_form_angle_is_the_rotation_s() {
        for psi in psis() {
            let r = SectionRotation::new(&psi);
            let (a, b) = (rotation_angle(&psi), r.angle());
            assert!((a - b).abs() < 1e-7, "{psi:?}: {a} against {b}");
        }
        let planar = Vector3::new(0.0, 0.0, 0.6);
        assert!((rotation_angle(&planar) - 0.6f64.asin()).abs() < 1e-15);
        assert_eq!(rotation_angle(&Vector3::zeros()), 0.0);
    }
}
